"""The Section 5.3 experiment: config defaults and validation, measurements, analyses, figure scripts."""

import dataclasses
import re
import runpy
import subprocess
import sys

import numpy as np
import pytest

from glamas import claims
from glamas.curves import convergence_episode, convergence_grid, convergence_ratio, final, grid_verdict
from glamas.experiments import gridworld as gw
from glamas.gridworld import MapError
from glamas.learners import two_observe
from glamas.qlearning import QSettings
from glamas.paths import REPO

FIGURES = ("fig10", "fig11a", "fig11b", "fig12a", "fig12b")


def setting(config, path: str):
    """The setting at a dotted ``path`` of ``config`` ('q.q_learning_rate', 'settings.two_observe.gla_L')."""
    value = config
    for part in path.split("."):
        value = value[part] if isinstance(value, dict) else getattr(value, part)
    return value


def test_config_defaults_are_the_chapter_parameters():
    config = gw.GridworldConfig()
    stated = claims.parameters("gridworld")
    assert stated  # the chapter states some of them
    for path, entry in stated.items():
        assert setting(config, path) == entry["value"], path


Q_FIELDS = {field.name for field in dataclasses.fields(QSettings)}
GLA_FIELDS = {field.name for field in dataclasses.fields(two_observe.GLASettings)}


def configured(**changes) -> gw.GridworldConfig:
    """The experiment's config with ``changes``, each to the settings class that owns it."""
    q = {k: v for k, v in changes.items() if k in Q_FIELDS}
    gla = {k: v for k, v in changes.items() if k in GLA_FIELDS}
    rest = {k: v for k, v in changes.items() if k not in Q_FIELDS | GLA_FIELDS}
    return gw.GridworldConfig(q=QSettings(**q), settings={"two_observe": two_observe.GLASettings(**gla)}, **rest)


