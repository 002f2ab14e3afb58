"""Experiment 1 of Section 4.2 (Fig. 5): one 2-action GLA per agent in the line world, joint context.
:mod:`.experiment` configures and runs it, :mod:`.analysis` measures it (expected rewards, best lines,
claims) and :mod:`.plots` draws it; this face hands their names on (:mod:`glamas.experiments.faces`)
and registers Fig. 5."""

from glamas.experiments.faces import face
from glamas.experiments.registry import Experiment, register
from glamas.experiments.single_gla.analysis import claim_rows
from glamas.experiments.single_gla.experiment import SingleGLAConfig, SingleGLAResult, run, scaled

__getattr__, __dir__ = face(__name__, __file__)

FIG5 = register(Experiment("single_gla", SingleGLAConfig, run, scaled, result=SingleGLAResult,
                           claim_rows=lambda result, config: claim_rows(result), figures=("fig5",),
                           to_arrays=SingleGLAResult.arrays, small_run={"runs": 2, "iterations": 2000},
                           small_run_seconds=3, recompute_minutes=0.5))
"""Fig. 5's experiment: experiment 1 with the joint context."""
