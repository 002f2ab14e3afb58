"""Generated warehouse maps (glamas.gridworld.generate): the density held as the agents grow, every
agent with its own start and goal, reproducible from the seed, and their text form loads back."""

import math
from collections import deque

import numpy as np
import pytest

from glamas import memory
from glamas.errors import UserError
from glamas.gridworld import load_map, map_text
from glamas.gridworld.generate import dimensions, free_cells, layout, map_bytes, warehouse

SIZES = (2, 8, 32, 128)


@pytest.fixture(scope="module")
def maps():
    return {n: warehouse(n, seed=1) for n in SIZES}


@pytest.mark.parametrize("n", SIZES)
def test_density_is_held_as_the_agents_grow(maps, n):
    g = maps[n]
    free = int((~g.blocked).sum())
    assert g.n_agents == n and g.name == f"warehouse_{n}_seed_1"
    assert 0.9 * 0.1 <= n / free <= 0.1  # agents per free cell, the default density
    assert g.n_rows <= g.n_cols <= 4 * g.n_rows


@pytest.mark.parametrize("n", SIZES)
def test_every_agent_has_its_own_start_and_goal_within_reach(maps, n):
    g = maps[n]
    goals = [g.goal_cells(k) for k in range(n)]
    assert all(len(own) == 1 for own in goals)
    cells = g.starts.tolist() + [own[0] for own in goals]
    assert len(set(cells)) == 2 * n and not g.blocked[cells].any()
    assert _connected(g)  # every free cell reachable from every other: aisles around every shelf


def _connected(g):
    free = np.flatnonzero(~g.blocked).tolist()
    seen, frontier = {free[0]}, deque([free[0]])
    while frontier:
        for other in g.open_neighbours(frontier.popleft()):
            if other not in seen:
                seen.add(other)
                frontier.append(other)
    return len(seen) == len(free)


@pytest.mark.parametrize("n", SIZES)
def test_text_form_loads_back(maps, n):
    g = maps[n]
    text = map_text(g)
    assert load_map(text).same_layout(g) and map_text(load_map(text)) == text
    assert ("start 10: row" in text) == (n >= 10) and ("goal 128: row" in text) == (n == 128)


def test_same_seed_same_map_other_seed_other_agents(maps):
    again = warehouse(32, seed=1)
    assert again.same_layout(maps[32])
    other = warehouse(32, seed=2)
    assert np.array_equal(other.blocked, maps[32].blocked) and not other.same_layout(maps[32])


def test_shelves_and_aisles():
    g = warehouse(2, seed=0, density=0.5, shelf_length=3)
    assert (g.n_rows, g.n_cols) == (3, 5) and g.blocked.reshape(3, 5).astype(int).tolist() == [
        [0, 0, 0, 0, 0], [0, 1, 1, 1, 0], [0, 0, 0, 0, 0]]
    assert free_cells(*layout(2, 0.5, 3), 3) == 12


@pytest.mark.parametrize("kwargs, message", [
    (dict(n_agents=0, seed=0), r"n_agents must be a whole number >= 1, got 0"),
    (dict(n_agents=2.0, seed=0), r"n_agents must be a whole number >= 1, got 2\.0"),
    (dict(n_agents=2, seed=-1), r"seed must be a whole number >= 0, got -1"),
    (dict(n_agents=2, seed=0, density=0.6), r"density \(agents per free cell\) must be in \(0, 0\.5\], got 0\.6"),
    (dict(n_agents=2, seed=0, shelf_length=0), r"shelf_length must be a whole number >= 1, got 0"),
])
def test_bad_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        warehouse(**kwargs)


def test_a_warehouse_that_cannot_be_laid_out_or_held_is_one_line_before_allocating(monkeypatch):
    monkeypatch.setattr(memory, "available_bytes", lambda: 16 * 2 ** 30)  # whatever this machine has
    with pytest.raises(UserError, match="no warehouse of 1 agents with shelves 100 cells long is between one and "
                                        "four times as wide as tall"):
        warehouse(1, 0, shelf_length=100)
    monkeypatch.setattr(memory, "available_bytes", lambda: 3 * 2 ** 30 // 10)
    with pytest.raises(UserError, match=r"a warehouse of 100000 agents has \d+ cells: making it needs about "
                                        r"0\.4 GiB, more than the 0.3 GiB available; choose fewer agents"):
        warehouse(10 ** 5, 0)


def test_a_warehouse_holds_memory_in_proportion_to_its_cells_plus_its_agents():
    """Each agent's goal is its own, stored per agent (no agents x cells table): at 10^5 agents
    the estimate is about 0.4 GiB (an agents x cells table of bools alone was 149 GiB)."""
    g = warehouse(1024, 0)
    goals = g.goals
    assert goals.own.size == g.n_agents and goals.shared.size == g.n_cells and not goals.shared.any()
    assert sum(array.nbytes for array in goals) < 16 * (g.n_cells + g.n_agents)
    bays_across, shelf_rows = layout(10 ** 5, 0.1, 3)
    n_cells = math.prod(dimensions(bays_across, shelf_rows, 3))
    assert map_bytes(10 ** 5, n_cells) < 2 ** 30 < 10 ** 5 * n_cells
