"""Many agents against a plan (glamas.experiments.warehouses): the per-episode log reduced by hand,
the seeds of every key distinct, a small run's shapes and skips, its measures against its plans,
and the config's one-line errors."""

import itertools

import numpy as np
import pytest

from glamas.errors import UserError
from glamas.experiments import warehouses as wh
from glamas.experiments.warehouses.experiment import greedy_rows, reduce_log
from glamas.learners import episode as ep

CAP = 10


def _log(steps_per_episode, collisions=0.0):
    """A per-episode log of 2 agents: each row the agents' steps (CAP: not in)."""
    log = np.zeros((len(steps_per_episode), ep.n_columns(2)))
    for row, steps in zip(log, steps_per_episode):
        row[:2] = steps
        row[ep.column(2, ep.LENGTH)] = max(steps)
        row[ep.column(2, ep.CAPPED)] = float(max(steps) >= CAP)
        row[ep.column(2, ep.COLLISIONS)] = collisions
    return log


def test_the_log_reduced_by_hand():
    log = _log([(CAP, CAP), (4, CAP), (4, CAP), (3, 5), (3, 5), (3, 5)], collisions=1.0)
    curve, reached, arrived = reduce_log(log, 2, CAP, blocks=3, window=2)
    assert curve[:, 0].tolist() == [0.0, 0.5, 1.0]  # CSR per block of two episodes
    assert curve[:, 1].tolist() == [0.25, 0.75, 1.0]  # ISR
    assert curve[:, 2].tolist() == [1.0, 1.0, 1.0]
    assert reached == 5  # ISR over episodes 4 and 5 (0.5 + 1) / 2 < 0.95; over 5 and 6 it is 1
    assert arrived.tolist() == [True, True]
    _, never, arrived = reduce_log(_log([(CAP, 3)] * 4), 2, CAP, blocks=2, window=2)
    assert never == -1 and arrived.tolist() == [False, True]


def test_greedy_rows_count_an_agent_out_with_the_cap():
    rows = greedy_rows(_log([(3, 5), (4, CAP)]), 2, CAP)
    completed, in_goal, soc, makespan = (rows[:, wh.GREEDY.index(name)] for name in
                                         ("completed", "in_goal", "sum_of_costs", "makespan"))
    assert completed.tolist() == [1.0, 0.0] and in_goal.tolist() == [1.0, 0.5]
    assert soc.tolist() == [8.0, 14.0] and makespan.tolist() == [5.0, 10.0]


def test_every_key_has_its_own_stream():
    keys = list(itertools.product(range(4), ("chapter", "field"), (8, 16, 32, 128), range(16), wh.LEARNERS))
    seeds = {wh.seed_of(*key) for key in keys}
    assert len(seeds) == len(keys)
    assert max(seeds) < 2 ** 48  # below the evaluations' seeds


@pytest.fixture(scope="module")
def small():
    config = wh.WarehousesConfig(agents=(3, 8), instances=2, episodes=20, blocks=4, window=5, evaluation_episodes=3,
                                 learners=("independent", "two_observe", "cq"), memory_budget_gib=0.001, max_steps=200)
    return wh.run(config, seed=0, workers=1)


def test_a_small_run_has_every_key_and_skips_what_does_not_fit(small):
    f, a, l, i = 2, 2, 3, 2
    assert small.greedy.shape == (f, a, l, i, 3, len(wh.GREEDY)) and small.curve.shape == (f, a, l, i, 4, len(wh.CURVE))
    cq = small.names().index("cq")
    assert not small.ran[:, 1, cq].any() and small.ran[:, :, :cq].all()  # CQ's tables of 8 agents exceed 1 MB
    assert np.isnan(small.greedy[:, 1, cq]).all() and np.isfinite(small.greedy[:, :, :cq]).all()
    assert wh.summary(small, "chapter", 8, "cq") is None
    assert "skipped" in wh.table(small, "chapter")


def test_the_measures_stand_against_the_plans(small):
    plans = small.plan(8)
    assert (plans[:, 0] >= plans[:, 2]).all() and (plans[:, 1] >= plans[:, 3]).all()  # never below the bounds
    for formulation, n, learner in itertools.product(("chapter", "field"), (3, 8), ("independent", "two_observe")):
        values = wh.per_instance(small, formulation, n, learner)
        assert ((0 <= values["isr"]) & (values["isr"] <= 1)).all()
        assert (values["csr"] <= values["isr"]).all()
        done = np.isfinite(values["soc_ratio"])
        assert (values["csr"][done] > 0).all()
        bound = small.plan(n)[:, 2] / small.plan(n)[:, 0]  # no episode beats each agent's shortest path alone
        assert (values["soc_ratio"][done] >= bound[done]).all()


def test_the_same_seed_the_same_result_with_two_workers(small):
    again = wh.run(small.config, seed=0, workers=2)
    assert np.array_equal(small.greedy, again.greedy, equal_nan=True)
    assert np.array_equal(small.curve, again.curve, equal_nan=True)


@pytest.mark.parametrize("changes, message", [({"agents": (2, 8)}, "agents must be distinct whole numbers >= 3"),
                                              ({"blocks": 7}, "blocks \\(7\\) must divide episodes"),
                                              ({"formulations": ("chapter", "other")}, "formulations must be"),
                                              ({"instances": 0}, "instances must be a whole number >= 1"),
                                              ({"learners": ("mmdp", "nobody")}, "learners must be"),
                                              ({"window": 5000}, "window \\(5000\\) must be at most")])
def test_bad_settings_are_one_line(changes, message):
    with pytest.raises(UserError, match=message):
        wh.WarehousesConfig(**changes)
