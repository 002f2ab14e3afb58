"""A learner is declared once: a toy learner with a setting of its own, defined and registered in
this file alone, runs in the gridworld experiments and in the scaling study by its name, its
setting held by its name in their configs; the registry keeps every learner's seeds whatever else
is registered, listed or trained, and in whatever order."""

import ast
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
import pytest
from numba import njit

from glamas import checks, parallel, rng, seeds
from glamas.experiments import gridworld as gw
from glamas.experiments import related_work as rw
from glamas.experiments import scaling as sc
from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners import registry
from glamas.learners.spec import Learner
from glamas.paths import REPO


@dataclass(frozen=True)
class WalkSettings:
    """The random walkers' own setting."""

    stay_prob: float = 0.0
    """Probability that an acting agent takes no step (it walks into a wall, the rules' bump)."""

    def __post_init__(self):
        checks.field_types(self)
        if not 0.0 <= self.stay_prob <= 1.0:
            raise ValueError(f"stay_prob must be in [0, 1], got {self.stay_prob!r}")


class Walk(NamedTuple):
    """The walkers' setting as their kernel reads it, named as WalkSettings."""

    stay_prob: float


@njit(cache=True, nogil=True)
def random_walk(world, learning, walk, schedule, q, log, state):
    """Agents that never learn: every acting agent moves in a direction drawn uniformly, or, with
    probability ``walk.stay_prob``, bumps into the border (a move north from the top row, else a
    move that stays)."""
    n_agents = world.starts.shape[0]
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n_agents)
    for episode in range(schedule.episodes):
        ep.start_episode(world.starts, cells, done, acc)
        t = 0
        while t < schedule.max_steps and not ep.all_done(done):
            for i in range(n_agents):
                actions[i] = rng.integer(state, rules.N_ACTIONS)
                if rng.uniform(state) < walk.stay_prob:
                    for a in range(rules.N_ACTIONS):
                        if world.next_cell[cells[i], a] == cells[i]:
                            actions[i] = a
            collisions = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, schedule.edges, acc, t, done)


RANDOM_WALK = Learner(name="random_walk", label="random walkers", kernel=random_walk,
                      table_shape=lambda n_cells, n_agents: (n_agents, n_cells, rules.N_ACTIONS),
                      defaults=WalkSettings(), inputs=lambda setup, gridmap: (Walk(setup.own.stay_prob),))


@pytest.fixture()
def registered():
    registry.register(RANDOM_WALK)
    yield RANDOM_WALK
    registry.unregister(RANDOM_WALK.name)


SMALL = {"episodes": 60, "runs": 2, "bins": 6, "max_steps": 2000}


def test_a_registered_learner_runs_beside_the_library_learners_with_its_own_setting(registered):
    config = rw.RelatedWorkConfig(learners=("independent", "sparse_maq", "random_walk"), **SMALL)
    assert config.own("random_walk") == WalkSettings()  # its defaults, held by its name
    result = rw.run(config, seed=1, workers=parallel.Threads(1))
    assert result.names() == ["independent", "sparse_maq", "random_walk"]
    walk = result.curves("random_walk", "steps")
    assert np.isfinite(walk).all() and (walk >= 10).all()
    assert result.local_entries[-1] == 25 * 4 and result.reward_samples[-1] == 0
    # registering it changed nobody's seeds: the library learners' curves are those without it
    alone = rw.run(replace(config, learners=("independent", "sparse_maq")), seed=1, workers=parallel.Threads(1))
    assert np.array_equal(result.log[:2], alone.log)
    # its setting reaches its kernel: walkers that mostly stay take longer
    slow = gw.run(gw.GridworldConfig(learners=("random_walk",), settings={"random_walk": WalkSettings(stay_prob=0.9)},
                                     **SMALL), seed=1, workers=parallel.Threads(1))
    assert slow.steps("random_walk").mean() > 2 * walk.mean()
    with pytest.raises(ValueError, match=r"stay_prob must be in \[0, 1\]"):
        WalkSettings(stay_prob=2.0)


def test_a_registered_learner_joins_the_scaling_study(registered):
    config = sc.ScalingConfig(agents=(2, 3), learners=("independent", "random_walk"), episodes=40, runs=2, bin_size=20)
    result = sc.run(config, seed=0, workers=parallel.Threads(1))
    assert result.ran.all() and result.table_shapes[1].tolist() == [[2, 35, 4], [3, 35, 4]]
    assert np.isfinite(result.curves("random_walk", 3, "collisions")).all()


