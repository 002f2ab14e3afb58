"""Generated maps for many agents: warehouses whose size grows with the number of agents.

The chapter's gridworld is "a very simplistic version of a warehouse, where agents moving on tracks,
have to get orders from the different aisles" (Section 5.3). :func:`warehouse` lays out such a
warehouse for any number of agents N: rows of shelves (blocked cells) ``shelf_length`` long, one
cell deep, with a one-cell aisle around every shelf, so every free cell is reachable from every
other. Its size is chosen so that the density, agents per free cell, stays near ``density`` as N
grows: scaling studies then compare numbers of agents, not crowding. Each agent gets its own start
and its own goal, 2N distinct free cells drawn from a seeded numpy Generator: the same (N, seed)
gives the same map.

Agents beyond 9 have no cell symbol; the map's text form (:func:`glamas.gridworld.maps.map_text`)
gives their starts and goals as trailer lines, and loads back to the same map.
"""

import math
from dataclasses import replace

import numpy as np

from glamas import memory
from glamas.gridworld.maps import GridMap, load_map
from glamas.errors import UserError


def warehouse(n_agents: int, seed: int, density: float = 0.1, shelf_length: int = 3) -> GridMap:
    """A warehouse of shelves and aisles for ``n_agents`` agents at about ``density`` agents per
    free cell (at most 0.5: starts and goals are 2N distinct cells), each agent with its own start
    and goal drawn from ``numpy.random.default_rng(seed)``; named ``warehouse_N_seed_S``."""
    check_arguments(n_agents, seed, density, shelf_length)
    check_fits(n_agents, density)
    bays_across, shelf_rows = layout(n_agents, density, shelf_length)
    _check_memory(n_agents, math.prod(dimensions(bays_across, shelf_rows, shelf_length)))
    blocked = shelves(bays_across, shelf_rows, shelf_length)
    free = np.flatnonzero(~blocked.ravel())
    chosen = np.random.default_rng(seed).choice(free, size=2 * n_agents, replace=False)
    text = _text(blocked, chosen[:n_agents], chosen[n_agents:])
    return replace(load_map(text), name=f"warehouse_{n_agents}_seed_{seed}")


def check_arguments(n_agents, seed, density: float = 0.1, shelf_length: int = 3) -> None:
    """Raise UserError naming the first argument of :func:`warehouse` out of range."""
    for name, value, low in (("n_agents", n_agents, 1), ("seed", seed, 0), ("shelf_length", shelf_length, 1)):
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < low:
            raise UserError(f"{name} must be a whole number >= {low}, got {value!r}")
    if isinstance(density, bool) or not isinstance(density, (int, float)) or not 0.0 < density <= 0.5:
        raise UserError(f"density (agents per free cell) must be in (0, 0.5], got {density!r}")


def layout(n_agents: int, density: float, shelf_length: int) -> tuple[int, int]:
    """(bays across, rows of shelves) of the warehouse with the fewest free cells, at least
    ``n_agents / density``, among those between one and four times as wide as tall (ties: the one
    closest to twice as wide as tall)."""
    wanted = math.ceil(n_agents / density)
    best = None
    for shelf_rows in range(1, math.isqrt(wanted) + 2):
        bays_across = _fewest_bays(shelf_rows, shelf_length, wanted)
        n_rows, n_cols = dimensions(bays_across, shelf_rows, shelf_length)
        if not n_rows <= n_cols <= 4 * n_rows:
            continue
        key = (free_cells(bays_across, shelf_rows, shelf_length), abs(n_cols - 2 * n_rows))
        if best is None or key < best[0]:
            best = key, (bays_across, shelf_rows)
    if best is None:
        raise UserError(f"no warehouse of {n_agents} agents with shelves {shelf_length} cells long is between one "
                        "and four times as wide as tall; choose shorter shelves or more agents")
    return best[1]


