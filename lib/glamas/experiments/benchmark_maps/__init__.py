"""The sparse-interaction benchmark (beyond the chapter): every learner on the field's maps against
each map's exact optimum. :mod:`.experiment` configures and runs it, :mod:`.analysis` measures it
(claims, tables) and :mod:`.plots` draws it; this face hands their names on (the plots' on first
use) and registers it."""

from pathlib import Path

from glamas.experiments.benchmark_maps.analysis import (claim_rows, excess_grid, measure, optimum_table, solved_table,
                                                        table)
from glamas.experiments.benchmark_maps.experiment import (FIELD_MAPS, BenchmarkConfig, BenchmarkResult, run, scaled,
                                                          seed_key)
from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.registry import Experiment, register
from glamas.paths import RESULTS

PLOTS = ("plot_table", "plot_curves", "plot_optimum")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["EXPERIMENT", "FIELD_MAPS", "BenchmarkConfig", "BenchmarkResult", "claim_rows", "excess_grid", "load",
           "measure", "optimum_table", "run", "scaled", "seed_key", "solved_table", "table", *PLOTS]

EXPERIMENT = register(Experiment("benchmark_maps", BenchmarkConfig, run, scaled, BenchmarkConfig.runs,
                                 BenchmarkConfig.episodes, BenchmarkResult, claim_rows=claim_rows,
                                 figures=("benchmark_maps_curves", "benchmark_maps_optimum", "benchmark_maps_table"),
                                 chapter=False))
"""The benchmark on the field's maps (its result file is shared by the benchmark_maps_* figure scripts)."""


def load(config: BenchmarkConfig = BenchmarkConfig(), seed: int = 0, results_dir: Path = RESULTS) -> BenchmarkResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
