"""What a result of the gridworld experiment says (Section 5.3): the numbers the chapter's claims
are about (:func:`measure`) and their verdicts, what 2observe's GLAs learned, the optimum the
learners are drawn against, and the notebook's text tables."""

import functools
import math
from dataclasses import replace

import numpy as np

from glamas import claims as chapter, training
from glamas import gla
from glamas.curves import (CONVERGENCE_TOLERANCE, DEFINITIONS, FINAL_FRACTION, coarsened, ratio,
                           convergence_episode, convergence_episodes, convergence_grid, convergence_ratio,
                           earlier_share, final, grid_verdict, interval_verdict, level_episode)
from glamas.experiments.gridworld.experiment import GridworldConfig, GridworldResult
from glamas.gridworld import GridMap, dp, rules
from glamas.learners import episode as ep
from glamas.learners import registry, two_observe
from glamas.portable import weighted_sum
from glamas.tables import Table


ZERO_COLLISIONS = 0.05
"""The learning curves' "zero collisions": at most one collision per 20 episodes. Exploration
keeps a learner that has found a collision-free path colliding now and then."""
CURVE_COLLISION_CLAIMS = ("mmdp_no_collisions", "two_observe_no_collisions")
"""The claims of zero collisions judged on Fig. 12a's learning curves, at a level of collisions per
episode (their threshold in data/chapter/section5.json)."""
ZERO_COLLISION_LEVELS = (0.02, 0.05, 0.1)
"""The levels of "zero collisions" the notebook shows the fast-to-zero claims at."""
COMPLETION = 0.95
"""A greedy policy is a solution when at least this share of its evaluation's episodes end with
every agent in its goal (before the step cap): a policy trapped short of the goal, colliding or
not, has found no solution."""
SATURATED = 1e-3
"""A GLA is saturated at a distance when its less likely choice has probability below this:
eq. 13's gradient, proportional to that probability, has all but vanished there."""


def curve_collision_claims() -> list[chapter.Claim]:
    """The claims of CURVE_COLLISION_CLAIMS as data/chapter holds them (their level: ``threshold``)."""
    return [claim for claim in chapter.load("gridworld") if claim.id in CURVE_COLLISION_CLAIMS]


def measure(result: GridworldResult, final_share: float = FINAL_FRACTION, zero_level: float = ZERO_COLLISIONS,
            tolerance: float | None = None, blocks: int = 1) -> dict:
    """The numbers the chapter's claims are about (data/chapter/section5.json), per learner and
    compared, at the measurement choices of docs/verdicts.md: final values over the last
    ``final_share`` of the episodes, "zero collisions" at ``zero_level``, and the convergence
    comparisons at every tolerance and block width (:func:`convergence_comparison`) or, given a
    ``tolerance``, at that one and ``blocks`` (:func:`convergence_at`)."""
    m = {}
    x = result.episodes
    for name in result.names():
        m[f"steps_{name}"] = final(result.steps(name), x, final_share)
        m[f"reward_{name}"] = final(result.reward(name), x, final_share)
        m[f"collisions_{name}"] = final(result.curves(name, "collisions"), x, final_share)
        m[f"coordinations_{name}"] = final(result.curves(name, "coordinations"), x, final_share)
        m[f"convergence_{name}"] = float(np.median(convergence_episodes(result.steps(name), x)))
        m[f"zero_collisions_after_{name}"] = zero_collisions_after(result, name, zero_level)
        m[f"capped_episodes_{name}"] = float(weighted_sum(result.curves(name, "capped").mean(axis=0), result.widths()))
        m.update(evaluation_measures(result, name))
    if "two_observe" in result.names():
        m.update(first_level_shares(result))
    if {"two_observe", "independent", "mmdp"} <= set(result.names()):
        for base in ("independent", "mmdp"):
            m[f"steps_two_observe_minus_{base}"] = m["steps_two_observe"] - m[f"steps_{base}"]
            m.update(convergence_metrics(result, "two_observe", base, tolerance, blocks))
        m["reward_two_observe_over_mmdp"] = ratio(m["reward_two_observe"], m["reward_mmdp"])
        m["reward_two_observe_minus_independent"] = m["reward_two_observe"] - m["reward_independent"]
        m["collisions_independent_off_3"] = abs(m["collisions_independent"] - 3.0)
        m["coordinations_two_observe_off_4"] = abs(m["coordinations_two_observe"] - 4.0)
    return m


