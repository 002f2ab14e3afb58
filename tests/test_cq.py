"""CQ-learning (glamas.learners.cq) step by step: the one-sample test against ER, test 1 and test 2
on hand-made reward streams, the other agents an agent tests and acts on, its variants' settings,
the memory it declares, and a frozen run from learned outputs."""

import numpy as np
import pytest

from glamas import parallel, training
from glamas.gridworld import load_map, rules, tunnel_to_goal
from glamas.gridworld.rewards import CHAPTER, FIELD, Rewards
from glamas.learners import cq
from glamas.learners import episode as ep
from glamas.learners.two_observe import NOBODY
from glamas.paths import MAPS
from glamas.qlearning import QLearning, QSettings
from glamas.rng import run_states

WINDOW = 20
T = cq.t_critical_values(2 * WINDOW - 2, 0.01)
"""The reference settings: t[19] = 2.861, the two-sided 1 % point at 19 degrees of freedom."""
DETECTION = cq.detection(cq.LEARNER.setup(), tunnel_to_goal())[0]
COLLISION = CHAPTER.collision


def summary(rewards, size=WINDOW):
    samples, window, added = np.zeros(size), np.zeros(3), 0
    for r in rewards:
        added = cq.add_reward(samples, added, window, r)
    return window


def collisions(k, size=WINDOW, other=0.0):
    """A window with ``k`` collisions, the other rewards ``other``."""
    return [COLLISION + other] * k + [other] * (size - k)


# --- the one-sample test against ER ------------------------------------------------------------

def test_reference_critical_value():
    assert T[WINDOW - 1] == pytest.approx(2.8609, abs=1e-4)


def test_one_sample_test_rejects_a_window_whose_mean_differs_from_er():
    # k collisions among 20 rewards of 0 against ER = 0: t^2 = 19 k / (20 - k); t^2 > 2.861^2 = 8.19 from k = 7
    assert not cq.differs_from_expected(0.0, summary(collisions(6)), T)  # t = 2.85
    assert cq.differs_from_expected(0.0, summary(collisions(7)), T)  # t = 3.20
    assert cq.differs_from_expected(-10.0, summary(collisions(13)), T)  # two-sided: a mean above ER too
    rng = np.random.default_rng(1)
    assert not cq.differs_from_expected(0.0, summary(rng.normal(0.0, 1.0, WINDOW)), T)
    assert cq.differs_from_expected(0.0, summary(rng.normal(3.0, 1.0, WINDOW)), T)


def test_zero_variance_rejects_exactly_when_the_value_differs_from_er():
    assert not cq.differs_from_expected(-1.0, summary([-1.0] * WINDOW), T)  # as alone
    assert cq.differs_from_expected(-1.0, summary([-11.0] * WINDOW), T)  # a collision on every visit
    assert cq.differs_from_expected(-1.0, summary([0.0] * WINDOW), T)  # different, even above
    assert not cq.differs_from_expected(0.0, summary([0.0]), T)  # one reward: no test


def test_a_state_action_never_tried_alone_is_never_rejected():
    for test in cq.TESTS.values():
        assert not cq.rejects(np.zeros(3), summary([COLLISION] * WINDOW), T, test)
        assert cq.rejects(summary([0.0] * 5), summary([COLLISION] * WINDOW), T, test)  # tried 5 times alone


def test_fewest_flagged_collisions_is_where_each_test_starts_to_flag():
    assert cq.fewest_flagged_collisions(cq.Settings(), CHAPTER) == 7  # as above: 6 in 20 is not flagged
    assert cq.fewest_flagged_collisions(cq.Settings(cq_significance=0.001), CHAPTER) > 7
    earlier = cq.Settings(cq_window=30, cq_significance=0.05, cq_test="two_sample")
    assert cq.fewest_flagged_collisions(earlier, CHAPTER) == 4  # the two-sample test: 3 in 30 is not flagged


def test_fewest_flagged_collisions_reads_the_collisions_reward():
    """A collision that pays what the move pays changes no reward, and no window is flagged."""
    never = cq.Settings().cq_window + 1
    assert cq.fewest_flagged_collisions(cq.Settings(), Rewards(collision=0.0)) == never
    assert cq.fewest_flagged_collisions(cq.Settings(), Rewards(move=-10.0, collision_replaces_move=True)) == never
    assert cq.fewest_flagged_collisions(cq.Settings(), FIELD) == 7


