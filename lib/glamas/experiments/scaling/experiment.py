"""The scaling study's configuration and run: the Section 5.3 learners on warehouse maps with 2 to
6 agents, to measure the argument of Table 1 and Section 3.1 that the joint learners' tables grow
exponentially in the number of agents while independent learners and 2observe stay linear.

Every map ``warehouse_N.txt`` is the same 5 x 7 warehouse (one one-track aisle to the shared goal,
entered from the right end) with N agents starting along the top and bottom rows, so only the
number of agents changes between the maps. Every learner runs through its registered spec
(:mod:`glamas.learners.registry`), so a new learner joins the study by its name. ``run`` allocates
a learner's tables only when they fit the memory budget (computed from its spec before allocating;
otherwise the learner is skipped at that N and the reason recorded), trains it and keeps
agent-mean learning curves.

The related-work learners of :mod:`glamas.experiments.related_work` join the study in their N-agent
forms: sparse tabular MAQ with pairwise coordination (:mod:`glamas.learners.sparse_maq`)
and CQ-learning observing the nearest other agent (:mod:`glamas.learners.cq`). Besides their local
Q tables they store joint values (sparse MAQ: every pair's joint table; CQ: 4 per marked joint
state, measured) and CQ its reward windows; all of it counts in their values per run.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np

from glamas import checks, memory, parallel
from glamas.gridworld import GridMap, load_map
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.learners.settings import LearnerSettings, LearningSettings, RelatedSettings, combine
from glamas.learners.spec import Learner
from glamas.errors import UserError


@dataclass(frozen=True)
class Variant:
    """A method of the study that is a registered learner with one setting changed."""

    learner: str
    """The learner it runs."""
    label: str
    """Its name in figures and tables."""


VARIANTS = {"two_observe_rule": Variant("two_observe", "2observe, fixed rule")}
"""The study's variants: 'two_observe_rule' is a diagnostic outside the chapter, 2observe with its
GLAs replaced by the rule "coordinate when delta < ScalingConfig.rule_distance"."""
CHAPTER_METHODS = registry.family("chapter") + tuple(VARIANTS)
RELATED_METHODS = registry.family("related")
METHODS = CHAPTER_METHODS + RELATED_METHODS
"""The study's methods by default."""


def known_methods() -> tuple:
    """What a ScalingConfig can train, and what a ScalingResult's codes index: METHODS, then every
    other registered learner."""
    return METHODS + registry.family("other")


MAX_AGENTS = 9
"""The map format numbers agents 1-9."""
METRICS = ("steps", "reward", "collisions", "coordinations", "capped")
"""What the study keeps of each episode log (glamas.learners.episode.METRICS, agent means)."""


