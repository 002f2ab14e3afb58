"""The crowd replay measured: per formulation, N and 2observe learner, what the greedy episodes
reach with the coordination on and off, how often the crowd comes back to a joint state, and how
often the coordination makes an agent yield. Every number is first a mean per instance (over its
greedy episodes), then the mean over instances with a 95 % interval (instances resampled)."""

from glamas.experiments.crowd.experiment import COORDINATION, MEASURES, CrowdResult
from glamas.experiments.warehouses.analysis import interval
from glamas.learners import registry
from glamas.tables import Table


def per_instance(result: CrowdResult, formulation: str, n: int, learner: str, coordination: str) -> dict:
    """Each of MEASURES, the mean over each instance's greedy episodes (instances,)."""
    return {name: result.measure(formulation, n, learner, coordination, name).mean(axis=1) for name in MEASURES}


def summary(result: CrowdResult, formulation: str, n: int, learner: str, coordination: str) -> dict:
    """Each of MEASURES as (mean, 95 % low, high, instances) over the instances."""
    return {name: interval(values) for name, values in per_instance(result, formulation, n, learner,
                                                                      coordination).items()}


COLUMNS = (("in_goal", "ISR"), ("completed", "CSR"), ("revisits", "revisits"), ("yields", "yields"))
"""The columns of :func:`table`: measure and heading, each a percentage."""


def table(result: CrowdResult, formulation: str) -> Table:
    """Per N, learner and coordination (rows): the greedy episodes' ISR and CSR, the share of steps
    that come back to a joint state (revisits) and of agent-steps on which the coordination
    replaced the preferred action (yields); each the mean over instances with its 95 % interval."""
    rows = [[f"N = {n}, {registry.label(learner)}, coord. {coordination}",
             *(_percent(summary(result, formulation, n, learner, coordination)[key]) for key, _ in COLUMNS)]
            for n in result.agents.tolist() for learner in result.names() for coordination in COORDINATION]
    return Table([f"{formulation} formulation", *(heading for _, heading in COLUMNS)], rows)


def _percent(value: tuple) -> str:
    mean, low, high, _ = value
    return f"{mean:.0%} [{low:.0%}, {high:.0%}]"


def effect(result: CrowdResult, formulation: str, n: int, learner: str, name: str = "in_goal") -> tuple:
    """What switching the coordination on does to ``name``, per instance: (on - off) as
    (mean, 95 % low, high, instances) over the instances (the same tables replayed both ways)."""
    on, off = (per_instance(result, formulation, n, learner, c)[name] for c in COORDINATION)
    return interval(on - off)


def effects_table(result: CrowdResult) -> str:
    """Per formulation, N and learner: the coordination's effect on ISR and on revisits (on - off,
    :func:`effect`), in percentage points."""
    lines = [f"{'formulation':12s} {'N':>5s} {'learner':24s} {'ISR on - off':>24s} {'revisits on - off':>24s}"]
    for formulation in result.formulations.tolist():
        for n in result.agents.tolist():
            for learner in result.names():
                cells = [_points(effect(result, formulation, n, learner, name)) for name in ("in_goal", "revisits")]
                lines.append(f"{formulation:12s} {n:5d} {registry.label(learner):24s}"
                             + "".join(f"{cell:>24s}" for cell in cells))
    return "\n".join(lines)


def _points(value: tuple) -> str:
    mean, low, high = (100 * v for v in value[:3])
    return f"{mean:+.1f} [{low:+.1f}, {high:+.1f}]"
