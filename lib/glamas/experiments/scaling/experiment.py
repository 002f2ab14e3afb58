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
forms: sparse cooperative Q-learning over the coordination graph of the agents close to each
other (:mod:`glamas.learners.sparse_maq`) and CQ-learning testing every other agent and acting on
the nearest one it marked (:mod:`glamas.learners.cq`). Besides their local Q tables they store
joint values (sparse MAQ: every pair's joint table, the graph's possible edges; CQ: 4 per marked
joint state, measured) and CQ its reward windows; all of it counts in their values per run.
"""

import math
import string
from dataclasses import dataclass, field

import numpy as np

from glamas import checks, memory, parallel, seeds, training
from glamas.errors import UserError
from glamas.experiments.gridworld.experiment import check_learners
from glamas.gridworld import GridMap, load_map
from glamas.gridworld.rewards import Rewards
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.qlearning import QSettings

CHAPTER_METHODS = ("independent", "joint_state", "mmdp", "two_observe", "two_observe_rule")
"""The chapter's learners and the fixed-rule variant of 2observe ('two_observe_rule', a diagnostic
outside the chapter: its GLAs replaced by the rule "coordinate when delta < 3")."""
RELATED_METHODS = ("sparse_maq", "cq")
"""The related-work learners, in their N-agent forms."""
METHODS = CHAPTER_METHODS + RELATED_METHODS
"""The study's learners by default."""
METRICS = ("steps", "reward", "collisions", "coordinations", "capped", "length")
"""What the study keeps of each episode log (glamas.learners.episode.METRICS; steps and reward
agent means, length the steps until every agent is in its goal)."""


@dataclass(frozen=True)
class ScalingConfig:
    """Settings of the scaling study: the maps, the learners and their settings (the shared
    Q-learning settings and each learner's own, by its name), the collision rule and the schedule."""

    agents: tuple = (2, 3, 4, 5, 6)
    """Numbers of agents N; map ``map.format(n=N)`` is used for each."""
    map: str = "warehouse_{n}"
    """A map's name in data/maps or a map file's path, with ``{n}`` for the number of agents."""
    learners: tuple = METHODS
    """Learners to train: distinct names of registered learners (glamas.learners.registry)."""
    q: QSettings = QSettings()
    """Tabular Q-learning, shared by every learner (the Section 5.3 experiment's)."""
    settings: dict = field(default_factory=dict)
    """Each learner's own settings by its name, completed with the defaults of every trained learner
    (as :attr:`glamas.experiments.gridworld.GridworldConfig.settings`)."""
    bounce: str = "previous"
    """Where a collided agent goes (glamas.gridworld.rules)."""
    rewards: Rewards = Rewards()
    """What a step pays (glamas.gridworld.rewards: the chapter's by default, ``rewards.FIELD`` the
    field's step costs)."""
    max_steps: int = 1000
    """Step cap per episode: with three or more agents an agent often gets trapped early on (see
    the notebook), and 1000 steps keep such episodes from taking the run's time."""
    episodes: int = 20_000
    """Episodes per run (each until every agent is in the goal, or the step cap)."""
    runs: int = 10
    """Independent runs per (learner, N)."""
    bin_size: int = 100
    """Episodes averaged into one point of the learning curves; must divide ``episodes``."""
    memory_budget_gib: float = 4.0
    """Memory the Q tables of all runs of one (learner, N) may take, in GiB (a sixth of a 24 GiB
    workstation, leaving room for other work); a learner whose tables would need more is skipped at that N."""
    evaluation_episodes: int = 100
    """Episodes of each evaluation of what a run learned, learning off (glamas.training.EVALUATIONS)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"max_steps": 1, "episodes": 1, "runs": 1, "bin_size": 1, "evaluation_episodes": 1})
        if self.episodes % self.bin_size:
            raise UserError(f"bin_size ({self.bin_size}) must divide episodes ({self.episodes}); "
                            "choose a bin size such as 100 that divides the episode count")
        checks.agent_counts(self, 2)
        check_learners(self, self.q)
        checks.positive(self, "memory_budget_gib")
        try:
            placeholders = {name for _, name, _, _ in string.Formatter().parse(self.map) if name is not None}
        except ValueError:  # a lone '{' or '}'
            placeholders = None
        if placeholders != {"n"}:
            raise UserError(f"map must hold '{{n}}' for the number of agents and no other '{{...}}', got {self.map!r}")
        for n in self.agents:
            gridmap = self.gridmap(n)
            if gridmap.n_agents != n:
                raise UserError(f"map {gridmap.name!r} has {gridmap.n_agents} agents, the study expects {n}: "
                                "give each map exactly N agents")

    def gridmap(self, n: int) -> GridMap:
        """The map with ``n`` agents (:func:`glamas.gridworld.load_map` of ``map.format(n=n)``)."""
        return load_map(self.map.format(n=n))

    def setup(self, name: str) -> spec.Setup:
        """What learner ``name`` runs with: the Q-learning settings and its own."""
        return registry.get(name).setup(self.q, self.settings.get(name))

    def memory_bytes(self) -> int:
        """Bytes of the largest runs held at once and of every log. A run's tables live in the
        worker that fills it, one run per worker at a time: at most the runs of the largest
        learner that fits the budget at once, whatever the number of workers."""
        budget = self.memory_budget_gib * 2 ** 30
        needs = [memory_needed(self, name, self.gridmap(n)) for n in self.agents for name in self.learners]
        largest = max((need for need in needs if need <= budget), default=0)
        logs = len(self.learners) * len(self.agents) * self.runs * self.n_bins * len(METRICS)
        return largest * (memory.WORKING_COPIES + 1) + logs * memory.BYTES_PER_VALUE

    @property
    def n_bins(self) -> int:
        return self.episodes // self.bin_size

    def schedule(self) -> ep.Schedule:
        """The runs' schedule: ``bin_size`` episodes per block of the learning curves."""
        return ep.Schedule(self.episodes, ep.uniform_edges(self.episodes, self.bin_size), self.max_steps)


