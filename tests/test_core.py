"""Seeding, parallel runs, result files, figure CLI, byte-reproducible figures, and the experiments'
packages: their faces, and no matplotlib where nothing is drawn."""

import dataclasses
import importlib
import inspect
import json
import os
import pkgutil
import subprocess
import sys

import numpy as np
import pytest
from numba import njit

import glamas.experiments
from glamas import cli, curves, errors, figures, parallel, plotting, provenance, results, rng
from glamas.experiments import registry

EXPERIMENT_PACKAGES = sorted(module.name for module in pkgutil.iter_modules(glamas.experiments.__path__)
                             if module.ispkg)
"""The experiments' packages (each with its experiment, analysis and plots modules), found without importing them."""


@njit(cache=True, nogil=True)
def _draws_run(n_draws, out, state):
    for t in range(n_draws):
        out[t] = rng.uniform(state)


def _draws(seed, n_runs, workers, chunk=None):
    out = np.zeros((n_runs, 50))
    parallel.run_batches(_draws_run, (50,), (out,), seed, workers=workers, chunk=chunk)
    return out


def test_same_seed_same_results_for_one_and_two_workers_and_any_chunking():
    one = _draws(7, 10, workers=1)
    assert np.array_equal(one, _draws(7, 10, workers=2))
    assert np.array_equal(one, _draws(7, 10, workers=2, chunk=3))
    assert np.array_equal(one, _draws(7, 10, workers=parallel.Threads(2), chunk=1))
    assert not np.array_equal(one, _draws(8, 10, workers=1))
    assert not np.array_equal(one[0], one[1])  # runs get different streams


def test_generator_output_is_uniform_and_integers_in_range():
    state = rng.run_states(0, 1)[0]
    draws = np.array([rng.uniform(state) for _ in range(20000)])
    assert 0.0 <= draws.min() and draws.max() < 1.0
    assert abs(draws.mean() - 0.5) < 0.01
    counts = np.bincount([rng.integer(state, 4) for _ in range(20000)], minlength=4)
    assert counts.min() > 4500 and len(counts) == 4
    probs = np.array([0.2, 0.0, 0.8])
    picks = np.bincount([rng.categorical(state, probs) for _ in range(20000)], minlength=3)
    assert picks[1] == 0 and abs(picks[0] / 20000 - 0.2) < 0.015


@pytest.mark.parametrize("seed, n_runs, message", [(-1, 3, "seed must be a non-negative"),
                                                   (1.5, 3, "seed must be a non-negative"),
                                                   (0, 0, "n_runs must be a positive")])
def test_bad_seeds_and_run_counts_are_rejected(seed, n_runs, message):
    with pytest.raises(ValueError, match=message):
        rng.run_states(seed, n_runs)


def test_bad_worker_counts_are_rejected():
    with pytest.raises(ValueError, match=r"Threads\(workers=...\) must be a whole number >= 1"):
        parallel.Threads(0)
    with pytest.raises(ValueError, match=r"Processes\(workers=...\) must be a whole number >= 1"):
        parallel.Processes(2.0)


@dataclasses.dataclass(frozen=True)
class _Config:
    runs: int = 3
    rate: float = 0.5

    def memory_bytes(self) -> int:
        return 8 * self.runs


def test_result_files_round_trip_and_refuse_other_configurations(tmp_path):
    path = tmp_path / "r.npz"
    results.save(path, _Config(), {"curve": np.arange(4.0)}, seed=1)
    assert np.array_equal(results.load(path, _Config(), seed=1)["curve"], np.arange(4.0))
    with pytest.raises(results.ResultFileError, match="stale.*runs: file 3, now 4"):
        results.load(path, _Config(runs=4), seed=1)
    with pytest.raises(results.ResultFileError, match="stale.*seed: file 1, now 2"):
        results.load(path, _Config(), seed=2)
    with pytest.raises(results.ResultFileError, match="different configuration.*not overwritten"):
        results.save(path, _Config(runs=4), {"curve": np.zeros(2)}, seed=1)
    assert np.array_equal(results.load(path, _Config(), seed=1)["curve"], np.arange(4.0))
    results.save(path, _Config(runs=4), {"curve": np.zeros(2)}, seed=1, overwrite=True)
    assert results.load(path, _Config(runs=4), seed=1)["curve"].tolist() == [0.0, 0.0]
    assert [p.name for p in tmp_path.iterdir()] == ["r.npz"]  # no temporary file left behind
    umask = os.umask(0)
    os.umask(umask)
    assert path.stat().st_mode & 0o777 == 0o666 & ~umask  # as any new file, not mkstemp's 0600


