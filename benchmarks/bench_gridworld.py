"""The gridworld learners of Section 5.3 (independent Q-learners and 2observe, Alg. 4): the
compiled run kernels against a plain-Python reference (lists, math, random) of the same episodes.

The reference implements the same rules, eq. 11, epsilon-greedy with random tie-breaking and, for
2observe, the GLAs (eq. 13-15) and the coordination mechanism. It runs fewer episodes; both sides
are timed in this process and compared per environment step (one joint move with its learning).
The compiled kernels are timed after a warm-up call, on one thread and on all threads.
"""

import math
import random
import time

from glamas import runs
from glamas.experiments import gridworld as gw
from glamas.learners import episode as ep

REFERENCE_EPISODES = 2_000
COMPILED_EPISODES, COMPILED_RUNS = 20_000, 4
ALPHA, GAMMA, EXPLOIT, MAX_STEPS = 0.05, 0.9, 0.9, 10_000
GLA_RATE, T, L = 0.01, 0.5, 8.0
FEEDBACK = ((1.0, 0.0), (0.0, 1.0))


class World:
    """TunnelToGoal as lists, with the rules of glamas.gridworld.rules for two agents."""

    def __init__(self):
        g = gw.GridworldConfig().gridmap()
        self.next_cell = g.next_cell.tolist()
        self.is_goal = g.is_goal.tolist()
        self.starts = g.starts.tolist()
        self.n_cols = g.n_cols

    def step(self, cells, done, actions):
        new = [c if d else self.next_cell[c][a] for c, d, a in zip(cells, done, actions)]
        rewards = [-1.0 if not done[i] and new[i] == cells[i] else 0.0 for i in range(2)]  # bumps
        collided = (not done[0] and not done[1]) and (
            (new[0] == new[1] and not self.is_goal[new[0]]) or (new[0] == cells[1] and new[1] == cells[0]))
        if collided:
            new = list(cells)
            rewards = [r - 10.0 for r in rewards]
        reached = [not done[i] and self.is_goal[new[i]] for i in range(2)]
        for i in range(2):
            if reached[i]:
                rewards[i] += 100.0
        return new, rewards, reached, int(collided)

    def would_collide(self, cells, actions):
        a, b = self.next_cell[cells[0]][actions[0]], self.next_cell[cells[1]][actions[1]]
        return (a == b and not self.is_goal[a]) or (a == cells[1] and b == cells[0])

    def could_collide(self, cells):
        """2observe's default "need": some joint action of the two agents collides."""
        return any(self.would_collide(cells, (a, b)) for a in range(4) for b in range(4))


def epsilon_greedy(row, rnd):
    if rnd.random() < EXPLOIT:
        best = max(row)
        return rnd.choice([a for a, v in enumerate(row) if v == best])
    return rnd.randrange(4)


def q_update(q, s, a, r, s_next, terminal):
    target = r if terminal else r + GAMMA * max(q[s_next])
    q[s][a] = (1 - ALPHA) * q[s][a] + ALPHA * target


def gla_probs(u, x):
    z = [sum(x[k] * max(-L, min(L, u[j][k])) for k in range(2)) / T for j in range(2)]
    top = max(z)
    e = [math.exp(v - top) for v in z]
    return [v / sum(e) for v in e]


def gla_update(u, x, action, beta, probs):
    for j in range(2):
        indicator = 1.0 if j == action else 0.0
        for k in range(2):
            h = max(-L, min(L, u[j][k]))
            u[j][k] += GLA_RATE * beta * x[k] / T * (indicator - probs[j]) + GLA_RATE * (h - u[j][k])


def reference_run(world, episodes, two_observe, seed=0):
    """One run in plain Python; returns the number of environment steps taken."""
    rnd = random.Random(seed)
    q = [[[0.0] * 4 for _ in range(25)] for _ in range(2)]
    u = [[[rnd.uniform(-1, 1) for _ in range(2)] for _ in range(2)] for _ in range(2)]
    steps = 0
    for _ in range(episodes):
        cells, done, t = list(world.starts), [False, False], 0
        while t < MAX_STEPS and not all(done):
            observing = two_observe and not any(done)
            if observing:
                delta = abs(cells[0] // world.n_cols - cells[1] // world.n_cols) + abs(cells[0] % world.n_cols - cells[1] % world.n_cols)
                x = [float(delta), 1.0]
                probs = [gla_probs(u[i], x) for i in range(2)]
                choices = [0 if rnd.random() < p[0] else 1 for p in probs]
            actions = [0 if done[i] else epsilon_greedy(q[i][cells[i]], rnd) for i in range(2)]
            if observing:
                coming = world.would_collide(cells, actions)
                need = world.could_collide(cells)
                both = choices[0] == 1 and choices[1] == 1
                if both and coming:
                    yielder = rnd.randrange(2)
                    actions[yielder] = rnd.choice([a for a in range(4) if a != actions[yielder]])
            new, rewards, reached, _ = world.step(cells, done, actions)
            for i in range(2):
                if not done[i]:
                    q_update(q[i], cells[i], actions[i], rewards[i], new[i], reached[i])
            if observing:
                for i in range(2):
                    beta = FEEDBACK[choices[i]][1 if need else 0] - (0.1 * delta if both and not need else 0.0)
                    gla_update(u[i], x, choices[i], beta, probs[i])
            t += 1
            done = [done[i] or reached[i] for i in range(2)]
            cells = new
        steps += t
    return steps


def _time_compiled(learner, workers):
    config = gw.GridworldConfig(learners=(learner,), episodes=COMPILED_EPISODES, runs=COMPILED_RUNS)
    start = time.perf_counter()
    result = gw.run(config, seed=0, workers=runs.Threads(workers))
    elapsed = time.perf_counter() - start
    steps = result.curves(learner, ep.LENGTH).sum(axis=0) @ result.widths()
    return elapsed / steps, steps


def main():
    world = World()
    for learner in ("independent", "two_observe"):
        gw.run(gw.GridworldConfig(learners=(learner,), episodes=100, runs=2), seed=0,
               workers=runs.Threads(1))  # compiles (or loads) the kernel in this process
        start = time.perf_counter()
        steps = reference_run(world, REFERENCE_EPISODES, learner == "two_observe")
        python = (time.perf_counter() - start) / steps
        print(f"{learner}: plain Python {python * 1e9:8.0f} ns per step "
              f"(1 run x {REFERENCE_EPISODES:,} episodes = {steps:,} steps, scaled per step)")
        for workers in sorted({1, runs.cores()}):
            compiled, n = _time_compiled(learner, workers)
            print(f"{learner}: compiled, {workers} thread(s) {compiled * 1e9:6.0f} ns per step "
                  f"({COMPILED_RUNS} runs x {COMPILED_EPISODES:,} episodes = {n:,.0f} steps)  "
                  f"speed-up {python / compiled:6.1f}x")


if __name__ == "__main__":
    main()
