"""The benchmark of instances measured: per formulation, N and learner, what its greedy policies
reach on the instances against each instance's plan, with 95 % intervals over the instances, when
its learning curves get there, and why agents stay out.

Every number is first a value per instance (the mean over its greedy episodes, or its learning
curve's last block), then the mean over instances with a bootstrap interval (instances resampled,
:func:`glamas.curves.mean_and_band`): the instances are the replicates.
"""

import math

import numpy as np

from glamas.curves import mean_and_band
from glamas.experiments.warehouses.experiment import HIGH_ISR, WarehousesResult
from glamas.learners import registry
from glamas.tables import Table

PLAN_COLUMNS = ("sum_of_costs", "makespan", "bound_sum_of_costs", "bound_makespan")
"""The columns of ``WarehousesResult.plans``."""
MEASURES = ("csr", "isr", "soc_ratio", "makespan_ratio", "collisions", "curve_csr", "curve_isr",
            "coordinations")
"""What :func:`per_instance` gives: the greedy episodes' CSR and ISR, their sum of costs and makespan
over the plan's (episodes in which every agent is in only), their collisions per episode, the
learning curve's CSR and ISR in its last block, and coordinations per agent-step of the greedy episodes."""


def per_instance(result: WarehousesResult, formulation: str, n: int, learner: str) -> dict:
    """Each of :data:`MEASURES` per instance (instances,); NaN where it is undefined (a ratio
    without a completed greedy episode) or the learner did not run."""
    g = {name: result.greedy_metric(formulation, n, learner, name) for name in
         ("completed", "in_goal", "sum_of_costs", "makespan", "collisions", "coordinations")}
    plan = result.plan(n).astype(float)
    done = g["completed"] == 1.0
    with np.errstate(invalid="ignore"):
        soc = np.where(done, g["sum_of_costs"] / plan[:, [0]], np.nan)
        makespan = np.where(done, g["makespan"] / plan[:, [1]], np.nan)
    return {"csr": g["completed"].mean(axis=1), "isr": g["in_goal"].mean(axis=1),
            "soc_ratio": _mean_of_finite(soc), "makespan_ratio": _mean_of_finite(makespan),
            "collisions": g["collisions"].mean(axis=1),
            "curve_csr": result.curve_metric(formulation, n, learner, "completed")[:, -1],
            "curve_isr": result.curve_metric(formulation, n, learner, "in_goal")[:, -1],
            "coordinations": g["coordinations"].sum(axis=1) / g["sum_of_costs"].sum(axis=1)}


def _mean_of_finite(values: np.ndarray) -> np.ndarray:
    """Per row, the mean of its finite values (NaN for a row without one)."""
    finite = np.isfinite(values)
    counts = finite.sum(axis=1)
    sums = np.where(finite, values, 0.0).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)


def interval(values: np.ndarray) -> tuple[float, float, float, int]:
    """(mean, 95 % low, high, instances) over the finite values of ``values`` (instances resampled);
    NaN with 0 instances where none is finite."""
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return math.nan, math.nan, math.nan, 0
    mean, low, high = mean_and_band(finite[:, None])
    return float(mean[0]), float(low[0]), float(high[0]), int(finite.size)


def summary(result: WarehousesResult, formulation: str, n: int, learner: str) -> dict | None:
    """Each of :data:`MEASURES` as :func:`interval` over the instances; None where the learner did
    not run."""
    if not result.ran[result.index(formulation, n, learner)]:
        return None
    return {name: interval(values) for name, values in per_instance(result, formulation, n, learner).items()}


def _cell(value: tuple, percent: bool) -> str:
    mean, low, high, count = value
    if count == 0:
        return "-"
    if percent:
        return f"{mean:.0%} [{low:.0%}, {high:.0%}]"
    return f"{_number(mean)} [{_number(low)}, {_number(high)}]"


def _number(value: float) -> str:
    """Two decimals, none from 100 on (collisions per episode run to thousands)."""
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.2f}"


COLUMNS = (("csr", "CSR", True), ("isr", "ISR", True), ("soc_ratio", "SoC / plan", False),
           ("makespan_ratio", "makespan / plan", False), ("collisions", "collisions", False),
           ("curve_isr", "ISR learning", True))
"""The columns of :func:`table`: measure, heading, shown as a percentage."""


