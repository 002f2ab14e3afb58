"""The gridworld experiment of the chapter's Section 5.3 (Fig. 9-12): independent Q-learners,
joint-state learners, the MMDP learner and 2observe (Alg. 4) on the TunnelToGoal map.

``run`` trains every learner for ``episodes`` episodes in ``runs`` independent runs, ``measure``
turns the binned learning curves into the numbers the chapter's claims are about, and the
``plot_*`` functions draw Fig. 10-12 and the analyses on a given matplotlib Axes.
"""

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from matplotlib.ticker import NullFormatter

from glamas import checks, gla, memory, parallel, results
from glamas import claims as chapter
from glamas.curves import (DEFINITIONS, convergence_episode, convergence_episodes, convergence_grid,
                           convergence_ratio, earlier_share, final, grid_verdict, interval_verdict,
                           level_episode, ratio)
from glamas.errors import UserError
from glamas.experiments.registry import Experiment, register
from glamas.gridworld import GridMap, dp, load_map, rules
from glamas.learners import episode as ep
from glamas.learners import registry, spec, two_observe
from glamas.learners.settings import LearningSettings
from glamas.paths import MAPS, RESULTS
from glamas.plotting import drawn_underneath, legend_below, learner_style, plot_mean_band

LEARNERS = registry.family("chapter")
"""The learners this experiment trains: the chapter's (glamas.learners.registry), in the order
their seeds are drawn."""


@dataclass(frozen=True)
class GridworldConfig(LearningSettings):
    """Settings of the Section 5.3 experiment: the learners' settings
    (:class:`glamas.learners.settings.LearningSettings`), plus the map, the learners and the schedule."""

    map_file: str = "tunnel_to_goal.txt"
    """Map file (data/maps format), a name in data/maps or a path; Fig. 9 is TunnelToGoal."""
    learners: tuple = LEARNERS
    """Which learners to train, a subset of independent, joint_state, mmdp, two_observe."""
    episodes: int = 200_000
    """Episodes ("iterations": until both agents are in the goal) per run (Sec. 5.3)."""
    runs: int = 20
    """Independent runs averaged (not stated in the chapter)."""
    bins: int = 200
    """Points of the learning curves: blocks of episodes with log-spaced ends (the first blocks
    one episode wide), so that learning in the first episodes is resolved (glamas.learners.episode)."""

    def __post_init__(self):
        super().__post_init__()
        checks.whole_numbers(self, {"episodes": 1, "runs": 1, "bins": 1})
        learners = tuple(self.learners)
        if not learners or len(set(learners)) != len(learners) or not set(learners) <= set(LEARNERS):
            raise UserError(f"learners must be distinct names from {LEARNERS}, got {self.learners!r}")
        object.__setattr__(self, "learners", learners)
        gridmap = self.gridmap()
        if gridmap.n_agents != 2:
            raise UserError(f"the learners are written for two agents; map {self.map_file!r} has {gridmap.n_agents}")

    def gridmap(self) -> GridMap:
        """The map: ``map_file`` as a path, or as a name in data/maps."""
        path = Path(self.map_file)
        return load_map(path if path.is_file() or path.parent != Path(".") else MAPS / path)

    def edges(self) -> np.ndarray:
        """The learning curves' block edges (glamas.learners.episode.log_edges)."""
        return ep.log_edges(self.episodes, self.bins)

    def schedule(self) -> ep.Schedule:
        return ep.Schedule(self.episodes, self.edges(), self.max_steps)

    def memory_bytes(self) -> int:
        """Bytes of every learner's runs: their tables and logs (:func:`learner_bytes`)."""
        gridmap = self.gridmap()
        return self.runs * sum(learner_bytes(name, self, gridmap, self.bins) for name in self.learners)

    def delta_scale(self) -> float:
        """What the GLA context multiplies delta by (``gla_delta_scale``) on this map."""
        return two_observe.delta_scale(self.gla_delta_scale, self.gridmap())


