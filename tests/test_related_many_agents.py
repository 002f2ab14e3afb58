"""Sparse cooperative Q-learning (the coordination graph, and the pairwise variant) and CQ-learning
(nearest agent) for N agents: the graphs, action choice per group, the agent-based update and
Kok and Vlassis's four cases, small runs, and the learners in the scaling study."""

import collections
from pathlib import Path

import numpy as np
import pytest

from benchmarks import kernels
from glamas import parallel, seeds, training
from glamas.experiments import gridworld as gw
from glamas.experiments import scaling as sc
from glamas.gridworld import load_map, rules
from glamas.gridworld.rules import E, N, S, W
from glamas.learners import coordination_graph as cg
from glamas.learners import cq, registry, spec, sparse_maq
from glamas.learners import episode as ep
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


OPEN_5X5 = """\
+-+-+-+-+-+
|1 2 3 . .|
+ + + + + +
|. . . . .|
+ + + + + +
|. . . . .|
+ + + + + +
|. . . . .|
+ + + + + +
|. . . . G|
+-+-+-+-+-+
"""


@pytest.fixture()
def open5():
    g = load_map(OPEN_5X5)
    return g, sparse_maq.coordination_index(g, 2)


def graph_of(g, index, cells, acting=(True, True, True), distance=2, coordination="graph"):
    """The coordination graph (or the pairwise variant's matching) of agents on ``cells``."""
    graph = cg.new_graph(len(cells))
    if coordination == "graph":
        cg.close_pairs(index, g.n_cells, np.array(cells), np.array(acting), graph)
    else:
        cg.matched_pairs(index, rules.distance_table(g.n_cells, g.n_cols), distance, np.array(cells), np.array(acting),
                         graph)
    return graph


def edges(graph):
    return [(int(graph.a[e]), int(graph.b[e])) for e in range(graph.count[0])]


def at(g, *places):
    return [g.cell(r, c) for r, c in places]


# --- sparse MAQ: the coordination graph and the pairs -------------------------------------------

def test_pairs_are_numbered_once_each():
    numbers = [cg.pair_number(i, j, 5) for i in range(5) for j in range(i + 1, 5)]
    assert numbers == list(range(sparse_maq.n_pairs(5)))


def test_the_graph_joins_every_close_pair_and_names_groups_by_their_lowest_agent(open5):
    g, index = open5
    # agent 0 at (1,1); agent 1 at (1,3), distance 2; agent 2 at (2,1), distance 1 from agent 0 and 3 from agent 1
    graph = graph_of(g, index, at(g, (1, 1), (1, 3), (2, 1)))
    assert edges(graph) == [(0, 1), (0, 2)] and graph.degree.tolist() == [2, 1, 1]
    assert graph.root.tolist() == [0, 0, 0] and graph.size[0] == 3
    assert graph.row[1] == index[g.cell(1, 1) * g.n_cells + g.cell(2, 1)]
    far = graph_of(g, index, at(g, (0, 0), (3, 4), (3, 3)))  # only agents 1 and 2 are close
    assert edges(far) == [(1, 2)] and far.root.tolist() == [0, 1, 1] and far.size[[0, 1]].tolist() == [1, 2]
    alone = graph_of(g, index, at(g, (1, 1), (1, 3), (2, 1)), acting=(True, False, False))
    assert edges(alone) == [] and alone.root.tolist() == [0, -1, -1]


def test_the_pairwise_variant_matches_an_agent_with_its_nearest_partner(open5):
    g, index = open5
    graph = graph_of(g, index, at(g, (1, 1), (1, 3), (2, 1)), coordination="pairs")
    assert edges(graph) == [(0, 2)] and graph.root.tolist() == [0, 1, 0]
    assert graph.row[0] == index[g.cell(1, 1) * g.n_cells + g.cell(2, 1)]
    # agent 2 at (1,2) is at distance 1 from agent 0 (1,1) and agent 1 (1,3): it pairs with agent 0
    assert edges(graph_of(g, index, at(g, (1, 1), (1, 3), (1, 2)), coordination="pairs")) == [(0, 2)]
    far = at(g, (0, 0), (3, 4), (3, 2))  # agents 1 and 2 at distance 2
    assert edges(graph_of(g, index, far, coordination="pairs")) == [(1, 2)]
    assert edges(graph_of(g, index, far, distance=1, coordination="pairs")) == []
    assert edges(graph_of(g, index, far, acting=(True, True, False), coordination="pairs")) == []


