"""Every kernel compiled into numba's cache at once, one process per core:
``python -m glamas.precompile`` (``make test`` runs it before the tests).

numba compiles a kernel the first time it runs with new types of arguments, some for ten seconds
and more (the kernels of N agents of 2observe and of sparse MAQ), and keeps it in its cache
(:mod:`glamas.sources` keeps the cache in step with the code). Processes that start at once, as
the test workers do, each compile the kernels they meet first, often the same ones; here each is
compiled once and every later process loads it. The tasks run what the experiments run, so that
the types are theirs: first every learner's kernels (one run of one episode on Fig. 9's map and on
a warehouse of three agents; learners that share a kernel in one task, so that no two processes
compile it at once), the largest first; then every stored experiment's small run
(:mod:`glamas.small_runs`, the longest first by its ``small_run_seconds``), which compiles what is
left (Section 4's learning loops, the exact optimum, the generated maps' paths). Those small runs are the portability check of
``tests/test_portable_results.py``: with ``--check`` their digests are compared with the committed
ones here, and ``make test`` leaves that test out of its pytest session instead of running them twice.
"""

import argparse
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor

from glamas import errors

TWO_AGENTS, N_AGENTS = "tunnel_to_goal", "warehouse_3"
"""The maps a learner's kernels are compiled on: the chapter's two agents, and a warehouse of three."""
COMPILE_SECONDS = {"two_observe": 24, "sparse_maq": 20, "cq": 7, "independent": 5, "mmdp": 4, "joint_state": 4}
"""About how long each learner's kernels took to compile on one core of the machine glamas is
developed on: the order in which the tasks are handed out (the longest first, so that no process
is left with a long one at the end). A learner not listed counts as 10 s."""
def learner_groups() -> list[tuple]:
    """The registered learners grouped by the kernels they run (a group is compiled by one
    process), the longest to compile first (:data:`COMPILE_SECONDS`)."""
    from glamas.learners import registry

    groups: dict = {}
    for name, learner in registry.LEARNERS.items():
        groups.setdefault((learner.kernel, learner.two_agent_kernel), []).append(name)
    return sorted((tuple(names) for names in groups.values()),
                  key=lambda names: -max(COMPILE_SECONDS.get(name, 10) for name in names))


def compile_learners(names: tuple) -> str:
    """Run each learner of ``names`` for one episode of one run on both maps."""
    from glamas.gridworld import load_map
    from glamas.learners import episode as ep
    from glamas import training
    from glamas.learners import registry

    for name in names:
        learner = registry.get(name)
        for map_name in (N_AGENTS, TWO_AGENTS):
            gridmap = load_map(map_name)
            training.train(learner, learner.setup(), gridmap, ep.Schedule(1, ep.log_edges(1, 1), 10), 1, 0, workers=1)
    return ", ".join(names)


def compile_experiment(name: str) -> str:
    """Experiment ``name``'s small run: its digest (:func:`glamas.small_runs.small_digest`)."""
    from glamas import small_runs

    return small_runs.small_digest(name, workers=1)


def precompile(workers: int | None = None) -> tuple[float, dict]:
    """Compile every kernel (module docstring) on ``workers`` processes (default: one per core);
    returns the seconds it took and the small runs' digests by experiment."""
    from glamas import small_runs
    from glamas.parallel import cores

    start = time.perf_counter()
    context = multiprocessing.get_context("spawn")  # fresh interpreters, as the test workers are
    with ProcessPoolExecutor(workers or cores(), mp_context=context) as pool:
        for future in [pool.submit(compile_learners, names) for names in learner_groups()]:
            future.result()
        names = list(small_runs.sizes())
        longest_first = sorted(names, key=lambda name: -small_runs.experiment_named(name).small_run_seconds)
        digests = {name: pool.submit(compile_experiment, name) for name in longest_first}
        digests = {name: digests[name].result() for name in names}
    return time.perf_counter() - start, digests


def main(argv=None) -> int:
    from glamas import small_runs

    parser = argparse.ArgumentParser(prog="python -m glamas.precompile",
                                     description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--workers", type=int, default=None, help="processes (default: one per core)")
    parser.add_argument("--check", action="store_true",
                        help=f"compare the small runs' digests with {small_runs.DIGESTS.name} (exit status 1 if any differs)")
    args = parser.parse_args(argv)
    seconds, digests = precompile(args.workers)
    print(f"precompile: every kernel in numba's cache ({seconds:.0f} s)")
    return small_runs.report(digests) if args.check else 0


if __name__ == "__main__":
    errors.run(main)