def test_missing_and_corrupted_result_files_give_clear_errors(tmp_path):
    with pytest.raises(results.ResultFileError, match="no result file at .*run the experiment"):
        results.load(tmp_path / "absent.npz", _Config())
    broken = tmp_path / "broken.npz"
    broken.write_bytes(b"not a zip archive")
    with pytest.raises(results.ResultFileError, match="not a readable glamas result file.*delete it"):
        results.load(broken, _Config())
    with pytest.raises(results.ResultFileError, match="not overwritten"):
        results.save(broken, _Config(), {"x": np.zeros(1)})
    assert broken.read_bytes() == b"not a zip archive"


def test_result_files_holding_objects_are_not_unpickled(tmp_path):
    path = tmp_path / "pickled.npz"
    np.savez(path, __config__=np.array(results.config_json(_Config())),
             __provenance__=np.array(json.dumps(provenance.record(_Config()))), evil=np.array([{}], dtype=object))
    with pytest.raises(results.ResultFileError, match="not a readable glamas result file.*allow_pickle"):
        results.load(path, _Config())


def _parse(argv):
    return cli.parse(cli.figure_parser("test", runs=5, iterations=100), argv)


@pytest.mark.parametrize("argv, message", [
    (["--runs", "0"], "--runs: must be at least 1, got 0"),
    (["--iterations", "ten"], "--iterations: expected a whole number, got 'ten'"),
    (["--seed", "-3"], "--seed: must be 0 or more, got -3"),
    (["--workers", "x"], "--workers: expected a whole number"),
    (["--bogus"], "unrecognized arguments: --bogus"),
])
def test_bad_command_line_arguments_are_rejected(argv, message, capsys):
    with pytest.raises(SystemExit):
        _parse(argv)
    assert message in capsys.readouterr().err


def test_out_must_be_a_directory(tmp_path, capsys):
    afile = tmp_path / "file.png"
    afile.write_text("")
    with pytest.raises(SystemExit):
        _parse(["--out", str(afile)])
    assert "is not a directory" in capsys.readouterr().err


@dataclasses.dataclass(frozen=True)
class _Result:
    curve: np.ndarray


def _experiment(run) -> registry.Experiment:
    return registry.Experiment("exp", _Config, run, lambda runs, iterations: _Config(runs=runs), 5, 100, _Result)


def test_load_or_run_reuses_a_result_of_the_same_configuration(tmp_path):
    calls = []

    def run(config, seed, workers, progress):
        calls.append(seed)
        return _Result(curve=np.full(3, float(seed)))

    experiment = _experiment(run)
    args = _parse(["--results", str(tmp_path), "--seed", "4"])
    first = figures.load_or_run(args, experiment, _Config())
    again = figures.load_or_run(args, experiment, _Config())
    assert calls == [4] and np.array_equal(first.curve, again.curve)
    figures.load_or_run(_parse(["--results", str(tmp_path), "--seed", "4", "--rerun"]), experiment, _Config())
    assert calls == [4, 4]
    for flags in ([], ["--rerun"]):
        with pytest.raises(results.ResultFileError, match="different configuration.*not overwritten"):
            figures.load_or_run(_parse(["--results", str(tmp_path), "--seed", "5"] + flags), experiment, _Config())
    assert calls == [4, 4]  # refused before running
    replaced = figures.load_or_run(_parse(["--results", str(tmp_path), "--seed", "5", "--force"]), experiment, _Config())
    assert calls == [4, 4, 5] and replaced.curve[0] == 5.0


def test_a_figure_is_drawn_from_its_experiment_at_the_command_line_scale(tmp_path, capsys):
    seen = []
    experiment = _experiment(lambda config, seed, workers, progress: _Result(curve=np.full(3, float(config.runs))))
    argv = ["--runs", "2", "--out", str(tmp_path), "--results", str(tmp_path)]
    with figures.figure(experiment, "f", "A figure.\n\nMore about it.", argv) as (ax, result, config):
        seen.append((config, result.curve.tolist()))
        ax.plot(result.curve)
    assert seen == [(_Config(runs=2), [2.0, 2.0, 2.0])]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["exp.npz", "f.pdf", "f.png"]
    assert capsys.readouterr().out.split() == [str(tmp_path / "f.png"), str(tmp_path / "f.pdf")]


