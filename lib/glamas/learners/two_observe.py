"""2observe (Section 5, Alg. 4): a GLA per agent decides from the agents' distance whether to
coordinate; the agents act on independent Q-learners over their own cells, and only when both
chose to coordinate they check whether their preferred actions collide and, if so, one of them
(picked at random) yields with a random other action (Section 5.2).

Alg. 4 as :func:`pair_step` plays it, every step while both agents act (delta their Manhattan
distance):

1. first level: each agent's GLA chooses coordinate or act alone from the context [delta, 1]
   (eq. 15, Boltzmann over x.u_a / T);
2. second level: each agent's Q-learner prefers an action epsilon-greedily on its own cell; if both
   chose to coordinate and the two preferred actions would collide, one agent, picked at random,
   keeps its action and the other takes one of its other three at random;
3. the agents move together and receive r_q, their rewards of the move;
4. each updates its own Q table by eq. 11 (as the independent learners);
5. each GLA receives r_c, its feedback (below), and updates by eq. 13 (the REINFORCE step and the
   bounding term toward h(u), eq. 14).

Plain-Python reference: ``two_observe`` (and ``two_observe_group`` for N agents) in
``lib/glamas/plain/gridworld.py``, with the GLA of ``lib/glamas/plain/gla.py``.

The GLAs' feedback r_c (Fig. 10) is lost. It is rebuilt as ``table[choice, need]`` plus the
chapter's ``0 - delta/10`` when both coordinated without need (Section 5.3), where "need" is one of
three readings (``NEEDS``):

* ``in_range`` (default): the agents could collide in this step, whatever they choose
  (:func:`glamas.gridworld.rules.could_collide`). Section 5.1 has the GLA judge whether the agents
  are within each other's range of interference, and the introduction asks for coordination only
  when a collision is possible.
* ``sampled``: the actions the agents' Q-learners prefer in this step would collide.
* ``outcome``: a collision happened in this step.

**N agents** (the chapter has two; :func:`group_step`). Each agent keeps the first level: one
2-action GLA with the context [delta, 1], delta now the Manhattan distance to the *nearest* other
agent still acting (lowest agent number on ties). An agent alone in the world (every other agent
in the goal) acts on its Q-learner and its GLA is not updated, as with two agents. The second level
generalises Section 5.2's coordination to groups: among the agents that chose to coordinate, those
whose preferred action would collide with another coordinating agent's preferred action go in a
random order; each keeps its preferred action unless it would collide with an agent earlier in the
order that kept its own, and then takes an action drawn uniformly from its other three. For two
agents this is the chapter's rule and draws the very same random numbers as
:func:`yield_at_random`. Need is read per agent: ``in_range``, it could collide with some other
acting agent; ``sampled``, its preferred action would collide with another acting agent's;
``outcome``, it collided. "Both coordinated" means it and its nearest other agent both chose to
coordinate. The log's coordinations count agent-steps coordinating with their nearest agent,
halved: for two agents, the steps on which both coordinated.

The group step looks only at each agent's neighbours, through indexes of the cells filled at the
start of a step (:class:`Group`): the nearest other agent is searched ring by ring outward from the
agent's cell on a grid of the acting agents (:func:`nearest_other`; once the rings have covered as
many cells as there are acting agents, those are tried one by one instead), "in range" on the
cells in range of its own (rules.in_range_lists) and only when the nearest agent is near enough,
a coming collision among the agents aiming at the agent's target and the agent on it (a
rules.CellIndex of the preferred actions, :func:`conflict`), and the move goes through
rules.step_indexed. Every answer is the one the search over all pairs gives (the lowest-numbered
agent among the nearest; the same agents in the coordination order), so the group step draws the
same random numbers and learns the same as over all pairs, at a cost that grows with its acting
agents, not with their pairs.

For two agents :func:`group_step` plays exactly what :func:`pair_step`, the chapter's Alg. 4
written for two, plays (same random numbers, Q tables, GLA parameters and counts, under every
reading), so the episode loops step with :func:`pair_step` whenever two agents act, which is
faster. The learner runs two agents on :func:`run_two`, whose loop has no group step and compiles
in less time (10 s against 16 s), and more on :func:`run` (its spec's ``two_agent_kernel`` and
``kernel``). ``need_counts`` counts observing agent-steps per distance, without and with need:
two agents observe at the same distance with the same need, so such a step counts twice.
"""

from collections import namedtuple
from dataclasses import dataclass, fields, replace
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import checks, gla, rng
from glamas.gridworld import GridMap, rules
from glamas.learners import episode as ep
from glamas.learners.independent import lone_step, table_shape
from glamas.learners.registry import register
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, q_update
from glamas.errors import UserError

ACT_ALONE = 0
"""GLA action: ignore the other agent this step."""
COORDINATE = 1
"""GLA action: coordinate with the other agent this step."""
N_GLA_INPUTS = 2
"""The GLA context [delta * delta_scale, 1]: the agents' Manhattan distance and a bias input."""
NOBODY = rules.NOBODY
"""The nearest other agent of an agent that has nobody to observe (:func:`nearest_others`)."""
GONE = -1
"""The cell a kept trace gives an agent in its goal (:func:`episodes`): it has left the map."""

NEED_IN_RANGE = 0
NEED_SAMPLED = 1
NEED_OUTCOME = 2
NEEDS = {"in_range": NEED_IN_RANGE, "sampled": NEED_SAMPLED, "outcome": NEED_OUTCOME}
"""The readings of Fig. 10's "need to coordinate" (module docstring), by name."""
DELTA_SCALES = ("cells", "unit")
"""How the GLA context holds delta: in cells, or divided by the map's largest distance."""


