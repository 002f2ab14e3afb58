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

from glamas import checks, figures, gla, results, runs
from glamas import claims as chapter
from glamas.curves import convergence_episode, convergence_ratio, final
from glamas.gridworld import GridMap, dp, load_map, rules
from glamas.learners import episode as ep
from glamas.learners import registry, spec, two_observe
from glamas.learners.settings import LearningSettings
from glamas.paths import MAPS, RESULTS
from glamas.plotting import drawn_underneath, legend_below, learner_style, plot_mean_band

EXPERIMENT = "gridworld"
RESULT_NAME = "gridworld"
"""Result file shared by the Fig. 11 and 12 scripts: the experiment runs once for all four."""
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
            raise ValueError(f"learners must be distinct names from {LEARNERS}, got {self.learners!r}")
        object.__setattr__(self, "learners", learners)
        gridmap = self.gridmap()
        if gridmap.n_agents != 2:
            raise ValueError(f"the learners are written for two agents; map {self.map_file!r} has {gridmap.n_agents}")

    def gridmap(self) -> GridMap:
        """The map: ``map_file`` as a path, or as a name in data/maps."""
        path = Path(self.map_file)
        return load_map(path if path.is_file() or path.parent != Path(".") else MAPS / path)

    def edges(self) -> np.ndarray:
        """The learning curves' block edges (glamas.learners.episode.log_edges)."""
        return ep.log_edges(self.episodes, self.bins)

    def schedule(self) -> ep.Schedule:
        return ep.Schedule(self.episodes, self.edges(), self.max_steps)

    def delta_scale(self) -> float:
        """What the GLA context multiplies delta by (``gla_delta_scale``) on this map."""
        return two_observe.delta_scale(self.gla_delta_scale, self.gridmap())


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
    workers (:func:`glamas.runs.run_many`).

    Each learner draws its runs' streams from its own master seed
    (:func:`glamas.learners.registry.master_seed` over LEARNERS): every (seed, learner) pair has
    its own streams, and a learner gets the same streams whichever other learners are trained with it.
    """
    work = trainings(config, seed)
    runs.run_many([batch for batch, _ in work], workers=workers, progress=progress)
    return result_of(config, [outputs for _, outputs in work])


def trainings(config: GridworldConfig, seed: int = 0) -> list:
    """Per learner of ``config``: its runs, ready to run (glamas.runs.Batch), and the outputs they fill."""
    gridmap, schedule = config.gridmap(), config.schedule()
    return [spec.batch(registry.get(name), config, gridmap, schedule, config.runs,
                       registry.master_seed(seed, LEARNERS, name)) for name in config.learners]


def result_of(config: GridworldConfig, outputs: list) -> GridworldResult:
    """The result of ``config`` from its learners' filled outputs (:func:`trainings`, in order)."""
    gridmap = config.gridmap()
    first_level = {key: np.stack([zeros] * config.runs) for key, zeros in two_observe.outputs(config, gridmap).items()}
    for learned in outputs:
        first_level.update({key: learned[key] for key in first_level.keys() & learned.keys()})
    codes = np.array([LEARNERS.index(name) for name in config.learners], dtype=np.int64)
    return GridworldResult(config=config, learners=codes, log=np.stack([learned["log"] for learned in outputs]),
                           table_shapes=np.array([learned["q"].shape[1:] for learned in outputs], dtype=np.int64),
                           gla_parameters=first_level["u"], need_counts=first_level["need_counts"],
                           episodes=config.edges()[1:])


def load(config: GridworldConfig = GridworldConfig(), seed: int = 0, results_dir: Path = RESULTS) -> GridworldResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return STUDY.load(results_dir, config, seed)


def _decided_ratio(m: dict, key: str, ratio: tuple[float, float, float]) -> None:
    """Store ``ratio``'s point value under ``key`` when its interval excludes 1, else NaN with the
    reason (the claim is then undecidable: the runs' spread cannot order the two learners)."""
    point, low, high = ratio
    m[f"{key}_point"], m[f"{key}_low"], m[f"{key}_high"] = point, low, high
    if low <= 1.0 <= high:
        m[key] = math.nan
        m[f"{key}:why_undecidable"] = (f"ratio {point:.2f}, but its 95 % interval over runs "
                                       f"[{low:.2f}, {high:.2f}] contains 1")
    else:
        m[key] = point


