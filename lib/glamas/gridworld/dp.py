"""Dynamic programming (chapter Section 2.2) on the gridworld's joint MMDP: the optimum the learners aim at.

The joint MMDP of a map has one state per assignment of cells to the agents (an agent on one of its
own goal cells is done: it no longer acts), one action per joint action (4**n), deterministic
transitions given by :func:`glamas.gridworld.rules.step` and the MMDP learner's shared reward
(:func:`glamas.gridworld.rules.shared_reward`), under a reward formulation
(:class:`glamas.gridworld.rewards.Rewards`, the chapter's by default). The search and the bounds
take the chapter's (:data:`glamas.gridworld.rewards.CHAPTER`): their stopping rule rests on its
+100 at the goal being the only positive reward. States no play can reach (two acting agents on
one cell, an agent on a blocked cell) and the all-done states are absorbing with reward 0.

:func:`value_iteration` is Alg. 2 with eq. 6 and the chapter's stopping rule (largest change
below epsilon); :func:`policy_iteration` is Alg. 1 with iterative policy evaluation (eq. 5).

The tables hold n_cells**n x 4**n entries (:func:`tabulated_bytes`), so they fit for two agents and
small maps of three. Beyond, :func:`searched_optimum` finds the same optimum, V*(start) and an
optimal episode, by a forward search over the joint states the starts lead to
(:mod:`glamas.gridworld.joint_search`), and :func:`optimum_bounds` states what each agent's own
shortest path says about it without any search.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from glamas.errors import UserError
from glamas.gridworld import joint_search, rules
from glamas.gridworld.joint import joint_index, split_index
from glamas.gridworld.maps import GridMap
from glamas.gridworld.rewards import CHAPTER, Rewards
from glamas.gridworld.rules import N_ACTIONS


@dataclass(frozen=True, eq=False)
class JointMDP:
    """The joint MMDP of a map as transition and reward tables over (joint state, joint action)."""

    gridmap: GridMap
    """The map the MDP is built from."""
    bounce: str
    """Where collided agents bounce to: 'previous' cell or 'start' cell."""
    next_state: np.ndarray
    """int64 (n_states, n_joint_actions): the joint state each joint action leads to."""
    reward: np.ndarray
    """float (n_states, n_joint_actions): the MMDP's shared reward (penalties summed, +100 when all are in)."""
    agent_rewards: np.ndarray
    """float (n_states, n_joint_actions, n_agents): each agent's own reward from the rules."""
    collisions: np.ndarray
    """int64 (n_states, n_joint_actions): colliding pairs in the step."""
    bumped: np.ndarray
    """bool (n_states, n_joint_actions, n_agents): which agents bump into a wall in the step."""
    reached: np.ndarray
    """bool (n_states, n_joint_actions, n_agents): which agents enter their goal in the step."""
    valid: np.ndarray
    """bool (n_states,): states play can reach (distinct cells for acting agents, none blocked)."""

    @property
    def n_states(self) -> int:
        return self.next_state.shape[0]

    @property
    def n_joint_actions(self) -> int:
        return self.next_state.shape[1]

    @property
    def start_state(self) -> int:
        return self.state(self.gridmap.starts)

    def state(self, cells) -> int:
        """The joint state of the agents' cells (agent 1 most significant)."""
        return int(np.ravel_multi_index(tuple(int(c) for c in cells), (self.gridmap.n_cells,) * self.gridmap.n_agents))

    def cells(self, state: int) -> tuple[int, ...]:
        """The agents' cells in a joint state."""
        return tuple(int(c) for c in np.unravel_index(state, (self.gridmap.n_cells,) * self.gridmap.n_agents))

    def actions(self, joint_action: int) -> tuple[int, ...]:
        """The agents' actions (N=0, E=1, S=2, W=3) in a joint action (agent 1 most significant)."""
        return tuple(int(a) for a in np.unravel_index(joint_action, (N_ACTIONS,) * self.gridmap.n_agents))


@dataclass(frozen=True, eq=False)
class DPSolution:
    """Optimal values and a greedy joint policy of a :class:`JointMDP`."""

    values: np.ndarray
    """float (n_states,): V of every joint state."""
    policy: np.ndarray
    """int64 (n_states,): the chosen joint action of every joint state."""
    iterations: int
    """Sweeps of value iteration, or improvement steps of policy iteration."""


