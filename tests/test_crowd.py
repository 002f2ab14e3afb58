"""2observe's coordination in a crowd (glamas.experiments.crowd): the replay plays the benchmark's
own greedy episodes (the same measures from the same seeds), revisits counted by hand, nobody
yields with the coordination off, and the config's one-line errors."""

from dataclasses import replace

import numpy as np
import pytest

from glamas.errors import UserError
from glamas.experiments import crowd
from glamas.experiments import warehouses as wh
from glamas.experiments.crowd.replay import revisits
from glamas.learners.two_observe import GONE

STUDY = replace(wh.WarehousesConfig(agents=(3, 8), instances=2, episodes=20, blocks=4, window=5,
                                    evaluation_episodes=3, max_steps=200), learners=crowd.LEARNERS)


@pytest.fixture(scope="module")
def small():
    return crowd.run(crowd.CrowdConfig(study=STUDY), seed=0, workers=1)


def test_the_replay_is_the_benchmarks_greedy_evaluation(small):
    benchmark = wh.run(STUDY, seed=0, workers=1)
    same = [wh.GREEDY.index(name) for name in ("completed", "in_goal", "makespan", "collisions")]
    for formulation in STUDY.formulations:
        for n in STUDY.agents:
            for learner in STUDY.learners:
                replayed = np.stack([small.measure(formulation, n, learner, "on", name)
                                     for name in ("completed", "in_goal", "length", "collisions")], axis=-1)
                assert np.array_equal(replayed, benchmark.greedy[benchmark.index(formulation, n, learner)][..., same])


def test_nobody_yields_with_the_coordination_off(small):
    yields = small.greedy[:, :, :, crowd.COORDINATION.index("off"), ..., crowd.MEASURES.index("yields")]
    assert np.all(yields == 0.0)
    assert np.all(np.isfinite(small.greedy))
    assert np.all((small.greedy[..., crowd.MEASURES.index("revisits")] >= 0)
                  & (small.greedy[..., crowd.MEASURES.index("revisits")] <= 1))


def test_revisits_counted_by_hand():
    a, b, c = [0, 5], [1, 5], [1, 6]
    trace = np.array([a, b, a, b, c, [GONE, GONE], [9, 9]])  # the last row lies beyond the episode
    assert revisits(trace, 5) == 2 / 5  # steps 2 and 3 come back to a and b
    assert revisits(np.array([a, b, c]), 2) == 0.0
    assert revisits(np.array([a]), 0) == 0.0


def test_the_tables_read_the_result(small):
    text = crowd.table(small, "field")
    assert "coord. on" in text and "coord. off" in text and "N = 8" in text
    assert "ISR on - off" in crowd.effects_table(small)
    mean, low, high, count = crowd.effect(small, "field", 8, "two_observe")
    assert count == STUDY.instances and low <= mean <= high


def test_a_learner_of_another_kernel_is_one_line():
    with pytest.raises(UserError, match="replays 2observe's kernel"):
        crowd.CrowdConfig(study=replace(STUDY, learners=("independent",)))
    with pytest.raises(UserError, match="WarehousesConfig"):
        crowd.CrowdConfig(study=3)
