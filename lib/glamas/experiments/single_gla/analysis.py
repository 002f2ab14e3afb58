"""What a result of experiment 1 says (Fig. 5): exact-on-a-grid expected rewards of the learned
policies (:func:`evaluate`), the best single line each context allows (exhaustive search), the
shares of Fig. 5a's regions the learned lines get right, and the claims' numbers."""

import functools
from dataclasses import dataclass, replace

import numpy as np
from numba import njit

from glamas import claims, gla, lineworld, portable
from glamas.curves import final_per_run
from glamas.experiments.single_gla.experiment import SingleGLAConfig, SingleGLAResult
from glamas.errors import UserError


@njit(cache=True)
def correct_probabilities(u, encoding, region3, agent, x1, x2, temperature, L, mode, out):
    """out[i]: probability (eq. 15) that the agent plays its part of the rewarded joint action
    at (x1[i], x2[i]) (region 3 read as ``region3``)."""
    context = np.empty(u.shape[1])
    probs = np.empty(2)
    for i in range(x1.shape[0]):
        lineworld.context(encoding, agent, x1[i], x2[i], context)
        gla.boltzmann(u, context, temperature, L, mode, probs)
        out[i] = probs[lineworld.best_action(x1[i], x2[i], agent, region3)]


@njit(cache=True)
def best_actions(x1, x2, agent, region3=lineworld.MOVE_APART):
    """The agent's part of the rewarded joint action at every point (region 3 read as ``region3``)."""
    out = np.empty(x1.shape[0], dtype=np.int64)
    for i in range(x1.shape[0]):
        out[i] = lineworld.best_action(x1[i], x2[i], agent, region3)
    return out


@njit(cache=True)
def regions(x1, x2):
    """The region of Fig. 5a (1, 2 or 3) of every point."""
    out = np.empty(x1.shape[0], dtype=np.int64)
    for i in range(x1.shape[0]):
        out[i] = lineworld.region(x1[i], x2[i])
    return out


def contexts(encoding: int, agent: int, x1: np.ndarray, x2: np.ndarray) -> np.ndarray:
    """(points, context length) the agent's contexts at the given positions."""
    out = np.empty((x1.shape[0], lineworld.CONTEXT_LENGTH[encoding]))
    _fill_contexts(encoding, agent, x1, x2, out)
    return out


@njit(cache=True)
def _fill_contexts(encoding, agent, x1, x2, out):
    for i in range(x1.shape[0]):
        lineworld.context(encoding, agent, x1[i], x2[i], out[i])


@dataclass(frozen=True)
class Evaluation:
    """Expected rewards of every run's final policies, averaged over the evaluation grid."""

    agent_reward: np.ndarray
    """(runs, 2) expected feedback of each agent's Boltzmann policy when the other agent plays
    its part of the rewarded joint action (i.e. the agent's probability of playing its part)."""
    line_reward: np.ndarray
    """(runs, 2) the same for the agent's learned line: the greedy (most probable) action."""
    team_reward: np.ndarray
    """(runs,) expected feedback when both agents play their Boltzmann policies."""


def _correct_on_grid(params: np.ndarray, config: SingleGLAConfig) -> np.ndarray:
    """(2 agents, grid points) each agent's probability of playing its part of the rewarded
    joint action, for parameters (2 agents, 2 actions, context length)."""
    encoding, mode = lineworld.encoding_code(config.context), config.gla_params().bounding_code
    region3 = lineworld.region3_code(config.region3_reward)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    correct = np.empty((2, x1.shape[0]))
    for agent in range(2):
        correct_probabilities(params[agent], encoding, region3, agent, x1, x2, config.temperature,
                              config.L, mode, correct[agent])
    return correct


def team_reward(params: np.ndarray, config: SingleGLAConfig) -> float:
    """Expected feedback of both agents' Boltzmann policies with the given parameters
    (2 agents, 2 actions, context length): the mean over the grid of P_A(right) P_B(right)."""
    correct = _correct_on_grid(params, config)
    return float((correct[0] * correct[1]).mean())


def evaluate(result: SingleGLAResult) -> Evaluation:
    """Exact-on-a-grid expected rewards of the learned policies (no sampling noise)."""
    return _evaluation(_correct_runs(result.params, result.config))


def _evaluation(correct: np.ndarray) -> Evaluation:
    """The expected rewards from every run's probabilities of playing each agent's part."""
    return Evaluation(correct.mean(axis=2), (correct > 0.5).mean(axis=2),
                      (correct[:, 0] * correct[:, 1]).mean(axis=1))


