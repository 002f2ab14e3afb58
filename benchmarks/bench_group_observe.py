"""2observe for N agents (glamas.learners.group_observe) on the four-agent warehouse: the compiled
kernel against a plain-Python reference (lists, math, random) of the same episodes.

The reference implements the same N-agent rules (collisions with bounce rounds), eq. 11,
epsilon-greedy with random tie-breaking, the GLAs (eq. 13-15) on the distance to the nearest other
agent, and the group coordination. It runs fewer episodes than the compiled kernel; both sides are
timed in this process and compared per environment step (one joint move with its learning). The
compiled kernel is timed after a warm-up call, on one thread and on all threads.
"""

import random
import sys
import time
from pathlib import Path


sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_gridworld import (ALPHA, EXPLOIT, FEEDBACK, GAMMA, epsilon_greedy, gla_probs,  # noqa: E402,F401
                             gla_update, q_update)

from glamas import runs  # noqa: E402
from glamas.experiments import scaling as sc  # noqa: E402
from glamas.gridworld import load_map  # noqa: E402
from glamas.learners import episode as ep  # noqa: E402
from glamas.paths import MAPS  # noqa: E402

N_AGENTS = 4
REFERENCE_EPISODES = 300
COMPILED_EPISODES, COMPILED_RUNS = 3_000, 4
MAX_STEPS = 1_000  # the scaling study's step cap (bench_gridworld's pieces use the chapter's rates)


