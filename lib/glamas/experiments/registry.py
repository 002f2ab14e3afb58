"""Every experiment by name: what the figure scripts, the ledger, ``make reproduce``, ``make verify``,
the small runs and the memory check need to know of one, declared once by the experiment itself.

The face of an experiment's package (its ``__init__``) makes one ``register(Experiment(...))``;
:func:`experiments` imports every package of :mod:`glamas.experiments` and returns what registered,
so that nothing else lists the experiments. This module is data only: it imports no experiment and
no plotting, so that the experiments stand below the figures and the command line that use them.
"""

import dataclasses
import importlib
import pkgutil
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from glamas import committed, results
from glamas.errors import UserError
from glamas.paths import RESULTS

REGISTRY: dict = {}
"""The registered experiments by name, in the order they registered."""
SEED = 0
"""The master seed of the committed results (the figure scripts' default)."""


@dataclass(frozen=True)
class Experiment:
    """One experiment: its configuration, how it runs, how its result is stored and judged, and
    the figure scripts drawn from it."""

    name: str
    """Its key in the claims of ``data/chapter/*.json``; its result file is ``name.npz``."""
    config: type
    """Its configuration class: a frozen dataclass whose ``memory_bytes()`` estimates a run's arrays."""
    run: Callable
    """``run(config, seed=, workers=, progress=)``: the result of a configuration."""
    configure: Callable
    """``configure(runs, iterations)``: the configuration at a command line's --runs and --iterations."""
    runs: int | None = None
    """The paper-scale --runs; None: its configuration class's ``runs``."""
    iterations: int | None = None
    """The paper-scale --iterations (learning iterations or episodes per run); None: its
    configuration class's field named by :attr:`counts`."""
    result: type | None = None
    """The dataclass of arrays :attr:`run` returns; a field named ``config`` is the configuration,
    which the file keeps as its header, not as an array. None with :attr:`to_arrays` and
    :attr:`from_arrays` for a result of another kind."""
    claim_rows: Callable | None = None
    """``claim_rows(result, config)``: the verdict rows of its claims (:func:`glamas.claims.verdicts`);
    None for an experiment without claims."""
    figures: tuple = ()
    """The scripts of ``paper_figures/`` drawn from it, by name: the first to run computes it."""
    chapter: bool = True
    """Whether its figures are the chapter's (``make figures``) or a study beyond it (``--all``)."""
    stored: bool = True
    """Whether its result is stored in a file; False for one computed in a second when needed."""
    copies: int = 1
    """How many results of the configuration one run makes (for the memory check before it)."""
    map_field: str | None = None
    """The dotted path of its configuration's map (``"map"``, ``"gridworld.map"``), which a command
    line's --map sets (:meth:`on_map`); None for an experiment that runs on no map."""
    counts: str | None = None
    """What :attr:`iterations` counts, 'iterations' or 'episodes': its scripts' option is named so
    (``--episodes``, with ``--iterations`` as the same option's other name); None: 'episodes' if its
    configuration class has a field ``episodes``, else 'iterations'."""
    to_arrays: Callable | None = None
    """``to_arrays(result) -> dict`` for a result that is not one dataclass of arrays; None: its
    result class's ``to_arrays``, if it has one."""
    from_arrays: Callable | None = None
    """``from_arrays(config, arrays) -> result``, the inverse of :attr:`to_arrays`; None: its result
    class's ``from_arrays``, if it has one."""
    small_run: dict | None = dataclasses.field(default=None, compare=False)
    """Its small run (:mod:`glamas.small_runs`): ``runs`` and ``iterations`` for :attr:`configure`
    and the configuration's fields replaced after, so that every kernel it runs runs in a second or
    two. None for an experiment not :attr:`stored`."""
    small_run_seconds: float = 1.0
    """About how long its small run takes once the learners' kernels are compiled: the order in
    which :mod:`glamas.precompile` hands the small runs out, the longest first."""
    recompute_minutes: float | None = None
    """About how long its paper-scale recomputation takes on 2 cores (measured), which
    ``small_runs --status`` tells; None where not measured."""

    def __post_init__(self):
        counts = self.counts or ("episodes" if hasattr(self.config, "episodes") else "iterations")
        if counts not in ("iterations", "episodes"):
            raise UserError(f"experiment {self.name!r}: counts must be 'iterations' or 'episodes', got {counts!r}")
        # Frozen: what is left None is read here, once, from the configuration and result classes,
        # so that a face states only what is its own.
        defaults = {"counts": counts, "runs": getattr(self.config, "runs", None),
                    "iterations": getattr(self.config, counts, None),
                    "to_arrays": getattr(self.result, "to_arrays", None), "from_arrays": getattr(self.result, "from_arrays", None)}
        for name, value in defaults.items():
            if getattr(self, name) is None:
                object.__setattr__(self, name, value)
        if not callable(getattr(self.config, "memory_bytes", None)):
            raise TypeError(f"experiment {self.name!r}: its config {self.config.__name__} needs a memory_bytes() "
                            "method, the estimate the memory check makes before a run")

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

    def on_map(self, config, name: str):
        """``config`` with its map (:attr:`map_field`) set to ``name``: a map's name in data/maps or a path."""
        head, _, rest = self.map_field.partition(".")
        if not rest:
            return dataclasses.replace(config, **{head: name})
        inner = Experiment.on_map(dataclasses.replace(self, map_field=rest), getattr(config, head), name)
        return dataclasses.replace(config, **{head: inner})

    def paper_scale(self):
        """The configuration of the committed result (the paper-scale --runs and --iterations)."""
        return self.configure(self.runs, self.iterations)

    def file(self, directory) -> Path:
        """Its result file in ``directory``."""
        return Path(directory) / f"{self.name}.npz"

    def load(self, directory, config, seed: int):
        """The result of ``config`` and master ``seed`` in ``directory``, its configuration and
        provenance checked (:func:`glamas.results.load`); computed when it is not :attr:`stored`."""
        if not isinstance(config, self.config):
            held = " (a result file's path goes in results_dir: its directory)" if isinstance(config, (str, Path)) else ""
            raise UserError(f"loading a result of {self.name} takes its configuration, a {self.config.__name__}, and "
                            f"the directory of its file {self.name}.npz as results_dir{held}; got {config!r}")
        if not self.stored:
            return self.run(config, seed=seed)
        return self.result_of(config, results.load(self.file(directory), config, seed=seed))

    def committed_or_run(self, config, seed: int = SEED):
        """The committed result (:meth:`load` from ``data/results``) when ``config`` is the paper
        scale and ``seed`` the committed :data:`SEED`; else computed (:attr:`run`, at ``config``'s scale)."""
        if (config, seed) == (self.paper_scale(), SEED):
            return self.load(RESULTS, config, seed)
        return self.run(config, seed=seed)