def choose(q, q_pairs, cells, graph, exploit, seed=0):
    actions = np.zeros(len(cells), np.int64)
    coordination = sparse_maq.Coordination(np.zeros(1, np.int64), 2, True, False, 20, 2)
    sparse_maq.choose_actions(q, q_pairs, np.array(cells), graph, exploit, actions, run_states(seed, 1)[0],
                              cg.new_scratch(len(cells), 2), coordination)
    return actions.tolist()


@pytest.fixture()
def tables(open5):
    g, index = open5
    return np.zeros((3, g.n_cells, 4)), np.zeros((3, int(index.max()) + 1, 16))


def test_a_pair_draws_one_joint_action_lower_agent_first(open5, tables):
    g, index = open5
    q, q_pairs = tables
    cells = at(g, (0, 0), (3, 4), (1, 0))  # agents 0 and 2 adjacent, agent 1 far
    graph = graph_of(g, index, cells)
    q_pairs[cg.pair_number(0, 2, 3), graph.row[0], 4 * S + W] = 1.0  # agent 0 goes S, agent 2 goes W
    q[1, cells[1], E] = 1.0
    assert choose(q, q_pairs, cells, graph, 1.0) == [S, E, W]


def test_a_group_plays_its_best_joint_action_or_explores_together(open5, tables):
    g, index = open5
    q, q_pairs = tables
    cells = at(g, (1, 1), (1, 3), (2, 1))  # the group 1 - 0 - 2
    graph = graph_of(g, index, cells)
    q_pairs[cg.pair_number(0, 1, 3), graph.row[0], 4 * E + W] = 2.0
    q_pairs[cg.pair_number(0, 2, 3), graph.row[1], 4 * E + S] = 2.0
    q_pairs[cg.pair_number(0, 2, 3), graph.row[1], 4 * S + E] = 3.0  # the best of its pair alone, not of the group
    assert choose(q, q_pairs, cells, graph, 1.0) == [E, W, S]
    explored = {tuple(choose(q, q_pairs, cells, graph, 0.0, seed)) for seed in range(2000)}
    assert len(explored) == 64  # every joint action of the group


def test_ties_in_a_group_are_drawn_among_every_best_joint_action(open5, tables):
    g, index = open5
    q, q_pairs = tables
    cells = at(g, (1, 1), (1, 3), (2, 1))
    graph = graph_of(g, index, cells)
    q_pairs[cg.pair_number(0, 2, 3), graph.row[1], [4 * E + S, 4 * S + E]] = 1.0  # two best for (0, 2), agent 1 free
    counts = collections.Counter(tuple(choose(q, q_pairs, cells, graph, 1.0, seed)) for seed in range(4000))
    assert len(counts) == 8 and min(counts.values()) > 4000 / 8 * 0.8  # 2 x 4 maximisers, drawn uniformly


def learn(g, index, q, q_pairs, cells, new_cells, rewards, actions, reached=(False, False, False), coordination="graph"):
    """One update of sparse MAQ's rules from ``cells`` to ``new_cells`` (glamas.learners.sparse_maq)."""
    n = len(cells)
    graphs = (graph_of(g, index, cells, coordination=coordination),
              graph_of(g, index, new_cells, acting=[not r for r in reached], coordination=coordination))
    buffers = ep.Buffers(np.array(cells), np.zeros(n, np.bool_), np.array(actions), np.array(new_cells),
                         np.array(rewards), np.zeros(n, np.bool_), np.zeros(n, np.bool_), np.array(reached),
                         np.zeros(ep.n_columns(n)))
    values = sparse_maq.Values(np.zeros(n), np.zeros(n), np.zeros(3), np.zeros(3))
    bundle = sparse_maq.Coordination(index, 2, coordination == "graph", False, 20, 2)
    sparse_maq.agent_values(q, q_pairs, buffers, graphs, values, cg.new_scratch(n, 2), bundle, run_states(0, 1)[0])
    sparse_maq.learn(q, q_pairs, buffers, graphs, values, QLearning(ALPHA, GAMMA, 0.9))


def row(g, index, a, b):
    return index[g.cell(*a) * g.n_cells + g.cell(*b)]


def test_a_pair_that_stays_together_makes_the_mmdp_update(open5, tables):
    g, index = open5
    q, q_pairs = tables
    pair, before, after = cg.pair_number(0, 2, 3), row(g, index, (0, 0), (1, 0)), row(g, index, (0, 1), (1, 1))
    q_pairs[pair, before, 4 * E + E] = 10.0
    q_pairs[pair, after] = np.arange(16.0)  # max 15
    q[1, g.cell(2, 4), N] = 0.5
    # agents 0 and 2 adjacent, then adjacent again (c -> c); agent 1 far, then far (u -> u)
    learn(g, index, q, q_pairs, at(g, (0, 0), (3, 4), (1, 0)), at(g, (0, 1), (2, 4), (1, 1)), [-1.0, 0.0, -10.0],
          (E, N, E))
    assert q_pairs[pair, before, 4 * E + E] == pytest.approx(10 + ALPHA * (-11 + GAMMA * 15 - 10))
    assert q_pairs[pair, before].sum() == q_pairs[pair, before, 4 * E + E]  # updated once
    assert q[1, g.cell(3, 4), N] == pytest.approx(ALPHA * (0 + GAMMA * 0.5))  # eq. 11


