"""The gridworld experiment of the chapter's Section 5.3, configured and run: independent
Q-learners, joint-state learners, the MMDP learner and 2observe (Alg. 4) on the TunnelToGoal map,
each trained for ``episodes`` episodes in ``runs`` independent runs. A result keeps the learning
curves (block means over episodes) and the final learned structures."""

from dataclasses import dataclass, field, fields

import numpy as np

from glamas import checks, memory, parallel, seeds, training
from glamas.errors import UserError
from glamas.gridworld import BOUNCE_MODES, GridMap, load_map
from glamas.gridworld.rewards import CHAPTER, Rewards
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.qlearning import QSettings

CHAPTER_LEARNERS = ("independent", "joint_state", "mmdp", "two_observe")
"""The chapter's learners (Sec. 5.3), which this experiment trains by default."""


@dataclass(frozen=True)
class GridworldConfig:
    """Settings of the Section 5.3 experiment: the map, the learners and their settings (the
    shared Q-learning settings and each learner's own, by its name), the collision rule, the
    rewards and the schedule."""

    map: str = "tunnel_to_goal"
    """A map's name in data/maps or a map file's path (:func:`glamas.gridworld.load_map`); Fig. 9
    is TunnelToGoal. Any number of agents."""
    learners: tuple = CHAPTER_LEARNERS
    """Which learners to train: distinct names of registered learners (glamas.learners.registry)."""
    q: QSettings = QSettings()
    """Tabular Q-learning, shared by every learner (Sec. 5.3: one learning rate for the Q-learners)."""
    settings: dict = field(default_factory=dict)
    """Each learner's own settings by its name (for example ``{"two_observe": GLASettings(gla_L=1.0)}``);
    completed with the defaults of every trained learner that has settings of its own, and only
    theirs kept."""
    bounce: str = "previous"
    """Where a collided agent goes: 'previous' cell (re-implementations) or its 'start' cell
    (glamas.gridworld.rules)."""
    rewards: Rewards = CHAPTER
    """What a step pays (glamas.gridworld.rewards): the chapter's (Sec. 5.3) by default."""
    max_steps: int = 10_000
    """Step cap per episode, a safeguard (not in the chapter); capped episodes are counted."""
    episodes: int = 200_000
    """Episodes ("iterations": until both agents are in the goal) per run (Sec. 5.3)."""
    runs: int = 20
    """Independent runs averaged (not stated in the chapter)."""
    bins: int = 200
    """Points of the learning curves: blocks of episodes with log-spaced ends (the first blocks
    one episode wide), so that learning in the first episodes is resolved (glamas.learners.episode)."""
    evaluation_episodes: int = 100
    """Episodes of each evaluation of what a run learned, learning off (glamas.training.EVALUATIONS:
    the greedy policy, the training's exploration on frozen tables, one random action per episode)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"max_steps": 1, "episodes": 1, "runs": 1, "bins": 1, "evaluation_episodes": 1})
        check_learners(self, self.q)
        gridmap = self.gridmap()
        for name in self.learners:  # what only the map decides (2observe's box) is checked before any run
            registry.get(name).inputs(self.setup(name), gridmap)

    def setup(self, name: str) -> spec.Setup:
        """What learner ``name`` runs with: the Q-learning settings and its own."""
        return registry.get(name).setup(self.q, self.settings.get(name))

    def own(self, name: str):
        """Learner ``name``'s own settings (None if it has none)."""
        return self.settings.get(name)

    def gridmap(self) -> GridMap:
        """The map (:func:`glamas.gridworld.load_map`)."""
        return load_map(self.map)

    def edges(self) -> np.ndarray:
        """The learning curves' block edges (glamas.learners.episode.log_edges)."""
        return ep.log_edges(self.episodes, self.bins)

    def schedule(self) -> ep.Schedule:
        return ep.Schedule(self.episodes, self.edges(), self.max_steps)

    def evaluation(self) -> training.Evaluation:
        """How each run's learned tables are evaluated (:func:`glamas.training.evaluation_of`)."""
        return training.evaluation_of(self.evaluation_episodes, self.q, self.gridmap())

    def memory_bytes(self) -> int:
        """Bytes of every learner's runs: their tables and logs (:func:`learner_bytes`)."""
        gridmap = self.gridmap()
        return self.runs * sum(learner_bytes(name, self.setup(name), gridmap, self.bins) for name in self.learners)