@dataclass(frozen=True)
class GLASettings:
    """2observe's own settings: the first level's GLAs (eq. 12-15) and their feedback (Fig. 10, lost;
    see the module docstring). The chapter's values as defaults where it states them (Sec. 5.3),
    the rest documented choices."""

    gla_learning_rate: float = 0.01
    """lambda of eq. 13 (Sec. 5.3)."""
    gla_temperature: float = 0.5
    """T of eq. 15 (not stated for this experiment; Sec. 4.2 uses 0.5)."""
    gla_K: float = 1.0
    """K of eq. 13 (not stated for this experiment; Sec. 4.2 uses 1)."""
    gla_L: float | None = None
    """L of eq. 14 (not stated for this experiment); None: the map's largest distance
    (:func:`box`), 8 on TunnelToGoal. Sec. 4.2's L = 1 bounds parameters for inputs in [-1, 1]; here
    delta runs to the map's largest distance, and L = 1 x that distance lets u.x draw a sharp
    boundary at any distance the map has."""
    gla_bounding: str = "clip"
    """h of eq. 14: 'clip' or 'printed' (see glamas.gla)."""
    gla_init_range: float = 0.1
    """GLA parameters start uniform in [-gla_init_range, gla_init_range] ("initialised randomly",
    range not stated). 0.1 keeps every start learnable: with delta up to 8 cells and T = 0.5 no
    logit exceeds 1.8, as Sec. 4's GLAs start on inputs in [-1, 1]; a range of 1 saturates some
    GLAs at delta >= 3 from the first step, where eq. 13's gradient has vanished."""
    gla_delta_scale: str = "cells"
    """The GLA context [delta, 1]: delta in 'cells', or 'unit' (divided by the map's largest
    distance, into [0, 1] like Sec. 4's inputs)."""
    gla_need: str = "in_range"
    """What "need to coordinate" means in Fig. 10 (lost): 'in_range', the agents could collide this
    step (Sec. 5.1: within each other's range of interference); 'sampled', their preferred actions
    would collide; 'outcome', they collided (module docstring)."""
    gla_feedback: tuple = ((1.0, 0.0), (0.0, 1.0))
    """Fig. 10 (lost), reconstructed: feedback[choice][need], choice 0 = act alone, 1 = coordinate:
    1 for the right choice, 0 for the wrong one."""
    coordination_penalty_per_cell: float = 0.1
    """Added feedback -this * delta when both coordinated without need (Sec. 5.3's 0 - delta/10)."""
    rule_distance: int | None = None
    """None: the GLAs learn when to coordinate (Alg. 4). A whole number d: a diagnostic, not in
    the chapter, replacing the GLAs by the fixed rule "coordinate when delta < d"."""

    def __post_init__(self):
        checks.field_types(self)
        _gla_params(self, 1.0 if self.gla_L is None else self.gla_L)  # glamas.gla's checks and messages
        if not (isinstance(self.gla_init_range, (int, float)) and self.gla_init_range >= 0):
            raise UserError(f"gla_init_range must be a number >= 0, got {self.gla_init_range!r}")
        if self.gla_L is not None and self.gla_init_range > self.gla_L:
            raise UserError(f"gla_init_range must be in [0, gla_L={self.gla_L}], got {self.gla_init_range!r}")
        table = np.array(self.gla_feedback, dtype=float) if _is_table(self.gla_feedback) else None
        if table is None or table.shape != (2, 2) or not np.isfinite(table).all():
            raise UserError("gla_feedback must be a 2x2 table of numbers, rows = (act alone, "
                             f"coordinate), columns = (no need, need); got {self.gla_feedback!r}")
        object.__setattr__(self, "gla_feedback", tuple(tuple(float(v) for v in row) for row in table))
        if not (isinstance(self.coordination_penalty_per_cell, (int, float)) and self.coordination_penalty_per_cell >= 0):
            raise UserError("coordination_penalty_per_cell must be a number >= 0, "
                             f"got {self.coordination_penalty_per_cell!r}")
        if self.gla_need not in NEEDS:
            raise UserError(f"gla_need must be one of {sorted(NEEDS)}, got {self.gla_need!r}")
        if self.gla_delta_scale not in DELTA_SCALES:
            raise UserError(f"gla_delta_scale must be one of {sorted(DELTA_SCALES)}, got {self.gla_delta_scale!r}")
        if self.rule_distance is not None:
            checks.whole_numbers(self, {"rule_distance": 0})