# --- test 1 and test 2 on reward streams -------------------------------------------------------

N_CELLS, S, A = 6, 2, rules.E
ER = -1.0  # (S, A) bumps into a wall alone


def alone():
    """Every state-action tried alone with reward 0, but (S, A): -1 (its ER)."""
    windows = np.zeros((2, N_CELLS, rules.N_ACTIONS, 3))
    windows[:, :, :] = summary([0.0] * WINDOW)
    windows[:, S, A] = summary([ER] * WINDOW)
    return windows


def first_windows():
    return cq.reward_windows((2, N_CELLS, rules.N_ACTIONS), WINDOW)


def test_test_1_waits_for_a_full_window():
    windows = first_windows()
    answers = [cq.test_1(windows, alone(), 0, S, A, ER + COLLISION, DETECTION) for _ in range(WINDOW)]
    assert answers == [False] * (WINDOW - 1) + [True]  # a collision on every visit, flagged once full
    assert windows.added[0, S, A] == WINDOW and windows.added[1, S, A] == 0  # agent 0's window only


def test_test_1_rejects_a_stream_with_enough_collisions_and_not_one_as_alone():
    windows = first_windows()
    rewards = [ER] * 14 + [ER + COLLISION] * 6 + [ER + COLLISION, ER, ER]
    answers = [cq.test_1(windows, alone(), 0, S, A, r, DETECTION) for r in rewards]
    # full with 6 collisions: no; the 21st reward replaces the oldest: 7 collisions among the last 20
    assert answers == [False] * WINDOW + [True, True, True]
    calm = first_windows()
    assert not any(cq.test_1(calm, alone(), 1, S, A, ER, DETECTION) for _ in range(3 * WINDOW))


@pytest.fixture()
def learned():
    q = np.zeros((2, N_CELLS, rules.N_ACTIONS))
    q[0, S] = [1.0, 2.0, 3.0, 4.0]
    return cq.Learned(q, np.zeros((2, N_CELLS, N_CELLS, rules.N_ACTIONS)), np.zeros((2, N_CELLS, N_CELLS), np.bool_))


def second_windows():
    return cq.reward_windows((2, N_CELLS, rules.N_ACTIONS, N_CELLS), WINDOW)


def test_test_2_waits_for_a_full_window_then_augments_and_copies_the_local_values(learned):
    q, q_aug, marked = learned
    windows = second_windows()
    for i in range(WINDOW):
        assert not marked[0, S].any(), i  # not full yet: no test
        cq.test_2(learned, windows, alone(), 0, S, A, ER + COLLISION, 4, DETECTION)
    assert marked[0, S, 4] and marked.sum() == 1
    assert q_aug[0, S, 4].tolist() == [1.0, 2.0, 3.0, 4.0]
    q_aug[0, S, 4, A] = 9.0  # learned since
    cq.test_2(learned, windows, alone(), 0, S, A, ER + COLLISION, 4, DETECTION)
    assert q_aug[0, S, 4, A] == 9.0 and windows.added[0, S, A, 4] == WINDOW + 1  # stored, not tested again


def test_test_2_keeps_a_window_per_other_cell_and_does_not_augment_as_alone(learned):
    _, _, marked = learned
    windows = second_windows()
    for r in collisions(6, other=ER):  # 6 collisions in 20: no
        cq.test_2(learned, windows, alone(), 0, S, A, r, 4, DETECTION)
    for r in [ER] * WINDOW:  # as alone
        cq.test_2(learned, windows, alone(), 0, S, A, r, 5, DETECTION)
    for r in [ER + COLLISION] * (WINDOW - 1):  # would reject, but one short of a full window
        cq.test_2(learned, windows, alone(), 0, S, A, r, 3, DETECTION)
    assert not marked.any()
    assert windows.added[0, S, A].tolist() == [0, 0, 0, WINDOW - 1, WINDOW, WINDOW]
    cq.test_2(learned, windows, alone(), 0, S, A, ER + COLLISION, 3, DETECTION)
    assert marked[0, S].tolist() == [False, False, False, True, False, False]


