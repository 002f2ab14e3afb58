"""2observe (Section 5, Alg. 4): a GLA per agent decides from the agents' distance whether to
coordinate; the agents act on independent Q-learners over their own cells, and only when both
chose to coordinate they check whether their preferred actions collide and, if so, one of them
(picked at random) yields with a random other action (Section 5.2).

The GLAs' feedback r_c (Fig. 10) is lost. It is rebuilt as ``table[choice, need]`` plus the
chapter's ``0 - delta/10`` when both coordinated without need (Section 5.3), where "need" is one of
three readings (``NEEDS``):

* ``in_range`` (default): the agents could collide in this step, whatever they choose
  (:func:`glamas.gridworld.rules.could_collide`). Section 5.1 has the GLA judge whether the agents
  are within each other's range of interference, and the introduction asks for coordination only
  when a collision is possible.
* ``sampled``: the actions the agents' Q-learners prefer in this step would collide.
* ``outcome``: a collision happened in this step.
"""

import numpy as np
from numba import njit

from glamas import gla, rng
from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners.independent import new_tables  # noqa: F401 (re-exported: the same state-action space, Section 5.3)
from glamas.qlearning import epsilon_greedy, q_update

ACT_ALONE = 0
"""GLA action: ignore the other agent this step."""
COORDINATE = 1
"""GLA action: coordinate with the other agent this step."""
N_GLA_INPUTS = 2
"""The GLA context [delta * delta_scale, 1]: the agents' Manhattan distance and a bias input."""

NEED_IN_RANGE = 0
NEED_SAMPLED = 1
NEED_OUTCOME = 2
NEEDS = {"in_range": NEED_IN_RANGE, "sampled": NEED_SAMPLED, "outcome": NEED_OUTCOME}
"""The readings of Fig. 10's "need to coordinate" (module docstring), by name."""


def new_need_counts(n_rows: int, n_cols: int) -> np.ndarray:
    """Room for the count of observed steps per distance delta (0 .. n_rows + n_cols - 2) without
    and with need, shape (deltas, 2): what the GLA's feedback depends on."""
    return np.zeros((n_rows + n_cols - 1, 2))


def new_gla_parameters(n_agents: int) -> np.ndarray:
    """Room for one 2-action GLA per agent, shape (agents, 2 actions, 2 inputs); the kernel
    draws the initial values from the run's own random stream."""
    return np.zeros((n_agents, 2, N_GLA_INPUTS))


@njit(cache=True, inline="always")
def yield_at_random(preferred, actions, state):
    """Section 5.2's coordination: one agent (picked at random) keeps its preferred action, the
    other takes an action drawn uniformly from its other three."""
    actions[0], actions[1] = preferred[0], preferred[1]
    yielder = rng.integer(state, 2)
    other = rng.integer(state, 3)
    actions[yielder] = other + 1 if other >= preferred[yielder] else other


@njit(cache=True, inline="always")
def first_level(next_cell, is_goal, cells, done, choices, preferred):
    """Alg. 4's if-condition for GLA ``choices`` and Q-preferred actions ``preferred``: (collision
    coming, both coordinated). When both hold, one agent yields (:func:`yield_at_random`).

    "Collision coming" means the preferred actions would collide (rules.would_collide): Section
    5.2's check, made only when both chose to coordinate.
    """
    coming = rules.would_collide(next_cell, is_goal, cells, done, preferred, 0, 1)
    choice0, choice1 = choices[0], choices[1]  # both read: arrays outside branches (glamas.learners.episode)
    return coming, choice0 == COORDINATE and choice1 == COORDINATE


@njit(cache=True, inline="always")
def need_before_step(need, in_range, cells, i, j, coming):
    """Agent i's need to coordinate with agent j under the readings decided before the move
    (``in_range``: the table of rules.in_range_table; ``sampled``: ``coming`` is whether i's and
    j's preferred actions collide); False for ``outcome``, which the move decides."""
    could_collide = in_range[cells[i], cells[j]]  # looked up outside the branches (glamas.learners.episode)
    if need == NEED_IN_RANGE:
        return could_collide
    return need == NEED_SAMPLED and coming


