"""2observe's coordination in a crowd (beyond the chapter): what its second level does with many agents.

The benchmark of instances (:mod:`glamas.experiments.warehouses`) keeps what each greedy episode
measures, not its path, so it cannot say whether 2observe's coordination itself holds agents back.
Here 2observe's runs of that benchmark (and its fixed rule's) are trained again from their own
seeds (:func:`glamas.experiments.warehouses.seed_of`: the same streams, so the same tables) and
their greedy episodes played again with every joint state kept (:func:`.replay.replay`, the same
steps and draws as the benchmark's evaluation), twice: with the coordination as learned, and with
it switched off on the same tables (every agent acts on its preferred action). Per greedy episode:
CSR and ISR, the episode's length and collisions, the share of its steps that bring the crowd back
to a joint state it was in before (revisits; with the coordination's random order and yields a
revisit need not become a cycle, but the crowd made no net progress between the two visits), and
the share of acting agent-steps on which the coordination replaced an agent's preferred action
(yields). What the coordination does is the difference between the two replays of the same tables.
"""

from dataclasses import dataclass, field, replace

import numpy as np

from glamas import memory, parallel, rng, training
from glamas.errors import UserError
from glamas.experiments.crowd.replay import replay, revisits
from glamas.experiments.warehouses.experiment import (GREEDY, WarehousesConfig, greedy_rows, scaled as warehouses_scaled,
                                                      seed_of)
from glamas.gridworld import GridMap
from glamas.learners import episode as ep
from glamas.learners import registry, two_observe

LEARNERS = ("two_observe", "two_observe_rule")
"""2observe with its learned first level (its GLAs) and with the fixed rule "coordinate when delta < 3"."""
COORDINATION = ("on", "off")
"""The two replays of the same tables: the coordination as learned, and switched off."""
MEASURES = ("completed", "in_goal", "length", "collisions", "revisits", "yields")
"""Per greedy episode: 1 if every agent is in, the share of agents in (ISR), the episode's length
and collisions, the share of its steps ending in a joint state it was in before, and the share of
acting agent-steps on which the coordination replaced the preferred action."""


def _study() -> WarehousesConfig:
    return WarehousesConfig(learners=LEARNERS)


@dataclass(frozen=True)
class CrowdConfig:
    """The benchmark of instances whose 2observe runs are replayed (its agents, instances,
    formulations, schedule and greedy episodes; its learners must be 2observe's)."""

    study: WarehousesConfig = field(default_factory=_study)
    """The benchmark's configuration, its learners 2observe's (:data:`LEARNERS` by default)."""

    def __post_init__(self):
        if not isinstance(self.study, WarehousesConfig):
            raise UserError(f"study must be a WarehousesConfig, got {self.study!r}")
        others = [name for name in self.study.learners if registry.get(name).kernel is not two_observe.run]
        if others:
            raise UserError(f"the crowd replays 2observe's kernel; {others} run another: choose among 2observe's "
                            f"learners, e.g. {', '.join(LEARNERS)}")

    def memory_bytes(self) -> int:
        """Bytes held at once, for the largest N: every run's tables and per-episode log, one
        replay's trace, and the stored arrays."""
        study, n = self.study, max(self.study.agents)
        gridmap = study.gridmap(n, 0)
        runs = len(study.formulations) * len(study.learners) * study.instances
        tables = sum(registry.get(name).bytes_per_run(study.setup(f, name), gridmap)
                     for f in study.formulations for name in study.learners) * study.instances
        logs = runs * study.episodes * ep.n_columns(n) * memory.BYTES_PER_VALUE
        trace = study.evaluation_episodes * (study.max_steps + 1) * n * 4
        stored = (len(study.formulations) * len(study.agents) * len(study.learners) * len(COORDINATION)
                  * study.instances * study.evaluation_episodes * len(MEASURES))
        return tables + logs + trace + stored * memory.BYTES_PER_VALUE


