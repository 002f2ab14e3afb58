"""The benchmarks' one door to glamas's compiled code: what a gridworld benchmark runs (a
:class:`Workload`), the run kernels' arguments built from it, and the calls.

Only this module knows the kernels' argument lists: the benchmarks, the C reference
(``c_reference``) and the tests of the references ask it for a kernel's outputs, so that a
change of those lists is adapted here alone. The runs go through ``glamas.runs`` as the
experiments' do: run ``r`` of ``seed`` draws from :func:`run_state` ``(seed, r)``.
"""

import functools
import time
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from glamas import rng, runs
from glamas.experiments.gridworld import GridworldConfig, delta_scale
from glamas.experiments.related_work import RelatedWorkConfig
from glamas.gridworld import BOUNCE_MODES, load_map, rules
from glamas.learners import cq, group_observe, independent, joint_state, mmdp, sparse_maq, two_observe
from glamas.learners import episode as ep
from glamas.paths import MAPS

Q_LEARNERS = {"independent": independent, "joint_state": joint_state, "mmdp": mmdp}
"""The chapter's Q-learners, which take the same arguments."""
OBSERVERS = {"two_observe": two_observe, "group_observe": group_observe}
"""2observe (Alg. 4, two agents) and its N-agent form, which take the same arguments."""
MODULES = {**Q_LEARNERS, **OBSERVERS, "sparse_maq": sparse_maq, "cq": cq}
LEARNERS = tuple(MODULES)
_RELATED = RelatedWorkConfig()


@dataclass(frozen=True)
class Workload:
    """One learner on one map for a number of episodes, with the experiments' settings."""

    learner: str
    """One of LEARNERS; sparse_maq runs sparse_maq.run with two agents and run_pairs with more."""
    episodes: int
    """Episodes of the run (CQ-learning: of the joint phase, after ``cq_solo_episodes``)."""
    map_file: str = "tunnel_to_goal.txt"
    """A map of data/maps."""
    block: int = 1
    """Episodes per row of the log (it must divide ``episodes``); 1: a row per episode."""
    learning: GridworldConfig = field(default_factory=GridworldConfig)
    """Q-learning, GLA and collision settings (the Section 5.3 experiment's by default); its map,
    learners, episodes, runs, bins and q_initial are not used (the tables start at zero)."""
    coordination_distance: int = _RELATED.coordination_distance
    """Sparse tabular MAQ: agents coordinate at Manhattan distance at most this."""
    cq_window: int = _RELATED.cq_window
    """CQ-learning: rewards kept per state-action, in the baseline and in the recent window."""
    cq_significance: float = _RELATED.cq_significance
    """CQ-learning: significance level of its t-test."""
    cq_solo_episodes: int = 0
    """CQ-learning: episodes each agent first learns alone."""

    def __post_init__(self):
        if self.learner not in LEARNERS:
            raise ValueError(f"learner must be one of {LEARNERS}, got {self.learner!r}")
        if self.episodes % self.block:
            raise ValueError(f"block ({self.block}) must divide episodes ({self.episodes})")

    def gridmap(self):
        return load_map(MAPS / self.map_file)

    def edges(self) -> np.ndarray:
        return ep.uniform_edges(self.episodes, self.block)

    def t_critical(self) -> np.ndarray:
        """CQ-learning's two-sided critical values of Student's t, by degrees of freedom."""
        return _t_critical(self.cq_window, self.cq_significance)


@functools.cache
def _t_critical(window: int, significance: float) -> np.ndarray:
    """Computed once per setting (a bisection in Python), so that no timing counts it: the kernel
    and the Python reference get the table ready-made."""
    return cq.t_critical_values(2 * window - 2, significance)


@dataclass
class Outputs:
    """A run kernel's outputs, each with a first axis of runs, and the time the runs took."""

    arrays: dict
    """The output arrays by name (q, log and the learner's own), in the kernel's order."""
    seconds: float
    """This thread's CPU time in the runs when they ran in this thread, else their wall time."""
    block: int
    """Episodes per row of the log."""

    @property
    def log(self) -> np.ndarray:
        return self.arrays["log"]

    def steps(self) -> float:
        """Environment steps (joint moves) of every run together."""
        n_agents = (self.log.shape[-1] - 4) // 2
        return float(self.log[..., ep.column(n_agents, ep.LENGTH)].sum() * self.block)


def run_state(seed: int, run: int = 0) -> np.ndarray:
    """The generator state of run ``run`` of ``seed`` (glamas.rng.chunk_states), as the kernels get it."""
    return rng.chunk_states(seed, run, run + 1)[0]


