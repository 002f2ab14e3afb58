"""The PettingZoo ParallelEnv adapter: PettingZoo's own API and seed tests, the same moves as
GridworldEnv, agents leaving at the goal, text rendering, and the error without the extra."""

import importlib
import subprocess
import sys

import numpy as np
import pytest
from pettingzoo.test import parallel_api_test, parallel_seed_test

from glamas.gridworld import GridworldEnv, load_map, tunnel_to_goal
from glamas.gridworld.generate import warehouse
from glamas.gridworld.pettingzoo_env import GridworldParallelEnv
from glamas.gridworld.rules import E, N, S, W
from glamas.paths import MAPS

THREE_AGENTS = """\
+-+-+-+-+
|1 . . 3|
+ +-+ + +
|. . . .|
+ + +-+ +
|2 . G .|
+-+-+-+-+
"""


@pytest.mark.filterwarnings("error")  # the API test warns about API faults
@pytest.mark.parametrize("gridmap", [tunnel_to_goal(), load_map(THREE_AGENTS)], ids=["tunnel", "three-agents"])
def test_pettingzoo_parallel_api_test_passes(gridmap):
    parallel_api_test(GridworldParallelEnv(gridmap, max_steps=60), num_cycles=200)


@pytest.mark.filterwarnings("error")
def test_pettingzoo_parallel_seed_test_passes():
    parallel_seed_test(lambda: GridworldParallelEnv(max_steps=60), num_cycles=100)


FIELD_MAPS = ["tunnel_to_goal_3", "tunnel_to_goal_4", "isr", "cit", "cmu"]
"""The field's maps by name, each agent with its own goals (data/maps)."""


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("name", FIELD_MAPS)
def test_pettingzoo_tests_pass_on_every_field_map(name):
    parallel_api_test(GridworldParallelEnv(name, max_steps=60), num_cycles=200)
    parallel_seed_test(lambda: GridworldParallelEnv(name, max_steps=60), num_cycles=100)


@pytest.fixture(scope="module")
def warehouse_128():
    return warehouse(128, seed=0)


@pytest.mark.filterwarnings("error")
def test_pettingzoo_tests_pass_with_128_agents(warehouse_128):
    parallel_api_test(GridworldParallelEnv(warehouse_128, max_steps=30), num_cycles=40)
    parallel_seed_test(lambda: GridworldParallelEnv(warehouse_128, max_steps=30), num_cycles=20)


def test_an_agent_is_done_in_its_own_goal_only():
    env = GridworldParallelEnv("isr", render_mode="ansi")  # agent 1 starts on agent 2's goal (6, 3), and back
    env.reset()
    assert env.render().splitlines()[-2:] == ["goal 1: row 7, col 0", "goal 2: row 6, col 3"]
    # agent 1 steps aside into the pocket (8, 3), waits by a bump, and agent 2 passes to its goal
    for action_1, action_2 in [(S, E), (S, E), (E, E), (N, N)]:
        _, rewards, terminations, _, _ = env.step({"agent_1": action_1, "agent_2": action_2})
    assert terminations == {"agent_1": False, "agent_2": True} and rewards == {"agent_1": 0.0, "agent_2": 100.0}
    assert env.agents == ["agent_1"]
    for _ in range(3):
        _, rewards, terminations, _, _ = env.step({"agent_1": W})
    assert terminations == {"agent_1": True} and rewards == {"agent_1": 100.0} and env.agents == []


def test_moves_are_gridworld_env_moves_and_observations_its_dicts_flattened():
    adapter, game = GridworldParallelEnv(load_map(THREE_AGENTS), max_steps=40), GridworldEnv(load_map(THREE_AGENTS), max_steps=40)
    observations, _ = adapter.reset(seed=3)
    expected, _ = game.reset()
    choices = np.random.default_rng(0).integers(0, 4, size=(40, 3))
    for t in range(40):
        for name, obs in expected.items():
            flat = [*obs["position"], *(x for cell in obs["others"] for x in cell)]
            assert observations[name].tolist() == flat and observations[name] in adapter.observation_space(name)
        if not game.agents:
            break
        actions = {name: int(choices[t, k]) for k, name in enumerate(game.possible_agents) if name in game.agents}
        observations, rewards, terminations, truncations, infos = adapter.step(actions)
        expected, *others = game.step(actions)
        assert [rewards, terminations, truncations, infos] == others
        assert adapter.agents == game.agents
    assert adapter.state().tolist() == [x for c in game.cells for x in game.gridmap.row_col(int(c))]


def test_an_agent_in_the_goal_is_terminated_and_removed():
    env = GridworldParallelEnv(max_steps=50)
    env.reset()
    plan_1 = [E, E, E, E, S, E, S, W, W, W, W]  # the collision-free episode of test_gridworld_env
    plan_2 = [N, E, E, E, E, N, W, W, W, W]
    for t in range(10):
        _, rewards, terminations, _, _ = env.step({"agent_1": plan_1[t], "agent_2": plan_2[t]})
    assert terminations == {"agent_1": False, "agent_2": True} and rewards["agent_2"] == 100.0
    assert env.agents == ["agent_1"]
    with pytest.raises(ValueError, match=r"actions for agents that are not live: \['agent_2'\]"):
        env.step({"agent_1": W, "agent_2": N})
    _, _, terminations, _, _ = env.step({"agent_1": plan_1[10]})
    assert terminations == {"agent_1": True} and env.agents == []


def test_spaces_are_fixed_per_agent_and_describe_the_map():
    env = GridworldParallelEnv(load_map(THREE_AGENTS))
    assert env.observation_space("agent_2") is env.observation_space("agent_2")
    assert env.observation_space("agent_1").nvec.tolist() == [3, 4] * 3
    assert env.action_space("agent_3").n == 4 and env.possible_agents == ["agent_1", "agent_2", "agent_3"]


def test_render_draws_the_map_file_with_the_agents():
    env = GridworldParallelEnv(render_mode="ansi")
    env.reset()
    assert env.render() == (MAPS / "tunnel_to_goal.txt").read_text().rstrip("\n")
    env.step({"agent_1": E, "agent_2": N})
    assert env.render().splitlines()[1] == "|. 1 . . .|" and env.render().splitlines()[7] == "|2 . . . .|"


def test_bad_render_choices_are_rejected():
    with pytest.raises(ValueError, match=r"render_mode must be None or one of \['ansi'\], got 'human'"):
        GridworldParallelEnv(render_mode="human")
    env = GridworldParallelEnv()
    env.reset()
    with pytest.raises(ValueError, match="render\\(\\) needs render_mode='ansi'"):
        env.render()


def test_without_the_extra_the_adapter_names_it_and_glamas_still_imports(monkeypatch):
    monkeypatch.setitem(sys.modules, "pettingzoo", None)  # makes `import pettingzoo` fail
    monkeypatch.delitem(sys.modules, "glamas.gridworld.pettingzoo_env")
    with pytest.raises(ImportError, match=r"optional extra 'pettingzoo'.*pip install -e '\.\[pettingzoo\]'"):
        importlib.import_module("glamas.gridworld.pettingzoo_env")
    code = ("import sys; sys.modules['pettingzoo'] = sys.modules['gymnasium'] = None; "
            "import glamas.gridworld, glamas.experiments.gridworld")
    subprocess.run([sys.executable, "-c", code], check=True)
