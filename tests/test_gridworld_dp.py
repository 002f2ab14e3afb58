"""Dynamic programming (Alg. 1, 2) on the joint MMDP of TunnelToGoal, checked against the optimum by hand.

By hand: each agent is 10 moves from the goal and 6 from the tunnel entrance (2, 4), the only
way in, so both cannot take a shortest path; one must reach the entrance a step later. The grid
is bipartite, so arriving one step late costs a wall bump (-1, arrival at 11) or two steps late
costs a two-step detour (arrival at 12, no penalty). Which is better depends on gamma.
"""

from pathlib import Path

import numpy as np
import pytest

from glamas.experiments import gridworld_optimum
from glamas.gridworld import dp, load_map, rules, tunnel_to_goal
from glamas.gridworld.rewards import Rewards


@pytest.fixture(scope="module")
def mdp():
    return dp.joint_mdp(tunnel_to_goal())


def test_tables(mdp):
    assert (mdp.n_states, mdp.n_joint_actions) == (625, 16)
    # 625 assignments minus the 24 with both agents on one non-goal cell.
    assert mdp.valid.sum() == 601
    start = mdp.start_state
    assert mdp.cells(start) == (0, 20)
    assert mdp.actions(1 * 4 + 0) == (1, 0)
    east_north = 1 * 4 + 0
    assert mdp.cells(int(mdp.next_state[start, east_north])) == (1, 15)
    assert mdp.reward[start, east_north] == 0.0
    goal = 10
    both_in = mdp.state((goal, goal))
    assert (mdp.next_state[both_in] == both_in).all() and (mdp.reward[both_in] == 0).all()


def test_shared_reward_only_when_the_last_agent_arrives(mdp):
    one_step_away = mdp.state((11, 20))  # agent 1 at (2, 1), agent 2 at its start
    west_north = 3 * 4 + 0
    assert mdp.agent_rewards[one_step_away, west_north].tolist() == [100.0, 0.0]
    assert mdp.reward[one_step_away, west_north] == 0.0
    last = mdp.state((10, 11))
    assert mdp.reward[last, 0 * 4 + 3] == 100.0


@pytest.mark.parametrize("gamma, steps, returns, bumps", [
    (0.9, [10, 11], [100.0, 99.0], 1),
    (0.95, [10, 11], [100.0, 99.0], 1),
    (0.99, [10, 12], [100.0, 100.0], 0),
])
def test_value_iteration_finds_the_hand_optimum(mdp, gamma, steps, returns, bumps):
    solution = dp.value_iteration(mdp, gamma)
    episode = dp.rollout(mdp, solution.policy)
    assert episode.finished and episode.collisions == 0
    assert sorted(episode.steps_to_goal.tolist()) == steps
    assert sorted(episode.returns.tolist(), reverse=True) == returns
    assert episode.bumps.sum() == bumps
    # V*(start) by hand: the last arrival pays 100 at its step, a bump costs 1 when it happens.
    late = max(steps)
    expected = 100.0 * gamma ** (late - 1)
    bump_steps = [t for t in range(len(episode.cells) - 1)
                  if any(episode.cells[t, i] == episode.cells[t + 1, i] and episode.cells[t, i] != 10 for i in range(2))]
    expected -= sum(gamma ** t for t in bump_steps)
    assert solution.values[mdp.start_state] == pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize("gamma", [0.9, 0.99])
def test_policy_iteration_agrees(mdp, gamma):
    by_values = dp.value_iteration(mdp, gamma, epsilon=1e-10)
    by_policies = dp.policy_iteration(mdp, gamma, epsilon=1e-10)
    assert np.abs(by_values.values - by_policies.values).max() < 1e-8
    a, b = dp.rollout(mdp, by_values.policy), dp.rollout(mdp, by_policies.policy)
    assert sorted(a.steps_to_goal.tolist()) == sorted(b.steps_to_goal.tolist())
    assert a.collisions == b.collisions == 0


def test_value_iteration_stops_on_the_epsilon_rule(mdp):
    # A loose epsilon stops earlier; the chapter's bound 2 eps gamma / (1 - gamma) still holds.
    gamma, eps = 0.9, 40.0
    loose = dp.value_iteration(mdp, gamma, eps)
    exact = dp.value_iteration(mdp, gamma, 1e-12)
    assert loose.iterations < exact.iterations
    policy_values = dp.policy_evaluation(mdp, loose.policy, gamma, 1e-12)
    assert np.abs(policy_values - exact.values).max() <= 2 * eps * gamma / (1 - gamma)


def test_selfish_shortest_paths_collide_at_the_entrance(mdp):
    episode = dp.rollout(mdp, dp.selfish_policy(mdp, 0.9), max_steps=10)
    assert not episode.finished
    assert episode.collisions == 5  # steps 6 to 10, every step at the entrance
    assert tuple(episode.cells[5]) == (9, 19)  # (1, 4) and (3, 4): both aim at (2, 4) next


