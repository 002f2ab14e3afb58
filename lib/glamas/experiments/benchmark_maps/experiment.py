"""The sparse-interaction benchmark, configured and run: every learner on each of the field's maps
(TunnelToGoal with 2, 3 and 4 agents; ISR, CIT and CMU, where two robots swap places through
narrow corridors), against each map's exact optimum.

The learners train as in the scaling study (:func:`glamas.experiments.scaling.experiment.sweep`:
the same settings by learner name, a learner skipped on a map where its tables exceed the memory
budget, each run evaluated with learning off after training), on the field's schedule: 2000
episodes with a fixed exploration, as De Hauwere, Vrancx and Nowé evaluate CQ-learning on these
maps. The optimum (:func:`glamas.gridworld.dp.exact_optimum`) is value iteration on the joint MMDP,
the chapter's Alg. 2, where its tables fit, and an exhaustive search of joint episodes elsewhere
(TunnelToGoal with 4 agents): exact on every map.
"""

from dataclasses import dataclass, field, replace

import numpy as np

from glamas import checks, memory, training
from glamas.errors import UserError
from glamas.experiments.gridworld.experiment import check_learners
from glamas.experiments.scaling.experiment import METHODS, METRICS, sweep
from glamas.gridworld import GridMap, dp, load_map, plans
from glamas.gridworld import rewards as formulations
from glamas.gridworld.rewards import Rewards
from glamas.learners import episode as ep
from glamas.learners import cq, registry, spec
from glamas.qlearning import QSettings

FIELD_MAPS = ("tunnel_to_goal", "tunnel_to_goal_3", "tunnel_to_goal_4", "isr", "cit", "cmu")
"""The maps of the sparse-interaction literature, in data/maps."""
MAX_AGENTS = 4
"""The most agents of a field map: the optimum's arrays hold this many agents (-1 beyond a map's own)."""
PLANS = ("sum_of_costs", "makespan")
"""The optimal plans as path finding counts them (glamas.gridworld.plans), in the order of
``BenchmarkResult.plan_steps``: the least sum of costs, the least makespan."""


@dataclass(frozen=True)
class BenchmarkConfig:
    """Settings of the benchmark: the maps, the learners and their settings (as the scaling study's:
    the shared Q-learning settings and each learner's own by its name), the collision rule and the
    schedule."""

    maps: tuple = FIELD_MAPS
    """The maps: names in data/maps or map files' paths (:func:`glamas.gridworld.load_map`)."""
    learners: tuple = METHODS
    """Learners to train: distinct names of registered learners."""
    q: QSettings = QSettings()
    """Tabular Q-learning, shared by every learner (the chapter's, Sec. 5.3)."""
    settings: dict = field(default_factory=dict)
    """Each learner's own settings by its name, completed with the defaults of every trained learner."""
    bounce: str = "previous"
    """Where a collided agent goes (glamas.gridworld.rules)."""
    rewards: Rewards = Rewards()
    """What a step pays (glamas.gridworld.rewards): the chapter's by default; :data:`FORMULATIONS`
    names the field's with the learning settings it comes with."""
    max_steps: int = 1000
    """Step cap per episode: an agent trapped early on would otherwise take a run's time."""
    episodes: int = 2000
    """Episodes per run: the field's evaluation of CQ-learning on these maps runs 2000."""
    runs: int = 10
    """Independent runs per (learner, map)."""
    bins: int = 50
    """Points of the learning curves: blocks of episodes with log-spaced ends (glamas.learners.episode)."""
    memory_budget_gib: float = 4.0
    """Memory the Q tables of all runs of one (learner, map) may take, in GiB; a learner whose
    tables would need more is skipped on that map (the joint learners on TunnelToGoal with 4 agents)."""
    evaluation_episodes: int = 100
    """Episodes of each evaluation of what a run learned, learning off (glamas.training.EVALUATIONS)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"max_steps": 1, "episodes": 1, "runs": 1, "bins": 1, "evaluation_episodes": 1})
        maps = tuple(self.maps) if isinstance(self.maps, (tuple, list)) else ()
        if not maps or len(set(maps)) != len(maps) or not all(isinstance(name, str) for name in maps):
            raise UserError(f"maps must be distinct map names or paths, got {self.maps!r}")
        object.__setattr__(self, "maps", maps)
        check_learners(self, self.q)
        checks.positive(self, "memory_budget_gib")
        for name in maps:
            if self.gridmap(name).n_agents > MAX_AGENTS:
                raise UserError(f"map {name!r} has more than {MAX_AGENTS} agents: the benchmark's maps have 2 to "
                                f"{MAX_AGENTS}; run many agents in the scaling study")

    def gridmap(self, name: str) -> GridMap:
        """Map ``name`` (:func:`glamas.gridworld.load_map`)."""
        return load_map(name)

    def setup(self, name: str) -> spec.Setup:
        """What learner ``name`` runs with: the Q-learning settings and its own."""
        return registry.get(name).setup(self.q, self.settings.get(name))

    def edges(self) -> np.ndarray:
        """The learning curves' block edges (glamas.learners.episode.log_edges)."""
        return ep.log_edges(self.episodes, self.bins)

    @property
    def n_bins(self) -> int:
        return self.edges().size - 1

    def schedule(self) -> ep.Schedule:
        return ep.Schedule(self.episodes, self.edges(), self.max_steps)

    def memory_bytes(self) -> int:
        """Bytes of the largest runs held at once (one (learner, map) within the budget, its runs'
        tables with the runner's and an evaluation's copies), the logs and the optimum's tables."""
        budget = self.memory_budget_gib * 2 ** 30
        needs = [self.runs * registry.get(name).bytes_per_run(self.setup(name), self.gridmap(m))
                 for m in self.maps for name in self.learners]
        largest = max((need for need in needs if need <= budget), default=0)
        logs = (len(self.learners) * len(self.maps) * self.runs * (self.n_bins + len(training.EVALUATIONS))
                * len(METRICS))
        optimum = max(dp.tabulated_bytes(self.gridmap(m)) if dp.tabulable(self.gridmap(m)) else 0 for m in self.maps)
        return largest * (memory.WORKING_COPIES + 1) + logs * memory.BYTES_PER_VALUE + optimum