def learner_bytes(name: str, settings, gridmap: GridMap, bins: int) -> int:
    """Bytes one run of learner ``name`` allocates: its tables (with the runner's working copy) and its log."""
    tables = registry.get(name).bytes_per_run(settings, gridmap)
    return tables * memory.WORKING_COPIES + bins * ep.n_columns(gridmap.n_agents) * memory.BYTES_PER_VALUE


@dataclass(frozen=True)
class GridworldResult:
    """Learning curves (block means over episodes) and final learned structures, all arrays."""

    config: GridworldConfig
    """The configuration that produced the arrays."""
    learners: np.ndarray
    """int (n_learners,): index into LEARNERS of each learner, in the order of the other arrays."""
    log: np.ndarray
    """(n_learners, runs, bins, columns): block means of the per-episode measurements; columns
    as in glamas.learners.episode (steps and reward per agent, length, collisions, coordinations, capped)."""
    table_shapes: np.ndarray
    """int (n_learners, 3): (tables, states, actions) of each learner's final Q tables."""
    gla_parameters: np.ndarray
    """(runs, agents, 2 actions, 2 inputs): 2observe's final GLA parameters (zeros if not run)."""
    gla_initial: np.ndarray
    """(runs, agents, 2 actions, 2 inputs): the GLA parameters 2observe's runs started from
    (zeros if not run)."""
    need_counts: np.ndarray
    """(runs, deltas, 2): 2observe's observing agent-steps per distance delta without / with need
    (``gla_need``; zeros if not run)."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block (the curves' x axis)."""

    def widths(self) -> np.ndarray:
        """int (bins,): episodes per block."""
        return np.diff(self.episodes, prepend=0)

    def names(self) -> list[str]:
        return [LEARNERS[k] for k in self.learners]

    def curves(self, learner: str, metric: str) -> np.ndarray:
        """(runs, bins) block means of one metric of glamas.learners.episode.METRICS for one
        learner (steps and reward: means of both agents)."""
        return ep.metric(self.log[self.names().index(learner)], metric)

    def steps(self, learner: str) -> np.ndarray:
        """(runs, bins): steps to the goal, averaged over both agents (Fig. 11a)."""
        return self.curves(learner, "steps")

    def reward(self, learner: str) -> np.ndarray:
        """(runs, bins): undiscounted reward per episode, averaged over both agents (Fig. 11b)."""
        return self.curves(learner, "reward")


def run(config: GridworldConfig = GridworldConfig(), seed: int = 0, workers=None,
        progress=None) -> GridworldResult:
    """Train every learner of ``config`` in ``config.runs`` runs, all learners' runs on one pool of
    workers (:func:`glamas.parallel.run_many`).

    Each learner draws its runs' streams from its own master seed
    (:func:`glamas.learners.registry.master_seed` over LEARNERS): every (seed, learner) pair has
    its own streams, and a learner gets the same streams whichever other learners are trained with it.
    """
    work = trainings(config, seed)
    parallel.run_many([batch for batch, _ in work], workers=workers, progress=progress)
    return result_of(config, [outputs for _, outputs in work], seed)


def trainings(config: GridworldConfig, seed: int = 0) -> list:
    """Per learner of ``config``: its runs, ready to run (glamas.parallel.Batch), and the outputs they fill."""
    gridmap, schedule = config.gridmap(), config.schedule()
    return [spec.batch(registry.get(name), config, gridmap, schedule, config.runs,
                       registry.master_seed(seed, LEARNERS, name)) for name in config.learners]


