"""The figure of Fig. 9's map solved: the agents' paths in the optimal or the selfish episode, on a
given matplotlib Axes."""

from glamas.experiments.gridworld_optimum.experiment import GridworldOptimumResult
from glamas.gridworld import draw
from glamas.errors import UserError


WAITS = {"optimal": "waits: bumps into a wall", "selfish": "stays: bounced back by a collision"}
"""Why an agent stays in a cell in each episode (the optimum's yielding agent walks into a wall
once; the selfish agents keep colliding at the passage)."""


def plot_episode(ax, result: GridworldOptimumResult, which: str = "optimal"):
    """The map of Fig. 9 with the agents' paths in the 'optimal' or the 'selfish' episode, the
    step at which each agent enters each cell, and a ring where an agent stays put."""
    episodes = {"optimal": result.optimal, "selfish": result.selfish}
    if which not in episodes:
        raise UserError(f"which must be one of {sorted(episodes)}, got {which!r}")
    draw.draw_map(ax, result.gridmap)
    draw.draw_paths(ax, result.gridmap, episodes[which].cells, numbered=True, wait_label=WAITS[which])
    steps = ", ".join("-" if s < 0 else str(s) for s in episodes[which].steps_to_goal)
    ax.set_title(f"{which}\nsteps to goal: {steps}; collisions: {episodes[which].collisions}", fontsize=9)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), ncols=2, fontsize=8, frameon=False)
