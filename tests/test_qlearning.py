"""Tabular Q-learning pieces: eq. 11 by hand, greedy tie-breaking, the exploitation rate."""

import numpy as np
import pytest

from glamas.qlearning import epsilon_greedy, greedy, q_update, row_max
from glamas.rng import run_states


def test_eq11_by_hand():
    q = np.zeros((3, 2))
    q[0, 1] = 1.0
    q[2] = [1.0, 4.0]
    # (1 - 0.5) * 1 + 0.5 * (2 + 0.9 * max(1, 4)) = 0.5 + 0.5 * 5.6
    q_update(q, 0, 1, 2.0, 2, False, 0.5, 0.9)
    assert q[0, 1] == pytest.approx(3.3)
    assert q[0, 0] == 0.0 and q[2].tolist() == [1.0, 4.0]


def test_eq11_terminal_transition_has_no_successor_term():
    q = np.zeros((2, 2))
    q[1] = [50.0, 80.0]
    q_update(q, 0, 0, 100.0, 1, True, 0.05, 0.9)
    assert q[0, 0] == pytest.approx(5.0)


def test_row_max():
    q = np.array([[-3.0, -1.0, -2.0]])
    assert row_max(q, 0) == -1.0


def test_greedy_breaks_ties_uniformly_among_the_best_only():
    state = run_states(1, 1)[0]
    row = np.array([1.0, 3.0, 3.0, 0.0])
    picks = np.array([greedy(row, state) for _ in range(4000)])
    assert set(picks.tolist()) == {1, 2}
    assert abs((picks == 1).mean() - 0.5) < 0.03  # 4000 fair coin flips: sd 0.008
    assert greedy(np.array([0.0, -1.0, 2.0, 1.0]), state) == 2


def test_epsilon_greedy_exploits_with_the_given_probability():
    state = run_states(2, 1)[0]
    row = np.array([0.0, 5.0, 0.0, 0.0])
    picks = np.array([epsilon_greedy(row, 0.9, state) for _ in range(40000)])
    # greedy with 0.9, and a uniform action (which may be the greedy one) with 0.1
    assert abs((picks == 1).mean() - (0.9 + 0.1 / 4)) < 0.005  # sd 0.0013
    for a in (0, 2, 3):
        assert abs((picks == a).mean() - 0.1 / 4) < 0.004
    assert all(epsilon_greedy(row, 1.0, state) == 1 for _ in range(200))
