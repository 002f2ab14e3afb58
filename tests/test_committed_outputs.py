"""The committed figures and results are what the code makes.

Every experiment's figure scripts redraw its figures from the committed results into a temporary
directory (one process per experiment, as ``make figures`` runs them), each the same figure as its
twin in ``paper_figures/output`` (:func:`glamas.figure_files.compare`: PNG byte for byte, PDF as
structure within its tolerance; on the machine that drew them, byte for byte); drawn twice in two
processes, a figure has the same bytes. The fast experiments (Fig. 5, 6 and 7) are recomputed at
paper scale (--rerun) and their arrays compared with ``data/results``. The slow ones (the
gridworld, the Fig. 10 readings, related work, scaling, and the Fig. 7 sweep) are recomputed by
``make verify``; ``tests/test_portable_results.py`` recomputes a small run of each against
committed digests.
"""

import subprocess
import sys

import numpy as np
import pytest

from glamas import figure_files
from glamas.experiments import registry
from glamas.paths import REPO, RESULTS

OUTPUT = REPO / "paper_figures" / "output"
RECOMPUTED = {"fig5": "single_gla", "fig6": "state_encoding", "fig7a": "and_network"}
"""Fast scripts recomputed at paper scale: script -> the result file it writes."""
DRAWN = [experiment.name for experiment in registry.experiments() if experiment.figures]
"""Every experiment that draws a figure."""


def _script(name: str, *args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(REPO / "paper_figures" / f"{name}.py"), *map(str, args)],
                          capture_output=True, text=True, timeout=300)


def _draw(experiment: str, out) -> None:
    """``experiment``'s figures drawn from the committed results into ``out``, as ``make figures`` does."""
    done = subprocess.run([sys.executable, "-m", "glamas.reproduce", "--experiment", experiment, "--out", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-500:]


def _not_the_same_figure(directory) -> list[str]:
    """The figures in ``directory`` that are not the same figure as their committed twins, with why."""
    drawn = sorted(directory.glob("*.png")) + sorted(directory.glob("*.pdf"))
    assert drawn, f"no figure was drawn in {directory}"
    found = {path.name: figure_files.compare(path.read_bytes(), (OUTPUT / path.name).read_bytes(), path.suffix)
             for path in drawn}
    return [f"{name}: {c.detail}" for name, c in found.items() if not c.equal]


def test_the_committed_figures_are_a_png_and_a_pdf_of_every_script():
    scripts = registry.figure_scripts(chapter_only=False)
    assert sorted(path.name for path in OUTPUT.iterdir()) == sorted(f"{name}.{suffix}" for name in scripts
                                                                   for suffix in ("pdf", "png"))


@pytest.mark.parametrize("experiment", DRAWN)
def test_every_figure_redraws_to_the_committed_figure(tmp_path, experiment):
    _draw(experiment, tmp_path)
    scripts = next(e for e in registry.experiments() if e.name == experiment).figures
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(f"{name}.{suffix}" for name in scripts
                                                                     for suffix in ("pdf", "png"))
    assert _not_the_same_figure(tmp_path) == [], "figures that differ from paper_figures/output"


@pytest.mark.parametrize("experiment", ["benchmark_maps", "scaling"])
def test_a_figure_drawn_twice_in_two_processes_has_the_same_bytes(tmp_path, experiment):
    # log axes of base 10 and 2, a label placed through one (the place that once differed between processors)
    _draw(experiment, tmp_path / "a")
    _draw(experiment, tmp_path / "b")
    for path in sorted((tmp_path / "a").iterdir()):
        assert path.read_bytes() == (tmp_path / "b" / path.name).read_bytes(), path.name


@pytest.mark.parametrize("script", sorted(RECOMPUTED))
def test_fast_experiments_recompute_to_the_committed_results(tmp_path, script):
    done = _script(script, "--out", tmp_path, "--results", tmp_path, "--rerun")
    assert done.returncode == 0, done.stderr[-500:]
    name = RECOMPUTED[script]
    with np.load(tmp_path / f"{name}.npz") as fresh, np.load(RESULTS / f"{name}.npz") as committed:
        arrays = [key for key in committed.files if key != "__provenance__"]
        assert sorted(arrays) == sorted(key for key in fresh.files if key != "__provenance__")
        assert [key for key in arrays if not np.array_equal(fresh[key], committed[key])] == []
    assert _not_the_same_figure(tmp_path) == []
