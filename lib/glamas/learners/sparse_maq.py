"""Sparse cooperative Q-learning, the related work of the chapter's Section 5.1: Kok and Vlassis's
sparse tabular multi-agent Q-learning ("Sparse tabular multiagent Q-learning", Benelearn 2004)
for two agents, and for N agents its coordination-graph form ("Collaborative multiagent
reinforcement learning by payoff propagation", JMLR 7, 2006, with its agent-based update). The
states in which agents must coordinate are given in advance: there they learn values of joint
actions, everywhere else each agent learns on its own cell.

**Coordination states.** Two acting agents coordinate when their Manhattan distance is at most
``coordination_distance`` (2 covers every collision: a swap at distance 1, a shared target at 1
or 2) and neither is on a goal of every agent (:func:`coordination_index`).

**Value rules.** In a state, the coordination graph (:mod:`glamas.learners.coordination_graph`)
has an edge for every pair of acting agents i < j in a coordination state, so an agent can be in
several edges. Each edge has a rule rho_ij(s_i, s_j, a_i, a_j): a row of the pair's own joint
table, over the pairs of cells it coordinates in and their 16 joint actions (a table per pair, not
one shared by every pair: on maps where agents have goals of their own, two agents' joint values
depend on who they are). An acting agent in no edge has its individual rule Q_i(s_i, a_i), its own
table. Agent i's value is the sum of the rules it is in, each divided by its number of agents:

    Q_i(s, a) = sum over i's edges ij of rho_ij(s_i, s_j, a_i, a_j) / 2,  or Q_i(s_i, a_i) alone,

and the global value Q(s, a) = sum_i Q_i(s, a) is the sum of all the rules.

**Acting.** Agents in no edge act epsilon-greedily on their own rule. A connected group of agents
explores together: with probability ``exploit_prob`` the group plays a joint action maximising
the sum of its edge rules, found by variable elimination (exact; ties broken uniformly among every
maximising joint action) or, as an option, by max-plus; otherwise a uniformly random joint action
of the group. A pair alone is Kok and Vlassis's epsilon-greedy over its 16 joint actions.

**Learning** (the agent-based update, Kok and Vlassis 2006): after the joint move, with rewards
R_i and next state s', a* is the joint action maximising Q(s', .) on the graph of s' (as when
acting: variable elimination, ties drawn uniformly), an agent that entered its goal has no future
value, and every rule of s is updated with its agents' shares of their temporal-difference errors:

    rho_k(s, a) += alpha * sum over agents i of rule k of [R_i + gamma Q_i(s', a*) - Q_i(s, a)] / m_i,

m_i the number of rules agent i is in at s (Kok and Vlassis divide by i's number of neighbours;
AI-Toolbox's ``SparseCooperativeQLearning`` divides only R_i). Every value is read before any rule
changes. When no agent is in two rules this is Kok and Vlassis's 2004 update, in its four cases
between coordinated (c) and uncoordinated (u) states; two of them are computed in their own form,
so that the two-agent learner is reproduced bit for bit:

- u -> u: Q_i(s_i, a_i) <- (1 - alpha) Q_i(s_i, a_i) + alpha [R_i + gamma max_a' Q_i(s'_i, a')] (eq. 11)
- c -> c (a pair alone in s and in s'): rho(s, a) += alpha [R_i + R_j + gamma max_a' rho(s', a') - rho(s, a)]
- u -> c and c -> u: the update above, an agent's next value being half its next pair's best
  joint value, or its own best value.

**Variant** (``coordination="pairs"``, registered as ``sparse_maq_pairs``): the graph keeps only a
greedy matching of the agents into pairs, closest pairs first (ties: lowest numbers), so an agent
coordinates with at most one other, its nearest; this was the N-agent learner before the graph.
With two agents the graph and the matching are the same single pair, and both learners are the
two-agent learner.

Plain-Python reference: ``sparse_maq`` in ``lib/glamas/plain/gridworld.py`` (variable elimination
in its ``Elimination``).
"""

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas import checks, rng
from glamas.gridworld import GridMap, rules
from glamas.learners import coordination_graph as cg
from glamas.learners import episode as ep
from glamas.learners.independent import lone_step, table_shape
from glamas.learners.registry import register
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, row_max

