"""CQ-learning (De Hauwere, Vrancx and Nowé, "Learning multi-agent state space representations",
AAMAS 2010): the chapter's future work (Sec. 6) of replacing the GLA by a statistical test. Each
agent learns its task alone; then, among the others, it finds from its own rewards where another
agent's state matters, and observes the other agent in those states only.

As published (the functions below cite these steps):

Phase alone. Each agent k learns its task alone (Q-learning on its own cell, eq. 11, the other
agents absent) and records, per own state-action, its expected immediate reward ER_k(s_k, a_k): the
mean of its last ``cq_window`` rewards there.

Phase together. Every step, each agent k not yet in its goal:

1. acts: if its state s_k is augmented with a state s_l and another agent is on s_l,
   epsilon-greedily on Q_aug(s_k, s_l, .), else on Q_k(s_k, .);
2. learns: in an augmented state, Q_aug(s_k, s_l, a_k) += alpha [r_k + gamma max_a Q_k(s'_k, a)
   - Q_aug(s_k, s_l, a_k)] (it bootstraps on the local values of the next state); Q_k stays as the
   phase alone left it;
3. test 1: stores r_k in the window W_k(s_k, a_k) of its last ``cq_window`` rewards there; once the
   window is full, a one-sample Student t-test of W_k(s_k, a_k) against ER_k(s_k, a_k) at the level
   ``cq_significance``;
4. test 2, when test 1 rejects: stores r_k in the window W_k(s_k, a_k, s_l) of every other agent l
   present, keyed by l's state; for each such s_l not yet augmenting s_k whose window is full, the
   same test of W_k(s_k, a_k, s_l) against ER_k(s_k, a_k); when it rejects, s_k is augmented with
   s_l, Q_aug(s_k, s_l, .) starting from Q_k(s_k, .).

The reference settings, window 20 and significance 0.01, are the defaults of :class:`Settings`.

Ours, where the publication leaves room:

- the test is two-sided (the critical value of Student's t at ``cq_window`` - 1 degrees of
  freedom). A full window of equal rewards (zero variance) rejects exactly when its value differs
  from ER: an agent that collides on every visit is flagged, one that never collides is not. A
  state-action never tried alone has no ER and is never tested. An augmentation is never withdrawn.
- The other agents present are those not yet in their goal (an agent in its goal has left the
  game). W_k(s_k, a_k, s_l) takes r_k on every step test 1 rejects, also when s_l already augments
  s_k (only the test is skipped then).
- **N agents** (the publication does not say which augmented state an agent acts on when several
  apply): test 2 runs per other agent present, on windows keyed by its cell whoever it is, so agent
  k's tables stay (own cell, other's cell) at any N. When the cells of several agents augment s_k,
  agent k acts on, and learns, the row of the nearest of them (Manhattan distance, lowest number on
  ties): the one that can reach it first, as 2observe's GLA context
  (:mod:`glamas.learners.two_observe`). With two agents this is the published algorithm.

Variants (named settings of :class:`Settings`), each alone or together:

- ``cq_detection="one_stage"``: no test 2; when test 1 rejects and this reward is below ER, the
  joint state of this very step (own cell, other's cell) is augmented;
- ``cq_test="two_sample"``: Student's two-sample t-test with pooled variance against the last
  ``cq_window`` rewards alone, flagging only a lower mean;
- ``cq_update_local=True``: Q_k learns by eq. 11 where the agent acts on it ("CQwU");
- ``cq_observe="nearest"``: an agent sees its nearest other agent only (lowest number on ties): it
  acts on Q_aug when that agent's cell augments s_k, and only that cell is tested.

This repository's earlier CQ-learning is ``Settings(cq_window=30, cq_significance=0.05,
cq_test="two_sample", cq_detection="one_stage", cq_update_local=True, cq_observe="nearest")``.

Memory: each reward window keeps its last ``cq_window`` rewards in a ring with their count, sum and
sum of squares: one per agent and state-action for test 1 (filled first alone, whose summary then
stays as the record of ER), and, for test 2, one per agent, state-action and other's cell, allocated
for the whole run (:func:`reward_samples`, :func:`window_bytes`).

Plain-Python reference: ``cq`` in ``lib/glamas/plain/gridworld.py``.
"""

