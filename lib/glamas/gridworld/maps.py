"""Gridworld maps: the text format of ``data/maps/*.txt``, its loader and the map it builds.

A map of R rows and C columns is drawn like a maze in 2R+1 lines of 2C+1 characters:

- cell lines (odd line index): odd columns hold the cell, ``.`` free, ``G`` goal, ``#`` blocked,
  ``1``-``9`` the start of that agent; even columns hold ``|`` (a wall between the cells left and
  right of it) or a space (open);
- separator lines (even line index): even columns hold ``+``; odd columns ``-`` (a wall between
  the cells above and below) or a space;
- the border is closed: first and last lines ``+-+-...+``, cell lines begin and end with ``|``.

Cells are numbered row by row, ``cell = row * n_cols + col``; row 0 is the top line. A start
symbol stands in place of the cell symbol, so a start is always a free cell (never the goal or a
blocked cell). Walls are symmetric by construction: one character separates two cells.

Every :class:`GridMap`, read from a file or built in Python, is checked by one function,
:func:`check_layout`, when it is made.
"""

import hashlib
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from glamas.errors import UserError
from glamas.gridworld.rules import E, N, N_ACTIONS, S, W
from glamas.paths import MAPS

FREE, GOAL, BLOCKED = ".", "G", "#"
_CELL_SYMBOLS = "free '.', goal 'G', blocked '#' or an agent's start '1'-'9'"
_STEPS = {N: (-1, 0), E: (0, 1), S: (1, 0), W: (0, -1)}


class MapError(UserError):
    """A map file that does not follow the format of :mod:`glamas.gridworld.maps`."""


@dataclass(frozen=True, eq=False)
class GridMap:
    """A loaded gridworld: its moves as a table, its goal and blocked cells and the agents' starts."""

    name: str
    """The map's name (file stem, or 'inline' for a map given as text)."""
    n_rows: int
    """Number of cell rows."""
    n_cols: int
    """Number of cell columns."""
    next_cell: np.ndarray
    """int64 (n_cells, 4): the cell each action N, E, S, W leads to; the cell itself when a wall,
    the border or a blocked cell stops the move."""
    is_goal: np.ndarray
    """bool (n_cells,): goal cells (absorbing)."""
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


