"""The gridworld experiment of Section 5.3 (Fig. 9-12): the chapter's four learners on TunnelToGoal.
:mod:`.experiment` configures and runs it, :mod:`.analysis` measures it (claims, tables, optimum) and
:mod:`.plots` draws it; this face hands their names on (the plots' on first use) and registers it."""

from dataclasses import replace
from pathlib import Path

from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.gridworld.analysis import (BOUNCE_READINGS, claim_rows, convergence_comparison,
                                                   convergence_report, convergence_spread, coordination_probability,
                                                   curve_collision_claims, evaluation_table, in_range_share,
                                                   measure, need_probability, optimum, state_action_spaces,
                                                   state_action_table, stuck_by_start, summary_table, with_learner,
                                                   zero_collisions_table)
from glamas.experiments.gridworld.experiment import (CHAPTER_LEARNERS, GridworldConfig, GridworldResult, learner_bytes,
                                                     result_of, run, scaled, seed_of, trainings)
from glamas.experiments.registry import SEED, Experiment, register
from glamas.paths import RESULTS

PLOTS = ("plot_steps", "plot_reward", "plot_collisions", "plot_coordinations", "plot_feedback_table",
         "plot_coordination_probability", "step_ticks", "collision_levels")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["BOUNCE_READINGS", "BOUNCE_START", "CHAPTER_LEARNERS", "EXPERIMENT", "GridworldConfig", "GridworldResult",
           "claim_rows", "convergence_comparison", "convergence_report", "convergence_spread", "coordination_probability",
           "curve_collision_claims", "evaluation_table", "in_range_share",
           "learner_bytes", "load", "measure", "need_probability", "optimum", "other_bounce", "result_of",
           "run", "seed_of", "state_action_spaces", "state_action_table", "stuck_by_start", "summary_table", "trainings",
           "with_learner", "zero_collisions_table", *PLOTS]

EXPERIMENT = register(Experiment("gridworld", GridworldConfig, run, scaled, GridworldConfig.runs,
                                 GridworldConfig.episodes, GridworldResult,
                                 claim_rows=lambda result, config: claim_rows(result, other_bounce(config)),
                                 figures=("fig9", "fig10", "fig11a", "fig11b", "fig12a", "fig12b"), map_field="map",
                                 counts="episodes", to_arrays=GridworldResult.to_arrays,
                                 from_arrays=GridworldResult.from_arrays))
"""The chapter's experiment of Section 5.3 (Fig. 9 and 10 draw its map and its GLAs' feedback)."""
def bounced_to_start(runs: int, episodes: int) -> GridworldConfig:
    """The chapter's experiment at ``runs`` and ``episodes`` with its literal bounce: collided agents
    go back to their start cell (Sec. 5.3, "bounced back to their original position")."""
    return replace(scaled(runs, episodes), bounce="start")


BOUNCE_START = register(Experiment("gridworld_bounce_start", GridworldConfig, run, bounced_to_start,
                                   GridworldConfig.runs, GridworldConfig.episodes, GridworldResult,
                                   figures=("gridworld_bounce_start",), chapter=False, map_field="map",
                                   counts="episodes", to_arrays=GridworldResult.to_arrays,
                                   from_arrays=GridworldResult.from_arrays))
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

