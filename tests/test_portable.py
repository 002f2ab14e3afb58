"""`glamas.portable`: within a unit in the last place of numpy's functions, exact where they are, and
the same bits on every machine (a digest of its values on fixed inputs, the same everywhere since
only IEEE arithmetic makes them)."""

import hashlib

import numpy as np
import pytest

from glamas import portable
from glamas.learners import episode as ep

RNG = np.random.default_rng(20261203)
# portable.exp, not np.exp: numpy's exp takes other machine code on other processors (AVX-512 or
# not), so inputs made with it would differ by machine and the digest below with them
POSITIVE = np.concatenate([portable.exp(RNG.uniform(-700, 700, 20_000)), RNG.uniform(0.1, 1e6, 20_000),
                           [1.0, 2.0, 0.5, 10.0, 1e-5, 1e22, 5e-324, 1.7976931348623157e308, 3.0]])


def _ulps(ours, reference) -> float:
    """The largest difference in units of the last place of ``reference``."""
    reference = np.asarray(reference, dtype=np.float64)
    return float(np.max(np.abs(ours - reference) / np.spacing(np.maximum(np.abs(reference), 1e-300))))


@pytest.mark.parametrize("ours, theirs", [(portable.log, np.log), (portable.log10, np.log10), (portable.log2, np.log2)])
def test_logarithms_are_within_two_units_in_the_last_place(ours, theirs):
    assert _ulps(ours(POSITIVE), theirs(POSITIVE)) <= 2.0


def test_exponentials_are_within_one_unit_in_the_last_place():
    x = RNG.uniform(-700, 700, 20_000)
    assert _ulps(portable.exp(x), np.exp(x)) <= 1.0
    y = RNG.uniform(-300, 300, 20_000)
    assert _ulps(portable.power10(y), 10.0 ** y) <= 1.0
    z = RNG.uniform(-1000, 1000, 20_000)
    assert _ulps(portable.power(2, z), 2.0 ** z) <= 1.0


def test_exact_where_the_answer_is_a_double():
    k = np.arange(-300, 300)
    assert np.array_equal(portable.log10(np.array([float(f"1e{j}") for j in k])), k)
    assert np.array_equal(portable.power10(k.astype(float)), [float(f"1e{j}") for j in k])
    assert np.array_equal(portable.log2(np.ldexp(1.0, k)), k)
    assert np.array_equal(portable.power(2, k.astype(float)), np.ldexp(1.0, k))
    assert portable.log(np.float64(1.0)) == 0.0 and portable.exp(np.float64(0.0)) == 1.0


def test_edges_of_the_domain_are_numpys():
    edges = np.array([0.0, -1.0, np.inf, np.nan])
    with np.errstate(divide="ignore", invalid="ignore"):
        assert np.array_equal(portable.log10(edges), np.log10(edges), equal_nan=True)
    big = np.array([np.inf, -np.inf, np.nan, 800.0, -800.0])
    with np.errstate(over="ignore"):
        assert np.array_equal(portable.exp(big), np.exp(big), equal_nan=True)


def test_cosines_and_sines_of_fractions_of_a_turn():
    turns = np.arange(720) / 720
    cos, sin = portable.cos_sin_of_turns(turns)
    assert np.max(np.abs(cos - np.cos(2 * np.pi * turns))) < 1e-15
    assert np.max(np.abs(sin - np.sin(2 * np.pi * turns))) < 1e-15
    assert (cos[[0, 180, 360, 540]] == [1, 0, -1, 0]).all() and (sin[[0, 180, 360, 540]] == [0, 1, 0, -1]).all()


@pytest.mark.parametrize("episodes, blocks", [(200_000, 200), (2000, 50), (20_000, 200), (100_000, 48)])
def test_log_spaced_edges_are_those_numpy_rounds_to(episodes, blocks):
    # the kernels' block edges and checkpoints: the committed results were made with numpy's
    expected = np.concatenate([[0], np.unique(np.round(np.geomspace(1, episodes, blocks)).astype(np.int64))])
    assert np.array_equal(ep.log_edges(episodes, blocks), expected)


def test_fits_and_sums_are_numpys_without_a_linear_algebra_library():
    x, y = RNG.uniform(1, 10, 7), RNG.uniform(1, 10, 7)
    assert portable.line_slope(x, y) == pytest.approx(np.polyfit(x, y, 1)[0], rel=1e-12)
    values, weights = RNG.uniform(size=(3, 50)), RNG.uniform(size=50)
    assert portable.weighted_sum(values, weights) == pytest.approx(values @ weights, rel=1e-12)


PORTABLE_DIGEST = "d980ff2924802d6b"
"""The start of the sha256 of the values below, as first computed: every machine gives these bits."""


def test_the_same_bits_on_every_machine():
    values = np.concatenate([portable.log(POSITIVE), portable.log10(POSITIVE), portable.log2(POSITIVE),
                             portable.exp(np.linspace(-700, 700, 4001)), portable.power10(np.linspace(-300, 300, 4001)),
                             *portable.cos_sin_of_turns(np.arange(720) / 720), portable.geomspace(1, 200_000, 200)])
    assert hashlib.sha256(values.tobytes()).hexdigest()[:16] == PORTABLE_DIGEST
