"""The gridworld rules (chapter Section 5.3), case by case."""

import numpy as np
import pytest

from glamas.gridworld import load_map, make_goals, rules, tunnel_to_goal
from glamas.gridworld.rewards import CHAPTER, FIELD
from glamas.gridworld.rules import E, N, S, W
from glamas.learners import episode

# A 1x4 corridor with the goal at the right end, and a 3x3 open room.
CORRIDOR = """\
+-+-+-+-+
|1 . 2 G|
+-+-+-+-+
"""
ROOM = """\
+-+-+-+
|1 . 2|
+ + + +
|. 3 .|
+ + + +
|. . G|
+-+-+-+
"""


def play(gridmap, cells, actions, done=None, bounce=rules.BOUNCE_PREVIOUS):
    """One rules.step from the given cells; returns the outputs as a dict."""
    n = len(cells)
    cells = np.array(cells, dtype=np.int64)
    done = np.zeros(n, dtype=bool) if done is None else np.array(done, dtype=bool)
    out = {"new_cells": np.empty(n, np.int64), "rewards": np.empty(n), "bumped": np.empty(n, bool),
           "collided": np.empty(n, bool), "reached": np.empty(n, bool)}
    world = rules.world(gridmap)._replace(bounce=bounce)
    out["n_collisions"] = rules.step(world, cells, done, np.array(actions, dtype=np.int64), out["new_cells"],
                                     out["rewards"], out["bumped"], out["collided"], out["reached"])
    return out


@pytest.fixture(scope="module")
def tunnel():
    return tunnel_to_goal()


@pytest.fixture(scope="module")
def room():
    return load_map(ROOM)


def test_free_moves_cost_nothing(tunnel):
    out = play(tunnel, [tunnel.cell(0, 0), tunnel.cell(4, 0)], [E, N])
    assert out["new_cells"].tolist() == [tunnel.cell(0, 1), tunnel.cell(3, 0)]
    assert out["rewards"].tolist() == [0.0, 0.0]
    assert out["n_collisions"] == 0 and not out["bumped"].any()


def test_wall_bump_costs_one_and_stays(tunnel):
    # (1, 0) south is the wall in front of the goal row; (3, 0) north likewise.
    out = play(tunnel, [tunnel.cell(1, 0), tunnel.cell(3, 0)], [S, N])
    assert out["new_cells"].tolist() == [tunnel.cell(1, 0), tunnel.cell(3, 0)]
    assert out["rewards"].tolist() == [CHAPTER.bump] * 2 == [-1.0, -1.0]
    assert out["bumped"].all() and out["n_collisions"] == 0


def test_border_bump(tunnel):
    out = play(tunnel, [tunnel.cell(0, 0), tunnel.cell(4, 0)], [N, W])
    assert out["new_cells"].tolist() == [tunnel.cell(0, 0), tunnel.cell(4, 0)]
    assert out["rewards"].tolist() == [-1.0, -1.0]


def test_same_target_collides_and_bounces_back(tunnel):
    # Both step into the tunnel entrance (2, 4) from above and below.
    a, b = tunnel.cell(1, 4), tunnel.cell(3, 4)
    out = play(tunnel, [a, b], [S, N])
    assert out["n_collisions"] == 1
    assert out["new_cells"].tolist() == [a, b]
    assert out["rewards"].tolist() == [CHAPTER.collision] * 2 == [-10.0, -10.0]
    assert out["collided"].all() and not out["bumped"].any()


def test_swap_collides(tunnel):
    a, b = tunnel.cell(2, 3), tunnel.cell(2, 4)
    out = play(tunnel, [a, b], [E, W])
    assert out["n_collisions"] == 1
    assert out["new_cells"].tolist() == [a, b]
    assert out["rewards"].tolist() == [-10.0, -10.0]


def test_moving_into_a_bumped_agent_collides(tunnel):
    # Agent 2 at (2, 4) bumps east into the border; agent 1 moves onto its cell.
    a, b = tunnel.cell(1, 4), tunnel.cell(2, 4)
    out = play(tunnel, [a, b], [S, E])
    assert out["n_collisions"] == 1
    assert out["new_cells"].tolist() == [a, b]
    assert out["rewards"].tolist() == [-10.0, -11.0]
    assert out["bumped"].tolist() == [False, True]


