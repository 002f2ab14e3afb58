"""The plain-Python steps of the algorithms (glamas.plain) do the work of the compiled kernels,
which the benchmarks time against them.

A reference draws its random numbers from whatever source it is given; here it gets glamas.rng's
own generator (:class:`KernelStream`), started from the state of the kernel's run.
It then draws the kernel's random numbers in the kernel's order, so it must play the kernel's very
episodes: its log (a row per episode: steps, rewards, length, collisions, coordinations, capped)
and, for the line-world experiments, its learned parameters equal the kernel's number for number.
"""

import numpy as np
import pytest

from benchmarks import bench_many_agents, kernels
from glamas import parallel, rng, seeds
from glamas.experiments import and_network, single_gla
from glamas.gridworld import BOUNCE_MODES, rules
from glamas.gridworld.rewards import CHAPTER, FIELD, Rewards
from glamas.learners import cq
from glamas.learners import episode as ep
from glamas.plain import gridworld as plain_gridworld
from glamas.plain import lineworld as plain_lineworld
from glamas.plain import many_agents as plain_many_agents


class KernelStream:
    """glamas.rng's stream as a reference's random source: ``random()`` is glamas.rng.uniform on
    its own copy of a run's generator state."""

    def __init__(self, state):
        self.state = np.array(state, dtype=np.uint64)

    def random(self):
        return rng.uniform(self.state)


def test_the_python_stream_is_glamas_rng():
    state = kernels.run_state(3)
    python = KernelStream(state)
    for n in (1, 2, 3, 4, 16):
        assert [rng.uniform(state) for _ in range(200)] == [python.random() for _ in range(200)]
        assert [rng.integer(state, n) for _ in range(200)] == [plain_gridworld.below(python, n) for _ in range(200)]


TUNNEL = "tunnel_to_goal"
WAREHOUSE = "warehouse_4"
SWAP = "isr"  # two agents swapping places: each one's goal is the other's start
PAIRED_GOALS = "tunnel_to_goal_4"  # agents 1 and 2 share a goal, 3 and 4 another
SCALING = 1000  # the scaling study's step cap
WORKLOADS = {
    "independent": kernels.Workload("independent", 200),
    "independent, bounce to start": kernels.Workload("independent", 200, bounce="start"),
    "joint_state": kernels.Workload("joint_state", 200),
    "mmdp": kernels.Workload("mmdp", 200),
    "two_observe": kernels.Workload("two_observe", 200),
    "sparse_maq": kernels.Workload("sparse_maq", 200),
    "cq": kernels.Workload("cq", 200, own=cq.Settings(cq_solo_episodes=20)),
    "cq, one stage": kernels.Workload("cq", 200, own=cq.Settings(cq_solo_episodes=20, cq_detection="one_stage")),
    "cq, two-sample test": kernels.Workload("cq", 200, own=cq.Settings(cq_solo_episodes=20, cq_test="two_sample")),
    "cq, local updates (CQwU)": kernels.Workload("cq", 200, own=cq.Settings(cq_solo_episodes=20, cq_update_local=True)),
    "cq, the earlier form": kernels.Workload("cq", 200, own=cq.Settings(
        cq_window=30, cq_significance=0.05, cq_solo_episodes=20, cq_test="two_sample", cq_detection="one_stage",
        cq_update_local=True, cq_observe="nearest")),
    "two_observe, 4 agents": kernels.Workload("two_observe", 20, WAREHOUSE, max_steps=SCALING),
    "sparse_maq, 4 agents": kernels.Workload("sparse_maq", 20, WAREHOUSE, max_steps=SCALING),
    "sparse_maq, 4 agents, bounce to start": kernels.Workload(
        "sparse_maq", 20, WAREHOUSE, max_steps=SCALING, bounce="start"),
    "sparse_maq, 6 agents": kernels.Workload("sparse_maq", 10, "warehouse_6", max_steps=SCALING),
    "sparse_maq_pairs, 4 agents": kernels.Workload("sparse_maq_pairs", 20, WAREHOUSE, max_steps=SCALING),
    "cq, 4 agents": kernels.Workload("cq", 100, WAREHOUSE, own=cq.Settings(cq_solo_episodes=20), max_steps=SCALING),
    "cq, 4 agents, nearest agent only": kernels.Workload(
        "cq", 100, WAREHOUSE, own=cq.Settings(cq_solo_episodes=20, cq_observe="nearest"), max_steps=SCALING),
    "cq, 4 agents, one stage": kernels.Workload(
        "cq", 20, WAREHOUSE, own=cq.Settings(cq_solo_episodes=10, cq_detection="one_stage"), max_steps=SCALING),
    "independent, own goals": kernels.Workload("independent", 100, SWAP),
    "two_observe, own goals": kernels.Workload("two_observe", 100, SWAP),
    "sparse_maq, own goals": kernels.Workload("sparse_maq", 100, SWAP),
    "cq, own goals": kernels.Workload("cq", 100, SWAP, own=cq.Settings(cq_solo_episodes=20)),
    "two_observe, goals by pairs": kernels.Workload("two_observe", 20, PAIRED_GOALS, max_steps=SCALING),
    "sparse_maq, goals by pairs": kernels.Workload("sparse_maq", 20, PAIRED_GOALS, max_steps=SCALING),
    "sparse_maq_pairs, goals by pairs": kernels.Workload("sparse_maq_pairs", 20, PAIRED_GOALS, max_steps=SCALING),
    "cq, goals by pairs": kernels.Workload("cq", 60, PAIRED_GOALS, own=cq.Settings(cq_solo_episodes=10), max_steps=SCALING),
    "independent, the field's rewards": kernels.Workload("independent", 100, rewards=FIELD),
    "independent, another collision reward": kernels.Workload("independent", 100, rewards=Rewards(collision=-25.0)),
    "mmdp, the field's rewards": kernels.Workload("mmdp", 300, rewards=FIELD),
    "two_observe, the field's rewards": kernels.Workload("two_observe", 300, rewards=FIELD),
    "two_observe, 4 agents, the field's rewards": kernels.Workload("two_observe", 20, WAREHOUSE, max_steps=SCALING,
                                                                  rewards=FIELD),
    "cq, 4 agents, the field's rewards": kernels.Workload("cq", 100, WAREHOUSE, own=cq.Settings(cq_solo_episodes=20),
                                                         max_steps=SCALING, rewards=FIELD),
}
COORDINATING = ("two_observe", "sparse_maq", "sparse_maq_pairs", "cq")


