"""The scaling study (beyond the chapter): the Section 5.3 learners on warehouse maps of 2 to 6 agents,
and the study of many agents, 2 to 128 on generated warehouses. :mod:`.experiment` configures and runs
them, :mod:`.analysis` measures them (growth fits, claims, tables) and :mod:`.plots` draws them; this
face hands their names on (:mod:`glamas.experiments.faces`) and registers both."""

from pathlib import Path

from glamas.experiments.faces import face
from glamas.experiments.registry import Experiment, register
from glamas.experiments.scaling.analysis import claim_rows
from glamas.experiments.scaling.experiment import ManyAgentsConfig, ScalingConfig, ScalingResult, many_agents_scaled, run, scaled
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

EXPERIMENT = register(Experiment("scaling", ScalingConfig, run, scaled, result=ScalingResult,
                                 claim_rows=lambda result, config: claim_rows(result),
                                 figures=("scaling_performance", "scaling_sizes"), chapter=False, map_field="map",
                                 small_run={"runs": 1, "iterations": 100, "agents": (2, 3), "evaluation_episodes": 5},
                                 recompute_minutes=2))
"""The scaling study (its result file is shared by the scaling_* figure scripts)."""


def load(config: ScalingConfig = ScalingConfig(), seed: int = 0, results_dir: Path = RESULTS) -> ScalingResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


MANY_AGENTS = register(Experiment("many_agents", ManyAgentsConfig, run, many_agents_scaled, result=ScalingResult,
                                  figures=("many_agents",), chapter=False, map_field="map",
                                  # 20 episodes, not 10, so that sparse MAQ's values reach its discount (make mutations)
                                  small_run={"runs": 1, "iterations": 20, "agents": (2, 8, 32), "evaluation_episodes": 2,
                                             "max_steps": 200},
                                  small_run_seconds=2, recompute_minutes=1))
"""The study of many agents, 2 to 128 on generated warehouses (drawn by paper_figures/many_agents.py)."""


def load_many_agents(config: ManyAgentsConfig = ManyAgentsConfig(), seed: int = 0,
                     results_dir: Path = RESULTS) -> ScalingResult:
    """The committed (or ``results_dir``'s) study of many agents, its configuration checked."""
    return MANY_AGENTS.load(results_dir, config, seed)
