"""Independent Q-learners (Section 5.3): each agent runs Alg. 3 on its own cell only, with its own
reward, ignoring the other agents (a 25 x 4 table each on TunnelToGoal).

Alg. 3 as each agent i runs it here, every step of an episode while it is not in its goal:

1. in its cell s_i, select an action a_i epsilon-greedily from Q_i(s_i, .) (exploitation
   ``exploit_prob``, ties broken at random);
2. the agents move together (:func:`glamas.gridworld.rules.step`): i receives its own reward r_i
   and its next cell s'_i;
3. eq. 11: Q_i(s_i, a_i) <- (1 - alpha) Q_i(s_i, a_i) + alpha [r_i + gamma max_a' Q_i(s'_i, a')],
   with no future value once s'_i is its goal.

Plain-Python reference of the same steps, on the same random numbers: ``independent`` in
``lib/glamas/plain/gridworld.py``."""

from numba import njit

from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners.registry import register
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
    cells, actions = buffers.cells, buffers.actions
    new_cells, rewards, reached = buffers.new_cells, buffers.rewards, buffers.reached
    actions[i] = epsilon_greedy(q[i, cells[i]], learning.exploit_prob, state)
    ep.step_alone(world, buffers, i)
    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], learning.q_learning_rate,
             learning.discount)
    return 0


@njit(cache=True, inline="always")
def pair_step(world, learning, q, pair, state, buffers):
    """One step of the agents ``pair = (i, j)``, i < j, when every other agent is in the goal:
    Alg. 3 for each, on the rules' two-agent path (rules.step_pair); the same draws and updates
    as the general step. Returns the number of collisions."""
    cells, actions = buffers.cells, buffers.actions
    new_cells, rewards, reached = buffers.new_cells, buffers.rewards, buffers.reached
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    i, j = pair  # written out for i and j: a loop over the pair costs the loop its speed
    actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
    actions[j] = epsilon_greedy(q[j, cells[j]], exploit, state)
    collisions = ep.step_pair(world, buffers, pair)
    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)
    q_update(q[j], cells[j], actions[j], rewards[j], new_cells[j], reached[j], alpha, gamma)
    return collisions


@njit(cache=True, nogil=True)
def run(world, learning, schedule, q, log, state):
    """One run of ``schedule.episodes`` episodes; learns in ``q`` and writes the binned ``log``."""
    episodes(world, learning, schedule, q, log, state, ep.buffers(world.starts.shape[0]), rules.cell_index(world))


@njit(**ep.LOOP)
def episodes(world, learning, schedule, q, log, state, buffers, index):
    """The episode loop of :func:`run`. While three or more agents act they step through the cell
    index ``index`` (rules.step_indexed): the work of a step grows with its acting agents only."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents = starts.shape[0]
    cells, done, acc = buffers.cells, buffers.done, buffers.acc
    actions, new_cells, rewards, reached = buffers.actions, buffers.new_cells, buffers.rewards, buffers.reached
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            first, second = ep.few_acting(done)
            if second >= 0:  # two agents act (the chapter's case, or the others are in the goal)
                collisions = pair_step(world, learning, q, (first, second), state, buffers)
            elif first >= 0:  # one agent acts
                collisions = lone_step(world, learning, q, first, state, buffers)
            else:
                for i in range(n_agents):
                    if not done[i]:
                        actions[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
                collisions = ep.step_indexed(world, index, buffers)
                for i in range(n_agents):
                    if not done[i]:
                        q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="independent", label="independent Q-learners", kernel=run, table_shape=table_shape,
                  family="chapter", rank=0)

register(LEARNER)
