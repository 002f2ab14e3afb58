"""The gridworld experiment's figures (Fig. 10-12) and the notebook's drawings of what 2observe's
GLAs learned, each drawn on a given matplotlib Axes in the styles of :mod:`glamas.plotting`."""

import numpy as np
from matplotlib.ticker import MaxNLocator, NullFormatter

from glamas.experiments.gridworld.analysis import (coordination_probability, curve_collision_claims,
                                                   first_level_settings, need_probability)
from glamas.experiments.gridworld.experiment import GridworldConfig
from glamas.gridworld import dp
from glamas.learners import registry
from glamas.plotting import (draw_claim_level, drawn_underneath, greedy_legend_entry, legend_below, learner_style,
                             mark_greedy, plot_mean_band)


def _line_style(name: str) -> dict:
    """Colour, width and stacking of learner ``name``'s curve (2observe wide and underneath,
    glamas.plotting.LEARNER_STYLES)."""
    under = drawn_underneath(name)
    return {**learner_style(name), "linewidth": 2.6 if under else 1.3, "zorder": 2 if under else 3}


def _plot_learners(ax, result, values, ylabel, reference=None):
    """Each learner's learning curve of ``values(name)`` (mean and band over runs) and the
    reference line, on a log axis of episodes (the learning happens in the first few thousand)."""
    for name in sorted(result.names(), key=lambda name: not drawn_underneath(name)):  # 2observe first
        plot_mean_band(ax, result.episodes, values(name), registry.label(name), **_line_style(name))
    if reference is not None:
        ax.axhline(reference, color="black", linestyle="--", linewidth=1, label="optimum (value iteration)")
    ax.set_xscale("log")
    ax.set_xlabel("episode")
    ax.set_ylabel(ylabel)


def _finish(ax, result, metric: str):
    """The greedy values of ``metric`` beside the curves (:func:`_mark_greedy`), then the legend."""
    _mark_greedy(ax, result, result.names(), metric)
    _legend_in_learner_order(ax, result.names())


GREEDY_AT = 2.0
"""Where the greedy values stand: this many times the last episode, right of the curves' end."""


def _mark_greedy(ax, result, names, metric: str):
    """Each learner's ``metric`` under the greedy evaluation of what it learned (mean over runs),
    right of its curve's end (:func:`glamas.plotting.mark_greedy`)."""
    x = result.episodes[-1] * GREEDY_AT
    for name in names:
        mark_greedy(ax, x, result.evaluation(name, metric).mean(), name)
    greedy_legend_entry(ax)
    ax.set_xlim(right=x * 1.4)


def _legend_in_learner_order(ax, names):
    """The legend below the axes, learners in their usual order whatever order they were drawn in."""
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda i: _legend_rank(labels[i], names))
    legend_below(ax, handles=[handles[i] for i in order], labels=[labels[i] for i in order])


def _legend_rank(label: str, names) -> int:
    ranks = {registry.label(name): k for k, name in enumerate(names)}
    return ranks.get(label, len(ranks))


STEP_SCALE = (1, 2, 5, 10, 100)
"""Fig. 11a's log-axis ticks in units of the map's shortest path (:func:`step_ticks`): the scale of
the steps, from the first episodes down to the goal."""
TAIL_OFFSETS = (0, 1, 2, 4, 6)
"""The zoomed tail's ticks above the map's shortest path, in tenths of it (at least 1 step each):
the final steps the text compares."""
TAIL_FROM = 100
"""The zoom shows the episodes from this one on, after the first drop of every learner."""