def measure(result: GridworldResult) -> dict:
    """The numbers the chapter's claims are about (data/chapter/section5.json), per learner and compared."""
    m = {}
    x = result.episodes
    for name in result.names():
        m[f"steps_{name}"] = final(result.steps(name), x)
        m[f"reward_{name}"] = final(result.reward(name), x)
        m[f"collisions_{name}"] = final(result.curves(name, "collisions"), x)
        m[f"coordinations_{name}"] = final(result.curves(name, "coordinations"), x)
        m[f"convergence_{name}"] = convergence_episode(result.steps(name), x)
        m[f"capped_episodes_{name}"] = float(result.curves(name, "capped").mean(axis=0) @ result.widths())
    if {"two_observe", "independent", "mmdp"} <= set(result.names()):
        for base in ("independent", "mmdp"):
            m[f"steps_two_observe_minus_{base}"] = m["steps_two_observe"] - m[f"steps_{base}"]
            _decided_ratio(m, f"convergence_two_observe_over_{base}",
                           convergence_ratio(result.steps("two_observe"), result.steps(base), x))
        m["reward_two_observe_over_mmdp"] = m["reward_two_observe"] / m["reward_mmdp"]
        m["reward_two_observe_minus_independent"] = m["reward_two_observe"] - m["reward_independent"]
        m["collisions_independent_off_3"] = abs(m["collisions_independent"] - 3.0)
        m["coordinations_two_observe_off_4"] = abs(m["coordinations_two_observe"] - 4.0)
    return m


def summary_table(result: GridworldResult) -> str:
    """Final values (last 10 % of the episodes, mean over runs) and convergence episode per learner,
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
    first_level = {"gla_parameters": "u", "need_counts": "need_counts"}
    return replace(result, log=log, **{field: getattr(other, field) for field, key in first_level.items() if key in learned})


def matches_committed(result: GridworldResult, config: GridworldConfig, seed: int = 0) -> bool:
    """Whether ``result`` equals, array for array, the committed result of ``config`` and ``seed``
    (data/results/gridworld.npz, its configuration checked)."""
    stored = results.load(RESULTS / f"{RESULT_NAME}.npz", config, seed=seed)
    return all(np.array_equal(getattr(result, name), stored[name]) for name in stored)


def claim_rows(result: GridworldResult) -> list[dict]:
    """The chapter's Section 5.3 claims with their verdicts, computed from ``result``."""
    return chapter.verdicts(chapter.load(EXPERIMENT), measure(result))


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
    p = config.gla_params()
    u = result.gla_parameters
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
    """2observe's convergence ratios against each baseline, with their 95 % intervals and verdicts."""
    m = measure(result)
    lines = [f"{'':28s} {'episodes':>9s}"]
    for name in result.names():
        lines.append(f"{registry.label(name):28s} {m[f'convergence_{name}']:9.0f}")
    for base in ("independent", "mmdp"):
        key = f"convergence_two_observe_over_{base}"
        decided = "undecidable" if np.isnan(m[key]) else ("faster" if m[key] < 1 else "slower")
        lines.append(f"2observe / {registry.label(base)}: ratio {m[f'{key}_point']:.3f}, 95 % interval over runs "
                     f"[{m[f'{key}_low']:.3f}, {m[f'{key}_high']:.3f}]: {decided}")
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
    in an inset, where the learners' final steps differ by one or two."""
    _plot_learners(ax, result, result.steps, "steps to goal (mean of the agents)",
                   None if optimum is None else optimum["steps"])
    _round_log_ticks(ax, STEP_TICKS)
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
    """Fig. 12b: steps per episode on which both 2observe agents chose to coordinate, against the
    chapter's "about four"."""
    ax.axhline(CHAPTER_COORDINATIONS, color="black", linestyle=":", linewidth=1.2,
               label='the chapter: "about four" per episode')
    _plot_learners(ax, result, lambda name: result.curves(name, "coordinations"),
                   "coordinations per episode", learners=["two_observe"])


def plot_variants(ax, results: dict, metric: str, learner: str = "two_observe"):
    """One learner's curve of ``metric`` ('steps', 'reward', 'collisions' or 'coordinations')
    for several configurations: ``results`` maps a label to a result."""
    for label, result in results.items():
        values = result.curves(learner, metric)
        plot_mean_band(ax, result.episodes, values, label)
    ax.set_xscale("log")
    ax.set_xlabel("episode")
    ax.set_ylabel(f"{metric} per episode")
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


STUDY = figures.Experiment(RESULT_NAME, run, GridworldConfig.runs, GridworldConfig.episodes, scaled, GridworldResult)
"""The chapter's experiment of Section 5.3 at --runs and --iterations (episodes)."""
