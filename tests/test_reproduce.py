"""The driver of `make figures`, `make reproduce` and `make verify` (glamas.reproduce): its
script lists, a figure drawn in-process equal to the committed one, a user error's exit, and
--fresh, which empties only what glamas wrote and refuses, deleting nothing, anything else."""

import pytest

from glamas import parallel, reproduce
from glamas.experiments import registry
from glamas.paths import DATA, REPO, RESULTS
from glamas.verify import FIGURES


def test_every_script_of_paper_figures_is_a_figure_of_one_experiment():
    named = [name for experiment in registry.experiments() for name in experiment.figures]
    assert sorted(named) == sorted(path.stem for path in reproduce.SCRIPTS.glob("*.py"))
    assert set(registry.figure_scripts()) < set(registry.figure_scripts(chapter_only=False)) == set(named)
    assert {"scaling_performance", "related_steps", "fig7_sweep"}.isdisjoint(registry.figure_scripts())


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


def _tree(directory):
    """Every file under ``directory`` with its bytes: what a refusal must leave as it was."""
    return {path: path.read_bytes() for path in sorted(directory.rglob("*")) if path.is_file()}


def _refused(argv, capsys) -> str:
    """The one line on stderr of ``reproduce.main(argv)``, checked to exit with status 2 before
    any script ran."""
    with pytest.raises(SystemExit) as stopped:
        reproduce.main(argv)
    assert stopped.value.code == 2
    captured = capsys.readouterr()
    assert "== paper_figures" not in captured.out
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    return lines[0]


@pytest.mark.parametrize("fresh, named", [("", "is empty"), ("  ", "is empty"), ("data", "is the repository's data/"),
                                          ("data/results", "is inside the repository's data/"),
                                          ("paper_figures", "is the repository's paper_figures/"),
                                          ("paper_figures/output/new", "is inside the repository's paper_figures/"),
                                          (".", "holds the repository's data/"), ("/", "holds the repository's data/")])
def test_fresh_refuses_an_empty_path_and_the_committed_directories(capsys, monkeypatch, fresh, named):
    monkeypatch.chdir(REPO)
    committed = {**_tree(DATA), **_tree(reproduce.SCRIPTS)}
    assert named in _refused(["--fresh", fresh], capsys)
    assert {**_tree(DATA), **_tree(reproduce.SCRIPTS)} == committed


def test_fresh_follows_a_symbolic_link_to_the_committed_results(tmp_path, capsys):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "results").symlink_to(DATA / "results")
    committed = _tree(DATA)
    line = _refused(["--fresh", str(tmp_path / "out")], capsys)
    assert f": {tmp_path / 'out' / 'results'} is inside the repository's data/" in line
    assert _tree(DATA) == committed


@pytest.mark.parametrize("foreign, named", [("notes.txt", "notes.txt"), ("figures/notes.txt", "figures/notes.txt"),
                                            ("results/notes.npz", "results/notes.npz"),
                                            ("results/fig5.csv", "results/fig5.csv"),
                                            ("figures/old/fig5.png", "figures/old"), ("log/a.png", "log")])
def test_fresh_refuses_a_directory_holding_what_glamas_did_not_write(tmp_path, capsys, foreign, named):
    out = tmp_path / "a b"
    for name in ("figures/fig5.png", "results/single_gla.npz", foreign):
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        (out / name).write_text(name)
    before = _tree(tmp_path)
    line = _refused(["--fresh", str(out)], capsys)
    assert f"holds {out / named}, which glamas did not write; nothing was deleted" in line
    assert _tree(tmp_path) == before


def test_fresh_empties_what_glamas_wrote_and_keeps_the_directories(tmp_path):
    out = tmp_path / "out"
    written = ["figures/fig5.png", "figures/fig5.pdf", "figures/fig5.png.k2x9.tmp", "results/single_gla.npz",
               "results/scaling.npz", "results/single_gla.npz.a1b2c3.tmp"]
    for name in written:
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        (out / name).write_text(name)
    assert reproduce.fresh_directories(str(out)) == (out / "figures", out / "results")
    assert sorted(path.relative_to(out).as_posix() for path in out.rglob("*")) == ["figures", "results"]


def test_fresh_takes_the_place_of_out_and_results(tmp_path, capsys):
    with pytest.raises(SystemExit) as stopped:
        reproduce.main(["--fresh", str(tmp_path), "--out", str(tmp_path)])
    assert stopped.value.code == 2 and "error: --fresh DIR chooses --out and --results" in capsys.readouterr().err


def test_the_result_files_fresh_may_empty_are_the_experiments(tmp_path):
    assert {path.name for path in RESULTS.glob("*.npz")} == set(registry.result_files())


def test_fresh_refuses_a_file(tmp_path, capsys):
    (tmp_path / "out").write_text("kept")
    assert "exists and is not a directory; nothing was deleted" in _refused(["--fresh", str(tmp_path / "out")], capsys)
    assert (tmp_path / "out").read_text() == "kept"


def test_fresh_draws_into_the_emptied_directories(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(registry, "figure_scripts", lambda chapter_only: ("fig9",))  # nothing to compute
    old = tmp_path / "a b" / "results" / "single_gla.npz"
    old.parent.mkdir(parents=True)
    old.write_text("an earlier run's")
    assert reproduce.main(["--fresh", str(tmp_path / "a b")]) == 0
    assert parallel.memo.MEMO_BYTES == 0  # the reuse of runs it turned on is off again for its caller
    assert (tmp_path / "a b" / "figures" / "fig9.png").read_bytes() == (FIGURES / "fig9.png").read_bytes()
    assert not any((tmp_path / "a b" / "results").iterdir())
