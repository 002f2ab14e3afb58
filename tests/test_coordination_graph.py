"""The coordination graph's joint maximisation (glamas.learners.coordination_graph): variable
elimination against brute force over every joint action on random small graphs (its count of
maximisers and the maximiser of every rank), max-plus exact on trees, max-plus taking over from
elimination beyond its largest rule, and a group's random joint action."""

import collections
import itertools

import numpy as np
import pytest

from glamas.learners import coordination_graph as cg
from glamas.learners import sparse_maq
from glamas.rng import run_states


def graph_of(n, pairs):
    """A graph of ``n`` acting agents with the edges ``pairs`` (i < j), edge k on row k."""
    graph = cg.new_graph(n)
    cg.clear(graph, np.ones(n, np.bool_))
    for k, (i, j) in enumerate(pairs):
        cg.add_edge(graph, i, j, k)
    cg.join_components(graph)
    return graph


def tables(n, pairs, rng, whole):
    """Each edge's 16 values on its row of its pair's table: small whole numbers (many ties) or reals."""
    q_pairs = np.zeros((n * (n - 1) // 2, max(len(pairs), 1), 16))
    for k, (i, j) in enumerate(pairs):
        q_pairs[cg.pair_number(i, j, n), k] = rng.integers(0, 3, 16) if whole else rng.normal(size=16)
    return q_pairs


def brute_force(q_pairs, graph, root):
    """The component's agents and every joint action of theirs (a tuple, lowest agent first) with its value."""
    n = graph.root.shape[0]
    members = [i for i in range(n) if graph.root[i] == root]
    values = {}
    for joint in itertools.product(range(4), repeat=len(members)):
        actions = np.zeros(n, np.int64)
        actions[members] = joint
        values[joint] = sum(cg.edge_value(q_pairs, graph, e, actions) for e in range(graph.count[0])
                            if graph.root[graph.a[e]] == root)
    return members, values


def random_graph(rng, n_low=2, n_high=6):
    n = int(rng.integers(n_low, n_high + 1))
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n) if rng.random() < 0.6]
    return n, pairs


def random_tree(rng, n):
    return [tuple(sorted((int(rng.integers(0, v)), v))) for v in range(1, n)]


def roots(graph):
    return [r for r in range(graph.root.shape[0]) if graph.root[r] == r and graph.size[r] > 1]


@pytest.mark.parametrize("seed", range(40))
def test_elimination_counts_and_ranks_every_maximising_joint_action(seed):
    rng = np.random.default_rng(seed)
    n, pairs = random_graph(rng)
    graph, q_pairs = graph_of(n, pairs), tables(n, pairs, rng, whole=True)
    scratch = cg.new_scratch(n, cg.MAX_SCOPE)
    for root in roots(graph):
        members, values = brute_force(q_pairs, graph, root)
        best = max(values.values())
        maximisers = {joint for joint, value in values.items() if value == best}
        total = cg.eliminate(q_pairs, graph, root, scratch, cg.MAX_SCOPE)
        assert total == len(maximisers)
        ranked = []
        for rank in range(int(total)):
            cg.assign_best(scratch, graph.size[root], float(rank))
            ranked.append(tuple(int(scratch.assign[m]) for m in members))
        assert sorted(ranked) == sorted(maximisers)  # each maximiser once: a uniform rank draws uniformly


@pytest.mark.parametrize("seed", range(20))
def test_elimination_finds_the_one_best_joint_action_of_real_valued_rules(seed):
    rng = np.random.default_rng(100 + seed)
    n, pairs = random_graph(rng, 3, 7)
    graph, q_pairs = graph_of(n, pairs), tables(n, pairs, rng, whole=False)
    scratch = cg.new_scratch(n, cg.MAX_SCOPE)
    bundle = sparse_maq.Coordination(np.zeros(1, np.int64), 2, True, False, 20, cg.MAX_SCOPE)
    for root in roots(graph):
        members, values = brute_force(q_pairs, graph, root)
        cg.best_joint(q_pairs, graph, root, scratch, bundle, run_states(0, 1)[0])
        assert tuple(int(scratch.assign[m]) for m in members) == max(values, key=values.get)


@pytest.mark.parametrize("seed", range(20))
def test_max_plus_is_exact_on_trees(seed):
    rng = np.random.default_rng(200 + seed)
    n = int(rng.integers(2, 9))
    pairs = random_tree(rng, n)
    graph, q_pairs = graph_of(n, pairs), tables(n, pairs, rng, whole=False)
    scratch = cg.new_scratch(n, 2)
    members, values = brute_force(q_pairs, graph, 0)
    cg.max_plus(q_pairs, graph, 0, scratch, n)  # messages cross a tree of n agents in fewer than n rounds
    assert tuple(int(scratch.assign[m]) for m in members) == max(values, key=values.get)


@pytest.mark.parametrize("seed", range(10))
def test_max_plus_on_graphs_with_cycles_keeps_the_best_joint_action_it_saw(seed):
    rng = np.random.default_rng(300 + seed)
    n = int(rng.integers(3, 7))
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]  # every pair: cycles everywhere
    graph, q_pairs = graph_of(n, pairs), tables(n, pairs, rng, whole=False)
    scratch = cg.new_scratch(n, 2)
    members, values = brute_force(q_pairs, graph, 0)
    first = cg.new_scratch(n, 2)
    cg.max_plus(q_pairs, graph, 0, first, 1)
    cg.max_plus(q_pairs, graph, 0, scratch, 20)
    found = values[tuple(int(scratch.assign[m]) for m in members)]
    assert values[tuple(int(first.assign[m]) for m in members)] <= found <= max(values.values())


def test_max_plus_takes_over_where_elimination_would_make_too_large_a_rule():
    rng = np.random.default_rng(5)
    pairs = [(0, 1), (0, 2), (0, 3)]  # a star: eliminating a leaf makes a rule over the centre alone
    graph, q_pairs = graph_of(4, pairs), tables(4, pairs, rng, whole=False)
    scratch = cg.new_scratch(4, 0)
    assert cg.eliminate(q_pairs, graph, 0, scratch, 0) == 0.0  # a rule over one agent is already too large
    bundle = sparse_maq.Coordination(np.zeros(1, np.int64), 2, True, False, 20, 0)
    cg.best_joint(q_pairs, graph, 0, scratch, bundle, run_states(0, 1)[0])
    members, values = brute_force(q_pairs, graph, 0)
    assert tuple(int(a) for a in scratch.assign) == max(values, key=values.get)  # max-plus, exact on this tree


def test_a_groups_random_joint_action_is_uniform_and_leaves_the_others_alone():
    graph = graph_of(4, [(0, 2), (2, 3)])  # the group 0 - 2 - 3; agent 1 alone
    state = run_states(1, 1)[0]
    seen = collections.Counter()
    for _ in range(6400):
        actions = np.full(4, 9, np.int64)
        cg.random_joint(graph, 0, actions, state)
        assert actions[1] == 9
        seen[tuple(actions[[0, 2, 3]])] += 1
    assert len(seen) == 64 and min(seen.values()) > 100 * 0.6 and max(seen.values()) < 100 * 1.4
