"""A glamas map and a plan of it in the terms of POGEMA (Skrynnik et al., ICLR 2025), the field's
many-agent grid benchmark, so that its own environment can replay glamas's instances: the grid as
rows of '.' (free) and '#' (blocked), each agent's start and target as [row, column] (POGEMA's
``GridConfig`` fields ``map``, ``agents_xy`` and ``targets_xy``), and a plan's moves as POGEMA's
actions. glamas does not depend on POGEMA: ``benchmarks/pogema_replay.py`` reads what
``benchmarks/pogema_tasks.py`` writes with these functions, in a virtual environment of its own.

POGEMA's grid knows blocked cells and the border only, one target per agent, and an action that
waits; a glamas map may also have walls between two free cells (TunnelToGoal's), several goal
cells per agent, and no wait (an agent stays by bumping). A map with such a wall is refused; an
agent with several goal cells takes the one its plan ends in; a bump is POGEMA's wait.
"""

import numpy as np

from glamas.errors import UserError
from glamas.gridworld.maps import GridMap
from glamas.gridworld.plans import Plan

POGEMA_MOVES = ((0, 0), (-1, 0), (1, 0), (0, -1), (0, 1))
"""POGEMA's actions 0-4 as (row, column) moves: wait, up, down, left, right (its ``GridConfig.MOVES``)."""
GLAMAS_MOVES = ((-1, 0), (0, 1), (1, 0), (0, -1))
"""glamas's actions N, E, S, W as (row, column) moves (:mod:`glamas.gridworld.rules`)."""


def pogema_task(gridmap: GridMap, plan: Plan | None = None) -> dict:
    """``gridmap`` as POGEMA's ``GridConfig`` takes it: ``map`` (its rows of '.' and '#'),
    ``agents_xy`` and ``targets_xy`` (each agent's start and goal as [row, column]). An agent with
    several goal cells takes the one it enters in ``plan``; without a plan, it is refused."""
    _check_no_inner_walls(gridmap)
    rows = ["".join("#" if gridmap.blocked[gridmap.cell(r, c)] else "." for c in range(gridmap.n_cols))
            for r in range(gridmap.n_rows)]
    return {"map": "\n".join(rows),
            "agents_xy": [list(gridmap.row_col(int(cell))) for cell in gridmap.starts],
            "targets_xy": [list(gridmap.row_col(_target(gridmap, plan, i))) for i in range(gridmap.n_agents)]}


def pogema_actions(gridmap: GridMap, plan: Plan) -> list[list[int]]:
    """(makespan, agents): every agent's POGEMA action at every step of ``plan``: the move from its
    cell to its next one, wait where it stays (a bump in glamas) and once it is in its goal."""
    cells = np.asarray(plan.cells)
    if cells.shape[1:] != gridmap.starts.shape or not np.array_equal(cells[0], gridmap.starts):
        raise UserError(f"the plan does not start from the starts of map {gridmap.name!r}; give a plan of that map")
    actions = []
    for t in range(cells.shape[0] - 1):
        row = []
        for i in range(gridmap.n_agents):
            here, there = int(cells[t, i]), int(cells[t + 1, i])
            (r0, c0), (r1, c1) = gridmap.row_col(here), gridmap.row_col(there)
            if there != here and there not in gridmap.next_cell[here]:
                raise UserError(f"the plan moves agent {i + 1} from ({r0}, {c0}) to ({r1}, {c1}) at step {t + 1}, "
                                f"not one move of map {gridmap.name!r}; give a plan of that map")
            row.append(0 if t >= plan.steps[i] else POGEMA_MOVES.index((r1 - r0, c1 - c0)))
        actions.append(row)
    return actions


def _check_no_inner_walls(gridmap: GridMap):
    """Refuse a map with a wall between two free cells: POGEMA's grid cannot hold it."""
    for cell in np.flatnonzero(~gridmap.blocked):
        r, c = gridmap.row_col(int(cell))
        for a, (dr, dc) in enumerate(GLAMAS_MOVES):
            inside = 0 <= r + dr < gridmap.n_rows and 0 <= c + dc < gridmap.n_cols
            if inside and not gridmap.blocked[gridmap.cell(r + dr, c + dc)] and gridmap.next_cell[cell, a] == cell:
                raise UserError(f"map {gridmap.name!r} has a wall between the free cells ({r}, {c}) and "
                                f"({r + dr}, {c + dc}), which POGEMA's grid cannot hold (it has blocked cells only); "
                                "export a map whose moves only blocked cells and the border stop")


def _target(gridmap: GridMap, plan: Plan | None, agent: int) -> int:
    """Agent ``agent``'s one goal cell, or the goal cell it enters in ``plan``."""
    goals = gridmap.goal_cells(agent)
    if len(goals) == 1:
        return goals[0]
    if plan is None:
        raise UserError(f"agent {agent + 1} of map {gridmap.name!r} has {len(goals)} goal cells and POGEMA takes "
                        "one target per agent; give a plan, whose last cell of each agent is its target")
    return int(np.asarray(plan.cells)[int(plan.steps[agent]), agent])
