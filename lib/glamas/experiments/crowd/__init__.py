"""2observe's coordination in a crowd (beyond the chapter): the benchmark of instances' 2observe runs
trained again from their seeds and their greedy episodes replayed with every joint state kept,
with the coordination on and off. :mod:`.experiment` configures and runs it, :mod:`.replay` plays
the episodes, :mod:`.analysis` measures them and :mod:`.plots` draws them; this face hands their
names on (:mod:`glamas.experiments.faces`) and registers the experiment."""

from pathlib import Path

from glamas.experiments.crowd.experiment import CrowdConfig, CrowdResult, run, scaled
from glamas.experiments.faces import face
from glamas.experiments.registry import Experiment, register
from glamas.experiments.warehouses.experiment import WarehousesConfig
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("crowd", CrowdConfig, run, scaled, WarehousesConfig.instances,
                                 WarehousesConfig.episodes, CrowdResult, figures=("crowd",), chapter=False,
                                 counts="episodes", small_run={"runs": 1, "iterations": 5}, small_run_seconds=5,
                                 recompute_minutes=11))
"""2observe's coordination in a crowd (its result file is drawn by paper_figures/crowd.py; --runs
counts instances per N)."""


def load(config: CrowdConfig = CrowdConfig(), seed: int = 0, results_dir: Path = RESULTS) -> CrowdResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
