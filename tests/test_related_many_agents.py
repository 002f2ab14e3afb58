"""Sparse tabular MAQ (pairwise coordination) and CQ-learning (nearest agent) for N agents: pair
matching, the four updates per pair, action choice, the two-agent paths unchanged bit for bit,
small runs, and the two learners in the scaling study."""

import numpy as np
import pytest

from glamas import parallel
from glamas.experiments import scaling as sc
from glamas.gridworld import load_map, rules
from glamas.gridworld.rules import E, S, W
from glamas.learners import cq, spec, sparse_maq
from glamas.learners import episode as ep
from glamas.learners.sparse_maq import NO_PARTNER
from glamas.paths import MAPS
from glamas.qlearning import QLearning
from glamas.rng import run_states

ALPHA, GAMMA = 0.5, 0.9
OPEN_3X3 = """\
+-+-+-+
|1 2 .|
+ + + +
|3 . .|
+ + + +
|. . G|
+-+-+-+
"""


@pytest.fixture()
def open3():
    g = load_map(OPEN_3X3)
    return g, sparse_maq.coordination_index(g, 2)


def match(g, index, cells, acting=(True, True, True), distance=2):
    partner, rows = np.empty(len(cells), np.int64), np.empty(len(cells), np.int64)
    pairs = sparse_maq.match_pairs(sparse_maq.Coordination(index, distance), rules.distance_table(g.n_cells, g.n_cols),
                                   np.array(cells), np.array(acting), partner, rows)
    return pairs, partner.tolist(), rows.tolist()


# --- sparse MAQ: pairs ------------------------------------------------------------------------

def test_pairs_are_numbered_once_each():
    numbers = [sparse_maq.pair_number(i, j, 5) for i in range(5) for j in range(i + 1, 5)]
    assert numbers == list(range(sparse_maq.n_pairs(5)))


def test_an_agent_coordinates_with_its_nearest_partner(open3):
    g, index = open3
    # agent 0 at (0,0), agent 1 at (0,2): distance 2; agent 2 at (1,0): distance 1 from agent 0
    pairs, partner, rows = match(g, index, [g.cell(0, 0), g.cell(0, 2), g.cell(1, 0)])
    assert pairs == 1 and partner == [2, NO_PARTNER, 0]
    assert rows[0] == rows[2] == index[g.cell(0, 0) * g.n_cells + g.cell(1, 0)] and rows[1] == -1


def test_ties_go_to_the_lowest_agent_numbers(open3):
    g, index = open3
    # agent 2 at (0,1) is at distance 1 from agent 0 (0,0) and agent 1 (0,2): it pairs with agent 0
    pairs, partner, _ = match(g, index, [g.cell(0, 0), g.cell(0, 2), g.cell(0, 1)])
    assert pairs == 1 and partner == [2, NO_PARTNER, 0]


def test_far_or_finished_agents_act_alone(open3):
    g, index = open3
    far = [g.cell(0, 0), g.cell(2, 1), g.cell(1, 2)]  # distances 3, 3 and 2 (agents 1, 2)
    assert match(g, index, far)[1] == [NO_PARTNER, 2, 1]
    assert match(g, index, far, distance=1)[1] == [NO_PARTNER] * 3
    assert match(g, index, far, acting=(True, True, False))[1] == [NO_PARTNER] * 3


def test_a_pair_draws_one_joint_action_lower_agent_first():
    q, q_pairs = np.zeros((3, 9, 4)), np.zeros((3, 5, 16))
    q_pairs[sparse_maq.pair_number(0, 2, 3), 4, 4 * S + W] = 1.0  # agent 0 goes S, agent 2 goes W
    q[1, 7, E] = 1.0
    actions, joint = np.zeros(3, np.int64), np.zeros(3, np.int64)
    sparse_maq.choose_actions(q, q_pairs, np.array([0, 7, 3]), np.zeros(3, np.bool_), np.array([2, NO_PARTNER, 0]),
                              np.array([4, -1, 4]), 1.0, actions, joint, run_states(0, 1)[0])
    assert actions.tolist() == [S, E, W] and joint[0] == 4 * S + W


