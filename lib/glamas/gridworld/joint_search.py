"""Forward search over the joint states of a map, step by step from the starts: the exact optimum
of the joint MMDP where its tables do not fit (:func:`glamas.gridworld.dp.searched_optimum`).

The MMDP's reward (:func:`glamas.gridworld.rules.shared_reward`) is never positive but for the +100
on the step that brings the last agent into its goal, so an episode of T steps is worth at most
100 gamma**(T - 1). Episodes of at most ``horizon`` steps are searched exhaustively, one layer of
joint states per step, keeping the best discounted return to each state; a joint state is dropped
when some acting agent is farther from its goal than the steps left (alone, an agent needs at least
that many). If the best episode found is worth at least 100 gamma**horizon, no longer one beats it.
"""

import numpy as np
from numba import njit

from glamas.gridworld import rules
from glamas.gridworld.joint import joint_index, split_index
from glamas.errors import UserError


def search_layers(world, distances, gamma: float, horizon: int, max_candidates: int):
    """The layers of the search up to ``horizon`` steps and the best finished episode.

    Returns (layers, best): ``layers[t]`` holds the joint states reached after t steps as arrays
    (states, values, parents, joint actions), ``parents`` indexing layer t - 1; ``best`` is (value,
    steps, parent index in layer steps - 1, joint action) of the best episode that brings every
    agent into its goal within the horizon, or None.
    """
    n_cells = world.next_cell.shape[0]
    start = joint_index(world.starts, n_cells)
    layers = [(np.array([start], np.int64), np.zeros(1), np.full(1, -1, np.int64), np.full(1, -1, np.int64))]
    best = None
    for t in range(horizon):
        states, values = layers[-1][:2]
        size = states.shape[0] * rules.N_ACTIONS ** world.starts.shape[0]
        if size > max_candidates:
            raise UserError(f"the search would try {size:,} joint moves after {t} steps (more than "
                             f"{max_candidates:,}): the map is too open for an exact search at horizon {horizon}")
        found = expand(world, distances, states, values, gamma ** t, horizon - t - 1, size)
        best = _better(best, found, t + 1)
        layers.append(_best_per_state(*found))
    return layers, best


def _better(best, found, steps):
    """The better of ``best`` and the best finished episode among ``found`` (ending after ``steps``)."""
    next_states, next_values, parents, actions, finished = found
    if not finished.any():
        return best
    k = int(np.flatnonzero(finished)[np.argmax(next_values[finished])])
    if best is None or next_values[k] > best[0]:
        return float(next_values[k]), steps, int(parents[k]), int(actions[k])
    return best


def _best_per_state(next_states, next_values, parents, actions, finished):
    """The next layer: per joint state not finished, its best value (the first found among ties)."""
    keep = ~finished
    next_states, next_values, parents, actions = next_states[keep], next_values[keep], parents[keep], actions[keep]
    order = np.lexsort((np.arange(next_states.shape[0]), -next_values, next_states))
    first = np.ones(order.shape[0], bool)
    first[1:] = next_states[order[1:]] != next_states[order[:-1]]
    chosen = order[first]
    return next_states[chosen], next_values[chosen], parents[chosen], actions[chosen]


@njit(cache=True)
def expand(world, distances, states, values, discount, steps_left, size):
    """Every joint move from every joint state of a layer: (next states, values, parent indices,
    joint actions, finished), trimmed; moves after which an acting agent is more than
    ``steps_left`` moves from its goal (``distances``: agents x cells, -1 where none) are dropped.
    ``discount`` weighs this step's shared reward; ``size`` bounds the moves."""
    n, n_cells = world.starts.shape[0], world.next_cell.shape[0]
    next_states, next_values = np.empty(size, np.int64), np.empty(size)
    parents, joint_actions, finished = np.empty(size, np.int64), np.empty(size, np.int64), np.empty(size, np.bool_)
    cells, done, actions = np.empty(n, np.int64), np.empty(n, np.bool_), np.zeros(n, np.int64)
    new_cells, rewards = np.empty(n, np.int64), np.empty(n)
    bumped, collided, reached = np.empty(n, np.bool_), np.empty(n, np.bool_), np.empty(n, np.bool_)
    count = 0
    for k in range(states.shape[0]):
        split_index(states[k], n_cells, cells)
        for i in range(n):
            done[i] = rules.is_goal(world.goals, i, cells[i])
        for joint in range(rules.N_ACTIONS ** n):
            split_index(joint, rules.N_ACTIONS, actions)
            if not _canonical(done, actions):
                continue
            rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            all_in, within_reach = True, True
            for i in range(n):
                acting = not (done[i] or reached[i])
                all_in = all_in and not acting
                d = distances[i, new_cells[i]]
                within_reach = within_reach and (not acting or 0 <= d <= steps_left)
            if not within_reach:
                continue
            next_states[count] = joint_index(new_cells, n_cells)
            next_values[count] = values[k] + discount * rules.shared_reward(world.payoffs, rewards, reached, all_in)
            parents[count], joint_actions[count], finished[count] = k, joint, all_in
            count += 1
    return next_states[:count], next_values[:count], parents[:count], joint_actions[:count], finished[:count]


@njit(cache=True)
def _canonical(done, actions):
    """Whether every agent already in its goal plays action 0: its action is ignored, so the
    other three would only repeat the move."""
    for i in range(done.shape[0]):
        if done[i] and actions[i] != 0:
            return False
    return True


def best_actions(layers, best) -> list[int]:
    """The joint actions of the best episode, first step first."""
    value, steps, parent, action = best
    actions = [action]
    for t in range(steps - 1, 0, -1):
        actions.append(int(layers[t][3][parent]))
        parent = int(layers[t][2][parent])
    return actions[::-1]
