"""Compare a full recomputation (``make verify``) with the committed results and figures.

``python -m glamas.verify DIR`` compares every result file in ``DIR/results`` with the one of the
same name in ``data/results`` (the configuration and every array equal; the provenance record may
differ, since committed files can predate it) and every figure in ``DIR/figures`` with the one in
``paper_figures/output`` (byte for byte). It prints one line per difference and exits 1 if there
is any, or if a committed file was not recomputed.
"""

import sys
from pathlib import Path

import numpy as np

from glamas.paths import REPO, RESULTS

FIGURES = REPO / "paper_figures" / "output"
_PROVENANCE = "__provenance__"


def result_differences(fresh: Path, committed: Path) -> list[str]:
    """What differs between two result files (empty: the same configuration and arrays)."""
    with np.load(fresh, allow_pickle=False) as a, np.load(committed, allow_pickle=False) as b:
        keys_a, keys_b = set(a.files) - {_PROVENANCE}, set(b.files) - {_PROVENANCE}
        if keys_a != keys_b:
            return [f"{committed.name}: arrays {sorted(keys_a ^ keys_b)} are in only one of the files"]
        return [f"{committed.name}: {key} differs" for key in sorted(keys_a) if not _equal(a[key], b[key])]


def _equal(x: np.ndarray, y: np.ndarray) -> bool:
    """Equal arrays; NaN equals NaN in float arrays (the scaling study marks skipped runs with it)."""
    return np.array_equal(x, y, equal_nan=x.dtype.kind in "fc" and y.dtype.kind in "fc")


def differences(directory: Path) -> list[str]:
    """Every difference between ``directory``'s recomputation and the committed files."""
    found = []
    for committed in sorted(RESULTS.glob("*.npz")):
        fresh = directory / "results" / committed.name
        found += result_differences(fresh, committed) if fresh.exists() else [f"{committed.name}: not recomputed"]
    for committed in sorted(FIGURES.iterdir()):
        fresh = directory / "figures" / committed.name
        if not fresh.exists():
            found.append(f"{committed.name}: not redrawn")
        elif fresh.read_bytes() != committed.read_bytes():
            found.append(f"{committed.name}: differs")
    return found


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1 or not Path(args[0]).is_dir():
        print("usage: python -m glamas.verify DIR (the directory `make verify` recomputed into)")
        return 2
    found = differences(Path(args[0]))
    for line in found:
        print(line)
    print(f"{len(found)} differences" if found else "every committed result and figure is what the code computes")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
