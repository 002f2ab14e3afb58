"""Independent Q-learners (Section 5.3): each agent runs Alg. 3 on its own cell only, with its own
reward, ignoring the other agent (a 25 x 4 table each on TunnelToGoal)."""

from numba import njit

from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, q_update


def table_shape(n_cells: int, n_agents: int) -> tuple:
    """One (cells x 4 actions) table per agent."""
    return n_agents, n_cells, rules.N_ACTIONS


@njit(cache=True, inline="always")
def lone_step(world, learning, q, i, state, buffers):
    """One step of agent i alone in the world (every other agent is in the goal): Alg. 3 on its
    own cell and table ``q[i]``; nobody is left to collide with (rules.step_alone). Also how
    2observe and sparse MAQ learn then: nobody is left to observe or coordinate with."""
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = buffers
    actions[i] = epsilon_greedy(q[i, cells[i]], learning.exploit_prob, state)
    rules.step_alone(world, cells, actions, new_cells, rewards, bumped, collided, reached, i)
    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], learning.q_learning_rate,
             learning.discount)


@njit(cache=True, nogil=True)
def run(world, learning, schedule, q, log, state):
    """One run of ``schedule.episodes`` episodes; learns in ``q`` and writes the binned ``log``."""
    episodes(world, learning, schedule, q, log, state, ep.buffers(world.starts.shape[0]))


@njit(**ep.LOOP)
def episodes(world, learning, schedule, q, log, state, buffers):
    """The episode loop of :func:`run`."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents = starts.shape[0]
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = buffers
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            lone = ep.lone_agent(done)
            if lone >= 0:  # the others are in the goal
                lone_step(world, learning, q, lone, state, buffers)
                t += 1
                ep.end_step(t, cells, done, new_cells, rewards, reached, 0, acc)
                continue
            for i in range(n_agents):
                if not done[i]:
                    actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
            if n_agents == 2:  # the chapter's case, on the rules' fast path
                collisions = rules.step_two(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            else:
                collisions = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            for i in range(n_agents):
                if not done[i]:
                    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="independent", label="independent Q-learners", kernel=run, table_shape=table_shape,
                  family="chapter")
