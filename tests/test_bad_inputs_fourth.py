"""Bad input and faults, one line each (exit status 2, no traceback, nothing committed changed):
the fourth round's cases that reach neither a result file nor the learner modules (those are in
test_verify.py, test_toy_learner.py, test_staleness_by_behaviour.py and test_seeds.py)."""

import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from glamas import errors, results
from glamas.errors import UserError
from glamas.experiments import gridworld, registry
from glamas.paths import REPO, RESULTS

SCRIPTS = REPO / "paper_figures"


def _error_line(*arguments, cwd=REPO) -> str:
    """The one line ``error: ...`` (or argparse's ``SCRIPT: error: ...``) of a command that exits with 2."""
    before = {path.name: path.stat().st_mtime_ns for path in RESULTS.glob("*.npz")}
    done = subprocess.run([sys.executable, *map(str, arguments)], cwd=cwd, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert {path.name: path.stat().st_mtime_ns for path in RESULTS.glob("*.npz")} == before
    return done.stderr.strip().splitlines()[-1]


def test_a_learner_that_no_mmdp_table_fits_is_skipped_not_an_overflow(tmp_path):
    from glamas.experiments import warehouses
    config = dataclasses.replace(warehouses.scaled(1, 10), learners=("mmdp",), agents=(8,), evaluation_episodes=1)
    result = warehouses.run(config, seed=0, workers=1)
    assert not result.ran.any() and result.bytes_needed.max() == np.iinfo(np.int64).max


def test_a_warehouse_too_large_for_memory_is_refused_before_its_layout_is_searched(tmp_path):
    line = _error_line(SCRIPTS / "warehouses.py", "--runs", "1", "--episodes", "10", "--set", "agents=100000000",
                       "--out", tmp_path, "--results", tmp_path)
    assert "a warehouse of 100000000 agents has at least 1000000000 cells" in line and "choose fewer agents" in line


def test_an_experiment_registered_again_under_a_taken_name_is_refused():
    from glamas.experiments import scaling
    known = registry.REGISTRY["scaling"]
    with pytest.raises(UserError, match="an experiment named 'scaling' is registered already"):
        registry.register(dataclasses.replace(known, figures=("many_agents",)))
    assert registry.REGISTRY["scaling"] is known is scaling.EXPERIMENT
    assert registry.register(known) is known  # the same experiment again (a reload) is taken


def test_a_setting_of_a_learner_not_trained_says_how_to_train_it(tmp_path):
    line = _error_line(SCRIPTS / "fig11a.py", "--learners", "independent,mmdp", "--set", "two_observe.gla_K=2.0",
                       "--out", tmp_path, "--results", tmp_path)
    assert line.endswith("the learner 'two_observe' is not trained here (independent,mmdp); train it too with "
                         "--learners independent,mmdp,two_observe")


def test_rewards_whose_sums_could_overflow_are_refused(tmp_path):
    line = _error_line(SCRIPTS / "scaling_performance.py", "--runs", "1", "--episodes", "10",
                       "--set", "rewards.goal=1e308", "--out", tmp_path, "--results", tmp_path)
    assert "Rewards.goal must be a number from -1e+12 to 1e+12" in line


def test_learners_one_level_down_are_chosen_with_learners():
    from glamas import overrides
    from glamas.experiments import crowd
    config = overrides.with_learners(crowd.EXPERIMENT.paper_scale(), "two_observe")
    assert config.study.learners == ("two_observe",)


def test_runs_given_twice_is_refused(tmp_path):
    line = _error_line(SCRIPTS / "fig11a.py", "--runs", "2", "--set", "runs=3", "--out", tmp_path, "--results", tmp_path)
    assert line.endswith("--set runs=3: runs has an option of its own, which would disagree with it: give --runs 3 "
                         "instead")


def test_loading_a_result_by_its_path_says_what_load_takes():
    with pytest.raises(UserError, match=r"loading a result of gridworld takes its configuration, a GridworldConfig, "
                                        r"and the directory of its file gridworld.npz as results_dir"):
        gridworld.load("out/results/gridworld.npz")


@pytest.mark.parametrize("config, record, named", [
    ("", None, "its configuration is not one glamas writes"),
    ("[1, 2]", None, "its configuration is not one glamas writes"),
    (None, "not json", "its record of what made it is not one glamas writes"),
    (None, "[]", "its record of what made it is not one glamas writes"),
])
def test_a_result_file_with_a_damaged_header_is_one_line_and_kept(tmp_path, config, record, named):
    good = gridworld.EXPERIMENT.file(RESULTS)
    with np.load(good, allow_pickle=False) as archive:
        content = {key: archive[key] for key in archive.files}
    if config is not None:
        content["__config__"] = np.array(config)
    if record is not None:
        content["__provenance__"] = np.array(record)
    damaged = tmp_path / "gridworld.npz"
    np.savez(damaged, **content)
    kept = damaged.read_bytes()
    with pytest.raises(results.UnreadableResultError, match=named):
        gridworld.load(results_dir=tmp_path)
    assert damaged.read_bytes() == kept


def test_a_fault_in_a_module_of_ones_own_is_the_users_to_fix(tmp_path):
    (tmp_path / "mine.py").write_text("def kernel(table):\n    return table['missing']\n")
    (tmp_path / "script.py").write_text(f"import sys\nsys.path.insert(0, {str(tmp_path)!r})\nfrom glamas import errors\n"
                                        "import mine\nerrors.run(lambda: mine.kernel({}))\n")
    line = _error_line(tmp_path / "script.py")
    assert line == (f"error: {tmp_path / 'mine.py'} fails (KeyError: 'missing'): the fault is in that module, not in "
                    "glamas; correct it")


def test_a_fault_inside_glamas_stays_a_bug_with_its_traceback(tmp_path):
    (tmp_path / "script.py").write_text("from glamas import errors\nfrom glamas.experiments import registry\n"
                                        "errors.run(lambda: registry.Experiment.arrays(None, None))\n")
    done = subprocess.run([sys.executable, str(tmp_path / "script.py")], capture_output=True, text=True, timeout=60)
    assert done.returncode == errors.EXIT_BUG and "Traceback" in done.stderr and "bug in glamas" in done.stderr
