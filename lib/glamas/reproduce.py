"""Run figure scripts of ``paper_figures/`` one after the other in one process: what ``make
figures``, ``make reproduce`` and ``make verify`` do.

``python -m glamas.reproduce [--all] [--out DIR] [--results DIR]`` calls the ``main`` of each
script of :data:`CHAPTER` (with ``--all``: every script, the studies beyond the chapter
included), in order, handing each the given --out and --results. With a --results directory that
holds no result, the first script of each experiment recomputes it and the scripts drawing other
figures of that experiment read what it just saved; without --results every script draws from the
committed results.

One process instead of one per script: Python, numba and matplotlib are imported once, the
worker processes of the runs (:mod:`glamas.runs`) start once and keep the kernels they loaded
(about a second per script otherwise), and runs that two scripts' experiments share are run once
(:data:`REUSED_BYTES`). A script's figure is the same either way (``make verify``
compares them byte for byte with the committed ones). A user error in a script stops the
sequence there with exit status 2; an --out or --results that cannot be written is refused
with one line before any script runs.
"""

import argparse
import importlib.util
import sys
from pathlib import Path

from glamas import atomic, cli, runs
from glamas.paths import REPO

SCRIPTS = REPO / "paper_figures"
CHAPTER = ("fig5", "fig6", "fig7a", "fig7b", "fig9", "fig9_optimum", "fig10", "fig11a", "fig11b", "fig12a",
           "fig12b")
"""The scripts of the chapter's figures (Fig. 5-12), in the order they run: each experiment's
first figure computes it."""


REUSED_BYTES = 128 * 2 ** 20
"""Outputs of the runs that the scripts share, at most (glamas.runs.reuse_batches): Fig. 11's
learners train as the Fig. 10 study's default reading and the related-work comparison's do."""


def every_script() -> tuple:
    """Every script of paper_figures/, in name order."""
    return tuple(path.stem for path in sorted(SCRIPTS.glob("*.py")))


def script_main(name: str):
    """The ``main(argv)`` of paper_figures/``name``.py."""
    path = SCRIPTS / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"paper_figures.{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main


def run(names, options: list) -> None:
    """Call each script's ``main(options)``, announcing it first."""
    for name in names:
        print(f"== paper_figures/{name}.py", flush=True)
        script_main(name)(list(options))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true",
                        help="every script of paper_figures/, the studies beyond the chapter included")
    parser.add_argument("--out", type=Path, help="directory for the figures (each script's --out)")
    parser.add_argument("--results", type=Path, help="directory for the result files (each script's --results)")
    args = parser.parse_args(argv)
    with cli.user_errors_reported():  # checked once here, before any script runs
        for flag, directory in (("--out", args.out), ("--results", args.results)):
            if directory is not None:
                atomic.check_writable_directory(directory, flag)
    options = [item for flag, value in (("--out", args.out), ("--results", args.results)) if value is not None
               for item in (flag, str(value))]
    runs.reuse_batches(REUSED_BYTES)
    run(every_script() if args.all else CHAPTER, options)  # a script's user error exits with status 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
