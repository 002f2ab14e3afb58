"""Speed of the compiled gridworld rules (glamas.gridworld.rules.step) against plain Python
(glamas.plain.gridworld.World.step).

Both sides play the same pre-drawn random joint actions on TunnelToGoal, restarting from the
starts whenever both agents are in the goal, and must end with the same totals (rewards,
collisions, episodes): the same work. The plain-Python reference replays only the first part of
the action sequence; its time is scaled per step.
"""

import time

import numpy as np

from benchmarks import kernels, timing
from glamas.plain import gridworld as plain_gridworld
from glamas import errors
from glamas.gridworld import rules, tunnel_to_goal

SIZES = {"full": (2_000_000, 200_000), "quick": (200_000, 20_000)}
"""Steps of the compiled walk, of the Python one."""


def main():
    n_steps, reference_steps = SIZES["quick" if timing.quick(__doc__) else "full"]
    gridmap = tunnel_to_goal()
    actions = np.random.default_rng(0).integers(0, rules.N_ACTIONS, size=(n_steps, gridmap.n_agents))
    kernels.walk_compiled(gridmap, "previous", actions[:10])  # compile (or load the cache) outside the timing

    start = time.perf_counter()
    kernels.walk_compiled(gridmap, "previous", actions)
    compiled_time = time.perf_counter() - start

    world, reference_actions = plain_gridworld.World(gridmap), actions[:reference_steps].tolist()
    start = time.perf_counter()
    reference = plain_gridworld.walk(world, reference_actions)
    reference_time = time.perf_counter() - start

    check = kernels.walk_compiled(gridmap, "previous", actions[:reference_steps])
    if check != reference:
        raise SystemExit(f"the compiled rules and the reference disagree: {check} vs {reference}")
    compiled_per_step = compiled_time / n_steps
    reference_per_step = reference_time / reference_steps
    print("gridworld rules.step, TunnelToGoal, 2 agents, random joint actions")
    print(f"  compiled:     {n_steps:>9,} steps in {compiled_time:6.3f} s  ({compiled_per_step * 1e9:7.1f} ns/step)")
    print(f"  plain Python: {reference_steps:>9,} steps in {reference_time:6.3f} s  ({reference_per_step * 1e9:7.1f} ns/step)"
          f"  (fewer steps, compared per step)")
    print(f"  same totals on the reference's steps: reward {reference[0]:.0f}, collisions {reference[1]}, "
          f"episodes {reference[2]}")
    print(f"  speed-up: {reference_per_step / compiled_per_step:.0f}x")


if __name__ == "__main__":
    errors.run(main)
