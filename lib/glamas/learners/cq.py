"""CQ-learning (De Hauwere, Vrancx and Nowé, "Learning multi-agent state space representations",
AAMAS 2010): the chapter's future work (Sec. 6) of replacing the GLA by a statistical test.

Each agent k first learns its task alone (single-agent Q-learning on its own cell, the other agent
absent) and keeps, per own state-action (s_k, a_k), a window of its immediate rewards: the
baseline. Then the agents learn together:

1. if agent k's joint state (s_k, s_l) is marked, it acts on Q_j(s_k, s_l, .), else on Q_k(s_k, .);
2. it observes its reward r_k and adds it to the window of recent rewards of (s_k, a_k);
3. it updates the table it acted on: Q_k by eq. 11, or
   Q_j(s_k, s_l, a_k) += alpha [r_k + gamma max_a Q_k(s'_k, a) - Q_j(s_k, s_l, a_k)]
   (CQ-learning bootstraps on the local values of the next state);
4. if the recent window is full and a Student t-test finds its mean significantly below the
   baseline's, and r_k is below the baseline mean, the joint state (s_k, s_l) in which this low
   reward came is marked: from then on agent k observes the other agent there, starting from
   Q_j(s_k, s_l, .) = Q_k(s_k, .).

Choices where the paper leaves room (named parameters of the experiment): the window length, the
test (two-sample Student t-test with pooled variance, two-sided, at a given significance, plus
"lower"), the number of episodes alone, and no unmarking. Memory is bounded: the baseline keeps
count, sum and sum of squares of its last ``window`` rewards, the recent window its last
``window`` rewards (sum and sum of squares kept up to date).

**N agents** (beyond the paper's two-agent experiments): the augmented state pairs an agent's cell
with the cell of its *nearest* other acting agent (Manhattan distance, lowest number on ties, as
2observe's GLA context in :mod:`glamas.learners.two_observe`), whoever that agent is: agent k's
tables stay (own cell, other's cell) whatever N, and a mark means "observe the nearest agent when
it is on that cell". An agent whose every other agent is in the goal has nobody to observe and
neither acts on nor marks joint states. With two agents the nearest other agent is simply the
other one, so this is the two-agent algorithm, unchanged.
"""

import functools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas import checks
from glamas.gridworld import GridMap, rules
from glamas.learners import episode as ep
from glamas.learners.independent import table_shape
from glamas.learners.spec import Learner
from glamas.learners.two_observe import NOBODY, nearest_others
from glamas.qlearning import epsilon_greedy, q_update, row_max

COUNT, SUM, SUM_SQUARES = 0, 1, 2
"""Fields of a reward window's summary."""


@dataclass(frozen=True)
class Settings:
    """CQ-learning's own settings: its test and its phase alone."""

    cq_window: int = 30
    """Rewards kept per state-action, in the baseline and in the recent window."""
    cq_significance: float = 0.05
    """Significance level of the two-sided Student t-test on immediate rewards."""
    cq_solo_episodes: int = 1000
    """Episodes each agent first learns alone (the single-agent phase), not counted in the
    experiment's episodes."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"cq_window": 2, "cq_solo_episodes": 1})
        if not (isinstance(self.cq_significance, float) and 0.0 < self.cq_significance < 1.0):
            raise UserError(f"cq_significance must be a number in (0, 1) such as 0.05, got {self.cq_significance!r}")


class TTest(NamedTuple):
    """CQ-learning's test and schedule as the kernel reads them, named as :class:`Settings`."""

    cq_window: int
    """Rewards kept per state-action, in the baseline and in the recent window."""
    t_critical: np.ndarray
    """Two-sided critical values of Student's t per degrees of freedom (:func:`t_critical_values`)."""
    cq_solo_episodes: int
    """Episodes each agent first learns alone."""


