"""The map format and loader: the bundled TunnelToGoal map and every malformed-map error."""

import importlib.util

import numpy as np
import pytest

from glamas.gridworld import MapError, canonical, load_map, map_text, tunnel_to_goal
from glamas.gridworld.maps import canonical_difference
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
    assert m.goal_table().tolist() == [m.is_goal.tolist()] * 2 and np.array_equal(m.shared_goal, m.is_goal)
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
    for array in (m.next_cell, *m.goals, m.blocked, m.starts, m.is_goal, m.shared_goal):
        with pytest.raises(ValueError):
            array[0] = 3


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
    (edit(GOOD, 4, 7, "x"), r"broken border at line 4, column 7: expected '\|'"),
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


# --- per-agent goals and the trailer --------------------------------------------------------------

SWAP = """\
+-+-+-+-+
|1 . . 2|
+ +-+-+ +
|. . . .|
+-+-+-+-+

goal 1: row 0, col 3
goal 2: row 0, col 0
"""
"""Two agents swapping places, as in ISR, CIT and CMU: each one's goal is the other's start."""

LETTERS = """\
+-+-+-+-+
|1 . b a|
+ + + + +
|2 . G #|
+-+-+-+-+
"""


def test_goal_lines_give_a_goal_on_another_agents_start():
    m = load_map(SWAP)
    assert m.goal_cells(0) == [m.cell(0, 3)] and m.goal_cells(1) == [m.cell(0, 0)]
    assert m.is_goal.sum() == 2 and not m.shared_goal.any()


def test_letters_are_own_goals_and_g_everyones():
    m = load_map(LETTERS)
    assert m.goal_cells(0) == [m.cell(0, 3), m.cell(1, 2)]
    assert m.goal_cells(1) == [m.cell(0, 2), m.cell(1, 2)]
    assert np.flatnonzero(m.shared_goal).tolist() == [m.cell(1, 2)]


def test_agents_beyond_nine_start_and_end_in_the_trailer():
    lines = ["+" + "-+" * 11, "|" + " ".join("123456789..") + "|", "+" + " +" * 10 + " +",
             "|" + " ".join("...........") + "|", "+" + "-+" * 11, ""]
    lines += [f"start {k}: row 0, col {k - 1}" for k in (10, 11)]
    lines += [f"goal {k}: row 1, col {k - 1}" for k in range(1, 12)]
    m = load_map("\n".join(lines) + "\n")
    assert m.n_agents == 11 and m.starts.tolist() == list(range(11))
    assert all(m.goal_cells(k) == [11 + k] for k in range(11))
    again = map_text(m)
    assert load_map(again).same_layout(m)
    assert "start 10: row 0, col 9" in again and "goal 11: row 1, col 10" in again


@pytest.mark.parametrize("text, message", [
    (SWAP + "goal 3: row 1, col 1\n", r"a goal of agent 3 at line 9, column 6, but agent 3 has no start; .*1\.\.2"),
    (LETTERS.replace("b a", "c a"), r"a goal of agent 3 at line 2, column 6, but agent 3 has no start"),
    (SWAP + "start 3: row 0, col 0\n", r"two starts on one cell \(row 0, col 0\): agent 3's at line 9, column 7 "
                                       r"and agent 1's at line 2, column 2"),
    (SWAP + "start 2: row 1, col 1\n", r"duplicate start of agent 2 at line 9, column 7 \(already at line 2, column 8\)"),
    (SWAP.replace("|1 . . 2|", "|1 . .|2|").replace("+ +-+-+ +", "+ +-+-+-+"),
     r"no goal is reachable from agent 1's start at line 2, column 2 \(its goals: \(row 0, col 3\)\)"),
    (SWAP + "goal 1: row 0, col 0\n", r"agent 1 starts on its own goal \(start at line 2, column 2, goal at line 9, "
                                      r"column 6\)"),
    (SWAP.replace("goal 2: row 0, col 0\n", ""), r"agent 2 \(start at line 2, column 8\) has no goal: mark its goal "
                                                 r"cell 'b' or 'G'.*'goal 2: row R, col C'"),
    (SWAP + "start 3: row 1, col 1\n", r"agent 3 \(start at line 9, column 7\) has no goal"),
    (SWAP + "start 3: row 1, col 1\ngoal 3: row 1, col 1\n", r"agent 3 starts on its own goal"),
    (SWAP + "goal 1: row 0, col 3\n", r"the goal of agent 1 at line 9, column 6 is given twice \(also at line 7, column 6"),
    (LETTERS + "goal 2: row 1, col 2\n", r"the goal of agent 2 at line 6, column 6 is given twice \(also at a 'G' cell\)"),
    (SWAP + "start 3: row 1, col 1\ngoal 3: row 1, col 3\ngoal 3: row 0, col 3\n", None),
    (SWAP + "start 3 row 1, col 1\n", r"line 9 after the maze is not a start or goal: expected 'start K: row R, "
                                      r"col C' or 'goal K: row R, col C', got 'start 3 row 1, col 1'"),
    (SWAP + "goal 1: row 2, col 0\n", r"row 2 at line 9, column 13 is outside the map: its rows are 0\.\.1"),
    (SWAP + "goal 1: row 1, col 4\n", r"col 4 at line 9, column 20 is outside the map: its columns are 0\.\.3"),
    (SWAP + "goal 0: row 1, col 1\n", r"agent 0 at line 9, column 6: agents are numbered from 1"),
    (LETTERS + "goal 1: row 1, col 3\n", r"the goal of agent 1 at line 6, column 6 is on a blocked cell \(row 1, col 3\)"),
    (SWAP.replace("|. . . .|", "|. . . .|\n"), r"maze line after a blank line at line 6, column 1"),
    (LETTERS.replace("b", "j"), r"unknown cell symbol 'j' at line 2, column 6: .*'a'-'i'"),
])
def test_per_agent_goal_faults_name_the_place(text, message):
    if message is None:  # a valid map: an agent with two goals
        assert load_map(text).goal_cells(2) == [3, 7]
        return
    with pytest.raises(MapError, match=message):
        load_map(text)


