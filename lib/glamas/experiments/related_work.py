"""The related-work learners beside the chapter's on TunnelToGoal (Fig. 11/12-style comparison):
sparse tabular multi-agent Q-learning (Kok and Vlassis 2004, coordination states given in
advance, cited in Sec. 5.1) and CQ-learning (De Hauwere, Vrancx and Nowé 2010, the statistical
test the chapter's Sec. 6 proposes instead of the GLA).

The chapter's learners run exactly as in :mod:`glamas.experiments.gridworld` (same settings,
same seeds); the related-work learners draw their streams from master seeds of their own, so
adding them changes nothing of the chapter's experiment.
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from glamas import claims as chapter
from glamas import parallel
from glamas.curves import ratio
from glamas.errors import UserError
from glamas.experiments.registry import Experiment, register
from glamas.experiments import gridworld as gw
from glamas.gridworld import GridMap, rules
from glamas.learners import cq, registry, spec, sparse_maq
from glamas.learners.settings import LearnerSettings, RelatedSettings, combine
from glamas.paths import RESULTS
from glamas.plotting import legend_below, legend_right, learner_style, mean_and_band, plot_mean_band

RELATED_LEARNERS = registry.family("related")
"""The related-work learners (glamas.learners.registry), in the order their seeds are drawn."""
CHAPTER_LEARNERS = ("independent", "mmdp", "two_observe")
"""The chapter's learners the comparison trains by default (the joint-state learners are left out)."""


@dataclass(frozen=True)
class RelatedWorkConfig(RelatedSettings):
    """The comparison's settings: the chapter's experiment plus the related-work learners' own
    (:class:`glamas.learners.settings.RelatedSettings`)."""

    gridworld: gw.GridworldConfig = gw.GridworldConfig(learners=CHAPTER_LEARNERS)
    """The chapter's experiment (map, episodes, runs, Q-learning settings) and which of its learners
    to train; the related-work learners use the same map, schedule and Q-learning settings."""
    learners: tuple = RELATED_LEARNERS
    """Which learners beyond the chapter's to train: distinct names of registered learners, such
    as sparse_maq and cq (may be empty)."""

    def __post_init__(self):
        super().__post_init__()
        learners = tuple(self.learners)
        if len(set(learners)) != len(learners) or not set(learners) <= set(registry.beyond_the_chapter()):
            raise UserError(f"learners must be distinct names from {registry.beyond_the_chapter()}, "
                             f"got {self.learners!r}")
        object.__setattr__(self, "learners", learners)
        # two agents: GridworldConfig already rejects other maps

    def settings(self) -> LearnerSettings:
        """Every learner's settings: the chapter experiment's and the related-work learners' own."""
        return combine(self.gridworld, self)

    def gridmap(self) -> GridMap:
        return self.gridworld.gridmap()

    def memory_bytes(self) -> int:
        """Bytes of the chapter's learners' runs and of the related-work learners' runs."""
        base, gridmap, settings = self.gridworld, self.gridmap(), self.settings()
        related = base.runs * sum(gw.learner_bytes(name, settings, gridmap, base.bins) for name in self.learners)
        return base.memory_bytes() + related


def learner_codes() -> tuple:
    """The learners a :class:`RelatedWorkResult`'s codes index: the chapter's four (codes 0-3),
    then every registered learner beyond them (the related-work learners 4 and 5)."""
    return gw.LEARNERS + registry.beyond_the_chapter()


@dataclass(frozen=True)
class RelatedWorkResult(gw.GridworldResult):
    """A :class:`~glamas.experiments.gridworld.GridworldResult` over the chapter's and other
    learners (codes into :func:`learner_codes`), with what each learner stores."""

    config: RelatedWorkConfig
    """The configuration that produced the arrays."""
    local_entries: np.ndarray
    """float (n_learners,): Q entries per agent over its own cells."""
    joint_entries: np.ndarray
    """float (n_learners, runs): Q entries per agent over joint states (joint actions for the
    MMDP and sparse learners, counted in the final tables; CQ: 4 per marked joint state)."""
    reward_samples: np.ndarray
    """int (n_learners,): immediate rewards each agent keeps for a statistical test (CQ only)."""
    cq_marked: np.ndarray
    """bool (runs, agents, own cell, other's cell): the joint states each CQ agent learned to
    observe (all False if CQ did not run)."""

    def names(self) -> list[str]:
        codes = learner_codes()
        return [codes[k] for k in self.learners]


