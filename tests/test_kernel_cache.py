"""numba's kernel cache never serves a kernel of older sources (glamas.sources): an edit to a
function that a cached kernel calls in another file gives a fresh kernel; where glamas cannot write
the cache numba would choose (NUMBA_CACHE_DIR or a __pycache__ that cannot be written), caching is
off for the run with one warning line, numba falls back to no other cache, and importing glamas
gives no traceback, in the worker processes too.

Each case runs in subprocesses on a copy of the package with two probe modules: ``probe_a.probe``
calls ``probe_b.value``, which the test edits. The user-wide cache numba would fall back to is a
directory of the test (XDG_CACHE_HOME). A directory that cannot be written is one below a regular
file (no permission stops root); the read-only variants run for other users."""

import os
import shutil
import subprocess
import sys

import pytest

from glamas import sources
from glamas.paths import REPO

PROBE_B = "from numba import njit\n\n\n@njit(cache=True)\ndef value():\n    return {value}\n"
PROBE_A = """import numpy as np
from numba import njit

from glamas.probe_b import value


@njit(cache=True)
def probe():
    return value()


@njit(cache=True, nogil=True)
def fill(out, state):
    out[0] = value()
"""
PRINT_PROBE = "from glamas.probe_a import probe; print(probe())"
PRINT_FILLED = ("import numpy as np; from glamas import parallel; from glamas.probe_a import fill; "
                "out = np.zeros((4, 1)); parallel.run_batches(fill, (), (out,), 0, workers=parallel.Processes(2), "
                "chunk=1); print(out.ravel().tolist())")
as_root = pytest.mark.skipif(os.geteuid() == 0, reason="permissions do not stop root")


@pytest.fixture
def root(tmp_path):
    """A copy of the package, with the probes, in ``tmp_path / 'lib'``."""
    package = tmp_path / "lib" / "glamas"
    shutil.copytree(REPO / "lib" / "glamas", package, ignore=shutil.ignore_patterns("__pycache__"))
    (package / "probe_a.py").write_text(PROBE_A)
    _set_value(tmp_path, 1)
    return tmp_path


def _set_value(root, value: int) -> None:
    (root / "lib" / "glamas" / "probe_b.py").write_text(PROBE_B.format(value=value))


def _run(root, code: str = PRINT_PROBE, numba_cache_dir=None) -> tuple:
    """``python -c code`` on the copy: (what it printed, its stderr lines); it must succeed."""
    env = dict(os.environ, PYTHONPATH=str(root / "lib"), XDG_CACHE_HOME=str(root / "user-cache"))
    env.pop("NUMBA_CACHE_DIR", None)
    env.pop(sources.CACHE_OFF_VARIABLE, None)
    if numba_cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = str(numba_cache_dir)
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    return done.stdout.strip(), done.stderr.splitlines()


def _cached(root) -> list:
    """Every numba cache file under ``root``: the copy's __pycache__, the user-wide cache, any other."""
    return sorted(path for path in root.rglob("*") if path.suffix in (".nbi", ".nbc"))


def _off(stderr: list) -> bool:
    """Whether stderr is the one warning that caching is off."""
    return len(stderr) == 1 and stderr[0].startswith("warning: numba's kernel cache is off for this run")


def _unwritable(root):
    """A directory path that no one can create: below a regular file."""
    (root / "a-file").write_text("")
    return root / "a-file" / "numba-cache"


def test_an_edit_to_a_function_a_cached_kernel_calls_gives_a_fresh_kernel(root):
    assert _run(root) == ("1", [])
    assert _cached(root) and all("__pycache__" in path.parts for path in _cached(root))
    assert _run(root) == ("1", [])  # from the cache
    _set_value(root, 2)
    assert _run(root) == ("2", [])


def test_a_numba_cache_dir_that_cannot_be_written_turns_caching_off(root):
    cache = _unwritable(root)
    printed, stderr = _run(root, numba_cache_dir=cache)
    assert printed == "1" and _off(stderr) and str(root / "a-file") in stderr[0]
    _set_value(root, 2)
    printed, stderr = _run(root, numba_cache_dir=cache)
    assert printed == "2" and _off(stderr)
    assert _cached(root) == []  # numba fell back to neither the __pycache__ nor the user-wide cache


