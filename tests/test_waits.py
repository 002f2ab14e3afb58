"""Every wait has a bound: a lock held by another process gives up after atomic.LOCK_WAIT_SECONDS
naming the holder, a Dask scheduler that refuses the connection fails at once, and a scheduler
or worker lost mid-run ends in one BackendError. Only generous upper bounds of the bounded waits
are timed."""

import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from glamas import atomic, figures, parallel, results, sources
from glamas.experiments import gridworld, single_gla

SMALL_LINE = single_gla.SingleGLAConfig(runs=2, iterations=200, record_points=10)
LONG_RUN = gridworld.GridworldConfig(runs=2, episodes=100_000_000, learners=("mmdp",))
"""Minutes of work for one worker: a run that is still going when its cluster is broken."""
HOLD = "import fcntl, os, sys, time; fd = os.open(sys.argv[1], {flags}); fcntl.flock(fd, fcntl.LOCK_EX); print('held', flush=True); time.sleep(120)"


def _held(path: Path, flags: str = "os.O_RDONLY") -> subprocess.Popen:
    """A process holding an exclusive lock on ``path`` until it is killed."""
    holder = subprocess.Popen([sys.executable, "-c", HOLD.format(flags=flags), str(path)], stdout=subprocess.PIPE,
                              text=True)
    assert holder.stdout.readline() == "held\n"
    return holder


def test_a_results_directory_locked_too_long_is_named_with_its_holder(tmp_path, monkeypatch):
    monkeypatch.setattr(atomic, "LOCK_WAIT_SECONDS", 1.0)
    holder = _held(tmp_path)
    try:
        started = time.monotonic()
        with pytest.raises(atomic.LockTimeoutError, match=rf"the directory {tmp_path} has been locked by process "
                                                          rf"{holder.pid} \(.*python.* -c .*\) for more than 1 s"):
            results.save(tmp_path / "r.npz", SMALL_LINE, {"x": np.zeros(1)})
        assert time.monotonic() - started < 30
    finally:
        holder.kill()
        holder.wait()
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_a_held_results_directory_is_refused_before_computing(tmp_path, capsys):
    holder = _held(tmp_path)
    try:
        started = time.monotonic()
        argv = ["--runs", "2", "--iterations", "200", "--results", str(tmp_path), "--out", str(tmp_path / "figures")]
        with pytest.raises(SystemExit) as stopped:
            with figures.figure(single_gla.FIG5, "fig5", "Fig. 5.", argv):
                pass
        assert stopped.value.code == 2 and time.monotonic() - started < 4 + atomic.CHECK_SECONDS
        assert re.search(rf"error: the directory {tmp_path} has been locked by process {holder.pid} \(.*\) for more "
                         rf"than {atomic.CHECK_SECONDS:g} s", capsys.readouterr().err)
    finally:
        holder.kill()
        holder.wait()
    assert not (tmp_path / "single_gla.npz").exists()


def test_the_kernel_cache_locked_too_long_turns_caching_off_with_one_warning(tmp_path, monkeypatch, capsys):
    from numba.core.dispatcher import Dispatcher

    package = tmp_path / "pkg"
    package.mkdir()
    (package / "kernel.py").write_text("x = 1\n")
    lock = sources.cache_directory(package) / "glamas-sources.lock"
    lock.parent.mkdir()
    lock.touch()
    monkeypatch.setattr(atomic, "LOCK_WAIT_SECONDS", 1.0)
    monkeypatch.setattr(Dispatcher, "enable_caching", Dispatcher.enable_caching)  # restored after the test
    monkeypatch.delenv(sources.CACHE_OFF_VARIABLE, raising=False)
    holder = _held(lock, "os.O_RDWR")
    try:
        assert not sources.prepare_kernel_cache(package)
    finally:
        holder.kill()
        holder.wait()
        os.environ.pop(sources.CACHE_OFF_VARIABLE, None)  # set with the warning: later processes decide anew
    warning = capsys.readouterr().err.splitlines()
    assert len(warning) == 1 and warning[0].startswith("warning: numba's kernel cache is off for this run")
    assert f"has been locked by process {holder.pid}" in warning[0]
    assert Dispatcher.enable_caching is sources._no_caching


# --- Dask -------------------------------------------------------------------------------------------

distributed = pytest.importorskip("distributed")


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def test_a_scheduler_that_refuses_the_connection_fails_at_once():
    address = f"tcp://127.0.0.1:{_free_port()}"
    started = time.monotonic()
    with pytest.raises(parallel.BackendError, match=f"cannot reach the Dask scheduler at {address} within 60 s "
                                                    r"\(connection refused: nothing listens there\)"):
        parallel.connect(parallel.Dask(address, timeout=60.0))
    assert time.monotonic() - started < 30  # far below the 60 s it may wait for a slow network


def _when_running(address: str, then) -> threading.Thread:
    """A thread that calls ``then()`` once the scheduler at ``address`` has a job processing."""
    def watch():
        with distributed.Client(address, timeout=30, set_as_default=False) as watcher:
            while not any(watcher.processing().values()):
                time.sleep(0.05)
        then()

    thread = threading.Thread(target=watch, daemon=True)
    thread.start()
    return thread


def _worker(address: str) -> subprocess.Popen:
    """A Dask worker process of one thread, without a nanny that would restart it once killed."""
    return subprocess.Popen([str(Path(sys.executable).parent / "dask"), "worker", address, "--nthreads", "1",
                             "--no-dashboard", "--no-nanny"], stderr=subprocess.DEVNULL)


def test_a_scheduler_lost_mid_run_is_one_backend_error():
    address = f"tcp://127.0.0.1:{_free_port()}"
    scheduler = subprocess.Popen([str(Path(sys.executable).parent / "dask"), "scheduler", "--host", "127.0.0.1",
                                  "--port", address.rsplit(":", 1)[1], "--no-dashboard"], stderr=subprocess.DEVNULL)
    worker = None
    try:
        with distributed.Client(address, timeout=60, set_as_default=False):  # waits for the scheduler to start
            worker = _worker(address)
            watcher = _when_running(address, lambda: scheduler.send_signal(signal.SIGKILL))
        with pytest.raises(parallel.BackendError, match=f"the Dask scheduler at {address} was lost mid-run "
                                                        r"\(scheduler-connection-lost\)"):
            gridworld.run(LONG_RUN, workers=parallel.Dask(address, timeout=5.0))
        watcher.join()
    finally:
        for process in (scheduler, worker):
            if process is not None:
                process.kill()
                process.wait()


def test_a_worker_lost_mid_run_is_one_backend_error():
    with distributed.LocalCluster(n_workers=0, processes=True, dashboard_address=None) as cluster:
        worker = _worker(cluster.scheduler_address)
        try:
            watcher = _when_running(cluster.scheduler_address, worker.kill)
            with pytest.raises(parallel.BackendError, match="has had no worker for 5 s with 1 jobs left"):
                gridworld.run(LONG_RUN, workers=parallel.Dask(cluster.scheduler_address, timeout=5.0))
            watcher.join()
        finally:
            worker.kill()
            worker.wait()
