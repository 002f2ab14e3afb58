"""Section 4's experiments at small scale: results, seeding, config errors, chapter parameters,
claims and the figure scripts."""

import importlib.util
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from glamas import claims, lineworld  # noqa: E402
from glamas.experiments import and_network, single_gla, state_encoding  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
RESULTS = REPO / "data" / "results"
SMALL_1 = single_gla.SingleGLAConfig(iterations=3000, runs=4, record_points=30, eval_grid=40)
SMALL_2 = and_network.ANDNetworkConfig(iterations=3000, runs=4, record_points=30, eval_grid=40)


def _load_script(name):
    spec = importlib.util.spec_from_file_location(name, REPO / "paper_figures" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# ---- experiment 1 ----

def test_single_gla_run_shapes_and_ranges():
    result = single_gla.run(SMALL_1, seed=1)
    assert result.reward.shape == (4, 30) and result.params.shape == (4, 2, 2, 3)
    assert ((result.reward >= 0) & (result.reward <= 1)).all()
    assert result.iteration[-1] == 3000
    # with clip bounding the parameters stay near the box [-L, L]
    assert np.abs(result.params).max() < 1.2


def test_single_gla_learns_above_chance():
    measured = single_gla.measure(single_gla.run(replace(SMALL_1, iterations=20000), seed=2))
    # before learning the team earns 1/4 (one rewarded joint action of four)
    assert measured["final_average_reward"] > 0.4
    assert measured["agent_a_line_reward"] > 0.7


@pytest.mark.parametrize("context, n_inputs", [("joint", 3), ("absolute", 2), ("deictic", 2)])
def test_each_context_has_its_length(context, n_inputs):
    result = single_gla.run(replace(SMALL_1, context=context, iterations=300), seed=0)
    assert result.params.shape[-1] == n_inputs


def test_single_gla_same_seed_same_results_for_one_and_two_workers():
    one = single_gla.run(SMALL_1, seed=5, workers=1)
    two = single_gla.run(SMALL_1, seed=5, workers=2)
    np.testing.assert_array_equal(one.reward, two.reward)
    np.testing.assert_array_equal(one.params, two.params)
    other = single_gla.run(SMALL_1, seed=6, workers=1)
    assert not np.array_equal(one.params, other.params)


def test_best_single_line_for_agent_b_matches_the_analytic_value():
    # B's best line is 'L iff d = x2 - x1 > 0.5': it errs only on -0.5 < d < 0 (where B should
    # play L), which holds 0.21875 of the square, so it earns 0.78125
    assert single_gla.best_line_reward("joint", 1, grid=200) == pytest.approx(0.78125, abs=0.01)
    assert single_gla.best_line_reward("joint", 0, grid=200) == pytest.approx(1.0, abs=1e-9)
    assert single_gla.best_line_reward("absolute", 0, grid=200) == pytest.approx(0.5, abs=0.01)


@pytest.mark.parametrize("region3_reward, expected", [("move_apart", (1.0, 1.0, 0.5)),
                                                      ("fixed_joint_action", (1.0, 1.0, 1.0))])
def test_best_lines_region_shares_are_the_ceiling_of_each_reading(region3_reward, expected):
    # under 'move_apart' B's best line gives up one half of region 3; under (L, R) both maps are lines
    config = replace(SMALL_1, eval_grid=200, region3_reward=region3_reward)
    np.testing.assert_allclose(single_gla.best_lines_region_shares(config), expected, atol=0.01)
    assert single_gla.best_line_reward("joint", 1, region3_reward=region3_reward) == pytest.approx(
        {"move_apart": 0.78125, "fixed_joint_action": 1.0}[region3_reward], abs=0.01)


@pytest.mark.parametrize("offset", single_gla.B_BEST_LINE_OFFSETS)
def test_fig5b_draws_agent_b_best_lines(offset):
    # the reference lines Fig. 5b draws for B score what the exhaustive search finds best
    x1, x2 = lineworld.state_grid(200)
    plays_left = np.where(x2 - x1 > offset, lineworld.LEFT, lineworld.RIGHT)
    share = (plays_left == single_gla.best_actions(x1, x2, 1)).mean()
    assert share == pytest.approx(single_gla.best_line_reward("joint", 1, grid=200), abs=0.01)


SMALL_6 = state_encoding.EncodingConfig(replace(SMALL_1, iterations=6000), checkpoints=24)


def test_encoding_comparison_metrics():
    results = state_encoding.compare_encodings(replace(SMALL_6, experiment=replace(SMALL_6.experiment, runs=3)), seed=0)
    assert set(results) == {"joint", "absolute", "deictic"}
    measured = state_encoding.measure_encodings(results)
    for claim in claims.load("state_encoding"):
        assert claim.metric in measured


def test_checkpoints_change_nothing_else_and_hold_the_parameters():
    plain = single_gla.run(SMALL_1, seed=3)
    recorded = single_gla.run(SMALL_1, seed=3, checkpoint_at=np.array([0, 0, 7, 3000]))
    np.testing.assert_array_equal(plain.reward, recorded.reward)
    np.testing.assert_array_equal(plain.params, recorded.params)
    assert not recorded.checkpoint_params[:, :2].any()  # init_scale 0: the start is all zeros
    assert recorded.checkpoint_params[:, 2].any()
    np.testing.assert_array_equal(recorded.checkpoint_params[:, 3], plain.params)
    assert set(plain.arrays()) == {"iteration", "reward", "params"}  # Fig. 5's file is unchanged


@pytest.mark.parametrize("box, expected", [("fig5", (1.0, 1.0, 1.0)), ("two", (2.0, 2.0, 2.0)),
                                           ("input_range", (1.0, 2.0, 2.0))])
def test_each_box_reading_gives_its_L(box, expected):
    config = state_encoding.EncodingConfig(box=box)
    assert tuple(config.encoding(name).L for name in state_encoding.ENCODING_NAMES) == expected
    with pytest.raises(ValueError, match="box must be one of"):
        state_encoding.EncodingConfig(box="wide")


def test_fig6_metrics_do_not_move_with_the_plot_window():
    # every Fig. 6 metric is read from the parameters at the checkpoints, none from the windows
    measured = [state_encoding.measure_encodings(state_encoding.compare_encodings(
        replace(SMALL_6, experiment=replace(SMALL_6.experiment, record_points=points)), seed=1))
        for points in (10, 300)]
    assert measured[0].keys() == measured[1].keys()
    assert all(measured[0][key] == measured[1][key] for key in measured[0])


def test_expected_rewards_do_not_move_with_the_checkpoints_or_the_grid():
    # the curve's mean is a trapezoid sum over log-spaced checkpoints, the expected reward a grid
    # average whose points on a region's edge count half on each side: neither moves much
    results = {n: state_encoding.compare_encodings(replace(SMALL_6, checkpoints=n), seed=2)["joint"] for n in (24, 96)}
    means = {n: state_encoding.curve_mean(state_encoding.expected_curves(r), r.checkpoint) for n, r in results.items()}
    np.testing.assert_allclose(means[24], means[96], atol=2e-3)
    finer = replace(results[24], config=replace(results[24].config, eval_grid=160))
    np.testing.assert_allclose(state_encoding.expected_curves(finer), state_encoding.expected_curves(results[24]), atol=5e-4)


def test_the_learning_speed_verdict_does_not_move_with_the_reach_level():
    # the committed result: deictic / joint iterations to reach 1 - tolerance of the final value
    results = state_encoding.FIG6.load(RESULTS, state_encoding.FIG6.paper_scale(), seed=0)
    curves = {name: results[name].expected_reward for name in ("deictic", "joint")}
    claim = next(c for c in claims.load("state_encoding") if c.id == "deictic_learns_faster")
    verdicts = set()
    for tolerance in np.linspace(0.03, 0.15, 7):
        reach = [state_encoding.reach_iteration(curves[name], results[name].checkpoint, tolerance) for name in curves]
        measured = state_encoding.speed_comparison(*reach)
        verdicts.add(claims.verdicts([claim], measured)[0]["verdict"])
    assert verdicts == {"reproduced"}


@pytest.mark.parametrize("change, message", [
    ({"iterations": 0}, "iterations must be a whole number >= 1, got 0"),
    ({"runs": 2.5}, "runs must be a whole number >= 1, got 2.5"),
    ({"record_points": 5000}, r"record_points \(5000\) cannot exceed iterations \(3000\)"),
    ({"context": "polar"}, "context must be one of"),
    ({"region3_reward": "towards"}, "region3_reward must be one of"),
    ({"learning_rate": -0.1}, "GLA learning_rate must be a finite number > 0"),
    ({"bounding": "soft"}, "GLA bounding must be one of"),
    ({"init_scale": 2.0}, r"init_scale must be a number in \[0, L=1.0\]"),
])
def test_single_gla_config_errors_name_the_problem(change, message):
    with pytest.raises(ValueError, match=message):
        replace(SMALL_1, **change)


def test_learned_lines_need_the_joint_context():
    result = single_gla.run(replace(SMALL_1, context="deictic", iterations=300), seed=0)
    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match="need the joint context"):
        single_gla.plot_learned_lines(ax, result, 0)
    plt.close(fig)


