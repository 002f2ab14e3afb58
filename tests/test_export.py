"""The export of glamas maps and plans to POGEMA's terms (glamas.gridworld.export): a warehouse's
grid, starts and targets as POGEMA reads them, a plan's actions that walk POGEMA's moves along the
plan's cells, and one line for what POGEMA's grid cannot hold. POGEMA itself is not installed here:
``make pogema-crosscheck`` replays the same tasks in it."""

import numpy as np
import pytest

from glamas.errors import UserError
from glamas.gridworld import export, generate, load_map, plans, prioritized

TWO_GOAL_CELLS = """\
+-+-+-+
|1 G G|
+-+-+-+
"""
"""One agent whose goal is two cells: POGEMA takes one target per agent."""


@pytest.mark.parametrize("n_agents", [8, 128])
def test_a_warehouse_and_its_plan_walk_the_same_cells_in_pogema_terms(n_agents):
    gridmap = generate.warehouse(n_agents, 0)
    plan = prioritized.plan(gridmap)
    task, actions = export.pogema_task(gridmap, plan), export.pogema_actions(gridmap, plan)
    rows = task["map"].split("\n")
    assert [len(row) for row in rows] == [gridmap.n_cols] * gridmap.n_rows
    assert np.array_equal(np.array([[ch == "#" for ch in row] for row in rows]).ravel(), gridmap.blocked)
    assert [tuple(xy) for xy in task["agents_xy"]] == [gridmap.row_col(int(c)) for c in gridmap.starts]
    assert [gridmap.cell(*xy) for xy in task["targets_xy"]] == [gridmap.goal_cells(i)[0] for i in range(n_agents)]
    xy = np.array(task["agents_xy"])
    for t, row in enumerate(actions):
        xy = xy + np.array([export.POGEMA_MOVES[a] for a in row])
        assert [gridmap.cell(int(r), int(c)) for r, c in xy] == plan.cells[t + 1].tolist()
    assert len(actions) == plan.makespan
    assert all(actions[t][i] == 0 for i in range(n_agents) for t in range(int(plan.steps[i]), plan.makespan))


def test_a_wall_between_free_cells_is_refused_naming_it():
    with pytest.raises(UserError, match=r"^map 'tunnel_to_goal' has a wall between the free cells \(1, 0\) and "
                                        r"\(2, 0\), which POGEMA's grid cannot hold"):
        export.pogema_task(load_map("tunnel_to_goal"))


def test_several_goal_cells_take_the_plans_last_cell_and_without_a_plan_are_refused():
    gridmap = load_map(TWO_GOAL_CELLS)
    with pytest.raises(UserError, match="agent 1 of map 'inline' has 2 goal cells and POGEMA takes one target"):
        export.pogema_task(gridmap)
    plan = prioritized.plan(gridmap)
    assert export.pogema_task(gridmap, plan)["targets_xy"] == [[0, 1]]


def test_a_plan_of_another_map_is_refused():
    gridmap, other = generate.warehouse(8, 0), generate.warehouse(8, 1)
    with pytest.raises(UserError, match="^the plan does not start from the starts of map"):
        export.pogema_actions(gridmap, prioritized.plan(other))
    plan = prioritized.plan(gridmap)
    jump = plans.Plan(steps=plan.steps, cells=np.concatenate([plan.cells[:1], plan.cells[2:]]))
    with pytest.raises(UserError, match=r"^the plan moves agent \d+ from .* at step 1, not one move of map"):
        export.pogema_actions(gridmap, jump)


def test_the_task_writer_refuses_a_missing_directory_before_computing(tmp_path):
    from benchmarks import pogema_tasks
    with pytest.raises(UserError, match="is not a directory; create it or give another OUT"):
        pogema_tasks.main([str(tmp_path / "missing" / "tasks.json")])
