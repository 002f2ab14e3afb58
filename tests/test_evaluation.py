"""The evaluation of what a run learned (glamas.training.evaluations): every learner's kernel,
run frozen from learned outputs, changes none of them; a frozen 2observe plays what a training
run plays when nothing it learns can change; the evaluations travel with their batch to every
backend and give the same numbers there."""

import numpy as np
import pytest

from glamas import parallel, rng, training
from glamas.experiments import gridworld as gw
from glamas.gridworld import load_map
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.qlearning import QLearning

LIBRARY = ("independent", "joint_state", "mmdp", "two_observe", "two_observe_rule", "sparse_maq", "cq")


@pytest.mark.parametrize("name", LIBRARY)
@pytest.mark.parametrize("map_name", ["tunnel_to_goal", "warehouse_3"])
def test_a_frozen_run_changes_nothing_it_learned(name, map_name):
    learner, gridmap = registry.get(name), load_map(map_name)
    setup = learner.setup(own=learner.defaults if name != "cq" else learner.defaults.__class__(cq_solo_episodes=20))
    schedule = ep.Schedule(60, ep.uniform_edges(60, 60), 500)
    learned = training.train(learner, setup, gridmap, schedule, 1, 5, workers=parallel.Threads(1))
    (evaluation,) = training.evaluations(learner, setup, gridmap, training.Evaluation(20, (0.9,)), 500, 5)
    copies = [array[0].copy() for array in learned.values()]
    copies[evaluation.log] = np.zeros_like(copies[evaluation.log])
    learner.kernel_for(gridmap.n_agents)(*evaluation.inputs, *copies, rng.run_states(9, 1)[0])
    for (key, array), played in zip(learned.items(), copies):
        if key == "log":
            assert ep.metric(played, "length")[0] > 0  # the evaluation played its episodes
        elif key not in learner.counters:  # 2observe counts the steps it observed: a count, not something learned
            assert np.array_equal(array[0], played), f"{name} changed {key}"


def test_a_frozen_2observe_plays_a_training_episode_that_learns_nothing():
    """A training run with both learning rates zero and exploitation 1 draws its GLAs and plays
    an episode; the frozen evaluation of those GLAs and tables, on the same stream after the
    GLAs' draws, plays the very same episode."""
    learner, gridmap = registry.get("two_observe"), load_map("tunnel_to_goal")
    setup = learner.setup()
    schedule = ep.Schedule(1, np.array([0, 1]), 200)
    q = np.random.default_rng(3).uniform(-1.0, 1.0, (1,) + learner.table_shape(gridmap.n_cells, gridmap.n_agents))
    u, u_initial, counts = (np.zeros((1,) + a.shape) for a in learner.outputs(setup, gridmap).values())
    world, _, automata, _ = spec.kernel_inputs(learner, setup, gridmap, schedule)
    still = (world, QLearning(0.0, 0.9, 1.0), automata._replace(gla_learning_rate=0.0), schedule)
    state = rng.run_states(4, 1)[0]
    after_draws = state.copy()
    for _ in range(u[0].size):  # the GLAs' initial parameters are the run's first draws
        rng.uniform(after_draws)
    trained_log = np.zeros((1, ep.n_columns(2)))
    learner.kernel_for(2)(*still, q[0].copy(), u[0], u_initial[0], counts[0], trained_log, state)
    (evaluation,) = training.evaluations(learner, setup, gridmap, training.Evaluation(1, (1.0,)), 200, 0)
    evaluated_log = np.zeros((1, ep.n_columns(2)))
    learner.kernel_for(2)(*evaluation.inputs, q[0].copy(), u[0].copy(), u_initial[0].copy(), counts[0].copy(),
                          evaluated_log, after_draws)
    assert np.array_equal(trained_log, evaluated_log) and ep.metric(trained_log, "length")[0] > 0


def test_an_experiment_keeps_every_evaluation_and_backends_agree():
    config = gw.GridworldConfig(learners=("independent", "two_observe"), runs=3, episodes=300, bins=10,
                                evaluation_episodes=7)
    threads = gw.run(config, workers=parallel.Threads(2))
    processes = gw.run(config, workers=2)
    assert threads.evaluated.shape == (2, 3, len(training.EVALUATIONS), ep.n_columns(2))
    assert np.array_equal(threads.evaluated, processes.evaluated) and np.array_equal(threads.log, processes.log)
    exploit = config.evaluation().exploits
    assert exploit == (1.0, 0.9, 1.0 - 1.0 / 20)  # greedy, the training's, one random action in 2 x 10 steps
    completion = threads.evaluation("two_observe", "completion")
    assert completion.shape == (3,) and ((0.0 <= completion) & (completion <= 1.0)).all()


def test_a_trapped_greedy_policy_has_no_solution_to_count_collisions_of():
    config = gw.GridworldConfig(learners=("independent",), runs=1, episodes=10, bins=5, max_steps=50,
                                evaluation_episodes=3)
    result = gw.run(config, workers=1)
    capped = dict(result.__dict__)
    capped["evaluated"] = result.evaluated.copy()
    capped["evaluated"][..., ep.column(2, ep.CAPPED)] = 1.0  # every greedy episode hit the cap
    m = gw.measure(type(result)(**capped))
    assert m["greedy_completion_independent"] == 0.0
    assert m["greedy_solution_collisions_independent"] == np.inf and np.isnan(m["collisions_per_perturbation_independent"])
