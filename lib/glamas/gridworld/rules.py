"""The rules of the chapter's gridworld (Section 5.3), compiled for the simulation kernels.

Agents move N, E, S or W. Each agent has its own goal cells (``GridMap.goals``, :class:`Goals`;
the chapter's two agents share one). Entering one of its goal cells is absorbing: an agent in its
goal no longer acts and has left the game, so no agent collides with it (another agent may walk through the
cell). Another agent's goal is an ordinary cell for an agent. A move into a wall, a blocked cell
or the border is a bump: the agent stays. Two acting agents collide when they target the same
cell, unless it is a goal of both (a bumped agent's target is its own cell), or swap cells; both
bounce back. What each of these pays is the world's reward formulation
(:class:`glamas.gridworld.rewards.Rewards`, ``World.payoffs``): under the chapter's, +100 at the
goal, -1 for a bump and -10 per collision an agent is in, added to its move's reward.

At goal cells: agents entering a cell that is the goal of both together do not collide (both are
done, as the chapter's two agents entering their shared goal); agents entering a cell that is the
goal of only one of them collide, as on any other cell, and both bounce (the cell is an ordinary
one for the other agent, and the chapter's collision is two agents aiming at one cell).

The chapter says only that collided agents are "bounced back to their original position";
``bounce`` chooses the cell they bounce to: the cell they moved from (``BOUNCE_PREVIOUS``, the
default; the chapter uses the same words for wall bumps, where the agent just stays) or their
start cell (``BOUNCE_START``). Neither is ever the agent's own goal, so a collided agent never
arrives.

N agents (the chapter has two): a bounced agent can land on a cell another agent has just
entered (A follows B, B collides with C and bounces back onto A). Such agents collide as well:
each pair sharing a cell that is not a goal of both is one more collision and both bounce. This
repeats until no two acting agents share such a cell. Bounce cells are distinct, so every round
bounces at least one agent that had not yet bounced, no pair collides twice in a step,
and the loop ends within N rounds. k agents aiming at the same cell (a goal of none of them) make
k(k-1)/2 collisions.

Precondition of :func:`step`: the acting agents are on distinct cells, none on one of its own
goals (true from the start cells on, since the rules preserve it).

**One statement of each rule.** Each rule is one small function, read by every path of a step:
an agent's move and what it pays (:func:`moved`), when two agents collide (:func:`collides`,
:func:`exempt`), where a collided agent goes (:func:`bounced`), what a collision pays
(:func:`collision_reward`) and an agent's reward for the step with the goal's (:func:`settle`);
every value paid is ``World.payoffs``'s. Four of them are compiled once each and left for LLVM to
inline, not inlined by numba wherever a step path calls them (glamas.learners.episode says why);
:func:`exempt` and :func:`collides` are inlined by numba, as LLVM left them calls.
:func:`step` applies them to every pair of agents;
:func:`step_indexed` (N agents), :func:`step_pair` (two acting agents) and :func:`step_alone`
(one) apply the same functions to the pairs that can collide, which is all that tells them
apart, and tests play each against :func:`step`. For the chapter's two agents :func:`step_pair`
measured no faster than :func:`step` (both in the learners' kernels: the independent learners
39.7 against 39.5 ns per step, 2observe 87.4 against 87.6, ``benchmarks.bench_gridworld
--quick``); it and :func:`step_alone` are kept for the loops of N agents, whose last two agents
(or last one) would otherwise be stepped by trying all N(N - 1)/2 pairs.

**Many agents.** :func:`step` tries every pair of agents, which is what a step of N agents costs
to check by hand and stays the rules' statement. :func:`step_indexed` reaches the same outcomes
(rewards, collisions, bounce cells: every output equal) at a cost that grows with the number of
agents and collisions only, through a :class:`CellIndex` of the cells: the acting agent on each
cell and, per cell, the agents aiming at it. Under the precondition a collision in the first round
is two agents aiming at one cell or swapping cells, found on the target cell; in a later round it is
an agent that has just bounced and an agent that has not collided and stands on (aims at) the
bounce cell, found there too. Bounce cells being distinct, the later rounds collide each such pair
once whatever the order in which the pairs are tried, as :func:`step` does. The episode loops of N
agents step with it (the chapter's two agents take :func:`step_pair`).
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from glamas.gridworld.rewards import CHAPTER, Payoffs, Rewards

N, E, S, W = 0, 1, 2, 3
N_ACTIONS = 4
ACTION_NAMES = ("N", "E", "S", "W")

NOBODY = -1
"""No agent (an empty cell of a :class:`CellIndex`, the end of a list of agents)."""

BOUNCE_PREVIOUS = 0
BOUNCE_START = 1
BOUNCE_MODES = {"previous": BOUNCE_PREVIOUS, "start": BOUNCE_START}


class Goals(NamedTuple):
    """Each agent's goal cells, stored so that their memory grows with the cells plus the agents'
    own goals, not with agents x cells: the cells that are every agent's goal (the chapter's 'G'),
    and each agent's own goals in one list, agent after agent. :func:`is_goal` reads them."""

    shared: np.ndarray
    """bool (cells,): the cells marked as every agent's goal."""
    first: np.ndarray
    """int (agents + 1,): agent i's own goals are ``own[first[i]:first[i + 1]]``."""
    own: np.ndarray
    """int (own goals,): each agent's own goal cells (none of them a shared one), agent after agent."""