def test_a_pycache_that_cannot_be_written_turns_caching_off_without_a_traceback(root):
    (root / "lib" / "glamas" / "__pycache__").write_text("")  # a file where the directory would be
    printed, stderr = _run(root)
    assert printed == "1" and _off(stderr) and "__pycache__" in stderr[0]
    _set_value(root, 2)
    assert _run(root)[0] == "2" and _cached(root) == []


def test_worker_processes_turn_caching_off_too_and_say_nothing_more(root):
    printed, stderr = _run(root, PRINT_FILLED, numba_cache_dir=_unwritable(root))
    assert printed == "[1.0, 1.0, 1.0, 1.0]" and _off(stderr)
    assert _cached(root) == []


@as_root
def test_a_read_only_numba_cache_dir_turns_caching_off(root):
    cache = root / "numba-cache"
    cache.mkdir(mode=0o555)
    printed, stderr = _run(root, numba_cache_dir=cache)
    assert printed == "1" and _off(stderr)
    assert _cached(root) == []


@as_root
def test_a_read_only_pycache_with_an_old_stamp_gives_a_fresh_kernel_without_a_traceback(root):
    assert _run(root) == ("1", [])  # caches the kernels and writes the stamp
    pycache = root / "lib" / "glamas" / "__pycache__"
    pycache.chmod(0o555)
    try:
        _set_value(root, 2)
        printed, stderr = _run(root)
        assert printed == "2" and _off(stderr)
    finally:
        pycache.chmod(0o755)


def test_cache_locators_chosen_by_the_user_turn_caching_off(tmp_path, monkeypatch, capsys):
    from numba.core import config
    from numba.core.dispatcher import Dispatcher

    monkeypatch.setattr(Dispatcher, "enable_caching", Dispatcher.enable_caching)  # restored after the test
    monkeypatch.delenv(sources.CACHE_OFF_VARIABLE, raising=False)
    monkeypatch.setenv("NUMBA_CACHE_LOCATOR_CLASSES", "UserWideCacheLocator")
    (tmp_path / "kernel.py").write_text("x = 1\n")
    try:
        assert not sources.prepare_kernel_cache(tmp_path)
    finally:
        monkeypatch.undo()
        config.reload_config()  # numba's own view of the environment, as before
        os.environ.pop(sources.CACHE_OFF_VARIABLE, None)
    stderr = capsys.readouterr().err.splitlines()
    assert _off(stderr) and "NUMBA_CACHE_LOCATOR_CLASSES=UserWideCacheLocator" in stderr[0]


def test_a_module_a_kernel_imports_is_a_kernel_source_and_a_figure_module_is_not():
    names = {path.relative_to(sources.PACKAGE).as_posix() for path in sources.kernel_source_files()}
    # modules with kernels, and gla.py and rng.py whose functions the kernels call
    assert {"gridworld/rules.py", "learners/two_observe.py", "gla.py", "rng.py"} <= names
    assert not {"plotting.py", "figures.py", "cli.py", "verify.py"} & names


def test_the_first_run_notice_asks_numba_s_cache_whether_a_kernel_compiles(tmp_path):
    """sources.uncached, which decides the one-line notice that a run's first jobs compile, reads
    the cache numba uses (under NUMBA_CACHE_DIR too): a kernel compiled once, in this process or
    another, no longer compiles."""
    (tmp_path / "kernel_module.py").write_text("from numba import njit\n\n\n@njit(cache=True)\n"
                                               "def add_one(x):\n    return x + 1\n")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(tmp_path)}
    code = ("from glamas import sources; import kernel_module as m; print(sources.uncached(m.add_one)); "
            "m.add_one(1); print(sources.uncached(m.add_one))")

    def ask():
        return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True).stdout.split()

    assert ask() == ["True", "False"]
    assert ask() == ["False", "False"]
