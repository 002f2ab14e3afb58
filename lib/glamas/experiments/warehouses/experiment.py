"""Many agents measured against a plan: every learner on many generated warehouses per number of
agents, under both reward formulations, beside a reference plan of each instance.

One warehouse per N (the study of many agents, :data:`glamas.experiments.scaling.MANY_AGENTS`)
cannot tell a method from a map. Here each N has :attr:`WarehousesConfig.instances` warehouses
(:func:`glamas.gridworld.generate.warehouse` with seeds 0, 1, ...), each trained once per learner
and formulation: the instances are the replicates. Each instance has a reference plan by
prioritized planning (:func:`glamas.gridworld.prioritized.plan`), so that what a learner reaches
stands next to what a plan of the same instance reaches, counted as multi-agent path finding counts
it (the many-agent grid benchmark POGEMA reports the same): the share of episodes in which every
agent reaches its goal (CSR), the share of agents that do (ISR), the sum of costs (every agent's
steps until it is in) and the makespan (the last arrival).

The learners train with the scaling study's settings under each formulation (the benchmark's
:data:`~glamas.experiments.benchmark_maps.FORMULATIONS`: the chapter's rewards and Q-learning, or
the field's step costs with the field's learning settings), on the field's schedule of 2000
episodes, and are evaluated greedily afterwards (learning off). Their logs are kept per episode,
one N at a time, and reduced to what is stored: the learning curve in blocks (CSR, ISR,
collisions), the first episode from which ISR stays high, and which agents ever reached their goal
while learning, the first thing to know of an agent that the greedy policy does not bring in.
"""

from dataclasses import dataclass, field

import numpy as np

from glamas import checks, memory, parallel, seeds, training
from glamas.errors import UserError
from glamas.experiments.benchmark_maps.experiment import FORMULATIONS
from glamas.experiments.gridworld.experiment import check_learners
from glamas.gridworld import GridMap, generate, prioritized
from glamas.gridworld.rewards import CHAPTER
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.qlearning import QSettings

LEARNERS = ("independent", "two_observe", "two_observe_rule", "sparse_maq", "cq")
"""The learners that fit many agents (the joint learners' tables do not, from N = 8 on)."""
GREEDY = ("completed", "in_goal", "sum_of_costs", "makespan", "collisions", "coordinations")
"""What each greedy episode stores: 1 if every agent is in (CSR's episodes), the share of agents
in (ISR), the agents' steps summed (an agent not in counts the cap), the episode's length, its
collisions and its coordinations (2observe's; 0 for the others)."""
CURVE = ("completed", "in_goal", "collisions")
"""The learning curve's block means: CSR, ISR and collisions per episode while learning."""
HIGH_ISR = 0.95
"""The ISR a learning curve must hold to count as having learned (:attr:`WarehousesResult.reached`)."""
FORMULATION_Q = {name: settings.get("q", QSettings()) for name, settings in FORMULATIONS.items()}
"""Each formulation's Q-learning settings (the chapter's by default)."""
FORMULATION_REWARDS = {name: settings.get("rewards", CHAPTER) for name, settings in FORMULATIONS.items()}
"""Each formulation's rewards (the chapter's by default)."""