def table(result: WarehousesResult, formulation: str) -> Table:
    """Per N and learner (rows): the greedy policies' CSR, ISR, sum of costs and makespan over the
    plan's (completed episodes only, '-' where none completed), collisions per episode, and the
    learning curve's ISR at its end; each the mean over instances with its 95 % interval; a learner
    whose tables exceed the memory budget is marked skipped."""
    rows = []
    for n in result.agents.tolist():
        for learner in result.names():
            found = summary(result, formulation, n, learner)
            cells = ["skipped"] + [""] * (len(COLUMNS) - 1) if found is None else \
                [_cell(found[key], percent) for key, _, percent in COLUMNS]
            rows.append([f"N = {n}, {registry.label(learner)}", *cells])
    return Table([f"{formulation} formulation", *(heading for _, heading, _ in COLUMNS)], rows)


def plans_table(result: WarehousesResult) -> Table:
    """Per N: the plans over the lower bounds (sum of costs and makespan, the mean over instances
    and the worst), and their mean sizes."""
    rows = []
    for n in result.agents.tolist():
        plan = result.plan(n).astype(float)
        soc, makespan = plan[:, 0] / plan[:, 2], plan[:, 1] / plan[:, 3]
        rows.append([n, plan.shape[0], f"{plan[:, 0].mean():.0f}", f"{soc.mean():.3f}", f"{soc.max():.3f}",
                     f"{plan[:, 1].mean():.1f}", f"{makespan.mean():.3f}", f"{makespan.max():.3f}"])
    return Table(["N", "instances", "plan SoC", "SoC / bound: mean", "worst", "plan makespan",
                  "makespan / bound: mean", "worst"], rows)


def reached_table(result: WarehousesResult, formulation: str) -> Table:
    """The budget axis: per learner and N, on how many instances the learning curve's ISR held
    HIGH_ISR over a window within the budget, and the median episodes it took there ('> budget'
    where no instance got there, '-' where the learner did not run)."""
    def cell(index) -> str:
        reached = result.reached[index]
        got = reached[reached >= 0]
        return f"{got.size}/{reached.size}: {int(np.median(got))}" if got.size else f"> {result.config.episodes}"
    return _by_learner_and_n(result, formulation, f"episodes to ISR >= {HIGH_ISR:.0%} ({formulation})", cell)


def causes_table(result: WarehousesResult, formulation: str) -> Table:
    """Why agents stay out: per learner and N, the share of the agents that the last greedy episode
    leaves short of their goal, and among those the share that never reached their goal in any
    training episode (their tables hold no value from it); means over instances."""
    def cell(index) -> str:
        never = result.never_in[index]
        never_text = f"{np.nanmean(never):.0%}" if np.isfinite(never).any() else "-"
        return f"{result.short[index].mean():.0%} / {never_text}"
    return _by_learner_and_n(result, formulation, f"agents out / never in while learning ({formulation})", cell)


def _by_learner_and_n(result: WarehousesResult, formulation: str, header: str, cell) -> Table:
    """A table of learners (rows) by N (columns): ``cell(index)`` of each (formulation, N, learner)
    index of the result's arrays, '-' where the learner did not run."""
    rows = [[registry.label(learner), *(cell(index) if result.ran[index] else "-"
                                        for index in (result.index(formulation, n, learner)
                                                      for n in result.agents.tolist()))]
            for learner in result.names()]
    return Table([header, *(f"N = {n}" for n in result.agents.tolist())], rows)


def coordination_table(result: WarehousesResult, learners: tuple = ("two_observe", "two_observe_rule",
                                                                      "independent")) -> Table:
    """2observe's coordination in a crowd: per formulation, N and learner of ``learners``,
    coordinations per agent-step of the greedy episodes beside their ISR (the independent learners,
    which never coordinate, as the reference)."""
    learners = [name for name in learners if name in result.names()]
    rows = []
    for formulation in result.formulations.tolist():
        for n in result.agents.tolist():
            found = [summary(result, formulation, n, learner) for learner in learners]
            rows.append([formulation, n, *("-" if f is None else f"{f['coordinations'][0]:.3f}, {f['isr'][0]:.0%}"
                                           for f in found)])
    return Table(["formulation", "N", *(f"{registry.label(name)}: coord., ISR" for name in learners)], rows)
