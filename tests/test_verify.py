"""`python -m glamas.verify`: a recomputation equal to the committed files passes; a difference, a
file on one side only or an unreadable file on either side fails with one line each; bad usage
exits 2 with `error:` on stderr."""

import shutil

import numpy as np
import pytest

from glamas import verify
from glamas.errors import UserError
from glamas.paths import RESULTS


@pytest.fixture
def twins(tmp_path, monkeypatch):
    """A small committed tree (one result file, one figure) and a recomputation equal to it:
    ``(recomputed directory, committed results, committed figures)``."""
    committed = tmp_path / "committed"
    for side in (committed, tmp_path / "out"):
        (side / "results").mkdir(parents=True)
        (side / "figures").mkdir()
        _save(side / "results" / "fig5.npz", curve=np.array([0.5, np.nan]))
        (side / "figures" / "fig5.png").write_bytes(b"\x89PNG drawn")
    monkeypatch.setattr(verify, "RESULTS", committed / "results")
    monkeypatch.setattr(verify, "FIGURES", committed / "figures")
    return tmp_path / "out", committed / "results", committed / "figures"


def _save(path, provenance="{}", **arrays):
    np.savez_compressed(path, __config__=np.array('{"type": "C"}'), __provenance__=np.array(provenance), **arrays)


def _verified(directory, capsys):
    """verify's exit status and the lines it printed."""
    status = verify.main([str(directory)])
    return status, capsys.readouterr().out.splitlines()


def test_the_committed_files_verify_against_themselves(tmp_path):
    shutil.copytree(RESULTS, tmp_path / "results")
    shutil.copytree(verify.FIGURES, tmp_path / "figures")
    assert verify.main([str(tmp_path)]) == 0


def test_equal_twins_pass_whatever_their_provenance_says(twins, capsys):
    out, _, _ = twins
    _save(out / "results" / "fig5.npz", provenance='{"glamas": "older"}', curve=np.array([0.5, np.nan]))
    status, printed = _verified(out, capsys)
    assert status == 0 and printed == [
        "every committed result and figure is what the code computes, and nothing else was computed"]


@pytest.mark.parametrize("side", ["committed", "recomputed"])
def test_a_file_on_one_side_only_is_a_difference(twins, capsys, side):
    out, committed_results, committed_figures = twins
    gone = committed_results / "fig5.npz" if side == "committed" else out / "figures" / "fig5.png"
    gone.unlink()
    status, printed = _verified(out, capsys)
    expected = ("results/fig5.npz: recomputed but not committed" if side == "committed"
                else "figures/fig5.png: committed")
    assert status == 1 and len(printed) == 2 and printed[0].startswith(expected)
    assert printed[-1] == "1 difference from the committed results and figures"


@pytest.mark.parametrize("side", ["committed", "recomputed"])
def test_a_truncated_result_file_on_either_side_is_named_unreadable(twins, capsys, side):
    out, committed_results, _ = twins
    damaged = committed_results / "fig5.npz" if side == "committed" else out / "results" / "fig5.npz"
    damaged.write_bytes(damaged.read_bytes()[:60])
    status, printed = _verified(out, capsys)
    assert status == 1 and len(printed) == 2
    assert printed[0].startswith(f"results/fig5.npz: the {side} file ") and "is unreadable (" in printed[0]


def test_a_differing_array_is_named(twins, capsys):
    out, _, _ = twins
    _save(out / "results" / "fig5.npz", curve=np.array([0.5, 0.25]))
    status, printed = _verified(out, capsys)
    assert status == 1 and printed[0] == "results/fig5.npz: curve differs"


def test_an_array_in_one_file_only_is_named(twins, capsys):
    out, _, _ = twins
    _save(out / "results" / "fig5.npz", curve=np.array([0.5, np.nan]), extra=np.zeros(2))
    status, printed = _verified(out, capsys)
    assert status == 1 and printed[0] == "results/fig5.npz: arrays ['extra'] are in only one of the files"


def test_a_differing_figure_is_named(twins, capsys):
    out, _, _ = twins
    (out / "figures" / "fig5.png").write_bytes(b"\x89PNG drawn otherwise")
    status, printed = _verified(out, capsys)
    assert status == 1 and printed[0] == "figures/fig5.png: differs from the committed figure: its bytes differ"


@pytest.mark.parametrize("argv", [[], ["a", "b"], ["nowhere"]])
def test_bad_usage_is_an_error_line_on_stderr_and_status_2(tmp_path, capsys, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)  # "nowhere" holds no results/ and figures/
    with pytest.raises(SystemExit) as stopped:
        verify.main(argv)
    assert stopped.value.code == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith("usage: python -m glamas.verify")
    assert len([line for line in captured.err.splitlines() if "error: " in line]) == 1


def _pdf_with_text_at(x_points: float) -> bytes:
    """A one-page PDF with one label ``x_points`` points from its left edge."""
    import io

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(2, 1))
    fig.text(x_points / 144.0, 0.5, "label")
    buffer = io.BytesIO()
    fig.savefig(buffer, format="pdf", metadata={"CreationDate": None, "Producer": None})
    plt.close(fig)
    return buffer.getvalue()


