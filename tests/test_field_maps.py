"""The sparse-interaction literature's maps in data/maps, held to what was checked against their
source, the public repository tkujiraski/MARL (its files Tunnel2Goal.py, TunnelToGoal3.py,
TunnelToGoal4.py, ISR.py, CIT.py and CMU.py, which encode cell (y, x) as [not a cell, wall W,
wall S, wall E, wall N]; docs/reproduction-notes.md, "The field's maps").

For each map the source was read independently of glamas: its cells, every open edge (each open
from both sides there), its starts and goals (agent k listed k-th), its cell count (the source's
``state``) and each agent's shortest path. ``edges`` is a digest of the sorted open edges
"r,c-r,c" computed from the source's encoding; the map file must give the same.
"""

import hashlib
from collections import deque

import numpy as np
import pytest

from glamas.gridworld import load_map, rules
from glamas.gridworld.rewards import CHAPTER

FIELD = {
    "tunnel_to_goal": dict(size=(5, 5), cells=25, starts=[(0, 0), (4, 0)], goals=[(2, 0), (2, 0)],
                           shortest=[10, 10], edges=(32, "a0bac343b739178a")),
    "tunnel_to_goal_3": dict(size=(5, 11), cells=55, starts=[(0, 0), (4, 0), (2, 10)], goals=[(2, 0)] * 3,
                             shortest=[10, 10, 10], edges=(86, "8ef7217bdbf08a13")),
    "tunnel_to_goal_4": dict(size=(5, 11), cells=55, starts=[(0, 0), (4, 0), (0, 10), (4, 10)],
                             goals=[(2, 0), (2, 0), (2, 10), (2, 10)], shortest=[10, 10, 10, 10],
                             edges=(78, "533f9b31dafe0928")),
    "isr": dict(size=(10, 9), cells=43, starts=[(6, 3), (7, 0)], goals=[(7, 0), (6, 3)], shortest=[4, 4],
                edges=(45, "70e07741fa14ca3b")),
    "cit": dict(size=(12, 14), cells=69, starts=[(5, 8), (0, 3)], goals=[(0, 3), (5, 8)], shortest=[10, 10],
                edges=(73, "0bc7fe5aecc2470d")),
    "cmu": dict(size=(7, 34), cells=133, starts=[(6, 32), (6, 3)], goals=[(6, 3), (6, 32)], shortest=[31, 31],
                edges=(138, "bab9c84b3f830cf6")),
}


def open_edges(gridmap):
    """The open edges between neighbouring cells, each as ((r, c), (r, c)) in order."""
    return sorted({tuple(sorted((gridmap.row_col(a), gridmap.row_col(b))))
                   for a in range(gridmap.n_cells) for b in gridmap.open_neighbours(a)})


def digest(edges):
    text = ";".join(f"{a[0]},{a[1]}-{b[0]},{b[1]}" for a, b in edges)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def shortest_path(gridmap, agent):
    """Moves from agent ``agent``'s start to its nearest goal cell (breadth-first)."""
    start = int(gridmap.starts[agent])
    distance, frontier = {start: 0}, deque([start])
    while frontier:
        cell = frontier.popleft()
        if gridmap.is_goal_of(agent, cell):
            return distance[cell]
        for other in gridmap.open_neighbours(cell):
            if other not in distance:
                distance[other] = distance[cell] + 1
                frontier.append(other)
    return None


@pytest.mark.parametrize("name", FIELD)
def test_layout_is_the_sources(name):
    g, expected = load_map(name), FIELD[name]
    assert (g.n_rows, g.n_cols) == expected["size"]
    assert int((~g.blocked).sum()) == expected["cells"]
    assert [g.row_col(int(s)) for s in g.starts] == expected["starts"]
    assert [[g.row_col(c) for c in g.goal_cells(k)] for k in range(g.n_agents)] == [[x] for x in expected["goals"]]
    edges = open_edges(g)
    assert (len(edges), digest(edges)) == expected["edges"]


