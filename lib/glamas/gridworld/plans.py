"""Optimal joint plans as multi-agent path finding counts them: the least sum of costs and the least
makespan, over the joint MMDP's transitions (:func:`glamas.gridworld.dp.joint_mdp`).

The MMDP's optimum (the chapter's Alg. 2, Fig. 9) pays +100 once, when the last agent is in: how
early the other agents arrive does not count, so its steps per agent are those of one among many
equally good joint policies. Path finding counts a plan by its *sum of costs* (every agent's steps
until it is in its goal, summed) and its *makespan* (the step at which the last agent is in),
against the lower bounds each agent's shortest path alone gives. A plan here is a sequence of joint
actions under glamas's rules (four moves, walls, agents leaving the game at their goal): without a
collision (a collision bounces both agents back, which only loses steps) and waiting only as the
rules allow it, by a bump into a wall or by stepping aside.

:func:`least_sum_of_costs` (ties broken by the makespan) and :func:`least_makespan` (ties broken by
the sum of costs) are Dijkstra's algorithm over the joint states, a step from a joint state costing
each agent still acting one: exact on every map whose joint tables fit (:func:`dp.tabulable`).
"""

import heapq
from dataclasses import dataclass

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas.gridworld import dp, rules
from glamas.gridworld.joint import joint_index, split_index
from glamas.gridworld.maps import GridMap

_SCALE = 1 << 32
"""Weight of the primary count in a step's cost, (primary, secondary) as one integer: a plan's
secondary count stays far below it."""


@dataclass(frozen=True)
class Plan:
    """A collision-free joint plan from the starts: optimal as this module finds it, a reference
    plan as :mod:`glamas.gridworld.prioritized` does."""

    steps: np.ndarray
    """int (agents,): each agent's steps until it is in its goal."""
    cells: np.ndarray
    """int (makespan + 1, agents): the agents' cells at every step, starts first."""

    @property
    def sum_of_costs(self) -> int:
        return int(self.steps.sum())

    @property
    def makespan(self) -> int:
        return int(self.steps.max())


def lower_bounds(gridmap: GridMap) -> tuple[int, int]:
    """(sum of costs, makespan) no plan can beat: each agent's shortest path alone
    (:func:`dp.shortest_steps`), summed and their largest."""
    alone = dp.shortest_steps(gridmap)
    return int(alone.sum()), int(alone.max())


def least_sum_of_costs(gridmap: GridMap, bounce: str = "previous") -> Plan:
    """The collision-free plan of least sum of costs (the least makespan among those)."""
    return _plan(gridmap, bounce, by_makespan=False)


def least_makespan(gridmap: GridMap, bounce: str = "previous") -> Plan:
    """The collision-free plan of least makespan (the least sum of costs among those)."""
    return _plan(gridmap, bounce, by_makespan=True)


def _plan(gridmap: GridMap, bounce: str, by_makespan: bool) -> Plan:
    if not dp.tabulable(gridmap):
        raise UserError(f"map {gridmap.name!r}: its joint tables are too large for an exact plan "
                        f"({dp.tabulated_bytes(gridmap) / 2 ** 30:.0f} GiB); use plans.lower_bounds")
    mdp = dp.joint_mdp(gridmap, bounce)
    start = int(joint_index(gridmap.starts, gridmap.n_cells))
    cost, parent = _dijkstra(mdp.next_state, mdp.collisions, mdp.valid, gridmap.goals, start, gridmap.n_cells,
                             by_makespan)
    reached = np.flatnonzero(parent >= 0)
    ends = reached[gridmap.in_goal(_all_cells(reached, gridmap)).all(axis=1)]  # one call for every state
    if not ends.size:
        raise UserError(f"map {gridmap.name!r}: no collision-free plan brings every agent to its goal")
    states = [int(min(ends, key=lambda s: cost[s]))]
    while states[-1] != start:
        states.append(int(parent[states[-1]]))
    cells = np.array([_cells(s, gridmap) for s in reversed(states)], dtype=np.int64)
    arrived = gridmap.in_goal(cells)  # (makespan + 1, agents)
    return Plan(steps=np.argmax(arrived, axis=0).astype(np.int64), cells=cells)


def _all_cells(states: np.ndarray, gridmap: GridMap) -> np.ndarray:
    """(states, agents): the cells of every joint state of ``states`` (:func:`glamas.gridworld.joint.split_index`)."""
    powers = gridmap.n_cells ** np.arange(gridmap.n_agents - 1, -1, -1, dtype=np.int64)
    return (states[:, None] // powers) % gridmap.n_cells


def _cells(state: int, gridmap: GridMap) -> np.ndarray:
    out = np.empty(gridmap.n_agents, np.int64)
    split_index(state, gridmap.n_cells, out)
    return out


@njit(cache=True)
def _dijkstra(next_state, collisions, valid, goals, start, n_cells, by_makespan):
    """Dijkstra's algorithm from ``start`` over the collision-free transitions, a step costing
    (1, agents acting) in that order of importance when ``by_makespan``, else (agents acting, 1).
    Returns each joint state's least cost and the state before it on a cheapest way (-1: unreached)."""
    n_states, n_agents = next_state.shape[0], goals.first.shape[0] - 1
    cost = np.full(n_states, np.iinfo(np.int64).max, np.int64)
    parent = np.full(n_states, -1, np.int64)
    settled = np.zeros(n_states, np.bool_)
    cells = np.empty(n_agents, np.int64)
    cost[start], parent[start] = 0, start
    heap = [(np.int64(0), np.int64(start))]
    while len(heap) > 0:
        paid, s = heapq.heappop(heap)
        if settled[s]:
            continue
        settled[s] = True
        split_index(s, n_cells, cells)
        acting = 0
        for i in range(n_agents):
            acting += 0 if rules.is_goal(goals, i, cells[i]) else 1
        if acting == 0:  # every agent in: the plan ends here
            continue
        step = _SCALE + acting if by_makespan else acting * _SCALE + 1
        for a in range(next_state.shape[1]):
            t = next_state[s, a]
            if collisions[s, a] == 0 and valid[t] and not settled[t] and paid + step < cost[t]:
                cost[t], parent[t] = paid + step, s
                heapq.heappush(heap, (cost[t], t))
    return cost, parent
