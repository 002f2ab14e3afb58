"""Sparse tabular multi-agent Q-learning (Kok and Vlassis, "Sparse tabular multiagent
Q-learning", Benelearn 2004), the related work of the chapter's Section 5.1: the joint states in
which the agents must coordinate are given in advance; there the agents learn one Q-value per
joint action (as the MMDP learner), everywhere else each agent learns on its own cell (as the
independent learners).

Here a joint state is a coordination state when both agents act and their Manhattan distance is
at most ``distance`` (2 covers every collision: a swap at distance 1, a shared target at 1 or 2).
The joint values Q(s, a) estimate the sum of the agents' rewards; the four updates between
coordinated (c) and uncoordinated (u) states follow Kok and Vlassis (as summarised by Nowé,
Vrancx and De Hauwere, "Game theory and multi-agent reinforcement learning", 2012, Sec. 14.4):

- c -> c: Q(s, a) += alpha [sum_i R_i + gamma max_a' Q(s', a') - Q(s, a)]
- c -> u: Q(s, a) += alpha [sum_i (R_i + gamma max_a' Q_i(s'_i, a')) - Q(s, a)]
- u -> c: Q_i(s_i, a_i) += alpha [R_i + gamma max_a' Q(s', a') / n - Q_i(s_i, a_i)]  (each agent i)
- u -> u: Q_i(s_i, a_i) += alpha [R_i + gamma max_a' Q_i(s'_i, a') - Q_i(s_i, a_i)]  (eq. 11)

with n = 2 agents sharing the joint value. An agent that enters the goal has no future term.

**N agents** (:func:`run_pairs`, beyond Kok and Vlassis's two-agent experiments, in the spirit of
their later coordination graphs): coordination is pairwise. Each pair of agents (i < j) has its own
joint table over the same coordination states (cell_i, cell_j) x 16 joint actions. Every step the
acting agents are matched greedily from the closest pair: pairs in a coordination state are taken
by increasing distance, then lowest i, then lowest j, skipping agents already matched, so an agent
close to several others coordinates with its nearest one (lowest number on ties). The four updates
are applied per pair and per single agent, each agent's next-state value being its own
max_a' Q_i(s'_i, a') when it acts alone next, half the best joint value of the pair it is in next,
and none when it entered the goal. A pair that stays matched makes the c -> c update; a pair that
breaks up sums its agents' rewards and next-state values (c -> u, also when an agent joins another
pair); a single agent learns its reward plus its next-state value (u -> u by eq. 11, u -> c with
the 1/2 share). With two agents :func:`run_pairs` is :func:`run` (same random numbers, same
arithmetic, bit for bit).
"""

import numpy as np
from numba import njit

from glamas.gridworld import rules
from glamas.gridworld.joint import joint_index
from glamas.learners import episode as ep
from glamas.learners.mmdp import split_joint_action
from glamas.qlearning import epsilon_greedy, q_update, row_max

N_AGENTS = 2
"""Agents of :func:`run`, and of each coordinating pair of :func:`run_pairs`."""
N_JOINT_ACTIONS = rules.N_ACTIONS ** N_AGENTS
NO_PARTNER = -1
"""``partner`` of an agent that acts alone (:func:`match_pairs`)."""


def coordination_index(gridmap, distance: int) -> np.ndarray:
    """int64 (cells ** 2,): the row of each joint state in the joint table, -1 where the agents act
    alone (two agents: :func:`pair_coordination_index`, whose pairs of cells are the joint states)."""
    if gridmap.n_agents != N_AGENTS:
        raise ValueError(f"sparse tabular Q-learning is written for two agents; map {gridmap.name!r} "
                         f"has {gridmap.n_agents} (use pair_coordination_index and run_pairs for N agents)")
    return pair_coordination_index(gridmap, distance)


def pair_coordination_index(gridmap, distance: int) -> np.ndarray:
    """int64 (cells ** 2,): the row of each pair of cells (a, b) in a pair's joint table, -1 where
    the two agents act alone. Coordination states: two distinct cells, neither the goal nor
    blocked, at Manhattan distance <= ``distance``; rows numbered in (a, b) order."""
    if isinstance(distance, bool) or not isinstance(distance, (int, np.integer)) or distance < 1:
        raise ValueError(f"the coordination distance must be a whole number >= 1, got {distance!r}")
    n = gridmap.n_cells
    usable = ~(gridmap.is_goal | gridmap.blocked)
    index = np.full(n * n, -1, dtype=np.int64)
    rows = 0
    for a in range(n):
        for b in range(n):
            if a != b and usable[a] and usable[b] and rules.manhattan(gridmap.n_cols, a, b) <= distance:
                index[a * n + b] = rows
                rows += 1
    return index


def new_tables(n_cells: int, n_agents: int) -> np.ndarray:
    """Q initial tables of the uncoordinated states: one (cells x 4 actions) table per agent."""
    return np.zeros((n_agents, n_cells, rules.N_ACTIONS))


