"""Staleness by behaviour (glamas.small_runs --adopt): after a change of the code, a committed
result whose experiment's small run still gives the committed bits is recorded again with the code
as it is, its arrays untouched; one whose small run gives other bits stays stale."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from glamas import committed, provenance, results, small_runs, sources
from glamas.experiments.gridworld import experiment as gw
from glamas.paths import REPO, RESULTS

NAME = "single_gla"  # the cheapest small run


@pytest.fixture
def edited(monkeypatch, tmp_path):
    """Copies of the committed results and digests, and the code record of a change of one kernel
    module (lineworld.py) that the records see, whatever it does."""
    shutil.copytree(RESULTS, tmp_path / "results")
    shutil.copy(small_runs.DIGESTS, tmp_path / "small_runs.json")
    monkeypatch.setattr(small_runs, "RESULTS", tmp_path / "results")
    monkeypatch.setattr(committed, "RESULTS", tmp_path / "results")
    monkeypatch.setattr(small_runs, "DIGESTS", tmp_path / "small_runs.json")
    real = provenance.code_record
    monkeypatch.setattr(provenance, "code_record", lambda config: {**real(config), "lineworld.py": "edited"})
    return tmp_path


def _load(directory):
    experiment = small_runs.experiment_named(NAME)
    return results.load(experiment.file(directory), experiment.paper_scale(), seed=0)


def test_a_change_that_keeps_the_behaviour_is_re_recorded_and_the_result_loads(edited, capsys):
    with pytest.raises(results.StaleResultError, match="small_runs --adopt"):
        _load(edited / "results")
    assert small_runs.status(NAME)[0] == "re-record"
    before = np.load(RESULTS / f"{NAME}.npz")
    assert small_runs.main(["--adopt", NAME]) == 0
    assert capsys.readouterr().out.strip() == f"{NAME}: re-recorded (its small run gives the committed bits)"
    after = _load(edited / "results")
    assert set(after) == {key for key in before.files if not key.startswith("__")}
    assert all(np.array_equal(after[key], before[key], equal_nan=True) for key in after)
    assert small_runs.committed_code()[NAME]["lineworld.py"] == "edited"
    assert small_runs.status(NAME)[0] == "current" and small_runs.status("gridworld")[0] == "re-record"


def test_a_change_of_behaviour_leaves_the_result_stale_naming_the_recomputation(edited, monkeypatch, capsys):
    monkeypatch.setattr(small_runs, "small_digest", lambda name, workers=None: "other bits")
    committed = (edited / "results" / f"{NAME}.npz").read_bytes()
    assert small_runs.main(["--adopt", NAME]) == 1
    out = capsys.readouterr().out.strip()
    assert out.count("\n") == 0 and out.startswith(f"{NAME}: stale, its small run gives other bits")
    assert "paper_figures/fig5.py --rerun" in out and "glamas/lineworld.py" in out
    assert (edited / "results" / f"{NAME}.npz").read_bytes() == committed
    with pytest.raises(results.StaleResultError):
        _load(edited / "results")


def test_a_result_recorded_with_other_code_than_its_digest_is_not_re_recorded(edited, capsys):
    digests = json.loads((edited / "small_runs.json").read_text())
    digests["code"][NAME] = {**digests["code"][NAME], "gla.py": "other"}
    (edited / "small_runs.json").write_text(json.dumps(digests))
    state, why = small_runs.status(NAME)
    assert state == "recompute" and "about 0.5 min on 2 cores" in why
    assert small_runs.main(["--adopt", NAME]) == 1
    assert capsys.readouterr().out.startswith(f"{NAME}: stale, not re-recorded")


def test_an_adoption_stopped_midway_keeps_each_result_and_its_digest_recorded_with_the_same_code(edited, monkeypatch):
    real = small_runs.small_digest

    def stopped_at_the_second(name, workers=None):
        if name != NAME:
            raise KeyboardInterrupt  # Ctrl-C, or a closed pipe, while the second small run computes
        return real(name, workers)

    monkeypatch.setattr(small_runs, "small_digest", stopped_at_the_second)
    with pytest.raises(KeyboardInterrupt):
        small_runs.adopt([NAME, "gridworld"])
    assert small_runs.status(NAME)[0] == "current"
    assert small_runs.committed_code()[NAME] == small_runs.stored_record(NAME)["code"]


def test_writing_the_digests_keeps_a_result_of_an_unchanged_digest_re_recordable(edited):
    # --write after recomputing another experiment: this one's digest is the same, so the code its
    # result was made with still gives it, and --adopt can still re-record the result
    small_runs.write(small_runs.committed())
    assert small_runs.status(NAME)[0] == "re-record"
    small_runs.write({**small_runs.committed(), NAME: "other bits"})
    assert small_runs.committed_code()[NAME]["lineworld.py"] == "edited"
    assert small_runs.status(NAME)[0] == "recompute"


def test_status_lists_every_committed_result(capsys):
    assert small_runs.main(["--status"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines == [f"{name}: current" for name in small_runs.sizes()]


def test_an_unknown_experiment_is_one_line(capsys):
    from glamas.errors import UserError
    with pytest.raises(UserError, match="no stored experiment named nonexistent"):
        small_runs.main(["--adopt", "nonexistent"])


def test_a_result_records_only_the_code_its_experiment_runs():
    line_world = small_runs.current_code("state_encoding")
    assert "lineworld.py" in line_world
    assert not [module for module in line_world if module.startswith("gridworld/")]  # Fig. 5 never runs it
    independent = provenance.code_record(gw.GridworldConfig(learners=("independent",)))
    assert "learners/independent.py" in independent and "gridworld/rules.py" in independent
    assert "learners/two_observe.py" not in independent  # a learner it does not train


@pytest.mark.long
def test_a_real_edit_of_the_rules_is_re_recorded_when_it_keeps_the_behaviour_and_not_when_it_changes_it(tmp_path):
    """In a copy of the code, maps, results and figure scripts: renaming a parameter of
    rules.collision_reward leaves Fig. 10's readings stale by their record; one command re-records them
    and their figure is drawn. Then a chapter reward's default changed (the collision's, -10 to -11):
    the same command leaves them stale, and the figure script refuses them."""
    for part in ("lib", "data", "paper_figures"):
        shutil.copytree(REPO / part, tmp_path / part, ignore=shutil.ignore_patterns("__pycache__", "output"))
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "lib"), "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "MPLBACKEND": "Agg"}

    def glamas(*args):
        return subprocess.run([sys.executable, "-m", *args], cwd=tmp_path, env=env, capture_output=True, text=True)

    def edit(module, old, new):
        path = tmp_path / "lib" / "glamas" / module
        assert old in path.read_text(), f"{module} no longer holds {old!r}: update this test"
        path.write_text(path.read_text().replace(old, new, 1))

    edit("gridworld/rules.py", "def collision_reward(payoffs, hit):\n", "def collision_reward(payoffs, collided):\n")
    edit("gridworld/rules.py", "return payoffs.collision if hit else", "return payoffs.collision if collided else")
    adopted = glamas("glamas.small_runs", "--adopt", "fig10_readings")
    assert adopted.returncode == 0 and "fig10_readings: re-recorded" in adopted.stdout
    drawn = glamas("glamas.reproduce", "--experiment", "fig10_readings", "--out", str(tmp_path / "figures"))
    assert drawn.returncode == 0, drawn.stderr
    assert list((tmp_path / "figures").glob("fig10_readings*.png"))

    edit("gridworld/rewards.py", "collision: float = -10.0", "collision: float = -11.0")
    kept = glamas("glamas.small_runs", "--adopt", "fig10_readings")
    assert kept.returncode == 1 and "fig10_readings: stale, its small run gives other bits" in kept.stdout
    assert "glamas/gridworld/rewards.py" in kept.stdout
    refused = glamas("glamas.reproduce", "--experiment", "fig10_readings", "--out", str(tmp_path / "figures"))
    assert refused.returncode == 2 and "stale" in refused.stderr + refused.stdout


def test_no_learner_imports_the_layer_that_runs_it():
    """The learners sit at the bottom: a learner's module (and what it imports) reaches neither the
    parallel layer nor the batches built above the learners (glamas.training)."""
    learners = [path for path in sorted((sources.PACKAGE / "learners").glob("*.py")) if path.name != "contract.py"]
    for path in learners:
        reached = [found.relative_to(sources.PACKAGE).as_posix() for found in sources.import_closure([path])]
        assert not [name for name in reached if name.startswith(provenance.RUNNING) or name == "training.py"], path.name


def test_an_edit_of_a_dask_message_or_a_plot_label_stales_nothing(monkeypatch):
    real = sources.code_digest
    edited = {sources.PACKAGE / "parallel" / "dask.py", sources.PACKAGE / "experiments" / "gridworld" / "plots.py",
              sources.PACKAGE / "plotting.py", sources.PACKAGE / "cli.py", sources.PACKAGE / "sources.py"}
    monkeypatch.setattr(sources, "code_digest", lambda path: "edited" if Path(path) in edited else real(path))
    assert {name: small_runs.status(name)[0] for name in small_runs.sizes()} == dict.fromkeys(small_runs.sizes(), "current")
