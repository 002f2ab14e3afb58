"""A learner is declared once: a toy learner defined and registered in this file alone runs in the
related-work comparison and in the scaling study by its name, and the registry keeps every
library learner's seeds whatever else is registered."""

import ast
from dataclasses import replace

import numpy as np
import pytest
from numba import njit

from glamas import parallel, rng
from glamas.experiments import gridworld as gw
from glamas.experiments import related_work as rw
from glamas.experiments import scaling as sc
from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners import registry
from glamas.learners.spec import Learner
from glamas.paths import REPO


@njit(cache=True, nogil=True)
def random_walk(world, learning, schedule, q, log, state):
    """Agents that never learn: every acting agent moves in a direction drawn uniformly."""
    n_agents = world.starts.shape[0]
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n_agents)
    for episode in range(schedule.episodes):
        ep.start_episode(world.starts, cells, done, acc)
        t = 0
        while t < schedule.max_steps and not ep.all_done(done):
            for i in range(n_agents):
                actions[i] = rng.integer(state, rules.N_ACTIONS)
            collisions = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, schedule.edges, acc, t, done)


RANDOM_WALK = Learner(name="random_walk", label="random walkers", kernel=random_walk,
                      table_shape=lambda n_cells, n_agents: (n_agents, n_cells, rules.N_ACTIONS))


@pytest.fixture()
def registered():
    registry.register(RANDOM_WALK)
    yield RANDOM_WALK
    registry.unregister(RANDOM_WALK.name)


def test_a_registered_learner_runs_beside_the_chapters_learners(registered):
    chapter = gw.GridworldConfig(learners=("independent",), episodes=60, runs=2, bins=6, max_steps=2000)
    config = rw.RelatedWorkConfig(gridworld=chapter, learners=("sparse_maq", "random_walk"))
    result = rw.run(config, seed=1, workers=parallel.Threads(1))
    assert result.names() == ["independent", "sparse_maq", "random_walk"]
    walk = result.curves("random_walk", "steps")
    assert np.isfinite(walk).all() and (walk >= 10).all()
    assert result.local_entries[-1] == 25 * 4 and result.reward_samples[-1] == 0
    # registering it changed nobody's seeds: the library learners' curves are those without it
    alone = rw.run(rw.RelatedWorkConfig(gridworld=chapter, learners=("sparse_maq",)), seed=1, workers=parallel.Threads(1))
    assert np.array_equal(result.log[:2], alone.log)


def test_a_registered_learner_joins_the_scaling_study(registered):
    config = sc.ScalingConfig(agents=(2, 3), methods=("independent", "random_walk"), episodes=40, runs=2, bin_size=20)
    result = sc.run(config, seed=0, workers=parallel.Threads(1))
    assert result.ran.all() and result.table_shapes[1].tolist() == [[2, 35, 4], [3, 35, 4]]
    assert np.isfinite(result.curves("random_walk", 3, "collisions")).all()


def test_unknown_learners_are_refused_by_name():
    with pytest.raises(ValueError, match="learners must be distinct names from"):
        rw.RelatedWorkConfig(learners=("random_walk",))
    with pytest.raises(ValueError, match="no learner 'random_walk'"):
        registry.get("random_walk")


def test_a_learner_of_no_family_or_with_anothers_seeds_is_refused(registered):
    with pytest.raises(ValueError, match="a learner's family must be one of"):
        registry.register(replace(RANDOM_WALK, name="walker", family="mine"))
    # walker_384911 falls on random_walk's seed slot (crc32 of the name modulo NAME_SLOTS)
    with pytest.raises(ValueError, match="would draw the seeds of 'random_walk'; choose another name"):
        registry.register(replace(RANDOM_WALK, name="walker_384911"))
    assert "walker" not in registry.LEARNERS and "walker_384911" not in registry.LEARNERS


def test_library_seeds_are_the_committed_formulas():
    assert [registry.master_seed(5, gw.LEARNERS, name) for name in gw.LEARNERS] == [20, 21, 22, 23]
    assert [registry.master_seed(5, rw.RELATED_LEARNERS, name, "related") for name in rw.RELATED_LEARNERS] == \
        [2 ** 32 + 10, 2 ** 32 + 11]
    assert registry.master_seed(0, (), "random_walk", "other") != registry.master_seed(1, (), "random_walk", "other")


def test_every_compiled_function_takes_at_most_ten_parameters():
    """Settings travel in named bundles (glamas.learners.spec), not in long positional lists where
    two swapped numbers would go unnoticed."""
    long = []
    for path in sorted((REPO / "lib" / "glamas").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            compiled = isinstance(node, ast.FunctionDef) and any("njit" in ast.unparse(d) for d in node.decorator_list)
            if compiled and len(node.args.args) > 10:
                long.append(f"{path.name}:{node.name} ({len(node.args.args)})")
    assert not long