def test_following_an_agent_that_moves_on_is_free(tunnel):
    a, b = tunnel.cell(2, 3), tunnel.cell(2, 2)
    out = play(tunnel, [a, b], [W, W])
    assert out["n_collisions"] == 0
    assert out["new_cells"].tolist() == [b, tunnel.cell(2, 1)]


def test_goal_pays_and_is_absorbing(tunnel):
    goal = tunnel.cell(2, 0)
    out = play(tunnel, [tunnel.cell(2, 1), goal], [W, E], done=[False, True])
    assert out["new_cells"].tolist() == [goal, goal]
    assert out["rewards"].tolist() == [CHAPTER.goal, 0.0] == [100.0, 0.0]
    assert out["reached"].tolist() == [True, False]
    assert out["n_collisions"] == 0


def test_done_agent_never_collides_or_moves(tunnel):
    goal = tunnel.cell(2, 0)
    out = play(tunnel, [goal, tunnel.cell(0, 0)], [E, E], done=[True, False])
    assert out["new_cells"].tolist() == [goal, tunnel.cell(0, 1)]
    assert out["rewards"].tolist() == [0.0, 0.0]
    assert not out["collided"].any() and not out["bumped"].any()


def test_both_enter_the_goal_together():
    gridmap = load_map("+-+-+-+\n|1 G 2|\n+-+-+-+\n")
    out = play(gridmap, gridmap.starts, [E, W])
    assert out["new_cells"].tolist() == [1, 1]
    assert out["rewards"].tolist() == [100.0, 100.0]
    assert out["reached"].all() and out["n_collisions"] == 0


def test_bounce_to_start(tunnel):
    a, b = tunnel.cell(1, 4), tunnel.cell(3, 4)
    out = play(tunnel, [a, b], [S, N], bounce=rules.BOUNCE_START)
    assert out["new_cells"].tolist() == tunnel.starts.tolist()
    assert out["rewards"].tolist() == [-10.0, -10.0]


def test_three_agents_on_one_target_make_three_collisions(room):
    # Agents at (0, 1), (1, 0) and (1, 2) all step into (1, 1).
    cells = [room.cell(0, 1), room.cell(1, 0), room.cell(1, 2)]
    out = play(room, cells, [S, E, W])
    assert out["n_collisions"] == 3
    assert out["new_cells"].tolist() == cells
    assert out["rewards"].tolist() == [-20.0, -20.0, -20.0]


def test_chain_collision_a_bounced_agent_hits_its_follower():
    # 1 follows 2 east; 2 and 3 collide in the last free cell; 2 bounces back onto 1.
    gridmap = load_map("+-+-+-+-+-+\n|1 2 . 3 G|\n+-+-+-+-+-+\n")
    out = play(gridmap, gridmap.starts, [E, E, W])
    assert out["n_collisions"] == 2
    assert out["new_cells"].tolist() == [0, 1, 3]
    assert out["rewards"].tolist() == [-10.0, -20.0, -10.0]
    assert out["collided"].all()


def test_chain_with_bounce_to_start_ends_on_the_starts(room):
    # Agents 1 and 2 collide in the centre; agent 3 meanwhile steps onto agent 2's start, so
    # agent 2 bounces home onto agent 3, which then bounces to its own start.
    cells = [room.cell(1, 0), room.cell(0, 1), room.cell(1, 2)]
    out = play(room, cells, [E, S, N], bounce=rules.BOUNCE_START)
    assert out["new_cells"].tolist() == room.starts.tolist()
    assert out["n_collisions"] == 2
    assert out["rewards"].tolist() == [-10.0, -20.0, -10.0]


