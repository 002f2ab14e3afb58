"""`make reproduce` and `make verify` delete nothing they did not make: the real make targets, run
in a copy of the repository's layout, refuse an empty OUT=, the committed data/ and
paper_figures/, and a directory holding a file glamas did not write, with one line and deleting
nothing; OUT reaches glamas as one argument, spaces and quotes included.

The copy's .venv/bin/python runs this test's interpreter, so make finds its environment ready;
every case is refused before anything is computed."""

import os
import shutil
import subprocess
import sys

import pytest

from glamas.paths import REPO

pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="needs GNU make")
LAYOUT = ("Makefile", "requirements.txt", "requirements-extras.txt", "pyproject.toml", "lib", "data",
          "paper_figures")
"""What of the repository the targets need: the Makefile, its prerequisites, the package and the
committed files."""


@pytest.fixture(scope="module")
def clone(tmp_path_factory):
    """A copy of :data:`LAYOUT` whose ``.venv`` make takes as installed."""
    root = tmp_path_factory.mktemp("clone")
    for name in LAYOUT:
        source = REPO / name
        if source.is_dir():
            shutil.copytree(source, root / name, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(source, root / name)
    python = root / ".venv" / "bin" / "python"
    python.parent.mkdir(parents=True)
    python.write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    python.chmod(0o755)
    (root / ".venv" / ".installed").touch()  # newer than the requirements it was copied after
    return root


def _tree(directory):
    """Every file under ``directory`` (compiled caches aside) with its bytes."""
    return {path: path.read_bytes() for path in sorted(directory.rglob("*"))
            if path.is_file() and "__pycache__" not in path.parts}


def _make(clone, *arguments):
    """``make ARGUMENTS`` in ``clone`` with the copy's package on the path: (status, stderr lines
    that are not make's own)."""
    env = dict(os.environ, PYTHONPATH=f"{clone / 'lib'}{os.pathsep}{clone}", PYTHONDONTWRITEBYTECODE="1")
    done = subprocess.run(["make", *arguments], cwd=clone, env=env, capture_output=True, text=True, timeout=300)
    ours = [line for line in done.stderr.splitlines() if not line.startswith("make")]
    return done.returncode, ours


@pytest.mark.parametrize("arguments, named", [
    (("reproduce", "OUT=data"), "--fresh data is the repository's data/"),
    (("reproduce", "OUT="), "--fresh is empty"),
    (("reproduce", "OUT=."), "--fresh . holds the repository's data/"),
    (("verify", "VERIFY=paper_figures"), "--fresh paper_figures is the repository's paper_figures/"),
])
def test_make_refuses_the_committed_directories_and_an_empty_path(clone, arguments, named):
    before = _tree(clone)
    status, errors = _make(clone, *arguments)
    assert status == 2 and len(errors) == 1
    assert errors[0].startswith(f"error: {named}") and "nothing was deleted" in errors[0]
    assert _tree(clone) == before


@pytest.mark.parametrize("out", ["a b", "it's here"])
def test_make_refuses_a_directory_holding_a_foreign_file_and_leaves_its_neighbours(clone, out):
    for name in (f"{out}/notes.txt", f"{out}/results/single_gla.npz", "a/kept.txt", "it/kept.txt"):
        (clone / name).parent.mkdir(parents=True, exist_ok=True)
        (clone / name).write_text(name)
    before = _tree(clone)
    status, errors = _make(clone, "reproduce", f"OUT={out}")
    assert status == 2 and errors == [f"error: --fresh {out} holds {out}/notes.txt, which glamas did not write; "
                                      "nothing was deleted: move it away or give another directory"]
    assert _tree(clone) == before
