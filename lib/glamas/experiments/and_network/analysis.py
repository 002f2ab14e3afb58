"""What the results of experiment 2 say: how well the learned L-region matches region I, P(L) and
P(R) per region and the stuck runs (Fig. 7); for the sweep, the stuck fraction at each region II
reward and how far the initialisation decides the outcome; the claims' verdicts."""

import functools

import numpy as np

from glamas import claims
from glamas.experiments.and_network.experiment import (PARABOLA_READINGS, ANDNetworkConfig, ANDNetworkResult, SweepResult,
                                                       evaluation_points, final_left_by_region, left_maps,
                                                       region_means)


def measure(result: ANDNetworkResult) -> dict:
    """Fig. 7's metrics: how well the learned L-region matches region I, final P(L) in region I
    (Fig. 7b's last point and on the evaluation grid), P(R) in region II, the lower of P(L) in
    I and P(R) in II, and the fraction of stuck runs."""
    p_left = left_maps(result)
    in_I, in_II = region_means(p_left, result.config)
    curve_end = result.prob_left[:, -1, :].mean(axis=0)
    left_I, right_II = in_I.mean(axis=0), 1.0 - in_II.mean(axis=0)
    return {
        "region_I_error_removed": _agreement(p_left, result.config).mean(),
        "final_prob_left_I_a": curve_end[0],
        "final_prob_left_I_b": curve_end[1],
        "final_prob_left_I_min": curve_end.min(),
        "grid_prob_left_I_a": left_I[0],
        "grid_prob_left_I_b": left_I[1],
        "grid_prob_right_II_a": right_II[0],
        "grid_prob_right_II_b": right_II[1],
        "grid_prob_right_II_min": right_II.min(),
        "grid_prob_region_action_min": min(left_I.min(), right_II.min()),
        "stuck_fraction": (in_I < result.config.stuck_threshold).all(axis=1).mean(),
    }


def _agreement(p_left: np.ndarray, config: ANDNetworkConfig) -> np.ndarray:
    """(runs,) how well the learned L-region matches region I (Fig. 7a), from every run's P(L)
    maps (runs, 2 agents, points): the share of the evaluation grid where 'both agents'
    P(L) > 1/2' agrees with 'inside the parabola', rescaled so that 0 is what the best constant
    guess (all I or all II) gets and 1 is the parabola itself: the fraction of the constant
    guess's errors the learned boundaries remove."""
    _, _, inside = evaluation_points(config)
    trivial = max(inside.mean(), 1.0 - inside.mean())
    agreement = ((p_left > 0.5).all(axis=1) == inside).mean(axis=1)
    return (agreement - trivial) / (1.0 - trivial)


def claim_rows(result: ANDNetworkResult, readings: dict | None = None) -> list[dict]:
    """The Fig. 7 claims (data/chapter/section4.json) with verdicts computed from ``result``, each
    also judged under the results of the other parabolas (``readings``: name -> result)."""
    other = {name: measure(found) for name, found in (readings or {}).items()}
    own = (result.config.parabola_curvature, result.config.parabola_offset)
    name = next((name for name, shape in PARABOLA_READINGS.items() if shape == own), "the configured parabola")
    return claims.verdicts(claims.load("and_network"), measure(result), readings=other, reading=name)


def stuck_runs(result: ANDNetworkResult) -> np.ndarray:
    """(runs,) True where the run ended stuck in 'R everywhere' (as :func:`measure` counts them)."""
    in_I, _ = final_left_by_region(result)
    return (in_I < result.config.stuck_threshold).all(axis=1)


def typical_runs(result: ANDNetworkResult, count: int = 2) -> list[int]:
    """Runs around the median final P(L) in region I (both agents): Fig. 7a's 'typical results'."""
    in_I, _ = final_left_by_region(result)
    order = np.argsort(in_I.mean(axis=1), kind="stable")
    middle = (order.shape[0] - count) // 2
    return [int(i) for i in order[middle:middle + count]]


BOOTSTRAP_DRAWS = 10_000
"""Resamples of the runs for the 95 % interval of the initialisation's share of the outcome."""


def measure_sweep(result: SweepResult, stuck_threshold: float | None = None) -> dict:
    """Stuck fraction at each reward, at the chapter's 0.5, at the highest value, and the rise;
    at the highest reward, how far the initialisation decides the outcome (:func:`init_dependence`).
    A run is stuck when both agents' final P(L) in region I lie below ``stuck_threshold`` (the
    configuration's by default; a measurement choice of docs/verdicts.md)."""
    threshold = result.config.stuck_threshold if stuck_threshold is None else stuck_threshold
    fractions = (result.prob_left_I < threshold).all(axis=-1).mean(axis=1)
    measured = {f"stuck_fraction_{value:g}": f for value, f in zip(result.reward_outside, fractions)}
    measured["stuck_fraction_lowest"] = fractions[0]
    measured["stuck_fraction_highest"] = fractions[-1]
    measured["stuck_fraction_rise"] = fractions[-1] - fractions[0]
    first = (result.prob_left_I[-1] < threshold).all(axis=1)
    measured["stuck_fraction_rerun"] = (result.rerun_prob_left_I < threshold).all(axis=1).mean()
    return measured | init_dependence(first, (result.rerun_prob_left_I < threshold).all(axis=1))


