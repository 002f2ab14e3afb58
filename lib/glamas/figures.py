"""What every figure script of ``paper_figures/`` does: parse the shared options, load the
experiment's result or run it, draw, save.

A script names the experiment its figure is drawn from, the figure and its size, and draws::

    def main(argv=None):
        with figures.figure(gridworld.EXPERIMENT, "fig11a", __doc__, argv) as (ax, result, config):
            gridworld.plot_steps(ax, result, gridworld.optimum(config))

:func:`figure` parses the command line of :func:`glamas.cli.figure_parser` at the
experiment's paper-scale defaults, reads the result from --results when a file of this
configuration is there or runs the experiment and saves its result there (:func:`load_or_run`;
--rerun runs it anyway), hands the drawing its axes, and saves the figure (PNG and PDF) to --out.
:func:`fixed_figure` does the same for a figure that runs no experiment (the map, a table of
settings). Either turns a user error into one line ``error: ...`` and exit status 2.
"""

import contextlib

import matplotlib
import matplotlib.pyplot as plt

from glamas import cli, errors, overrides, plotting, results
from glamas.errors import UserError
from glamas.experiments.registry import Experiment


@contextlib.contextmanager
def figure(experiment: Experiment, name: str, description: str, argv=None, size: tuple = (6.0, 4.0), *,
           nrows: int = 1, ncols: int = 1, min_runs: int = 1, claims: list = ()):
    """Figure ``name`` drawn from ``experiment``: parses ``argv`` (:func:`parse`; ``description``
    is the script's docstring), loads or runs the experiment (:func:`load_or_run`), yields
    ``(axes, result, config)`` to draw on (the axes of :func:`glamas.plotting.new_figure` for
    ``size`` in inches, ``nrows`` by ``ncols``), then saves the figure to --out. ``claims``
    (glamas.claims.Claim) are judged on this figure: their levels must be drawn
    (:func:`glamas.plotting.shows_claims`)."""
    with errors.reported():
        args, config = parse(description, experiment, argv, min_runs)
        result = load_or_run(args, experiment, config)
        with _saved(name, args.out, size, nrows, ncols, claims) as axes:
            yield axes, result, config


def parse(description: str, experiment: Experiment, argv=None, min_runs: int = 1):
    """The shared options at ``experiment``'s paper-scale defaults, parsed (:func:`glamas.cli.parse`),
    and the experiment's configuration at --runs and --iterations (and --map, --learners and --set,
    :mod:`glamas.overrides`): ``(args, config)``.
    ``description`` is the script's docstring; its first paragraph is the --help text."""
    parser = cli.figure_parser(_summary(description), runs=experiment.runs, iterations=experiment.iterations,
                               maps=experiment.map_field is not None,
                               settings=[entry for entry in overrides.settable(experiment.paper_scale())
                                         if entry.partition("=")[0] not in overrides.OWN_OPTIONS],
                               counts=experiment.counts)
    args = cli.parse(parser, argv)
    if args.runs < min_runs:
        parser.error(f"--runs must be at least {min_runs}: the figure shows {min_runs} runs")
    config = experiment.configure(args.runs, args.iterations)
    if getattr(args, "map", None) is not None:
        config = experiment.on_map(config, args.map)
    try:
        if args.learners is not None:
            config = overrides.with_learners(config, args.learners)
        for assignment in args.set or ():
            overrides.check_not_own(assignment)
            config = overrides.with_setting(config, assignment)
    except UserError as error:
        parser.error(str(error))
    return args, config


def load_or_run(args, experiment: Experiment, config):
    """The result of ``config``: read from --results when a file of this configuration is there
    (unless --rerun or --force), otherwise run (:func:`glamas.cli.run_experiment`) and saved there.

    Figures drawn from one experiment share its result file instead of running it again. A file
    of this configuration made with another map or library version is refused as stale (--rerun),
    an unreadable one as unreadable (--rerun or --force replaces it); one of another configuration
    is refused before the run (unless --force replaces it). With --no-compute (``make figures``)
    nothing runs: a missing file is refused too, its message naming the script that computes it.
    """
    path = experiment.file(args.results)
    if args.no_compute:
        return experiment.load(args.results, config, args.seed)
    if path.exists() and not (args.rerun or args.force):
        try:
            return experiment.load(args.results, config, args.seed)
        except (results.StaleResultError, results.UnreadableResultError):
            raise
        except results.ResultFileError:
            pass  # another configuration's: run_experiment refuses it before running
    result = cli.run_experiment(args, experiment.name, config, experiment.run, experiment.copies)
    results.save(path, config, experiment.arrays(result), seed=args.seed, overwrite=args.force,
                 replace_unreadable=args.rerun)
    return result


@contextlib.contextmanager
def fixed_figure(name: str, description: str, argv=None, size: tuple = (6.0, 4.0), *, nrows: int = 1,
                 ncols: int = 1):
    """Figure ``name`` of no experiment (it depends on no run, no seed): yields the axes to draw
    on, then saves it to --out, the only one of the shared options it uses."""
    with errors.reported():
        args = cli.parse(cli.figure_parser(_summary(description)), argv)
        with _saved(name, args.out, size, nrows, ncols) as axes:
            yield axes


@contextlib.contextmanager
def _saved(name: str, out, size: tuple, nrows: int, ncols: int, claims: list = ()):
    """New axes (of a figure showing ``claims``); once drawn, the figure saved as ``name`` (PNG and
    PDF) in ``out`` and the paths printed. The figure is closed in any case: a script's ``main``
    may be called many times."""
    matplotlib.use("Agg")  # into files, never on a screen; here, not at import: notebooks import the experiments
    fig, axes = plotting.new_figure(*size, nrows=nrows, ncols=ncols)
    plotting.shows_claims(fig, claims)
    try:
        yield axes
        for path in plotting.save_figure(fig, out, name):
            print(path)
    finally:
        plt.close(fig)


def _summary(docstring: str) -> str:
    """The first paragraph of a script's docstring, on one line."""
    return " ".join(docstring.strip().split("\n\n")[0].split())
