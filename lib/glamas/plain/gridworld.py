"""The gridworld learners step by step in plain Python (lists, loops and one random source; no
NumPy, nothing compiled): the rules of glamas.gridworld.rules under any reward formulation
(glamas.gridworld.rewards), eq. 11 with epsilon-greedy and
random tie-breaking, the GLAs of eq. 13-15 ('clip' bounding, need 'in_range', delta in cells: the
experiments' settings), 2observe (Alg. 4) and its N-agent form, sparse tabular MAQ and
CQ-learning.

Each learner's step does what its compiled kernel does, step for step: it draws the same random numbers
in the same order (``rnd.random()`` for a uniform in [0, 1), :func:`below` for glamas.rng.integer)
and does the same arithmetic in the same order. Given a stream equal to the kernel's (the tests
drive it with glamas.rng's xoshiro256** in Python) it plays the kernel's very episodes; the
benchmarks drive it with ``random.Random``. :func:`run` returns the log the kernel writes with
blocks of one episode: a row per episode in the columns of glamas.learners.episode.
"""

import math

from glamas.errors import UserError
from glamas.gridworld.rewards import CHAPTER
from glamas.gridworld.rules import N_ACTIONS
from glamas.learners.two_observe import box
from glamas.plain import gla as plain_gla

COORDINATE = 1
"""The GLA action "coordinate" of 2observe (0: act alone)."""


def below(rnd, n):
    """An integer in [0, n) from one uniform draw, as glamas.rng.integer."""
    return min(int(rnd.random() * n), n - 1)


