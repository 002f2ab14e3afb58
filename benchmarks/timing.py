"""What the benchmarks share: their ``--quick`` option, and the comparison of a plain-Python
reference with the compiled kernel on one thread and on all, in one process."""

import argparse
import dataclasses
import random
import time

from benchmarks import kernels
from glamas.plain import gridworld as plain_gridworld
from glamas import parallel


def quick(description: str) -> bool:
    """Whether the command line asks for ``--quick``: sizes small enough to check that the
    benchmark runs (its times then say little)."""
    parser = argparse.ArgumentParser(description=description.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="small sizes: checks that the benchmark runs; its times then say little")
    return parser.parse_args().quick


def compare(label: str, unit: str, python: tuple, compiled) -> None:
    """Print the plain-Python time per ``unit``, then the compiled time per ``unit`` on one thread
    and on all with the speed-up. ``python`` is (seconds, units, what was timed); ``compiled(workers)``
    runs the kernel on glamas.parallel.Threads(workers) and returns the same."""
    seconds, count, what = python
    per_unit = seconds / count
    print(f"{label}: plain Python {per_unit * 1e9:8.0f} ns per {unit} ({what}, scaled per {unit})")
    for workers in sorted({1, parallel.cores()}):
        seconds, count, what = compiled(workers)
        print(f"{label}: compiled, {workers} thread(s) {seconds / count * 1e9:6.0f} ns per {unit} ({what})  "
              f"speed-up {per_unit * count / seconds:6.1f}x")


def compare_gridworld(label: str, reference: kernels.Workload, workload: kernels.Workload, n_runs: int) -> None:
    """:func:`compare` per environment step (one joint move with its learning): the Python
    reference on one run of ``reference``, the compiled kernel on ``n_runs`` runs of ``workload``."""
    kernels.run_compiled(dataclasses.replace(workload, episodes=workload.block))  # compiles or loads the kernel
    if reference.learner == "cq":
        reference.t_critical()  # CQ-learning's table, made outside the timing as the kernel's is
    start = time.perf_counter()
    steps = plain_gridworld.steps(plain_gridworld.run(reference, random.Random(0)))
    python = (time.perf_counter() - start, steps, f"1 run x {reference.episodes:,} episodes = {steps:,} steps")

    def compiled(workers):
        out = kernels.run_compiled(workload, 0, n_runs, parallel.Threads(workers))
        return out.seconds, out.steps(), f"{n_runs} runs x {workload.episodes:,} episodes = {out.steps():,.0f} steps"
    compare(label, "step", python, compiled)
