"""Experiment 2's figures, each on a given matplotlib Axes: the learned boundaries over the
parabola (Fig. 7a), P(L) in region I over iterations (Fig. 7b) and the stuck sweep."""

import numpy as np

from glamas.experiments.and_network.analysis import stuck_runs, wilson_interval
from glamas.experiments.and_network.experiment import ANDNetworkConfig, ANDNetworkResult, SweepResult, left_map
from glamas.plotting import data_bounds, legend_below


def plot_parabola(ax, config: ANDNetworkConfig):
    """Region I (inside the parabola) shaded, with its border."""
    x = np.linspace(-1.0, 1.0, 401)
    border = config.parabola_curvature * x ** 2 + config.parabola_offset
    ax.fill_between(x, np.clip(border, -1, 1), 1.0, color="tab:blue", alpha=0.2, linewidth=0)
    ax.plot(x, np.where(border <= 1, border, np.nan), color="k", lw=1.5)
    ax.text(0.0, 0.4, "I: (L, L) 0.9", ha="center")
    ax.text(0.98, -0.95, f"II: (R, R) {config.reward_outside:g}", ha="right")
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x1 (position of agent A)")
    ax.set_ylabel("x2 (position of agent B)")


AGENT_COLOURS = (("A", "tab:red"), ("B", "tab:purple"))
"""Each agent's name and colour in Fig. 7a and 7b."""


def plot_boundaries(ax, result: ANDNetworkResult, run_index: int, grid: int = 200, title: str | None = None):
    """Fig. 7a: over the parabola, each agent's learned boundary P(L) = 1/2 for one run; ``title``
    says which run it is (default: its index), the index then goes to the legend's title."""
    plot_parabola(ax, result.config)
    centres = -1.0 + (np.arange(grid) + 0.5) * (2.0 / grid)
    x1, x2 = np.meshgrid(centres, centres, indexing="xy")
    p_left = left_map(result, run_index, x1.ravel(), x2.ravel())
    for agent, (name, colour) in enumerate(AGENT_COLOURS):
        ax.contour(x1, x2, p_left[agent].reshape(x1.shape), levels=[0.5], colors=colour,
                   linewidths=2)
        ax.plot([], [], color=colour, lw=2, label=f"agent {name}: P(L) = 1/2")
    legend_below(ax, title=None if title is None else f"run {run_index}", title_fontsize="small")
    ax.set_title(f"run {run_index}" if title is None else title, fontsize="medium")


def plot_prob_left(ax, result: ANDNetworkResult):
    """Fig. 7b: P(L) in region I of both agents over iterations: every run faint (the runs split
    into those that learned and those stuck in 'R everywhere', which a mean over all runs would
    hide), and each group's mean per agent, A solid and wide under B dashed, so both show; the
    stuck group's means carry markers, so that the legend tells the groups apart."""
    stuck = stuck_runs(result)
    for agent, (name, colour) in enumerate(AGENT_COLOURS):
        ax.plot(result.iteration, result.prob_left[:, :, agent].T, color=colour, alpha=0.12, linewidth=0.6)
    for group, label, marker in ((~stuck, "that learned", None), (stuck, "that got stuck", "o")):
        for agent, (name, colour) in enumerate(AGENT_COLOURS):
            if group.any():
                ax.plot(result.iteration, result.prob_left[group, :, agent].mean(axis=0), color=colour,
                        linewidth=2.8 if agent == 0 else 1.4, linestyle="-" if agent == 0 else "--",
                        marker=marker, markevery=0.1, markersize=6 if agent == 0 else 3,
                        label=f"agent {name}, mean of the {group.sum()} runs {label}")
    ax.plot([], [], color="0.5", alpha=0.4, linewidth=0.6, label="one run (per agent)")
    ax.set_title(f"stuck in 'R everywhere' at the end: {stuck.sum()} of {stuck.size} runs "
                 f"({stuck.mean():.0%})", fontsize="medium")
    ax.set_xlabel("iteration")
    ax.set_ylabel("P(L) in region I")
    ax.set_ylim(0, 1)
    legend_below(ax, ncols=1)


def plot_stuck_fraction(ax, result: SweepResult):
    """Fraction of runs stuck in 'R everywhere' against region II's reward (the rewards swept
    labelled), with 95 % Wilson intervals over the runs, the legend saying so."""
    n = result.stuck.shape[1]
    fractions = result.stuck.mean(axis=1)
    low, high = wilson_interval(fractions, n)
    ax.errorbar(result.reward_outside, fractions, yerr=[fractions - low, high - fractions],
                marker="o", capsize=3, label=f"fraction of the {n} runs; bars: its 95 % Wilson interval")
    ax.set_xticks(result.reward_outside, [f"{reward:g}" for reward in result.reward_outside])
    ax.set_xlabel("reward of (R, R) in region II")
    ax.set_ylabel("fraction of runs stuck in 'R everywhere'")
    ax.set_ylim(-0.02, 1.02)
    data_bounds(ax, (0.0, 1.0))
    ax.legend(loc="upper left", fontsize="small")
