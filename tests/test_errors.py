"""One error handling for every command (glamas.errors): a user error is one line ``error: ...`` on
stderr and exit status 2 without a traceback; anything else keeps its traceback and is named a bug.
A message about a committed file names the figure script that recomputes it, or git checkout.

The commands run in a copy of the repository's layout when they must find a committed file
damaged, missing or edited; nothing of the repository itself is touched."""

import ast
import os
import shutil
import struct
import subprocess
import sys
import zipfile

import pytest

from glamas import committed, errors
from glamas.paths import REPO
from glamas.experiments import registry

LAYOUT = ("lib", "data", "paper_figures", "docs", "README.md")
"""What of the repository the commands read: the package, the committed files, the ledger's pages."""
TIME_LIMIT = 120


@pytest.fixture
def clone(tmp_path):
    """A copy of :data:`LAYOUT` (without compiled caches) whose package the commands import."""
    for name in LAYOUT:
        source = REPO / name
        if source.is_dir():
            shutil.copytree(source, tmp_path / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(source, tmp_path / name)
    return tmp_path


def _command(clone, *arguments) -> subprocess.CompletedProcess:
    """``python ARGUMENTS`` in ``clone``, importing the copy's package."""
    env = dict(os.environ, PYTHONPATH=str(clone / "lib"))
    return subprocess.run([sys.executable, *arguments], cwd=clone, env=env, capture_output=True, text=True,
                          timeout=TIME_LIMIT)


def _one_error_line(done: subprocess.CompletedProcess) -> str:
    """The one line ``error: ...`` of a command that exited with status 2, without a traceback."""
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), done.stderr
    return lines[0]


# --- the handler ---------------------------------------------------------------------------------

@pytest.mark.parametrize("error, line", [
    (errors.UserError("bad\ninput"), "error: bad input"),
    (FileNotFoundError(2, "No such file or directory", "x.npz"), "error: No such file or directory: x.npz"),
])
def test_a_user_error_or_a_file_error_is_one_line_and_status_2(capsys, error, line):
    def main():
        raise error

    with pytest.raises(SystemExit) as stopped:
        errors.run(main)
    assert stopped.value.code == errors.EXIT_USER_ERROR
    assert capsys.readouterr().err == line + "\n"


def test_any_other_error_keeps_its_traceback_and_is_named_a_bug(capsys):
    def main():
        raise ValueError("not a UserError: a bug")

    with pytest.raises(SystemExit) as stopped:
        errors.run(main)
    assert stopped.value.code == errors.EXIT_BUG
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "Traceback (most recent call last):" and "ValueError: not a UserError: a bug" in err
    assert err[-1].startswith("this is a bug in glamas, not in your input: please report it") and "command:" in err[-1]


def test_a_command_exits_with_the_status_its_main_returns():
    with pytest.raises(SystemExit) as stopped:
        errors.run(lambda: 1)
    assert stopped.value.code == 1


def _main_blocks():
    """Every module of the package, the figure scripts and the benchmarks that runs as a command,
    with the statements of its ``if __name__ == "__main__":`` block."""
    files = [*(REPO / "lib" / "glamas").rglob("*.py"), *(REPO / "paper_figures").glob("*.py"),
             *(REPO / "benchmarks").glob("*.py")]
    for path in files:
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, ast.If) and ast.unparse(node.test) == "__name__ == '__main__'":
                yield path, [ast.unparse(statement) for statement in node.body]


OUTSIDE_GLAMAS = {"pogema_replay.py": ["sys.exit(main())"]}
"""Commands that run in another virtual environment and import nothing of glamas (POGEMA's), with
their own one-line errors and exit status 2."""


