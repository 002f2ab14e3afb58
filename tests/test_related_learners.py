"""The related-work learners: sparse tabular MAQ's coordination states, CQ-learning's two-sample
variant and its augmented update (its steps: tests/test_cq.py), small runs of both, seeds,
configuration errors and the figure scripts (sparse MAQ's updates by hand:
tests/test_related_many_agents.py)."""

import dataclasses
import math
import runpy

import matplotlib.pyplot as plt
import numpy as np
import pytest

from glamas import claims
from glamas.curves import final
from glamas.experiments import gridworld as gw
from glamas.experiments import related_work as rw
from glamas.gridworld import tunnel_to_goal
from glamas.gridworld.rules import S
from glamas.learners import cq, registry, sparse_maq
from glamas.paths import REPO

ALPHA, GAMMA = 0.5, 0.9
SMALL = rw.RelatedWorkConfig(learners=("independent", "mmdp", "sparse_maq", "cq"), episodes=400, runs=2, bins=20,
                             settings={"cq": cq.Settings(cq_solo_episodes=50)})


# --- sparse tabular MAQ ------------------------------------------------------------------------

def test_coordination_states_are_the_close_joint_states():
    g = tunnel_to_goal()
    index = sparse_maq.coordination_index(g, 2)
    rows = np.flatnonzero(index >= 0)
    assert index[rows].tolist() == list(range(rows.size))  # numbered in joint-state order
    goal = int(np.flatnonzero(g.is_goal)[0])
    for joint in rows:
        a, b = divmod(int(joint), g.n_cells)
        assert a != b and goal not in (a, b) and 1 <= rules_distance(g, a, b) <= 2
    assert index[g.cell(1, 4) * 25 + g.cell(3, 4)] >= 0  # the tunnel entrance, distance 2
    assert index[g.cell(0, 0) * 25 + g.cell(4, 0)] == -1  # the starts, distance 4
    assert sparse_maq.pair_table_shape(SMALL.setup("sparse_maq"), g) == (1, rows.size, 16)


def rules_distance(g, a, b):
    (ra, ca), (rb, cb) = g.row_col(a), g.row_col(b)
    return abs(ra - rb) + abs(ca - cb)


def test_coordination_index_errors_name_the_problem():
    with pytest.raises(ValueError, match="coordination distance must be a whole number >= 1"):
        sparse_maq.coordination_index(tunnel_to_goal(), 0)


def test_t_critical_values_match_the_tables():
    t = cq.t_critical_values(60, 0.05)
    assert math.isinf(t[0])
    assert t[1] == pytest.approx(12.7062, abs=1e-4)
    assert t[10] == pytest.approx(2.2281, abs=1e-4)
    assert t[58] == pytest.approx(2.0017, abs=1e-4)
    assert cq.t_critical_values(5, 0.01)[5] == pytest.approx(4.0321, abs=1e-4)
    assert cq.two_sided_p_value(2.2281389, 10) == pytest.approx(0.05, abs=1e-6)
    with pytest.raises(ValueError, match="significance level must be in"):
        cq.t_critical_values(5, 1.5)


def _window(rewards, size):
    samples, summary, added = np.zeros(size), np.zeros(3), 0
    for r in rewards:
        added = cq.add_reward(samples, added, summary, r)
    return summary


def test_reward_window_keeps_the_summary_of_its_last_rewards():
    summary = _window([5.0, -10.0, 0.0, -1.0, 2.0], 3)
    assert summary.tolist() == [3.0, 1.0, 5.0]  # the last three: 0, -1, 2


