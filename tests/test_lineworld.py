"""The line world of Fig. 4: experiment 1's regions and rewards, experiment 2's parabola and
rewards, and the three context encodings of Fig. 6, case by case."""

import numpy as np
import pytest

from glamas import lineworld as lw
from glamas.rng import run_states

L, R, A, B = lw.LEFT, lw.RIGHT, lw.AGENT_A, lw.AGENT_B


@pytest.mark.parametrize("x1, x2, expected", [
    (-0.9, 0.9, 1),    # A far left of B
    (0.9, -0.9, 2),    # A far right of B
    (0.1, 0.3, 3),     # close, A left
    (0.3, 0.1, 3),     # close, A right
    (-0.25, 0.25, 1),  # distance exactly 0.5 is not 'less than 0.5'
    (0.0, 0.0, 3),
])
def test_regions_of_experiment_1(x1, x2, expected):
    assert lw.region(x1, x2) == expected


@pytest.mark.parametrize("x1, x2, region3, best_a, best_b", [
    (-0.9, 0.9, lw.MOVE_APART, L, L),  # region 1: both Left
    (0.9, -0.9, lw.MOVE_APART, R, R),  # region 2: both Right
    (0.1, 0.3, lw.MOVE_APART, L, R),   # region 3, A left of B: move apart
    (0.3, 0.1, lw.MOVE_APART, R, L),   # region 3, A right of B: move apart
    (-0.9, 0.9, lw.FIXED_JOINT_ACTION, L, L),  # regions 1 and 2 do not depend on the reading
    (0.9, -0.9, lw.FIXED_JOINT_ACTION, R, R),
    (0.1, 0.3, lw.FIXED_JOINT_ACTION, L, R),  # region 3: (L, R) on either side
    (0.3, 0.1, lw.FIXED_JOINT_ACTION, L, R),
])
def test_rewarded_joint_action_pays_one_and_the_others_zero(x1, x2, region3, best_a, best_b):
    for a in (L, R):
        for b in (L, R):
            expected = 1.0 if (a, b) == (best_a, best_b) else 0.0
            assert lw.regions_reward(x1, x2, a, b, region3) == expected
    assert (lw.best_action(x1, x2, A, region3), lw.best_action(x1, x2, B, region3)) == (best_a, best_b)


def test_unknown_region3_reading_is_named():
    with pytest.raises(ValueError, match="region3_reward must be one of"):
        lw.region3_code("towards")


def test_parabola_region_and_its_rewards():
    assert lw.inside_parabola(0.0, 0.0, 1.0, -0.5)
    assert lw.inside_parabola(1.0, 0.5, 1.0, -0.5)       # on the border counts as inside
    assert not lw.inside_parabola(1.0, 0.4, 1.0, -0.5)
    assert not lw.inside_parabola(0.0, -0.6, 1.0, -0.5)
    pay = lambda inside, a, b: lw.parabola_reward(inside, a, b, 0.9, 0.5, 0.1)
    assert [pay(True, a, b) for a, b in ((L, L), (L, R), (R, L), (R, R))] == [0.9, 0.1, 0.1, 0.1]
    assert [pay(False, a, b) for a, b in ((L, L), (L, R), (R, L), (R, R))] == [0.1, 0.1, 0.1, 0.5]


@pytest.mark.parametrize("encoding, agent, expected", [
    (lw.JOINT, A, [0.2, -0.6, 1.0]),
    (lw.JOINT, B, [0.2, -0.6, 1.0]),     # both agents see the same joint location
    (lw.ABSOLUTE, A, [0.8, 1.0]),
    (lw.ABSOLUTE, B, [0.8, 1.0]),
    (lw.DEICTIC, A, [0.8, 1.0]),         # own minus other: 0.2 - (-0.6)
    (lw.DEICTIC, B, [-0.8, 1.0]),        # -0.6 - 0.2
])
def test_contexts(encoding, agent, expected):
    out = np.empty(lw.CONTEXT_LENGTH[encoding])
    lw.context(encoding, agent, 0.2, -0.6, out)
    np.testing.assert_allclose(out, expected)


def test_restart_is_uniform_on_the_line():
    state = run_states(3, 1)[0]
    positions = np.array([lw.restart(state) for _ in range(20000)])
    assert positions.min() >= -1.0 and positions.max() < 1.0
    np.testing.assert_allclose(positions.mean(axis=0), 0.0, atol=0.02)
    np.testing.assert_allclose(positions.var(axis=0), 1.0 / 3.0, atol=0.01)


def test_unknown_encoding_is_named():
    with pytest.raises(ValueError, match="context must be one of .*'deictic'.* got 'polar'"):
        lw.encoding_code("polar")


def test_state_grid_covers_the_square_at_cell_midpoints():
    x1, x2 = lw.state_grid(4)
    assert x1.shape == (16,)
    assert sorted(set(x1.tolist())) == [-0.75, -0.25, 0.25, 0.75]
    assert x2.mean() == 0.0
