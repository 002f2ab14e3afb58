"""`python -m glamas.verify`: a recomputation equal to the committed files passes, any difference fails."""

import shutil

import numpy as np

from glamas import verify
from glamas.paths import RESULTS


def _copy_of_the_committed(tmp_path):
    shutil.copytree(RESULTS, tmp_path / "results")
    shutil.copytree(verify.FIGURES, tmp_path / "figures")
    return tmp_path


def test_the_committed_files_verify_against_themselves(tmp_path):
    assert verify.main([str(_copy_of_the_committed(tmp_path))]) == 0


def test_a_changed_array_a_changed_figure_and_a_missing_file_are_reported(tmp_path, capsys):
    out = _copy_of_the_committed(tmp_path)
    with np.load(out / "results" / "fig5.npz") as archive:
        arrays = {key: archive[key] for key in archive.files}
    key = next(k for k in arrays if not k.startswith("__") and arrays[k].dtype.kind == "f")
    arrays[key] = arrays[key] + 1.0
    np.savez(out / "results" / "fig5.npz", **arrays)
    (out / "figures" / "fig9.png").write_bytes(b"not a figure")
    (out / "results" / "fig6.npz").unlink()
    assert verify.main([str(out)]) == 1
    printed = capsys.readouterr().out
    assert f"fig5.npz: {key} differs" in printed and "fig9.png: differs" in printed
    assert "fig6.npz: not recomputed" in printed


def test_a_missing_directory_is_one_usage_line(tmp_path, capsys):
    assert verify.main([str(tmp_path / "nowhere")]) == 2
    assert capsys.readouterr().out.strip().splitlines() == [
        "usage: python -m glamas.verify DIR (the directory `make verify` recomputed into)"]