def load_map(source) -> GridMap:
    """A :class:`GridMap` from a map's name in ``data/maps`` (``"tunnel_to_goal"``, with or
    without ``.txt``), a map file's path, or the map's text; raises :class:`MapError` (naming the
    file for a map read from one). A file is parsed once per content (:func:`map_text_hash`):
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


def _parse(text: str, name: str) -> GridMap:
    lines = text.splitlines()
    while lines and not lines[-1].strip():
        lines.pop()
    _check_shape(lines)
    n_rows, n_cols = (len(lines) - 1) // 2, (len(lines[0]) - 1) // 2
    _check_border_and_joints(lines)
    symbols = [[_cell_symbol(lines, r, c) for c in range(n_cols)] for r in range(n_rows)]
    next_cell = np.empty((n_rows * n_cols, N_ACTIONS), dtype=np.int64)
    for r in range(n_rows):
        for c in range(n_cols):
            for action, (dr, dc) in _STEPS.items():
                next_cell[r * n_cols + c, action] = _move(lines, symbols, r, c, dr, dc, n_cols)
    flat = [s for row in symbols for s in row]
    is_goal = np.array([s == GOAL for s in flat])
    blocked = np.array([s == BLOCKED for s in flat])
    starts = _starts(flat, n_cols, name)
    for array in (next_cell, is_goal, blocked, starts):
        array.setflags(write=False)
    return GridMap(name, n_rows, n_cols, next_cell, is_goal, blocked, starts)


def _where(line: int, col: int) -> str:
    return f"line {line + 1}, column {col + 1}"


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
    if symbol not in (FREE, GOAL, BLOCKED) and symbol not in "123456789":
        raise MapError(f"unknown cell symbol {symbol!r} at {_where(i, j)}: use {_CELL_SYMBOLS}")
    return symbol


def _move(lines, symbols, r, c, dr, dc, n_cols):
    """The cell reached from (r, c) by the step (dr, dc): itself if a wall or blocked cell stops it."""
    wall = lines[2 * r + 1 + dr][2 * c + 1 + dc]
    if wall != " " or symbols[r + dr][c + dc] == BLOCKED or symbols[r][c] == BLOCKED:
        return r * n_cols + c
    return (r + dr) * n_cols + (c + dc)


def _starts(flat, n_cols, name):
    found = {}
    for cell, symbol in enumerate(flat):
        if symbol.isdigit():
            if symbol in found:
                first = found[symbol]
                raise MapError(f"duplicate start of agent {symbol} at {_cell_where(cell, n_cols)} "
                               f"(already at {_cell_where(first, n_cols)}): each agent starts once")
            found[symbol] = cell
    if not found:
        raise MapError(f"map {name!r} has no start: mark agent 1's start cell '1' (and '2', ... for more agents)")
    for k in range(1, len(found) + 1):
        if str(k) not in found:
            raise MapError(f"agent numbers must be consecutive from 1: agent {k} has no start but "
                           f"{max(found)} does; number the starts 1..{len(found)}")
    return np.array([found[str(k)] for k in range(1, len(found) + 1)], dtype=np.int64)


def _cell_where(cell, n_cols):
    r, c = divmod(cell, n_cols)
    return _where(2 * r + 1, 2 * c + 1)


def check_layout(gridmap: GridMap) -> None:
    """Raise MapError unless ``gridmap`` is a world the rules can play: tables of its size, a goal,
    every agent starting on a cell of its own that is neither blocked nor a goal (an agent in a goal
    is done before it acts), and a goal reachable from every start."""
    name, n_rows, n_cols = gridmap.name, gridmap.n_rows, gridmap.n_cols
    if not all(isinstance(n, (int, np.integer)) and not isinstance(n, bool) and n >= 1 for n in (n_rows, n_cols)):
        raise MapError(f"map {name!r}: n_rows and n_cols must be whole numbers >= 1, got {n_rows!r} and {n_cols!r}")
    cells = gridmap.n_cells
    for field, shape, kind in (("next_cell", (cells, N_ACTIONS), np.integer), ("is_goal", (cells,), np.bool_),
                               ("blocked", (cells,), np.bool_), ("starts", (np.size(gridmap.starts),), np.integer)):
        array = getattr(gridmap, field)
        if not (isinstance(array, np.ndarray) and np.issubdtype(array.dtype, kind) and array.shape == shape):
            raise MapError(f"map {name!r}: {field} must be an array of {kind.__name__} of shape {shape} for its "
                           f"{n_rows}x{n_cols} cells, got {array!r}")
    if ((gridmap.next_cell < 0) | (gridmap.next_cell >= gridmap.n_cells)).any():
        raise MapError(f"map {name!r}: next_cell leads outside the cells 0..{gridmap.n_cells - 1}")
    if not gridmap.is_goal.any():
        raise MapError(f"map {name!r} has no goal: mark at least one cell 'G'")
    _check_starts(gridmap)
    _check_goal_reachable(gridmap)


def _check_starts(gridmap: GridMap) -> None:
    starts = [int(start) for start in gridmap.starts]
    if not starts:
        raise MapError(f"map {gridmap.name!r} has no start: mark agent 1's start cell '1'")
    for agent, start in enumerate(starts, 1):
        if not 0 <= start < gridmap.n_cells:
            raise MapError(f"map {gridmap.name!r}: agent {agent}'s start {start} is outside the cells "
                           f"0..{gridmap.n_cells - 1}")
        where = _cell_where(start, gridmap.n_cols)
        if gridmap.is_goal[start]:
            raise MapError(f"map {gridmap.name!r}: agent {agent} starts on a goal at {where}, where it is done "
                           "before it acts; start it on a free cell")
        if gridmap.blocked[start]:
            raise MapError(f"map {gridmap.name!r}: agent {agent} starts on a blocked cell at {where}")
        if starts.index(start) != agent - 1:
            raise MapError(f"map {gridmap.name!r}: agents {starts.index(start) + 1} and {agent} both start at {where}; "
                           "each agent starts on a cell of its own")


def _check_goal_reachable(gridmap: GridMap):
    seen = {int(g) for g in np.flatnonzero(gridmap.is_goal)}
    frontier = deque(seen)
    while frontier:  # backwards search from the goals: moves are symmetric, so neighbours suffice
        cell = frontier.popleft()
        for other in gridmap.open_neighbours(cell):
            if other not in seen:
                seen.add(other)
                frontier.append(other)
    for agent, start in enumerate(gridmap.starts, 1):
        if int(start) not in seen:
            raise MapError(f"no goal is reachable from agent {agent}'s start at "
                           f"{_cell_where(int(start), gridmap.n_cols)}: open a wall on the way")