# ---- experiment 2 ----

def test_and_network_run_shapes_and_ranges():
    result = and_network.run(SMALL_2, seed=1)
    assert result.prob_left.shape == (4, 30, 2)
    assert result.params.shape == (4, 2, 2, 2, 5)
    assert ((result.prob_left >= 0) & (result.prob_left <= 1)).all()
    assert result.iteration[0] == 0 and result.iteration[-1] == 3000
    # the unwired network inputs stay zero, so their parameters never move from the initial ones
    unwired = and_network.run(replace(SMALL_2, init_scale=0.0), seed=1).params[..., 3:]
    assert not unwired.any()


def test_and_network_starts_at_one_quarter_with_zero_parameters():
    result = and_network.run(replace(SMALL_2, init_scale=0.0), seed=0)
    np.testing.assert_allclose(result.prob_left[:, 0, :], 0.25)


def test_and_network_same_seed_same_results_for_one_and_two_workers():
    one = and_network.run(SMALL_2, seed=3, workers=1)
    two = and_network.run(SMALL_2, seed=3, workers=2)
    np.testing.assert_array_equal(one.prob_left, two.prob_left)
    np.testing.assert_array_equal(one.params, two.params)


def test_sweep_and_its_metrics():
    result = and_network.sweep(replace(SMALL_2, runs=3), (0.5, 1.0), seed=0)
    assert result.stuck.shape == (2, 3) and result.prob_left_I.shape == (2, 3, 2)
    assert result.rerun_prob_left_I.shape == (3, 2)
    measured = and_network.measure_sweep(result)
    assert measured["stuck_fraction_rise"] == measured["stuck_fraction_1"] - measured["stuck_fraction_0.5"]
    rerun = and_network.run(replace(SMALL_2, runs=3, reward_outside=1.0, stream=and_network.RERUN_STREAM), seed=0)
    np.testing.assert_array_equal(result.rerun_prob_left_I, and_network.final_left_by_region(rerun)[0])


