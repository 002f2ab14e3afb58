"""The reward formulation (glamas.gridworld.rewards): an episode's rewards by hand under each
preset, the values reaching the learners' kernels, and the field's settings in the benchmark."""

import dataclasses

import numpy as np
import pytest

from glamas import training
from glamas.errors import UserError
from glamas.experiments import benchmark_maps, gridworld
from glamas.gridworld import GridworldEnv, load_map, rules
from glamas.gridworld.rewards import CHAPTER, FIELD, PRESETS, Rewards, preset
from glamas.gridworld.rules import E, N, W
from glamas.learners import episode as ep
from glamas.learners import registry
from glamas.plain import gridworld as plain_gridworld
from glamas.plain import many_agents as plain_many_agents

CORRIDOR = """\
+-+-+-+-+
|1 . 2 G|
+-+-+-+-+
"""
SCRIPT = [  # (action of agent 1, of agent 2), cells 0..3 from the left, G the goal of both
    (E, N),  # 1 moves to cell 1; 2 bumps into the border
    (E, N),  # 1 aims at cell 2, where 2 bumps again: a collision, both stay
    (W, E),  # 1 moves back to cell 0; 2 enters the goal
    (E, None),
    (E, None),
    (E, None),  # 1 enters the goal
]
BY_HAND = {
    # chapter: a move pays 0, a bump -1, a collision -10 added, the goal +100
    "chapter": [(0.0, -1.0), (-10.0, -11.0), (0.0, 100.0), (0.0,), (0.0,), (100.0,)],
    # field: a move or a bump pays -1, a collision -10 in place of it, the goal 0 besides the move
    "field": [(-1.0, -1.0), (-10.0, -10.0), (-1.0, -1.0), (-1.0,), (-1.0,), (-1.0,)],
}


@pytest.mark.parametrize("name", BY_HAND)
def test_an_episode_pays_what_the_formulation_says(name):
    env = GridworldEnv(load_map(CORRIDOR), rewards=preset(name))
    env.reset()
    paid = []
    for moves in SCRIPT:
        actions = {agent: a for agent, a in zip(env.possible_agents, moves) if agent in env.agents}
        _, rewards, terminations, _, infos = env.step(actions)
        paid.append(tuple(rewards[agent] for agent in actions))
    assert paid == BY_HAND[name]
    assert terminations == {"agent_1": True} and not env.agents


def test_the_chapters_formulation_is_the_default_and_the_chapters_values():
    assert Rewards() == CHAPTER == PRESETS["chapter"]
    assert (CHAPTER.goal, CHAPTER.move, CHAPTER.bump, CHAPTER.collision) == (100.0, 0.0, -1.0, -10.0)
    assert not CHAPTER.collision_replaces_move and FIELD.collision_replaces_move


@pytest.mark.parametrize("changes, named", [({"goal": float("nan")}, "Rewards.goal"), ({"move": "-1"}, "Rewards.move"),
                                            ({"collision_replaces_move": 1}, "Rewards.collision_replaces_move")])
def test_a_bad_value_is_one_line_naming_the_field(changes, named):
    with pytest.raises(UserError, match=named):
        Rewards(**changes)
    with pytest.raises(UserError, match="chapter"):
        preset("fieldish")


def _rewards_learned(rewards: Rewards) -> np.ndarray:
    learner = registry.get("independent")
    out = training.train(learner, learner.setup(), load_map("isr"), ep.Schedule(20, ep.log_edges(20, 2), 200), 2, 0,
                         rewards=rewards, workers=1)
    return ep.metric(out["log"], "reward")


CHANGED = {"goal": {"goal": 99.5}, "move": {"move": -0.5}, "bump": {"bump": -1.5}, "collision": {"collision": -10.5},
           "collision_replaces_move": {"move": -1.0, "collision_replaces_move": True}}
"""One value changed from the chapter's (where a collision replaces a move that costs, so that
replacing differs from adding)."""