PAIR = 2
"""Agents of an edge rule."""
N_JOINT_ACTIONS = rules.N_ACTIONS ** PAIR
COORDINATIONS = ("graph", "pairs")
"""Who coordinates: every close pair (the coordination graph), or a greedy matching into pairs."""
MAXIMISERS = ("elimination", "max_plus")
"""How a group finds its best joint action: variable elimination (exact) or max-plus."""


@dataclass(frozen=True)
class Settings:
    """Sparse MAQ's own settings: where the agents coordinate, given in advance as Kok and Vlassis
    require, and how."""

    coordination_distance: int = 2
    """The agents coordinate in the joint states where their Manhattan distance is at most this;
    2 covers every collision."""
    coordination: str = "graph"
    """'graph': every pair of agents in a coordination state is an edge of the coordination graph
    (Kok and Vlassis 2006); 'pairs': a greedy matching into pairs, closest first (the variant)."""
    maximiser: str = "elimination"
    """How a connected group finds the joint action maximising its rules: 'elimination'
    (variable elimination, exact) or 'max_plus'."""
    max_plus_rounds: int = 20
    """Max-plus's rounds of messages at most (also where elimination would make too large a rule)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"coordination_distance": 1, "max_plus_rounds": 1})
        if self.coordination not in COORDINATIONS:
            raise UserError(f"coordination must be one of {COORDINATIONS}, got {self.coordination!r}")
        if self.maximiser not in MAXIMISERS:
            raise UserError(f"maximiser must be one of {MAXIMISERS}, got {self.maximiser!r}")


class Coordination(NamedTuple):
    """Where and how the agents coordinate, as the kernel reads it."""

    index: np.ndarray
    """int64 (cells ** 2,): :func:`coordination_index`."""
    coordination_distance: int
    """Agents coordinate at Manhattan distance at most this."""
    graph: bool
    """True: the coordination graph; False: the greedy matching into pairs."""
    max_plus: bool
    """True: groups maximise by max-plus; False: by variable elimination."""
    max_plus_rounds: int
    """Max-plus's rounds at most."""
    max_scope: int
    """Variable elimination's largest rule, in agents (glamas.learners.coordination_graph.MAX_SCOPE)."""


def coordination_index(gridmap, distance: int) -> np.ndarray:
    """int64 (cells ** 2,): the row of each pair of cells (a, b) in a pair's joint table, -1 where
    the two agents act alone. Coordination states: two distinct cells, neither blocked nor a goal
    of every agent (no agent acts there; a goal of some agents is an ordinary cell for the others),
    at Manhattan distance <= ``distance``; rows numbered in (a, b) order."""
    if isinstance(distance, bool) or not isinstance(distance, (int, np.integer)) or distance < 1:
        raise UserError(f"the coordination distance must be a whole number >= 1, got {distance!r}")
    n = gridmap.n_cells
    usable = ~(gridmap.shared_goal | gridmap.blocked)
    index = np.full(n * n, -1, dtype=np.int64)
    rows = 0
    for a in range(n):
        for b in range(n):
            if a != b and usable[a] and usable[b] and rules.manhattan(gridmap.n_cols, a, b) <= distance:
                index[a * n + b] = rows
                rows += 1
    return index


def n_pairs(n_agents: int) -> int:
    """Pairs of agents, each with its own joint table."""
    return n_agents * (n_agents - 1) // 2


def coordination(setup, gridmap: GridMap) -> tuple:
    """The kernel's own input: the Coordination bundle of its settings (``setup.own``) on ``gridmap``."""
    own = setup.own
    return (Coordination(coordination_index(gridmap, own.coordination_distance), own.coordination_distance,
                         own.coordination == "graph", own.maximiser == "max_plus", own.max_plus_rounds, cg.MAX_SCOPE),)


def pair_table_shape(setup, gridmap: GridMap) -> tuple:
    """(pairs, coordination states, 16 joint actions) of the pairs' joint tables."""
    states = int((coordination_index(gridmap, setup.own.coordination_distance) >= 0).sum())
    return n_pairs(gridmap.n_agents), states, N_JOINT_ACTIONS