def test_another_stream_keeps_the_initial_parameters_and_changes_the_rest():
    # with a vanishing learning rate the final parameters are the initial ones
    still = replace(SMALL_2, iterations=30, record_points=2, learning_rate=1e-12)
    first, other = (and_network.run(replace(still, stream=k), seed=2) for k in (0, 1))
    np.testing.assert_allclose(first.params, other.params, atol=1e-9)
    assert not np.array_equal(first.prob_left[:, 0], other.prob_left[:, 0])  # other probe points
    moving = [and_network.run(replace(SMALL_2, stream=k), seed=2).params for k in (1, 2)]
    assert not np.array_equal(moving[0], moving[1])
    with pytest.raises(ValueError, match="at least two values"):
        and_network.sweep(SMALL_2, (0.5,))


def test_and_network_metrics_cover_the_claims():
    measured = and_network.measure(and_network.run(SMALL_2, seed=0))
    for claim in claims.load("and_network"):
        assert claim.metric in measured


@pytest.mark.parametrize("change, message", [
    ({"reward_outside": 1.5}, r"reward_outside must be in \[0, 1\]"),
    ({"stuck_threshold": -0.1}, r"stuck_threshold must be in \[0, 1\]"),
    ({"parabola_curvature": -1.0}, "parabola_curvature must be >= 0 so that region I is convex"),
    ({"parabola_offset": 1.0}, "parabola_offset must be < 1 so that region I meets the square"),
    ({"probe_points": 0}, "probe_points must be a whole number >= 1"),
    ({"stream": -1}, "stream must be a whole number >= 0"),
    ({"temperature": 0.0}, "GLA temperature must be a finite number > 0"),
])
def test_and_network_config_errors_name_the_problem(change, message):
    with pytest.raises(ValueError, match=message):
        replace(SMALL_2, **change)


