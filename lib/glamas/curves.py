"""What the experiments read from learning curves (runs on the first axis, points or blocks of
episodes on the second): the mean over the runs with its bootstrap band, the final value, the mean
over the last FINAL_FRACTION of the episodes (or iterations), per run or over the runs, and the
episode from which a curve has converged."""

import math

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas.portable import weighted_sum

FINAL_FRACTION = 0.1
"""The "final" value of a curve is its mean over the last 10 % of the episodes (or iterations)."""
CONVERGENCE_TOLERANCE = 0.05
"""A curve has converged once it stays within 5 % of its final value."""
TOLERANCES = (0.03, 0.05, 0.10, 0.15)
"""The tolerances over which every convergence verdict is shown (3 % to 15 %): a verdict that
changes inside this range is reported as changing, never read at one tolerance only."""
BOOTSTRAP_DRAWS = 2000
"""Resamples of the runs behind the 95 % interval of a convergence ratio."""
BAND_DRAWS = 1000
"""Resamples of the runs behind every band."""
DEFINITIONS = ("per_run", "run_mean", "shared_level")
"""The definitions of "converges faster" that :func:`convergence_ratio` computes:

* ``per_run`` (decides the claims): the median over runs of the episode after which each run's
  own curve stays within the tolerance of its own final value;
* ``run_mean``: the episode after which the mean curve over runs stays within the tolerance of
  its final value;
* ``shared_level``: the episode after which the mean curve stays at or below one level for both
  learners, the worse learner's final value plus the tolerance (curves where lower is better).
"""


def ratio(numerator: float, denominator: float) -> float:
    """``numerator / denominator`` of two final values; NaN (undecidable) when the denominator is
    0, as a final reward can be exactly in a run of a few episodes."""
    return numerator / denominator if denominator else math.nan


def _final_weights(episodes: np.ndarray, fraction: float = FINAL_FRACTION) -> np.ndarray:
    """Each block's (ending at ``episodes``) number of episodes in the last ``fraction``."""
    starts = np.concatenate([[0], episodes[:-1]])
    cut = episodes[-1] * (1.0 - fraction)
    return np.clip(episodes - np.maximum(starts, cut), 0, None)


def final(curves: np.ndarray, episodes: np.ndarray, fraction: float = FINAL_FRACTION) -> float:
    """Mean over runs and over the last ``fraction`` of the episodes: each block (ending at
    ``episodes``) weighted by how many of its episodes lie in that last part."""
    weights = _final_weights(episodes, fraction)
    return float(weighted_sum(curves.mean(axis=0), weights) / weights.sum())


def final_by_run(curves: np.ndarray, episodes: np.ndarray) -> np.ndarray:
    """:func:`final` of each run on its own."""
    weights = _final_weights(episodes)
    return weighted_sum(curves, weights) / weights.sum()


def final_per_run(curves: np.ndarray, fraction: float = FINAL_FRACTION) -> np.ndarray:
    """Per run: the mean of a curve of equally spaced points over its last ``fraction`` (at least
    one point)."""
    tail = max(1, int(round(curves.shape[1] * fraction)))
    return curves[:, -tail:].mean(axis=1)


def mean_and_band(curves: np.ndarray, seed: int = 0):
    """Mean over runs (axis 0) and its 95 % bootstrap band (percentiles of the means of runs
    resampled with replacement; fixed seed, so figures stay byte-reproducible). The band is made of
    means of real runs, so it never leaves the range the runs span (a count never goes below 0)."""
    curves = np.asarray(curves, dtype=np.float64)
    mean = curves.mean(axis=0)
    if curves.shape[0] < 2:
        return mean, mean, mean
    picks = np.random.default_rng(seed).integers(0, curves.shape[0], (BAND_DRAWS, curves.shape[0]))
    low, high = np.percentile(resampled_means(curves, picks), [2.5, 97.5], axis=0)
    return mean, low, high