def outputs(setup, gridmap: GridMap) -> dict:
    """One run's pair tables ``q_pairs``, filled with ``q_initial``."""
    return {"q_pairs": np.full(pair_table_shape(setup, gridmap), float(setup.q.q_initial))}


def joint_room(setup, gridmap: GridMap) -> int:
    """Joint values per run: every pair's joint table, all of it learned."""
    return math.prod(pair_table_shape(setup, gridmap))


def joint_learned(outputs: dict, setup, gridmap: GridMap) -> np.ndarray:
    """Per run, the joint values learned: every pair's whole joint table."""
    return np.full(outputs["q"].shape[0], float(joint_room(setup, gridmap)))


# --- one step ----------------------------------------------------------------------------------

@njit(cache=True, inline="always")
def connect(coordination, distances, cells, acting, graph):
    """The coordination graph of the ``acting`` agents on ``cells`` into ``graph`` (the greedy
    matching for the pairwise variant); ``distances`` is rules.distance_table. Returns its edges."""
    if coordination.graph:
        return cg.close_pairs(coordination.index, distances.shape[0], cells, acting, graph)
    return cg.matched_pairs(coordination.index, distances, coordination.coordination_distance, cells, acting, graph)


@njit(cache=True, inline="always")
def choose_actions(q, q_pairs, cells, graph, exploit, actions, state, scratch, coordination):
    """Epsilon-greedy per connected group, groups in the order of their lowest agent: an agent
    alone on its own row; a pair on its joint row (first component to the lower agent); a larger
    group with probability ``exploit`` on its best joint action (coordination_graph.best_joint,
    ties drawn uniformly), else on a uniformly random one."""
    n = cells.shape[0]
    for i in range(n):
        if graph.root[i] != i:  # done, or not its group's lowest agent
            continue
        size = graph.size[i]
        if size == 1:
            actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
        elif size == PAIR:
            e = graph.first[i]
            j = graph.b[e]
            joint = epsilon_greedy(q_pairs[cg.pair_number(i, j, n), graph.row[e]], exploit, state)
            actions[i], actions[j] = joint // rules.N_ACTIONS, joint % rules.N_ACTIONS
        elif rng.uniform(state) < exploit:
            cg.best_joint(q_pairs, graph, i, scratch, coordination, state)
            for m in range(i, n):
                if graph.root[m] == i:
                    actions[m] = scratch.assign[m]
        else:
            cg.random_joint(graph, i, actions, state)


@njit(cache=True, inline="always")
def agent_value(graph, i, edge_values):
    """Agent i's share of its edge rules: sum over its edges of their values / 2."""
    value = 0.0
    for e in range(graph.count[0]):
        if graph.a[e] == i or graph.b[e] == i:
            value += edge_values[e] / PAIR
    return value


@njit(cache=True, inline="always")
def best_edge_values(q_pairs, graph, scratch, coordination, edge_values, state):
    """Each edge's rule at a*, the joint action maximising the sum of the rules (in a group of
    three or more, ties drawn from ``state``, as in :func:`choose_actions`); a pair alone takes its
    row's maximum, its value whichever maximiser a* is."""
    n = graph.root.shape[0]
    for r in range(n):
        if graph.root[r] != r or graph.size[r] == 1:
            continue
        if graph.size[r] == PAIR:
            e = graph.first[r]
            edge_values[e] = row_max(q_pairs[cg.pair_number(r, graph.b[e], n)], graph.row[e])
            continue
        cg.best_joint(q_pairs, graph, r, scratch, coordination, state)
        for e in range(graph.count[0]):
            if graph.root[graph.a[e]] == r:
                edge_values[e] = cg.edge_value(q_pairs, graph, e, scratch.assign)


class Values(NamedTuple):
    """The values of a step's update, read before any rule changes (:func:`agent_values`)."""

    now: np.ndarray
    """(agents,): Q_i(s, a)."""
    after: np.ndarray
    """(agents,): Q_i(s', a*)."""
    edges_now: np.ndarray
    """(pairs,): each edge rule of s at a."""
    edges_after: np.ndarray
    """(pairs,): each edge rule of s' at a*."""