# --- steps 3 and 4 together, for three agents ---------------------------------------------------

def detect_stream(rewards, cells, done, settings, nearest=(NOBODY,) * 3):
    """Agent 0 in cell S takes action A and gets ``rewards`` one by one, the others where ``cells``
    says: its marks and its test 2 windows' counts of rewards per other's cell."""
    q = np.zeros((3, N_CELLS, rules.N_ACTIONS))
    learned = cq.Learned(q, np.zeros((3, N_CELLS, N_CELLS, rules.N_ACTIONS)), np.zeros((3, N_CELLS, N_CELLS), np.bool_))
    bundle = cq.detection(cq.LEARNER.setup(own=settings), tunnel_to_goal())[0]
    shape = (3, N_CELLS, rules.N_ACTIONS)
    first, second = cq.reward_windows(shape, WINDOW), cq.reward_windows(shape + (N_CELLS,), WINDOW)
    base = np.concatenate([alone(), alone()[:1]])
    seen = (np.array(cells), np.array(done), np.array(nearest))
    for r in rewards:
        cq.detect(learned, first, second, base, 0, A, r, seen, bundle)
    return learned.marked[0, S], second.added[0, S, A]


def test_test_2_windows_fill_only_once_test_1_rejects_and_for_every_other_agent_present():
    # 6 collisions in the first 20 rewards, then a collision on every step: test 1 rejects from the 21st on
    rewards = [ER] * 14 + [ER + COLLISION] * 31
    marks, counts = detect_stream(rewards, [S, 4, 5], [False, False, False], cq.Settings())
    assert counts.tolist() == [0, 0, 0, 0, 25, 25]  # both others' cells, from the 21st reward on
    assert marks.tolist() == [False] * 4 + [True, True]  # each full after 20 of those: augmented
    marks, counts = detect_stream(rewards, [S, 4, 5], [False, False, True], cq.Settings())
    assert counts.tolist() == [0, 0, 0, 0, 25, 0] and marks.sum() == 1  # agent 2 is in its goal: absent
    marks, counts = detect_stream(rewards, [S, 4, 5], [False, False, False], cq.Settings(cq_observe="nearest"),
                                  nearest=(2, NOBODY, NOBODY))
    assert counts.tolist() == [0, 0, 0, 0, 0, 25] and marks.tolist() == [False] * 5 + [True]  # its nearest only


def test_one_stage_augments_the_joint_states_of_a_low_reward_once_test_1_rejects():
    settings = cq.Settings(cq_detection="one_stage")
    marks, counts = detect_stream(collisions(6, other=ER) + [ER], [S, 4, 5], [False] * 3, settings)
    assert not marks.any() and not counts.any()  # test 1 never rejected; no test 2
    marks, counts = detect_stream([ER] * 14 + [ER + COLLISION] * 7, [S, 4, 5], [False] * 3, settings)
    assert marks.tolist() == [False] * 4 + [True, True] and not counts.any()  # the 21st: rejected, and low
    marks, _ = detect_stream([ER + 5.0] * WINDOW, [S, 4, 5], [False] * 3, settings)
    assert not marks.any()  # test 1 rejects rewards above ER: not this state's conflict


# --- which agent's cell an agent acts on -------------------------------------------------------

def observe(cells, done, marks, mode, k=0):
    g = load_map(MAPS / "warehouse_4.txt")
    augmenting = np.zeros(g.n_cells, np.bool_)
    augmenting[[g.cell(*rc) for rc in marks]] = True
    where = np.array([g.cell(*rc) for rc in cells])
    return cq.observe(rules.distance_table(g.n_cells, g.n_cols), where, np.array(done), k, augmenting,
                      cq.OBSERVED[mode])


