"""The map format and loader: the bundled TunnelToGoal map and every malformed-map error."""

import importlib.util

import numpy as np
import pytest

from glamas.gridworld import MapError, load_map, tunnel_to_goal
from glamas.gridworld.maps import map_hash, map_path
from glamas.gridworld.rules import E, N, S, W
from glamas.paths import MAPS, REPO

GOOD = """\
+-+-+-+
|1 . G|
+ +-+ +
|2 # .|
+-+-+-+
"""


def test_tunnel_to_goal_layout():
    m = tunnel_to_goal()
    assert (m.name, m.n_rows, m.n_cols, m.n_cells, m.n_agents) == ("tunnel_to_goal", 5, 5, 25, 2)
    assert m.starts.tolist() == [m.cell(0, 0), m.cell(4, 0)]
    assert np.flatnonzero(m.is_goal).tolist() == [m.cell(2, 0)]
    assert not m.blocked.any()
    # Walls above and below the goal row in columns 0-3; (2, 4) is the only way in.
    for col in range(4):
        assert m.next_cell[m.cell(1, col), S] == m.cell(1, col)
        assert m.next_cell[m.cell(3, col), N] == m.cell(3, col)
    assert m.next_cell[m.cell(1, 4), S] == m.cell(2, 4)
    assert m.next_cell[m.cell(3, 4), N] == m.cell(2, 4)
    assert m.next_cell[m.cell(2, 1), W] == m.cell(2, 0)
    assert m.row_col(m.cell(3, 2)) == (3, 2)


def test_moves_are_symmetric():
    m = tunnel_to_goal()
    opposite = {N: S, S: N, E: W, W: E}
    for cell in range(m.n_cells):
        for action in (N, E, S, W):
            other = m.next_cell[cell, action]
            if other != cell:
                assert m.next_cell[other, opposite[action]] == cell


def test_blocked_cells_and_inner_walls():
    m = load_map(GOOD)
    assert m.name == "inline" and m.blocked.tolist() == [False, False, False, False, True, False]
    assert m.next_cell[m.cell(1, 0), E] == m.cell(1, 0)  # into the blocked cell
    assert m.next_cell[m.cell(0, 1), S] == m.cell(0, 1)  # wall '-'
    assert m.next_cell[m.cell(0, 2), S] == m.cell(1, 2)


def test_arrays_are_read_only():
    m = tunnel_to_goal()
    with pytest.raises(ValueError):
        m.next_cell[0, 0] = 3


def test_load_from_path_and_trailing_blank_lines(tmp_path):
    path = tmp_path / "small.txt"
    path.write_text(GOOD + "\n\n")
    assert load_map(path).name == "small"
    assert load_map(str(path)).n_cells == 6
    assert load_map(MAPS / "tunnel_to_goal.txt").n_agents == 2


def test_cell_and_row_col_reject_outside():
    m = tunnel_to_goal()
    with pytest.raises(ValueError, match=r"\(5, 0\) is outside the 5x5 map"):
        m.cell(5, 0)
    with pytest.raises(ValueError, match="cell 25 is outside"):
        m.row_col(25)


def edit(text, line, col, char):
    """``text`` with the character at 1-based (line, col) replaced."""
    lines = text.splitlines()
    row = lines[line - 1]
    lines[line - 1] = row[:col - 1] + char + row[col:]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("text, message", [
    (edit(GOOD, 2, 4, "x"), r"unknown cell symbol 'x' at line 2, column 4"),
    (edit(GOOD, 2, 3, "*"), r"wall at line 2, column 3: expected '\|' or ' ', found '\*'"),
    (edit(GOOD, 3, 4, "|"), r"wall at line 3, column 4: expected '-' or ' '"),
    (edit(GOOD, 3, 3, " "), r"wall joint at line 3, column 3: expected '\+'"),
    (edit(GOOD, 1, 2, " "), r"broken border at line 1, column 2: expected '-'"),
    (edit(GOOD, 4, 7, " "), r"broken border at line 4, column 7: expected '\|'"),
    (edit(GOOD, 5, 1, "-"), r"broken border at line 5, column 1: expected '\+'"),
    (GOOD.replace("|2 # .|", "|2 # . |"), r"ragged rows: line 4 has 8 characters, line 1 has 7"),
    ("+-+\n|1|\n", r"2R\+1 lines .* got 2 lines"),
    ("+-+-\n|1 G\n+-+-\n", r"line 1 has 4 characters"),
    (GOOD.replace("G", "."), r"has no goal: mark at least one cell 'G'"),
    (GOOD.replace("1", ".").replace("2", "."), r"has no start"),
    (GOOD.replace("1", "3"), r"consecutive from 1: agent 1 has no start"),
    (GOOD.replace("2", "1"), r"duplicate start of agent 1 at line 4, column 2 \(already at line 2, column 2\)"),
    (GOOD.replace("+ +-+ +", "+-+-+ +"), r"no goal is reachable from agent 2's start at line 4, column 2"),
])
def test_malformed_maps_name_the_place(text, message):
    with pytest.raises(MapError, match=message):
        load_map(text)


def test_missing_file_and_wrong_type():
    with pytest.raises(MapError, match="no map file nowhere.txt"):
        load_map("nowhere.txt")
    with pytest.raises(TypeError, match="path or the map's text"):
        load_map(42)


def load_script(name):
    spec = importlib.util.spec_from_file_location(name, REPO / "paper_figures" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", ["fig9", "fig9_optimum"])
def test_fig9_scripts_are_byte_reproducible(tmp_path, name):
    script = load_script(name)
    script.main(["--out", str(tmp_path / "a")])
    script.main(["--out", str(tmp_path / "b")])
    names = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert names == [f"{name}.pdf", f"{name}.png"]
    for drawn in names:
        assert (tmp_path / "a" / drawn).read_bytes() == (tmp_path / "b" / drawn).read_bytes()


def test_fig9_rejects_a_file_as_out(tmp_path, capsys):
    target = tmp_path / "file.txt"
    target.write_text("x")
    with pytest.raises(SystemExit):
        load_script("fig9").main(["--out", str(target)])
    assert "exists and is not a directory" in capsys.readouterr().err


def test_draw_map_walls():
    from glamas.gridworld.draw import _walls
    walls = _walls(tunnel_to_goal())
    # The border (4 lines) and the 8 wall segments above and below the goal row.
    assert len(walls) == 4 + 8
    assert ([0, 1], [2, 2]) in walls and ([3, 4], [3, 3]) in walls and ([4, 5], [2, 2]) not in walls


def test_a_map_by_name_with_or_without_txt_is_parsed_once():
    assert load_map("tunnel_to_goal") is load_map("tunnel_to_goal.txt") is load_map(MAPS / "tunnel_to_goal.txt")
    assert map_path("warehouse_3") == MAPS / "warehouse_3.txt"


def test_an_edited_map_file_is_parsed_again_and_hashes_anew(tmp_path):
    path = tmp_path / "small.txt"
    path.write_text(GOOD)
    first, first_hash = load_map(path), map_hash(path)
    path.write_text(GOOD.replace("2 #", "2 ."))
    assert load_map(path) is not first and not load_map(path).blocked.any()
    assert map_hash(str(path)) != first_hash


def test_an_unknown_name_lists_the_maps_there_are():
    with pytest.raises(MapError, match=r"no map file nowhere; .* data/maps \(.*tunnel_to_goal.*\)"):
        map_path("nowhere")