@njit(cache=True, inline="always")
def is_goal(goals, i, c):
    """Whether cell c is a goal of agent i: a shared goal or one of its own."""
    found = goals.shared[c]
    for k in range(goals.first[i], goals.first[i + 1]):
        found = found or goals.own[k] == c
    return found


class World(NamedTuple):
    """The map and the collision rule as the compiled kernels read them (:func:`world`)."""

    next_cell: np.ndarray
    """int (cells, 4): the cell each action leads to (the cell itself for a bump)."""
    goals: Goals
    """Each agent's goal cells (:func:`is_goal`)."""
    starts: np.ndarray
    """int (agents,): each agent's start cell."""
    bounce: int
    """Where a collided agent goes: BOUNCE_PREVIOUS or BOUNCE_START."""
    n_cols: int
    """The map's width (cell = row * n_cols + col), for distances."""
    payoffs: Payoffs
    """What a step pays (the reward formulation, :class:`glamas.gridworld.rewards.Rewards`)."""


class CellIndex(NamedTuple):
    """Agents by cell, for the steps of many agents (:func:`step_indexed`; 2observe's group step
    keeps one of its own). Every cell is NOBODY between two steps: a step fills in the cells it
    uses and empties them again, at a cost of its acting agents, not of the map."""

    occupant: np.ndarray
    """int (cells,): the acting agent on each cell (the acting agents are on distinct cells)."""
    claimant: np.ndarray
    """int (cells,): the highest-numbered acting agent aiming at each cell; the others aiming at
    it follow in ``next_claimant``."""
    next_claimant: np.ndarray
    """int (agents,): the next lower-numbered agent aiming at the same cell, NOBODY after the last."""
    queue: np.ndarray
    """int (agents,): scratch, the agents in the order they collided (:func:`step_indexed`)."""


def world(gridmap, bounce: str = "previous", rewards: Rewards = CHAPTER) -> World:
    """The kernels' view of ``gridmap`` with the collision rule ``bounce`` ('previous' or 'start')
    and the reward formulation ``rewards``."""
    return World(gridmap.next_cell, gridmap.goals, gridmap.starts, BOUNCE_MODES[bounce], gridmap.n_cols,
                 rewards.kernel_bundle())