@dataclass(frozen=True)
class ManyAgentsConfig(ScalingConfig):
    """The study of many agents: the scaling study's learners and settings on generated warehouses
    of 2, 8, 32 and 128 agents (``data/maps/aisles_N.txt``, :func:`glamas.gridworld.generate.warehouse`
    with seed 0), the density of agents per free cell held at about 0.1, each agent with its own
    start and goal. The joint learners' tables stop fitting any memory from N = 8 on: they are
    skipped there, the sizes they would need kept."""

    agents: tuple = (2, 8, 32, 128)
    """Numbers of agents N: a generated map of each, the density held."""
    map: str = "aisles_{n}"
    """The generated warehouses in data/maps."""
    episodes: int = 2000
    """Episodes per run (the field's schedule, as on the field's maps)."""
    runs: int = 5
    """Independent runs per (learner, N)."""


def label(name: str) -> str:
    """A learner's name in the study's figures and tables (its N-agent form's, where that differs)."""
    learner = registry.get(name)
    return learner.n_agent_label or learner.label


def memory_needed(config: ScalingConfig, name: str, gridmap: GridMap) -> int:
    """Bytes the tables of all of ``config.runs`` runs of learner ``name`` on ``gridmap`` take together
    (CQ: with its marks)."""
    return config.runs * registry.get(name).bytes_per_run(config.setup(name), gridmap)