class World:
    """The warehouse as lists, with the rules of glamas.gridworld.rules for N agents."""

    def __init__(self):
        g = load_map(MAPS / f"warehouse_{N_AGENTS}.txt")
        self.next_cell = g.next_cell.tolist()
        self.is_goal = g.is_goal.tolist()
        self.starts = g.starts.tolist()
        self.n_cols, self.n_cells = g.n_cols, g.n_cells

    def distance(self, a, b):
        return abs(a // self.n_cols - b // self.n_cols) + abs(a % self.n_cols - b % self.n_cols)

    def would_collide(self, cells, done, actions, i, j):
        if done[i] or done[j]:
            return False
        a, b = self.next_cell[cells[i]][actions[i]], self.next_cell[cells[j]][actions[j]]
        return (a == b and not self.is_goal[a]) or (a == cells[j] and b == cells[i])

    def could_collide(self, cells, done, i, j):
        """2observe's default "need": some joint action of agents i and j collides."""
        return any(self.would_collide(cells, done, {i: a, j: b}, i, j) for a in range(4) for b in range(4))

    def step(self, cells, done, actions):
        n = len(cells)
        new = [c if d else self.next_cell[c][a] for c, d, a in zip(cells, done, actions)]
        rewards = [-1.0 if not done[i] and new[i] == cells[i] else 0.0 for i in range(n)]
        collided = [False] * n
        pairs = [(i, j) for i in range(n) for j in range(i + 1, n) if not done[i] and not done[j]]
        found = [(i, j) for i, j in pairs if (new[i] == new[j] and not self.is_goal[new[i]])
                 or (new[i] == cells[j] and new[j] == cells[i])]
        while found:
            for i, j in found:
                rewards[i] -= 10.0
                rewards[j] -= 10.0
                collided[i] = collided[j] = True
            new = [cells[i] if collided[i] else new[i] for i in range(n)]
            found = [(i, j) for i, j in pairs if new[i] == new[j] and not self.is_goal[new[i]]
                     and not (collided[i] and collided[j])]
        reached = [not done[i] and self.is_goal[new[i]] for i in range(n)]
        for i in range(n):
            if reached[i]:
                rewards[i] += 100.0
        return new, rewards, reached


def nearest(world, cells, done, i):
    others = [(world.distance(cells[i], cells[j]), j) for j in range(len(cells)) if j != i and not done[j]]
    return min(others) if others and not done[i] else (0, None)


def coordinate(world, cells, done, choices, preferred, rnd):
    n = len(cells)
    actions = list(preferred)
    group = [i for i in range(n) if not done[i] and choices[i] == 1 and any(
        j != i and choices[j] == 1 and world.would_collide(cells, done, preferred, i, j) for j in range(n))]
    rnd.shuffle(group)
    kept = []
    for i in group:
        if any(world.would_collide(cells, done, preferred, i, j) for j in kept):
            actions[i] = rnd.choice([a for a in range(4) if a != preferred[i]])
        else:
            kept.append(i)
    return actions


def reference_run(world, episodes, seed=0):
    """One run in plain Python; returns the number of environment steps taken."""
    rnd = random.Random(seed)
    n = len(world.starts)
    q = [[[0.0] * 4 for _ in range(world.n_cells)] for _ in range(n)]
    u = [[[rnd.uniform(-1, 1) for _ in range(2)] for _ in range(2)] for _ in range(n)]
    steps = 0
    for _ in range(episodes):
        cells, done, t = list(world.starts), [False] * n, 0
        while t < MAX_STEPS and not all(done):
            near = [nearest(world, cells, done, i) for i in range(n)]
            xs = [[float(d), 1.0] for d, _ in near]
            probs = [gla_probs(u[i], xs[i]) for i in range(n)]
            choices = [0 if j is None or rnd.random() < probs[i][0] else 1 for i, (_, j) in enumerate(near)]
            preferred = [0 if done[i] else epsilon_greedy(q[i][cells[i]], rnd) for i in range(n)]
            need = [any(world.could_collide(cells, done, i, j) for j in range(n) if j != i)
                    for i in range(n)]
            actions = coordinate(world, cells, done, choices, preferred, rnd)
            new, rewards, reached = world.step(cells, done, actions)
            for i in range(n):
                if not done[i]:
                    q_update(q[i], cells[i], actions[i], rewards[i], new[i], reached[i])
            for i, (delta, j) in enumerate(near):
                if j is not None:
                    both = choices[i] == 1 and choices[j] == 1
                    beta = FEEDBACK[choices[i]][int(need[i])] - (0.1 * delta if both and not need[i] else 0.0)
                    gla_update(u[i], xs[i], choices[i], beta, probs[i])
            t += 1
            done = [done[i] or reached[i] for i in range(n)]
            cells = new
        steps += t
    return steps


def _time_compiled(workers, episodes):
    """Seconds and environment steps (joint moves) of the compiled kernel's runs."""
    config = sc.ScalingConfig(agents=(N_AGENTS,), methods=("two_observe",), episodes=episodes,
                              runs=COMPILED_RUNS, bin_size=100)
    start = time.perf_counter()
    _, log = sc.train(config, config.gridmap(N_AGENTS), "two_observe", 0, runs.Threads(workers))
    elapsed = time.perf_counter() - start
    return elapsed, log[..., ep.column(N_AGENTS, ep.LENGTH)].sum() * config.bin_size


def main():
    world = World()
    _time_compiled(1, 100)  # compile
    start = time.perf_counter()
    steps = reference_run(world, REFERENCE_EPISODES)
    python = (time.perf_counter() - start) / steps
    print(f"2observe, {N_AGENTS} agents: plain Python {python * 1e9:8.0f} ns per step "
          f"(1 run x {REFERENCE_EPISODES:,} episodes = {steps:,} steps, scaled per step)")
    for workers in sorted({1, runs.cores()}):
        elapsed, n = _time_compiled(workers, COMPILED_EPISODES)
        compiled = elapsed / n
        print(f"2observe, {N_AGENTS} agents: compiled, {workers} thread(s) {compiled * 1e9:6.0f} ns per step "
              f"({COMPILED_RUNS} runs x {COMPILED_EPISODES:,} episodes = {n:,.0f} steps)  "
              f"speed-up {python / compiled:6.1f}x")


if __name__ == "__main__":
    main()
