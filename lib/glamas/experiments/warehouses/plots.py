"""The benchmark of instances drawn: the greedy policies' share of agents in (ISR) and of episodes
with every agent in (CSR) against N, per formulation, each with its 95 % interval over instances;
and the learning curves' ISR at one N."""

import numpy as np

from glamas import plotting
from glamas.experiments.warehouses.analysis import summary
from glamas.experiments.warehouses.experiment import WarehousesResult
from glamas.learners import registry


def plot_greedy(axes, result: WarehousesResult, measure: str = "isr"):
    """One panel per formulation: ``measure`` of :func:`summary` ('isr' or 'csr') of every learner
    against N (log scale), the mean over instances with its interval as error bars."""
    for ax, formulation in zip(axes, result.formulations.tolist()):
        for k, learner in enumerate(result.names()):
            points = [(n, summary(result, formulation, n, learner)) for n in result.agents.tolist()]
            points = [(n, found[measure]) for n, found in points if found is not None]
            if not points:
                continue
            n = np.array([p[0] for p in points], dtype=float) * 1.04 ** (k - (len(result.names()) - 1) / 2)
            mean, low, high = (np.array([p[1][j] for p in points]) for j in range(3))
            ax.errorbar(n, mean, yerr=[mean - low, high - mean], capsize=3,
                        label=registry.label(learner), **plotting.learner_style(learner, marker=True))
        ax.set_xscale("log")
        ax.set_xticks(result.agents.tolist(), [str(n) for n in result.agents.tolist()])
        ax.minorticks_off()
        ax.set_ylim(-0.03, 1.03)
        ax.set_xlabel("agents N")
        ax.set_ylabel(f"greedy {measure.upper()} (mean over instances)")
        ax.set_title(f"{formulation} formulation")


def plot_curves(axes, result: WarehousesResult, n: int, metric: str = "in_goal"):
    """One panel per formulation: the learning curves' ``metric`` at ``n`` agents, the mean over
    instances with its 95 % band."""
    episodes = result.block_ends()
    for ax, formulation in zip(axes, result.formulations.tolist()):
        for learner in result.names():
            if not result.ran[result.index(formulation, n, learner)]:
                continue
            plotting.plot_mean_band(ax, episodes, result.curve_metric(formulation, n, learner, metric),
                                    registry.label(learner), **plotting.learner_style(learner))
        ax.set_ylim(-0.03, 1.03)
        ax.set_xlabel("episode")
        ax.set_ylabel("ISR while learning" if metric == "in_goal" else metric)
        ax.set_title(f"N = {n}, {formulation} formulation")
