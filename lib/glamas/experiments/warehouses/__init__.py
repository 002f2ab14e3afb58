"""Many agents against a plan (beyond the chapter): every learner on many generated warehouses per
number of agents, under both reward formulations, beside a reference plan of each instance.
:mod:`.experiment` configures and runs it, :mod:`.analysis` measures it and :mod:`.plots` draws
it; this face hands their names on (:mod:`glamas.experiments.faces`) and registers the experiment."""

from pathlib import Path

from glamas.experiments.faces import face
from glamas.experiments.registry import Experiment, register
from glamas.experiments.warehouses.experiment import WarehousesConfig, WarehousesResult, run, scaled
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("warehouses", WarehousesConfig, run, scaled, WarehousesConfig.instances,
                                 result=WarehousesResult, figures=("warehouses",), chapter=False,
                                 small_run={"runs": 2, "iterations": 100, "agents": (3, 8), "evaluation_episodes": 2,
                                            "max_steps": 200},
                                 small_run_seconds=7, recompute_minutes=24))
"""Many agents against a plan (its result file is drawn by paper_figures/warehouses.py; --runs counts
instances per N)."""


def load(config: WarehousesConfig = WarehousesConfig(), seed: int = 0, results_dir: Path = RESULTS) -> WarehousesResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
