"""The gridworld learners of Section 5.3 (independent, joint-state and MMDP Q-learners, 2observe of
Alg. 4, and its N-agent form for two agents): the compiled run kernels against a plain-C reference
of the same work (``reference_gridworld.c``, built here with ``cc -O2``) and a plain-Python
reference (lists, math, random).

The C reference draws the same random numbers in the same order as the kernels, so a kernel and
the C reference play the very same episodes: their logs must be identical, and this benchmark says
so. They are timed in this process, alternately, on one run each, by the thread's CPU time (other
jobs on a shared machine then count little); the ratio is C time / kernel time, per pair, median
over the pairs: 1 would be the speed of plain C. The Python reference runs fewer episodes with its
own random numbers and is compared per environment step (one joint move with its learning).

The N-agent 2observe (glamas.learners.group_observe) for two agents plays 2observe's steps (its
need counts aside), so it is timed against the 2observe C reference.
"""

import math
import random
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from glamas import rng
from glamas.experiments import gridworld as gw
from glamas.learners import episode as ep
from glamas.learners import group_observe, independent, joint_state, mmdp, two_observe

sys.path.insert(0, str(Path(__file__).parent))
import c_reference  # noqa: E402  (beside this script)

REFERENCE_EPISODES = 1_000
COMPILED_EPISODES, PAIRS = 20_000, 7
ALPHA, GAMMA, EXPLOIT, MAX_STEPS = 0.05, 0.9, 0.9, 10_000
GLA_RATE, T, L = 0.01, 0.5, 8.0
FEEDBACK = ((1.0, 0.0), (0.0, 1.0))
KERNELS = {"independent": independent, "joint_state": joint_state, "mmdp": mmdp,
           "two_observe": two_observe, "group_observe": group_observe}
C_OF = {"group_observe": "two_observe"}
"""The C reference a kernel is timed against, when not its own."""


class World:
    """TunnelToGoal as lists, with the rules of glamas.gridworld.rules for two agents."""

    def __init__(self):
        g = gw.GridworldConfig().gridmap()
        self.next_cell = g.next_cell.tolist()
        self.is_goal = g.is_goal.tolist()
        self.starts = g.starts.tolist()
        self.n_cols = g.n_cols
        self.n_cells = g.n_cells

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
    return rnd.randrange(len(row))


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


class Learner:
    """The plain-Python learners: who acts on which table, and what each learns from a step."""

    def __init__(self, world, name):
        self.world, self.name = world, name
        states = world.n_cells ** (1 if name in ("independent", "two_observe") else 2)
        actions = 16 if name == "mmdp" else 4
        self.q = [[[0.0] * actions for _ in range(states)] for _ in range(1 if name == "mmdp" else 2)]

    def state(self, cells, i):
        return cells[i] if self.name in ("independent", "two_observe") else cells[0] * self.world.n_cells + cells[1]

    def act(self, cells, done, rnd):
        if self.name == "mmdp":
            return list(divmod(epsilon_greedy(self.q[0][self.state(cells, 0)], rnd), 4))
        return [0 if done[i] else epsilon_greedy(self.q[i][self.state(cells, i)], rnd) for i in range(2)]

    def learn(self, cells, done, actions, new, rewards, reached):
        if self.name == "mmdp":
            finished = all(done[i] or reached[i] for i in range(2))
            shared = sum(rewards) - 100.0 * sum(reached) + (100.0 if finished and any(reached) else 0.0)
            q_update(self.q[0], self.state(cells, 0), actions[0] * 4 + actions[1], shared,
                     self.state(new, 0), finished)
            return
        for i in range(2):
            if not done[i]:
                q_update(self.q[i], self.state(cells, i), actions[i], rewards[i], self.state(new, i), reached[i])