BYTES_PER_CELL, BYTES_PER_AGENT = 256, 512
"""What making a warehouse holds at its peak, per cell and per agent (its text, the parse, the
map's tables; the goals are each agent's own, :class:`glamas.gridworld.rules.Goals`): measured at
about 150 bytes per cell from 2,000 to 8,000 agents, with a margin."""


def map_bytes(n_agents: int, n_cells: int) -> int:
    """The memory making a warehouse of ``n_agents`` agents and ``n_cells`` cells needs: it grows
    with the cells plus the agents, not their product."""
    return BYTES_PER_CELL * n_cells + BYTES_PER_AGENT * n_agents


def check_fits(n_agents: int, density: float = 0.1) -> None:
    """Refuse, before the layout is searched (seconds to minutes for millions of agents), a warehouse
    whose free cells alone, at least ``n_agents / density``, would not fit in the memory there is."""
    _check_memory(n_agents, math.ceil(n_agents / density), "at least ")


def _check_memory(n_agents: int, n_cells: int, bound: str = "") -> None:
    """Refuse, before allocating, a warehouse that would not fit in the memory there is."""
    needed = map_bytes(n_agents, n_cells)
    if needed > memory.available_bytes():
        raise memory.MemoryEstimateError(f"a warehouse of {n_agents} agents has {bound}{n_cells} cells: making it needs "
                                         f"{'at least ' if bound else 'about '}{memory.gib(needed)}, more than the "
                                         f"{memory.gib(memory.available_bytes())} available; choose fewer agents")


def _fewest_bays(shelf_rows: int, shelf_length: int, wanted: int) -> int:
    """The fewest bays across that give ``wanted`` free cells with ``shelf_rows`` rows of shelves."""
    bays_across = 1
    while free_cells(bays_across, shelf_rows, shelf_length) < wanted:
        bays_across += 1
    return bays_across


def dimensions(bays_across: int, shelf_rows: int, shelf_length: int) -> tuple[int, int]:
    """(rows, columns) of a warehouse of ``shelf_rows`` rows of ``bays_across`` shelves: a row of
    aisle above, below and between the rows of shelves, a column of aisle left and right of each."""
    return 2 * shelf_rows + 1, bays_across * (shelf_length + 1) + 1


def free_cells(bays_across: int, shelf_rows: int, shelf_length: int) -> int:
    """Free cells of a warehouse of ``shelf_rows`` rows of ``bays_across`` shelves."""
    n_rows, n_cols = dimensions(bays_across, shelf_rows, shelf_length)
    return n_rows * n_cols - bays_across * shelf_rows * shelf_length


def shelves(bays_across: int, shelf_rows: int, shelf_length: int) -> np.ndarray:
    """bool (rows, cols): the shelf cells. Odd rows hold shelves of ``shelf_length`` cells, each
    with a one-cell aisle left and right of it; even rows are aisles."""
    n_rows, n_cols = dimensions(bays_across, shelf_rows, shelf_length)
    blocked = np.zeros((n_rows, n_cols), dtype=bool)
    for bay in range(bays_across):
        first = bay * (shelf_length + 1) + 1
        blocked[1::2, first:first + shelf_length] = True
    return blocked


def _text(blocked: np.ndarray, starts: np.ndarray, goals: np.ndarray) -> str:
    """The map's text: shelves '#', every start and goal a trailer line (agents may be more than 9)."""
    n_rows, n_cols = blocked.shape
    lines = ["+" + "-+" * n_cols]
    for r in range(n_rows):
        cells = "".join(("#" if b else ".") + " " for b in blocked[r])
        lines += ["|" + cells[:-1] + "|", "+" + ("-+" if r == n_rows - 1 else " +") * n_cols]
    lines += [f"start {k}: row {c // n_cols}, col {c % n_cols}" for k, c in enumerate(starts.tolist(), 1)]
    lines += [f"goal {k}: row {c // n_cols}, col {c % n_cols}" for k, c in enumerate(goals.tolist(), 1)]
    return "\n".join(lines) + "\n"
