"""Compare a full recomputation (``make verify``) with the committed results and figures.

``python -m glamas.verify DIR`` compares, in both directions, the result files in ``DIR/results``
with those in ``data/results`` and the figures in ``DIR/figures`` with those in
``paper_figures/output``: every committed file must have a recomputed twin of the same name and
every recomputed file a committed one, so that a file missing on either side cannot pass. Twin
result files must hold the same configuration and arrays (the provenance record may differ, since
committed files can predate it), twin figures the same bytes; a file that cannot be read, on
either side, is a difference too.

It prints one line per difference, then a summary line, and exits 0 when everything is equal, 1
on any difference, 2 on bad usage (the usage and one line ``error: ...`` on stderr).
"""

import argparse
import zipfile
import zlib
from pathlib import Path

import numpy as np

from glamas import errors
from glamas.committed import figure_advice, result_advice, shown
from glamas.paths import FIGURES, RESULTS

_PROVENANCE = "__provenance__"
_UNREADABLE = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error, NotImplementedError)
"""What a missing, damaged, truncated or foreign archive raises while it is read."""


class UnreadableFile(Exception):
    """A file of one side could not be read; the message says which side, and why."""


def differences(directory: Path) -> list[str]:
    """Every difference between ``directory``'s recomputation and the committed files, both ways."""
    return (_compare(Path(directory) / "results", RESULTS, result_differences)
            + _compare(Path(directory) / "figures", FIGURES, figure_differences))


def _compare(recomputed: Path, committed: Path, compare) -> list[str]:
    """The differences between the files of two directories: a name in one only, or twins that
    ``compare(recomputed_file, committed_file)`` finds different or cannot read."""
    ours, theirs = _names(recomputed), _names(committed)
    found = []
    for name in sorted(ours | theirs):
        label = f"{recomputed.name}/{name}"
        if name not in ours:
            found.append(f"{label}: committed ({shown(committed)}) but not recomputed")
        elif name not in theirs:
            found.append(f"{label}: recomputed but not committed (no {shown(committed / name)})")
        else:
            try:
                found += [f"{label}: {text}" for text in compare(recomputed / name, committed / name)]
            except UnreadableFile as error:
                found.append(f"{label}: {error}")
    return found


def _names(directory: Path) -> set:
    """The names of the entries of ``directory`` (none if it does not exist)."""
    return {path.name for path in directory.iterdir()} if directory.is_dir() else set()


def result_differences(recomputed: Path, committed: Path) -> list[str]:
    """What differs between two result files (empty: the same configuration and arrays)."""
    a, b = _arrays(recomputed, "recomputed"), _arrays(committed, "committed")
    if set(a) != set(b):
        return [f"arrays {sorted(set(a) ^ set(b))} are in only one of the files"]
    return [f"{key} differs" for key in sorted(a) if not _equal(a[key], b[key])]


def figure_differences(recomputed: Path, committed: Path) -> list[str]:
    """What differs between two figure files (empty: the same bytes)."""
    same = _bytes(recomputed, "recomputed") == _bytes(committed, "committed")
    return [] if same else ["differs from the committed figure"]


def _arrays(path: Path, side: str) -> dict:
    """Every array of result file ``path`` but its provenance record, read whole (a damaged
    member fails here, not later); UnreadableFile naming ``side`` if it cannot be read."""
    try:
        with np.load(path, allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files if key != _PROVENANCE}
    except _UNREADABLE as error:
        raise _unreadable(path, side, error) from None


def _bytes(path: Path, side: str) -> bytes:
    """The bytes of figure ``path``; UnreadableFile naming ``side`` if it cannot be read."""
    try:
        return path.read_bytes()
    except OSError as error:
        raise _unreadable(path, side, error) from None


def _unreadable(path: Path, side: str, error: Exception) -> UnreadableFile:
    reason = " ".join(str(error).split()) or type(error).__name__
    return UnreadableFile(f"the {side} file {shown(path)} is unreadable ({reason}); {_fix(path, side)}")


def _fix(path: Path, side: str) -> str:
    """What makes the unreadable file ``path`` of ``side`` readable again: for a committed one the
    figure script that recomputes it, or git checkout (:mod:`glamas.committed`)."""
    if side == "recomputed":
        return "recompute it (make verify)"
    return result_advice(path.name) if path.suffix == ".npz" else figure_advice(path.name)


def _equal(x: np.ndarray, y: np.ndarray) -> bool:
    """Equal arrays; NaN equals NaN in float arrays (the scaling study marks skipped runs with it)."""
    return np.array_equal(x, y, equal_nan=x.dtype.kind in "fc" and y.dtype.kind in "fc")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.verify",
                                     description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("directory", metavar="DIR", type=Path,
                        help="the directory `make verify` recomputed into (its results/ and figures/)")
    args = parser.parse_args(argv)
    missing = [f"{name}/" for name in ("results", "figures") if not (args.directory / name).is_dir()]
    if missing:
        parser.error(f"{args.directory} holds no {' and no '.join(missing)}: give the directory "
                     "`make verify` recomputed into")
    found = differences(args.directory)
    for line in found:
        print(line)
    print(f"{len(found)} difference{'s' * (len(found) != 1)} from the committed results and figures" if found else
          "every committed result and figure is what the code computes, and nothing else was computed")
    return 1 if found else 0


if __name__ == "__main__":
    errors.run(main)
