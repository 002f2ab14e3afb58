"""N agents: the warehouse maps, the N-agent log, 2observe's group coordination rule by rule, the
N-agent learners in small runs, and the scaling study's config, memory check, claims and figures."""

import collections

import numpy as np
import pytest
from glamas import claims, training
from glamas.curves import final
from glamas.experiments import gridworld as gw
from glamas.experiments import scaling as sc
from glamas.gridworld import load_map, rules
from glamas.gridworld.rules import E, N, S, W
from glamas.learners import episode as ep
from glamas.learners import independent, joint_state, mmdp, registry, spec, two_observe
from glamas.learners.two_observe import ACT_ALONE, COORDINATE
from glamas.paths import MAPS
from glamas.rng import run_states

OPEN_3X3 = """\
+-+-+-+
|1 2 .|
+ + + +
|3 . .|
+ + + +
|. . G|
+-+-+-+
"""


# --- maps ------------------------------------------------------------------------------------

def test_every_map_file_loads():
    files = sorted(MAPS.glob("*.txt"))
    assert len(files) >= 6
    for path in files:
        gridmap = load_map(path)
        assert gridmap.n_agents >= 2, path.name


def test_warehouse_maps_are_one_layout_with_n_agents():
    maps = [load_map(MAPS / f"warehouse_{n}.txt") for n in range(2, 7)]
    for n, gridmap in zip(range(2, 7), maps):
        assert gridmap.n_agents == n
        assert np.array_equal(gridmap.next_cell, maps[0].next_cell)
        assert np.array_equal(gridmap.starts[:2], maps[0].starts)
    g = maps[0]
    # the aisle to the goal (row 2) is one track, entered only from its right end (2, 6)
    aisle = [g.cell(2, c) for c in range(7)]
    for c in range(6):
        assert g.open_neighbours(aisle[c]) <= set(aisle)
    assert g.open_neighbours(g.cell(2, 6)) == {g.cell(1, 6), g.cell(3, 6), g.cell(2, 5)}


# --- the N-agent log layout --------------------------------------------------------------------

def test_log_layout_is_steps_then_rewards_then_the_measures_for_any_number_of_agents():
    assert ep.n_columns(2) == 8 and [ep.reward_column(2, i) for i in (0, 1)] == [2, 3]
    assert [ep.column(2, m) for m in (ep.LENGTH, ep.COLLISIONS, ep.COORDINATIONS, ep.CAPPED)] == [4, 5, 6, 7]
    assert ep.n_columns(5) == 14 and ep.reward_column(5, 0) == 5 and ep.column(5, ep.CAPPED) == 13
    log = np.arange(14.0)[None]
    assert ep.metric(log, "steps").tolist() == [2.0] and ep.metric(log, "reward").tolist() == [7.0]
    assert ep.metric(log, "collisions").tolist() == [11.0] and ep.metric(log, "capped").tolist() == [13.0]


# --- 2observe for N agents: rules ------------------------------------------------------------

def _converging_three():
    """Agents above, left of and below the centre of a 3x3 world, all heading into it."""
    g = load_map(OPEN_3X3)  # the start cells do not matter here
    cells = np.array([g.cell(0, 1), g.cell(1, 0), g.cell(2, 1)])
    return g, cells, np.zeros(3, np.bool_), np.array([S, E, N])


def _coordinate(g, cells, done, choices, preferred, state):
    """two_observe.coordinate_group on ``g`` with the group's index filled as group_step fills it,
    and emptied after: (count, actions)."""
    group = two_observe.group_arrays(rules.world(g))
    actions = np.zeros(len(cells), np.int64)
    two_observe.index_preferred(group, g.next_cell, cells, done, preferred)
    count = two_observe.coordinate_group(g.next_cell, g.goals, cells, done, np.array(choices), preferred, actions,
                                         group, state)
    two_observe.clear_preferred(group, g.next_cell, cells, done, preferred)
    assert (group.index.occupant == rules.NOBODY).all() and (group.index.claimant == rules.NOBODY).all()
    return count, actions


