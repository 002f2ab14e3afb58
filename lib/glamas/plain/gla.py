"""Generalized learning automata (Section 4.1, eq. 12-15) in plain Python: the arithmetic of
glamas.gla in its order, with 'clip' bounding (the experiments' setting)."""

import math


def bound(eta, L):
    """h of eq. 14, 'clip'."""
    return max(-L, min(L, eta))


def added(values) -> float:
    """The sum of ``values`` added left to right, as the kernels add (the built-in ``sum`` of floats
    compensates its rounding from Python 3.12 on, and so gives other bits)."""
    total = 0.0
    for value in values:
        total += value
    return total


def probabilities(u, x, temperature, L):
    """Eq. 15 at h(u): one probability per row (action) of u."""
    z = [added(xk * bound(v, L) for xk, v in zip(x, row)) / temperature for row in u]
    top = max(z)
    e = [1.0 if v == top else math.exp(v - top) for v in z]  # exp(0) is 1 exactly, as glamas.gla.boltzmann
    total = added(e)
    return [v / total for v in e]


def act(u, x, temperature, L, rnd):
    """Eq. 12 for a 2-action GLA: (action, the probabilities it acted with), one uniform draw."""
    probs = probabilities(u, x, temperature, L)
    return (0 if rnd.random() < probs[0] else 1), probs


def update(u, x, action, beta, probs, learning_rate, temperature, K, L):
    """Eq. 13 in place, with the probabilities ``probs`` the GLA acted with."""
    for j, row in enumerate(u):
        indicator = 1.0 if j == action else 0.0
        for k in range(len(row)):
            gradient = x[k] / temperature * (indicator - probs[j])
            h = bound(row[k], L)
            row[k] += learning_rate * beta * gradient + learning_rate * K * (h - row[k])