def t_test(setup, gridmap: GridMap) -> tuple:
    """The kernel's own input: the TTest bundle of its settings (``setup.own``)."""
    settings = setup.own
    t_critical = t_critical_values(2 * settings.cq_window - 2, settings.cq_significance)
    return (TTest(settings.cq_window, t_critical, settings.cq_solo_episodes),)


def freeze(inputs: tuple) -> tuple:
    """The kernel's own input with learning off (:attr:`glamas.learners.spec.Learner.freeze`): no
    phase alone, so the baseline stays empty and no joint state is marked; with the Q-learning rate
    zero nothing else changes either."""
    (t_test,) = inputs
    return (t_test._replace(cq_solo_episodes=0),)


def outputs(setup, gridmap: GridMap) -> dict:
    """One run's joint-state values ``q_aug`` (agents, own cell, other's cell, 4 actions) and
    ``marked``, the joint states each agent observes (agents, own cell, other's cell); only marked
    rows are ever used, so the learned table is 4 entries per marked joint state."""
    n, c = gridmap.n_agents, gridmap.n_cells
    return {"q_aug": np.zeros((n, c, c, rules.N_ACTIONS)), "marked": np.zeros((n, c, c), dtype=np.bool_)}


def joint_room(setup, gridmap: GridMap) -> int:
    """Joint values per run allocated: a row for every agent and joint state."""
    return gridmap.n_agents * gridmap.n_cells ** 2 * rules.N_ACTIONS


def reward_samples(setup, gridmap: GridMap) -> int:
    """Rewards kept per run for the test: a recent window per agent and state-action."""
    return gridmap.n_agents * gridmap.n_cells * rules.N_ACTIONS * setup.own.cq_window


def mark_bytes(setup, gridmap: GridMap) -> int:
    """The marks per run: a flag per agent and joint state."""
    return gridmap.n_agents * gridmap.n_cells ** 2


def joint_learned(outputs: dict, setup, gridmap: GridMap) -> np.ndarray:
    """Per run, the joint values learned: 4 per marked joint state."""
    return outputs["marked"].sum(axis=(1, 2, 3)) * float(rules.N_ACTIONS)


# --- the test: Student's two-sample t-test ---------------------------------------------------

def _incomplete_beta(a: float, b: float, x: float) -> float:
    """Regularised incomplete beta function I_x(a, b), by its continued fraction (modified Lentz)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    if x > (a + 1.0) / (a + b + 2.0):
        return 1.0 - _incomplete_beta(b, a, 1.0 - x)
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x)) / a
    tiny = 1e-300
    c, d = 1.0, 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    f = d
    for m in range(1, 500):
        for numerator in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                          -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1.0 + numerator * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + numerator / c
            c = c if abs(c) > tiny else tiny
            f *= c * d
        if abs(c * d - 1.0) < 1e-15:
            break
    return front * f


def two_sided_p_value(t: float, df: int) -> float:
    """P(|T| >= |t|) for Student's t distribution with ``df`` degrees of freedom."""
    return _incomplete_beta(df / 2.0, 0.5, df / (df + t * t))


def t_critical_values(max_df: int, significance: float) -> np.ndarray:
    """The two-sided critical values of Student's t at ``significance`` for 0 .. ``max_df``
    degrees of freedom (index = df; infinite at df 0, where there is no test), by bisection
    (computed once per process for each (max_df, significance))."""
    if not 0.0 < significance < 1.0:
        raise UserError(f"the significance level must be in (0, 1), got {significance!r}")
    return np.array(_t_critical_values(max_df, significance))


@functools.lru_cache(maxsize=None)
def _t_critical_values(max_df: int, significance: float) -> tuple:
    values = np.full(max_df + 1, np.inf)
    for df in range(1, max_df + 1):
        low, high = 0.0, 1.0
        while two_sided_p_value(high, df) > significance:
            high *= 2.0
        for _ in range(200):
            mid = 0.5 * (low + high)
            low, high = (mid, high) if two_sided_p_value(mid, df) > significance else (low, mid)
        values[df] = high
    return tuple(values)


