"""The figure of Fig. 10's readings, each panel on a given matplotlib Axes: the share of GLAs that
coordinate at each distance, and the final collisions, reading by reading."""

import numpy as np

from glamas.experiments.fig10_readings.experiment import READINGS
from glamas.plotting import legend_below


def _colour(row: dict) -> str:
    """A reading's colour in both panels: its place in READINGS among the ten of matplotlib's
    cycle; the reference rule, the last reading, in black."""
    k = list(READINGS).index(row["reading"])
    return "black" if k == len(READINGS) - 1 else f"C{k % 10}"


def plot_coordination(ax, rows: list[dict]):
    """The share of final GLAs that coordinate at each distance under each reading, against the
    rule "coordinate when the agents could collide this step" (delta <= 2)."""
    for k, row in enumerate(rows):
        ax.plot(row["deltas"], row["coordinating"], "o-", label=f"{k + 1}: {row['reading']}", color=_colour(row),
                linewidth=2.5 if k == 0 else 1.2)
    x = rows[0]["deltas"]
    ax.step(x, (x <= 2).astype(float), where="mid", color="black", linestyle="--",
            label="could collide (delta <= 2)")
    ax.set_xlabel("delta (Manhattan distance between the agents)")
    ax.set_ylabel("share of GLAs that coordinate (P > 1/2)")
    ax.set_ylim(-0.03, 1.03)
    legend_below(ax, ncols=2)


def plot_collisions(ax, rows: list[dict]):
    """Final collisions per episode under each reading (log axis), against the chapter's "zero
    collisions" (at most one per 20 episodes, the claim's threshold), and the greedy policy's after
    training (black diamonds; at the axis' left edge where none collided)."""
    y = np.arange(len(rows))[::-1]
    ax.barh(y, [row["collisions"] for row in rows], color=[_colour(row) for row in rows])
    greedy = np.array([row["greedy_collisions"] for row in rows])
    left = min([row["collisions"] for row in rows] + list(greedy[greedy > 0])) / 3
    ax.plot(np.maximum(greedy, left), y, "D", color="white", markeredgecolor="black", linestyle="none",
            label="greedy policy after training (learning off), mean over runs")
    ax.set_yticks(y, [f"{k + 1}: {row['reading']}" for k, row in enumerate(rows)], fontsize="small")
    ax.axvline(0.05, color="black", linestyle="--", linewidth=1, label="zero collisions (claim: <= 0.05)")
    ax.set_xscale("log")
    ax.set_xlabel("final collisions per episode")
    legend_below(ax, ncols=1)