class World:
    """A map as lists, with the rules of glamas.gridworld.rules: ``step`` for any number of
    agents (rules.step), ``step_two`` for two (rules.step_pair, the learners' two-agent path).
    Each agent has its own goals (``goals[i]``, a set of cells); agents entering a goal of both
    together do not collide."""

    def __init__(self, gridmap, bounce="previous", rewards=CHAPTER):
        self.gridmap, self.rewards = gridmap, rewards
        self.next_cell = gridmap.next_cell.tolist()
        self.goals = [set(gridmap.goal_cells(i)) for i in range(gridmap.n_agents)]
        self.shared_goal = gridmap.shared_goal.tolist()
        self.usable = (~(gridmap.shared_goal | gridmap.blocked)).tolist()
        self.starts = gridmap.starts.tolist()
        self.n_cols, self.n_cells = gridmap.n_cols, gridmap.n_cells
        self.bounce_to_start = bounce == "start"

    def distance(self, a, b):
        return abs(a // self.n_cols - b // self.n_cols) + abs(a % self.n_cols - b % self.n_cols)

    def move_reward(self, cell, done, new):
        """What an acting agent's move pays before collisions and the goal (rules.moved)."""
        return 0.0 if done else self.rewards.bump if new == cell else self.rewards.move

    def settle(self, reward, hit, arrived):
        """An acting agent's reward for the step (rules.settle): the collision's alone if it collided
        and a collision replaces the move's reward, plus the goal's if it arrived."""
        if hit and self.rewards.collision_replaces_move:
            reward = self.rewards.collision
        return reward + self.rewards.goal if arrived else reward

    def bounced(self, cells):
        """Where collided agents go: their start cells or the cells they came from."""
        return self.starts if self.bounce_to_start else cells

    def both_goal(self, i, j, cell):
        """Whether ``cell`` is a goal of agent i and of agent j: entering it together is no collision."""
        return cell in self.goals[i] and cell in self.goals[j]

    def would_collide(self, cells, done, actions, i, j):
        """Whether acting agents i and j playing ``actions`` target one cell (a goal of not both) or swap."""
        if done[i] or done[j]:
            return False
        a, b = self.next_cell[cells[i]][actions[i]], self.next_cell[cells[j]][actions[j]]
        return (a == b and not self.both_goal(i, j, a)) or (a == cells[j] and b == cells[i])

    def in_range_table(self):
        """rules.in_range_table: ``table[a][b]``, whether agents on cells a and b could collide in
        one step (entering a goal of every agent together is none), made once per run as the
        kernels make it."""
        def could_collide(a, b):
            return any((ta == tb and not self.shared_goal[ta]) or (ta == b and tb == a)
                       for ta in self.next_cell[a] for tb in self.next_cell[b])
        return [[could_collide(a, b) for b in range(self.n_cells)] for a in range(self.n_cells)]

    def step_two(self, cells, done, actions):
        """One joint move of two agents: (new cells, rewards, reached, collisions)."""
        (c0, c1), (d0, d1) = cells, done
        new0 = c0 if d0 else self.next_cell[c0][actions[0]]
        new1 = c1 if d1 else self.next_cell[c1][actions[1]]
        r0, r1 = self.move_reward(c0, d0, new0), self.move_reward(c1, d1, new1)
        hit = not d0 and not d1 and ((new0 == new1 and not self.both_goal(0, 1, new0)) or (new0 == c1 and new1 == c0))
        if hit:
            r0 += self.rewards.collision
            r1 += self.rewards.collision
            new0, new1 = self.bounced(cells)
        reached = [not d0 and new0 in self.goals[0], not d1 and new1 in self.goals[1]]
        return [new0, new1], [self.settle(r0, hit, reached[0]), self.settle(r1, hit, reached[1])], reached, int(hit)

    def step(self, cells, done, actions):
        """One joint move of any number of agents, bounce rounds included (rules.step)."""
        n = len(cells)
        new = [c if d else self.next_cell[c][a] for c, d, a in zip(cells, done, actions)]
        rewards = [self.move_reward(c, d, m) for c, d, m in zip(cells, done, new)]
        pairs = [(i, j) for i in range(n) for j in range(i + 1, n) if not done[i] and not done[j]]
        found = [(i, j) for i, j in pairs if (new[i] == new[j] and not self.both_goal(i, j, new[i]))
                 or (new[i] == cells[j] and new[j] == cells[i])]
        collided, collisions, back = [False] * n, 0, self.bounced(cells)
        while found:  # bounced agents may land where another agent now is
            for i, j in found:
                rewards[i] += self.rewards.collision
                rewards[j] += self.rewards.collision
                collided[i] = collided[j] = True
            collisions += len(found)
            new = [back[i] if collided[i] else new[i] for i in range(n)]
            found = [(i, j) for i, j in pairs if new[i] == new[j] and not self.both_goal(i, j, new[i])
                     and not (collided[i] and collided[j])]
        reached = [not d and m in self.goals[i] for i, (d, m) in enumerate(zip(done, new))]
        settled = [self.settle(r, hit, arrived) for r, hit, arrived in zip(rewards, collided, reached)]
        return new, settled, reached, collisions


def walk(world, actions):
    """Play the joint ``actions`` with World.step, restarting from the starts whenever every agent
    is in the goal: (total reward, collisions, episodes), as kernels.walk_compiled."""
    n = len(world.starts)
    cells, done = list(world.starts), [False] * n
    total, collisions, episodes = 0.0, 0, 0
    for joint in actions:
        cells, rewards, reached, hits = world.step(cells, done, joint)
        collisions += hits
        for r in rewards:
            total += r
        done = [d or r for d, r in zip(done, reached)]
        if all(done):
            episodes += 1
            cells, done = list(world.starts), [False] * n
    return total, collisions, episodes


# --- Q-learning (eq. 11) and 2observe's GLAs --------------------------------------------------

def tables(count, states, actions):
    return [[[0.0] * actions for _ in range(states)] for _ in range(count)]


def epsilon_greedy(row, exploit, rnd):
    """glamas.qlearning.epsilon_greedy: greedy with probability ``exploit`` (a draw only on a tie),
    else a uniform action."""
    if rnd.random() < exploit:
        best = max(row)
        ties = row.count(best)
        pick = 0 if ties == 1 else below(rnd, ties)
        return [a for a, v in enumerate(row) if v == best][pick]
    return below(rnd, len(row))


def q_update(q, s, a, r, s_next, terminal, alpha, gamma):
    """Eq. 11 (no successor term after entering the goal)."""
    target = r if terminal else r + gamma * max(q[s_next])
    q[s][a] = (1.0 - alpha) * q[s][a] + alpha * target


def learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma):
    """Eq. 11 for every acting agent on its own cell's table."""
    for i in range(len(cells)):
        if not done[i]:
            q_update(q[i], cells[i], actions[i], rewards[i], new[i], reached[i], alpha, gamma)


def gla_feedback(table, penalty_per_cell, choice, need, both, delta):
    """r_c of Alg. 4 as glamas.learners.two_observe.gla_feedback."""
    beta = table[choice][1 if need else 0]
    if both and not need:
        beta -= penalty_per_cell * delta
    return beta


