"""A collision-free joint plan for many agents, by prioritized planning: where the exact planner
(:mod:`glamas.gridworld.plans`, Dijkstra over the joint states) no longer fits, a reference plan
whose sum of costs and makespan bound the optimum from above, beside the lower bounds.

Prioritized planning (Erdmann & Lozano-Perez, Algorithmica 2, 1987; Silver's cooperative A*,
AIIDE 2005) plans the agents one after the other in a priority order. Each agent takes a path of
fewest steps by space-time A* over (cell, step), its heuristic its exact distance to its goal
cells alone (breadth first, consistent), against a reservation table of the paths already
planned: a path may not enter a cell at a step a higher-priority agent is on it (a collision on
one target, or a bump against an agent that stays), nor swap cells with one. Under glamas's rules
(:mod:`glamas.gridworld.rules`) an agent is on its path from its start at step 0 until it enters
its goal, and reserves nothing after: it has left the game. Two agents may enter a goal of both
at the same step. There is no wait action: an agent stays on a cell only by a move that bumps
into a wall or the border there, and the plan's action is then that move; elsewhere it steps
aside.

The first order puts the agent with the longest shortest path first (ties: the lower agent
number), as it is the one whose detours would lengthen the makespan most. When an agent finds no
path, it moves to the front of the order and the agents are planned again, up to ``restarts``
times; an order tried before gives way to a random one from ``numpy.random.default_rng(seed)``.
The usual failure on a warehouse is an agent overrun at its start: a higher agent enters its
start cell at step 1 while the only other way out is taken. Raised to the front, it leaves first.
(With random orders instead, warehouse(1024, seed) had no plan after 11 orders for 3 of the
seeds 0-7; moving to the front planned every seed 0-23 within 6 orders.) Prioritized planning
is incomplete (an order may fail, or every order, on an instance with a plan) and not optimal;
each agent's path is the best given those before it.
"""

import heapq

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas.gridworld import rules
from glamas.gridworld.maps import GridMap
from glamas.gridworld.plans import Plan
from glamas.gridworld.rules import N_ACTIONS, NOBODY

RESTARTS = 10
"""Priority orders tried after the first one fails."""
_SCALE = 1 << 32
"""Weight of a node's estimate in its heap key, before its step (a later step first among equal
estimates: the search dives along one shortest path instead of widening over all of them)."""