@dataclass(frozen=True)
class ScalingResult:
    """Agent-mean learning curves and table sizes for every (method, N), all arrays."""

    config: ScalingConfig
    """The configuration that produced the arrays."""
    learners: np.ndarray
    """str (learners,): the learners' names, in the order of the other arrays."""
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
    evaluated: np.ndarray
    """(methods, agents, runs, evaluations, METRICS): what each run learned, evaluated with learning
    off (glamas.training.EVALUATIONS), means over ``config.evaluation_episodes`` episodes; NaN
    where skipped."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block."""

    def names(self) -> list[str]:
        return [str(name) for name in self.learners]

    def curves(self, method: str, n: int, metric: str) -> np.ndarray:
        """(runs, bins) block means of one of METRICS for one method and number of agents."""
        return self.log[self.names().index(method), list(self.agents).index(n), :, :, METRICS.index(metric)]

    def evaluation(self, method: str, n: int, metric: str, mode: str = "greedy") -> np.ndarray:
        """(runs,): one of METRICS, or ``completion`` (1 - capped), for one method and N under
        evaluation ``mode`` of glamas.training.EVALUATIONS."""
        rows = self.evaluated[self.names().index(method), list(self.agents).index(n), :,
                              training.EVALUATIONS.index(mode)]
        if metric == "completion":
            return np.clip(1.0 - rows[:, METRICS.index("capped")], 0.0, 1.0)
        return rows[:, METRICS.index(metric)]

    def shape(self, method: str, n: int) -> tuple[int, int, int]:
        """(tables, states, actions) of one method's Q tables at N, from its spec in Python integers:
        exact however many agents (``table_shapes`` holds at most an int64's 2^63 - 1)."""
        return registry.get(method).table_shape(self.config.gridmap(int(n)).n_cells, int(n))

    def memory_needed(self, method: str, n: int) -> int:
        """Bytes the tables of all runs of one method at N take, in Python integers (exact where
        ``bytes_needed`` saturates)."""
        return memory_needed(self.config, method, self.config.gridmap(int(n)))

    def q_entries(self) -> np.ndarray:
        """(methods, agents): Q-table entries per run (all agents' tables together), as floats
        (infinite beyond a float's 1.8e308: the MMDP learner's of 128 agents)."""
        return np.array([[_as_float(math.prod(self.shape(name, n))) for n in self.agents] for name in self.names()])

    def parameters(self) -> np.ndarray:
        """(methods, agents): values stored per run: Q entries, GLA parameters, joint values and
        reward samples."""
        return self.q_entries() + self.gla_parameters + self.joint_entries + self.reward_samples


def seed_of(seed: int, name: str, n_agents: int) -> int:
    """Master seed of one (learner, N), named by the seed, the study, N and the learner
    (:func:`glamas.seeds.named`): a learner gets the same streams at a given N whatever else is
    trained or registered (the study of many agents shares them: it is this study at more agents)."""
    return seeds.named(*case_names(seed, n_agents), name)


def case_names(seed: int, n_agents: int) -> tuple:
    """What names the runs of one N (:func:`sweep`): the seed, the study and N."""
    return seed, "scaling", n_agents


def _as_float(count: int) -> float:
    """``count`` as a float, infinite where it exceeds a float's range."""
    try:
        return float(count)
    except OverflowError:
        return math.inf


def _as_int64(count: int) -> int:
    """``count`` as an int64 array can hold it: at most 2^63 - 1. Only the tables of many agents
    count beyond (an MMDP learner's of 9 agents), and the study skips those, far over any budget."""
    return min(int(count), np.iinfo(np.int64).max)


def run(config: ScalingConfig = ScalingConfig(), seed: int = 0, workers=None, progress=None) -> ScalingResult:
    """Train every learner at every N that fits the memory budget (``config.runs`` runs each), all
    runs on one pool of workers (:func:`sweep`)."""
    arrays = sweep(config, [config.gridmap(n) for n in config.agents], [case_names(seed, n) for n in config.agents],
                   workers, progress)
    return ScalingResult(config=config, learners=np.array(config.learners),
                         agents=np.array(config.agents, dtype=np.int64), **arrays)


