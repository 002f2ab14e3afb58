"""What every learner's episode loop shares: buffers, the episode bookkeeping and the binned log.

An episode (the chapter's "iteration", Section 5.3) starts with every agent on its start cell
and ends when every agent is in its goal, or at the step cap. The per-episode measurements are
averaged over blocks of episodes straight into ``log`` (one row per block), so a 200,000-episode
run stays small. The blocks are given by their ``edges`` (block k holds the episodes
``edges[k] <= episode < edges[k + 1]``): :func:`uniform_edges` for blocks of one size,
:func:`log_edges` for blocks that start one episode wide and widen geometrically, so that the
first episodes, where learning happens, are resolved as well as the last ones.

Each learner's run kernel is two functions: ``run`` allocates the run's :class:`Buffers` and calls its
episode loop (``episodes``), compiled with the :data:`LOOP` options. The helpers here, like the
pieces of the step loops, are inlined into the loop by numba (``inline="always"``), except the
small ones called at many places (``rng.next_u64``, ``qlearning.q_update``,
``qlearning.greedy``, and ``rules.moved``, ``bounced``, ``collision_reward`` and ``settle``, which
every step path composes): numba's inlining copies a piece, and every piece inlined into it, at each
place it is called and compiles every copy, so these are compiled once and left for LLVM to inline
(which it does: the loops' machine code has no call to them). That halved the compile time of the
two-agent loops (independent learners from 10 to 6 s, 2observe from 18 to 10 s) and did not change
their speed.

The loop allocates nothing, so it is compiled without numba's reference counting (``_nrt=False``):
numba otherwise counts references on the arrays the loop hands to its inlined pieces, at every
step, whenever a piece uses an array on some of its paths only, and that counting cost sparse
MAQ's loop more than its learning (175 against 47 ns per step for two agents, the same results).
The arrays stay alive in ``run``, which holds them until the loop returns. The loops use numpy's
error model (no zero-division checks; no divisor in them can be zero).

A log row has the same layout for any number of agents N (:func:`n_columns`): N columns of steps
(the steps agent i took to reach the goal, the cap if it did not), N columns of reward (agent i's
undiscounted environment reward in the episode), then the episode's ``MEASURES``. Kernels address
a column with :func:`steps_column`, :func:`reward_column` and :func:`column`; analyses read a
metric of ``METRICS`` (agent means for steps and reward) with :func:`metric`.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import portable
from glamas.gridworld import rules

MEASURES = ("length", "collisions", "coordinations", "capped")
"""The per-episode measurements after the agents' columns: steps until every agent was in the goal,
agent-agent collision events, coordinations (what counts as one is the learner's: 2observe's steps
on which both agents chose to coordinate), 1 when the episode hit the step cap."""
LENGTH, COLLISIONS, COORDINATIONS, CAPPED = range(len(MEASURES))
"""The kernels' codes of MEASURES (:func:`column`)."""
METRICS = ("steps", "reward") + MEASURES
"""What :func:`metric` reads from a log: steps and reward as agent means, then MEASURES."""


LOOP = {"cache": True, "nogil": True, "error_model": "numpy", "_nrt": False}
"""numba options of an episode loop: cached, without the GIL, numpy's error model (no
zero-division checks: no divisor in the learners can be zero), no reference counting (it
allocates nothing)."""


class Schedule(NamedTuple):
    """How long a run lasts and how its log is binned, as the kernels read it."""

    episodes: int
    """Episodes per run."""
    edges: np.ndarray
    """int (blocks + 1,): the log's block edges (:func:`uniform_edges`, :func:`log_edges`)."""
    max_steps: int
    """Step cap per episode."""


def uniform_edges(n_episodes: int, block: int) -> np.ndarray:
    """Edges of blocks of ``block`` episodes (``block`` must divide ``n_episodes``)."""
    return np.arange(0, n_episodes + 1, block, dtype=np.int64)


def log_edges(n_episodes: int, blocks: int) -> np.ndarray:
    """Edges of at most ``blocks`` blocks whose ends are log-spaced from episode 1 to
    ``n_episodes`` (rounded; the first blocks one episode wide)."""
    ends = np.unique(np.round(portable.geomspace(1, n_episodes, blocks)).astype(np.int64))
    return np.concatenate([np.zeros(1, np.int64), ends])


@njit(cache=True, inline="always")
def n_columns(n_agents):
    """Columns of a log row for ``n_agents`` agents."""
    return 2 * n_agents + len(MEASURES)


@njit(cache=True, inline="always")
def steps_column(n_agents, i):
    """The column of agent i's steps to the goal."""
    return i


@njit(cache=True, inline="always")
def reward_column(n_agents, i):
    """The column of agent i's reward."""
    return n_agents + i


@njit(cache=True, inline="always")
def column(n_agents, measure):
    """The column of a measure (LENGTH, COLLISIONS, COORDINATIONS or CAPPED)."""
    return 2 * n_agents + measure


