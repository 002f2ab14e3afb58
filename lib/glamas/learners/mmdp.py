"""The MMDP learner (Sections 3.1 and 5.3): one central Q-learner over the joint cells and the joint
actions (625 x 16 on TunnelToGoal) that learns from the single shared reward.

Every step, with s the joint cell: select the joint action a = (a_1, a_2) epsilon-greedily from
Q(s, .) over the 16 joint actions; the agents move together; the shared reward R is the agents'
penalties summed, plus +100 when the last agent enters its goal (Sec. 5.3: "when both agents reach
the goal", :func:`glamas.gridworld.rules.shared_reward`); eq. 11 on the joint table,
Q(s, a) <- (1 - alpha) Q(s, a) + alpha [R + gamma max_a' Q(s', a')], with no future value once every
agent is in.

Plain-Python reference: ``mmdp`` and ``shared_reward`` in ``lib/glamas/plain/gridworld.py``."""

from numba import njit

from glamas.gridworld import rules
from glamas.gridworld.joint import joint_index, split_index
from glamas.learners import episode as ep
from glamas.learners.registry import register
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, q_update


def table_shape(n_cells: int, n_agents: int) -> tuple:
    """A single (joint cells x joint actions) table."""
    return 1, n_cells ** n_agents, rules.N_ACTIONS ** n_agents


@njit(cache=True, inline="always")
def split_joint_action(joint, actions):
    """Each agent's component of a joint action (agent 0 most significant, base 4)."""
    split_index(joint, rules.N_ACTIONS, actions)


@njit(cache=True, nogil=True)
def run(world, learning, schedule, q, log, state):
    """One run of ``schedule.episodes`` episodes; learns in ``q[0]`` and writes the binned ``log``.

    An agent in the goal no longer acts, so its component of the chosen joint action is ignored.
    """
    episodes(world, learning, schedule, q, log, state, ep.buffers(world.starts.shape[0]))


@njit(**ep.LOOP)
def episodes(world, learning, schedule, q, log, state, buffers):
    """The episode loop of :func:`run`."""
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    starts, edges, max_steps = world.starts, schedule.edges, schedule.max_steps
    n_agents, n_cells = starts.shape[0], world.next_cell.shape[0]
    table = q[0]
    cells, done, acc = buffers.cells, buffers.done, buffers.acc
    actions, new_cells, rewards, reached = buffers.actions, buffers.new_cells, buffers.rewards, buffers.reached
    for episode in range(schedule.episodes):
        ep.start_episode(starts, cells, done, acc)
        t = 0
        while t < max_steps and not ep.all_done(done):
            s = joint_index(cells, n_cells)
            joint = epsilon_greedy(table[s], exploit, state)
            split_joint_action(joint, actions)
            if n_agents == 2:  # the chapter's case, on the rules' fast path
                collisions = ep.step_pair(world, buffers, (0, 1))
            else:
                collisions = ep.step(world, buffers)
            finished = True
            for i in range(n_agents):
                finished = finished and (done[i] or reached[i])
            shared = rules.shared_reward(world.payoffs, rewards, reached, finished)
            q_update(table, s, joint, shared, joint_index(new_cells, n_cells), finished, alpha, gamma)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, edges, acc, t, done)


LEARNER = Learner(name="mmdp", label="MMDP learner", kernel=run, table_shape=table_shape, joint_tables=True,
                  family="chapter", rank=2)

register(LEARNER)