def _is_table(value) -> bool:
    try:
        np.array(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def _gla_params(settings: GLASettings, L: float) -> gla.GLAParams:
    return gla.GLAParams(learning_rate=settings.gla_learning_rate, temperature=settings.gla_temperature,
                         K=settings.gla_K, L=L, bounding=settings.gla_bounding)


def largest_distance(gridmap: GridMap) -> int:
    """The largest Manhattan distance delta the map's rows and columns allow (8 on TunnelToGoal)."""
    return gridmap.n_rows + gridmap.n_cols - 2


def box(settings: GLASettings, gridmap: GridMap) -> float:
    """L of eq. 14 on ``gridmap``: ``gla_L``, or the map's largest distance when it is None."""
    return float(largest_distance(gridmap)) if settings.gla_L is None else float(settings.gla_L)


def gla_params(settings: GLASettings, gridmap: GridMap) -> gla.GLAParams:
    """The GLAs' eq. 13-15 parameters on ``gridmap`` (the box L from :func:`box`)."""
    L = box(settings, gridmap)
    if settings.gla_init_range > L:
        raise UserError(f"gla_init_range ({settings.gla_init_range}) must be at most the GLA box L = {L:g} "
                         f"on map {gridmap.name!r}; give a smaller gla_init_range or a larger gla_L")
    return _gla_params(settings, L)


Automata = namedtuple("Automata", [field.name for field in fields(GLASettings)])
"""2observe's first level as the kernel reads it: each of :class:`GLASettings` under its name, in
the form :func:`automata` gives it."""


def delta_scale(mode: str, gridmap: GridMap) -> float:
    """The factor of delta in the GLA context: 1 for 'cells', one over the map's largest
    Manhattan distance for 'unit'."""
    return 1.0 if mode == "cells" else 1.0 / largest_distance(gridmap)


def automata(setup, gridmap: GridMap) -> tuple:
    """The kernel's own input: the :data:`Automata` bundle of 2observe's settings (``setup.own``) on
    ``gridmap``: the box L as it is on the map (:func:`box`), codes where the settings hold names
    (``gla_bounding`` of glamas.gla.BOUNDING_MODES, ``gla_need`` of NEEDS), the feedback a (2, 2)
    array, the delta scale its factor (:func:`delta_scale`), and ``rule_distance`` -1 where the
    GLAs learn. A ``gla_init_range`` below 0 starts a run from the GLA parameters it is given
    (:func:`freeze`)."""
    s = setup.own
    p = gla_params(s, gridmap)
    return (Automata(gla_learning_rate=p.learning_rate, gla_temperature=p.temperature, gla_K=p.K, gla_L=p.L,
                     gla_bounding=p.bounding_code, gla_init_range=float(s.gla_init_range),
                     gla_delta_scale=delta_scale(s.gla_delta_scale, gridmap), gla_need=NEEDS[s.gla_need],
                     gla_feedback=np.array(s.gla_feedback),
                     coordination_penalty_per_cell=float(s.coordination_penalty_per_cell),
                     rule_distance=-1 if s.rule_distance is None else s.rule_distance),)


def freeze(inputs: tuple) -> tuple:
    """The kernel's own input with learning off (:attr:`glamas.learners.spec.Learner.freeze`): the
    GLAs neither drawn afresh nor updated (lambda of eq. 13 zero), so a run plays the GLA
    parameters it is given."""
    (automata,) = inputs
    return (automata._replace(gla_learning_rate=0.0, gla_init_range=-1.0),)


def outputs(setup, gridmap: GridMap) -> dict:
    """One run's GLA parameters ``u`` (agents, 2 actions, 2 inputs; drawn by the kernel from the
    run's stream, then learned), the parameters it drew at the start ``u_initial``, and
    ``need_counts`` (distances 0 .. rows + cols - 2, without / with need)."""
    shape = (gridmap.n_agents, 2, N_GLA_INPUTS)
    return {"u": np.zeros(shape), "u_initial": np.zeros(shape), "need_counts": np.zeros((largest_distance(gridmap) + 1, 2))}


def gla_parameters(setup, gridmap: GridMap) -> int:
    """The GLAs' parameters per run (none when the fixed rule replaces them)."""
    return 0 if setup.own.rule_distance is not None else gridmap.n_agents * 2 * N_GLA_INPUTS


@njit(cache=True, inline="always")
def init_glas(u, u_initial, init_range, state):
    """Every GLA parameter uniform in [-init_range, init_range] ("initialised randomly", Section 5.3),
    the run's first draws, kept in ``u_initial`` too; a negative ``init_range`` keeps ``u`` and
    ``u_initial`` as they are given (a frozen evaluation of learned GLAs, :func:`freeze`)."""
    if init_range < 0.0:
        return
    for i in range(u.shape[0]):
        for j in range(2):
            for k in range(N_GLA_INPUTS):
                u[i, j, k] = init_range * (2.0 * rng.uniform(state) - 1.0)
                u_initial[i, j, k] = u[i, j, k]


@njit(cache=True, inline="always")
def yield_at_random(preferred, actions, pair, state):
    """Section 5.2's coordination of the agents ``pair``: one of them (picked at random) keeps
    its preferred action, the other takes an action drawn uniformly from its other three."""
    yielder = pair[rng.integer(state, 2)]
    other = rng.integer(state, 3)
    actions[yielder] = other + 1 if other >= preferred[yielder] else other


@njit(cache=True, inline="always")
def first_level(next_cell, goals, cells, done, choices, preferred, pair):
    """Alg. 4's if-condition for the agents ``pair = (i, j)``, their GLA ``choices`` and
    Q-preferred actions ``preferred``: (collision coming, both coordinated). When both hold, one
    agent yields (:func:`yield_at_random`).

    "Collision coming" means the preferred actions would collide (rules.would_collide): Section
    5.2's check, made only when both chose to coordinate.
    """
    i, j = pair
    coming = rules.would_collide(next_cell, goals, cells, done, preferred, i, j)
    choice_i, choice_j = choices[i], choices[j]  # both read: arrays outside branches (glamas.learners.episode)
    return coming, choice_i == COORDINATE and choice_j == COORDINATE


@njit(cache=True, inline="always")
def need_before_step(need, in_range, cells, i, j, coming):
    """Agent i's need to coordinate with agent j under the readings decided before the move
    (``in_range``: the table of rules.in_range_table; ``sampled``: ``coming`` is whether i's and
    j's preferred actions collide); False for ``outcome``, which the move decides."""
    could_collide = in_range[cells[i], cells[j]]  # looked up outside the branches (glamas.learners.episode)
    if need == NEED_IN_RANGE:
        return could_collide
    return need == NEED_SAMPLED and coming


@njit(cache=True, inline="always")
def gla_feedback(table, penalty_per_cell, choice, need, both, delta):
    """r_c of Alg. 4 (Fig. 10, reconstructed): table[choice, need], minus ``penalty_per_cell *
    delta`` when both coordinated without need (Section 5.3's 0 - delta/10)."""
    beta = table[choice, 1 if need else 0]
    # & rather than and: both sides read, no branch on the choices, which go either way while the
    # GLAs learn (as in the group step's tests of both choices)
    return beta - (penalty_per_cell * delta if both & (not need) else 0.0)


@njit(cache=True, inline="always")
def nearest_others(distances, cells, done, nearest, deltas):
    """For every acting agent: the nearest other acting agent (lowest number on ties) and its
    Manhattan distance (``distances``: rules.distance_table); ``nearest`` is NOBODY for agents that
    are done or alone."""
    n = cells.shape[0]
    for i in range(n):
        nearest[i] = NOBODY
        deltas[i] = 0
        if done[i]:
            continue
        for j in range(n):
            if j == i or done[j]:
                continue
            d = distances[cells[i], cells[j]]
            if nearest[i] == NOBODY or d < deltas[i]:
                nearest[i] = j
                deltas[i] = d


@njit(cache=True, inline="always")
def random_order(members, count, state):
    """Shuffle ``members[:count]`` uniformly (Durstenfeld: from the back, one draw per place)."""
    for i in range(count - 1, 0, -1):
        j = rng.integer(state, i + 1)
        members[i], members[j] = members[j], members[i]


class Rings(NamedTuple):
    """The map's cells as :func:`nearest_other` searches them, ring by ring around a cell: a grid
    with a border of empty cells as wide as the widest ring searched, so that a ring is a list of
    offsets, the same from every cell."""

    grid: np.ndarray
    """int32 (padded cells,): the acting agent on each cell, NOBODY elsewhere and on the border
    (filled during a step, empty between steps; 32 bits, for the cache)."""
    padded: np.ndarray
    """int (cells,): each map cell's place in ``grid``."""
    offsets: np.ndarray
    """int: the offsets in ``grid`` of the cells at distance 1, RING_END, those at distance 2,
    RING_END, and so on (a loop to the next RING_END is one the compiler does not vectorize: vector
    gathers cost the few cells of a ring more than plain loads)."""
    depth: int
    """The rings in ``offsets``."""
    rows: np.ndarray
    """int (cells,): each map cell's row."""
    cols: np.ndarray
    """int (cells,): each map cell's column."""


RING_END = np.iinfo(np.int64).min
"""The end of a ring in ``Rings.offsets`` (no offset)."""
FAR = np.uint32(0xFFFFFFFF)
"""NOBODY in ``Rings.grid`` read as an unsigned number: above every agent's number."""


@njit(cache=True, inline="always")
def rings(world):
    """:class:`Rings` for the world: as many rings as :func:`nearest_other` can search before it
    tries the agents one by one (rings 1 .. D cover 2 D (D + 1) cells, at least the agents)."""
    n_agents, n_cells, n_cols = world.starts.shape[0], world.next_cell.shape[0], world.n_cols
    n_rows = n_cells // n_cols
    depth = 1
    while 2 * depth * (depth + 1) < n_agents:
        depth += 1
    width = n_cols + 2 * depth
    grid = np.full((n_rows + 2 * depth) * width, NOBODY, np.int32)
    padded, rows, cols = np.empty(n_cells, np.int64), np.empty(n_cells, np.int64), np.empty(n_cells, np.int64)
    for cell in range(n_cells):
        rows[cell], cols[cell] = cell // n_cols, cell % n_cols
        padded[cell] = (rows[cell] + depth) * width + cols[cell] + depth
    offsets = np.empty(2 * depth * (depth + 1) + depth, np.int64)
    k = 0
    for d in range(1, depth + 1):
        for dr in range(-d, d + 1):
            rest = d - abs(dr)
            for dc in range(-rest, rest + 1, max(2 * rest, 1)):  # -rest and rest, or 0
                offsets[k] = dr * width + dc
                k += 1
        offsets[k] = RING_END
        k += 1
    return Rings(grid, padded, offsets, depth, rows, cols)


@njit(cache=True, inline="always")
def unsigned(place):
    """``place``, an index known not to be negative, as an unsigned number. Numba checks every
    signed index for a negative value (to count it from the end); in the group step's innermost
    loops (the rings, the cells in range, the agents aiming at a cell) that check cost some 15 % of
    the step's time at 128 agents (benchmarks/bench_many_agents.py)."""
    return np.uint64(place)


@njit(cache=True, inline="always")
def nearest_other(rings, cells, acting, n_acting, i):
    """(the nearest other acting agent of acting agent i, its Manhattan distance): the lowest
    number among the nearest, as :func:`nearest_others`; (NOBODY, 0) when i acts alone.

    ``rings.grid`` holds the acting agents by cell, ``acting[:n_acting]`` the acting agents in
    increasing order. The search goes ring by ring outward from i's cell, every cell at distance 1,
    then 2, and so on (the lowest agent number of the first ring that has one); once the rings have
    covered as many cells as there are acting agents, it tries those agents one by one instead (few
    agents far apart)."""
    grid, offsets = rings.grid, rings.offsets
    cell = cells[i]
    here = rings.padded[cell]
    covered, k = 0, 0
    for d in range(1, rings.depth + 1):
        if covered >= n_acting:
            break
        lowest = FAR
        offset = offsets[unsigned(k)]
        while offset != RING_END:
            lowest = min(lowest, np.uint32(grid[unsigned(here + offset)]))
            k += 1
            offset = offsets[unsigned(k)]
        k += 1
        if lowest != FAR:
            return np.int64(lowest), d
        covered += 4 * d
    row, col, rows, cols = rings.rows[cell], rings.cols[cell], rings.rows, rings.cols
    best, best_d = NOBODY, 0
    for m in range(n_acting):
        j = acting[m]
        other = cells[j]
        d = abs(rows[other] - row) + abs(cols[other] - col)
        if j != i and (best == NOBODY or d < best_d):
            best, best_d = j, d
    return best, best_d


@njit(cache=True)
def conflict(next_cell, goals, cells, done, preferred, index, i, among):
    """Whether agent i's preferred action would collide (rules.would_collide) with the preferred
    action of an agent j with ``among[j]``. Only the agents that can collide with it are tried:
    the agents aiming at i's target and the agent on it, from ``index`` (rules.index_agents with
    the preferred actions). Compiled once and called from its three places, where LLVM inlines it,
    rather than copied into each by numba (glamas.learners.episode)."""
    target = unsigned(next_cell[cells[i], preferred[i]])
    j = index.claimant[target]
    while j != NOBODY:
        if j != i and among[unsigned(j)] and rules.would_collide(next_cell, goals, cells, done, preferred, i, j):
            return True
        j = index.next_claimant[unsigned(j)]
    j = index.occupant[target]
    return j != NOBODY and j != i and among[j] and rules.would_collide(next_cell, goals, cells, done, preferred, i, j)


@njit(cache=True, inline="always")
def in_range_of_any(group, cells, i):
    """Whether acting agent i could collide with some other acting agent in this step: an acting
    agent on a cell in range of i's (rules.in_range_lists; ``group.rings.grid`` holds the acting
    agents by cell). ``group.deltas[i]``, i's distance to its nearest other agent, must be the
    step's: farther than ``group.reach`` nobody is in range."""
    if group.deltas[i] > group.reach:
        return False
    cell, first, near, grid = cells[i], group.in_range_first, group.in_range_padded, group.rings.grid
    for k in range(first[cell], first[cell + 1]):
        if grid[unsigned(near[unsigned(k)])] != NOBODY:
            return True
    return False


@njit(cache=True, inline="always")
def coordinate_group(next_cell, goals, cells, done, choices, preferred, actions, group, state):
    """Section 5.2's coordination for a group (module docstring): fill ``actions`` from the
    ``preferred`` ones; return how many coordinating agents were in a coming collision.

    ``group`` (:func:`group_arrays`) holds the per-run buffers, and in ``group.index`` the acting
    agents by cell and by preferred target (:func:`index_preferred`), through which each agent
    tries only the agents it could collide with (:func:`conflict`).
    """
    order, kept, coordinating, index = group.order, group.kept, group.coordinating, group.index
    n = cells.shape[0]
    n_coordinating = 0
    for i in range(n):
        actions[i] = preferred[i]
        coordinating[i] = (not done[i]) & (choices[i] == COORDINATE)
        kept[i] = False  # so far: kept[j] holds for the agents earlier in the order that keep theirs
        order[n_coordinating] = i  # the coordinating agents first, counted without a branch on them
        n_coordinating += coordinating[i]
    count = 0
    for k in range(n_coordinating):
        i = order[k]
        order[count] = i  # then those of them in a coming collision
        count += conflict(next_cell, goals, cells, done, preferred, index, i, coordinating)
    random_order(order, count, state)
    for k in range(count):
        i = order[k]
        keep = not conflict(next_cell, goals, cells, done, preferred, index, i, kept)
        kept[i] = keep
        if not keep:
            other = rng.integer(state, 3)
            actions[i] = other + 1 if other >= preferred[i] else other
    return count


@njit(cache=True, inline="always")
def index_preferred(group, next_cell, cells, done, preferred):
    """Enter the acting agents in ``group.index`` by cell and by the target of their preferred
    action (rules.index_agents); :func:`clear_preferred` empties it."""
    rules.index_agents(group.index, cells, done, next_cell, preferred)


@njit(cache=True, inline="always")
def clear_preferred(group, next_cell, cells, done, preferred):
    """Empty what :func:`index_preferred` filled."""
    rules.clear_index(group.index, cells, done, next_cell, preferred)


class Agents(NamedTuple):
    """Each agent's first-level arrays (:func:`per_run`)."""

    choices: np.ndarray
    """Its GLA's choice, ACT_ALONE or COORDINATE."""
    preferred: np.ndarray
    """The action its Q-learner prefers (an action even for agents already done: rules.would_collide
    reads it)."""
    probs: np.ndarray
    """(agents, 2): its GLA's probabilities."""
    inputs: np.ndarray
    """(agents, N_GLA_INPUTS): its GLA's context [delta, 1]."""


@njit(cache=True, inline="always")
def per_run(world):
    """The per-run arrays of :func:`episodes_two` and :func:`pair_step`: (the in-range table
    rules.in_range_table, the step's ep.Buffers, the :class:`Agents`), unpacked by name where read.
    A plain tuple, not a NamedTuple: numba concatenates plain tuples only, and the crowd's replay
    builds :func:`episodes`'s arrays as ``(*per_run(world), ...)``."""
    n = world.starts.shape[0]
    agents = Agents(np.empty(n, np.int64), np.zeros(n, np.int64), np.empty((n, 2)), np.ones((n, N_GLA_INPUTS)))
    return rules.in_range_table(world.next_cell, rules.shared_goals(world.goals)), ep.buffers(n), agents


class Group(NamedTuple):
    """:func:`group_step`'s per-run arrays (:func:`group_arrays`), one entry per agent unless said."""

    nearest: np.ndarray
    """Each agent's nearest other acting agent (NOBODY: done or alone)."""
    deltas: np.ndarray
    """Its distance to that agent."""
    coming: np.ndarray
    """Whether its preferred action would collide with another agent's."""
    needed: np.ndarray
    """Its need to coordinate (module docstring)."""
    order: np.ndarray
    """The coordination order (:func:`coordinate_group`)."""
    kept: np.ndarray
    """Who keeps its preferred action (:func:`coordinate_group`)."""
    coordinating: np.ndarray
    """Acting and chose to coordinate (:func:`coordinate_group`)."""
    everyone: np.ndarray
    """True for every agent (:func:`conflict` with anyone)."""
    acting: np.ndarray
    """The acting agents in increasing order, first the step's count of them."""
    rings: Rings
    """The acting agents by cell, for the nearest other agent (:func:`nearest_other`)."""
    index: rules.CellIndex
    """The acting agents by cell and by preferred target, filled during a step."""
    step_index: rules.CellIndex
    """rules.step_indexed's own."""
    in_range_first: np.ndarray
    """(cells + 1,): where each cell's list of the cells in range starts (rules.in_range_lists)."""
    in_range_padded: np.ndarray
    """The cells in range, cell by cell (rules.in_range_lists), as places in ``rings.grid``."""
    reach: int
    """The largest Manhattan distance between two cells in range (2 on a grid): agents farther
    apart can neither collide nor be in range."""


@njit(cache=True, inline="always")
def group_arrays(world):
    """:func:`group_step`'s per-run arrays (:class:`Group`), which :func:`episodes` adds to
    :func:`per_run`'s."""
    n = world.starts.shape[0]
    first, near = rules.in_range_lists(world.next_cell, rules.shared_goals(world.goals))
    around = rings(world)
    reach = 0
    for a in range(first.shape[0] - 1):
        for k in range(first[a], first[a + 1]):
            reach = max(reach, rules.manhattan(world.n_cols, a, near[k]))
            near[k] = around.padded[near[k]]
    return Group(np.empty(n, np.int64), np.empty(n, np.int64), np.empty(n, np.bool_), np.empty(n, np.bool_),
                 np.empty(n, np.int64), np.empty(n, np.bool_), np.empty(n, np.bool_), np.ones(n, np.bool_),
                 np.empty(n, np.int64), around, rules.cell_index(world), rules.cell_index(world), first, near, reach)


@njit(cache=True, nogil=True)
def run_two(world, learning, automata, schedule, q, u, u_initial, need_counts, log, state):
    """One run of Alg. 4 for two agents, the chapter's case (:func:`episodes_two`), from GLAs
    initialised randomly (:func:`init_glas`)."""
    init_glas(u, u_initial, automata.gla_init_range, state)
    episodes_two(world, learning, automata, schedule, q, u, need_counts, log, state, per_run(world))


@njit(cache=True, nogil=True)
def run(world, learning, automata, schedule, q, u, u_initial, need_counts, log, state):
    """One run of Alg. 4 for any number of agents (:func:`episodes`), from GLAs initialised randomly."""
    init_glas(u, u_initial, automata.gla_init_range, state)
    episodes(world, learning, automata, schedule, q, u, need_counts, log, state,
             (*per_run(world), group_arrays(world), nothing_kept()))


@njit(cache=True, inline="always")
def nothing_kept():
    """:func:`episodes`'s ``kept`` arrays when nothing is to be kept: a trace and yields of no episodes."""
    return np.empty((0, 0, 0), np.int32), np.empty(0, np.int64)


@njit(cache=True, inline="always")
def keep_cells(row, cells, done):
    """Every agent's cell into ``row`` of a trace, GONE for an agent in its goal."""
    for i in range(cells.shape[0]):
        row[i] = GONE if done[i] else cells[i]


@njit(cache=True, inline="always")
def yielded(done, preferred, actions):
    """The acting agents whose action is not the one they preferred (the coordination made them yield)."""
    count = 0
    for i in range(done.shape[0]):
        count += (not done[i]) and actions[i] != preferred[i]
    return count


@njit(cache=True, inline="always")
def pair_step(world, learning, automata, q, u, need_counts, pair, state, own):
    """One step of Alg. 4 for the agents ``pair = (i, j)``, i < j, when every other agent is in
    the goal (the chapter's two agents); learns in ``q`` and ``u``, counts the step in
    ``need_counts`` and returns the number of collisions. ``own``: :func:`per_run`'s.

    The GLAs see ``[delta * gla_delta_scale, 1]``. ``rule_distance`` >= 0 replaces the GLAs by the
    fixed rule "coordinate when delta < rule_distance" (a diagnostic).
    """
    next_cell, goals, n_agents = world.next_cell, world.goals, world.starts.shape[0]
    alpha, gamma, exploit = learning.q_learning_rate, learning.discount, learning.exploit_prob
    temperature, L, bounding = automata.gla_temperature, automata.gla_L, automata.gla_bounding
    need, rule_distance, feedback = automata.gla_need, automata.rule_distance, automata.gla_feedback
    learn_first_level = rule_distance < 0
    in_range, buffers, agents = own
    cells, done, actions, acc = buffers.cells, buffers.done, buffers.actions, buffers.acc
    new_cells, rewards, reached = buffers.new_cells, buffers.rewards, buffers.reached
    choices, preferred, probs, inputs = agents.choices, agents.preferred, agents.probs, agents.inputs
    i, j = pair  # written out for i and j: a loop over the pair costs the loop its speed
    delta = rules.manhattan(world.n_cols, cells[i], cells[j])
    x = inputs[i]  # both agents' GLAs see the same input
    x[0] = delta * automata.gla_delta_scale
    if learn_first_level:
        choices[i] = gla.act_two(u[i], x, temperature, L, bounding, probs[i], state)
        choices[j] = gla.act_two(u[j], x, temperature, L, bounding, probs[j], state)
    else:
        choices[i] = choices[j] = COORDINATE if delta < rule_distance else ACT_ALONE
    preferred[i] = epsilon_greedy(q[i, cells[i]], exploit, state)
    preferred[j] = epsilon_greedy(q[j, cells[j]], exploit, state)
    coming, both = first_level(next_cell, goals, cells, done, choices, preferred, pair)
    actions[i], actions[j] = preferred[i], preferred[j]
    if both and coming:
        yield_at_random(preferred, actions, pair, state)
    needed = need_before_step(need, in_range, cells, i, j, coming)
    if both:
        acc[ep.column(n_agents, ep.COORDINATIONS)] += 1
    collisions = ep.step_pair(world, buffers, pair)
    if need == NEED_OUTCOME:
        needed = collisions > 0
    need_counts[delta, 1 if needed else 0] += 2  # both agents observe: same delta, same need
    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)
    q_update(q[j], cells[j], actions[j], rewards[j], new_cells[j], reached[j], alpha, gamma)
    if learn_first_level:
        penalty, rate, K = automata.coordination_penalty_per_cell, automata.gla_learning_rate, automata.gla_K
        beta_i = gla_feedback(feedback, penalty, choices[i], needed, both, delta)
        gla.update(u[i], x, choices[i], beta_i, rate, temperature, K, L, bounding, probs[i])
        beta_j = gla_feedback(feedback, penalty, choices[j], needed, both, delta)
        gla.update(u[j], x, choices[j], beta_j, rate, temperature, K, L, bounding, probs[j])
    return collisions


