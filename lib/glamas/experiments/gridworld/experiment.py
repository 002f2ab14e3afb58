"""The gridworld experiment of the chapter's Section 5.3, configured and run: independent
Q-learners, joint-state learners, the MMDP learner and 2observe (Alg. 4) on the TunnelToGoal map,
each trained for ``episodes`` episodes in ``runs`` independent runs. A result keeps the learning
curves (block means over episodes) and the final learned structures."""

from dataclasses import dataclass

import numpy as np

from glamas import checks, memory, parallel
from glamas.gridworld import GridMap, load_map
from glamas.learners import episode as ep
from glamas.learners import registry, spec, two_observe
from glamas.learners.settings import LearningSettings
from glamas.errors import UserError


LEARNERS = registry.family("chapter")
"""The learners this experiment trains: the chapter's (glamas.learners.registry), in the order
their seeds are drawn."""


@dataclass(frozen=True)
class GridworldConfig(LearningSettings):
    """Settings of the Section 5.3 experiment: the learners' settings
    (:class:`glamas.learners.settings.LearningSettings`), plus the map, the learners and the schedule."""

    map_file: str = "tunnel_to_goal.txt"
    """Map file (data/maps format), a name in data/maps or a path; Fig. 9 is TunnelToGoal."""
    learners: tuple = LEARNERS
    """Which learners to train, a subset of independent, joint_state, mmdp, two_observe."""
    episodes: int = 200_000
    """Episodes ("iterations": until both agents are in the goal) per run (Sec. 5.3)."""
    runs: int = 20
    """Independent runs averaged (not stated in the chapter)."""
    bins: int = 200
    """Points of the learning curves: blocks of episodes with log-spaced ends (the first blocks
    one episode wide), so that learning in the first episodes is resolved (glamas.learners.episode)."""

    def __post_init__(self):
        super().__post_init__()
        checks.whole_numbers(self, {"episodes": 1, "runs": 1, "bins": 1})
        learners = tuple(self.learners)
        if not learners or len(set(learners)) != len(learners) or not set(learners) <= set(LEARNERS):
            raise UserError(f"learners must be distinct names from {LEARNERS}, got {self.learners!r}")
        object.__setattr__(self, "learners", learners)
        gridmap = self.gridmap()
        if gridmap.n_agents != 2:
            raise UserError(f"the learners are written for two agents; map {self.map_file!r} has {gridmap.n_agents}")

    def gridmap(self) -> GridMap:
        """The map: ``map_file`` as a name in data/maps or a path (:func:`glamas.gridworld.load_map`)."""
        return load_map(self.map_file)

    def edges(self) -> np.ndarray:
        """The learning curves' block edges (glamas.learners.episode.log_edges)."""
        return ep.log_edges(self.episodes, self.bins)

    def schedule(self) -> ep.Schedule:
        return ep.Schedule(self.episodes, self.edges(), self.max_steps)

    def memory_bytes(self) -> int:
        """Bytes of every learner's runs: their tables and logs (:func:`learner_bytes`)."""
        gridmap = self.gridmap()
        return self.runs * sum(learner_bytes(name, self, gridmap, self.bins) for name in self.learners)

    def delta_scale(self) -> float:
        """What the GLA context multiplies delta by (``gla_delta_scale``) on this map."""
        return two_observe.delta_scale(self.gla_delta_scale, self.gridmap())


def learner_bytes(name: str, settings, gridmap: GridMap, bins: int) -> int:
    """Bytes one run of learner ``name`` allocates: its tables (with the runner's working copy) and its log."""
    tables = registry.get(name).bytes_per_run(settings, gridmap)
    return tables * memory.WORKING_COPIES + bins * ep.n_columns(gridmap.n_agents) * memory.BYTES_PER_VALUE