def check_learners(config, q: QSettings) -> None:
    """What every config that trains learners checks: its ``learners`` distinct names of registered
    learners (stored as a tuple), its ``settings`` completed with their defaults (:func:`own_settings`,
    under the Q-learning settings ``q``), its ``bounce`` a collision rule."""
    checks.distinct_names(config, "learners", registry.LEARNERS, "registered learners")
    object.__setattr__(config, "settings", own_settings(config.learners, q, config.settings))
    checks.one_of(config, "bounce", BOUNCE_MODES)


def own_settings(learners: tuple, q: QSettings, given) -> dict:
    """The own settings of ``learners`` by name: those ``given`` (a dict by learner name), the
    defaults of the others that have settings of their own; settings for a name that is no
    registered learner, or of another learner's class, are refused."""
    if not isinstance(given, dict):
        raise UserError(f"settings must be a dict of each learner's own settings by its name, got {given!r}")
    unknown = sorted(set(given) - set(registry.LEARNERS))
    if unknown:
        raise UserError(f"settings for {unknown}, which are no registered learners ({', '.join(registry.LEARNERS)})")
    chosen = {name: registry.get(name).setup(q, given.get(name)).own for name in learners}
    return {name: own for name, own in chosen.items() if own is not None}


def learner_bytes(name: str, setup: spec.Setup, gridmap: GridMap, bins: int) -> int:
    """Bytes one run of learner ``name`` allocates: its tables (with the runner's working copy and
    the copy an evaluation plays) and its log."""
    tables = registry.get(name).bytes_per_run(setup, gridmap)
    return tables * (memory.WORKING_COPIES + 1) + bins * ep.n_columns(gridmap.n_agents) * memory.BYTES_PER_VALUE


