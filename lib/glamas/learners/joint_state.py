"""Joint-state learners (Section 5.3): each agent runs Alg. 3 over the joint cells of both agents
(625 states on TunnelToGoal) with its own reward, still choosing only its own action (4).

Every step, with s = (s_1, s_2) the joint cell: each agent i not in its goal selects a_i
epsilon-greedily from Q_i(s, .); the agents move together; each updates by eq. 11 on the joint
cells, Q_i(s, a_i) <- (1 - alpha) Q_i(s, a_i) + alpha [r_i + gamma max_a' Q_i(s', a')].

Plain-Python reference: ``joint_state`` in ``lib/glamas/plain/gridworld.py``."""

from numba import njit

from glamas.gridworld import rules
from glamas.gridworld.joint import joint_index
from glamas.learners import episode as ep
from glamas.learners.registry import register
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, q_update


def table_shape(n_cells: int, n_agents: int) -> tuple:
    """One (joint cells x 4 actions) table per agent."""
    return n_agents, n_cells ** n_agents, rules.N_ACTIONS


@njit(cache=True, nogil=True)
def run(world, learning, schedule, q, log, state):
    """One run of ``schedule.episodes`` episodes; learns in ``q`` and writes the binned ``log``."""
    episodes(world, learning, schedule, q, log, state, ep.buffers(world.starts.shape[0]))


@njit(**ep.LOOP)
def episodes(world, learning, schedule, q, log, state, buffers):
    """The episode loop of :func:`run`."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents, n_cells = starts.shape[0], world.next_cell.shape[0]
    cells, done, acc = buffers.cells, buffers.done, buffers.acc
    actions, new_cells, rewards, reached = buffers.actions, buffers.new_cells, buffers.rewards, buffers.reached
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            s = joint_index(cells, n_cells)
            for i in range(n_agents):
                if not done[i]:
                    actions[i] = epsilon_greedy(q[i, s], exploit, state)
            if n_agents == 2:  # the chapter's case, on the rules' fast path
                collisions = ep.step_pair(world, buffers, (0, 1))
            else:
                collisions = ep.step(world, buffers)
            s_next = joint_index(new_cells, n_cells)
            for i in range(n_agents):
                if not done[i]:
                    q_update(q[i], s, actions[i], rewards[i], s_next, reached[i], alpha, gamma)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="joint_state", label="joint-state learners", kernel=run, table_shape=table_shape,
                  joint_tables=True, family="chapter", rank=1)

register(LEARNER)
