"""The related-work learners, sparse tabular MAQ and CQ-learning, beside the chapter's on TunnelToGoal
(a Fig. 11/12-style comparison). :mod:`.experiment` configures and runs it, :mod:`.analysis` measures it
(what each learner stores, claims, table) and :mod:`.plots` draws it; this face hands their names on (the
plots' on first use) and registers it."""

from pathlib import Path

from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.gridworld.experiment import GridworldConfig
from glamas.experiments.registry import Experiment, register
from glamas.experiments.related_work.analysis import (claim_rows, fewest_flagged_collisions, final_interval,
                                                      marked_distances, measure, summary_table, usable_joint_states)
from glamas.experiments.related_work.experiment import (CHAPTER_LEARNERS, RELATED_LEARNERS, RelatedWorkConfig,
                                                        RelatedWorkResult, run, scaled)
from glamas.paths import RESULTS

PLOTS = ("plot_curve", "note_cq_solo_phase", "plot_coordinations", "plot_size_and_reward", "plot_marked_distances")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["CHAPTER_LEARNERS", "EXPERIMENT", "RELATED_LEARNERS", "RelatedWorkConfig", "RelatedWorkResult",
           "claim_rows", "fewest_flagged_collisions", "final_interval", "load", "marked_distances",
           "measure", "run", "summary_table", "usable_joint_states", *PLOTS]

EXPERIMENT = register(Experiment("related_work", RelatedWorkConfig, run, scaled, GridworldConfig.runs,
                                 GridworldConfig.episodes, RelatedWorkResult, claim_rows=claim_rows,
                                 figures=("related_collisions", "related_coordinations", "related_reward",
                                          "related_sizes", "related_steps"), chapter=False, map_field="map",
                                 counts="episodes", to_arrays=RelatedWorkResult.to_arrays,
                                 from_arrays=RelatedWorkResult.from_arrays))
"""The related-work comparison (its result file is shared by the related_* figure scripts)."""


def load(config: RelatedWorkConfig | None = None, seed: int = 0, results_dir: Path = RESULTS) -> RelatedWorkResult:
    """The committed (or ``results_dir``'s) result of ``config`` (None: the comparison's defaults)
    and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, RelatedWorkConfig() if config is None else config, seed)