class Automata:
    """The agents' GLAs of 2observe with the workload's settings, initialised from ``rnd``."""

    def __init__(self, settings, gridmap, rnd):
        c, self.rnd = settings, rnd
        self.u = [[[c.gla_init_range * (2.0 * rnd.random() - 1.0) for _ in range(2)] for _ in range(2)]
                  for _ in range(gridmap.n_agents)]
        self.rate, self.temperature, self.K = c.gla_learning_rate, c.gla_temperature, c.gla_K
        self.L = box(c, gridmap)
        self.feedback, self.penalty = c.gla_feedback, c.coordination_penalty_per_cell

    def act(self, i, x):
        """(choice, probabilities) of agent i's GLA in context x."""
        return plain_gla.act(self.u[i], x, self.temperature, self.L, self.rnd)

    def learn(self, i, x, choice, probs, need, both, delta):
        beta = gla_feedback(self.feedback, self.penalty, choice, need, both, delta)
        plain_gla.update(self.u[i], x, choice, beta, probs, self.rate, self.temperature, self.K, self.L)


def yield_action(preferred, rnd):
    """A uniform draw from the three actions other than ``preferred`` (one draw)."""
    other = below(rnd, 3)
    return other + 1 if other >= preferred else other


def nearest_others(world, cells, done):
    """For every agent: (distance, number) of the nearest other acting agent (lowest number on
    ties), None when it is done or alone."""
    n = len(cells)
    return [None if done[i] or all(done[j] for j in range(n) if j != i)
            else min((world.distance(cells[i], cells[j]), j) for j in range(n) if j != i and not done[j])
            for i in range(n)]


# --- the learners: each returns the step of one joint move with its learning ------------------------

def independent(world, workload, rnd):
    q_settings = workload.q
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(2, world.n_cells, N_ACTIONS)

    def step(cells, done):
        actions = [0 if done[i] else epsilon_greedy(q[i][cells[i]], exploit, rnd) for i in range(2)]
        new, rewards, reached, collisions = world.step_two(cells, done, actions)
        learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma)
        return new, rewards, reached, collisions, 0
    return step


def joint_state(world, workload, rnd):
    q_settings, n_cells = workload.q, world.n_cells
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(2, n_cells ** 2, N_ACTIONS)

    def step(cells, done):
        s = cells[0] * n_cells + cells[1]
        actions = [0 if done[i] else epsilon_greedy(q[i][s], exploit, rnd) for i in range(2)]
        new, rewards, reached, collisions = world.step_two(cells, done, actions)
        s_next = new[0] * n_cells + new[1]
        for i in range(2):
            if not done[i]:
                q_update(q[i], s, actions[i], rewards[i], s_next, reached[i], alpha, gamma)
        return new, rewards, reached, collisions, 0
    return step


def shared_reward(goal, rewards, reached, finished):
    """The MMDP learner's reward (rules.shared_reward): the agents' rewards summed without their
    goal's reward ``goal``, which is paid once when the last agent enters its goal."""
    total, arrived = 0.0, False
    for r, entered in zip(rewards, reached):
        total += r
        if entered:
            total -= goal
            arrived = True
    if finished and arrived:
        total += goal
    return total


def mmdp(world, workload, rnd):
    q_settings, n_cells = workload.q, world.n_cells
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = [[0.0] * N_ACTIONS ** 2 for _ in range(n_cells ** 2)]

    def step(cells, done):
        s = cells[0] * n_cells + cells[1]
        joint = epsilon_greedy(q[s], exploit, rnd)
        actions = [joint // N_ACTIONS, joint % N_ACTIONS]
        new, rewards, reached, collisions = world.step_two(cells, done, actions)
        finished = all(done[i] or reached[i] for i in range(2))
        shared = shared_reward(world.rewards.goal, rewards, reached, finished)
        q_update(q, s, joint, shared, new[0] * n_cells + new[1], finished, alpha, gamma)
        return new, rewards, reached, collisions, 0
    return step


def two_observe(world, workload, rnd):
    """Alg. 4: two agents as glamas.learners.two_observe.pair_step, more as group_step."""
    if len(world.starts) != 2:
        return two_observe_group(world, workload, rnd)
    q_settings, c = workload.setup()
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(2, world.n_cells, N_ACTIONS)
    glas = Automata(c, world.gridmap, rnd)
    in_range = world.in_range_table()

    def step(cells, done):
        if done[0] or done[1]:  # nobody to observe: Q alone, the GLAs do not learn
            actions = [0 if done[i] else epsilon_greedy(q[i][cells[i]], exploit, rnd) for i in range(2)]
            new, rewards, reached, collisions = world.step_two(cells, done, actions)
            learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma)
            return new, rewards, reached, collisions, 0
        delta = world.distance(cells[0], cells[1])
        x = [float(delta), 1.0]
        (choice0, probs0), (choice1, probs1) = glas.act(0, x), glas.act(1, x)
        preferred = [epsilon_greedy(q[i][cells[i]], exploit, rnd) for i in range(2)]
        both = choice0 == COORDINATE and choice1 == COORDINATE
        actions = list(preferred)
        if both and world.would_collide(cells, done, preferred, 0, 1):  # one of them, at random, yields
            yielder = below(rnd, 2)
            actions[yielder] = yield_action(preferred[yielder], rnd)
        need = in_range[cells[0]][cells[1]]
        new, rewards, reached, collisions = world.step_two(cells, done, actions)
        learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma)
        glas.learn(0, x, choice0, probs0, need, both, delta)
        glas.learn(1, x, choice1, probs1, need, both, delta)
        return new, rewards, reached, collisions, int(both)
    return step


