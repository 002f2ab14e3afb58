"""The GLA against eq. 12-15, and GLA networks."""

import numpy as np
import pytest

from glamas import gla, rng

PARAMS = gla.GLAParams(learning_rate=0.1, temperature=0.5, K=1.0, L=1.0)


def softmax_eq15(u, x, temperature, bounded):
    """Eq. 15 written directly with NumPy, at the given h(u)."""
    z = bounded(u) @ x / temperature
    e = np.exp(z - z.max())
    return e / e.sum()


def test_probabilities_are_eq15_and_sum_to_one():
    u = np.array([[0.3, -0.2, 0.5], [-0.7, 0.4, 0.1], [2.0, -3.0, 0.0]])
    x = np.array([0.4, -0.9, 1.0])
    probs = gla.GLA(3, 3, PARAMS, u=u).probabilities(x)
    assert probs.sum() == pytest.approx(1.0)
    assert probs == pytest.approx(softmax_eq15(u, x, 0.5, lambda v: np.clip(v, -1, 1)))


def test_printed_bounding_evaluates_at_zero_inside_the_box():
    u = np.array([[0.3, -0.2], [-0.7, 1.5]])
    x = np.array([1.0, 1.0])
    params = gla.GLAParams(learning_rate=0.1, bounding="printed")
    printed_h = lambda v: np.where(np.abs(v) >= 1, np.sign(v), 0.0)  # noqa: E731
    assert gla.GLA(2, 2, params, u=u).probabilities(x) == pytest.approx(softmax_eq15(u, x, 0.5, printed_h))


def test_gradient_of_log_g_matches_finite_differences():
    v = np.array([[0.3, -0.2, 0.5], [-0.7, 0.4, 0.1]])
    x = np.array([0.4, -0.9, 1.0])
    temperature, action = 0.5, 1
    probs = softmax_eq15(v, x, temperature, lambda w: w)
    grad = np.empty_like(v)
    gla.grad_log_g(x, action, probs, temperature, grad)
    eps = 1e-6
    numeric = np.empty_like(v)
    for j in range(v.shape[0]):
        for k in range(v.shape[1]):
            plus, minus = v.copy(), v.copy()
            plus[j, k] += eps
            minus[j, k] -= eps
            numeric[j, k] = (np.log(softmax_eq15(plus, x, temperature, lambda w: w)[action])
                             - np.log(softmax_eq15(minus, x, temperature, lambda w: w)[action])) / (2 * eps)
    assert grad == pytest.approx(numeric, abs=1e-6)


def test_update_is_eq13():
    u = np.array([[0.3, 1.4], [-0.7, -2.0]])
    x = np.array([0.5, 1.0])
    automaton = gla.GLA(2, 2, gla.GLAParams(learning_rate=0.1, temperature=0.5, K=2.0, L=1.0), u=u)
    h = np.clip(u, -1, 1)
    probs = softmax_eq15(u, x, 0.5, lambda v: np.clip(v, -1, 1))
    action, beta = 0, 0.8
    grad = np.outer(np.eye(2)[action] - probs, x) / 0.5
    expected = u + 0.1 * beta * grad + 0.1 * 2.0 * (h - u)
    automaton.update(x, action, beta)
    assert automaton.u == pytest.approx(expected)


def test_bounding_term_only_acts_outside_the_box_with_clip():
    inside = np.array([[0.5, -0.9], [0.0, 0.99]])
    automaton = gla.GLA(2, 2, PARAMS, u=inside)
    automaton.update([1.0, 1.0], 0, beta=0.0)
    assert automaton.u == pytest.approx(inside)
    outside = np.array([[3.0, -1.0], [-5.0, 0.0]])
    automaton = gla.GLA(2, 2, PARAMS, u=outside)
    automaton.update([1.0, 1.0], 0, beta=0.0)
    assert automaton.u == pytest.approx(outside + 0.1 * (np.clip(outside, -1, 1) - outside))


def test_printed_bounding_term_decays_parameters_inside_the_box():
    inside = np.array([[0.5, -0.9], [0.0, 0.99]])
    automaton = gla.GLA(2, 2, gla.GLAParams(learning_rate=0.1, bounding="printed"), u=inside)
    automaton.update([1.0, 1.0], 0, beta=0.0)
    assert automaton.u == pytest.approx(0.9 * inside)


def test_a_gla_learns_a_linearly_separable_mapping():
    """Two contexts with different best actions: the GLA must come to prefer each one's best."""
    automaton = gla.GLA(2, 2, gla.GLAParams(learning_rate=0.05))
    state = rng.run_states(3, 1)[0]
    contexts = [np.array([-1.0, 1.0]), np.array([1.0, 1.0])]
    for t in range(4000):
        x = contexts[t % 2]
        action = automaton.act(x, state)
        automaton.update(x, action, beta=1.0 if action == t % 2 else 0.0)
    assert automaton.probabilities(contexts[0])[0] > 0.9
    assert automaton.probabilities(contexts[1])[1] > 0.9


