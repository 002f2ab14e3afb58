"""Jobs on this machine: a pool of threads in this process, or loky's reusable worker processes
handed one job at a time, a kernel that may still be compiling left to the worker compiling it.
"""

import contextlib
import signal
import threading
import warnings
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, as_completed, wait

from glamas.parallel.backends import BackendError, Processes, Threads, cores
from glamas.parallel.job import batch_chunk, fill_chunk, run_chunk

# loky's idle workers exit after a few seconds; a job handed out as one exits makes loky start
# another and warn from its own thread. The job still runs and its result is the same, so the
# warning is noise (it would land in a notebook's stderr at random).
warnings.filterwarnings("ignore", message="A worker stopped while some jobs were given to the executor",
                        category=UserWarning)


def run_in_threads(backend: Threads, jobs: list):
    """Jobs on a pool of threads: the kernels release the GIL (nogil), so they run at once. Stopped
    early (an error, an interrupt), the jobs not yet started are dropped; those running end theirs."""
    pool = ThreadPoolExecutor(backend.workers or cores())
    try:
        for future in as_completed([pool.submit(batch_chunk, k, fill_chunk, *job) for k, *job in jobs]):
            yield future.result()
    finally:
        pool.shutdown(cancel_futures=True)


def run_in_processes(backend: Processes, jobs: list):
    """Jobs on local worker processes (loky's reusable executor: the workers outlive the call and
    keep the kernels they loaded), one job per worker at a time, in the order of ``jobs`` but
    for :func:`_next_job`'s choice; yields ``(k, start, filled outputs)`` as jobs finish."""
    from joblib.externals.loky import get_reusable_executor
    from joblib.externals.loky.process_executor import TerminatedWorkerError

    n_workers = backend.workers or cores()
    with _interrupts_ignored():
        executor = get_reusable_executor(max_workers=n_workers)
    waiting, running, ready = list(jobs), {}, set()
    try:
        while waiting or running:
            while waiting and len(running) < n_workers:
                job = waiting.pop(_next_job(waiting, running.values(), ready))
                with _interrupts_ignored():  # a submission may start a worker
                    running[executor.submit(batch_chunk, job[0], run_chunk, *job[1:])] = job
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                ready.add(running.pop(future)[1])
                yield future.result()
    except TerminatedWorkerError as error:
        codes = next((line for line in str(error).splitlines() if "exit codes" in line), "").strip()
        raise BackendError(f"a worker process died mid-run (killed, out of memory or crashed; {codes}); "
                           "run again, with fewer --workers if memory is short") from None
    finally:
        if waiting or running:  # stopped early (an error, an interrupt): no work left behind in the workers
            executor.shutdown(wait=False, kill_workers=True)


@contextlib.contextmanager
def _interrupts_ignored():
    """SIGINT ignored while worker processes may start (in the main thread, the only one that can
    set it): they inherit the ignoring for their life, so the terminal's Ctrl-C, sent to every
    process of the group, stops this process alone, which stops them, instead of tracing back in a
    worker still starting. A Ctrl-C in those milliseconds is lost: press it again."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler if previous is None else previous)


def _next_job(waiting: list, running, ready: set) -> int:
    """Where in ``waiting`` the next job to hand out is: the first job whose kernel is not being
    compiled. A kernel whose first job still runs may be compiling (numba's cache holds it only
    once that job has it), and a second worker taking up the same kernel then would compile it
    again instead of doing other work. The first job when every waiting job's kernel is being
    compiled. Jobs are ``(k, kernel name, ...)``; ``ready`` holds the kernels with a job done."""
    compiling = {job[1] for job in running} - ready
    return next((i for i, job in enumerate(waiting) if job[1] not in compiling), 0)
