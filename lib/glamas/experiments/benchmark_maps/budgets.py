"""The benchmark's budget axis: every learner's greedy policy on every field map after each of
several numbers of training episodes, under each reward formulation.

The benchmark judges every learner at the field's 2000 episodes; the chapter trains 2observe for
200,000 (Sec. 5.3), and a learner that solves nothing at 2000 may need more, not fail. Each budget
is the benchmark itself (:func:`glamas.experiments.benchmark_maps.experiment.configured` at that
many episodes, the same seeds), so the runs of a budget are those of the benchmark at that
length: its first episodes are those of a shorter budget's runs, and a result's budget of 2000
equals the benchmark's result. Only what the greedy evaluations after training measure is kept.
"""

import math
from dataclasses import dataclass

import numpy as np

from glamas import checks, training
from glamas.errors import UserError
from glamas.experiments.benchmark_maps.analysis import SOLVED_COLLISIONS
from glamas.experiments.benchmark_maps.experiment import (FIELD_MAPS, FORMULATIONS, PLANS, BenchmarkConfig,
                                                          case_names, configured, optimal_plans)
from glamas.experiments.gridworld.analysis import COMPLETION
from glamas.experiments.scaling.experiment import METHODS, METRICS, sweep
from glamas.learners import registry
from glamas.tables import Table

DECADES = 3
"""Budgets of the axis at a command line's --iterations E: E / 100, E / 10 and E episodes."""


@dataclass(frozen=True)
class BudgetsConfig:
    """Settings of the budget axis: the formulations and budgets, and the benchmark's own settings
    that the axis keeps the same at every budget."""

    formulations: tuple = tuple(FORMULATIONS)
    """Reward formulations (the benchmark's FORMULATIONS), each with the learning settings it comes with."""
    budgets: tuple = (2_000, 20_000, 200_000)
    """Training episodes per run, increasing: the field's 2000 up to the chapter's 200,000 for 2observe."""
    maps: tuple = FIELD_MAPS
    """The maps: names in data/maps or map files' paths."""
    learners: tuple = METHODS
    """Learners to train: distinct names of registered learners."""
    runs: int = 10
    """Independent runs per (formulation, budget, learner, map)."""
    evaluation_episodes: int = 100
    """Episodes of each evaluation of what a run learned, learning off."""
    memory_budget_gib: float = 4.0
    """Memory the Q tables of all runs of one (learner, map) may take, in GiB (the benchmark's)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"runs": 1, "evaluation_episodes": 1})
        checks.distinct_names(self, "formulations", FORMULATIONS, "reward formulations")
        budgets = tuple(self.budgets)
        if not budgets or not all(isinstance(b, int) and not isinstance(b, bool) and b >= 1 for b in budgets) \
                or list(budgets) != sorted(set(budgets)):
            raise UserError(f"budgets must be increasing whole numbers of episodes >= 1, got {self.budgets!r}")
        object.__setattr__(self, "budgets", budgets)
        for formulation in self.formulations:
            self.benchmark(formulation, budgets[0])  # the benchmark's own checks: maps, learners, budget

    def benchmark(self, formulation: str, budget: int) -> BenchmarkConfig:
        """The benchmark of one point of the axis: ``formulation``'s settings, ``budget`` episodes."""
        return configured(formulation, episodes=budget, maps=self.maps, learners=self.learners, runs=self.runs,
                          evaluation_episodes=self.evaluation_episodes, memory_budget_gib=self.memory_budget_gib)

    def memory_bytes(self) -> int:
        """The largest benchmark of the axis (they run one after the other) and the evaluations kept."""
        kept = (len(self.formulations) * len(self.budgets) * len(self.learners) * len(self.maps) * self.runs
                * len(training.EVALUATIONS) * len(METRICS) * 8)
        return max(self.benchmark(f, b).memory_bytes() for f in self.formulations for b in self.budgets) + kept


@dataclass(frozen=True)
class BudgetsResult:
    """What every run learned at each point of the axis, evaluated with learning off."""

    config: BudgetsConfig
    """The configuration that produced the arrays."""
    formulations: np.ndarray
    """str (formulations,): the formulations' names."""
    budgets: np.ndarray
    """int (budgets,): training episodes per run."""
    learners: np.ndarray
    """str (learners,): the learners' names."""
    maps: np.ndarray
    """str (maps,): the maps' names."""
    ran: np.ndarray
    """bool (formulations, budgets, learners, maps): whether the learner ran (its tables fit the budget)."""
    evaluated: np.ndarray
    """(formulations, budgets, learners, maps, runs, evaluations, METRICS): each run's evaluations
    after training (glamas.training.EVALUATIONS); NaN where skipped."""
    plan_steps: np.ndarray
    """int (maps, PLANS, MAX_AGENTS): each agent's steps in each map's optimal plans (the benchmark's)."""

    def evaluation(self, formulation: str, budget: int, learner: str, map_name: str, metric: str,
                   mode: str = "greedy") -> np.ndarray:
        """(runs,): one of METRICS, or ``completion`` (1 - capped), under evaluation ``mode``."""
        index = (list(self.formulations).index(formulation), list(self.budgets).index(budget),
                 list(self.learners).index(learner), list(self.maps).index(map_name))
        rows = self.evaluated[index][:, training.EVALUATIONS.index(mode)]
        if metric == "completion":
            return np.clip(1.0 - rows[:, METRICS.index("capped")], 0.0, 1.0)
        return rows[:, METRICS.index(metric)]