@pytest.mark.parametrize("changes, message", [
    ({"bins": 0}, "bins must be a whole number >= 1"),
    ({"gla_need": "soon"}, "gla_need must be one of ['in_range', 'outcome', 'sampled']"),
    ({"gla_delta_scale": "km"}, "gla_delta_scale must be one of ['cells', 'unit']"),
    ({"episodes": 0}, "episodes must be a whole number >= 1"),
    ({"runs": 2.5}, "runs must be a whole number >= 1"),
    ({"exploit_prob": 1.5}, "exploit_prob must be a number in (0, 1]"),
    ({"discount": 0}, "discount must be a number in (0, 1]"),
    ({"bounce": "wall"}, "bounce must be one of ['previous', 'start']"),
    ({"learners": ("independent", "sarsa")}, "learners must be distinct names of registered learners"),
    ({"learners": ()}, "learners must be distinct names of registered learners"),
    ({"gla_temperature": -1.0}, "GLA temperature must be a finite number > 0"),
    ({"gla_bounding": "soft"}, "GLA bounding must be one of"),
    ({"gla_init_range": 2.0, "gla_L": 1.0}, "gla_init_range must be in [0, gla_L=1.0]"),
    ({"gla_init_range": 9.0}, "gla_init_range (9.0) must be at most the GLA box L = 8 on map 'tunnel_to_goal'"),
    ({"gla_feedback": ((1, 0, 0), (0, 1, 0))}, "gla_feedback must be a 2x2 table"),
    ({"gla_feedback": "ones"}, "gla_feedback must be a 2x2 table"),
    ({"coordination_penalty_per_cell": -0.1}, "coordination_penalty_per_cell must be a number >= 0"),
    ({"q_initial": float("nan")}, "q_initial must be a finite number"),
    ({"rule_distance": -1}, "rule_distance must be a whole number >= 0"),
])
def test_bad_configurations_are_rejected_with_a_message(changes, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        configured(**changes)


def test_settings_are_held_by_learner_name_and_completed_with_defaults():
    config = gw.GridworldConfig(learners=("independent", "two_observe", "cq"))
    assert set(config.settings) == {"two_observe", "cq"}  # the independent learners have none of their own
    assert config.own("two_observe") == two_observe.GLASettings() and config.own("independent") is None
    assert dataclasses.replace(config, learners=("independent",)).settings == {}  # only the trained learners' kept
    with pytest.raises(ValueError, match=r"settings for \['sarsa'\], which are no registered learners"):
        gw.GridworldConfig(settings={"sarsa": two_observe.GLASettings()})
    with pytest.raises(ValueError, match="learner 'cq' takes settings of its own of type Settings, got GLASettings"):
        gw.GridworldConfig(learners=("cq",), settings={"cq": two_observe.GLASettings()})


def test_a_map_by_name_or_path_with_any_number_of_agents(tmp_path):
    with pytest.raises(MapError, match="no map file"):
        gw.GridworldConfig(map="no_such_map")
    assert gw.GridworldConfig().gridmap().name == "tunnel_to_goal"
    path = REPO / "data" / "maps" / "tunnel_to_goal.txt"
    assert gw.GridworldConfig(map=str(path)).gridmap().n_cells == 25
    config = gw.GridworldConfig(map="tunnel_to_goal_3", learners=("independent", "two_observe"), runs=1, episodes=20,
                                bins=5, max_steps=500)
    result = gw.run(config, workers=1)
    assert result.log.shape[-1] == 2 * 3 + 4 and result.output("two_observe", "u").shape[1] == 3
    assert gw.optimum(config)["steps"] == pytest.approx(11.0)  # 10, 11 and 12 steps
    assert gw.optimum(gw.GridworldConfig(map="tunnel_to_goal_4")) is None  # too large to tabulate


def test_final_and_convergence_episode_on_a_made_up_curve():
    episodes = np.arange(1, 11) * 100
    curves = np.array([[40.0, 30, 20, 12, 10.4, 10, 10, 10, 10, 10]] * 2)
    assert final(curves, episodes) == 10.0  # the last 10 % of the episodes
    assert convergence_episode(curves, episodes) == 400.0  # 12 is the last block outside 5 %
    assert convergence_episode(np.full((2, 10), 3.0), episodes) == 0.0


@pytest.fixture(scope="module")
def small():
    config = gw.GridworldConfig(episodes=400, runs=2, bins=20)
    return config, gw.run(config, seed=1, workers=1)


def test_measure_gives_every_claimed_metric_and_verdicts_are_computed(small):
    _, result = small
    measured = gw.measure(result)
    rows = gw.claim_rows(result)
    assert len(rows) == len(claims.load("gridworld"))
    for row in rows:
        assert row["value"] == measured[row["claim"].metric] or np.isnan(row["value"])
        assert row["points"][0][1] == row["value"] or np.isnan(row["value"])  # the first point is the default
        assert row["holds"] == (row["verdict"] == claims.REPRODUCED)
    assert measured["steps_independent"] == pytest.approx(final(result.steps("independent"), result.episodes))
    assert measured["coordinations_independent"] == 0.0


def test_state_action_spaces_are_measured_from_the_tables(small):
    rows = {row["learner"]: row for row in gw.state_action_spaces(small[1])}
    assert rows["independent"]["q_entries_per_agent"] == 25 * 4
    assert rows["joint_state"]["q_entries_per_agent"] == 625 * 4
    assert rows["mmdp"]["q_entries_per_agent"] == 625 * 16 / 2  # one central table for two agents
    assert rows["two_observe"]["q_entries_per_agent"] == 25 * 4
    assert rows["two_observe"]["gla_parameters_per_agent"] == 4
    assert rows["mmdp"]["gla_parameters_per_agent"] == 0


def test_coordination_probability_is_eq15_of_the_final_parameters(small):
    config, result = small
    u = np.zeros_like(result.output("two_observe", "u"))
    u[:, :, 1] = [-0.5, 0.75]  # coordinate: x.u = -0.5 delta + 0.75; act alone: 0
    made_up = dataclasses.replace(result, own={"two_observe": {**result.own["two_observe"], "u": u}})
    p = gw.coordination_probability(made_up, config, [0, 1, 2, 4])
    expected = 1 / (1 + np.exp(-(-0.5 * np.array([0, 1, 2, 4]) + 0.75) / config.own("two_observe").gla_temperature))
    assert np.allclose(p, expected)


def test_optimum_is_the_value_iteration_episode():
    best = gw.optimum(gw.GridworldConfig())
    assert best["steps"] == 10.5 and best["collisions"] == 0.0  # 10 and 11 steps (Fig. 9 notes)


def _run_figure(name, argv):
    runpy.run_path(str(REPO / "paper_figures" / f"{name}.py"), run_name="not_main")["main"](argv)


def test_figure_scripts_small_scale_are_byte_reproducible(tmp_path):
    for attempt in ("a", "b"):  # two independent runs from scratch
        argv = ["--runs", "2", "--iterations", "300", "--workers", "1",
                "--out", str(tmp_path / attempt / "out"), "--results", str(tmp_path / attempt / "results")]
        for name in FIGURES:
            _run_figure(name, argv)
    for name in FIGURES:
        for ext in ("png", "pdf"):
            a = (tmp_path / "a" / "out" / f"{name}.{ext}").read_bytes()
            assert a == (tmp_path / "b" / "out" / f"{name}.{ext}").read_bytes(), f"{name}.{ext}"
    assert sorted(p.name for p in (tmp_path / "a" / "results").iterdir()) == ["gridworld.npz"]


def test_figure_script_runs_from_another_directory(tmp_path):
    done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig12b.py"), "--runs", "2",
                           "--iterations", "200", "--out", "out", "--results", "results"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "fig12b.png").is_file() and (tmp_path / "results" / "gridworld.npz").is_file()


