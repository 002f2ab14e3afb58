"""Bad input and faults, one line each (exit status 2, no traceback, nothing committed changed):
the fifth round's cases. Shared records written by commands running at once, the committed
figures and a reduced run, a damaged digests file, a learner module that exits on import, and
what an interrupt, a full disk or a foreign file says."""

import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from glamas import atomic, errors, small_runs
from glamas.errors import UserError
from glamas.paths import REPO, RESULTS

SCRIPTS = REPO / "paper_figures"


def _run(*arguments, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, *map(str, arguments)], cwd=REPO, capture_output=True, text=True,
                          timeout=120, **kwargs)


def _error_line(*arguments, **kwargs) -> str:
    """The one line ``error: ...`` (or argparse's ``SCRIPT: error: ...``) of a command that exits with 2."""
    before = {path.name: path.stat().st_mtime_ns for path in RESULTS.glob("*.npz")}
    done = _run(*arguments, **kwargs)
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert {path.name: path.stat().st_mtime_ns for path in RESULTS.glob("*.npz")} == before
    return done.stderr.strip().splitlines()[-1]


# --- shared records written at once ---------------------------------------------------------------

ADOPTING = """
import sys, time
from pathlib import Path
from glamas import small_runs
copy = Path(sys.argv[1])
small_runs.DIGESTS, small_runs.RESULTS = copy / "small_runs.json", copy / "results"
# a re-recording of a harmless change of code, its small run's seconds kept, the result file left alone
small_runs.status = lambda name: ("re-record", "")
small_runs.small_digest = lambda name, workers=None: time.sleep(2) or small_runs.committed()[name]
small_runs._rerecord = lambda name: None
small_runs.current_code = lambda name: {"lineworld.py": "edited"}
sys.exit(small_runs.main(["--adopt", sys.argv[2]]))
"""


def test_two_re_recordings_at_once_both_keep_their_record(tmp_path):
    shutil.copy(small_runs.DIGESTS, tmp_path / "small_runs.json")
    names = ("single_gla", "state_encoding")
    running = [subprocess.Popen([sys.executable, "-c", ADOPTING, tmp_path, name], stdout=subprocess.PIPE, text=True)
               for name in names]
    outputs = [process.communicate(timeout=60)[0] for process in running]
    assert [process.returncode for process in running] == [0, 0], outputs
    code = json.loads((tmp_path / "small_runs.json").read_text())["code"]
    assert [code[name] for name in names] == [{"lineworld.py": "edited"}] * 2
    assert not list(tmp_path.glob("*.tmp"))


# --- a damaged digests file -------------------------------------------------------------------------