OPTIMUM_DISCOUNT = QSettings().discount
"""The discount of the optimum (the chapter's joint MMDP, Fig. 9's): the chapter's, whatever the
learners' formulation. Under the field's (discount 1, 0 at the goal) the MMDP of the chapter's
rewards would value every collision-free plan alike."""

FIELD_Q = QSettings(q_learning_rate=0.1, q_initial=0.0, exploit_prob=0.9, discount=1.0)
"""The field's Q-learning: learning rate 0.1, discount 1, exploration 0.1 (the public
implementation's evaluation script)."""
FIELD_CQ = cq.Settings(cq_solo_episodes=10_000, cq_solo_exploit_prob=0.2)
"""The field's phase alone: 10,000 episodes at exploration 0.8 (its pre-learning files)."""
FORMULATIONS = {"chapter": {},
                "field": {"rewards": formulations.FIELD, "q": FIELD_Q, "settings": {"cq": FIELD_CQ}}}
"""The settings each reward formulation comes with: the chapter's are the defaults; the field's
rewards come with the field's learning settings (docs/reproduction-notes.md)."""


def configured(formulation: str, **changes) -> BenchmarkConfig:
    """The benchmark under ``formulation`` (:data:`FORMULATIONS`), with ``changes`` to its fields."""
    if formulation not in FORMULATIONS:
        raise UserError(f"formulation must be one of {sorted(FORMULATIONS)}, got {formulation!r}")
    return replace(BenchmarkConfig(), **{**FORMULATIONS[formulation], **changes})


def case_names(seed: int, map_name: str) -> tuple:
    """What names the runs on map ``map_name`` (:func:`glamas.experiments.scaling.experiment.sweep`,
    :func:`glamas.seeds.named`): the seed, the benchmark and the map, so that a map's runs keep
    their streams whatever other maps run, under either formulation and at every budget."""
    return seed, "benchmark_maps", map_name