@pytest.fixture()
def tables():
    q = np.zeros((3, 9, 4))
    q[0, 1] = [1.0, 4.0, 2.0, 0.0]  # agent 0's next cell 1: max 4
    q[2, 5] = [3.0, 0.0, 6.0, 1.0]  # agent 2's next cell 5: max 6
    q_pairs = np.zeros((3, 4, 16))
    q_pairs[:, 2] = np.arange(16.0)  # every pair's next row 2: max 15
    q_pairs[:, 0, 5] = 10.0
    return q, q_pairs


def learn(q, q_pairs, partner, partner_next, rewards, reached=(False, False, False), actions=(E, S, W)):
    matches = (np.array(partner), np.array([0 if p != NO_PARTNER else -1 for p in partner]), np.array([5, 0, 5]),
               np.array(partner_next), np.array([2 if p != NO_PARTNER else -1 for p in partner_next]))
    sparse_maq.learn_pairs(q, q_pairs, np.array([0, 3, 6]), np.zeros(3, np.bool_), np.array(actions),
                           np.array(rewards), np.array([1, 4, 5]), np.array(reached), matches,
                           QLearning(ALPHA, GAMMA, 0.9))


def test_a_pair_that_stays_together_makes_the_mmdp_update(tables):
    q, q_pairs = tables
    learn(q, q_pairs, [2, NO_PARTNER, 0], [2, NO_PARTNER, 0], [-1.0, 0.0, -10.0])
    pair = sparse_maq.pair_number(0, 2, 3)
    assert q_pairs[pair, 0, 5] == pytest.approx(10 + ALPHA * (-11 + GAMMA * 15 - 10))
    assert q_pairs[pair, 0].sum() == q_pairs[pair, 0, 5]  # updated once, by the lower agent
    assert q[1, 3, S] == pytest.approx(ALPHA * (0 + GAMMA * q[1, 4].max()))  # agent 1 alone: eq. 11


def test_a_pair_that_breaks_up_sums_each_agents_next_value(tables):
    q, q_pairs = tables
    # pair (0, 2) breaks: agent 0 acts alone next, agent 2 joins agent 1 (half their best joint value)
    learn(q, q_pairs, [2, NO_PARTNER, 0], [NO_PARTNER, 2, 1], [0.0, 0.0, -1.0])
    pair = sparse_maq.pair_number(0, 2, 3)
    assert q_pairs[pair, 0, 5] == pytest.approx(10 + ALPHA * ((0 + GAMMA * 4) + (-1 + GAMMA * 15 / 2) - 10))
    # agent 1 joins a pair: its own value learns half the pair's best joint value
    assert q[1, 3, S] == pytest.approx(ALPHA * (0 + GAMMA * 15 / 2))


def test_an_agent_entering_the_goal_has_no_future_term(tables):
    q, q_pairs = tables
    learn(q, q_pairs, [2, NO_PARTNER, 0], [NO_PARTNER, NO_PARTNER, NO_PARTNER], [0.0, 100.0, 100.0],
          reached=(False, True, True))
    assert q_pairs[sparse_maq.pair_number(0, 2, 3), 0, 5] == pytest.approx(10 + ALPHA * ((0 + GAMMA * 4) + 100 - 10))
    assert q[1, 3, S] == pytest.approx(ALPHA * 100)


def test_index_for_many_agents_and_its_errors():
    three = load_map(OPEN_3X3)
    with pytest.raises(ValueError, match="coordination distance must be a whole number >= 1"):
        sparse_maq.coordination_index(three, 0)
    # ordered pairs of the 8 usable cells: 10 adjacent pairs, 11 at distance 2 (none with the goal)
    assert (sparse_maq.coordination_index(three, 2) >= 0).sum() == 2 * (10 + 11)


# --- CQ-learning: the nearest other agent ------------------------------------------------------