@pytest.mark.parametrize("field, value, message", [
    ("learning_rate", 0.0, "learning_rate must be a finite number > 0"),
    ("temperature", -1.0, "temperature must be a finite number > 0"),
    ("K", float("nan"), "K must be a finite number > 0"),
    ("L", 0, "L must be a finite number > 0"),
    ("bounding", "tanh", "bounding must be one of"),
])
def test_bad_parameters_are_rejected(field, value, message):
    kwargs = {"learning_rate": 0.01, field: value}
    with pytest.raises(ValueError, match=message):
        gla.GLAParams(**kwargs)


def test_bad_shapes_are_rejected():
    with pytest.raises(ValueError, match="n_actions >= 2"):
        gla.GLA(1, 3, PARAMS)
    with pytest.raises(ValueError, match=r"u must have shape \(2, 3\)"):
        gla.GLA(2, 3, PARAMS, u=np.zeros((3, 2)))
    with pytest.raises(ValueError, match=r"context must have shape \(3,\)"):
        gla.GLA(2, 3, PARAMS).probabilities([1.0, 2.0])
    with pytest.raises(TypeError, match="GLAParams"):
        gla.GLA(2, 3, {"learning_rate": 0.1})


def _run_network(network, params, context):
    n = network.n_units
    inputs, probs = np.zeros((n, network.n_inputs)), np.zeros((n, max(network.unit_actions)))
    chosen = np.zeros(n, dtype=np.int64)
    state = rng.run_states(0, 1)[0]
    automaton = gla.GLAParams(learning_rate=0.1, temperature=0.5, L=1.0).settings()
    action = gla.network_act(params, np.asarray(context, float), network.arrays(), automaton,
                             inputs, probs, chosen, state)
    return action, chosen, inputs


def test_and_network_plays_L_only_when_both_units_output_1():
    network = gla.and_network(n_context=1)
    for first, second, expected in [(1, 1, 0), (1, 0, 1), (0, 1, 1), (0, 0, 1)]:
        params = np.zeros((2, 2, network.n_inputs))
        params[0, first, 0] = params[1, second, 0] = 1.0  # a context of 100 makes these certain
        action, chosen, _ = _run_network(network, params, [100.0])
        assert (chosen.tolist(), action) == ([first, second], expected)


def test_network_units_read_the_earlier_units_they_are_wired_to():
    network = gla.GLANetwork(n_context=1, unit_actions=(2, 2), output_table=(0, 1, 2, 3),
                             wiring=((False, False), (True, False)))
    params = np.zeros((2, 2, network.n_inputs))
    params[0, 1, 0] = 1.0
    action, chosen, inputs = _run_network(network, params, [100.0])
    assert inputs[1].tolist() == [100.0, float(chosen[0]), 0.0]
    assert inputs[0].tolist() == [100.0, 0.0, 0.0]


def test_network_structure_is_checked():
    with pytest.raises(ValueError, match="strictly lower-triangular"):
        gla.GLANetwork(n_context=1, unit_actions=(2, 2), output_table=(0, 1, 1, 0),
                       wiring=((False, True), (False, False)))
    with pytest.raises(ValueError, match="one entry per joint unit action: 4"):
        gla.GLANetwork(n_context=1, unit_actions=(2, 2), output_table=(0, 1))


@pytest.mark.parametrize("temperature", [0.5, 0.3])
@pytest.mark.parametrize("bounding", ["clip", "printed"])
def test_act_two_is_act_for_two_actions(bounding, temperature):
    """act_two (the branch-free act of 2observe's GLAs) gives act's probabilities and draw, bit for
    bit: on ties (exp(0) = 1 exactly), on either action the likelier, inside and outside the box."""
    draws = np.random.default_rng(0)
    mode = gla.BOUNDING_MODES[bounding]
    cases = [np.zeros((2, 2)), np.array([[0.3, 0.3], [0.3, 0.3]])] + [draws.uniform(-3, 3, (2, 2)) for _ in range(200)]
    for u in cases:
        x = np.array([draws.integers(0, 9), 1.0])
        state_general, state_two = rng.run_states(7, 1)[0], rng.run_states(7, 1)[0]
        probs_general, probs_two = np.empty(2), np.empty(2)
        for _ in range(5):
            action = gla.act(u, x, temperature, 2.0, mode, probs_general, state_general)
            assert gla.act_two(u, x, temperature, 2.0, mode, probs_two, state_two) == action
            assert probs_two.tobytes() == probs_general.tobytes()
