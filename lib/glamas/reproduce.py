"""Run figure scripts of ``paper_figures/`` one after the other in one process: what ``make
figures``, ``make reproduce`` and ``make verify`` do.

``python -m glamas.reproduce [--all] [--out DIR] [--results DIR] [--fresh DIR]`` calls the ``main``
of each figure script of the chapter's experiments (with ``--all``: of every experiment, the
studies beyond the chapter included; :func:`glamas.experiments.registry.figure_scripts`), in order,
handing each the given --out and --results. With a --results directory that holds no result, the
first script of each experiment recomputes it and the scripts drawing other figures of that
experiment read what it just saved; without --results every script draws from the committed
results and computes nothing (``--no-compute``): a committed result that is missing, stale or
damaged stops it with one line naming the script that recomputes it. ``--fresh DIR`` recomputes
into ``DIR/figures`` and ``DIR/results``, emptied first (:func:`fresh_directories`): what ``make
reproduce`` and ``make verify`` run, so that the Makefile deletes nothing itself.

One process instead of one per script: Python, numba and matplotlib are imported once, the
worker processes of the runs (:mod:`glamas.parallel`) start once and keep the kernels they loaded
(about a second per script otherwise), and runs that two scripts' experiments share are run once
(:data:`REUSED_BYTES`). A script's figure is the same either way (``make verify``
compares them byte for byte with the committed ones). A user error in a script stops the
sequence there with exit status 2; an --out or --results that cannot be written is refused
with one line before any script runs.
"""

import argparse
import fnmatch
import importlib.util
from pathlib import Path

from glamas import atomic, errors, parallel
from glamas.errors import UserError
from glamas.experiments import registry
from glamas.paths import DATA, SCRIPTS


REUSED_BYTES = 128 * 2 ** 20
"""Outputs of the runs that the scripts share, at most (glamas.parallel.reuse_batches): Fig. 11's
learners train as the Fig. 10 study's default reading and the related-work comparison's do."""


def script_main(name: str):
    """The ``main(argv)`` of paper_figures/``name``.py."""
    path = SCRIPTS / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"paper_figures.{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main


def scripts(experiment: str | None, every: bool) -> tuple:
    """The figure scripts to run: ``experiment``'s, or every experiment's (``every``), or the chapter's."""
    if experiment is None:
        return registry.figure_scripts(chapter_only=not every)
    known = {e.name: e for e in registry.experiments()}
    if experiment not in known:
        raise UserError(f"no experiment {experiment!r}; the experiments are {', '.join(known)}")
    return tuple(sorted(known[experiment].figures, key=registry.figure_order))


def run(names, options: list) -> None:
    """Call each script's ``main(options)``, announcing it first."""
    for name in names:
        print(f"== paper_figures/{name}.py", flush=True)
        script_main(name)(list(options))


COMMITTED = (DATA, SCRIPTS)
"""The directories of the committed results and figures: ``--fresh`` never empties one of them,
a directory inside one, or a directory holding one (such as the repository itself)."""
FIGURE_PATTERNS = ("*.png", "*.pdf")
"""The names of the files a figure script writes to its --out."""


def fresh_layout() -> dict:
    """What ``--fresh DIR`` may hold: per subdirectory, the names of the files glamas writes there."""
    return {"figures": FIGURE_PATTERNS, "results": registry.result_files()}


def fresh_directories(text: str) -> tuple:
    """``--fresh DIR`` checked, then emptied of what glamas wrote there: ``(DIR/figures,
    DIR/results)``. Every check comes before the first deletion, so that a refusal (UserError)
    deletes nothing; a file glamas did not write is never deleted, but refused."""
    if not text.strip():
        raise UserError("--fresh is empty (make's OUT or VERIFY set to nothing?); nothing was deleted: "
                         "give the directory to recompute into, e.g. out/reproduce")
    directory = Path(text)
    layout = fresh_layout()
    for place in (directory, *(directory / name for name in layout)):
        _refuse_committed(place, text)
    doomed = _written_by_glamas(directory, layout, text)
    for path in doomed:
        path.unlink()
    return directory / "figures", directory / "results"