@njit(cache=True)
def moved(world, cell, is_done, action):
    """An agent's move before collisions and the goal: (the cell it moves to, whether it bumped,
    what the move pays: the bump's or the move's reward). A done agent stays and is paid nothing."""
    target = world.next_cell[cell, action]  # read either way, a done agent's ignored: no branch around the load
    new = cell if is_done else target
    bump = not is_done and new == cell
    payoffs = world.payoffs
    return new, bump, 0.0 if is_done else payoffs.bump if bump else payoffs.move


@njit(cache=True, inline="always")
def exempt(goals, i, j, cell):
    """Whether agents i and j may be on ``cell`` together without colliding: it is a goal of both."""
    return is_goal(goals, i, cell) and is_goal(goals, j, cell)


@njit(cache=True, inline="always")
def collides(goals, i, j, cell_i, cell_j, new_i, new_j):
    """Whether acting agents i and j moving from ``cell_i``, ``cell_j`` to ``new_i``, ``new_j``
    collide: one target that is not a goal of both (:func:`exempt`), or a swap."""
    return (new_i == new_j and not exempt(goals, i, j, new_i)) or (new_i == cell_j and new_j == cell_i)


@njit(cache=True)
def bounced(world, i, cell):
    """Where agent i goes when it collides moving from ``cell`` (``world.bounce``)."""
    start = world.starts[i]  # read either way: no branch around the load
    return cell if world.bounce == BOUNCE_PREVIOUS else start


@njit(cache=True)
def collision_reward(payoffs, hit):
    """What one collision adds to each of its two agents' rewards (nothing when not ``hit``)."""
    return payoffs.collision if hit else 0.0


@njit(cache=True)
def settle(payoffs, reward, hit, arrived):
    """An acting agent's reward for the step, from its move's reward with the collisions added
    (``reward``): the collision's reward alone if it collided and the formulation says a collision
    replaces the move's reward, else ``reward``; plus the goal's reward if it ``arrived``."""
    if hit and payoffs.collision_replaces_move:
        reward = payoffs.collision
    return reward + payoffs.goal if arrived else reward


@njit(cache=True, inline="always")
def _start(world, cells, done, actions, new_cells, rewards, bumped, collided, reached):
    """Write every agent's move (:func:`moved`) into the output arrays, nobody collided or arrived
    yet; returns the number of acting agents."""
    acting = 0
    for i in range(cells.shape[0]):
        is_done = done[i]
        new, bump, reward = moved(world, cells[i], is_done, actions[i])
        new_cells[i] = new
        bumped[i] = bump
        rewards[i] = reward
        collided[i] = False
        reached[i] = False
        acting += 0 if is_done else 1
    return acting


@njit(cache=True, inline="always")
def _finish(world, done, new_cells, rewards, collided, reached):
    """Settle every acting agent's reward and arrival (:func:`settle`) on its cell after the step."""
    for i in range(new_cells.shape[0]):
        arrived = not done[i] and is_goal(world.goals, i, new_cells[i])
        reached[i] = arrived
        rewards[i] = settle(world.payoffs, rewards[i], collided[i], arrived)


@njit(cache=True, inline="always")
def _collide_if(hit, i, j, rewards, collided, payoffs):
    """When ``hit``: agents i and j are paid a collision (:func:`collision_reward`) and marked
    collided. Returns 1 for a collision, else 0 (the arrays are written either way, without a branch)."""
    penalty = collision_reward(payoffs, hit)
    hit_i, hit_j = collided[i], collided[j]
    rewards[i] += penalty
    rewards[j] += penalty
    collided[i] = hit_i or hit
    collided[j] = hit_j or hit
    return 1 if hit else 0


