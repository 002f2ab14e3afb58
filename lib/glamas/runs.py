"""Independent runs in parallel: one generator state per run, chunks of runs mapped to workers.

A run kernel is the compiled function of one run, ``kernel(*inputs, *outputs_of_the_run, state)``
with ``@njit(cache=True, nogil=True)``: it reads the shared ``inputs`` and its own generator
``state`` and writes only its run's slice of each output. A job is one chunk of runs, and the
``workers`` argument of :func:`run_batches` and :func:`run_many` (and of every experiment's
``run``) picks who runs the jobs: local processes by default (loky, joblib's pool of reusable
workers; an int or None is their number, see
:class:`Processes`), threads in this process (:class:`Threads`), or a Dask distributed cluster
(:class:`Dask`, optional extra ``dask``). A job derives its runs' generator states from the
master seed and its run indices (:func:`glamas.rng.chunk_states`), so every backend, number of
workers and chunking gives bit-identical results.

A process may keep the outputs of the batches it runs (:func:`reuse_batches`): the runs are
deterministic, so a later batch with the same kernel, master seed, inputs and initial outputs
takes them instead of running again. glamas.reproduce does so, running every figure script in
one process: the 2observe of Fig. 11 is the default reading of the Fig. 10 study, and the
related-work comparison trains the chapter's learners as Fig. 11 does.

On one machine threads do the same work without the processes' start-up, which costs about a
second per script (benchmarks/bench_backends.py). Processes are the default because a job that
imports its kernel by name and returns its outputs is what carries over to a cluster unchanged.
"""

import asyncio
import collections
import hashlib
import importlib
import itertools
import os
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, as_completed, wait
from dataclasses import dataclass

import numpy as np
from tqdm import tqdm  # not tqdm.auto: it warns in notebooks without ipywidgets

from glamas.rng import check_seed, chunk_states

BACKENDS = ("threads", "processes", "dask")
# loky's idle workers exit after a few seconds; a job handed out as one exits makes loky start
# another and warn from its own thread. The job still runs and its result is the same, so the
# warning is noise (it would land in a notebook's stderr at random).
warnings.filterwarnings("ignore", message="A worker stopped while some jobs were given to the executor",
                        category=UserWarning)
DASK_INSTALL = "pip install -e '.[dask]' in the glamas repository (or: pip install -r requirements-extras.txt)"


def _check_count(backend: str, workers) -> None:
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"{backend}(workers=...) must be a whole number >= 1 or None, got {workers!r}")


class BackendError(RuntimeError):
    """A backend that cannot run: its optional extra is missing, its scheduler is unreachable, or
    its workers are gone."""


class NonFiniteError(FloatingPointError):
    """A run produced NaN or infinite values: a setting drove the learning out of range."""


POLL_SECONDS = 0.05
"""How often a wait on a Dask cluster looks for finished jobs and whether it still has workers."""


@dataclass(frozen=True)
class Threads:
    """Threads in this process, each running one job at a time."""

    workers: int | None = None
    """Threads (None: one per core)."""

    def __post_init__(self):
        _check_count("Threads", self.workers)


@dataclass(frozen=True)
class Processes:
    """Local worker processes (loky's reusable executor, from joblib), each running one job at a
    time; the default, what an int or None ``workers`` means. One process is this one: a single
    worker's jobs run in the calling process."""

    workers: int | None = None
    """Processes (None: one per core)."""

    def __post_init__(self):
        _check_count("Processes", self.workers)


@dataclass(frozen=True)
class Dask:
    """A running Dask distributed scheduler; each job runs one chunk of runs on one of its workers.

    The workers need glamas installed (same version); each of their threads runs one job at a time.
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

    ``name`` is one of BACKENDS (None: 'dask' if a scheduler is given, else 'processes');
    a ``scheduler`` address implies 'dask' (``timeout``: seconds to wait for it).
    """
    if name is None:
        name = "processes" if scheduler is None else "dask"
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
    return Threads(workers) if name == "threads" else Processes(workers)


def require_dask():
    """Import Dask distributed, or fail naming the optional extra to install."""
    try:
        return importlib.import_module("distributed")
    except ImportError:
        raise BackendError(f"the dask backend needs the optional extra 'dask', which is not installed: "
                           f"{DASK_INSTALL}") from None