def test_three_agents_aiming_at_one_cell_one_keeps_the_others_draw_another_action():
    g, cells, done, preferred = _converging_three()
    keepers = np.zeros(3)
    for state in run_states(11, 600):
        count, actions = _coordinate(g, cells, done, [COORDINATE] * 3, preferred, state)
        assert count == 3
        kept = actions == preferred
        assert kept.sum() == 1
        keepers += kept
    assert np.all(np.abs(keepers / 600 - 1 / 3) < 0.07)  # the keeper is uniform over the group


def test_an_agent_acting_alone_keeps_its_action_and_only_the_coordinating_pair_resolves():
    g, cells, done, preferred = _converging_three()
    for state in run_states(12, 100):
        count, actions = _coordinate(g, cells, done, [COORDINATE, COORDINATE, ACT_ALONE], preferred, state)
        assert count == 2
        assert actions[2] == preferred[2]
        assert (actions[:2] == preferred[:2]).sum() == 1


def test_no_collision_coming_draws_nothing():
    g, cells, done, _ = _converging_three()
    preferred = np.array([E, W, E])  # (0,1)->(0,2), (1,0) bumps, (2,1)->(2,2): no two collide
    state = run_states(13, 1)[0]
    before = state.copy()
    count, actions = _coordinate(g, cells, done, [COORDINATE] * 3, preferred, state)
    assert count == 0 and np.array_equal(actions, preferred) and np.array_equal(state, before)


def test_a_yielding_agent_no_longer_blocks_the_others():
    # A = (0,0) E swaps with B = (0,1) W and aims where C = (1,1) N aims: A conflicts with B and
    # with C, B and C do not conflict. If A comes first it keeps and B, C yield; otherwise A
    # yields (it collides with the kept B or C) and B and C both keep their actions.
    g = load_map(OPEN_3X3)
    cells = np.array([g.cell(0, 0), g.cell(0, 1), g.cell(1, 1)])
    preferred = np.array([E, W, N])
    outcomes = set()
    for state in run_states(14, 300):
        count, actions = _coordinate(g, cells, np.zeros(3, np.bool_), [COORDINATE] * 3, preferred, state)
        kept = tuple((actions == preferred).tolist())
        assert count == 3 and kept in {(True, False, False), (False, True, True)}
        outcomes.add(kept)
    assert len(outcomes) == 2


def test_two_agents_draw_what_the_two_agent_rule_draws():
    _, cells, done, preferred = _converging_three()
    cells2, done2, pref2 = cells[:2].copy(), done[:2].copy(), preferred[:2].copy()
    for state in run_states(15, 50):
        a, b = state.copy(), state.copy()
        expected = pref2.copy()
        two_observe.yield_at_random(pref2, expected, (0, 1), a)
        g2 = load_map(OPEN_3X3.replace("3", "."))
        _, actions = _coordinate(g2, cells2, done2, [COORDINATE] * 2, pref2, b)
        assert np.array_equal(actions, expected) and np.array_equal(a, b)


def test_nearest_other_agent_ignores_agents_in_the_goal_and_breaks_ties_by_number():
    g = load_map(OPEN_3X3)
    cells = np.array([g.cell(1, 1), g.cell(0, 1), g.cell(1, 0)])
    nearest, deltas = np.zeros(3, np.int64), np.zeros(3, np.int64)
    two_observe.nearest_others(rules.distance_table(g.n_cells, g.n_cols), cells, np.zeros(3, np.bool_), nearest, deltas)
    assert nearest.tolist() == [1, 0, 0] and deltas.tolist() == [1, 1, 1]
    two_observe.nearest_others(rules.distance_table(g.n_cells, g.n_cols), cells, np.array([False, True, True]), nearest, deltas)
    assert nearest.tolist() == [two_observe.NOBODY] * 3


