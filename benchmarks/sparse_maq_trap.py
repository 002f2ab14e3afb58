"""The trap of sparse MAQ on the warehouses: for the coordination-graph learner (``sparse_maq``) and
the pairwise variant (``sparse_maq_pairs``) at N = 2..6 agents (data/maps/warehouse_N.txt, the
scaling study's step cap of 1000), both from the same master seed (sparse MAQ's: with two agents
the two learners are the same, and give the same numbers), the share of episodes that hit the cap
(all of them and the last tenth), the agents trapped at the end (their mean steps in the last
tenth at least 90 % of the cap), and from the final tables what the values on the aisle hold: the
cells of the one-track aisle to the goal (walls above and below), each agent's own values there
(the share exactly 0; the mean over the aisle of its best value, for the trapped agents and the
others) and the pairs' joint values in the coordination states of two agents both in the aisle
(the share exactly 0, the largest).

    python -m benchmarks.sparse_maq_trap [--runs 4] [--episodes 20000] [--workers 2] [--seed 0]
"""

import argparse

import numpy as np

from glamas import cli, errors, parallel
from glamas.experiments import gridworld, scaling
from glamas.learners import registry, sparse_maq

LEARNERS = ("sparse_maq", "sparse_maq_pairs")
AGENTS = (2, 3, 4, 5, 6)


def aisle_rows(setup, gridmap, cells) -> np.ndarray:
    """The pairs' joint-table rows of two agents both on ``cells``."""
    index = sparse_maq.coordination_index(gridmap, setup.own.coordination_distance)
    rows = [index[a * gridmap.n_cells + b] for a in cells for b in cells if a != b]
    return np.array([r for r in rows if r >= 0], dtype=np.int64)


def measure(name: str, n: int, runs: int, episodes: int, seed: int, workers) -> dict:
    """The trap (glamas.experiments.scaling.trap) of learner ``name`` with N = ``n`` from sparse MAQ's
    master seed, and the pairs' joint values on the aisle."""
    t = scaling.trap(name, n, runs, episodes, workers=workers, master_seed=gridworld.seed_of(seed, "sparse_maq"))
    gridmap = scaling.ScalingConfig().gridmap(n)
    joint = t["outputs"]["q_pairs"][:, :, aisle_rows(registry.get(name).setup(), gridmap,
                                                     scaling.aisle_cells(gridmap)), :]
    return {**t, "joint_zero": (joint == 0.0).mean() if joint.size else float("nan"),
            "joint_max": joint.max() if joint.size else float("nan")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=cli.positive_count, default=4, help="runs per learner and N (default 4)")
    parser.add_argument("--episodes", type=cli.positive_count, default=20_000,
                        help="episodes per run, a multiple of 10 (default 20,000)")
    parser.add_argument("--workers", type=cli.positive_count, default=2, help="threads (default 2)")
    parser.add_argument("--seed", type=cli.seed_number, default=0, help="master seed (default 0)")
    args = parser.parse_args()
    scaling.check_trap(args.runs, args.episodes)
    print(f"{args.runs} runs x {args.episodes:,} episodes, step cap {scaling.ScalingConfig.max_steps}; last: the last tenth of the episodes")
    print(f"{'learner':17} N  capped  (last)  trapped agents  aisle own =0  best: trapped  free"
          f"  joint =0    max")
    for n in AGENTS:
        for name in LEARNERS:
            m = measure(name, n, args.runs, args.episodes, args.seed, parallel.Threads(args.workers))
            print(f"{name:17} {n}  {m['capped']:6.3f}  {m['capped_last']:6.3f}  {m['trapped']:7d} of {m['agents']:3d}"
                  f"  {m['aisle_zero']:12.3f}  {m['best_trapped']:13.1f}  {m['best_free']:4.1f}"
                  f"  {m['joint_zero']:8.3f}  {m['joint_max']:5.1f}", flush=True)


if __name__ == "__main__":
    errors.run(main)
