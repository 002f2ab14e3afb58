"""The sparse-interaction benchmark (beyond the chapter): every learner on the field's maps against
each map's exact optimum. :mod:`.experiment` configures and runs it, :mod:`.analysis` measures it
(claims, tables), :mod:`.budgets` repeats it at several numbers of training episodes and
:mod:`.plots` draws them; this face hands their names on (:mod:`glamas.experiments.faces`) and
registers the benchmark under each formulation and its budget axis."""

from pathlib import Path

from glamas.experiments.benchmark_maps import budgets
from glamas.experiments.benchmark_maps.analysis import claim_rows, field_claim_rows
from glamas.experiments.benchmark_maps.experiment import BenchmarkConfig, BenchmarkResult, configured, field_scaled, run, scaled
from glamas.experiments.faces import face
from glamas.experiments.registry import Experiment, register
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

# Small runs: the budget leaves out the joint learners' tables of TunnelToGoal with 3 agents (85 MB a
# run, which the evaluations would copy for most of the time); the field's formulation and the budget
# axis run the same kernels on a two-agent map and TunnelToGoal 4 only, since the exact plans of
# TunnelToGoal 3, which the benchmark's own small run computes, took most of their time.
EXPERIMENT = register(Experiment("benchmark_maps", BenchmarkConfig, run, scaled, result=BenchmarkResult,
                                 claim_rows=claim_rows,
                                 figures=("benchmark_maps_curves", "benchmark_maps_optimum", "benchmark_maps_plans",
                                          "benchmark_maps_table"), chapter=False,
                                 small_run={"runs": 2, "iterations": 100, "evaluation_episodes": 5,
                                            "memory_budget_gib": 0.1},
                                 small_run_seconds=12, recompute_minutes=1))
"""The benchmark on the field's maps (its result file is shared by the benchmark_maps_* figure scripts)."""
FIELD_EXPERIMENT = register(Experiment("benchmark_maps_field", BenchmarkConfig, run, field_scaled,
                                       result=BenchmarkResult, claim_rows=field_claim_rows,
                                       figures=("benchmark_maps_field_table",), chapter=False,
                                       small_run={"runs": 2, "iterations": 100, "evaluation_episodes": 5,
                                                  "memory_budget_gib": 0.1, "maps": ("isr", "tunnel_to_goal_4")},
                                       recompute_minutes=0.5))
"""The same benchmark under the field's reward formulation and learning settings (``configured("field")``)."""
BUDGETS_EXPERIMENT = register(Experiment("benchmark_maps_budgets", budgets.BudgetsConfig, budgets.run, budgets.scaled,
                                         iterations=budgets.BudgetsConfig.budgets[-1], result=budgets.BudgetsResult,
                                         figures=("benchmark_maps_budgets",), chapter=False, counts="episodes",
                                         small_run={"runs": 1, "iterations": 100, "evaluation_episodes": 5,
                                                    "memory_budget_gib": 0.1, "maps": ("isr", "tunnel_to_goal_4")},
                                         recompute_minutes=14))
"""The benchmark's budget axis (:mod:`.budgets`): the greedy policies after 2,000 to 200,000 episodes."""


def load(config: BenchmarkConfig = BenchmarkConfig(), seed: int = 0, results_dir: Path = RESULTS) -> BenchmarkResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


def load_field(config: BenchmarkConfig | None = None, seed: int = 0, results_dir: Path = RESULTS) -> BenchmarkResult:
    """The committed (or ``results_dir``'s) result under the field's formulation (default:
    ``configured("field")``), its configuration checked."""
    return FIELD_EXPERIMENT.load(results_dir, configured("field") if config is None else config, seed)


def load_budgets(config: budgets.BudgetsConfig = budgets.BudgetsConfig(), seed: int = 0,
                 results_dir: Path = RESULTS) -> budgets.BudgetsResult:
    """The committed (or ``results_dir``'s) budget axis, its configuration checked."""
    return BUDGETS_EXPERIMENT.load(results_dir, config, seed)
