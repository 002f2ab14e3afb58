"""Who runs the jobs: the backends that the ``workers`` argument names, and how a command line's
choices make one.

On one machine threads do the same work without the processes' start-up, which costs about a
second per script (benchmarks/bench_backends.py). Processes are the default because a job that
imports its kernel by name and returns its outputs is what carries over to a cluster unchanged.
"""

import importlib
import os
from dataclasses import dataclass

from glamas.errors import UserError

BACKENDS = ("threads", "processes", "dask")
DASK_INSTALL = "pip install -e '.[dask]' in the glamas repository (or: pip install -r requirements-extras.txt)"


def _check_count(backend: str, workers) -> None:
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise UserError(f"{backend}(workers=...) must be a whole number >= 1 or None, got {workers!r}")


class BackendError(UserError, RuntimeError):
    """A backend that cannot run: its optional extra is missing, its scheduler is unreachable, or
    its workers are gone."""


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
            raise UserError(f"Dask(scheduler=...) must be the scheduler's address such as "
                             f"'tcp://HOST:8786', got {self.scheduler!r}")
        if isinstance(self.timeout, bool) or not isinstance(self.timeout, (int, float)) or not self.timeout > 0:
            raise UserError(f"Dask(timeout=...) must be a positive number of seconds, got {self.timeout!r}")


def backend(name: str | None = None, workers: int | None = None, scheduler: str | None = None,
            timeout: float = 10.0):
    """The ``workers`` value for ``run`` from command-line style choices.

    ``name`` is one of BACKENDS (None: 'dask' if a scheduler is given, else 'processes');
    a ``scheduler`` address implies 'dask' (``timeout``: seconds to wait for it).
    """
    if name is None:
        name = "processes" if scheduler is None else "dask"
    if name not in BACKENDS:
        raise UserError(f"backend must be one of {', '.join(BACKENDS)}, got {name!r}")
    if name == "dask":
        if scheduler is None:
            raise UserError("the dask backend needs the scheduler's address: --scheduler ADDRESS "
                             "(start a scheduler with `dask scheduler`, it prints the address)")
        if workers is not None:
            raise UserError("--workers does not apply to the dask backend: the cluster's workers "
                             "(`dask worker ADDRESS`) set how many jobs run at once")
        require_dask()
        return Dask(scheduler, timeout)
    if scheduler is not None:
        raise UserError(f"--scheduler means the dask backend, not {name!r}: drop --backend {name} "
                         "or the --scheduler address")
    return Threads(workers) if name == "threads" else Processes(workers)


def as_backend(workers):
    """The backend ``workers`` stands for (an int or None: local processes)."""
    if workers is None or (isinstance(workers, int) and not isinstance(workers, bool)):
        return Processes(workers)
    if not isinstance(workers, (Processes, Threads, Dask)):
        raise UserError(f"workers must be a process count, None (one per core) or a backend "
                         f"(glamas.parallel.Processes, Threads or Dask), got {workers!r}")
    return workers


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