def new_outputs(workload: Workload, n_runs: int) -> dict:
    """Fresh outputs of ``n_runs`` runs of the workload's kernel, in the kernel's order."""
    g, name = workload.gridmap(), workload.learner
    n, module = g.n_agents, MODULES[name]
    arrays = {"q": np.stack([module.new_tables(g.n_cells, n)] * n_runs)}
    if name in OBSERVERS:
        arrays["u"] = np.zeros((n_runs,) + module.new_gla_parameters(n).shape)
        arrays["need_counts"] = np.zeros((n_runs,) + module.new_need_counts(g.n_rows, g.n_cols).shape)
    elif name == "sparse_maq":
        index = sparse_maq.pair_coordination_index(g, workload.coordination_distance)
        joint = sparse_maq.new_joint_table(index) if n == 2 else sparse_maq.new_pair_tables(index, n)
        arrays["q_joint"] = np.zeros((n_runs,) + joint.shape)
    elif name == "cq":
        tables = cq.new_augmented_tables(g.n_cells, n)
        arrays["q_aug"], arrays["marked"] = (np.stack([table] * n_runs) for table in tables)
    arrays["log"] = np.zeros((n_runs, workload.edges().size - 1, ep.n_columns(n)))
    return arrays


def _kernel_and_inputs(workload: Workload):
    """The workload's run kernel and the inputs it shares between runs (all but outputs and state)."""
    w, g, c = workload, workload.gridmap(), workload.learning
    world = (g.next_cell, g.is_goal, g.starts, BOUNCE_MODES[c.bounce])
    learning = (c.q_learning_rate, c.discount, c.exploit_prob)
    schedule = (w.episodes, w.edges(), c.max_steps)
    if w.learner in Q_LEARNERS:
        return Q_LEARNERS[w.learner].run, world + learning + schedule
    if w.learner in OBSERVERS:
        p = c.gla_params()
        automata = (p.learning_rate, p.temperature, p.K, p.L, p.bounding_code, float(c.gla_init_range),
                    np.array(c.gla_feedback), float(c.coordination_penalty_per_cell),
                    two_observe.NEEDS[c.gla_need], delta_scale(c.gla_delta_scale, g),
                    -1 if c.rule_distance is None else c.rule_distance)
        return OBSERVERS[w.learner].run, world + (g.n_cols,) + learning + automata + schedule
    if w.learner == "sparse_maq":
        index = sparse_maq.pair_coordination_index(g, w.coordination_distance)
        if g.n_agents == 2:
            return sparse_maq.run, world + (index,) + learning + schedule
        return sparse_maq.run_pairs, world + (g.n_cols, index, w.coordination_distance) + learning + schedule
    solo = (w.cq_window, w.t_critical(), w.cq_solo_episodes)
    return cq.run, world + (g.n_cols,) + learning + solo + schedule


def run_compiled(workload: Workload, seed: int = 0, n_runs: int = 1, workers=None) -> Outputs:
    """``n_runs`` runs of the workload's compiled kernel: in this thread (``workers`` None, timed
    by its CPU time) or on glamas.runs ``workers`` (timed by the wall clock)."""
    kernel, inputs = _kernel_and_inputs(workload)
    arrays = new_outputs(workload, n_runs)
    if workers is None:
        start = time.thread_time()
        _, filled = runs.fill_chunk(kernel, inputs, seed, 0, n_runs, tuple(arrays.values()))
        seconds = time.thread_time() - start
        arrays = dict(zip(arrays, filled))
    else:
        start = time.perf_counter()
        runs.run_batches(kernel, inputs, tuple(arrays.values()), seed, workers=workers)
        seconds = time.perf_counter() - start
    return Outputs(arrays, seconds, workload.block)


@njit(cache=True)
def compiled_walk(next_cell, is_goal, starts, bounce, actions):
    """Play ``actions`` (n_steps, n_agents) with rules.step, restarting from the starts whenever
    every agent is in the goal; returns total reward, collisions and episodes."""
    n = starts.shape[0]
    cells, done = starts.copy(), np.zeros(n, np.bool_)
    new_cells, rewards = np.empty(n, np.int64), np.empty(n)
    bumped, collided, reached = np.empty(n, np.bool_), np.empty(n, np.bool_), np.empty(n, np.bool_)
    total, collisions, episodes = 0.0, 0, 0
    for t in range(actions.shape[0]):
        collisions += rules.step(next_cell, is_goal, starts, bounce, cells, done, actions[t],
                                 new_cells, rewards, bumped, collided, reached)
        all_done = True
        for i in range(n):
            total += rewards[i]
            cells[i] = new_cells[i]
            done[i] = done[i] or reached[i]
            all_done = all_done and done[i]
        if all_done:
            episodes += 1
            for i in range(n):
                cells[i] = starts[i]
                done[i] = False
    return total, collisions, episodes