def test_a_pair_that_breaks_up_sums_each_agents_next_value(open5, tables):
    g, index = open5
    q, q_pairs = tables
    pair, before = cg.pair_number(0, 2, 3), row(g, index, (0, 0), (1, 0))
    q_pairs[pair, before, 4 * E + S] = 10.0
    q[0, g.cell(0, 1)] = [1.0, 4.0, 2.0, 0.0]  # max 4
    q[2, g.cell(2, 0)] = [3.0, 0.0, 6.0, 1.0]  # max 6
    # agents 0 and 2 adjacent, then 3 apart: each acts alone next (c -> u)
    learn(g, index, q, q_pairs, at(g, (0, 0), (3, 4), (1, 0)), at(g, (0, 1), (2, 4), (2, 0)), [0.0, 0.0, -1.0],
          (E, N, S))
    assert q_pairs[pair, before, 4 * E + S] == pytest.approx(10 + ALPHA * ((0 + GAMMA * 4) + (-1 + GAMMA * 6) - 10))


def test_agents_joining_a_pair_learn_half_its_best_joint_value(open5, tables):
    g, index = open5
    q, q_pairs = tables
    q_pairs[cg.pair_number(0, 2, 3), row(g, index, (1, 0), (2, 0))] = np.arange(16.0)  # max 15
    q[0, g.cell(0, 0), S] = 2.0
    # agents 0 and 2 three apart (u), then adjacent (u -> c)
    learn(g, index, q, q_pairs, at(g, (0, 0), (3, 4), (3, 0)), at(g, (1, 0), (2, 4), (2, 0)), [0.0, -1.0, -1.0],
          (S, N, N))
    assert q[0, g.cell(0, 0), S] == pytest.approx(2 + ALPHA * (0 + GAMMA * 15 / 2 - 2))
    assert q[2, g.cell(3, 0), N] == pytest.approx(ALPHA * (-1 + GAMMA * 15 / 2))


def test_an_agent_in_two_edges_takes_half_of_each_and_shares_its_error(open5, tables):
    g, index = open5
    q, q_pairs = tables
    r01, r02 = row(g, index, (1, 1), (1, 3)), row(g, index, (1, 1), (2, 1))
    q_pairs[cg.pair_number(0, 1, 3), r01, 4 * N + E] = 8.0
    q_pairs[cg.pair_number(0, 2, 3), r02, 4 * N + S] = 4.0
    new_cells = at(g, (0, 1), (1, 4), (3, 1))  # every agent alone next
    q[0, new_cells[0]] = [1.0, 4.0, 2.0, 0.0]
    q[1, new_cells[1]] = [0.5, 0.0, 0.0, 0.0]
    q[2, new_cells[2]] = [3.0, 0.0, 6.0, 1.0]
    rewards = [-1.0, 0.0, -10.0]
    # edges (0, 1) and (0, 2): agent 0 is in two rules
    learn(g, index, q, q_pairs, at(g, (1, 1), (1, 3), (2, 1)), new_cells, rewards, (N, E, S))
    now = [8 / 2 + 4 / 2, 8 / 2, 4 / 2]  # Q_i(s, a): each edge rule halved, summed over i's edges
    error = [rewards[i] + GAMMA * q[i, new_cells[i]].max() - now[i] for i in range(3)]
    assert q_pairs[cg.pair_number(0, 1, 3), r01, 4 * N + E] == pytest.approx(8 + ALPHA * (error[0] / 2 + error[1]))
    assert q_pairs[cg.pair_number(0, 2, 3), r02, 4 * N + S] == pytest.approx(4 + ALPHA * (error[0] / 2 + error[2]))