def sweep(config, gridmaps: list, cases: list, workers=None, progress=None) -> dict:
    """Every learner of ``config`` trained and evaluated on each of ``gridmaps`` (a study's cases)
    where its tables fit ``config.memory_budget_gib``: ``config.runs`` runs each, the runs of
    learner ``name`` on case j drawing their master seed from ``seeds.named(*cases[j], name)``
    (:func:`glamas.seeds.named`; ``cases[j]`` names the case), all on one pool of workers
    (:func:`glamas.parallel.run_many`). Each run's Q tables stay in the worker that fills them (the
    study keeps learning curves, evaluations and table sizes), so memory holds the tables of the
    runs in progress only. ``config`` holds
    learners, their settings (``setup``), q, bounce, rewards, runs, the schedule (``schedule()``, ``n_bins``),
    ``evaluation_episodes`` and the memory budget. Returns the arrays of a result, with a case axis
    after the learners' (:class:`ScalingResult`'s fields from ``ran`` on)."""
    m, a = len(config.learners), len(gridmaps)
    ran = np.zeros((m, a), dtype=bool)
    shapes = np.zeros((m, a, 3), dtype=np.int64)
    glas = np.zeros((m, a), dtype=np.int64)
    joints = np.zeros((m, a))
    samples = np.zeros((m, a), dtype=np.int64)
    needed = np.zeros((m, a), dtype=np.int64)
    log = np.full((m, a, config.runs, config.n_bins, len(METRICS)), np.nan)
    evaluated = np.full((m, a, config.runs, len(training.EVALUATIONS), len(METRICS)), np.nan)
    budget = config.memory_budget_gib * 2 ** 30
    schedule = config.schedule()
    trainings = {}
    for j, (gridmap, case) in enumerate(zip(gridmaps, cases)):
        evaluation = training.evaluation_of(config.evaluation_episodes, config.q, gridmap)
        for k, name in enumerate(config.learners):
            learner, setup = registry.get(name), config.setup(name)
            shapes[k, j] = [_as_int64(size) for size in learner.table_shape(gridmap.n_cells, gridmap.n_agents)]
            glas[k, j] = learner.gla_parameters(setup, gridmap)
            joints[k, j], samples[k, j] = learner.joint_room(setup, gridmap), learner.reward_samples(setup, gridmap)
            needed[k, j] = _as_int64(config.runs * learner.bytes_per_run(setup, gridmap))
            if needed[k, j] <= budget:
                batch, outputs = training.batch(learner, setup, gridmap, schedule, config.runs,
                                                seeds.named(*case, name), bounce=config.bounce,
                                                rewards=config.rewards, keep_q=False, evaluation=evaluation)
                trainings[k, j] = learner, setup, gridmap, batch, outputs
    # One run per job: runs differ widely in length (some spend most episodes at the step cap),
    # and small jobs keep every worker busy until the last runs are done.
    parallel.run_many([batch for *_, batch, _ in trainings.values()], workers=workers, progress=progress, chunk=1)
    for (k, j), (learner, setup, gridmap, _, outputs) in trainings.items():
        joints[k, j] = learner.joint_learned(outputs, setup, gridmap).mean()
        ran[k, j] = True
        log[k, j] = agent_means(outputs["log"])
        evaluated[k, j] = agent_means(training.evaluated(outputs))
    return {"ran": ran, "table_shapes": shapes, "gla_parameters": glas, "joint_entries": joints,
            "reward_samples": samples, "bytes_needed": needed, "log": log, "evaluated": evaluated,
            "episodes": schedule.edges[1:]}


def agent_means(log: np.ndarray) -> np.ndarray:
    """(runs, bins, METRICS) from an N-agent log (glamas.learners.episode layout)."""
    return np.stack([ep.metric(log, name) for name in METRICS], axis=-1)


def many_agents_scaled(runs: int, episodes: int) -> ManyAgentsConfig:
    """The study of many agents at ``runs`` and ``episodes``, in blocks that divide the episodes."""
    return ManyAgentsConfig(runs=runs, episodes=episodes, bin_size=math.gcd(episodes, ManyAgentsConfig.bin_size))