def test_would_collide(tunnel):
    a, b = tunnel.cell(1, 4), tunnel.cell(3, 4)
    cells, done = np.array([a, b]), np.zeros(2, bool)
    check = lambda actions, d=done: rules.would_collide(tunnel.next_cell, tunnel.goals, cells, d,
                                                        np.array(actions), 0, 1)
    assert check([S, N])
    assert not check([S, S])
    assert not check([S, N], np.array([False, True]))
    swap = np.array([tunnel.cell(2, 3), tunnel.cell(2, 4)])
    assert rules.would_collide(tunnel.next_cell, tunnel.goals, swap, done, np.array([E, W]), 0, 1)


PAYOFFS = CHAPTER.kernel_bundle()


def test_shared_reward_pays_the_goal_once_when_the_last_agent_arrives():
    rewards = np.array([100.0, -10.0])
    reached = np.array([True, False])
    assert rules.shared_reward(PAYOFFS, rewards, reached, False) == -10.0
    assert rules.shared_reward(PAYOFFS, np.array([0.0, 99.0]), np.array([False, True]), True) == 99.0
    assert rules.shared_reward(PAYOFFS, np.array([100.0, 100.0]), np.array([True, True]), True) == 100.0
    assert rules.shared_reward(PAYOFFS, np.array([0.0, 0.0]), np.array([False, False]), True) == 0.0


def test_manhattan(tunnel):
    assert rules.manhattan(tunnel.n_cols, tunnel.cell(0, 0), tunnel.cell(4, 0)) == 4
    assert rules.manhattan(tunnel.n_cols, tunnel.cell(1, 3), tunnel.cell(3, 1)) == 4
    assert rules.manhattan(tunnel.n_cols, 7, 7) == 0


def test_corridor_same_target_between_the_starts():
    gridmap = load_map(CORRIDOR)
    out = play(gridmap, gridmap.starts, [E, W])
    assert out["n_collisions"] == 1
    assert out["new_cells"].tolist() == gridmap.starts.tolist()


def every_agent_goal(gridmap, n_agents):
    """The goals of ``n_agents`` agents whose goal is ``gridmap``'s shared goal."""
    return make_goals(gridmap.shared_goal, [[] for _ in range(n_agents)])


def _step_outputs(step, gridmap, cells, done, actions, bounce, agents, rewards):
    """``step``'s collisions and the outputs of ``agents`` under the reward formulation ``rewards``."""
    n = cells.shape[0]
    out = (np.empty(n, np.int64), np.empty(n), np.empty(n, bool), np.empty(n, bool), np.empty(n, bool))
    starts = np.arange(n, dtype=np.int64)  # distinct start cells, for the bounce to the start
    world = rules.World(gridmap.next_cell, every_agent_goal(gridmap, n), starts, bounce, gridmap.n_cols,
                        rewards.kernel_bundle())
    collisions = step(world, cells, done, actions, *out)
    return [collisions] + [a[list(agents)].tolist() for a in out]


FORMULATIONS = {"chapter": CHAPTER, "field": FIELD}
"""The reward formulations the fast paths are held to the general step under."""


@pytest.mark.parametrize("rewards", FORMULATIONS.values(), ids=FORMULATIONS)
@pytest.mark.parametrize("bounce", [rules.BOUNCE_PREVIOUS, rules.BOUNCE_START])
@pytest.mark.parametrize("pair", [(0, 1), (0, 2), (1, 2)])
def test_two_agent_fast_path_equals_the_general_step(tunnel, bounce, pair, rewards):
    """step_pair gives step's outputs for agents i and j, the third agent in the goal, for every
    joint action from every pair of cells the rules can reach (distinct acting cells; a done
    agent on the goal)."""
    goal = int(np.flatnonzero(tunnel.is_goal)[0])
    free = [c for c in range(tunnel.n_cells) if not tunnel.is_goal[c]]
    placements = [((a, b), (False, False)) for a in free for b in free if a != b]
    placements += [((goal, b), (True, False)) for b in free] + [((a, goal), (False, True)) for a in free]
    i, j = pair
    for (a, b), pair_done in placements:
        cells, done = np.full(3, goal, np.int64), np.ones(3, bool)
        cells[[i, j]], done[[i, j]] = (a, b), pair_done
        for joint in range(16):
            actions = np.zeros(3, np.int64)
            actions[[i, j]] = divmod(joint, 4)
            fast = _step_outputs(lambda *step: rules.step_pair(*step, pair), tunnel, cells, done, actions, bounce, pair,
                                 rewards)
            assert fast == _step_outputs(rules.step, tunnel, cells, done, actions, bounce, pair, rewards), \
                (a, b, done, actions)