def test_the_two_sample_variant_flags_rewards_that_drop_when_the_other_agent_is_near():
    rng = np.random.default_rng(0)
    t = cq.t_critical_values(58, 0.05)
    baseline = _window(np.zeros(30), 30)  # the state-action alone: 0 every time
    near = _window(np.where(rng.random(30) < 0.4, -10.0, 0.0), 30)  # collisions 40 % of the time
    unchanged = _window(np.zeros(30), 30)
    assert cq.significantly_lower(baseline, near, t)
    assert not cq.significantly_lower(baseline, unchanged, t)
    assert not cq.significantly_lower(near, baseline, t)  # higher is no conflict
    rare = _window([-10.0] * 3 + [0.0] * 27, 30)  # t = sqrt(29 p / (1 - p)) = 1.80 < 2.00
    assert not cq.significantly_lower(baseline, rare, t)
    assert cq.significantly_lower(baseline, _window([-10.0] * 4 + [0.0] * 26, 30), t)  # 2.11 > 2.00
    noisy = _window(rng.normal(0, 1, 30), 30)
    same = _window(rng.normal(0, 1, 30), 30)
    assert not cq.significantly_lower(noisy, same, t)


def test_fewest_flagged_collisions_is_where_the_test_starts_to_flag():
    config = rw.RelatedWorkConfig()
    assert rw.fewest_flagged_collisions(config) == 7  # 6 in 20 is not flagged at 1 %
    strict = dataclasses.replace(config, settings={"cq": cq.Settings(cq_significance=0.001)})
    assert rw.fewest_flagged_collisions(strict) > 7


def test_augmented_update_bootstraps_on_the_local_next_values():
    q = np.zeros((25, 4))
    q[4] = [0.0, 8.0, 1.0, 2.0]
    q_aug = np.zeros((25, 25, 4))
    q_aug[9, 19, S] = 1.0
    cq.augmented_update(q_aug, q, 9, 19, S, -10.0, 4, False, ALPHA, GAMMA)
    assert q_aug[9, 19, S] == pytest.approx(1 + ALPHA * (-10 + GAMMA * 8 - 1))


# --- small runs --------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def small():
    return rw.run(SMALL, seed=3, workers=1)


def test_small_run_logs_both_learners_and_cq_marks_only_close_joint_states(small):
    assert small.names() == ["independent", "mmdp", "sparse_maq", "cq"]
    for name in ("sparse_maq", "cq"):
        assert np.isfinite(small.curves(name, "steps")).all()
        assert (small.curves(name, "steps") >= 10).all(), name
        assert (small.reward(name) <= 100).all()
        assert small.steps(name).mean(axis=0)[-1] < 40, name  # they learn the way to the goal
        assert (small.curves(name, "coordinations") > 0).any(), name
    assert small.output("cq", "marked").any()  # the tunnel entrance makes conflicts
    assert (rw.marked_distances(small, SMALL) <= 2).all()  # collisions only come from close agents
    index = sparse_maq.coordination_index(tunnel_to_goal(), 2)
    assert small.joint_entries[2].tolist() == [(index.max() + 1) * 16 / 2] * 2
    assert small.joint_entries[3].tolist() == (small.output("cq", "marked").sum(axis=(2, 3)).mean(axis=1) * 4).tolist()
    assert small.local_entries.tolist() == [100.0, 0.0, 100.0, 100.0]
    # CQ-learning's windows: test 1's per state-action, test 2's per state-action and other's cell
    assert small.reward_samples.tolist() == [0, 0, 0, 25 * 4 * (1 + 25) * SMALL.own("cq").cq_window]


def test_chapter_learners_keep_their_seeds_and_results_do_not_depend_on_workers(small):
    chapter = gw.run(gw.GridworldConfig(learners=("independent", "mmdp"), episodes=400, runs=2, bins=20), seed=3, workers=1)
    assert np.array_equal(small.log[:2], chapter.log)
    two = rw.run(SMALL, seed=3, workers=2)
    assert np.array_equal(small.log, two.log) and np.array_equal(small.output("cq", "marked"), two.output("cq", "marked"))
    seeds = [gw.seed_of(3, name) for name in (*rw.RELATED_LEARNERS, *gw.CHAPTER_LEARNERS)]
    assert len(set(seeds)) == len(seeds)


