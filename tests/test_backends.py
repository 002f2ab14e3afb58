"""Run backends: local processes (joblib, the default), threads and a Dask cluster give
bit-identical results."""

import dataclasses
import functools
import sys

import numpy as np
import pytest
from numba import njit

from glamas import cli, parallel, reproduce, rng, seeds
from glamas.experiments import benchmark_maps, gridworld, single_gla
from glamas.learners import and_network as and_network_learner
from glamas.learners import registry, two_observe
from glamas.learners import single_gla as single_gla_learner
from glamas.qlearning import QSettings

SINGLE = single_gla.SingleGLAConfig(iterations=600, runs=7, record_points=6)
GRID = gridworld.GridworldConfig(episodes=40, runs=3, bins=10, q=QSettings(q_initial=0.5), max_steps=200)


def _arrays(result) -> dict:
    return {f.name: getattr(result, f.name) for f in dataclasses.fields(result)
            if isinstance(getattr(result, f.name), np.ndarray)}


def _assert_identical(a, b):
    a, b = _arrays(a), _arrays(b)
    assert a.keys() == b.keys() and a
    for name in a:
        assert a[name].dtype == b[name].dtype, name
        assert np.array_equal(a[name], b[name], equal_nan=a[name].dtype.kind == "f"), name


@pytest.fixture(scope="module")
def dask_scheduler():
    """An in-process Dask cluster: one worker with two threads, so two jobs run at once."""
    import distributed
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        yield cluster.scheduler_address


SINGLE_SEED = seeds.named(11, "single_gla")
"""The master seed of experiment 1's runs for its seed 11 (glamas.experiments.single_gla.run)."""


@pytest.fixture(scope="module")
def reference():
    """Both experiments on one thread in this process (experiment 1 on master seed 11, whose runs
    draw from SINGLE_SEED)."""
    return {"single": single_gla.run(SINGLE, seed=11, workers=parallel.Threads(1)),
            "grid": gridworld.run(GRID, seed=2, workers=parallel.Threads(1))}


def test_chunk_states_are_the_slices_of_the_whole_spawn():
    whole = rng.run_states(9, 12)
    assert np.array_equal(rng.chunk_states(9, 0, 12), whole)
    assert np.array_equal(rng.chunk_states(9, 5, 8), whole[5:8])
    assert np.array_equal(rng.chunk_states(9, 11, 12), rng.run_states(9, 40)[11:12])
    with pytest.raises(ValueError, match="0 <= start < stop"):
        rng.chunk_states(9, 4, 4)
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        rng.chunk_states(-1, 0, 2)


@pytest.mark.parametrize("workers", [None, 2, parallel.Processes(2), parallel.Processes(1), parallel.Threads(2)],
                         ids=["default", "int-2", "Processes(2)", "Processes(1)", "Threads(2)"])
def test_local_backends_give_the_one_thread_results_bit_for_bit(reference, workers):
    _assert_identical(single_gla.run(SINGLE, seed=11, workers=workers), reference["single"])
    _assert_identical(gridworld.run(GRID, seed=2, workers=workers), reference["grid"])


def test_a_dask_cluster_gives_the_one_thread_results_bit_for_bit(reference, dask_scheduler):
    backend = parallel.Dask(dask_scheduler)
    _assert_identical(single_gla.run(SINGLE, seed=11, workers=backend), reference["single"])
    _assert_identical(gridworld.run(GRID, seed=2, workers=backend), reference["grid"])


def test_the_benchmark_sweep_on_a_two_worker_dask_cluster_is_the_local_one_bit_for_bit():
    """The field's benchmark (two of its maps, learners of both kinds) on a cluster of two Dask
    workers gives the results of one local thread."""
    import distributed
    config = benchmark_maps.BenchmarkConfig(maps=("isr", "tunnel_to_goal_3"), learners=("independent", "two_observe", "cq"),
                                            runs=2, episodes=60, bins=6, evaluation_episodes=4)
    local = benchmark_maps.run(config, seed=5, workers=parallel.Threads(1))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster:
        _assert_identical(benchmark_maps.run(config, seed=5, workers=parallel.Dask(cluster.scheduler_address)), local)


def no_checkpoints(n_runs):
    """The single-GLA kernel's checkpoint output for runs that record none."""
    return np.zeros((n_runs, 0, 2, 2, 3))


def test_job_size_does_not_change_results(reference):
    params = np.zeros_like(reference["single"].params)
    reward = np.zeros_like(reference["single"].reward)
    parallel.run_batches(single_gla_learner.learn, single_gla_learner.kernel_inputs(SINGLE), (params, reward, no_checkpoints(7)),
                         SINGLE_SEED, workers=parallel.Processes(2), chunk=3)
    assert np.array_equal(reward, reference["single"].reward)
    assert np.array_equal(params, reference["single"].params)


