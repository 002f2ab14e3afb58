"""The coordination graph of sparse cooperative Q-learning (Kok and Vlassis, "Collaborative
multiagent reinforcement learning by payoff propagation", JMLR 7, 2006) as compiled pieces for
:mod:`glamas.learners.sparse_maq`: which agents coordinate in a state, and the joint action that
maximises the sum of their value rules.

**The graph of a state.** The agents are its nodes; an edge joins two acting agents i < j whose
cells form a coordination state (:func:`glamas.learners.sparse_maq.coordination_index`), and holds
their edge rule: row ``row`` of the pair's joint table ``q_pairs[pair_number(i, j)]``, 16 values
indexed ``4 a_i + a_j``. :func:`close_pairs` makes every such pair an edge, so an agent can be in
several; :func:`matched_pairs` keeps only a greedy matching, closest pairs first (the pairwise
variant). A connected group of agents (a *component*) is named by its lowest agent, its ``root``.

**Variable elimination** (Guestrin, Koller and Parr 2002, as Kok and Vlassis 2006 use it) finds a
joint action of a component maximising the sum of its edge rules, exactly: an agent is eliminated by
replacing the rules it is in by one new rule over its remaining neighbours, their best sum over its
four actions (agents with the fewest remaining neighbours first, the highest number on ties); then
the agents choose their actions in the reverse order, each its best given the others'. Each new rule
also counts the maximising actions behind each of its values, so the last count is the number of
maximising joint actions, and a rank among them (:func:`assign_best`) picks one: a uniform rank, a
uniform choice among ties. A rule over more than ``max_scope`` agents is not made (at most 4 **
max_scope values): the component is then maximised by max-plus.

**Max-plus** (Kok and Vlassis 2006, their payoff propagation), an option: every agent sends each
neighbour, for each of the neighbour's actions, its best sum of their edge rule and the messages it
received from its other neighbours, less the mean over the four actions (the normalisation that
makes the messages converge on graphs with cycles); after each round every agent takes the action
with the best sum of its received messages (the lowest action on ties), and the best joint action
seen so far is kept (the anytime extension). It stops when no message changes, or after its rounds.
On a tree it is exact once the messages have travelled across it (when the maximiser is unique).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import rng
from glamas.gridworld.rules import N_ACTIONS
from glamas.learners import episode as ep

MAX_SCOPE = 6
"""The most agents a rule made by variable elimination may have (4 ** 6 = 4096 values): more
only with seven or more agents in one tightly connected group."""
DRAW_AGENTS = 13
"""Agents whose random joint action one draw gives (4 ** 13 = 2 ** 26 joint actions, far within a
draw's 53 bits)."""


class Graph(NamedTuple):
    """The coordination graph of one state, as the kernel keeps it (:func:`new_graph`)."""

    a: np.ndarray
    """int64 (pairs,): the lower agent of each edge."""
    b: np.ndarray
    """int64 (pairs,): the higher agent of each edge."""
    row: np.ndarray
    """int64 (pairs,): each edge's row of its pair's joint table."""
    count: np.ndarray
    """int64 (1,): the number of edges."""
    degree: np.ndarray
    """int64 (agents,): each agent's edges."""
    first: np.ndarray
    """int64 (agents,): each agent's first edge, -1 if none."""
    root: np.ndarray
    """int64 (agents,): the lowest agent of each acting agent's component, -1 for an agent that does not act."""
    size: np.ndarray
    """int64 (agents,): the agents of the component of each root."""


class Scratch(NamedTuple):
    """Working arrays of variable elimination and max-plus (:func:`new_scratch`). Rules are
    numbered: the component's edges first, then the rules elimination makes."""

    assign: np.ndarray
    """int64 (agents,): the joint action being examined, then the one chosen."""
    alive: np.ndarray
    """bool (agents,): the agents not yet eliminated."""
    linked: np.ndarray
    """bool (agents, agents): which agents share a rule."""
    order: np.ndarray
    """int64 (agents,): the agents in the order they were eliminated."""
    made: np.ndarray
    """int64 (agents,): the rule the elimination of each agent made."""
    bucket: np.ndarray
    """int64 (rules,): the rules each eliminated agent replaced, agent after agent."""
    bucket_span: np.ndarray
    """int64 (agents, 2): where each agent's rules start and end in ``bucket``."""
    used: np.ndarray
    """bool (rules,): rules already replaced."""
    scope: np.ndarray
    """int64 (rules, MAX_SCOPE): the agents of each rule, the first one's action the most significant."""
    arity: np.ndarray
    """int64 (rules,): the agents of each rule."""
    offset: np.ndarray
    """int64 (rules,): where each rule starts in ``values`` and ``counts``."""
    maker: np.ndarray
    """int64 (rules,): the agent whose elimination made each rule (-1 for an edge)."""
    values: np.ndarray
    """float64 (pool,): the values of the rules."""
    counts: np.ndarray
    """float64 (pool,): how many maximising actions give each value."""
    base: np.ndarray
    """int64 (rules,): per replaced rule, its entry with the eliminated agent's action 0 (:func:`load_bucket`)."""
    stride: np.ndarray
    """int64 (rules,): per replaced rule, the step between the eliminated agent's actions."""
    rank: np.ndarray
    """float64 (agents,): the rank each agent chooses by (:func:`assign_best`)."""
    messages: np.ndarray
    """float64 (2, pairs, 2, 4): max-plus messages of the last and this round along each edge
    (to its higher agent, to its lower agent), over the receiver's actions."""
    belief: np.ndarray
    """float64 (agents, 4): the sum of the messages each agent received."""
    best: np.ndarray
    """int64 (agents,): the best joint action max-plus has seen."""


@njit(cache=True, inline="always")
def pair_number(i, j, n_agents):
    """The joint table of agents i < j: pairs numbered (0, 1), (0, 2), ..., (1, 2), ..."""
    return i * n_agents - i * (i + 1) // 2 + j - i - 1


@njit(cache=True)
def new_graph(n_agents):
    """An empty :class:`Graph` for ``n_agents`` agents."""
    pairs = n_agents * (n_agents - 1) // 2
    return Graph(np.zeros(pairs, np.int64), np.zeros(pairs, np.int64), np.zeros(pairs, np.int64),
                 np.zeros(1, np.int64), np.zeros(n_agents, np.int64), np.full(n_agents, -1, np.int64),
                 np.full(n_agents, -1, np.int64), np.zeros(n_agents, np.int64))


@njit(cache=True)
def new_scratch(n_agents, max_scope):
    """Working arrays for ``n_agents`` agents whose rules made have at most ``max_scope`` agents."""
    pairs = n_agents * (n_agents - 1) // 2
    rules = pairs + n_agents
    pool = pairs * N_ACTIONS ** 2 + n_agents * N_ACTIONS ** max_scope
    return Scratch(np.zeros(n_agents, np.int64), np.zeros(n_agents, np.bool_), np.zeros((n_agents, n_agents), np.bool_),
                   np.zeros(n_agents, np.int64), np.zeros(n_agents, np.int64), np.zeros(rules, np.int64),
                   np.zeros((n_agents, 2), np.int64), np.zeros(rules, np.bool_), np.zeros((rules, MAX_SCOPE), np.int64),
                   np.zeros(rules, np.int64), np.zeros(rules, np.int64), np.zeros(rules, np.int64), np.zeros(pool),
                   np.zeros(pool), np.zeros(rules, np.int64), np.zeros(rules, np.int64), np.zeros(n_agents),
                   np.zeros((2, max(pairs, 1), 2, N_ACTIONS)), np.zeros((n_agents, N_ACTIONS)), np.zeros(n_agents, np.int64))


# --- the graph of a state ----------------------------------------------------------------------

@njit(cache=True, inline="always")
def clear(graph, acting):
    """No edges; every acting agent its own component."""
    graph.count[0] = 0
    for i in range(acting.shape[0]):
        graph.degree[i] = 0
        graph.first[i] = -1
        graph.root[i] = i if acting[i] else -1
        graph.size[i] = 0


@njit(cache=True, inline="always")
def add_edge(graph, i, j, row):
    """Edge i < j on row ``row`` of their joint table."""
    e = graph.count[0]
    graph.a[e], graph.b[e], graph.row[e] = i, j, row
    graph.count[0] = e + 1
    for m in (i, j):
        if graph.first[m] < 0:
            graph.first[m] = e
        graph.degree[m] += 1


@njit(cache=True, inline="always")
def root_of(root, i):
    """The root of agent i while components are being merged (roots point to lower agents)."""
    while root[i] != i:
        i = root[i]
    return i


@njit(cache=True, inline="always")
def join_components(graph):
    """Name each acting agent's component by its lowest agent (``root``) and count its agents (``size``)."""
    root = graph.root
    for e in range(graph.count[0]):
        ra, rb = root_of(root, graph.a[e]), root_of(root, graph.b[e])
        root[max(ra, rb)] = min(ra, rb)
    for i in range(root.shape[0]):
        if root[i] >= 0:
            root[i] = root[root[i]]  # a lower agent's root is final already
            graph.size[root[i]] += 1


@njit(cache=True, inline="always")
def close_pairs(index, n_cells, cells, acting, graph):
    """The coordination graph: an edge for every pair of acting agents i < j whose cells
    (cells[i], cells[j]) are a coordination state (``index`` >= 0), in (i, j) order. Returns the edges."""
    clear(graph, acting)
    n = cells.shape[0]
    for i in range(n):
        if not acting[i]:
            continue
        base = cells[i] * n_cells
        for j in range(i + 1, n):
            row = index[base + cells[j]]
            if acting[j] and row >= 0:
                add_edge(graph, i, j, row)
    join_components(graph)
    return graph.count[0]


@njit(cache=True, inline="always")
def matched_pairs(index, distances, distance, cells, acting, graph):
    """The pairwise variant's graph: the acting agents matched into pairs closest first (distance
    1 to ``distance``; ties: lowest i, then lowest j; agents already matched are skipped), an edge
    per pair in a coordination state. ``distances`` is rules.distance_table. Returns the edges."""
    clear(graph, acting)
    n, n_cells = cells.shape[0], distances.shape[0]
    for d in range(1, distance + 1):
        for i in range(n):
            if not acting[i] or graph.degree[i] > 0:
                continue
            for j in range(i + 1, n):
                if not acting[j] or graph.degree[j] > 0 or distances[cells[i], cells[j]] != d:
                    continue
                row = index[cells[i] * n_cells + cells[j]]
                if row >= 0:
                    add_edge(graph, i, j, row)
                    graph.root[j] = i
                    break
    for i in range(n):
        if graph.root[i] >= 0:
            graph.size[graph.root[i]] += 1
    return graph.count[0]


@njit(cache=True, inline="always")
def edge_value(q_pairs, graph, e, actions):
    """Edge e's rule at the joint action ``actions``: rho_ij(s_i, s_j, a_i, a_j)."""
    i, j = graph.a[e], graph.b[e]
    return q_pairs[pair_number(i, j, actions.shape[0]), graph.row[e], actions[i] * N_ACTIONS + actions[j]]


# --- variable elimination ----------------------------------------------------------------------

@njit(cache=True, inline="always")
def holds(scratch, f, v):
    """Whether agent v is in rule f."""
    for s in range(scratch.arity[f]):
        if scratch.scope[f, s] == v:
            return True
    return False


@njit(cache=True, inline="always")
def entry(scratch, f):
    """The entry of rule f at the joint action ``scratch.assign``."""
    index = scratch.offset[f]
    stride = 1
    for s in range(scratch.arity[f] - 1, -1, -1):
        index += scratch.assign[scratch.scope[f, s]] * stride
        stride *= N_ACTIONS
    return index


@njit(cache=True, inline="always")
def load_bucket(scratch, v):
    """For each rule agent v's elimination replaced, its entry at ``scratch.assign`` with v's
    action 0 (``base``) and the step from one action of v to the next (``stride``)."""
    for k in range(scratch.bucket_span[v, 0], scratch.bucket_span[v, 1]):
        f = scratch.bucket[k]
        index, stride = scratch.offset[f], 1
        for s in range(scratch.arity[f] - 1, -1, -1):
            u = scratch.scope[f, s]
            if u == v:
                scratch.stride[k] = stride
            else:
                index += scratch.assign[u] * stride
            stride *= N_ACTIONS
        scratch.base[k] = index


@njit(cache=True, inline="always")
def bucket_value(scratch, v, action):
    """The sum of the rules v's elimination replaced, at the loaded joint action with v playing ``action``."""
    total = 0.0
    for k in range(scratch.bucket_span[v, 0], scratch.bucket_span[v, 1]):
        total += scratch.values[scratch.base[k] + action * scratch.stride[k]]
    return total


@njit(cache=True, inline="always")
def bucket_count(scratch, v, action):
    """The maximising actions of the agents eliminated before v behind those rules' values."""
    count = 1.0
    for k in range(scratch.bucket_span[v, 0], scratch.bucket_span[v, 1]):
        count *= scratch.counts[scratch.base[k] + action * scratch.stride[k]]
    return count


@njit(cache=True, inline="always")
def fewest_neighbours(scratch, n):
    """The agent left with the fewest remaining neighbours (the highest number on ties)."""
    best, fewest = -1, n + 1
    for v in range(n - 1, -1, -1):
        if not scratch.alive[v]:
            continue
        neighbours = 0
        for u in range(n):
            if scratch.alive[u] and scratch.linked[v, u]:
                neighbours += 1
        if neighbours < fewest:
            best, fewest = v, neighbours
    return best


@njit(cache=True, inline="always")
def load_edges(q_pairs, graph, root, scratch):
    """The first rules: the edges of the component of ``root``, in edge order, each its pair's 16
    values (every count 1); its agents alive and linked to their neighbours. Returns the rules and
    the values they take."""
    n = graph.root.shape[0]
    for i in range(n):
        scratch.alive[i] = graph.root[i] == root
        for j in range(n):
            scratch.linked[i, j] = False
    rules, pool = 0, 0
    for e in range(graph.count[0]):
        i, j = graph.a[e], graph.b[e]
        if graph.root[i] != root:
            continue
        scratch.linked[i, j] = scratch.linked[j, i] = True
        scratch.scope[rules, 0], scratch.scope[rules, 1] = i, j
        scratch.arity[rules], scratch.offset[rules], scratch.maker[rules], scratch.used[rules] = 2, pool, -1, False
        table = q_pairs[pair_number(i, j, n), graph.row[e]]
        for joint in range(N_ACTIONS * N_ACTIONS):
            scratch.values[pool + joint] = table[joint]
            scratch.counts[pool + joint] = 1.0
        rules += 1
        pool += N_ACTIONS * N_ACTIONS
    return rules, pool


@njit(cache=True, inline="always")
def fill_rule(scratch, f, v):
    """The values and counts of rule f, made by eliminating v: at each action of its agents, the
    best sum of v's replaced rules over v's actions and how many maximising actions give it."""
    arity, offset = scratch.arity[f], scratch.offset[f]
    for x in range(N_ACTIONS ** arity):
        rest = x
        for s in range(arity - 1, -1, -1):
            scratch.assign[scratch.scope[f, s]] = rest % N_ACTIONS
            rest //= N_ACTIONS
        load_bucket(scratch, v)
        best, count = -np.inf, 0.0
        for action in range(N_ACTIONS):
            value = bucket_value(scratch, v, action)
            if value > best:
                best, count = value, bucket_count(scratch, v, action)
            elif value == best:
                count += bucket_count(scratch, v, action)
        scratch.values[offset + x] = best
        scratch.counts[offset + x] = count


@njit(cache=True, inline="always")
def eliminate(q_pairs, graph, root, scratch, max_scope):
    """Variable elimination over the component of ``root``: eliminates its agents (fewest
    remaining neighbours first, the highest number on ties), each replacing the rules it is in by
    one over its remaining neighbours. Returns the number of maximising joint actions, or 0 when
    a rule would have more than ``max_scope`` agents."""
    n = graph.root.shape[0]
    rules, pool = load_edges(q_pairs, graph, root, scratch)
    filled = 0
    for step in range(graph.size[root]):
        v = fewest_neighbours(scratch, n)
        f = rules + step
        arity = 0
        for u in range(n):
            if scratch.alive[u] and u != v and scratch.linked[v, u]:
                if arity == max_scope:
                    return 0.0
                scratch.scope[f, arity] = u
                arity += 1
        scratch.bucket_span[v, 0] = filled
        for g in range(f):
            if not scratch.used[g] and holds(scratch, g, v):
                scratch.bucket[filled] = g
                scratch.used[g] = True
                filled += 1
        scratch.bucket_span[v, 1] = filled
        scratch.arity[f], scratch.offset[f], scratch.maker[f], scratch.used[f] = arity, pool, v, False
        pool += N_ACTIONS ** arity
        fill_rule(scratch, f, v)
        for s in range(arity):
            for t in range(arity):
                scratch.linked[scratch.scope[f, s], scratch.scope[f, t]] = s != t
        scratch.alive[v] = False
        scratch.order[step], scratch.made[v] = v, f
    return scratch.counts[scratch.offset[rules + graph.size[root] - 1]]


@njit(cache=True, inline="always")
def assign_best(scratch, steps, rank):
    """After :func:`eliminate` of a component of ``steps`` agents: its maximising joint action of
    rank ``rank`` (0 <= rank < their number) into ``scratch.assign``. The agents choose in the
    reverse order of elimination, each among its actions that reach the best value given the
    others' (action by action, each standing for as many joint actions as its count), and hands
    what is left of its rank to the agents eliminated before it, as the digits of a number whose
    bases are their counts."""
    scratch.rank[scratch.order[steps - 1]] = rank
    for step in range(steps - 1, -1, -1):
        v = scratch.order[step]
        f, left = scratch.made[v], scratch.rank[v]
        best = scratch.values[entry(scratch, f)]
        load_bucket(scratch, v)
        chosen = -1
        for action in range(N_ACTIONS):
            if bucket_value(scratch, v, action) == best:
                chosen = action
                count = bucket_count(scratch, v, action)
                if left < count:
                    break
                left -= count
        scratch.assign[v] = chosen
        for k in range(scratch.bucket_span[v, 0], scratch.bucket_span[v, 1]):
            g = scratch.bucket[k]
            if scratch.maker[g] >= 0:
                base = scratch.counts[entry(scratch, g)]
                digit = left % base
                scratch.rank[scratch.maker[g]] = digit
                left = (left - digit) / base


# --- max-plus ----------------------------------------------------------------------------------

@njit(cache=True, inline="always")
def send(q_pairs, graph, scratch, e, to_lower):
    """Edge e's message this round to its lower agent (``to_lower``) or its higher one: for each
    of the receiver's actions, the sender's best sum of the edge rule and the messages it received
    last round from its other neighbours, less the mean over the receiver's actions. Returns the
    largest change from the last round's message."""
    i, j = graph.a[e], graph.b[e]
    sender = j if to_lower else i
    back = 0 if to_lower else 1  # the message the sender received along this edge
    table = q_pairs[pair_number(i, j, graph.root.shape[0]), graph.row[e]]
    message = scratch.messages[1, e, 1 if to_lower else 0]
    total = 0.0
    for r in range(N_ACTIONS):
        best = -np.inf
        for s in range(N_ACTIONS):
            joint = r * N_ACTIONS + s if to_lower else s * N_ACTIONS + r
            value = table[joint] + scratch.belief[sender, s] - scratch.messages[0, e, back, s]
            best = max(best, value)
        message[r] = best
        total += best
    change = 0.0
    for r in range(N_ACTIONS):
        message[r] -= total / N_ACTIONS
        change = max(change, abs(message[r] - scratch.messages[0, e, 1 if to_lower else 0, r]))
    return change


@njit(cache=True, inline="always")
def gather(graph, root, scratch):
    """Each agent of the component's belief: the sum of the messages it received last round, and
    its best action by it (the lowest on ties) into ``scratch.assign``."""
    for i in range(graph.root.shape[0]):
        for a in range(N_ACTIONS):
            scratch.belief[i, a] = 0.0
    for e in range(graph.count[0]):
        if graph.root[graph.a[e]] == root:
            for a in range(N_ACTIONS):
                scratch.belief[graph.b[e], a] += scratch.messages[0, e, 0, a]
                scratch.belief[graph.a[e], a] += scratch.messages[0, e, 1, a]
    for i in range(graph.root.shape[0]):
        if graph.root[i] == root:
            best = 0
            for a in range(1, N_ACTIONS):
                if scratch.belief[i, a] > scratch.belief[i, best]:
                    best = a
            scratch.assign[i] = best


@njit(cache=True, inline="always")
def component_value(q_pairs, graph, root, actions):
    """The sum of the component's edge rules at ``actions``."""
    total = 0.0
    for e in range(graph.count[0]):
        if graph.root[graph.a[e]] == root:
            total += edge_value(q_pairs, graph, e, actions)
    return total


@njit(cache=True, inline="always")
def max_plus(q_pairs, graph, root, scratch, rounds):
    """Max-plus over the component of ``root`` for at most ``rounds`` rounds (module docstring):
    the best joint action seen into ``scratch.assign``."""
    n = graph.root.shape[0]
    for e in range(graph.count[0]):
        for k in range(2):
            for a in range(N_ACTIONS):
                scratch.messages[0, e, k, a] = 0.0
    best_value = -np.inf
    for _ in range(rounds):
        gather(graph, root, scratch)
        change = 0.0
        for e in range(graph.count[0]):
            if graph.root[graph.a[e]] == root:
                change = max(change, send(q_pairs, graph, scratch, e, True))
                change = max(change, send(q_pairs, graph, scratch, e, False))
        for e in range(graph.count[0]):
            for k in range(2):
                for a in range(N_ACTIONS):
                    scratch.messages[0, e, k, a] = scratch.messages[1, e, k, a]
        gather(graph, root, scratch)
        value = component_value(q_pairs, graph, root, scratch.assign)
        if value > best_value:
            best_value = value
            for i in range(n):
                scratch.best[i] = scratch.assign[i]
        if change == 0.0:
            break
    for i in range(n):
        scratch.assign[i] = scratch.best[i]


# --- a component's joint action ----------------------------------------------------------------

@njit(cache=True, inline="always")
def draw_rank(total, state):
    """A uniform rank among ``total`` maximising joint actions (a draw only when there are several)."""
    if total <= 1.0:
        return 0.0
    return min(np.floor(rng.uniform(state) * total), total - 1.0)


@njit(**ep.LOOP)  # called from two places in the loop: compiled once, as the loop (glamas.learners.episode)
def best_joint(q_pairs, graph, root, scratch, maximiser, state):
    """A joint action of the component of ``root`` maximising the sum of its edge rules, into
    ``scratch.assign``. ``maximiser`` (glamas.learners.sparse_maq.Coordination) chooses how: by
    variable elimination, uniformly among the maximisers (a draw from ``state`` only when there
    are several); by max-plus (``max_plus``, or when elimination would make a rule over more than
    ``max_scope`` agents), the best joint action it finds in ``max_plus_rounds`` rounds."""
    if not maximiser.max_plus:
        total = eliminate(q_pairs, graph, root, scratch, maximiser.max_scope)
        if total > 0.0:
            assign_best(scratch, graph.size[root], draw_rank(total, state))
            return
    max_plus(q_pairs, graph, root, scratch, maximiser.max_plus_rounds)


@njit(cache=True, inline="always")
def random_joint(graph, root, actions, state):
    """A uniformly random joint action of the component of ``root`` into ``actions``: one draw
    per DRAW_AGENTS of its agents, the lowest agent's action the most significant digit."""
    left, i = graph.size[root], root
    while left > 0:
        k = min(left, DRAW_AGENTS)
        joint = rng.integer(state, N_ACTIONS ** k)
        members = 0
        last = i
        while members < k:  # the next k agents of the component, from i on
            if graph.root[last] == root:
                members += 1
            last += 1
        for m in range(last - 1, i - 1, -1):
            if graph.root[m] == root:
                actions[m] = joint % N_ACTIONS
                joint //= N_ACTIONS
        left -= k
        i = last