@pytest.mark.parametrize("density", [0.02, 0.1, 0.5])
def test_nearest_other_by_rings_is_the_nearest_of_all_pairs(density):
    """two_observe.nearest_other (rings around the agent's cell, or the acting agents one by one
    when they are few) finds what the search over all pairs finds (nearest_others): the nearest
    acting agent, the lowest-numbered among equals, from crowded to nearly empty."""
    from glamas.gridworld import generate
    g = generate.warehouse(64, seed=2, density=density)
    world = rules.world(g)
    rings = two_observe.rings(world)
    distances = rules.distance_table(g.n_cells, g.n_cols)
    free = np.flatnonzero(~g.blocked)
    draws = np.random.default_rng(3)
    fallbacks = 0
    for trial in range(200):
        cells = draws.choice(free, g.n_agents, replace=False).astype(np.int64)
        done = draws.random(g.n_agents) < draws.choice([0.0, 0.5, 0.95])
        acting = np.flatnonzero(~done)
        rings.grid[rings.padded[cells[acting]]] = acting
        expected, deltas = np.zeros(g.n_agents, np.int64), np.zeros(g.n_agents, np.int64)
        two_observe.nearest_others(distances, cells, done, expected, deltas)
        for i in acting:
            found = two_observe.nearest_other(rings, cells, acting, acting.size, i)
            assert found == (expected[i], deltas[i] if expected[i] != two_observe.NOBODY else 0), (trial, i)
            fallbacks += 2 * deltas[i] * (deltas[i] - 1) >= acting.size
        rings.grid[rings.padded[cells[acting]]] = rules.NOBODY
    assert fallbacks > 0  # the agents tried one by one, too


def test_group_coordination_through_the_index_is_the_all_pairs_one():
    """coordinate_group, which tries only the agents aiming at an agent's target or on it, gives
    the actions and draws of the coordination over all pairs (glamas.plain.gridworld), on
    crowds of 64 agents with random choices and preferences."""
    from glamas import rng
    from glamas.gridworld import generate

    from glamas.plain import gridworld as plain_gridworld

    class Stream:
        def __init__(self, state):
            self.state = state

        def random(self):
            return rng.uniform(self.state)

    g = generate.warehouse(64, seed=4, density=0.4)
    world = plain_gridworld.World(g)
    free = np.flatnonzero(~g.blocked)
    draws = np.random.default_rng(5)
    yielded = 0
    for state in run_states(19, 100):
        cells = draws.choice(free, g.n_agents, replace=False).astype(np.int64)
        done = draws.random(g.n_agents) < 0.2
        choices = np.where(draws.random(g.n_agents) < 0.7, COORDINATE, ACT_ALONE)
        preferred = draws.integers(0, 4, g.n_agents)
        expected = plain_gridworld.coordinate_group(world, cells.tolist(), done.tolist(), choices.tolist(),
                                                     preferred.tolist(), Stream(state.copy()))
        _, actions = _coordinate(g, cells, done, choices, preferred, state)
        assert actions.tolist() == expected
        yielded += (actions != preferred).sum()
    assert yielded > 0


@pytest.mark.long
@pytest.mark.parametrize("reading", [{"gla_need": need, "gla_L": L} for need in sorted(two_observe.NEEDS)
                                     for L in (1.0, 8.0)] + [{"rule_distance": 3}], ids=str)
def test_2observe_pair_step_plays_the_group_step_for_two_agents(reading):
    """pair_step (two acting agents: the chapter's Alg. 4) draws, moves and learns as group_step
    does for the same two agents, from every pair of distinct free cells of TunnelToGoal, with
    Q values and GLA parameters that make the agents coordinate, yield and collide. So run_two,
    which steps with pair_step, plays what run plays for two agents."""
    learner = registry.get("two_observe")
    assert learner.kernel_for(2) is two_observe.run_two and learner.kernel_for(3) is two_observe.run
    own = two_observe.GLASettings(gla_feedback=((1.0, 0.0), (1.0, 1.0)), **reading)
    config = gw.GridworldConfig(learners=("two_observe",), settings={"two_observe": own})
    g = config.gridmap()
    world, learning, automata, _ = spec.kernel_inputs(learner, config.setup("two_observe"), g, config.schedule())
    free = [c for c in range(g.n_cells) if not (g.is_goal[c] or g.blocked[c])]
    pairs = [(a, b) for a in free for b in free if a != b]
    draws = np.random.default_rng(5)
    outcomes = collections.Counter()
    for (a, b), state in zip(pairs, run_states(17, len(pairs))):
        q = draws.uniform(-1.0, 1.0, (2, g.n_cells, rules.N_ACTIONS))
        u = draws.uniform(-3.0, 3.0, (2, 2, two_observe.N_GLA_INPUTS))
        steps = []
        for step in ("pair", "group"):
            own = two_observe.per_run(world)
            _, buffers, agents = own
            buffers.cells[:], buffers.done[:], buffers.acc[:] = (a, b), False, 0.0
            agents.probs[:] = 0.0  # written only where the GLAs act
            learned = (q.copy(), u.copy(), np.zeros((g.n_rows + g.n_cols - 1, 2)), state.copy())
            if step == "pair":
                collisions = two_observe.pair_step(world, learning, automata, *learned[:3], (0, 1), learned[3], own)
            else:
                collisions = two_observe.group_step(world, learning, automata, *learned,
                                                    (*own, two_observe.group_arrays(world), two_observe.nothing_kept()))
            steps.append((collisions, learned, buffers, (agents.choices, agents.preferred, agents.probs)))
        (collisions, *pair), (group_collisions, *group) = steps
        assert collisions == group_collisions, (a, b)
        for x, y in zip(_flat(pair), _flat(group)):
            assert np.array_equal(x, y), (a, b)
        _, played, (_, preferred, _) = pair
        outcomes.update({"coordinated": played.acc[ep.column(2, ep.COORDINATIONS)] > 0, "collided": collisions > 0,
                         "yielded": not np.array_equal(played.actions, preferred)})
    assert outcomes["coordinated"] and outcomes["collided"] and outcomes["yielded"]  # every branch covered


