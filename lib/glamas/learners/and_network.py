"""Experiment 2's learners (Section 4.2, Fig. 7): each agent an AND network of two 2-action GLAs
(:func:`glamas.gla.and_network`) on the joint context [x1, x2, 1]; the agent plays L only when
both units output 1. The experiment is :mod:`glamas.experiments.and_network`."""

from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import gla, lineworld, rng

CONTEXT_LENGTH = 3  # the joint context [x1, x2, 1]
NETWORK = gla.and_network(CONTEXT_LENGTH)


@njit(cache=True)
def left_probability(agent_params, context, temperature, L, mode, inputs, probs):
    """P(agent plays L) = product over its two units of P(unit outputs 1) (eq. 15): the units
    of the AND network are not wired to each other, so they act independently."""
    p = 1.0
    for k in range(agent_params.shape[0]):
        for i in range(context.shape[0]):
            inputs[k, i] = context[i]
        for j in range(context.shape[0], inputs.shape[1]):
            inputs[k, j] = 0.0
        gla.boltzmann(agent_params[k], inputs[k], temperature, L, mode, probs[k])
        p *= probs[k, 1]
    return p


@njit(cache=True)
def probe_mean(params, probes, temperature, L, mode, inputs, probs, context, out):
    """out[agent] = P(L) of the agent averaged over the probe points."""
    for agent in range(2):
        total = 0.0
        for i in range(probes.shape[0]):
            context[0], context[1], context[2] = probes[i, 0], probes[i, 1], 1.0
            total += left_probability(params[agent], context, temperature, L, mode,
                                      inputs[agent], probs[agent])
        out[agent] = total / probes.shape[0]


class Task(NamedTuple):
    """Experiment 2's regions and feedback (Sec. 4.2) as the compiled kernel takes them."""

    curvature: float
    """Region I is x2 >= curvature * x1**2 + offset."""
    offset: float
    """See curvature."""
    reward_inside: float
    """Feedback for (L, L) in region I."""
    reward_outside: float
    """Feedback for (R, R) in region II."""
    reward_other: float
    """Feedback for every other joint action."""


@njit(cache=True, nogil=True)
def learn(iterations, automaton, init_scale, stream, task, network, probes, params, prob_left, state):
    """One run of experiment 2: both AND-network agents act (eq. 12, 15) and learn (eq. 13).

    ``automaton`` is the :class:`glamas.gla.Settings` every unit shares; ``stream`` > 0 reseeds
    the run's generator after the initial parameters are drawn (:func:`glamas.rng.reseed`), so
    the run keeps them and meets other probes, positions and actions; ``task`` is the
    :class:`Task`, ``network`` the agents' :class:`glamas.gla.NetworkArrays`. ``probes`` (n, 2)
    is filled with uniform points of region I, ``params`` with the initial and then the learned
    unit parameters, ``prob_left`` with Fig. 7b's curve.
    """
    for agent in range(2):
        for k in range(params.shape[1]):
            for a in range(params.shape[2]):
                for i in range(params.shape[3]):
                    params[agent, k, a, i] = init_scale * (2.0 * rng.uniform(state) - 1.0)
    if stream > 0:
        rng.reseed(state, stream)
    for i in range(probes.shape[0]):  # rejection sampling: uniform in region I
        x1, x2 = lineworld.restart(state)
        while not lineworld.inside_parabola(x1, x2, task.curvature, task.offset):
            x1, x2 = lineworld.restart(state)
        probes[i, 0], probes[i, 1] = x1, x2
    n_units, n_inputs = params.shape[1], params.shape[3]
    units = (np.zeros((2, n_units, n_inputs)), np.zeros((2, n_units, params.shape[2])),
             np.zeros((2, n_units), dtype=np.int64))
    iterate(iterations, automaton, task, network, probes, params, prob_left, state, np.empty(CONTEXT_LENGTH), units)


@njit(cache=True, nogil=True, _nrt=False)
def iterate(iterations, automaton, task, network, probes, params, prob_left, state, context, units):
    """The learning loop of :func:`learn`, compiled without reference counting as the gridworld
    learners' episode loops are (glamas.learners.episode.LOOP); ``units``: each agent's unit
    inputs, probabilities and chosen actions."""
    temperature, L, mode = automaton.temperature, automaton.L, automaton.bounding
    curvature, offset = task.curvature, task.offset
    reward_inside, reward_outside, reward_other = task.reward_inside, task.reward_outside, task.reward_other
    inputs, probs, chosen = units
    n_points = prob_left.shape[0]
    point = 0
    next_record = 0  # the curve starts at the initial policy, iteration 0
    for t in range(iterations + 1):
        if t == next_record:
            probe_mean(params, probes, temperature, L, mode, inputs, probs, context,
                        prob_left[point])
            point += 1
            next_record = point * iterations // (n_points - 1) if n_points > 1 else iterations + 1
        if t == iterations:
            break
        x1, x2 = lineworld.restart(state)
        context[0], context[1], context[2] = x1, x2, 1.0
        action_a = gla.network_act(params[0], context, network, automaton, inputs[0], probs[0], chosen[0], state)
        action_b = gla.network_act(params[1], context, network, automaton, inputs[1], probs[1], chosen[1], state)
        inside = lineworld.inside_parabola(x1, x2, curvature, offset)
        beta = lineworld.parabola_reward(inside, action_a, action_b, reward_inside,
                                         reward_outside, reward_other)
        for agent in range(2):
            gla.network_update(params[agent], network, beta, automaton, inputs[agent], probs[agent], chosen[agent])


def kernel_inputs(config) -> tuple:
    """The arguments of :func:`learn` before its outputs and state, for ``config``
    (:class:`glamas.experiments.and_network.ANDNetworkConfig`)."""
    c = config
    task = Task(float(c.parabola_curvature), float(c.parabola_offset), float(c.reward_inside),
                float(c.reward_outside), float(c.reward_other))
    return c.iterations, c.gla_params().settings(), float(c.init_scale), int(c.stream), task, NETWORK.arrays()