@dataclass(frozen=True)
class BenchmarkResult:
    """Agent-mean learning curves, evaluations and table sizes for every (learner, map), and each
    map's exact optimum; all arrays (the scaling study's, with maps for numbers of agents)."""

    config: BenchmarkConfig
    """The configuration that produced the arrays."""
    learners: np.ndarray
    """str (learners,): the learners' names, in the order of the other arrays."""
    maps: np.ndarray
    """str (maps,): the maps' names."""
    ran: np.ndarray
    """bool (learners, maps): whether the learner ran (False: its tables exceed the budget)."""
    table_shapes: np.ndarray
    """int (learners, maps, 3): (tables, states, actions) of the Q tables per run."""
    gla_parameters: np.ndarray
    """int (learners, maps): GLA parameters per run."""
    joint_entries: np.ndarray
    """float (learners, maps): joint values per run beyond the Q tables (mean over runs)."""
    reward_samples: np.ndarray
    """int (learners, maps): immediate rewards kept per run for a statistical test (CQ-learning)."""
    bytes_needed: np.ndarray
    """int (learners, maps): bytes of Q tables for all runs together."""
    log: np.ndarray
    """(learners, maps, runs, bins, METRICS): block means of the agent-mean measurements; NaN where skipped."""
    evaluated: np.ndarray
    """(learners, maps, runs, evaluations, METRICS): each run evaluated with learning off
    (glamas.training.EVALUATIONS); NaN where skipped."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block."""
    optimum_steps: np.ndarray
    """int (maps, MAX_AGENTS): each agent's steps to its goal in an optimal episode (-1 beyond the map's agents)."""
    optimum_returns: np.ndarray
    """float (maps, MAX_AGENTS): each agent's undiscounted return in that episode (NaN beyond its agents)."""
    optimum_cells: np.ndarray
    """int (maps, steps + 1, MAX_AGENTS): the agents' cells in that episode, starts first (-1 after
    its end and beyond the map's agents)."""
    plan_steps: np.ndarray
    """int (maps, PLANS, MAX_AGENTS): each agent's steps in the collision-free plan of least sum of
    costs and in the one of least makespan (glamas.gridworld.plans; -1 beyond the map's agents, and
    on a map whose joint tables do not fit)."""
    plan_cells: np.ndarray
    """int (maps, PLANS, steps + 1, MAX_AGENTS): the agents' cells in those plans, starts first (-1
    after a plan's end, beyond the map's agents, and on a map whose joint tables do not fit)."""

    def names(self) -> list[str]:
        return [str(name) for name in self.learners]

    def map_names(self) -> list[str]:
        return [str(name) for name in self.maps]

    def _case(self, learner: str, map_name: str) -> tuple:
        return self.names().index(learner), self.map_names().index(map_name)

    def curves(self, learner: str, map_name: str, metric: str) -> np.ndarray:
        """(runs, bins) block means of one of METRICS."""
        k, j = self._case(learner, map_name)
        return self.log[k, j, :, :, METRICS.index(metric)]

    def evaluation(self, learner: str, map_name: str, metric: str, mode: str = "greedy") -> np.ndarray:
        """(runs,): one of METRICS, or ``completion`` (1 - capped), under evaluation ``mode``."""
        k, j = self._case(learner, map_name)
        rows = self.evaluated[k, j, :, training.EVALUATIONS.index(mode)]
        if metric == "completion":
            return np.clip(1.0 - rows[:, METRICS.index("capped")], 0.0, 1.0)
        return rows[:, METRICS.index(metric)]

    def optimum(self, map_name: str) -> dict:
        """Map ``map_name``'s optimal episode as the learners' measurements read it: its length
        (until every agent is in: the same in every optimal episode, where the agent means of steps
        may differ between equally good ones), agent means of steps and return, no collisions."""
        j = self.map_names().index(map_name)
        steps, returns = self.optimum_steps[j], self.optimum_returns[j]
        agents = steps >= 0
        return {"length": float(steps.max()), "steps": float(steps[agents].mean()),
                "reward": float(returns[agents].mean()), "collisions": 0.0}

    def plan(self, map_name: str, kind: str = "sum_of_costs") -> dict:
        """Map ``map_name``'s optimal plan of ``kind`` (:data:`PLANS`): each agent's steps, its sum
        of costs and makespan; None for each on a map whose joint tables do not fit (its lower
        bounds: :func:`glamas.gridworld.plans.lower_bounds`)."""
        j = self.map_names().index(map_name)
        row = self.plan_steps[j, PLANS.index(kind)]
        steps = row[:int((self.optimum_steps[j] >= 0).sum())]  # the map's agents
        known = bool((steps >= 0).all())
        return {"steps": steps.tolist() if known else None, "sum_of_costs": int(steps.sum()) if known else None,
                "makespan": int(steps.max()) if known else None}

    def plan_episode(self, map_name: str, kind: str = "sum_of_costs") -> np.ndarray:
        """int (steps + 1, agents): the agents' cells in map ``map_name``'s optimal plan of ``kind``."""
        j = self.map_names().index(map_name)
        n = int((self.optimum_steps[j] >= 0).sum())
        cells = self.plan_cells[j, PLANS.index(kind), :, :n]
        return cells[(cells >= 0).all(axis=1)]

    def optimum_episode(self, map_name: str) -> np.ndarray:
        """int (steps + 1, agents): the agents' cells in map ``map_name``'s optimal episode."""
        j = self.map_names().index(map_name)
        n = int((self.optimum_steps[j] >= 0).sum())
        cells = self.optimum_cells[j, :, :n]
        return cells[(cells >= 0).all(axis=1)]