def _flat(arrays) -> list:
    return [x for a in arrays for x in (_flat(a) if isinstance(a, tuple) else [a])]


# --- the scaling study -----------------------------------------------------------------------

SMALL = sc.ScalingConfig(agents=(2, 3), episodes=200, runs=2, bin_size=100, memory_budget_gib=0.01)


@pytest.fixture(scope="module")
def small_result():
    return sc.run(SMALL, seed=1, workers=1)


def test_small_study_runs_every_method_that_fits_and_skips_the_rest(small_result):
    r = small_result
    assert r.names() == list(sc.METHODS)
    # MMDP at N=3: 42875 x 64 entries x 8 bytes x 2 runs = 44 MB > 0.01 GiB
    assert r.ran[:5].tolist() == [[True, True], [True, True], [True, False], [True, True], [True, True]]
    assert np.isnan(r.log[2, 1]).all() and np.isfinite(r.log[r.ran]).all()
    assert r.table_shapes[:5, 1].tolist() == [[3, 35, 4], [3, 42875, 4], [1, 42875, 64], [3, 35, 4], [3, 35, 4]]
    assert r.gla_parameters[3].tolist() == [8, 12] and r.gla_parameters[4].tolist() == [0, 0]
    assert (r.curves("two_observe_rule", 3, "coordinations") > 0).all()  # the rule coordinates
    assert r.bytes_needed[2, 1] == 2 * 42875 * 64 * 8
    steps = r.curves("independent", 3, "steps")
    assert (steps >= 10).all() and (steps <= SMALL.max_steps).all()


def test_same_seed_same_study_for_one_and_two_workers(small_result):
    again = sc.run(SMALL, seed=1, workers=2)
    assert np.array_equal(small_result.log, again.log, equal_nan=True)


def test_plan_table_sets_every_learner_beside_a_plan_no_better_than_its_bounds(small_result):
    lines = sc.plan_table(small_result).splitlines()
    n = len(small_result.agents)
    rows = {" ".join(line.split()[:-n]): line.split()[-n:] for line in lines[1:5]}
    bound_cost, cost, bound_span, span = (list(map(int, rows[name])) for name in (
        "lower bound: sum of costs", "plan: sum of costs", "lower bound: makespan", "plan: makespan"))
    assert all(b <= c for b, c in zip(bound_cost, cost)) and all(b <= s for b, s in zip(bound_span, span))
    learners = lines[6:]
    assert len(learners) == len(small_result.names())
    mmdp = next(line for line in learners if line.startswith(sc.label("mmdp")))
    assert mmdp.split()[-1] == "-"  # skipped at N = 3: no ratio to a plan


def test_n_agent_kernels_run_on_the_warehouse():
    g = load_map(MAPS / "warehouse_4.txt")
    for learner in (independent.LEARNER, joint_state.LEARNER, mmdp.LEARNER):
        if learner is mmdp.LEARNER:
            g = load_map(MAPS / "warehouse_3.txt")
        outputs = training.train(learner, learner.setup(), g, ep.Schedule(20, ep.uniform_edges(20, 10), 500), 1, 2,
                                 workers=1)
        assert (outputs["log"][0, :, :g.n_agents] >= 1).all() and np.abs(outputs["q"]).sum() > 0


