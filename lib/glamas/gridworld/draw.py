"""Drawing a gridworld map (the chapter's Fig. 9) and agents' paths on a matplotlib Axes."""

import numpy as np
from matplotlib.patches import Circle, Rectangle

from glamas.gridworld.maps import GridMap
from glamas.gridworld.rules import E, S
from glamas.plotting import ON_LINES

_AGENT_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple",
                  "tab:brown", "tab:pink", "tab:gray", "tab:olive")


INDEX_MARGIN = 0.5
"""Room left of and above the map for the row and column indices."""


def draw_map(ax, gridmap: GridMap):
    """Walls, blocked cells, the goals and the agents' numbered starts; row 0 at the top, with the
    row and column indices (from 0, as the notebooks cite cells) along the left and top edges. A
    goal of every agent is a green 'G' (the chapter's Fig. 9); a goal of some agents is striped in
    their colours and labelled with their numbers ('G2', 'G1,2')."""
    rows, cols = gridmap.n_rows, gridmap.n_cols
    ax.set_xlim(-INDEX_MARGIN, cols + 0.05)
    ax.set_ylim(rows + 0.05, -INDEX_MARGIN)
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
        if gridmap.shared_goal[cell]:
            ax.add_patch(_square(c, r, "#d9f0d3"))
            # smaller on wide maps, whose cells are small: the steps' numbers in its corners stay clear
            ax.text(c + 0.5, r + 0.5, "G", ha="center", va="center", fontsize=14 if cols <= 6 else 8,
                    fontweight="bold")
        elif gridmap.is_goal[cell]:
            _draw_own_goal(ax, r, c, gridmap.goal_owners(cell),
                           under_a_start=cell in gridmap.starts)
    for wall in _walls(gridmap):
        ax.plot(*wall, color="black", linewidth=3, solid_capstyle="projecting", zorder=3)
    for agent, start in enumerate(gridmap.starts):
        r, c = gridmap.row_col(int(start))
        ax.add_patch(_disc(c, r, agent_colour(agent)))
        ax.text(c + 0.5, r + 0.5, str(agent + 1), ha="center", va="center", color="white",
                fontsize=11, fontweight="bold", zorder=5)
    _draw_indices(ax, rows, cols)


def _draw_own_goal(ax, r: int, c: int, agents: list[int], under_a_start: bool):
    """A goal cell of ``agents`` (0 for agent 1), not of every agent: a stripe per agent in its
    colour, light, and 'G' with their numbers (at the cell's edge where a start's disc covers its
    middle, as in ISR, CIT and CMU, where each agent's goal is the other's start)."""
    width = 1.0 / len(agents)
    for k, agent in enumerate(agents):
        ax.add_patch(Rectangle((c + k * width, r), width, 1, facecolor=agent_colour(agent), alpha=0.25,
                               edgecolor="none", zorder=1))
    label = "G" + ",".join(str(a + 1) for a in agents)
    size = 7 if under_a_start or len(label) > 2 else 12
    # under a start's disc, at the edge away from the corner where the owner writes its arrival
    foot = 0.88 if _NUMBER_CORNERS[agents[0] % len(_NUMBER_CORNERS)][1] < 0.5 else 0.12
    ax.text(c + 0.5, r + (foot if under_a_start else 0.5), label, ha="center", va="center", fontweight="bold",
            fontsize=size, color=agent_colour(agents[0]) if len(agents) == 1 else "black", zorder=5)


def agent_colour(agent: int) -> str:
    """The colour of agent ``agent`` (0 for agent 1), cycling through nine."""
    return _AGENT_COLOURS[agent % len(_AGENT_COLOURS)]


def _draw_indices(ax, rows: int, cols: int):
    """Column indices above the map, row indices left of it, and which is which in the corner."""
    for c in range(cols):
        ax.text(c + 0.5, -0.2, str(c), ha="center", va="center", fontsize=7, color="0.3")
    for r in range(rows):
        ax.text(-0.2, r + 0.5, str(r), ha="center", va="center", fontsize=7, color="0.3")
    ax.text(-0.2, -0.2, "r\\c", ha="center", va="center", fontsize=6, color="0.5")