@dataclass(frozen=True)
class ScalingConfig(RelatedSettings):
    """Settings of the scaling study: the learners' settings (``learning`` and the related-work
    learners' own, :class:`glamas.learners.settings.RelatedSettings`), the maps and the schedule."""

    agents: tuple = (2, 3, 4, 5, 6)
    """Numbers of agents N; map ``map_pattern.format(n=N)`` is used for each."""
    map_pattern: str = "warehouse_{n}.txt"
    """Map file name (in data/maps, or a path) with ``{n}`` for the number of agents."""
    methods: tuple = METHODS
    """Learners to train: distinct names of :func:`known_methods` (the registered learners and VARIANTS)."""
    rule_distance: int = 3
    """The fixed rule's distance for 'two_observe_rule' (3: delta at most 2, where every collision
    of two agents comes from)."""
    episodes: int = 20_000
    """Episodes per run (each until every agent is in the goal, or the step cap)."""
    runs: int = 10
    """Independent runs per (method, N)."""
    bin_size: int = 100
    """Episodes averaged into one point of the learning curves; must divide ``episodes``."""
    memory_budget_gib: float = 4.0
    """Memory the Q tables of all runs of one (method, N) may take, in GiB (a sixth of a 24 GiB
    workstation, leaving room for other work); a learner whose tables would need more is skipped at that N."""
    learning: LearningSettings = field(default_factory=lambda: LearningSettings(max_steps=1000))
    """Q-learning, GLA and collision settings (the Section 5.3 experiment's defaults, with a
    1000-step cap per episode: with three or more agents an agent often gets trapped early on, see
    the notebook)."""

    def __post_init__(self):
        super().__post_init__()
        checks.whole_numbers(self, {"episodes": 1, "runs": 1, "bin_size": 1})
        if self.episodes % self.bin_size:
            raise UserError(f"bin_size ({self.bin_size}) must divide episodes ({self.episodes}); "
                             "choose a bin size such as 100 that divides the episode count")
        agents = tuple(self.agents) if isinstance(self.agents, (tuple, list)) else None
        if (not agents or len(set(agents)) != len(agents)
                or not all(isinstance(n, int) and 2 <= n <= MAX_AGENTS for n in agents)):
            raise UserError(f"agents must be distinct whole numbers from 2 to {MAX_AGENTS}, got {self.agents!r}")
        object.__setattr__(self, "agents", tuple(sorted(agents)))
        methods = tuple(self.methods) if isinstance(self.methods, (tuple, list)) else ()
        if not methods or len(set(methods)) != len(methods) or not set(methods) <= set(known_methods()):
            raise UserError(f"methods must be distinct names from {known_methods()}, got {self.methods!r}")
        object.__setattr__(self, "methods", methods)
        if isinstance(self.rule_distance, bool) or not isinstance(self.rule_distance, int) or self.rule_distance < 0:
            raise UserError(f"rule_distance must be a whole number >= 0, got {self.rule_distance!r}")
        if not (isinstance(self.memory_budget_gib, (int, float)) and self.memory_budget_gib > 0):
            raise UserError(f"memory_budget_gib must be a number > 0, got {self.memory_budget_gib!r}")
        if "{n}" not in self.map_pattern:
            raise UserError(f"map_pattern must contain '{{n}}' for the number of agents, got {self.map_pattern!r}")
        for n in self.agents:
            gridmap = self.gridmap(n)
            if gridmap.n_agents != n:
                raise UserError(f"map {gridmap.name!r} has {gridmap.n_agents} agents, the study expects {n}: "
                                 f"give each map file exactly N starts 1..N")

    def gridmap(self, n: int) -> GridMap:
        """The map with ``n`` agents: ``map_pattern`` as a name in data/maps or a path
        (:func:`glamas.gridworld.load_map`)."""
        return load_map(self.map_pattern.format(n=n))

    def memory_bytes(self) -> int:
        """Bytes of the largest runs held at once and of every log. A run's tables live in the
        worker that fills it, one run per worker at a time: at most the runs of the largest
        learner that fits the budget at once, whatever the number of workers."""
        budget = self.memory_budget_gib * 2 ** 30
        needs = [memory_needed(self, method, self.gridmap(n)) for n in self.agents for method in self.methods]
        largest = max((need for need in needs if need <= budget), default=0)
        logs = len(self.methods) * len(self.agents) * self.runs * self.n_bins * len(METRICS)
        return largest * memory.WORKING_COPIES + logs * memory.BYTES_PER_VALUE

    @property
    def n_bins(self) -> int:
        return self.episodes // self.bin_size

    def schedule(self) -> ep.Schedule:
        """The runs' schedule: ``bin_size`` episodes per block of the learning curves."""
        return ep.Schedule(self.episodes, ep.uniform_edges(self.episodes, self.bin_size), self.learning.max_steps)

    def settings(self, method: str) -> LearnerSettings:
        """The settings ``method`` runs with: ``learning`` and the related-work learners' own, and
        for the fixed-rule variant its rule distance."""
        settings = combine(self.learning, self)
        return replace(settings, rule_distance=self.rule_distance) if method in VARIANTS else settings


def learner_of(method: str) -> Learner:
    """The registered learner a method runs (a variant's learner, or the method itself)."""
    return registry.get(VARIANTS[method].learner if method in VARIANTS else method)


def label(method: str) -> str:
    """A method's name in figures and tables (its N-agent form's, where that differs)."""
    return VARIANTS[method].label if method in VARIANTS else (learner_of(method).n_agent_label or registry.label(method))


def memory_needed(config: ScalingConfig, method: str, gridmap: GridMap) -> int:
    """Bytes the tables of all of ``config.runs`` runs on ``gridmap`` take together (CQ: with its marks)."""
    return config.runs * learner_of(method).bytes_per_run(config.settings(method), gridmap)


@dataclass(frozen=True)
class ScalingResult:
    """Agent-mean learning curves and table sizes for every (method, N), all arrays."""

    config: ScalingConfig
    """The configuration that produced the arrays."""
    methods: np.ndarray
    """int (methods,): index into :func:`known_methods` of each method, in the order of the other arrays."""
    agents: np.ndarray
    """int (agents,): the numbers of agents N."""
    ran: np.ndarray
    """bool (methods, agents): whether the learner ran (False: its tables exceed the budget)."""
    table_shapes: np.ndarray
    """int (methods, agents, 3): (tables, states, actions) of the Q tables per run, from the
    learner's spec: the tables its runs fill, or would fill where it was skipped."""
    gla_parameters: np.ndarray
    """int (methods, agents): GLA parameters per run (2observe: 4 per agent)."""
    joint_entries: np.ndarray
    """float (methods, agents): joint values per run beyond the Q tables of ``table_shapes``:
    sparse MAQ every pair's joint table, CQ 4 per marked joint state (mean over runs; where skipped,
    its room for every joint state); 0 for the chapter's learners."""
    reward_samples: np.ndarray
    """int (methods, agents): immediate rewards kept per run for CQ's test (0 for the others)."""
    bytes_needed: np.ndarray
    """int (methods, agents): bytes of Q tables for all runs together."""
    log: np.ndarray
    """(methods, agents, runs, bins, METRICS): block means of steps to goal and reward (means
    over the agents), collisions, coordinations, capped episodes; NaN where skipped."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block."""

    def names(self) -> list[str]:
        known = known_methods()
        return [known[k] for k in self.methods]

    def curves(self, method: str, n: int, metric: str) -> np.ndarray:
        """(runs, bins) block means of one of METRICS for one method and number of agents."""
        return self.log[self.names().index(method), list(self.agents).index(n), :, :, METRICS.index(metric)]

    def q_entries(self) -> np.ndarray:
        """(methods, agents): Q-table entries per run (all agents' tables together)."""
        return self.table_shapes.prod(axis=2, dtype=float)  # exact below 2^53; int64 would wrap for many agents

    def parameters(self) -> np.ndarray:
        """(methods, agents): values stored per run: Q entries, GLA parameters, joint values and
        reward samples."""
        return self.q_entries() + self.gla_parameters + self.joint_entries + self.reward_samples