@dataclass(frozen=True, eq=False)
class Rollout:
    """One episode from the starts under a deterministic joint policy."""

    cells: np.ndarray
    """int64 (n_steps + 1, n_agents): the agents' cells, starts first."""
    steps_to_goal: np.ndarray
    """int64 (n_agents,): the step at which each agent entered its goal (-1: not within the steps)."""
    returns: np.ndarray
    """float (n_agents,): each agent's undiscounted sum of its own rewards."""
    collisions: int
    """Colliding pairs over the episode."""
    bumps: np.ndarray
    """int64 (n_agents,): wall bumps of each agent."""
    finished: bool
    """Whether every agent was in its goal at the end."""


MAX_TABLE_ENTRIES = 50_000_000
"""The most (joint state, joint action) entries :func:`joint_mdp` tabulates (about 2 GB for three agents)."""


def tabulable(gridmap: GridMap) -> bool:
    """Whether :func:`joint_mdp` tabulates ``gridmap``'s joint MMDP (at most MAX_TABLE_ENTRIES entries)."""
    return (gridmap.n_cells * N_ACTIONS) ** gridmap.n_agents <= MAX_TABLE_ENTRIES


def tabulated_bytes(gridmap: GridMap) -> int:
    """The bytes of :func:`joint_mdp`'s tables for ``gridmap``: per (joint state, joint action) the
    next state, shared reward and collisions (8 bytes each), each agent's reward (8) and bumped
    and reached flags (1 each); per joint state its validity."""
    n = gridmap.n_agents
    n_states = gridmap.n_cells ** n
    return n_states * N_ACTIONS ** n * (3 * 8 + n * (8 + 2)) + n_states


def joint_mdp(gridmap: GridMap, bounce: str = "previous", rewards: Rewards = CHAPTER) -> JointMDP:
    """Tabulate the joint MMDP of ``gridmap`` (n_cells**n_agents states, 4**n_agents joint actions)
    under the reward formulation ``rewards``."""
    if bounce not in rules.BOUNCE_MODES:
        raise UserError(f"bounce must be one of {sorted(rules.BOUNCE_MODES)}, got {bounce!r}")
    n_states = gridmap.n_cells ** gridmap.n_agents
    if not tabulable(gridmap):
        raise UserError(f"the joint MMDP of {gridmap.name!r} has {n_states} states x "
                         f"{N_ACTIONS ** gridmap.n_agents} joint actions ({tabulated_bytes(gridmap) / 1e9:,.1f} GB of "
                         "tables): too large to tabulate; use searched_optimum or optimum_bounds, or fewer agents")
    shape = (n_states, N_ACTIONS ** gridmap.n_agents)
    tables = dict(next_state=np.empty(shape, np.int64), reward=np.empty(shape),
                  agent_rewards=np.empty(shape + (gridmap.n_agents,)), collisions=np.empty(shape, np.int64),
                  bumped=np.empty(shape + (gridmap.n_agents,), bool),
                  reached=np.empty(shape + (gridmap.n_agents,), bool), valid=np.empty(n_states, bool))
    _tabulate(rules.world(gridmap, bounce, rewards), gridmap.blocked, *tables.values())
    return JointMDP(gridmap, bounce, **tables)


@njit(cache=True)
def _tabulate(world, blocked, next_state, reward, agent_rewards, collisions, agent_bumped, agent_reached, valid):
    n_cells, n = world.next_cell.shape[0], world.starts.shape[0]
    cells, done, actions = np.empty(n, np.int64), np.empty(n, np.bool_), np.empty(n, np.int64)
    new_cells, rewards = np.empty(n, np.int64), np.empty(n)
    bumped, collided, reached = np.empty(n, np.bool_), np.empty(n, np.bool_), np.empty(n, np.bool_)
    for s in range(next_state.shape[0]):
        split_index(s, n_cells, cells)
        all_done = True
        for i in range(n):
            done[i] = rules.is_goal(world.goals, i, cells[i])
            all_done = all_done and done[i]
        valid[s] = _is_valid(cells, done, blocked)
        for ja in range(next_state.shape[1]):
            if all_done or not valid[s]:
                next_state[s, ja], reward[s, ja], collisions[s, ja] = s, 0.0, 0
                agent_rewards[s, ja, :] = 0.0
                agent_bumped[s, ja, :] = False
                agent_reached[s, ja, :] = False
                continue
            split_index(ja, N_ACTIONS, actions)
            collisions[s, ja] = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            all_done_after = True
            for i in range(n):
                all_done_after = all_done_after and (done[i] or reached[i])
                agent_rewards[s, ja, i] = rewards[i]
                agent_bumped[s, ja, i] = bumped[i]
                agent_reached[s, ja, i] = reached[i]
            reward[s, ja] = rules.shared_reward(world.payoffs, rewards, reached, all_done_after)
            next_state[s, ja] = joint_index(new_cells, n_cells)