def coordinate_group(world, cells, done, choices, preferred, rnd):
    """The group coordination of glamas.learners.two_observe.coordinate_group: the coordinating agents in a coming
    collision with another coordinating agent go in a random order; each keeps its preferred
    action unless it would collide with an earlier one that kept its own."""
    n = len(cells)
    order = [i for i in range(n) if not done[i] and choices[i] == COORDINATE and any(
        j != i and choices[j] == COORDINATE and world.would_collide(cells, done, preferred, i, j)
        for j in range(n))]
    for k in range(len(order) - 1, 0, -1):  # Durstenfeld's shuffle, from the back
        m = below(rnd, k + 1)
        order[k], order[m] = order[m], order[k]
    actions, kept = list(preferred), []
    for i in order:
        if any(world.would_collide(cells, done, preferred, i, j) for j in kept):
            actions[i] = yield_action(preferred[i], rnd)
        else:
            kept.append(i)
    return actions


def two_observe_group(world, workload, rnd):
    """2observe for N agents (glamas.learners.two_observe.group_step)."""
    (q_settings, c), n = workload.setup(), len(world.starts)
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(n, world.n_cells, N_ACTIONS)
    glas = Automata(c, world.gridmap, rnd)
    in_range = world.in_range_table()

    def step(cells, done):
        near = nearest_others(world, cells, done)
        xs = [None if seen is None else [float(seen[0]), 1.0] for seen in near]
        acted = [(0, None) if x is None else glas.act(i, x) for i, x in enumerate(xs)]
        choices = [choice for choice, _ in acted]
        preferred = [0 if done[i] else epsilon_greedy(q[i][cells[i]], exploit, rnd) for i in range(n)]
        actions = coordinate_group(world, cells, done, choices, preferred, rnd)
        both = [seen is not None and choices[i] == COORDINATE and choices[seen[1]] == COORDINATE
                for i, seen in enumerate(near)]
        needs = [any(j != i and not done[j] and in_range[cells[i]][cells[j]] for j in range(n)) for i in range(n)]
        new, rewards, reached, collisions = world.step(cells, done, actions)
        learn_own_cells(q, cells, done, actions, rewards, new, reached, alpha, gamma)
        for i, seen in enumerate(near):
            if seen is not None:
                glas.learn(i, xs[i], choices[i], acted[i][1], needs[i], both[i], seen[0])
        return new, rewards, reached, collisions, sum(both) / 2
    return step


# --- sparse cooperative Q-learning (glamas.learners.sparse_maq) ----------------------------------

def coordination_states(world, distance):
    """The joint states (a, b) of two agents in which they coordinate: distinct usable cells (not
    blocked, not a goal of every agent) at Manhattan distance at most ``distance``."""
    usable = [a for a in range(world.n_cells) if world.usable[a]]
    return [(a, b) for a in usable for b in usable if a != b and world.distance(a, b) <= distance]


def close_pairs(states, cells, acting):
    """The coordination graph's edges: every pair of acting agents i < j in a coordination state,
    in (i, j) order (coordination_graph.close_pairs)."""
    n = len(cells)
    return [(i, j) for i in range(n) for j in range(i + 1, n)
            if acting[i] and acting[j] and (cells[i], cells[j]) in states]


def matched_pairs(world, states, distance, cells, acting):
    """The pairwise variant's edges: pairs matched closest first (ties: lowest i, then lowest j),
    in the order they are matched (coordination_graph.matched_pairs)."""
    n = len(cells)
    matched, edges = [False] * n, []
    for d in range(1, distance + 1):
        for i in range(n):
            if not acting[i] or matched[i]:
                continue
            for j in range(i + 1, n):
                if (acting[j] and not matched[j] and world.distance(cells[i], cells[j]) == d
                        and (cells[i], cells[j]) in states):
                    matched[i] = matched[j] = True
                    edges.append((i, j))
                    break
    return edges