@njit(cache=True, inline="always")
def step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached):
    """One joint move of all agents in ``world``; fills the output arrays, returns the number of
    collisions.

    ``cells``, ``done`` and ``actions`` are the agents' current cells, whether each is already in
    its goal (then its action is ignored) and their actions. Writes each agent's ``new_cells``,
    ``rewards`` (``world.payoffs``), and whether it ``bumped``, ``collided`` or ``reached`` its
    goal in this step. Returns the number of colliding pairs.
    Inlined like every piece of the episode loops: left as a call, it cost sparse MAQ's loop of
    four agents 164 against 98 ns per step (the loops are compiled without reference counting,
    glamas.learners.episode, so the two-agent paths beside it are not slowed).
    """
    goals, payoffs = world.goals, world.payoffs
    n = cells.shape[0]
    acting = _start(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)

    # First round: the moves themselves (:func:`collides`).
    n_collisions = 0
    for i in range(n if acting > 1 else 0):  # a collision takes two acting agents
        new_i, cell_i, done_i = new_cells[i], cells[i], done[i]
        for j in range(i + 1, n):
            hit = not (done_i or done[j]) and collides(goals, i, j, cell_i, cells[j], new_i, new_cells[j])
            n_collisions += _collide_if(hit, i, j, rewards, collided, payoffs)

    # Later rounds: bounced agents may land where another agent now is.
    found, rounds = n_collisions, 0
    while found > 0 and rounds < n:
        rounds += 1
        for i in range(n):
            back, hit, new = bounced(world, i, cells[i]), collided[i], new_cells[i]
            new_cells[i] = back if hit else new
        found = 0
        for i in range(n):
            new_i, done_i = new_cells[i], done[i]
            for j in range(i + 1, n):
                new_j, done_j, hit_i, hit_j = new_cells[j], done[j], collided[i], collided[j]
                shared = new_i == new_j and not exempt(goals, i, j, new_i)
                # both already at their (distinct) bounce cells: only a broken precondition gets there
                again = not (done_i or done_j) and shared and not (hit_i and hit_j)
                found += _collide_if(again, i, j, rewards, collided, payoffs)
        n_collisions += found

    _finish(world, done, new_cells, rewards, collided, reached)
    return n_collisions


@njit(cache=True, inline="always")
def cell_index(world):
    """An empty :class:`CellIndex` for the world's cells and agents (made once per run)."""
    n_cells, n = world.next_cell.shape[0], world.starts.shape[0]
    return CellIndex(np.full(n_cells, NOBODY, np.int64), np.full(n_cells, NOBODY, np.int64),
                     np.full(n, NOBODY, np.int64), np.empty(n, np.int64))


@njit(cache=True, inline="always")
def index_agents(index, cells, done, targets_of, actions):
    """Enter the acting agents in ``index``: each on its cell, and each in the list of the cell it
    aims at, ``targets_of[cell, action]`` (the world's next_cell) for its action in ``actions``."""
    occupant, claimant, next_claimant = index.occupant, index.claimant, index.next_claimant
    for i in range(cells.shape[0]):
        if done[i]:
            continue
        cell = cells[i]
        target = targets_of[cell, actions[i]]
        occupant[cell] = i
        next_claimant[i] = claimant[target]
        claimant[target] = i


@njit(cache=True, inline="always")
def clear_index(index, cells, done, targets_of, actions):
    """Empty the cells :func:`index_agents` filled (with the same arguments)."""
    occupant, claimant = index.occupant, index.claimant
    for i in range(cells.shape[0]):
        if not done[i]:
            cell = cells[i]
            occupant[cell] = NOBODY
            claimant[targets_of[cell, actions[i]]] = NOBODY


@njit(cache=True, inline="always")
def _collide_queued(i, j, rewards, collided, queue, queued, payoffs):
    """Agents i and j collide: both are paid a collision (:func:`collision_reward`); each is queued
    the first time it collides. Returns the new length of the queue."""
    penalty = collision_reward(payoffs, True)
    rewards[i] += penalty
    rewards[j] += penalty
    if not collided[i]:
        collided[i] = True
        queue[queued] = i
        queued += 1
    if not collided[j]:
        collided[j] = True
        queue[queued] = j
        queued += 1
    return queued