@njit(cache=True, inline="always")
def gla_feedback(table, penalty_per_cell, choice, need, both, delta):
    """r_c of Alg. 4 (Fig. 10, reconstructed): table[choice, need], minus ``penalty_per_cell *
    delta`` when both coordinated without need (Section 5.3's 0 - delta/10)."""
    beta = table[choice, 1 if need else 0]
    if both and not need:
        beta -= penalty_per_cell * delta
    return beta


@njit(cache=True, nogil=True, error_model="numpy")
def run(next_cell, is_goal, starts, bounce, n_cols, alpha, gamma, exploit, gla_rate, temperature,
        K, L, bounding, init_range, feedback_table, penalty_per_cell, need, delta_scale,
        rule_distance, n_episodes, edges, max_steps, q, u, need_counts, log, state):
    """One run of ``n_episodes`` episodes of Alg. 4; learns in ``q`` and ``u``, writes ``log``
    and counts the observed steps per (delta, need) in ``need_counts``.

    ``need`` is a code of ``NEEDS``; the GLAs see ``[delta * delta_scale, 1]``. When one agent is
    in the goal there is nobody to observe: the other acts on its Q alone and the GLAs are not
    updated. ``rule_distance`` >= 0 replaces the GLAs by the fixed rule "coordinate when delta <
    rule_distance" (a diagnostic; -1: the GLAs learn, as in Alg. 4).
    """
    learn_first_level = rule_distance < 0
    n_agents = starts.shape[0]
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n_agents)
    choices = np.empty(n_agents, np.int64)
    preferred = np.zeros(n_agents, np.int64)  # one of the actions even for done agents (rules.would_collide)
    probs = np.empty((n_agents, 2))
    x = np.ones(N_GLA_INPUTS)
    in_range = rules.in_range_table(next_cell, is_goal)
    needed = False
    for i in range(n_agents):  # "initialised randomly" (Section 5.3)
        for j in range(2):
            for k in range(N_GLA_INPUTS):
                u[i, j, k] = init_range * (2.0 * rng.uniform(state) - 1.0)
    for episode in range(n_episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            observing = not (done[0] or done[1])
            if observing:
                delta = rules.manhattan(n_cols, cells[0], cells[1])
                x[0] = delta * delta_scale
                for i in range(n_agents):
                    if learn_first_level:
                        choices[i] = gla.act(u[i], x, temperature, L, bounding, probs[i], state)
                    else:
                        choices[i] = COORDINATE if delta < rule_distance else ACT_ALONE
                for i in range(n_agents):
                    preferred[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
                coming, both = first_level(next_cell, is_goal, cells, done, choices, preferred)
                actions[0], actions[1] = preferred[0], preferred[1]
                if both and coming:
                    yield_at_random(preferred, actions, state)
                needed = need_before_step(need, in_range, cells, 0, 1, coming)
                if both:
                    acc[ep.COORDINATIONS] += 1
            else:
                for i in range(n_agents):
                    if not done[i]:
                        actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
            collisions = rules.step_two(next_cell, is_goal, starts, bounce, cells, done, actions,
                                        new_cells, rewards, bumped, collided, reached)
            if observing:
                if need == NEED_OUTCOME:
                    needed = collisions > 0
                need_counts[delta, 1 if needed else 0] += 1
            for i in range(n_agents):
                if not done[i]:
                    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i],
                             alpha, gamma)
            if observing and learn_first_level:
                for i in range(n_agents):
                    beta = gla_feedback(feedback_table, penalty_per_cell, choices[i], needed, both, delta)
                    gla.update(u[i], x, choices[i], beta, gla_rate, temperature, K, L, bounding, probs[i])
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)
