"""Independent runs in parallel: one generator state per run, chunks of runs mapped to a backend.

Batch kernels have the form ``batch(*inputs, states, *outputs)`` and loop ``prange`` over
``states``; run ``r`` reads only ``states[r]`` and writes only ``outputs[...][r]``, so the
results are the same for any number of workers and any chunking.

The ``workers`` argument of :func:`run_batches` (and of every experiment's ``run``) picks who
runs the chunks: an int or None means numba threads in this process (:class:`Threads`, the
default); :class:`Processes` sends each chunk as a job to local processes (joblib);
:class:`Dask` sends them to a Dask distributed cluster (optional extra ``dask``). A job gets
the kernel's name, its inputs, the seed and its run indices; it derives its runs' states with
:func:`glamas.rng.chunk_states` and returns its output slices, which the caller writes back.
So every backend gives bit-identical results.

Threads stay the default: on one machine processes only add their start-up (benchmarks/
bench_backends.py), since the numba threads already use every core.
"""

import importlib
import os
import threading
from dataclasses import dataclass

import numba
import numpy as np
from tqdm import tqdm  # not tqdm.auto: it warns in notebooks without ipywidgets

from glamas.rng import check_seed, chunk_states, run_states

BACKENDS = ("threads", "processes", "dask")
DASK_INSTALL = "pip install -e '.[dask]' in the glamas repository (or: pip install -r requirements-extras.txt)"


class BackendError(RuntimeError):
    """A backend that cannot run: its optional extra is missing or its scheduler is unreachable."""


@dataclass(frozen=True)
class Threads:
    """Numba threads in this process (what an int or None ``workers`` means)."""

    workers: int | None = None
    """Threads (None: every core numba may use)."""


@dataclass(frozen=True)
class Processes:
    """Local worker processes (joblib's loky backend); each job runs one chunk of runs."""

    workers: int | None = None
    """Processes (None: one per core). Each uses its share of the cores as numba threads."""

    def __post_init__(self):
        if self.workers is not None and (isinstance(self.workers, bool) or not isinstance(self.workers, int)
                                         or self.workers < 1):
            raise ValueError(f"Processes(workers=...) must be a whole number >= 1 or None, got {self.workers!r}")


@dataclass(frozen=True)
class Dask:
    """A running Dask distributed scheduler; each job runs one chunk of runs on one of its workers.

    The workers need glamas installed (same version); each runs a job on all its numba threads.
    """

    scheduler: str
    """The scheduler's address, e.g. 'tcp://192.0.2.1:8786' (what `dask scheduler` prints)."""
    timeout: float = 10.0
    """Seconds to wait for the scheduler before giving up."""

    def __post_init__(self):
        if not isinstance(self.scheduler, str) or not self.scheduler.strip():
            raise ValueError(f"Dask(scheduler=...) must be the scheduler's address such as "
                             f"'tcp://HOST:8786', got {self.scheduler!r}")
        if isinstance(self.timeout, bool) or not isinstance(self.timeout, (int, float)) or not self.timeout > 0:
            raise ValueError(f"Dask(timeout=...) must be a positive number of seconds, got {self.timeout!r}")


def backend(name: str | None = None, workers: int | None = None, scheduler: str | None = None,
            timeout: float = 10.0):
    """The ``workers`` value for ``run`` from command-line style choices.

    ``name`` is one of BACKENDS (None: 'dask' if a scheduler is given, else 'threads');
    a ``scheduler`` address implies 'dask' (``timeout``: seconds to wait for it). Threads keep
    the plain ``workers`` (int or None).
    """
    if name is None:
        name = "threads" if scheduler is None else "dask"
    if name not in BACKENDS:
        raise ValueError(f"backend must be one of {', '.join(BACKENDS)}, got {name!r}")
    if name == "dask":
        if scheduler is None:
            raise ValueError("the dask backend needs the scheduler's address: --scheduler ADDRESS "
                             "(start a scheduler with `dask scheduler`, it prints the address)")
        if workers is not None:
            raise ValueError("--workers does not apply to the dask backend: the cluster's workers "
                             "(`dask worker ADDRESS`) set how many jobs run at once")
        require_dask()
        return Dask(scheduler, timeout)
    if scheduler is not None:
        raise ValueError(f"--scheduler means the dask backend, not {name!r}: drop --backend {name} "
                         "or the --scheduler address")
    return workers if name == "threads" else Processes(workers)


def require_dask():
    """Import Dask distributed, or fail naming the optional extra to install."""
    try:
        return importlib.import_module("distributed")
    except ImportError:
        raise BackendError(f"the dask backend needs the optional extra 'dask', which is not installed: "
                           f"{DASK_INSTALL}") from None


def set_workers(workers: int | None) -> int:
    """Use ``workers`` threads for the batch kernels (None: all cores); returns the number used."""
    available = numba.config.NUMBA_NUM_THREADS
    if workers is None:
        workers = available
    if not isinstance(workers, int) or not 1 <= workers <= available:
        raise ValueError(f"workers must be an integer from 1 to {available} (the cores numba may use), got {workers!r}")
    numba.set_num_threads(workers)
    return workers


