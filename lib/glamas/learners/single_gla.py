"""Experiment 1's learners (Section 4.2): one 2-action GLA per agent in the line world, both
seeing a context made from the joint position (:mod:`glamas.lineworld`), acting with eq. 15 and
learning with eq. 13-14 from a common 0/1 feedback. The experiment is
:mod:`glamas.experiments.single_gla`."""

import numpy as np
from numba import njit

from glamas import gla, lineworld, rng


@njit(cache=True, nogil=True)
def learn(encoding, region3, iterations, automaton, init_scale, checkpoint_at, params, reward, checkpoints, state):
    """One run of experiment 1: the loop of Section 4.2 with eq. 12-15 for both agents.

    ``region3`` is the reading of region 3's reward (lineworld.REGION3_REWARDS), ``automaton``
    the :class:`glamas.gla.Settings` both GLAs share; ``params`` (2, 2, n) is
    filled with the initial and then the learned parameters, ``reward`` with the average feedback
    of each of its len(reward) windows, ``checkpoints`` (len(checkpoint_at), 2, 2, n) with the
    parameters after checkpoint_at[c] iterations (sorted, in [0, iterations]). Recording draws
    nothing: the streams, rewards and parameters are the same with or without checkpoints.
    """
    n_inputs = params.shape[2]
    for agent in range(2):
        for action in range(2):
            for k in range(n_inputs):
                params[agent, action, k] = init_scale * (2.0 * rng.uniform(state) - 1.0)
    iterate((encoding, region3), iterations, automaton, checkpoint_at, params, reward, checkpoints, state,
            np.empty((2, n_inputs)), np.empty((2, 2)))


@njit(cache=True, nogil=True, _nrt=False)
def iterate(task, iterations, automaton, checkpoint_at, params, reward, checkpoints, state, contexts, probs):
    """The learning loop of :func:`learn`, compiled without reference counting as the gridworld
    learners' episode loops are (glamas.learners.episode.LOOP); ``task`` is :func:`learn`'s
    (encoding, region3), ``contexts`` and ``probs`` hold each agent's context and action
    probabilities."""
    encoding, region3 = task
    learning_rate, temperature, K = automaton.learning_rate, automaton.temperature, automaton.K
    L, mode = automaton.L, automaton.bounding
    context_a, context_b, probs_a, probs_b = contexts[0], contexts[1], probs[0], probs[1]
    u_a, u_b = params[0], params[1]
    n_points = reward.shape[0]
    point, window_start, window_sum = 0, 0, 0.0
    window_end = iterations // n_points
    recorded = 0
    for t in range(iterations):
        recorded = record(params, t, checkpoint_at, checkpoints, recorded)
        x1, x2 = lineworld.restart(state)
        lineworld.context(encoding, lineworld.AGENT_A, x1, x2, context_a)
        lineworld.context(encoding, lineworld.AGENT_B, x1, x2, context_b)
        action_a = gla.act(u_a, context_a, temperature, L, mode, probs_a, state)
        action_b = gla.act(u_b, context_b, temperature, L, mode, probs_b, state)
        beta = lineworld.regions_reward(x1, x2, action_a, action_b, region3)
        gla.update(u_a, context_a, action_a, beta, learning_rate, temperature, K, L, mode, probs_a)
        gla.update(u_b, context_b, action_b, beta, learning_rate, temperature, K, L, mode, probs_b)
        window_sum += beta
        if t + 1 == window_end:
            reward[point] = window_sum / (window_end - window_start)
            point += 1
            window_start, window_sum = window_end, 0.0
            window_end = (point + 1) * iterations // n_points
    record(params, iterations, checkpoint_at, checkpoints, recorded)


@njit(cache=True, nogil=True, _nrt=False)
def record(params, done, checkpoint_at, checkpoints, recorded):
    """Copy ``params`` into every checkpoint due after ``done`` iterations, from number
    ``recorded`` on; returns how many checkpoints are recorded now."""
    while recorded < checkpoint_at.shape[0] and checkpoint_at[recorded] == done:
        for agent in range(params.shape[0]):
            for action in range(params.shape[1]):
                for k in range(params.shape[2]):
                    checkpoints[recorded, agent, action, k] = params[agent, action, k]
        recorded += 1
    return recorded


NO_CHECKPOINTS = np.zeros(0, dtype=np.int64)
"""The checkpoints of a run that records none (Fig. 5)."""


def kernel_inputs(config, checkpoint_at: np.ndarray = NO_CHECKPOINTS) -> tuple:
    """The arguments of :func:`learn` before its outputs and state, for ``config``
    (:class:`glamas.experiments.single_gla.SingleGLAConfig`) and the iterations after which
    the parameters are recorded."""
    encoding, region3 = lineworld.encoding_code(config.context), lineworld.region3_code(config.region3_reward)
    return (encoding, region3, config.iterations, config.gla_params().settings(), float(config.init_scale),
            np.asarray(checkpoint_at, dtype=np.int64))
