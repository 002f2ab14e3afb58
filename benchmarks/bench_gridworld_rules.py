"""Speed of the compiled gridworld rules (glamas.gridworld.rules.step) against plain Python.

Both sides play the same pre-drawn random joint actions on TunnelToGoal, restarting from the
starts whenever both agents are in the goal, and must end with the same totals (rewards,
collisions, episodes): the same work. The plain-Python reference (lists, no NumPy) replays only
the first part of the action sequence; its time is scaled per step.
"""

import time

import numpy as np
from numba import njit

from glamas.gridworld import rules, tunnel_to_goal

N_STEPS = 2_000_000
REFERENCE_STEPS = 200_000


@njit(cache=True)
def compiled_walk(next_cell, is_goal, starts, bounce, actions):
    """Play ``actions`` (n_steps, n_agents) with rules.step; returns total reward, collisions, episodes."""
    n = starts.shape[0]
    cells, done = starts.copy(), np.zeros(n, np.bool_)
    new_cells, rewards = np.empty(n, np.int64), np.empty(n)
    bumped, collided, reached = np.empty(n, np.bool_), np.empty(n, np.bool_), np.empty(n, np.bool_)
    total, collisions, episodes = 0.0, 0, 0
    for t in range(actions.shape[0]):
        collisions += rules.step(next_cell, is_goal, starts, bounce, cells, done, actions[t],
                                 new_cells, rewards, bumped, collided, reached)
        all_done = True
        for i in range(n):
            total += rewards[i]
            cells[i] = new_cells[i]
            done[i] = done[i] or reached[i]
            all_done = all_done and done[i]
        if all_done:
            episodes += 1
            for i in range(n):
                cells[i] = starts[i]
                done[i] = False
    return total, collisions, episodes


def python_step(next_cell, is_goal, cells, done, actions):
    """The rules of glamas.gridworld.rules.step (bounce to the previous cell) in plain Python."""
    n = len(cells)
    new = [cells[i] if done[i] else next_cell[cells[i]][actions[i]] for i in range(n)]
    rewards = [0.0 if done[i] or new[i] != cells[i] else -1.0 for i in range(n)]
    collided = [False] * n
    collisions = 0
    for i in range(n):
        for j in range(i + 1, n):
            if done[i] or done[j]:
                continue
            if (new[i] == new[j] and not is_goal[new[i]]) or (new[i] == cells[j] and new[j] == cells[i]):
                rewards[i] -= 10.0
                rewards[j] -= 10.0
                collided[i] = collided[j] = True
                collisions += 1
    while collisions:
        new = [cells[i] if collided[i] else new[i] for i in range(n)]
        found = 0
        for i in range(n):
            for j in range(i + 1, n):
                if done[i] or done[j] or new[i] != new[j] or is_goal[new[i]] or (collided[i] and collided[j]):
                    continue
                rewards[i] -= 10.0
                rewards[j] -= 10.0
                collided[i] = collided[j] = True
                found += 1
        collisions += found
        if not found:
            break
    reached = [not done[i] and is_goal[new[i]] for i in range(n)]
    for i in range(n):
        if reached[i]:
            rewards[i] += 100.0
    return new, rewards, reached, collisions


def python_walk(next_cell, is_goal, starts, actions):
    cells, done = list(starts), [False] * len(starts)
    total, collisions, episodes = 0.0, 0, 0
    for joint in actions:
        cells, rewards, reached, c = python_step(next_cell, is_goal, cells, done, joint)
        collisions += c
        total += sum(rewards)
        done = [d or r for d, r in zip(done, reached)]
        if all(done):
            episodes += 1
            cells, done = list(starts), [False] * len(starts)
    return total, collisions, episodes


def main():
    gridmap = tunnel_to_goal()
    actions = np.random.default_rng(0).integers(0, rules.N_ACTIONS, size=(N_STEPS, gridmap.n_agents))
    args = (gridmap.next_cell, gridmap.is_goal, gridmap.starts, rules.BOUNCE_PREVIOUS)
    compiled_walk(*args, actions[:10])  # compile (or load the cache) outside the timing

    start = time.perf_counter()
    compiled_walk(*args, actions)
    compiled_time = time.perf_counter() - start

    lists = (gridmap.next_cell.tolist(), gridmap.is_goal.tolist(), gridmap.starts.tolist())
    reference_actions = actions[:REFERENCE_STEPS].tolist()
    start = time.perf_counter()
    reference = python_walk(*lists, reference_actions)
    reference_time = time.perf_counter() - start

    check = compiled_walk(*args, actions[:REFERENCE_STEPS])
    if check != reference:
        raise SystemExit(f"the compiled rules and the reference disagree: {check} vs {reference}")
    compiled_per_step = compiled_time / N_STEPS
    reference_per_step = reference_time / REFERENCE_STEPS
    print("gridworld rules.step, TunnelToGoal, 2 agents, random joint actions")
    print(f"  compiled:     {N_STEPS:>9,} steps in {compiled_time:6.3f} s  ({compiled_per_step * 1e9:7.1f} ns/step)")
    print(f"  plain Python: {REFERENCE_STEPS:>9,} steps in {reference_time:6.3f} s  ({reference_per_step * 1e9:7.1f} ns/step)"
          f"  (fewer steps, compared per step)")
    print(f"  same totals on the reference's steps: reward {reference[0]:.0f}, collisions {reference[1]}, "
          f"episodes {reference[2]}")
    print(f"  speed-up: {reference_per_step / compiled_per_step:.0f}x")


if __name__ == "__main__":
    main()