def run(config: BenchmarkConfig = BenchmarkConfig(), seed: int = 0, workers=None, progress=None) -> BenchmarkResult:
    """Every learner on every map (:func:`glamas.experiments.scaling.experiment.sweep`), and each
    map's exact optimum (:func:`glamas.gridworld.dp.exact_optimum` at :data:`OPTIMUM_DISCOUNT`)."""
    gridmaps = [config.gridmap(name) for name in config.maps]
    arrays = sweep(config, gridmaps, [case_names(seed, name) for name in config.maps], workers, progress)
    episodes = [dp.exact_optimum(gridmap, OPTIMUM_DISCOUNT, config.bounce) for gridmap in gridmaps]
    steps = np.full((len(gridmaps), MAX_AGENTS), -1, dtype=np.int64)
    returns = np.full((len(gridmaps), MAX_AGENTS), np.nan)
    cells = np.full((len(gridmaps), max(e.cells.shape[0] for e in episodes), MAX_AGENTS), -1, dtype=np.int64)
    for j, (gridmap, episode) in enumerate(zip(gridmaps, episodes)):
        n = gridmap.n_agents
        steps[j, :n], returns[j, :n], cells[j, :episode.cells.shape[0], :n] = (episode.steps_to_goal, episode.returns,
                                                                                episode.cells)
    plan_steps, plan_cells = optimal_plans(gridmaps, config.bounce)
    return BenchmarkResult(config=config, learners=np.array(config.learners), maps=np.array(config.maps), **arrays,
                           optimum_steps=steps, optimum_returns=returns, optimum_cells=cells,
                           plan_steps=plan_steps, plan_cells=plan_cells)


def optimal_plans(gridmaps: list, bounce: str) -> tuple[np.ndarray, np.ndarray]:
    """Each optimal plan (:data:`PLANS`) of every map whose joint tables fit: int (maps, PLANS,
    MAX_AGENTS), each agent's steps, and int (maps, PLANS, steps + 1, MAX_AGENTS), its cells (-1
    elsewhere, after a plan's end and beyond a map's agents)."""
    found = {(j, k): find(gridmap, bounce) for j, gridmap in enumerate(gridmaps) if dp.tabulable(gridmap)
             for k, find in enumerate((plans.least_sum_of_costs, plans.least_makespan))}
    longest = max((plan.cells.shape[0] for plan in found.values()), default=1)
    steps = np.full((len(gridmaps), len(PLANS), MAX_AGENTS), -1, dtype=np.int64)
    cells = np.full((len(gridmaps), len(PLANS), longest, MAX_AGENTS), -1, dtype=np.int64)
    for (j, k), plan in found.items():
        n = plan.steps.size
        steps[j, k, :n], cells[j, k, :plan.cells.shape[0], :n] = plan.steps, plan.cells
    return steps, cells


def scaled(runs: int, episodes: int) -> BenchmarkConfig:
    """The benchmark at ``runs`` and ``episodes``."""
    return BenchmarkConfig(runs=runs, episodes=episodes)


def field_scaled(runs: int, episodes: int) -> BenchmarkConfig:
    """The benchmark under the field's formulation at ``runs`` and ``episodes``."""
    return configured("field", runs=runs, episodes=episodes)
