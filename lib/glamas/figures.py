"""What every figure script of ``paper_figures/`` does: parse the shared options, load the
experiment's result or run it, draw, save.

A script names the experiment its figure is drawn from, the figure and its size, and draws::

    def main(argv=None):
        with gridworld.STUDY.figure("fig11a", __doc__, argv) as (ax, result, config):
            gridworld.plot_steps(ax, result, gridworld.optimum(config))

:meth:`Experiment.figure` parses the command line of :func:`glamas.cli.figure_parser` at the
experiment's paper-scale defaults, reads the result from --results when a file of this
configuration is there or runs the experiment and saves its result there (:func:`load_or_run`;
--rerun runs it anyway), hands the drawing its axes, and saves the figure (PNG and PDF) to --out.
:func:`fixed_figure` does the same for a figure that runs no experiment (the map, a table of
settings). Either turns a user error into one line ``error: ...`` and exit status 2.
"""

import contextlib
import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import matplotlib
import matplotlib.pyplot as plt

from glamas import cli, plotting, results


@dataclass(frozen=True)
class Experiment:
    """An experiment as the figure scripts run it and store its result."""

    name: str
    """Its result file in --results is ``name.npz``, shared by every figure drawn from it."""
    run: Callable
    """``run(config, seed=, workers=, progress=)``: the result of a configuration."""
    runs: int
    """The paper-scale --runs."""
    iterations: int
    """The paper-scale --iterations (learning iterations or episodes per run)."""
    configure: Callable
    """``configure(runs, iterations)``: the configuration at the command line's scale."""
    result: type | None = None
    """The dataclass of arrays :attr:`run` returns; a field named ``config`` is the configuration,
    which the file keeps as its header, not as an array. None with :attr:`to_arrays` and
    :attr:`from_arrays` for a result of another kind."""
    copies: int = 1
    """How many results of the configuration one run makes (for the memory check before it)."""
    to_arrays: Callable | None = None
    """``to_arrays(result) -> dict`` for a result that is not one dataclass of arrays."""
    from_arrays: Callable | None = None
    """``from_arrays(config, arrays) -> result``, the inverse of :attr:`to_arrays`."""

    def arrays(self, result) -> dict:
        """The arrays of ``result`` its file stores."""
        if self.to_arrays is not None:
            return self.to_arrays(result)
        return {f.name: getattr(result, f.name) for f in dataclasses.fields(result) if f.name != "config"}

    def result_of(self, config, arrays: dict):
        """The result that a file of ``config`` holding ``arrays`` stores."""
        if self.from_arrays is not None:
            return self.from_arrays(config, arrays)
        carries_config = "config" in {f.name for f in dataclasses.fields(self.result)}
        return self.result(config=config, **arrays) if carries_config else self.result(**arrays)

    def paper_scale(self):
        """The configuration of the committed result (the paper-scale --runs and --iterations)."""
        return self.configure(self.runs, self.iterations)

    def file(self, directory) -> Path:
        """Its result file in ``directory``."""
        return Path(directory) / f"{self.name}.npz"

    def load(self, directory, config, seed: int):
        """The result of ``config`` and master ``seed`` in ``directory``, its configuration and
        provenance checked (:func:`glamas.results.load`)."""
        return self.result_of(config, results.load(self.file(directory), config, seed=seed))

    @contextlib.contextmanager
    def figure(self, name: str, description: str, argv=None, size: tuple = (6.0, 4.0), *,
               nrows: int = 1, ncols: int = 1, min_runs: int = 1):
        """Figure ``name`` drawn from this experiment: parses ``argv`` (:func:`parse`; ``description``
        is the script's docstring), loads or runs the experiment (:func:`load_or_run`), yields
        ``(axes, result, config)`` to draw on (the axes of :func:`glamas.plotting.new_figure` for
        ``size`` in inches, ``nrows`` by ``ncols``), then saves the figure to --out."""
        with cli.user_errors_reported():
            args, config = parse(description, self, argv, min_runs)
            result = load_or_run(args, self, config)
            with _saved(name, args.out, size, nrows, ncols) as axes:
                yield axes, result, config


def parse(description: str, experiment: Experiment, argv=None, min_runs: int = 1):
    """The shared options at ``experiment``'s paper-scale defaults, parsed (:func:`glamas.cli.parse`),
    and the experiment's configuration at --runs and --iterations: ``(args, config)``.
    ``description`` is the script's docstring; its first paragraph is the --help text."""
    parser = cli.figure_parser(_summary(description), runs=experiment.runs, iterations=experiment.iterations)
    args = cli.parse(parser, argv)
    if args.runs < min_runs:
        parser.error(f"--runs must be at least {min_runs}: the figure shows {min_runs} runs")
    return args, experiment.configure(args.runs, args.iterations)


def load_or_run(args, experiment: Experiment, config):
    """The result of ``config``: read from --results when a file of this configuration is there
    (unless --rerun or --force), otherwise run (:func:`glamas.cli.run_experiment`) and saved there.

    Figures drawn from one experiment share its result file instead of running it again. A file
    of this configuration made with another map or library version is refused as stale (--rerun);
    one of another configuration is refused before the run (unless --force replaces it).
    """
    path = experiment.file(args.results)
    if path.exists() and not (args.rerun or args.force):
        try:
            return experiment.load(args.results, config, args.seed)
        except results.StaleResultError:
            raise
        except results.ResultFileError:
            pass  # another configuration's or unreadable: run_experiment refuses it before running
    result = cli.run_experiment(args, experiment.name, config, experiment.run, experiment.copies)
    results.save(path, config, experiment.arrays(result), seed=args.seed, overwrite=args.force)
    return result


@contextlib.contextmanager
def fixed_figure(name: str, description: str, argv=None, size: tuple = (6.0, 4.0), *, nrows: int = 1,
                 ncols: int = 1):
    """Figure ``name`` of no experiment (it depends on no run, no seed): yields the axes to draw
    on, then saves it to --out, the only one of the shared options it uses."""
    with cli.user_errors_reported():
        args = cli.parse(cli.figure_parser(_summary(description)), argv)
        with _saved(name, args.out, size, nrows, ncols) as axes:
            yield axes


@contextlib.contextmanager
def _saved(name: str, out, size: tuple, nrows: int, ncols: int):
    """New axes; once drawn, the figure saved as ``name`` (PNG and PDF) in ``out`` and the paths
    printed. The figure is closed in any case: a script's ``main`` may be called many times."""
    matplotlib.use("Agg")  # into files, never on a screen; here, not at import: notebooks import the experiments
    fig, axes = plotting.new_figure(*size, nrows=nrows, ncols=ncols)
    try:
        yield axes
        for path in plotting.save_figure(fig, out, name):
            print(path)
    finally:
        plt.close(fig)


def _summary(docstring: str) -> str:
    """The first paragraph of a script's docstring, on one line."""
    return " ".join(docstring.strip().split("\n\n")[0].split())
