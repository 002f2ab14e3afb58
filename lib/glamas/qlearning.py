"""Tabular Q-learning (chapter Section 2.2, eq. 11 and Alg. 3) as compiled pieces for the kernels.

A Q table is a 2-d float array, one row per state and one column per action. Nothing here
allocates, so the episode loops can call these functions every step; they are inlined into the
kernels, where a call would cost more than the work: by numba (``inline="always"``), or, for
``q_update`` and ``greedy``, which the loops call at several places, by LLVM, which costs compile
time once instead of at every place (:mod:`glamas.learners.episode`).
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import checks, rng
from glamas.errors import UserError


@dataclass(frozen=True)
class QSettings:
    """Tabular Q-learning (eq. 11, Alg. 3), shared by every Q-learner of an experiment: the
    chapter's values (Section 5.3) as defaults, the rest documented choices."""

    q_learning_rate: float = 0.05
    """alpha of eq. 11 for every Q-learner (Sec. 5.3)."""
    q_initial: float = 0.0
    """Initial value of every Q-table entry (Sec. 5.3)."""
    exploit_prob: float = 0.9
    """Probability of the greedy action; the chapter's "epsilon = 0.9" read as exploitation."""
    discount: float = 0.9
    """gamma of eq. 11 (not stated in the chapter)."""

    def __post_init__(self):
        checks.field_types(self)
        for name in ("q_learning_rate", "exploit_prob", "discount"):
            checks.in_unit_interval(self, name)
        if not np.isfinite(self.q_initial):
            raise UserError(f"q_initial must be a finite number, got {self.q_initial!r}")

    def kernel_bundle(self) -> "QLearning":
        """These settings as the kernels read them."""
        return QLearning(self.q_learning_rate, self.discount, self.exploit_prob)


class QLearning(NamedTuple):
    """The Q-learning settings as the kernels read them, named as in :class:`QSettings`."""

    q_learning_rate: float
    """alpha of eq. 11."""
    discount: float
    """gamma of eq. 11."""
    exploit_prob: float
    """Probability of the greedy action (:func:`epsilon_greedy`)."""


@njit(cache=True)  # inlined by LLVM (module docstring)
def q_update(q, s, a, r, s_next, terminal, alpha, gamma):
    """Eq. 11: Q(s, a) <- (1 - alpha) Q(s, a) + alpha (r + gamma max_a' Q(s', a')).

    A terminal transition (the agent entered the absorbing goal, whose value stays zero) has
    no successor term.
    """
    target = r
    if not terminal:
        target += gamma * row_max(q, s_next)
    q[s, a] = (1.0 - alpha) * q[s, a] + alpha * target


@njit(cache=True, inline="always")
def row_max(q, s):
    """max_a Q(s, a)."""
    best = q[s, 0]
    for a in range(1, q.shape[1]):
        if q[s, a] > best:
            best = q[s, a]
    return best


@njit(cache=True, inline="always")
def best_and_ties(q_row):
    """max_a q_row[a] and how many actions reach it."""
    best = q_row[0]
    ties = 1
    for a in range(1, q_row.shape[0]):
        if q_row[a] > best:
            best = q_row[a]
            ties = 1
        elif q_row[a] == best:
            ties += 1
    return best, ties


@njit(cache=True, inline="always")
def nth_best(q_row, best, pick):
    """The action of the ``pick``-th (from 0) entry of q_row equal to ``best``."""
    for a in range(q_row.shape[0]):
        if q_row[a] == best:
            if pick == 0:
                return a
            pick -= 1
    return q_row.shape[0] - 1  # not reached: pick < ties


@njit(cache=True)  # inlined by LLVM (module docstring)
def greedy(q_row, state):
    """argmax_a q_row[a], ties broken uniformly at random (one draw, only when there is a tie)."""
    best, ties = best_and_ties(q_row)
    pick = 0 if ties == 1 else rng.integer(state, ties)
    return nth_best(q_row, best, pick)


@njit(cache=True, inline="always")
def epsilon_greedy(q_row, exploit_prob, state):
    """The chapter's epsilon-greedy selection (Section 5.3), with epsilon read as the probability
    of exploiting: greedy (random tie-break) with probability ``exploit_prob``, otherwise an
    action drawn uniformly from all actions."""
    if rng.uniform(state) < exploit_prob:
        return greedy(q_row, state)
    return rng.integer(state, q_row.shape[0])