import functools
import math
from collections import namedtuple
from dataclasses import dataclass, fields
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas import checks
from glamas.gridworld import GridMap, rules
from glamas.gridworld.rewards import Rewards
from glamas.gridworld.rules import NOBODY
from glamas.learners import episode as ep
from glamas.learners.independent import table_shape
from glamas.learners.registry import register
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, q_update, row_max

COUNT, SUM, SUM_SQUARES = 0, 1, 2
"""Fields of a reward window's summary."""
ONE_SAMPLE, TWO_SAMPLE = 0, 1
TESTS = {"one_sample": ONE_SAMPLE, "two_sample": TWO_SAMPLE}
"""The tests of a reward window, by name (module docstring)."""
TWO_STAGE, ONE_STAGE = 0, 1
DETECTIONS = {"two_stage": TWO_STAGE, "one_stage": ONE_STAGE}
"""How a rejected test augments a state, by name (module docstring)."""
EVERY, NEAREST = 0, 1
OBSERVED = {"every": EVERY, "nearest": NEAREST}
"""Which other agents an agent tests and acts on, by name (module docstring)."""


@dataclass(frozen=True)
class Settings:
    """CQ-learning's own settings: its tests, its phase alone and its variants (module docstring);
    the defaults are the published algorithm at its reference settings."""

    cq_window: int = 20
    """Rewards kept per window (the last ones): alone per state-action (ER), and per window of
    test 1 and test 2."""
    cq_significance: float = 0.01
    """Significance level of the tests."""
    cq_solo_episodes: int = 1000
    """Episodes each agent first learns alone (the single-agent phase), not counted in the
    experiment's episodes."""
    cq_solo_exploit_prob: float | None = None
    """Probability of the greedy action in the phase alone; None: the experiment's
    ``exploit_prob``, as in every chapter-formulation run (the field's public implementation
    explores more there: 0.2, an exploration of 0.8)."""
    cq_test: str = "one_sample"
    """'one_sample': Student's one-sample t-test against ER, two-sided (published);
    'two_sample': the two-sample test with pooled variance against the rewards alone, lower only."""
    cq_detection: str = "two_stage"
    """'two_stage': test 1 on the state-action, then test 2 per other agent's state (published);
    'one_stage': test 1 alone augments the joint state of the step."""
    cq_update_local: bool = False
    """Whether Q_k learns (eq. 11) in the joint phase where the agent acts on it ("CQwU"); the
    published CQ-learning keeps it frozen."""
    cq_observe: str = "every"
    """'every': every other agent present is tested, the nearest augmenting one acted on;
    'nearest': the nearest other agent only."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"cq_window": 2, "cq_solo_episodes": 1})
        if self.cq_solo_exploit_prob is not None:
            checks.in_unit_interval(self, "cq_solo_exploit_prob")
        if not (isinstance(self.cq_significance, float) and 0.0 < self.cq_significance < 1.0):
            raise UserError(f"cq_significance must be a number in (0, 1) such as 0.01, got {self.cq_significance!r}")
        for name, options in (("cq_test", TESTS), ("cq_detection", DETECTIONS), ("cq_observe", OBSERVED)):
            if getattr(self, name) not in options:
                raise UserError(f"{name} must be one of {sorted(options)}, got {getattr(self, name)!r}")
        if not isinstance(self.cq_update_local, (bool, np.bool_)):
            raise UserError(f"cq_update_local must be True or False, got {self.cq_update_local!r}")


Detection = namedtuple("Detection", [field.name for field in fields(Settings)])
"""CQ-learning's settings as the kernel reads them: each of :class:`Settings` under its name, in
the form :func:`detection` gives it."""


def detection(setup, gridmap: GridMap) -> tuple:
    """The kernel's own input: the :data:`Detection` bundle of its settings (``setup.own``): the
    significance as the two-sided critical values of Student's t at that level per degrees of
    freedom (:func:`t_critical_values`), codes where the settings hold names (TESTS, DETECTIONS,
    OBSERVED), the phase alone's probability of the greedy action (the experiment's where the
    setting is None). ``cq_solo_episodes`` 0 means no phase alone, hence no ER and no test
    (:func:`freeze`)."""
    s = setup.own
    solo_exploit = setup.q.exploit_prob if s.cq_solo_exploit_prob is None else s.cq_solo_exploit_prob
    return (Detection(cq_window=s.cq_window, cq_significance=t_critical_values(2 * s.cq_window - 2, s.cq_significance),
                      cq_solo_episodes=s.cq_solo_episodes, cq_solo_exploit_prob=float(solo_exploit),
                      cq_test=TESTS[s.cq_test], cq_detection=DETECTIONS[s.cq_detection],
                      cq_update_local=bool(s.cq_update_local), cq_observe=OBSERVED[s.cq_observe]),)


def freeze(inputs: tuple) -> tuple:
    """The kernel's own input with learning off (:attr:`glamas.learners.spec.Learner.freeze`): no
    phase alone, so no state-action has an ER, no test runs and nothing is augmented; with the
    Q-learning rate zero Q_k and Q_aug stay as given too."""
    (bundle,) = inputs
    return (bundle._replace(cq_solo_episodes=0),)


def outputs(setup, gridmap: GridMap) -> dict:
    """One run's augmented values ``q_aug`` (agents, own cell, other's cell, 4 actions) and
    ``marked``, whether s_k is augmented with the other's cell (agents, own cell, other's cell);
    only augmented rows are ever used, so the learned table is 4 entries per augmented state."""
    n, c = gridmap.n_agents, gridmap.n_cells
    return {"q_aug": np.zeros((n, c, c, rules.N_ACTIONS)), "marked": np.zeros((n, c, c), dtype=np.bool_)}


def joint_room(setup, gridmap: GridMap) -> int:
    """Augmented values per run allocated: a row for every agent, own cell and other's cell."""
    return gridmap.n_agents * gridmap.n_cells ** 2 * rules.N_ACTIONS


