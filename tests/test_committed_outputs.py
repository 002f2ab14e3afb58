"""The committed figures and results are what the code makes.

Every experiment's figure scripts redraw its figures from the committed results into a temporary
directory (in the test's process, one experiment after another, as ``make figures`` draws them),
each the same figure as its twin in ``paper_figures/output`` (:func:`glamas.figure_files.compare`:
PNG byte for byte, PDF as structure within its tolerance; on the machine that drew them, byte for
byte) and laid out cleanly (:func:`glamas.plotting.layout_faults`); drawn twice in two processes, a
figure has the same bytes (one figure with log axes stands for all: every figure is drawn by the
same code path). Ten of the hundred runs of the fast experiments (Fig. 5, 6 and 7, and Fig. 6 and
7 under their other readings) are recomputed at paper scale and compared with those of
``data/results``; at paper scale the claims read those other readings (and the gridworld's literal
bounce) from there. The slow ones
(the gridworld, the Fig. 10 readings, related work, scaling, and the Fig. 7 sweep) are recomputed
by ``make verify``; ``tests/test_portable_results.py`` recomputes a small run of each against
committed digests.
"""

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from glamas import figure_files, plotting, reproduce
from glamas.experiments import and_network, gridworld, registry, state_encoding
from glamas.paths import REPO, RESULTS

OUTPUT = REPO / "paper_figures" / "output"
DRAWN = [experiment.name for experiment in registry.experiments() if experiment.figures]
"""Every experiment that draws a figure."""


def _draw(experiment: str, out, monkeypatch) -> dict:
    """``experiment``'s figures drawn from the committed results into ``out``, as ``make figures``
    does: in this process, which has drawn other figures before (as ``make figures``'s has).
    Returns each figure's layout faults (:func:`glamas.plotting.layout_faults`), found once it is saved
    (a draw before saving would move its constrained layout)."""
    faults, save = {}, plotting.save_figure

    def saved_then_checked(fig, directory, name):
        paths = save(fig, directory, name)
        faults[name] = plotting.layout_faults(fig)
        return paths

    monkeypatch.setattr(plotting, "save_figure", saved_then_checked)
    assert reproduce.main(["--experiment", experiment, "--out", str(out)]) == 0
    return faults


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
def test_every_figure_redraws_to_the_committed_figure_laid_out_cleanly(tmp_path, experiment, monkeypatch):
    faults = _draw(experiment, tmp_path, monkeypatch)
    scripts = next(e for e in registry.experiments() if e.name == experiment).figures
    assert faults == {name: [] for name in scripts}, "layout faults (tests/test_figure_layout.py shows each kind)"
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(f"{name}.{suffix}" for name in scripts
                                                                       for suffix in ("pdf", "png"))
    assert _not_the_same_figure(tmp_path) == [], "figures that differ from paper_figures/output"


TWICE = "scaling_sizes"
"""The figure drawn twice, in two processes: a log axis and the label placed beside its tick
labels (a place that once differed between processors), and one of the quickest to draw."""


def test_a_figure_drawn_twice_in_two_processes_is_the_same_bytes(tmp_path):
    for out in ("a", "b"):
        done = subprocess.run([sys.executable, str(REPO / "paper_figures" / f"{TWICE}.py"), "--no-compute",
                               "--out", str(tmp_path / out)], capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr[-500:]
    for suffix in ("png", "pdf"):
        assert (tmp_path / "a" / f"{TWICE}.{suffix}").read_bytes() == (tmp_path / "b" / f"{TWICE}.{suffix}").read_bytes()


RECOMPUTED_RUNS = 10
"""Runs of the fast experiments recomputed at paper scale: the first of the committed runs. Run r
draws from its own stream, the same whatever the number of runs (glamas.rng), so ten runs are ten
of the committed hundred, bit for bit; every array that has runs has them on its first axis."""


@pytest.mark.parametrize("experiment", ["single_gla", "state_encoding", "state_encoding_readings", "and_network",
                                        "and_network_readings"])
def test_fast_experiments_recompute_to_the_committed_results(experiment):
    found = next(e for e in registry.experiments() if e.name == experiment)
    config = found.configure(RECOMPUTED_RUNS, found.iterations)
    fresh = found.arrays(found.run(config, seed=0))
    with np.load(RESULTS / f"{experiment}.npz") as stored:
        arrays = {key: stored[key] for key in stored.files if key not in ("__provenance__", "__config__")}
    assert sorted(fresh) == sorted(arrays)
    def first_runs(key):  # an array of runs: the committed first RECOMPUTED_RUNS
        array, ours = arrays[key], fresh[key]
        with_runs = array.shape != ours.shape and array.shape[1:] == ours.shape[1:]
        return array[:RECOMPUTED_RUNS] if with_runs else array
    assert [key for key in arrays if not np.array_equal(fresh[key], first_runs(key))] == []


def test_at_paper_scale_the_claims_read_the_other_readings_from_the_committed_results(monkeypatch):
    def recomputed(*args, **kwargs):
        raise AssertionError("recomputed instead of read from data/results")

    for face, read, name in ((state_encoding, state_encoding.other_box_readings, "FIG6_READINGS"),
                             (and_network, and_network.other_parabolas, "FIG7_READINGS")):
        experiment = dataclasses.replace(getattr(face, name), run=recomputed)
        monkeypatch.setattr(face, name, experiment)
        stored = experiment.arrays(read.__wrapped__(experiment.paper_scale()))
        with np.load(experiment.file(RESULTS)) as committed:
            assert all(np.array_equal(committed[key], value) for key, value in stored.items())
        with pytest.raises(AssertionError, match="recomputed"):
            read.__wrapped__(experiment.configure(2, 100))  # any other scale is computed
    bounce = dataclasses.replace(gridworld.BOUNCE_START, run=recomputed)
    monkeypatch.setattr(gridworld, "BOUNCE_START", bounce)
    (stored,) = gridworld.other_bounce(gridworld.EXPERIMENT.paper_scale()).values()
    with np.load(bounce.file(RESULTS)) as committed:
        assert all(np.array_equal(committed[key], value) for key, value in bounce.arrays(stored).items())
    with pytest.raises(AssertionError, match="recomputed"):
        gridworld.other_bounce(gridworld.EXPERIMENT.configure(2, 100))
