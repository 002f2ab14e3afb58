"""Experiment 1's learning loop (Section 4.2, eq. 12-15, joint context): the compiled run
kernel against a plain-Python reference (lists, math, random) doing the same work.

The reference runs fewer iterations; both are timed in this process and compared per
iteration of one run (both agents acting and learning once). The compiled kernel is timed
after a warm-up call, on one thread and on all threads.
"""

import math
import random
import time

from glamas import runs
from glamas.experiments import single_gla

REFERENCE_ITERATIONS = 20_000
COMPILED = single_gla.SingleGLAConfig(runs=8, iterations=100_000)


def _bound(eta, L):
    return max(-L, min(L, eta))  # h of eq. 14, 'clip'


def _best_action(x1, x2, agent):
    if abs(x1 - x2) < 0.5:
        a_is_left = x1 < x2
        return (0 if a_is_left else 1) if agent == 0 else (1 if a_is_left else 0)
    return 0 if x1 < x2 else 1


def reference_run(iterations, learning_rate=0.01, temperature=0.5, K=1.0, L=1.0, seed=0):
    """One run of experiment 1 in plain Python: returns the total feedback."""
    rnd = random.Random(seed)
    u = [[[0.0] * 3 for _ in range(2)] for _ in range(2)]  # agent, action, input
    total = 0.0
    for _ in range(iterations):
        x = [2.0 * rnd.random() - 1.0, 2.0 * rnd.random() - 1.0, 1.0]
        actions, probs = [], []
        for agent in range(2):
            z = [sum(x[k] * _bound(u[agent][i][k], L) for k in range(3)) / temperature for i in range(2)]
            top = max(z)
            e = [math.exp(v - top) for v in z]
            p = [v / sum(e) for v in e]
            actions.append(0 if rnd.random() < p[0] else 1)
            probs.append(p)
        rewarded = all(actions[agent] == _best_action(x[0], x[1], agent) for agent in range(2))
        beta = 1.0 if rewarded else 0.0
        total += beta
        for agent in range(2):
            for j in range(2):
                indicator = 1.0 if j == actions[agent] else 0.0
                for k in range(3):
                    gradient = x[k] / temperature * (indicator - probs[agent][j])
                    h = _bound(u[agent][j][k], L)
                    u[agent][j][k] += learning_rate * beta * gradient + learning_rate * K * (h - u[agent][j][k])
    return total


def _time_compiled(workers):
    start = time.perf_counter()
    single_gla.run(COMPILED, seed=0, workers=runs.Threads(workers))
    return (time.perf_counter() - start) / (COMPILED.runs * COMPILED.iterations)


def main():
    single_gla.run(single_gla.SingleGLAConfig(runs=2, iterations=1000, record_points=10), seed=0,
                   workers=runs.Threads(1))  # compiles (or loads) the kernel in this process
    start = time.perf_counter()
    reference_run(REFERENCE_ITERATIONS)
    python_per_iteration = (time.perf_counter() - start) / REFERENCE_ITERATIONS
    print(f"plain Python : {python_per_iteration * 1e9:10.0f} ns per iteration "
          f"(1 run x {REFERENCE_ITERATIONS:,} iterations, scaled per iteration)")
    for workers in sorted({1, runs.cores()}):
        compiled = _time_compiled(workers)
        print(f"compiled, {workers} thread(s): {compiled * 1e9:7.0f} ns per iteration "
              f"({COMPILED.runs} runs x {COMPILED.iterations:,} iterations)  "
              f"speed-up {python_per_iteration / compiled:6.1f}x")


if __name__ == "__main__":
    main()