def run_batches(batch, inputs: tuple, outputs: tuple, seed: int, *, workers=None,
                progress: str | None = None, chunk: int = 8) -> None:
    """Fill ``outputs`` (arrays whose first axis is the run) by calling ``batch`` on chunks of runs.

    ``workers``: an int or None (threads, see :func:`set_workers`), or a :class:`Threads`,
    :class:`Processes` or :class:`Dask` backend. ``progress`` names a progress bar (None: no
    bar). A chunk of runs is the unit of the bar and, outside threads, one job.
    """
    n_runs = outputs[0].shape[0]
    if isinstance(workers, Threads):
        workers = workers.workers
    if workers is None or isinstance(workers, int):
        _run_in_threads(batch, inputs, outputs, seed, workers, progress, chunk)
        return
    if not isinstance(workers, (Processes, Dask)):
        raise ValueError(f"workers must be a thread count, None (all cores) or a backend "
                         f"(glamas.runs.Threads, Processes or Dask), got {workers!r}")
    check_seed(seed)
    kernel = _kernel_name(batch)
    inputs = tuple(_for_transport(x) for x in inputs)
    jobs = [(kernel, inputs, seed, start, min(start + chunk, n_runs),
             tuple(out[start:start + chunk] for out in outputs)) for start in range(0, n_runs, chunk)]
    run_jobs = _run_in_processes if isinstance(workers, Processes) else _run_on_dask
    with tqdm(total=n_runs, desc=progress, unit="run", disable=progress is None) as bar:
        for start, filled in run_jobs(workers, jobs):
            for out, part in zip(outputs, filled):
                out[start:start + part.shape[0]] = part
            bar.update(filled[0].shape[0])


def _run_in_threads(batch, inputs, outputs, seed, workers, progress, chunk):
    states = run_states(seed, outputs[0].shape[0])
    set_workers(workers)
    with tqdm(total=states.shape[0], desc=progress, unit="run", disable=progress is None) as bar:
        for start in range(0, states.shape[0], chunk):
            stop = min(start + chunk, states.shape[0])
            batch(*inputs, states[start:stop], *(out[start:stop] for out in outputs))
            bar.update(stop - start)


_KERNEL_LOCK = threading.Lock()


def run_chunk(kernel: str, inputs: tuple, seed: int, start: int, stop: int, initial: tuple,
              threads: int | None = None) -> tuple[int, tuple]:
    """One job: runs ``start`` to ``stop - 1`` of a sweep; returns ``(start, filled outputs)``.

    ``kernel`` is 'module:name' of the batch kernel, ``initial`` the outputs' initial slices
    (some kernels read them, e.g. initial Q values). ``threads``: numba threads (None: as set).
    """
    batch = _resolve_kernel(kernel)
    states = chunk_states(seed, start, stop)
    inputs = tuple(_as_sent(x) for x in inputs)
    outputs = tuple(np.array(x) for x in initial)  # copies: the caller's arrays stay untouched
    # One parallel launch at a time per process: numba's workqueue threading layer aborts on
    # concurrent launches (a Dask worker with several threads would make them).
    with _KERNEL_LOCK:
        if threads is not None:
            numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        batch(*inputs, states, *outputs)
    return start, outputs


@dataclass(frozen=True)
class _ReadOnly:
    """A read-only input array in transit: transports lose the flag, and numba types a
    read-only array apart (another compilation, another cache entry)."""

    array: np.ndarray


def _for_transport(x):
    return _ReadOnly(x) if isinstance(x, np.ndarray) and not x.flags.writeable else x


def _as_sent(x):
    """A copy of an input array, read-only if the caller's was."""
    if isinstance(x, _ReadOnly):
        x = np.array(x.array)
        x.flags.writeable = False
    elif isinstance(x, np.ndarray):
        x = np.array(x)
    return x


def _kernel_name(batch) -> str:
    """'module:name' of a module-level batch kernel, which a worker process can import."""
    function = getattr(batch, "py_func", batch)
    name = f"{function.__module__}:{function.__qualname__}"
    try:
        importable = function.__module__ != "__main__" and _resolve_kernel(name) is batch
    except (ImportError, AttributeError):
        importable = False
    if not importable:
        raise ValueError(f"the batch kernel {name} is not a module-level function of an importable "
                         "module, so worker processes cannot load it; define it at the top level of a "
                         "module, or use the threads backend")
    return name


def _resolve_kernel(name: str):
    module, _, attribute = name.partition(":")
    target = importlib.import_module(module)
    for part in attribute.split("."):
        target = getattr(target, part)
    return target


def _run_in_processes(backend: Processes, jobs: list):
    from joblib import Parallel, delayed

    n_processes = backend.workers or os.cpu_count() or 1
    threads = max(1, numba.config.NUMBA_NUM_THREADS // n_processes)
    # max_nbytes=None: no memory-mapped (read-only) arguments.
    parallel = Parallel(n_jobs=n_processes, backend="loky", return_as="generator_unordered", max_nbytes=None)
    yield from parallel(delayed(run_chunk)(*job, threads) for job in jobs)


def connect(backend: Dask):
    """A Dask client of the backend's scheduler (close it after use), or a clear error."""
    distributed = require_dask()
    try:
        return distributed.Client(backend.scheduler, timeout=backend.timeout, set_as_default=False)
    except (OSError, TimeoutError) as error:
        raise BackendError(f"cannot reach the Dask scheduler at {backend.scheduler} within "
                           f"{backend.timeout:g} s ({error}); check the address, or start a scheduler "
                           "with `dask scheduler` and workers with `dask worker ADDRESS`") from None


def _run_on_dask(backend: Dask, jobs: list):
    distributed = require_dask()
    with connect(backend) as client:
        futures = [client.submit(run_chunk, *job, pure=False) for job in jobs]
        for future in distributed.as_completed(futures, loop=client.loop):
            yield future.result()