@pytest.mark.parametrize("field", CHANGED)
def test_every_value_reaches_the_kernel(field):
    """A run with one value changed pays other rewards (the same seed, so the same first episode)."""
    base = dataclasses.replace(CHAPTER, **{name: value for name, value in CHANGED[field].items() if name != field})
    changed = dataclasses.replace(CHAPTER, **CHANGED[field])
    assert not np.array_equal(_rewards_learned(changed), _rewards_learned(base))


def test_the_field_formulation_comes_with_the_fields_learning_settings():
    config = benchmark_maps.configured("field", runs=2)
    assert config.rewards == FIELD and config.runs == 2
    assert (config.q.q_learning_rate, config.q.discount, config.q.exploit_prob) == (0.1, 1.0, 0.9)
    assert (config.settings["cq"].cq_solo_episodes, config.settings["cq"].cq_solo_exploit_prob) == (10_000, 0.2)
    assert benchmark_maps.configured("chapter") == benchmark_maps.BenchmarkConfig()
    with pytest.raises(UserError, match="formulation must be one of"):
        benchmark_maps.configured("pogema")


def test_the_push_margin_by_hand():
    """Next to the goal, under the chapter's rewards: pushing scores -10 + 0.9 * 100 = 80, backing off
    0.9 * 90 = 81; under the field's, -10 - 1 against -1 - 2, at every distance."""
    assert benchmark_maps.push_margin(CHAPTER, 0.9, 1) == pytest.approx(-1.0)
    assert benchmark_maps.push_margin(CHAPTER, 0.9, 2) == pytest.approx(0.09 * 90 - 10)
    assert [benchmark_maps.push_margin(FIELD, 1.0, d) for d in (1, 5, 30)] == [-8.0, -8.0, -8.0]


OTHER_COLLISION = Rewards(collision=-25.0)
"""The chapter's rewards but for the collision's."""


def _swap(gridmap):
    """Two cells a, b of ``gridmap`` with a move east from a to b and west back, neither a goal."""
    goal = gridmap.goal_table()
    for a in range(gridmap.n_cells):
        b = gridmap.next_cell[a, E]
        if b != a and gridmap.next_cell[b, W] == a and not goal[:, [a, b]].any():
            return a, b
    raise AssertionError("no two cells to swap on")


@pytest.mark.parametrize("rewards", [CHAPTER, OTHER_COLLISION], ids=["chapter", "other collision"])
def test_the_chapters_experiment_pays_its_rewards_on_every_path_and_in_the_references(rewards):
    """Two agents swapping cells on the chapter's map collide: the world of the chapter's gridworld
    experiment under ``rewards`` pays each the collision's reward on every path of the rules, and
    the plain-Python references pay the same."""
    config = gridworld.GridworldConfig(learners=("independent",), runs=1, episodes=10, rewards=rewards)
    [(work, _)] = gridworld.trainings(config)
    world, gridmap = work.inputs[0], config.gridmap()
    assert world.payoffs == rewards.kernel_bundle()
    a, b = _swap(gridmap)
    cells, done, actions = np.array([a, b]), np.zeros(2, bool), np.array([E, W])
    out = (np.empty(2, np.int64), np.empty(2), np.empty(2, bool), np.empty(2, bool), np.empty(2, bool))
    paid = []
    for step in (lambda: rules.step(world, cells, done, actions, *out),
                 lambda: rules.step_pair(world, cells, done, actions, *out, (0, 1)),
                 lambda: rules.step_indexed(world, rules.cell_index(world), cells, done, actions, *out)):
        assert step() == 1
        paid.append(out[1].tolist())
    python = plain_gridworld.World(gridmap, config.bounce, rewards)
    paid += [python.step_two([a, b], [False, False], [E, W])[1], python.step([a, b], [False, False], [E, W])[1],
             plain_many_agents.IndexedWorld(gridmap, config.bounce, rewards).step([a, b], [False, False], [E, W])[1]]
    assert paid == [[rewards.collision] * 2] * len(paid)