@pytest.mark.parametrize("path", sorted(MAPS.glob("*.txt")), ids=lambda p: p.stem)
def test_every_map_file_is_in_its_canonical_form(path):
    difference = canonical_difference(path)
    assert difference is None, (f"{path.name} loads, but is not in the canonical form of data/maps: {difference}; "
                                f"`python -m glamas.gridworld.canonical {path} --write` puts it in that form")
    assert load_map(map_text(load_map(path))).same_layout(load_map(path))


def test_a_map_in_another_reasonable_form_is_the_same_map(tmp_path, capsys):
    written = (MAPS / "isr.txt").read_text()
    loose = "\r\n".join("    " + line + "  " for line in written.splitlines()) + "\r\n\r\n"
    assert load_map(loose).same_layout(load_map("isr"))
    path = tmp_path / "loose.txt"
    path.write_bytes(loose.encode())
    assert "line 1 is '    +-+-" in canonical_difference(path)
    assert canonical.main([str(path)]) == 0 and capsys.readouterr().out == written
    assert canonical.main([str(path), "--write"]) == 0 and path.read_text() == written
    assert canonical_difference(path) is None
    canonical.main([str(path), "--write"])
    assert "in its canonical form already" in capsys.readouterr().out
    with pytest.raises(MapError, match="no map file no_such_map; give a map file's path or the name of a map"):
        canonical.main(["no_such_map", "--write"])


def random_map_text(rng, n_rows, n_cols, n_agents):
    """A random map's text: random walls and blocked cells, starts and goals as symbols, 'G' or trailer lines."""
    cells = rng.permutation(n_rows * n_cols)
    blocked = set(cells[2 * n_agents:][rng.random(len(cells) - 2 * n_agents) < 0.15].tolist())
    symbols, trailer = ["."] * (n_rows * n_cols), []
    for cell in blocked:
        symbols[cell] = "#"
    for k, cell in enumerate(cells[:n_agents].tolist(), 1):
        if k <= 9 and rng.random() < 0.8:
            symbols[cell] = str(k)
        else:
            trailer.append(f"start {k}: row {cell // n_cols}, col {cell % n_cols}")
    for k, cell in enumerate(cells[n_agents:2 * n_agents].tolist(), 1):
        if rng.random() < 0.1:
            symbols[cell] = "G"
        elif k <= 9 and rng.random() < 0.6:
            symbols[cell] = "abcdefghi"[k - 1]
        trailer.append(f"goal {k}: row {cell // n_cols}, col {cell % n_cols}")  # given twice where a symbol holds it
    lines = ["+" + "-+" * n_cols]
    for r in range(n_rows):
        walls = ["|" if rng.random() < 0.2 else " " for _ in range(n_cols - 1)]
        lines.append("|" + "".join(s + w for s, w in zip(symbols[r * n_cols:(r + 1) * n_cols], walls + ["|"])))
        lines.append("+" + "".join(("-" if r == n_rows - 1 or rng.random() < 0.2 else " ") + "+" for _ in range(n_cols)))
    trailer = [t for t in trailer if not _held_by_symbol(t, symbols, n_cols)]
    return "\n".join(lines + trailer) + "\n"


def _held_by_symbol(line, symbols, n_cols):
    """Whether the goal line ``line`` repeats a goal its cell's symbol already gives."""
    kind, agent, _, row, _, col = line.replace(":", "").replace(",", "").split()
    symbol = symbols[int(row) * n_cols + int(col)]
    return kind == "goal" and (symbol == "G" or (int(agent) <= 9 and symbol == "abcdefghi"[int(agent) - 1]))


def test_random_maps_are_written_back_to_the_same_map():
    rng = np.random.default_rng(7)
    loaded = 0
    for _ in range(400):
        n_rows, n_cols = int(rng.integers(1, 7)), int(rng.integers(2, 9))
        text = random_map_text(rng, n_rows, n_cols, int(rng.integers(1, min(12, n_rows * n_cols // 2) + 1)))
        try:
            m = load_map(text)
        except MapError:
            continue  # a goal walled off, or 'G' on a start's own goal
        loaded += 1
        again = map_text(m)
        assert load_map(again).same_layout(m), text
        assert map_text(load_map(again)) == again
    assert loaded > 100


@pytest.mark.parametrize("name, labels", [("tunnel_to_goal", ["G"]), ("isr", ["G1", "G2"]),
                                          ("tunnel_to_goal_4", ["G1,2", "G3,4"])])
def test_draw_map_labels_each_agents_goal(name, labels):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from glamas.gridworld.draw import draw_map
    fig, ax = plt.subplots()
    draw_map(ax, load_map(name))
    texts = [t.get_text() for t in ax.texts]
    plt.close(fig)
    assert sorted(t for t in texts if t.startswith("G")) == labels
