"""Many agents against a plan (beyond the chapter): every learner on many generated warehouses per
number of agents, under both reward formulations, beside a reference plan of each instance.
:mod:`.experiment` configures and runs it, :mod:`.analysis` measures it and :mod:`.plots` draws
it; this face hands their names on (the plots' on first use) and registers the experiment."""

from pathlib import Path

from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.registry import Experiment, register
from glamas.experiments.warehouses.analysis import (causes_table, coordination_table, per_instance, plans_table,
                                                    reached_table, summary, table)
from glamas.experiments.warehouses.experiment import (CURVE, GREEDY, LEARNERS, WarehousesConfig, WarehousesResult,
                                                      run, scaled, seed_of)
from glamas.paths import RESULTS

PLOTS = ("plot_greedy", "plot_curves")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["CURVE", "EXPERIMENT", "GREEDY", "LEARNERS", "WarehousesConfig", "WarehousesResult", "causes_table",
           "coordination_table", "load", "per_instance", "plans_table", "reached_table", "run", "scaled", "seed_of", "summary", "table", *PLOTS]

EXPERIMENT = register(Experiment("warehouses", WarehousesConfig, run, scaled, WarehousesConfig.instances,
                                 WarehousesConfig.episodes, WarehousesResult, figures=("warehouses",),
                                 chapter=False, counts="episodes"))
"""Many agents against a plan (its result file is drawn by paper_figures/warehouses.py; --runs counts
instances per N)."""


def load(config: WarehousesConfig = WarehousesConfig(), seed: int = 0, results_dir: Path = RESULTS) -> WarehousesResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
