"""Sparse tabular MAQ with pairwise coordination and CQ-learning observing the nearest agent
(glamas.learners.sparse_maq.run_pairs, glamas.learners.cq) on the four-agent warehouse: the
compiled run kernels against a plain-Python reference (lists, math, random, collections.deque)
of the same episodes.

The reference implements the same N-agent rules (bench_group_observe.World), eq. 11,
epsilon-greedy with random tie-breaking, the pair matching and the four update cases per pair,
CQ-learning's phase alone, reward windows, t-test (bench_related.lower) and marks on the nearest
agent's cell. It runs fewer episodes than the compiled kernels (CQ-learning: the same share of
episodes alone); both sides are timed in this process and compared per environment step of the
joint phase (one joint move with its learning; CQ-learning's phase alone is timed on both
sides). The compiled kernels are timed after a warm-up call, on one thread and on all threads.
"""

import random
import sys
import time
from collections import deque
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_group_observe import (ALPHA, EXPLOIT, GAMMA, MAX_STEPS, N_AGENTS, World, epsilon_greedy,  # noqa: E402
                                 q_update)
from bench_related import lower  # noqa: E402

from glamas.experiments import scaling as sc  # noqa: E402
from glamas.gridworld import BOUNCE_PREVIOUS  # noqa: E402
from glamas.learners import cq, sparse_maq  # noqa: E402
from glamas.learners import episode as ep  # noqa: E402
from glamas import runs  # noqa: E402

REFERENCE_EPISODES = 300
COMPILED_EPISODES, COMPILED_RUNS = 3_000, 4
SOLO_SHARE = 20  # episodes alone per agent = episodes / SOLO_SHARE on both sides
WINDOW, SIGNIFICANCE, DISTANCE = 30, 0.05, 2


def match(world, index, cells, acting):
    """Pairs closest first (ties: lowest numbers): partner of each agent or None."""
    partner = [None] * len(cells)
    for d in range(1, DISTANCE + 1):
        for i in range(len(cells)):
            for j in range(i + 1, len(cells)):
                if (acting[i] and acting[j] and partner[i] is None and partner[j] is None
                        and world.distance(cells[i], cells[j]) == d
                        and index[cells[i] * world.n_cells + cells[j]] >= 0):
                    partner[i], partner[j] = j, i
    return partner


def sparse_reference(world, index, episodes, seed=0):
    """One run of pairwise sparse tabular MAQ in plain Python; returns the environment steps taken."""
    rnd, n, c = random.Random(seed), len(world.starts), world.n_cells
    q = [[[0.0] * 4 for _ in range(c)] for _ in range(n)]
    q_pairs = {(i, j): [[0.0] * 16 for _ in range(max(index) + 1)] for i in range(n) for j in range(i + 1, n)}

    def row(partner, cells, i):  # the pair table row of agent i and its partner
        lo, hi = min(i, partner[i]), max(i, partner[i])
        return q_pairs[lo, hi][index[cells[lo] * c + cells[hi]]]

    def value(partner, cells, reached, i):
        if reached[i]:
            return 0.0
        return max(q[i][cells[i]]) if partner[i] is None else max(row(partner, cells, i)) / 2

    steps = 0
    for _ in range(episodes):
        cells, done, t = list(world.starts), [False] * n, 0
        while t < MAX_STEPS and not all(done):
            partner = match(world, index, cells, [not d for d in done])
            actions, joint = [0] * n, [0] * n
            for i in range(n):
                if done[i] or (partner[i] is not None and partner[i] < i):
                    continue
                if partner[i] is None:
                    actions[i] = epsilon_greedy(q[i][cells[i]], rnd)
                else:
                    joint[i] = epsilon_greedy(row(partner, cells, i), rnd)
                    actions[i], actions[partner[i]] = divmod(joint[i], 4)
            new, rewards, reached = world.step(cells, done, actions)
            after = match(world, index, new, [not (done[i] or reached[i]) for i in range(n)])
            for i in range(n):
                j = partner[i]
                if done[i] or (j is not None and j < i):
                    continue
                if j is None and after[i] is None:
                    q_update(q[i], cells[i], actions[i], rewards[i], new[i], reached[i])
                elif j is None:
                    old = q[i][cells[i]][actions[i]]
                    share = value(after, new, reached, i)
                    q[i][cells[i]][actions[i]] = old + ALPHA * (rewards[i] + GAMMA * share - old)
                else:
                    target = sum(rewards[m] + GAMMA * value(after, new, reached, m) for m in (i, j))
                    values = row(partner, cells, i)
                    values[joint[i]] += ALPHA * (target - values[joint[i]])
            t += 1
            done = [done[i] or reached[i] for i in range(n)]
            cells = new
        steps += t
    return steps


def nearest(world, cells, done, i):
    """The nearest other acting agent (lowest number on ties), None when alone."""
    others = [(world.distance(cells[i], cells[j]), j) for j in range(len(cells)) if j != i and not done[j]]
    return None if done[i] or not others else min(others)[1]