@njit(cache=True)
def _is_valid(cells, done, blocked):
    """Whether play can reach the agents' ``cells``: none blocked, no two acting agents on one cell
    (an agent in its goal has left the game: another agent may stand on that cell)."""
    for i in range(cells.shape[0]):
        if blocked[cells[i]]:
            return False
        for j in range(i + 1, cells.shape[0]):
            if cells[i] == cells[j] and not (done[i] or done[j]):
                return False
    return True


def _check_gamma_epsilon(gamma, epsilon):
    if not isinstance(gamma, (int, float)) or not 0.0 < gamma < 1.0:
        raise UserError(f"gamma must be a discount factor in (0, 1), got {gamma!r}")
    if not isinstance(epsilon, (int, float)) or not epsilon > 0.0:
        raise UserError(f"epsilon must be a number > 0, got {epsilon!r}")


def q_values(mdp: JointMDP, values: np.ndarray, gamma: float) -> np.ndarray:
    """Q(s, a) = R(s, a) + gamma V(s') for deterministic transitions (eq. 6 inside the max)."""
    return mdp.reward + gamma * values[mdp.next_state]


def value_iteration(mdp: JointMDP, gamma: float, epsilon: float = 1e-9, max_sweeps: int = 100_000) -> DPSolution:
    """Alg. 2: sweep eq. 6 until the largest change of V is below ``epsilon``; the policy is greedy in V."""
    _check_gamma_epsilon(gamma, epsilon)
    values = np.zeros(mdp.n_states)
    for sweep in range(1, max_sweeps + 1):
        new_values = q_values(mdp, values, gamma).max(axis=1)
        change = np.abs(new_values - values).max()
        values = new_values
        if change < epsilon:
            return DPSolution(values, greedy_policy(mdp, values, gamma), sweep)
    raise RuntimeError(f"value iteration did not reach epsilon={epsilon} in {max_sweeps} sweeps; raise max_sweeps")


def greedy_policy(mdp: JointMDP, values: np.ndarray, gamma: float) -> np.ndarray:
    """Eq. 4: the joint action maximising R + gamma V (the lowest-numbered one among ties)."""
    return q_values(mdp, values, gamma).argmax(axis=1).astype(np.int64)


def policy_evaluation(mdp: JointMDP, policy: np.ndarray, gamma: float, epsilon: float) -> np.ndarray:
    """Eq. 5 for a deterministic policy, iterated until the largest change is below ``epsilon``."""
    rows = np.arange(mdp.n_states)
    reward, successor = mdp.reward[rows, policy], mdp.next_state[rows, policy]
    values = np.zeros(mdp.n_states)
    while True:
        new_values = reward + gamma * values[successor]
        if np.abs(new_values - values).max() < epsilon:
            return new_values
        values = new_values


def policy_iteration(mdp: JointMDP, gamma: float, epsilon: float = 1e-9, max_iterations: int = 1000) -> DPSolution:
    """Alg. 1: evaluate the policy (eq. 5), improve it greedily, stop when it no longer changes.

    Starts from 'every agent goes north'. A state keeps its action when that action is still
    within ``tie`` of the best, so evaluation round-off cannot make the policy cycle between
    equally good actions.
    """
    _check_gamma_epsilon(gamma, epsilon)
    tie = 1e3 * epsilon / (1.0 - gamma)
    policy = np.zeros(mdp.n_states, dtype=np.int64)
    rows = np.arange(mdp.n_states)
    for iteration in range(1, max_iterations + 1):
        values = policy_evaluation(mdp, policy, gamma, epsilon)
        q = q_values(mdp, values, gamma)
        best = q.argmax(axis=1)
        keep = q[rows, policy] >= q[rows, best] - tie
        improved = np.where(keep, policy, best)
        if np.array_equal(improved, policy):
            return DPSolution(values, policy, iteration)
        policy = improved
    raise RuntimeError(f"policy iteration did not settle in {max_iterations} improvements; raise max_iterations")