def reference_run(world, episodes, name, seed=0):
    """One run in plain Python; returns the number of environment steps taken."""
    rnd = random.Random(seed)
    learner = Learner(world, name)
    two_observe = name == "two_observe"
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
            actions = learner.act(cells, done, rnd)
            if observing:
                coming = world.would_collide(cells, actions)
                need = world.could_collide(cells)
                both = choices[0] == 1 and choices[1] == 1
                if both and coming:
                    yielder = rnd.randrange(2)
                    actions[yielder] = rnd.choice([a for a in range(4) if a != actions[yielder]])
            new, rewards, reached, _ = world.step(cells, done, actions)
            learner.learn(cells, done, actions, new, rewards, reached)
            if observing:
                for i in range(2):
                    beta = FEEDBACK[choices[i]][1 if need else 0] - (0.1 * delta if both and not need else 0.0)
                    gla_update(u[i], x, choices[i], beta, probs[i])
            t += 1
            done = [done[i] or reached[i] for i in range(2)]
            cells = new
        steps += t
    return steps


def _one_run(name, episodes):
    """The kernel's arguments for one run of ``episodes`` episodes: inputs and fresh outputs."""
    learner = C_OF.get(name, name)
    config = gw.GridworldConfig(learners=(learner,), episodes=episodes, runs=1)
    g = config.gridmap()
    q = gw._MODULES[learner].new_tables(g.n_cells, g.n_agents)
    log = np.zeros((config.edges().size - 1, ep.N_COLUMNS))
    if learner == "two_observe":
        outputs = (q, two_observe.new_gla_parameters(2), two_observe.new_need_counts(g.n_rows, g.n_cols), log)
    else:
        outputs = (q, log)
    return gw._kernel_inputs(learner, config, g), outputs, config.edges()


def _timed(run, name, seed):
    inputs, outputs, edges = _one_run(name, COMPILED_EPISODES)
    start = time.thread_time()
    run(*inputs, *outputs, rng.run_states(seed, 1)[0])
    return time.thread_time() - start, outputs[-1], outputs[-1][:, ep.LENGTH] @ np.diff(edges)


def compare_with_c(reference, name):
    """(median C time / kernel time over the pairs, kernel ns per step, logs identical)."""
    kernel, c_run = KERNELS[name].run, reference.run(C_OF.get(name, name))
    ratios, per_step, same = [], [], True
    for pair in range(PAIRS):
        kernel_time, kernel_log, steps = _timed(kernel, name, pair)
        c_time, c_log, _ = _timed(c_run, name, pair)
        ratios.append(c_time / kernel_time)
        per_step.append(kernel_time / steps)
        same = same and np.array_equal(kernel_log, c_log)
    return statistics.median(ratios), statistics.median(per_step), same


def kernel_per_step(name):
    return statistics.median(t / steps for t, _, steps in (_timed(KERNELS[name].run, name, pair) for pair in range(3)))


def main():
    world = World()
    reference = c_reference.load()
    for name in KERNELS:  # compiles (or loads) every kernel in this process first
        inputs, outputs, _ = _one_run(name, 20)
        KERNELS[name].run(*inputs, *outputs, rng.run_states(0, 1)[0])
    print(f"one run of {COMPILED_EPISODES:,} episodes per timing, {PAIRS} kernel / C pairs; "
          f"plain Python: {REFERENCE_EPISODES:,} episodes; times are CPU times of this thread")
    print(f"{'kernel':15s} {'ns/step':>8s} {'speed vs C':>11s} {'same log as C':>14s} {'Python ns/step':>15s} {'speed vs Python':>16s}")
    for name in KERNELS:
        python_name = C_OF.get(name, name)
        start = time.thread_time()
        steps = reference_run(world, REFERENCE_EPISODES, python_name)
        python = (time.thread_time() - start) / steps
        if reference is None:
            per_step, vs_c = kernel_per_step(name), "-"
            same = "-"
        else:
            ratio, per_step, identical = compare_with_c(reference, name)
            vs_c, same = f"{ratio:10.2f}x", ("yes" if identical else "no")
        print(f"{name:15s} {per_step * 1e9:8.1f} {vs_c:>11s} {same:>14s} {python * 1e9:15.0f} {python / per_step:15.0f}x")
    for name, other in C_OF.items():
        print(f"({name}: two agents, against the C and Python references of {other})")


if __name__ == "__main__":
    main()
