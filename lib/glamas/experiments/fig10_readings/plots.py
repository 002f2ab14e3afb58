"""The figure of Fig. 10's readings, each panel on a given matplotlib Axes: the share of GLAs that
coordinate at each distance, and the final collisions, reading by reading."""

import numpy as np

from glamas.experiments.fig10_readings.experiment import READINGS
from glamas.experiments.gridworld.plots import collision_levels
from glamas.plotting import GREEDY_LABEL, legend_below


WORDS = {
    "in_range, L=8": "need = could collide, box 8 (default)",
    "in_range, L=8, init 1": "the same, started in [-1, 1]",
    "in_range, L=8, unit delta": "the same, distance in [0, 1]",
    "in_range, L=8, unit delta, init 1": "distance in [0, 1], started in [-1, 1]",
    "in_range, L=1": "need = could collide, box 1",
    "in_range, unit delta, L=1": "box 1, distance in [0, 1]",
    "in_range, coordinating never wrong": "coordinating never wrong",
    "sampled, L=1": "need = actions collide, box 1",
    "sampled, L=8": "need = actions collide, box 8",
    "outcome, L=8": "need = collided, box 8",
    "no GLA: fixed rule delta <= 2": "no GLA: rule delta <= 2",
}
"""Each reading of :data:`READINGS` in words, as the figure's labels give it."""


def _label(k: int, row: dict) -> str:
    return f"{k + 1}: {WORDS.get(row['reading'], row['reading'])}"


def _colour(row: dict) -> str:
    """A reading's colour in both panels: its place in READINGS among the ten of matplotlib's
    cycle; the reference rule, the last reading, in black."""
    k = list(READINGS).index(row["reading"])
    return "black" if k == len(READINGS) - 1 else f"C{k % 10}"


def plot_coordination(ax, rows: list[dict]):
    """The share of final GLAs that coordinate at each distance under each reading, against the
    rule "coordinate when the agents could collide this step" (delta <= 2)."""
    for k, row in enumerate(rows):
        ax.plot(row["deltas"], row["coordinating"], "o-", label=_label(k, row), color=_colour(row),
                linewidth=2.5 if k == 0 else 1.2)
    x = rows[0]["deltas"]
    ax.step(x, (x <= 2).astype(float), where="mid", color="black", linestyle="--",
            label="could collide (delta <= 2)")
    ax.set_xlabel("delta (Manhattan distance between the agents)")
    ax.set_ylabel("share of GLAs that coordinate (P > 1/2)")
    ax.set_ylim(-0.03, 1.03)
    legend_below(ax, ncols=2)


def plot_collisions(ax, rows: list[dict]):
    """Final collisions per episode under each reading (a dot in the reading's colour, on a log
    axis: no bar, whose length a log axis would measure from an arbitrary floor), against the
    chapter's "zero collisions" (at most one per 20 episodes, the claim's level), and the greedy
    policy's after training (diamonds; a left-pointing triangle at the axis' left edge where it
    never collided, which a log axis cannot place)."""
    y = np.arange(len(rows))[::-1]
    ax.scatter([row["collisions"] for row in rows], y, c=[_colour(row) for row in rows], s=60, zorder=3,
               label="final collisions per episode while learning")
    greedy = np.array([row["greedy_collisions"] for row in rows])
    ax.plot(greedy[greedy > 0], y[greedy > 0], "D", color="white", markeredgecolor="black", linestyle="none",
            label=GREEDY_LABEL)
    ax.set_xscale("log")
    if (greedy == 0).any():
        edge = ax.get_xlim()[0]
        ax.plot(np.full((greedy == 0).sum(), edge), y[greedy == 0], "<", color="white",
                markeredgecolor="black", linestyle="none", clip_on=False, label="greedy policy: no collision")
        ax.set_xlim(left=edge)
    ax.set_yticks(y, [_label(k, row) for k, row in enumerate(rows)], fontsize="small")
    ax.grid(axis="y", color="0.9", linewidth=0.8)
    level, = collision_levels()
    ax.axvline(level, color="black", linestyle="--", linewidth=1, label=f"zero collisions (claim: <= {level:g})")
    ax.set_xlabel("final collisions per episode")
    legend_below(ax, ncols=1)
