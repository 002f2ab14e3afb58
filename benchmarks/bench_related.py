"""The related-work learners (sparse tabular MAQ and CQ-learning): the compiled run kernels
against a plain-Python reference (lists, math, random, collections.deque) of the same episodes.

The reference implements the same rules (bench_gridworld.World), eq. 11, epsilon-greedy with
random tie-breaking, sparse MAQ's four update cases and CQ-learning's phase alone, reward windows,
t-test and marks. It runs fewer episodes (CQ-learning: the same share of episodes alone); both
sides are timed in this process and compared per environment step of the joint phase (one joint
move with its learning). The compiled kernels are timed after a warm-up call, on one thread and on
all threads.
"""

import math
import random
import sys
import time
from collections import deque
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_gridworld import ALPHA, EXPLOIT, GAMMA, MAX_STEPS, World, epsilon_greedy, q_update  # noqa: E402

from glamas.gridworld import BOUNCE_PREVIOUS, tunnel_to_goal  # noqa: E402
from glamas.learners import cq, sparse_maq  # noqa: E402
from glamas.learners import episode as ep  # noqa: E402
from glamas import runs  # noqa: E402

REFERENCE_EPISODES = 2_000
COMPILED_EPISODES, COMPILED_RUNS = 20_000, 4
SOLO_SHARE = 20  # episodes alone per agent = episodes / SOLO_SHARE on both sides
WINDOW, SIGNIFICANCE = 30, 0.05


