"""The scaling study's figures, each on a given matplotlib Axes: the values stored per run against
the number of agents, the final performance against it, and the learning curves at one N."""

import math

import numpy as np

from glamas.experiments.scaling.analysis import final_with_band
from glamas.experiments.scaling.experiment import ScalingConfig, ScalingResult, label
from glamas.learners.spec import BYTES_PER_VALUE
from glamas.plotting import (data_bounds, greedy_legend_entry, learner_style, legend_right, mark_greedy,
                             plot_mean_band)
from glamas.errors import UserError


MACHINE_MEMORY_GIB = 24
"""A workstation's memory, 24 GiB, drawn for scale: one run's tables beyond it fit no such machine."""
COINCIDE = 1.1
"""Methods whose stored values stay within this factor of each other at every N draw on one line
on a log axis: :func:`plot_sizes` sets them side by side and says so."""
DODGE = 0.1
"""Horizontal distance, in agents, between methods drawn side by side at one N."""
OFF_SCALE_DECADES = 20
""":func:`plot_sizes`' axis reaches this many decades above the most any learner that ran stores
(or the workstation's memory, if more); a skipped learner's table beyond it (10^85 values) is an
open triangle at the axis' top, its size in the legend: drawn at its value, it would squeeze every
learner that ran into the bottom of the axis."""


def plot_sizes(ax, result: ScalingResult, config: ScalingConfig | None = None, legend: bool = True):
    """Values learned per run (Q entries + GLA parameters) against N (log scale): filled markers
    where the learner ran, open markers where its tables were only computed (skipped), with the
    24 GiB workstation's memory for one run and the study's memory budget if ``config`` is given.
    Methods that store nearly the same (within COINCIDE) are drawn side by side, with a note."""
    params = result.parameters()
    shifts, groups = _coinciding_shifts(params)
    workstation = MACHINE_MEMORY_GIB * 2 ** 30 / BYTES_PER_VALUE
    top = 10.0 ** OFF_SCALE_DECADES * max(workstation, params[result.ran & np.isfinite(params)].max(initial=0.0))
    off = ~(params <= top)  # beyond the axis, or too many to count (infinite)
    for k, method in enumerate(result.names()):
        x = result.agents + shifts[k]
        ax.plot(x, params[k], "-", **learner_style(method))
        ax.plot([], [], "-", label=label(method), **learner_style(method, marker=True))  # the legend's entry
        ok, shown = result.ran[k], ~off[k]
        ax.plot(x[ok & shown], params[k, ok & shown], linestyle="none", **learner_style(method, marker=True))
        ax.plot(x[~ok & shown], params[k, ~ok & shown], linestyle="none", mfc="none",
                **learner_style(method, marker=True))
        if off[k].any():
            sizes = ", ".join(f"10^{math.log10(math.prod(result.shape(method, n))):.0f} (N = {n})"
                              for n in result.agents[off[k]])
            ax.plot([], [], " ", label=f"off the axis: {label(method)}, about {sizes} values")
    ax.plot([], [], "o", color="0.4", mfc="none", linestyle="none", label="open: skipped (tables computed, not run)")
    ax.axhline(workstation, color="black", linestyle=":", linewidth=1,
               label=f"a {MACHINE_MEMORY_GIB} GiB workstation, one run")
    if config is not None:
        entries = config.memory_budget_gib * 2 ** 30 / BYTES_PER_VALUE / config.runs
        ax.axhline(entries, color="black", linestyle="--", linewidth=1,
                   label=f"memory budget ({config.memory_budget_gib:g} GiB for {config.runs} runs)")
    ax.set_yscale("log")
    if np.isfinite(params[off]).any():  # a table beyond the axis: at its top, as an open triangle
        ax.set_ylim(top=top)
        for j, n in enumerate(result.agents):  # the methods off the axis at one N side by side
            beyond = np.flatnonzero(off[:, j])
            for i, k in enumerate(beyond):
                ax.plot(n * (1 + DODGE * (i - (beyond.size - 1) / 2)), top, linestyle="none", clip_on=False,
                        mfc="none", **{**learner_style(result.names()[k]), "marker": "^"})
        ax.plot([], [], "^", color="0.4", mfc="none", linestyle="none",
                label="open triangle at the top: off the axis")
    _agents_axis(ax, result)
    ax.set_ylabel("values stored per run")
    if groups:
        names = "; ".join(" = ".join(label(result.names()[k]) for k in group) for group in groups)
        ax.set_title(f"drawn side by side, as they store within {COINCIDE - 1:.0%} of each other at every N:\n{names}",
                     fontsize="small", pad=10)  # clear of the top tick label
    if legend:
        legend_right(ax)