def components(edges, acting):
    """{lowest agent: its group's agents, ascending} of the acting agents."""
    root = [i if active else None for i, active in enumerate(acting)]

    def find(i):
        while root[i] != i:
            i = root[i]
        return i
    for i, j in edges:
        a, b = find(i), find(j)
        root[max(a, b)] = min(a, b)
    groups = {}
    for i, active in enumerate(acting):
        if active:
            groups.setdefault(find(i), []).append(i)
    return groups


class Elimination:
    """Variable elimination over one group's edge rules (coordination_graph.eliminate and
    assign_best): ``rules`` holds the edges as (i, j, 16 values) and the rules made as (scope,
    values, counts, maker)."""

    def __init__(self, edges, members):
        self.rules = [("edge", i, j, table) for i, j, table in edges]
        self.used = [False] * len(self.rules)
        self.linked = {v: set() for v in members}
        for i, j, _ in edges:
            self.linked[i].add(j)
            self.linked[j].add(i)
        self.alive, self.order, self.made, self.bucket = set(members), [], {}, {}
        self.assign = {}

    def holds(self, rule, v):
        return v in (rule[1], rule[2]) if rule[0] == "edge" else v in rule[1]

    def value(self, rule):
        if rule[0] == "edge":
            return rule[3][self.assign[rule[1]] * N_ACTIONS + self.assign[rule[2]]]
        return rule[2][self.index(rule[1])]

    def count(self, rule):
        return 1.0 if rule[0] == "edge" else rule[3][self.index(rule[1])]

    def index(self, scope):
        index = 0
        for u in scope:
            index = index * N_ACTIONS + self.assign[u]
        return index

    def bucket_value(self, v):
        total = 0.0
        for k in self.bucket[v]:
            total += self.value(self.rules[k])
        return total

    def bucket_count(self, v):
        count = 1.0
        for k in self.bucket[v]:
            count *= self.count(self.rules[k])
        return count

    def run(self):
        """Eliminate every agent; the number of maximising joint actions."""
        while self.alive:
            v = min(self.alive, key=lambda u: (len(self.linked[u] & self.alive), -u))
            scope = sorted(self.linked[v] & self.alive - {v})
            self.bucket[v] = [k for k in range(len(self.rules)) if not self.used[k] and self.holds(self.rules[k], v)]
            for k in self.bucket[v]:
                self.used[k] = True
            values, counts = [], []
            for x in range(N_ACTIONS ** len(scope)):
                rest = x
                for u in reversed(scope):
                    self.assign[u] = rest % N_ACTIONS
                    rest //= N_ACTIONS
                best, count = -math.inf, 0.0
                for action in range(N_ACTIONS):
                    self.assign[v] = action
                    value = self.bucket_value(v)
                    if value > best:
                        best, count = value, self.bucket_count(v)
                    elif value == best:
                        count += self.bucket_count(v)
                values.append(best)
                counts.append(count)
            self.made[v] = len(self.rules)
            self.rules.append(("made", scope, values, counts, v))
            self.used.append(False)
            for u in scope:
                self.linked[u] |= set(scope) - {u}
            self.alive.remove(v)
            self.order.append(v)
        return self.rules[-1][3][0]

    def choose(self, rank):
        """The maximising joint action of rank ``rank``: {agent: action}."""
        ranks = {self.order[-1]: rank}
        for v in reversed(self.order):
            left, best, chosen = ranks[v], self.value(self.rules[self.made[v]]), -1
            for action in range(N_ACTIONS):
                self.assign[v] = action
                if self.bucket_value(v) == best:
                    chosen = action
                    count = self.bucket_count(v)
                    if left < count:
                        break
                    left -= count
            self.assign[v] = chosen
            for k in self.bucket[v]:
                rule = self.rules[k]
                if rule[0] == "made":
                    base = self.count(rule)
                    digit = left % base
                    ranks[rule[4]] = digit
                    left = (left - digit) / base
        return dict(self.assign)