def evaluation_measures(result: GridworldResult, name: str) -> dict:
    """What learner ``name`` learned, evaluated with learning off (glamas.training.EVALUATIONS),
    means over runs: steps, reward, collisions, coordinations and completion of the greedy policy
    and of the frozen tables under the training's exploration; collisions per perturbation (the
    perturbed evaluation's collisions per random action); and ``greedy_solution_collisions``: the
    greedy collisions per episode of a policy that completes (COMPLETION), infinite for one that
    does not, so that a trapped policy never passes as collision-free."""
    m = {}
    for mode in ("greedy", "exploring"):
        for metric in ("steps", "reward", "collisions", "coordinations", "completion"):
            m[f"{mode}_{metric}_{name}"] = float(result.evaluation(name, metric, mode).mean())
    completed = m[f"greedy_completion_{name}"] >= COMPLETION
    m[f"greedy_solution_collisions_{name}"] = m[f"greedy_collisions_{name}"] if completed else math.inf
    m[f"collisions_per_perturbation_{name}"] = (collisions_per_perturbation(result, name) if completed
                                                else math.nan)  # no solution to perturb
    return m


def collisions_per_perturbation(result: GridworldResult, name: str) -> float:
    """The collisions a random action adds to the greedy policy: the perturbed evaluation's
    (glamas.training.evaluation_of: about one random action per episode) collisions beyond the
    greedy one's, per random action, over all runs: how robust the learned solution is to one wrong move."""
    exploit = result.config.evaluation().exploits[training.EVALUATIONS.index("perturbed")]
    rows = result.evaluated[result.names().index(name), :, training.EVALUATIONS.index("perturbed")]
    random_actions = (1.0 - exploit) * float(rows[:, :result.config.gridmap().n_agents].sum())  # agent-steps
    extra = ep.metric(rows, "collisions") - result.evaluation(name, "collisions")
    return ratio(float(extra.sum()), random_actions)


def evaluation_table(result: GridworldResult) -> Table:
    """Per learner, what it learned evaluated with learning off (:func:`evaluation_measures`, means
    over runs): the greedy policy's steps, reward, collisions, coordinations and completion; the
    frozen tables' collisions under the training's exploration; collisions per perturbation."""
    m = measure(result)
    return Table(["learner", "steps", "reward", "collisions", "coord.", "completed", "exploring", "per perturbation"],
                 [[registry.label(name), f"{m[f'greedy_steps_{name}']:.2f}", f"{m[f'greedy_reward_{name}']:.1f}",
                   f"{m[f'greedy_collisions_{name}']:.3f}", f"{m[f'greedy_coordinations_{name}']:.2f}",
                   f"{m[f'greedy_completion_{name}']:.0%}", f"{m[f'exploring_collisions_{name}']:.3f}",
                   chapter.value_text(m[f'collisions_per_perturbation_{name}'], 3, 'no solution')]
                  for name in result.names()])


BOUNCE_READINGS = {"previous": "bounce to the previous cell", "start": "bounce to the start cell"}
"""The readings of Sec. 5.3's "bounced back to their original position" (GridworldConfig.bounce) by
name, as a verdict names them."""


def claim_rows(result: GridworldResult, readings: dict | None = None) -> list[dict]:
    """The chapter's Section 5.3 claims with their verdicts, computed from ``result`` at every
    measurement choice of their rules and under the results of the other readings (``readings``:
    name -> result; :func:`glamas.experiments.gridworld.other_bounce`)."""
    other = {name: functools.partial(measure, found) for name, found in (readings or {}).items()}
    return chapter.verdicts(chapter.load("gridworld"), functools.partial(measure, result), readings=other,
                            reading=BOUNCE_READINGS[result.config.bounce])