@dataclass(frozen=True)
class WarehousesConfig:
    """Settings of the benchmark of instances: the numbers of agents, the instances of each, the
    formulations and learners, and the scaling study's schedule and budget."""

    agents: tuple = (8, 32, 128)
    """Numbers of agents N; each has :attr:`instances` generated warehouses."""
    instances: int = 16
    """Warehouses per N: ``generate.warehouse(N, seed)`` for seeds 0 to instances - 1."""
    density: float = 0.1
    """Agents per free cell of the generated warehouses (the study of many agents')."""
    formulations: tuple = tuple(FORMULATIONS)
    """Reward formulations (the benchmark's FORMULATIONS), each with the learning settings it comes with."""
    learners: tuple = LEARNERS
    """Learners to train: distinct names of registered learners."""
    settings: dict = field(default_factory=dict)
    """Each learner's own settings by its name (a formulation's own replace its learners')."""
    bounce: str = "previous"
    """Where a collided agent goes (glamas.gridworld.rules)."""
    max_steps: int = 1000
    """Step cap per episode (the study of many agents'): many times every plan's makespan."""
    episodes: int = 2000
    """Episodes per run (the field's schedule)."""
    blocks: int = 20
    """Points of the learning curves: blocks of episodes of one size; must divide ``episodes``."""
    window: int = 100
    """Episodes over which ISR must average at least HIGH_ISR for a run to count as having learned."""
    evaluation_episodes: int = 10
    """Greedy episodes after training (learning off), each kept."""
    memory_budget_gib: float = 4.0
    """Memory the tables of one run may take, in GiB; a learner whose tables would need more is
    skipped at that N (CQ-learning from 32 agents on, sparse MAQ at 128)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"instances": 1, "max_steps": 1, "episodes": 1, "blocks": 1, "window": 1,
                                    "evaluation_episodes": 1})
        checks.agent_counts(self, 3)
        checks.distinct_names(self, "formulations", FORMULATIONS, "reward formulations")
        check_learners(self, FORMULATION_Q["chapter"])
        if self.episodes % self.blocks:
            raise UserError(f"blocks ({self.blocks}) must divide episodes ({self.episodes}); choose e.g. 20")
        if self.window > self.episodes:
            raise UserError(f"window ({self.window}) must be at most episodes ({self.episodes})")
        checks.positive(self, "memory_budget_gib")
        generate.check_arguments(max(self.agents), self.instances - 1, self.density)
        generate.check_fits(max(self.agents), self.density)

    def gridmap(self, n: int, instance: int) -> GridMap:
        """Warehouse ``instance`` of ``n`` agents."""
        return generate.warehouse(n, instance, self.density)

    def setup(self, formulation: str, name: str) -> spec.Setup:
        """What learner ``name`` runs with under ``formulation``: the formulation's Q-learning
        settings, and its own settings (the formulation's for it, else the config's)."""
        own = FORMULATIONS[formulation].get("settings", {}).get(name, self.settings.get(name))
        return registry.get(name).setup(FORMULATION_Q[formulation], own)

    def rewards(self, formulation: str):
        """What a step pays under ``formulation``."""
        return FORMULATION_REWARDS[formulation]

    def schedule(self) -> ep.Schedule:
        """Training with every episode in a row of its own (reduced after the runs: :func:`reduce_log`)."""
        return ep.Schedule(self.episodes, ep.uniform_edges(self.episodes, 1), self.max_steps)

    def memory_bytes(self) -> int:
        """Bytes held at once, for the N that takes the most: every run of that N within the budget
        with its tables (a learner's own tables come back to this process; the Q tables stay in the
        worker, one run's at a time with the runner's copies) and its per-episode log, and the
        stored arrays."""
        budget = self.memory_budget_gib * 2 ** 30

        def of_n(n: int) -> int:
            gridmap = self.gridmap(n, 0)
            runs = [need for f in self.formulations for name in self.learners
                    if (need := registry.get(name).bytes_per_run(self.setup(f, name), gridmap)) <= budget]
            logs = self.episodes * ep.n_columns(n) * memory.BYTES_PER_VALUE
            return self.instances * (sum(runs) + len(runs) * logs) + max(runs, default=0) * memory.WORKING_COPIES

        keys = len(self.formulations) * len(self.agents) * len(self.learners) * self.instances
        stored = keys * (self.evaluation_episodes * len(GREEDY) + self.blocks * len(CURVE) + 4)
        return max(of_n(n) for n in self.agents) + stored * memory.BYTES_PER_VALUE


@dataclass(frozen=True)
class WarehousesResult:
    """For every (formulation, N, learner, instance): the greedy episodes after training, the
    learning curve, when ISR first stayed high, and which agents never reached their goal while
    learning; for every (N, instance): the reference plan and the lower bounds. All arrays; NaN
    (or -1) where a learner did not run."""

    config: WarehousesConfig
    """The configuration that produced the arrays."""
    formulations: np.ndarray
    """str (formulations,)."""
    agents: np.ndarray
    """int (agents,): the numbers of agents N."""
    learners: np.ndarray
    """str (learners,)."""
    ran: np.ndarray
    """bool (formulations, agents, learners): whether the learner ran (its tables fit the budget)."""
    bytes_needed: np.ndarray
    """int (formulations, agents, learners): bytes of one run's tables on the first instance."""
    greedy: np.ndarray
    """(formulations, agents, learners, instances, evaluation episodes, GREEDY): each greedy episode."""
    curve: np.ndarray
    """(formulations, agents, learners, instances, blocks, CURVE): the learning curve's block means."""
    reached: np.ndarray
    """int (formulations, agents, learners, instances): the episodes after which the mean ISR over
    the last ``window`` episodes first reached HIGH_ISR; -1 where it never did within the budget."""
    never_in: np.ndarray
    """(formulations, agents, learners, instances): the share of the agents that the last greedy
    episode leaves short of their goal and that never reached it in any training episode
    (NaN where every agent is in)."""
    short: np.ndarray
    """(formulations, agents, learners, instances): the share of all agents that the last greedy
    episode leaves short of their goal."""
    plans: np.ndarray
    """int (agents, instances, 4): the plan's sum of costs and makespan, then the lower bounds' (each
    agent's shortest path alone, summed and their largest)."""

    def names(self) -> list[str]:
        return [str(name) for name in self.learners]

    def index(self, formulation: str, n: int, learner: str) -> tuple:
        return (list(self.formulations).index(formulation), list(self.agents).index(n),
                list(self.learners).index(learner))

    def greedy_metric(self, formulation: str, n: int, learner: str, metric: str) -> np.ndarray:
        """(instances, episodes): one of GREEDY for each greedy episode."""
        return self.greedy[self.index(formulation, n, learner)][..., GREEDY.index(metric)]

    def curve_metric(self, formulation: str, n: int, learner: str, metric: str) -> np.ndarray:
        """(instances, blocks): one of CURVE per block of the learning curves."""
        return self.curve[self.index(formulation, n, learner)][..., CURVE.index(metric)]

    def plan(self, n: int) -> np.ndarray:
        """int (instances, 4): sum of costs, makespan, and their lower bounds, per instance."""
        return self.plans[list(self.agents).index(n)]

    def block_ends(self) -> np.ndarray:
        """The episode that ends each block of the learning curves."""
        size = self.config.episodes // self.config.blocks
        return np.arange(size, self.config.episodes + 1, size)