def run(config: RelatedWorkConfig = RelatedWorkConfig(), seed: int = 0, workers=None,
        progress=None) -> RelatedWorkResult:
    """Train the chapter's learners as :func:`glamas.experiments.gridworld.run` does (same seeds, so
    the same results) and the related-work learners of ``config``, ``config.gridworld.runs`` runs
    each, all on one pool of workers."""
    base, settings = config.gridworld, config.settings()
    gridmap, schedule = base.gridmap(), base.schedule()
    chapter = gw.trainings(base, seed)
    related = [spec.batch(registry.get(name), settings, gridmap, schedule, base.runs,
                          registry.master_seed(seed, RELATED_LEARNERS, name, registry.get(name).family))
               for name in config.learners]
    parallel.run_many([batch for batch, _ in chapter + related], workers=workers, progress=progress)
    chapter_result = gw.result_of(base, [outputs for _, outputs in chapter], seed)
    shapes = np.array([outputs["q"].shape[1:] for _, outputs in related], dtype=np.int64).reshape(-1, 3)
    learned = np.array([registry.get(name).joint_learned(outputs, settings, gridmap)
                        for name, (_, outputs) in zip(config.learners, related)]).reshape(-1, base.runs)
    log = np.array([outputs["log"] for _, outputs in related]).reshape((-1,) + chapter_result.log.shape[1:])
    marked = next((outputs["marked"] for _, outputs in related if "marked" in outputs),
                  np.stack([cq.outputs(settings, gridmap)["marked"]] * base.runs))
    names = chapter_result.names() + list(config.learners)
    shapes = np.concatenate([chapter_result.table_shapes, shapes])
    learned = np.concatenate([np.zeros((len(chapter_result.names()), base.runs)), learned])
    return RelatedWorkResult(
        config=config, learners=np.array([learner_codes().index(name) for name in names], dtype=np.int64),
        log=np.concatenate([chapter_result.log, log]), table_shapes=shapes,
        gla_parameters=chapter_result.gla_parameters, gla_initial=chapter_result.gla_initial,
        need_counts=chapter_result.need_counts,
        episodes=chapter_result.episodes, **storage(names, shapes, learned, settings, gridmap), cq_marked=marked)


