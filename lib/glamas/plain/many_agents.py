"""Plain-Python references of the N-agent steps through the index of cells (lists, dicts and loops;
no NumPy, nothing compiled): the rules of glamas.gridworld.rules.step_indexed, and the N-agent
step of the independent Q-learners and of 2observe (glamas.learners.two_observe.group_step, with
its GLAs or the fixed rule), each agent looking at its neighbours only: the nearest other agent
ring by ring, coming collisions among the agents aiming at its target or standing on it, "in
range" on the cells in range of its own.

They do the kernels' work in the kernels' order and draw the kernels' random numbers (the helpers
of glamas.plain.gridworld: eq. 11, epsilon-greedy with random tie-breaking, the GLAs of eq.
13-15 with 'clip' bounding, need 'in_range', delta in cells: the experiments' settings), so on the
kernel's stream they play the kernel's very episodes (tests/test_benchmark_references.py). They
take the general step whenever agents act, also when one or two do, where the kernels take their
one- and two-agent paths (rules.step_alone, rules.step_pair, the pair steps): the outcomes are the
same, so the reference's cost per agent-step measures the index's work at every number of agents
(benchmarks.bench_many_agents).

:func:`run` returns the log the kernel writes with blocks of one episode (glamas.plain.gridworld.play).
"""

from glamas.errors import UserError
from glamas.gridworld import rules
from glamas.gridworld.rewards import CHAPTER
from glamas.gridworld.rules import N_ACTIONS

from glamas.plain.gridworld import (
    COORDINATE,
    Automata,
    World,
    below,
    epsilon_greedy,
    learn_own_cells,
    play,
    tables,
    yield_action,
)

NOBODY = -1


class IndexedWorld(World):
    """A map as lists with the rules of N agents through an index of cells (rules.step_indexed),
    and what the group step looks up around an agent: the rings of cells at each distance, the
    cells in range of each cell."""

    def __init__(self, gridmap, bounce="previous", rewards=CHAPTER):
        super().__init__(gridmap, bounce, rewards)
        self.n_rows = gridmap.n_rows
        self.occupant = [NOBODY] * self.n_cells  # the acting agents by cell during a step
        first, near = rules.in_range_lists(gridmap.next_cell, gridmap.shared_goal)
        first, near = first.tolist(), near.tolist()
        self.in_range = [near[first[a]:first[a + 1]] for a in range(self.n_cells)]
        self.reach = max((self.distance(a, b) for a in range(self.n_cells) for b in self.in_range[a]), default=0)

    def index(self, cells, done, actions):
        """Enter the acting agents by cell (``occupant``) and by the cell they aim at: a dict
        target -> agents in increasing order (rules.index_agents)."""
        aiming = {}
        for i, (cell, is_done) in enumerate(zip(cells, done)):
            if not is_done:
                self.occupant[cell] = i
                aiming.setdefault(self.next_cell[cell][actions[i]], []).append(i)
        return aiming

    def clear(self, cells, done):
        for cell, is_done in zip(cells, done):
            if not is_done:
                self.occupant[cell] = NOBODY

    def step(self, cells, done, actions):
        """One joint move of any number of agents through the index (rules.step_indexed): (new
        cells, rewards, reached, collisions)."""
        n = len(cells)
        new = [c if d else self.next_cell[c][a] for c, d, a in zip(cells, done, actions)]
        rewards = [self.move_reward(c, d, m) for c, d, m in zip(cells, done, new)]
        aiming = self.index(cells, done, actions)
        collided, queue, back = [False] * n, [], self.bounced(cells)
        collisions = 0

        def collide(i, j):
            rewards[i] += self.rewards.collision
            rewards[j] += self.rewards.collision
            for k in (i, j):
                if not collided[k]:
                    collided[k] = True
                    queue.append(k)

        for i in range(n):  # first round: the agents aiming at one cell, and swaps
            if done[i]:
                continue
            target = new[i]
            for j in aiming[target]:
                if j >= i:
                    break
                if not self.both_goal(i, j, target):
                    collisions += 1
                    collide(i, j)
            j = self.occupant[target]
            if j > i and new[j] == cells[i]:
                collisions += 1
                collide(i, j)
        first = 0
        while first < len(queue):  # later rounds: bounced agents onto agents that have not collided
            last = len(queue)
            for a in queue[first:last]:
                new[a] = back[a]
            for a in queue[first:last]:
                cell = new[a]
                for b in aiming.get(cell, ()):
                    if not collided[b] and not self.both_goal(a, b, cell):
                        collisions += 1
                        collide(a, b)
            first = last
        self.clear(cells, done)
        reached = [not d and m in self.goals[i] for i, (d, m) in enumerate(zip(done, new))]
        settled = [self.settle(r, hit, arrived) for r, hit, arrived in zip(rewards, collided, reached)]
        return new, settled, reached, collisions

    def nearest(self, cells, acting, i):
        """(nearest other acting agent, its distance) of acting agent i, the lowest number among
        equals, with ``occupant`` filled (two_observe.nearest_other): ring by ring while the rings
        cover fewer cells than there are acting agents, then the acting agents one by one."""
        row, col = divmod(cells[i], self.n_cols)
        covered, d = 0, 1
        while covered < len(acting) and d <= self.n_rows + self.n_cols - 2:
            found = [self.occupant[r * self.n_cols + c] for r, c in self.ring(row, col, d)]
            found = [j for j in found if j != NOBODY]
            if found:
                return min(found), d
            covered += 4 * d
            d += 1
        return min((self.distance(cells[i], cells[j]), j) for j in acting if j != i)[::-1]

    def ring(self, row, col, d):
        """The cells (row, col) of the map at distance d from (row, col)."""
        for r in range(max(row - d, 0), min(row + d, self.n_rows - 1) + 1):
            rest = d - abs(r - row)
            for c in ((col - rest, col + rest) if rest else (col,)):
                if 0 <= c < self.n_cols:
                    yield r, c

    def in_range_of_any(self, cells, i, delta):
        """Some other acting agent on a cell in range of i's (``occupant`` filled; none beyond reach)."""
        return delta <= self.reach and any(self.occupant[b] != NOBODY for b in self.in_range[cells[i]])

    def conflict(self, cells, done, preferred, aiming, i, among):
        """i's preferred action would collide with that of an agent j with ``among[j]``: the agents
        aiming at i's target and the one on it are tried (``aiming`` and ``occupant`` of the
        preferred actions)."""
        target = self.next_cell[cells[i]][preferred[i]]
        candidates = aiming.get(target, []) + [self.occupant[target]]
        return any(j != NOBODY and j != i and among[j] and self.would_collide(cells, done, preferred, i, j)
                   for j in candidates)