def test_a_pdf_equal_within_the_tolerance_is_said_apart_and_passes(twins, capsys):
    out, _, committed_figures = twins
    (committed_figures / "label.pdf").write_bytes(_pdf_with_text_at(30.0))
    (out / "figures" / "label.pdf").write_bytes(_pdf_with_text_at(30.0 + 1e-9))
    status, printed = _verified(out, capsys)
    assert status == 0 and len(printed) == 2
    assert printed[0].startswith("figures/label.pdf: the same figure, not the same bytes: numbers within ")
    assert printed[1] == ("every committed result and figure is what the code computes (1 PDF figure the same "
                          "within 1e-06 pt, not byte for byte), and nothing else was computed")


def test_a_label_moved_by_a_hundredth_of_a_point_is_a_difference(twins, capsys):
    out, _, committed_figures = twins
    (committed_figures / "label.pdf").write_bytes(_pdf_with_text_at(30.0))
    (out / "figures" / "label.pdf").write_bytes(_pdf_with_text_at(30.01))
    status, printed = _verified(out, capsys)
    assert status == 1 and printed[0].startswith("figures/label.pdf: differs from the committed figure: PDF object ")
    assert printed[-1] == "1 difference from the committed results and figures"


@pytest.fixture
def stale_and_recomputed(tmp_path, monkeypatch):
    """A committed single_gla result recorded with other code, its recomputation by the code as it
    is (the same arrays), and verify pointed at them: (config, committed dir, recomputed dir)."""
    from glamas import results
    from glamas.experiments import single_gla
    config = single_gla.FIG5.paper_scale()
    committed, out = tmp_path / "committed", tmp_path / "out"
    for side in (committed, out):
        (side / "results").mkdir(parents=True)
        (side / "figures").mkdir()
    np.savez(committed / "results" / "single_gla.npz", __config__=np.array(results.config_json(config, 0)),
             __provenance__=np.array('{"version": "0.6.0", "maps": {}}'), x=np.arange(3.0))
    results.save(out / "results" / "single_gla.npz", config, {"x": np.arange(3.0)}, seed=0)
    monkeypatch.setattr(verify, "RESULTS", committed / "results")
    monkeypatch.setattr(verify, "FIGURES", committed / "figures")
    return config, committed, out


def test_adopt_takes_the_recomputed_results_only_when_nothing_differs(stale_and_recomputed, capsys):
    from glamas import results
    config, committed, out = stale_and_recomputed
    with pytest.raises(results.StaleResultError, match="records not the code that computed it"):
        results.load(committed / "results" / "single_gla.npz", config, seed=0)
    assert verify.main([str(out), "--adopt"]) == 0
    assert "adopted 1 recomputed result file" in capsys.readouterr().out
    assert np.array_equal(results.load(committed / "results" / "single_gla.npz", config, seed=0)["x"], np.arange(3.0))
    np.savez(out / "results" / "single_gla.npz", __config__=np.array(results.config_json(config, 0)),
             __provenance__=np.array("{}"), x=np.arange(4.0))
    before = (committed / "results" / "single_gla.npz").read_bytes()
    assert verify.main([str(out), "--adopt"]) == 1
    assert "adopted nothing" in capsys.readouterr().out
    assert (committed / "results" / "single_gla.npz").read_bytes() == before


def test_adopt_refuses_files_their_own_record_says_the_current_code_did_not_compute(tmp_path, monkeypatch, capsys):
    """A copy of the committed files is no recomputation: after an edit of a kernel (seen here as
    a changed record of the code), adopting it must take nothing, and leave the committed files."""
    from glamas import provenance
    shutil.copytree(RESULTS, tmp_path / "copy" / "results")
    shutil.copytree(verify.FIGURES, tmp_path / "copy" / "figures")
    real = provenance.code_record
    monkeypatch.setattr(provenance, "code_record", lambda config: {**real(config), "learners/independent.py": "edited"})
    before = {path.name: path.read_bytes() for path in RESULTS.glob("*.npz")}
    # (on another Python than the one that recorded the committed files, the line names both Pythons too)
    with pytest.raises(UserError, match=r"was not computed by the code as it is \(the code that computes it changed "
                                        r"since it was made \(glamas/learners/independent.py\)[^)]*\).*adopted nothing"):
        verify.main([str(tmp_path / "copy"), "--adopt"])
    assert {path.name: path.read_bytes() for path in RESULTS.glob("*.npz")} == before


def test_arrays_of_another_dtype_differ(twins, capsys):
    out, committed_results, _ = twins
    _save(committed_results / "fig5.npz", curve=np.array([1, 2], dtype=np.int64))
    _save(out / "results" / "fig5.npz", curve=np.array([1.0, 2.0]))
    status, printed = _verified(out, capsys)
    assert status == 1 and "curve" in printed[0]


def test_one_experiment_is_compared_and_adopted_alone(stale_and_recomputed, capsys):
    from glamas import results
    config, committed, out = stale_and_recomputed
    np.savez(committed / "results" / "gridworld.npz", x=np.arange(2.0))  # another experiment, not recomputed
    assert verify.main([str(out), "--adopt"]) == 1  # the whole comparison misses gridworld.npz
    capsys.readouterr()
    assert verify.main([str(out), "--adopt", "--experiment", "single_gla"]) == 0
    assert "adopted 1 recomputed result file" in capsys.readouterr().out
    assert np.array_equal(results.load(committed / "results" / "single_gla.npz", config, seed=0)["x"], np.arange(3.0))
    with pytest.raises(UserError, match="--experiment nonexistent: no stored experiment of that name"):
        verify.main([str(out), "--experiment", "nonexistent"])
