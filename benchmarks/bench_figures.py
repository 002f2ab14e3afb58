"""Whole-process time of the Section 4 figure scripts (Fig. 5, 6, 7a, 7b) at paper scale, numba
compilation included, against the plain-Python references of the same learning work
(glamas.plain.lineworld).

Each script runs as its own process, as `make figures` runs it, with an empty numba cache (so
every kernel compiles) and empty output and result directories. The plain-Python side times the
reference learning loops of experiments 1 and 2 for a few thousand iterations in this process and
scales them to the iterations the scripts perform. It counts only the learning iterations, not the
evaluation grids, probes and plots the scripts also do, so the ratio printed is a lower bound.
With ``--quick`` the scripts run 2 runs of 2,000 iterations instead.
"""

import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks import timing
from glamas.plain import lineworld as plain_lineworld
from glamas import errors
from glamas.experiments import and_network, single_gla, state_encoding
from glamas.paths import REPO

SCRIPTS = ("fig5", "fig6", "fig7a", "fig7b")
REFERENCE_ITERATIONS = 10_000
QUICK = ("--runs", "2", "--iterations", "2000")
"""The scripts' options with --quick (7a needs two runs)."""


def _per_iteration(reference, config_class) -> float:
    config = config_class(iterations=REFERENCE_ITERATIONS, runs=1)
    start = time.perf_counter()
    reference(config, random.Random(0))
    return (time.perf_counter() - start) / REFERENCE_ITERATIONS


def learning_iterations(options: tuple) -> dict:
    """Learning iterations (one for both agents) each script performs with ``options`` (its
    defaults when empty)."""
    scale = dict(zip(options[::2], map(int, options[1::2])))
    exp1, exp2 = single_gla.SingleGLAConfig(), and_network.ANDNetworkConfig()
    one_experiment_1 = scale.get("--runs", exp1.runs) * scale.get("--iterations", exp1.iterations)
    return {"fig5": ("exp. 1", one_experiment_1),
            "fig6": ("exp. 1", len(state_encoding.ENCODING_NAMES) * one_experiment_1),
            "fig7a": ("exp. 2", scale.get("--runs", exp2.runs) * scale.get("--iterations", exp2.iterations)),
            "fig7b": ("exp. 2", 0)}  # fig7b reads the run fig7a saved


def run_scripts(options: tuple) -> dict:
    """Wall time of each script as a fresh process with a cold numba cache."""
    seconds = {}
    with tempfile.TemporaryDirectory() as scratch:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(scratch) / "numba-cache"))
        for name in SCRIPTS:
            start = time.perf_counter()
            subprocess.run([sys.executable, str(REPO / "paper_figures" / f"{name}.py"),
                            "--out", scratch, "--results", scratch, *options],
                           check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            seconds[name] = time.perf_counter() - start
    return seconds


def main():
    options = QUICK if timing.quick(__doc__) else ()
    python = {"exp. 1": _per_iteration(plain_lineworld.single_gla_run, single_gla.SingleGLAConfig),
              "exp. 2": _per_iteration(plain_lineworld.and_network_run, and_network.ANDNetworkConfig)}
    for experiment, per_iteration in python.items():
        print(f"plain Python, {experiment}: {per_iteration * 1e6:6.1f} us per iteration "
              f"({REFERENCE_ITERATIONS:,} iterations timed)")
    compiled = run_scripts(options)
    work = learning_iterations(options)
    print(f"\n{'script':8} {'compiled, whole process':>24} {'plain Python (estimate)':>24}")
    for name in SCRIPTS:
        experiment, iterations = work[name]
        print(f"{name:8} {compiled[name]:22.1f} s {iterations * python[experiment]:22.0f} s")
    total_compiled = sum(compiled.values())
    total_python = sum(iterations * python[experiment] for experiment, iterations in work.values())
    print(f"{'total':8} {total_compiled:22.1f} s {total_python:22.0f} s")
    scale = "with " + " ".join(options) if options else "at paper scale"
    print(f"\nFig. 5-7 {scale}, compile included: {total_compiled:.1f} s (aim at paper scale: well under "
          f"60 s); {total_python / total_compiled:.0f}x the plain-Python reference (aim: at least 30x)")


if __name__ == "__main__":
    errors.run(main)