def convergence_metrics(result: GridworldResult, name: str, base: str, tolerance: float | None = None,
                        blocks: int = 1) -> dict:
    """:func:`convergence_comparison`, or given a ``tolerance`` only the claim's metric at it and
    ``blocks`` (:func:`convergence_at`): a measurement choice of docs/verdicts.md."""
    if tolerance is None and blocks == 1:
        return convergence_comparison(result, name, base)
    return convergence_at(result, name, base, CONVERGENCE_TOLERANCE if tolerance is None else tolerance, blocks)


def convergence_at(result: GridworldResult, name: str, base: str, tolerance: float, blocks: int) -> dict:
    """``convergence_<name>_over_<base>``: the per-run ratio of convergence episodes on blocks
    ``blocks`` times the stored width at ``tolerance``, NaN (undecidable) when its 95 % interval
    contains 1; with the reason."""
    key = f"convergence_{name}_over_{base}"
    curves, ends = coarsened(result.steps(name), result.episodes, blocks)
    baseline, _ = coarsened(result.steps(base), result.episodes, blocks)
    point, low, high = convergence_ratio(curves, baseline, ends, "per_run", tolerance)
    return _decided(key, point, low, high)


def _decided(key: str, point: float, low: float, high: float) -> dict:
    """``key``: the ratio ``point`` where its interval [low, high] excludes 1, else NaN with the reason."""
    if interval_verdict(low, high) != "undecidable":
        return {key: point}
    return {key: math.nan,
            f"{key}{chapter.WHY_UNDECIDABLE}": f"ratio {point:.2f}, but its 95 % interval [{low:.2f}, {high:.2f}] contains 1"}


def convergence_comparison(result: GridworldResult, name: str, base: str) -> dict:
    """"``name`` converges faster than ``base``" under every definition of curves.DEFINITIONS, each
    at every tolerance and block width of curves.convergence_grid. ``convergence_<name>_over_<base>``
    decides the claims: the per-run ratio at the default tolerance and blocks, NaN (undecidable)
    when its 95 % interval contains 1 (the claims are judged at every other tolerance and block
    width as measurement choices of docs/verdicts.md); with ``_point``, ``_low``, ``_high`` and
    ``_verdict`` (the grid's: the verdict every tolerance and block width gives, or undecidable). The
    run-mean and shared-level definitions are kept beside it (suffixes ``_run_mean``,
    ``_shared_level``), and ``..._earlier_share`` is the share of run pairs in which ``name``'s run
    converges first."""
    key, x = f"convergence_{name}_over_{base}", result.episodes
    curves, baseline = result.steps(name), result.steps(base)
    m = {}
    for definition in DEFINITIONS:
        label = key if definition == "per_run" else f"{key}_{definition}"
        point, low, high = convergence_ratio(curves, baseline, x, definition)
        grid = convergence_grid(curves, baseline, x, definition)
        verdict = grid_verdict(grid)
        m.update({f"{label}_point": point, f"{label}_low": low, f"{label}_high": high, f"{label}_verdict": verdict})
        m.update(_decided(label, point, low, high))
    m[f"{key}_earlier_share"] = earlier_share(curves, baseline, x)
    return m


def zero_collisions_after(result: GridworldResult, name: str, level: float = ZERO_COLLISIONS) -> float:
    """The share of the run after which learner ``name``'s mean collisions per episode stay at or
    below ``level`` (1: they end above it, the learner never settles at zero collisions)."""
    return level_episode(result.curves(name, "collisions"), result.episodes, level) / result.episodes[-1]


def in_range_distances(gridmap: GridMap) -> tuple[np.ndarray, np.ndarray]:
    """The distances at which two agents could collide in one step from some pair of cells (in
    range of interference), and those at which they never can (out of range), on ``gridmap``."""
    share = in_range_share(gridmap)
    deltas = np.arange(share.size)
    seen = ~np.isnan(share)
    return deltas[seen & (share > 0)], deltas[seen & (share == 0) & (deltas > 0)]


