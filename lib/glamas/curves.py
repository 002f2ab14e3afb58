"""What the experiments read from learning curves (runs on the first axis, points or blocks of
episodes on the second): the final value, the mean over the last FINAL_FRACTION of the episodes
(or iterations), per run or over the runs, and the episode from which a curve has converged."""

import numpy as np

FINAL_FRACTION = 0.1
"""The "final" value of a curve is its mean over the last 10 % of the episodes (or iterations)."""
CONVERGENCE_TOLERANCE = 0.05
"""A learner has converged once its mean steps curve stays within 5 % of its final value."""
BOOTSTRAP_DRAWS = 2000
"""Resamples of the runs behind the 95 % interval of a convergence ratio."""


def final(curves: np.ndarray, episodes: np.ndarray) -> float:
    """Mean over runs and over the last FINAL_FRACTION of the episodes: each block (ending at
    ``episodes``) weighted by how many of its episodes lie in that last part."""
    starts = np.concatenate([[0], episodes[:-1]])
    cut = episodes[-1] * (1.0 - FINAL_FRACTION)
    weights = np.clip(episodes - np.maximum(starts, cut), 0, None)
    return float(curves.mean(axis=0) @ weights / weights.sum())


def convergence_episode(curves: np.ndarray, episodes: np.ndarray) -> float:
    """The episode after which the run-mean curve stays within CONVERGENCE_TOLERANCE of its
    final value: the end of the last block outside it (0 if none is)."""
    target = final(curves, episodes)
    outside = np.flatnonzero(np.abs(curves.mean(axis=0) - target) > CONVERGENCE_TOLERANCE * abs(target))
    return float(episodes[outside[-1]]) if outside.size else 0.0


def convergence_ratio(curves: np.ndarray, baseline: np.ndarray, episodes: np.ndarray,
                      seed: int = 0) -> tuple[float, float, float]:
    """The ratio of the convergence episodes of ``curves`` and ``baseline`` (runs, blocks), with
    a 95 % bootstrap interval: runs resampled with replacement, each learner on its own."""
    draws = np.random.default_rng(seed)
    ratios = np.empty(BOOTSTRAP_DRAWS)
    for k in range(BOOTSTRAP_DRAWS):
        a = curves[draws.integers(0, curves.shape[0], curves.shape[0])]
        b = baseline[draws.integers(0, baseline.shape[0], baseline.shape[0])]
        ratios[k] = convergence_episode(a, episodes) / max(convergence_episode(b, episodes), 1.0)
    point = convergence_episode(curves, episodes) / max(convergence_episode(baseline, episodes), 1.0)
    low, high = np.percentile(ratios, [2.5, 97.5])
    return point, float(low), float(high)



def final_per_run(curves: np.ndarray, fraction: float = FINAL_FRACTION) -> np.ndarray:
    """Per run: the mean of a curve of equally spaced points over its last ``fraction`` (at least
    one point)."""
    tail = max(1, int(round(curves.shape[1] * fraction)))
    return curves[:, -tail:].mean(axis=1)