def rollout(mdp: JointMDP, policy: np.ndarray, max_steps: int | None = None) -> Rollout:
    """Follow a deterministic joint policy from the start cells until every agent is in its goal
    or ``max_steps`` (default: the number of joint states, beyond which a deterministic policy loops)."""
    max_steps = mdp.n_states if max_steps is None else max_steps
    n = mdp.gridmap.n_agents
    state = mdp.start_state
    path = [mdp.cells(state)]
    steps, returns, bumps = np.full(n, -1, np.int64), np.zeros(n), np.zeros(n, np.int64)
    collisions = 0
    while len(path) <= max_steps and not _all_in_goal(mdp.gridmap, path[-1]):
        action = int(policy[state])
        returns += mdp.agent_rewards[state, action]
        bumps += mdp.bumped[state, action]
        steps[mdp.reached[state, action]] = len(path)
        collisions += int(mdp.collisions[state, action])
        state = int(mdp.next_state[state, action])
        path.append(mdp.cells(state))
    finished = _all_in_goal(mdp.gridmap, path[-1])
    return Rollout(np.array(path, np.int64), steps, returns, collisions, bumps, finished)


def _all_in_goal(gridmap: GridMap, cells) -> bool:
    return bool(gridmap.in_goal(np.asarray(cells)).all())


def selfish_policy(mdp: JointMDP, gamma: float) -> np.ndarray:
    """The joint policy of agents that each follow their own single-agent optimum, ignoring the others."""
    gridmap = mdp.gridmap
    own = []
    for i in range(gridmap.n_agents):
        # the map's arrays stay read-only: a writable array would be typed apart by numba, and
        # _tabulate compiled a second time (2 s)
        alone = joint_mdp(gridmap.alone(i), mdp.bounce)
        own.append(value_iteration(alone, gamma).policy)
    policy = np.empty(mdp.n_states, np.int64)
    for state in range(mdp.n_states):
        cells = mdp.cells(state)
        policy[state] = np.ravel_multi_index(tuple(own[i][c] for i, c in enumerate(cells)),
                                             (N_ACTIONS,) * gridmap.n_agents)
    return policy


def optimal_rollout(gridmap: GridMap, gamma: float, bounce: str = "previous", epsilon: float = 1e-9,
                    rewards: Rewards = CHAPTER) -> Rollout:
    """The episode of the optimal joint policy (value iteration) from the starts, under ``rewards``."""
    mdp = joint_mdp(gridmap, bounce, rewards)
    episode = rollout(mdp, value_iteration(mdp, gamma, epsilon).policy)
    if not episode.finished:
        raise UserError(f"the optimal policy of {gridmap.name!r} does not bring every agent to its goal")
    return episode


def exact_optimum(gridmap: GridMap, gamma: float, bounce: str = "previous") -> Rollout:
    """An episode of an optimal joint policy from the starts: by value iteration where the joint
    MMDP can be tabulated (:func:`optimal_rollout`), else by exhaustive search (:func:`searched_optimum`).
    Both are exact; they may pick different ones of equally good episodes."""
    if tabulable(gridmap):
        return optimal_rollout(gridmap, gamma, bounce)
    return searched_optimum(gridmap, gamma, bounce).episode


def goal_distances(gridmap: GridMap) -> np.ndarray:
    """int64 (agents, cells): the moves from each cell to the agent's nearest goal cell, alone on
    the map (-1 where none is reachable); breadth-first from the goals (moves are symmetric)."""
    distances = np.full((gridmap.n_agents, gridmap.n_cells), -1, np.int64)
    for agent in range(gridmap.n_agents):
        frontier = gridmap.goal_cells(agent)
        distances[agent, frontier] = 0
        while frontier:
            following = []
            for cell in frontier:
                for other in gridmap.open_neighbours(cell):
                    if distances[agent, other] < 0:
                        distances[agent, other] = distances[agent, cell] + 1
                        following.append(other)
            frontier = following
    return distances


def shortest_steps(gridmap: GridMap) -> np.ndarray:
    """int64 (agents,): each agent's shortest path from its start to its goal, alone on the map."""
    return goal_distances(gridmap)[np.arange(gridmap.n_agents), gridmap.starts]


