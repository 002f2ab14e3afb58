"""Settings from the command line (glamas.overrides, the figure scripts' --learners and --set): any
field of a configuration, of a dataclass in it or of a learner's own settings, read as its type and
checked by its dataclass; a bad one is one line and exit status 2."""

import json
import subprocess
import sys

import numpy as np
import pytest

from glamas import overrides
from glamas.errors import UserError
from glamas.experiments import gridworld as gw
from glamas.paths import REPO

CONFIG = gw.GridworldConfig()


def test_a_field_a_nested_field_and_a_learners_setting_are_set_with_their_types():
    config = overrides.with_setting(CONFIG, "episodes=300")
    config = overrides.with_setting(config, "q.q_learning_rate=0.1")
    config = overrides.with_setting(config, "two_observe.gla_learning_rate=0.02")
    config = overrides.with_setting(config, "two_observe.gla_L=3")  # a field now None: its annotation's type
    assert (config.episodes, config.q.q_learning_rate) == (300, 0.1)
    assert (config.settings["two_observe"].gla_learning_rate, config.settings["two_observe"].gla_L) == (0.02, 3.0)
    assert overrides.with_setting(config, "two_observe.gla_L=none").settings["two_observe"].gla_L is None
    assert overrides.with_learners(CONFIG, "independent, two_observe").learners == ("independent", "two_observe")


def test_every_listed_setting_can_be_given_back_as_it_is_listed():
    for entry in overrides.settable(CONFIG):
        assert overrides.with_setting(CONFIG, entry) == CONFIG, entry


@pytest.mark.parametrize("assignment, message", [
    ("two_observe.rate=0.2", "GLASettings has no setting 'rate'; it has gla_learning_rate,"),
    ("foo.x=1", "GridworldConfig has no setting 'foo'; it has map,"),
    ("q.q_learning_rate=abc", "expected a finite number, got 'abc'"),
    ("q.q_learning_rate=5", "q_learning_rate must be a number in (0, 1], got 5.0"),
    ("episodes=-3", "episodes must be a whole number >= 1, got -3"),
    ("q=1", "that names a group of settings, not one; add .FIELD"),
    ("bounce=sideways", "bounce must be one of ['previous', 'start'], got 'sideways'"),
    ("novalue", "expected NAME.FIELD=VALUE, e.g. --set q.q_learning_rate=0.05"),
])
def test_a_bad_setting_is_one_line_naming_it(assignment, message):
    with pytest.raises(UserError) as error:
        overrides.with_setting(CONFIG, assignment)
    assert str(error.value).startswith(f"--set {assignment}: ") and message in str(error.value)
    assert "\n" not in str(error.value)


def _fig11a(tmp_path, *args):
    return subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig11a.py"), "--runs", "1",
                           "--iterations", "100", "--backend", "threads", "--workers", "1",
                           "--results", str(tmp_path), "--out", str(tmp_path), *args],
                          capture_output=True, text=True, timeout=120)


def test_the_command_line_trains_the_chosen_learners_with_the_given_setting_and_stores_them(tmp_path):
    done = _fig11a(tmp_path, "--learners", "independent,two_observe", "--set", "two_observe.gla_learning_rate=0.02")
    assert done.returncode == 0, done.stderr
    with np.load(tmp_path / "gridworld.npz", allow_pickle=False) as archive:
        stored = json.loads(str(archive["__config__"]))
        assert archive["learners"].tolist() == ["independent", "two_observe"]
    assert "0.02" in json.dumps(stored["fields"]["settings"])


def test_a_bad_set_on_the_command_line_is_one_line_and_status_2_before_computing(tmp_path):
    done = _fig11a(tmp_path, "--set", "two_observe.rate=0.2")
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert done.stderr.strip().splitlines()[-1].startswith("fig11a.py: error: --set two_observe.rate=0.2: ")
    assert not (tmp_path / "gridworld.npz").exists()


def test_help_lists_the_settings():
    done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig11a.py"), "--help"],
                          capture_output=True, text=True, timeout=60)
    assert "two_observe.gla_learning_rate=0.01" in " ".join(done.stdout.split())


def test_the_experiments_of_episodes_take_episodes_and_iterations_as_one_option():
    from glamas import cli
    from glamas.experiments import registry, single_gla
    counting = {e.name: e.counts for e in registry.experiments()}
    assert counting["gridworld"] == counting["scaling"] == counting["benchmark_maps"] == "episodes"
    assert counting["single_gla"] == "iterations"
    parser = cli.figure_parser("x", runs=2, iterations=10, counts="episodes")
    assert parser.parse_args(["--episodes", "30"]).iterations == parser.parse_args(["--iterations", "30"]).iterations
    parser = cli.figure_parser("x", runs=2, iterations=10)
    with pytest.raises(SystemExit):
        parser.parse_args(["--episodes", "30"])
    with pytest.raises(UserError, match="counts must be 'iterations' or 'episodes'"):
        registry.Experiment("x", single_gla.SingleGLAConfig, None, None, 1, 1, None, counts="steps")
