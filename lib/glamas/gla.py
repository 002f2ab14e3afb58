"""Generalized learning automata (chapter Section 4.1, eq. 12-15) and feed-forward networks of them.

A GLA with ``r`` actions keeps one parameter vector ``u_i`` per action, stored as the rows of
``u`` (shape ``r x n_inputs``). Given a context ``x`` it acts with the Boltzmann probabilities of
eq. 15 and learns with the bounded REINFORCE rule of eq. 13-14.

The compiled functions take plain arrays and scalars so that simulation kernels can call them
in their inner loops (inlined there: ``inline="always"``); :class:`GLA` and :class:`GLANetwork`
are the checked, user-facing wrappers.
"""

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import rng
from glamas.errors import UserError

BOUND_CLIP = 0
BOUND_PRINTED = 1
BOUNDING_MODES = {"clip": BOUND_CLIP, "printed": BOUND_PRINTED}


@dataclass(frozen=True)
class GLAParams:
    """Learning parameters of a GLA (eq. 13-15)."""

    learning_rate: float
    """lambda in eq. 13: step size of both the gradient and the bounding term."""
    temperature: float = 0.5
    """T in eq. 15: Boltzmann temperature; lower is greedier."""
    K: float = 1.0
    """K_i in eq. 13: strength of the term that pulls u back towards h(u); the same for every i."""
    L: float = 1.0
    """L_i in eq. 14: half-width of the box [-L, L] that h bounds each parameter to."""
    bounding: str = "clip"
    """h of eq. 14: 'clip' (h(eta) = eta inside the box, Phansalkar and Thathachar's original)
    or 'printed' (h(eta) = 0 inside the box, as eq. 14 is printed). See the README."""

    def __post_init__(self):
        for name in ("learning_rate", "temperature", "K", "L"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not np.isfinite(value) or value <= 0:
                raise UserError(f"GLA {name} must be a finite number > 0, got {value!r}")
        if self.bounding not in BOUNDING_MODES:
            raise UserError(
                f"GLA bounding must be one of {sorted(BOUNDING_MODES)}, got {self.bounding!r}"
            )

    @property
    def bounding_code(self) -> int:
        return BOUNDING_MODES[self.bounding]

    def settings(self) -> "Settings":
        """These parameters as the compiled kernels take them."""
        return Settings(float(self.learning_rate), float(self.temperature), float(self.K), float(self.L),
                        self.bounding_code)


class Settings(NamedTuple):
    """The constants of eq. 13-15 shared by every GLA of a compiled kernel (a :class:`GLAParams`
    with h as its code): one argument instead of five, unpacked once at the top of the kernel."""

    learning_rate: float
    """lambda of eq. 13."""
    temperature: float
    """T of eq. 15."""
    K: float
    """K_i of eq. 13."""
    L: float
    """L_i of eq. 14."""
    bounding: int
    """h of eq. 14: BOUND_CLIP or BOUND_PRINTED."""


@njit(cache=True, inline="always")
def bound(eta, L, mode):
    """h_i of eq. 14: L above the box, -L below it; inside it eta ('clip') or 0 ('printed')."""
    if eta >= L:
        return L
    if eta <= -L:
        return -L
    return eta if mode == BOUND_CLIP else 0.0


@njit(cache=True, inline="always")
def logit(u, x, temperature, L, mode, i):
    """x.h(u_i) / T, the exponent of action i in eq. 15."""
    z = 0.0
    for k in range(u.shape[1]):
        z += x[k] * bound(u[i, k], L, mode)
    return z / temperature


@njit(cache=True, inline="always")
def boltzmann(u, x, temperature, L, mode, probs):
    """Eq. 15 at h(u): probs[i] = exp(x.h(u_i)/T) / sum_j exp(x.h(u_j)/T), written into probs."""
    n_actions = u.shape[0]
    largest = -np.inf
    for i in range(n_actions):
        probs[i] = logit(u, x, temperature, L, mode, i)
        largest = max(largest, probs[i])
    total = 0.0
    for i in range(n_actions):
        shifted = probs[i] - largest  # shifted for overflow safety; the ratio is unchanged
        probs[i] = 1.0 if shifted == 0.0 else np.exp(shifted)  # exp(0) is 1 exactly: no exp for the largest
        total += probs[i]
    for i in range(n_actions):
        probs[i] /= total


@njit(cache=True, inline="always")
def act(u, x, temperature, L, mode, probs, state):
    """Eq. 12: draw an action with the probabilities of eq. 15 (left in probs for the update)."""
    boltzmann(u, x, temperature, L, mode, probs)
    return rng.categorical(state, probs)


@njit(cache=True, inline="always")
def act_two(u, x, temperature, L, mode, probs, state):
    """:func:`act` for a GLA of two actions (2observe's): the same probabilities, left in probs,
    and the same draw, bit for bit, written without a branch on which action is the likelier.
    While a GLA is undecided that branch goes either way at random, and the processor mispredicts
    it: with act_two instead of act, 2observe's steps took 6 % (128 agents) to 10 % (2 agents) less
    time (benchmarks/bench_many_agents.py)."""
    z_0, z_1 = logit(u, x, temperature, L, mode, 0), logit(u, x, temperature, L, mode, 1)
    first_larger = z_0 >= z_1
    largest, other = (z_0, z_1) if first_larger else (z_1, z_0)
    e = np.exp(other - largest)  # exp(0) is 1 exactly: as boltzmann's 1.0 for the largest when they tie
    p_0, p_1 = (1.0, e) if first_larger else (e, 1.0)
    total = p_0 + p_1
    probs[0], probs[1] = p_0 / total, p_1 / total
    return 0 if rng.uniform(state) < probs[0] else 1


@njit(cache=True, inline="always")
def grad_log_g(x, action, probs, temperature, grad):
    """d ln g(x, a, v) / d v_jk = (x_k / T) (1[j == a] - g(x, a_j, v)), with probs = g(x, ., v)."""
    for j in range(grad.shape[0]):
        indicator = 1.0 if j == action else 0.0
        for k in range(grad.shape[1]):
            grad[j, k] = x[k] / temperature * (indicator - probs[j])


@njit(cache=True, inline="always")
def update(u, x, action, beta, learning_rate, temperature, K, L, mode, probs):
    """Eq. 13 in place: u += lambda beta dln g/du (x, a, h(u)) + lambda K (h(u) - u).

    ``probs`` must be eq. 15 at the current h(u), as left by :func:`act`; the gradient is the
    closed form of :func:`grad_log_g`, inlined to avoid a temporary array.
    """
    for j in range(u.shape[0]):
        indicator = 1.0 if j == action else 0.0
        for k in range(u.shape[1]):
            gradient = x[k] / temperature * (indicator - probs[j])
            h = bound(u[j, k], L, mode)
            u[j, k] += learning_rate * beta * gradient + learning_rate * K * (h - u[j, k])


class GLA:
    """A single generalized learning automaton: ``r`` actions, contexts of length ``n_inputs``."""

    def __init__(self, n_actions: int, n_inputs: int, params: GLAParams, u=None):
        if not isinstance(params, GLAParams):
            raise TypeError(f"params must be a GLAParams, got {type(params).__name__}")
        if not isinstance(n_actions, (int, np.integer)) or n_actions < 2:
            raise UserError(f"a GLA needs n_actions >= 2, got {n_actions!r}")
        if not isinstance(n_inputs, (int, np.integer)) or n_inputs < 1:
            raise UserError(f"a GLA needs n_inputs >= 1, got {n_inputs!r}")
        shape = (int(n_actions), int(n_inputs))
        self.u = np.zeros(shape) if u is None else np.array(u, dtype=np.float64)
        if self.u.shape != shape:
            raise UserError(f"u must have shape {shape} (actions x inputs), got {self.u.shape}")
        self.params = params
        self._probs = np.empty(shape[0])

    def _context(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=np.float64)
        if x.shape != (self.u.shape[1],):
            raise UserError(f"context must have shape ({self.u.shape[1]},), got {x.shape}")
        return x

    def probabilities(self, x) -> np.ndarray:
        """Eq. 15 for context x."""
        p = self.params
        boltzmann(self.u, self._context(x), p.temperature, p.L, p.bounding_code, self._probs)
        return self._probs.copy()

    def act(self, x, state) -> int:
        """Draw an action for context x with the run's generator state (see glamas.rng)."""
        p = self.params
        return act(self.u, self._context(x), p.temperature, p.L, p.bounding_code, self._probs, state)

    def update(self, x, action: int, beta: float) -> None:
        """Eq. 13 for the action taken in context x and its feedback beta."""
        if not 0 <= action < self.u.shape[0]:
            raise UserError(f"action must be in [0, {self.u.shape[0]}), got {action!r}")
        p, x = self.params, self._context(x)
        boltzmann(self.u, x, p.temperature, p.L, p.bounding_code, self._probs)
        update(self.u, x, action, float(beta), p.learning_rate, p.temperature, p.K, p.L,
               p.bounding_code, self._probs)


@dataclass(frozen=True)
class GLANetwork:
    """The structure of a feed-forward network of GLAs that acts as one agent (Section 4.1).

    Unit ``k`` sees the shared context followed by the actions of the earlier units ``j < k`` it
    is wired to (``wiring[k][j]``); the joint action of all units, read as a mixed-radix number
    (unit 0 most significant), indexes ``output_table`` to give the agent's action. Every unit
    learns from the agent's feedback.
    """

    n_context: int
    """Length of the context vector given to every unit."""
    unit_actions: tuple
    """Number of actions of each unit, in feed-forward order."""
    output_table: tuple
    """Agent action for each joint unit action (mixed radix, unit 0 most significant)."""
    wiring: tuple = field(default=())
    """wiring[k][j] is True when unit k takes unit j's action (j < k) as an extra input."""

    def __post_init__(self):
        n_units = len(self.unit_actions)
        if self.n_context < 1 or n_units < 1 or min(self.unit_actions) < 2:
            raise UserError("a GLA network needs n_context >= 1 and units with >= 2 actions each")
        wiring = np.zeros((n_units, n_units), dtype=bool) if not self.wiring else np.array(self.wiring, dtype=bool)
        if wiring.shape != (n_units, n_units) or np.triu(wiring).any():
            raise UserError(
                f"wiring must be {n_units}x{n_units} and strictly lower-triangular "
                "(a unit may only read earlier units: the feed-forward condition)"
            )
        if len(self.output_table) != int(np.prod(self.unit_actions)):
            raise UserError(
                f"output_table needs one entry per joint unit action: {int(np.prod(self.unit_actions))}, "
                f"got {len(self.output_table)}"
            )

    @property
    def n_units(self) -> int:
        return len(self.unit_actions)

    @property
    def n_inputs(self) -> int:
        """Input length of every unit: the context plus one slot per unit (zero when unwired)."""
        return self.n_context + self.n_units

    def arrays(self) -> "NetworkArrays":
        """The structure as arrays for the compiled kernels."""
        unit_actions = np.array(self.unit_actions, dtype=np.int64)
        wiring = np.zeros((self.n_units, self.n_units), dtype=np.bool_)
        if self.wiring:
            wiring[:] = np.array(self.wiring, dtype=bool)
        radix = np.ones(self.n_units, dtype=np.int64)
        for k in range(self.n_units - 2, -1, -1):
            radix[k] = radix[k + 1] * unit_actions[k + 1]
        return NetworkArrays(unit_actions, wiring, np.array(self.output_table, dtype=np.int64), radix)


class NetworkArrays(NamedTuple):
    """A :class:`GLANetwork` as the compiled kernels take it."""

    unit_actions: np.ndarray
    """int (units,): the number of actions of each unit."""
    wiring: np.ndarray
    """bool (units, units): wiring[k, j] when unit k reads unit j's action."""
    output_table: np.ndarray
    """int (joint unit actions,): the agent's action for each joint unit action."""
    radix: np.ndarray
    """int (units,): the place value of each unit's action in the joint unit action."""


def and_network(n_context: int) -> GLANetwork:
    """Section 4.2's agent: two 2-action GLAs (actions 0/1); the agent plays its first action
    (L = 0) only when both output 1, and its second (R = 1) otherwise."""
    return GLANetwork(n_context=n_context, unit_actions=(2, 2), output_table=(1, 1, 1, 0))


@njit(cache=True, inline="always")
def network_act(params, context, network, automaton, inputs, probs, chosen, state):
    """One forward pass: each unit acts on its input (eq. 12); returns the agent's action.

    params has shape (units, max actions, n_context + units); ``network`` is the
    :class:`NetworkArrays`, ``automaton`` the :class:`Settings` every unit shares; inputs, probs
    and chosen are per-unit buffers kept for :func:`network_update`.
    """
    unit_actions, wiring, output_table, radix = network
    temperature, L, mode = automaton.temperature, automaton.L, automaton.bounding
    n_units = unit_actions.shape[0]
    n_context = context.shape[0]
    joint = 0
    for k in range(n_units):
        for i in range(n_context):
            inputs[k, i] = context[i]
        for j in range(n_units):
            inputs[k, n_context + j] = chosen[j] if (j < k and wiring[k, j]) else 0.0
        r = unit_actions[k]
        chosen[k] = act(params[k, :r], inputs[k], temperature, L, mode, probs[k, :r], state)
        joint += chosen[k] * radix[k]
    return output_table[joint]


@njit(cache=True, inline="always")
def network_update(params, network, beta, automaton, inputs, probs, chosen):
    """Eq. 13 for every unit, each with its own input and action and the agent's feedback."""
    learning_rate, temperature, K, L, mode = automaton
    unit_actions = network.unit_actions
    for k in range(unit_actions.shape[0]):
        r = unit_actions[k]
        update(params[k, :r], inputs[k], chosen[k], beta, learning_rate, temperature, K, L,
               mode, probs[k, :r])
