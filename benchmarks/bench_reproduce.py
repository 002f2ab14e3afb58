"""Whole-process time of recomputing the chapter (Fig. 5-12) as `make reproduce` does: each figure
script of the Makefile's CHAPTER list as its own process, in order, with the same arguments, into
empty result and figure directories and with an empty numba cache, so that every kernel compiles
and every experiment is recomputed at paper scale. Prints each script's wall time and the CPU time
of its processes (its own and its workers', user + system): on a machine shared with other jobs the
wall time grows with their load, the CPU time much less.

It costs minutes of both cores: run it on a quiet machine (`make benchmark` runs it too).
"""

import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def chapter_scripts() -> list[str]:
    """The CHAPTER list of the Makefile (the scripts `make reproduce` runs, in order)."""
    found = re.search(r"^CHAPTER := (.+)$", (REPO / "Makefile").read_text(), re.MULTILINE)
    return found.group(1).split()


def main():
    seconds = {}
    with tempfile.TemporaryDirectory() as scratch:
        figures, results = Path(scratch) / "figures", Path(scratch) / "results"
        figures.mkdir()
        results.mkdir()
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(scratch) / "numba-cache"))
        for name in chapter_scripts():
            command = [sys.executable, str(REPO / "paper_figures" / f"{name}.py"), "--out", str(figures),
                       "--results", str(results)]
            cpu_before, start = _children_cpu(), time.perf_counter()
            subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            seconds[name] = (time.perf_counter() - start, _children_cpu() - cpu_before)
            print(f"{name:8} {seconds[name][0]:6.1f} s wall {seconds[name][1]:7.1f} s CPU", flush=True)
    wall, cpu = (sum(s[k] for s in seconds.values()) for k in (0, 1))
    print(f"{'total':8} {wall:6.1f} s wall {cpu:7.1f} s CPU  (Fig. 5-12 recomputed, cold numba cache, "
          f"{os.cpu_count()} cores; aim: 60 s wall on 2 cores)")


def _children_cpu() -> float:
    """User + system CPU seconds of the finished child processes (and theirs) so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


if __name__ == "__main__":
    main()