def test_the_pairwise_variant_learns_with_the_pair_it_matched(open5, tables):
    g, index = open5
    q, q_pairs = tables
    r02 = row(g, index, (1, 1), (2, 1))
    q_pairs[cg.pair_number(0, 2, 3), r02, 4 * N + S] = 4.0
    new_cells = at(g, (0, 1), (1, 4), (3, 1))
    q[0, new_cells[0]] = [1.0, 4.0, 2.0, 0.0]
    q[1, new_cells[1]] = [0.5, 0.0, 0.0, 0.0]
    q[2, new_cells[2]] = [3.0, 0.0, 6.0, 1.0]
    learn(g, index, q, q_pairs, at(g, (1, 1), (1, 3), (2, 1)), new_cells, [-1.0, 0.0, -10.0], (N, E, S),
          coordination="pairs")  # agent 0 matched with agent 2, its nearest; agent 1 alone
    assert q_pairs[cg.pair_number(0, 2, 3), r02, 4 * N + S] == pytest.approx(
        4 + ALPHA * ((-1 + GAMMA * 4) + (-10 + GAMMA * 6) - 4))
    assert q[1, g.cell(1, 3), E] == pytest.approx(ALPHA * (0 + GAMMA * 0.5))
    assert not q_pairs[cg.pair_number(0, 1, 3)].any()


def test_the_next_value_is_the_share_of_the_best_joint_action_of_the_next_group(open5, tables):
    g, index = open5
    q, q_pairs = tables
    # agents 0 and 2 a pair, agent 1 alone; next, the group 0 - 2 - 1 whose best joint action is a*
    new_cells = at(g, (0, 1), (1, 3), (1, 1))
    n02, n12 = row(g, index, (0, 1), (1, 1)), row(g, index, (1, 3), (1, 1))
    q_pairs[cg.pair_number(0, 2, 3), n02, 4 * E + S] = 2.0
    q_pairs[cg.pair_number(1, 2, 3), n12, 4 * W + S] = 2.0
    q_pairs[cg.pair_number(0, 2, 3), n02, 4 * S + E] = 3.0  # a* = (E, W, S): 2 + 2 > 3
    learn(g, index, q, q_pairs, at(g, (1, 1), (1, 4), (2, 1)), new_cells, [0.0, -1.0, 0.0], (N, W, N))
    assert q[1, g.cell(1, 4), W] == pytest.approx(ALPHA * (-1 + GAMMA * 2 / 2))  # half its edge (1, 2) at a*


def test_an_agent_entering_the_goal_has_no_future_term(open5, tables):
    g, index = open5
    q, q_pairs = tables
    pair, before = cg.pair_number(1, 2, 3), row(g, index, (3, 4), (4, 3))
    q_pairs[pair, before, 4 * S + E] = 10.0
    q[0, g.cell(0, 1)] = [1.0, 4.0, 2.0, 0.0]
    learn(g, index, q, q_pairs, at(g, (0, 0), (3, 4), (4, 3)), at(g, (0, 1), (4, 4), (4, 4)), [0.0, 100.0, 100.0],
          (E, S, E), reached=(False, True, True))
    assert q_pairs[pair, before, 4 * S + E] == pytest.approx(10 + ALPHA * (100 + 100 - 10))
    assert q[0, g.cell(0, 0), E] == pytest.approx(ALPHA * (0 + GAMMA * 4))


def test_index_for_many_agents_and_its_errors():
    three = load_map(OPEN_3X3)
    with pytest.raises(ValueError, match="coordination distance must be a whole number >= 1"):
        sparse_maq.coordination_index(three, 0)
    # ordered pairs of the 8 usable cells: 10 adjacent pairs, 11 at distance 2 (none with the goal)
    assert (sparse_maq.coordination_index(three, 2) >= 0).sum() == 2 * (10 + 11)


# --- sparse MAQ: runs -----------------------------------------------------------------------------

BEFORE = np.load(Path(__file__).with_name("data") / "sparse_maq_pairs_e8d567d.npz")
"""Outputs of sparse MAQ before the coordination graph (commit e8d567d, pairwise matching): 2 runs
of seed 11 of each case below, made with benchmarks.kernels.run_compiled."""
BEFORE_CASES = {
    "tunnel": dict(episodes=300),
    "tunnel_start": dict(episodes=100, bounce="start"),
    "isr": dict(episodes=100, map="isr"),
    "warehouse_3": dict(episodes=20, map="warehouse_3", max_steps=1000),
    "warehouse_4": dict(episodes=20, map="warehouse_4", max_steps=1000),
    "tunnel_to_goal_4": dict(episodes=20, map="tunnel_to_goal_4", max_steps=1000),
}
TWO_AGENTS = ("tunnel", "tunnel_start", "isr")


def run_case(learner, case, own=None):
    return kernels.run_compiled(kernels.Workload(learner, **BEFORE_CASES[case], own=own), seed=11, n_runs=2).arrays


def same_as_before(arrays, case):
    return all(np.array_equal(arrays[name], BEFORE[f"{case}/{name}"]) for name in ("q", "q_pairs", "log"))


