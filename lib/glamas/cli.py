"""The command line shared by the figure scripts in ``paper_figures/``."""

import argparse
import contextlib
import dataclasses
from pathlib import Path

from glamas import plotting, results
from glamas import runs as runners  # "runs" is the run count in figure_parser
from glamas.paths import REPO, RESULTS

DEFAULT_OUT = REPO / "paper_figures" / "output"


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _seed(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {value}")
    return value


def figure_parser(description: str, *, runs: int, iterations: int | None, seed: int = 0):
    """An argument parser with --runs, --iterations, --seed, --workers, --backend, --scheduler,
    --out, --results, --force and --rerun.

    ``iterations`` None leaves --iterations out (for figures without an iteration count).
    """
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--runs", type=_positive_int, default=runs,
                        help=f"independent runs to average (default {runs})")
    if iterations is not None:
        parser.add_argument("--iterations", type=_positive_int, default=iterations,
                            help=f"learning iterations per run (default {iterations})")
    parser.add_argument("--seed", type=_seed, default=seed, help=f"master seed (default {seed})")
    parser.add_argument("--workers", type=_positive_int, default=None,
                        help="worker processes (threads with --backend threads) for the runs "
                             "(default: one per core); results do not depend on it")
    parser.add_argument("--backend", choices=runners.BACKENDS, default=None,
                        help="who runs the runs: local processes (default), threads in this "
                             "process, or a Dask cluster; results are bit-identical")
    parser.add_argument("--scheduler", metavar="ADDRESS", default=None,
                        help="address of a Dask scheduler (e.g. tcp://HOST:8786); implies --backend dask")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT,
                        help=f"directory for the PNG and PDF (default {DEFAULT_OUT.relative_to(REPO)})")
    parser.add_argument("--results", type=Path, default=RESULTS,
                        help=f"directory for the result file (default {RESULTS.relative_to(REPO)})")
    parser.add_argument("--force", action="store_true",
                        help="replace a result file that another configuration made")
    parser.add_argument("--rerun", action="store_true",
                        help="run the experiment even if --results holds a result of this configuration")
    return parser


def parse(parser: argparse.ArgumentParser, argv=None) -> argparse.Namespace:
    """Parse ``argv``; reject an --out that exists and is not a directory.

    ``args.workers`` becomes what the experiments' ``run(..., workers=)`` takes: a
    :mod:`glamas.runs` backend.
    """
    args = parser.parse_args(argv)
    if "backend" in args:
        try:
            args.workers = runners.backend(args.backend, args.workers, args.scheduler)
            if isinstance(args.workers, runners.Dask):
                runners.connect(args.workers).close()  # an unreachable scheduler fails here, not mid-way
        except (ValueError, runners.BackendError) as error:
            parser.error(str(error))
    for option in ("out", "results"):
        path = getattr(args, option)
        if path.exists() and not path.is_dir():
            parser.error(f"--{option} {path} exists and is not a directory; give a directory path")
    return args


def load_or_run(args: argparse.Namespace, name: str, config, run, result_type):
    """The result of ``config``: read from --results when a file of this configuration is there
    (unless --rerun), otherwise ``run(config, seed=, workers=, progress=)`` and saved.

    Figures drawn from one experiment share its result file instead of running it again.
    ``result_type`` is a dataclass of arrays; a field named ``config`` is not stored as an array
    but is the configuration the file is checked against.
    """
    path = args.results / f"{name}.npz"
    carries_config = "config" in {f.name for f in dataclasses.fields(result_type)}
    if path.exists() and not (args.rerun or args.force):
        with contextlib.suppress(results.ResultFileError):  # unusable: refused just below
            arrays = results.load(path, config, seed=args.seed)
            return result_type(config=config, **arrays) if carries_config else result_type(**arrays)
    if not args.force:
        try:
            results.check_writable(path, config, seed=args.seed)
        except results.ResultFileError as error:
            raise SystemExit(f"error: {error} (--force)") from None
    result = run(config, seed=args.seed, workers=args.workers, progress=name)
    arrays = {f.name: getattr(result, f.name) for f in dataclasses.fields(result) if f.name != "config"}
    results.save(path, config, arrays, seed=args.seed, overwrite=True)
    return result


def write_outputs(args: argparse.Namespace, name: str, fig, config, arrays: dict) -> list[Path]:
    """Save the figure (PNG, PDF) to --out and the result arrays with their config to --results."""
    written = plotting.save_figure(fig, args.out, name)
    written.append(results.save(args.results / f"{name}.npz", config, arrays, seed=args.seed,
                                overwrite=args.force))
    return written
