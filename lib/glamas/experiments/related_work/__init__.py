"""The related-work learners, sparse tabular MAQ and CQ-learning, beside the chapter's on TunnelToGoal
(a Fig. 11/12-style comparison). :mod:`.experiment` configures and runs it, :mod:`.analysis` measures it
(what each learner stores, claims, table) and :mod:`.plots` draws it; this face hands their names on
(:mod:`glamas.experiments.faces`) and registers it."""

from pathlib import Path

from glamas.experiments.faces import face
from glamas.experiments.registry import Experiment, register
from glamas.experiments.related_work.analysis import claim_rows
from glamas.experiments.related_work.experiment import RelatedWorkConfig, RelatedWorkResult, run, scaled
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("related_work", RelatedWorkConfig, run, scaled, result=RelatedWorkResult,
                                 claim_rows=claim_rows,
                                 figures=("related_collisions", "related_coordinations", "related_reward",
                                          "related_sizes", "related_steps"), chapter=False, map_field="map",
                                 small_run={"runs": 2, "iterations": 300}, recompute_minutes=1))
"""The related-work comparison (its result file is shared by the related_* figure scripts)."""


def load(config: RelatedWorkConfig | None = None, seed: int = 0, results_dir: Path = RESULTS) -> RelatedWorkResult:
    """The committed (or ``results_dir``'s) result of ``config`` (None: the comparison's defaults)
    and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, RelatedWorkConfig() if config is None else config, seed)
