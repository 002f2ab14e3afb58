"""The Section 5.3 learners: table shapes, small runs of each, seeding, and 2observe's first level."""

import numpy as np
import pytest

from glamas.experiments import gridworld as gw
from glamas.gridworld import rules, tunnel_to_goal
from glamas.gridworld.rules import E, N, S, W
from glamas.learners import independent, joint_state, mmdp, two_observe
from glamas.learners.two_observe import ACT_ALONE, COORDINATE, first_level, gla_feedback, yield_at_random
from glamas.rng import run_states

SMALL = gw.GridworldConfig(episodes=200, runs=2, bins=20)


def test_table_shapes_follow_section_5_3():
    assert independent.table_shape(25, 2) == (2, 25, 4)
    assert joint_state.table_shape(25, 2) == (2, 625, 4)
    assert mmdp.table_shape(25, 2) == (1, 625, 16)
    assert two_observe.table_shape(25, 2) == (2, 25, 4)
    assert two_observe.outputs(SMALL, SMALL.gridmap())["u"].shape == (2, 2, 2)


def test_mmdp_joint_action_components():
    actions = np.zeros(2, np.int64)
    mmdp.split_joint_action(7, actions)
    assert actions.tolist() == [1, 3]
    mmdp.split_joint_action(12, actions)
    assert actions.tolist() == [3, 0]


@pytest.fixture(scope="module")
def small_result():
    return gw.run(SMALL, seed=5, workers=1)


def test_every_learner_runs_and_its_log_is_consistent(small_result):
    for name in gw.CHAPTER_LEARNERS:
        steps = small_result.curves(name, "steps")
        assert np.isfinite(small_result.log).all()
        assert (steps >= 10).all(), name  # 10 moves is the shortest path of either agent
        assert (small_result.curves(name, "length") >= steps).all()
        assert (small_result.reward(name) <= 100).all()
        capped = small_result.curves(name, "capped")  # early positive-value loops can hit the cap
        assert ((0 <= capped) & (capped <= 1)).all()
        assert (small_result.curves(name, "length") <= SMALL.max_steps).all()
        if name != "two_observe":
            assert (small_result.curves(name, "coordinations") == 0).all()
    assert small_result.table_shapes.tolist() == [[2, 25, 4], [2, 625, 4], [1, 625, 16], [2, 25, 4]]
    assert np.abs(small_result.output("two_observe", "u")).max() > 0  # initialised randomly


def test_learners_learn_the_way_to_the_goal(small_result):
    # After a few hundred episodes the learners need far fewer steps than the early random walk.
    for name in ("independent", "two_observe"):
        steps = small_result.steps(name).mean(axis=0)
        assert steps[-1] < 0.5 * steps[0], name


def test_same_seed_same_results_for_one_and_two_workers(small_result):
    two = gw.run(SMALL, seed=5, workers=2)
    assert np.array_equal(small_result.log, two.log)
    assert np.array_equal(small_result.output("two_observe", "u"), two.output("two_observe", "u"))
    assert not np.array_equal(small_result.log, gw.run(SMALL, seed=6, workers=1).log)


def test_a_learner_gets_the_same_streams_whatever_it_is_trained_with(small_result):
    alone = gw.run(gw.GridworldConfig(episodes=200, runs=2, bins=20, learners=("mmdp",)), seed=5, workers=1)
    assert np.array_equal(alone.log[0], small_result.log[2])


# --- 2observe's first level (Alg. 4, Sec. 5.2), case by case --------------------------------

@pytest.fixture()
def tunnel_entrance():
    """Agents just above and below the tunnel entrance E = (2, 4), both heading into it."""
    g = tunnel_to_goal()
    cells = np.array([g.cell(1, 4), g.cell(3, 4)])
    return g, cells, np.zeros(2, np.bool_), np.array([S, N])


def _first_level(g, cells, done, choices, preferred, state):
    """The actions of Alg. 4's first level, as the kernel plays it."""
    coming, both = first_level(g.next_cell, g.goals, cells, done, np.array(choices), preferred, (0, 1))
    actions = preferred.copy()
    if both and coming:
        yield_at_random(preferred, actions, (0, 1), state)
    return actions, coming, both