def result_of(config: GridworldConfig, outputs: list, seed: int = 0) -> GridworldResult:
    """The result of ``config`` and ``seed`` from its learners' filled outputs (:func:`trainings`,
    in order)."""
    gridmap = config.gridmap()
    first_level = {key: np.stack([zeros] * config.runs) for key, zeros in two_observe.outputs(config, gridmap).items()}
    for learned in outputs:
        first_level.update({key: learned[key] for key in first_level.keys() & learned.keys()})
    initial = np.zeros_like(first_level["u"])
    if "two_observe" in config.learners:
        initial = two_observe.initial_parameters(config, gridmap, registry.master_seed(seed, LEARNERS, "two_observe"),
                                                 config.runs)
    codes = np.array([LEARNERS.index(name) for name in config.learners], dtype=np.int64)
    return GridworldResult(config=config, learners=codes, log=np.stack([learned["log"] for learned in outputs]),
                           table_shapes=np.array([learned["q"].shape[1:] for learned in outputs], dtype=np.int64),
                           gla_parameters=first_level["u"], gla_initial=initial,
                           need_counts=first_level["need_counts"],
                           episodes=config.edges()[1:])


def load(config: GridworldConfig = GridworldConfig(), seed: int = 0, results_dir: Path = RESULTS) -> GridworldResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


ZERO_COLLISIONS = 0.05
"""The learning curves' "zero collisions": at most one collision per 20 episodes. Exploration
keeps a learner that has found a collision-free path colliding now and then."""
ZERO_COLLISION_LEVELS = (0.02, 0.05, 0.1)
"""The levels of "zero collisions" the notebook shows the fast-to-zero claims at."""
SATURATED = 1e-3
"""A GLA is saturated at a distance when its less likely choice has probability below this:
eq. 13's gradient, proportional to that probability, has all but vanished there."""


def measure(result: GridworldResult) -> dict:
    """The numbers the chapter's claims are about (data/chapter/section5.json), per learner and compared."""
    m = {}
    x = result.episodes
    for name in result.names():
        m[f"steps_{name}"] = final(result.steps(name), x)
        m[f"reward_{name}"] = final(result.reward(name), x)
        m[f"collisions_{name}"] = final(result.curves(name, "collisions"), x)
        m[f"coordinations_{name}"] = final(result.curves(name, "coordinations"), x)
        m[f"convergence_{name}"] = float(np.median(convergence_episodes(result.steps(name), x)))
        m[f"zero_collisions_after_{name}"] = zero_collisions_after(result, name)
        m[f"capped_episodes_{name}"] = float(result.curves(name, "capped").mean(axis=0) @ result.widths())
    if "two_observe" in result.names():
        m.update(first_level_shares(result))
    if {"two_observe", "independent", "mmdp"} <= set(result.names()):
        for base in ("independent", "mmdp"):
            m[f"steps_two_observe_minus_{base}"] = m["steps_two_observe"] - m[f"steps_{base}"]
            m.update(convergence_comparison(result, "two_observe", base))
        m["reward_two_observe_over_mmdp"] = ratio(m["reward_two_observe"], m["reward_mmdp"])
        m["reward_two_observe_minus_independent"] = m["reward_two_observe"] - m["reward_independent"]
        m["collisions_independent_off_3"] = abs(m["collisions_independent"] - 3.0)
        m["coordinations_two_observe_off_4"] = abs(m["coordinations_two_observe"] - 4.0)
    return m


def convergence_comparison(result: GridworldResult, name: str, base: str) -> dict:
    """"``name`` converges faster than ``base``" under every definition of curves.DEFINITIONS, each
    at every tolerance and block width of curves.convergence_grid. ``convergence_<name>_over_<base>``
    decides the claims: the per-run ratio at the default tolerance and blocks, NaN (undecidable)
    unless every tolerance and block width gives the same verdict, so that none of them can move
    it; with ``_point``, ``_low``, ``_high`` and ``_verdict`` (the grid's). The run-mean and
    shared-level definitions are kept beside it (suffixes ``_run_mean``, ``_shared_level``), and
    ``..._earlier_share`` is the share of run pairs in which ``name``'s run converges first."""
    key, x = f"convergence_{name}_over_{base}", result.episodes
    curves, baseline = result.steps(name), result.steps(base)
    m = {}
    for definition in DEFINITIONS:
        label = key if definition == "per_run" else f"{key}_{definition}"
        point, low, high = convergence_ratio(curves, baseline, x, definition)
        grid = convergence_grid(curves, baseline, x, definition)
        verdict = grid_verdict(grid)
        m.update({f"{label}_point": point, f"{label}_low": low, f"{label}_high": high, f"{label}_verdict": verdict})
        m[label] = point if verdict != "undecidable" else math.nan
        if verdict == "undecidable":
            counts = {v: sum(interval_verdict(low, high) == v for *_, low, high in grid) for v in ("faster", "undecidable", "slower")}
            m[f"{label}{chapter.WHY_UNDECIDABLE}"] = (
                f"ratio {point:.2f} [{low:.2f}, {high:.2f}], but over tolerances of 3 to 15 % and blocks 1 to 4 "
                f"times as wide the 95 % intervals say faster {counts['faster']}, undecidable "
                f"{counts['undecidable']} and slower {counts['slower']} times")
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


