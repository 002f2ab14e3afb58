"""The benchmark's figures, each on given matplotlib Axes: the map-by-learner table of the greedy
policies against the optimum, the learning curves on every map, the maps with their optimal
episodes and plans, and the budget axis."""

import numpy as np
from matplotlib.ticker import NullLocator

from glamas.experiments.benchmark_maps.analysis import excess_grid, measure
from glamas.experiments.benchmark_maps.budgets import BudgetsResult, solved_counts
from glamas.experiments.benchmark_maps.experiment import BenchmarkResult
from glamas.experiments.gridworld.analysis import COMPLETION
from glamas.experiments.scaling.plots import CURVE_LABELS
from glamas.gridworld import draw, plans
from glamas.gridworld.rewards import CHAPTER, PRESETS
from glamas.learners import registry
from glamas.plotting import (data_bounds, greedy_legend_entry, learner_style, legend_below_figure, mark_greedy,
                             plot_mean_band)

BUDGET_SHIFT = 0.03
"""How far apart (in decades of the budget axis) the budget figure sets the learners at one budget."""
GREEDY_AT = 2.0
"""Where the greedy values stand: this many times the last episode, right of the curves' end."""
MAP_TITLES = {"tunnel_to_goal": "TunnelToGoal", "tunnel_to_goal_3": "TunnelToGoal 3",
              "tunnel_to_goal_4": "TunnelToGoal 4", "isr": "ISR", "cit": "CIT", "cmu": "CMU"}
"""The field's maps as the literature names them; another map by its name, spaced."""


def map_title(name: str) -> str:
    """Map ``name`` as a reader knows it (MAP_TITLES)."""
    return MAP_TITLES.get(name, name.replace("_", " "))


def plot_table(ax, result: BenchmarkResult):
    """Learners (rows) by maps (columns): the greedy policy's episode length over the optimum's
    (colour; 1 is optimal) and its collisions per episode; 'no solution' where it completes fewer
    than COMPLETION of its episodes, 'skipped' where the learner's tables exceed the budget."""
    grid, m = excess_grid(result), measure(result)
    names, maps = result.names(), result.map_names()
    ax.imshow(np.clip(grid, 1.0, 2.0), cmap="Greens_r", vmin=0.8, vmax=2.2, aspect="auto")
    for k, name in enumerate(names):
        for j, map_name in enumerate(maps):
            key = f"{name}_{map_name}"
            if not result.ran[k, j]:
                text, colour = "skipped", "0.5"
            elif np.isnan(grid[k, j]):
                text, colour = f"no solution\n{m[f'greedy_completion_{key}']:.0%} done", "tab:red"
            else:
                text, colour = f"x{grid[k, j]:.2f}\n{m[f'greedy_collisions_{key}']:.2f} coll.", "black"
            ax.text(j, k, text, ha="center", va="center", fontsize="x-small", color=colour)
    ax.set_xticks(range(len(maps)), [map_title(name) for name in maps], rotation=20, fontsize="small")
    ax.set_yticks(range(len(names)), [registry.label(name) for name in names], fontsize="small")
    under = "" if result.config.rewards == CHAPTER else f" under the {_formulation(result.config.rewards)} rewards"
    ax.set_title(f"greedy policy after {result.config.episodes} episodes{under}: episode length over the optimum's, "
                 f"collisions per episode\n('no solution': fewer than {COMPLETION:.0%} of its episodes end with "
                 "every agent in its goal)", fontsize="small")


def _formulation(rewards) -> str:
    """The name of a preset formulation ("field's"), or "own" for another."""
    return next((f"{name}'s" for name, preset in PRESETS.items() if preset == rewards), "own")


def plot_curves(axes, result: BenchmarkResult, metric: str = "collisions"):
    """One panel per map: every learner's learning curve of ``metric`` (mean and 95 % band over
    runs) and its greedy value after training beside the curves' end; the optimum as a dashed line
    for steps, length and reward."""
    for ax, map_name in zip(np.ravel(axes), result.map_names()):
        j = result.map_names().index(map_name)
        ran = [name for k, name in enumerate(result.names()) if result.ran[k, j]]
        for name in ran:
            plot_mean_band(ax, result.episodes, result.curves(name, map_name, metric), registry.label(name),
                           **learner_style(name))
        if metric in ("steps", "length", "reward"):
            ax.axhline(result.optimum(map_name)[metric], color="black", linestyle="--", linewidth=1,
                       label="optimum (exact)")
        ax.set_xscale("log")
        if metric in ("steps", "length"):
            ax.set_yscale("log")
        x = result.episodes[-1] * GREEDY_AT
        for name in ran:
            mark_greedy(ax, x, result.evaluation(name, map_name, metric).mean(), name)
        ax.set_xlim(right=x * 1.4)
        ax.set_title(map_title(map_name), fontsize="small")
        ax.set_xlabel("episode", fontsize="small")
        ax.set_ylabel(CURVE_LABELS[metric], fontsize="small")
    greedy_legend_entry(np.ravel(axes)[0])


