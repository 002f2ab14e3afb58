"""The committed figures and results are what the code makes.

Every figure script redraws its figures from the committed results into a temporary directory
(all in one process, as ``make figures`` runs them), byte for byte equal to
``paper_figures/output``; the fast experiments (Fig. 5, 6 and 7) are recomputed at paper scale
(--rerun) and their arrays compared with ``data/results``. The slow ones
(the gridworld, the Fig. 10 readings, related work, scaling, and the Fig. 7 sweep) are recomputed
by ``make verify``.
"""

import subprocess
import sys

import numpy as np
import pytest

from glamas.paths import REPO, RESULTS

OUTPUT = REPO / "paper_figures" / "output"
RECOMPUTED = {"fig5": "single_gla", "fig6": "state_encoding", "fig7a": "and_network"}
"""Fast scripts recomputed at paper scale: script -> the result file it writes."""


def _script(name: str, *args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(REPO / "paper_figures" / f"{name}.py"), *map(str, args)],
                          capture_output=True, text=True, timeout=300)


def _same_figures(directory) -> list[str]:
    """Names of the figures in ``directory`` whose bytes differ from the committed ones."""
    drawn = sorted(directory.glob("*.png")) + sorted(directory.glob("*.pdf"))
    assert drawn, f"no figure was drawn in {directory}"
    return [path.name for path in drawn if path.read_bytes() != (OUTPUT / path.name).read_bytes()]


def test_every_figure_redraws_to_the_committed_bytes(tmp_path):
    # as `make figures` draws them: every script, one after the other in one process
    done = subprocess.run([sys.executable, "-m", "glamas.reproduce", "--all", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-500:]
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(path.name for path in OUTPUT.iterdir())
    assert _same_figures(tmp_path) == [], "figures that differ from paper_figures/output"


@pytest.mark.parametrize("script", sorted(RECOMPUTED))
def test_fast_experiments_recompute_to_the_committed_results(tmp_path, script):
    done = _script(script, "--out", tmp_path, "--results", tmp_path, "--rerun")
    assert done.returncode == 0, done.stderr[-500:]
    name = RECOMPUTED[script]
    with np.load(tmp_path / f"{name}.npz") as fresh, np.load(RESULTS / f"{name}.npz") as committed:
        arrays = [key for key in committed.files if key != "__provenance__"]
        assert sorted(arrays) == sorted(key for key in fresh.files if key != "__provenance__")
        assert [key for key in arrays if not np.array_equal(fresh[key], committed[key])] == []
    assert _same_figures(tmp_path) == []
