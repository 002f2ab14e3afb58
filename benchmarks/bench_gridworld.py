"""The gridworld learners of Section 5.3 (independent, joint-state and MMDP Q-learners, 2observe of
Alg. 4): the compiled run kernels against a plain-C reference
of the same work (``reference_gridworld.c``, built here with ``cc -O2``) and their plain-Python
references (glamas.plain.gridworld).

The C reference draws the same random numbers in the same order as the kernels, so a kernel and
the C reference play the very same episodes: their logs must be identical, and this benchmark says
so. They are timed in this process, alternately, on one run each, by the thread's CPU time (other
jobs on a shared machine then count little); the ratio is C time / kernel time, per pair, median
over the pairs: 1 would be the speed of plain C. The Python references (which play the kernels'
episodes on the kernels' stream: tests/test_benchmark_references.py) run fewer episodes with
random.Random and are compared per environment step (one joint move with its learning).
"""

import random
import statistics
import time

import numpy as np

from benchmarks import c_reference, kernels, timing
from glamas.plain import gridworld as plain_gridworld
from glamas import errors

LEARNERS = ("independent", "joint_state", "mmdp", "two_observe")
SIZES = {"full": (1_000, 20_000, 7), "quick": (100, 2_000, 3)}
"""Episodes of the Python run, episodes of each compiled and C run, kernel / C pairs."""


def workload(name: str, episodes: int) -> kernels.Workload:
    """One run of TunnelToGoal with the chapter's settings, logged in 100 blocks."""
    return kernels.Workload(name, episodes, block=episodes // 100)


def compare_with_c(reference, name: str, episodes: int, pairs: int):
    """(median C time / kernel time over the pairs, kernel seconds per step, logs identical)."""
    compiled = workload(name, episodes)
    ratios, per_step, same = [], [], True
    for seed in range(pairs):
        kernel, c = kernels.run_compiled(compiled, seed), reference.run(compiled, seed)
        ratios.append(c.seconds / kernel.seconds)
        per_step.append(kernel.seconds / kernel.steps())
        same = same and np.array_equal(kernel.log, c.log)
    return statistics.median(ratios), statistics.median(per_step), same


def kernel_per_step(name: str, episodes: int) -> float:
    """Median kernel seconds per step over three runs (where there is no C reference)."""
    timed = (kernels.run_compiled(workload(name, episodes), seed) for seed in range(3))
    return statistics.median(out.seconds / out.steps() for out in timed)


def python_per_step(name: str, episodes: int) -> float:
    """The Python reference's seconds per step on one run, by the thread's CPU time."""
    reference = kernels.Workload(name, episodes)
    start = time.thread_time()
    steps = plain_gridworld.steps(plain_gridworld.run(reference, random.Random(0)))
    return (time.thread_time() - start) / steps


def main():
    python_episodes, episodes, pairs = SIZES["quick" if timing.quick(__doc__) else "full"]
    reference = c_reference.load()
    for name in LEARNERS:  # compiles (or loads) every kernel in this process first
        kernels.run_compiled(workload(name, 100))
    print(f"one run of {episodes:,} episodes per timing, {pairs} kernel / C pairs; "
          f"plain Python: {python_episodes:,} episodes; times are CPU times of this thread")
    print(f"{'kernel':15s} {'ns/step':>8s} {'speed vs C':>11s} {'same log as C':>14s} {'Python ns/step':>15s} {'speed vs Python':>16s}")
    for name in LEARNERS:
        python = python_per_step(name, python_episodes)
        if reference is None:
            per_step, vs_c, same = kernel_per_step(name, episodes), "-", "-"
        else:
            ratio, per_step, identical = compare_with_c(reference, name, episodes, pairs)
            vs_c, same = f"{ratio:10.2f}x", ("yes" if identical else "no")
        print(f"{name:15s} {per_step * 1e9:8.1f} {vs_c:>11s} {same:>14s} {python * 1e9:15.0f} {python / per_step:15.0f}x")


if __name__ == "__main__":
    errors.run(main)