def map_panels(axes) -> list:
    """The panels of the field's six maps on a 3 x 3 grid of ``axes``: the TunnelToGoal maps in the
    first row, ISR and CIT (14 columns) across two thirds of the second, CMU (34 columns) alone
    across the third, so that the wide maps' cells are large enough for their step numbers."""
    grid = axes[0, 0].get_gridspec()
    for ax in (axes[1, 1], axes[1, 2], *axes[2]):
        ax.remove()
    figure = axes[0, 0].figure
    return [*axes[0], axes[1, 0], figure.add_subplot(grid[1, 1:]), figure.add_subplot(grid[2, :])]


def plot_optimum(ax, result: BenchmarkResult, map_name: str):
    """Map ``map_name`` with the agents' paths in its optimal episode, numbered by step."""
    gridmap = result.config.gridmap(map_name)
    draw.draw_map(ax, gridmap)
    draw.draw_paths(ax, gridmap, result.optimum_episode(map_name), numbered=gridmap.n_agents <= 3)
    steps = ", ".join(str(int(s)) for s in result.optimum_steps[result.map_names().index(map_name)] if s >= 0)
    ax.set_title(f"{map_title(map_name)}: optimal steps {steps}", fontsize="small")


def plot_plan(ax, result: BenchmarkResult, map_name: str):
    """Map ``map_name`` with the agents' paths in its plan of least sum of costs, numbered by step,
    and the plan of least makespan in the title (the lower bounds alone where the joint tables do
    not fit)."""
    gridmap = result.config.gridmap(map_name)
    cost, span = result.plan(map_name, "sum_of_costs"), result.plan(map_name, "makespan")
    draw.draw_map(ax, gridmap)
    if cost["steps"] is None:
        bound_cost, bound_makespan = plans.lower_bounds(gridmap)
        ax.set_title(f"{map_title(map_name)}: too large for an exact plan\n(lower bounds: sum of costs "
                     f"{bound_cost}, makespan {bound_makespan})", fontsize="small")
        return
    draw.draw_paths(ax, gridmap, result.plan_episode(map_name), numbered=gridmap.n_agents <= 3)
    other = ("the same plan" if span["steps"] == cost["steps"] else
             f"steps {', '.join(map(str, span['steps']))}, sum of costs {span['sum_of_costs']}")
    ax.set_title(f"{map_title(map_name)}: least sum of costs {cost['sum_of_costs']} "
                 f"(steps {', '.join(map(str, cost['steps']))})\nleast makespan {span['makespan']}: {other}",
                 fontsize="small")


def plot_budgets(axes, result: BudgetsResult):
    """One panel per formulation of a budget axis (:mod:`.budgets`): the maps each learner's greedy
    policy solves (a collision-free solution) after each budget of training episodes, the budgets
    labelled as run; the learners set side by side at each budget (BUDGET_SHIFT), each with its
    own marker, so that learners solving as many maps stay visible and every count stays whole."""
    names = list(map(str, result.learners))
    for ax, formulation in zip(np.ravel(axes), map(str, result.formulations)):
        for k, (name, counts) in enumerate(zip(names, solved_counts(result, formulation))):
            shift = 10.0 ** ((k - (len(names) - 1) / 2) * BUDGET_SHIFT)
            ax.plot(result.budgets * shift, counts, label=registry.label(name), **learner_style(name, marker=True))
        ax.set_xscale("log")
        ax.set_xticks(result.budgets, [f"{budget:,}" for budget in result.budgets])
        ax.xaxis.set_minor_locator(NullLocator())  # the budgets alone
        ax.set_ylim(-0.3, result.maps.size + 0.3)
        data_bounds(ax, (0, result.maps.size))
        ax.set_xlabel("training episodes per run", fontsize="small")
        ax.set_ylabel(f"maps solved (of {result.maps.size})", fontsize="small")
        ax.set_title(f"the {formulation}'s formulation: greedy policy collision-free and completing "
                     f"{COMPLETION:.0%}", fontsize="small")
    legend_below_figure(np.ravel(axes)[0])