def _agents_axis(ax, result: ScalingResult):
    """The x axis of the numbers of agents: linear for a few, doubling (log base 2) for many."""
    if result.agents.max() > 8 * result.agents.min():
        ax.set_xscale("log", base=2)
    ax.set_xticks(result.agents, [str(n) for n in result.agents])
    ax.set_xlabel("agents N")


GREEDY_LABELS = {"steps": "greedy policy: steps to goal (agent mean)", "collisions": "greedy policy: collisions per episode",
                 "completion": "greedy policy: episodes completed", "reward": "greedy policy: reward (agent mean)"}


def plot_greedy(ax, result: ScalingResult, metric: str, legend: bool = True):
    """Every method's greedy policy after training against N (mean and range over runs, at the N it
    ran at): ``metric`` of GREEDY_LABELS (``completion``: the share of episodes that end with every
    agent in its goal)."""
    if metric not in GREEDY_LABELS:
        raise UserError(f"metric must be one of {sorted(GREEDY_LABELS)}, got {metric!r}")
    for k, method in enumerate(result.names()):
        ns = [int(n) for n, ok in zip(result.agents, result.ran[k]) if ok]
        if not ns:
            continue
        values = [result.evaluation(method, n, metric) for n in ns]
        mean = np.array([v.mean() for v in values])
        ax.errorbar(ns, mean, yerr=[mean - [v.min() for v in values], [v.max() for v in values] - mean], capsize=2,
                    linewidth=1.2, label=label(method), **learner_style(method, marker=True))
    _agents_axis(ax, result)
    ax.set_ylabel(GREEDY_LABELS[metric])
    if metric == "completion":
        data_bounds(ax, (0.0, 1.0))
    if legend:
        legend_right(ax)


def _coinciding_shifts(params: np.ndarray) -> tuple[np.ndarray, list[list[int]]]:
    """Horizontal shifts (methods,) that set apart the methods storing within COINCIDE of each
    other at every N, and those groups of method indices (groups of two or more)."""
    groups: list[list[int]] = []
    for k in range(params.shape[0]):
        for group in groups:
            if np.all(np.maximum(params[k], params[group[0]]) <= COINCIDE * np.minimum(params[k], params[group[0]])):
                group.append(k)
                break
        else:
            groups.append([k])
    shifts = np.zeros(params.shape[0])
    for group in groups:
        for i, k in enumerate(group):
            shifts[k] = DODGE * (i - (len(group) - 1) / 2)
    return shifts, [group for group in groups if len(group) > 1]


_METRIC_LABELS = {"steps": "final steps to goal (agent mean)", "reward": "final reward (agent mean)",
                  "collisions": "final collisions per episode", "coordinations": "final coordinations per episode",
                  "convergence": "episodes until within 5 % of final steps"}


