"""Fig. 10 as an inverse problem (beyond the chapter): 2observe under several readings of its lost GLA
feedback, each judged by Section 5.3's claims. :mod:`.experiment` configures and runs the readings,
:mod:`.analysis` judges them (summary, tables) and :mod:`.plots` draws them; this face hands their names
on (the plots' on first use) and registers the study."""

from pathlib import Path

from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.fig10_readings.analysis import coordinating_share, deltas, summary, table, verdict_table
from glamas.experiments.fig10_readings.experiment import READINGS, ReadingsConfig, ReadingsResult, run, scaled
from glamas.experiments.gridworld.experiment import GridworldConfig
from glamas.experiments.registry import Experiment, register
from glamas.paths import RESULTS

PLOTS = ("plot_coordination", "plot_collisions")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["EXPERIMENT", "READINGS", "ReadingsConfig", "ReadingsResult", "coordinating_share", "deltas", "load",
           "run", "summary", "table", "verdict_table", *PLOTS]

EXPERIMENT = register(Experiment("fig10_readings", ReadingsConfig, run, scaled, GridworldConfig.runs,
                                 GridworldConfig.episodes, ReadingsResult, figures=("fig10_readings",),
                                 chapter=False, map_field="gridworld.map", counts="episodes"))
"""The readings of Fig. 10 (no claims of its own: :func:`summary` judges each reading by Sec. 5.3's)."""


def load(config: ReadingsConfig = ReadingsConfig(), seed: int = 0, results_dir: Path = RESULTS) -> ReadingsResult:
    """The committed study of ``config`` (``results_dir/fig10_readings.npz``), its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
