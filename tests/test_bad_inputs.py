"""Catalogue of bad inputs and faults: each gets one clear message, nothing committed is changed,
nothing hangs and nothing stale is served.

Command-line cases run the figure scripts as subprocesses with tiny settings and threads, and
check exit status 2, one ``error:`` line and no traceback; library cases check the exception's
message. Every command must fail within 60 s.
"""

import concurrent.futures
import contextlib
import dataclasses
import hashlib
import http.server
import json
import math
import os
import re
import shutil
import socket
import struct
import subprocess
import sys
import threading
import time
import zipfile

import matplotlib.pyplot as plt
import numpy as np
import pytest

import glamas
from glamas import cli, errors, figures, memory, parallel, plotting, provenance, results, sources
from glamas.experiments import and_network, gridworld, gridworld_optimum, registry, scaling, single_gla
from glamas.gridworld import MapError, load_map
from glamas.learners import two_observe
from glamas.paths import MAPS, REPO, RESULTS

COMMITTED = (REPO / "paper_figures" / "output", RESULTS)
FAST = ["--backend", "threads", "--workers", "1"]
SMALL_LINE = single_gla.SingleGLAConfig(runs=2, iterations=200, record_points=10)
TIME_LIMIT = 60


def _hashes() -> dict:
    return {path: hashlib.sha256(path.read_bytes()).hexdigest()
            for directory in COMMITTED for path in sorted(directory.iterdir())}


@pytest.fixture(scope="module", autouse=True)
def committed_outputs_unchanged():
    """Whatever the catalogue does, the committed figures and results stay byte for byte."""
    before = _hashes()
    yield
    assert _hashes() == before


def _script(name: str, *args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(REPO / "paper_figures" / f"{name}.py"), *map(str, args)],
                          capture_output=True, text=True, timeout=TIME_LIMIT)


def _assert_user_error(done: subprocess.CompletedProcess, message: str) -> None:
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr, done.stderr
    errors = [line for line in done.stderr.splitlines() if "error: " in line]
    assert len(errors) == 1 and message in errors[0], done.stderr


def _other_result(directory, name: str) -> bytes:
    """A result file ``name`` of another configuration in ``directory``; returns its bytes."""
    path = results.save(directory / f"{name}.npz", SMALL_LINE, {"x": np.zeros(2)}, seed=99)
    return path.read_bytes()


# --- outputs: nothing committed is replaced, nothing is written half ---------------------------

def test_reduced_run_with_default_paths_leaves_the_committed_outputs_alone():
    key = "runs=2,iterations=200"
    created = [cli.SCRATCH_OUT / key / "fig6.png", cli.SCRATCH_OUT / key / "fig6.pdf",
               cli.SCRATCH_RESULTS / key / "state_encoding.npz"]
    existed = {path: path.exists() for path in created}
    committed = _hashes()
    try:
        done = _script("fig6", "--runs", 2, "--iterations", 200, "--force", *FAST)  # --force: whatever out/ held
        assert done.returncode == 0, done.stderr
        assert "writing to out/" in done.stderr
        assert all(path.is_file() for path in created)
        assert _hashes() == committed
    finally:
        for path in created:
            if not existed[path]:
                path.unlink(missing_ok=True)


def test_runs_of_two_maps_at_one_small_scale_keep_a_result_each():
    """A reduced run's default directories are those of its settings, so a second map at the same
    scale neither collides with the first nor replaces it."""
    keys = [f"runs=1,iterations=120,map={name}" for name in ("isr", "cit")]
    made = [directory / key for key in keys for directory in (cli.SCRATCH_OUT, cli.SCRATCH_RESULTS)]
    existed = {path: path.exists() for path in made}
    try:
        for name in ("isr", "cit"):
            done = _script("fig11a", "--runs", 1, "--iterations", 120, "--map", name, *FAST)
            assert done.returncode == 0, done.stderr
        first = (cli.SCRATCH_RESULTS / keys[0] / "gridworld.npz").read_bytes()
        assert (cli.SCRATCH_RESULTS / keys[1] / "gridworld.npz").read_bytes() != first
        assert all((cli.SCRATCH_OUT / key / "fig11a.png").is_file() for key in keys)
    finally:
        for path in made:
            if not existed[path]:
                shutil.rmtree(path, ignore_errors=True)


