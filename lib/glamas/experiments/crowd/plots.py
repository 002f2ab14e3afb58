"""The crowd replay drawn: per formulation, 2observe's greedy ISR and its revisits against N, with
the coordination on (solid) and off (dashed) on the same tables, each the mean over instances with
its 95 % interval."""

import numpy as np

from glamas import plotting
from glamas.experiments.crowd.analysis import summary
from glamas.experiments.crowd.experiment import COORDINATION, CrowdResult
from glamas.learners import registry

LINES = {"on": "-", "off": "--"}
"""The line of each replay."""


def plot_crowd(axes, result: CrowdResult, measure: str = "in_goal"):
    """One panel per formulation: ``measure`` ('in_goal' or 'revisits') of every learner and
    coordination against N (log scale), error bars over instances."""
    agents = result.agents.tolist()
    for ax, formulation in zip(axes, result.formulations.tolist()):
        for k, learner in enumerate(result.names()):
            for c, coordination in enumerate(COORDINATION):
                found = [summary(result, formulation, n, learner, coordination)[measure] for n in agents]
                mean, low, high = (np.array([f[j] for f in found]) for j in range(3))
                shift = 1.03 ** (2 * k + c - 1.5)
                style = {**plotting.learner_style(learner, marker=True), "linestyle": LINES[coordination]}
                ax.errorbar(np.array(agents, dtype=float) * shift, mean, yerr=[mean - low, high - mean], capsize=3,
                            label=f"{registry.label(learner)}, coordination {coordination}", **style)
        ax.set_xscale("log")
        ax.set_xticks(agents, [str(n) for n in agents])
        ax.minorticks_off()
        ax.set_ylim(-0.03, 1.03)
        ax.set_xlabel("agents N")
        ax.set_ylabel("greedy ISR" if measure == "in_goal" else "share of steps back to a joint state")
        ax.set_title(f"{formulation} formulation")
