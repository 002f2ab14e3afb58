"""Experiment 1's learning loop (Section 4.2, eq. 12-15, joint context): the compiled run kernel
against its plain-Python reference (glamas.plain.lineworld.single_gla_run; tests/
test_benchmark_references.py checks that it learns the kernel's parameters).

The reference runs fewer iterations; both are timed in this process and compared per iteration of
one run (both agents acting and learning once). The compiled kernel is timed after a warm-up call,
on one thread and on all threads.
"""

import random
import time

from benchmarks import timing
from glamas.plain import lineworld as plain_lineworld
from glamas import errors, parallel
from glamas.experiments.single_gla import SingleGLAConfig, run

SIZES = {"full": (20_000, SingleGLAConfig(runs=8, iterations=100_000)),
         "quick": (2_000, SingleGLAConfig(runs=2, iterations=10_000))}
"""Iterations of the Python run, the compiled runs."""


def main():
    reference_iterations, compiled = SIZES["quick" if timing.quick(__doc__) else "full"]
    run(SingleGLAConfig(runs=2, iterations=1000, record_points=10), seed=0,
        workers=parallel.Threads(1))  # compiles (or loads) the kernel in this process
    reference = SingleGLAConfig(runs=1, iterations=reference_iterations)
    start = time.perf_counter()
    plain_lineworld.single_gla_run(reference, random.Random(0))
    python = (time.perf_counter() - start, reference_iterations, f"1 run x {reference_iterations:,} iterations")

    def timed(workers):
        start = time.perf_counter()
        run(compiled, seed=0, workers=parallel.Threads(workers))
        return (time.perf_counter() - start, compiled.runs * compiled.iterations,
                f"{compiled.runs} runs x {compiled.iterations:,} iterations")
    timing.compare("experiment 1", "iteration", python, timed)


if __name__ == "__main__":
    errors.run(main)