@pytest.mark.parametrize("force", [(), ("--force",)])
def test_a_reduced_run_into_the_committed_results_is_refused_without_advising_force(force):
    committed = _hashes()
    done = _script("fig5", "--runs", 2, "--iterations", 200, "--results", "data/results", *force, *FAST)
    _assert_user_error(done, "--results data/results is the directory of the committed results, which only a run "
                             "at the paper-scale settings writes; this run's results go to out/results/runs=2,"
                             "iterations=200 (leave out --results)")
    assert "--force" not in done.stderr.splitlines()[-1] and _hashes() == committed


def test_unwritable_out_is_refused_before_computing(tmp_path):
    afile = tmp_path / "file"
    afile.write_text("")
    started = time.monotonic()
    _assert_user_error(_script("fig6", "--out", afile / "sub", *FAST), f"--out {afile / 'sub'} is not a writable directory")
    assert time.monotonic() - started < 20


@pytest.mark.skipif(os.geteuid() == 0, reason="permissions do not stop root")
def test_read_only_results_directory_is_refused_before_computing(tmp_path):
    read_only = tmp_path / "read_only"
    read_only.mkdir(mode=0o555)
    _assert_user_error(_script("fig6", "--results", read_only, *FAST), f"--results {read_only} is not a writable directory")


def test_results_that_is_a_file_is_refused(tmp_path):
    afile = tmp_path / "file"
    afile.write_text("")
    _assert_user_error(_script("fig6", "--results", afile, *FAST), "exists and is not a directory")


def test_result_of_another_configuration_is_refused_before_computing(tmp_path):
    stored = _other_result(tmp_path, "and_network")
    done = _script("fig7b", "--runs", 2, "--iterations", 100, "--out", tmp_path, "--results", tmp_path, *FAST)
    _assert_user_error(done, "holds results of a different configuration")
    assert (tmp_path / "and_network.npz").read_bytes() == stored and not (tmp_path / "fig7b.png").exists()


def test_damaged_result_file_is_refused_with_its_reason(tmp_path):
    (tmp_path / "and_network.npz").write_bytes(b"PK\x03\x04 damaged")
    done = _script("fig7b", "--runs", 2, "--iterations", 100, "--out", tmp_path, "--results", tmp_path, *FAST)
    _assert_user_error(done, "is not a readable glamas result file")


def test_fig9_out_that_is_a_file_is_refused(tmp_path):
    afile = tmp_path / "file"
    afile.write_text("")
    _assert_user_error(_script("fig9", "--out", afile), "exists and is not a directory")


def test_a_figure_save_that_fails_midway_keeps_the_previous_file(tmp_path, monkeypatch):
    fig, ax = plotting.new_figure()
    ax.plot([0, 1])
    plotting.save_figure(fig, tmp_path, "f")
    before = (tmp_path / "f.png").read_bytes()

    def dies(handle, **kwargs):
        handle.write(b"half")
        raise KeyboardInterrupt  # as a kill in the middle of the write

    monkeypatch.setattr(fig, "savefig", dies)
    with pytest.raises(KeyboardInterrupt):
        plotting.save_figure(fig, tmp_path, "f")
    assert (tmp_path / "f.png").read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.pdf", "f.png"]
    plt.close(fig)


def test_leftover_temporary_files_are_removed_by_the_next_write(tmp_path):
    leftover = tmp_path / "r.npz.abc123.tmp"
    leftover.write_bytes(b"")
    results.save(tmp_path / "r.npz", SMALL_LINE, {"x": np.zeros(1)})
    assert not leftover.exists()


def test_a_concurrent_writer_of_another_configuration_is_not_silently_replaced(tmp_path):
    args = cli.parse(cli.figure_parser("t", runs=2, iterations=200), ["--results", str(tmp_path), "--out", str(tmp_path)])
    other = dataclasses.replace(SMALL_LINE, runs=3)

    def run_while_another_saves(config, seed, workers, progress):
        results.save(tmp_path / "exp.npz", other, {"reward": np.ones(1)}, seed=seed)  # the other run finishes first
        return single_gla.run(config, seed=seed, workers=parallel.Threads(1))

    experiment = dataclasses.replace(single_gla.FIG5, name="exp", run=run_while_another_saves)
    with pytest.raises(results.ResultFileError, match="different configuration and was not overwritten"):
        figures.load_or_run(args, experiment, SMALL_LINE)
    assert results.load(tmp_path / "exp.npz", other, seed=0)["reward"].tolist() == [1.0]