@dataclass(frozen=True, eq=False)
class OptimumBounds:
    """What each agent's shortest path alone says about the joint optimum: no joint episode brings
    an agent in sooner, and none pays more than the agents' single-agent optima summed."""

    steps: np.ndarray
    """int64 (n_agents,): each agent's steps to its goal, at least (its shortest path)."""
    episode_steps: int
    """The episode's steps until the last agent is in, at least (the longest shortest path)."""
    value: float
    """V*(start) of the MMDP, at most: 100 gamma**(episode_steps - 1), the +100 at the earliest last arrival."""
    returns: float
    """The agents' undiscounted returns summed, at most: their single-agent optima summed (+100 each)."""
    discounted_returns: float
    """The agents' discounted returns summed, at most: sum of 100 gamma**(steps_i - 1)."""


def optimum_bounds(gridmap: GridMap, gamma: float) -> OptimumBounds:
    """:class:`OptimumBounds` of ``gridmap`` for the discount ``gamma``: computed from each agent's
    shortest path alone, for maps whose joint MMDP is too large to solve."""
    _check_gamma_epsilon(gamma, 1.0)
    steps = shortest_steps(gridmap)
    last = int(steps.max())
    return OptimumBounds(steps, last, CHAPTER.goal * gamma ** (last - 1), CHAPTER.goal * gridmap.n_agents,
                         float(np.sum(CHAPTER.goal * gamma ** (steps - 1.0))))


@dataclass(frozen=True, eq=False)
class SearchedOptimum:
    """The optimum of the joint MMDP from the starts, found by :func:`searched_optimum`."""

    value: float
    """V*(start): the discounted shared reward of an optimal joint play (as :func:`value_iteration`'s)."""
    episode: Rollout
    """An optimal episode (among equally good ones, the first the search found)."""
    horizon: int
    """The longest episodes searched: a longer one is worth at most 100 gamma**horizon <= value."""
    states: int
    """Joint states the search kept, over all its steps."""


def searched_optimum(gridmap: GridMap, gamma: float, bounce: str = "previous", max_steps: int | None = None,
                     max_candidates: int = 50_000_000) -> SearchedOptimum:
    """The joint MMDP's optimum from the starts without its tables: exhaustive forward search over
    episodes of at most H steps (:mod:`glamas.gridworld.joint_search`), H growing from the longest
    shortest path until the best episode found is worth at least what any longer one could be
    (100 gamma**H) or H passes ``max_steps`` (default: four times the longest shortest path).
    ``max_candidates`` bounds the joint moves tried after one step."""
    _check_gamma_epsilon(gamma, 1.0)
    if bounce not in rules.BOUNCE_MODES:
        raise UserError(f"bounce must be one of {sorted(rules.BOUNCE_MODES)}, got {bounce!r}")
    world, distances = rules.world(gridmap, bounce), goal_distances(gridmap)
    lowest = int(shortest_steps(gridmap).max())
    max_steps = 4 * lowest if max_steps is None else max_steps
    for horizon in range(lowest, max_steps + 1):
        layers, best = joint_search.search_layers(world, distances, gamma, horizon, max_candidates)
        if best is not None and best[0] >= CHAPTER.goal * gamma ** horizon:
            episode = play(gridmap, bounce, joint_search.best_actions(layers, best))
            return SearchedOptimum(best[0], episode, horizon, sum(layer[0].shape[0] for layer in layers))
    raise RuntimeError(f"no episode of {gridmap.name!r} within {max_steps} steps is provably optimal; raise max_steps")


def play(gridmap: GridMap, bounce: str, joint_actions: list[int]) -> Rollout:
    """The episode of ``joint_actions`` (each a base-4 number, agent 1 most significant) from the starts."""
    world, n = rules.world(gridmap, bounce), gridmap.n_agents
    cells, done, actions = gridmap.starts.copy(), np.zeros(n, bool), np.empty(n, np.int64)
    out = (np.empty(n, np.int64), np.empty(n), np.empty(n, bool), np.empty(n, bool), np.empty(n, bool))
    path, steps, returns, bumps, collisions = [cells.copy()], np.full(n, -1, np.int64), np.zeros(n), np.zeros(n, np.int64), 0
    for t, joint in enumerate(joint_actions, 1):
        split_index(joint, N_ACTIONS, actions)
        collisions += rules.step(world, cells, done, actions, *out)
        new_cells, rewards, bumped, _, reached = out
        returns += np.where(done, 0.0, rewards)
        bumps += bumped
        steps[reached] = t
        done |= reached
        cells = new_cells.copy()
        path.append(cells.copy())
    return Rollout(np.array(path, np.int64), steps, returns, collisions, bumps, bool(done.all()))