@njit(cache=True)
def significantly_lower(baseline, recent, t_critical):
    """Whether the recent rewards' mean is significantly below the baseline's: Student's
    two-sample t-test with pooled variance (two-sided critical value ``t_critical[df]``), applied
    to window summaries (count, sum, sum of squares)."""
    n1, n2 = baseline[COUNT], recent[COUNT]
    if n1 < 1.0 or n2 < 1.0 or n1 + n2 < 3.0:
        return False
    m1, m2 = baseline[SUM] / n1, recent[SUM] / n2
    if m2 >= m1:
        return False
    squares = max(baseline[SUM_SQUARES] - baseline[SUM] * m1, 0.0) + max(recent[SUM_SQUARES] - recent[SUM] * m2, 0.0)
    df = int(n1 + n2 - 2.0)
    spread = squares / df * (1.0 / n1 + 1.0 / n2)
    if spread <= 0.0:
        return True  # both windows constant, at different values
    return (m1 - m2) / math.sqrt(spread) > t_critical[df]


# --- reward windows ---------------------------------------------------------------------------

@njit(cache=True)
def add_reward(samples, added, summary, r):
    """Add reward ``r`` to a window of ``samples.shape[0]`` rewards (ring buffer; ``added`` counts
    every reward ever added) and keep its summary (count, sum, sum of squares) up to date."""
    size = samples.shape[0]
    slot = added % size
    if added >= size:
        old = samples[slot]
        summary[SUM] -= old
        summary[SUM_SQUARES] -= old * old
    else:
        summary[COUNT] += 1.0
    samples[slot] = r
    summary[SUM] += r
    summary[SUM_SQUARES] += r * r
    return added + 1


# --- the learner ------------------------------------------------------------------------------

