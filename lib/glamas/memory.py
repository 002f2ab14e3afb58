"""Memory a run will need, estimated from its configuration before anything is allocated.

The result and table arrays of every experiment have sizes known from the config (runs, points,
bins, the map's cells and agents). :func:`check` compares the estimate with the memory available
on this machine, so that a run too large for it stops with a message at once instead of failing
on an allocation (or filling the memory) later.
"""

import os

BYTES_PER_VALUE = 8  # float64 and int64 arrays
WORKING_COPIES = 2
"""The runner fills a copy of each job's slice of the outputs before writing it back."""


class MemoryEstimateError(MemoryError):
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
    available; returns the estimate in bytes."""
    needed = estimate(config) * copies
    available = available_bytes()
    if needed > available:
        raise MemoryEstimateError(
            f"this run needs about {_gib(needed)} for its arrays, more than the {_gib(available)} of "
            "memory available; use fewer runs or iterations (--runs, --iterations) or a smaller map")
    return needed


def estimate(config) -> int:
    """Bytes of the arrays a run of ``config`` allocates (0 for a config without an estimate)."""
    from glamas.experiments import and_network, gridworld, gridworld_optimum, related_work, scaling, single_gla

    estimators = {single_gla.SingleGLAConfig: _single_gla, single_gla.EncodingConfig: _encodings,
                  and_network.ANDNetworkConfig: _and_network,
                  gridworld.GridworldConfig: _gridworld, related_work.RelatedWorkConfig: _related_work,
                  scaling.ScalingConfig: _scaling, gridworld_optimum.GridworldOptimumConfig: _gridworld_optimum}
    estimator = estimators.get(type(config))
    return 0 if estimator is None else int(estimator(config))


def _single_gla(config) -> int:
    per_run = config.record_points + 2 * 2 * 3  # reward curve, (agents, actions, longest context)
    return config.runs * per_run * BYTES_PER_VALUE * WORKING_COPIES


def _encodings(config) -> int:
    """One encoding of Fig. 6: experiment 1's arrays and the parameters at its checkpoints."""
    per_run = (config.checkpoints + 1) * 2 * 2 * 3  # the start and the checkpoints, parameters as above
    return _single_gla(config.experiment) + config.experiment.runs * per_run * BYTES_PER_VALUE * WORKING_COPIES


def _and_network(config) -> int:
    # P(L) curve and probe points per agent, (agents, units, unit actions, inputs) parameters
    per_run = 2 * config.record_points + 2 * config.probe_points + 2 * 2 * 2 * 3
    return config.runs * per_run * BYTES_PER_VALUE * WORKING_COPIES


def _gridworld(config) -> int:
    gridmap = config.gridmap()
    return config.runs * sum(_learner(name, config, gridmap, config.bins) for name in config.learners)


def _learner(name: str, settings, gridmap, bins: int) -> int:
    """Bytes one run of learner ``name`` allocates: its tables (working copies of them) and its log."""
    from glamas.learners import episode, registry

    tables = registry.get(name).bytes_per_run(settings, gridmap)
    return tables * WORKING_COPIES + bins * episode.n_columns(gridmap.n_agents) * BYTES_PER_VALUE


def _related_work(config) -> int:
    base = config.gridworld
    gridmap, settings = base.gridmap(), config.settings()
    related = base.runs * sum(_learner(name, settings, gridmap, base.bins) for name in config.learners)
    return _gridworld(base) + related


def _scaling(config) -> int:
    from glamas.experiments import scaling

    budget = config.memory_budget_gib * 2 ** 30
    # A run's tables live in the worker that fills it, one run per worker at a time: at most the
    # runs of the largest learner that fits the budget at once, whatever the number of workers.
    needs = [scaling.memory_needed(config, method, config.gridmap(n))
             for n in config.agents for method in config.methods]
    largest = max((need for need in needs if need <= budget), default=0)
    logs = len(config.methods) * len(config.agents) * config.runs * config.n_bins * len(scaling.METRICS)
    return largest * WORKING_COPIES + logs * BYTES_PER_VALUE


def _gridworld_optimum(config) -> int:
    from glamas.gridworld import load_map
    from glamas.paths import MAPS

    gridmap = load_map(MAPS / f"{config.map_name}.txt")
    n = gridmap.n_agents
    # glamas.gridworld.dp's tables per joint state and action: next state, reward, collisions,
    # each agent's reward (8 bytes) and bumped and reached flags (1 byte), and the Q values
    return gridmap.n_cells ** n * 4 ** n * (4 * BYTES_PER_VALUE + n * (BYTES_PER_VALUE + 2))


def _gib(n_bytes: float) -> str:
    return f"{n_bytes / 2 ** 30:,.1f} GiB"
