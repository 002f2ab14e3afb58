"""Plain-Python references of Section 4.2's line-world experiments (lists, math and one random
source): experiment 1's single GLAs with the joint context (glamas.learners.single_gla.learn)
and experiment 2's AND networks (glamas.learners.and_network.learn).

As the gridworld references (``plain_gridworld``), each draws the same random numbers in the same
order as its kernel and does the same arithmetic: on a stream equal to the kernel's it learns the
very same parameters. Each returns (total feedback, final GLA parameters).
"""

from glamas.plain import gla as plain_gla


def act(u, x, config, rnd):
    """Eq. 12 with the experiment's settings: (action, probabilities)."""
    return plain_gla.act(u, x, config.temperature, config.L, rnd)


def update(u, x, action, beta, probs, config):
    """Eq. 13 with the experiment's settings."""
    plain_gla.update(u, x, action, beta, probs, config.learning_rate, config.temperature, config.K, config.L)


def restart(rnd):
    """New uniform positions (x1, x2) on [-1, 1]."""
    x1 = 2.0 * rnd.random() - 1.0
    x2 = 2.0 * rnd.random() - 1.0
    return x1, x2


def best_action(x1, x2, agent):
    """Experiment 1's rewarded action of agent 0 (A) or 1 (B): L = 0, R = 1 (lineworld.best_action)."""
    if abs(x1 - x2) < 0.5:  # region 3: the agents move apart
        a_is_left = x1 < x2
        return (0 if a_is_left else 1) if agent == 0 else (1 if a_is_left else 0)
    return 0 if x1 < x2 else 1


def single_gla_run(config, rnd):
    """One run of experiment 1 with the joint context [x1, x2, 1] (``config``: a SingleGLAConfig)."""
    c = config
    u = [[[c.init_scale * (2.0 * rnd.random() - 1.0) for _ in range(3)] for _ in range(2)] for _ in range(2)]
    total = 0.0
    for _ in range(c.iterations):
        x1, x2 = restart(rnd)
        x = [x1, x2, 1.0]
        (action_a, probs_a), (action_b, probs_b) = act(u[0], x, c, rnd), act(u[1], x, c, rnd)
        beta = 1.0 if action_a == best_action(x1, x2, 0) and action_b == best_action(x1, x2, 1) else 0.0
        update(u[0], x, action_a, beta, probs_a, c)
        update(u[1], x, action_b, beta, probs_b, c)
        total += beta
    return total, u


def inside_parabola(x1, x2, config):
    return x2 >= config.parabola_curvature * x1 * x1 + config.parabola_offset


def and_network_run(config, rnd):
    """One run of experiment 2 (``config``: an ANDNetworkConfig): each agent two 2-action units on
    the joint context, playing L (0) only when both output 1.

    The kernel's units have two more inputs, one per unit, which stay zero (the units are not
    wired to each other): their initial values are drawn here too, so that both sides stay on one
    stream, and never matter. So are the points where the kernel probes P(L) (rejection sampling
    in region I); P(L) itself is not computed, which makes the reference's work a lower bound.
    """
    c = config
    u = [[[[c.init_scale * (2.0 * rnd.random() - 1.0) for _ in range(5)][:3] for _ in range(2)]
          for _ in range(2)] for _ in range(2)]  # agent, unit, unit action, input
    for _ in range(c.probe_points):
        while not inside_parabola(*restart(rnd), c):
            pass
    total = 0.0
    for _ in range(c.iterations):
        x1, x2 = restart(rnd)
        x = [x1, x2, 1.0]
        acted = [[act(unit, x, c, rnd) for unit in agent] for agent in u]
        plays_left = [all(choice == 1 for choice, _ in units) for units in acted]
        inside = inside_parabola(x1, x2, c)
        if inside and plays_left[0] and plays_left[1]:
            beta = c.reward_inside
        elif not inside and not plays_left[0] and not plays_left[1]:
            beta = c.reward_outside
        else:
            beta = c.reward_other
        total += beta
        for agent, units in zip(u, acted):
            for unit, (choice, probs) in zip(agent, units):
                update(unit, x, choice, beta, probs, c)
    return total, u
