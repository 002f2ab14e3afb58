"""Drawing a gridworld map (the chapter's Fig. 9) and agents' paths on a matplotlib Axes."""

import numpy as np
from matplotlib.patches import Circle, Rectangle

from glamas.gridworld.maps import GridMap
from glamas.gridworld.rules import E, S

_AGENT_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple",
                  "tab:brown", "tab:pink", "tab:gray", "tab:olive")


def draw_map(ax, gridmap: GridMap):
    """Walls, blocked cells, the goal and the agents' numbered starts; row 0 at the top."""
    rows, cols = gridmap.n_rows, gridmap.n_cols
    ax.set_xlim(-0.05, cols + 0.05)
    ax.set_ylim(rows + 0.05, -0.05)
    ax.set_aspect("equal")
    ax.set_axis_off()
    for x in range(cols + 1):
        ax.plot([x, x], [0, rows], color="0.85", linewidth=0.6, zorder=0)
    for y in range(rows + 1):
        ax.plot([0, cols], [y, y], color="0.85", linewidth=0.6, zorder=0)
    for cell in range(gridmap.n_cells):
        r, c = gridmap.row_col(cell)
        if gridmap.blocked[cell]:
            ax.add_patch(_square(c, r, "0.35"))
        if gridmap.is_goal[cell]:
            ax.add_patch(_square(c, r, "#d9f0d3"))
            ax.text(c + 0.5, r + 0.5, "G", ha="center", va="center", fontsize=14, fontweight="bold")
    for wall in _walls(gridmap):
        ax.plot(*wall, color="black", linewidth=3, solid_capstyle="projecting", zorder=3)
    for agent, start in enumerate(gridmap.starts):
        r, c = gridmap.row_col(int(start))
        ax.add_patch(_disc(c, r, _AGENT_COLOURS[agent % len(_AGENT_COLOURS)]))
        ax.text(c + 0.5, r + 0.5, str(agent + 1), ha="center", va="center", color="white",
                fontsize=11, fontweight="bold", zorder=5)


def draw_paths(ax, gridmap: GridMap, cells: np.ndarray):
    """The agents' cells over an episode (array (n_steps + 1, n_agents)) as offset polylines."""
    n = cells.shape[1]
    for agent in range(n):
        offset = 0.12 * (agent - (n - 1) / 2)
        points = np.array([gridmap.row_col(int(c)) for c in cells[:, agent]], dtype=float)
        ax.plot(points[:, 1] + 0.5 + offset, points[:, 0] + 0.5 + offset, marker="o", markersize=3,
                color=_AGENT_COLOURS[agent % len(_AGENT_COLOURS)], linewidth=1.5, zorder=4,
                label=f"agent {agent + 1}")


def _walls(gridmap: GridMap):
    """Line segments ([x0, x1], [y0, y1]) of the border and of every wall between two free cells."""
    rows, cols = gridmap.n_rows, gridmap.n_cols
    segments = [([0, cols], [0, 0]), ([0, cols], [rows, rows]), ([0, 0], [0, rows]), ([cols, cols], [0, rows])]
    for cell in range(gridmap.n_cells):
        r, c = gridmap.row_col(cell)
        if c + 1 < cols and gridmap.next_cell[cell, E] == cell and not _touches_blocked(gridmap, cell, cell + 1):
            segments.append(([c + 1, c + 1], [r, r + 1]))
        if r + 1 < rows and gridmap.next_cell[cell, S] == cell and not _touches_blocked(gridmap, cell, cell + cols):
            segments.append(([c, c + 1], [r + 1, r + 1]))
    return segments


def _touches_blocked(gridmap, a, b):
    return bool(gridmap.blocked[a] or gridmap.blocked[b])


def _square(c, r, colour):
    return Rectangle((c, r), 1, 1, facecolor=colour, edgecolor="none", zorder=1)


def _disc(c, r, colour):
    return Circle((c + 0.5, r + 0.5), 0.3, facecolor=colour, edgecolor="none", zorder=4)