@pytest.mark.parametrize("argv, message", [
    (["--runs", "0"], "must be at least 1"),
    (["--iterations", "many"], "expected a whole number"),
    (["--seed", "-2"], "must be 0 or more"),
])
def test_bad_command_line_arguments_are_rejected(argv, message, capsys, tmp_path):
    with pytest.raises(SystemExit):
        _run_figure("fig11a", argv + ["--out", str(tmp_path)])
    assert message in capsys.readouterr().err


def test_out_that_is_a_file_is_rejected(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    with pytest.raises(SystemExit):
        _run_figure("fig11b", ["--out", str(tmp_path / "file")])
    assert "exists and is not a directory" in capsys.readouterr().err


def test_final_weighs_log_spaced_blocks_by_their_episodes_in_the_last_tenth():
    episodes = np.array([1, 2, 4, 8, 16, 50, 100])  # last 10 %: episodes 90 .. 100 of the last block
    curves = np.array([[9.0, 9, 9, 9, 9, 5, 2]] * 3)
    assert final(curves, episodes) == 2.0
    episodes = np.array([10, 85, 95, 100])  # blocks 85-95 (5 of its episodes) and 95-100 (all 5)
    assert final(np.array([[0.0, 0, 4, 2]]), episodes) == 3.0


def test_a_convergence_ratio_is_decided_only_when_its_interval_excludes_one():
    episodes = np.arange(1, 101)
    fast = np.where(episodes < 10, 50.0, 10.0) + np.zeros((20, 1))
    slow = np.where(episodes < 60, 50.0, 10.0) + np.zeros((20, 1))
    point, low, high = convergence_ratio(fast, slow, episodes)
    assert point == pytest.approx(9 / 59) and high < 1
    assert grid_verdict(convergence_grid(fast, slow, episodes)) == "faster"
    assert grid_verdict(convergence_grid(slow, fast, episodes)) == "slower"
    noisy = slow.copy()
    noisy[:10] = fast[:10]  # half the runs converge early, half late: the runs cannot order them
    _, low, high = convergence_ratio(noisy, slow, episodes, "run_mean")
    assert low <= 1 <= high
    assert grid_verdict(convergence_grid(noisy, slow, episodes, "run_mean")) == "undecidable"


def test_the_step_ticks_derived_from_the_map_are_tunnel_to_goals_on_tunnel_to_goal():
    assert gw.step_ticks(gw.GridworldConfig().gridmap()) == ((10, 20, 50, 100, 1000), (10, 11, 12, 14, 16))
    log_ticks, tail = gw.step_ticks(gw.GridworldConfig(map="cmu").gridmap())  # 31 steps alone
    assert log_ticks[0] == 31 and tail == (31, 34, 37, 43, 49)