@pytest.mark.parametrize("damage, named", [
    (lambda text: text[:len(text) // 2], "not JSON, cut short or edited"),
    (lambda text: "[]", "a JSON list where an object belongs"),
    (lambda text: '{"digests": []}', "its digests or records of code are missing"),
])
def test_a_damaged_digests_file_is_one_line_naming_it_and_how_to_rewrite_it(tmp_path, monkeypatch, damage, named):
    damaged = tmp_path / "small_runs.json"
    damaged.write_text(damage(small_runs.DIGESTS.read_text()))
    monkeypatch.setattr(small_runs, "DIGESTS", damaged)
    with pytest.raises(UserError) as raised:
        small_runs.main(["--adopt", "single_gla"])
    assert str(raised.value).startswith(f"{damaged} is damaged ({named}") and str(raised.value).endswith(
        f"`git checkout -- {damaged}`, or rewrite it with `.venv/bin/python -m glamas.small_runs --write` "
        f"(about {small_runs.WRITE_MINUTES} min on 2 cores)")


def test_the_damaged_committed_digests_file_stops_adopt_with_one_line(tmp_path):
    copy = tmp_path / "small_runs.json"
    copy.write_text("[]")
    script = (f"import sys\nfrom pathlib import Path\nfrom glamas import errors, small_runs\n"
              f"small_runs.DIGESTS = Path({str(copy)!r})\nerrors.run(lambda: small_runs.main(['--adopt']))\n")
    line = _error_line("-c", script)
    assert line.startswith(f"error: {copy} is damaged (a JSON list where an object belongs)")


def test_write_replaces_a_damaged_digests_file(tmp_path, monkeypatch):
    damaged = tmp_path / "small_runs.json"
    damaged.write_text('{"digests": {"single_gla": "ab')
    monkeypatch.setattr(small_runs, "DIGESTS", damaged)
    monkeypatch.setattr(small_runs, "RESULTS", tmp_path / "results")
    small_runs.write({"single_gla": "cd"})
    assert small_runs.committed() == {"single_gla": "cd"} and "lineworld.py" in small_runs.committed_code()["single_gla"]



def test_write_says_which_small_run_it_computes(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(small_runs, "DIGESTS", tmp_path / "small_runs.json")
    monkeypatch.setattr(small_runs, "RESULTS", tmp_path / "results")
    monkeypatch.setattr(small_runs, "small_digest", lambda name, workers=None: name)
    assert small_runs.main(["--write"]) == 0
    names = list(small_runs.sizes())
    assert capsys.readouterr().err.splitlines() == [f"small run {number} of {len(names)}: {name}"
                                                    for number, name in enumerate(names, 1)]
    assert small_runs.committed() == {name: name for name in names}

# --- the committed figures and a run off the paper scale --------------------------------------------

@pytest.mark.parametrize("spelling", ["paper_figures/output", "./paper_figures//output/", "paper_figures/../paper_figures/output",
                                      "link"])
def test_a_reduced_run_into_the_committed_figures_is_refused_naming_its_scratch_folder(tmp_path, spelling):
    (tmp_path / "link").symlink_to(SCRIPTS / "output")
    out = tmp_path / "link" if spelling == "link" else spelling
    figures = {path.name: path.read_bytes() for path in (SCRIPTS / "output").glob("fig11a.*")}
    line = _error_line(SCRIPTS / "fig11a.py", "--runs", 1, "--episodes", 20, "--learners", "independent",
                       "--out", out, "--results", tmp_path / "results")
    assert line.startswith("error: --out ") and line.endswith(
        "is the directory of the committed figures, which only a run at the paper-scale settings writes; this run's "
        "figures go to out/figures/runs=1,iterations=20,learners=independent (leave out --out)")
    assert {path.name: path.read_bytes() for path in (SCRIPTS / "output").glob("fig11a.*")} == figures
    assert not (tmp_path / "results").exists()


# --- a learner module of one's own that exits on import ---------------------------------------------

@pytest.mark.parametrize("ending", ["raise SystemExit(0)", "import sys; sys.exit(3)", "raise KeyboardInterrupt"])
def test_a_learner_module_that_exits_on_import_is_a_failing_import_named(tmp_path, ending):
    (tmp_path / "mine.py").write_text(f"{ending}\n")
    done = _run(SCRIPTS / "fig11a.py", "--runs", 1, "--episodes", 20, "--learners", "independent,mine",
                "--out", tmp_path, "--results", tmp_path,
                env={**os.environ, "GLAMAS_LEARNERS": "mine", "PYTHONPATH": str(tmp_path)})
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    warning = done.stderr.splitlines()[0]
    assert warning.startswith("warning: GLAMAS_LEARNERS names the module 'mine', which fails on import (")
    assert "learners must be distinct names of registered learners" in done.stderr.splitlines()[-1]


# --- an interrupted run -------------------------------------------------------------------------------

def _children(pid: int) -> set:
    return {int(child) for task in Path(f"/proc/{pid}/task").iterdir()
            for child in (task / "children").read_text().split()}


def _wait_for_workers(pid: int) -> None:
    """Until process ``pid`` has started its worker processes (a Ctrl-C while they start is lost)."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and sum(b"popen_loky" in Path(f"/proc/{child}/cmdline").read_bytes()
                                              for child in _children(pid) if _alive(child)) < 2:
        time.sleep(0.1)
    time.sleep(0.5)


def _alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.parametrize("signum, status, line", [(signal.SIGINT, 130, "interrupted; nothing was written"),
                                                  (signal.SIGTERM, 143, "stopped (SIGTERM); nothing was written")])
def test_an_interrupted_run_says_so_in_one_line_and_its_workers_stop_with_it(tmp_path, signum, status, line):
    """Ctrl-C reaches every process of the terminal's group; SIGTERM the main process alone."""
    command = [SCRIPTS / "fig11a.py", "--runs", 100, "--episodes", 3000, "--workers", 2, "--out", tmp_path,
               "--results", tmp_path]
    running = subprocess.Popen([sys.executable, *map(str, command)], cwd=REPO, stderr=subprocess.PIPE,
                               start_new_session=True)
    stderr = []
    threading.Thread(target=lambda: stderr.extend(iter(lambda: running.stderr.read(1), b"")), daemon=True).start()
    _wait_for_workers(running.pid)
    workers = _children(running.pid)
    (os.killpg if signum == signal.SIGINT else os.kill)(running.pid, signum)
    assert running.wait(timeout=20) == status
    time.sleep(1)
    text = b"".join(stderr).decode()
    assert "Traceback" not in text and text.strip().splitlines()[-1] == line, text
    assert not [pid for pid in workers if _alive(pid)] and not list(tmp_path.iterdir())


def test_an_interrupted_write_of_the_small_runs_says_so_in_one_line_and_keeps_the_file(tmp_path):
    shutil.copy(small_runs.DIGESTS, tmp_path / "small_runs.json")
    script = (f"from pathlib import Path\nfrom glamas import errors, small_runs\n"
              f"small_runs.DIGESTS, small_runs.RESULTS = Path({str(tmp_path)!r}) / 'small_runs.json', Path({str(tmp_path)!r})\n"
              "errors.run(lambda: small_runs.main(['--write']))\n")
    running = subprocess.Popen([sys.executable, "-c", script], cwd=REPO, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    assert running.stderr.readline().startswith("small run 1 of ")
    # as a user does: Ctrl-C to the whole group, again if one landed while worker processes started
    # (they ignore it then), until the command ends; the small runs may run in this process alone
    # (one core), with no workers at all
    for _ in range(40):
        os.killpg(running.pid, signal.SIGINT)
        try:
            status = running.wait(timeout=0.5)
            break
        except subprocess.TimeoutExpired:
            continue
    assert status == 130
    said = running.stderr.read()
    assert "Traceback" not in said and said.strip().splitlines()[-1] == "interrupted; nothing was written", said
    assert (tmp_path / "small_runs.json").read_text() == small_runs.DIGESTS.read_text()


def test_what_an_interrupted_command_had_written_is_named(tmp_path, monkeypatch):
    monkeypatch.setattr(atomic, "written", [])
    assert errors.interrupted(signal.SIGINT) == "interrupted; nothing was written"
    with atomic.locked(tmp_path):
        atomic.write_text(tmp_path / "a.json", "{}")
    assert errors.interrupted(signal.SIGTERM) == f"stopped (SIGTERM); it had written {tmp_path / 'a.json'}"


# --- a full disk, a file that is not an archive ---------------------------------------------------------

def test_a_full_disk_names_the_file_being_written(tmp_path):
    def full(handle):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(OSError) as raised, atomic.locked(tmp_path):
        atomic.write(tmp_path / "fig5.png", full)
    assert errors.one_line(raised.value) == f"No space left on device: {tmp_path / 'fig5.png'}"
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("content, kind", [
    (b"hello, this is text\n", "a text file beginning 'hello, this is text'"),
    (b"", "an empty file"),
    (b"\x93NUMPY\x01\x00v\x00{'descr': '<f8'", "a single NumPy array (.npy)"),
    (b"\x80\x04\x95\x0b\x00", "pickled Python data"),
    (b"\x00\x01\x02\xff\xfe binary", "binary data of another format"),
])
def test_a_file_named_npz_that_is_no_archive_is_named_with_what_it_is(tmp_path, content, kind):
    (tmp_path / "gridworld.npz").write_bytes(content)
    line = _error_line(SCRIPTS / "fig11a.py", "--out", tmp_path, "--results", tmp_path)
    assert line.startswith(f"error: {tmp_path / 'gridworld.npz'} is not a readable glamas result file (it is {kind}, "
                           "not a NumPy archive of arrays (.npz)); run again with --rerun")
    assert (tmp_path / "gridworld.npz").read_bytes() == content
