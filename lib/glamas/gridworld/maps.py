"""Gridworld maps: the text format of ``data/maps/*.txt``, its loader and writer, and the map it builds.

A map of R rows and C columns is drawn like a maze in 2R+1 lines of 2C+1 characters:

- cell lines (odd line index): odd columns hold the cell: ``.`` free, ``#`` blocked, ``1``-``9``
  the start of that agent, ``G`` a goal of every agent, ``a``-``i`` a goal of agent 1-9 only
  (``a`` agent 1's, ``b`` agent 2's, ...); even columns hold ``|`` (a wall between the cells left
  and right of it) or a space (open);
- separator lines (even line index): even columns hold ``+``; odd columns ``-`` (a wall between
  the cells above and below) or a space;
- the border is closed: first and last lines ``+-+-...+``, cell lines begin and end with ``|``.

A trailer may follow the maze (after blank lines or none) for what one symbol per cell cannot say,
one start or goal per line, rows and columns counted from 0 as :meth:`GridMap.cell` counts them::

    start 12: row 3, col 4
    goal 1: row 7, col 0

A goal line gives agent K a goal on a cell whose symbol is taken: another agent's start (in the
ISR, CIT and CMU maps the two agents swap places, each one's goal the other's start) or another
agent's goal. Agents beyond 9 have no symbol: their starts and goals are trailer lines.

The rules on the whole: agents are numbered 1..N without gaps, each starts once, on a free cell of
its own (no two starts on a cell); agent k's goals are the ``G`` cells, its letter's cells and its
goal lines, at least one, none of them its start (it would be done before moving), some reachable
from its start. Another agent's goal is an ordinary cell for agent k. Every fault is one
:class:`MapError` naming its line and column and the fix.

Cells are numbered row by row, ``cell = row * n_cols + col``; row 0 is the top line. Walls are
symmetric by construction: one character separates two cells. :func:`map_text` writes a map in
this format (walls drawn around blocked cells, symbols where they fit, the trailer for the rest);
what it writes loads back to the same map. The reader takes any line ending, spaces after the
last character of a line and an indentation common to every line; ``python -m
glamas.gridworld.canonical FILE`` prints a map in the form :func:`map_text` writes (its canonical
form, which the maps of ``data/maps`` are in), ``--write`` puts it in the file.
Every :class:`GridMap`, read from a file or built in Python, is checked by one function,
:func:`check_layout`, when it is made.
"""

import hashlib
import re
import textwrap
from collections import deque
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from glamas.errors import UserError
from glamas.gridworld.rules import E, N, N_ACTIONS, S, W, Goals
from glamas.paths import MAPS

FREE, GOAL, BLOCKED = ".", "G", "#"
START_SYMBOLS = "123456789"
"""The start of agent 1, 2, ... 9 in the maze."""
GOAL_LETTERS = "abcdefghi"
"""A goal of agent 1, 2, ... 9 alone in the maze."""
_CELL_SYMBOLS = ("free '.', blocked '#', agent k's start '1'-'9', every agent's goal 'G' "
                 "or agent k's own goal 'a'-'i' (a for agent 1)")
_STEPS = {N: (-1, 0), E: (0, 1), S: (1, 0), W: (0, -1)}
_TRAILER_LINE = re.compile(r"(start|goal) +(\d+) *: *row +(\d+) *, *col +(\d+)")
_TRAILER_WORD = re.compile(r"\s*(start|goal)\b")
_TRAILER_FORM = "'start K: row R, col C' or 'goal K: row R, col C'"


class MapError(UserError):
    """A map file that does not follow the format of :mod:`glamas.gridworld.maps`."""