def draw_paths(ax, gridmap: GridMap, cells: np.ndarray, numbered: bool = False, wait_label: str | None = None):
    """The agents' cells over an episode (array (n_steps + 1, n_agents)) as offset polylines, a dot
    on each cell passed through (none on a start or a goal, which their disc and letter mark).

    ``numbered``: the step at which each agent enters each cell next to it (a range "5-6" where it
    stays, the entry step alone in its goal), each agent's numbers in a corner of its own
    (agent 1 upper left, 2 lower right, 3 upper right, 4 lower left).
    ``wait_label``: a ring where an agent stays in a cell other than its goal, labelled so.
    """
    n = cells.shape[1]
    for agent in range(n):
        offset = 0.12 * (agent - (n - 1) / 2)
        colour = agent_colour(agent)
        points = np.array([gridmap.row_col(int(c)) for c in cells[:, agent]], dtype=float)
        # a dot on each cell passed through; the starts' discs and the goals' letters mark their own cells
        passed = [t for t, c in enumerate(cells[:, agent]) if c not in gridmap.starts and not gridmap.is_goal[c]]
        ax.plot(points[:, 1] + 0.5 + offset, points[:, 0] + 0.5 + offset, marker="o", markersize=3,
                markevery=passed, color=colour, linewidth=1.5, zorder=4, label=f"agent {agent + 1}")
        stays = _stays(cells[:, agent])
        if numbered:
            _number_steps(ax, gridmap, stays, agent, colour)
        if wait_label is not None:
            _mark_waits(ax, gridmap, stays, agent, offset, wait_label if agent == 0 else None)


def _stays(path: np.ndarray) -> list[tuple[int, int, int]]:
    """(first step, last step, cell) of every stretch of consecutive steps in one cell."""
    stretches = []
    for t, cell in enumerate(path):
        if stretches and stretches[-1][2] == cell:
            stretches[-1] = (stretches[-1][0], t, int(cell))
        else:
            stretches.append((t, t, int(cell)))
    return stretches


_NUMBER_CORNERS = ((0.2, 0.22), (0.78, 0.8), (0.78, 0.22), (0.2, 0.8))
"""In which corner of a cell agents 1 to 4 write their step numbers (x, y from the upper left)."""
INSET = 0.05
"""How far (a share of a cell) step numbers stand from their corner's edges: in the corner, clear
of the path through the cell's middle, the letter of a goal and the ring of a wait."""


def _number_steps(ax, gridmap, stays, agent, colour):
    """Agent ``agent``'s step numbers in the corner of its own of each cell it enters after its
    start, a cell entered again listing all its visits ("1, 3")."""
    dx, dy = _NUMBER_CORNERS[agent % len(_NUMBER_CORNERS)]
    visits: dict = {}
    for first, last, cell in stays:
        if last == 0:
            continue  # the start: its disc marks it
        once = first == last or gridmap.is_goal_of(agent, cell)  # an agent in its goal stays there: its entry step only
        visits.setdefault(cell, []).append(str(first) if once else f"{first}-{last}")
    for cell, labels in visits.items():
        r, c = gridmap.row_col(cell)
        ax.text(c + (INSET if dx < 0.5 else 1 - INSET), r + (INSET if dy < 0.5 else 1 - INSET), ", ".join(labels),
                ha="left" if dx < 0.5 else "right", va="top" if dy < 0.5 else "bottom", fontsize=6, color=colour,
                fontweight="bold", zorder=6, path_effects=ON_LINES)


def _mark_waits(ax, gridmap, stays, agent, offset, label):
    """A ring on every cell (not its goal) the agent stays in for more than one step."""
    waits = [cell for first, last, cell in stays if last > first and not gridmap.is_goal_of(agent, cell)]
    for k, cell in enumerate(waits):
        r, c = gridmap.row_col(cell)
        ax.plot(c + 0.5 + offset, r + 0.5 + offset, marker="o", markersize=11, markerfacecolor="none",
                markeredgecolor="black", markeredgewidth=1.5, linestyle="none", zorder=5,
                label=label if k == 0 else None)


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
