"""Whole-process time of the Section 4 figure scripts (Fig. 5, 6, 7a, 7b) at paper scale, numba
compilation included, against a plain-Python reference of the same learning work.

Each script runs as its own process, as `make figures` runs it, with an empty numba cache (so
every kernel compiles) and empty output and result directories. The plain-Python side times the
reference learning loops of experiments 1 and 2 for a few thousand iterations in this process and
scales them to the iterations the scripts perform. It counts only the learning iterations, not the
evaluation grids, probes and plots the scripts also do, so the ratio printed is a lower bound.
"""

import math
import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_gla  # noqa: E402  (the experiment 1 plain-Python reference)

from glamas.experiments import and_network, single_gla  # noqa: E402
from glamas.paths import REPO  # noqa: E402

SCRIPTS = ("fig5", "fig6", "fig7a", "fig7b")
REFERENCE_ITERATIONS = 10_000


def reference_and_network_run(iterations, learning_rate=0.005, temperature=0.5, K=1.0, L=1.0,
                              curvature=1.0, offset=-0.5, seed=0):
    """One run of experiment 2 in plain Python: two agents, each an AND of two 2-action GLAs."""
    rnd = random.Random(seed)
    u = [[[[0.5 * (2 * rnd.random() - 1) for _ in range(3)] for _ in range(2)] for _ in range(2)]
         for _ in range(2)]  # agent, unit, unit action, input
    total = 0.0
    for _ in range(iterations):
        x = [2.0 * rnd.random() - 1.0, 2.0 * rnd.random() - 1.0, 1.0]
        chosen, probs, plays_left = [], [], []
        for agent in range(2):
            unit_choices, unit_probs = [], []
            for unit in u[agent]:
                z = [sum(x[k] * max(-L, min(L, unit[a][k])) for k in range(3)) / temperature for a in range(2)]
                top = max(z)
                e = [math.exp(v - top) for v in z]
                p = [v / sum(e) for v in e]
                unit_choices.append(0 if rnd.random() < p[0] else 1)
                unit_probs.append(p)
            chosen.append(unit_choices)
            probs.append(unit_probs)
            plays_left.append(unit_choices == [1, 1])
        inside = x[1] >= curvature * x[0] ** 2 + offset
        if inside and all(plays_left):
            beta = 0.9
        elif not inside and not any(plays_left):
            beta = 0.5
        else:
            beta = 0.1
        total += beta
        for agent in range(2):
            for k, unit in enumerate(u[agent]):
                for a in range(2):
                    indicator = 1.0 if a == chosen[agent][k] else 0.0
                    for i in range(3):
                        gradient = x[i] / temperature * (indicator - probs[agent][k][a])
                        h = max(-L, min(L, unit[a][i]))
                        unit[a][i] += learning_rate * beta * gradient + learning_rate * K * (h - unit[a][i])
    return total


def _per_iteration(reference) -> float:
    start = time.perf_counter()
    reference(REFERENCE_ITERATIONS)
    return (time.perf_counter() - start) / REFERENCE_ITERATIONS


def learning_iterations() -> dict:
    """Learning iterations (one for both agents) each script performs at its default scale."""
    exp1, exp2 = single_gla.SingleGLAConfig(), and_network.ANDNetworkConfig()
    one_experiment_1 = exp1.runs * exp1.iterations
    return {"fig5": ("exp. 1", one_experiment_1),
            "fig6": ("exp. 1", len(single_gla.ENCODING_NAMES) * one_experiment_1),
            "fig7a": ("exp. 2", exp2.runs * exp2.iterations),
            "fig7b": ("exp. 2", 0)}  # fig7b reads the run fig7a saved


def run_scripts() -> dict:
    """Wall time of each script as a fresh process with a cold numba cache."""
    seconds = {}
    with tempfile.TemporaryDirectory() as scratch:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(scratch) / "numba-cache"))
        for name in SCRIPTS:
            start = time.perf_counter()
            subprocess.run([sys.executable, str(REPO / "paper_figures" / f"{name}.py"),
                            "--out", scratch, "--results", scratch],
                           check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            seconds[name] = time.perf_counter() - start
    return seconds


def main():
    python = {"exp. 1": _per_iteration(bench_gla.reference_run),
              "exp. 2": _per_iteration(reference_and_network_run)}
    for experiment, per_iteration in python.items():
        print(f"plain Python, {experiment}: {per_iteration * 1e6:6.1f} us per iteration "
              f"({REFERENCE_ITERATIONS:,} iterations timed)")
    compiled = run_scripts()
    work = learning_iterations()
    print(f"\n{'script':8} {'compiled, whole process':>24} {'plain Python (estimate)':>24}")
    for name in SCRIPTS:
        experiment, iterations = work[name]
        print(f"{name:8} {compiled[name]:22.1f} s {iterations * python[experiment]:22.0f} s")
    total_compiled = sum(compiled.values())
    total_python = sum(iterations * python[experiment] for experiment, iterations in work.values())
    print(f"{'total':8} {total_compiled:22.1f} s {total_python:22.0f} s")
    print(f"\nFig. 5-7 at paper scale, compile included: {total_compiled:.1f} s (aim: well under 60 s); "
          f"{total_python / total_compiled:.0f}x the plain-Python reference (aim: at least 30x)")


if __name__ == "__main__":
    main()
