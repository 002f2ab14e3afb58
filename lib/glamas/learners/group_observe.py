"""2observe (Section 5, Alg. 4) for N agents: the chapter's two-agent algorithm generalised.

Each agent keeps the chapter's first level: one 2-action GLA with the context [delta, 1], where
delta is now the Manhattan distance to the *nearest* other agent still acting (lowest agent number
on ties). Agents alone in the world (every other agent in the goal) act on their Q-learner and
their GLA is not updated, as in the two-agent kernel.

The second level generalises Section 5.2's coordination to groups: among the agents that chose to
coordinate, those whose preferred action would collide with another coordinating agent's preferred
action go in a random order; each keeps its preferred action unless it would collide with an agent
earlier in the order that kept its own, and then takes an action drawn uniformly from its other
three. For two agents this is the chapter's rule ("one agent, picked at random, keeps its action,
the other takes a random other action") and draws the very same random numbers as
:func:`glamas.learners.two_observe.yield_at_random`.

GLA feedback per agent i (Fig. 10, reconstructed: :func:`two_observe.gla_feedback`), with "need"
read per agent (:data:`two_observe.NEEDS`): ``in_range``, i could collide with some other acting
agent in this step; ``sampled``, i's preferred action would collide with some other acting agent's
preferred action; ``outcome``, i collided in this step. "Both coordinated" means i and its nearest
other agent both chose to coordinate (then the penalty ``-penalty_per_cell * delta`` applies when
i had no need).

With two agents, :func:`run_group` reproduces :func:`two_observe.run` exactly under every reading
(same random numbers, same log, same GLA parameters); only ``need_counts`` counts each observing
agent, so twice per step. :func:`run` therefore runs two agents on :func:`two_observe.run`, the
faster kernel. The log's coordinations column counts agent-steps coordinating with their nearest agent,
halved: for two agents, the steps on which both coordinated.
"""

import numpy as np
from numba import njit

from glamas import gla, rng
from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners import two_observe
from glamas.learners.independent import new_tables  # the same state-action space as two agents
from glamas.learners.two_observe import (ACT_ALONE, COORDINATE, N_GLA_INPUTS, NEED_IN_RANGE, NEED_OUTCOME,
                                         NEED_SAMPLED, gla_feedback, new_gla_parameters)
from glamas.qlearning import epsilon_greedy, q_update

__all__ = ["coordinate_group", "nearest_others", "new_need_counts", "new_gla_parameters",
           "new_tables", "random_order", "run", "run_group"]

NOBODY = -1
"""``nearest`` of an agent that has no other acting agent to observe."""


def new_need_counts(n_rows: int, n_cols: int) -> np.ndarray:
    """Room for the count of observing agent-steps per distance delta without / with need for
    that agent, shape (deltas, 2)."""
    return np.zeros((n_rows + n_cols - 1, 2))


@njit(cache=True, inline="always")
def nearest_others(n_cols, cells, done, nearest, deltas):
    """For every acting agent: the nearest other acting agent (lowest number on ties) and its
    Manhattan distance; ``nearest`` is NOBODY for agents that are done or alone."""
    n = cells.shape[0]
    for i in range(n):
        nearest[i] = NOBODY
        deltas[i] = 0
        if done[i]:
            continue
        for j in range(n):
            if j == i or done[j]:
                continue
            d = rules.manhattan(n_cols, cells[i], cells[j])
            if nearest[i] == NOBODY or d < deltas[i]:
                nearest[i] = j
                deltas[i] = d


@njit(cache=True, inline="always")
def random_order(members, count, state):
    """Shuffle ``members[:count]`` uniformly (Durstenfeld: from the back, one draw per place)."""
    for i in range(count - 1, 0, -1):
        j = rng.integer(state, i + 1)
        members[i], members[j] = members[j], members[i]


@njit(cache=True, inline="always")
def collision_coming(next_cell, is_goal, cells, done, preferred, i):
    """Whether agent i's preferred action would collide with another agent's preferred action."""
    for j in range(cells.shape[0]):
        if j != i and rules.would_collide(next_cell, is_goal, cells, done, preferred, i, j):
            return True
    return False


@njit(cache=True, inline="always")
def in_range_of_any(in_range, cells, done, i):
    """Whether acting agent i could collide with some other acting agent in this step
    (``in_range``: the table of rules.in_range_table)."""
    for j in range(cells.shape[0]):
        if j != i and not done[j] and in_range[cells[i], cells[j]]:
            return True
    return False


@njit(cache=True, inline="always")
def need_of(need, in_range, cells, done, coming, collided, i):
    """Agent i's need under reading ``need`` (module docstring); ``collided`` is the step's."""
    if need == NEED_IN_RANGE:
        return in_range_of_any(in_range, cells, done, i)
    if need == NEED_SAMPLED:
        return coming[i]
    return need == NEED_OUTCOME and collided[i]


@njit(cache=True, inline="always")
def coordinate_group(next_cell, is_goal, cells, done, choices, preferred, actions, order, kept, state):
    """Section 5.2's coordination for a group (module docstring): fill ``actions`` from the
    ``preferred`` ones; return how many coordinating agents were in a coming collision.

    ``order`` and ``kept`` are per-run buffers of one entry per agent.
    """
    n = cells.shape[0]
    count = 0
    for i in range(n):
        actions[i] = preferred[i]
        if done[i] or choices[i] != COORDINATE:
            continue
        for j in range(n):
            if j != i and choices[j] == COORDINATE and rules.would_collide(
                    next_cell, is_goal, cells, done, preferred, i, j):
                order[count] = i
                count += 1
                break
    random_order(order, count, state)
    for k in range(count):
        i = order[k]
        kept[i] = True
        for m in range(k):
            j = order[m]
            if kept[j] and rules.would_collide(next_cell, is_goal, cells, done, preferred, i, j):
                kept[i] = False
                break
        if not kept[i]:
            other = rng.integer(state, 3)
            actions[i] = other + 1 if other >= preferred[i] else other
    return count