def cores() -> int:
    """The cores this process may run on (what a backend's workers=None means)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


@dataclass(frozen=True)
class Batch:
    """The runs of one run kernel: ``kernel(*inputs, *outputs_of_the_run, state)`` for every run,
    the runs' streams drawn from master seed ``seed`` (:func:`run_batches`)."""

    kernel: object
    """The compiled run kernel (``@njit(cache=True, nogil=True)``)."""
    inputs: tuple
    """What every run reads."""
    outputs: tuple
    """Arrays whose first axis is the run, each run filling its own slice, or :class:`Scratch`
    for an output that the caller does not keep."""
    seed: int
    """The master seed of the runs' streams (:func:`glamas.rng.chunk_states`)."""


@dataclass(frozen=True)
class Scratch:
    """An output that the caller does not keep, in place of its array in :attr:`Batch.outputs`:
    each run fills an array of its own (``shape[1:]`` of ``dtype``, starting at ``value``) that
    is dropped after the run. Nothing of it is allocated in the caller or sent back: an
    experiment that wants only the learning curves of a joint learner of four agents would
    otherwise allocate and receive gigabytes of Q tables."""

    shape: tuple
    """(runs, ...): the run axis, then one run's array."""
    dtype: np.dtype
    value: object
    """Every element's value at the start of a run."""

    @property
    def ndim(self) -> int:
        return len(self.shape)

    def runs(self, start: int, stop: int) -> "Scratch":
        """Runs ``start`` to ``stop - 1`` (as slicing an array's first axis; ``start`` < runs)."""
        return Scratch((min(stop, self.shape[0]) - start, *self.shape[1:]), self.dtype, self.value)


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
    run's (:func:`_recall`)."""
    workers = _backend(workers)
    for batch in batches:
        _check_batch(batch)
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1):
        raise ValueError(f"chunk must be a whole number of runs >= 1 or None, got {chunk!r}")
    keys = [_memo_key(batch) for batch in batches]
    to_run = [k for k, key in enumerate(keys) if not _recall(key, batches[k])]
    per_batch = []  # each batch's jobs: (batch number, start, stop, the outputs' initial slices)
    for k in to_run:
        batch = batches[k]
        n_runs = batch.outputs[0].shape[0]
        size = chunk_size(n_runs, workers) if chunk is None else chunk
        per_batch.append([(k, start, min(start + size, n_runs), tuple(_runs_of(out, start, start + size)
                                                                       for out in batch.outputs))
                          for start in range(0, n_runs, size)])
    # The batches' jobs taken in turn: the workers start on different kernels, so that each
    # compiles (or loads) a different one at first instead of all the same.
    jobs = [job for turn in itertools.zip_longest(*per_batch) for job in turn if job is not None]
    if not jobs:
        return
    if not isinstance(workers, Dask) and (workers.workers or cores()) > len(jobs):
        workers = type(workers)(max(1, len(jobs)))  # a worker without a job would only cost its start-up
    if isinstance(workers, Processes) and (workers.workers or cores()) == 1:  # one process: this one
        for k in to_run:
            _kernel_name(batches[k].kernel)  # importable, as for more workers
        done = (_batch_chunk(k, fill_chunk, batches[k].kernel, batches[k].inputs, batches[k].seed, start, stop, first,
                             False) for k, start, stop, first in jobs)
    elif isinstance(workers, Threads):
        done = _run_in_threads(workers, [(k, batches[k].kernel, batches[k].inputs, batches[k].seed, start, stop, first)
                                         for k, start, stop, first in jobs])
    else:
        sent = [(_kernel_name(b.kernel), tuple(_for_transport(x) for x in b.inputs)) for b in batches]
        tasks = [(k, *sent[k], batches[k].seed, start, stop, tuple(_Filled.of(x) for x in first))
                 for k, start, stop, first in jobs]
        done = (_run_in_processes if isinstance(workers, Processes) else _run_on_dask)(workers, tasks)
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
        _remember(keys[k], batches[k])


MEMO_BYTES = 0
"""Most bytes of outputs that this process keeps of the batches it has run, to fill an identical
batch with instead of running it (:func:`_recall`); 0, the default, keeps none
(:func:`reuse_batches` sets it)."""
_memo = collections.OrderedDict()  # batch key -> copies of its filled outputs, least recently used first


def reuse_batches(max_bytes: int) -> None:
    """From now on keep up to ``max_bytes`` of the outputs of the batches this process runs, and
    fill a batch identical to one of them from them instead of running it (0: keep none, the
    default). glamas.reproduce does, running every figure script in one process."""
    global MEMO_BYTES
    if isinstance(max_bytes, bool) or not isinstance(max_bytes, int) or max_bytes < 0:
        raise ValueError(f"max_bytes must be a whole number >= 0, got {max_bytes!r}")
    MEMO_BYTES = max_bytes
    while _memo and _kept_bytes() > MEMO_BYTES:
        _memo.popitem(last=False)