def first_level_shares(result: GridworldResult) -> dict:
    """What 2observe's GLAs learned, GLA by GLA (Sec. 5.1: the first level decides whether the
    agents are within each other's range of interference): the share of final GLAs that coordinate
    (P(coordinate) > 1/2) at every in-range distance, that act alone at every out-of-range one,
    and the share of GLAs saturated on the wrong choice somewhere (:func:`stuck_share`) at the
    start of the runs and at their end."""
    config = result.config
    near, far = in_range_distances(config.gridmap())
    u, u_initial = result.output("two_observe", "u"), result.output("two_observe", "u_initial")
    p_near = coordination_probabilities(u, config, near)
    p_far = coordination_probabilities(u, config, far)
    return {"coordinates_in_range_share_two_observe": float((p_near > 0.5).all(axis=-1).mean()),
            "alone_out_of_range_share_two_observe": float((p_far < 0.5).all(axis=-1).mean()),
            "stuck_at_start_share_two_observe": stuck_share(u_initial, config),
            "stuck_at_end_share_two_observe": stuck_share(u, config)}


def stuck_share(u: np.ndarray, config: GridworldConfig) -> float:
    """The share of the GLAs ``u`` (runs, agents, 2, 2) that :func:`stuck_glas` finds stuck."""
    return float(stuck_glas(u, config).mean())


def stuck_glas(u: np.ndarray, config: GridworldConfig) -> np.ndarray:
    """bool (runs, agents): the GLAs ``u`` (runs, agents, 2, 2) saturated (SATURATED) on the wrong
    choice at some distance of the map: acting alone where the agents could collide, or
    coordinating where they cannot. From there eq. 13 can hardly bring them back."""
    near, far = in_range_distances(config.gridmap())
    wrong_near = coordination_probabilities(u, config, near) < SATURATED
    wrong_far = coordination_probabilities(u, config, far) > 1.0 - SATURATED
    return wrong_near.any(axis=-1) | wrong_far.any(axis=-1)


def stuck_by_start(result: GridworldResult) -> dict:
    """How 2observe's GLAs that end stuck (:func:`stuck_glas`) started: counts of all GLAs, of those
    saturated on a wrong choice at the start, of those stuck at the end, and of those both."""
    config = result.config
    start = stuck_glas(result.output("two_observe", "u_initial"), config)
    end = stuck_glas(result.output("two_observe", "u"), config)
    return {"GLAs": int(start.size), "saturated at the start": int(start.sum()),
            "stuck at the end": int(end.sum()), "stuck at the end, saturated at the start": int((start & end).sum())}


def summary_table(result: GridworldResult) -> Table:
    """Final values (last 10 % of the episodes, mean over runs) and convergence episode (median
    over runs of each run's own, curves.convergence_episodes) per learner,
    rounded to what 20 runs resolve."""
    m = measure(result)
    return Table(["learner", "steps", "reward", "collisions", "coordinations", "converged by", "capped/run"],
                 [[registry.label(name), f"{m[f'steps_{name}']:.2f}", f"{m[f'reward_{name}']:.1f}",
                   f"{m[f'collisions_{name}']:.3f}", f"{m[f'coordinations_{name}']:.2f}",
                   f"{m[f'convergence_{name}']:.0f}", f"{m[f'capped_episodes_{name}']:.1f}"] for name in result.names()])


def with_learner(result: GridworldResult, other: GridworldResult, name: str) -> GridworldResult:
    """``result`` with learner ``name``'s curves and own outputs taken from ``other`` (to compare a
    variant of one learner against the same baselines)."""
    k, j = result.names().index(name), other.names().index(name)
    log, evaluated = result.log.copy(), result.evaluated.copy()
    log[k], evaluated[k] = other.log[j], other.evaluated[j]
    own = {**result.own, **({name: other.own[name]} if name in other.own else {})}
    return replace(result, log=log, evaluated=evaluated, own=own)


