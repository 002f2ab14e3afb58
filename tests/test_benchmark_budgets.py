"""The benchmark's budget axis (glamas.experiments.benchmark_maps.budgets): each budget is the
benchmark itself at that many episodes, the committed axis agrees with the committed benchmarks,
the episodes a learner needs are read from the greedy evaluations, and bad settings are one line."""

import dataclasses

import numpy as np
import pytest

from glamas import training
from glamas.errors import UserError
from glamas.experiments import benchmark_maps as bm
from glamas.experiments.benchmark_maps import budgets
from glamas.experiments.scaling.experiment import METRICS


SMALL = budgets.BudgetsConfig(maps=("isr",), learners=("independent", "cq"), budgets=(3, 12), runs=2,
                              evaluation_episodes=3)


def test_a_budget_is_the_benchmark_at_that_many_episodes():
    result = budgets.run(SMALL, seed=4)
    for f, formulation in enumerate(SMALL.formulations):
        for b, budget in enumerate(SMALL.budgets):
            alone = bm.run(SMALL.benchmark(formulation, budget), seed=4)
            np.testing.assert_array_equal(result.evaluated[f, b], alone.evaluated)
    assert result.plan_steps[0, 0, :2].tolist() == [6, 4]  # ISR's least sum of costs


def test_the_committed_axis_at_2000_episodes_is_the_committed_benchmark():
    """The budget of the field's 2000 episodes holds the very evaluations the benchmark's result
    files hold, under each formulation: the axis continues the benchmark rather than redoing it."""
    axis = bm.load_budgets()
    for f, benchmark in ((0, bm.load()), (1, bm.load_field())):
        b = axis.budgets.tolist().index(benchmark.config.episodes)
        np.testing.assert_array_equal(axis.evaluated[f, b], benchmark.evaluated)
        np.testing.assert_array_equal(axis.ran[f, b], benchmark.ran)
    np.testing.assert_array_equal(axis.plan_steps, bm.load().plan_steps)


def _axis(completion: list, collisions: list) -> budgets.BudgetsResult:
    """A one-formulation, one-learner, one-map axis whose greedy evaluations are ``completion`` and
    ``collisions`` at budgets 10, 100 and 1000."""
    config = budgets.BudgetsConfig(formulations=("chapter",), maps=("isr",), learners=("cq",), budgets=(10, 100, 1000),
                                   runs=1)
    evaluated = np.zeros((1, 3, 1, 1, 1, len(training.EVALUATIONS), len(METRICS)))
    evaluated[0, :, 0, 0, 0, 0, METRICS.index("capped")] = 1 - np.array(completion)
    evaluated[0, :, 0, 0, 0, 0, METRICS.index("collisions")] = collisions
    evaluated[0, :, 0, 0, 0, 0, METRICS.index("steps")] = 5.0
    plan = np.full((1, 2, 4), -1)
    plan[0, :, :2] = [6, 4]
    return budgets.BudgetsResult(config=config, formulations=np.array(["chapter"]), budgets=np.array([10, 100, 1000]),
                                 learners=np.array(["cq"]), maps=np.array(["isr"]), ran=np.ones((1, 3, 1, 1), bool),
                                 evaluated=evaluated, plan_steps=plan)


def test_the_episodes_needed_are_the_first_budget_of_a_collision_free_solution():
    solved_late = _axis(completion=[0.5, 1.0, 1.0], collisions=[0.0, 0.2, 0.0])  # completes at 100, clean at 1000
    assert budgets.needed(solved_late, "chapter", "cq", "isr") == 1000
    assert budgets.solved_counts(solved_late, "chapter").tolist() == [[0, 0, 1]]
    assert budgets.greedy(solved_late, "chapter", 1000, "cq", "isr")["cost_ratio"] == pytest.approx(1.0)
    never = _axis(completion=[0.5, 0.9, 0.94], collisions=[0.0, 0.0, 0.0])  # just short of COMPLETION
    assert budgets.needed(never, "chapter", "cq", "isr") is None
    assert "> 1,000" in budgets.needed_table(never, "chapter")


@pytest.mark.parametrize("change, message", [
    ({"formulations": ("pogema",)}, "formulations must be distinct names"),
    ({"formulations": ()}, "formulations must be distinct names"),
    ({"budgets": (2000, 200)}, "budgets must be increasing whole numbers"),
    ({"budgets": (0, 10)}, "budgets must be increasing whole numbers"),
    ({"budgets": (10, 10)}, "budgets must be increasing whole numbers"),
    ({"learners": ("nobody",)}, "learners must be distinct names"),
    ({"runs": 0}, "runs"),
])
def test_bad_settings_are_one_line(change, message):
    with pytest.raises(UserError, match=message):
        dataclasses.replace(SMALL, **change)


def test_a_command_lines_iterations_give_budgets_a_decade_apart():
    assert budgets.scaled(10, 200_000) == budgets.BudgetsConfig()
    assert budgets.scaled(2, 5).budgets == (1, 5)