def plan(gridmap: GridMap, bounce: str = "previous", seed: int = 0, restarts: int = RESTARTS) -> Plan:
    """A collision-free plan of ``gridmap`` by prioritized planning (module docstring): the first
    priority order, then up to ``restarts`` more, each with the agent that failed moved to the
    front (or a random one from ``seed`` in place of an order tried before). ``bounce`` is the
    rule the plan is played under ('previous' or 'start'); a plan without collisions plays the
    same under both, so it is checked only. Raises UserError when every order fails. (An agent
    whose goal is out of its reach alone has no map: GridMap refuses it, naming the agent.)"""
    if bounce not in rules.BOUNCE_MODES:
        raise UserError(f"bounce must be one of {sorted(rules.BOUNCE_MODES)}, got {bounce!r}")
    for name, value in (("seed", seed), ("restarts", restarts)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
            raise UserError(f"{name} must be a whole number >= 0, got {value!r}")
    rng, tried = np.random.default_rng(seed), set()
    order = first_order(gridmap)
    for _ in range(restarts + 1):
        tried.add(order.tobytes())
        steps, cells, failed = _plan_in_order(gridmap.next_cell, gridmap.goals, gridmap.starts, order)
        if failed == NOBODY:
            return Plan(steps=steps, cells=cells)
        order = np.concatenate(([failed], order[order != failed]))
        if order.tobytes() in tried:  # moving to the front goes round in a circle
            order = rng.permutation(gridmap.n_agents)
    raise UserError(f"map {gridmap.name!r}: prioritized planning found no collision-free plan in {restarts + 1} "
                    f"priority orders (in the last, agent {failed + 1} had no way); try more restarts or another "
                    "seed, or on a small map plans.least_sum_of_costs, which tells whether any plan exists")


def first_order(gridmap: GridMap) -> np.ndarray:
    """int (agents,): the first priority order, the longest shortest path first, ties by agent number."""
    return np.argsort(-shortest_steps(gridmap), kind="stable")


def shortest_steps(gridmap: GridMap) -> np.ndarray:
    """int64 (agents,): each agent's shortest path alone, as :func:`glamas.gridworld.dp.shortest_steps`
    (compiled: that one takes about 40 s on a warehouse of 1024 agents)."""
    return _shortest_steps(gridmap.next_cell, gridmap.goals, gridmap.starts)


def lower_bounds(gridmap: GridMap) -> tuple[int, int]:
    """(sum of costs, makespan) no plan can beat, as :func:`glamas.gridworld.plans.lower_bounds`."""
    alone = shortest_steps(gridmap)
    return int(alone.sum()), int(alone.max())


@njit(cache=True)
def _goal_distances(next_cell, goals, agent, distance, queue):
    """Fill ``distance`` with the moves from each cell to the nearest goal cell of ``agent`` (-1:
    none reachable), breadth first from its goal cells (moves are symmetric); ``queue`` is scratch
    of one entry per cell."""
    distance[:] = -1
    tail = 0
    for cell in range(next_cell.shape[0]):
        if goals.shared[cell]:
            distance[cell] = 0
            queue[tail] = cell
            tail += 1
    for k in range(goals.first[agent], goals.first[agent + 1]):
        distance[goals.own[k]] = 0
        queue[tail] = goals.own[k]
        tail += 1
    head = 0
    while head < tail:
        cell = queue[head]
        head += 1
        for a in range(N_ACTIONS):
            other = next_cell[cell, a]
            if distance[other] < 0:
                distance[other] = distance[cell] + 1
                queue[tail] = other
                tail += 1


@njit(cache=True)
def _shortest_steps(next_cell, goals, starts):
    """Each agent's distance alone from its start to its goal cells (:func:`_goal_distances`)."""
    n_cells = next_cell.shape[0]
    distance, queue = np.empty(n_cells, np.int64), np.empty(n_cells, np.int64)
    alone = np.empty(starts.shape[0], np.int64)
    for i in range(starts.shape[0]):
        _goal_distances(next_cell, goals, i, distance, queue)
        alone[i] = distance[starts[i]]
    return alone


@njit(cache=True)
def _plan_in_order(next_cell, goals, starts, order):
    """Plan the agents one after the other in ``order``, each against the paths before it.
    Returns (steps per agent, cells (makespan + 1, agents), NOBODY) or, when an agent finds no
    path, (empty, empty, that agent).

    The reservations are a dense table of the agent on each (step, cell), with rows for the steps
    up to the makespan so far (a quarter more when a path outgrows them): a look-up is one load,
    where a hash of (cell, step) would cost several at every node A* generates, and the rows grow
    only with the makespan. On warehouse(1024, 0), 225 rows of 16,241 cells at 4 bytes: 15 MB, as
    much for each of A*'s two tables beside it."""
    n_cells, n = next_cell.shape[0], starts.shape[0]
    occupant = np.full((1, n_cells), NOBODY, np.int32)
    seen, came_from = np.zeros((1, n_cells), np.int32), np.empty((1, n_cells), np.int32)
    distance, queue = np.empty(n_cells, np.int64), np.empty(n_cells, np.int64)
    paths = [np.empty(0, np.int64) for _ in range(n)]
    horizon = 0  # the last step anything is reserved at
    for k in range(n):
        agent = order[k]
        _goal_distances(next_cell, goals, agent, distance, queue)
        path = _space_time_astar(agent, starts[agent], next_cell, goals, distance, occupant, horizon,
                                 seen, came_from, k + 1)
        if path.shape[0] == 0:
            return np.empty(0, np.int64), np.empty((0, n), np.int64), agent
        arrival = path.shape[0] - 1
        if arrival >= occupant.shape[0]:
            occupant, seen, came_from = _grown(occupant, max(arrival + 1, occupant.shape[0] * 5 // 4))
        _reserve(occupant, path, agent)
        horizon = max(horizon, arrival)
        paths[agent] = path
    steps = np.empty(n, np.int64)
    cells = np.empty((horizon + 1, n), np.int64)
    for agent in range(n):
        path = paths[agent]
        steps[agent] = path.shape[0] - 1
        cells[:path.shape[0], agent] = path
        cells[path.shape[0]:, agent] = path[-1]  # in its goal, out of the game
    return steps, cells, NOBODY


@njit(cache=True)
def _grown(occupant, rows):
    """The reservation table with ``rows`` steps (its reservations kept), and A*'s tables as large
    (fresh: a search marks only its own nodes, by its own stamp)."""
    grown = np.full((rows, occupant.shape[1]), NOBODY, np.int32)
    grown[:occupant.shape[0]] = occupant
    return grown, np.zeros(grown.shape, np.int32), np.empty(grown.shape, np.int32)


@njit(cache=True)
def _reserve(occupant, path, agent):
    """Enter ``agent`` on each (step, cell) of its ``path``, up to its arrival. A cell already
    taken there is a goal of both agents, which they enter together: the first one stays, since
    anyone else may enter that cell then only if it is its goal too (:func:`_free`)."""
    for t in range(path.shape[0]):
        if occupant[t, path[t]] == NOBODY:
            occupant[t, path[t]] = agent


@njit(cache=True)
def _free(agent, cell, target, t, occupant, goals):
    """Whether ``agent`` may go from ``cell`` at step t to ``target`` (itself: a bump) at t + 1:
    no reserved agent there then but one entering a goal of both, and no swap with a reserved agent."""
    other = occupant[t + 1, target]
    if other != NOBODY and not (rules.is_goal(goals, agent, target) and rules.is_goal(goals, other, target)):
        return False
    other = occupant[t, target]
    return target == cell or other == NOBODY or occupant[t + 1, cell] != other


@njit(cache=True)
def _space_time_astar(agent, start, next_cell, goals, distance, occupant, horizon, seen, came_from, stamp):
    """The path of fewest steps of ``agent`` from ``start`` into its goal against the reservations
    up to step ``horizon``: space-time A* (Silver 2005), its heuristic the distance alone
    (``distance``). Every way to (cell, t) costs t, so a node is final when first generated (marked
    in ``seen`` with this search's ``stamp``, its cell before in ``came_from``). After ``horizon``
    nothing is reserved: a node there goes on by its shortest path, so the search covers at most
    (horizon + 1) x cells nodes, and ends (an empty path) when none of them leads on."""
    n_cells = next_cell.shape[0]
    seen[0, start] = stamp
    heap = [(np.int64(distance[start] * _SCALE), np.int64(start))]  # node: t * n_cells + cell
    while len(heap) > 0:
        node = heapq.heappop(heap)[1]
        t, cell = node // n_cells, node % n_cells
        if rules.is_goal(goals, agent, cell) or t >= horizon:
            return _path(cell, t, next_cell, distance, came_from)
        for a in range(N_ACTIONS):
            target = next_cell[cell, a]
            if seen[t + 1, target] != stamp and _free(agent, cell, target, t, occupant, goals):
                seen[t + 1, target] = stamp
                came_from[t + 1, target] = cell
                heapq.heappush(heap, ((t + 1 + distance[target]) * _SCALE - (t + 1), (t + 1) * n_cells + target))
    return np.empty(0, np.int64)


@njit(cache=True)
def _path(cell, t, next_cell, distance, came_from):
    """int64 (arrival + 1,): the cells from the start to the goal through ``cell`` at step t: back
    along ``came_from``, then on by a move that brings the agent one step nearer its goal."""
    path = np.empty(t + distance[cell] + 1, np.int64)
    path[t] = cell
    for k in range(t, 0, -1):
        path[k - 1] = came_from[k, path[k]]
    for k in range(t, path.shape[0] - 1):
        here = path[k]
        for a in range(N_ACTIONS):
            if distance[next_cell[here, a]] == distance[here] - 1:
                path[k + 1] = next_cell[here, a]
                break
    return path