def storage(names: list, shapes: np.ndarray, learned: np.ndarray, settings, gridmap: GridMap) -> dict:
    """What each agent stores, per learner: its Q entries over its own cells, its Q entries over
    joint states per run (its joint Q tables, and the joint values ``learned`` beyond them), and
    its reward samples."""
    n_agents = gridmap.n_agents
    joint = [registry.get(name).joint_tables for name in names]
    local = [0.0 if is_joint else float(np.prod(shape[1:])) for is_joint, shape in zip(joint, shapes)]
    tables = [np.prod(shape) / n_agents if is_joint else 0.0 for is_joint, shape in zip(joint, shapes)]
    samples = [registry.get(name).reward_samples(settings, gridmap) // n_agents for name in names]
    return {"local_entries": np.array(local), "joint_entries": np.array(tables)[:, None] + learned / n_agents,
            "reward_samples": np.array(samples, dtype=np.int64)}


def load(config: RelatedWorkConfig = RelatedWorkConfig(), seed: int = 0, results_dir: Path = RESULTS) -> RelatedWorkResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


# --- measurements and claims --------------------------------------------------------------------

def usable_joint_states(config: RelatedWorkConfig) -> int:
    """Joint states in which both agents act: ordered pairs of distinct cells, neither the goal nor blocked."""
    g = config.gridworld.gridmap()
    usable = int((~(g.is_goal | g.blocked)).sum())
    return usable * (usable - 1)


def marked_distances(result: RelatedWorkResult, config: RelatedWorkConfig) -> np.ndarray:
    """Manhattan distance of every joint state a CQ agent marked (all runs and agents pooled)."""
    n_cols = config.gridworld.gridmap().n_cols
    _, _, own, other = np.nonzero(result.cq_marked)
    return np.abs(own // n_cols - other // n_cols) + np.abs(own % n_cols - other % n_cols)


def measure(result: RelatedWorkResult, config: RelatedWorkConfig) -> dict:
    """:func:`glamas.experiments.gridworld.measure` for every learner, plus each learner's stored
    values and the related-work comparisons (data/chapter/related_work.json)."""
    m = gw.measure(result)
    names = result.names()
    for k, name in enumerate(names):
        m[f"q_entries_{name}"] = float(result.local_entries[k] + result.joint_entries[k].mean())
    if "cq" in names:
        per_agent = result.cq_marked.sum(axis=(2, 3)).mean()
        m["marked_joint_states_cq"] = float(per_agent)
        m["marked_fraction_cq"] = float(per_agent / usable_joint_states(config))
        distances = marked_distances(result, config)
        m["marked_within_coordination_distance_cq"] = float((distances <= config.coordination_distance).mean()) if distances.size else 0.0
    for name in set(names) & set(RELATED_LEARNERS):
        if "mmdp" in names:
            m[f"reward_{name}_over_mmdp"] = ratio(m[f"reward_{name}"], m["reward_mmdp"])
            m[f"q_entries_{name}_over_mmdp"] = m[f"q_entries_{name}"] / m["q_entries_mmdp"]
            m.update(gw.convergence_comparison(result, name, "mmdp"))
        if "independent" in names:
            m[f"reward_{name}_minus_independent"] = m[f"reward_{name}"] - m["reward_independent"]
    return m


def final_interval(result: RelatedWorkResult, name: str, metric: str = "collisions") -> tuple[float, float, float]:
    """Learner ``name``'s final value of one metric (``gw.final``, last 10 % of the episodes)
    as (mean over runs, 95 % bootstrap interval of that mean: runs resampled, as the figures' bands)."""
    per_run = np.array([gw.final(curve[None], result.episodes) for curve in result.curves(name, metric)])
    mean, low, high = mean_and_band(per_run[:, None])
    return float(mean[0]), float(low[0]), float(high[0])


def fewest_flagged_collisions(config: RelatedWorkConfig) -> int:
    """The fewest collisions among the ``cq_window`` recent rewards of a state-action that
    CQ-learning's test flags against a baseline without any (``cq_window`` equal rewards, as of a
    state-action that never collided alone); the other recent rewards equal the baseline's."""
    window = config.cq_window
    t_critical = cq.t_critical_values(2 * window - 2, config.cq_significance)
    baseline = np.array([window, 0.0, 0.0])
    for k in range(1, window + 1):
        penalties = k * rules.COLLISION_PENALTY
        if cq.significantly_lower(baseline, np.array([window, penalties, penalties * rules.COLLISION_PENALTY]), t_critical):
            return k
    return window + 1  # never: not even a window of collisions only


def claim_rows(result: RelatedWorkResult, config: RelatedWorkConfig) -> list[dict]:
    """The related-work claims (data/chapter/related_work.json) with verdicts computed from ``result``."""
    return chapter.verdicts(chapter.load("related_work"), measure(result, config))


def summary_table(result: RelatedWorkResult, config: RelatedWorkConfig) -> str:
    """Per learner: final steps, reward, collisions and coordinations (last 10 % of the episodes,
    mean over runs), convergence episode, and what each agent stores (measured)."""
    m = measure(result, config)
    lines = [f"{'learner':24s} {'steps':>6s} {'reward':>7s} {'collisions':>10s} {'coordinations':>13s} "
             f"{'converged by':>12s} {'Q entries/agent':>15s} {'samples/agent':>13s} {'GLA params/agent':>16s}"]
    settings, gridmap = config.settings(), config.gridmap()
    for k, name in enumerate(result.names()):
        gla_parameters = registry.get(name).gla_parameters(settings, gridmap) // gridmap.n_agents
        lines.append(f"{registry.label(name):24s} {m[f'steps_{name}']:6.2f} {m[f'reward_{name}']:7.1f} "
                     f"{m[f'collisions_{name}']:10.3f} {m[f'coordinations_{name}']:13.2f} "
                     f"{m[f'convergence_{name}']:12.0f} {m[f'q_entries_{name}']:15.0f} "
                     f"{result.reward_samples[k]:13d} {gla_parameters:16d}")
    return "\n".join(lines)


# --- plots: each draws on a given Axes -------------------------------------------------------

def plot_coordinations(ax, result: RelatedWorkResult):
    """Steps per episode on which the agents observed each other: both 2observe GLAs chose to
    coordinate, sparse MAQ's agents were in a coordination state, or a CQ agent acted on a marked
    joint state."""
    for name in result.names():
        coordinations = result.curves(name, "coordinations")
        if coordinations.any():  # the learners that never observe each other draw nothing
            plot_mean_band(ax, result.episodes, coordinations, registry.label(name), **learner_style(name))
    ax.set_xscale("log")
    ax.set_xlabel("episode")
    ax.set_ylabel("steps observing the other agent")
    legend_below(ax)


def plot_size_and_reward(ax, result: RelatedWorkResult, config: RelatedWorkConfig):
    """Each learner's Q entries per agent (measured) against its final reward: the chapter's
    trade-off between state-action space and coordination (learners on the same point share a
    legend entry). A learner that also stores reward samples for a statistical test (CQ-learning)
    gets a second, open marker at Q entries + samples, joined by an arrow: that memory is the
    chapter's argument for the GLA, which needs none."""
    m = measure(result, config)
    points = {}
    for name in result.names():
        points.setdefault((m[f"q_entries_{name}"], round(m[f"reward_{name}"], 1)), []).append(name)
    for (entries, reward), names in points.items():
        ax.plot(entries, reward, markersize=8, linestyle="none", label=" = ".join(registry.label(n) for n in names),
                **learner_style(names[0], marker=True))
    for k, name in enumerate(result.names()):
        if result.reward_samples[k] > 0:
            _plot_with_samples(ax, name, m[f"q_entries_{name}"], m[f"reward_{name}"], int(result.reward_samples[k]))
    ax.set_xscale("log")
    ax.margins(x=0.15, y=0.08)
    ax.set_xlabel("values stored per agent (log)")
    ax.set_ylabel("final reward per episode (mean of the agents)")
    legend_right(ax)


def _plot_with_samples(ax, name: str, entries: float, reward: float, samples: int):
    """An open marker at ``entries + samples``, labelled, and an arrow to it from the Q-entries point."""
    style = learner_style(name, marker=True)
    ax.plot(entries + samples, reward, markersize=8, linestyle="none", mfc="none",
            label=f"{registry.label(name)}: Q entries + {samples} reward samples", **style)
    ax.annotate("", (entries + samples, reward), xytext=(entries, reward),
                arrowprops={"arrowstyle": "->", "color": style["color"], "shrinkA": 6, "shrinkB": 6})


def plot_marked_distances(ax, result: RelatedWorkResult, config: RelatedWorkConfig):
    """Per Manhattan distance between the agents: the joint states a CQ agent learned to observe
    (mean per agent and run) beside the coordination states sparse MAQ is given in advance."""
    gridmap = config.gridworld.gridmap()
    given = np.flatnonzero(sparse_maq.coordination_index(gridmap, config.coordination_distance) >= 0)
    own, other = np.divmod(given, gridmap.n_cells)
    given_distances = np.abs(own // gridmap.n_cols - other // gridmap.n_cols) + np.abs(own % gridmap.n_cols - other % gridmap.n_cols)
    marked = marked_distances(result, config)
    per_agent = result.cq_marked.shape[0] * result.cq_marked.shape[1]
    distances = np.arange(1, max(config.coordination_distance, marked.max(initial=1)) + 1)
    ax.bar(distances - 0.2, [(given_distances == d).sum() for d in distances], width=0.4, **learner_style("sparse_maq"),
           label="sparse MAQ: coordination states (given)")
    ax.bar(distances + 0.2, [(marked == d).sum() / per_agent for d in distances], width=0.4, **learner_style("cq"),
           label="CQ-learning: marked joint states per agent")
    ax.set_xticks(distances)
    ax.set_yscale("log")
    ax.set_ylim(top=ax.get_ylim()[1] * 10)  # room for the legend above the bars
    ax.set_xlabel("Manhattan distance between the agents")
    ax.set_ylabel("joint states (log)")
    legend_below(ax, ncols=1)


def plot_curve(ax, result: RelatedWorkResult, config: RelatedWorkConfig, plot):
    """One of the chapter's curves for the comparison: ``plot`` (:func:`glamas.experiments.gridworld.plot_steps`,
    ``plot_reward`` or ``plot_collisions``) against the map's optimum, CQ-learning's solo phase noted."""
    plot(ax, result, gw.optimum(config.gridworld))
    note_cq_solo_phase(ax, result, config)


def note_cq_solo_phase(ax, result: RelatedWorkResult, config: RelatedWorkConfig):
    """Say, above the axes, that CQ-learning's curve starts after the episodes each of its agents
    first learned alone: its episode 1 is not the others' episode 1."""
    if "cq" in result.names():
        ax.set_title(f"CQ-learning's curve starts after {config.cq_solo_episodes} episodes in which each of its "
                     "agents\nfirst learned alone (not on the x axis): it starts from what they learned there",
                     fontsize="small", color=learner_style("cq")["color"])


# --- the experiment of the figure scripts (paper_figures/related_*.py) --------------------------

def scaled(runs: int, episodes: int) -> RelatedWorkConfig:
    """The comparison at ``runs`` and ``episodes``, beside the chapter's learners it trains by default."""
    return RelatedWorkConfig(gridworld=gw.GridworldConfig(learners=CHAPTER_LEARNERS, runs=runs, episodes=episodes))


EXPERIMENT = register(Experiment("related_work", RelatedWorkConfig, run, scaled, gw.GridworldConfig.runs,
                                 gw.GridworldConfig.episodes, RelatedWorkResult, claim_rows=claim_rows,
                                 figures=("related_collisions", "related_coordinations", "related_reward",
                                          "related_sizes", "related_steps"), chapter=False))
"""The related-work comparison (its result file is shared by the related_* figure scripts)."""