@njit(cache=True, inline="always")
def group_step(world, learning, automata, q, u, need_counts, state, arrays):
    """One step of Alg. 4 for any number of acting agents, with the group coordination of the
    module docstring; as :func:`pair_step` otherwise. ``arrays``: :func:`episodes`'s, as it is given
    them (taken apart there and passed as its pieces, the step at 128 agents took some 15 % longer).
    Each agent's lookups go through the group's index of the cells (:class:`Group`, module
    docstring): a step costs in proportion to its acting agents."""
    _, buffers, agents, group, _ = arrays  # not the in-range table: the group's index answers
    next_cell, goals, n_agents = world.next_cell, world.goals, world.starts.shape[0]
    alpha, gamma = learning.q_learning_rate, learning.discount
    learn_first_level = automata.rule_distance < 0
    cells, done, actions, acc = buffers.cells, buffers.done, buffers.actions, buffers.acc
    new_cells, rewards, collided, reached = buffers.new_cells, buffers.rewards, buffers.collided, buffers.reached
    choices, preferred, probs, x = agents.choices, agents.preferred, agents.probs, agents.inputs
    nearest, deltas, coming, needed, acting = group.nearest, group.deltas, group.coming, group.needed, group.acting
    grid, padded = group.rings.grid, group.rings.padded
    n_acting = 0
    for i in range(n_agents):
        if not done[i]:
            acting[n_acting] = i
            n_acting += 1
            grid[padded[cells[i]]] = i
    for i in range(n_agents):
        nearest[i], deltas[i] = NOBODY, 0
        choices[i] = ACT_ALONE
        if done[i]:
            continue
        nearest[i], deltas[i] = nearest_other(group.rings, cells, acting, n_acting, i)
        if nearest[i] == NOBODY:
            continue
        if automata.gla_need == NEED_IN_RANGE:  # decided by the cells before the move, read here near them
            needed[i] = in_range_of_any(group, cells, i)
        x[i, 0] = deltas[i] * automata.gla_delta_scale
        if learn_first_level:
            choices[i] = gla.act_two(u[i], x[i], automata.gla_temperature, automata.gla_L,
                                     automata.gla_bounding, probs[i], state)
        elif deltas[i] < automata.rule_distance:
            choices[i] = COORDINATE
    for i in range(n_agents):
        if not done[i]:
            preferred[i] = epsilon_greedy(q[i, cells[i]], learning.exploit_prob, state)
    index_preferred(group, next_cell, cells, done, preferred)
    if automata.gla_need == NEED_SAMPLED:  # read by that reading only
        for i in range(n_agents):
            coming[i] = (not done[i] and deltas[i] <= group.reach
                         and conflict(next_cell, goals, cells, done, preferred, group.index, i, group.everyone))
    coordinate_group(next_cell, goals, cells, done, choices, preferred, actions, group, state)
    paired = 0
    for i in range(n_agents):
        if nearest[i] != NOBODY:
            paired += (choices[i] == COORDINATE) & (choices[nearest[i]] == COORDINATE)
    acc[ep.column(n_agents, ep.COORDINATIONS)] += paired / 2
    collisions = ep.step_indexed(world, group.step_index, buffers)
    for i in range(n_agents):
        if nearest[i] != NOBODY:
            if automata.gla_need == NEED_SAMPLED:
                needed[i] = coming[i]
            elif automata.gla_need == NEED_OUTCOME:
                needed[i] = collided[i]
            need_counts[deltas[i], 1 if needed[i] else 0] += 1
    clear_preferred(group, next_cell, cells, done, preferred)
    for k in range(n_acting):
        grid[padded[cells[acting[k]]]] = NOBODY
    for i in range(n_agents):
        if not done[i]:
            q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i], alpha, gamma)
    if learn_first_level:
        for i in range(n_agents):
            if nearest[i] == NOBODY:
                continue
            both = (choices[i] == COORDINATE) & (choices[nearest[i]] == COORDINATE)
            beta = gla_feedback(automata.gla_feedback, automata.coordination_penalty_per_cell, choices[i],
                                needed[i], both, deltas[i])
            gla.update(u[i], x[i], choices[i], beta, automata.gla_learning_rate, automata.gla_temperature,
                       automata.gla_K, automata.gla_L, automata.gla_bounding, probs[i])
    return collisions