def windows_per_run(setup, gridmap: GridMap) -> int:
    """Reward windows per run: test 1's per agent and state-action, and with two stages test 2's
    per agent, state-action and other's cell."""
    n, c = gridmap.n_agents, gridmap.n_cells
    second = c if setup.own.cq_detection == "two_stage" else 0
    return n * c * rules.N_ACTIONS * (1 + second)


def reward_samples(setup, gridmap: GridMap) -> int:
    """Rewards kept per run for the tests: ``cq_window`` per reward window."""
    return windows_per_run(setup, gridmap) * setup.own.cq_window


def window_bytes(setup, gridmap: GridMap) -> int:
    """Bytes per run beyond the values: the augmentation flags, and per reward window its count of
    rewards added (int64) and its summary (3 float64), plus the summaries kept of the phase alone."""
    n, c = gridmap.n_agents, gridmap.n_cells
    alone = n * c * rules.N_ACTIONS * 3 * 8
    return n * c * c + windows_per_run(setup, gridmap) * (8 + 3 * 8) + alone


def joint_learned(outputs: dict, setup, gridmap: GridMap) -> np.ndarray:
    """Per run, the augmented values learned: 4 per augmented state."""
    return outputs["marked"].sum(axis=(1, 2, 3)) * float(rules.N_ACTIONS)


# --- Student's t: critical values ---------------------------------------------------------------

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


@njit(cache=True, inline="always")
def differs_from_expected(expected, window, t_critical):
    """Student's one-sample t-test, two-sided, of a window's summary (count, sum, sum of squares)
    against the ``expected`` reward: |mean - ER| / (sd / sqrt(n)) > t_critical[n - 1], compared
    squared. Zero variance: rejects exactly when the mean differs from ER."""
    n = window[COUNT]
    if n < 2.0:
        return False
    mean = window[SUM] / n
    gap = mean - expected
    squares = max(window[SUM_SQUARES] - window[SUM] * mean, 0.0)
    if squares <= 0.0:
        return gap != 0.0
    t = t_critical[int(n) - 1]
    return gap * gap * n * (n - 1.0) > t * t * squares


@njit(cache=True, inline="always")
def significantly_lower(baseline, recent, t_critical):
    """The variant ``two_sample``: whether the recent rewards' mean is significantly below the
    baseline's, by Student's two-sample t-test with pooled variance (two-sided critical value
    ``t_critical[df]``), on window summaries (count, sum, sum of squares)."""
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


