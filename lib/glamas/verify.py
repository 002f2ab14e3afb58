"""Compare a full recomputation (``make verify``) with the committed results and figures.

``python -m glamas.verify DIR`` compares, in both directions, the result files in ``DIR/results``
with those in ``data/results`` and the figures in ``DIR/figures`` with those in
``paper_figures/output``: every committed file must have a recomputed twin of the same name and
every recomputed file a committed one, so that a file missing on either side cannot pass. Twin
result files must hold the same configuration and arrays (the provenance record may differ, since
committed files can predate it), twin figures the same figure (:func:`glamas.figure_files.compare`:
PNG byte for byte, PDF as structure with every real number within its tolerance); a file that cannot
be read, on either side, is a difference too.

It prints one line per difference, then one per PDF that is the same figure but not the same bytes
(a number's last decimal rounded otherwise on another processor: not a difference, but said), then a
summary line, and exits 0 when everything is equal, 1 on any difference, 2 on bad usage (the usage
and one line ``error: ...`` on stderr).

A committed result records the code that computed it (:mod:`glamas.provenance`), so a change of
that code makes it stale even when it computes the same arrays. ``--adopt`` then takes the
recomputed result files in place of the committed ones, with their new records, and only when
nothing differs: every array and figure the same, so the records are what changed
(``make verify ADOPT=1``). The records are made when adopting, of the code as it is then.
"""

import argparse
import zipfile
import zlib
from pathlib import Path
from typing import NamedTuple

import numpy as np

from glamas import errors, figure_files
from glamas.committed import figure_advice, result_advice, shown
from glamas.paths import FIGURES, RESULTS
from glamas.results import open_archive

_PROVENANCE = "__provenance__"
_CONFIG = "__config__"
_UNREADABLE = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error, NotImplementedError)
"""What a missing, damaged, truncated or foreign archive raises while it is read."""


class UnreadableFile(Exception):
    """A file of one side could not be read; the message says which side, and why."""


class Finding(NamedTuple):
    """One line of the report."""

    text: str
    difference: bool
    """True for a difference; False for a figure that is the same within the tolerance only."""


def findings(directory: Path, experiment: str | None = None) -> list[Finding]:
    """Everything :func:`main` reports of ``directory``'s recomputation against the committed files,
    both ways: the differences, and the figures equal within the PDF tolerance only; of every file,
    or of one ``experiment``'s result file and figures only."""
    results, figures = _files_of(experiment)
    return (_compare(Path(directory) / "results", RESULTS, result_differences, results)
            + _compare(Path(directory) / "figures", FIGURES, figure_findings, figures))


def _files_of(experiment: str | None) -> tuple:
    """(result file names, figure file names) of ``experiment``; (None, None) for every file."""
    if experiment is None:
        return None, None
    from glamas.experiments import registry

    known = {e.name: e for e in registry.experiments() if e.stored}
    if experiment not in known:
        raise errors.UserError(f"--experiment {experiment}: no stored experiment of that name; those: "
                               f"{', '.join(known)}")
    figures = {f"{name}{suffix}" for name in known[experiment].figures for suffix in (".png", ".pdf")}
    return {known[experiment].file(".").name}, figures


def differences(directory: Path) -> list[str]:
    """Every difference between ``directory``'s recomputation and the committed files, both ways."""
    return [found.text for found in findings(directory) if found.difference]


def _compare(recomputed: Path, committed: Path, compare, only: set | None = None) -> list[Finding]:
    """The findings of two directories (of the names ``only``, or all): a name in one only, or
    twins that ``compare(recomputed_file, committed_file)`` finds different (or the same within a
    tolerance only), or cannot read."""
    ours, theirs = _names(recomputed), _names(committed)
    if only is not None:
        ours, theirs = ours & only, theirs & only
    found = []
    for name in sorted(ours | theirs):
        label = f"{recomputed.name}/{name}"
        if name not in ours:
            found.append(Finding(f"{label}: committed ({shown(committed)}) but not recomputed", True))
        elif name not in theirs:
            found.append(Finding(f"{label}: recomputed but not committed (no {shown(committed / name)})", True))
        else:
            try:
                found += [Finding(f"{label}: {text}", real) for text, real in compare(recomputed / name, committed / name)]
            except UnreadableFile as error:
                found.append(Finding(f"{label}: {error}", True))
    return found


def _names(directory: Path) -> set:
    """The names of the entries of ``directory`` (none if it does not exist)."""
    return {path.name for path in directory.iterdir()} if directory.is_dir() else set()


def result_differences(recomputed: Path, committed: Path) -> list[tuple]:
    """What differs between two result files, as (text, True) (empty: the same configuration and arrays)."""
    a, b = _arrays(recomputed, "recomputed"), _arrays(committed, "committed")
    if set(a) != set(b):
        return [(f"arrays {sorted(set(a) ^ set(b))} are in only one of the files", True)]
    return [(f"{key} differs", True) for key in sorted(a) if not _equal(a[key], b[key])]