def sparse_maq(world, workload, rnd):
    """Sparse cooperative Q-learning over the coordination graph, or the pairwise variant, for any
    number of agents (sparse_maq.run); groups maximise by variable elimination."""
    (q_settings, c), n = workload.setup(), len(world.starts)
    if c.maximiser != "elimination":
        raise UserError(f"the plain step of sparse MAQ plays variable elimination only, not {c.maximiser!r}")
    distance = c.coordination_distance
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    q = tables(n, world.n_cells, N_ACTIONS)
    states = set(coordination_states(world, distance))
    q_pairs = {(i, j): {state: [0.0] * N_ACTIONS ** 2 for state in states} for i in range(n) for j in range(i + 1, n)}

    def graph(cells, acting):
        if c.coordination == "graph":
            return close_pairs(states, cells, acting)
        return matched_pairs(world, states, distance, cells, acting)

    def row(edge, cells):
        i, j = edge
        return q_pairs[i, j][cells[i], cells[j]]

    def best_joint(edges, members, cells):
        group = [(i, j, row((i, j), cells)) for i, j in edges if i in members]
        elimination = Elimination(group, members)
        total = elimination.run()
        rank = float(min(math.floor(rnd.random() * total), total - 1.0)) if total > 1.0 else 0.0
        return elimination.choose(rank)

    def choose(cells, edges, groups):
        actions = [0] * n
        for root, members in sorted(groups.items()):
            if len(members) == 1:
                actions[root] = epsilon_greedy(q[root][cells[root]], exploit, rnd)
            elif len(members) == 2:
                actions[members[0]], actions[members[1]] = divmod(epsilon_greedy(row(members, cells), exploit, rnd),
                                                                  N_ACTIONS)
            elif rnd.random() < exploit:
                for m, action in best_joint(edges, members, cells).items():
                    actions[m] = action
            else:
                for start in range(0, len(members), 13):  # coordination_graph.DRAW_AGENTS
                    chunk = members[start:start + 13]
                    joint = below(rnd, N_ACTIONS ** len(chunk))
                    for m in reversed(chunk):
                        joint, actions[m] = divmod(joint, N_ACTIONS)
        return actions

    def agent_value(edges, i, edge_values):
        value = 0.0
        for edge, v in zip(edges, edge_values):
            if i in edge:
                value += v / 2
        return value

    def best_edge_values(edges, groups, cells):
        values = [0.0] * len(edges)
        for root, members in sorted(groups.items()):
            if len(members) == 2:
                values[edges.index(tuple(members))] = max(row(members, cells))
            elif len(members) > 2:
                joint = best_joint(edges, members, cells)
                for e, (i, j) in enumerate(edges):
                    if i in members:
                        values[e] = row((i, j), cells)[joint[i] * N_ACTIONS + joint[j]]
        return values

    def step(cells, done):
        acting = [not d for d in done]
        edges = graph(cells, acting)
        groups = components(edges, acting)
        actions = choose(cells, edges, groups)
        new, rewards, reached, collisions = world.step(cells, done, actions)
        acting_next = [not (done[i] or reached[i]) for i in range(n)]
        edges_next = graph(new, acting_next)
        degree = [sum(i in edge for edge in edges) for i in range(n)]
        degree_next = [sum(i in edge for edge in edges_next) for i in range(n)]
        edges_now = [row(edge, cells)[actions[edge[0]] * N_ACTIONS + actions[edge[1]]] for edge in edges]
        edges_after = best_edge_values(edges_next, components(edges_next, acting_next), new)
        now, after = [0.0] * n, [0.0] * n
        for i in range(n):
            if done[i]:
                continue
            now[i] = q[i][cells[i]][actions[i]] if degree[i] == 0 else agent_value(edges, i, edges_now)
            if not reached[i]:
                after[i] = max(q[i][new[i]]) if degree_next[i] == 0 else agent_value(edges_next, i, edges_after)

        def shared_error(agents):
            target = current = 0.0
            for m in agents:
                share = max(degree[m], 1)
                target += rewards[m] / share
                target += gamma * after[m] / share
                current += now[m] / share
            return target - current
        for i in range(n):  # individual rules
            if done[i] or degree[i] > 0:
                continue
            s, a = cells[i], actions[i]
            if reached[i] or degree_next[i] == 0:  # u -> u: eq. 11
                target = rewards[i] if reached[i] else rewards[i] + gamma * after[i]
                q[i][s][a] = (1.0 - alpha) * q[i][s][a] + alpha * target
            else:  # u -> c
                q[i][s][a] += alpha * shared_error((i,))
        for e, (i, j) in enumerate(edges):  # edge rules
            values, joint = row((i, j), cells), actions[i] * N_ACTIONS + actions[j]
            if degree[i] == degree[j] == 1 and degree_next[i] == degree_next[j] == 1 and (i, j) in edges_next:  # c -> c
                best = edges_after[edges_next.index((i, j))]
                values[joint] += alpha * (rewards[i] + rewards[j] + gamma * best - values[joint])
            else:
                values[joint] += alpha * shared_error((i, j))
        return new, rewards, reached, collisions, len(edges)
    return step


