"""Fig. 10 as an inverse problem (beyond the chapter): 2observe under several readings of its lost GLA
feedback, each judged by Section 5.3's claims. :mod:`.experiment` configures and runs the readings,
:mod:`.analysis` judges them (summary, tables) and :mod:`.plots` draws them; this face hands their names
on (:mod:`glamas.experiments.faces`) and registers the study."""

from pathlib import Path

from glamas.experiments.faces import face
from glamas.experiments.fig10_readings.experiment import ReadingsConfig, ReadingsResult, run, scaled
from glamas.experiments.gridworld.experiment import GridworldConfig
from glamas.experiments.registry import Experiment, register
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("fig10_readings", ReadingsConfig, run, scaled, GridworldConfig.runs,
                                 GridworldConfig.episodes, ReadingsResult, figures=("fig10_readings",),
                                 chapter=False, map_field="gridworld.map", counts="episodes",
                                 small_run={"runs": 2, "iterations": 300}, recompute_minutes=1))
"""The readings of Fig. 10 (no claims of its own: :func:`summary` judges each reading by Sec. 5.3's)."""


def load(config: ReadingsConfig = ReadingsConfig(), seed: int = 0, results_dir: Path = RESULTS) -> ReadingsResult:
    """The committed study of ``config`` (``results_dir/fig10_readings.npz``), its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
