"""The line world of the chapter's Fig. 4 (Section 4.2): two agents A and B on [-1, 1].

Every iteration both agents are put at uniform random positions ``x1`` (A) and ``x2`` (B), each
picks Left (``L = 0``) or Right (``R = 1``), and both receive one common feedback in [0, 1] that
depends on the joint position and the joint action. All functions are compiled so that the
experiment kernels can call them in their inner loops.
"""

import numpy as np
from numba import njit

from glamas import rng
from glamas.errors import UserError

LEFT = 0
RIGHT = 1
AGENT_A = 0
AGENT_B = 1

# Context encodings of Fig. 6; every one ends with a bias input 1.
JOINT = 0
ABSOLUTE = 1
DEICTIC = 2
ENCODINGS = {"joint": JOINT, "absolute": ABSOLUTE, "deictic": DEICTIC}
CONTEXT_LENGTH = {JOINT: 3, ABSOLUTE: 2, DEICTIC: 2}

# Experiment 1 (Fig. 5a): the half-width of region 3, the band where the agents are close.
CLOSE_DISTANCE = 0.5

# Readings of region 3's reward (Sec. 4.2: +1 when both agents move apart from each other).
MOVE_APART = 0  # the left agent L, the right one R: the rewarded joint action flips at x1 = x2
FIXED_JOINT_ACTION = 1  # (L, R) on all of region 3: apart only where A is left of B
REGION3_REWARDS = {"move_apart": MOVE_APART, "fixed_joint_action": FIXED_JOINT_ACTION}


@njit(cache=True)
def restart(state):
    """New uniform random positions (x1, x2) on [-1, 1] (the restart after every iteration)."""
    x1 = 2.0 * rng.uniform(state) - 1.0
    x2 = 2.0 * rng.uniform(state) - 1.0
    return x1, x2


@njit(cache=True)
def region(x1, x2):
    """Region of Fig. 5a: 3 where |x1 - x2| < 0.5 (it takes precedence), else 1 where A is left
    of B (x1 < x2), else 2."""
    if abs(x1 - x2) < CLOSE_DISTANCE:
        return 3
    return 1 if x1 < x2 else 2


@njit(cache=True)
def best_action(x1, x2, agent, region3):
    """The agent's part of experiment 1's only rewarded joint action at (x1, x2).

    Region 1: (L, L); region 2: (R, R); region 3 read as ``region3``: MOVE_APART, the left agent
    L and the right one R; FIXED_JOINT_ACTION, (L, R) wherever the agents are.
    """
    r = region(x1, x2)
    if r == 1:
        return LEFT
    if r == 2:
        return RIGHT
    a_is_left = x1 < x2 or region3 == FIXED_JOINT_ACTION
    if agent == AGENT_A:
        return LEFT if a_is_left else RIGHT
    return RIGHT if a_is_left else LEFT


@njit(cache=True)
def regions_reward(x1, x2, action_a, action_b, region3):
    """Experiment 1's feedback: 1 for the region's rewarded joint action (region 3 read as
    ``region3``, :func:`best_action`), 0 otherwise."""
    if action_a == best_action(x1, x2, AGENT_A, region3) and action_b == best_action(x1, x2, AGENT_B, region3):
        return 1.0
    return 0.0


@njit(cache=True)
def inside_parabola(x1, x2, curvature, offset):
    """Region I of experiment 2 (Fig. 7a): x2 >= curvature * x1**2 + offset, a convex set."""
    return x2 >= curvature * x1 * x1 + offset


@njit(cache=True)
def parabola_reward(inside, action_a, action_b, reward_inside, reward_outside, reward_other):
    """Experiment 2's feedback: (L, L) inside the parabola pays reward_inside, (R, R) outside it
    pays reward_outside, any other joint action pays reward_other."""
    if inside and action_a == LEFT and action_b == LEFT:
        return reward_inside
    if not inside and action_a == RIGHT and action_b == RIGHT:
        return reward_outside
    return reward_other


@njit(cache=True)
def context(encoding, agent, x1, x2, out):
    """Write the agent's context vector into ``out`` (Fig. 6's three encodings).

    joint: [x1, x2, 1]; absolute distance: [|x1 - x2|, 1]; deictic distance, from the agent's
    own point of view (own position minus the other's): [x_self - x_other, 1].
    """
    if encoding == JOINT:
        out[0] = x1
        out[1] = x2
        out[2] = 1.0
    elif encoding == ABSOLUTE:
        out[0] = abs(x1 - x2)
        out[1] = 1.0
    else:
        out[0] = x1 - x2 if agent == AGENT_A else x2 - x1
        out[1] = 1.0


def region3_code(name: str) -> int:
    """The compiled code of a reading of region 3's reward, with a clear error for unknown names."""
    if name not in REGION3_REWARDS:
        raise UserError(f"region3_reward must be one of {sorted(REGION3_REWARDS)}, got {name!r}")
    return REGION3_REWARDS[name]


def encoding_code(name: str) -> int:
    """The compiled code of a context encoding name, with a clear error for unknown names."""
    if name not in ENCODINGS:
        raise UserError(f"context must be one of {sorted(ENCODINGS)}, got {name!r}")
    return ENCODINGS[name]


def state_grid(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Midpoints of an n x n grid over [-1, 1]^2 as flat arrays (x1, x2): the evaluation grid
    that turns expectations over uniform positions into exact-enough averages."""
    centres = -1.0 + (np.arange(n) + 0.5) * (2.0 / n)
    x1, x2 = np.meshgrid(centres, centres, indexing="ij")
    return x1.ravel(), x2.ravel()