def _kept_bytes() -> int:
    return sum(out.nbytes for kept in _memo.values() for out in kept)


def _memo_key(batch: Batch):
    """What makes a batch's outputs what they are: its kernel, and a digest of its master seed,
    inputs and initial outputs (the runs are deterministic); None for a batch with a Scratch
    output, whose outputs take more than an eighth of MEMO_BYTES, or whose inputs hold something
    other than arrays, numbers, strings and tuples of them."""
    if any(isinstance(out, Scratch) for out in batch.outputs):
        return None
    if sum(out.nbytes for out in batch.outputs) > MEMO_BYTES // 8:
        return None
    digest = hashlib.blake2b(digest_size=20)
    if not _digest(digest, (batch.seed, batch.inputs, batch.outputs)):
        return None
    return batch.kernel, digest.hexdigest()


def _digest(digest, x) -> bool:
    """Feed ``x`` to ``digest``; False where it holds something else than :func:`_memo_key` takes."""
    if isinstance(x, np.ndarray):
        digest.update(f"array {x.dtype.str} {x.shape}:".encode())
        digest.update(np.ascontiguousarray(x).tobytes())
        return True
    if isinstance(x, tuple):
        digest.update(f"{type(x).__qualname__} {len(x)}(".encode())
        if not all(_digest(digest, item) for item in x):
            return False
        digest.update(b")")
        return True
    if x is None or isinstance(x, (bool, int, float, str, np.generic)):
        digest.update(f"{type(x).__qualname__} {x!r};".encode())
        return True
    return False


def _recall(key, batch: Batch) -> bool:
    """Fill ``batch``'s outputs from the batch of the same ``key`` that this process ran before
    (a figure script drawing what another one has trained, as glamas.reproduce runs them all);
    False if there is none."""
    if key is None or key not in _memo:
        return False
    _memo.move_to_end(key)
    for out, kept in zip(batch.outputs, _memo[key]):
        out[...] = kept
    return True


def _remember(key, batch: Batch) -> None:
    """Keep copies of ``batch``'s filled outputs under ``key``, forgetting the least recently
    used batches beyond MEMO_BYTES."""
    if key is None:
        return
    _memo[key] = tuple(out.copy() for out in batch.outputs)
    while _kept_bytes() > MEMO_BYTES:
        _memo.popitem(last=False)


def _backend(workers):
    """The backend ``workers`` stands for (an int or None: local processes)."""
    if workers is None or (isinstance(workers, int) and not isinstance(workers, bool)):
        return Processes(workers)
    if not isinstance(workers, (Processes, Threads, Dask)):
        raise ValueError(f"workers must be a process count, None (one per core) or a backend "
                         f"(glamas.runs.Processes, Threads or Dask), got {workers!r}")
    return workers


def _check_batch(batch: Batch) -> None:
    check_seed(batch.seed)
    if any(out.ndim < 2 for out in batch.outputs):
        raise ValueError("every output needs an axis of runs and an array per run (ndim >= 2), got shapes "
                         f"{[out.shape for out in batch.outputs]}")


def check_finite(kernel, start: int, filled: tuple) -> None:
    """Raise :class:`NonFiniteError` if a floating-point output of runs ``start, ...`` holds NaN
    or infinity: a learning rate, K, reward or penalty too large makes the updates overflow, and
    every later number would be meaningless."""
    for k, part in enumerate(filled):
        if part is None or not np.issubdtype(part.dtype, np.floating):
            continue
        finite = np.isfinite(part.reshape(part.shape[0], -1)).all(axis=1)
        if not finite.all():
            run = start + int(np.argmin(finite))
            function = getattr(kernel, "py_func", kernel)
            name = f"{getattr(function, '__module__', '?')}.{getattr(function, '__qualname__', function)}"
            raise NonFiniteError(f"run {run} of {name} produced NaN or infinite values in its output {k}: "
                                 "a learning rate, K, reward or penalty is too large for the learning to stay "
                                 "finite; lower it")


