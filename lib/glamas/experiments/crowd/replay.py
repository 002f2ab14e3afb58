"""2observe's greedy episodes played again with every joint state kept.

The kernels keep what an episode measures, not its path. :func:`replay` plays the episodes of
2observe's kernel (:func:`glamas.learners.two_observe.episodes`, the same kernel, so the same steps
in the same order from the same stream and the same log) and has it keep, besides, each step's
joint state in ``trace`` and count in ``yields`` the agent-steps on which the second level's
coordination replaced an agent's preferred action (Section 5.2: the agent that yields takes one of
its other actions).
"""

import numpy as np
from numba import njit

from glamas.learners import two_observe

@njit(cache=True)
def replay(world, learning, automata, schedule, q, u, need_counts, log, state, kept):
    """:func:`glamas.learners.two_observe.run` with its GLAs frozen (:func:`two_observe.freeze`:
    the run draws no parameters), keeping ``kept = (trace, yields)``: each episode's joint states in
    ``trace`` (episodes, max_steps + 1, agents), row t every agent's cell after t steps
    (two_observe.GONE once in its goal), and the coordination's replaced actions per episode in
    ``yields`` (episodes,)."""
    arrays = (*two_observe.per_run(world), two_observe.group_arrays(world), kept)
    two_observe.episodes(world, learning, automata, schedule, q, u, need_counts, log, state, arrays)


def revisits(trace: np.ndarray, length: int) -> float:
    """The share of an episode's ``length`` steps that end in a joint state the episode was in
    before (rows 1..length of its ``trace`` that equal an earlier row): steps on which the crowd
    as a whole came back rather than moved on."""
    if length == 0:
        return 0.0
    _, first = np.unique(trace[:length + 1], axis=0, return_index=True)
    return float((length + 1 - first.size) / length)
