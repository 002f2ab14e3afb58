"""What Fig. 6's results say: the team's expected reward at every checkpoint, exact on the
evaluation grid (:func:`expected_curves`), and from it, never from the plot's windows, the
claims' comparisons of the encodings: paired differences, effect sizes and learning speed."""

import functools

import numpy as np
from numba import njit

from glamas import claims, gla, lineworld
from glamas.curves import BOOTSTRAP_DRAWS
from glamas.experiments.single_gla.analysis import best_actions, contexts
from glamas.experiments.single_gla.experiment import SingleGLAConfig, SingleGLAResult
from glamas.portable import weighted_sum


@njit(cache=True)
def team_rewards(params, contexts_a, contexts_b, part_a, part_b, weight, temperature, L, mode, out):
    """out[m]: the expected feedback of both agents' Boltzmann policies (eq. 15 at h(u), two
    actions: P(L) = 1 / (1 + exp(-(h(u_L) - h(u_R)).x / T))) with parameters params[m] (2 agents,
    2 actions, inputs): the weighted mean over the points of P_A(part) P_B(part), from each
    point's contexts, parts of the rewarded joint action and weight (:func:`grid_points`)."""
    n_inputs = contexts_a.shape[1]
    w = np.empty((2, n_inputs))
    for m in range(params.shape[0]):
        for agent in range(2):
            for k in range(n_inputs):
                w[agent, k] = (gla.bound(params[m, agent, lineworld.LEFT, k], L, mode)
                               - gla.bound(params[m, agent, lineworld.RIGHT, k], L, mode)) / temperature
        total = 0.0
        for i in range(contexts_a.shape[0]):
            z_a, z_b = 0.0, 0.0
            for k in range(n_inputs):
                z_a += w[0, k] * contexts_a[i, k]
                z_b += w[1, k] * contexts_b[i, k]
            p_a = 1.0 / (1.0 + np.exp(-z_a if part_a[i] == lineworld.LEFT else z_a))
            p_b = 1.0 / (1.0 + np.exp(-z_b if part_b[i] == lineworld.LEFT else z_b))
            total += weight[i] * p_a * p_b
        out[m] = total / weight.sum()


EDGE_NUDGE = 1e-9
"""How far :func:`grid_points` moves a point to read the rewarded action on each side of it."""


def grid_points(config: SingleGLAConfig) -> tuple:
    """The evaluation grid as :func:`team_rewards` reads it: (contexts of A, contexts of B, A's
    part, B's part, weight). Each point counts half with the rewarded joint action just left and
    half with the one just right of it (x1 -+ EDGE_NUDGE): the same inside a region, and on a
    region's edge (the grid puts points on x1 = x2 and |x1 - x2| = 0.5) an even split, as the edge
    splits the point's cell. Counting such a point wholly on one side would bias each run's
    expected reward by up to a cell's width times its policy's jump there, a run-to-run scatter
    that halves with every doubling of the grid. Points with the same contexts and parts are
    merged, their weights added (the distance contexts see about 2 eval_grid distinct points)."""
    encoding = lineworld.encoding_code(config.context)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    n = lineworld.CONTEXT_LENGTH[encoding]
    seen = np.column_stack([contexts(encoding, lineworld.AGENT_A, x1, x2), contexts(encoding, lineworld.AGENT_B, x1, x2)])
    rows = np.vstack([np.column_stack([seen, best_actions(x1 + side, x2, lineworld.AGENT_A),
                                       best_actions(x1 + side, x2, lineworld.AGENT_B)])
                      for side in (-EDGE_NUDGE, EDGE_NUDGE)])
    _, first, counts = np.unique(np.round(rows, 12), axis=0, return_index=True, return_counts=True)
    rows = rows[first]
    return (np.ascontiguousarray(rows[:, :n]), np.ascontiguousarray(rows[:, n:2 * n]), rows[:, 2 * n].astype(np.int64),
            rows[:, 2 * n + 1].astype(np.int64), counts / 2.0)


def expected_curves(result: SingleGLAResult) -> np.ndarray:
    """(runs, checkpoints) the team's expected feedback (:func:`team_rewards` on the evaluation
    grid) at every checkpoint of every run: Fig. 6's learning curve without sampling noise, which
    the run stores (``result.expected_reward``) and the claims, tables and figures read."""
    config = result.config
    runs, points = result.checkpoint_params.shape[:2]
    out = np.empty(runs * points)
    team_rewards(result.checkpoint_params.reshape(runs * points, *result.checkpoint_params.shape[2:]),
                 *grid_points(config), config.temperature, config.L, config.gla_params().bounding_code, out)
    return out.reshape(runs, points)


