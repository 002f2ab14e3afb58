"""The run backends on one sweep: local processes (joblib, the default), threads and a local
Dask cluster.

The sweep is the Section 5.3 gridworld experiment (all four learners) at a reduced scale. Each
backend runs it twice in this process: the first time includes starting the workers (and their
loading of the cached kernels), the second is the steady state. Every backend's result is
checked bit for bit against the threads result, and the time is printed as a ratio to it.
"""

import dataclasses
import time

import numpy as np

from glamas import errors, parallel
from glamas.experiments import gridworld

SWEEP = gridworld.GridworldConfig(episodes=4_000, runs=16)


def _timed(workers):
    start = time.perf_counter()
    result = gridworld.run(SWEEP, seed=0, workers=workers)
    return time.perf_counter() - start, result


def _same(a, b) -> bool:
    return all(np.array_equal(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a))


def main():
    from distributed import LocalCluster

    print(f"gridworld sweep: {SWEEP.runs} runs x {SWEEP.episodes} episodes x {len(SWEEP.learners)} learners")
    _timed(parallel.Threads())  # compiles (or loads) the kernels
    baseline, reference = _timed(parallel.Threads())
    print(f"threads (all cores): {baseline:6.2f} s")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        for name, workers in [("threads, 1", parallel.Threads(1)), ("processes, 2 (default)", None),
                              ("dask LocalCluster, 2 processes", parallel.Dask(cluster.scheduler_address))]:
            first, result = _timed(workers)
            steady, again = _timed(workers)
            identical = _same(result, reference) and _same(again, reference)
            print(f"{name:>31}: first {first:6.2f} s, then {steady:6.2f} s = {steady / baseline:4.2f} x threads; "
                  f"bit-identical: {identical}")
            if not identical:
                raise SystemExit(f"{name} gave different results")


if __name__ == "__main__":
    errors.run(main)