def step_ticks(gridmap) -> tuple[tuple, tuple]:
    """The ticks of Fig. 11a on ``gridmap``: (log axis, zoomed tail), from the agents' mean shortest
    path alone s (glamas.gridworld.dp.shortest_steps): s times STEP_SCALE, and s plus TAIL_OFFSETS
    times max(1, s // 10). On TunnelToGoal (s = 10): (10, 20, 50, 100, 1000) and (10, 11, 12, 14, 16)."""
    s = int(dp.shortest_steps(gridmap).mean())
    return tuple(s * k for k in STEP_SCALE), tuple(s + k * max(1, s // 10) for k in TAIL_OFFSETS)


def plot_steps(ax, result, optimum=None):
    """Fig. 11a: steps from start to goal, mean of the agents (mean and 95 % band over runs), on
    a log axis with ticks at round values (:func:`step_ticks`), and the tail (episode 100 on)
    zoomed on a linear axis in an inset, where the learners' final steps differ by one or two; a
    run of fewer episodes has no tail, and no inset."""
    _plot_learners(ax, result, result.steps, "steps to goal (mean of the agents)",
                   None if optimum is None else optimum["steps"])
    log_ticks, tail_ticks = step_ticks(result.config.gridmap())
    _round_log_ticks(ax, log_ticks)
    _finish(ax, result, "steps")
    if result.episodes[-1] >= TAIL_FROM:
        _plot_step_tail(ax, result, optimum, tail_ticks)


def _round_log_ticks(ax, ticks):
    """Log y axis labelled at ``ticks`` as plain numbers (no 10^k, no unlabelled minor ticks)."""
    ax.set_yscale("log")
    ax.set_yticks(ticks, [f"{t:g}" for t in ticks])
    ax.yaxis.set_minor_formatter(NullFormatter())


def _plot_step_tail(ax, result, optimum, ticks):
    """An inset in the empty upper right (every curve is below twice the shortest path there): the
    steps from TAIL_FROM on, on a linear steps axis at ``ticks``, its range widened to every curve
    where a learner that fails on another map stays far above them (then at round ticks)."""
    tail, keep = _tail(ax, result, result.steps, [0.5, 0.35, 0.47, 0.48])
    if optimum is not None:
        tail.axhline(optimum["steps"], color="black", linestyle="--", linewidth=1)
    means = [result.steps(name)[:, keep].mean(axis=0) for name in result.names()]
    low, high = min(ticks[0], *(m.min() for m in means)), max(*(m.max() for m in means))
    if high <= ticks[-1] + 2:
        tail.set_yticks(ticks)
        tail.set_ylim(ticks[0] - 0.5, ticks[-1] + 2)
    else:
        tail.yaxis.set_major_locator(MaxNLocator(nbins=5, integer=True))
        tail.set_ylim(low - 0.5, high * 1.05)
    tail.grid(axis="y", linewidth=0.4, color="0.85")
    tail.set_title(f"from episode {TAIL_FROM}, steps on a linear axis", fontsize="x-small")


def _tail(ax, result, curves, box) -> tuple:
    """An inset of ``ax`` at ``box`` (axes fractions; clear of a value written under the top edge,
    glamas.plotting.mark_greedy): each learner's ``curves(name)`` from episode TAIL_FROM on (mean
    and band over runs) on a log axis of episodes. Returns the inset and the episodes it shows."""
    tail = ax.inset_axes(box)
    keep = result.episodes >= TAIL_FROM
    for name in sorted(result.names(), key=lambda name: not drawn_underneath(name)):
        plot_mean_band(tail, result.episodes[keep], curves(name)[:, keep], registry.label(name), **_line_style(name))
    tail.set_xscale("log")
    tail.tick_params(labelsize="x-small")
    return tail, keep


def plot_reward(ax, result, optimum=None):
    """Fig. 11b: undiscounted reward per episode, mean of both agents."""
    _plot_learners(ax, result, result.reward, "reward per episode\n(mean of the agents)",
                   None if optimum is None else optimum["reward"])
    _finish(ax, result, "reward")


def plot_collisions(ax, result, optimum=None):
    """Fig. 12a: agent-agent collisions per episode, with the level the claims of zero collisions
    are judged at (:func:`collision_levels`); from episode TAIL_FROM on, zoomed in an inset on a
    linear axis a few times that level high, where a curve's place against the level shows."""
    _plot_learners(ax, result, lambda name: result.curves(name, "collisions"), "collisions per episode",
                   None if optimum is None else optimum["collisions"])
    levels = collision_levels()
    for level in levels:
        draw_claim_level(ax, level, f"zero collisions, the claims' level: <= {level:g}")
    _finish(ax, result, "collisions")
    if result.episodes[-1] >= TAIL_FROM:
        _plot_collision_tail(ax, result, levels)


def collision_levels() -> list[float]:
    """The levels of collisions per episode the claims of zero collisions are judged at, read from
    data/chapter (glamas.experiments.gridworld.analysis.curve_collision_claims)."""
    return sorted({claim.threshold for claim in curve_collision_claims()})


LEVEL_ZOOM = 4.0
"""Fig. 12a's inset reaches this many times the claims' level: room above it for a curve that misses it."""


def _plot_collision_tail(ax, result, levels):
    """An inset in the empty upper right: the collisions from TAIL_FROM on, on a linear axis from 0
    to LEVEL_ZOOM times the highest level, with the levels; a curve above the inset's top (the
    independent learners' three collisions) leaves it."""
    tail, _ = _tail(ax, result, lambda name: result.curves(name, "collisions"), [0.5, 0.4, 0.47, 0.45])
    for level in levels:
        draw_claim_level(tail, level, None)
    tail.set_ylim(-0.05 * LEVEL_ZOOM * max(levels), LEVEL_ZOOM * max(levels))
    tail.set_title(f"from episode {TAIL_FROM}, collisions up to {LEVEL_ZOOM * max(levels):g}", fontsize="x-small")


CHAPTER_COORDINATIONS = 4.0
"""Sec. 5.3: 2observe converges to "about four" coordinations per episode (Fig. 12b)."""


def plot_coordinations(ax, result):
    """Fig. 12b: steps per episode on which both 2observe agents chose to coordinate: every run
    (faint), the median over runs and its interquartile range, against the chapter's "about four",
    and the greedy policy's coordinations after training (:func:`_mark_greedy`).
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
    _mark_greedy(ax, result, ["two_observe"], "coordinations")
    legend_below(ax, ncols=1)  # four long entries: in two columns they reach past the canvas


NEED_LABELS = {"in_range": ("cannot collide this step", "could collide this step"),
               "sampled": ("preferred actions would not collide", "preferred actions would collide"),
               "outcome": ("no collision this step", "collided this step")}
"""What "no need" and "need" mean under each reading of Fig. 10, in words."""


def plot_feedback_table(ax, config: GridworldConfig):
    """Fig. 10 (lost, reconstructed): the GLA feedback 2observe's settings in ``config`` use."""
    settings = first_level_settings(config)
    f, c = settings.gla_feedback, settings.coordination_penalty_per_cell
    cells = [[f"{f[0][0]:g}", f"{f[0][1]:g}"],
             [f"{f[1][0]:g}  ({f[1][0]:g} - {c:g}·δ if both coordinate)", f"{f[1][1]:g}"]]
    ax.axis("off")
    no_need, need = NEED_LABELS[settings.gla_need]
    table = ax.table(cellText=cells, rowLabels=["act alone", "coordinate"],
                     colLabels=[f"no need ({no_need})", f"need ({need})"], loc="center", cellLoc="center")
    table.scale(1, 2)
    ax.set_title("Fig. 10, reconstructed: 2observe's GLA feedback", fontsize="medium")


def plot_coordination_probability(ax, result, config: GridworldConfig):
    """What 2observe's GLAs learned: P(coordinate | delta) of each final GLA (faint) and their
    mean, against the rule "coordinate when the agents could collide this step" (delta <= 2 on a
    4-connected grid), with the observed P(need | delta) that the GLA's feedback depends on."""
    deltas = np.arange(1, result.output("two_observe", "need_counts").shape[1])  # never at distance 0 while both act
    p = coordination_probability(result, config, deltas)
    for curve in p.reshape(-1, deltas.size):
        ax.plot(deltas, curve, alpha=0.15, linewidth=0.8, **learner_style("two_observe"))
    ax.plot(deltas, p.mean(axis=(0, 1)), "o-", label="P(coordinate), learned (mean of the GLAs)",
            **learner_style("two_observe"))
    ax.step(deltas, (deltas <= 2).astype(float), where="mid", color="black", linestyle="--",
            label="coordinate when delta <= 2 (could collide)")
    ax.plot(deltas, need_probability(result)[1:], "s:", color="tab:gray",
            label=f"P(need | delta), observed (need: {NEED_LABELS[first_level_settings(config).gla_need][1]})")
    ax.set_xlabel("delta (Manhattan distance between the agents)")
    ax.set_ylabel("probability")
    ax.set_ylim(-0.03, 1.03)
    ax.legend(fontsize="small")
