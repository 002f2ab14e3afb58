"""The command line shared by the figure scripts in ``paper_figures/`` (:mod:`glamas.figures`).

Output policy: a run at the paper-scale defaults (the --runs, --iterations, --seed and --map the
script was made with) writes to ``paper_figures/output`` and ``data/results``; any other run writes
to a directory of its settings under ``out/figures`` and ``out/results`` (git-ignored; for example
``out/results/runs=2,map=isr``) unless --out or --results say where, so a reduced run never
replaces the committed outputs and runs of other settings never share a result file. Every user
error stops the script before it computes with one line ``error: ...`` on stderr and exit status
2 (:mod:`glamas.errors`).
"""

import argparse
import contextlib
import hashlib
import re
import sys
from pathlib import Path

from glamas import atomic, memory, parallel, results
from glamas.checks import MAX_COUNT, suspect_settings
from glamas.errors import UserError
from glamas.paths import FIGURES, REPO, RESULTS

DEFAULT_OUT = FIGURES
SCRATCH_OUT = REPO / "out" / "figures"
"""Where the figures of a run that is not at the paper-scale defaults go by default (in the
directory of its settings, :func:`scratch_key`)."""
SCRATCH_RESULTS = REPO / "out" / "results"
"""Where the result files of a run that is not at the paper-scale defaults go by default (in the
directory of its settings, :func:`scratch_key`)."""
PAPER_SCALE_OPTIONS = ("runs", "iterations", "seed", "map", "learners", "set")
"""The options that change a result: at their defaults, a run reproduces the committed outputs."""
MAX_SEED = 2 ** 32 - 1
"""The largest master seed: one 32-bit word of the names that make each run's master seed
(:func:`glamas.seeds.named`)."""
WORKERS_PER_CORE = 4
"""More local workers than this per core only add start-up time and memory."""
NO_EXPERIMENT = "not used: this figure runs no experiment"
"""The help of every option but --out in the parser of a figure that runs no experiment."""