def test_both_coordinate_and_a_collision_is_coming_one_random_agent_yields(tunnel_entrance):
    g, cells, done, preferred = tunnel_entrance
    state = run_states(3, 1)[0]
    yielders = []
    for _ in range(3000):
        actions, coming, both = _first_level(g, cells, done, (COORDINATE, COORDINATE), preferred, state)
        assert coming and both
        changed = np.flatnonzero(actions != preferred)
        assert changed.size == 1  # one keeps its action, the other takes another one
        yielders.append((changed[0], actions[changed[0]]))
    agents = np.array([y[0] for y in yielders])
    assert abs(agents.mean() - 0.5) < 0.04
    others = [a for agent, a in yielders if agent == 0]
    assert set(others) == {N, E, W}  # all other actions of agent 0 (preferred S), about equally
    assert min(others.count(a) for a in (N, E, W)) > 0.25 * len(others)


@pytest.mark.parametrize("choices", [(COORDINATE, ACT_ALONE), (ACT_ALONE, COORDINATE), (ACT_ALONE, ACT_ALONE)])
def test_unless_both_coordinate_the_agents_play_their_preferred_actions(tunnel_entrance, choices):
    g, cells, done, preferred = tunnel_entrance
    actions, coming, both = _first_level(g, cells, done, choices, preferred, run_states(0, 1)[0])
    assert coming and not both
    assert actions.tolist() == preferred.tolist()  # the collision happens


def test_both_coordinate_without_a_collision_coming_keeps_the_preferred_actions(tunnel_entrance):
    g, cells, done, _ = tunnel_entrance
    preferred = np.array([W, E])
    actions, coming, both = _first_level(g, cells, done, (COORDINATE, COORDINATE), preferred, run_states(0, 1)[0])
    assert both and not coming
    assert actions.tolist() == [W, E]


def test_gla_feedback_table_and_needless_coordination_penalty():
    table = np.array(two_observe.GLASettings().gla_feedback)
    assert gla_feedback(table, 0.1, ACT_ALONE, False, False, 3) == 1.0
    assert gla_feedback(table, 0.1, ACT_ALONE, True, False, 3) == 0.0
    assert gla_feedback(table, 0.1, COORDINATE, True, True, 2) == 1.0
    assert gla_feedback(table, 0.1, COORDINATE, True, False, 2) == 1.0
    assert gla_feedback(table, 0.1, COORDINATE, False, False, 3) == 0.0
    assert gla_feedback(table, 0.1, COORDINATE, False, True, 3) == pytest.approx(-0.3)  # 0 - delta/10
    other = np.array([[1.0, 0.0], [1.0, 1.0]])
    assert gla_feedback(other, 0.1, COORDINATE, False, True, 4) == pytest.approx(0.6)


def test_two_observe_counts_its_observed_steps_by_distance(small_result):
    counts = small_result.output("two_observe", "need_counts")
    assert counts.shape == (2, 9, 2)  # deltas 0 .. 8 on the 5 x 5 map
    assert counts[:, 0].sum() == 0  # two acting agents never share a cell
    assert counts[:, 1:3, 1].sum() > 0  # in range at distances 1 and 2 (the default reading)
    assert counts[:, 3:, 1].sum() == 0  # and never farther apart
    assert gw.need_probability(small_result).shape == (9,)


def test_fixed_rule_first_level_replaces_the_glas():
    def ruled(distance):
        config = gw.GridworldConfig(episodes=200, runs=2, bins=2, learners=("two_observe",),
                                    settings={"two_observe": two_observe.GLASettings(rule_distance=distance)})
        return gw.run(config, seed=2, workers=1)
    never, always = ruled(0), ruled(99)
    assert (never.curves("two_observe", "coordinations") == 0).all()
    # coordinating at every distance: every observed step is a coordination
    observed = always.output("two_observe", "need_counts").sum(axis=(1, 2)) / 2  # each agent counts the step it observed
    assert np.allclose(always.curves("two_observe", "coordinations") @ always.widths(), observed)
    # the GLAs do not learn under a fixed rule: the parameters keep the random initial values the
    # kernel drew first from each run's stream
    assert np.array_equal(never.output("two_observe", "u"), always.output("two_observe", "u"))
    assert np.array_equal(never.output("two_observe", "u_initial"), never.output("two_observe", "u"))