@pytest.mark.parametrize("rewards", FORMULATIONS.values(), ids=FORMULATIONS)
@pytest.mark.parametrize("lone", [0, 1, 2])
def test_lone_agent_step_equals_the_general_step(tunnel, lone, rewards):
    """step_alone gives step's outputs for the only acting agent (the others on the goal), from
    every free cell with every action, and no collision."""
    goal = int(np.flatnonzero(tunnel.is_goal)[0])
    world = rules.World(tunnel.next_cell, every_agent_goal(tunnel, 3), np.zeros(3, np.int64), rules.BOUNCE_PREVIOUS,
                        tunnel.n_cols, rewards.kernel_bundle())
    done = np.arange(3) != lone
    assert episode.few_acting(done) == (lone, -1) and episode.few_acting(np.zeros(3, bool)) == (-1, -1)
    assert episode.few_acting(np.arange(3) == lone) == tuple(a for a in range(3) if a != lone)
    for cell in (c for c in range(tunnel.n_cells) if not tunnel.is_goal[c]):
        cells = np.where(done, goal, cell).astype(np.int64)
        for action in range(4):
            actions = np.full(3, action, np.int64)
            general = (np.empty(3, np.int64), np.empty(3), np.empty(3, bool), np.empty(3, bool), np.empty(3, bool))
            alone = tuple(np.zeros_like(a) for a in general)
            assert rules.step(world, cells, done, actions, *general) == 0
            assert rules.step_alone(world, cells, actions, *alone, lone) == 0
            assert [a[lone] for a in alone] == [a[lone] for a in general], (cell, action)


# --- per-agent goals ------------------------------------------------------------------------------

OWN_GOALS = """\
+-+-+-+-+
|1 . a 3|
+ + + + +
|2 . . c|
+-+-+-+-+
goal 2: row 0, col 2
"""
"""Agents 1 and 2 share the goal (0, 2); agent 3's goal is (1, 3), an ordinary cell for the others."""


@pytest.fixture(scope="module")
def own_goals():
    return load_map(OWN_GOALS)


def test_another_agents_goal_is_an_ordinary_cell(own_goals):
    g = own_goals
    out = play(g, [g.cell(1, 2), g.cell(1, 0), g.cell(0, 3)], [E, N, W])  # 1 enters 3's goal, 3 enters 1's
    assert out["new_cells"].tolist() == [g.cell(1, 3), g.cell(0, 0), g.cell(0, 2)]
    assert out["reached"].tolist() == [False, False, False] and out["rewards"].tolist() == [0.0, 0.0, 0.0]


def test_entering_a_goal_of_both_together_is_no_collision(own_goals):
    g = own_goals
    out = play(g, [g.cell(0, 1), g.cell(1, 2), g.cell(1, 0)], [E, N, E])
    assert out["n_collisions"] == 0 and out["new_cells"].tolist()[:2] == [g.cell(0, 2)] * 2
    assert out["reached"].tolist() == [True, True, False] and out["rewards"].tolist() == [100.0, 100.0, 0.0]


def test_entering_a_goal_of_one_of_them_together_collides(own_goals):
    g = own_goals
    cells = [g.cell(0, 1), g.cell(1, 0), g.cell(0, 3)]  # agents 1 and 3 aim at (0, 2), agent 1's goal only
    out = play(g, cells, [E, N, W])
    assert out["n_collisions"] == 1 and out["new_cells"].tolist() == [cells[0], g.cell(0, 0), cells[2]]
    assert out["reached"].tolist() == [False, False, False] and out["rewards"].tolist() == [-10.0, 0.0, -10.0]