@njit(cache=True, nogil=True, error_model="numpy")
def run(next_cell, is_goal, starts, bounce, n_cols, alpha, gamma, exploit, gla_rate, temperature,
        K, L, bounding, init_range, feedback_table, penalty_per_cell, need, delta_scale,
        rule_distance, n_episodes, edges, max_steps, q, u, need_counts, log, state):
    """One run of ``n_episodes`` episodes of Alg. 4 for N agents; learns in ``q`` and ``u``,
    writes ``log`` (N-agent layout of glamas.learners.episode) and ``need_counts``.

    ``rule_distance`` >= 0 replaces the GLAs by the fixed rule "coordinate when delta <
    rule_distance" (a diagnostic; -1: the GLAs learn, as in Alg. 4).

    Two agents play the steps of :func:`run_group` on the two-agent kernel
    (:func:`glamas.learners.two_observe.run`, module docstring), which is faster; both agents
    observe with the same delta and the same need, so each of its need counts counts twice.
    """
    if starts.shape[0] == 2:
        counts = np.zeros_like(need_counts)
        two_observe.run(next_cell, is_goal, starts, bounce, n_cols, alpha, gamma, exploit, gla_rate,
                        temperature, K, L, bounding, init_range, feedback_table, penalty_per_cell, need,
                        delta_scale, rule_distance, n_episodes, edges, max_steps, q, u, counts, log, state)
        need_counts += 2.0 * counts
    else:
        run_group(next_cell, is_goal, starts, bounce, n_cols, alpha, gamma, exploit, gla_rate, temperature,
                  K, L, bounding, init_range, feedback_table, penalty_per_cell, need, delta_scale,
                  rule_distance, n_episodes, edges, max_steps, q, u, need_counts, log, state)


@njit(cache=True, nogil=True, error_model="numpy")
def run_group(next_cell, is_goal, starts, bounce, n_cols, alpha, gamma, exploit, gla_rate, temperature,
              K, L, bounding, init_range, feedback_table, penalty_per_cell, need, delta_scale,
              rule_distance, n_episodes, edges, max_steps, q, u, need_counts, log, state):
    """:func:`run` for any number of agents, with the group coordination of the module docstring."""
    learn_first_level = rule_distance < 0
    n_agents = starts.shape[0]
    coordinations_column = ep.column(n_agents, ep.COORDINATIONS)
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n_agents)
    choices = np.empty(n_agents, np.int64)
    preferred = np.zeros(n_agents, np.int64)  # one of the actions even for done agents (rules.would_collide)
    nearest = np.empty(n_agents, np.int64)
    deltas = np.empty(n_agents, np.int64)
    coming = np.empty(n_agents, np.bool_)
    needed = np.empty(n_agents, np.bool_)
    order = np.empty(n_agents, np.int64)
    kept = np.empty(n_agents, np.bool_)
    probs = np.empty((n_agents, 2))
    x = np.ones((n_agents, N_GLA_INPUTS))
    in_range = rules.in_range_table(next_cell, is_goal)
    for i in range(n_agents):  # "initialised randomly" (Section 5.3)
        for j in range(2):
            for k in range(N_GLA_INPUTS):
                u[i, j, k] = init_range * (2.0 * rng.uniform(state) - 1.0)
    for episode in range(n_episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            nearest_others(n_cols, cells, done, nearest, deltas)
            for i in range(n_agents):
                choices[i] = ACT_ALONE
                if nearest[i] == NOBODY:
                    continue
                x[i, 0] = deltas[i] * delta_scale
                if learn_first_level:
                    choices[i] = gla.act(u[i], x[i], temperature, L, bounding, probs[i], state)
                elif deltas[i] < rule_distance:
                    choices[i] = COORDINATE
            for i in range(n_agents):
                if not done[i]:
                    preferred[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
            for i in range(n_agents):
                coming[i] = collision_coming(next_cell, is_goal, cells, done, preferred, i)
            coordinate_group(next_cell, is_goal, cells, done, choices, preferred, actions, order, kept, state)
            paired = 0
            for i in range(n_agents):
                if nearest[i] != NOBODY and choices[i] == COORDINATE and choices[nearest[i]] == COORDINATE:
                    paired += 1
            acc[coordinations_column] += paired / 2
            collisions = rules.step(next_cell, is_goal, starts, bounce, cells, done, actions,
                                    new_cells, rewards, bumped, collided, reached)
            for i in range(n_agents):
                if nearest[i] != NOBODY:
                    needed[i] = need_of(need, in_range, cells, done, coming, collided, i)
                    need_counts[deltas[i], 1 if needed[i] else 0] += 1
            for i in range(n_agents):
                if not done[i]:
                    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i],
                             alpha, gamma)
            if learn_first_level:
                for i in range(n_agents):
                    if nearest[i] == NOBODY:
                        continue
                    both = choices[i] == COORDINATE and choices[nearest[i]] == COORDINATE
                    beta = gla_feedback(feedback_table, penalty_per_cell, choices[i], needed[i], both, deltas[i])
                    gla.update(u[i], x[i], choices[i], beta, gla_rate, temperature, K, L, bounding, probs[i])
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)