@dataclass(frozen=True)
class GridworldResult:
    """Learning curves (block means over episodes) and final learned structures, all arrays."""

    config: GridworldConfig
    """The configuration that produced the arrays."""
    learners: np.ndarray
    """str (n_learners,): the learners' names, in the order of the other arrays."""
    log: np.ndarray
    """(n_learners, runs, bins, columns): block means of the per-episode measurements; columns
    as in glamas.learners.episode (steps and reward per agent, length, collisions, coordinations, capped)."""
    evaluated: np.ndarray
    """(n_learners, runs, evaluations, columns): what each run learned, evaluated with learning off
    (glamas.training.EVALUATIONS), the means over ``config.evaluation_episodes`` episodes in
    the columns of ``log``."""
    table_shapes: np.ndarray
    """int (n_learners, 3): (tables, states, actions) of each learner's final Q tables."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block (the curves' x axis)."""
    own: dict
    """What each trained learner learned beyond its Q tables, by its name and then by the names of
    its spec's outputs (:attr:`glamas.learners.spec.Learner.outputs`), runs on the first axis:
    2observe's final GLA parameters ``u``, those it drew at the start ``u_initial`` and its
    ``need_counts``, CQ-learning's ``q_aug`` and ``marked``, sparse MAQ's ``q_pairs``; a learner
    with none has no entry. Its file holds them as ``learner.output`` arrays (:meth:`to_arrays`)."""

    def output(self, learner: str, name: str) -> np.ndarray:
        """Learner ``learner``'s own output ``name`` (runs first); one line naming what is missing."""
        if name not in self.own.get(learner, {}):
            trained = ", ".join(f"{k} ({', '.join(v)})" for k, v in self.own.items()) or "none"
            raise UserError(f"this result holds no output {name!r} of {learner!r}; its learners' own outputs: {trained}")
        return self.own[learner][name]

    def to_arrays(self) -> dict:
        """The arrays of its file: its fields, and each learner's own outputs as ``learner.output``."""
        arrays = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in ("config", "own")}
        return arrays | {f"{name}.{key}": array for name, outputs in self.own.items() for key, array in outputs.items()}

    @classmethod
    def from_arrays(cls, config, arrays: dict):
        """The inverse of :meth:`to_arrays`."""
        own: dict = {}
        for key in [key for key in arrays if "." in key]:
            name, _, output = key.partition(".")
            own.setdefault(name, {})[output] = arrays[key]
        return cls(config=config, own=own, **{key: array for key, array in arrays.items() if "." not in key})

    def widths(self) -> np.ndarray:
        """int (bins,): episodes per block."""
        return np.diff(self.episodes, prepend=0)

    def names(self) -> list[str]:
        return [str(name) for name in self.learners]

    def curves(self, learner: str, metric: str) -> np.ndarray:
        """(runs, bins) block means of one metric of glamas.learners.episode.METRICS for one
        learner (steps and reward: means of both agents)."""
        return ep.metric(self.log[self.names().index(learner)], metric)

    def evaluation(self, learner: str, metric: str, mode: str = "greedy") -> np.ndarray:
        """(runs,): one metric of glamas.learners.episode.METRICS for one learner under evaluation
        ``mode`` of glamas.training.EVALUATIONS (``completion``: 1 - capped, the share of the
        evaluation's episodes that ended with every agent in its goal)."""
        rows = self.evaluated[self.names().index(learner), :, training.EVALUATIONS.index(mode)]
        if metric == "completion":
            return np.clip(1.0 - ep.metric(rows, "capped"), 0.0, 1.0)  # the block mean of 1s may pass 1 by rounding
        return ep.metric(rows, metric)

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

    Each learner draws its runs' streams from its own master seed (:func:`seed_of`): every (seed,
    learner) pair has its own streams, whichever other learners are trained or registered.
    """
    work = trainings(config, seed)
    parallel.run_many([batch for batch, _ in work], workers=workers, progress=progress)
    return result_of(config, [outputs for _, outputs in work])


def trainings(config: GridworldConfig, seed: int = 0) -> list:
    """Per learner of ``config``: its runs, ready to run (glamas.parallel.Batch), and the outputs they fill."""
    gridmap, schedule = config.gridmap(), config.schedule()
    evaluation = config.evaluation()
    return [training.batch(registry.get(name), config.setup(name), gridmap, schedule, config.runs,
                           seed_of(seed, name), bounce=config.bounce, rewards=config.rewards,
                           evaluation=evaluation)
            for name in config.learners]


def seed_of(seed: int, learner: str) -> int:
    """The master seed of the runs of ``learner``, named by the master ``seed``, this experiment
    and the learner (:func:`glamas.seeds.named`). The related work and the readings of Fig. 10
    train on the same seeds, so that the chapter's learners give the same runs in each."""
    return seeds.named(seed, "gridworld", learner)


def result_of(config: GridworldConfig, outputs: list) -> GridworldResult:
    """The result of ``config`` from its learners' filled outputs (:func:`trainings`, in order)."""
    gridmap = config.gridmap()
    own = {name: {key: learned[key] for key in registry.get(name).outputs(config.setup(name), gridmap)}
           for name, learned in zip(config.learners, outputs)}
    return GridworldResult(config=config, learners=np.array(config.learners),
                           log=np.stack([learned["log"] for learned in outputs]),
                           evaluated=np.stack([training.evaluated(learned) for learned in outputs]),
                           table_shapes=np.array([learned["q"].shape[1:] for learned in outputs], dtype=np.int64),
                           episodes=config.edges()[1:], own={name: arrays for name, arrays in own.items() if arrays})


def scaled(runs: int, episodes: int) -> GridworldConfig:
    """The chapter's experiment at ``runs`` and ``episodes``."""
    return GridworldConfig(runs=runs, episodes=episodes)