@njit(cache=True, inline="always")
def agent_values(q, q_pairs, buffers, graphs, values, scratch, coordination, state):
    """Every acting agent's Q_i(s, a) and Q_i(s', a*) into ``values`` (now, next, and the edges'
    rules behind them), all read before any rule changes: an agent entering its goal has no next
    value, an agent in no edge its own rule's (best) value."""
    cells, done, actions = buffers.cells, buffers.done, buffers.actions
    new_cells, reached = buffers.new_cells, buffers.reached
    graph, graph_next = graphs
    now, after, edges_now, edges_after = values.now, values.after, values.edges_now, values.edges_after
    for e in range(graph.count[0]):
        edges_now[e] = cg.edge_value(q_pairs, graph, e, actions)
    best_edge_values(q_pairs, graph_next, scratch, coordination, edges_after, state)
    for i in range(cells.shape[0]):
        if done[i]:
            continue
        now[i] = q[i, cells[i], actions[i]] if graph.degree[i] == 0 else agent_value(graph, i, edges_now)
        if reached[i]:
            after[i] = 0.0
        elif graph_next.degree[i] == 0:
            after[i] = row_max(q[i], new_cells[i])
        else:
            after[i] = agent_value(graph_next, i, edges_after)


@njit(cache=True, inline="always")
def shared_error(graph, agents, rewards, values, gamma):
    """sum over the rule's ``agents`` of [R_i + gamma Q_i(s', a*) - Q_i(s, a)] / m_i, summed as
    Kok and Vlassis's c -> u case: rewards and discounted next values agent after agent, minus
    the current values."""
    now, after = values.now, values.after
    target, current = 0.0, 0.0
    for i in agents:
        share = max(graph.degree[i], 1)
        target += rewards[i] / share
        target += gamma * after[i] / share
        current += now[i] / share
    return target - current


@njit(cache=True, inline="always")
def stays_a_pair(graph, graph_next, e, reached):
    """Whether edge e's agents coordinate only with each other in s and again in s' (c -> c)."""
    i, j = graph.a[e], graph.b[e]
    if graph.degree[i] != 1 or graph.degree[j] != 1 or reached[i] or reached[j]:
        return False
    return graph_next.degree[i] == 1 and graph_next.degree[j] == 1 and graph_next.b[graph_next.first[i]] == j


@njit(cache=True, inline="always")
def learn(q, q_pairs, buffers, graphs, values, learning):
    """The agent-based update of every rule of s (module docstring), from the ``values`` read before."""
    cells, done, actions = buffers.cells, buffers.done, buffers.actions
    rewards, reached = buffers.rewards, buffers.reached
    graph, graph_next = graphs
    after, edges_after = values.after, values.edges_after
    alpha, gamma = learning.q_learning_rate, learning.discount
    n = cells.shape[0]
    for i in range(n):  # individual rules
        if done[i] or graph.degree[i] > 0:
            continue
        s, a, r = cells[i], actions[i], rewards[i]
        if reached[i] or graph_next.degree[i] == 0:  # u -> u: eq. 11
            target = r if reached[i] else r + gamma * after[i]
            q[i, s, a] = (1.0 - alpha) * q[i, s, a] + alpha * target
        else:  # u -> c
            q[i, s, a] += alpha * shared_error(graph, (i,), rewards, values, gamma)
    for e in range(graph.count[0]):  # edge rules
        i, j = graph.a[e], graph.b[e]
        pair, row, joint = cg.pair_number(i, j, n), graph.row[e], actions[i] * rules.N_ACTIONS + actions[j]
        if stays_a_pair(graph, graph_next, e, reached):  # c -> c: the MMDP update
            best = edges_after[graph_next.first[i]]
            q_pairs[pair, row, joint] += alpha * (rewards[i] + rewards[j] + gamma * best - q_pairs[pair, row, joint])
        else:
            q_pairs[pair, row, joint] += alpha * shared_error(graph, (i, j), rewards, values, gamma)