def state_action_table(result: GridworldResult) -> str:
    """:func:`state_action_spaces` as text: the measured counterpart of Table 1 for this map."""
    lines = [f"{'learner':24s} {'Q tables':>8s} {'states':>7s} {'actions':>7s} {'Q entries/agent':>15s} {'GLA params/agent':>16s}"]
    for row in state_action_spaces(result):
        lines.append(f"{registry.label(row['learner']):24s} {row['tables']:8d} {row['states']:7d} {row['actions']:7d} "
                     f"{row['q_entries_per_agent']:15.0f} {row['gla_parameters_per_agent']:16d}")
    return "\n".join(lines)


def state_action_spaces(result: GridworldResult) -> list[dict]:
    """Table 1 / Sec. 5.3 analysis, measured from the learners' final tables: per learner the
    number of Q tables, their states and actions, the Q entries per agent and the GLA parameters."""
    rows = []
    gridmap = result.config.gridmap()
    for name, (tables, states, actions) in zip(result.names(), result.table_shapes):
        q_per_agent = tables * states * actions / gridmap.n_agents
        gla_per_agent = registry.get(name).gla_parameters(result.config.setup(name), gridmap) // gridmap.n_agents
        rows.append({"learner": name, "tables": int(tables), "states": int(states),
                     "actions": int(actions), "q_entries_per_agent": q_per_agent,
                     "gla_parameters_per_agent": gla_per_agent})
    return rows


def coordination_probability(result: GridworldResult, config: GridworldConfig, deltas) -> np.ndarray:
    """P(coordinate | delta) of 2observe's final GLAs (eq. 15), shape (runs, agents, len(deltas))."""
    return coordination_probabilities(result.output("two_observe", "u"), config, deltas)


def coordination_probabilities(u: np.ndarray, config: GridworldConfig, deltas) -> np.ndarray:
    """P(coordinate | delta) (eq. 15) of the GLA parameters ``u`` (runs, agents, 2, 2), shape
    (runs, agents, len(deltas)) under 2observe's settings in ``config``; under the fixed rule
    (``rule_distance``), its 0 or 1."""
    settings, gridmap = first_level_settings(config), config.gridmap()
    if settings.rule_distance is not None:
        rule = (np.asarray(deltas) < settings.rule_distance).astype(float)
        return np.broadcast_to(rule, u.shape[:2] + rule.shape).copy()
    p = two_observe.gla_params(settings, gridmap)
    scale = two_observe.delta_scale(settings.gla_delta_scale, gridmap)
    contexts = [np.array([delta * scale, 1.0]) for delta in deltas]
    probs = np.empty(2)
    out = np.empty(u.shape[:2] + (len(deltas),))
    for r in range(u.shape[0]):
        for i in range(u.shape[1]):
            for d, x in enumerate(contexts):
                gla.boltzmann(u[r, i], x, p.temperature, p.L, p.bounding_code, probs)
                out[r, i, d] = probs[two_observe.COORDINATE]
    return out


def first_level_settings(config: GridworldConfig) -> two_observe.GLASettings:
    """2observe's own settings in ``config`` (its defaults if it is not trained there)."""
    return config.setup("two_observe").own


def optimum(config: GridworldConfig) -> dict | None:
    """The reference the learners are drawn against: the episode of the optimal joint policy
    (value iteration on the MMDP, gamma = the Q-learners' discount), agent means, no exploration;
    None where the joint MMDP is too large to tabulate (:func:`glamas.gridworld.dp.tabulable`)."""
    gridmap = config.gridmap()
    if not dp.tabulable(gridmap):
        return None
    episode = dp.optimal_rollout(gridmap, config.q.discount, config.bounce, rewards=config.rewards)
    return {"steps": float(episode.steps_to_goal.mean()), "reward": float(episode.returns.mean()),
            "collisions": float(episode.collisions)}