def metric(log: np.ndarray, name: str) -> np.ndarray:
    """Metric ``name`` of METRICS from a log whose last axis is a row: steps and reward averaged
    over the agents, the others as they are (shape: the log's without its last axis)."""
    n_agents = (log.shape[-1] - len(MEASURES)) // 2
    if name == "steps":
        return log[..., :n_agents].mean(axis=-1)
    if name == "reward":
        return log[..., n_agents:2 * n_agents].mean(axis=-1)
    return log[..., 2 * n_agents + MEASURES.index(name)]


class Buffers(NamedTuple):
    """One step's arrays, one entry per agent unless said (:func:`buffers`), as the rules
    (glamas.gridworld.rules.step) fill them."""

    cells: np.ndarray
    """Each agent's cell."""
    done: np.ndarray
    """Whether it is in its goal (it no longer acts)."""
    actions: np.ndarray
    """Its action this step."""
    new_cells: np.ndarray
    """Its cell after the move."""
    rewards: np.ndarray
    """Its reward of the move."""
    bumped: np.ndarray
    """Whether it bumped into a wall or the border."""
    collided: np.ndarray
    """Whether it collided with another agent."""
    reached: np.ndarray
    """Whether it entered its goal."""
    acc: np.ndarray
    """(:func:`n_columns`,): the episode's log row, accumulated."""


@njit(cache=True, inline="always")
def buffers(n_agents):
    """Per-run :class:`Buffers` of ``n_agents`` agents."""
    return Buffers(np.empty(n_agents, np.int64), np.empty(n_agents, np.bool_), np.zeros(n_agents, np.int64),
                   np.empty(n_agents, np.int64), np.empty(n_agents, np.float64), np.empty(n_agents, np.bool_),
                   np.empty(n_agents, np.bool_), np.empty(n_agents, np.bool_),
                   np.empty(n_columns(n_agents), np.float64))


@njit(cache=True, inline="always")
def step(world, b):
    """The agents' joint move (rules.step) on the buffers ``b``; the number of collisions."""
    return rules.step(world, b.cells, b.done, b.actions, b.new_cells, b.rewards, b.bumped, b.collided, b.reached)


@njit(cache=True, inline="always")
def step_pair(world, b, pair):
    """rules.step_pair on the buffers ``b``: only the agents ``pair`` act."""
    return rules.step_pair(world, b.cells, b.done, b.actions, b.new_cells, b.rewards, b.bumped, b.collided, b.reached,
                           pair)


@njit(cache=True, inline="always")
def step_indexed(world, index, b):
    """rules.step_indexed on the buffers ``b``, through the cell index ``index``."""
    return rules.step_indexed(world, index, b.cells, b.done, b.actions, b.new_cells, b.rewards, b.bumped, b.collided,
                              b.reached)


@njit(cache=True, inline="always")
def step_alone(world, b, i):
    """rules.step_alone on the buffers ``b``: agent i acts alone."""
    rules.step_alone(world, b.cells, b.actions, b.new_cells, b.rewards, b.bumped, b.collided, b.reached, i)


@njit(cache=True, inline="always")
def start_episode(starts, cells, done, acc):
    """Every agent on its start cell, none in the goal, the episode's counters at zero."""
    for i in range(starts.shape[0]):
        cells[i] = starts[i]
        done[i] = False
    acc[:] = 0.0


@njit(cache=True, inline="always")
def all_done(done):
    for i in range(done.shape[0]):
        if not done[i]:
            return False
    return True


@njit(cache=True, inline="always")
def few_acting(done):
    """The agents not yet in the goal when they are one or two: ``(i, -1)`` for one alone,
    ``(i, j)`` with i < j for two; ``(-1, -1)`` when three or more are (or none). The loops of N
    agents take the one- and two-agent paths of the rules then (rules.step_alone, rules.step_pair)."""
    first, second = -1, -1
    for i in range(done.shape[0]):
        if not done[i]:
            if second >= 0:
                return -1, -1
            if first >= 0:
                second = i
            else:
                first = i
    return first, second


@njit(cache=True, inline="always")
def end_step(t, cells, done, new_cells, rewards, reached, collisions, acc):
    """Book step ``t``'s rewards, arrivals and collisions, then move the agents to their new cells."""
    n = cells.shape[0]
    acc[column(n, COLLISIONS)] += collisions
    for i in range(n):
        if done[i]:
            continue
        acc[reward_column(n, i)] += rewards[i]
        if reached[i]:
            acc[steps_column(n, i)] = t
            done[i] = True
        cells[i] = new_cells[i]


@njit(cache=True, inline="always")
def end_episode(log, episode, edges, acc, t, done):
    """Close the episode after ``t`` steps and add its measurements to its block's mean (the
    block of ``episode`` between its ``edges``)."""
    n = done.shape[0]
    acc[column(n, LENGTH)] = t
    for i in range(n):
        if not done[i]:
            acc[steps_column(n, i)] = t
            acc[column(n, CAPPED)] = 1.0
    row = np.searchsorted(edges, episode, side="right") - 1
    width = edges[row + 1] - edges[row]
    for k in range(acc.shape[0]):
        log[row, k] += acc[k] / width