@pytest.mark.parametrize("observe, near_share", [("every", 0.4), ("nearest", 0.9)])
def test_cq_marks_with_many_agents_pair_an_agent_with_a_near_agent(observe, near_share):
    """Every other agent present is tested: the cells of farther agents, often where they stand when
    a near agent collides, are augmented too, though less often than the near ones; the variant that
    sees its nearest agent only augments near cells."""
    g = load_map(MAPS / "warehouse_3.txt")
    n = g.n_agents
    setup = cq.LEARNER.setup(own=cq.Settings(cq_solo_episodes=200, cq_observe=observe))
    outputs = spec.train(cq.LEARNER, setup, g, ep.Schedule(400, ep.uniform_edges(400, 100), 1000), 1, 2,
                         workers=parallel.Threads(1))
    q_aug, marked, log = outputs["q_aug"], outputs["marked"], outputs["log"]
    _, own, other = np.nonzero(marked[0])
    assert own.size > 0 and (log[0, :, ep.column(n, ep.COORDINATIONS)] > 0).any()
    distances = np.abs(own // g.n_cols - other // g.n_cols) + np.abs(own % g.n_cols - other % g.n_cols)
    assert np.mean(distances <= 2) >= near_share  # conflicts come from near agents
    assert np.argmax(np.bincount(distances)) <= 2
    for k in range(n):  # a marked row starts from the local values and is learned from there
        assert np.abs(q_aug[0, k][~marked[0, k]]).sum() == 0


# --- the scaling study -------------------------------------------------------------------------

SMALL = sc.ScalingConfig(agents=(2, 3), episodes=200, runs=2, bin_size=100, learners=sc.RELATED_METHODS,
                         settings={"cq": cq.Settings(cq_solo_episodes=100)})


@pytest.fixture(scope="module")
def small():
    return sc.run(SMALL, seed=1, workers=1)


def test_the_study_counts_the_pair_tables_and_the_reward_windows(small):
    assert small.names() == ["sparse_maq", "cq"] and small.ran.all()
    rows = [int(sparse_maq.coordination_index(SMALL.gridmap(n), 2).max()) + 1 for n in (2, 3)]
    assert small.joint_entries[0].tolist() == [1 * rows[0] * 16, 3 * rows[1] * 16]
    windows = [n * 35 * 4 * (1 + 35) for n in (2, 3)]  # CQ-learning's: test 1's and test 2's
    assert small.reward_samples[1].tolist() == [w * 20 for w in windows]
    assert small.parameters()[1].tolist() == [2 * 140 + small.joint_entries[1, 0] + windows[0] * 20,
                                              3 * 140 + small.joint_entries[1, 1] + windows[1] * 20]
    flags_and_summaries = 3 * 35 * 35 + windows[1] * 32 + 3 * 140 * 24
    assert small.bytes_needed[1, 1] == 2 * ((3 * 140 + 3 * 35 * 35 * 4 + windows[1] * 20) * 8 + flags_and_summaries)
    assert np.isfinite(small.log).all() and (small.curves("cq", 3, "coordinations") > 0).any()


def test_new_methods_leave_the_chapter_methods_seeds_and_results_alone(small):
    assert [sc.seed_of(2, m, 3) for m in sc.CHAPTER_METHODS] == [(2 * 16 + 3) * 5 + k for k in range(5)]
    assert sc.seed_of(0, "sparse_maq", 2) >= 2 ** 32 and sc.seed_of(0, "cq", 2) != sc.seed_of(0, "sparse_maq", 2)
    again = sc.run(SMALL, seed=1, workers=2)
    assert np.array_equal(small.log, again.log) and np.array_equal(small.joint_entries, again.joint_entries)


def test_the_related_claims_get_measured_values(small):
    m = sc.measure(small)
    assert m["collisions_sparse_maq_max"] == max(m["collisions_sparse_maq_2"], m["collisions_sparse_maq_3"])
    assert "parameters_cq_over_two_observe_min" not in m  # 2observe did not run
    assert 1 < m["growth_factor_sparse_maq"] < 10
