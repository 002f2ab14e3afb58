"""The driver of `make figures`, `make reproduce` and `make verify` (glamas.reproduce): its
script lists, a figure drawn in-process equal to the committed one, and a user error's exit."""

import pytest

from glamas import reproduce
from glamas.verify import FIGURES


def test_the_chapter_scripts_are_scripts_of_paper_figures():
    assert set(reproduce.CHAPTER) < set(reproduce.every_script())
    assert {"scaling_performance", "related_steps", "fig7_sweep"} <= set(reproduce.every_script())


def test_a_script_run_by_the_driver_draws_the_committed_figure(tmp_path, capsys):
    reproduce.run(["fig9", "fig9"], ["--out", str(tmp_path)])  # twice in one process: the same bytes
    assert (tmp_path / "fig9.png").read_bytes() == (FIGURES / "fig9.png").read_bytes()
    assert capsys.readouterr().out.count("== paper_figures/fig9.py") == 2


@pytest.mark.parametrize("option", ["--out", "--results"])
def test_a_user_error_stops_the_driver_with_one_line_and_status_2(tmp_path, capsys, option):
    not_a_directory = tmp_path / "file"
    not_a_directory.write_text("kept")
    with pytest.raises(SystemExit) as stopped:
        reproduce.main([option, str(not_a_directory)])
    assert stopped.value.code == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert len(err.splitlines()) == 1 and option in err
    assert "== paper_figures" not in captured.out  # refused before any script ran
    assert not_a_directory.read_text() == "kept"