@njit(cache=True, inline="always")
def rejects(alone, window, t_critical, test):
    """Test 1 or 2: whether a full reward ``window`` (its summary) differs from the rewards of its
    state-action ``alone`` (their summary: ER_k(s_k, a_k) = their mean) by the ``test`` of TESTS.
    A state-action never tried alone has no ER and is never rejected."""
    if alone[COUNT] < 1.0:
        return False
    if test == ONE_SAMPLE:
        return differs_from_expected(alone[SUM] / alone[COUNT], window, t_critical)
    return significantly_lower(alone, window, t_critical)


def fewest_flagged_collisions(settings: Settings, rewards: Rewards) -> int:
    """The fewest collisions among a full window that the test of ``settings`` flags, for a
    state-action that never collided alone (``cq_window`` equal rewards alone) and whose other
    rewards are those alone, under ``rewards`` (a collision shifts a move's reward by the
    collision's, less the move's where it replaces it); ``cq_window`` + 1 when not even a window
    of collisions is flagged."""
    window = settings.cq_window
    t_critical = t_critical_values(2 * window - 2, settings.cq_significance)
    alone = np.array([window, 0.0, 0.0])
    shift = rewards.collision - (rewards.move if rewards.collision_replaces_move else 0.0)
    for k in range(1, window + 1):
        recent = np.array([window, k * shift, k * shift * shift])
        if rejects(alone, recent, t_critical, TESTS[settings.cq_test]):
            return k
    return window + 1


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


class Windows(NamedTuple):
    """Reward windows, one per index of a shape (:func:`reward_windows`), each a ring of rewards."""

    samples: np.ndarray
    """(shape, size): the window's last rewards (:func:`add_reward`)."""
    added: np.ndarray
    """int (shape): rewards ever added."""
    summary: np.ndarray
    """(shape, 3): count, sum and sum of squares of the rewards kept."""


@njit(cache=True, inline="always")
def reward_windows(shape, size):
    """Empty :class:`Windows` of ``size`` rewards, one per index of ``shape``."""
    return Windows(np.zeros(shape + (size,)), np.zeros(shape, np.int64), np.zeros(shape + (3,)))


class Learned(NamedTuple):
    """What the phase together learns (:func:`run`'s outputs)."""

    q: np.ndarray
    """Q_k per agent, own cell and action."""
    q_aug: np.ndarray
    """Q_aug per agent, own cell, other's cell and action."""
    marked: np.ndarray
    """Whether agent k's own cell is augmented with the other's cell."""


class Observing(NamedTuple):
    """Per agent, who it observes in a step (:func:`observe`)."""

    observed: np.ndarray
    """The other agent whose row of Q_aug it acts on (NOBODY: none)."""
    nearest: np.ndarray
    """Its nearest other agent (variant ``nearest``)."""
    distances: np.ndarray
    """rules.distance_table: Manhattan distances between cells."""


class Together(NamedTuple):
    """The per-run arrays of the phase together (:func:`episodes`)."""

    buffers: ep.Buffers
    first: Windows
    """Test 1's windows, per agent and state-action."""
    second: Windows
    """Test 2's, per agent, state-action and other's cell (none with one stage)."""
    alone: np.ndarray
    """The summaries of the phase alone: ER_k(s_k, a_k) = their means."""
    observing: Observing


# --- the learner ------------------------------------------------------------------------------

@njit(**ep.LOOP)
def learn_alone(world, learning, exploit, n_episodes, max_steps, q, windows, state, buffers):
    """The phase alone: each agent in turn learns ``n_episodes`` episodes alone (the others count
    as already in the goal, so they neither act nor collide), taking the greedy action with
    probability ``exploit``, and fills its reward ``windows`` (:class:`Windows`), whose means are
    ER."""
    alpha, gamma = learning.q_learning_rate, learning.discount
    starts = world.starts
    n_agents = starts.shape[0]
    samples, added, summary = windows.samples, windows.added, windows.summary
    cells, done, actions, acc = buffers.cells, buffers.done, buffers.actions, buffers.acc
    new_cells, rewards, reached = buffers.new_cells, buffers.rewards, buffers.reached
    for k in range(n_agents):
        for _ in range(n_episodes):
            ep.start_episode(starts, cells, done, acc)
            for i in range(n_agents):
                done[i] = i != k
            t = 0
            while t < max_steps and not done[k]:
                s, a = cells[k], epsilon_greedy(q[k, cells[k]], exploit, state)
                actions[k] = a
                ep.step_alone(world, buffers, k)
                q_update(q[k], s, a, rewards[k], new_cells[k], reached[k], alpha, gamma)
                added[k, s, a] = add_reward(samples[k, s, a], added[k, s, a], summary[k, s, a], rewards[k])
                t += 1
                ep.end_step(t, cells, done, new_cells, rewards, reached, 0, acc)


