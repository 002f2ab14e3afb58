"""Whole-process time of recomputing the chapter (Fig. 5-12) as `make reproduce` does, and with
``--all`` of recomputing everything, the studies beyond the chapter included, as `make verify`
does: ``python -m glamas.reproduce`` as one process, into empty result and figure directories and
with an empty numba cache, so that every kernel compiles and every experiment is recomputed at
paper scale. Prints the wall time of the driver's start (its imports) and of each script (from
the driver's announcements), and the total wall and CPU time of the process and its workers
(user + system): on a machine shared with other jobs the wall time grows with their load, the CPU
time much less.

It costs minutes of both cores: run it on a quiet machine (`make benchmark` runs it too).
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from glamas import errors

ANNOUNCEMENT = "== paper_figures/"
AIMS = {False: ("Fig. 5-12", 40), True: ("everything", None)}
"""What is recomputed, and the aim in seconds of wall time on 2 cores (everything, as `make verify`
recomputes it, has none: its time is stated in docs/usage.md)."""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="every script, the studies beyond the chapter included")
    everything = parser.parse_args().all
    with tempfile.TemporaryDirectory() as scratch:
        figures, results = Path(scratch) / "figures", Path(scratch) / "results"
        figures.mkdir()
        results.mkdir()
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(scratch) / "numba-cache"))
        command = [sys.executable, "-m", "glamas.reproduce", *(["--all"] if everything else []),
                   "--out", str(figures), "--results", str(results)]
        wall = time_scripts(command, env)
    cpu = _children_cpu()
    what, aim = AIMS[everything]
    print(f"{'total':22} {wall:6.1f} s wall {cpu:7.1f} s CPU  ({what} recomputed in one process, cold numba "
          f"cache, {os.cpu_count()} cores" + (f"; aim: {aim} s wall on 2 cores)" if aim else ")"))


def time_scripts(command: list, env: dict) -> float:
    """Run ``command``, printing the wall time of each script it announces; its total wall time."""
    start = time.perf_counter()
    current, since = "(start)", start  # the driver's imports, before its first script
    with subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True) as process:
        for line in process.stdout:
            if line.startswith(ANNOUNCEMENT):
                now = time.perf_counter()
                _report(current, now - since)
                current, since = line[len(ANNOUNCEMENT):].strip().removesuffix(".py"), now
    if process.returncode:
        raise SystemExit(f"{' '.join(command)} failed with exit status {process.returncode}")
    end = time.perf_counter()
    _report(current, end - since)
    return end - start


def _report(name, seconds: float) -> None:
    print(f"{name:22} {seconds:6.1f} s wall", flush=True)


def _children_cpu() -> float:
    """User + system CPU seconds of the finished child processes (and theirs) so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


if __name__ == "__main__":
    errors.run(main)