def _refuse_committed(place: Path, text: str) -> None:
    """Raise UserError if ``place`` (its symbolic links followed) is, lies inside or holds a
    directory of :data:`COMMITTED`; ``text`` is the --fresh given."""
    resolved = place.resolve()
    for committed in (path.resolve() for path in COMMITTED):
        relation = ("is" if resolved == committed else "is inside" if committed in resolved.parents
                    else "holds" if resolved in committed.parents else None)
        if relation:
            subject = text if place == Path(text) else f"{text}: {place}"
            raise UserError(f"--fresh {subject} {relation} the repository's {committed.name}/ (committed files); "
                             "nothing was deleted: give a directory outside data/ and paper_figures/, "
                             "e.g. out/reproduce")


def _written_by_glamas(directory: Path, layout: dict, text: str) -> list:
    """The files of ``directory``'s subdirectories in ``layout``, each a file glamas writes there or
    a temporary file of one (:func:`glamas.atomic.write`; :func:`glamas.atomic.locked` locks the
    directory itself, so there is no lock file); UserError naming the first other entry."""
    if not directory.exists():
        return []
    if not directory.is_dir():
        raise UserError(f"--fresh {text} exists and is not a directory; nothing was deleted: "
                         "give a directory path")
    found = []
    for entry in sorted(directory.iterdir()):
        patterns = layout.get(entry.name) if entry.is_dir() else None
        if patterns is None:
            raise _foreign(entry, text)
        for path in sorted(entry.iterdir()):
            if not (path.is_file() and any(fnmatch.fnmatchcase(path.name, pattern)
                                           for name in patterns for pattern in (name, f"{name}*.tmp"))):
                raise _foreign(path, text)
            found.append(path)
    return found


def _foreign(path: Path, text: str) -> UserError:
    """The refusal of --fresh ``text`` for holding ``path``, which glamas did not write."""
    return UserError(f"--fresh {text} holds {path}, which glamas did not write; nothing was deleted: "
                      "move it away or give another directory")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.reproduce",
                                     description=" ".join(__doc__.split("\n\n")[0].split()))
    scope = parser.add_mutually_exclusive_group()
    scope.add_argument("--all", action="store_true",
                       help="every script of paper_figures/, the studies beyond the chapter included")
    scope.add_argument("--experiment", metavar="NAME",
                       help="the scripts of one experiment only (for example benchmark_maps)")
    parser.add_argument("--out", type=Path, help="directory for the figures (each script's --out)")
    parser.add_argument("--results", type=Path, help="directory for the result files (each script's --results)")
    parser.add_argument("--fresh", metavar="DIR",
                        help="recompute into DIR: the figures into DIR/figures and the results into DIR/results, "
                             "both emptied first (instead of --out and --results). Refused with one line, "
                             "deleting nothing, when DIR is empty, is, lies inside or holds the repository's "
                             "data/ or paper_figures/, or holds anything but figures (*.png, *.pdf) in figures/, "
                             "result files of glamas's experiments in results/, and their temporary files")
    args = parser.parse_args(argv)
    if args.fresh is not None and (args.out or args.results):
        parser.error("--fresh DIR chooses --out and --results: give either --fresh or --out/--results")
    with errors.reported():  # checked once here, before any script runs
        names = scripts(args.experiment, args.all)
        if args.fresh is not None:
            args.out, args.results = fresh_directories(args.fresh)
        for flag, directory in (("--out", args.out), ("--results", args.results)):
            if directory is not None:
                atomic.check_writable_directory(directory, flag)
    options = [item for flag, value in (("--out", args.out), ("--results", args.results)) if value is not None
               for item in (flag, str(value))]
    if args.results is None:
        options.append("--no-compute")  # drawing from the committed results: never recompute one at paper scale
    parallel.reuse_batches(REUSED_BYTES)
    try:
        run(names, options)  # a script's user error exits with status 2
    finally:
        parallel.reuse_batches(0)  # a caller in this process (a test, a notebook) runs its own batches again
    return 0


if __name__ == "__main__":
    errors.run(main)