def scaled(runs: int, episodes: int) -> ScalingConfig:
    """The study at ``runs`` and ``episodes``, in blocks that divide the episodes."""
    return ScalingConfig(runs=runs, episodes=episodes, bin_size=math.gcd(episodes, ScalingConfig.bin_size))


TRAPPED = 0.9
"""An agent is trapped when its mean steps over the last tenth of the episodes reach this share of
the step cap (:func:`trap`)."""


def aisle_cells(gridmap: GridMap) -> np.ndarray:
    """The cells of a warehouse's one-track aisles: free, not a goal, walled above and below."""
    stay = np.arange(gridmap.n_cells)
    walled = (gridmap.next_cell[:, 0] == stay) & (gridmap.next_cell[:, 2] == stay)
    return np.flatnonzero(walled & ~gridmap.is_goal & ~gridmap.blocked)


def trap(name: str, n: int, runs: int, episodes: int, seed: int = 0, config: ScalingConfig = ScalingConfig(),
         workers=None, master_seed: int | None = None) -> dict:
    """What traps agents, measured: ``runs`` runs of learner ``name`` on the study's map of ``n``
    agents with its settings and step cap, its Q tables kept. Returns the share of episodes that hit
    the cap (``capped``; ``capped_last``: in the last tenth), the agents trapped at the end
    (``trapped`` of ``agents``: TRAPPED), the share of the agents' own values on the aisle
    (:func:`aisle_cells`) that are exactly 0 (``aisle_zero``), and the mean over the aisle of each
    agent's best own value, for the trapped agents and the others (``best_trapped``, ``best_free``),
    the same over the other free cells but the goal for the trapped agents (``elsewhere_trapped``),
    and the runs' ``outputs``. The runs draw from the study's seeds of (seed, learner, N), or from
    ``master_seed``."""
    check_trap(runs, episodes)
    learner, gridmap = registry.get(name), config.gridmap(n)
    schedule = ep.Schedule(episodes, ep.uniform_edges(episodes, episodes // 10), config.max_steps)
    master_seed = seed_of(seed, name, n) if master_seed is None else master_seed
    out = training.train(learner, config.setup(name), gridmap, schedule, runs, master_seed, bounce=config.bounce,
                         rewards=config.rewards, workers=workers)
    capped = ep.metric(out["log"], "capped")
    trapped = out["log"][:, -1, :n] >= TRAPPED * config.max_steps  # (runs, agents)
    aisle = aisle_cells(gridmap)
    elsewhere = np.setdiff1d(np.flatnonzero(~gridmap.blocked & ~gridmap.is_goal), aisle)
    own = out["q"][:, :, aisle, :]
    best = own.max(axis=-1).mean(axis=-1)  # (runs, agents)
    best_elsewhere = out["q"][:, :, elsewhere, :].max(axis=-1).mean(axis=-1)
    return {"capped": float(capped.mean()), "capped_last": float(capped[:, -1].mean()),
            "trapped": int(trapped.sum()), "agents": int(trapped.size), "aisle_zero": float((own == 0.0).mean()),
            "best_trapped": _mean_where(best, trapped), "best_free": _mean_where(best, ~trapped),
            "elsewhere_trapped": _mean_where(best_elsewhere, trapped), "outputs": out}


def check_trap(runs: int, episodes: int) -> None:
    """Refuse in one line what :func:`trap` cannot measure: no run, or episodes that are not tenths."""
    for name, value, low in (("runs", runs, 1), ("episodes", episodes, 10)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise UserError(f"{name} must be a whole number >= {low}, got {value!r}")
    if episodes % 10:
        raise UserError(f"episodes must be a multiple of 10 (the trap reads the last tenth), got {episodes}")


def _mean_where(values: np.ndarray, chosen: np.ndarray) -> float:
    return float(values[chosen].mean()) if chosen.any() else math.nan