@dataclass(frozen=True, eq=False)
class GridMap:
    """A loaded gridworld: its moves as a table, its blocked cells, each agent's start and goals."""

    name: str
    """The map's name (file stem, or 'inline' for a map given as text)."""
    n_rows: int
    """Number of cell rows."""
    n_cols: int
    """Number of cell columns."""
    next_cell: np.ndarray
    """int64 (n_cells, 4): the cell each action N, E, S, W leads to; the cell itself when a wall,
    the border or a blocked cell stops the move."""
    goals: Goals
    """Each agent's goal cells (absorbing for it; ordinary cells for the others): the cells that are
    every agent's goal and each agent's own (:class:`glamas.gridworld.rules.Goals`, :func:`make_goals`),
    in memory that grows with the cells plus the agents' own goals."""
    blocked: np.ndarray
    """bool (n_cells,): cells no agent can enter."""
    starts: np.ndarray
    """int64 (n_agents,): the start cell of agent 1, 2, ..."""

    def __post_init__(self):
        check_layout(self)

    @property
    def n_cells(self) -> int:
        return self.n_rows * self.n_cols

    @property
    def n_agents(self) -> int:
        return int(self.starts.shape[0])

    @cached_property
    def is_goal(self) -> np.ndarray:
        """bool (n_cells,): cells that are some agent's goal (drawing, and the chapter's
        experiments, whose maps have one goal shared by every agent)."""
        marked = self.goals.shared.copy()
        marked[self.goals.own] = True
        return _read_only(marked)

    @cached_property
    def shared_goal(self) -> np.ndarray:
        """bool (n_cells,): cells that are every agent's goal. No agent acts on one, and agents
        entering one together never collide: the cells any two agents treat alike."""
        owners = np.bincount(self.goals.own, minlength=self.n_cells)
        return _read_only(self.goals.shared | (owners == self.n_agents))

    def own_goals(self, agent: int) -> np.ndarray:
        """The goal cells of agent ``agent`` (0 for agent 1) that are not every agent's by mark."""
        return self.goals.own[self.goals.first[agent]:self.goals.first[agent + 1]]

    def goal_cells(self, agent: int) -> list[int]:
        """The goal cells of agent ``agent`` (0 for agent 1), in increasing order."""
        return sorted(np.flatnonzero(self.goals.shared).tolist() + self.own_goals(agent).tolist())

    def is_goal_of(self, agent: int, cell: int) -> bool:
        """Whether ``cell`` is a goal of agent ``agent`` (0 for agent 1)."""
        return bool(self.goals.shared[cell]) or bool((self.own_goals(agent) == cell).any())

    def goal_owners(self, cell: int) -> list[int]:
        """The agents (0 for agent 1) whose goal ``cell`` is, in increasing order."""
        if self.goals.shared[cell]:
            return list(range(self.n_agents))
        return (np.searchsorted(self.goals.first, np.flatnonzero(self.goals.own == cell), side="right") - 1).tolist()

    def in_goal(self, cells: np.ndarray) -> np.ndarray:
        """bool, the shape of ``cells`` (..., n_agents): whether agent i's cell ``cells[..., i]`` is
        one of its goals."""
        cells = np.asarray(cells)
        found = self.goals.shared[cells]
        for agent in range(self.n_agents):
            found[..., agent] |= np.isin(cells[..., agent], self.own_goals(agent))
        return found

    def alone(self, agent: int) -> "GridMap":
        """This map with agent ``agent`` (0 for agent 1) as its only agent."""
        return replace(self, starts=self.starts[agent:agent + 1],
                       goals=make_goals(self.goals.shared, [self.own_goals(agent).tolist()]))

    def goal_table(self) -> np.ndarray:
        """bool (n_agents, n_cells): ``table[i, c]``, cell c is a goal of agent i. Agents x cells
        values: for small maps (tests, the plain references of the benchmarks)."""
        table = np.repeat(self.goals.shared[None, :], self.n_agents, axis=0)
        for agent in range(self.n_agents):
            table[agent, self.own_goals(agent)] = True
        return table

    def cell(self, row: int, col: int) -> int:
        """The number of the cell at (row, col)."""
        if not (0 <= row < self.n_rows and 0 <= col < self.n_cols):
            raise UserError(f"({row}, {col}) is outside the {self.n_rows}x{self.n_cols} map {self.name!r}")
        return row * self.n_cols + col

    def row_col(self, cell: int) -> tuple[int, int]:
        """(row, col) of a cell number."""
        if not 0 <= cell < self.n_cells:
            raise UserError(f"cell {cell} is outside the map {self.name!r}, which has cells 0..{self.n_cells - 1}")
        return divmod(int(cell), self.n_cols)

    def open_neighbours(self, cell: int) -> set[int]:
        """The cells one move away from ``cell``."""
        return {int(c) for c in self.next_cell[cell] if c != cell}

    def same_layout(self, other: "GridMap") -> bool:
        """Whether ``other`` is this map under any name: same size, moves, blocked cells, starts and goals."""
        return ((self.n_rows, self.n_cols, self.n_agents) == (other.n_rows, other.n_cols, other.n_agents)
                and all(np.array_equal(getattr(self, f), getattr(other, f)) for f in ("next_cell", "blocked", "starts"))
                and np.array_equal(self.shared_goal, other.shared_goal)
                and all(self.goal_cells(agent) == other.goal_cells(agent) for agent in range(self.n_agents)))


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def load_map(source) -> GridMap:
    """A :class:`GridMap` from a map's name in ``data/maps`` (``"tunnel_to_goal"``, with or
    without ``.txt``), a map file's path, or the map's text; raises :class:`MapError` (naming the
    file for a map read from one). A file is parsed once per content (:func:`map_hash`):
    the experiments ask for their map many times, and an edited file is parsed again."""
    if isinstance(source, str) and "\n" in source:
        return _parse(source.removeprefix(_BOM), "inline")
    path = map_path(source)
    data = _read_bytes(path)
    key = (path.stem, hashlib.sha256(data).hexdigest())
    if key not in _PARSED:
        try:
            _PARSED[key] = _parse(_decode(data), path.stem)
        except MapError as error:
            raise MapError(f"map file {path}: {error}") from None
    return _PARSED[key]


