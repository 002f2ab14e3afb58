"""The related-work comparison's figures (Fig. 11/12-style, beyond the chapter), each on a given
matplotlib Axes: the chapter's curves with the related-work learners, the steps on which the agents
observe each other, what each learner stores against its reward, and the joint states observed."""

import numpy as np

from glamas.experiments.gridworld import analysis as gw_analysis
from glamas.experiments.related_work.analysis import marked_distances, measure
from glamas.experiments.related_work.experiment import RelatedWorkConfig, RelatedWorkResult
from glamas.learners import registry, sparse_maq
from glamas.plotting import legend_below, legend_right, learner_style, plot_mean_band


def plot_curve(ax, result: RelatedWorkResult, config: RelatedWorkConfig, plot):
    """One of the chapter's curves for the comparison: ``plot`` (:func:`glamas.experiments.gridworld.plot_steps`,
    ``plot_reward`` or ``plot_collisions``) against the map's optimum, CQ-learning's solo phase noted."""
    plot(ax, result, gw_analysis.optimum(config))
    note_cq_solo_phase(ax, result, config)


def note_cq_solo_phase(ax, result: RelatedWorkResult, config: RelatedWorkConfig):
    """Say, above the axes, that CQ-learning's curve starts after the episodes each of its agents
    first learned alone: its episode 1 is not the others' episode 1."""
    if "cq" in result.names():
        solo = config.setup("cq").own.cq_solo_episodes
        ax.set_title(f"CQ-learning's curve starts after {solo} episodes in which each of its "
                     "agents\nfirst learned alone (not on the x axis): it starts from what they learned there",
                     fontsize="small", color=learner_style("cq")["color"])


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
    gridmap, distance = config.gridmap(), config.setup("sparse_maq").own.coordination_distance
    given = np.flatnonzero(sparse_maq.coordination_index(gridmap, distance) >= 0)
    own, other = np.divmod(given, gridmap.n_cells)
    given_distances = np.abs(own // gridmap.n_cols - other // gridmap.n_cols) + np.abs(own % gridmap.n_cols - other % gridmap.n_cols)
    marked = marked_distances(result, config)
    runs, agents = result.output("cq", "marked").shape[:2]
    per_agent = runs * agents
    distances = np.arange(1, max(distance, marked.max(initial=1)) + 1)
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
