"""2observe, the independent Q-learners and 2observe's fixed rule for N = 2 to 1024 agents: the cost
per agent-step (one acting agent's move with its learning) of their compiled run kernels on the
generated warehouses (glamas.gridworld.generate.warehouse(N, seed 0): about 0.1 agents per free
cell at every N), and of a plain-Python reference of the same work at the smallest and the largest
N (glamas.plain.many_agents; it plays the kernels' episodes: tests/test_benchmark_references.py).

Per step, an agent's work in the kernels depends on its neighbours and not on N: the rules and
2observe's group step look agents up through an index of the cells (glamas.gridworld.rules.
step_indexed, glamas.learners.two_observe.group_step), so the cost per agent-step grows with an
agent's neighbours (more of them in range in a crowd), not with N itself. At N = 2 the kernels take
their two-agent paths (rules.step_pair, the pair steps), written for the chapter's two agents; the
ratio of the N = 128 cost to the N = 2 cost compares the N-agent step with them, and is printed as
measured. The ratio of the N = 1024 cost to the N = 32 cost compares the N-agent step with itself
in crowds of one density: the aim is within 1.25x, an agent's cost flat in N. The reference takes
the general step at every N.

Every N plays the scaling study's step cap; small N run more episodes, so that each timing covers
millions of agent-steps (their runs learn longer: the costs compare steps, not learning stages).
Times are CPU times of this thread, medians over runs of different seeds, each without the time of
a run of no steps (the call and the run's tables: an agent's Q table covers every cell, so the
tables of N agents grow as N times the cells, about N squared at one density). CQ-learning and
sparse MAQ are not timed here (``NOT_TIMED``).
"""

import functools
import random
import statistics
import time

from glamas import errors
from glamas.gridworld import generate
from glamas.gridworld.maps import map_text
from glamas.learners import episode as ep

from benchmarks import kernels, timing
from glamas.plain import many_agents as plain_many_agents

LEARNERS = ("two_observe", "independent", "two_observe_rule")
NOT_TIMED = ("cq", "sparse_maq")
"""Their N-agent steps compare pairs of agents as their papers do (CQ-learning tests every other
agent, sparse MAQ builds the coordination graph over all close pairs) and move with the all-pairs
rules (rules.step), so their cost per agent-step grows with N by design; benchmarks/
bench_related_many_agents.py times them against their Python references at four agents."""
AGENTS = (2, 8, 32, 128, 512, 1024)
MAP_SEED = 0
MAX_STEPS = 1000
"""The scaling study's step cap."""
SIZES = {
    "full": {"episodes": {2: 20_000, 8: 1_000, 32: 200, 128: 50, 512: 100, 1024: 50}, "repeats": 3,
             "python": {2: (200, 1000), 128: (1, 1000)}},
    "quick": {"episodes": {2: 500, 8: 50, 32: 10, 128: 2, 512: 1, 1024: 1}, "repeats": 1,
              "python": {2: (20, 1000), 128: (1, 50)}},
}
"""Episodes of a compiled run per N and the runs timed per learner and N; the Python reference's
(episodes, step cap) of its one run per N (the compiled kernel is timed on the same work for the
speed-up)."""


@functools.cache
def warehouse_text(n_agents: int) -> str:
    """The generated warehouse of ``n_agents`` agents, as the text a Workload takes for its map."""
    return map_text(generate.warehouse(n_agents, MAP_SEED))


def workload(learner: str, n_agents: int, episodes: int, max_steps: int = MAX_STEPS,
             bounce: str = "previous") -> kernels.Workload:
    """``learner`` with the experiments' settings on the warehouse of ``n_agents`` agents."""
    return kernels.Workload(learner, episodes, warehouse_text(n_agents), max_steps=max_steps, bounce=bounce)


def agent_steps(log) -> float:
    """Acting agent-steps of a log of blocks of one episode: each agent's steps until it reached
    its goal, or the episode's length when it did not."""
    n_agents = (log.shape[-1] - len(ep.MEASURES)) // 2
    return float(log[..., :n_agents].sum())