def test_a_job_runs_any_slice_of_the_sweep_on_its_own(reference):
    inputs = single_gla_learner.kernel_inputs(SINGLE)
    initial = (np.zeros((2,) + reference["single"].params.shape[1:]), np.zeros((2, SINGLE.record_points)),
               no_checkpoints(2))
    start, (params, reward, _) = parallel.run_chunk("glamas.learners.single_gla:learn", inputs, SINGLE_SEED, 4, 6, initial)
    assert start == 4
    assert np.array_equal(reward, reference["single"].reward[4:6])
    assert np.array_equal(params, reference["single"].params[4:6])
    assert not initial[1].any()  # the job fills copies, not the arrays it was given


RUN_KERNELS = ([single_gla_learner.learn, and_network_learner.learn, two_observe.run_two]
               + [learner.kernel for learner in registry.LEARNERS.values()])


@pytest.mark.parametrize("kernel", RUN_KERNELS, ids=lambda k: f"{k.py_func.__module__}.{k.__name__}")
def test_run_kernels_release_the_gil_so_threads_run_them_at_once(kernel):
    assert kernel.targetoptions.get("nogil") is True


def test_jobs_are_about_four_per_local_worker():
    assert parallel.chunk_size(100, parallel.Processes(2)) == 13 and parallel.chunk_size(100, parallel.Threads(1)) == 25
    assert parallel.chunk_size(3, parallel.Processes(2)) == 1 and parallel.chunk_size(100, parallel.Dask("tcp://h:1")) == 8


def test_a_kernel_that_workers_cannot_import_runs_on_threads_with_one_line(capsys):
    @njit(nogil=True)
    def local_kernel(out, state):
        out[0] = rng.uniform(state)

    threads = np.zeros((3, 1))
    parallel.run_batches(local_kernel, (), (threads,), 0, workers=parallel.Threads())  # threads need no import
    assert threads.all() and capsys.readouterr().err == ""
    for workers in (parallel.Processes(1), parallel.Processes(2)):
        out = np.zeros((3, 1))
        parallel.run_batches(local_kernel, (), (out,), 0, workers=workers)
        assert np.array_equal(out, threads)
        note = capsys.readouterr().err
        assert note.count("\n") == 1 and "local_kernel cannot be imported by worker processes" in note
    with pytest.raises(ValueError, match="local_kernel is not a module-level function of an importable module"):
        parallel.job.kernel_name(local_kernel)  # what the Dask backend refuses, in one line


