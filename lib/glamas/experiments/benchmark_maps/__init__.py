"""The sparse-interaction benchmark (beyond the chapter): every learner on the field's maps against
each map's exact optimum. :mod:`.experiment` configures and runs it, :mod:`.analysis` measures it
(claims, tables), :mod:`.budgets` repeats it at several numbers of training episodes and
:mod:`.plots` draws them; this face hands their names on (the plots' on first use) and registers
the benchmark under each formulation and its budget axis."""

from pathlib import Path

from glamas.experiments.benchmark_maps import budgets
from glamas.experiments.benchmark_maps.analysis import (claim_rows, excess_grid, field_claim_rows, formulations_table,
                                                        margin_table, measure, optimum_table, plans_table, push_margin,
                                                        solved_table, table)
from glamas.experiments.benchmark_maps.experiment import (FIELD_MAPS, FORMULATIONS, PLANS, BenchmarkConfig,
                                                          BenchmarkResult, case_names, configured, field_scaled, run,
                                                          scaled)
from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.registry import Experiment, register
from glamas.paths import RESULTS

PLOTS = ("plot_table", "plot_curves", "plot_optimum", "plot_plan", "plot_budgets", "map_panels", "map_title")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["BUDGETS_EXPERIMENT", "EXPERIMENT", "FIELD_EXPERIMENT", "FIELD_MAPS", "FORMULATIONS", "PLANS",
           "BenchmarkConfig", "BenchmarkResult", "budgets", "case_names", "claim_rows", "configured", "excess_grid",
           "field_claim_rows", "field_scaled", "formulations_table", "load", "load_budgets", "load_field",
           "margin_table", "measure", "optimum_table", "plans_table", "push_margin", "run", "scaled",
           "solved_table", "table", *PLOTS]

EXPERIMENT = register(Experiment("benchmark_maps", BenchmarkConfig, run, scaled, BenchmarkConfig.runs,
                                 BenchmarkConfig.episodes, BenchmarkResult, claim_rows=claim_rows,
                                 figures=("benchmark_maps_curves", "benchmark_maps_optimum", "benchmark_maps_plans",
                                          "benchmark_maps_table"),
                                 chapter=False, counts="episodes"))
"""The benchmark on the field's maps (its result file is shared by the benchmark_maps_* figure scripts)."""
FIELD_EXPERIMENT = register(Experiment("benchmark_maps_field", BenchmarkConfig, run, field_scaled, BenchmarkConfig.runs,
                                       BenchmarkConfig.episodes, BenchmarkResult, claim_rows=field_claim_rows,
                                       figures=("benchmark_maps_field_table",), chapter=False, counts="episodes"))
"""The same benchmark under the field's reward formulation and learning settings (``configured("field")``)."""
BUDGETS_EXPERIMENT = register(Experiment("benchmark_maps_budgets", budgets.BudgetsConfig, budgets.run, budgets.scaled,
                                         budgets.BudgetsConfig.runs, budgets.BudgetsConfig.budgets[-1],
                                         budgets.BudgetsResult, figures=("benchmark_maps_budgets",), chapter=False,
                                         counts="episodes"))
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
