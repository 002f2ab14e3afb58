"""The one runner of every experiment's runs: batches of runs cut into jobs, the jobs handed to
the backend that ``workers`` names, their outputs checked and written back."""

import sys

import numpy as np
from tqdm import tqdm  # not tqdm.auto: it warns in notebooks without ipywidgets

from glamas import sources
from glamas.errors import UserError
from glamas.parallel import dask, local, memo
from glamas.parallel.backends import Dask, Processes, Threads, as_backend, cores
from glamas.parallel.batch import Batch, check_batch, check_finite, jobs_of
from glamas.parallel.job import batch_chunk, fill_chunk, importable, kernel_label, to_send


def run_batches(kernel, inputs: tuple, outputs: tuple, seed: int, *, workers=None,
                progress: str | None = None, chunk: int | None = None) -> None:
    """Fill ``outputs`` (arrays whose first axis is the run) by calling the run ``kernel`` for
    every run, in chunks of runs.

    ``workers``: a :class:`Processes`, :class:`Threads` or :class:`Dask` backend, or an int or
    None for ``Processes(workers)``. ``progress`` names a progress bar (None: no bar). A chunk
    of runs is one job; ``chunk`` runs per job (None: see :func:`chunk_size`).
    """
    run_many([Batch(kernel, inputs, outputs, seed)], workers=workers, progress=progress, chunk=chunk)


def run_many(batches: list, *, workers=None, progress: str | None = None, chunk: int | None = None) -> None:
    """:func:`run_batches` for several batches at once, all their jobs on one pool of workers: the
    workers take up the next batch's jobs while the last jobs of another still run, instead of
    waiting for them. Each batch's runs get the streams and results they get alone.

    After :func:`reuse_batches`, a batch that this process has run before (the same kernel,
    master seed, inputs and initial outputs) is not run again: its outputs are copied from that
    run's (:func:`glamas.parallel.memo.recall`)."""
    workers = as_backend(workers)
    for batch in batches:
        check_batch(batch)
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1):
        raise UserError(f"chunk must be a whole number of runs >= 1 or None, got {chunk!r}")
    keys = [memo.key_of(batch) for batch in batches]
    to_run = [k for k, key in enumerate(keys) if not memo.recall(key, batches[k])]
    jobs = jobs_of(batches, to_run, workers, chunk)
    if not jobs:
        return
    if not isinstance(workers, Dask) and (workers.workers or cores()) > len(jobs):
        workers = type(workers)(max(1, len(jobs)))  # a worker without a job would only cost its start-up
    if progress is not None and not isinstance(workers, Dask):
        _say_if_compiling([batches[k] for k in to_run])
    done = _hand_out(workers, batches, to_run, jobs)
    stops = {(k, start): stop for k, start, stop, _ in jobs}
    with tqdm(total=sum(stop - start for _, start, stop, _ in jobs), desc=progress, unit="run",
              disable=progress is None) as bar:
        for k, start, filled in done:
            check_finite(batches[k].kernel, start, filled)
            for out, part in zip(batches[k].outputs, filled):
                if part is None:  # a Scratch output: nothing came back
                    continue
                target = out[start:start + part.shape[0]]
                if not np.may_share_memory(target, part):  # else filled in place
                    target[...] = part
            bar.update(stops[k, start] - start)
    for k in to_run:
        memo.remember(keys[k], batches[k])


def _say_if_compiling(batches: list) -> None:
    """One line on stderr when a kernel of ``batches`` is not in numba's cache
    (:func:`glamas.sources.uncached`): its first jobs compile it, the progress bar still at 0."""
    if any(sources.uncached(batch.kernel) for batch in batches):
        print("compiling the kernels into numba's cache before the first run (about a minute on 2 cores, once)",
              file=sys.stderr, flush=True)


def _hand_out(workers, batches: list, to_run: list, jobs: list):
    """``jobs`` started on ``workers``: an iterator of ``(batch number, start, filled outputs)``
    as they finish. Local processes become as many threads of this process when a kernel is not
    importable by another process (defined in a notebook or a script's ``__main__``): the runs
    are the same, and one line on stderr says so."""
    if isinstance(workers, Processes):
        foreign = [name for name in dict.fromkeys(kernel_label(batches[k].kernel) for k in to_run
                                                  if not importable(batches[k].kernel))]
        if foreign:
            print(f"note: {', '.join(foreign)} cannot be imported by worker processes (define it at the top level "
                  "of a module to run it in processes): running on threads of this process, with the same results",
                  file=sys.stderr)
            workers = Threads(workers.workers or cores())
    if isinstance(workers, Processes) and (workers.workers or cores()) == 1:  # one process: this one
        return (batch_chunk(k, fill_chunk, batches[k].kernel, batches[k].inputs, batches[k].seed, start, stop, first,
                            False, batches[k].evaluations) for k, start, stop, first in jobs)
    if isinstance(workers, Threads):
        return local.run_in_threads(workers, [(k, batches[k].kernel, batches[k].inputs, batches[k].seed, start, stop,
                                               first, True, batches[k].evaluations) for k, start, stop, first in jobs])
    tasks = to_send(batches, jobs)
    return (local.run_in_processes if isinstance(workers, Processes) else dask.run_on_dask)(workers, tasks)