@njit(cache=True, inline="always")
def nearest_other(distances, cells, done, k, augmenting, only_augmenting):
    """The nearest other agent present to agent k (Manhattan distance from the table
    ``distances``, lowest number on ties), among those whose cell augments k's
    (``augmenting[cell]``) when ``only_augmenting``; NOBODY if there is none."""
    nearest, least = NOBODY, 0
    own = cells[k]
    for l in range(cells.shape[0]):
        if l == k or done[l] or (only_augmenting and not augmenting[cells[l]]):
            continue
        d = distances[own, cells[l]]
        if nearest == NOBODY or d < least:
            nearest, least = l, d
    return nearest


@njit(cache=True, inline="always")
def observe(distances, cells, done, k, augmenting, mode):
    """Step 1 for agent k: (the other agent whose cell augments k's state now and whose row of Q_aug
    it acts on, its nearest other agent); NOBODY for none. ``mode`` EVERY: the nearest of the
    agents whose cell augments k's (``augmenting[cell]``), and no nearest agent is needed; NEAREST:
    its nearest other agent, if that one's cell augments k's."""
    if mode == EVERY:
        return nearest_other(distances, cells, done, k, augmenting, True), NOBODY
    nearest = nearest_other(distances, cells, done, k, augmenting, False)
    return (nearest if nearest != NOBODY and augmenting[cells[nearest]] else NOBODY), nearest


@njit(cache=True)
def augmented_update(q_aug, q, s, other, a, r, s_next, terminal, alpha, gamma):
    """Step 2 in an augmented state: Q_aug(s, other, a) learns r plus the local value of the next state."""
    target = r
    if not terminal:
        target += gamma * row_max(q, s_next)
    q_aug[s, other, a] += alpha * (target - q_aug[s, other, a])


@njit(cache=True, inline="always")
def augment(learned, k, s, other):
    """Step 4's outcome: agent k's state ``s`` is augmented with the other's cell, its values
    starting from the local ones (nothing changes if it already is)."""
    q, q_aug, marked = learned.q, learned.q_aug, learned.marked
    if marked[k, s, other]:
        return
    marked[k, s, other] = True
    for a in range(q.shape[2]):
        q_aug[k, s, other, a] = q[k, s, a]


@njit(cache=True, inline="always")
def test_1(windows, alone, k, s, a, r, detection):
    """Step 3: store r in W_k(s, a); whether the window is full and the test rejects it against the
    state-action's rewards ``alone``."""
    samples, added, summary = windows.samples, windows.added, windows.summary
    added[k, s, a] = add_reward(samples[k, s, a], added[k, s, a], summary[k, s, a], r)
    if added[k, s, a] < detection.cq_window:
        return False
    return rejects(alone[k, s, a], summary[k, s, a], detection.cq_significance, detection.cq_test)


@njit(cache=True, inline="always")
def test_2(learned, windows, alone, k, s, a, r, other, detection):
    """Step 4 for one other agent present on cell ``other``: store r in W_k(s, a, other); if
    ``other`` does not augment s yet and its window is full and the test rejects it against ER,
    augment s with it."""
    samples, added, summary = windows.samples, windows.added, windows.summary
    added[k, s, a, other] = add_reward(samples[k, s, a, other], added[k, s, a, other], summary[k, s, a, other], r)
    if learned.marked[k, s, other] or added[k, s, a, other] < detection.cq_window:
        return
    if rejects(alone[k, s, a], summary[k, s, a, other], detection.cq_significance, detection.cq_test):
        augment(learned, k, s, other)