# --- CQ-learning (glamas.learners.cq) ----------------------------------------------------------------

class RewardWindow:
    """The last ``size`` rewards of a state-action in a ring buffer, with their count, sum and sum
    of squares kept up to date (cq.add_reward)."""

    __slots__ = ("samples", "added", "count", "total", "squares")

    def __init__(self, size):
        self.samples, self.added = [0.0] * size, 0
        self.count = self.total = self.squares = 0.0

    def add(self, r):
        size = len(self.samples)
        slot = self.added % size
        if self.added >= size:
            old = self.samples[slot]
            self.total -= old
            self.squares -= old * old
        else:
            self.count += 1.0
        self.samples[slot] = r
        self.total += r
        self.squares += r * r
        self.added += 1


def differs_from_expected(expected, window, t_critical):
    """Student's one-sample t-test, two-sided, of a window against the expected reward; zero
    variance rejects when the mean differs (cq.differs_from_expected)."""
    n = window.count
    if n < 2.0:
        return False
    mean = window.total / n
    gap = mean - expected
    squares = max(window.squares - window.total * mean, 0.0)
    if squares <= 0.0:
        return gap != 0.0
    t = t_critical[int(n) - 1]
    return gap * gap * n * (n - 1.0) > t * t * squares


def significantly_lower(baseline, recent, t_critical):
    """Student's two-sample t-test with pooled variance on window summaries: the recent mean is
    significantly below the baseline's (cq.significantly_lower)."""
    n1, n2 = baseline.count, recent.count
    if n1 < 1.0 or n2 < 1.0 or n1 + n2 < 3.0:
        return False
    m1, m2 = baseline.total / n1, recent.total / n2
    if m2 >= m1:
        return False
    squares = max(baseline.squares - baseline.total * m1, 0.0) + max(recent.squares - recent.total * m2, 0.0)
    df = int(n1 + n2 - 2.0)
    spread = squares / df * (1.0 / n1 + 1.0 / n2)
    if spread <= 0.0:
        return True
    return (m1 - m2) / math.sqrt(spread) > t_critical[df]


def rejects(alone, window, t_critical, test):
    """Test 1 or 2 of a full window against the state-action's rewards alone (cq.rejects)."""
    if alone.count < 1.0:
        return False
    if test == "one_sample":
        return differs_from_expected(alone.total / alone.count, window, t_critical)
    return significantly_lower(alone, window, t_critical)


def windows(n_agents, n_cells, size):
    return [[[RewardWindow(size) for _ in range(N_ACTIONS)] for _ in range(n_cells)] for _ in range(n_agents)]


def learn_alone(world, workload, q, alone, rnd):
    """CQ-learning's phase alone: each agent in turn learns alone (the others count as in the goal)
    and fills the reward windows ``alone`` whose means are ER (cq.learn_alone)."""
    (q_settings, c), n = workload.setup(), len(world.starts)
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    actions = [0] * n
    for k in range(n):
        for _ in range(c.cq_solo_episodes):
            cells, done, t = list(world.starts), [i != k for i in range(n)], 0
            while t < workload.max_steps and not done[k]:
                s = cells[k]
                a = actions[k] = epsilon_greedy(q[k][s], exploit, rnd)
                new, rewards, reached, _ = world.step(cells, done, actions)
                q_update(q[k], s, a, rewards[k], new[k], reached[k], alpha, gamma)
                alone[k][s][a].add(rewards[k])
                t += 1
                done[k], cells = reached[k], new