def chapter_settings(result: GridworldResult) -> GridworldConfig:
    """The chapter learners' settings that made ``result`` (a related-work result keeps them as its
    configuration's ``gridworld``)."""
    return getattr(result.config, "gridworld", result.config)


def first_level_shares(result: GridworldResult) -> dict:
    """What 2observe's GLAs learned, GLA by GLA (Sec. 5.1: the first level decides whether the
    agents are within each other's range of interference): the share of final GLAs that coordinate
    (P(coordinate) > 1/2) at every in-range distance, that act alone at every out-of-range one,
    and the share of GLAs saturated on the wrong choice somewhere (:func:`stuck_share`) at the
    start of the runs and at their end."""
    config = chapter_settings(result)
    near, far = in_range_distances(config.gridmap())
    p_near = coordination_probabilities(result.gla_parameters, config, near)
    p_far = coordination_probabilities(result.gla_parameters, config, far)
    return {"coordinates_in_range_share_two_observe": float((p_near > 0.5).all(axis=-1).mean()),
            "alone_out_of_range_share_two_observe": float((p_far < 0.5).all(axis=-1).mean()),
            "stuck_at_start_share_two_observe": stuck_share(result.gla_initial, config),
            "stuck_at_end_share_two_observe": stuck_share(result.gla_parameters, config)}


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
    config = chapter_settings(result)
    start, end = stuck_glas(result.gla_initial, config), stuck_glas(result.gla_parameters, config)
    return {"GLAs": int(start.size), "saturated at the start": int(start.sum()),
            "stuck at the end": int(end.sum()), "stuck at the end, saturated at the start": int((start & end).sum())}


def summary_table(result: GridworldResult) -> str:
    """Final values (last 10 % of the episodes, mean over runs) and convergence episode (median
    over runs of each run's own, curves.convergence_episodes) per learner,
    rounded to what 20 runs resolve."""
    m = measure(result)
    lines = [f"{'learner':24s} {'steps':>6s} {'reward':>7s} {'collisions':>10s} {'coordinations':>13s} "
             f"{'converged by':>12s} {'capped/run':>10s}"]
    for name in result.names():
        lines.append(f"{registry.label(name):24s} {m[f'steps_{name}']:6.2f} {m[f'reward_{name}']:7.1f} "
                     f"{m[f'collisions_{name}']:10.3f} {m[f'coordinations_{name}']:13.2f} "
                     f"{m[f'convergence_{name}']:12.0f} {m[f'capped_episodes_{name}']:10.1f}")
    return "\n".join(lines)


def with_learner(result: GridworldResult, other: GridworldResult, name: str) -> GridworldResult:
    """``result`` with learner ``name``'s curves and 2observe's arrays taken from ``other`` (to
    compare a variant of one learner against the same baselines)."""
    k, j = result.names().index(name), other.names().index(name)
    log = result.log.copy()
    log[k] = other.log[j]
    learned = registry.get(name).outputs(other.config, other.config.gridmap())
    first_level = {"gla_parameters": "u", "gla_initial": "u", "need_counts": "need_counts"}
    return replace(result, log=log, **{field: getattr(other, field) for field, key in first_level.items() if key in learned})