def in_range_share(gridmap: GridMap) -> np.ndarray:
    """Per distance delta (0 .. rows + cols - 2): the share of ordered pairs of distinct usable
    cells at that distance from which two agents could collide in one step (NaN where no pair is)."""
    usable = np.flatnonzero(~(gridmap.is_goal | gridmap.blocked))
    a, b = np.meshgrid(usable, usable, indexing="ij")
    a, b = a[a != b], b[a != b]
    delta = np.abs(a // gridmap.n_cols - b // gridmap.n_cols) + np.abs(a % gridmap.n_cols - b % gridmap.n_cols)
    in_range = rules.in_range_table(gridmap.next_cell, gridmap.is_goal)[a, b]
    n_deltas = gridmap.n_rows + gridmap.n_cols - 1
    with np.errstate(invalid="ignore"):
        return (np.bincount(delta, weights=in_range, minlength=n_deltas)
                / np.bincount(delta, minlength=n_deltas))


def convergence_report(result: GridworldResult) -> str:
    """"2observe converges faster" against each baseline under every definition of
    curves.DEFINITIONS at every block width and tolerance of curves.convergence_grid: the ratio of
    the convergence episodes, its 95 % interval over runs and its verdict; per definition, the
    verdict that none of them moves (per_run decides the claims)."""
    lines = [f"{'against':24s} {'definition':13s} {'blocks':>6s} {'tolerance':>9s} {'ratio':>7s} "
             f"{'95 % interval':>16s}  verdict"]
    for base in ("independent", "mmdp"):
        for definition in DEFINITIONS:
            grid = convergence_grid(result.steps("two_observe"), result.steps(base), result.episodes, definition)
            for factor, tolerance, point, low, high in grid:
                lines.append(f"{registry.label(base):24s} {definition:13s} {f'x{factor}':>6s} {tolerance:9.0%} "
                             f"{point:7.3f} [{low:6.3f}, {high:6.3f}]  {interval_verdict(low, high)}")
            lines.append(f"{registry.label(base):24s} {definition:13s} {'all':>6s} {'all':>9s} {'':7s} {'':16s}  "
                         f"{grid_verdict(grid)}")
    return "\n".join(lines)


def convergence_spread(result: GridworldResult) -> str:
    """Per learner: the episode after which its run-mean steps curve stays within 5 % of its final
    value, beside the quartiles over runs of each run's own convergence episode."""
    x = result.episodes
    lines = [f"{'learner':24s} {'mean curve settles':>18s} {'runs settle: 25 %':>18s} {'median':>7s} {'75 %':>7s}"]
    for name in result.names():
        quartiles = np.percentile(convergence_episodes(result.steps(name), x), [25, 50, 75])
        lines.append(f"{registry.label(name):24s} {convergence_episode(result.steps(name), x):18.0f} "
                     + " ".join(f"{q:{w}.0f}" for q, w in zip(quartiles, (18, 7, 7))))
    return "\n".join(lines)


def zero_collisions_table(result: GridworldResult) -> str:
    """Per learner, the share of the run after which its mean collisions per episode stay at or
    below each level of ZERO_COLLISION_LEVELS (1.000: they end above it)."""
    lines = [f"{'learner':24s} " + " ".join(f"{'<= ' + format(level, 'g'):>8s}" for level in ZERO_COLLISION_LEVELS)]
    for name in result.names():
        lines.append(f"{registry.label(name):24s} "
                     + " ".join(f"{zero_collisions_after(result, name, level):8.3f}" for level in ZERO_COLLISION_LEVELS))
    return "\n".join(lines)


def need_probability(result: GridworldResult) -> np.ndarray:
    """P(need | delta) over 2observe's observed steps, pooled over runs (NaN where a distance
    never occurred): under the symmetric table, coordinating pays where it is above 1/2."""
    counts = result.output("two_observe", "need_counts").sum(axis=0)
    seen = counts.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(seen > 0, counts[:, 1] / seen, np.nan)