@pytest.mark.parametrize("call, message", [
    (lambda: parallel.backend("gpu"), "backend must be one of threads, processes, dask, got 'gpu'"),
    (lambda: parallel.backend("dask"), "the dask backend needs the scheduler's address: --scheduler ADDRESS"),
    (lambda: parallel.backend("processes", scheduler="tcp://h:8786"), "--scheduler means the dask backend, not 'processes'"),
    (lambda: parallel.backend(None, workers=2, scheduler="tcp://h:8786"), "--workers does not apply to the dask backend"),
    (lambda: parallel.Processes(0), r"Processes\(workers=...\) must be a whole number >= 1"),
    (lambda: parallel.Dask(""), r"Dask\(scheduler=...\) must be the scheduler's address"),
    (lambda: parallel.Dask("tcp://h:8786", timeout=0), r"Dask\(timeout=...\) must be a positive number"),
    (lambda: single_gla.run(SINGLE, workers="dask"), "workers must be a process count, None .* or a backend"),
    (lambda: single_gla.run(SINGLE, workers=True), "workers must be a process count, None .* or a backend"),
    (lambda: parallel.run_batches(single_gla_learner.learn, (), (np.zeros((2, 1)),), 0, chunk=0),
     "chunk must be a whole number of runs >= 1 or None, got 0"),
    (lambda: parallel.run_batches(single_gla_learner.learn, (), (np.zeros((2, 1)), np.zeros(2)), 0),
     r"every output needs an axis of runs and an array per run \(ndim >= 2\), got shapes \[\(2, 1\), \(2,\)\]"),
])
def test_bad_backend_choices_are_rejected(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_backend_choices_map_to_backends():
    assert parallel.backend() == parallel.Processes() and parallel.backend("threads", workers=2) == parallel.Threads(2)
    assert parallel.backend("processes", workers=2) == parallel.Processes(2)
    assert parallel.backend(None, scheduler="tcp://h:8786") == parallel.Dask("tcp://h:8786")


def test_dask_without_the_extra_names_the_extra_and_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # makes `import distributed` fail
    with pytest.raises(parallel.BackendError, match=r"optional extra 'dask'.*pip install -e '\.\[dask\]'"):
        parallel.backend("dask", scheduler="tcp://h:8786")
    with pytest.raises(parallel.BackendError, match="optional extra 'dask'"):
        single_gla.run(SINGLE, workers=parallel.Dask("tcp://h:8786"))


def test_an_unreachable_scheduler_is_named():
    with pytest.raises(parallel.BackendError, match=r"cannot reach the Dask scheduler at tcp://127\.0\.0\.1:9 within 0\.5 s"):
        single_gla.run(SINGLE, workers=parallel.Dask("tcp://127.0.0.1:9", timeout=0.5))


def _parse(argv):
    return cli.parse(cli.figure_parser("test", runs=5, iterations=100), argv)


def test_command_line_backends(dask_scheduler):
    assert _parse([]).workers == parallel.Processes() and _parse(["--workers", "2"]).workers == parallel.Processes(2)
    assert _parse(["--backend", "threads", "--workers", "2"]).workers == parallel.Threads(2)
    assert _parse(["--backend", "processes", "--workers", "2"]).workers == parallel.Processes(2)
    assert _parse(["--scheduler", dask_scheduler]).workers == parallel.Dask(dask_scheduler)
    assert _parse(["--backend", "dask", "--scheduler", dask_scheduler]).workers == parallel.Dask(dask_scheduler)


@pytest.mark.parametrize("argv, message", [
    (["--backend", "gpu"], "argument --backend: invalid choice: 'gpu'"),
    (["--backend", "dask"], "the dask backend needs the scheduler's address"),
    (["--backend", "threads", "--scheduler", "tcp://h:8786"], "--scheduler means the dask backend, not 'threads'"),
    (["--scheduler", "tcp://h:8786", "--workers", "2"], "--workers does not apply to the dask backend"),
])
def test_bad_command_line_backends_are_rejected(argv, message, capsys):
    with pytest.raises(SystemExit):
        _parse(argv)
    assert message in capsys.readouterr().err


def test_command_line_without_the_dask_extra(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(SystemExit):
        _parse(["--scheduler", "tcp://h:8786"])
    assert "optional extra 'dask'" in capsys.readouterr().err


def test_command_line_with_an_unreachable_scheduler_names_its_address(monkeypatch, capsys):
    monkeypatch.setattr(parallel, "backend", functools.partial(parallel.backend, timeout=0.5))  # a short wait
    with pytest.raises(SystemExit):
        _parse(["--scheduler", "tcp://127.0.0.1:9"])
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9 within 0.5 s" in capsys.readouterr().err


def test_an_output_slice_of_one_value_travels_as_its_value_and_comes_back_equal():
    filled, varied, nan = np.full((2, 3), 5.0), np.arange(6.0).reshape(2, 3), np.full(3, np.nan)
    sent = parallel.job.Filled.of(filled)
    assert isinstance(sent, parallel.job.Filled) and parallel.job._array_of(sent, copy=False).dtype == filled.dtype
    assert np.array_equal(parallel.job._array_of(sent, copy=False), filled)
    assert parallel.job.Filled.of(varied) is varied and parallel.job.Filled.of(nan) is nan  # sent as they are


@pytest.mark.parametrize("workers", [parallel.Processes(1), parallel.Processes(2), parallel.Threads(2)], ids=repr)
def test_a_scratch_output_is_filled_by_the_runs_and_not_kept(reference, workers):
    """A Scratch output changes nothing of the kept outputs, and nothing of it comes back."""
    reward = np.zeros_like(reference["single"].reward)
    params = parallel.Scratch(reference["single"].params.shape, np.dtype(float), 0.0)
    parallel.run_batches(single_gla_learner.learn, single_gla_learner.kernel_inputs(SINGLE), (params, reward, no_checkpoints(7)),
                         SINGLE_SEED, workers=workers, chunk=3)
    assert np.array_equal(reward, reference["single"].reward)
    _, (dropped, kept, _) = parallel.run_chunk("glamas.learners.single_gla:learn", single_gla_learner.kernel_inputs(SINGLE),
                                               SINGLE_SEED, 4, 6, (params.runs(4, 6), np.zeros((2, SINGLE.record_points)),
                                                          no_checkpoints(2)))
    assert dropped is None and np.array_equal(kept, reference["single"].reward[4:6])


def test_a_second_worker_takes_another_kernel_while_the_first_compiles_one():
    """parallel.local._next_job: a job of a kernel whose first job still runs (maybe compiling it) waits
    while another kernel has a job; in order otherwise."""
    a1, a2, b1 = (0, "m:a", 1), (0, "m:a", 2), (1, "m:b", 1)
    assert parallel.local._next_job([a2, b1], [a1], set()) == 1
    assert parallel.local._next_job([a2, b1], [a1], {"m:a"}) == 0
    assert parallel.local._next_job([a2], [a1], set()) == 0


def test_a_batch_run_before_takes_its_outputs_instead_of_running_again(monkeypatch):
    monkeypatch.setattr(parallel.memo, "_kept", type(parallel.memo._kept)())
    monkeypatch.setattr(parallel.memo, "MEMO_BYTES", parallel.memo.MEMO_BYTES)
    parallel.reuse_batches(reproduce.REUSED_BYTES)
    first = gridworld.run(GRID, workers=1)

    def no_run(*args):
        raise AssertionError("ran a batch it had run before")

    monkeypatch.setattr(parallel.local, "run_in_processes", no_run)
    _assert_identical(first, gridworld.run(GRID, workers=2))
    with pytest.raises(AssertionError, match="ran a batch"):  # another seed: other runs
        gridworld.run(GRID, seed=1, workers=2)
    with pytest.raises(AssertionError, match="ran a batch"):  # another setting
        gridworld.run(dataclasses.replace(GRID, q=QSettings(q_initial=0.25)), workers=2)
    with pytest.raises(ValueError, match="max_bytes must be a whole number >= 0, got -1"):
        parallel.reuse_batches(-1)