def seed_of(seed: int, formulation: str, n: int, instance: int, learner: str) -> int:
    """The master seed of one run, named by the master ``seed``, this experiment, the formulation,
    N, the instance and the learner (:func:`glamas.seeds.named`)."""
    return seeds.named(seed, "warehouses", formulation, n, instance, learner)


def reduce_log(log: np.ndarray, n: int, max_steps: int, blocks: int, window: int) -> tuple:
    """From one run's per-episode log (episodes, columns): the curve (blocks, CURVE), the episodes
    until ISR held (see ``WarehousesResult.reached``) and the agents that ever arrived (bool (n,)).
    An agent is in when its steps are below the cap (one arriving on the capping step counts as out)."""
    per_episode = greedy_rows(log, n, max_steps)[:, [GREEDY.index(name) for name in CURVE]]
    curve = per_episode.reshape(blocks, -1, len(CURVE)).mean(axis=1)
    in_goal = per_episode[:, CURVE.index("in_goal")]
    held = np.convolve(in_goal, np.ones(window) / window, mode="valid") >= HIGH_ISR
    reached = int(np.argmax(held)) + window if held.any() else -1
    return curve, reached, (log[:, :n] < max_steps).any(axis=0)


def greedy_rows(log: np.ndarray, n: int, max_steps: int) -> np.ndarray:
    """(episodes, GREEDY) from a per-episode log (an agent is in when its steps are below the cap)."""
    steps = log[:, :n]
    return np.stack([1.0 - log[:, ep.column(n, ep.CAPPED)], (steps < max_steps).mean(axis=1), steps.sum(axis=1),
                     log[:, ep.column(n, ep.LENGTH)], log[:, ep.column(n, ep.COLLISIONS)],
                     log[:, ep.column(n, ep.COORDINATIONS)]], axis=-1)