def test_bounce_to_start_changes_nothing_at_the_optimum():
    episode = dp.optimal_rollout(tunnel_to_goal(), 0.9, bounce="start")
    assert sorted(episode.steps_to_goal.tolist()) == [10, 11] and episode.collisions == 0


def test_three_agents_in_a_small_room():
    room = load_map("+-+-+-+\n|1 . 2|\n+ + + +\n|. G 3|\n+-+-+-+\n")
    episode = dp.optimal_rollout(room, 0.9)
    assert episode.finished and episode.collisions == 0
    assert sorted(episode.steps_to_goal.tolist()) == [1, 2, 2]


@pytest.mark.parametrize("call, message", [
    (lambda m: dp.value_iteration(m, 1.0), r"gamma must be a discount factor in \(0, 1\)"),
    (lambda m: dp.policy_iteration(m, 0.9, epsilon=0), r"epsilon must be a number > 0"),
    (lambda m: dp.joint_mdp(m.gridmap, bounce="home"), r"bounce must be one of \['previous', 'start'\]"),
    (lambda m: dp.value_iteration(m, 0.9, max_sweeps=2), r"did not reach epsilon=.* in 2 sweeps"),
])
def test_bad_arguments(mdp, call, message):
    with pytest.raises((ValueError, RuntimeError), match=message):
        call(mdp)


def test_joint_mdp_refuses_huge_maps():
    big = load_map("+" + "-+" * 9 + "\n|1 2 3 4 5 6 7 8 G|\n+" + "-+" * 9 + "\n")
    with pytest.raises(ValueError, match="too large to tabulate"):
        dp.joint_mdp(big)


def test_experiment_measure_and_config_errors():
    metrics = gridworld_optimum.measure(gridworld_optimum.run(gridworld_optimum.GridworldOptimumConfig()))
    assert metrics["optimal_total_steps"] == 21 and metrics["optimal_collisions"] == 0
    assert metrics["value_gap"] < 1e-8 and metrics["selfish_collisions"] >= 1
    with pytest.raises(ValueError, match="no map file nowhere; give a map file's path or the name of a map in data/maps"):
        gridworld_optimum.GridworldOptimumConfig(map="nowhere")
    with pytest.raises(ValueError, match=r"gamma must be a float in \(0, 1\)"):
        gridworld_optimum.GridworldOptimumConfig(gamma=1.5)
    with pytest.raises(ValueError, match="bounce must be one of"):
        gridworld_optimum.GridworldOptimumConfig(bounce="home")


@pytest.mark.parametrize("field, value, message", [
    ("epsilon", 0.0, r"epsilon must be a float > 0"),
    ("selfish_steps", 0, r"selfish_steps must be a positive integer"),
    ("gamma", 1, r"gamma must be a float in \(0, 1\), got 1"),
])
def test_experiment_config_errors(field, value, message):
    with pytest.raises(ValueError, match=message):
        gridworld_optimum.GridworldOptimumConfig(**{field: value})


def test_plot_episode_rejects_unknown_episode():
    import matplotlib
    matplotlib.use("Agg")
    from glamas import plotting
    result = gridworld_optimum.run(gridworld_optimum.GridworldOptimumConfig())
    fig, ax = plotting.new_figure(3, 3)
    with pytest.raises(ValueError, match=r"which must be one of \['optimal', 'selfish'\], got 'best'"):
        gridworld_optimum.plot_episode(ax, result, "best")


# --- per-agent goals, the field's maps, and the search beyond the tables ---------------------------

SWAP_WITH_A_POCKET = Path(__file__).parent / "data" / "swap_with_a_pocket.txt"
"""Two agents swapping ends of a corridor with one pocket: one must step aside (a map file shared
with tests/test_plans.py)."""