def test_an_agent_in_its_goal_has_left_the_game(own_goals):
    g = own_goals
    goal_3 = g.cell(1, 3)
    out = play(g, [g.cell(1, 0), g.cell(1, 2), goal_3], [N, E, W], done=[False, False, True])
    assert out["new_cells"].tolist() == [g.cell(0, 0), goal_3, goal_3] and out["n_collisions"] == 0


def test_swapping_into_each_others_goal_collides():
    swap = load_map("+-+-+\n|1 2|\n+-+-+\ngoal 1: row 0, col 1\ngoal 2: row 0, col 0\n")
    out = play(swap, swap.starts, [E, W])
    assert out["n_collisions"] == 1 and out["new_cells"].tolist() == swap.starts.tolist()
    assert not out["reached"].any()


def _placements(g, pair, third):
    """Cells and done flags of three agents the rules can reach: agent ``third`` done on its goal,
    the pair acting on distinct cells (none on its own goal) or one of them done on its goal."""
    def own_goal(k):
        return g.goal_cells(k)[0]
    acting = {k: [c for c in range(g.n_cells) if not g.is_goal_of(k, c)] for k in pair}
    i, j = pair
    found = [((a, b), (False, False)) for a in acting[i] for b in acting[j] if a != b]
    found += [((own_goal(i), b), (True, False)) for b in acting[j]]
    found += [((a, own_goal(j)), (False, True)) for a in acting[i]]
    for (a, b), pair_done in found:
        cells, done = np.empty(3, np.int64), np.ones(3, bool)
        cells[third] = own_goal(third)
        cells[[i, j]], done[[i, j]] = (a, b), pair_done
        yield cells, done


@pytest.mark.parametrize("rewards", FORMULATIONS.values(), ids=FORMULATIONS)
@pytest.mark.parametrize("bounce", [rules.BOUNCE_PREVIOUS, rules.BOUNCE_START])
@pytest.mark.parametrize("pair", [(0, 1), (0, 2), (1, 2)])
def test_two_agent_fast_path_equals_the_general_step_with_own_goals(own_goals, bounce, pair, rewards):
    g, third = own_goals, 3 - sum(pair)
    world = rules.world(g, rewards=rewards)._replace(bounce=bounce)
    for cells, done in _placements(g, pair, third):
        for joint in range(16):
            actions = np.zeros(3, np.int64)
            actions[list(pair)] = divmod(joint, 4)
            general, fast = ([np.empty(3, np.int64), np.empty(3), *(np.empty(3, bool) for _ in range(3))]
                             for _ in range(2))
            n_general = rules.step(world, cells, done, actions, *general)
            n_fast = rules.step_pair(world, cells, done, actions, *fast, pair)
            assert n_fast == n_general
            assert [a[list(pair)].tolist() for a in fast] == [a[list(pair)].tolist() for a in general], (cells, done, actions)


def test_in_range_table_exempts_the_goal_of_every_agent_only(own_goals):
    g = own_goals
    assert not g.shared_goal.any()  # no cell is every agent's goal: entering any cell together collides
    table = rules.in_range_table(g.next_cell, g.shared_goal)
    assert table[g.cell(0, 2), g.cell(1, 3)]  # both could enter (1, 2)
    assert table[g.cell(0, 1), g.cell(1, 2)]  # both could enter (1, 1), or (0, 2): a collision unless agents 1 and 2
    assert rules.shared_goals(g.goals).tolist() == g.shared_goal.tolist()


# --- many agents: the indexed step ------------------------------------------------------------------

def _crowds():
    """Maps and bounce rules for the indexed step: the chapter's, goals of several agents, and
    generated warehouses, some as crowded as starts and goals allow (chains of bounces)."""
    from glamas.gridworld import generate
    yield load_map("tunnel_to_goal"), rules.BOUNCE_PREVIOUS
    yield load_map("tunnel_to_goal_4"), rules.BOUNCE_START
    yield load_map(OWN_GOALS), rules.BOUNCE_PREVIOUS
    for n, density, bounce in ((8, 0.5, rules.BOUNCE_PREVIOUS), (8, 0.5, rules.BOUNCE_START),
                               (32, 0.3, rules.BOUNCE_PREVIOUS), (32, 0.5, rules.BOUNCE_START),
                               (128, 0.1, rules.BOUNCE_PREVIOUS), (128, 0.4, rules.BOUNCE_START)):
        yield generate.warehouse(n, seed=n, density=density), bounce