def register(experiment: Experiment) -> Experiment:
    """Make ``experiment`` known by its name. Another experiment of the same name is refused; the
    same module registering the same experiment again (a reload) replaces it."""
    known = REGISTRY.get(experiment.name)
    if known is not None and _identity(known) != _identity(experiment):
        raise UserError(f"an experiment named {experiment.name!r} is registered already (by {known.run.__module__}); "
                        f"{experiment.run.__module__} must choose another name")
    REGISTRY[experiment.name] = experiment
    if experiment.stored:
        committed.SCRIPTS_OF[experiment.file(".").name] = experiment.figures
    return experiment


def _identity(experiment: Experiment) -> tuple:
    """What stays the same when a module registers its experiment again (a reload): the module of
    its run, its configuration's class by name, its figures."""
    return (experiment.run.__module__, experiment.config.__module__, experiment.config.__qualname__,
            tuple(experiment.figures))


def experiments() -> tuple:
    """Every experiment: those each package of :mod:`glamas.experiments` registers in its face
    (imported here, so that an experiment is known by being there; its plots, and matplotlib with
    them, are not) and any registered since; the chapter's first, each part in the order of its
    first figure (:func:`figure_order`)."""
    package = importlib.import_module("glamas.experiments")
    for module in pkgutil.iter_modules(package.__path__, f"{package.__name__}."):
        importlib.import_module(module.name)
    return tuple(sorted(REGISTRY.values(),
                        key=lambda e: (not e.chapter, figure_order(e.figures[0] if e.figures else e.name))))


def figure_order(name: str) -> tuple:
    """The sort key of a figure script's name that puts fig9 before fig9_optimum before fig10."""
    return tuple(int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name))


def figure_scripts(chapter_only: bool = True) -> tuple:
    """The figure scripts of the experiments (of the chapter's only, unless ``chapter_only`` is
    False), in the order they run: the chapter's first, each part in figure order, so that an
    experiment's first figure computes it and the figures after it read its result."""
    known = experiments()
    parts = (True,) if chapter_only else (True, False)
    return tuple(name for chapter in parts
                 for name in sorted((name for e in known if e.chapter == chapter for name in e.figures), key=figure_order))


def result_files() -> tuple:
    """The names of the result files the experiments store (``name.npz``)."""
    return tuple(sorted(f"{experiment.name}.npz" for experiment in experiments() if experiment.stored))