def new_joint_table(index: np.ndarray) -> np.ndarray:
    """Q initial table of the coordination states: (coordination states x 16 joint actions)."""
    return np.zeros((int(index.max()) + 1, N_JOINT_ACTIONS))


@njit(cache=True)
def coordinated_to_coordinated(q_joint, k, joint, rewards, k_next, alpha, gamma):
    """c -> c: the MMDP update of the joint value on the summed reward."""
    total = 0.0
    for i in range(rewards.shape[0]):
        total += rewards[i]
    q_joint[k, joint] += alpha * (total + gamma * row_max(q_joint, k_next) - q_joint[k, joint])


@njit(cache=True)
def coordinated_to_uncoordinated(q_joint, k, joint, q, new_cells, rewards, reached, alpha, gamma):
    """c -> u: the joint value learns the sum of each agent's reward and own next-state value
    (none for an agent that entered the goal)."""
    target = 0.0
    for i in range(rewards.shape[0]):
        target += rewards[i]
        if not reached[i]:
            target += gamma * row_max(q[i], new_cells[i])
    q_joint[k, joint] += alpha * (target - q_joint[k, joint])


@njit(cache=True)
def uncoordinated_to_coordinated(q, cells, actions, rewards, q_joint, k_next, alpha, gamma):
    """u -> c: each agent's own value learns its reward plus its 1/n share of the joint value."""
    n = cells.shape[0]
    share = row_max(q_joint, k_next) / n
    for i in range(n):
        old = q[i, cells[i], actions[i]]
        q[i, cells[i], actions[i]] = old + alpha * (rewards[i] + gamma * share - old)


@njit(cache=True)
def uncoordinated_to_uncoordinated(q, cells, done, actions, rewards, new_cells, reached, alpha, gamma):
    """u -> u: independent Q-learning (eq. 11) for every acting agent."""
    for i in range(cells.shape[0]):
        if not done[i]:
            q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)


@njit(cache=True)
def coordination_row(index, cells, n_cells):
    """The joint table's row of the agents' joint state, -1 unless it is a coordination state (an
    agent in the goal no longer acts: goal cells are in no coordination state)."""
    return index[joint_index(cells, n_cells)]