def resampled_means(curves: np.ndarray, picks: np.ndarray) -> np.ndarray:
    """(draws, points): for each row of ``picks`` (draws, k), the mean of those rows of ``curves``
    (runs, points): ``curves[picks].mean(axis=1)`` to the bit (each sum in the order of the picks),
    without the (draws, k, points) copy that indexing makes."""
    return _resampled_means(np.ascontiguousarray(curves, dtype=np.float64), np.ascontiguousarray(picks, dtype=np.int64))


@njit(cache=True)
def _resampled_means(curves, picks):
    draws, k = picks.shape
    out = np.empty((draws, curves.shape[1]))
    for d in range(draws):
        row = out[d]
        row[:] = curves[picks[d, 0]]
        for j in range(1, k):
            row += curves[picks[d, j]]
        row /= k
    return out


def convergence_episode(curves: np.ndarray, episodes: np.ndarray, tolerance: float = CONVERGENCE_TOLERANCE) -> float:
    """The episode after which the run-mean curve stays within ``tolerance`` of its final value."""
    return float(convergence_episodes(curves.mean(axis=0), episodes, tolerance))


def convergence_episodes(curves: np.ndarray, episodes: np.ndarray, tolerance: float = CONVERGENCE_TOLERANCE) -> np.ndarray:
    """Per run (or per row of any curves): the episode after which the run's own curve stays
    within ``tolerance`` of its own final value."""
    targets = final_by_run(curves, episodes)[..., None]
    return _last_outside(np.abs(curves - targets) > tolerance * np.abs(targets), episodes)


def _last_outside(outside: np.ndarray, episodes: np.ndarray) -> np.ndarray:
    """Per row of ``outside`` (..., blocks): the end of its last block that is outside, 0 if none."""
    last = outside.shape[-1] - 1 - np.argmax(outside[..., ::-1], axis=-1)
    return np.where(outside.any(axis=-1), episodes[last], 0).astype(np.float64)


def level_episode(curves: np.ndarray, episodes: np.ndarray, level: float) -> float:
    """The episode after which the run-mean curve stays at or below ``level`` (0 if it always
    does; the last episode if it ends above it)."""
    return float(_last_outside(curves.mean(axis=0) > level, episodes))


def shared_level(curves: np.ndarray, baseline: np.ndarray, episodes: np.ndarray, tolerance: float) -> float:
    """The level both learners are timed to under ``shared_level``: the worse (higher) of their
    final values, raised by ``tolerance``."""
    return (1.0 + tolerance) * max(final(curves, episodes), final(baseline, episodes))


def convergence_ratio(curves: np.ndarray, baseline: np.ndarray, episodes: np.ndarray,
                      definition: str = "per_run", tolerance: float = CONVERGENCE_TOLERANCE,
                      seed: int = 0) -> tuple[float, float, float]:
    """The ratio of the convergence episodes of ``curves`` and ``baseline`` (runs, blocks) under
    ``definition``, with a 95 % bootstrap interval: the runs of each learner resampled with
    replacement on their own (the learners' runs have streams of their own, so no run of one is
    the pair of a run of the other). A baseline converged at episode 0 counts as 1."""
    if definition not in DEFINITIONS:
        raise UserError(f"definition must be one of {DEFINITIONS}, got {definition!r}")
    draws = np.random.default_rng(seed)
    picks_a = draws.integers(0, curves.shape[0], (BOOTSTRAP_DRAWS, curves.shape[0]))
    picks_b = draws.integers(0, baseline.shape[0], (BOOTSTRAP_DRAWS, baseline.shape[0]))
    if definition == "per_run":  # each run's episode is its own: resample the episodes
        a, b = convergence_episodes(curves, episodes, tolerance), convergence_episodes(baseline, episodes, tolerance)
        point = np.median(a) / max(np.median(b), 1.0)
        ratios = np.median(a[picks_a], axis=1) / np.maximum(np.median(b[picks_b], axis=1), 1.0)
    else:  # the statistic of the mean curve of each resample of the runs
        level = shared_level(curves, baseline, episodes, tolerance)
        a = _mean_curve_episodes(curves.mean(axis=0), episodes, definition, tolerance, level)
        b = _mean_curve_episodes(baseline.mean(axis=0), episodes, definition, tolerance, level)
        point = a / max(b, 1.0)
        ratios = (_mean_curve_episodes(resampled_means(curves, picks_a), episodes, definition, tolerance, level)
                  / np.maximum(_mean_curve_episodes(resampled_means(baseline, picks_b), episodes, definition,
                                                    tolerance, level), 1.0))
    low, high = np.percentile(ratios, [2.5, 97.5])
    return float(point), float(low), float(high)


