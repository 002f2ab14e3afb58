"""The related-work learners (sparse tabular MAQ and CQ-learning) on TunnelToGoal: the compiled run
kernels against their plain-Python references (glamas.plain.gridworld.sparse_maq and .cq: the
same rules, eq. 11, epsilon-greedy with random tie-breaking, sparse MAQ's four update cases (two
agents' coordination graph is one pair), CQ-learning's phase alone, reward windows, test 1 per
state-action, test 2 per other agent's cell and augmentations; tests/test_benchmark_references.py
checks that they play the kernels' episodes).

The references run fewer episodes (CQ-learning: the same share of episodes alone); both sides are
timed in this process and compared per environment step of the joint phase (one joint move with
its learning; CQ-learning's phase alone is timed on both sides). The compiled kernels are timed
after a warm-up call, on one thread and on all threads.
"""

from benchmarks import kernels, timing
from glamas import errors
from glamas.learners import cq

SIZES = {"full": (2_000, 20_000, 4), "quick": (200, 2_000, 2)}
"""Episodes of the Python run, episodes and runs of the compiled ones."""
SOLO_SHARE = 20
"""CQ-learning's episodes alone per agent: the episodes together / SOLO_SHARE, on both sides."""


def workload(name: str, episodes: int, block: int = 1) -> kernels.Workload:
    own = cq.Settings(cq_solo_episodes=episodes // SOLO_SHARE) if name == "cq" else None
    return kernels.Workload(name, episodes, block=block, own=own)


def main():
    reference_episodes, episodes, n_runs = SIZES["quick" if timing.quick(__doc__) else "full"]
    for name in ("sparse_maq", "cq"):
        timing.compare_gridworld(name, workload(name, reference_episodes), workload(name, episodes, episodes // 100),
                                 n_runs)


if __name__ == "__main__":
    errors.run(main)