@njit(**ep.LOOP)
def episodes_two(world, learning, automata, schedule, q, u, need_counts, log, state, own):
    """The episodes of Alg. 4 for two agents; learns in ``q`` and ``u``, writes ``log`` and counts
    the observing agent-steps per (delta, need) in ``need_counts``. While both act they take
    :func:`pair_step`; once one is in the goal, the other acts on its Q-learner, with nobody to
    observe and its GLA not updated."""
    _, buffers, _ = own
    cells, done, acc = buffers.cells, buffers.done, buffers.acc
    for episode in range(schedule.episodes):
        ep.start_episode(world.starts, cells, done, acc)
        t = 0
        while t < schedule.max_steps and not ep.all_done(done):
            first, second = ep.few_acting(done)
            if second >= 0:
                collisions = pair_step(world, learning, automata, q, u, need_counts, (first, second), state, own)
            else:
                collisions = lone_step(world, learning, q, first, state, buffers)
            t += 1
            ep.end_step(t, cells, done, buffers.new_cells, buffers.rewards, buffers.reached, collisions, acc)
        ep.end_episode(log, episode, schedule.edges, acc, t, done)


@njit(**ep.LOOP)
def episodes(world, learning, automata, schedule, q, u, need_counts, log, state, arrays):
    """:func:`episodes_two` for any number of agents: :func:`group_step` while three or more act.
    ``arrays``: :func:`per_run`'s, then the :class:`Group` (:func:`group_arrays`) and ``kept =
    (trace, yields)``. Kept arrays of as many episodes as the schedule (not of none:
    :func:`nothing_kept`) keep, besides, each episode's joint states in ``trace`` (episodes,
    max_steps + 1, agents), row t every agent's cell after t steps (GONE once in its goal,
    :func:`keep_cells`), and count in ``yields`` the agent-steps on which the coordination replaced
    an agent's preferred action (:func:`yielded`): what the crowd's replay reads
    (glamas.experiments.crowd.replay). A plain tuple, as the replay builds it: given as a
    NamedTuple by :func:`run`, the loop would be compiled a second time for the replay."""
    in_range, buffers, agents, _, (trace, yields) = arrays
    own = in_range, buffers, agents
    cells, done, actions, acc = buffers.cells, buffers.done, buffers.actions, buffers.acc
    keeping = trace.shape[0] > 0
    for episode in range(schedule.episodes):
        ep.start_episode(world.starts, cells, done, acc)
        t = 0
        if keeping:
            keep_cells(trace[episode, t], cells, done)
        while t < schedule.max_steps and not ep.all_done(done):
            first, second = ep.few_acting(done)
            if second >= 0:
                collisions = pair_step(world, learning, automata, q, u, need_counts, (first, second), state, own)
            elif first >= 0:
                collisions = lone_step(world, learning, q, first, state, buffers)
            else:
                collisions = group_step(world, learning, automata, q, u, need_counts, state, arrays)
            if keeping and (second >= 0 or first < 0):  # a lone agent has nobody to yield to
                yields[episode] += yielded(done, agents.preferred, actions)
            t += 1
            ep.end_step(t, cells, done, buffers.new_cells, buffers.rewards, buffers.reached, collisions, acc)
            if keeping:
                keep_cells(trace[episode, t], cells, done)
        ep.end_episode(log, episode, schedule.edges, acc, t, done)


LEARNER = Learner(name="two_observe", label="2observe", n_agent_label="2observe (N agents)",
                  kernel=run, two_agent_kernel=run_two, table_shape=table_shape, inputs=automata,
                  defaults=GLASettings(), freeze=freeze, outputs=outputs, counters=("need_counts",),
                  gla_parameters=gla_parameters, family="chapter",
                  rank=3)
RULE = replace(LEARNER, name="two_observe_rule", label="2observe, fixed rule", n_agent_label="",
               defaults=GLASettings(rule_distance=3), rank=4)
"""A diagnostic outside the chapter: 2observe with its GLAs replaced by the fixed rule "coordinate
when delta < 3" (delta at most 2, where every collision of two agents comes from)."""

register(LEARNER)
register(RULE)
