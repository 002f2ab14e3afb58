"""The benchmarks' one door to glamas's compiled code: what a gridworld benchmark runs (a
:class:`Workload`), the run kernels' arguments built from it (by glamas.learners.spec, from the
learner's registry entry), and the calls.

Only this module knows how the kernels are called: the benchmarks, the C reference
(``c_reference``) and the tests of the references ask it for a kernel's outputs, so that a
change of the kernels' arguments is adapted here alone. The runs go through ``glamas.parallel`` as the
experiments' do: run ``r`` of ``seed`` draws from :func:`run_state` ``(seed, r)``.
"""

import functools
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from glamas import parallel, rng, training
from glamas.gridworld import load_map, rules
from glamas.gridworld.rewards import CHAPTER, Rewards
from glamas.learners import cq, registry, spec
from glamas.learners import episode as ep
from glamas.qlearning import QSettings


@dataclass(frozen=True)
class Workload:
    """One learner on one map for a number of episodes, with the experiments' settings."""

    learner: str
    """A learner of glamas.learners.registry."""
    episodes: int
    """Episodes of the run (CQ-learning: of the joint phase, after its ``cq_solo_episodes``)."""
    map: str = "tunnel_to_goal"
    """A map of data/maps, or a map's text (glamas.gridworld.load_map): a generated map's
    (benchmarks.bench_many_agents)."""
    block: int = 1
    """Episodes per row of the log (it must divide ``episodes``); 1: a row per episode."""
    own: Any = None
    """The learner's own settings (its spec's ``defaults``, the experiments', when None)."""
    q: QSettings = QSettings()
    """Q-learning's settings (the experiments')."""
    bounce: str = "previous"
    """Where a collided agent goes (glamas.gridworld.rules)."""
    rewards: Rewards = CHAPTER
    """What the gridworld pays (glamas.gridworld.rewards): the chapter's."""
    max_steps: int = 10_000
    """Step cap per episode (the chapter's experiment's)."""

    def __post_init__(self):
        self.setup()  # an unknown learner or settings of another learner fail here
        if self.episodes % self.block:
            raise ValueError(f"block ({self.block}) must divide episodes ({self.episodes})")

    def setup(self) -> spec.Setup:
        """The learner's Q-learning settings and its own (glamas.learners.spec.Setup)."""
        return registry.get(self.learner).setup(self.q, self.own)

    def gridmap(self):
        return load_map(self.map)

    def schedule(self) -> ep.Schedule:
        return ep.Schedule(self.episodes, ep.uniform_edges(self.episodes, self.block), self.max_steps)

    def t_critical(self) -> np.ndarray:
        """CQ-learning's two-sided critical values of Student's t, by degrees of freedom."""
        own = self.setup().own
        return _t_critical(own.cq_window, own.cq_significance)


@functools.cache
def _t_critical(window: int, significance: float) -> np.ndarray:
    """Computed once per setting (a bisection in Python), so that the Python reference's timing
    does not count it: the kernel gets the table ready-made too."""
    return cq.t_critical_values(2 * window - 2, significance)


@dataclass
class Outputs:
    """A run kernel's outputs, each with a first axis of runs, and the time the runs took."""

    arrays: dict
    """The output arrays by name (q, the learner's own, log), in the kernel's order."""
    seconds: float
    """This thread's CPU time in the runs when they ran in this thread, else their wall time."""
    block: int
    """Episodes per row of the log."""

    @property
    def log(self) -> np.ndarray:
        return self.arrays["log"]

    def steps(self) -> float:
        """Environment steps (joint moves) of every run together."""
        return float(ep.metric(self.log, "length").sum() * self.block)


def run_state(seed: int, run: int = 0) -> np.ndarray:
    """The generator state of run ``run`` of ``seed`` (glamas.rng.chunk_states), as the kernels get it."""
    return rng.chunk_states(seed, run, run + 1)[0]


def new_outputs(workload: Workload, n_runs: int) -> dict:
    """Fresh outputs of ``n_runs`` runs of the workload's kernel, in the kernel's order."""
    return training.allocate(registry.get(workload.learner), workload.setup(), workload.gridmap(),
                             workload.schedule(), n_runs)


def run_compiled(workload: Workload, seed: int = 0, n_runs: int = 1, workers=None) -> Outputs:
    """``n_runs`` runs of the workload's compiled kernel: in this thread (``workers`` None, timed
    by its CPU time) or on glamas.parallel ``workers`` (timed by the wall clock)."""
    learner, gridmap = registry.get(workload.learner), workload.gridmap()
    inputs = spec.kernel_inputs(learner, workload.setup(), gridmap, workload.schedule(), workload.bounce,
                                workload.rewards)
    arrays = new_outputs(workload, n_runs)
    if workers is None:
        start = time.thread_time()
        _, filled = parallel.fill_chunk(learner.kernel_for(gridmap.n_agents), inputs, seed, 0, n_runs, tuple(arrays.values()))
        seconds = time.thread_time() - start
        arrays = dict(zip(arrays, filled))
    else:
        start = time.perf_counter()
        parallel.run_batches(learner.kernel_for(gridmap.n_agents), inputs, tuple(arrays.values()), seed, workers=workers)
        seconds = time.perf_counter() - start
    return Outputs(arrays, seconds, workload.block)


def walk_compiled(gridmap, bounce: str, actions: np.ndarray, rewards: Rewards = CHAPTER) -> tuple:
    """Play ``actions`` (n_steps, n_agents) with the compiled rules.step under ``rewards``, restarting
    from the starts whenever every agent is in the goal: (total reward, collisions, episodes)."""
    return _walk(rules.world(gridmap, bounce, rewards), actions)


@njit(cache=True)
def _walk(world, actions):
    n = world.starts.shape[0]
    cells, done = world.starts.copy(), np.zeros(n, np.bool_)
    new_cells, rewards = np.empty(n, np.int64), np.empty(n)
    bumped, collided, reached = np.empty(n, np.bool_), np.empty(n, np.bool_), np.empty(n, np.bool_)
    total, collisions, episodes = 0.0, 0, 0
    for t in range(actions.shape[0]):
        collisions += rules.step(world, cells, done, actions[t], new_cells, rewards, bumped, collided, reached)
        all_done = True
        for i in range(n):
            total += rewards[i]
            cells[i] = new_cells[i]
            done[i] = done[i] or reached[i]
            all_done = all_done and done[i]
        if all_done:
            episodes += 1
            for i in range(n):
                cells[i] = world.starts[i]
                done[i] = False
    return total, collisions, episodes