def _correct_runs(params: np.ndarray, config: SingleGLAConfig) -> np.ndarray:
    """(runs, 2 agents, grid points) :func:`_correct_on_grid` for every run's parameters."""
    return np.stack([_correct_on_grid(u, config) for u in params])


@functools.lru_cache(maxsize=None)  # a constant of the problem, asked for by every measure
def best_line_reward(encoding_name: str, agent: int, grid: int = 200, angles: int = 720,
                     region3_reward: str = "move_apart") -> float:
    """The best expected reward a single line (a fixed threshold on a linear function of the
    context, i.e. a deterministic 2-action GLA policy) gives the agent, the other agent playing
    its part of the rewarded joint action (exhaustive search, :func:`best_line_shares`)."""
    encoding, region3 = lineworld.encoding_code(encoding_name), lineworld.region3_code(region3_reward)
    x1, x2 = lineworld.state_grid(grid)
    return float(best_line_shares(encoding, region3, agent, x1, x2, np.ones((1, x1.shape[0])), angles)[0])


def best_line_shares(encoding: int, region3: int, agent: int, x1: np.ndarray, x2: np.ndarray,
                     counts: np.ndarray, angles: int = 720) -> np.ndarray:
    """(rows of ``counts``,) the largest share of the points (x1, x2) a single line of the agent
    plays its part of the rewarded joint action at (region 3 read as ``region3``), counting point
    i with weight counts[row, i] (1 everywhere: the agent's best line; 1 where the other agent
    plays its part: the agent's best line given the other's policy, its best response among lines).

    Exhaustive search: for each direction w of the non-bias inputs (``angles`` directions over the
    circle when there are two, +-1 when there is one), every threshold between consecutive
    distinct projections w.x is tried, with L on the side of larger projections.
    """
    features, directions, wants_left = _line_search(encoding, region3, agent, x1, x2, angles)
    counts = np.asarray(counts, dtype=np.float64)
    return _best_threshold(features, directions, wants_left, counts)[0] / x1.shape[0]


def best_line_plays(encoding: int, region3: int, agent: int, x1: np.ndarray, x2: np.ndarray,
                    angles: int = 720) -> np.ndarray:
    """(points,) True where the agent's best single line (:func:`best_line_shares` with weight 1
    everywhere; of tied lines the first found) plays its part of the rewarded joint action."""
    features, directions, wants_left = _line_search(encoding, region3, agent, x1, x2, angles)
    _, direction, threshold = _best_threshold(features, directions, wants_left, np.ones((1, x1.shape[0])))
    if direction[0] < 0:  # no threshold beats playing L everywhere
        return wants_left.copy()
    return (_projection(features, directions[direction[0]]) > threshold[0]) == wants_left


