"""`glamas.figure_files.compare`: the same figure passes, a real change fails.

A PDF whose numbers differ by a rounding of another processor (1e-9 pt) is the same figure; a label
moved by a hundredth of a point, another figure, or the figure of a reduced run is not; a PNG is
compared byte for byte."""

import io
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from glamas import figure_files, plotting  # noqa: E402
from glamas.paths import REPO  # noqa: E402

OUTPUT = REPO / "paper_figures" / "output"


def _figure(label_at: float = 30.0, format: str = "pdf", log: bool = True) -> bytes:
    """A small figure on log axes with a label ``label_at`` points from its left edge."""
    fig, ax = plotting.new_figure(2.0, 1.5)
    ax.plot([1, 10, 100], [3, 1, 2])
    if log:
        ax.set_xscale("log")
    fig.text(label_at / 144.0, 0.02, "label")
    buffer = io.BytesIO()
    fig.savefig(buffer, format=format, metadata=plotting._PDF_METADATA if format == "pdf" else plotting._PNG_METADATA)
    plt.close(fig)
    return buffer.getvalue()


def test_the_same_figure_is_the_same_bytes():
    assert figure_files.compare(_figure(), _figure(), ".pdf") == (True, True, "")


def test_a_pdf_whose_numbers_moved_by_a_rounding_is_the_same_figure():
    found = figure_files.compare(_figure(30.0 + 1e-9), _figure(30.0), ".pdf")
    assert not found.same_bytes and found.equal and "numbers within 1e-09 pt" in found.detail


@pytest.mark.parametrize("moved", [0.01, -0.01, 1e-5])
def test_a_label_moved_beyond_the_tolerance_is_another_figure(moved):
    found = figure_files.compare(_figure(30.0 + moved), _figure(30.0), ".pdf")
    assert not found.equal and found.detail.startswith("PDF object ")


def test_a_png_is_compared_byte_for_byte():
    found = figure_files.compare(_figure(31.0, "png"), _figure(30.0, "png"), ".png")
    assert found == (False, False, "its bytes differ")


def test_another_committed_figure_is_another_figure():
    for suffix in (".pdf", ".png"):
        found = figure_files.compare((OUTPUT / f"fig11a{suffix}").read_bytes(), (OUTPUT / f"fig11b{suffix}").read_bytes(),
                                     suffix)
        assert not found.equal


def test_the_figure_of_a_reduced_run_is_another_figure(tmp_path):
    done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig5.py"), "--runs", "2", "--iterations",
                           "2000", "--out", str(tmp_path), "--results", str(tmp_path)], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-500:]
    for suffix in (".pdf", ".png"):
        drawn = (tmp_path / f"fig5{suffix}").read_bytes()
        assert not figure_files.compare(drawn, (OUTPUT / f"fig5{suffix}").read_bytes(), suffix).equal


def test_a_damaged_pdf_is_another_figure_and_says_why():
    good = _figure()
    found = figure_files.compare(good[: len(good) // 2], good, ".pdf")
    assert not found.equal and "not a PDF glamas can read" in found.detail
