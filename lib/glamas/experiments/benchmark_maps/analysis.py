"""What the benchmark says: per (learner, map) the final learning-curve values and what the learned
greedy policy does against the map's optimum, and the claims of ``data/chapter/benchmark_maps.json``:
the field's reported outcomes on these maps (De Hauwere, Vrancx and Nowé, ICAART 2011) and the
chapter's zero collisions carried to them."""

import functools
import math

import numpy as np

from glamas import claims as chapter
from glamas.curves import FINAL_FRACTION, final
from glamas.experiments.benchmark_maps.experiment import BenchmarkResult
from glamas.experiments.gridworld.analysis import COMPLETION
from glamas.gridworld import plans
from glamas.gridworld.rewards import Rewards
from glamas.learners import registry
from glamas.tables import Table

TUNNEL_3 = "tunnel_to_goal_3"
"""The map where the field reports the independent learners doing well, by luck of exploration."""


def measure(result: BenchmarkResult, final_share: float = FINAL_FRACTION) -> dict:
    """Per (learner, map): final collisions and steps of the learning curves; the greedy policy's
    collisions, completion, episode length and its excess over the optimum's (NaN for a policy
    that does not complete), and the collisions of a greedy policy that completes (infinite
    otherwise); the comparisons the claims are about. Final values average the last ``final_share``
    of the episodes (a measurement choice of docs/verdicts.md)."""
    m = {}
    for k, name in enumerate(result.names()):
        for j, map_name in enumerate(result.map_names()):
            if result.ran[k, j]:
                m.update(case_measures(result, name, map_name, final_share))
    m.update(claim_measures(result, m))
    return m


def case_measures(result: BenchmarkResult, name: str, map_name: str, final_share: float = FINAL_FRACTION) -> dict:
    """The measurements of one learner on one map (:func:`measure`), keys ``<metric>_<learner>_<map>``."""
    key = f"{name}_{map_name}"
    m = {f"collisions_{key}": final(result.curves(name, map_name, "collisions"), result.episodes, final_share),
         f"steps_{key}": final(result.curves(name, map_name, "steps"), result.episodes, final_share)}
    for metric in ("collisions", "completion", "length", "reward", "coordinations"):
        m[f"greedy_{metric}_{key}"] = float(result.evaluation(name, map_name, metric).mean())
    completes = m[f"greedy_completion_{key}"] >= COMPLETION
    m[f"greedy_solution_collisions_{key}"] = m[f"greedy_collisions_{key}"] if completes else math.inf
    m[f"greedy_excess_length_{key}"] = (m[f"greedy_length_{key}"] - result.optimum(map_name)["length"]
                                        if completes else math.nan)
    # the agents' steps summed (the greedy evaluation keeps their mean) over the least sum of costs
    plan = result.plan(map_name)
    m[f"greedy_cost_ratio_{key}"] = (float(result.evaluation(name, map_name, "steps").mean()) * len(plan["steps"])
                                     / plan["sum_of_costs"] if completes and plan["steps"] else math.nan)
    return m


def claim_measures(result: BenchmarkResult, m: dict) -> dict:
    """The comparisons of data/chapter/benchmark_maps.json, from the per-case measurements ``m``."""
    out = {}
    names, maps = result.names(), result.map_names()
    for name in ("cq", "two_observe"):
        if name in names:
            for metric in ("greedy_solution_collisions", "collisions"):  # the greedy policy's; the curves'
                values = [m[f"{metric}_{name}_{map_name}"] for map_name in maps if f"{metric}_{name}_{map_name}" in m]
                out[f"{metric}_{name}_max"] = max(values, default=math.nan)
    if "independent" in names and TUNNEL_3 in maps and len(maps) > 1:
        elsewhere = [m[f"collisions_independent_{map_name}"] for map_name in maps if map_name != TUNNEL_3]
        out["collisions_independent_elsewhere_min"] = min(elsewhere)
        out["collisions_independent_tunnel_3_over_elsewhere_min"] = (
            m[f"collisions_independent_{TUNNEL_3}"] / min(elsewhere) if min(elsewhere) > 0 else math.nan)
    joint = [f"collisions_{name}_{TUNNEL_3}" for name in ("joint_state", "mmdp") if name in names]
    if joint and all(key in m for key in joint):
        out["collisions_joint_learners_tunnel_3_min"] = min(m[key] for key in joint)
    return out


def solo_value(rewards: Rewards, discount: float, distance: int) -> float:
    """The discounted return of an agent alone ``distance`` steps from its goal on its shortest
    path: a move's reward every step, the goal's on the last."""
    moves = sum(discount ** t for t in range(distance)) * rewards.move
    return moves + discount ** (distance - 1) * rewards.goal


def push_margin(rewards: Rewards, discount: float, distance: int) -> float:
    """What pushing into an agent that blocks the next cell is worth over backing off one cell,
    ``distance`` steps from the goal, as a learner that values its next cell by the solo values
    (CQ-learning's augmented values) scores it: the collision's reward (added to or in place of
    the move's) and staying, against a move and one step farther. Negative: backing off wins."""
    push = rewards.collision + (0.0 if rewards.collision_replaces_move else rewards.move)
    staying = push + discount * solo_value(rewards, discount, distance)
    backing_off = rewards.move + discount * solo_value(rewards, discount, distance + 1)
    return staying - backing_off


def margin_table(formulations: dict, distances=range(1, 9)) -> str:
    """:func:`push_margin` at each distance under each of ``formulations`` (name -> (rewards, discount))."""
    lines = [f"{'distance to the goal':24s}" + "".join(f"{d:>8d}" for d in distances)]
    for name, (rewards, discount) in formulations.items():
        lines.append(f"{name:24s}" + "".join(f"{push_margin(rewards, discount, d):8.2f}" for d in distances))
    return "\n".join(lines)


