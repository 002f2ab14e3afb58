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

**N agents** (beyond Kok and Vlassis's two-agent experiments, in the spirit of their later
coordination graphs): coordination is pairwise. Each pair of agents (i < j) has its own
joint table over the same coordination states (cell_i, cell_j) x 16 joint actions. Every step the
acting agents are matched greedily from the closest pair: pairs in a coordination state are taken
by increasing distance, then lowest i, then lowest j, skipping agents already matched, so an agent
close to several others coordinates with its nearest one (lowest number on ties). The four updates
are applied per pair and per single agent, each agent's next-state value being its own
max_a' Q_i(s'_i, a') when it acts alone next, half the best joint value of the pair it is in next,
and none when it entered the goal. A pair that stays matched makes the c -> c update; a pair that
breaks up sums its agents' rewards and next-state values (c -> u, also when an agent joins another
pair); a single agent learns its reward plus its next-state value (u -> u by eq. 11, u -> c with
the 1/2 share). With two agents there is one pair, matched exactly in the coordination states,
and these are Kok and Vlassis's four updates.
"""

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas import checks
from glamas.gridworld import GridMap, rules
from glamas.learners import episode as ep
from glamas.learners.independent import lone_step, table_shape
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy

PAIR = 2
"""Agents of a coordinating pair."""
N_JOINT_ACTIONS = rules.N_ACTIONS ** PAIR
NO_PARTNER = -1
"""``partner`` of an agent that acts alone (:func:`match_pairs`)."""


@dataclass(frozen=True)
class Settings:
    """Sparse tabular MAQ's own setting: where the agents coordinate, given in advance as Kok and
    Vlassis require."""

    coordination_distance: int = 2
    """The agents coordinate in the joint states where their Manhattan distance is at most this;
    2 covers every collision."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"coordination_distance": 1})


class Coordination(NamedTuple):
    """Where pairs coordinate, as the kernel reads it."""

    index: np.ndarray
    """int64 (cells ** 2,): :func:`coordination_index`."""
    coordination_distance: int
    """Pairs coordinate at Manhattan distance at most this."""


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
    distance = setup.own.coordination_distance
    return (Coordination(coordination_index(gridmap, distance), distance),)


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


@njit(cache=True, inline="always")
def best_of(tables, k, row):
    """max_a tables[k, row, a]: :func:`glamas.qlearning.row_max` of table k's row ``row``."""
    best = tables[k, row, 0]
    for a in range(1, tables.shape[2]):
        value = tables[k, row, a]
        if value > best:
            best = value
    return best


@njit(cache=True, inline="always")
def coordinated_to_coordinated(q_pairs, pair, row, joint, reward, row_next, alpha, gamma):
    """c -> c: the MMDP update of the pair's joint value on its summed ``reward``."""
    q_pairs[pair, row, joint] += alpha * (reward + gamma * best_of(q_pairs, pair, row_next) - q_pairs[pair, row, joint])


@njit(cache=True, inline="always")
def pair_number(i, j, n_agents):
    """The joint table of agents i < j: pairs numbered (0, 1), (0, 2), ..., (1, 2), ..."""
    return i * n_agents - i * (i + 1) // 2 + j - i - 1


@njit(cache=True, inline="always")
def match_pairs(coordination, distances, cells, acting, partner, rows):
    """Match the ``acting`` agents into coordinating pairs, closest pairs first (ties: lowest i,
    then lowest j; agents already matched are skipped): ``partner[i]`` is i's partner or
    NO_PARTNER, ``rows[i]`` the pair's coordination row. ``distances`` is rules.distance_table.
    Returns the number of pairs."""
    index = coordination.index
    n = cells.shape[0]
    for i in range(n):
        partner[i] = NO_PARTNER
        rows[i] = -1
    pairs = 0
    for d in range(1, coordination.coordination_distance + 1):
        for i in range(n):
            if not acting[i] or partner[i] != NO_PARTNER:
                continue
            for j in range(i + 1, n):
                if not acting[j] or partner[j] != NO_PARTNER or distances[cells[i], cells[j]] != d:
                    continue
                k = index[cells[i] * distances.shape[0] + cells[j]]
                if k >= 0:
                    partner[i], partner[j], rows[i], rows[j] = j, i, k, k
                    pairs += 1
                    break
    return pairs


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def next_value(q, q_pairs, i, new_cells, reached, partner_next, rows_next):
    """Agent i's value of its next state: none after entering the goal, half the best joint value
    of the pair it coordinates in next, else its own best value."""
    j, cell, row, arrived = partner_next[i], new_cells[i], rows_next[i], reached[i]
    if arrived:
        return 0.0
    if j == NO_PARTNER:
        return best_of(q, i, cell)
    return best_of(q_pairs, pair_number(min(i, j), max(i, j), q.shape[0]), row) / PAIR


