"""Memory a run will need, estimated from its configuration before anything is allocated.

The result and table arrays of every experiment have sizes known from the config (runs, points,
bins, the map's cells and agents): each experiment's configuration estimates them in its
``memory_bytes()``. :func:`check` compares the estimate with the memory available on this machine, so that a run too large for it stops with a message at once instead of failing
on an allocation (or filling the memory) later.
"""

import os

from glamas.errors import UserError

BYTES_PER_VALUE = 8  # float64 and int64 arrays
WORKING_COPIES = 2
"""The runner fills a copy of each job's slice of the outputs before writing it back."""


class MemoryEstimateError(UserError, MemoryError):
    """A run whose arrays would not fit in the memory available."""


def available_bytes() -> int:
    """Memory available to a new allocation: MemAvailable of /proc/meminfo, or the physical memory."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def check(config, copies: int = 1) -> int:
    """Raise :class:`MemoryEstimateError` if ``copies`` runs of ``config`` need more memory than is
    available; returns the estimate in bytes (``config.memory_bytes()``, which every experiment's
    configuration has: :class:`glamas.experiments.registry.Experiment` requires it)."""
    needed = int(config.memory_bytes()) * copies
    available = available_bytes()
    if needed > available:
        raise MemoryEstimateError(
            f"this run needs about {gib(needed)} for its arrays, more than the {gib(available)} of "
            "memory available; use fewer runs or iterations (--runs, --iterations) or a smaller map")
    return needed


def per_run(runs: int, values: int) -> int:
    """Bytes of ``runs`` runs that each fill ``values`` float64 or int64 values, with the runner's
    working copy of each."""
    return runs * values * BYTES_PER_VALUE * WORKING_COPIES


def gib(n_bytes: float) -> str:
    return f"{n_bytes / 2 ** 30:,.1f} GiB"
