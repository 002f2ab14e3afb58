"""The gridworld of Fig. 9 solved exactly by dynamic programming on the joint MMDP: the yardstick of
Section 5.3's learners. :mod:`.experiment` configures and solves it, :mod:`.analysis` measures the
optimal and selfish episodes and :mod:`.plots` draws them; this face hands their names on
(:mod:`glamas.experiments.faces`) and registers it."""

from glamas.experiments.faces import face
from glamas.experiments.gridworld_optimum.analysis import claim_rows
from glamas.experiments.gridworld_optimum.experiment import GridworldOptimumConfig, GridworldOptimumResult, run
from glamas.experiments.registry import Experiment, register

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("gridworld_optimum", GridworldOptimumConfig, run,
                                 lambda runs, iterations: GridworldOptimumConfig(), 1, 1, GridworldOptimumResult,
                                 claim_rows=lambda result, config: claim_rows(result), figures=("fig9_optimum",),
                                 stored=False, map_field="map"))
"""The exact optimum of Fig. 9's map: computed in a second whenever it is needed, never stored."""