def test_a_figure_needs_the_runs_it_shows(tmp_path, capsys):
    experiment = _experiment(lambda config, seed, workers, progress: _Result(curve=np.zeros(3)))
    with pytest.raises(SystemExit):
        with figures.figure(experiment, "f", "A figure.", ["--runs", "1", "--out", str(tmp_path)], min_runs=2):
            pass
    assert "--runs must be at least 2" in capsys.readouterr().err


def test_a_figure_that_runs_no_experiment_uses_only_out(tmp_path, capsys):
    afile = tmp_path / "file"
    afile.write_text("")
    argv = ["--runs", "7", "--seed", "3", "--results", str(afile), "--scheduler", "tcp:/bad", "--out", str(tmp_path)]
    with figures.fixed_figure("f", "A map.", argv) as ax:
        ax.plot([0, 1])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.pdf", "f.png", "file"]
    parser = cli.figure_parser("A map.")
    help_text = " ".join(parser.format_help().split())
    assert "It runs no experiment: only --out changes what it writes." in help_text
    unused = [action for action in parser._actions if action.dest not in ("out", "help")]
    assert len(unused) >= 12 and help_text.count(cli.NO_EXPERIMENT) == len(unused)  # every option but --out


def test_a_drawing_error_saves_no_figure_and_is_one_line(tmp_path, capsys):
    with pytest.raises(SystemExit) as stopped:
        with figures.fixed_figure("f", "A map.", ["--out", str(tmp_path)]):
            raise errors.UserError("no such\nmap")
    assert stopped.value.code == 2 and capsys.readouterr().err == "error: no such map\n"
    assert list(tmp_path.iterdir()) == []


def test_figures_are_byte_reproducible(tmp_path):
    def draw(directory):
        fig, ax = plotting.new_figure()
        plotting.plot_mean_band(ax, np.arange(5), np.arange(15.0).reshape(3, 5) ** 0.5, "curve")
        ax.legend()
        return plotting.save_figure(fig, directory, "figure")

    first, second = draw(tmp_path / "a"), draw(tmp_path / "b")
    for a, b in zip(first, second):
        assert a.read_bytes() == b.read_bytes(), a.name


def test_mean_and_band_stays_within_the_runs():
    counts = np.array([[0.0, 1.0], [0.0, 1.0], [9.0, 1.0]])  # a count with one outlying run
    mean, low, high = curves.mean_and_band(counts)
    assert mean.tolist() == [3.0, 1.0]
    assert 0.0 <= low[0] < mean[0] < high[0] <= 9.0 and low[1] == high[1] == 1.0


def test_running_and_measuring_the_experiments_imports_no_matplotlib():
    """Each experiment's face, experiment and analysis modules, the registry and the ledger import no
    matplotlib, nor does finding every experiment (checked in a fresh interpreter): it comes with
    the first drawing function asked for."""
    modules = ["glamas.experiments.registry", "glamas.ledger"] + [
        f"glamas.experiments.{name}.{job}" for name in EXPERIMENT_PACKAGES for job in ("experiment", "analysis")]
    code = (f"import importlib, sys\nfor name in {modules!r}: importlib.import_module(name)\n"
            "importlib.import_module('glamas.experiments.registry').experiments()\n"
            "print(sorted(name for name in sys.modules if name.split('.')[0] == 'matplotlib'))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-500:]
    assert done.stdout.strip() == "[]"


@pytest.mark.parametrize("name", EXPERIMENT_PACKAGES)
def test_a_face_hands_on_every_name_of_its_experiment_analysis_and_plots(name):
    face = importlib.import_module(f"glamas.experiments.{name}")
    for job in ("experiment", "analysis", "plots"):
        module = importlib.import_module(f"glamas.experiments.{name}.{job}")
        own = {attribute for attribute, value in vars(module).items() if not attribute.startswith("_")
               and (inspect.isfunction(value) or inspect.isclass(value)) and value.__module__ == module.__name__}
        assert own <= set(dir(face)), job
        assert [attribute for attribute in own if getattr(face, attribute) is not getattr(module, attribute)] == [], job
    with pytest.raises(AttributeError, match="no attribute 'plot_nothing'"):
        face.plot_nothing


def test_every_experiment_package_registers_its_experiments_with_no_list_naming_it():
    registering = {experiment.run.__module__.split(".")[2] for experiment in registry.experiments()}
    assert registering == set(EXPERIMENT_PACKAGES)