@njit(cache=True, inline="always")
def step_indexed(world, index, cells, done, actions, new_cells, rewards, bumped, collided, reached):
    """:func:`step` through the cell index ``index`` (:func:`cell_index`; empty, and left empty):
    the same outputs and number of collisions (module docstring), with work in proportion to the
    acting agents and their collisions instead of their pairs. Same precondition as :func:`step`."""
    next_cell, goals, payoffs = world.next_cell, world.goals, world.payoffs
    occupant, claimant, next_claimant, queue = index
    n = cells.shape[0]
    _start(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
    index_agents(index, cells, done, next_cell, actions)

    # First round: the agents aiming at one cell (not a goal of both), pair by pair, and swaps.
    n_collisions, queued = 0, 0
    for i in range(n):
        if done[i]:
            continue
        new_i = new_cells[i]
        j = next_claimant[i]  # the lower-numbered agents aiming at new_i
        while j != NOBODY:
            if not exempt(goals, i, j, new_i):
                n_collisions += 1
                queued = _collide_queued(i, j, rewards, collided, queue, queued, payoffs)
            j = next_claimant[j]
        j = occupant[new_i]  # a swap, counted once: from its lower-numbered agent
        if j > i and new_cells[j] == cells[i]:
            n_collisions += 1
            queued = _collide_queued(i, j, rewards, collided, queue, queued, payoffs)

    # Later rounds: the agents that collided in the last round bounce, onto the cells of agents
    # that have not collided (which stand on the cells they aim at).
    first = 0
    while first < queued:
        last = queued
        for k in range(first, last):
            a = queue[k]
            new_cells[a] = bounced(world, a, cells[a])
        for k in range(first, last):
            a = queue[k]
            cell = new_cells[a]
            b = claimant[cell]
            while b != NOBODY:
                if not collided[b] and not exempt(goals, a, b, cell):
                    n_collisions += 1
                    queued = _collide_queued(a, b, rewards, collided, queue, queued, payoffs)
                b = next_claimant[b]
        first = last

    clear_index(index, cells, done, next_cell, actions)
    _finish(world, done, new_cells, rewards, collided, reached)
    return n_collisions


@njit(cache=True, inline="always")
def step_pair(world, cells, done, actions, new_cells, rewards, bumped, collided, reached, pair):
    """:func:`step` for the agents ``pair = (i, j)`` when every other agent is in its goal (the
    chapter's two agents are (0, 1), and one of them may be in the goal too); fills agent i's and
    j's entries of the output arrays. Two agents collide at most once and bounce to distinct
    cells, so the later rounds of :func:`step` never find anything; a bounce cell is never the
    agent's goal (module docstring), so an agent arrives when its target is its goal and it did
    not collide.

    Every array is read and written outside the branches, the rules applied to scalars in
    between: the compiler keeps the scalars in registers.
    """
    goals, payoffs = world.goals, world.payoffs
    i, j = pair
    cell_i, cell_j, done_i, done_j = cells[i], cells[j], done[i], done[j]
    new_i, bump_i, reward_i = moved(world, cell_i, done_i, actions[i])
    new_j, bump_j, reward_j = moved(world, cell_j, done_j, actions[j])
    back_i, back_j = bounced(world, i, cell_i), bounced(world, j, cell_j)
    goal_i, goal_j = is_goal(goals, i, new_i), is_goal(goals, j, new_j)
    hit = not done_i and not done_j and collides(goals, i, j, cell_i, cell_j, new_i, new_j)
    reward_i += collision_reward(payoffs, hit)
    reward_j += collision_reward(payoffs, hit)
    if hit:
        new_i, new_j = back_i, back_j
    arrived_i = not done_i and not hit and goal_i
    arrived_j = not done_j and not hit and goal_j
    reward_i = settle(payoffs, reward_i, hit, arrived_i)
    reward_j = settle(payoffs, reward_j, hit, arrived_j)
    new_cells[i], new_cells[j] = new_i, new_j
    rewards[i], rewards[j] = reward_i, reward_j
    bumped[i], bumped[j] = bump_i, bump_j
    collided[i], collided[j] = hit, hit
    reached[i], reached[j] = arrived_i, arrived_j
    return 1 if hit else 0


@njit(cache=True, inline="always")
def step_alone(world, cells, actions, new_cells, rewards, bumped, collided, reached, i):
    """:func:`step` when agent i is the only one acting (the others are in their goals): no
    collision is possible; fills agent i's entries of the output arrays, returns 0."""
    new, bump, reward = moved(world, cells[i], False, actions[i])
    arrived = is_goal(world.goals, i, new)
    new_cells[i] = new
    bumped[i] = bump
    collided[i] = False
    reached[i] = arrived
    rewards[i] = settle(world.payoffs, reward, False, arrived)
    return 0


@njit(cache=True, inline="always")
def would_collide(next_cell, goals, cells, done, actions, i, j):
    """Whether agents i and j would collide playing ``actions`` (:func:`collides`); never when one
    of them is done (its action, which must be one of the four, is ignored). ``goals``: the
    world's (:class:`Goals`).

    Used by 2observe (Alg. 4) to check the agents' preferred actions; other agents are ignored.
    """
    cell_i, cell_j = cells[i], cells[j]
    target_i, target_j = next_cell[cell_i, actions[i]], next_cell[cell_j, actions[j]]
    return not (done[i] or done[j]) and collides(goals, i, j, cell_i, cell_j, target_i, target_j)


@njit(cache=True, inline="always")
def could_collide(next_cell, shared_goal, a, b):
    """Whether two acting agents on cells ``a`` and ``b`` could collide in this step: some joint
    action of theirs makes them target the same cell (a bump targets its own cell) that is not in
    ``shared_goal``, or swap cells. On a 4-connected grid this needs a Manhattan distance of at
    most 2, and a wall between them can rule it out.

    ``shared_goal`` (bool, cells) is where two agents entering together do not collide: the goals
    of every agent (GridMap.shared_goal, :func:`shared_goals`), whoever the two agents are. For two
    agents these are the goals of both, and the answer is exact; with more agents it is exact for
    every pair whose common goals are every agent's (also when no two agents share a goal), and
    otherwise it may call in range a pair whose only possible collision would be entering a goal
    of both together, which is none.

    This is 2observe's "within each other's range of interference" (Section 5.1), computed from
    the rules and the map; it does not depend on what the agents then choose.
    """
    for action_a in range(N_ACTIONS):
        target_a = next_cell[a, action_a]
        for action_b in range(N_ACTIONS):
            target_b = next_cell[b, action_b]
            if target_a == target_b and not shared_goal[target_a]:
                return True
            if target_a == b and target_b == a:
                return True
    return False


@njit(cache=True)
def in_range_table(next_cell, shared_goal):
    """:func:`could_collide` for every pair of cells, ``table[a, b]``: made once per run, so that a
    kernel looks the answer up instead of trying the 16 joint actions every step. Only the pairs
    :func:`in_range_lists` tries can be in range: the table costs the map's cells, not their pairs,
    to fill."""
    n_cells = next_cell.shape[0]
    table = np.zeros((n_cells, n_cells), np.bool_)
    first, near = in_range_lists(next_cell, shared_goal)
    for a in range(n_cells):
        table[a, a] = could_collide(next_cell, shared_goal, a, a)
        for k in range(first[a], first[a + 1]):
            table[a, near[k]] = True
    return table


@njit(cache=True)
def in_range_lists(next_cell, shared_goal):
    """:func:`could_collide` as lists, ``(first, near)``: the cells b != a in range of cell a are
    ``near[first[a]:first[a + 1]]`` (12 at most on a grid). Two agents can collide only when a
    move of one and a move of the other lead to one cell, or when one moves to the other's cell:
    b is tried only when it has a move to a cell a has a move to, or a has a move to b, so a map of
    C cells costs some 20 C tries, whatever its shape."""
    n_cells = next_cell.shape[0]
    into_first, into = _moves_into(next_cell)
    tried = np.full(n_cells, NOBODY, np.int64)  # the last (pass, cell a) for which b was tried
    first = np.zeros(n_cells + 1, np.int64)
    near = np.empty(0, np.int64)
    for fill in range(2):  # count, then fill
        for a in range(n_cells):
            count = 0
            for action in range(N_ACTIONS):
                target = next_cell[a, action]
                for k in range(into_first[target], into_first[target + 1] + 1):
                    b = into[k] if k < into_first[target + 1] else target  # what moves into the target, then the target
                    if b != a and tried[b] != fill * n_cells + a:
                        tried[b] = fill * n_cells + a
                        if could_collide(next_cell, shared_goal, a, b):
                            if fill:
                                near[first[a] + count] = b
                            count += 1
            if not fill:
                first[a + 1] = first[a] + count
        if not fill:
            near = np.empty(first[n_cells], np.int64)
    return first, near


@njit(cache=True)
def _moves_into(next_cell):
    """``(first, into)``: the cells with a move to cell t (other than t itself) are
    ``into[first[t]:first[t + 1]]``."""
    n_cells = next_cell.shape[0]
    first = np.zeros(n_cells + 1, np.int64)
    for b in range(n_cells):
        for action in range(N_ACTIONS):
            t = next_cell[b, action]
            if t != b and _first_move_to(next_cell, b, action):
                first[t + 1] += 1
    for t in range(n_cells):
        first[t + 1] += first[t]
    into = np.empty(first[n_cells], np.int64)
    filled = first[:n_cells].copy()
    for b in range(n_cells):
        for action in range(N_ACTIONS):
            t = next_cell[b, action]
            if t != b and _first_move_to(next_cell, b, action):
                into[filled[t]] = b
                filled[t] += 1
    return first, into


@njit(cache=True)
def _first_move_to(next_cell, b, action):
    """Whether ``action`` is the first of b's actions leading to its cell (each move counted once)."""
    for earlier in range(action):
        if next_cell[b, earlier] == next_cell[b, action]:
            return False
    return True


@njit(cache=True)
def shared_goals(goals):
    """bool (cells,): the cells that are a goal of every agent (GridMap.shared_goal): the shared
    ones, and a cell every agent has among its own."""
    shared = goals.shared.copy()
    n_agents = goals.first.shape[0] - 1
    owners = np.zeros(shared.shape[0], np.int64)
    for k in range(goals.own.shape[0]):
        owners[goals.own[k]] += 1
    for c in range(shared.shape[0]):
        shared[c] = shared[c] or owners[c] == n_agents
    return shared


@njit(cache=True, inline="always")
def shared_reward(payoffs, rewards, reached, all_done_after):
    """The MMDP learner's single reward for one step (Section 5.3).

    The agents' rewards summed without their individual goal rewards (``payoffs.goal``), plus the
    goal's reward once when this step puts the last agent in its goal: the chapter pays the MMDP
    learner +100 when both agents are in.
    """
    total = 0.0
    any_reached = False
    for i in range(rewards.shape[0]):
        total += rewards[i]
        if reached[i]:
            total -= payoffs.goal
            any_reached = True
    if all_done_after and any_reached:
        total += payoffs.goal
    return total


@njit(cache=True)
def distance_table(n_cells, n_cols):
    """:func:`manhattan` for every pair of cells, ``table[a, b]``: made once per run, so that a
    kernel looks distances up instead of dividing cell numbers every step."""
    table = np.empty((n_cells, n_cells), np.int64)
    for a in range(n_cells):
        for b in range(n_cells):
            table[a, b] = manhattan(n_cols, a, b)
    return table


@njit(cache=True, inline="always")
def manhattan(n_cols, a, b):
    """Manhattan distance between cells a and b (cell = row * n_cols + col)."""
    return abs(a // n_cols - b // n_cols) + abs(a % n_cols - b % n_cols)
