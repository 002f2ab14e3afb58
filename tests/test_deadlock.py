"""CQ-learning's greedy replay (glamas.experiments.benchmark_maps.deadlock): its runs are the
benchmark's, so the replay ends as the committed greedy evaluations do; a cycle is found only
where no tie can break it; a map of other than two agents is one line."""

import numpy as np
import pytest

from glamas.errors import UserError
from glamas.experiments import benchmark_maps as bm
from glamas.experiments.benchmark_maps import deadlock

CONFIG = bm.BenchmarkConfig(runs=3)


@pytest.fixture(scope="module")
def isr():
    return deadlock.trained(CONFIG, "isr")


def test_the_replays_end_as_the_committed_greedy_evaluations(isr):
    """The chapter's formulation on ISR: no tie on the way, so the replay is the greedy policy, and
    its runs are the first of the benchmark's (the same seeds): caught in a cycle, as the committed
    evaluation never completes."""
    committed = bm.load().evaluation("cq", "isr", "completion")[:CONFIG.runs]
    replays = [deadlock.replay(CONFIG, "isr", isr, run) for run in range(CONFIG.runs)]
    assert [r.arrived for r in replays] == [bool(c >= 0.95) for c in committed] == [False] * CONFIG.runs
    for r in replays:
        assert r.ties == 0 and len(r.cycle) in (1, 2) and r.collisions == 0
        assert all(d.augmented and d.margin > 0 for step in r.cycle for d in step)
    assert "0 bring every agent in, 3 end in a cycle" in deadlock.cycles_summary(replays)


def test_a_tied_state_that_comes_back_is_no_cycle(isr):
    """Values all equal: every step a tie, so no state's return proves a cycle; the episode runs to
    the cap (or arrives) instead."""
    flat = {name: np.zeros_like(array) if name != "marked" else array for name, array in isr.items()}
    r = deadlock.replay(CONFIG, "isr", flat, 0)
    assert r.cycle_start is None and r.ties > 0
    assert r.arrived or len(r.steps) == CONFIG.max_steps


def test_a_map_of_three_agents_is_refused_in_one_line():
    with pytest.raises(UserError, match="has 3 agents: the replay reads two agents' tables"):
        deadlock.trained(CONFIG, "tunnel_to_goal_3")