def _mean_curve_episodes(means: np.ndarray, episodes: np.ndarray, definition: str, tolerance: float, level: float):
    """For mean curves (..., blocks): the episode after which each stays within ``tolerance`` of
    its final value (``run_mean``) or at or below ``level`` (``shared_level``)."""
    if definition == "run_mean":
        return convergence_episodes(means, episodes, tolerance)
    return _last_outside(means > level, episodes)


BLOCK_FACTORS = (1, 2, 4)
"""Block widths, as multiples of a result's own, over which a convergence verdict is shown."""


def convergence_grid(curves: np.ndarray, baseline: np.ndarray, episodes: np.ndarray,
                     definition: str = "per_run") -> list[tuple]:
    """(block factor, tolerance, ratio, low, high): :func:`convergence_ratio` at every block width
    of BLOCK_FACTORS (:func:`coarsened`) and every tolerance of TOLERANCES."""
    rows = []
    for factor in BLOCK_FACTORS:
        a, ends = coarsened(curves, episodes, factor)
        b, _ = coarsened(baseline, episodes, factor)
        rows.extend((factor, tolerance) + convergence_ratio(a, b, ends, definition, tolerance)
                    for tolerance in TOLERANCES)
    return rows


def interval_verdict(low: float, high: float) -> str:
    """What a 95 % interval of a ratio of convergence episodes says: 'faster' (below 1),
    'slower' (above 1) or 'undecidable' (it contains 1)."""
    return "faster" if high < 1.0 else ("slower" if low > 1.0 else "undecidable")


def grid_verdict(rows: list[tuple]) -> str:
    """The verdict every row of :func:`convergence_grid` gives, or 'undecidable' when they differ:
    a verdict no tolerance or block width moves."""
    verdicts = {interval_verdict(low, high) for *_, low, high in rows}
    return verdicts.pop() if len(verdicts) == 1 else "undecidable"


def earlier_share(curves: np.ndarray, baseline: np.ndarray, episodes: np.ndarray,
                  tolerance: float = CONVERGENCE_TOLERANCE) -> float:
    """The share of all pairs (run of ``curves``, run of ``baseline``) in which the first run
    converges earlier (per-run convergence episodes; a tie counts one half): the probability that
    a run of the first learner settles before a run of the second."""
    a = convergence_episodes(curves, episodes, tolerance)[:, None]
    b = convergence_episodes(baseline, episodes, tolerance)[None, :]
    return float(((a < b) + 0.5 * (a == b)).mean())


def coarsened(curves: np.ndarray, episodes: np.ndarray, factor: int) -> tuple[np.ndarray, np.ndarray]:
    """The curves (runs, blocks) on blocks ``factor`` times wider: each run of ``factor``
    neighbouring blocks merged into one, its value the mean over its episodes (the last block
    takes what is left). To show that a measure does not depend on the block width."""
    if factor == 1:
        return curves, episodes
    widths = np.diff(episodes, prepend=0)
    groups = np.arange(episodes.size) // factor
    summed = np.zeros(curves.shape[:-1] + (groups[-1] + 1,))
    np.add.at(summed, (..., groups), curves * widths)
    merged_widths = np.bincount(groups, weights=widths)
    return summed / merged_widths, episodes[np.r_[np.flatnonzero(np.diff(groups)), episodes.size - 1]]