def plot_final(ax, result: ScalingResult, metric: str, legend: bool = True):
    """One final measurement ('steps', 'reward', 'collisions', 'coordinations' or 'convergence')
    against N for every method, at the N each method ran at: the value of :func:`measure` with its
    95 % bootstrap interval over runs, the methods side by side at each N. Convergence: a method
    still outside 5 % of its final steps in the last block never settled; it is drawn as an open
    triangle above the end of the runs, not as a number of episodes."""
    if metric not in _METRIC_LABELS:
        raise UserError(f"metric must be one of {sorted(_METRIC_LABELS)}, got {metric!r}")
    names = result.names()
    never_settled = False
    for k, method in enumerate(names):
        ns = np.array([int(n) for n, ok in zip(result.agents, result.ran[k]) if ok], dtype=float)
        if not ns.size:
            continue
        value, low, high = np.array([final_with_band(result, method, int(n), metric) for n in ns]).T
        x = ns + DODGE * 0.5 * (k - (len(names) - 1) / 2)
        unsettled = (value >= result.episodes[-1]) if metric == "convergence" else np.zeros(ns.size, bool)
        shown = np.where(unsettled, np.nan, value)
        # a statistic that is not a mean (the convergence episode) can lie outside its percentile
        # interval: the bar then ends at the value
        below = np.fmax(shown - np.where(unsettled, np.nan, low), 0.0)
        above = np.fmax(np.where(unsettled, np.nan, high) - shown, 0.0)
        ax.errorbar(x, shown, yerr=[below, above],
                    capsize=2, linewidth=1.2, label=label(method), **learner_style(method, marker=True))
        if unsettled.any():
            never_settled = True
            ax.plot(x[unsettled], np.full(unsettled.sum(), result.episodes[-1] * 1.05), linestyle="none",
                    mfc="none", markersize=7, **{**learner_style(method), "marker": "^"})
    if never_settled:
        _mark_never_settled(ax, result.episodes[-1])
    if metric in GREEDY_METRICS:
        _mark_greedy(ax, result, metric)
    ax.set_xticks(result.agents)
    ax.set_xlabel("agents N")
    ax.set_ylabel(_METRIC_LABELS[metric])
    if legend:
        legend_right(ax)


GREEDY_METRICS = ("steps", "reward", "collisions", "coordinations")
"""The measurements :func:`plot_final` also shows for the greedy policy after training."""


def _mark_greedy(ax, result: ScalingResult, metric: str):
    """Every method's ``metric`` under the greedy evaluation of what it learned (mean over runs),
    beside its final learning-curve value at each N it ran at (:func:`glamas.plotting.mark_greedy`)."""
    names = result.names()
    for k, method in enumerate(names):
        ns = [int(n) for n, ok in zip(result.agents, result.ran[k]) if ok]
        x = np.array(ns) + DODGE * 0.5 * (k - (len(names) - 1) / 2) + DODGE / 4
        mark_greedy(ax, x, [result.evaluation(method, n, metric).mean() for n in ns], method)
    greedy_legend_entry(ax)


def _mark_never_settled(ax, last: int):
    """The end of the runs as a line, and what the open triangles above it mean."""
    ax.axhline(last, color="black", linestyle=":", linewidth=1)
    ax.set_ylim(top=last * 1.18)
    ax.text(0.01, last * 1.13, "open triangles: never settled within 5 % (not a number of episodes)",
            transform=ax.get_yaxis_transform(), fontsize="x-small", va="center")


CURVE_LABELS = {"steps": "steps to goal (agent mean)", "reward": "reward (agent mean)",
                "collisions": "collisions per episode", "coordinations": "coordinations per episode",
                "capped": "capped episodes", "length": "steps until every agent is in (episode length)"}
"""The y axis of :func:`plot_curves` for each of METRICS."""


def plot_curves(ax, result: ScalingResult, n: int, metric: str = "steps", legend: bool = True):
    """Learning curves (mean and 95 % band over runs) of every method that ran with ``n`` agents."""
    if n not in result.agents:
        raise UserError(f"no results for N = {n}; the study has N in {result.agents.tolist()}")
    j = list(result.agents).index(n)
    for k, method in enumerate(result.names()):
        if result.ran[k, j]:
            plot_mean_band(ax, result.episodes, result.curves(method, n, metric), label(method),
                           **learner_style(method))
    ax.set_xscale("log")
    ax.set_xlabel("episode")
    ax.set_ylabel(f"{CURVE_LABELS[metric]}, N = {n}")
    if legend:
        legend_right(ax)