_PARSED: dict = {}
"""Parsed maps by (name, SHA-256 of the file's bytes): a GridMap is immutable, so one serves all."""


def map_path(source) -> Path:
    """The file of a map given by name in ``data/maps`` (with or without ``.txt``) or by path; a
    path that names a directory, or a name that is no map there, is refused with the known maps."""
    if not isinstance(source, (str, Path)):
        raise TypeError(f"a map is given by name, path or the map's text, got {type(source).__name__}")
    path = Path(source)
    if path.is_file():
        return path
    if path.parent == Path(".") and not path.is_absolute():
        for candidate in (MAPS / path, MAPS / f"{path}.txt"):
            if candidate.is_file():
                return candidate
    known = ", ".join(sorted(p.stem for p in MAPS.glob("*.txt")))
    raise MapError(f"no map file {source}; give a map file's path or the name of a map in data/maps ({known})")


def map_hash(source) -> str:
    """SHA-256 of the bytes of the map file ``source`` names (:func:`map_path`): what a result
    records of its map, so that an edited map makes it stale (:mod:`glamas.provenance`)."""
    return hashlib.sha256(_read_bytes(map_path(source))).hexdigest()


def _read_bytes(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except OSError as error:
        raise MapError(f"map file {path}: cannot read it ({error.strerror})") from None


_BOM = "\ufeff"  # some editors start UTF-8 files with it; it is not part of the map


def _decode(data: bytes) -> str:
    """The text of a map file's bytes: UTF-8, with or without a byte-order mark."""
    try:
        return data.decode("utf-8").removeprefix(_BOM)
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        raise MapError(f"line {line} is not UTF-8 text (byte {data[error.start]:#04x}); "
                       "save the map as UTF-8 (its symbols are plain ASCII)") from None


def tunnel_to_goal() -> GridMap:
    """The chapter's Fig. 9 gridworld (De Hauwere's 'TunnelToGoal'), from ``data/maps``."""
    return load_map("tunnel_to_goal")


# --- reading ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Placement:
    """A start or goal of one agent as the map gives it: a symbol in the maze or a trailer line."""

    agent: int
    """The agent's number, 1 up."""
    cell: int
    where: str
    """Where the map gives it ("line L, column C"), for messages."""


def _parse(text: str, name: str) -> GridMap:
    # Any line ending, spaces after a line's last character and a common indentation (a map
    # pasted into a Python string or a notebook) are not part of the map: every maze line ends
    # with '|' or '+', so nothing the format says is lost.
    lines = [line.rstrip() for line in text.expandtabs().splitlines()]
    lines = textwrap.dedent("\n".join(lines)).split("\n")
    while lines and not lines[-1]:
        lines.pop()
    maze, trailer = _split_trailer(lines)
    _check_shape(maze)
    n_rows, n_cols = (len(maze) - 1) // 2, (len(maze[0]) - 1) // 2
    _check_border_and_joints(maze)
    symbols = [[_cell_symbol(maze, r, c) for c in range(n_cols)] for r in range(n_rows)]
    next_cell = np.empty((n_rows * n_cols, N_ACTIONS), dtype=np.int64)
    for r in range(n_rows):
        for c in range(n_cols):
            for action, (dr, dc) in _STEPS.items():
                next_cell[r * n_cols + c, action] = _move(maze, symbols, r, c, dr, dc, n_cols)
    flat = [s for row in symbols for s in row]
    blocked = np.array([s == BLOCKED for s in flat])
    starts, goals = _maze_placements(flat, n_cols)
    for kind, placement in _trailer_placements(trailer, n_rows, n_cols, blocked):
        (starts if kind == "start" else goals).append(placement)
    start_of = _starts(starts, n_cols, name)
    goal_set = _goals(goals, start_of, [cell for cell, s in enumerate(flat) if s == GOAL], n_rows * n_cols, name)
    gridmap = GridMap(name, n_rows, n_cols, next_cell, goal_set, blocked,
                      np.array([start_of[k].cell for k in sorted(start_of)], dtype=np.int64))
    for array in (next_cell, *goal_set, blocked, gridmap.starts):
        array.setflags(write=False)
    return gridmap


def _where(line: int, col: int) -> str:
    return f"line {line + 1}, column {col + 1}"


def _split_trailer(lines):
    """(maze lines, trailer lines as (line index, text)): the maze ends at the first blank line or
    the first 'start' or 'goal' line; blank lines after it are skipped."""
    end = next((i for i, line in enumerate(lines) if not line.strip() or _TRAILER_WORD.match(line)), len(lines))
    trailer = [(i, line) for i, line in enumerate(lines[end:], end) if line.strip()]
    for i, line in trailer:
        if line.lstrip()[:1] in ("+", "|"):
            raise MapError(f"maze line after a blank line at {_where(i, 0)}: the maze is one block of lines; "
                           "remove the blank line")
    return lines[:end], trailer


def _check_shape(lines):
    if len(lines) < 3 or len(lines) % 2 == 0:
        raise MapError(f"a map has 2R+1 lines for R cell rows (at least 3), got {len(lines)} lines")
    width = len(lines[0])
    if width < 3 or width % 2 == 0:
        raise MapError(f"line 1 has {width} characters; a map line has 2C+1 characters for C columns (at least 3)")
    for i, line in enumerate(lines):
        if len(line) != width:
            raise MapError(f"ragged rows: line {i + 1} has {len(line)} characters, line 1 has {width}; "
                           f"every line must be 2C+1 characters long")


def _expect(lines, i, j, allowed: str, what: str):
    if lines[i][j] not in allowed:
        choices = " or ".join(repr(a) for a in allowed)
        raise MapError(f"{what} at {_where(i, j)}: expected {choices}, found {lines[i][j]!r}")


def _check_border_and_joints(lines):
    last_line, last_col = len(lines) - 1, len(lines[0]) - 1
    for i, line in enumerate(lines):
        for j in range(len(line)):
            on_border = i in (0, last_line) or j in (0, last_col)
            if i % 2 == 0 and j % 2 == 0:
                _expect(lines, i, j, "+", "broken border" if on_border else "wall joint")
            elif i % 2 == 0:
                _expect(lines, i, j, "-" if on_border else "- ", "broken border" if on_border else "wall")
            elif j % 2 == 0:
                _expect(lines, i, j, "|" if on_border else "| ", "broken border" if on_border else "wall")


def _cell_symbol(lines, r, c):
    i, j = 2 * r + 1, 2 * c + 1
    symbol = lines[i][j]
    if symbol not in (FREE, GOAL, BLOCKED) and symbol not in START_SYMBOLS + GOAL_LETTERS:
        raise MapError(f"unknown cell symbol {symbol!r} at {_where(i, j)}: use {_CELL_SYMBOLS}")
    return symbol


def _move(lines, symbols, r, c, dr, dc, n_cols):
    """The cell reached from (r, c) by the step (dr, dc): itself if a wall or blocked cell stops it."""
    wall = lines[2 * r + 1 + dr][2 * c + 1 + dc]
    if wall != " " or symbols[r + dr][c + dc] == BLOCKED or symbols[r][c] == BLOCKED:
        return r * n_cols + c
    return (r + dr) * n_cols + (c + dc)


def _cell_where(cell, n_cols):
    r, c = divmod(cell, n_cols)
    return _where(2 * r + 1, 2 * c + 1)


def check_layout(gridmap: GridMap) -> None:
    """Raise MapError unless ``gridmap`` is a world the rules can play: tables of its size, every
    agent with a goal, starting on a cell of its own that is neither blocked nor one of its goals
    (it would be done before it acts), and a goal of its reachable from its start."""
    name, n_rows, n_cols = gridmap.name, gridmap.n_rows, gridmap.n_cols
    if not all(isinstance(n, (int, np.integer)) and not isinstance(n, bool) and n >= 1 for n in (n_rows, n_cols)):
        raise MapError(f"map {name!r}: n_rows and n_cols must be whole numbers >= 1, got {n_rows!r} and {n_cols!r}")
    cells, agents = gridmap.n_rows * gridmap.n_cols, np.size(gridmap.starts)
    if not isinstance(gridmap.goals, Goals):
        raise MapError(f"map {name!r}: goals must be a Goals (glamas.gridworld.maps.make_goals), got {gridmap.goals!r}")
    own = np.size(gridmap.goals.own)
    for field, array, shape, kind in (("next_cell", gridmap.next_cell, (cells, N_ACTIONS), np.integer),
                                      ("goals.shared", gridmap.goals.shared, (cells,), np.bool_),
                                      ("goals.first", gridmap.goals.first, (agents + 1,), np.integer),
                                      ("goals.own", gridmap.goals.own, (own,), np.integer),
                                      ("blocked", gridmap.blocked, (cells,), np.bool_),
                                      ("starts", gridmap.starts, (agents,), np.integer)):
        if not (isinstance(array, np.ndarray) and np.issubdtype(array.dtype, kind) and array.shape == shape):
            raise MapError(f"map {name!r}: {field} must be an array of {kind.__name__} of shape {shape} for its "
                           f"{n_rows}x{n_cols} cells and {agents} agents, got {array!r}")
    if ((gridmap.next_cell < 0) | (gridmap.next_cell >= cells)).any():
        raise MapError(f"map {name!r}: next_cell leads outside the cells 0..{cells - 1}")
    _check_goal_lists(gridmap)
    _check_starts(gridmap)
    _check_goals_reachable(gridmap)


def _check_goal_lists(gridmap: GridMap) -> None:
    """Each agent's own goals a list of distinct cells of the map, none of them a shared one
    (:func:`make_goals` makes them so)."""
    goals, name = gridmap.goals, gridmap.name
    if goals.first[0] != 0 or goals.first[-1] != goals.own.size or (np.diff(goals.first) < 0).any():
        raise MapError(f"map {name!r}: goals.first must rise from 0 to the number of own goals ({goals.own.size}); "
                       "build the goals with glamas.gridworld.maps.make_goals")
    if ((goals.own < 0) | (goals.own >= gridmap.n_cells)).any():
        raise MapError(f"map {name!r}: an own goal lies outside the cells 0..{gridmap.n_cells - 1}")
    for agent in range(gridmap.n_agents):
        cells = gridmap.own_goals(agent)
        if np.unique(cells).size != cells.size or goals.shared[cells].any():
            raise MapError(f"map {name!r}: agent {agent + 1}'s own goals repeat a cell or a shared goal; give each "
                           "goal once (glamas.gridworld.maps.make_goals)")


def _check_starts(gridmap: GridMap) -> None:
    starts = [int(start) for start in gridmap.starts]
    if not starts:
        raise MapError(f"map {gridmap.name!r} has no start: mark agent 1's start cell '1'")
    for agent, start in enumerate(starts, 1):
        if not 0 <= start < gridmap.n_cells:
            raise MapError(f"map {gridmap.name!r}: agent {agent}'s start {start} is outside the cells "
                           f"0..{gridmap.n_cells - 1}")
        where = _cell_where(start, gridmap.n_cols)
        if not gridmap.goal_cells(agent - 1):
            raise MapError(f"map {gridmap.name!r} has no goal for agent {agent}: mark at least one cell 'G', or "
                           f"give agent {agent} its own goal")
        if gridmap.is_goal_of(agent - 1, start):
            raise MapError(f"map {gridmap.name!r}: agent {agent} starts on its own goal at {where}, where it is done "
                           "before it acts; start it on another cell")
        if gridmap.blocked[start]:
            raise MapError(f"map {gridmap.name!r}: agent {agent} starts on a blocked cell at {where}")
        if starts.index(start) != agent - 1:
            raise MapError(f"map {gridmap.name!r}: agents {starts.index(start) + 1} and {agent} both start at {where}; "
                           "each agent starts on a cell of its own")


def _check_goals_reachable(gridmap: GridMap):
    area = _areas(gridmap)
    for agent, start in enumerate(gridmap.starts.tolist(), 1):
        goals = gridmap.goal_cells(agent - 1)
        if not any(area[g] == area[start] for g in goals):
            cells = ", ".join(_row_col_text(g, gridmap.n_cols) for g in goals)
            raise MapError(f"no goal is reachable from agent {agent}'s start at {_cell_where(start, gridmap.n_cols)} "
                           f"(its goals: {cells}): open a wall on the way")


def _maze_placements(flat, n_cols):
    """The starts ('1'-'9') and own goals ('a'-'i') the maze's symbols give."""
    starts, goals = [], []
    for cell, symbol in enumerate(flat):
        if symbol in START_SYMBOLS:
            starts.append(_Placement(START_SYMBOLS.index(symbol) + 1, cell, _cell_where(cell, n_cols)))
        elif symbol in GOAL_LETTERS:
            goals.append(_Placement(GOAL_LETTERS.index(symbol) + 1, cell, _cell_where(cell, n_cols)))
    return starts, goals


def _trailer_placements(trailer, n_rows, n_cols, blocked):
    """(kind, placement) of every trailer line, 'start' or 'goal', each on a cell of the map that is not blocked."""
    placements = []
    for i, line in trailer:
        indent = len(line) - len(line.lstrip())
        match = _TRAILER_LINE.fullmatch(line.strip())
        if match is None:
            raise MapError(f"line {i + 1} after the maze is not a start or goal: expected {_TRAILER_FORM}, "
                           f"got {line.strip()!r}")
        kind, agent, row, col = match.group(1), *(int(match.group(k)) for k in (2, 3, 4))
        at = {k: _where(i, indent + match.start(k)) for k in (2, 3, 4)}
        if agent < 1:
            raise MapError(f"agent 0 at {at[2]}: agents are numbered from 1")
        if row >= n_rows:
            raise MapError(f"row {row} at {at[3]} is outside the map: its rows are 0..{n_rows - 1}")
        if col >= n_cols:
            raise MapError(f"col {col} at {at[4]} is outside the map: its columns are 0..{n_cols - 1}")
        cell = row * n_cols + col
        if blocked[cell]:
            raise MapError(f"the {kind} of agent {agent} at {at[2]} is on a blocked cell (row {row}, col {col}): "
                           "give a free cell")
        placements.append((kind, _Placement(agent, cell, at[2])))
    return placements


def _starts(placements, n_cols, name):
    """Agent number -> its start placement; each agent starts once, no two on a cell, numbered 1..N."""
    by_agent, by_cell = {}, {}
    for p in placements:
        if p.agent in by_agent:
            raise MapError(f"duplicate start of agent {p.agent} at {p.where} "
                           f"(already at {by_agent[p.agent].where}): each agent starts once")
        if p.cell in by_cell:
            other = by_cell[p.cell]
            raise MapError(f"two starts on one cell {_row_col_text(p.cell, n_cols)}: agent {p.agent}'s at {p.where} "
                           f"and agent {other.agent}'s at {other.where}; give each agent a cell of its own")
        by_agent[p.agent], by_cell[p.cell] = p, p
    if not by_agent:
        raise MapError(f"map {name!r} has no start: mark agent 1's start cell '1' (and '2', ... for more agents)")
    for k in range(1, len(by_agent) + 1):
        if k not in by_agent:
            last = max(by_agent)
            raise MapError(f"agent numbers must be consecutive from 1: agent {k} has no start but "
                           f"agent {last} does (at {by_agent[last].where}); number the starts 1..{len(by_agent)}")
    return by_agent


def _goals(placements, start_of, every_goal, n_cells, name):
    """Each agent's goals (:func:`make_goals`), the shared 'G' cells and its own; checked."""
    n_agents = len(start_of)
    shared = np.zeros(n_cells, dtype=bool)
    shared[every_goal] = True
    own = [[] for _ in range(n_agents)]
    if not every_goal and not placements:
        raise MapError(f"map {name!r} has no goal: mark at least one cell 'G' (every agent's goal), or give "
                       f"agent k its own goal with its letter ('a' for agent 1) or a line 'goal K: row R, col C'")
    given = {}
    for p in placements:
        if p.agent not in start_of:
            raise MapError(f"a goal of agent {p.agent} at {p.where}, but agent {p.agent} has no start; "
                           f"the map's agents are 1..{n_agents}: give it a start or remove the goal")
        if shared[p.cell] or (p.agent, p.cell) in given:
            first = given.get((p.agent, p.cell), "a 'G' cell")
            raise MapError(f"the goal of agent {p.agent} at {p.where} is given twice (also at {first}); remove one")
        own[p.agent - 1].append(p.cell)
        given[(p.agent, p.cell)] = p.where
    for agent, start in sorted(start_of.items()):
        if not (every_goal or own[agent - 1]):
            letter = f"'{GOAL_LETTERS[agent - 1]}' or " if agent <= len(GOAL_LETTERS) else ""
            raise MapError(f"agent {agent} (start at {start.where}) has no goal: mark its goal cell {letter}'G' "
                           f"(every agent's), or add a line 'goal {agent}: row R, col C' after the maze")
        if shared[start.cell] or (agent, start.cell) in given:
            where = given.get((agent, start.cell), "a 'G' cell")
            raise MapError(f"agent {agent} starts on its own goal (start at {start.where}, goal at {where}): "
                           "it would be done before it moves; move its start or its goal")
    return make_goals(shared, own)


def make_goals(shared: np.ndarray, own: list) -> Goals:
    """The :class:`glamas.gridworld.rules.Goals` of the cells marked ``shared`` (bool, cells: every
    agent's goal) and each agent's own goal cells ``own[i]`` (lists, agent by agent, in increasing order)."""
    first = np.zeros(len(own) + 1, dtype=np.int64)
    first[1:] = np.cumsum([len(cells) for cells in own])
    cells = np.array([c for agent_cells in own for c in sorted(agent_cells)], dtype=np.int64)
    # read-only always: numba types a writable array apart and would compile every kernel again
    return Goals(*(_read_only(np.array(a)) for a in (np.asarray(shared, dtype=bool), first, cells)))


def goals_from_table(table: np.ndarray) -> Goals:
    """The goals of a table ``table[i, c]`` (bool, agents x cells: cell c is a goal of agent i):
    the cells that are every agent's goal marked shared, the others each agent's own."""
    table = np.asarray(table, dtype=bool)
    shared = table.all(axis=0) if table.shape[0] else np.zeros(table.shape[1], dtype=bool)
    return make_goals(shared, [np.flatnonzero(row & ~shared).tolist() for row in table])


def _row_col_text(cell, n_cols):
    r, c = divmod(int(cell), n_cols)
    return f"(row {r}, col {c})"


def _areas(gridmap: GridMap) -> list[int]:
    """Each cell's area: cells an agent can walk between share one (moves are symmetric)."""
    area = [-1] * gridmap.n_cells
    for first in range(gridmap.n_cells):
        if area[first] >= 0:
            continue
        area[first], frontier = first, deque([first])
        while frontier:
            for other in gridmap.open_neighbours(frontier.popleft()):
                if area[other] < 0:
                    area[other] = first
                    frontier.append(other)
    return area


# --- writing ------------------------------------------------------------------------------------

def map_text(gridmap: GridMap, cells=None) -> str:
    """``gridmap`` in the format of this module, agent k on cell ``cells[k - 1]`` (default: its
    start): the maze, then a trailer line for every start and goal no symbol can hold (agents
    beyond 9; goals on a start cell or on another agent's goal). A goal of every agent is 'G', a
    goal of some agents the letter of the lowest-numbered of them (up to 9) and goal lines for the
    others. Walls are drawn where no move crosses between two cells, around blocked cells too.
    What it writes for the starts loads back to ``gridmap`` (:meth:`GridMap.same_layout`)."""
    cells = gridmap.starts if cells is None else np.asarray(cells)
    symbols, trailer = _cell_symbols(gridmap, [int(c) for c in cells])
    lines = ["+" + "-+" * gridmap.n_cols]
    for r in range(gridmap.n_rows):
        cell_line, below = "|", "+"
        for c in range(gridmap.n_cols):
            cell = gridmap.cell(r, c)
            right = c == gridmap.n_cols - 1 or _wall(gridmap, cell, cell + 1)
            down = r == gridmap.n_rows - 1 or _wall(gridmap, cell, cell + gridmap.n_cols)
            cell_line += symbols[cell] + ("|" if right else " ")
            below += ("-" if down else " ") + "+"
        lines += [cell_line, below]
    return "\n".join(lines + trailer) + "\n"


def _cell_symbols(gridmap: GridMap, cells: list[int]) -> tuple[list[str], list[str]]:
    """Each cell's symbol and the trailer lines for what no symbol holds (starts, then goals, by agent)."""
    symbols = ["#" if b else FREE for b in gridmap.blocked.tolist()]
    starts, goals = [], []
    for agent, cell in enumerate(cells, 1):
        if agent <= len(START_SYMBOLS):
            symbols[cell] = START_SYMBOLS[agent - 1]
        else:
            starts.append(_trailer_line("start", agent, gridmap, cell))
    for cell in range(gridmap.n_cells):
        owners = [a + 1 for a in gridmap.goal_owners(cell)]
        if not owners or symbols[cell] != FREE:
            goals += [(a, _trailer_line("goal", a, gridmap, cell)) for a in owners]
        elif len(owners) == gridmap.n_agents:
            symbols[cell] = GOAL
        elif owners[0] <= len(GOAL_LETTERS):
            symbols[cell] = GOAL_LETTERS[owners[0] - 1]
            goals += [(a, _trailer_line("goal", a, gridmap, cell)) for a in owners[1:]]
        else:
            goals += [(a, _trailer_line("goal", a, gridmap, cell)) for a in owners]
    return symbols, starts + [line for _, line in sorted(goals, key=lambda g: g[0])]


def _trailer_line(kind: str, agent: int, gridmap: GridMap, cell: int) -> str:
    row, col = gridmap.row_col(cell)
    return f"{kind} {agent}: row {row}, col {col}"


def _wall(gridmap: GridMap, a: int, b: int) -> bool:
    """A wall between neighbouring cells a and b: no move crosses between them."""
    return b not in gridmap.open_neighbours(a) and a not in gridmap.open_neighbours(b)


def canonical_difference(path) -> str | None:
    """None when map file ``path`` is in its canonical form (:func:`map_text`), else the first line
    that differs, both ways, for a message."""
    text = _decode(_read_bytes(Path(path)))
    canonical = map_text(load_map(path))
    if text == canonical:
        return None
    ours, theirs = text.splitlines(), canonical.splitlines()
    line = next((i for i, (a, b) in enumerate(zip(ours, theirs)) if a != b), min(len(ours), len(theirs)))
    found = ours[line] if line < len(ours) else "(the end of the file)"
    written = theirs[line] if line < len(theirs) else "(the end of the file)"
    return f"line {line + 1} is {found!r} where the canonical form has {written!r}"