@dataclass(frozen=True)
class CrowdResult:
    """Every replayed greedy episode, by formulation, N, learner, coordination and instance."""

    config: CrowdConfig
    """The configuration that produced the arrays."""
    formulations: np.ndarray
    """str (formulations,)."""
    agents: np.ndarray
    """int (agents,): the numbers of agents N."""
    learners: np.ndarray
    """str (learners,)."""
    greedy: np.ndarray
    """(formulations, agents, learners, COORDINATION, instances, greedy episodes, MEASURES)."""

    def names(self) -> list[str]:
        return [str(name) for name in self.learners]

    def measure(self, formulation: str, n: int, learner: str, coordination: str, name: str) -> np.ndarray:
        """(instances, episodes): one of MEASURES for each replayed greedy episode."""
        index = (list(self.formulations).index(formulation), list(self.agents).index(n),
                 list(self.learners).index(learner), COORDINATION.index(coordination))
        return self.greedy[index][..., MEASURES.index(name)]


def greedy_episodes(study: WarehousesConfig, formulation: str, name: str, gridmap: GridMap, master_seed: int,
                    learned: dict, coordination: str) -> np.ndarray:
    """(greedy episodes, MEASURES): the benchmark's greedy evaluation of one run (its inputs and
    stream, :func:`glamas.training.evaluations`) replayed from the run's ``learned`` outputs,
    with the coordination 'on' as learned or 'off' (the fixed rule at distance 0: nobody coordinates)."""
    learner, setup, n = registry.get(name), study.setup(formulation, name), gridmap.n_agents
    evaluation = training.Evaluation(study.evaluation_episodes, (1.0,), per_episode=True)
    (greedy,) = training.evaluations(learner, setup, gridmap, evaluation, study.max_steps, master_seed, study.bounce,
                                     study.rewards(formulation))
    world, learning, automata, schedule = greedy.inputs  # automata frozen: the replay draws no GLA parameters
    if coordination == "off":
        automata = automata._replace(rule_distance=0)
    log = np.zeros((study.evaluation_episodes, ep.n_columns(n)))
    trace = np.empty((study.evaluation_episodes, study.max_steps + 1, n), np.int32)
    yields = np.zeros(study.evaluation_episodes, np.int64)
    replay(world, learning, automata, schedule, *(learned[key][0].copy() for key in ("q", "u", "need_counts")),
           log, rng.chunk_states(greedy.seed, 0, 1)[0], (trace, yields))
    column = dict(zip(GREEDY, greedy_rows(log, n, study.max_steps).T))
    length = column["makespan"].astype(np.int64)  # the episode's length
    return np.stack([column["completed"], column["in_goal"], column["makespan"], column["collisions"],
                     [revisits(trace[e], length[e]) for e in range(length.size)],
                     yields / column["sum_of_costs"]], axis=-1)  # acting agent-steps


def run(config: CrowdConfig = CrowdConfig(), seed: int = 0, workers=None, progress=None) -> CrowdResult:
    """Train the benchmark's 2observe runs again from their seeds, N by N, and replay each one's
    greedy episodes with the coordination on and off."""
    study = config.study
    shape = (len(study.formulations), len(study.agents), len(study.learners), len(COORDINATION), study.instances,
             study.evaluation_episodes, len(MEASURES))
    greedy = np.full(shape, np.nan)
    for a, n in enumerate(study.agents):
        gridmaps = [study.gridmap(n, instance) for instance in range(study.instances)]
        batches = {(f, k, instance): training.batch(registry.get(name), study.setup(formulation, name), gridmap,
                                                    study.schedule(), 1, seed_of(seed, formulation, n, instance, name),
                                                    bounce=study.bounce, rewards=study.rewards(formulation))
                   for f, formulation in enumerate(study.formulations) for k, name in enumerate(study.learners)
                   for instance, gridmap in enumerate(gridmaps)}
        parallel.run_many([work for work, _ in batches.values()], workers=workers, progress=progress, chunk=1)
        for (f, k, instance), (work, learned) in batches.items():
            formulation, name = study.formulations[f], study.learners[k]
            for c, coordination in enumerate(COORDINATION):
                greedy[f, a, k, c, instance] = greedy_episodes(study, formulation, name, gridmaps[instance],
                                                               work.seed, learned, coordination)
    return CrowdResult(config=config, formulations=np.array(study.formulations),
                       agents=np.array(study.agents, dtype=np.int64), learners=np.array(study.learners),
                       greedy=greedy)


def scaled(runs: int, episodes: int) -> CrowdConfig:
    """The replay at ``runs`` instances per N and ``episodes`` (the benchmark's :func:`scaled`)."""
    return CrowdConfig(study=replace(warehouses_scaled(runs, episodes), learners=LEARNERS))