@njit(cache=True, inline="always")
def learn_pairs(q, q_pairs, cells, done, actions, rewards, new_cells, reached, matches, learning):
    """The four updates per pair and per single agent (module docstring). ``matches`` holds the
    step's (partner, rows, joint actions) and the next state's (partner, rows)."""
    partner, rows, joint, partner_next, rows_next = matches
    alpha, gamma = learning.q_learning_rate, learning.discount
    n = cells.shape[0]
    for i in range(n):
        j, j_next, is_done, row, row_next, joint_i = partner[i], partner_next[i], done[i], rows[i], rows_next[i], joint[i]
        s, a, r, s_next, arrived = cells[i], actions[i], rewards[i], new_cells[i], reached[i]
        if is_done or NO_PARTNER < j < i:  # the pair's lower agent acts and learns for it
            continue
        if j == NO_PARTNER and j_next == NO_PARTNER:  # u -> u: eq. 11
            target = r
            if not arrived:
                target += gamma * best_of(q, i, s_next)
            q[i, s, a] = (1.0 - alpha) * q[i, s, a] + alpha * target
        elif j == NO_PARTNER:  # u -> c
            old = q[i, s, a]
            share = next_value(q, q_pairs, i, new_cells, reached, partner_next, rows_next)
            q[i, s, a] = old + alpha * (r + gamma * share - old)
        elif j_next == j:  # c -> c, the same pair
            coordinated_to_coordinated(q_pairs, pair_number(i, j, n), row, joint_i, r + rewards[j], row_next, alpha, gamma)
        else:  # c -> u: the pair breaks up
            target = 0.0
            for m in (i, j):
                target += rewards[m]
                target += gamma * next_value(q, q_pairs, m, new_cells, reached, partner_next, rows_next)
            pair = pair_number(i, j, n)
            q_pairs[pair, row, joint_i] += alpha * (target - q_pairs[pair, row, joint_i])


@njit(cache=True, nogil=True)
def run(world, learning, coordination, schedule, q, q_pairs, log, state):
    """One run of ``schedule.episodes`` episodes with pairwise coordination; learns in ``q`` and
    ``q_pairs``, writes the binned ``log`` (coordinations: coordinating pairs summed over the steps)."""
    n_agents = world.starts.shape[0]
    pairing = (np.empty(n_agents, np.bool_), rules.distance_table(world.next_cell.shape[0], world.n_cols),
               (np.empty(n_agents, np.int64), np.empty(n_agents, np.int64), np.zeros(n_agents, np.int64),
                np.empty(n_agents, np.int64), np.empty(n_agents, np.int64)))
    episodes(world, learning, coordination, schedule, q, q_pairs, log, state, ep.buffers(n_agents), pairing)


@njit(**ep.LOOP)
def episodes(world, learning, coordination, schedule, q, q_pairs, log, state, buffers, pairing):
    """The episode loop of :func:`run`; ``pairing``: who acts, the distance table and the
    matches (partner, rows, joint actions, next partner, next rows)."""
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents = starts.shape[0]
    coordinations_column = ep.column(n_agents, ep.COORDINATIONS)
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = buffers
    acting, distances, matches = pairing
    partner, rows, joint, partner_next, rows_next = matches
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
            acc[coordinations_column] += match_pairs(coordination, distances, cells, acting, partner, rows)
            choose_actions(q, q_pairs, cells, done, partner, rows, learning.exploit_prob, actions, joint, state)
            if second >= 0:  # two agents act: the rules' two-agent path
                collisions = rules.step_pair(world, cells, done, actions, new_cells, rewards, bumped, collided, reached,
                                             (first, second))
            else:
                collisions = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            for i in range(n_agents):
                acting[i] = not (done[i] or reached[i])
            match_pairs(coordination, distances, new_cells, acting, partner_next, rows_next)
            learn_pairs(q, q_pairs, cells, done, actions, rewards, new_cells, reached, matches, learning)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="sparse_maq", label="sparse tabular MAQ", n_agent_label="sparse MAQ (pairs)",
                  kernel=run, table_shape=table_shape,
                  defaults=Settings(), inputs=coordination, outputs=outputs, joint_room=joint_room,
                  joint_learned=joint_learned, family="related", seed_slot=0)