def exhaustive_value(gridmap, gamma, bounce="previous"):
    """V*(start) by breadth-first search over every joint state the starts reach, step by step,
    keeping the best discounted shared reward to each; stops once no longer episode can be better
    (an episode ending after T steps is worth at most 100 gamma**(T - 1))."""
    world, n = rules.world(gridmap, bounce), gridmap.n_agents
    layer, best, t = {tuple(gridmap.starts.tolist()): 0.0}, -np.inf, 0
    while best < 100.0 * gamma ** t:
        following = {}
        for cells, value in layer.items():
            done = np.array([gridmap.is_goal_of(i, c) for i, c in enumerate(cells)])
            for joint in range(4 ** n):
                actions = np.array([joint // 4 ** (n - 1 - i) % 4 for i in range(n)], np.int64)
                out = (np.empty(n, np.int64), np.empty(n), np.empty(n, bool), np.empty(n, bool), np.empty(n, bool))
                rules.step(world, np.array(cells, np.int64), done, actions, *out)
                all_in = bool((done | out[4]).all())
                total = value + gamma ** t * rules.shared_reward(world.payoffs, out[1], out[4], all_in)
                if all_in:
                    best = max(best, total)
                else:
                    key = tuple(out[0].tolist())
                    following[key] = max(following.get(key, -np.inf), total)
        layer, t = following, t + 1
    return best


@pytest.mark.parametrize("bounce", ["previous", "start"])
def test_the_optimum_on_a_small_map_is_the_exhaustive_searchs(bounce):
    gridmap = load_map(SWAP_WITH_A_POCKET)
    mdp = dp.joint_mdp(gridmap, bounce)
    solution = dp.value_iteration(mdp, 0.9, epsilon=1e-12)
    expected = exhaustive_value(gridmap, 0.9, bounce)
    assert solution.values[mdp.start_state] == pytest.approx(expected, abs=1e-9)
    assert dp.searched_optimum(gridmap, 0.9, bounce).value == pytest.approx(expected, abs=1e-12)
    episode = dp.rollout(mdp, solution.policy)
    assert episode.finished and episode.collisions == 0 and dp.shortest_steps(gridmap).tolist() == [3, 3]
    assert max(episode.steps_to_goal) == 5  # one agent waits in the pocket while the other passes


@pytest.mark.parametrize("name, value, last", [
    ("tunnel_to_goal", 100 * 0.9 ** 10 - 0.9 ** 5, 11),
    ("isr", 100 * 0.9 ** 5, 6),
    ("cit", 100 * 0.9 ** 12 - 0.9 ** 5, 13),
    ("cmu", 100 * 0.9 ** 32, 33),
])
def test_two_agent_field_maps_value_iteration_and_search_agree(name, value, last):
    gridmap = load_map(name)
    mdp = dp.joint_mdp(gridmap)
    solution = dp.value_iteration(mdp, 0.9)
    episode = dp.rollout(mdp, solution.policy)
    assert episode.finished and episode.collisions == 0 and max(episode.steps_to_goal) == last
    searched = dp.searched_optimum(gridmap, 0.9)
    assert solution.values[mdp.start_state] == pytest.approx(value, abs=1e-9)
    assert searched.value == pytest.approx(value, abs=1e-9) and max(searched.episode.steps_to_goal) == last


@pytest.mark.parametrize("name, value, steps", [
    ("tunnel_to_goal_3", 100 * 0.9 ** 11 - 0.9 ** 4, [10, 11, 12]),
    # agents 2 and 4 cannot wait by a wall bump at the tunnels' entrances (no wall there) and bump earlier
    ("tunnel_to_goal_4", 100 * 0.9 ** 10 - 2 * 0.9 ** 4, [10, 11, 11, 10]),
])
def test_three_and_four_agents_by_search(name, value, steps):
    gridmap = load_map(name)
    found = dp.searched_optimum(gridmap, 0.9)
    assert found.value == pytest.approx(value, abs=1e-9) and found.episode.steps_to_goal.tolist() == steps
    assert found.episode.finished and found.episode.collisions == 0
    bounds = dp.optimum_bounds(gridmap, 0.9)
    assert bounds.steps.tolist() == [10] * gridmap.n_agents and bounds.episode_steps == 10
    assert found.value <= bounds.value == pytest.approx(100 * 0.9 ** 9)
    assert found.episode.returns.sum() <= bounds.returns == 100.0 * gridmap.n_agents


def test_the_four_agent_tables_do_not_fit():
    gridmap = load_map("tunnel_to_goal_4")
    assert dp.tabulated_bytes(gridmap) > 100e9  # 55**4 joint states x 256 joint actions
    with pytest.raises(ValueError, match=r"149\.9 GB of tables\): too large to tabulate; use searched_optimum"):
        dp.joint_mdp(gridmap)


def test_three_agents_value_iteration_agrees_with_the_search():
    gridmap = load_map("tunnel_to_goal_3")
    mdp = dp.joint_mdp(gridmap)
    solution = dp.value_iteration(mdp, 0.9)
    assert solution.values[mdp.start_state] == pytest.approx(dp.searched_optimum(gridmap, 0.9).value, abs=1e-9)


def test_goal_distances_and_the_search_refusals():
    gridmap = load_map(SWAP_WITH_A_POCKET)
    assert dp.goal_distances(gridmap).tolist() == [[3, 2, 1, 0, -1, 3, -1, -1], [0, 1, 2, 3, -1, 2, -1, -1]]
    with pytest.raises(RuntimeError, match=r"within 3 steps is provably optimal; raise max_steps"):
        dp.searched_optimum(gridmap, 0.9, max_steps=3)
    with pytest.raises(ValueError, match=r"would try 16 joint moves after 0 steps \(more than 10\)"):
        dp.searched_optimum(gridmap, 0.9, max_candidates=10)


def test_the_mdp_pays_the_given_rewards(mdp):
    """Under another collision reward every colliding joint move pays it in place of the chapter's."""
    other = dp.joint_mdp(tunnel_to_goal(), rewards=Rewards(collision=-25.0))
    hit = mdp.collisions > 0
    assert hit.any()
    np.testing.assert_array_equal(other.agent_rewards[hit], mdp.agent_rewards[hit] - 15.0)
    np.testing.assert_array_equal(other.agent_rewards[~hit], mdp.agent_rewards[~hit])