def matches_committed(result: GridworldResult, config: GridworldConfig, seed: int = 0) -> bool:
    """Whether ``result`` equals, array for array, the committed result of ``config`` and ``seed``
    (data/results/gridworld.npz, its configuration checked)."""
    stored = results.load(EXPERIMENT.file(RESULTS), config, seed=seed)
    return all(np.array_equal(getattr(result, name), stored[name]) for name in stored)


def claim_rows(result: GridworldResult) -> list[dict]:
    """The chapter's Section 5.3 claims with their verdicts, computed from ``result``."""
    return chapter.verdicts(chapter.load("gridworld"), measure(result))


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
        gla_per_agent = registry.get(name).gla_parameters(result.config, gridmap) // gridmap.n_agents
        rows.append({"learner": name, "tables": int(tables), "states": int(states),
                     "actions": int(actions), "q_entries_per_agent": q_per_agent,
                     "gla_parameters_per_agent": gla_per_agent})
    return rows


def coordination_probability(result: GridworldResult, config: GridworldConfig, deltas) -> np.ndarray:
    """P(coordinate | delta) of 2observe's final GLAs (eq. 15), shape (runs, agents, len(deltas))."""
    return coordination_probabilities(result.gla_parameters, config, deltas)


def coordination_probabilities(u: np.ndarray, config: GridworldConfig, deltas) -> np.ndarray:
    """P(coordinate | delta) (eq. 15) of the GLA parameters ``u`` (runs, agents, 2, 2), shape
    (runs, agents, len(deltas)); under the fixed rule (``rule_distance``), its 0 or 1."""
    if config.rule_distance is not None:
        rule = (np.asarray(deltas) < config.rule_distance).astype(float)
        return np.broadcast_to(rule, u.shape[:2] + rule.shape).copy()
    p = config.gla_params()
    contexts = [np.array([delta * config.delta_scale(), 1.0]) for delta in deltas]
    probs = np.empty(2)
    out = np.empty(u.shape[:2] + (len(deltas),))
    for r in range(u.shape[0]):
        for i in range(u.shape[1]):
            for d, x in enumerate(contexts):
                gla.boltzmann(u[r, i], x, p.temperature, p.L, p.bounding_code, probs)
                out[r, i, d] = probs[two_observe.COORDINATE]
    return out


def optimum(config: GridworldConfig) -> dict:
    """The reference the learners are drawn against: the episode of the optimal joint policy
    (value iteration on the MMDP, gamma = config.discount), agent means, no exploration."""
    episode = dp.optimal_rollout(config.gridmap(), config.discount, config.bounce)
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
    counts = result.need_counts.sum(axis=0)
    seen = counts.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(seen > 0, counts[:, 1] / seen, np.nan)


# --- plots: each draws on a given Axes -------------------------------------------------------

def _line_style(name: str) -> dict:
    """Colour, width and stacking of learner ``name``'s curve (2observe wide and underneath,
    glamas.plotting.LEARNER_STYLES)."""
    under = drawn_underneath(name)
    return {**learner_style(name), "linewidth": 2.6 if under else 1.3, "zorder": 2 if under else 3}


def _plot_learners(ax, result, values, ylabel, reference=None, learners=None):
    x = result.episodes
    names = list(learners or result.names())
    for name in sorted(names, key=lambda name: not drawn_underneath(name)):  # 2observe first
        plot_mean_band(ax, x, values(name), registry.label(name), **_line_style(name))
    if reference is not None:
        ax.axhline(reference, color="black", linestyle="--", linewidth=1, label="optimum (value iteration)")
    ax.set_xscale("log")  # the learning happens in the first few thousand episodes
    ax.set_xlabel("episode")
    ax.set_ylabel(ylabel)
    _legend_in_learner_order(ax, names)