def chunk_size(n_runs: int, backend) -> int:
    """Runs per job: about four jobs per local worker, so that runs of unequal length even out
    while a job stays long next to sending it; 8 runs on a cluster of unknown size."""
    if isinstance(backend, Dask):
        return 8
    return max(1, -(-n_runs // (4 * (backend.workers or cores()))))


def fill_chunk(kernel, inputs: tuple, seed: int, start: int, stop: int, initial: tuple,
               copy: bool = True) -> tuple[int, tuple]:
    """One job: runs ``start`` to ``stop - 1`` of a sweep; returns ``(start, filled outputs)``.

    ``initial`` are the outputs' initial slices (some kernels read them, e.g. initial Q values).
    With ``copy`` the job fills copies: the caller's arrays stay untouched until it writes the
    result back, and jobs running at once never write to one cache line (which would slow them
    down). Without, it fills ``initial`` itself: arrays the job owns, or the caller's when one
    job runs at a time in the caller's process (no copy of tables that may take gigabytes).
    A :class:`Scratch` (or a :class:`_Filled` in transit) becomes an array of the job's own;
    a Scratch's filled output is returned as None.
    """
    outputs = tuple(_array_of(x, copy) for x in initial)
    for r, state in enumerate(chunk_states(seed, start, stop)):
        kernel(*inputs, *(out[r] for out in outputs), state)
    return start, tuple(None if isinstance(x, Scratch) else out for x, out in zip(initial, outputs))


def _array_of(x, copy: bool) -> np.ndarray:
    """The array a job fills for the initial output slice ``x`` (:func:`fill_chunk`)."""
    if isinstance(x, (Scratch, _Filled)):
        return np.full(x.shape, x.value, x.dtype)
    return np.array(x) if copy else x


def _runs_of(out, start: int, stop: int):
    """Runs ``start`` to ``stop - 1`` of an output: an array's slice, or a Scratch's."""
    return out.runs(start, stop) if isinstance(out, Scratch) else out[start:stop]


def run_chunk(kernel: str, inputs: tuple, seed: int, start: int, stop: int,
              initial: tuple) -> tuple[int, tuple]:
    """:func:`fill_chunk` in a worker process: ``kernel`` is the run kernel's 'module:name'. It
    fills arrays of its own: made from a _Filled or Scratch, or copies of what it was sent."""
    return fill_chunk(_resolve_kernel(kernel), tuple(_as_sent(x) for x in inputs), seed, start, stop, initial)


def _batch_chunk(k: int, run, *job) -> tuple[int, int, tuple]:
    """``run(*job)`` (fill_chunk or run_chunk) for batch ``k``: ``(k, start, filled outputs)``."""
    return (k, *run(*job))


def _run_in_threads(backend: Threads, jobs: list):
    """Jobs on a pool of threads: the kernels release the GIL (nogil), so they run at once."""
    with ThreadPoolExecutor(backend.workers or cores()) as pool:
        for future in as_completed([pool.submit(_batch_chunk, k, fill_chunk, *job) for k, *job in jobs]):
            yield future.result()


@dataclass(frozen=True)
class _Filled:
    """An output slice of one value in transit: its shape, type and value instead of its bytes.
    Initial outputs mostly are (Q tables filled with their initial value, zeros), and the joint
    learners' tables of four agents take hundreds of MB per job."""

    shape: tuple
    dtype: np.dtype
    value: object

    @staticmethod
    def of(x):
        """An output slice ``x`` as a _Filled if every element equals the first (NaN never
        does), else ``x`` (a Scratch as it is)."""
        if isinstance(x, Scratch) or x.size == 0 or not (x == x.flat[0]).all():
            return x
        return _Filled(x.shape, x.dtype, x.flat[0])


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


def _kernel_name(kernel) -> str:
    """'module:name' of a module-level run kernel, which a worker process can import."""
    function = getattr(kernel, "py_func", kernel)
    name = f"{function.__module__}:{function.__qualname__}"
    try:
        importable = function.__module__ != "__main__" and _resolve_kernel(name) is kernel
    except (ImportError, AttributeError):
        importable = False
    if not importable:
        raise ValueError(f"the run kernel {name} is not a module-level function of an importable "
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
    """Jobs on local worker processes (loky's reusable executor: the workers outlive the call and
    keep the kernels they loaded), one job per worker at a time, in the order of ``jobs`` but
    for :func:`_next_job`'s choice; yields ``(k, start, filled outputs)`` as jobs finish."""
    from joblib.externals.loky import get_reusable_executor
    from joblib.externals.loky.process_executor import TerminatedWorkerError

    n_workers = backend.workers or cores()
    executor = get_reusable_executor(max_workers=n_workers)
    waiting, running, ready = list(jobs), {}, set()
    try:
        while waiting or running:
            while waiting and len(running) < n_workers:
                job = waiting.pop(_next_job(waiting, running.values(), ready))
                running[executor.submit(_batch_chunk, job[0], run_chunk, *job[1:])] = job
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                ready.add(running.pop(future)[1])
                yield future.result()
    except TerminatedWorkerError as error:
        codes = next((line for line in str(error).splitlines() if "exit codes" in line), "").strip()
        raise BackendError(f"a worker process died mid-run (killed, out of memory or crashed; {codes}); "
                           "run again, with fewer --workers if memory is short") from None
    finally:
        if waiting or running:  # stopped early (an error): no work left behind in the workers
            executor.shutdown(wait=False, kill_workers=True)


def _next_job(waiting: list, running, ready: set) -> int:
    """Where in ``waiting`` the next job to hand out is: the first job whose kernel is not being
    compiled. A kernel whose first job still runs may be compiling (numba's cache holds it only
    once that job has it), and a second worker taking up the same kernel then would compile it
    again instead of doing other work. The first job when every waiting job's kernel is being
    compiled. Jobs are ``(k, kernel name, ...)``; ``ready`` holds the kernels with a job done."""
    compiling = {job[1] for job in running} - ready
    return next((i for i, job in enumerate(waiting) if job[1] not in compiling), 0)


def connect(backend: Dask):
    """A Dask client of the backend's scheduler (close it after use), or a clear error within
    about ``backend.timeout`` seconds: a malformed address, nothing listening, or a server that
    is not a Dask scheduler."""
    distributed = require_dask()
    failure = f"cannot reach the Dask scheduler at {backend.scheduler} within {backend.timeout:g} s"
    advice = "check the address, or start a scheduler with `dask scheduler` and workers with `dask worker ADDRESS`"
    try:
        with ThreadPoolExecutor(1) as thread:  # its own event loop: the caller may be running one (Jupyter)
            thread.submit(asyncio.run, _probe(distributed, backend)).result()
        return distributed.Client(backend.scheduler, timeout=backend.timeout, set_as_default=False)
    except (OSError, TimeoutError, asyncio.TimeoutError) as error:
        raise BackendError(f"{failure} ({str(error) or 'no answer'}); {advice}") from None
    except ValueError as error:
        raise BackendError(f"{backend.scheduler!r} is not a Dask scheduler address ({error}); "
                           "give one such as tcp://HOST:8786") from None


async def _probe(distributed, backend: Dask) -> None:
    """Ask the address for its identity, with a deadline: distributed's own client waits without
    one for a server that accepts the connection but never answers as a scheduler would."""
    async def identity():
        comm = await distributed.comm.connect(backend.scheduler, timeout=backend.timeout)
        try:
            await comm.write({"op": "identity"})
            return await comm.read()
        finally:
            comm.abort()

    reply = await asyncio.wait_for(identity(), backend.timeout)
    if not (isinstance(reply, dict) and reply.get("type") == "Scheduler"):
        raise OSError(f"the server there answered, but not as a Dask scheduler ({str(reply)[:80]})")


def _run_on_dask(backend: Dask, jobs: list):
    distributed = require_dask()
    with connect(backend) as client:
        futures = [client.submit(_batch_chunk, k, run_chunk, *job, pure=False) for k, *job in jobs]
        finished = distributed.as_completed(futures, loop=client.loop)
        without_workers = None  # since when the cluster has had no worker
        while not finished.is_empty():
            batch = finished.next_batch(block=False)
            if not batch:  # nothing new: look whether anyone is still working, then wait a little
                without_workers = _check_workers(client, backend, without_workers, finished.count())
                time.sleep(POLL_SECONDS)
            for future in batch:
                yield _result(distributed, future)


def _check_workers(client, backend: Dask, without_workers, n_pending: int):
    """When the cluster has no workers left, raise after ``backend.timeout`` seconds; returns
    since when it has had none (None: it has workers)."""
    if client.scheduler_info().get("workers"):
        return None
    now = time.monotonic()
    if without_workers is not None and now - without_workers > backend.timeout:
        raise BackendError(f"the Dask cluster at {backend.scheduler} has had no worker for "
                           f"{backend.timeout:g} s with {n_pending} jobs left (a worker was lost or none "
                           "was started); start workers with `dask worker ADDRESS`")
    return now if without_workers is None else without_workers


def _result(distributed, future):
    try:
        return future.result()
    except distributed.KilledWorker as error:
        raise BackendError(f"a job was lost with the Dask workers that ran it ({error}); check the "
                           "workers' memory and logs, then run again") from None