def test_growth_fits_recover_linear_and_exponential_sizes():
    assert sc.growth([2, 3, 4], [2 * 35, 3 * 35, 4 * 35])["loglog_slope"] == pytest.approx(1.0)
    assert sc.growth([2, 3], [35.0 ** 2, 35.0 ** 3])["factor_per_agent"] == pytest.approx(35.0)
    assert np.isnan(sc.growth([2], [4.0])["factor_per_agent"])


def test_claim_verdicts_come_from_the_measurements(small_result):
    rows = sc.claim_rows(small_result)
    assert [row["claim"].id for row in rows] == [c.id for c in claims.load("scaling")]
    m = sc.measure(small_result)
    by_id = {row["claim"].id: row for row in rows}
    assert by_id["independent_linear_in_agents"]["value"] == pytest.approx(m["loglog_slope_independent_off_1"])
    assert by_id["independent_linear_in_agents"]["holds"]
    assert m["largest_n_mmdp"] == 2 and by_id["mmdp_not_for_large_systems"]["holds"]
    assert np.isnan(m["growth_factor_mmdp"]) and not by_id["mmdp_exponential_in_agents"]["holds"]
    assert "skipped" in sc.size_table(small_result) and "MMDP learner" in sc.performance_table(small_result)


def test_pivot_table_has_a_row_per_method_and_counts_capped_runs(small_result):
    m = sc.measure(small_result)
    capped = small_result.curves("independent", 3, "capped")
    capped_runs = sum(final(run[None], small_result.episodes) > 0 for run in capped)
    assert m["capped_runs_independent_3"] == capped_runs
    table = sc.pivot_table(small_result, "collisions").splitlines()
    assert table[0].split() == ["collisions", "N", "=", "2", "N", "=", "3"] and len(table) == 1 + len(sc.METHODS)
    assert table[3].split()[-1] == "-"  # the MMDP learner did not fit at N = 3
    assert table[1].split()[-1] == f"{m['collisions_independent_3']:.2f}"
    with pytest.raises(ValueError, match="metric must be one of"):
        sc.pivot_table(small_result, "speed")


@pytest.mark.parametrize("kwargs, message", [
    ({"agents": (1, 2)}, "agents must be distinct whole numbers >= 2"),
    ({"agents": (2, 2)}, "agents must be distinct"),
    ({"learners": ("mmdp", "sarsa")}, "learners must be distinct names of registered learners"),
    ({"episodes": 250, "bin_size": 100}, "bin_size (100) must divide episodes (250)"),
    ({"runs": 0}, "runs must be a whole number >= 1"),
    ({"memory_budget_gib": 0}, "memory_budget_gib must be a number > 0"),
    ({"map": "warehouse"}, "map must hold '{n}' for the number of agents"),
    ({"map": "aisles_{n}_{m}"}, "map must hold '{n}' for the number of agents and no other '{...}'"),
    ({"map": "aisles_{n"}, "map must hold '{n}'"),
    ({"map": "warehouse_{n}", "agents": (7,)}, "no map file"),
    ({"map": "warehouse_3.txt{n}"}, "no map file"),
    ({"q": {"discount": 0.5}}, "q must be a QSettings"),
])
def test_config_errors_name_the_problem(kwargs, message):
    with pytest.raises(Exception, match=None) as error:
        sc.ScalingConfig(**kwargs)
    assert message in str(error.value)


def test_a_map_with_the_wrong_number_of_agents_is_refused(tmp_path):
    (tmp_path / "w_2.txt").write_text((MAPS / "warehouse_3.txt").read_text())
    with pytest.raises(ValueError, match="has 3 agents, the study expects 2"):
        sc.ScalingConfig(agents=(2,), map=str(tmp_path / "w_{n}.txt"))


def test_plots_refuse_unknown_metrics_and_agents(small_result):
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match="metric must be one of"):
        sc.plot_final(ax, small_result, "speed")
    with pytest.raises(ValueError, match="no results for N = 5"):
        sc.plot_curves(ax, small_result, 5)
    plt.close(fig)