def run(config: BudgetsConfig = BudgetsConfig(), seed: int = 0, workers=None, progress=None) -> BudgetsResult:
    """The benchmark's learners (:func:`glamas.experiments.scaling.experiment.sweep`) at every
    formulation and budget of ``config``, one benchmark after the other, with the benchmark's seeds."""
    shape = (len(config.formulations), len(config.budgets), len(config.learners), len(config.maps))
    ran = np.zeros(shape, dtype=bool)
    evaluated = np.full(shape + (config.runs, len(training.EVALUATIONS), len(METRICS)), np.nan)
    for f, formulation in enumerate(config.formulations):
        for b, budget in enumerate(config.budgets):
            benchmark = config.benchmark(formulation, budget)
            gridmaps = [benchmark.gridmap(name) for name in benchmark.maps]
            arrays = sweep(benchmark, gridmaps, [case_names(seed, name) for name in benchmark.maps], workers, progress)
            ran[f, b], evaluated[f, b] = arrays["ran"], arrays["evaluated"]
    first = config.benchmark(config.formulations[0], config.budgets[0])
    return BudgetsResult(config=config, formulations=np.array(config.formulations),
                         budgets=np.array(config.budgets, dtype=np.int64), learners=np.array(config.learners),
                         maps=np.array(config.maps), ran=ran, evaluated=evaluated,
                         plan_steps=optimal_plans([first.gridmap(name) for name in first.maps], first.bounce)[0])


def scaled(runs: int, episodes: int) -> BudgetsConfig:
    """The axis at ``runs`` and a largest budget of ``episodes``: :data:`DECADES` budgets a decade
    apart (fewer where ``episodes`` is small)."""
    budgets = sorted({max(1, episodes // 10 ** k) for k in range(DECADES)})
    return BudgetsConfig(runs=runs, budgets=tuple(budgets))


def greedy(result: BudgetsResult, formulation: str, budget: int, learner: str, map_name: str) -> dict:
    """What one learner's greedy policy does on one map after ``budget`` episodes (means over runs):
    its completion, its collisions per episode, its agents' steps summed over the least sum of costs
    (NaN for a policy that does not complete), and whether it is a collision-free solution (it
    completes, COMPLETION, with at most SOLVED_COLLISIONS collisions per episode); None where the
    learner did not run."""
    index = (list(result.formulations).index(formulation), list(result.budgets).index(budget),
             list(result.learners).index(learner), list(result.maps).index(map_name))
    if not result.ran[index]:
        return None
    completion = float(result.evaluation(formulation, budget, learner, map_name, "completion").mean())
    collisions = float(result.evaluation(formulation, budget, learner, map_name, "collisions").mean())
    plan = result.plan_steps[index[3], PLANS.index("sum_of_costs")]
    agents = plan[plan >= 0] if (plan >= 0).any() else None
    steps = float(result.evaluation(formulation, budget, learner, map_name, "steps").mean())
    completes = completion >= COMPLETION
    return {"completion": completion, "collisions": collisions,
            "cost_ratio": steps * agents.size / agents.sum() if completes and agents is not None else math.nan,
            "solved": completes and collisions <= SOLVED_COLLISIONS}


def needed(result: BudgetsResult, formulation: str, learner: str, map_name: str) -> int | None:
    """The least budget after which the learner's greedy policy is a collision-free solution of the
    map (:func:`greedy`), None where no budget of the axis gets there (or it did not run)."""
    for budget in result.budgets.tolist():
        case = greedy(result, formulation, budget, learner, map_name)
        if case is not None and case["solved"]:
            return budget
    return None


def needed_table(result: BudgetsResult, formulation: str) -> Table:
    """Learners (rows) by maps (columns): the episodes each needs (:func:`needed`); '> cap' where
    the largest budget is not enough, '-' where the learner's tables exceed the memory budget."""
    maps, cap = list(map(str, result.maps)), int(result.budgets[-1])

    def cell(learner, map_name):
        budget = needed(result, formulation, learner, map_name)
        if budget is not None:
            return f"{budget:,}"
        return f"> {cap:,}" if greedy(result, formulation, cap, learner, map_name) is not None else "-"
    return Table([f"episodes needed ({formulation})", *maps],
                 [[registry.label(learner), *(cell(learner, map_name) for map_name in maps)]
                  for learner in map(str, result.learners)])


def solved_counts(result: BudgetsResult, formulation: str) -> np.ndarray:
    """int (learners, budgets): the maps each learner's greedy policy solves after each budget."""
    def solves(budget, learner, map_name):
        case = greedy(result, formulation, budget, learner, map_name)
        return case is not None and case["solved"]
    return np.array([[sum(solves(budget, learner, map_name) for map_name in map(str, result.maps))
                      for budget in result.budgets.tolist()] for learner in map(str, result.learners)])