def init_dependence(first: np.ndarray, rerun: np.ndarray, draws: int = BOOTSTRAP_DRAWS) -> dict:
    """How far the initialisation decides whether a run gets stuck, from the outcomes (runs,) of
    the same initial parameters on two streams: the agreement of run r's two outcomes (same
    initialisation), the agreement of run r's first with run s's rerun for every s != r (another
    initialisation), and the initialisation's share of the outcome, (same - other) / (1 - other):
    the fraction of the disagreement between unrelated initialisations that keeping the
    initialisation removes (close to Cohen's kappa of the two streams; 0: the stream alone
    decides, 1: the initialisation does), with its 95 % bootstrap interval over runs (in a
    resample, copies of one run count as other initialisations, which can only lower the share).
    The share decided against 0 (``init_share_of_outcome_depends``: the outcome depends on the
    initialisation) and against DECIDES (``init_share_of_outcome_decided``: it decides the outcome),
    each NaN when the interval reaches both sides, or when every run ends alike (no disagreement to
    remove)."""
    pairs = np.stack([first, rerun]).astype(np.float64)
    boot = np.random.default_rng(0).integers(0, first.shape[0], (draws, first.shape[0]))
    same, other = _agreements(pairs[None])
    shares = _init_share(*_agreements(pairs[:, boot].transpose(1, 0, 2)))
    low, high = np.nanpercentile(shares, [2.5, 97.5]) if np.isfinite(shares).any() else (np.nan, np.nan)
    share = _init_share(same, other)[0]
    measured = {"init_agreement_same": same[0], "init_agreement_other": other[0], "init_share_of_outcome": share,
                "init_share_of_outcome_low": low, "init_share_of_outcome_high": high}
    for key, level in (("init_share_of_outcome_depends", DEPENDS), ("init_share_of_outcome_decided", DECIDES)):
        measured[key] = share if not low <= level <= high else np.nan
        if np.isnan(share):
            measured[key + claims.WHY_UNDECIDABLE] = (
                "every run ends alike on both streams: no disagreement for the initialisation to explain")
        elif np.isnan(measured[key]):
            measured[key + claims.WHY_UNDECIDABLE] = (
                f"share {share:.2f}, but its 95 % interval [{low:.2f}, {high:.2f}] reaches both sides of {level:g}")
    return measured


DEPENDS = 0.0
"""The initialisation's share of the outcome above which the outcome depends on it: keeping the
initialisation makes two runs agree more often than runs of other initialisations do."""
DECIDES = 0.5
"""The initialisation's share of the outcome above which it decides the outcome more than the
stream does: the claim's threshold, which its interval must clear to decide."""


def _agreements(pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per sample of ``pairs`` (samples, 2 streams, runs) of 0/1 outcomes: the share of runs whose
    two outcomes agree, and the share of ordered pairs of positions r != s where the first
    stream's outcome of r agrees with the second's of s."""
    a, b = pairs[:, 0], pairs[:, 1]
    n = a.shape[1]
    same = (a == b).sum(axis=1)
    ones_a, ones_b = a.sum(axis=1), b.sum(axis=1)
    every_pair = ones_a * ones_b + (n - ones_a) * (n - ones_b)  # agreeing (r, s) over all r, s
    return same / n, (every_pair - same) / (n * (n - 1))


def _init_share(same: np.ndarray, other: np.ndarray) -> np.ndarray:
    """(same - other) / (1 - other), NaN where other is 1."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(other < 1, (same - other) / (1 - other), np.nan)


def sweep_claim_rows(result: SweepResult) -> list[dict]:
    """The sweep's claims (data/chapter/section4.json) with their verdicts computed from ``result``
    at every measurement choice of their rules."""
    return claims.verdicts(claims.load("and_network_sweep"), functools.partial(measure_sweep, result))


def wilson_interval(fractions: np.ndarray, n: int, z: float = 1.96):
    """The 95 % Wilson score interval (low, high) of each share in ``fractions`` of ``n`` runs:
    unlike the normal one, it stays inside [0, 1] and is not empty at a share of 0 or 1."""
    centre = (fractions + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(fractions * (1 - fractions) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half