def curve_mean(curves: np.ndarray, iteration: np.ndarray) -> np.ndarray:
    """(runs,) each curve's mean over the iterations from the first to the last checkpoint
    (trapezoids between checkpoints): the height of the learning curve averaged over the run."""
    widths = np.diff(iteration)
    return weighted_sum(curves[:, 1:] + curves[:, :-1], widths) / (2.0 * widths.sum())


REACH_TOLERANCE = 0.05
"""Learning speed: the iteration at which the expected reward first reaches 95 % of its final value."""


def reach_iteration(curves: np.ndarray, iteration: np.ndarray, tolerance: float = REACH_TOLERANCE) -> np.ndarray:
    """(runs,) the iteration at which each curve (runs, checkpoints) first reaches (1 - tolerance)
    times its last value, linear between the checkpoints that bracket it (0 if the first does)."""
    target = (1.0 - tolerance) * curves[:, -1]
    out = np.empty(curves.shape[0])
    for r, (curve, level) in enumerate(zip(curves, target)):
        c = int(np.argmax(curve >= level))
        if c == 0:
            out[r] = iteration[0]
            continue
        share = (level - curve[c - 1]) / (curve[c] - curve[c - 1])
        out[r] = iteration[c - 1] + share * (iteration[c] - iteration[c - 1])
    return out


COMPARISONS = (("deictic", "joint"), ("joint", "absolute"), ("deictic", "absolute"))
"""Fig. 6's pairs of encodings (better, worse) in the chapter's ordering."""


def measure_encodings(results: dict, tolerance: float = REACH_TOLERANCE, drawn: float = 1.0, read: float = 1.0) -> dict:
    """Fig. 6's metrics, all from the expected reward at the checkpoints (:func:`expected_curves`),
    none from the plot windows: per encoding the mean over runs of the learning curve's mean
    (:func:`curve_mean`) and final value; per pair of encodings (run r of each shares its seed) the
    paired difference of both with its 95 % interval and Cohen's d; the absolute distance's
    smaller d against the others; each pair's lead as a reader sees it (:func:`visible_leads`: the
    first ``drawn`` of the run drawn, the first ``read`` of that read); deictic against joint, the
    iterations to reach 1 - ``tolerance`` of the final value (:func:`speed_comparison`)."""
    curves = {name: res.expected_reward for name, res in results.items()}
    per_run = {name: {"mean": curve_mean(curve, results[name].checkpoint), "final": curve[:, -1]}
               for name, curve in curves.items()}
    measured = {f"{name}_expected_{key}": values.mean() for name, rows in per_run.items() for key, values in rows.items()}
    for better, worse in COMPARISONS:
        for key in ("mean", "final"):
            a, b = per_run[better][key], per_run[worse][key]
            label = f"{better}_minus_{worse}_{key}"
            measured[label], measured[f"{label}_low"], measured[f"{label}_high"] = paired_interval(a, b)
            measured[f"{label}_effect"] = cohen_d(a, b)
    for key in ("mean", "final"):
        measured[f"absolute_worst_{key}_effect"] = min(measured[f"joint_minus_absolute_{key}_effect"],
                                                       measured[f"deictic_minus_absolute_{key}_effect"])
    measured.update(visible_leads(curves, results["deictic"].checkpoint, drawn, read))
    measured["absolute_worst_mean_visible"] = min(measured["joint_minus_absolute_mean_visible"],
                                                  measured["deictic_minus_absolute_mean_visible"])
    iteration = results["deictic"].checkpoint
    measured.update(speed_comparison(reach_iteration(curves["deictic"], iteration, tolerance),
                                     reach_iteration(curves["joint"], iteration, tolerance)))
    for key in [k for k in measured if np.isnan(measured[k])]:
        measured[key + claims.WHY_UNDECIDABLE] = ("no run-to-run spread or no paired runs to judge by "
                                                  "(fewer than two runs, identical ones, or a curve at its "
                                                  "final value from the start)")
    return measured


def visible_leads(curves: dict, iteration: np.ndarray, drawn: float = 1.0, read: float = 1.0) -> dict:
    """Per pair of COMPARISONS, ``<better>_minus_<worse>_mean_visible``: the mean lead of the better
    encoding's curve over the worse one's over the part of the plot a reader reads, as a share of
    the plot's height (:func:`plotted_span`), with the first ``drawn`` of the run drawn and its
    first ``read`` read (docs/verdicts.md, rule ``curve_lead``); and ``plotted_span``."""
    end = iteration[-1] * drawn
    span = plotted_span({name: truncated(curve, iteration, end)[0] for name, curve in curves.items()})
    seen = {name: curve_mean(*truncated(curve, iteration, end * read)) for name, curve in curves.items()}
    out = {"plotted_span": span}
    for better, worse in COMPARISONS:
        out[f"{better}_minus_{worse}_mean_visible"] = float((seen[better] - seen[worse]).mean() / span)
    return out


