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
Written for two agents: with more, the coordination states would be groups of agents, each with
its own joint table (a coordination graph), which this module does not build.
"""

import numpy as np
from numba import njit, prange

from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners.joint_state import joint_index
from glamas.learners.mmdp import split_joint_action
from glamas.qlearning import epsilon_greedy, q_update, row_max

N_AGENTS = 2
"""The sparse learner is written for two agents (see the module docstring)."""
N_JOINT_ACTIONS = rules.N_ACTIONS ** N_AGENTS


def coordination_index(gridmap, distance: int) -> np.ndarray:
    """int64 (cells ** 2,): the row of each joint state in the joint table, -1 where the agents act
    alone. Coordination states: two distinct cells, neither the goal nor blocked, at Manhattan
    distance <= ``distance``; rows numbered in joint-state order."""
    if gridmap.n_agents != N_AGENTS:
        raise ValueError(f"sparse tabular Q-learning is written for two agents; map {gridmap.name!r} "
                         f"has {gridmap.n_agents}")
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


@njit(cache=True)
def run(next_cell, is_goal, starts, bounce, index, alpha, gamma, exploit, n_episodes, bin_size,
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
        ep.end_episode(log, episode, bin_size, acc, t, done)


@njit(parallel=True, cache=True)
def batch(next_cell, is_goal, starts, bounce, index, alpha, gamma, exploit, n_episodes, bin_size,
          max_steps, states, q, q_joint, log):
    """:func:`run` for every run in parallel (glamas.runs batch-kernel form)."""
    for r in prange(states.shape[0]):
        run(next_cell, is_goal, starts, bounce, index, alpha, gamma, exploit, n_episodes, bin_size,
            max_steps, q[r], q_joint[r], log[r], states[r])