def seed_of(seed: int, method: str, n_agents: int) -> int:
    """Master seed of one (method, N) (:func:`glamas.learners.registry.master_seed` with the key
    ``16 seed + N``): distinct for every (seed, method, N), and a method gets the same streams at a
    given N whatever else is trained with it."""
    family = learner_of(method).family
    members = RELATED_METHODS if family == "related" else CHAPTER_METHODS
    return registry.master_seed(seed * 16 + n_agents, members, method, family)


def _as_int64(count: int) -> int:
    """``count`` as an int64 array can hold it: at most 2^63 - 1. Only the tables of many agents
    count beyond (an MMDP learner's of 9 agents), and the study skips those, far over any budget."""
    return min(int(count), np.iinfo(np.int64).max)


def run(config: ScalingConfig = ScalingConfig(), seed: int = 0, workers=None, progress=None) -> ScalingResult:
    """Train every method at every N that fits the memory budget (``config.runs`` runs each), all
    runs on one pool of workers (:func:`glamas.parallel.run_many`). Each run's Q tables stay in the
    worker that fills them (the study keeps learning curves and table sizes), so memory holds
    the tables of the runs in progress only."""
    m, a = len(config.methods), len(config.agents)
    ran = np.zeros((m, a), dtype=bool)
    shapes = np.zeros((m, a, 3), dtype=np.int64)
    glas = np.zeros((m, a), dtype=np.int64)
    joints = np.zeros((m, a))
    samples = np.zeros((m, a), dtype=np.int64)
    needed = np.zeros((m, a), dtype=np.int64)
    log = np.full((m, a, config.runs, config.n_bins, len(METRICS)), np.nan)
    budget = config.memory_budget_gib * 2 ** 30
    schedule = config.schedule()
    trainings = {}
    for j, n in enumerate(config.agents):
        gridmap = config.gridmap(n)
        for k, method in enumerate(config.methods):
            learner, settings = learner_of(method), config.settings(method)
            shapes[k, j] = [_as_int64(size) for size in learner.table_shape(gridmap.n_cells, n)]
            glas[k, j] = learner.gla_parameters(settings, gridmap)
            joints[k, j], samples[k, j] = learner.joint_room(settings, gridmap), learner.reward_samples(settings, gridmap)
            needed[k, j] = _as_int64(memory_needed(config, method, gridmap))
            if needed[k, j] <= budget:
                batch, outputs = spec.batch(learner, settings, gridmap, schedule, config.runs, seed_of(seed, method, n),
                                            keep_q=False)
                trainings[k, j] = learner, settings, gridmap, batch, outputs
    # One run per job: runs differ widely in length (some spend most episodes at the step cap),
    # and small jobs keep every worker busy until the last runs are done.
    parallel.run_many([batch for *_, batch, _ in trainings.values()], workers=workers, progress=progress, chunk=1)
    for (k, j), (learner, settings, gridmap, _, outputs) in trainings.items():
        joints[k, j] = learner.joint_learned(outputs, settings, gridmap).mean()
        ran[k, j] = True
        log[k, j] = agent_means(outputs["log"])
    codes = np.array([known_methods().index(name) for name in config.methods], dtype=np.int64)
    return ScalingResult(config=config, methods=codes, agents=np.array(config.agents, dtype=np.int64), ran=ran,
                         table_shapes=shapes, gla_parameters=glas, joint_entries=joints, reward_samples=samples,
                         bytes_needed=needed, log=log, episodes=schedule.edges[1:])


def agent_means(log: np.ndarray) -> np.ndarray:
    """(runs, bins, METRICS) from an N-agent log (glamas.learners.episode layout)."""
    return np.stack([ep.metric(log, name) for name in METRICS], axis=-1)


def scaled(runs: int, episodes: int) -> ScalingConfig:
    """The study at ``runs`` and ``episodes``, in blocks that divide the episodes."""
    return ScalingConfig(runs=runs, episodes=episodes, bin_size=math.gcd(episodes, ScalingConfig.bin_size))