# ---- the chapter's parameters and claims ----

@pytest.mark.parametrize("experiment, config", [
    ("single_gla", single_gla.SingleGLAConfig()),
    ("state_encoding", state_encoding.EncodingConfig().encoding("joint")),
    ("and_network", and_network.ANDNetworkConfig()),
])
def test_config_defaults_are_the_chapters_parameters(experiment, config):
    for field, entry in claims.parameters(experiment).items():
        assert getattr(config, field) == entry["value"], f"{experiment}.{field} ({entry['where']})"


def test_single_gla_metrics_cover_the_claims():
    measured = single_gla.measure(single_gla.run(SMALL_1, seed=0))
    for claim in claims.load("single_gla"):
        assert claim.metric in measured


# ---- figure scripts ----

FIGURES = [("fig5", "single_gla"), ("fig6", "state_encoding"), ("fig7a", "and_network"), ("fig7b", "and_network"),
           ("fig7_sweep", "and_network_sweep")]  # (script and figure name, result file name)
SMALL_ARGS = ["--runs", "2", "--iterations", "200", "--seed", "4", "--workers", "1"]


@pytest.mark.parametrize("name, result_name", FIGURES)
def test_figure_script_writes_byte_identical_files(tmp_path, name, result_name):
    main = _load_script(name).main
    main(SMALL_ARGS + ["--out", str(tmp_path / "a"), "--results", str(tmp_path / "a")])
    main(SMALL_ARGS + ["--out", str(tmp_path / "b"), "--results", str(tmp_path / "b")])
    for suffix in ("png", "pdf"):
        first = (tmp_path / "a" / f"{name}.{suffix}").read_bytes()
        assert first == (tmp_path / "b" / f"{name}.{suffix}").read_bytes()
    assert (tmp_path / "a" / f"{result_name}.npz").exists()


def test_fig7a_and_fig7b_share_one_run(tmp_path):
    out = ["--out", str(tmp_path), "--results", str(tmp_path)]
    _load_script("fig7a").main(SMALL_ARGS + out)
    stored = (tmp_path / "and_network.npz").read_bytes()
    _load_script("fig7b").main(SMALL_ARGS + out)
    assert (tmp_path / "and_network.npz").read_bytes() == stored
    with pytest.raises(SystemExit, match="different configuration"):
        _load_script("fig7b").main(["--runs", "3"] + SMALL_ARGS[2:] + out)


@pytest.mark.parametrize("args, message", [
    (["--runs", "0"], "--runs: must be at least 1, got 0"),
    (["--iterations", "many"], "--iterations: expected a whole number, got 'many'"),
    (["--seed", "-3"], "--seed: must be 0 or more, got -3"),
])
def test_figure_script_rejects_bad_arguments(capsys, args, message):
    with pytest.raises(SystemExit):
        _load_script("fig5").main(args)
    assert message in capsys.readouterr().err


def test_fig7a_needs_two_runs(capsys, tmp_path):
    with pytest.raises(SystemExit):
        _load_script("fig7a").main(["--runs", "1", "--out", str(tmp_path)])
    assert "--runs must be at least 2" in capsys.readouterr().err


def test_figure_script_rejects_an_out_that_is_a_file(capsys, tmp_path):
    existing = tmp_path / "file.txt"
    existing.write_text("x")
    with pytest.raises(SystemExit):
        _load_script("fig6").main(["--out", str(existing)])
    assert "exists and is not a directory" in capsys.readouterr().err