# --- hangs: bounded waits -------------------------------------------------------------------

def test_too_many_workers_are_refused():
    _assert_user_error(_script("fig6", "--runs", 2, "--iterations", 200, "--workers", 100000),
                       "--workers 100000 is more than 4 per core")


def test_workers_are_capped_at_the_number_of_jobs(monkeypatch):
    seen = []
    original = parallel.local.run_in_threads
    monkeypatch.setattr(parallel.local, "run_in_threads", lambda backend, jobs: seen.append(backend.workers) or original(backend, jobs))
    single_gla.run(SMALL_LINE, workers=parallel.Threads(64))
    assert seen == [2]


def test_malformed_scheduler_address_fails_at_once():
    started = time.monotonic()
    _assert_user_error(_script("fig6", "--runs", 2, "--iterations", 200, "--scheduler", "tcp:/bad::address"),
                       "'tcp:/bad::address' is not a Dask scheduler address")
    assert time.monotonic() - started < 15


def test_a_server_that_is_not_a_dask_scheduler_fails_within_the_timeout():
    pytest.importorskip("distributed")
    with socket.socket() as server:  # accepts connections, never answers
        server.bind(("127.0.0.1", 0))
        server.listen()
        address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
        started = time.monotonic()
        with pytest.raises(parallel.BackendError, match=f"cannot reach the Dask scheduler at {address} within 1 s"):
            parallel.connect(parallel.Dask(address, timeout=1.0))
        assert time.monotonic() - started < 5


def test_a_port_out_of_range_and_servers_of_other_protocols_are_one_line_each():
    pytest.importorskip("distributed")
    with pytest.raises(parallel.BackendError, match="'tcp://127.0.0.1:99999' is not a Dask scheduler address "
                                                    r"\(port 99999 is out of range 1-65535\)"):
        parallel.connect(parallel.Dask("tcp://127.0.0.1:99999", timeout=1.0))
    web = http.server.HTTPServer(("127.0.0.1", 0), http.server.BaseHTTPRequestHandler)  # waits for a request
    threading.Thread(target=web.serve_forever, daemon=True).start()
    with socket.socket() as banner:  # greets every connection in another protocol
        banner.bind(("127.0.0.1", 0))
        banner.listen()

        def greet():
            with contextlib.suppress(OSError):
                while True:
                    connection, _ = banner.accept()
                    connection.sendall(b"SSH-2.0-OpenSSH_9.2\r\n")
                    connection.close()
        threading.Thread(target=greet, daemon=True).start()
        try:
            started = time.monotonic()
            with pytest.raises(parallel.BackendError, match="sent no Dask handshake"):
                parallel.connect(parallel.Dask(f"tcp://127.0.0.1:{web.server_address[1]}", timeout=1.0))
            with pytest.raises(parallel.BackendError, match="does not speak Dask's protocol \\(it began with b'SSH-2.0-'"):
                parallel.connect(parallel.Dask(f"tcp://127.0.0.1:{banner.getsockname()[1]}", timeout=1.0))
            assert time.monotonic() - started < 5
        finally:
            web.shutdown()
            web.server_close()


def test_a_cluster_without_workers_is_reported_within_the_timeout():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        started = time.monotonic()
        with pytest.raises(parallel.BackendError, match="has had no worker for 1 s with 1 jobs left"):
            single_gla.run(SMALL_LINE, workers=parallel.Dask(cluster.scheduler_address, timeout=1.0))
        assert time.monotonic() - started < 10