def _legend_in_learner_order(ax, names):
    """The legend below the axes, learners in their usual order whatever order they were drawn in."""
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda i: _legend_rank(labels[i], names))
    legend_below(ax, handles=[handles[i] for i in order], labels=[labels[i] for i in order])


def _legend_rank(label: str, names) -> int:
    ranks = {registry.label(name): k for k, name in enumerate(names)}
    return ranks.get(label, len(ranks))


STEP_TICKS = (10, 20, 50, 100, 1000)
"""Fig. 11a's log-axis ticks: the scale of the steps, from the first episodes down to the goal."""
STEP_TAIL_TICKS = (10, 11, 12, 14, 16)
"""The zoomed tail's ticks: the final steps the text compares (the optimum is about 10.5)."""
TAIL_FROM = 100
"""The zoom shows the episodes from this one on, after the first drop of every learner."""


def plot_steps(ax, result, optimum=None):
    """Fig. 11a: steps from start to goal, mean of both agents (mean and 95 % band over runs), on
    a log axis with ticks at round values, and the tail (episode 100 on) zoomed on a linear axis
    in an inset, where the learners' final steps differ by one or two; a run of fewer episodes
    has no tail, and no inset."""
    _plot_learners(ax, result, result.steps, "steps to goal (mean of the agents)",
                   None if optimum is None else optimum["steps"])
    _round_log_ticks(ax, STEP_TICKS)
    if result.episodes[-1] >= TAIL_FROM:
        _plot_step_tail(ax, result, optimum)


def _round_log_ticks(ax, ticks):
    """Log y axis labelled at ``ticks`` as plain numbers (no 10^k, no unlabelled minor ticks)."""
    ax.set_yscale("log")
    ax.set_yticks(ticks, [f"{t:g}" for t in ticks])
    ax.yaxis.set_minor_formatter(NullFormatter())


def _plot_step_tail(ax, result, optimum):
    """An inset in the empty upper right (every curve is below 20 steps there): the steps from
    TAIL_FROM on, linear axis, ticks at STEP_TAIL_TICKS."""
    tail = ax.inset_axes([0.5, 0.4, 0.47, 0.5])
    keep = result.episodes >= TAIL_FROM
    for name in sorted(result.names(), key=lambda name: not drawn_underneath(name)):
        plot_mean_band(tail, result.episodes[keep], result.steps(name)[:, keep], registry.label(name), **_line_style(name))
    if optimum is not None:
        tail.axhline(optimum["steps"], color="black", linestyle="--", linewidth=1)
    tail.set_xscale("log")
    tail.set_yticks(STEP_TAIL_TICKS)
    tail.set_ylim(STEP_TAIL_TICKS[0] - 0.5, STEP_TAIL_TICKS[-1] + 2)
    tail.grid(axis="y", linewidth=0.4, color="0.85")
    tail.tick_params(labelsize="x-small")
    tail.set_title(f"from episode {TAIL_FROM}, linear axis", fontsize="x-small")


def plot_reward(ax, result, optimum=None):
    """Fig. 11b: undiscounted reward per episode, mean of both agents."""
    _plot_learners(ax, result, result.reward, "reward per episode (mean of the agents)",
                   None if optimum is None else optimum["reward"])


def plot_collisions(ax, result, optimum=None):
    """Fig. 12a: agent-agent collisions per episode."""
    _plot_learners(ax, result, lambda name: result.curves(name, "collisions"), "collisions per episode",
                   None if optimum is None else optimum["collisions"])


CHAPTER_COORDINATIONS = 4.0
"""Sec. 5.3: 2observe converges to "about four" coordinations per episode (Fig. 12b)."""


