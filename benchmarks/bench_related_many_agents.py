"""Sparse cooperative Q-learning over the coordination graph, its pairwise variant, and CQ-learning
testing every other agent (glamas.learners.sparse_maq, glamas.learners.cq) on the four-agent
warehouse: the compiled run kernels against their plain-Python references
(glamas.plain.gridworld.sparse_maq and .cq: the same N-agent rules, eq. 11, epsilon-greedy
with random tie-breaking, the coordination graph or the pair matching, variable elimination in
groups of three or more, the agent-based update; CQ-learning's phase alone, reward windows, test 1
per state-action, test 2 per other agent's cell and the nearest augmenting agent;
tests/test_benchmark_references.py checks that they play the kernels' episodes).

The references run fewer episodes than the compiled kernels (CQ-learning: the same share of
episodes alone); both sides are timed in this process and compared per environment step of the
joint phase (one joint move with its learning; CQ-learning's phase alone is timed on both sides).
The compiled kernels are timed after a warm-up call, on one thread and on all threads.
"""

from benchmarks import kernels, timing
from benchmarks.bench_related import SOLO_SHARE
from glamas import errors
from glamas.learners import cq

N_AGENTS = 4
MAX_STEPS = 1000
"""The scaling study's step cap (the chapter's rates and its settings otherwise)."""
SIZES = {"full": (300, 3_000, 4), "quick": (30, 300, 2)}
"""Episodes of the Python run, episodes and runs of the compiled ones."""


def workload(name: str, episodes: int, block: int = 1) -> kernels.Workload:
    own = cq.Settings(cq_solo_episodes=episodes // SOLO_SHARE) if name == "cq" else None
    return kernels.Workload(name, episodes, f"warehouse_{N_AGENTS}", block, own, max_steps=MAX_STEPS)


def main():
    reference_episodes, episodes, n_runs = SIZES["quick" if timing.quick(__doc__) else "full"]
    for name in ("sparse_maq", "sparse_maq_pairs", "cq"):
        timing.compare_gridworld(f"{name}, {N_AGENTS} agents", workload(name, reference_episodes),
                                 workload(name, episodes, episodes // 100), n_runs)


if __name__ == "__main__":
    errors.run(main)