def test_a_worker_process_killed_mid_run_is_reported_at_once():
    psutil = pytest.importorskip("psutil")

    def busy(worker) -> bool:
        """Whether ``worker`` is running a job (its CPU time grows), not idle in a pool kept from an
        earlier test, whose death the run would never see."""
        before = sum(worker.cpu_times()[:2])
        time.sleep(0.3)
        return sum(worker.cpu_times()[:2]) > before + 0.1

    def kill_a_worker():
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            workers = [p for p in psutil.Process().children(recursive=True) if "popen_loky" in " ".join(p.cmdline())]
            for worker in workers:
                try:
                    if busy(worker):
                        worker.kill()
                        return
                except (psutil.NoSuchProcess, ProcessLookupError):
                    pass  # a worker of an earlier pool, gone meanwhile: look again
            time.sleep(0.05)

    killer = threading.Thread(target=kill_a_worker, daemon=True)
    killer.start()
    config = gridworld.GridworldConfig(runs=2, episodes=1_000_000, learners=("mmdp",))
    with pytest.raises(parallel.BackendError, match=r"a worker process died mid-run .*SIGKILL"):
        gridworld.run(config, workers=parallel.Processes(2))
    killer.join()


# --- resources: estimated before allocating --------------------------------------------------

def test_huge_run_count_is_refused_by_the_memory_estimate():
    _assert_user_error(_script("fig6", "--runs", 2_000_000_000, "--iterations", 200, *FAST), "this run needs about")


def test_huge_episode_count_is_refused_by_the_memory_estimate(tmp_path):
    """The scaling study logs blocks of 100 episodes: their count grows with the episodes."""
    done = _script("scaling_performance", "--runs", 2, "--iterations", 2 ** 31 - 1, "--out", tmp_path,
                   "--results", tmp_path, *FAST)
    _assert_user_error(done, "this run needs about")


def test_iterations_beyond_the_integer_range_are_refused():
    _assert_user_error(_script("fig6", "--iterations", 10 ** 13, *FAST), "must be at most 2147483647")


