"""The scaling study (beyond the chapter): the Section 5.3 learners on warehouse maps of 2 to 6 agents,
and the study of many agents, 2 to 128 on generated warehouses. :mod:`.experiment` configures and runs
them, :mod:`.analysis` measures them (growth fits, claims, tables) and :mod:`.plots` draws them; this
face hands their names on (the plots' on first use) and registers both."""

from pathlib import Path

from glamas.experiments.faces import plots_on_first_use
from glamas.experiments.registry import Experiment, register
from glamas.experiments.scaling.analysis import (claim_rows, growth, growth_table, measure, performance_table,
                                                 pivot_table, plan_table, size_table, trap_table)
from glamas.experiments.scaling.experiment import (CHAPTER_METHODS, METHODS, RELATED_METHODS, ManyAgentsConfig,
                                                   ScalingConfig, ScalingResult, aisle_cells, label, many_agents_scaled,
                                                   check_trap, run, scaled, seed_of, trap)
from glamas.paths import RESULTS

PLOTS = ("plot_sizes", "plot_final", "plot_curves", "plot_greedy")
"""The drawing functions of :mod:`.plots` this face hands on."""
__getattr__ = plots_on_first_use(__name__, PLOTS)

__all__ = ["CHAPTER_METHODS", "EXPERIMENT", "MANY_AGENTS", "METHODS", "RELATED_METHODS", "ManyAgentsConfig",
           "ScalingConfig", "ScalingResult", "load_many_agents",
           "aisle_cells", "claim_rows", "growth", "growth_table", "label", "load", "measure", "performance_table",
           "check_trap", "pivot_table", "plan_table", "run", "seed_of", "size_table", "trap", "trap_table", *PLOTS]

EXPERIMENT = register(Experiment("scaling", ScalingConfig, run, scaled, ScalingConfig.runs, ScalingConfig.episodes,
                                 ScalingResult, claim_rows=lambda result, config: claim_rows(result),
                                 figures=("scaling_performance", "scaling_sizes"), chapter=False, map_field="map",
                                 counts="episodes"))
"""The scaling study (its result file is shared by the scaling_* figure scripts)."""


def load(config: ScalingConfig = ScalingConfig(), seed: int = 0, results_dir: Path = RESULTS) -> ScalingResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


MANY_AGENTS = register(Experiment("many_agents", ManyAgentsConfig, run, many_agents_scaled, ManyAgentsConfig.runs,
                                  ManyAgentsConfig.episodes, ScalingResult, figures=("many_agents",), chapter=False,
                                  map_field="map", counts="episodes"))
"""The study of many agents, 2 to 128 on generated warehouses (drawn by paper_figures/many_agents.py)."""


def load_many_agents(config: ManyAgentsConfig = ManyAgentsConfig(), seed: int = 0,
                     results_dir: Path = RESULTS) -> ScalingResult:
    """The committed (or ``results_dir``'s) study of many agents, its configuration checked."""
    return MANY_AGENTS.load(results_dir, config, seed)