def _line_search(encoding, region3, agent, x1, x2, angles):
    """The inputs of :func:`_best_threshold`: the agent's contexts without the bias input, the
    directions to try (the second half the first's negatives, exactly), and where the agent's part
    of the rewarded joint action is L."""
    features = np.ascontiguousarray(contexts(encoding, agent, x1, x2)[:, :-1])
    wants_left = best_actions(x1, x2, agent, region3) == lineworld.LEFT
    if features.shape[1] == 1:
        directions = np.array([[1.0], [-1.0]])
    else:
        half = np.column_stack(portable.cos_sin_of_turns(np.arange(angles // 2) / angles))
        directions = np.concatenate([half, -half])
    return features, directions, wants_left


@njit(cache=True)
def _projection(features, direction):
    """features @ direction by hand: numba's matmul needs scipy, and the search and
    :func:`best_line_plays` must round alike."""
    projection = np.zeros(features.shape[0])
    for k in range(features.shape[1]):
        projection += features[:, k] * direction[k]
    return projection


def _best_threshold(features, directions, wants_left, counts):
    """Per row of ``counts``: the largest weighted count of points a rule 'L iff w.x is above the
    threshold' gets right, over every direction w and every threshold between two distinct
    projections (or beyond all of them); with the first best direction's index (-1: L everywhere)
    and its threshold.

    Direction d + D/2 is minus direction d, so its projections are the negatives of d's and its
    order of the points is d's reversed: each sort serves two directions, d's order walked forward
    and backward. The sort is numpy's (stable, many times faster than numba's; within a run of
    equal projections the order does not matter). The counts are whole numbers, so their sums do
    not depend on the order they are added in, and the first best direction is the one a walk over
    d = 0, 1, ... finds."""
    by_point = np.ascontiguousarray(np.asarray(counts, dtype=np.float64).T)  # (points, rows): rows walk together
    half = directions.shape[0] // 2
    left_total = (by_point * wants_left[:, None]).sum(axis=0)  # whole numbers: exact in any order
    found = np.full((2 * half, by_point.shape[1]), -np.inf)
    at = np.zeros_like(found)
    for d in range(half):
        projection = _projection(features, directions[d])
        order = np.argsort(projection, kind="stable")
        _walk(projection, order, wants_left, by_point, left_total, 1.0, found[d], at[d])
        _walk(projection, order[::-1], wants_left, by_point, left_total, -1.0, found[d + half], at[d + half])
    return _first_best(found, at, left_total)


@njit(cache=True)
def _walk(projection, order, wants_left, by_point, left_total, sign, found, at):
    """One direction's split points in ``order`` (ascending ``sign`` x projection), for every row
    of counts at once (``by_point``: points by rows): the largest count right and the first
    threshold reaching it into ``found`` and ``at`` (one per row)."""
    n, rows = order.shape[0], by_point.shape[1]
    right_below, left_above = np.zeros(rows), left_total.copy()
    for i in range(n):
        j = order[i]
        if wants_left[j]:
            for r in range(rows):
                left_above[r] -= by_point[j, r]
        else:
            for r in range(rows):
                right_below[r] += by_point[j, r]
        if i + 1 == n or projection[order[i + 1]] != projection[j]:
            for r in range(rows):
                value = right_below[r] + left_above[r]
                if value > found[r]:
                    found[r], at[r] = value, sign * projection[j]


@njit(cache=True)
def _first_best(found, at, left_total):
    """Per row, the best of ``found`` (directions by rows) if it beats L everywhere
    (``left_total``), the first direction reaching it and its threshold."""
    rows = found.shape[1]
    best = left_total.copy()
    best_direction = np.full(rows, -1, dtype=np.int64)
    best_threshold = np.full(rows, -np.inf)
    for d in range(found.shape[0]):
        for r in range(rows):
            if found[d, r] > best[r]:
                best[r], best_direction[r], best_threshold[r] = found[d, r], d, at[d, r]
    return best, best_direction, best_threshold


REGIONS = (1, 2, 3)
"""The regions of Fig. 5a: 1 (A left of B), 2 (A right of B), 3 (closer than 0.5)."""


def region_shares(correct: np.ndarray, x1: np.ndarray, x2: np.ndarray) -> np.ndarray:
    """(runs, 3) per region of Fig. 5a, the share of its points where the most probable joint
    action is the region's rewarded one, from ``correct`` (runs, 2 agents, points): each agent's
    probability of playing its part. The agents act independently, so the most probable joint
    action is the pair of each agent's most probable action (a tie counts as not playing it):
    the label Fig. 5b gives the cell of the learned lines the point lies in."""
    both = (correct > 0.5).all(axis=1)
    labels = regions(x1, x2)
    return np.column_stack([both[:, labels == k].mean(axis=1) for k in REGIONS])


@functools.lru_cache(maxsize=None)  # a constant of the configuration, asked for by every measure
def best_lines_region_shares(config: SingleGLAConfig, angles: int = 720) -> np.ndarray:
    """(3,) :func:`region_shares` of each agent's best single line (:func:`best_line_plays`, on
    the evaluation grid): what Fig. 5b would show for the best lines the context allows under
    this reward, the ceiling of the learned lines' shares. A's best line is perfect under either
    reading of region 3, so the pair is also the team's best; under 'move_apart' B's two best
    lines (x2 = x1 +- 0.5) tie and, by symmetry, give the same shares. The best lines maximise
    the whole square's share, so in one region a learned pair can exceed them (by giving up
    another, or by the grid's rounding at the borders): a share of the ceiling can pass 1."""
    encoding, region3 = lineworld.encoding_code(config.context), lineworld.region3_code(config.region3_reward)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    plays = np.stack([best_line_plays(encoding, region3, agent, x1, x2, angles) for agent in range(2)])
    shares = region_shares(plays[None].astype(np.float64), x1, x2)[0]
    shares.flags.writeable = False  # cached: shared by every caller
    return shares


def best_response_gap(params: np.ndarray, config: SingleGLAConfig, agent: int, grid: int = 100,
                      angles: int = 180) -> np.ndarray:
    """(runs,) how much the agent's learned line loses against the best line it could draw given
    the other agent's learned line (params: runs, 2 agents, 2 actions, inputs): the share of the
    points of a grid x grid grid where both lines play their parts, for the agent's best line
    (exhaustive search, :func:`best_line_shares`) minus for its learned line. The search is over
    every run, so it uses a coarser grid and fewer directions than :func:`best_line_reward`."""
    correct = _correct_runs(params, replace(config, eval_grid=grid)) > 0.5
    x1, x2 = lineworld.state_grid(grid)
    best = best_line_shares(lineworld.encoding_code(config.context), lineworld.region3_code(config.region3_reward),
                            agent, x1, x2, correct[:, 1 - agent].astype(np.float64), angles)
    return best - (correct[:, 0] & correct[:, 1]).mean(axis=1)


def measure(result: SingleGLAResult) -> dict:
    """Fig. 5's metrics: per region the share where the most probable joint action is the
    region's rewarded one, the same for the best single lines (the ceiling) and the share of the
    ceiling reached; each agent's gap to its best line given the other's; each agent's expected
    reward (policy and learned line) against the best a single line can reach with this context;
    the team's expected and final average reward."""
    config = result.config
    correct = _correct_runs(result.params, config)
    ev = _evaluation(correct)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    per_run = region_shares(correct, x1, x2)
    ceiling = best_lines_region_shares(config)
    of_ceiling = per_run / ceiling
    line_best = [best_line_reward(config.context, agent, config.eval_grid, region3_reward=config.region3_reward)
                 for agent in range(2)]
    measured = {}
    for k, region in enumerate(REGIONS):
        measured[f"region_{region}_share"] = per_run[:, k].mean()
        measured[f"region_{region}_ceiling"] = ceiling[k]
        measured[f"region_{region}_share_of_ceiling"] = of_ceiling[:, k].mean()
        measured[f"region_{region}_share_of_ceiling_lowest_run"] = of_ceiling[:, k].min()
    gaps = [best_response_gap(result.params, config, agent).mean() for agent in range(2)]
    return measured | {
        "agent_a_best_response_gap": gaps[0],
        "agent_b_best_response_gap": gaps[1],
        "agent_a_reward": ev.agent_reward[:, 0].mean(),
        "agent_b_reward": ev.agent_reward[:, 1].mean(),
        "agent_a_line_reward": ev.line_reward[:, 0].mean(),
        "agent_b_line_reward": ev.line_reward[:, 1].mean(),
        "best_line_a": line_best[0],
        "best_line_b": line_best[1],
        "agent_a_line_gap": line_best[0] - ev.line_reward[:, 0].mean(),
        "agent_b_line_gap": line_best[1] - ev.line_reward[:, 1].mean(),
        "team_reward": ev.team_reward.mean(),
        "final_average_reward": final_per_run(result.reward).mean(),
    }


def claim_rows(result: SingleGLAResult) -> list[dict]:
    """The Fig. 5 claims (data/chapter/section4.json) with verdicts computed from ``result``."""
    return claims.verdicts(claims.load("single_gla"), measure(result))


def typical_run(result: SingleGLAResult) -> int:
    """The run whose team reward is the median one (the 'typical result' of Fig. 5b)."""
    team = evaluate(result).team_reward
    return int(np.argsort(team, kind="stable")[(team.shape[0] - 1) // 2])


B_BEST_LINE_OFFSETS = (-0.5, 0.5)
"""Agent B's best single lines in the joint context are x2 = x1 + c for these c (tied): B's
rewarded action depends only on x2 - x1 (L above 0.5 and in (-0.5, 0), R elsewhere), and a
threshold at either band edge gets all but one band of width 0.5 right (share 25/32; the
exhaustive search of :func:`best_line_reward` finds no better line)."""


def learned_line(result: SingleGLAResult, run_index: int, agent: int) -> tuple[float, float]:
    """(slope, intercept) of the agent's learned line (h(u_L) - h(u_R)).x = 0 (eq. 14-15) as
    x2 = slope x1 + intercept, for the joint context; the agent prefers L above it when the x2
    weight is positive."""
    if result.config.context != "joint":
        raise UserError(f"learned lines live in the (x1, x2) plane: they need the joint context, "
                         f"this result used {result.config.context!r}")
    hu = bounded(result.params[run_index, agent], result.config)
    w = hu[0] - hu[1]
    return float(-w[0] / w[1]), float(-w[2] / w[1])


def bounded(u: np.ndarray, config: SingleGLAConfig) -> np.ndarray:
    """h(u) of eq. 14, the parameters eq. 15 actually uses."""
    clipped = np.clip(u, -config.L, config.L)
    if config.bounding == "clip":
        return clipped
    return np.where(np.abs(u) >= config.L, clipped, 0.0)