def truncated(curves: np.ndarray, iteration: np.ndarray, end: float) -> tuple[np.ndarray, np.ndarray]:
    """The curves (runs, checkpoints) and their iterations up to ``end``, the value at ``end``
    interpolated linearly between the checkpoints that bracket it."""
    keep = int(np.searchsorted(iteration, end, side="left"))
    if keep < iteration.shape[0] and iteration[keep] == end:
        return curves[:, :keep + 1], iteration[:keep + 1]
    at_end = np.array([np.interp(end, iteration, curve) for curve in curves])
    return np.column_stack([curves[:, :keep], at_end]), np.append(iteration[:keep], end)


def plotted_span(curves: dict) -> float:
    """The height of Fig. 6's plot: from the lowest to the highest point of the encodings' mean
    curves (mean over runs at every checkpoint), the range a reader's axis spans. A gap between two
    curves is read against it: what share of the plot's height separates them."""
    means = np.array([curve.mean(axis=0) for curve in curves.values()])
    return float(means.max() - means.min())


def paired_interval(better: np.ndarray, worse: np.ndarray) -> tuple[float, float, float]:
    """The mean of the per-run differences and its 95 % confidence interval (normal; NaN ends
    with one run)."""
    diff = better - worse
    half = 1.96 * diff.std(ddof=1) / np.sqrt(diff.shape[0]) if diff.shape[0] > 1 else np.nan
    return float(diff.mean()), float(diff.mean() - half), float(diff.mean() + half)


def cohen_d(better: np.ndarray, worse: np.ndarray) -> float:
    """Cohen's d: the difference of the means over runs in units of the runs' pooled standard
    deviation (NaN with one run or no spread)."""
    if better.shape[0] < 2:
        return float("nan")
    spread = np.sqrt((better.var(ddof=1) + worse.var(ddof=1)) / 2)
    return float((better.mean() - worse.mean()) / spread) if spread > 0 else float("nan")


def speed_comparison(deictic: np.ndarray, joint: np.ndarray, seed: int = 0) -> dict:
    """Deictic against joint from the paired iterations to reach the level (runs,): the share of
    runs where the deictic context gets there first (ties count half), and the median of the
    per-run ratios deictic / joint with its 95 % bootstrap interval (run pairs resampled)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(joint > 0, deictic / np.where(joint > 0, joint, 1.0), np.nan)
    share = float(np.mean((deictic < joint) + 0.5 * (deictic == joint)))
    if ratio.shape[0] < 2 or np.isnan(ratio).any():
        return {"deictic_earlier_share": share, "deictic_joint_reach_ratio": float(np.median(ratio)),
                "deictic_joint_reach_ratio_low": float("nan"), "deictic_joint_reach_ratio_high": float("nan")}
    draws = np.random.default_rng(seed).integers(0, ratio.shape[0], (BOOTSTRAP_DRAWS, ratio.shape[0]))
    low, high = np.percentile(np.median(ratio[draws], axis=1), [2.5, 97.5])
    return {"deictic_earlier_share": share, "deictic_joint_reach_ratio": float(np.median(ratio)),
            "deictic_joint_reach_ratio_low": float(low), "deictic_joint_reach_ratio_high": float(high)}


def paired_curve(results: dict, better: str, worse: str) -> tuple:
    """(iterations, mean, low, high): the paired difference of two encodings' expected rewards at
    every checkpoint, with its 95 % interval over runs."""
    a, b = results[better].expected_reward, results[worse].expected_reward
    rows = np.array([paired_interval(a[:, c], b[:, c]) for c in range(a.shape[1])])
    return results[better].checkpoint, rows[:, 0], rows[:, 1], rows[:, 2]


def encoding_claim_rows(results: dict, readings: dict | None = None, box: str = "fig5") -> list[dict]:
    """The Fig. 6 claims (data/chapter/section4.json) with verdicts computed from ``results``, each
    judged at every measurement choice of its rule and under the results of the other readings of
    the box (``readings``: name -> results; ``box`` names the reading of ``results``)."""
    other = {f"box {name}": functools.partial(measure_encodings, found) for name, found in (readings or {}).items()}
    return claims.verdicts(claims.load("state_encoding"), functools.partial(measure_encodings, results),
                           readings=other, reading=f"box {box}")