def test_a_big_map_for_the_joint_learners_is_refused_before_allocating(tmp_path):
    size = 100
    lines = ["+" + "-+" * size]
    for r in range(size):
        row = ["."] * size
        if r == 0:
            row[0], row[-1] = "1", "2"
        if r == size - 1:
            row[size // 2] = "G"
        lines.append("|" + " ".join(row) + "|")
        lines.append("+" + ("-+" if r == size - 1 else " +") * size)
    path = tmp_path / "big.txt"
    path.write_text("\n".join(lines) + "\n")
    config = gridworld.GridworldConfig(map=str(path), runs=20, episodes=10, bins=10)
    with pytest.raises(memory.MemoryEstimateError, match="this run needs about .* GiB .* more than"):
        memory.check(config)


def test_the_joint_optimum_of_a_six_agent_map_is_refused_before_allocating():
    with pytest.raises(memory.MemoryEstimateError, match="this run needs about .* GiB"):
        gridworld_optimum.run(gridworld_optimum.GridworldOptimumConfig(map="warehouse_6"))


def test_the_paper_scale_defaults_fit_the_memory_estimate():
    for experiment in registry.experiments():
        assert 0 < experiment.paper_scale().memory_bytes() * experiment.copies < memory.available_bytes()


# --- bad files -------------------------------------------------------------------------------

def _tunnel_bytes() -> bytes:
    return (MAPS / "tunnel_to_goal.txt").read_bytes()


def test_map_that_is_not_utf8_names_file_and_line(tmp_path):
    path = tmp_path / "latin1.txt"
    path.write_bytes(_tunnel_bytes().replace(b"G", b"\xe9", 1))
    with pytest.raises(MapError, match=r"map file .*latin1.txt: line \d+ is not UTF-8 text \(byte 0xe9\)"):
        load_map(path)


def test_map_with_a_byte_order_mark_loads(tmp_path):
    path = tmp_path / "bom.txt"
    path.write_bytes(b"\xef\xbb\xbf" + _tunnel_bytes())
    assert load_map(path).n_cells == load_map(MAPS / "tunnel_to_goal.txt").n_cells


def test_map_errors_name_the_file(tmp_path):
    path = tmp_path / "ragged.txt"
    path.write_text("+-+\n|G|\n+-+-+\n")
    with pytest.raises(MapError, match=r"map file .*ragged.txt: ragged rows: line 3"):
        load_map(path)


def _damaged_copy(tmp_path):
    path = results.save(tmp_path / "r.npz", SMALL_LINE, {"x": np.arange(1000.0)})
    data = bytearray(path.read_bytes())
    with zipfile.ZipFile(path) as archive:
        info = archive.getinfo("x.npy")
    name_length, extra_length = struct.unpack("<HH", data[info.header_offset + 26:info.header_offset + 30])
    start = info.header_offset + 30 + name_length + extra_length  # the compressed array
    data[start + info.compress_size // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    return path


def test_result_file_with_a_bad_checksum_gives_one_clear_error(tmp_path):
    with pytest.raises(results.ResultFileError, match="r.npz is not a readable glamas result file"):
        results.load(_damaged_copy(tmp_path), SMALL_LINE)


def test_result_file_holding_a_pickled_array_is_refused(tmp_path):
    path = tmp_path / "pickled.npz"
    np.savez(path, __config__=np.array(results.config_json(SMALL_LINE)),
             __provenance__=np.array(json.dumps(provenance.record(SMALL_LINE))), evil=np.array([{}], dtype=object))
    with pytest.raises(results.ResultFileError, match="not a readable glamas result file.*allow_pickle"):
        results.load(path, SMALL_LINE)


def test_truncated_result_file_is_refused(tmp_path):
    path = results.save(tmp_path / "r.npz", SMALL_LINE, {"x": np.arange(1000.0)})
    path.write_bytes(path.read_bytes()[:200])
    with pytest.raises(results.ResultFileError, match="not a readable glamas result file"):
        results.load(path, SMALL_LINE)


# --- stale results and kernels ---------------------------------------------------------------

def test_result_of_an_edited_map_is_stale(tmp_path):
    path = tmp_path / "map.txt"
    path.write_bytes(_tunnel_bytes())
    config = gridworld.GridworldConfig(map=str(path), runs=1, episodes=10, bins=10)
    stored = results.save(tmp_path / "gw.npz", config, {"x": np.zeros(1)})
    path.write_bytes(_tunnel_bytes() + b"\n")
    with pytest.raises(results.StaleResultError, match="the map file of map changed since it was made"):
        results.load(stored, config)


def test_result_of_another_library_version_is_stale(tmp_path, monkeypatch):
    stored = results.save(tmp_path / "r.npz", SMALL_LINE, {"x": np.zeros(1)})
    monkeypatch.setattr(glamas, "__version__", "0.0.0")
    with pytest.raises(results.StaleResultError, match=r"this is glamas 0\.0\.0.*\(--rerun\)"):
        results.load(stored, SMALL_LINE)


def test_figure_script_refuses_a_stale_result_and_names_rerun(tmp_path):
    config = gridworld.GridworldConfig(runs=2, episodes=200)
    record = dict(provenance.record(config), version="0.0.0")
    np.savez(tmp_path / "gridworld.npz", __config__=np.array(results.config_json(config, 0)),
             __provenance__=np.array(json.dumps(record)))
    done = _script("fig12b", "--runs", 2, "--iterations", 200, "--out", tmp_path, "--results", tmp_path, *FAST)
    _assert_user_error(done, "it was made by glamas 0.0.0")
    assert "--rerun" in done.stderr


def _package(tmp_path):
    package = tmp_path / "pkg"
    (package / "__pycache__").mkdir(parents=True)
    (package / "kernel.py").write_text(KERNEL.format(x=1))
    (package / "figure.py").write_text("y = 1\n")  # imports no numba and no kernel imports it
    return package


KERNEL = "from numba import njit\n\nx = {x}\n"



def test_cached_kernels_are_dropped_when_a_source_changes(tmp_path):
    package = _package(tmp_path)
    sources.refresh_kernel_cache(package)
    cached = [package / "__pycache__" / "kernel.run-1.py311.nbi", package / "__pycache__" / "kernel.run-1.py311.0.nbc"]
    for path in cached:
        path.write_bytes(b"old code")
    assert not sources.refresh_kernel_cache(package) and all(path.exists() for path in cached)
    (package / "figure.py").write_text("y = 2\n")  # cannot change a kernel: the cache stays
    assert not sources.refresh_kernel_cache(package) and all(path.exists() for path in cached)
    (package / "kernel.py").write_text(KERNEL.format(x=2))
    assert sources.refresh_kernel_cache(package) and not any(path.exists() for path in cached)


def test_a_numba_cache_directory_elsewhere_is_refreshed_too(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "numba"))
    package = _package(tmp_path)
    sources.refresh_kernel_cache(package)
    cached = sources.cache_directory(package) / "kernel.run-1.py311.nbi"
    cached.write_bytes(b"old code")
    (package / "kernel.py").write_text(KERNEL.format(x=2))
    assert sources.refresh_kernel_cache(package) and not cached.exists()


def test_importers_at_once_refresh_the_kernel_cache_once(tmp_path):
    package = _package(tmp_path)
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        refreshed = list(pool.map(lambda _: sources.refresh_kernel_cache(package), range(8)))
    assert refreshed.count(True) == 1


# --- configs and numbers ---------------------------------------------------------------------

@pytest.mark.parametrize("make, message", [
    (lambda: single_gla.SingleGLAConfig(runs="10"), "SingleGLAConfig.runs must be a whole number, got '10'"),
    (lambda: single_gla.SingleGLAConfig(iterations=2 ** 40), "iterations must be at most 2147483647"),
    (lambda: and_network.ANDNetworkConfig(learning_rate="fast"), "ANDNetworkConfig.learning_rate must be a finite number"),
    (lambda: gridworld.GridworldConfig(map=None), "GridworldConfig.map must be a string, got None"),
    (lambda: two_observe.GLASettings(coordination_penalty_per_cell=math.inf),
     "GLASettings.coordination_penalty_per_cell must be a finite number, got inf"),
    (lambda: two_observe.GLASettings(gla_learning_rate=math.nan), "gla_learning_rate must be a finite number"),
    (lambda: gridworld.GridworldConfig(q=None), "GridworldConfig.q must be a QSettings, got None"),
    (lambda: gridworld_optimum.GridworldOptimumConfig(epsilon=math.inf),
     "GridworldOptimumConfig.epsilon must be a finite number, got inf"),
    (lambda: scaling.ScalingConfig(memory_budget_gib="4"), "ScalingConfig.memory_budget_gib must be a finite number"),
    (lambda: scaling.ScalingConfig(q={"discount": 0.9}), "ScalingConfig.q must be a QSettings, got {'discount': 0.9}"),
])
def test_wrong_types_and_non_finite_settings_are_refused_with_the_field(make, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        make()


def test_learning_that_leaves_the_finite_numbers_stops_the_run():
    config = dataclasses.replace(SMALL_LINE, learning_rate=1e300)
    with pytest.raises(parallel.NonFiniteError, match="glamas.learners.single_gla.learn produced NaN or infinite"):
        single_gla.run(config, workers=parallel.Threads(1))


def test_figure_scripts_name_the_setting_likely_responsible(tmp_path):
    args = cli.parse(cli.figure_parser("t", runs=2, iterations=200), ["--results", str(tmp_path), "--out", str(tmp_path)])
    args.workers = parallel.Threads(1)
    config = dataclasses.replace(SMALL_LINE, learning_rate=1e300)
    with pytest.raises(parallel.NonFiniteError, match=r"likely responsible: learning_rate=1e\+300 \(default 0.01\)"):
        cli.run_experiment(args, "exp", config, single_gla.run)
    assert not (tmp_path / "exp.npz").exists()


def test_user_errors_become_one_line_and_exit_status_2(capsys):
    with pytest.raises(SystemExit) as stopped:
        with errors.reported():
            raise results.ResultFileError("the file\nis bad")
    assert stopped.value.code == 2 and capsys.readouterr().err == "error: the file is bad\n"


# --- the PettingZoo adapter ------------------------------------------------------------------

@pytest.fixture
def env():
    pettingzoo_env = pytest.importorskip("glamas.gridworld.pettingzoo_env")
    return pettingzoo_env.GridworldParallelEnv()


@pytest.mark.parametrize("seed", ["abc", -1, 1.5, True])
def test_adapter_reset_refuses_a_bad_seed(env, seed):
    with pytest.raises(ValueError, match=f"seed must be None or a whole number >= 0, got {seed!r}"):
        env.reset(seed=seed)


def test_adapter_takes_a_map_path_string():
    pettingzoo_env = pytest.importorskip("glamas.gridworld.pettingzoo_env")
    assert pettingzoo_env.GridworldParallelEnv(str(MAPS / "warehouse_3.txt")).possible_agents[-1] == "agent_3"
    with pytest.raises(MapError, match="no map file"):
        pettingzoo_env.GridworldParallelEnv("no_such_map.txt")


def test_adapter_samplers_of_neighbouring_seeds_differ(env):
    def samples(seed, agent):
        env.reset(seed=seed)
        return [env.action_space(agent).sample() for _ in range(32)]

    assert samples(7, "agent_2") != samples(8, "agent_1")
    assert samples(7, "agent_1") == samples(7, "agent_1")



def test_a_result_without_its_provenance_record_is_stale(tmp_path):
    path = tmp_path / "old.npz"
    np.savez(path, __config__=np.array(results.config_json(SMALL_LINE)), x=np.zeros(1))
    with pytest.raises(results.StaleResultError, match=r"records neither the maps nor the glamas version .*\(--rerun\)"):
        results.load(path, SMALL_LINE)


@pytest.mark.parametrize("argv, message", [(["--runs", "0"], "argument --runs: must be at least 1, got 0"),
                                           (["--seed", "-1"], "argument --seed: must be 0 or more, got -1"),
                                           (["--seed", str(2 ** 32)], "argument --seed: must be at most 4294967295"),
                                           (["--episodes", "5"], "error: episodes must be a whole number >= 10, got 5"),
                                           (["--episodes", "15"], "error: episodes must be a multiple of 10")])
def test_the_trap_benchmark_refuses_bad_options_before_computing(argv, message, monkeypatch, capsys):
    from benchmarks import sparse_maq_trap
    monkeypatch.setattr(sys, "argv", ["sparse_maq_trap.py", *argv])
    with pytest.raises(SystemExit) as stopped:
        errors.run(sparse_maq_trap.main)
    err = capsys.readouterr().err
    assert stopped.value.code == 2 and message in err and "Traceback" not in err


def test_a_result_of_edited_code_is_stale_and_of_edited_comments_is_not(tmp_path, monkeypatch):
    clone = tmp_path / "glamas"
    shutil.copytree(sources.PACKAGE, clone, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(sources, "PACKAGE", clone)
    config = gridworld.GridworldConfig(runs=1, episodes=10, bins=10)
    stored = results.save(tmp_path / "gw.npz", config, {"x": np.zeros(1)})
    kernel = clone / "learners" / "independent.py"
    text = kernel.read_text()
    kernel.write_text(text.replace('"""Independent Q-learners', '"""Independent Q-learners (edited)', 1) + "# a comment\n")
    spec = clone / "learners" / "spec.py"
    spec.write_text(spec.read_text().replace('"""Its name in configs and result files."""', '"""Its name."""'))
    assert results.load(stored, config)["x"].shape == (1,)  # docstrings (of attributes too) and comments are not code
    kernel.write_text(text.replace("return n_agents, n_cells, rules.N_ACTIONS", "return n_agents, n_cells, 4"))
    with pytest.raises(results.StaleResultError, match=r"gw\.npz is stale: the code that computes it changed since "
                                                       r"it was made \(glamas/learners/independent\.py\)"):
        results.load(stored, config)


@pytest.mark.parametrize("edit, problem", [
    (lambda a: {**a, "learners": a["learners"][::-1]}, "arrays whose contents differ from those it recorded: learners"),
    (lambda a: {**a, "log": a["log"][:1]}, "arrays whose contents differ from those it recorded: log"),
    (lambda a: {**a, "log": np.full_like(a["log"], np.nan)}, "arrays whose contents differ from those it recorded: log"),
    (lambda a: {k: v for k, v in a.items() if k != "log"}, "arrays missing: log"),
    (lambda a: {**a, "extra": np.zeros(2)}, "arrays it did not record: extra"),
])
def test_a_result_file_whose_arrays_were_edited_is_refused_naming_them_and_kept(tmp_path, edit, problem):
    arrays = {"learners": np.array(["independent", "mmdp"]), "log": np.arange(6.0).reshape(2, 3)}
    path = results.save(tmp_path / "r.npz", SMALL_LINE, arrays)
    with np.load(path) as archive:
        header = {key: archive[key] for key in ("__config__", "__provenance__")}
    np.savez(path, **header, **edit(arrays))
    before = path.read_bytes()
    with pytest.raises(results.ResultFileError, match=rf"r\.npz is damaged or was edited \({re.escape(problem)}"):
        results.load(path, SMALL_LINE)
    assert path.read_bytes() == before
