"""Experiment 1's figures: Fig. 5's regions and learned lines, and the average feedback over
iterations of Fig. 6 (and of any results side by side), each on a given matplotlib Axes."""

import numpy as np

from glamas import lineworld
from glamas.experiments.single_gla.analysis import B_BEST_LINE_OFFSETS, bounded
from glamas.experiments.single_gla.experiment import SingleGLAResult
from glamas.plotting import ON_LINES, legend_below, plot_mean_band
from glamas.portable import weighted_sum
from glamas.errors import UserError


def plot_regions(ax, region3_reward: str = "move_apart"):
    """Fig. 5a: the three regions of experiment 1 and their rewarded joint actions (A, B), region 3
    read as ``region3_reward``."""
    x = np.linspace(-1.0, 1.0, 401)
    upper = np.clip(x + lineworld.CLOSE_DISTANCE, -1.0, 1.0)
    lower = np.clip(x - lineworld.CLOSE_DISTANCE, -1.0, 1.0)
    ax.fill_between(x, upper, 1.0, color="tab:blue", alpha=0.35, linewidth=0)
    ax.fill_between(x, -1.0, lower, color="tab:orange", alpha=0.35, linewidth=0)
    ax.fill_between(x, lower, upper, color="tab:green", alpha=0.35, linewidth=0)
    ax.text(-0.55, 0.7, "1: (L, L)", ha="center", va="center")
    ax.text(0.55, -0.7, "2: (R, R)", ha="center", va="center")
    label = {"move_apart": "3: move apart", "fixed_joint_action": "3: (L, R)"}[region3_reward]
    ax.text(0.0, 0.0, label, ha="center", va="center", rotation=45)
    _square(ax)


def plot_learned_lines(ax, result: SingleGLAResult, run_index: int, grid: int = 200):
    """Fig. 5b: each agent's learned line (u_L - u_R).x = 0 (joint context) and the most
    probable joint action in each cell of the partition the two lines make, written where the cell
    is farthest from every line drawn and from the square's edges (so that no line crosses it)."""
    if result.config.context != "joint":
        raise UserError(f"learned lines are drawn in the (x1, x2) plane: they need the joint "
                         f"context, this result used {result.config.context!r}")
    u = result.params[run_index]
    x1, x2 = lineworld.state_grid(grid)
    xs = np.column_stack([x1, x2, np.ones_like(x1)])
    hu = bounded(u, result.config)
    prefers_left = [weighted_sum(xs, hu[agent, 0] - hu[agent, 1]) > 0 for agent in range(2)]
    t = np.linspace(-1.0, 1.0, 401)
    _draw_reference_lines(ax, t, result.config.region3_reward)
    for agent, (name, colour) in enumerate((("A", "tab:red"), ("B", "tab:purple"))):
        w = hu[agent, 0] - hu[agent, 1]
        _draw_line(ax, w, t, colour, f"agent {name}")
    lines = [hu[agent, 0] - hu[agent, 1] for agent in range(2)] + [
        np.array([1.0, -1.0, c]) for offsets, _ in REFERENCE_LINES[result.config.region3_reward] for c in offsets]
    clear = np.min([np.abs(weighted_sum(xs, w)) / np.hypot(w[0], w[1]) for w in lines]
                   + [1 - np.abs(x1), 1 - np.abs(x2)], axis=0)  # and from the square's edges
    for left_a in (True, False):
        for left_b in (True, False):
            cell = (prefers_left[0] == left_a) & (prefers_left[1] == left_b)
            if cell.mean() > 0.02:  # label cells large enough to hold text
                label = f"({'L' if left_a else 'R'}, {'L' if left_b else 'R'})"
                at = np.flatnonzero(cell)[np.argmax(clear[cell])]  # the cell's point farthest from every line
                ax.text(x1[at], x2[at], label, ha="center", va="center", path_effects=ON_LINES)
    legend_below(ax, ncols=2)
    _square(ax)


REFERENCE_LINES = {
    "move_apart": (((0.0,), "x1 = x2: agent A's ideal line"),
                   (B_BEST_LINE_OFFSETS, "x2 = x1 ± 0.5: agent B's best single lines (tied)")),
    "fixed_joint_action": (((-0.5,), "x2 = x1 - 0.5: agent A's ideal line"),
                           ((0.5,), "x2 = x1 + 0.5: agent B's ideal line")),
}
"""Per reading of region 3, each agent's best single lines x2 = x1 + c (offsets c) and their
label: under 'fixed_joint_action' A plays L where x2 - x1 > -0.5 and B where x2 - x1 > 0.5."""


def _draw_reference_lines(ax, t, region3_reward: str):
    """Where each agent's best single lines lie (:data:`REFERENCE_LINES`)."""
    for (offsets, label), colour, style in zip(REFERENCE_LINES[region3_reward], ("black", "0.4"), ("--", ":")):
        for k, c in enumerate(offsets):
            inside = np.abs(t + c) <= 1
            ax.plot(t[inside], t[inside] + c, color=colour, linestyle=style, linewidth=1.3,
                    label=label if k == 0 else None)


def plot_reward_curves(ax, results: dict):
    """Fig. 6: average feedback over iterations per context encoding, mean and 95 % band over runs."""
    for name, res in results.items():
        plot_mean_band(ax, res.iteration, res.reward, label=name)
    ax.set_xlabel("iteration")
    ax.set_ylabel("average reward")
    legend_below(ax, ncols=3)


def _draw_line(ax, w, t, colour, label):
    """The line w[0] x1 + w[1] x2 + w[2] = 0 inside the square (nothing if it misses it)."""
    if abs(w[1]) >= abs(w[0]) and w[1] != 0:
        x, y = t, -(w[0] * t + w[2]) / w[1]
    elif w[0] != 0:
        x, y = -(w[1] * t + w[2]) / w[0], t
    else:
        return
    inside = (np.abs(x) <= 1) & (np.abs(y) <= 1)
    ax.plot(np.where(inside, x, np.nan), np.where(inside, y, np.nan), color=colour, lw=2, label=label)


def _square(ax):
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x1 (position of agent A)")
    ax.set_ylabel("x2 (position of agent B)")
