"""The PettingZoo-shaped GridworldEnv: dicts in and out, the same rules as the kernels, clear errors."""

import pytest

from glamas.gridworld import tunnel_to_goal
from glamas.gridworld.env import GridworldEnv
from glamas.gridworld.rules import E, N, S, W


@pytest.fixture
def env():
    env = GridworldEnv(tunnel_to_goal(), max_steps=50)
    env.reset(seed=0)
    return env


def test_reset_returns_the_starts(env):
    observations, infos = env.reset()
    assert env.agents == ["agent_1", "agent_2"]
    assert observations["agent_1"] == {"position": (0, 0), "others": ((4, 0),)}
    assert observations["agent_2"] == {"position": (4, 0), "others": ((0, 0),)}
    assert infos == {"agent_1": {}, "agent_2": {}}


def test_step_moves_and_rewards(env):
    observations, rewards, terminations, truncations, infos = env.step({"agent_1": E, "agent_2": W})
    assert observations["agent_1"]["position"] == (0, 1)
    assert observations["agent_2"]["position"] == (4, 0)
    assert rewards == {"agent_1": 0.0, "agent_2": -1.0}
    assert infos["agent_2"]["bumped"] and not infos["agent_1"]["bumped"]
    assert terminations == truncations == {"agent_1": False, "agent_2": False}


def test_optimal_episode_collision_free_and_terminating(env):
    # Agent 2 takes its shortest path; agent 1 yields once at (1, 4) by bumping east.
    plan_1 = [E, E, E, E, S, E, S, W, W, W, W]
    plan_2 = [N, E, E, E, E, N, W, W, W, W]
    totals = {"agent_1": 0.0, "agent_2": 0.0}
    for t in range(11):
        actions = {name: plan[t] for name, plan in (("agent_1", plan_1), ("agent_2", plan_2)) if name in env.agents}
        _, rewards, terminations, _, infos = env.step(actions)
        assert not any(info["collided"] for info in infos.values())
        for name, reward in rewards.items():
            totals[name] += reward
        if t == 9:
            assert terminations["agent_2"] and env.agents == ["agent_1"]
    assert totals == {"agent_1": 99.0, "agent_2": 100.0}
    assert env.agents == []


def test_collision_at_the_entrance(env):
    for action_1, action_2 in [(E, N), (E, E), (E, E), (E, E), (S, E)]:
        env.step({"agent_1": action_1, "agent_2": action_2})
    observations, rewards, _, _, infos = env.step({"agent_1": S, "agent_2": N})
    assert rewards == {"agent_1": -10.0, "agent_2": -10.0}
    assert infos["agent_1"]["collisions_in_step"] == 1
    assert observations["agent_1"]["position"] == (1, 4) and observations["agent_2"]["position"] == (3, 4)


def test_bounce_to_start():
    env = GridworldEnv(tunnel_to_goal(), bounce="start")
    env.reset()
    for action_1, action_2 in [(E, N), (E, E), (E, E), (E, E), (S, E)]:
        env.step({"agent_1": action_1, "agent_2": action_2})
    observations, *_ = env.step({"agent_1": S, "agent_2": N})
    assert observations["agent_1"]["position"] == (0, 0) and observations["agent_2"]["position"] == (4, 0)


def test_truncation():
    env = GridworldEnv(tunnel_to_goal(), max_steps=2)
    env.reset()
    env.step({"agent_1": N, "agent_2": S})
    _, _, terminations, truncations, _ = env.step({"agent_1": N, "agent_2": S})
    assert truncations == {"agent_1": True, "agent_2": True} and not any(terminations.values())
    assert env.agents == []


@pytest.mark.parametrize("actions, error, message", [
    ({"agent_1": N}, ValueError, r"no action for live agents \['agent_2'\]"),
    ({"agent_1": N, "agent_2": N, "agent_3": N}, ValueError, r"not live: \['agent_3'\]"),
    ({"agent_1": 4, "agent_2": N}, ValueError, r"action of agent_1 must be 0 \(N\), 1 \(E\), 2 \(S\) or 3 \(W\), got 4"),
    ({"agent_1": "N", "agent_2": N}, ValueError, r"action of agent_1 must be .* got 'N'"),
    ({"agent_1": True, "agent_2": N}, ValueError, r"action of agent_1 must be"),
    ([N, N], TypeError, r"actions must be a dict agent name -> action, got list"),
])
def test_bad_actions(env, actions, error, message):
    with pytest.raises(error, match=message):
        env.step(actions)


def test_step_before_reset_and_bad_arguments():
    with pytest.raises(RuntimeError, match=r"call reset\(\) before step\(\)"):
        GridworldEnv(tunnel_to_goal()).step({"agent_1": N, "agent_2": N})
    with pytest.raises(ValueError, match="bounce must be one of"):
        GridworldEnv(tunnel_to_goal(), bounce="home")
    with pytest.raises(ValueError, match="max_steps must be a positive integer, got 0"):
        GridworldEnv(tunnel_to_goal(), max_steps=0)
    with pytest.raises(ValueError, match="rewards must be a glamas.gridworld.rewards.Rewards, got 'field'"):
        GridworldEnv(tunnel_to_goal(), rewards="field")


def test_done_agent_action_rejected(env):
    env.reset()
    plan_2 = [N, E, E, E, E, N, W, W, W, W]
    for action in plan_2:
        env.step({"agent_1": N, "agent_2": action} if "agent_2" in env.agents else {"agent_1": N})
    with pytest.raises(ValueError, match=r"not live: \['agent_2'\]"):
        env.step({"agent_1": N, "agent_2": W})
