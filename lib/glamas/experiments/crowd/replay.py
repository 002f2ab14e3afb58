"""2observe's greedy episodes played again with every joint state kept.

The kernels keep what an episode measures, not its path. :func:`replay` plays the episodes of
2observe's kernel (:func:`glamas.learners.two_observe.episodes`) step for step, the same steps in
the same order from the same stream, so that on the same inputs it writes the same log; besides, it
keeps each step's joint state in ``trace`` and counts in ``yields`` the agent-steps on which the
second level's coordination replaced an agent's preferred action (Section 5.2: the agent that
yields takes one of its other actions).
"""

import numpy as np
from numba import njit

from glamas.learners import episode as ep
from glamas.learners import two_observe
from glamas.learners.independent import lone_step

GONE = -1
"""The cell a trace gives an agent in its goal: it has left the map (glamas.gridworld.rules)."""


@njit(cache=True)
def replay(world, learning, automata, schedule, q, u, need_counts, log, state, kept):
    """:func:`glamas.learners.two_observe.run` with its GLAs frozen (:func:`two_observe.freeze`:
    the run draws no parameters), step for step as :func:`two_observe.episodes` plays it, keeping
    ``kept = (trace, yields)``: each episode's joint states in ``trace`` (episodes, max_steps + 1,
    agents), row t every agent's cell after t steps (GONE once in its goal), and the coordination's
    replaced actions per episode in ``yields`` (episodes,)."""
    trace, yields = kept
    arrays = (*two_observe.per_run(world), two_observe.group_arrays(world))
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = arrays[1]
    preferred = arrays[2][1]
    for episode in range(schedule.episodes):
        ep.start_episode(world.starts, cells, done, acc)
        t = 0
        _keep(trace[episode, t], cells, done)
        while t < schedule.max_steps and not ep.all_done(done):
            first, second = ep.few_acting(done)
            if second >= 0:
                collisions = two_observe.pair_step(world, learning, automata, q, u, need_counts, (first, second),
                                                   state, arrays)
                yields[episode] += _replaced(done, preferred, actions)
            elif first >= 0:
                collisions = lone_step(world, learning, q, first, state, arrays[1])
            else:
                collisions = two_observe.group_step(world, learning, automata, q, u, need_counts, state, arrays)
                yields[episode] += _replaced(done, preferred, actions)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
            _keep(trace[episode, t], cells, done)
        ep.end_episode(log, episode, schedule.edges, acc, t, done)


@njit(cache=True, inline="always")
def _keep(row, cells, done):
    for i in range(cells.shape[0]):
        row[i] = GONE if done[i] else cells[i]


@njit(cache=True, inline="always")
def _replaced(done, preferred, actions):
    """The acting agents whose action is not the one they preferred (the coordination made them yield)."""
    count = 0
    for i in range(done.shape[0]):
        count += (not done[i]) and actions[i] != preferred[i]
    return count


def revisits(trace: np.ndarray, length: int) -> float:
    """The share of an episode's ``length`` steps that end in a joint state the episode was in
    before (rows 1..length of its ``trace`` that equal an earlier row): steps on which the crowd
    as a whole came back rather than moved on."""
    if length == 0:
        return 0.0
    _, first = np.unique(trace[:length + 1], axis=0, return_index=True)
    return float((length + 1 - first.size) / length)