def formulations_table(results: dict, learner: str, metrics=("greedy_completion", "greedy_solution_collisions",
                                                             "collisions")) -> Table:
    """One learner's measurements (:func:`measure`) per map under each formulation: ``results``
    maps a formulation's name to the benchmark's result under it ('no solution' where the greedy
    policy does not complete, '-' where the learner did not run)."""
    measured = {name: measure(result) for name, result in results.items()}
    maps = next(iter(results.values())).map_names()
    return Table([registry.label(learner), *maps],
                 [[f"{metric} ({name})", *(chapter.value_text(m.get(f'{metric}_{learner}_{map_name}', math.nan), 3)
                                           for map_name in maps)]
                  for metric in metrics for name, m in measured.items()])


SOLVED_COLLISIONS = 0.05
"""A greedy policy that completes and collides at most this often per episode (once in 20
episodes, the claims' threshold) counts as a collision-free solution in :func:`solved_table`."""


def solved_table(result: BenchmarkResult) -> str:
    """Per learner, the maps on which its greedy policy is a collision-free solution (it completes,
    COMPLETION, with at most SOLVED_COLLISIONS collisions per episode), and how many of those maps
    it solves optimally (its episodes no longer than the optimum's)."""
    m, lines = measure(result), []
    for name in result.names():
        solved = [map_name for map_name in result.map_names()
                  if m.get(f"greedy_solution_collisions_{name}_{map_name}", math.inf) <= SOLVED_COLLISIONS]
        optimal = [map_name for map_name in solved if m[f"greedy_excess_length_{name}_{map_name}"] <= 0]
        lines.append(f"{registry.label(name):24s} {len(solved)} of {len(result.map_names())}: "
                     f"{', '.join(solved) or '-'}; optimal on {', '.join(optimal) or 'none'}")
    return "\n".join(lines)


def claim_rows(result: BenchmarkResult, config=None) -> list[dict]:
    """The benchmark's claims (data/chapter/benchmark_maps.json) with verdicts computed from ``result``."""
    return chapter.verdicts(chapter.load("benchmark_maps"), functools.partial(measure, result))


def field_claim_rows(result: BenchmarkResult, config=None) -> list[dict]:
    """The field's claims judged under the field's formulation (``benchmark_maps_field`` in
    data/chapter/benchmark_maps.json): the same measurements of a result of the field's rewards
    and learning settings."""
    return chapter.verdicts(chapter.load("benchmark_maps_field"), functools.partial(measure, result))


def table(result: BenchmarkResult, metric: str = "greedy_solution_collisions") -> Table:
    """One measurement of :func:`measure` per learner (rows) and map (columns); '-' where the
    learner did not run (its tables exceed the memory budget), 'no solution' where its greedy policy
    does not complete (the measurement's NaN or infinity)."""
    m, maps = measure(result), result.map_names()
    return Table([metric, *maps], [[registry.label(name), *(chapter.value_text(m[key], 3, 'no solution')
                                                            if (key := f"{metric}_{name}_{map_name}") in m else "-"
                                                            for map_name in maps)]
                                   for name in result.names()])


def optimum_table(result: BenchmarkResult) -> str:
    """Each map's size, agents and exact optimum: steps per agent, episode length and returns."""
    lines = [f"{'map':18s} {'agents':>6s} {'cells':>6s} {'steps per agent':>18s} {'length':>6s} {'returns':>22s}"]
    for map_name in result.map_names():
        j, gridmap = result.map_names().index(map_name), result.config.gridmap(map_name)
        n = gridmap.n_agents
        steps = ", ".join(str(int(s)) for s in result.optimum_steps[j, :n])
        returns = ", ".join(f"{r:g}" for r in result.optimum_returns[j, :n])
        lines.append(f"{map_name:18s} {n:6d} {int((~gridmap.blocked).sum()):6d} {steps:>18s} "
                     f"{int(result.optimum_steps[j].max()):6d} {returns:>22s}")
    return "\n".join(lines)


def plans_table(result: BenchmarkResult) -> Table:
    """Each map's optimal plans as path finding counts them (glamas.gridworld.plans): the least sum
    of costs and the least makespan, each agent's steps, and the lower bounds (each agent's shortest
    path alone); '-' where the joint tables do not fit."""
    header = ["map", "least sum of costs: steps", "sum", "makespan", "least makespan: steps", "sum", "makespan",
              "bounds: sum", "makespan"]
    rows = []
    for map_name in result.map_names():
        row = [map_name]
        for plan in (result.plan(map_name, "sum_of_costs"), result.plan(map_name, "makespan")):
            known = plan["steps"] is not None
            row += [", ".join(map(str, plan["steps"])), plan["sum_of_costs"], plan["makespan"]] if known else ["-"] * 3
        rows.append(row + list(plans.lower_bounds(result.config.gridmap(map_name))))
    return Table(header, rows)


def excess_grid(result: BenchmarkResult) -> np.ndarray:
    """(learners, maps): the greedy policy's episode length over the optimum's, NaN where the learner
    did not run or its greedy policy does not complete (:func:`case_measures`)."""
    m = measure(result)
    grid = np.full((len(result.names()), len(result.map_names())), np.nan)
    for k, name in enumerate(result.names()):
        for j, map_name in enumerate(result.map_names()):
            excess = m.get(f"greedy_excess_length_{name}_{map_name}", math.nan)
            grid[k, j] = (excess + result.optimum(map_name)["length"]) / result.optimum(map_name)["length"]
    return grid
