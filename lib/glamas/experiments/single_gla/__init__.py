"""Experiment 1 of Section 4.2 (Fig. 5): one 2-action GLA per agent in the line world, joint context.
:mod:`.experiment` configures and runs it, :mod:`.analysis` measures it (expected rewards, best lines,
claims) and :mod:`.plots` draws it; this face hands their names on (the plots' on first use), registers Fig. 5."""

from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.registry import Experiment, register
from glamas.experiments.single_gla.analysis import (B_BEST_LINE_OFFSETS, REGIONS, best_actions, best_line_reward,
                                                    best_lines_region_shares, best_response_gap, claim_rows,
                                                    evaluate, learned_line, measure, team_reward, typical_run)
from glamas.experiments.single_gla.experiment import SingleGLAConfig, SingleGLAResult, run, scaled

PLOTS = ("plot_regions", "plot_learned_lines", "plot_reward_curves")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["B_BEST_LINE_OFFSETS", "FIG5", "REGIONS", "SingleGLAConfig", "SingleGLAResult", "best_actions",
           "best_line_reward", "best_lines_region_shares", "best_response_gap", "claim_rows", "evaluate",
           "learned_line", "measure", "run", "scaled", "team_reward", "typical_run", *PLOTS]

FIG5 = register(Experiment(
    "single_gla", SingleGLAConfig, run, scaled, SingleGLAConfig.runs, SingleGLAConfig.iterations, SingleGLAResult,
    claim_rows=lambda result, config: claim_rows(result), figures=("fig5",), to_arrays=SingleGLAResult.arrays))
"""Fig. 5's experiment: experiment 1 with the joint context."""