def kernel_ns(learner: str, n_agents: int, episodes: int, repeats: int, max_steps: int = MAX_STEPS,
              setup: bool = True) -> tuple:
    """(median ns per agent-step over ``repeats`` runs, agent-steps per run). Without ``setup``,
    the time of a run of no steps (the call and the run's tables) is taken off each run's."""
    work = workload(learner, n_agents, episodes, max_steps)
    fixed = 0.0 if setup else statistics.median(
        kernels.run_compiled(workload(learner, n_agents, 1, max_steps=0), seed).seconds for seed in range(repeats))
    costs, counts = [], []
    for seed in range(repeats):
        out = kernels.run_compiled(work, seed)
        counts.append(agent_steps(out.log))
        costs.append((out.seconds - fixed) / counts[-1] * 1e9)
    return statistics.median(costs), statistics.median(counts)


def python_ns(learner: str, n_agents: int, episodes: int, max_steps: int) -> float:
    """The Python reference's ns per agent-step on one run, by the thread's CPU time, its episodes
    only (not its tables and lists, made before)."""
    work, rnd = workload(learner, n_agents, episodes, max_steps), random.Random(0)
    prepared = plain_many_agents.prepare(work, rnd)
    start = time.thread_time()
    log = plain_many_agents.run(work, rnd, prepared)
    seconds = time.thread_time() - start
    return seconds / sum(sum(row[:n_agents]) for row in log) * 1e9


def main():
    size = SIZES["quick" if timing.quick(__doc__) else "full"]
    for name in LEARNERS:  # compiles (or loads) both kernels of every learner first
        for n in (2, 3):
            kernels.run_compiled(workload(name, n, 1, max_steps=10))
    print(f"ns per agent-step on generate.warehouse(N, seed {MAP_SEED}), step cap {MAX_STEPS}; CPU time of this "
          f"thread without the run's setup (its tables grow as agents x cells), median of {size['repeats']} run(s); "
          "episodes per run: "
          + ", ".join(f"N={n} {e:,}" for n, e in size["episodes"].items()))
    print(f"{'learner':18s}" + "".join(f"{f'N={n}':>9s}" for n in AGENTS) + f"{'128/2':>8s}{'1024/32':>9s}"
          "   agent-steps per run")
    for name in LEARNERS:
        timed = dict(zip(AGENTS, (kernel_ns(name, n, size["episodes"][n], size["repeats"], setup=False)
                                  for n in AGENTS)))
        cost = {n: ns for n, (ns, _) in timed.items()}
        print(f"{name:18s}" + "".join(f"{cost[n]:9.1f}" for n in AGENTS) + f"{cost[128] / cost[2]:7.2f}x"
              f"{cost[1024] / cost[32]:8.2f}x   " + ", ".join(f"{count:,.0f}" for _, count in timed.values()))
    print("aim: 1024/32 within 1.25x (an agent's cost flat in N); 128/2 as measured (the two-agent paths)")
    print(f"{', '.join(NOT_TIMED)}: not timed here (their steps compare pairs of agents; bench_related_many_agents)")
    (small, (e_small, cap_small)), (large, (e_large, cap_large)) = size["python"].items()
    print(f"\nplain Python reference (glamas.plain.many_agents), one run: N={small} {e_small} episodes, "
          f"N={large} {e_large} episode(s) of at most {cap_large} steps; the kernel timed on the same work; "
          "both without the runs' setup")
    print(f"{'learner':18s}{f'N={small}':>9s}{f'N={large}':>9s}{'128/2':>8s}   kernel N={small}, N={large}: "
          "ns per agent-step, speed-up")
    for name in LEARNERS:
        python = [python_ns(name, small, e_small, cap_small), python_ns(name, large, e_large, cap_large)]
        compiled = [kernel_ns(name, small, e_small, 20, cap_small, setup=False)[0],
                    kernel_ns(name, large, e_large, 3, cap_large, setup=False)[0]]
        print(f"{name:18s}{python[0]:9.0f}{python[1]:9.0f}{python[1] / python[0]:7.2f}x   "
              + ", ".join(f"{c:.1f} ({p / c:.0f}x)" for c, p in zip(compiled, python)))


if __name__ == "__main__":
    errors.run(main)