def figure_findings(recomputed: Path, committed: Path) -> list[tuple]:
    """(text, is a difference) of two figure files (:func:`glamas.figure_files.compare`): nothing
    for the same bytes; for a PDF that is the same figure within the tolerance only, a note."""
    found = figure_files.compare(_bytes(recomputed, "recomputed"), _bytes(committed, "committed"), recomputed.suffix)
    if found.same_bytes:
        return []
    if found.equal:
        return [(f"the same figure, not the same bytes: {found.detail} (rounding of another processor)", False)]
    return [(f"differs from the committed figure: {found.detail}", True)]


def _arrays(path: Path, side: str) -> dict:
    """Every array of result file ``path`` but its provenance record, read whole (a damaged
    member fails here, not later); UnreadableFile naming ``side`` if it cannot be read."""
    try:
        with open_archive(path) as archive:
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
    """Equal arrays of one dtype; NaN equals NaN in float arrays (the scaling study marks skipped
    runs with it)."""
    return x.dtype == y.dtype and np.array_equal(x, y, equal_nan=x.dtype.kind in "fc")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.verify",
                                     description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("directory", metavar="DIR", type=Path,
                        help="the directory `make verify` recomputed into (its results/ and figures/)")
    parser.add_argument("--adopt", action="store_true",
                        help="when nothing differs, copy the recomputed result files over the committed ones "
                             "(their records of the code that computed them are the new code's)")
    parser.add_argument("--experiment", metavar="NAME", help="compare (and adopt) one experiment's result file and "
                        "figures only, e.g. after python -m glamas.reproduce --experiment NAME --fresh DIR")
    args = parser.parse_args(argv)
    missing = [f"{name}/" for name in ("results", "figures") if not (args.directory / name).is_dir()]
    if missing:
        parser.error(f"{args.directory} holds no {' and no '.join(missing)}: give the directory "
                     "`make verify` recomputed into")
    found = findings(args.directory, args.experiment)
    real = [line.text for line in found if line.difference]
    close = [line.text for line in found if not line.difference]
    for line in real + close:
        print(line)
    within = (f" ({len(close)} PDF figure{'s' * (len(close) != 1)} the same within "
              f"{figure_files.TOLERANCE:g} pt, not byte for byte)") if close else ""
    print(f"{len(real)} difference{'s' * (len(real) != 1)} from the committed results and figures{within}" if real else
          f"every committed result and figure is what the code computes{within}, and nothing else was computed")
    if args.adopt and not real:
        adopted = adopt(args.directory / "results", _files_of(args.experiment)[0])
        print(f"adopted {adopted} recomputed result file{'s' * (adopted != 1)} in {shown(RESULTS)}: the same arrays, "
              "recorded with the code that computed them now")
    elif args.adopt:
        print("adopted nothing: the recomputation differs from the committed files")
    return 1 if real else 0


def adopt(recomputed: Path, only: set | None = None) -> int:
    """Save the arrays of every result file of ``recomputed`` as its committed twin, with the record
    of the code as it is now (:func:`glamas.results.save`), of those named ``only`` (or every one);
    returns how many. Each is the
    paper-scale result of its experiment (its configuration checked against the file's), and its
    own record must say that the code as it is now computed it: a file is trusted by its record,
    never by its place (a copy of the committed files is not a recomputation). Nothing is adopted
    unless every file passes."""
    from glamas import provenance, results
    from glamas.experiments import registry

    experiments = {experiment.name: experiment for experiment in registry.experiments()}
    files = sorted(path for path in recomputed.glob("*.npz") if only is None or path.name in only)
    taken = []
    for path in files:
        experiment = experiments.get(path.stem)
        if experiment is None:
            raise errors.UserError(f"{shown(path)} is the result of no registered experiment; adopted nothing")
        config = experiment.paper_scale()
        stored = results.stored_config(path)
        seed = results.stored_seed(path)
        if stored != results.config_json(config, seed):
            raise errors.UserError(f"{shown(path)} is not the paper-scale result of {path.stem}; adopted nothing")
        changed = provenance.mismatch(results.stored_provenance(path), provenance.record(config))
        if changed:
            raise errors.UserError(f"{shown(path)} was not computed by the code as it is ({changed}): recompute it "
                                   "(make verify) before adopting it; adopted nothing")
        taken.append((path, config, seed))
    for path, config, seed in taken:
        results.save(RESULTS / path.name, config, results.load(path, config, seed=seed), seed=seed, overwrite=True)
    return len(taken)


if __name__ == "__main__":
    errors.run(main)