@dataclass(frozen=True)
class GridworldResult:
    """Learning curves (block means over episodes) and final learned structures, all arrays."""

    config: GridworldConfig
    """The configuration that produced the arrays."""
    learners: np.ndarray
    """int (n_learners,): index into LEARNERS of each learner, in the order of the other arrays."""
    log: np.ndarray
    """(n_learners, runs, bins, columns): block means of the per-episode measurements; columns
    as in glamas.learners.episode (steps and reward per agent, length, collisions, coordinations, capped)."""
    table_shapes: np.ndarray
    """int (n_learners, 3): (tables, states, actions) of each learner's final Q tables."""
    gla_parameters: np.ndarray
    """(runs, agents, 2 actions, 2 inputs): 2observe's final GLA parameters (zeros if not run)."""
    gla_initial: np.ndarray
    """(runs, agents, 2 actions, 2 inputs): the GLA parameters 2observe's runs started from
    (zeros if not run)."""
    need_counts: np.ndarray
    """(runs, deltas, 2): 2observe's observing agent-steps per distance delta without / with need
    (``gla_need``; zeros if not run)."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block (the curves' x axis)."""

    def widths(self) -> np.ndarray:
        """int (bins,): episodes per block."""
        return np.diff(self.episodes, prepend=0)

    def names(self) -> list[str]:
        return [LEARNERS[k] for k in self.learners]

    def curves(self, learner: str, metric: str) -> np.ndarray:
        """(runs, bins) block means of one metric of glamas.learners.episode.METRICS for one
        learner (steps and reward: means of both agents)."""
        return ep.metric(self.log[self.names().index(learner)], metric)

    def steps(self, learner: str) -> np.ndarray:
        """(runs, bins): steps to the goal, averaged over both agents (Fig. 11a)."""
        return self.curves(learner, "steps")

    def reward(self, learner: str) -> np.ndarray:
        """(runs, bins): undiscounted reward per episode, averaged over both agents (Fig. 11b)."""
        return self.curves(learner, "reward")


def run(config: GridworldConfig = GridworldConfig(), seed: int = 0, workers=None,
        progress=None) -> GridworldResult:
    """Train every learner of ``config`` in ``config.runs`` runs, all learners' runs on one pool of
    workers (:func:`glamas.parallel.run_many`).

    Each learner draws its runs' streams from its own master seed
    (:func:`glamas.learners.registry.master_seed` over LEARNERS): every (seed, learner) pair has
    its own streams, and a learner gets the same streams whichever other learners are trained with it.
    """
    work = trainings(config, seed)
    parallel.run_many([batch for batch, _ in work], workers=workers, progress=progress)
    return result_of(config, [outputs for _, outputs in work], seed)


def trainings(config: GridworldConfig, seed: int = 0) -> list:
    """Per learner of ``config``: its runs, ready to run (glamas.parallel.Batch), and the outputs they fill."""
    gridmap, schedule = config.gridmap(), config.schedule()
    return [spec.batch(registry.get(name), config, gridmap, schedule, config.runs,
                       registry.master_seed(seed, LEARNERS, name)) for name in config.learners]


def result_of(config: GridworldConfig, outputs: list, seed: int = 0) -> GridworldResult:
    """The result of ``config`` and ``seed`` from its learners' filled outputs (:func:`trainings`,
    in order)."""
    gridmap = config.gridmap()
    first_level = {key: np.stack([zeros] * config.runs) for key, zeros in two_observe.outputs(config, gridmap).items()}
    for learned in outputs:
        first_level.update({key: learned[key] for key in first_level.keys() & learned.keys()})
    initial = np.zeros_like(first_level["u"])
    if "two_observe" in config.learners:
        initial = two_observe.initial_parameters(config, gridmap, registry.master_seed(seed, LEARNERS, "two_observe"),
                                                 config.runs)
    codes = np.array([LEARNERS.index(name) for name in config.learners], dtype=np.int64)
    return GridworldResult(config=config, learners=codes, log=np.stack([learned["log"] for learned in outputs]),
                           table_shapes=np.array([learned["q"].shape[1:] for learned in outputs], dtype=np.int64),
                           gla_parameters=first_level["u"], gla_initial=initial,
                           need_counts=first_level["need_counts"],
                           episodes=config.edges()[1:])


def scaled(runs: int, episodes: int) -> GridworldConfig:
    """The chapter's experiment at ``runs`` and ``episodes``."""
    return GridworldConfig(runs=runs, episodes=episodes)