def independent(world, workload, rnd):
    """The independent Q-learners for any number of agents (independent.episodes)."""
    q_settings, n = workload.q, len(world.starts)
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(n, world.n_cells, N_ACTIONS)

    def step(cells, done):
        actions = [0 if done[i] else epsilon_greedy(q[i][cells[i]], exploit, rnd) for i in range(n)]
        new, rewards, reached, collisions = world.step(cells, done, actions)
        learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma)
        return new, rewards, reached, collisions, 0
    return step


def coordinate_group(world, cells, done, choices, preferred, aiming, rnd):
    """two_observe.coordinate_group through the index: the coordinating agents in a coming
    collision with another coordinating agent, in a random order; each keeps its preferred action
    unless it would collide with an earlier one that kept its own."""
    n = len(cells)
    coordinating = [not done[i] and choices[i] == COORDINATE for i in range(n)]
    order = [i for i in range(n) if coordinating[i] and world.conflict(cells, done, preferred, aiming, i, coordinating)]
    for k in range(len(order) - 1, 0, -1):  # Durstenfeld's shuffle, from the back
        m = below(rnd, k + 1)
        order[k], order[m] = order[m], order[k]
    actions, kept = list(preferred), [False] * n
    for i in order:
        if world.conflict(cells, done, preferred, aiming, i, kept):
            actions[i] = yield_action(preferred[i], rnd)
        else:
            kept[i] = True
    return actions


def two_observe(world, workload, rnd):
    """2observe for any number of agents (two_observe.group_step), with its GLAs or, when the
    settings give ``rule_distance``, the fixed rule (the GLAs drawn, as the kernel draws them, and
    not used)."""
    (q_settings, c), n = workload.setup(), len(world.starts)
    if c.gla_need != "in_range" or c.gla_delta_scale != "cells" or c.gla_bounding != "clip":
        raise UserError("the plain N-agent step of 2observe plays the experiments' settings only (need "
                        "'in_range', delta in cells, 'clip' bounds)")
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(n, world.n_cells, N_ACTIONS)
    glas = Automata(c, world.gridmap, rnd)
    rule = c.rule_distance

    def step(cells, done):
        acting = [i for i in range(n) if not done[i]]
        for i in acting:
            world.occupant[cells[i]] = i
        near = [None] * n  # (distance, nearest other agent) of every agent that has one
        needs, xs, acted = [False] * n, [None] * n, [(0, None)] * n
        for i in acting if len(acting) > 1 else ():
            j, delta = world.nearest(cells, acting, i)
            near[i] = delta, j
            needs[i] = world.in_range_of_any(cells, i, delta)
            xs[i] = [float(delta), 1.0]
            acted[i] = glas.act(i, xs[i]) if rule is None else (COORDINATE if delta < rule else 0, None)
        choices = [choice for choice, _ in acted]
        preferred = [0 if done[i] else epsilon_greedy(q[i][cells[i]], exploit, rnd) for i in range(n)]
        world.clear(cells, done)
        aiming = world.index(cells, done, preferred)
        actions = coordinate_group(world, cells, done, choices, preferred, aiming, rnd)
        world.clear(cells, done)
        both = [seen is not None and choices[i] == COORDINATE and choices[seen[1]] == COORDINATE
                for i, seen in enumerate(near)]
        new, rewards, reached, collisions = world.step(cells, done, actions)
        learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma)
        for i, seen in enumerate(near):
            if seen is not None and rule is None:
                glas.learn(i, xs[i], choices[i], acted[i][1], needs[i], both[i], seen[0])
        return new, rewards, reached, collisions, sum(both) / 2
    return step


REFERENCES = {"independent": independent, "two_observe": two_observe, "two_observe_rule": two_observe}
"""The learners with a reference here, by registry name. CQ-learning and sparse MAQ have
all-pairs references in glamas.plain.gridworld; theirs go here once their kernels step
through the index."""


def prepare(workload, rnd):
    """The run's world and its step (tables, GLAs drawn from ``rnd``, the index's lists): what
    :func:`run` does before the episodes."""
    world = IndexedWorld(workload.gridmap(), workload.bounce, workload.rewards)
    return world, REFERENCES[workload.learner](world, workload, rnd)


def run(workload, rnd, prepared=None):
    """One run of the workload's learner in plain Python, drawing from ``rnd``: its log, a row per
    episode. ``prepared``: :func:`prepare`'s, made beforehand (with the same ``rnd``)."""
    world, step = prepare(workload, rnd) if prepared is None else prepared
    return play(world, workload.episodes, workload.max_steps, step)