@njit(**ep.LOOP)
def learn_alone(world, learning, n_episodes, max_steps, q, windows, state, buffers):
    """The single-agent phase: each agent in turn learns ``n_episodes`` episodes alone (the other
    counts as already in the goal, so it neither acts nor collides) and fills its reward
    ``windows`` (samples, added, summary)."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    starts = world.starts
    n_agents = starts.shape[0]
    samples, added, summary = windows
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = buffers
    for k in range(n_agents):
        for _ in range(n_episodes):
            ep.start_episode(starts, cells, done, acc)
            for i in range(n_agents):
                done[i] = i != k
            t = 0
            while t < max_steps and not done[k]:
                s, a = cells[k], epsilon_greedy(q[k, cells[k]], exploit, state)
                actions[k] = a
                rules.step_alone(world, cells, actions, new_cells, rewards, bumped, collided, reached, k)
                q_update(q[k], s, a, rewards[k], new_cells[k], reached[k], alpha, gamma)
                added[k, s, a] = add_reward(samples[k, s, a], added[k, s, a], summary[k, s, a], rewards[k])
                t += 1
                ep.end_step(t, cells, done, new_cells, rewards, reached, 0, acc)


@njit(cache=True)
def augmented_update(q_aug, q, s, other, a, r, s_next, terminal, alpha, gamma):
    """Step 3 in a marked joint state: Q_j(s, other, a) learns r plus the local value of the next state."""
    target = r
    if not terminal:
        target += gamma * row_max(q, s_next)
    q_aug[s, other, a] += alpha * (target - q_aug[s, other, a])


@njit(cache=True)
def mark_if_conflict(q_aug, marked, q, s, other, r, baseline, recent, t_critical):
    """Step 4: mark joint state (s, other) when the recent rewards of the state-action are
    significantly below the baseline and this reward ``r`` is below the baseline mean; the new
    joint-state values start from the local ones. Returns whether it marked."""
    if marked[s, other] or baseline[COUNT] < 1.0 or r >= baseline[SUM] / baseline[COUNT]:
        return False
    if not significantly_lower(baseline, recent, t_critical):
        return False
    marked[s, other] = True
    for a in range(q.shape[1]):
        q_aug[s, other, a] = q[s, a]
    return True


@njit(cache=True, nogil=True)
def run(world, learning, t_test, schedule, q, q_aug, marked, log, state):
    """One run: ``cq_solo_episodes`` episodes alone per agent, then ``schedule.episodes`` episodes
    together; learns in ``q``, ``q_aug`` and ``marked``, writes the binned ``log`` of the joint
    episodes (coordinations: steps on which an agent acted on a marked joint state)."""
    n_agents, n_cells = world.starts.shape[0], world.next_cell.shape[0]
    samples = np.zeros((n_agents, n_cells, rules.N_ACTIONS, t_test.cq_window))
    added = np.zeros((n_agents, n_cells, rules.N_ACTIONS), np.int64)
    summary = np.zeros((n_agents, n_cells, rules.N_ACTIONS, 3))
    buffers = ep.buffers(n_agents)
    learn_alone(world, learning, t_test.cq_solo_episodes, schedule.max_steps, q, (samples, added, summary), state,
                buffers)
    baseline = summary.copy()  # frozen: the rewards of the task alone
    summary[:] = 0.0
    added[:] = 0
    observing = (np.zeros(n_agents, np.bool_), np.empty(n_agents, np.int64), np.empty(n_agents, np.int64),
                 rules.distance_table(n_cells, world.n_cols))
    episodes(world, learning, t_test, schedule, q, q_aug, marked, log, state,
             (buffers, (samples, added, summary), baseline, observing))


@njit(**ep.LOOP)
def episodes(world, learning, t_test, schedule, q, q_aug, marked, log, state, arrays):
    """The joint phase of :func:`run`: its reward windows (samples, added, summary), the frozen
    ``baseline``, and per agent whether it observes its nearest agent (``joint``), which agent
    that is and how far, from the distance table."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    window, t_critical = t_test.cq_window, t_test.t_critical
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents = starts.shape[0]
    coordinations_column = ep.column(n_agents, ep.COORDINATIONS)
    buffers, (samples, added, summary), baseline, (joint, nearest, deltas, distances) = arrays
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = buffers
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            nearest_others(distances, cells, done, nearest, deltas)  # NOBODY: alone, nobody to observe
            observed = False
            for k in range(n_agents):
                joint[k] = nearest[k] != NOBODY and marked[k, cells[k], cells[nearest[k]]]
                if done[k]:
                    continue
                row = q_aug[k, cells[k], cells[nearest[k]]] if joint[k] else q[k, cells[k]]
                actions[k] = epsilon_greedy(row, exploit, state)
                observed = observed or joint[k]
            if observed:
                acc[coordinations_column] += 1
            collisions = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            for k in range(n_agents):
                if done[k]:
                    continue
                s, a, other = cells[k], actions[k], cells[nearest[k]]  # other: used only if not NOBODY
                if joint[k]:
                    augmented_update(q_aug[k], q[k], s, other, a, rewards[k], new_cells[k], reached[k], alpha, gamma)
                else:
                    q_update(q[k], s, a, rewards[k], new_cells[k], reached[k], alpha, gamma)
                added[k, s, a] = add_reward(samples[k, s, a], added[k, s, a], summary[k, s, a], rewards[k])
                if nearest[k] != NOBODY and added[k, s, a] >= window:
                    mark_if_conflict(q_aug[k], marked[k], q[k], s, other, rewards[k], baseline[k, s, a],
                                     summary[k, s, a], t_critical)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="cq", label="CQ-learning", n_agent_label="CQ-learning (nearest)",
                  kernel=run, table_shape=table_shape, inputs=t_test, freeze=freeze, outputs=outputs,
                  joint_room=joint_room, reward_samples=reward_samples, extra_bytes=mark_bytes,
                  joint_learned=joint_learned, defaults=Settings(), family="related", seed_slot=1)