@pytest.mark.parametrize("name", FIELD)
def test_shortest_paths_are_the_sources(name):
    g = load_map(name)
    assert [shortest_path(g, k) for k in range(g.n_agents)] == FIELD[name]["shortest"]


def test_isr_cit_and_cmu_swap_places():
    for name in ("isr", "cit", "cmu"):
        g = load_map(name)
        assert g.goal_cells(0) == [int(g.starts[1])] and g.goal_cells(1) == [int(g.starts[0])]
        assert not g.shared_goal.any()


@pytest.mark.parametrize("name", FIELD)
def test_the_chapters_rewards_hold(name):
    """Alone (the others in their goals), each agent walks its shortest path for +100 at its end,
    and a move into the border costs -1; two agents entering one cell that is not a goal of both
    pay -10 each."""
    g = load_map(name)
    world = rules.world(g)
    n = g.n_agents
    for agent in range(n):
        cells = np.array([g.goal_cells(k)[0] if k != agent else int(g.starts[k]) for k in range(n)], np.int64)
        done = np.arange(n) != agent
        total, steps = 0.0, 0
        while not g.is_goal_of(agent, cells[agent]):
            actions = np.zeros(n, np.int64)
            actions[agent] = _towards_goal(g, agent, int(cells[agent]))
            out = [np.empty(n, np.int64), np.empty(n), *(np.empty(n, bool) for _ in range(3))]
            rules.step(world, cells, done, actions, *out)
            cells, total, steps = out[0], total + out[1][agent], steps + 1
        assert (steps, total) == (FIELD[name]["shortest"][agent], CHAPTER.goal)
    corner = np.array([g.starts[0]] + [g.goal_cells(k)[0] for k in range(1, n)], np.int64)
    bumps = [a for a in range(4) if g.next_cell[corner[0], a] == corner[0]]
    out = [np.empty(n, np.int64), np.empty(n), *(np.empty(n, bool) for _ in range(3))]
    rules.step(world, corner, np.arange(n) != 0, np.full(n, bumps[0], np.int64), *out)
    assert out[1][0] == CHAPTER.bump == -1.0
    a, b, target = _two_cells_one_step_from(g, agents=(0, 1))
    actions = np.zeros(n, np.int64)
    actions[0] = [x for x in range(4) if g.next_cell[a, x] == target][0]
    actions[1] = [x for x in range(4) if g.next_cell[b, x] == target][0]
    cells = np.array([a, b] + [g.goal_cells(k)[0] for k in range(2, n)], np.int64)
    rules.step(world, cells, np.arange(n) >= 2, actions, *out)
    assert out[1][:2].tolist() == [CHAPTER.collision] * 2 == [-10.0, -10.0]


def _towards_goal(g, agent, cell):
    """An action that shortens agent ``agent``'s path from ``cell`` to its goal."""
    here = _distance_to_goal(g, agent, cell)
    return next(a for a in range(4) if _distance_to_goal(g, agent, int(g.next_cell[cell, a])) == here - 1)


def _distance_to_goal(g, agent, cell):
    goals = g.goal_cells(agent)
    distance, frontier = {c: 0 for c in goals}, deque(goals)
    while frontier:
        here = frontier.popleft()
        for other in g.open_neighbours(here):
            if other not in distance:
                distance[other] = distance[here] + 1
                frontier.append(other)
    return distance[cell]


def _two_cells_one_step_from(g, agents):
    """Two free cells, neither a goal of its agent, and a neighbour of both that is a goal of not both."""
    i, j = agents
    for a in range(g.n_cells):
        for b in range(a + 1, g.n_cells):
            if g.blocked[a] or g.blocked[b] or g.is_goal_of(i, a) or g.is_goal_of(j, b):
                continue
            for c in sorted(g.open_neighbours(a) & g.open_neighbours(b)):
                if not (g.is_goal_of(i, c) and g.is_goal_of(j, c)):
                    return a, b, c
    raise AssertionError("no two cells with a common neighbour")