CROWDS = [(*crowd, (CHAPTER, FIELD)[k % 2]) for k, crowd in enumerate(_crowds())]
"""The crowds under the chapter's rewards and the field's in turn."""


@pytest.mark.parametrize("gridmap, bounce, rewards", CROWDS,
                         ids=lambda x: getattr(x, "name", x if isinstance(x, int) else None))
def test_indexed_step_plays_the_general_step(gridmap, bounce, rewards):
    """step_indexed gives step's outputs and collisions on every step of a random walk (agents
    leave at their goals, all start again when all are in), and leaves its index empty."""
    world = rules.world(gridmap, rewards=rewards)._replace(bounce=bounce)
    index = rules.cell_index(world)
    n = gridmap.n_agents
    draws = np.random.default_rng(n)
    cells, done = gridmap.starts.copy(), np.zeros(n, bool)
    counts = np.zeros(3)  # collisions, steps with a later round, arrivals
    for _ in range(3000 if n <= 8 else 600):
        actions = draws.integers(0, 4, n)
        general, indexed = ([np.empty(n, np.int64), np.empty(n), *(np.empty(n, bool) for _ in range(3))]
                            for _ in range(2))
        n_general = rules.step(world, cells, done, actions, *general)
        n_indexed = rules.step_indexed(world, index, cells, done, actions, *indexed)
        assert n_indexed == n_general
        for x, y in zip(indexed, general):
            assert np.array_equal(x, y)
        counts += (n_general, _bounced_into(gridmap, cells, done, actions, general[3]), general[4].sum())
        cells, done = general[0].copy(), done | general[4]
        if done.all():
            cells, done = gridmap.starts.copy(), np.zeros(n, bool)
    assert (index.occupant == rules.NOBODY).all() and (index.claimant == rules.NOBODY).all()
    assert counts[0] > 0 and counts[2] > 0
    if n >= 8:
        assert counts[1] > 0  # agents hit by a bounced agent: later rounds


def _bounced_into(gridmap, cells, done, actions, collided):
    """Agents that collided though no other acting agent aimed at their target or swapped with
    them: a bounced agent hit them, in a later round."""
    targets = np.where(done, -1, gridmap.next_cell[cells, actions])
    aimed = np.bincount(targets[~done], minlength=gridmap.n_cells)
    at = dict(zip(cells[~done].tolist(), np.flatnonzero(~done).tolist()))
    swapped = [not done[i] and targets[at[targets[i]]] == cells[i] if targets[i] in at and at[targets[i]] != i else False
               for i in range(len(cells))]
    return int(sum(collided[i] and aimed[targets[i]] == 1 and not swapped[i] for i in range(len(cells))))


def test_in_range_lists_and_table_are_could_collide_for_every_pair_of_cells():
    """rules.in_range_lists and rules.in_range_table, which try only the cells that can reach a
    cell in common, answer rules.could_collide for every pair of cells of every map."""
    from glamas.gridworld import generate
    from glamas.paths import MAPS
    maps = [load_map(path) for path in sorted(MAPS.glob("*.txt"))] + [generate.warehouse(n, 1) for n in (2, 8, 32)]
    for g in maps:
        for goals in (g.shared_goal, g.is_goal):
            tried = np.array([[rules.could_collide(g.next_cell, goals, a, b) for b in range(g.n_cells)]
                              for a in range(g.n_cells)])
            assert np.array_equal(rules.in_range_table(g.next_cell, goals), tried), g.name
            first, near = rules.in_range_lists(g.next_cell, goals)
            for a in range(g.n_cells):
                assert sorted(near[first[a]:first[a + 1]].tolist()) == [b for b in np.flatnonzero(tried[a]) if b != a]
