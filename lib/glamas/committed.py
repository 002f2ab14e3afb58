"""The committed results (``data/results``) and figures (``paper_figures/output``), and what makes
each of them again.

A message about a missing, stale or damaged committed file gives this advice rather than a
generic "--rerun" or "delete it": the figure script that recomputes the file, or ``git checkout``
of the committed version. Deleting a committed file would only leave git with a change to undo.
"""

from pathlib import Path

from glamas.paths import FIGURES, REPO, RESULTS, SCRIPTS

SCRIPTS_OF: dict = {}
"""Result file name (``gridworld.npz``) -> the figure scripts of its experiment, in order: filled
by :func:`glamas.experiments.registry.register` as each experiment registers, so that this module,
which result files use, stands below the experiments."""
PYTHON = ".venv/bin/python"
"""The interpreter a message's command names: the one ``make`` installs, so that the command runs as
written from the repository root."""
RUNS_ITS_EXPERIMENT = "figures.figure("
"""What the source of a figure script that runs its experiment calls (the others call
figures.fixed_figure: a map, a table of settings)."""


def advice(path, option: str = "--rerun") -> str | None:
    """How to make ``path`` again when it is a committed result file (:func:`result_advice`) or
    figure (:func:`figure_advice`); None for any other path."""
    path = Path(path)
    directory = path.parent.resolve()
    if directory == RESULTS.resolve():
        return result_advice(path.name, option)
    if directory == FIGURES.resolve():
        return figure_advice(path.name)
    return None


def result_advice(name: str, option: str = "--rerun") -> str:
    """How to make the committed result file ``name`` again: the figure script that computes it,
    run with ``option`` (--rerun), or git checkout. Where the file is of another configuration
    (``option`` --force) the advice never replaces it: the run goes to another --results."""
    restore = f"restore the committed one with `git checkout -- {shown(RESULTS / name)}`"
    script = computing_script(name)
    if script is None:
        return restore
    if option == "--force":
        return (f"give the run another --results directory (for example `{PYTHON} {shown(SCRIPTS / script)}.py "
                f"--results out/results` at the paper scale), or {restore}")
    return f"recompute it with `{PYTHON} {shown(SCRIPTS / script)}.py {option}`, or {restore}"


def figure_advice(name: str) -> str:
    """How to make the committed figure ``name`` (``fig11a.png``) again: its script, or git checkout."""
    restore = f"restore the committed one with `git checkout -- {shown(FIGURES / name)}`"
    script = SCRIPTS / f"{Path(name).stem}.py"
    return f"draw it again with `{PYTHON} {shown(script)}`, or {restore}" if script.is_file() else restore


def stale_advice(name: str) -> str:
    """How to make the committed result file ``name``, stale after a change of code, current again:
    re-recorded when the change kept its behaviour (:mod:`glamas.small_runs`), else recomputed."""
    script = computing_script(name)
    recompute = f"`{PYTHON} {shown(SCRIPTS / script)}.py --rerun`" if script else "its experiment run again"
    return (f"if the change kept what it computes, `{PYTHON} -m glamas.small_runs --adopt {Path(name).stem}` records "
            f"it with this code in seconds (it checks its small run); otherwise recompute it with {recompute}")


def computing_script(result_file: str) -> str | None:
    """The figure script (its name, ``fig11a``) that computes the result file ``result_file``
    (``gridworld.npz``): the first of its experiment's scripts that runs the experiment; None for a
    file of no registered experiment (:data:`SCRIPTS_OF`)."""
    return next((name for name in SCRIPTS_OF.get(result_file, ())
                 if RUNS_ITS_EXPERIMENT in (SCRIPTS / f"{name}.py").read_text()), None)


def shown(path: Path) -> str:
    """``path`` relative to the repository when it is inside it (as a reader types it there)."""
    return str(path.relative_to(REPO)) if path.is_relative_to(REPO) else str(path)