def _whole_number(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None


def _whole_number_in(low: int, high: int, below: str):
    """An argparse type: a whole number from ``low`` to ``high``; ``below`` is the message for a
    smaller one."""
    def whole_number_in(text: str) -> int:
        value = _whole_number(text)
        if value < low:
            raise argparse.ArgumentTypeError(f"{below}, got {value}")
        if value > high:
            raise argparse.ArgumentTypeError(f"must be at most {high}, got {value}")
        return value
    return whole_number_in


positive_count = _positive_int = _whole_number_in(1, MAX_COUNT, "must be at least 1")
"""An argparse type: a whole number of runs, episodes or workers, at least 1 (for every command's options)."""
seed_number = _seed = _whole_number_in(0, MAX_SEED, "must be 0 or more")
"""An argparse type: a master seed, 0 or more."""


def figure_parser(description: str, *, runs: int | None = None, iterations: int | None = None, seed: int = 0,
                  maps: bool = False, settings: list | None = None, counts: str = "iterations"):
    """An argument parser with --runs, --iterations, --seed, --learners, --set, --workers, --backend,
    --scheduler, --out, --results, --force, --rerun and --no-compute, at the paper-scale defaults
    ``runs``, ``iterations`` and ``seed``; with ``maps``, also --map (the experiment runs on a map it
    names). ``settings`` (:func:`glamas.overrides.settable`) is the list --help gives for --set.
    ``counts`` 'episodes' names --iterations --episodes (both names are one option, ``args.iterations``).

    ``runs`` None: a figure that runs no experiment (a map, a table of settings). It takes the same
    options, so that every figure script takes one command line (``make reproduce``, ``make
    verify``), but says in its help that only --out is used.
    """
    experiment = runs is not None
    epilog = ("settings --set reaches, at their paper-scale values: " + "; ".join(settings)) if settings else None
    parser = argparse.ArgumentParser(description=description if experiment else
                                     f"{description} It runs no experiment: only --out changes what it writes.",
                                     epilog=epilog)

    def option(name, help, **kwargs):
        parser.add_argument(name, help=help if experiment else NO_EXPERIMENT, **kwargs)

    option("--runs", type=_positive_int, default=runs, help=f"independent runs to average (default {runs})")
    if counts == "episodes":
        parser.add_argument("--episodes", "--iterations", dest="iterations", metavar="N", type=_positive_int,
                            default=iterations, help=f"episodes per run (default {iterations}; --iterations is "
                                                     "this option's other name)")
    else:
        option("--iterations", type=_positive_int, default=iterations,
               help=f"learning iterations per run (default {iterations})")
    option("--seed", type=_seed, default=seed, help=f"master seed (default {seed})")
    if maps:
        option("--map", default=None, help="the map to run on: a map's name in data/maps (for example isr, "
               "tunnel_to_goal_3) or a map file's path (default: the experiment's own, the paper-scale one)")
    option("--learners", metavar="NAMES", default=None,
           help="the learners to train, comma-separated registered names (default: the experiment's own)")
    option("--set", metavar="PATH=VALUE", action="append", default=None,
           help="any setting of the experiment's configuration, a dataclass in it or a learner's own "
                "(e.g. q.q_learning_rate=0.1, two_observe.gla_learning_rate=0.02); repeatable; the list is below")
    option("--workers", type=_positive_int, default=None,
           help="worker processes (threads with --backend threads) for the runs (default: one per core); "
                "results do not depend on it")
    option("--backend", choices=parallel.BACKENDS, default=None,
           help="who runs the runs: local processes (default), threads in this process, or a Dask "
                "cluster; results are bit-identical")
    option("--scheduler", metavar="ADDRESS", default=None,
           help="address of a Dask scheduler (e.g. tcp://HOST:8786); implies --backend dask")
    scratch = f" at the paper-scale --runs/--iterations/--seed/--map, else {SCRATCH_OUT.relative_to(REPO)}/SETTINGS"
    parser.add_argument("--out", type=Path, default=None, help=f"directory for the PNG and PDF (default "
                        f"{DEFAULT_OUT.relative_to(REPO)}{scratch if experiment else ''})")
    option("--results", type=Path, default=None,
           help=f"directory for the result file (default {RESULTS.relative_to(REPO)} at the paper-scale "
                f"--runs/--iterations/--seed/--map, else {SCRATCH_RESULTS.relative_to(REPO)}/SETTINGS, "
                "SETTINGS naming the options off their defaults, e.g. runs=2,map=isr)")
    option("--force", action="store_true", help="replace a result file that another configuration made")
    option("--rerun", action="store_true",
           help="run the experiment even if --results holds a result of this configuration (or an unreadable file)")
    option("--no-compute", action="store_true",
           help="never run the experiment: draw from the result file in --results, and fail naming the script "
                "that computes it when it is missing (make figures)")
    return parser


def parse(parser: argparse.ArgumentParser, argv=None) -> argparse.Namespace:
    """Parse ``argv``, choose the output directories (see the module's output policy) and check
    they can be written, before anything is computed.

    ``args.workers`` becomes what the experiments' ``run(..., workers=)`` takes: a
    :mod:`glamas.parallel` backend. For a figure that runs no experiment (:func:`figure_parser` without
    ``runs``) only --out is looked at: its figure is the same whatever the other options say.
    """
    args = parser.parse_args(argv)
    if parser.get_default("runs") is None:
        args.out = DEFAULT_OUT if args.out is None else args.out
        _check_directories(parser, args, ("out",))
        return args
    _check_workers(parser, args.workers)
    if args.no_compute and (args.rerun or args.force):
        parser.error("--no-compute never runs the experiment: drop --rerun and --force, or --no-compute")
    try:
        args.workers = parallel.backend(args.backend, args.workers, args.scheduler)
        if isinstance(args.workers, parallel.Dask):
            parallel.connect(args.workers).close()  # an unreachable scheduler fails here, not mid-way
    except UserError as error:
        parser.error(str(error))
    _choose_directories(parser, args)
    _check_directories(parser, args, ("out", "results"))
    return args


def _check_directories(parser, args, options) -> None:
    for option in options:
        try:
            atomic.check_writable_directory(getattr(args, option), f"--{option}")
        except UserError as error:
            parser.error(str(error))


def _check_workers(parser, workers: int | None) -> None:
    limit = WORKERS_PER_CORE * parallel.cores()
    if workers is not None and workers > limit:
        parser.error(f"--workers {workers} is more than {WORKERS_PER_CORE} per core of this machine "
                     f"({parallel.cores()} cores); give at most {limit}, or use a Dask cluster (--scheduler)")


def _choose_directories(parser, args) -> None:
    """Fill in the --out and --results not given, by the output policy (module docstring)."""
    key = scratch_key(parser, args)
    defaults = {"out": DEFAULT_OUT, "results": RESULTS} if not key else \
        {"out": SCRATCH_OUT / key, "results": SCRATCH_RESULTS / key}
    unset = [option for option in defaults if getattr(args, option) is None]
    for option in unset:
        setattr(args, option, defaults[option])
    _refuse_committed(args, key)
    if unset and key:
        print(f"note: not the paper-scale --runs/--iterations/--seed/--map: writing to "
              f"{SCRATCH_OUT.parent.relative_to(REPO)}/ (figures/{key}, results/{key}; --out and --results choose)",
              file=sys.stderr)


def _refuse_committed(args, key: str) -> None:
    """Refuse a run off the paper scale (``key``, :func:`scratch_key`) whose --out or --results is
    the directory of the committed figures or results, however it is spelled (a link included):
    only a run at the paper-scale defaults writes them. The line names where the run would go."""
    if not key:
        return
    for option, kind, committed, scratch in (("out", "figures", DEFAULT_OUT, SCRATCH_OUT),
                                             ("results", "results", RESULTS, SCRATCH_RESULTS)):
        given = getattr(args, option)
        if Path(given).resolve() == committed.resolve():
            raise UserError(f"--{option} {given} is the directory of the committed {kind}, which only a run at "
                            f"the paper-scale settings writes; this run's {kind} go to "
                            f"{(scratch / key).relative_to(REPO)} (leave out --{option})")


def scratch_key(parser: argparse.ArgumentParser, args: argparse.Namespace) -> str:
    """The directory name of a run's settings off the paper scale: each of PAPER_SCALE_OPTIONS that
    differs from its default as ``name=value``, joined by commas ('' at the paper scale; the --set
    assignments joined by '+'). A value with other characters than letters, digits and ``._=,+-``
    (a map's path, a pattern) has them replaced by '_' and a digest of what was given appended, so
    that two settings never share a name."""
    parts = []
    for option in PAPER_SCALE_OPTIONS:
        value = getattr(args, option, None)
        if option in args and value != parser.get_default(option):
            text = "+".join(value) if isinstance(value, list) else str(value)
            plain = re.sub(r"[^\w.=,+-]", "_", text)
            if plain != text:
                plain = f"{plain}-{hashlib.sha256(text.encode()).hexdigest()[:8]}"
            parts.append(f"{option}={plain}")
    return ",".join(parts)


def check_before_run(args: argparse.Namespace, name: str, config, copies: int = 1) -> None:
    """What a run of ``copies`` times ``config`` needs, checked before it computes: no other process
    holds the results directory, its result file ``name`` can take the result (unless --force;
    --rerun replaces an unreadable one), and its arrays fit in memory."""
    atomic.check_unlocked(args.results)
    if not args.force:
        results.check_writable(args.results / f"{name}.npz", config, seed=args.seed, replace_unreadable=args.rerun)
    memory.check(config, copies)


def run_experiment(args: argparse.Namespace, name: str, config, run, copies: int = 1):
    """``run(config, seed=, workers=, progress=name)`` after :func:`check_before_run`; a run that
    leaves the finite numbers names the settings furthest from their defaults."""
    check_before_run(args, name, config, copies)
    with _naming_suspects(config):
        return run(config, seed=args.seed, workers=args.workers, progress=name)


@contextlib.contextmanager
def _naming_suspects(config):
    try:
        yield
    except parallel.NonFiniteError as error:
        suspects = suspect_settings(config)
        if not suspects:
            raise
        raise parallel.NonFiniteError(f"{error}; likely responsible: {suspects}") from None