def test_measure_gives_every_claimed_metric(small):
    rows = rw.claim_rows(small, SMALL)
    assert [row["claim"].id for row in rows] == [c.id for c in claims.load("related_work")]
    m = rw.measure(small, SMALL)
    assert m["q_entries_sparse_maq_over_mmdp"] == pytest.approx(m["q_entries_sparse_maq"] / 5000)
    assert "CQ-learning" in rw.summary_table(small, SMALL)


def test_final_interval_is_the_final_mean_with_a_band_over_runs(small):
    mean, low, high = rw.final_interval(small, "cq")
    assert mean == pytest.approx(final(small.curves("cq", "collisions"), small.episodes))
    assert low <= mean <= high
    per_run = [final(c[None], small.episodes) for c in small.curves("independent", "steps")]
    _, low, high = rw.final_interval(small, "independent", "steps")
    assert min(per_run) <= low <= high <= max(per_run)  # a band of run means stays in the runs' range


@pytest.mark.parametrize("changes, message", [
    ({"learners": ("cq", "cq")}, "learners must be distinct names"),
    ({"learners": ("q_lambda",)}, "learners must be distinct names"),
    ({"settings": {"sparse_maq": {"coordination_distance": 0}}}, "learner 'sparse_maq' takes settings of its own of type Settings"),
])
def test_bad_configurations_are_rejected_with_a_message(changes, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        dataclasses.replace(SMALL, **changes)


@pytest.mark.parametrize("make, message", [
    (lambda: sparse_maq.Settings(coordination_distance=0), "coordination_distance must be a whole number >= 1"),
    (lambda: sparse_maq.Settings(coordination="nearest"), "coordination must be one of ('graph', 'pairs')"),
    (lambda: sparse_maq.Settings(maximiser="brute"), "maximiser must be one of ('elimination', 'max_plus')"),
    (lambda: sparse_maq.Settings(max_plus_rounds=0), "max_plus_rounds must be a whole number >= 1"),
    (lambda: cq.Settings(cq_window=1), "cq_window must be a whole number >= 2"),
    (lambda: cq.Settings(cq_solo_episodes=2.5), "cq_solo_episodes must be a whole number >= 1"),
    (lambda: cq.Settings(cq_significance=5), "cq_significance must be a number in (0, 1)"),
    (lambda: cq.Settings(cq_solo_exploit_prob=1.5), "cq_solo_exploit_prob must be a number in (0, 1], got 1.5"),
])
def test_bad_settings_are_rejected_with_a_message(make, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        make()


def test_figure_scripts_share_one_result_and_are_byte_reproducible(tmp_path):
    names = ("related_steps", "related_reward", "related_collisions", "related_coordinations", "related_sizes")
    for attempt in ("a", "b"):
        argv = ["--runs", "2", "--iterations", "300", "--workers", "1",
                "--out", str(tmp_path / attempt / "out"), "--results", str(tmp_path / attempt / "results")]
        for name in names:
            runpy.run_path(str(REPO / "paper_figures" / f"{name}.py"), run_name="not_main")["main"](argv)
    assert sorted(p.name for p in (tmp_path / "a" / "results").iterdir()) == ["related_work.npz"]
    for name in names:
        for ext in ("png", "pdf"):
            assert (tmp_path / "a" / "out" / f"{name}.{ext}").read_bytes() == \
                (tmp_path / "b" / "out" / f"{name}.{ext}").read_bytes(), f"{name}.{ext}"


def test_plots_draw_on_a_given_axes(small):
    fig, axes = plt.subplots(1, 3)
    rw.plot_coordinations(axes[0], small)
    rw.plot_size_and_reward(axes[1], small, SMALL)
    rw.plot_marked_distances(axes[2], small, SMALL)
    assert [len(ax.get_legend().get_texts()) for ax in (axes[0], axes[2])] == [2, 2]
    sizes = [text.get_text() for text in axes[1].get_legend().get_texts()]
    assert all(any(registry.label(name) in text for text in sizes) for name in small.names())
    assert sum("reward samples" in text for text in sizes) == 1  # CQ-learning's stored rewards
    plt.close(fig)