def test_the_initial_glas_are_drawn_in_the_init_range(small_result):
    u = small_result.output("two_observe", "u_initial")
    assert 0 < np.abs(u).max() <= SMALL.own("two_observe").gla_init_range
    assert not np.array_equal(u, small_result.output("two_observe", "u"))  # learning moved them


# --- Fig. 10's readings of "need to coordinate" ------------------------------------------------


def _collides_under_some_joint_action(g, a, b):
    """From the rules themselves: does any of the 16 joint moves of agents on a and b collide?"""
    cells, done = np.array([a, b]), np.zeros(2, np.bool_)
    buffers = [np.empty(2, t) for t in (np.int64, np.float64, np.bool_, np.bool_, np.bool_)]
    return any(rules.step(rules.world(g), cells, done, np.array([x, y]), *buffers) > 0
               for x in range(4) for y in range(4))


def test_in_range_is_some_joint_action_colliding_under_the_rules():
    g = tunnel_to_goal()
    table = rules.in_range_table(g.next_cell, g.shared_goal)
    free = [c for c in range(g.n_cells) if not g.is_goal[c] and not g.blocked[c]]
    for a in free:
        for b in free:
            if a != b:
                expected = _collides_under_some_joint_action(g, a, b)
                assert rules.could_collide(g.next_cell, g.shared_goal, a, b) == expected, (a, b)
                assert table[a, b] == expected, (a, b)
                if rules.manhattan(g.n_cols, a, b) > 2:
                    assert not expected  # one move each: never from farther than 2 cells


def test_a_wall_takes_close_agents_out_of_range():
    g = tunnel_to_goal()
    # distance 1 across the wall above row 2, distance 2 across the goal between two walls
    assert not rules.could_collide(g.next_cell, g.shared_goal, g.cell(1, 1), g.cell(2, 1))
    assert not rules.could_collide(g.next_cell, g.shared_goal, g.cell(1, 0), g.cell(3, 0))
    # the tunnel entrance from above and below, and two agents side by side
    assert rules.could_collide(g.next_cell, g.shared_goal, g.cell(1, 4), g.cell(3, 4))
    assert rules.could_collide(g.next_cell, g.shared_goal, g.cell(0, 0), g.cell(0, 1))


@pytest.mark.parametrize("need, preferred, expected", [
    ("in_range", (S, N), True), ("in_range", (N, S), True),  # in range whatever they choose
    ("sampled", (S, N), True), ("sampled", (N, S), False),  # only if the preferred moves collide
    ("outcome", (S, N), False),  # decided by the move, not before it
])
def test_need_before_the_move_under_each_reading(tunnel_entrance, need, preferred, expected):
    g, cells, done, _ = tunnel_entrance
    coming = rules.would_collide(g.next_cell, g.goals, cells, done, np.array(preferred), 0, 1)
    in_range = rules.in_range_table(g.next_cell, g.shared_goal)
    assert two_observe.need_before_step(two_observe.NEEDS[need], in_range, cells, 0, 1, coming) == expected


def test_outcome_reading_feeds_back_the_collision_that_happened():
    """Under 'outcome', coordinating is rewarded only on a step with a collision: when the
    yielding agent's random move still collides, or when only one agent coordinated."""
    table = np.array(two_observe.GLASettings(gla_need="outcome").gla_feedback)
    assert gla_feedback(table, 0.1, COORDINATE, True, False, 2) == 1.0  # collided: coordinating was right
    assert gla_feedback(table, 0.1, COORDINATE, False, True, 2) == pytest.approx(-0.2)  # avoided: "no need"
    assert gla_feedback(table, 0.1, ACT_ALONE, False, False, 2) == 1.0