@njit(cache=True, nogil=True)
def run(next_cell, is_goal, starts, bounce, index, alpha, gamma, exploit, n_episodes, edges,
        max_steps, q, q_joint, log, state):
    """One run of ``n_episodes`` episodes; learns in ``q`` and ``q_joint``, writes the binned
    ``log`` (COORDINATIONS: steps taken in a coordination state, on a joint action)."""
    n_agents, n_cells = starts.shape[0], next_cell.shape[0]
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n_agents)
    for episode in range(n_episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            k = coordination_row(index, cells, n_cells)
            joint = 0
            if k >= 0:
                joint = epsilon_greedy(q_joint[k], exploit, state)
                split_joint_action(joint, actions)
                acc[ep.COORDINATIONS] += 1
            else:
                for i in range(n_agents):
                    if not done[i]:
                        actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
            collisions = rules.step(next_cell, is_goal, starts, bounce, cells, done, actions,
                                    new_cells, rewards, bumped, collided, reached)
            k_next = coordination_row(index, new_cells, n_cells)
            if k >= 0 and k_next >= 0:
                coordinated_to_coordinated(q_joint, k, joint, rewards, k_next, alpha, gamma)
            elif k >= 0:
                coordinated_to_uncoordinated(q_joint, k, joint, q, new_cells, rewards, reached, alpha, gamma)
            elif k_next >= 0:
                uncoordinated_to_coordinated(q, cells, actions, rewards, q_joint, k_next, alpha, gamma)
            else:
                uncoordinated_to_uncoordinated(q, cells, done, actions, rewards, new_cells, reached, alpha, gamma)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


# --- N agents: pairwise coordination (module docstring) ------------------------------------------

def n_pairs(n_agents: int) -> int:
    """Pairs of agents, each with its own joint table."""
    return n_agents * (n_agents - 1) // 2


def new_pair_tables(index: np.ndarray, n_agents: int) -> np.ndarray:
    """Q initial tables of the coordination states: (pairs, coordination states, 16 joint actions)."""
    return np.zeros((n_pairs(n_agents), int(index.max()) + 1, N_JOINT_ACTIONS))


@njit(cache=True)
def pair_number(i, j, n_agents):
    """The joint table of agents i < j: pairs numbered (0, 1), (0, 2), ..., (1, 2), ..."""
    return i * n_agents - i * (i + 1) // 2 + j - i - 1


@njit(cache=True)
def match_pairs(index, n_cols, n_cells, distance, cells, acting, partner, rows):
    """Match the ``acting`` agents into coordinating pairs, closest pairs first (ties: lowest i,
    then lowest j; agents already matched are skipped): ``partner[i]`` is i's partner or
    NO_PARTNER, ``rows[i]`` the pair's coordination row. Returns the number of pairs."""
    n = cells.shape[0]
    for i in range(n):
        partner[i] = NO_PARTNER
        rows[i] = -1
    pairs = 0
    for d in range(1, distance + 1):
        for i in range(n):
            if not acting[i] or partner[i] != NO_PARTNER:
                continue
            for j in range(i + 1, n):
                if not acting[j] or partner[j] != NO_PARTNER or rules.manhattan(n_cols, cells[i], cells[j]) != d:
                    continue
                k = index[cells[i] * n_cells + cells[j]]
                if k >= 0:
                    partner[i], partner[j], rows[i], rows[j] = j, i, k, k
                    pairs += 1
                    break
    return pairs


@njit(cache=True)
def choose_actions(q, q_pairs, cells, done, partner, rows, exploit, actions, joint, state):
    """Epsilon-greedy on the pair's joint row for matched agents (drawn once per pair, by its lower
    agent, first component to the lower agent), on the own row for the others."""
    n = cells.shape[0]
    for i in range(n):
        j = partner[i]
        if done[i] or NO_PARTNER < j < i:  # the pair's lower agent acts and learns for it
            continue
        if j == NO_PARTNER:
            actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
        else:
            joint[i] = epsilon_greedy(q_pairs[pair_number(i, j, n), rows[i]], exploit, state)
            actions[i], actions[j] = joint[i] // rules.N_ACTIONS, joint[i] % rules.N_ACTIONS


@njit(cache=True)
def next_value(q, q_pairs, i, new_cells, reached, partner_next, rows_next):
    """Agent i's value of its next state: none after entering the goal, half the best joint value
    of the pair it coordinates in next, else its own best value."""
    if reached[i]:
        return 0.0
    j = partner_next[i]
    if j == NO_PARTNER:
        return row_max(q[i], new_cells[i])
    return row_max(q_pairs[pair_number(min(i, j), max(i, j), q.shape[0])], rows_next[i]) / N_AGENTS


@njit(cache=True)
def learn_pairs(q, q_pairs, cells, done, actions, joint, rewards, new_cells, reached, partner, rows,
                partner_next, rows_next, alpha, gamma):
    """The four updates per pair and per single agent (module docstring)."""
    n = cells.shape[0]
    for i in range(n):
        j = partner[i]
        if done[i] or NO_PARTNER < j < i:  # the pair's lower agent acts and learns for it
            continue
        if j == NO_PARTNER and partner_next[i] == NO_PARTNER:  # u -> u
            q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)
        elif j == NO_PARTNER:  # u -> c
            old = q[i, cells[i], actions[i]]
            share = next_value(q, q_pairs, i, new_cells, reached, partner_next, rows_next)
            q[i, cells[i], actions[i]] = old + alpha * (rewards[i] + gamma * share - old)
        elif partner_next[i] == j:  # c -> c, the same pair
            pair_rewards = rewards[i:j + 1:j - i]  # (r_i, r_j)
            coordinated_to_coordinated(q_pairs[pair_number(i, j, n)], rows[i], joint[i], pair_rewards,
                                       rows_next[i], alpha, gamma)
        else:  # c -> u: the pair breaks up
            target = 0.0
            for m in (i, j):
                target += rewards[m]
                target += gamma * next_value(q, q_pairs, m, new_cells, reached, partner_next, rows_next)
            table = q_pairs[pair_number(i, j, n)]
            table[rows[i], joint[i]] += alpha * (target - table[rows[i], joint[i]])


@njit(cache=True, nogil=True)
def run_pairs(next_cell, is_goal, starts, bounce, n_cols, index, distance, alpha, gamma, exploit, n_episodes,
              edges, max_steps, q, q_pairs, log, state):
    """One run of ``n_episodes`` episodes of N agents with pairwise coordination; learns in ``q``
    and ``q_pairs``, writes the binned ``log`` (N-agent layout; COORDINATIONS: coordinating pairs
    summed over the steps)."""
    n_agents, n_cells = starts.shape[0], next_cell.shape[0]
    coordinations_column = ep.column(n_agents, ep.COORDINATIONS)
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n_agents)
    acting = np.empty(n_agents, np.bool_)
    partner, rows, joint = np.empty(n_agents, np.int64), np.empty(n_agents, np.int64), np.zeros(n_agents, np.int64)
    partner_next, rows_next = np.empty(n_agents, np.int64), np.empty(n_agents, np.int64)
    for episode in range(n_episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            for i in range(n_agents):
                acting[i] = not done[i]
            acc[coordinations_column] += match_pairs(index, n_cols, n_cells, distance, cells, acting, partner, rows)
            choose_actions(q, q_pairs, cells, done, partner, rows, exploit, actions, joint, state)
            collisions = rules.step(next_cell, is_goal, starts, bounce, cells, done, actions,
                                    new_cells, rewards, bumped, collided, reached)
            for i in range(n_agents):
                acting[i] = not (done[i] or reached[i])
            match_pairs(index, n_cols, n_cells, distance, new_cells, acting, partner_next, rows_next)
            learn_pairs(q, q_pairs, cells, done, actions, joint, rewards, new_cells, reached, partner, rows,
                        partner_next, rows_next, alpha, gamma)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)