def cq_reference(world, episodes, t_critical, seed=0):
    """One run of CQ-learning (nearest agent) in plain Python; returns the steps of the joint phase."""
    rnd, n, c = random.Random(seed), len(world.starts), world.n_cells
    q = [[[0.0] * 4 for _ in range(c)] for _ in range(n)]
    windows = [[[deque(maxlen=WINDOW) for _ in range(4)] for _ in range(c)] for _ in range(n)]
    for k in range(n):  # the phase alone: the others count as already in the goal
        for _ in range(episodes // SOLO_SHARE):
            cells, done, t = list(world.starts), [i != k for i in range(n)], 0
            while t < MAX_STEPS and not done[k]:
                s = cells[k]
                a = epsilon_greedy(q[k][s], rnd)
                new, rewards, reached = world.step(cells, done, [a] * n)
                q_update(q[k], s, a, rewards[k], new[k], reached[k])
                windows[k][s][a].append(rewards[k])
                t += 1
                done[k], cells = reached[k], new
    baseline = [[[list(w) for w in row] for row in agent] for agent in windows]
    recent = [[[deque(maxlen=WINDOW) for _ in range(4)] for _ in range(c)] for _ in range(n)]
    q_aug = [{} for _ in range(n)]  # marked (own cell, nearest agent's cell) -> 4 values
    steps = 0
    for _ in range(episodes):
        cells, done, t = list(world.starts), [False] * n, 0
        while t < MAX_STEPS and not all(done):
            near = [nearest(world, cells, done, k) for k in range(n)]
            keys = [None if near[k] is None else (cells[k], cells[near[k]]) for k in range(n)]
            joint = [keys[k] is not None and keys[k] in q_aug[k] for k in range(n)]
            actions = [0 if done[k] else epsilon_greedy(q_aug[k][keys[k]] if joint[k] else q[k][cells[k]], rnd)
                       for k in range(n)]
            new, rewards, reached = world.step(cells, done, actions)
            for k in range(n):
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
                if (keys[k] is not None and len(recent[k][s][a]) == WINDOW and keys[k] not in q_aug[k] and base
                        and rewards[k] < sum(base) / len(base) and lower(base, recent[k][s][a], t_critical)):
                    q_aug[k][keys[k]] = list(q[k][s])
            t += 1
            done = [done[i] or reached[i] for i in range(n)]
            cells = new
        steps += t
    return steps


def compiled(name, workers, episodes, t_critical):
    """Seconds per environment step of the compiled run kernel, and the steps it took."""
    g = sc.ScalingConfig(agents=(N_AGENTS,)).gridmap(N_AGENTS)
    world = (g.next_cell, g.is_goal, g.starts, BOUNCE_PREVIOUS, g.n_cols)
    learning = (ALPHA, GAMMA, EXPLOIT)
    schedule = (episodes, episodes // 100, MAX_STEPS)
    q = np.zeros((COMPILED_RUNS, N_AGENTS, g.n_cells, 4))
    log = np.zeros((COMPILED_RUNS, 100, ep.n_columns(N_AGENTS)))
    threads = runs.Threads(workers)
    if name == "sparse_maq":
        index = sparse_maq.pair_coordination_index(g, DISTANCE)
        q_pairs = np.zeros((COMPILED_RUNS,) + sparse_maq.new_pair_tables(index, N_AGENTS).shape)
        call = lambda: runs.run_batches(sparse_maq.run_pairs, (*world, index, DISTANCE, *learning, *schedule),  # noqa: E731
                                        (q, q_pairs, log), 0, workers=threads)
    else:
        tables = cq.new_augmented_tables(g.n_cells, N_AGENTS)
        q_aug, marked = (np.stack([table] * COMPILED_RUNS) for table in tables)
        extra = (WINDOW, t_critical, episodes // SOLO_SHARE)
        call = lambda: runs.run_batches(cq.run, (*world, *learning, *extra, *schedule), (q, q_aug, marked, log), 0,  # noqa: E731
                                        workers=threads)
    start = time.perf_counter()
    call()
    elapsed = time.perf_counter() - start
    steps = log[..., ep.column(N_AGENTS, ep.LENGTH)].sum() * (episodes // 100)
    return elapsed / steps, steps


def main():
    world = World()
    gridmap = sc.ScalingConfig(agents=(N_AGENTS,)).gridmap(N_AGENTS)
    index = sparse_maq.pair_coordination_index(gridmap, DISTANCE).tolist()
    critical = cq.t_critical_values(2 * WINDOW - 2, SIGNIFICANCE)
    references = {"sparse_maq": lambda: sparse_reference(world, index, REFERENCE_EPISODES),
                  "cq": lambda: cq_reference(world, REFERENCE_EPISODES, critical.tolist())}
    for name, reference in references.items():
        compiled(name, 1, 100, critical)  # compile (or load the cache) before timing
        start = time.perf_counter()
        steps = reference()
        python = (time.perf_counter() - start) / steps
        print(f"{name}, {N_AGENTS} agents: plain Python {python * 1e9:8.0f} ns per step "
              f"(1 run x {REFERENCE_EPISODES:,} episodes = {steps:,} steps, scaled per step)")
        for workers in sorted({1, runs.cores()}):
            seconds, n = compiled(name, workers, COMPILED_EPISODES, critical)
            print(f"{name}, {N_AGENTS} agents: compiled, {workers} thread(s) {seconds * 1e9:6.0f} ns per step "
                  f"({COMPILED_RUNS} runs x {COMPILED_EPISODES:,} episodes = {n:,.0f} steps)  "
                  f"speed-up {python / seconds:6.1f}x")


if __name__ == "__main__":
    main()
