"""The gridworld experiment of Section 5.3 (Fig. 9-12): the chapter's four learners on TunnelToGoal.
:mod:`.experiment` configures and runs it, :mod:`.analysis` measures it (claims, tables, optimum) and
:mod:`.plots` draws it; this face hands their names on (:mod:`glamas.experiments.faces`) and registers it."""

from dataclasses import replace
from pathlib import Path

from glamas.experiments.faces import face
from glamas.experiments.gridworld.analysis import BOUNCE_READINGS, claim_rows
from glamas.experiments.gridworld.experiment import GridworldConfig, GridworldResult, run, scaled
from glamas.experiments.registry import SEED, Experiment, register
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("gridworld", GridworldConfig, run, scaled, result=GridworldResult,
                                 claim_rows=lambda result, config: claim_rows(result, other_bounce(config)),
                                 figures=("fig9", "fig10", "fig11a", "fig11b", "fig12a", "fig12b"), map_field="map",
                                 small_run={"runs": 2, "iterations": 300}, recompute_minutes=1))
"""The chapter's experiment of Section 5.3 (Fig. 9 and 10 draw its map and its GLAs' feedback)."""


def bounced_to_start(runs: int, episodes: int) -> GridworldConfig:
    """The chapter's experiment at ``runs`` and ``episodes`` with its literal bounce: collided agents
    go back to their start cell (Sec. 5.3, "bounced back to their original position")."""
    return replace(scaled(runs, episodes), bounce="start")


BOUNCE_START = register(Experiment("gridworld_bounce_start", GridworldConfig, run, bounced_to_start,
                                   result=GridworldResult, figures=("gridworld_bounce_start",), chapter=False,
                                   map_field="map", small_run={"runs": 2, "iterations": 300}, recompute_minutes=1))
"""The same experiment with the chapter's literal bounce, collided agents back at their start cell
(Sec. 5.3): a reading its claims are also judged under."""


def other_bounce(config: GridworldConfig, seed: int = SEED) -> dict:
    """The experiment under the literal bounce when ``config`` bounces to the previous cell (reading
    -> result; nothing otherwise): at paper scale the committed result (its configuration and
    provenance checked), else computed at ``config``'s scale from the same seed."""
    if config.bounce != "previous":
        return {}
    return {BOUNCE_READINGS["start"]: BOUNCE_START.committed_or_run(replace(config, bounce="start"), seed)}


def load(config: GridworldConfig = GridworldConfig(), seed: int = 0, results_dir: Path = RESULTS) -> GridworldResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)
