"""2observe's coordination in a crowd (beyond the chapter): the benchmark of instances' 2observe runs
trained again from their seeds and their greedy episodes replayed with every joint state kept,
with the coordination on and off. :mod:`.experiment` configures and runs it, :mod:`.replay` plays
the episodes, :mod:`.analysis` measures them and :mod:`.plots` draws them; this face hands their
names on (the plots' on first use) and registers the experiment."""

from pathlib import Path

from glamas.experiments.crowd.analysis import effect, effects_table, per_instance, summary, table
from glamas.experiments.crowd.experiment import (COORDINATION, LEARNERS, MEASURES, CrowdConfig, CrowdResult,
                                                 greedy_episodes, run, scaled)
from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.registry import Experiment, register
from glamas.experiments.warehouses.experiment import WarehousesConfig
from glamas.paths import RESULTS

PLOTS = ("plot_crowd",)
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["COORDINATION", "EXPERIMENT", "LEARNERS", "MEASURES", "CrowdConfig", "CrowdResult", "effect",
           "effects_table", "greedy_episodes", "load", "per_instance", "run", "scaled", "summary", "table", *PLOTS]

EXPERIMENT = register(Experiment("crowd", CrowdConfig, run, scaled, WarehousesConfig.instances,
                                 WarehousesConfig.episodes, CrowdResult, figures=("crowd",), chapter=False,
                                 counts="episodes"))
"""2observe's coordination in a crowd (its result file is drawn by paper_figures/crowd.py; --runs
counts instances per N)."""


def load(config: CrowdConfig = CrowdConfig(), seed: int = 0, results_dir: Path = RESULTS) -> CrowdResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