@pytest.mark.parametrize("case", TWO_AGENTS)
def test_with_two_agents_the_graph_learner_is_the_two_agent_learner_bit_for_bit(case):
    assert same_as_before(run_case("sparse_maq", case), case)
    assert same_as_before(run_case("sparse_maq", case, sparse_maq.Settings(maximiser="max_plus")), case)


@pytest.mark.parametrize("case", list(BEFORE_CASES))
def test_the_pairwise_variant_is_the_learner_of_before_bit_for_bit(case):
    assert same_as_before(run_case("sparse_maq_pairs", case), case)


def test_with_more_agents_the_graph_coordinates_every_close_pair():
    graph, pairs = run_case("sparse_maq", "warehouse_4"), run_case("sparse_maq_pairs", "warehouse_4")
    assert not np.array_equal(graph["log"], pairs["log"])
    # the graph counts an edge per close pair, the matching at most one per agent: more coordinations per step
    per_step = [ep.metric(out["log"], "coordinations").sum() / ep.metric(out["log"], "length").sum() for out in (graph, pairs)]
    assert per_step[0] > per_step[1]
    max_plus = run_case("sparse_maq", "warehouse_4", sparse_maq.Settings(maximiser="max_plus"))
    assert np.isfinite(max_plus["q_pairs"]).all() and max_plus["log"].any()


@pytest.mark.parametrize("name, map_name", [("sparse_maq", "warehouse_4"), ("sparse_maq_pairs", "warehouse_4"),
                                            ("sparse_maq", "tunnel_to_goal")])
def test_a_frozen_run_from_the_learned_tables_changes_none_of_them(name, map_name):
    """Learner.freeze's contract: the kernel run from learned outputs with the Q-learning rate 0."""
    learner, gridmap = registry.get(name), load_map(map_name)
    setup = learner.setup()
    schedule = ep.Schedule(60, ep.uniform_edges(60, 10), 1000)
    learned = training.train(learner, setup, gridmap, schedule, 1, 3, workers=parallel.Threads(1))
    world, learning, *own, schedule = spec.kernel_inputs(learner, setup, gridmap, schedule)
    frozen = (world, learning._replace(q_learning_rate=0.0), *learner.freeze(tuple(own)), schedule)
    start = tuple(np.array(learned[key]) for key in ("q", "q_pairs")) + (np.zeros_like(learned["log"]),)
    _, (q, q_pairs, log) = parallel.fill_chunk(learner.kernel_for(gridmap.n_agents), frozen, 9, 0, 1, start)
    assert np.array_equal(q, learned["q"]) and np.array_equal(q_pairs, learned["q_pairs"])
    assert (ep.metric(log, "length") > 0).all()


def test_the_pairwise_variant_has_seeds_of_its_own():
    assert gw.seed_of(5, "sparse_maq_pairs") != gw.seed_of(5, "sparse_maq")
    assert sc.seed_of(1, "sparse_maq_pairs", 4) not in {sc.seed_of(1, name, 4) for name in sc.METHODS}


# --- CQ-learning: the nearest other agent ------------------------------------------------------

@pytest.mark.parametrize("observe, near_share", [("every", 0.4), ("nearest", 0.9)])
def test_cq_marks_with_many_agents_pair_an_agent_with_a_near_agent(observe, near_share):
    """Every other agent present is tested: the cells of farther agents, often where they stand when
    a near agent collides, are augmented too, though less often than the near ones; the variant that
    sees its nearest agent only augments near cells."""
    g = load_map(MAPS / "warehouse_3.txt")
    n = g.n_agents
    setup = cq.LEARNER.setup(own=cq.Settings(cq_solo_episodes=200, cq_observe=observe))
    outputs = training.train(cq.LEARNER, setup, g, ep.Schedule(400, ep.uniform_edges(400, 100), 1000), 1, 2,
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
    assert [sc.seed_of(2, m, 3) for m in sc.CHAPTER_METHODS] == [seeds.named(2, "scaling", 3, m)
                                                                 for m in sc.CHAPTER_METHODS]
    again = sc.run(SMALL, seed=1, workers=2)
    assert np.array_equal(small.log, again.log) and np.array_equal(small.joint_entries, again.joint_entries)


def test_the_related_claims_get_measured_values(small):
    m = sc.measure(small)
    assert m["collisions_sparse_maq_max"] == max(m["collisions_sparse_maq_2"], m["collisions_sparse_maq_3"])
    assert "parameters_cq_over_two_observe_min" not in m  # 2observe did not run
    assert 1 < m["growth_factor_sparse_maq"] < 10
