"""Optimal joint plans as path finding counts them (glamas.gridworld.plans): against an exhaustive
search through the environment, on the field's maps against what the MMDP's optimum gives, and one
line for an instance without a plan."""

from pathlib import Path

import numpy as np
import pytest

from glamas.errors import UserError
from glamas.gridworld import GridworldEnv, dp, load_map, plans

SWAP_WITH_A_POCKET = Path(__file__).parent / "data" / "swap_with_a_pocket.txt"
"""Two agents swapping ends of a corridor with one pocket: one must step into it and wait."""
NO_WAY_PAST = """\
+-+-+-+
|1 . 2|
+-+-+-+
goal 1: row 0, col 2
goal 2: row 0, col 0
"""
"""Two agents swapping ends of a corridor without a side cell: no plan exists."""


def _exhaustive(gridmap, horizon: int) -> tuple[int, int]:
    """(least sum of costs, least makespan) over every sequence of joint actions of up to
    ``horizon`` steps without a collision, played through the environment: breadth first by step,
    each joint state kept with the least cost it was reached with at that step."""
    env = GridworldEnv(gridmap)
    n, best_cost, best_span = gridmap.n_agents, None, None
    layer = {tuple(gridmap.starts.tolist()): 0}
    for t in range(1, horizon + 1):
        following = {}
        for cells, cost in layer.items():
            done = [bool(gridmap.is_goal_of(i, c)) for i, c in enumerate(cells)]
            for joint in range(4 ** n):
                env.reset()
                env._cells[:] = cells
                env._done[:] = done
                env.agents = [a for a, d in zip(env.possible_agents, done) if not d]
                actions = {a: joint // 4 ** k % 4 for k, a in enumerate(env.possible_agents) if a in env.agents}
                _, _, terminated, _, infos = env.step(actions)
                if any(info["collided"] for info in infos.values()):
                    continue
                new, paid = tuple(env.cells.tolist()), cost + len(actions)
                if all(gridmap.is_goal_of(i, c) for i, c in enumerate(new)):
                    best_cost = paid if best_cost is None else min(best_cost, paid)
                    best_span = t if best_span is None else best_span
                elif paid < following.get(new, paid + 1):
                    following[new] = paid
        layer = following
    return best_cost, best_span


def test_the_plans_are_the_exhaustive_searchs():
    gridmap = load_map(SWAP_WITH_A_POCKET)
    cost, span = plans.least_sum_of_costs(gridmap), plans.least_makespan(gridmap)
    assert (cost.sum_of_costs, span.makespan) == _exhaustive(gridmap, horizon=8)
    assert cost.cells[0].tolist() == gridmap.starts.tolist() and len(cost.cells) == cost.makespan + 1
    assert plans.lower_bounds(gridmap) == (6, 3) and cost.sum_of_costs > 6  # one agent waits


def test_on_isr_one_agent_arrives_in_its_shortest_path_while_the_other_steps_aside():
    """The MMDP's optimum counts only the last arrival: its episode takes 6 steps for both agents;
    the plan of least sum of costs brings one in after its shortest path, 4."""
    isr = load_map("isr")
    plan = plans.least_sum_of_costs(isr)
    assert sorted(plan.steps.tolist()) == [4, 6] and plan.makespan == 6
    assert sorted(dp.exact_optimum(isr, 0.9).steps_to_goal.tolist()) == [6, 6]
    assert plans.lower_bounds(isr) == (8, 4)


def test_an_instance_without_a_plan_is_one_line():
    with pytest.raises(UserError, match="no collision-free plan"):
        plans.least_sum_of_costs(load_map(NO_WAY_PAST))


def test_a_map_whose_tables_do_not_fit_is_refused_with_the_bounds_named():
    with pytest.raises(UserError, match="lower_bounds"):
        plans.least_makespan(load_map("tunnel_to_goal_4"))
    assert np.array_equal(plans.lower_bounds(load_map("tunnel_to_goal_4")), (40, 10))
