"""Prioritized planning (glamas.gridworld.prioritized): its plans played through the rules bring every
agent in without a collision, on warehouses of up to 1024 agents; on two-agent maps against the
exact plan; one line for an instance without a plan; the same seed, the same plan."""

from pathlib import Path

import numpy as np
import pytest

from glamas.errors import UserError
from glamas.gridworld import dp, generate, load_map, plans, prioritized, rules

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
INTO_A_SHARED_GOAL = """\
+-+-+-+
|1 G 2|
+-+-+-+
"""
"""Two agents entering their shared goal together, as the rules let them, in one step each."""

TWO_AGENT_MAPS = ["tunnel_to_goal", "isr", "cit", "cmu", "warehouse_2", "aisles_2", SWAP_WITH_A_POCKET,
                  INTO_A_SHARED_GOAL]
"""The field's maps, the other two-agent maps of data/maps, the swap with a pocket and the shared
goal (the exact plan takes no detour on aisles_2 and the shared goal only)."""


def _replay(gridmap, plan, bounce="previous"):
    """Play ``plan`` through rules.step from the starts, each agent's action the move from its cell
    to its next one (a bump where it stays), checking the cells at every step. Returns (the
    collisions, the step each agent entered its goal at; -1: never)."""
    world, n = rules.world(gridmap, bounce), gridmap.n_agents
    cells, done = gridmap.starts.copy(), np.zeros(n, bool)
    out = (np.empty(n, np.int64), np.empty(n), np.empty(n, bool), np.empty(n, bool), np.empty(n, bool))
    collisions, arrived = 0, np.full(n, -1)
    for t in range(1, plan.makespan + 1):
        leads = gridmap.next_cell[cells] == plan.cells[t][:, None]  # (agents, actions)
        assert leads[~done].any(axis=1).all(), f"step {t} of the plan is no move"
        actions = leads.argmax(axis=1).astype(np.int64)  # a done agent's is ignored
        collisions += rules.step(world, cells, done, actions, *out)
        new_cells, reached = out[0], out[4]
        arrived[reached] = t
        done |= reached
        cells = new_cells.copy()
        assert np.array_equal(cells, plan.cells[t]), f"the plan and the rules part at step {t}"
    return collisions, arrived


def _check_plays(gridmap, plan, bounce="previous"):
    assert plan.cells.shape == (plan.makespan + 1, gridmap.n_agents)
    assert np.array_equal(plan.cells[0], gridmap.starts)
    collisions, arrived = _replay(gridmap, plan, bounce)
    assert collisions == 0 and np.array_equal(arrived, plan.steps)  # every agent in, the last at the makespan
    assert (plan.steps >= prioritized.shortest_steps(gridmap)).all()


@pytest.mark.parametrize("n_agents, seed", [(8, s) for s in range(5)] + [(32, s) for s in range(3)]
                         + [(128, s) for s in range(3)] + [(1024, 1)])
def test_warehouse_plans_bring_every_agent_in_without_a_collision(n_agents, seed):
    """warehouse(128, 0) and (1024, 1) take more than the first order (module docstring)."""
    gridmap = generate.warehouse(n_agents, seed)
    _check_plays(gridmap, prioritized.plan(gridmap))


def test_a_plan_plays_the_same_when_collided_agents_bounce_to_their_start():
    gridmap = generate.warehouse(32, 0)
    _check_plays(gridmap, prioritized.plan(gridmap, bounce="start"), bounce="start")


def test_the_lower_bounds_are_the_plans_modules():
    gridmap = generate.warehouse(32, 0)
    assert prioritized.lower_bounds(gridmap) == plans.lower_bounds(gridmap)
    assert np.array_equal(prioritized.shortest_steps(gridmap), dp.shortest_steps(gridmap))


@pytest.mark.parametrize("source", TWO_AGENT_MAPS, ids=[*TWO_AGENT_MAPS[:6], "swap_with_a_pocket",
                                                    "into_a_shared_goal"])
def test_on_two_agents_no_better_than_the_exact_plan_and_as_good_without_a_detour(source):
    gridmap = load_map(source)
    plan, exact = prioritized.plan(gridmap), plans.least_sum_of_costs(gridmap)
    _check_plays(gridmap, plan)
    assert plan.sum_of_costs >= exact.sum_of_costs
    if exact.sum_of_costs == plans.lower_bounds(gridmap)[0]:
        assert plan.sum_of_costs == exact.sum_of_costs


def test_an_instance_without_a_plan_is_one_line():
    with pytest.raises(UserError, match=r"^map 'inline': prioritized planning found no collision-free plan "
                                        r"in 3 priority orders .*restarts") as error:
        prioritized.plan(load_map(NO_WAY_PAST), restarts=2)
    assert "\n" not in str(error.value)


@pytest.mark.parametrize("arguments, message", [(dict(bounce="back"), "bounce must be one of"),
                                                (dict(restarts=-1), "restarts must be a whole number"),
                                                (dict(seed=1.5), "seed must be a whole number")])
def test_bad_arguments_are_one_line(arguments, message):
    with pytest.raises(UserError, match=message):
        prioritized.plan(load_map(SWAP_WITH_A_POCKET), **arguments)


def test_the_same_seed_gives_the_same_plan():
    gridmap = generate.warehouse(128, 0)
    first, again = prioritized.plan(gridmap, seed=3), prioritized.plan(gridmap, seed=3)
    assert np.array_equal(first.cells, again.cells) and np.array_equal(first.steps, again.steps)