def test_reordering_the_registry_or_the_learners_changes_no_result():
    config = gw.GridworldConfig(learners=("independent", "two_observe", "cq"), **SMALL)
    first = gw.run(config, seed=2, workers=parallel.Threads(1))
    order = list(registry.LEARNERS.items())
    try:
        registry.LEARNERS.clear()
        registry.LEARNERS.update(reversed(order))
        again = gw.run(replace(config, learners=("cq", "two_observe", "independent")), seed=2, workers=parallel.Threads(1))
    finally:
        registry.LEARNERS.clear()
        registry.LEARNERS.update(order)
    for name in config.learners:
        assert np.array_equal(first.curves(name, "reward"), again.curves(name, "reward")), name
    assert np.array_equal(first.output("two_observe", "u"), again.output("two_observe", "u"))


def test_unknown_learners_are_refused_by_name():
    with pytest.raises(ValueError, match="learners must be distinct names of registered learners"):
        rw.RelatedWorkConfig(learners=("random_walk",))
    with pytest.raises(ValueError, match="no learner 'random_walk'"):
        registry.get("random_walk")


def test_a_learner_of_no_family_or_of_a_bad_rank_is_refused(registered):
    with pytest.raises(ValueError, match="a learner's family must be one of"):
        registry.register(replace(RANDOM_WALK, name="walker", family="mine"))
    with pytest.raises(ValueError, match="its rank must be a whole number >= 0 or None"):
        registry.register(replace(RANDOM_WALK, name="walker", family="chapter", rank=-1))
    assert "walker" not in registry.LEARNERS


def test_a_second_learner_of_a_registered_name_is_refused_and_the_first_kept(registered):
    with pytest.raises(ValueError, match=r"a learner named 'independent' is registered already \(by "
                                         r"glamas\.learners\.independent\); \S*test_learner_spec must choose another name"):
        registry.register(replace(RANDOM_WALK, name="independent", family="chapter", rank=0))
    assert registry.get("independent").kernel.__module__ == "glamas.learners.independent"
    assert registry.register(RANDOM_WALK) is RANDOM_WALK  # the same module again: replaced


def test_seeds_are_named_by_the_experiment_and_the_learner(registered):
    """The gridworld experiment's are named by the seed, the experiment and the learner (a learner
    of one's own too); the scaling study's by the seed, the study, N and the learner."""
    assert [gw.seed_of(5, name) for name in (*gw.CHAPTER_LEARNERS, "random_walk")] == [
        seeds.named(5, "gridworld", name) for name in (*gw.CHAPTER_LEARNERS, "random_walk")]
    assert [sc.seed_of(2, name, 3) for name in sc.CHAPTER_METHODS] == [seeds.named(2, "scaling", 3, name)
                                                                       for name in sc.CHAPTER_METHODS]


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


def test_a_module_placed_in_the_learners_package_is_found_by_being_there(tmp_path, monkeypatch):
    import sys

    import glamas.learners
    (tmp_path / "dropped_in.py").write_text(
        "from dataclasses import replace\n"
        "from glamas.learners import independent\n"
        "from glamas.learners.registry import register\n"
        "LEARNER = register(replace(independent.LEARNER, name='dropped_in', family='other', rank=None))\n")
    monkeypatch.setattr(glamas.learners, "__path__", [*glamas.learners.__path__, str(tmp_path)])
    try:
        registry.discover()
        assert registry.get("dropped_in").label == "independent Q-learners"
        assert list(registry.LEARNERS)[-1] == "dropped_in"  # the library's own first, in their fixed order
    finally:
        registry.unregister("dropped_in")
        sys.modules.pop("glamas.learners.dropped_in", None)


def test_every_learner_the_library_declares_is_registered():
    import importlib
    import pkgutil

    import glamas.learners
    declared = {value.name for info in pkgutil.iter_modules(glamas.learners.__path__, "glamas.learners.")
                for value in vars(importlib.import_module(info.name)).values() if isinstance(value, Learner)}
    assert declared and declared <= set(registry.LEARNERS)