def plot_coordinations(ax, result):
    """Fig. 12b: steps per episode on which both 2observe agents chose to coordinate: every run
    (faint), the median over runs and its interquartile range, against the chapter's "about four".
    The median, not the mean: a few runs whose GLAs coordinate far from need would pull a mean up."""
    x, per_run = result.episodes, result.curves("two_observe", "coordinations")
    style = learner_style("two_observe")
    for curve in per_run:
        ax.plot(x, curve, alpha=0.2, linewidth=0.6, **style)
    low, median, high = np.percentile(per_run, [25, 50, 75], axis=0)
    ax.fill_between(x, low, high, alpha=0.3, linewidth=0, label="2observe, interquartile range over runs", **style)
    ax.plot(x, median, linewidth=2.2, label="2observe, median over runs (faint: each run)", **style)
    ax.axhline(CHAPTER_COORDINATIONS, color="black", linestyle=":", linewidth=1.2,
               label='the chapter: "about four" per episode')
    ax.set_xscale("log")
    ax.set_xlabel("episode")
    ax.set_ylabel("coordinations per episode")
    legend_below(ax)


NEED_LABELS = {"in_range": ("cannot collide this step", "could collide this step"),
               "sampled": ("preferred actions would not collide", "preferred actions would collide"),
               "outcome": ("no collision this step", "collided this step")}
"""What "no need" and "need" mean under each reading of Fig. 10, in words."""


def plot_feedback_table(ax, config: GridworldConfig):
    """Fig. 10 (lost, reconstructed): the GLA feedback actually used."""
    f, c = config.gla_feedback, config.coordination_penalty_per_cell
    cells = [[f"{f[0][0]:g}", f"{f[0][1]:g}"],
             [f"{f[1][0]:g}  ({f[1][0]:g} - {c:g}·δ if both coordinate)", f"{f[1][1]:g}"]]
    ax.axis("off")
    no_need, need = NEED_LABELS[config.gla_need]
    table = ax.table(cellText=cells, rowLabels=["act alone", "coordinate"],
                     colLabels=[f"no need ({no_need})", f"need ({need})"], loc="center", cellLoc="center")
    table.scale(1, 2)
    ax.set_title(f"Fig. 10, reconstructed: 2observe's GLA feedback (need = {config.gla_need})", fontsize="medium")


def plot_coordination_probability(ax, result, config: GridworldConfig):
    """What 2observe's GLAs learned: P(coordinate | delta) of each final GLA (faint) and their
    mean, against the rule "coordinate when the agents could collide this step" (delta <= 2 on a
    4-connected grid), with the observed P(need | delta) that the GLA's feedback depends on."""
    deltas = np.arange(1, result.need_counts.shape[1])  # two acting agents are never at distance 0
    p = coordination_probability(result, config, deltas)
    for curve in p.reshape(-1, deltas.size):
        ax.plot(deltas, curve, alpha=0.15, linewidth=0.8, **learner_style("two_observe"))
    ax.plot(deltas, p.mean(axis=(0, 1)), "o-", label="P(coordinate), learned (mean of the GLAs)",
            **learner_style("two_observe"))
    ax.step(deltas, (deltas <= 2).astype(float), where="mid", color="black", linestyle="--",
            label="coordinate when delta <= 2 (could collide)")
    ax.plot(deltas, need_probability(result)[1:], "s:", color="tab:gray",
            label=f"P(need | delta), observed ({config.gla_need})")
    ax.set_xlabel("delta (Manhattan distance between the agents)")
    ax.set_ylabel("probability")
    ax.set_ylim(-0.03, 1.03)
    ax.legend(fontsize="small")


# --- the experiment of the figure scripts (paper_figures/fig11a.py ... fig12b.py) ----------------



def scaled(runs: int, episodes: int) -> GridworldConfig:
    """The chapter's experiment at ``runs`` and ``episodes``."""
    return GridworldConfig(runs=runs, episodes=episodes)


EXPERIMENT = register(Experiment("gridworld", GridworldConfig, run, scaled, GridworldConfig.runs,
                                 GridworldConfig.episodes, GridworldResult,
                                 claim_rows=lambda result, config: claim_rows(result),
                                 figures=("fig9", "fig10", "fig11a", "fig11b", "fig12a", "fig12b")))
"""The chapter's experiment of Section 5.3 (Fig. 9 and 10 draw its map and its GLAs' feedback)."""