def cq(world, workload, rnd):
    """CQ-learning for any number of agents and each of its variants (cq.run): the phase alone,
    then test 1 per state-action and test 2 per other agent's cell (or one stage), acting on the
    augmented values of the nearest augmenting agent (or of the nearest agent only)."""
    (q_settings, c), n = workload.setup(), len(world.starts)
    alpha, gamma, exploit = q_settings.q_learning_rate, q_settings.discount, q_settings.exploit_prob
    every, two_stage = c.cq_observe == "every", c.cq_detection == "two_stage"
    q = tables(n, world.n_cells, N_ACTIONS)
    alone = windows(n, world.n_cells, c.cq_window)
    learn_alone(world, workload, q, alone, rnd)
    first = windows(n, world.n_cells, c.cq_window)  # W_k(s_k, a_k)
    second = {}  # (k, s_k, a_k, other's cell) -> W_k(s_k, a_k, s_l)
    t_critical = workload.t_critical().tolist()
    q_aug = [{} for _ in range(n)]  # agent k: augmented (own cell, other's cell) -> 4 values

    def observe(k, cells, done):
        """(the agent whose augmented values agent k acts on, its nearest other agent); None: none."""
        others = [(world.distance(cells[k], cells[l]), l) for l in range(n) if l != k and not done[l]]
        nearest = min(others)[1] if others else None
        if every:
            augmenting = [seen for seen in others if (cells[k], cells[seen[1]]) in q_aug[k]]
            return (min(augmenting)[1] if augmenting else None), None
        return (nearest if nearest is not None and (cells[k], cells[nearest]) in q_aug[k] else None), nearest

    def augment(k, s, other):
        if (s, other) not in q_aug[k]:
            q_aug[k][s, other] = list(q[k][s])

    def detect(k, s, a, r, cells, done, nearest):
        """Test 1 on W_k(s, a), then test 2 per other agent present (or one stage)."""
        base, window = alone[k][s][a], first[k][s][a]
        window.add(r)
        if window.added < c.cq_window or not rejects(base, window, t_critical, c.cq_test):
            return
        for l in range(n):
            if l == k or done[l] or (not every and l != nearest):
                continue
            other = cells[l]
            if two_stage:
                pair = second.setdefault((k, s, a, other), RewardWindow(c.cq_window))
                pair.add(r)
                if ((s, other) not in q_aug[k] and pair.added >= c.cq_window
                        and rejects(base, pair, t_critical, c.cq_test)):
                    augment(k, s, other)
            elif r < base.total / base.count:
                augment(k, s, other)

    def step(cells, done):
        seen = [(None, None) if done[k] else observe(k, cells, done) for k in range(n)]
        rows = [q_aug[k][cells[k], cells[seen[k][0]]] if seen[k][0] is not None else q[k][cells[k]] for k in range(n)]
        actions = [0 if done[k] else epsilon_greedy(rows[k], exploit, rnd) for k in range(n)]
        new, rewards, reached, collisions = world.step(cells, done, actions)
        for k in range(n):
            if done[k]:
                continue
            s, a, r = cells[k], actions[k], rewards[k]
            observed, nearest = seen[k]
            if observed is not None:  # Q_aug learns r plus the local value of the next state
                row = q_aug[k][s, cells[observed]]
                target = r if reached[k] else r + gamma * max(q[k][new[k]])
                row[a] += alpha * (target - row[a])
            elif c.cq_update_local:
                q_update(q[k], s, a, r, new[k], reached[k], alpha, gamma)
            detect(k, s, a, r, cells, done, nearest)
        observed = any(seen[k][0] is not None for k in range(n) if not done[k])
        return new, rewards, reached, collisions, int(observed)
    return step


LEARNERS = {"independent": independent, "joint_state": joint_state, "mmdp": mmdp, "two_observe": two_observe,
            "sparse_maq": sparse_maq, "sparse_maq_pairs": sparse_maq, "cq": cq}


def play(world, episodes, max_steps, step):
    """The episode loop of glamas.learners.episode: ``step(cells, done)`` makes one joint move with
    its learning and returns (new cells, rewards, reached, collisions, coordinations); a log row
    per episode (steps and reward per agent, length, collisions, coordinations, capped)."""
    n = len(world.starts)
    log = []
    for _ in range(episodes):
        cells, done = list(world.starts), [False] * n
        steps, reward = [0] * n, [0.0] * n
        t, collisions, coordinations = 0, 0, 0.0
        while t < max_steps and not all(done):
            new, rewards, reached, hits, coordinated = step(cells, done)
            t += 1
            collisions += hits
            coordinations += coordinated
            for i in range(n):
                if not done[i]:
                    reward[i] += rewards[i]
                    if reached[i]:
                        steps[i], done[i] = t, True
            cells = new
        log.append([s if d else t for s, d in zip(steps, done)] + reward
                   + [t, collisions, coordinations, 0.0 if all(done) else 1.0])
    return log


def run(workload, rnd):
    """One run of the workload's learner in plain Python, drawing from ``rnd``: its log, a row per
    episode."""
    world = World(workload.gridmap(), workload.bounce, workload.rewards)
    step = LEARNERS[workload.learner](world, workload, rnd)
    return play(world, workload.episodes, workload.max_steps, step)


def steps(log):
    """Environment steps (joint moves) of a log's episodes."""
    n_agents = (len(log[0]) - 4) // 2
    return sum(row[2 * n_agents] for row in log)
