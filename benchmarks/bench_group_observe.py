"""2observe for N agents (glamas.learners.two_observe.run, its group_step) on the four-agent warehouse: the
compiled kernel against its plain-Python reference (glamas.plain.gridworld.two_observe_group: the same
N-agent rules with bounce rounds, eq. 11, epsilon-greedy with random tie-breaking, the GLAs of eq.
13-15 on the distance to the nearest other agent, the group coordination; tests/
test_benchmark_references.py checks that it plays the kernel's episodes).

The reference runs fewer episodes than the compiled kernel; both sides are timed in this process
and compared per environment step (one joint move with its learning). The compiled kernel is timed
after a warm-up call, on one thread and on all threads.
"""

from benchmarks import kernels, timing
from glamas import errors

N_AGENTS = 4
MAX_STEPS = 1000
"""The scaling study's step cap (the chapter's rates and 2observe's settings otherwise)."""
SIZES = {"full": (300, 3_000, 4), "quick": (30, 300, 2)}
"""Episodes of the Python run, episodes and runs of the compiled ones."""


def main():
    reference_episodes, episodes, n_runs = SIZES["quick" if timing.quick(__doc__) else "full"]
    map_name = f"warehouse_{N_AGENTS}"
    timing.compare_gridworld(
        f"2observe, {N_AGENTS} agents",
        kernels.Workload("two_observe", reference_episodes, map_name, max_steps=MAX_STEPS),
        kernels.Workload("two_observe", episodes, map_name, block=episodes // 100, max_steps=MAX_STEPS), n_runs)


if __name__ == "__main__":
    errors.run(main)