@pytest.mark.parametrize("case", WORKLOADS)
def test_gridworld_reference_plays_the_kernels_episodes(case):
    workload = WORKLOADS[case]
    compiled = kernels.run_compiled(workload, seed=5)
    log = compiled.log[0]
    np.testing.assert_array_equal(plain_gridworld.run(workload, KernelStream(kernels.run_state(5))), log)
    assert ep.metric(log, "collisions").sum() > 0  # the episodes have collisions
    if workload.learner in COORDINATING:
        assert ep.metric(log, "coordinations").sum() > 0  # and coordinated steps
    if workload.learner == "cq":
        assert compiled.arrays["marked"].any()  # CQ-learning's tests augmented states


def test_the_sparse_maq_reference_plays_groups_by_variable_elimination(monkeypatch):
    """Groups of three or more agents coordinate in the four-agent runs above: the reference's
    variable elimination is what plays the kernel's episodes there."""
    eliminations = []
    run = plain_gridworld.Elimination.run
    monkeypatch.setattr(plain_gridworld.Elimination, "run", lambda self: eliminations.append(1) or run(self))
    workload = WORKLOADS["sparse_maq, 4 agents"]
    log = plain_gridworld.run(workload, KernelStream(kernels.run_state(5)))
    np.testing.assert_array_equal(log, kernels.run_compiled(workload, seed=5).log[0])
    assert len(eliminations) > 100


@pytest.mark.parametrize("learner", sorted(plain_many_agents.REFERENCES))
@pytest.mark.parametrize("n_agents, episodes, bounce", [(2, 100, "previous"), (16, 3, "start"), (128, 1, "previous")])
def test_many_agent_reference_plays_the_kernels_episodes(learner, n_agents, episodes, bounce):
    """bench_many_agents' plain-Python reference (the index of cells in lists) plays the kernel's
    episodes on its generated warehouses, at its smallest and largest number of agents too."""
    workload = bench_many_agents.workload(learner, n_agents, episodes, max_steps=200, bounce=bounce)
    log = kernels.run_compiled(workload, seed=5).log[0]
    np.testing.assert_array_equal(plain_many_agents.run(workload, KernelStream(kernels.run_state(5))), log)
    assert ep.metric(log, "collisions").sum() > 0
    if learner != "independent":
        assert ep.metric(log, "coordinations").sum() > 0


@pytest.mark.parametrize("map_file", [TUNNEL, WAREHOUSE, SWAP, PAIRED_GOALS])
@pytest.mark.parametrize("bounce", sorted(BOUNCE_MODES))
@pytest.mark.parametrize("rewards", [CHAPTER, FIELD], ids=["chapter", "field"])
def test_rules_reference_ends_with_the_compiled_totals(map_file, bounce, rewards):
    gridmap = kernels.Workload("independent", 1, map_file).gridmap()
    actions = np.random.default_rng(0).integers(0, rules.N_ACTIONS, size=(20_000, gridmap.n_agents))
    compiled = kernels.walk_compiled(gridmap, bounce, actions, rewards)
    python = plain_gridworld.walk(plain_gridworld.World(gridmap, bounce, rewards), actions.tolist())
    assert python == compiled
    assert compiled[1] > 0 and compiled[2] > 0  # collisions and finished episodes


@pytest.mark.parametrize("init_scale", [0.0, 0.5])
def test_experiment_1_reference_learns_the_kernels_parameters(init_scale):
    config = single_gla.SingleGLAConfig(runs=1, iterations=4000, record_points=1, init_scale=init_scale)
    result = single_gla.run(config, seed=7, workers=parallel.Threads(1))
    total, u = plain_lineworld.single_gla_run(config, KernelStream(kernels.run_state(seeds.named(7, "single_gla"))))
    np.testing.assert_array_equal(np.array(u), result.params[0])
    assert total / config.iterations == result.reward[0, 0]


def test_experiment_2_reference_learns_the_kernels_parameters():
    config = and_network.ANDNetworkConfig(runs=1, iterations=4000, record_points=2)
    result = and_network.run(config, seed=7, workers=parallel.Threads(1))
    _, u = plain_lineworld.and_network_run(config, KernelStream(kernels.run_state(seeds.named(7, "and_network"))))
    context = len(u[0][0][0])
    np.testing.assert_array_equal(np.array(u), result.params[0, ..., :context])