def test_every_command_reports_its_errors_through_glamas_errors():
    blocks = dict(_main_blocks())
    assert {"reproduce.py", "verify.py", "ledger.py", "fig11a.py", "bench_gla.py"} <= {path.name for path in blocks}
    assert {path.name: body for path, body in blocks.items()
            if body != ["errors.run(main)"] and OUTSIDE_GLAMAS.get(path.name) != body} == {}
    for name in OUTSIDE_GLAMAS:
        tree = ast.parse((REPO / "benchmarks" / name).read_text())
        imported = {alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import)
                    for alias in node.names}
        imported |= {node.module.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
        assert not imported & {"glamas", "benchmarks"}, name


def test_bad_input_is_a_user_error_not_a_bare_value_error():
    """Every ``raise ValueError`` of the package is a UserError."""
    raised = [f"{path.relative_to(REPO)}:{node.lineno}" for path in (REPO / "lib" / "glamas").rglob("*.py")
              for node in ast.walk(ast.parse(path.read_text()))
              if isinstance(node, ast.Raise) and node.exc is not None and "ValueError(" in ast.unparse(node.exc)]
    assert raised == []


# --- the ledger and verify -------------------------------------------------------------------------

def test_ledger_refuses_a_readme_without_its_markers_before_any_work(clone):
    readme = clone / "README.md"
    readme.write_text(readme.read_text().replace("<!-- verdicts:end -->", ""))
    for mode in ("--check", "--write"):
        line = _one_error_line(_command(clone, "-m", "glamas.ledger", mode))
        assert "README.md must hold one <!-- verdicts:start --> ... <!-- verdicts:end --> pair" in line
    assert (clone / "docs" / "ledger.md").read_text() == (REPO / "docs" / "ledger.md").read_text()


def test_ledger_names_the_script_of_a_damaged_committed_result_and_git_checkout(clone):
    damaged = clone / "data" / "results" / "gridworld.npz"
    damaged.write_bytes(damaged.read_bytes()[:5000])
    line = _one_error_line(_command(clone, "-m", "glamas.ledger", "--check"))
    assert "gridworld.npz is not a readable glamas result file" in line
    assert line.endswith("recompute it with `.venv/bin/python paper_figures/fig11a.py --rerun`, or restore the committed "
                         "one with `git checkout -- data/results/gridworld.npz`")


def test_ledger_names_the_script_of_a_missing_committed_result(clone):
    (clone / "data" / "results" / "state_encoding.npz").unlink()
    line = _one_error_line(_command(clone, "-m", "glamas.ledger"))
    assert "no result file at" in line and "`.venv/bin/python paper_figures/fig6.py --rerun`" in line


def test_verify_usage_errors_are_one_line_on_stderr():
    done = subprocess.run([sys.executable, "-m", "glamas.verify"], capture_output=True, text=True, timeout=TIME_LIMIT)
    assert done.returncode == 2 and done.stdout == "" and "Traceback" not in done.stderr
    assert [line for line in done.stderr.splitlines() if "error: " in line] == [
        "python -m glamas.verify: error: the following arguments are required: DIR"]


# --- the advice about committed files --------------------------------------------------------------

def test_every_committed_result_has_a_script_that_computes_it():
    registry.experiments()  # each experiment tells glamas.committed its scripts as it registers
    for path in sorted((REPO / "data" / "results").glob("*.npz")):
        script = committed.computing_script(path.name)
        assert committed.RUNS_ITS_EXPERIMENT in (REPO / "paper_figures" / f"{script}.py").read_text()
    assert committed.computing_script("gridworld.npz") == "fig11a"  # fig9 and fig10 draw its map and table


def test_advice_is_for_committed_files_only(tmp_path):
    registry.experiments()
    assert committed.advice(tmp_path / "gridworld.npz") is None
    assert committed.advice(REPO / "data" / "results" / "scaling.npz", "--force").startswith(
        "give the run another --results directory (for example `.venv/bin/python paper_figures/scaling_performance.py "
        "--results out/results` at the paper scale), or restore the committed one")
    assert committed.advice(REPO / "data" / "results" / "scaling.npz").startswith(
        "recompute it with `.venv/bin/python paper_figures/scaling_performance.py --rerun`")
    assert committed.advice(REPO / "paper_figures" / "output" / "fig9.png") == (
        "draw it again with `.venv/bin/python paper_figures/fig9.py`, or restore the committed one with "
        "`git checkout -- paper_figures/output/fig9.png`")


# --- damaged results and make figures ---------------------------------------------------------------

FAST = ("--runs", "2", "--iterations", "100", "--backend", "threads", "--workers", "1")


def _damage_member(path, member: str) -> None:
    """Flip a byte in the middle of the compressed data of ``member`` of the archive ``path``: its
    header (configuration, provenance) stays readable, the member fails its checksum."""
    data = bytearray(path.read_bytes())
    with zipfile.ZipFile(path) as archive:
        info = archive.getinfo(member)
    name_length, extra_length = struct.unpack("<HH", data[info.header_offset + 26:info.header_offset + 30])
    data[info.header_offset + 30 + name_length + extra_length + info.compress_size // 2] ^= 0xFF
    path.write_bytes(bytes(data))


def test_a_damaged_result_is_named_and_kept_unless_rerun_replaces_it(tmp_path):
    script = str(REPO / "paper_figures" / "fig7b.py")
    where = ("--out", str(tmp_path), "--results", str(tmp_path))
    assert subprocess.run([sys.executable, script, *FAST, *where], capture_output=True, timeout=TIME_LIMIT).returncode == 0
    stored = tmp_path / "and_network.npz"
    _damage_member(stored, "params.npy")
    damaged = stored.read_bytes()
    for figure in ("fig7b.png", "fig7b.pdf"):
        (tmp_path / figure).unlink()
    done = subprocess.run([sys.executable, script, *FAST, *where], capture_output=True, text=True, timeout=TIME_LIMIT)
    line = _one_error_line(done)
    assert f"{stored} is not a readable glamas result file" in line and "--rerun or --force to replace it" in line
    assert stored.read_bytes() == damaged and not (tmp_path / "fig7b.png").exists()
    rerun = subprocess.run([sys.executable, script, *FAST, *where, "--rerun"], capture_output=True, text=True,
                           timeout=TIME_LIMIT)
    assert rerun.returncode == 0, rerun.stderr
    assert stored.read_bytes() != damaged and (tmp_path / "fig7b.png").exists()


def test_make_figures_computes_nothing_and_names_the_script_of_a_missing_result(clone):
    (clone / "data" / "results" / "single_gla.npz").unlink()
    before = sorted(path.name for path in (clone / "data" / "results").iterdir())
    done = _command(clone, "-m", "glamas.reproduce", "--all")
    assert _one_error_line(done) == (
        f"error: no result file at {clone / 'data' / 'results' / 'single_gla.npz'}; recompute it with "
        "`.venv/bin/python paper_figures/fig5.py --rerun`, or restore the committed one with "
        "`git checkout -- data/results/single_gla.npz`")
    assert sorted(path.name for path in (clone / "data" / "results").iterdir()) == before


def test_no_compute_refuses_to_be_combined_with_rerun_or_force():
    for flag in ("--rerun", "--force"):
        done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig5.py"), "--no-compute", flag],
                              capture_output=True, text=True, timeout=TIME_LIMIT)
        assert done.returncode == 2 and "--no-compute never runs the experiment" in done.stderr