# --- the run -----------------------------------------------------------------------------------

class Work(NamedTuple):
    """The per-run arrays of :func:`episodes` besides the step buffers."""

    acting: np.ndarray
    """(agents,): who acts in the graph being built."""
    distances: np.ndarray
    """rules.distance_table."""
    graphs: tuple
    """The coordination graphs of s and of s' (coordination_graph.new_graph)."""
    values: Values
    scratch: cg.Scratch
    """The maximisers' working arrays (coordination_graph.new_scratch)."""


@njit(cache=True, nogil=True)
def run(world, learning, coordination, schedule, q, q_pairs, log, state):
    """One run of ``schedule.episodes`` episodes; learns in ``q`` and ``q_pairs``, writes the
    binned ``log`` (coordinations: the coordination graph's edges summed over the steps)."""
    n_agents, n_cells = world.starts.shape[0], world.next_cell.shape[0]
    pairs = max(n_agents * (n_agents - 1) // 2, 1)
    work = Work(np.empty(n_agents, np.bool_), rules.distance_table(n_cells, world.n_cols),
                (cg.new_graph(n_agents), cg.new_graph(n_agents)),
                Values(np.zeros(n_agents), np.zeros(n_agents), np.zeros(pairs), np.zeros(pairs)),
                cg.new_scratch(n_agents, min(max(n_agents - 1, 0), coordination.max_scope)))
    episodes(world, learning, coordination, schedule, q, q_pairs, log, state, ep.buffers(n_agents), work)


@njit(**ep.LOOP)
def episodes(world, learning, coordination, schedule, q, q_pairs, log, state, buffers, work):
    """The episode loop of :func:`run`; ``work``: :class:`Work`."""
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents = starts.shape[0]
    coordinations_column = ep.column(n_agents, ep.COORDINATIONS)
    cells, done, actions, acc = buffers.cells, buffers.done, buffers.actions, buffers.acc
    new_cells, rewards, reached = buffers.new_cells, buffers.rewards, buffers.reached
    acting, distances, graphs, values, scratch = work.acting, work.distances, work.graphs, work.values, work.scratch
    graph, graph_next = graphs
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            first, second = ep.few_acting(done)
            if first >= 0 and second < 0:  # the others are in the goal: nobody to coordinate with, u -> u
                lone_step(world, learning, q, first, state, buffers)
                t += 1
                ep.end_step(t, cells, done, new_cells, rewards, reached, 0, acc)
                continue
            for i in range(n_agents):
                acting[i] = not done[i]
            acc[coordinations_column] += connect(coordination, distances, cells, acting, graph)
            choose_actions(q, q_pairs, cells, graph, learning.exploit_prob, actions, state, scratch, coordination)
            if second >= 0:  # two agents act: the rules' two-agent path
                collisions = ep.step_pair(world, buffers, (first, second))
            else:
                collisions = ep.step(world, buffers)
            for i in range(n_agents):
                acting[i] = not (done[i] or reached[i])
            connect(coordination, distances, new_cells, acting, graph_next)
            agent_values(q, q_pairs, buffers, graphs, values, scratch, coordination, state)
            learn(q, q_pairs, buffers, graphs, values, learning)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="sparse_maq", label="sparse tabular MAQ", n_agent_label="sparse MAQ (graph)",
                  kernel=run, table_shape=table_shape,
                  defaults=Settings(), inputs=coordination, outputs=outputs, joint_room=joint_room,
                  joint_learned=joint_learned, family="related", rank=0)
"""The coordination-graph learner; its seeds are the sparse MAQ's of before (related slot 0)."""
PAIRS = replace(LEARNER, name="sparse_maq_pairs", label="sparse tabular MAQ, pairs", n_agent_label="sparse MAQ (pairs)",
                defaults=Settings(coordination="pairs"), rank=2)
"""The pairwise variant (the N-agent learner before the coordination graph); slot 2 is beyond the
related family's stride of 2, so it draws from its name's slot and leaves every other learner's
seeds alone."""

register(LEARNER)
register(PAIRS)