def test_an_agent_acts_on_the_nearest_agent_whose_cell_augments_its_own():
    cells = [(2, 2), (2, 4), (2, 0), (0, 2)]  # agents 1, 2, 3 at distances 2, 2, 2
    assert observe(cells, [False] * 4, [(2, 0), (0, 2)], "every") == (2, NOBODY)  # ties: lowest number
    assert observe(cells, [False, False, True, False], [(2, 0), (0, 2)], "every") == (3, NOBODY)  # 2 is done
    cells[3] = (1, 2)  # agent 3 at distance 1
    assert observe(cells, [False] * 4, [(2, 0), (1, 2)], "every") == (3, NOBODY)
    assert observe(cells, [False] * 4, [], "every") == (NOBODY, NOBODY)
    # only the nearest agent: acts on it if its cell augments, else on Q_k even if another's does
    assert observe(cells, [False] * 4, [(2, 0), (1, 2)], "nearest") == (3, 3)
    assert observe(cells, [False] * 4, [(2, 0)], "nearest") == (NOBODY, 3)
    assert observe(cells, [False, True, True, True], [(2, 0)], "nearest") == (NOBODY, NOBODY)  # alone


# --- settings and memory -----------------------------------------------------------------------

def test_the_defaults_are_the_published_algorithm_at_its_reference_settings():
    s = cq.Settings()
    assert (s.cq_window, s.cq_significance, s.cq_test, s.cq_detection, s.cq_update_local, s.cq_observe) == (
        20, 0.01, "one_sample", "two_stage", False, "every")


@pytest.mark.parametrize("changes, message", [
    ({"cq_test": "welch"}, "cq_test must be one of ['one_sample', 'two_sample']"),
    ({"cq_detection": "both"}, "cq_detection must be one of ['one_stage', 'two_stage']"),
    ({"cq_observe": "all"}, "cq_observe must be one of ['every', 'nearest']"),
    ({"cq_update_local": 1}, "cq_update_local must be True or False"),
])
def test_bad_variants_are_rejected_with_a_message(changes, message):
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]")):
        cq.Settings(**changes)


def test_memory_counts_every_window_and_flag():
    g = tunnel_to_goal()
    published, one_stage = cq.LEARNER.setup(), cq.LEARNER.setup(own=cq.Settings(cq_detection="one_stage"))
    per_action = 2 * 25 * 4
    assert cq.reward_samples(published, g) == per_action * (1 + 25) * WINDOW
    assert cq.reward_samples(one_stage, g) == per_action * WINDOW
    assert cq.joint_room(published, g) == 2 * 25 * 25 * 4
    assert cq.window_bytes(published, g) == 2 * 25 * 25 + per_action * (1 + 25) * 32 + per_action * 24
    assert cq.LEARNER.bytes_per_run(published, g) == (
        (per_action + 2 * 25 * 25 * 4 + per_action * 26 * WINDOW) * 8 + cq.window_bytes(published, g))


# --- a frozen run from learned outputs ---------------------------------------------------------

FROZEN = {
    "published, two agents": ("tunnel_to_goal", cq.Settings(cq_solo_episodes=100)),
    "the earlier form (local updates, one stage)": ("tunnel_to_goal", cq.Settings(
        cq_window=30, cq_significance=0.05, cq_solo_episodes=100, cq_test="two_sample", cq_detection="one_stage",
        cq_update_local=True, cq_observe="nearest")),
    "published, four agents": ("warehouse_4", cq.Settings(cq_solo_episodes=20)),
}


@pytest.mark.parametrize("case", FROZEN)
@pytest.mark.parametrize("exploit", [0.9, 1.0])
def test_a_frozen_run_changes_nothing_learned_and_logs_its_episodes(case, exploit):
    map_name, settings = FROZEN[case]
    g = load_map(map_name)
    setup = cq.LEARNER.setup(QSettings(), settings)
    schedule = ep.Schedule(300, ep.uniform_edges(300, 100), 1000)
    trained = training.train(cq.LEARNER, setup, g, schedule, 1, 4, workers=parallel.Threads(1))
    assert trained["marked"].any()  # something to keep
    world = rules.world(g)
    frozen = cq.LEARNER.freeze(tuple(cq.LEARNER.inputs(setup, g)))
    learned = {name: trained[name][0].copy() for name in ("q", "q_aug", "marked")}
    log = np.zeros((3, ep.n_columns(g.n_agents)))
    cq.LEARNER.kernel(world, QLearning(0.0, 0.9, exploit), *frozen, schedule, learned["q"], learned["q_aug"],
                      learned["marked"], log, run_states(9, 1)[0])
    for name, array in learned.items():
        assert np.array_equal(array, trained[name][0]), name
    assert (ep.metric(log, "length") > 0).all() and (ep.metric(log, "steps") > 0).all()