@njit(cache=True, inline="always")
def detect(learned, first, second, alone, k, a, r, seen, detection):
    """Steps 3-4 for agent k after its action ``a`` and reward ``r``, ``seen`` = (cells, done,
    nearest) as they were when it acted: test 1, then test 2 per other agent present (two stages),
    or the augmentation of the joint state of this step when r is below ER (one stage).
    ``first``, ``second``: test 1's and test 2's windows."""
    cells, done, nearest = seen
    s = cells[k]
    if not test_1(first, alone, k, s, a, r, detection):
        return
    below = r < alone[k, s, a, SUM] / alone[k, s, a, COUNT]  # r < ER (test 1 rejected: ER exists)
    for l in range(cells.shape[0]):
        if l == k or done[l] or (detection.cq_observe == NEAREST and l != nearest[k]):
            continue
        if detection.cq_detection == TWO_STAGE:
            test_2(learned, second, alone, k, s, a, r, cells[l], detection)
        elif below:
            augment(learned, k, s, cells[l])


@njit(cache=True, nogil=True)
def run(world, learning, detection, schedule, q, q_aug, marked, log, state):
    """One run: ``cq_solo_episodes`` episodes alone per agent, then ``schedule.episodes`` episodes
    together; learns in ``q`` (alone, and together in the variant ``cq_update_local``), ``q_aug``
    and ``marked``, writes the binned ``log`` of the joint episodes (coordinations: steps on which
    an agent acted on an augmented state)."""
    n_agents, n_cells = world.starts.shape[0], world.next_cell.shape[0]
    per_action = (n_agents, n_cells, rules.N_ACTIONS)
    first = reward_windows(per_action, detection.cq_window)
    buffers = ep.buffers(n_agents)
    learn_alone(world, learning, detection.cq_solo_exploit_prob, detection.cq_solo_episodes, schedule.max_steps, q,
                first, state, buffers)
    alone = first.summary.copy()  # the summaries alone: ER_k(s_k, a_k) = their means
    first.added[:] = 0
    first.summary[:] = 0.0
    others = n_cells if detection.cq_detection == TWO_STAGE else 0  # test 2's windows, per other's cell
    second = reward_windows(per_action + (others,), detection.cq_window)
    observing = Observing(np.zeros(n_agents, np.int64), np.zeros(n_agents, np.int64),
                          rules.distance_table(n_cells, world.n_cols))
    episodes(world, learning, detection, schedule, Learned(q, q_aug, marked), log, state,
             Together(buffers, first, second, alone, observing))


@njit(**ep.LOOP)
def episodes(world, learning, detection, schedule, learned, log, state, arrays):
    """The phase together of :func:`run`: learns in ``learned`` (:class:`Learned`); ``arrays``:
    :class:`Together`."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents = starts.shape[0]
    q, q_aug, marked = learned.q, learned.q_aug, learned.marked
    coordinations_column = ep.column(n_agents, ep.COORDINATIONS)
    buffers, alone = arrays.buffers, arrays.alone
    observed, nearest, distances = arrays.observing.observed, arrays.observing.nearest, arrays.observing.distances
    cells, done, actions, acc = buffers.cells, buffers.done, buffers.actions, buffers.acc
    new_cells, rewards, reached = buffers.new_cells, buffers.rewards, buffers.reached
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            coordinated = False
            for k in range(n_agents):  # step 1
                if done[k]:
                    continue
                s = cells[k]
                observed[k], nearest[k] = observe(distances, cells, done, k, marked[k, s], detection.cq_observe)
                row = q[k, s] if observed[k] == NOBODY else q_aug[k, s, cells[observed[k]]]
                actions[k] = epsilon_greedy(row, exploit, state)
                coordinated = coordinated or observed[k] != NOBODY
            if coordinated:
                acc[coordinations_column] += 1
            collisions = ep.step(world, buffers)
            for k in range(n_agents):  # steps 2-4
                if done[k]:
                    continue
                s, a, r = cells[k], actions[k], rewards[k]
                if observed[k] != NOBODY:
                    augmented_update(q_aug[k], q[k], s, cells[observed[k]], a, r, new_cells[k], reached[k], alpha, gamma)
                elif detection.cq_update_local:
                    q_update(q[k], s, a, r, new_cells[k], reached[k], alpha, gamma)
                detect(learned, arrays.first, arrays.second, alone, k, a, r, (cells, done, nearest), detection)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="cq", label="CQ-learning", n_agent_label="CQ-learning (every other agent)",
                  kernel=run, table_shape=table_shape, inputs=detection, freeze=freeze, outputs=outputs,
                  joint_room=joint_room, reward_samples=reward_samples, extra_bytes=window_bytes,
                  joint_learned=joint_learned, defaults=Settings(), family="related", rank=1)

register(LEARNER)