def sparse_reference(world, index, episodes, seed=0):
    """One run of sparse tabular MAQ in plain Python; returns the environment steps taken."""
    rnd = random.Random(seed)
    q = [[[0.0] * 4 for _ in range(25)] for _ in range(2)]
    q_joint = [[0.0] * 16 for _ in range(max(index) + 1)]
    steps = 0
    for _ in range(episodes):
        cells, done, t = list(world.starts), [False, False], 0
        while t < MAX_STEPS and not all(done):
            k = index[cells[0] * 25 + cells[1]]
            if k >= 0:
                joint = epsilon_greedy(q_joint[k], rnd)
                actions = [joint // 4, joint % 4]
            else:
                actions = [0 if done[i] else epsilon_greedy(q[i][cells[i]], rnd) for i in range(2)]
            new, rewards, reached, _ = world.step(cells, done, actions)
            k_next = index[new[0] * 25 + new[1]]
            if k >= 0 and k_next >= 0:
                q_joint[k][joint] += ALPHA * (sum(rewards) + GAMMA * max(q_joint[k_next]) - q_joint[k][joint])
            elif k >= 0:
                target = sum(rewards[i] + (0.0 if reached[i] else GAMMA * max(q[i][new[i]])) for i in range(2))
                q_joint[k][joint] += ALPHA * (target - q_joint[k][joint])
            elif k_next >= 0:
                for i in range(2):
                    old = q[i][cells[i]][actions[i]]
                    q[i][cells[i]][actions[i]] = old + ALPHA * (rewards[i] + GAMMA * max(q_joint[k_next]) / 2 - old)
            else:
                for i in range(2):
                    if not done[i]:
                        q_update(q[i], cells[i], actions[i], rewards[i], new[i], reached[i])
            t += 1
            done = [done[i] or reached[i] for i in range(2)]
            cells = new
        steps += t
    return steps


def lower(baseline, recent, t_critical):
    """Student's two-sample t-test with pooled variance: recent mean significantly below baseline."""
    n1, n2 = len(baseline), len(recent)
    m1, m2 = sum(baseline) / n1, sum(recent) / n2
    if n1 + n2 < 3 or m2 >= m1:
        return False
    squares = sum((r - m1) ** 2 for r in baseline) + sum((r - m2) ** 2 for r in recent)
    spread = squares / (n1 + n2 - 2) * (1 / n1 + 1 / n2)
    return spread <= 0 or (m1 - m2) / math.sqrt(spread) > t_critical[n1 + n2 - 2]


def cq_reference(world, episodes, t_critical, seed=0):
    """One run of CQ-learning in plain Python; returns the environment steps of the joint phase."""
    rnd = random.Random(seed)
    q = [[[0.0] * 4 for _ in range(25)] for _ in range(2)]
    windows = [[[deque(maxlen=WINDOW) for _ in range(4)] for _ in range(25)] for _ in range(2)]
    for k in range(2):  # the phase alone: the other agent counts as already in the goal
        for _ in range(episodes // SOLO_SHARE):
            cells, done, t = list(world.starts), [i != k for i in range(2)], 0
            while t < MAX_STEPS and not done[k]:
                s = cells[k]
                a = epsilon_greedy(q[k][s], rnd)
                new, rewards, reached, _ = world.step(cells, done, [a, a])
                q_update(q[k], s, a, rewards[k], new[k], reached[k])
                windows[k][s][a].append(rewards[k])
                t += 1
                done[k], cells = reached[k], new
    baseline = [[[list(w) for w in row] for row in agent] for agent in windows]
    recent = [[[deque(maxlen=WINDOW) for _ in range(4)] for _ in range(25)] for _ in range(2)]
    q_aug = [{}, {}]  # marked (own cell, other's cell) -> 4 values
    steps = 0
    for _ in range(episodes):
        cells, done, t = list(world.starts), [False, False], 0
        while t < MAX_STEPS and not all(done):
            together = not any(done)
            keys = [(cells[k], cells[1 - k]) for k in range(2)]
            joint = [together and keys[k] in q_aug[k] for k in range(2)]
            actions = [0 if done[k] else epsilon_greedy(q_aug[k][keys[k]] if joint[k] else q[k][cells[k]], rnd)
                       for k in range(2)]
            new, rewards, reached, _ = world.step(cells, done, actions)
            for k in range(2):
                if done[k]:
                    continue
                s, a = cells[k], actions[k]
                if joint[k]:
                    target = rewards[k] + (0.0 if reached[k] else GAMMA * max(q[k][new[k]]))
                    q_aug[k][keys[k]][a] += ALPHA * (target - q_aug[k][keys[k]][a])
                else:
                    q_update(q[k], s, a, rewards[k], new[k], reached[k])
                recent[k][s][a].append(rewards[k])
                base = baseline[k][s][a]
                if (together and len(recent[k][s][a]) == WINDOW and keys[k] not in q_aug[k] and base
                        and rewards[k] < sum(base) / len(base) and lower(base, recent[k][s][a], t_critical)):
                    q_aug[k][keys[k]] = list(q[k][s])
            t += 1
            done = [done[i] or reached[i] for i in range(2)]
            cells = new
        steps += t
    return steps


def compiled(name, workers):
    """Seconds per environment step of the compiled run kernel, and the steps it took."""
    g = tunnel_to_goal()
    world = (g.next_cell, g.is_goal, g.starts, BOUNCE_PREVIOUS)
    learning = (ALPHA, GAMMA, EXPLOIT)
    schedule = (COMPILED_EPISODES, COMPILED_EPISODES // 100, MAX_STEPS)
    q = np.zeros((COMPILED_RUNS, 2, 25, 4))
    log = np.zeros((COMPILED_RUNS, 100, ep.N_COLUMNS))
    threads = runs.Threads(workers)
    if name == "sparse_maq":
        index = sparse_maq.coordination_index(g, 2)
        q_joint = np.zeros((COMPILED_RUNS,) + sparse_maq.new_joint_table(index).shape)
        call = lambda: runs.run_batches(sparse_maq.run, (*world, index, *learning, *schedule),  # noqa: E731
                                        (q, q_joint, log), 0, workers=threads)
    else:
        q_aug, marked = (np.stack([table] * COMPILED_RUNS) for table in cq.new_augmented_tables(25, 2))
        extra = (WINDOW, cq.t_critical_values(2 * WINDOW - 2, SIGNIFICANCE), COMPILED_EPISODES // SOLO_SHARE)
        call = lambda: runs.run_batches(cq.run, (*world, g.n_cols, *learning, *extra, *schedule),  # noqa: E731
                                        (q, q_aug, marked, log), 0, workers=threads)
    start = time.perf_counter()
    call()
    elapsed = time.perf_counter() - start
    steps = log[:, :, ep.LENGTH].sum() * (COMPILED_EPISODES // 100)
    return elapsed / steps, steps


def main():
    world = World()
    index = sparse_maq.coordination_index(tunnel_to_goal(), 2).tolist()
    t_critical = cq.t_critical_values(2 * WINDOW - 2, SIGNIFICANCE).tolist()
    references = {"sparse_maq": lambda: sparse_reference(world, index, REFERENCE_EPISODES),
                  "cq": lambda: cq_reference(world, REFERENCE_EPISODES, t_critical)}
    for name, reference in references.items():
        compiled(name, 1)  # compile (or load the cache) before timing
        start = time.perf_counter()
        steps = reference()
        python = (time.perf_counter() - start) / steps
        print(f"{name}: plain Python {python * 1e9:8.0f} ns per step "
              f"(1 run x {REFERENCE_EPISODES:,} episodes = {steps:,} steps, scaled per step)")
        for workers in sorted({1, runs.cores()}):
            seconds, n = compiled(name, workers)
            print(f"{name}: compiled, {workers} thread(s) {seconds * 1e9:6.0f} ns per step "
                  f"({COMPILED_RUNS} runs x {COMPILED_EPISODES:,} episodes = {n:,.0f} steps)  "
                  f"speed-up {python / seconds:6.1f}x")


if __name__ == "__main__":
    main()