def run(config: WarehousesConfig = WarehousesConfig(), seed: int = 0, workers=None, progress=None) -> WarehousesResult:
    """Plan every instance, then train and evaluate every learner on it under every formulation
    (one run each), N by N so that the per-episode logs of one N are held at a time."""
    f_, a_, l_, i_ = len(config.formulations), len(config.agents), len(config.learners), config.instances
    ran = np.zeros((f_, a_, l_), dtype=bool)
    needed = np.zeros((f_, a_, l_), dtype=np.int64)
    greedy = np.full((f_, a_, l_, i_, config.evaluation_episodes, len(GREEDY)), np.nan)
    curve = np.full((f_, a_, l_, i_, config.blocks, len(CURVE)), np.nan)
    reached = np.full((f_, a_, l_, i_), -1, dtype=np.int64)
    never_in = np.full((f_, a_, l_, i_), np.nan)
    short = np.full((f_, a_, l_, i_), np.nan)
    plans = np.zeros((a_, i_, 4), dtype=np.int64)
    budget = config.memory_budget_gib * 2 ** 30
    evaluation = training.Evaluation(config.evaluation_episodes, (1.0,), per_episode=True)
    for a, n in enumerate(config.agents):
        gridmaps = [config.gridmap(n, instance) for instance in range(i_)]
        for instance, gridmap in enumerate(gridmaps):
            plan = prioritized.plan(gridmap, config.bounce)
            plans[a, instance] = (plan.sum_of_costs, plan.makespan, *prioritized.lower_bounds(gridmap))
        batches = {}
        for f, formulation in enumerate(config.formulations):
            for k, name in enumerate(config.learners):
                learner, setup = registry.get(name), config.setup(formulation, name)
                # an MMDP's tables for many agents need more bytes than an int64 holds: they never fit
                needed[f, a, k] = min(learner.bytes_per_run(setup, gridmaps[0]), np.iinfo(np.int64).max)
                if needed[f, a, k] > budget:
                    continue
                ran[f, a, k] = True
                for instance, gridmap in enumerate(gridmaps):
                    batches[f, k, instance] = training.batch(
                        learner, setup, gridmap, config.schedule(), 1, seed_of(seed, formulation, n, instance, name),
                        bounce=config.bounce, rewards=config.rewards(formulation), keep_q=False, evaluation=evaluation)
        parallel.run_many([work for work, _ in batches.values()], workers=workers, progress=progress, chunk=1)
        for (f, k, instance), (_, outputs) in batches.items():
            curve[f, a, k, instance], reached[f, a, k, instance], ever = reduce_log(
                outputs["log"][0], n, config.max_steps, config.blocks, config.window)
            rows = greedy_rows(outputs["evaluated"][0][0], n, config.max_steps)
            greedy[f, a, k, instance] = rows
            out = outputs["evaluated"][0][0][-1, :n] >= config.max_steps  # the last greedy episode's agents not in
            short[f, a, k, instance] = out.mean()
            never_in[f, a, k, instance] = (out & ~ever).sum() / out.sum() if out.any() else np.nan
    return WarehousesResult(config=config, formulations=np.array(config.formulations),
                            agents=np.array(config.agents, dtype=np.int64), learners=np.array(config.learners),
                            ran=ran, bytes_needed=needed, greedy=greedy, curve=curve, reached=reached,
                            never_in=never_in, short=short, plans=plans)


def scaled(runs: int, episodes: int) -> WarehousesConfig:
    """The benchmark at ``runs`` instances per N and ``episodes`` (in blocks that divide them)."""
    blocks = next(b for b in range(min(WarehousesConfig.blocks, episodes), 0, -1) if episodes % b == 0)
    return WarehousesConfig(instances=runs, episodes=episodes, blocks=blocks,
                            window=min(WarehousesConfig.window, episodes))
