"""Whole-process time of recomputing the chapter (Fig. 5-12) as `make reproduce` does: each figure
script of the Makefile's CHAPTER list as its own process, in order, with the same arguments, into
empty result and figure directories and with an empty numba cache, so that every kernel compiles
and every experiment is recomputed at paper scale. Prints each script's wall time and the total.

It costs minutes of both cores: run it on a quiet machine (`make benchmark` runs it too).
"""

import os
import re
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
            command = [sys.executable, str(REPO / "paper_figures" / f"{name}.py"), "--out", str(figures)]
            if name != "fig9":  # Fig. 9 draws the map and its exact optimum: no result file
                command += ["--results", str(results)]
            start = time.perf_counter()
            subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            seconds[name] = time.perf_counter() - start
            print(f"{name:8} {seconds[name]:6.1f} s", flush=True)
    print(f"{'total':8} {sum(seconds.values()):6.1f} s  (Fig. 5-12 recomputed, cold numba cache, "
          f"{os.cpu_count()} cores; aim: 60 s on 2 cores)")


if __name__ == "__main__":
    main()
