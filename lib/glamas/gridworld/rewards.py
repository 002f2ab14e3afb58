"""What the gridworld pays (the reward formulation): a setting of the world, read by every kernel.

Two formulations are named (:data:`PRESETS`):

* ``chapter``, the chapter's (Section 5.3): +100 on entering the goal, nothing per move, -1 for a
  bump into a wall, -10 per collision added to the move's reward. Every experiment of the chapter
  runs under it, and it is the default everywhere.
* ``field``, the step-cost formulation of the public implementation of the sparse-interaction
  maps (its environment and its evaluation script at their latest commit): -1 per move, a bump
  -1 as well, 0 at the goal, and -10 for a collision *in place of* the move's -1 (once, however
  many agents the agent collided with). Under it every step costs, so that a shorter path is
  better at every distance from the goal; under the chapter's, +100 discounted over many steps
  weighs less than one collision, which is what makes CQ-learning stall on ISR and CIT (notebook 07).

What the public implementation does differently besides its rewards (its agents stay on their
goal cells as obstacles until every agent is in, and the step that brings the last one in pays
everyone the goal reward in place of the step's cost) is a matter of the rules, not of the
rewards: glamas's agents leave the game at their goal under both formulations
(docs/reproduction-notes.md).
"""

import math
from dataclasses import dataclass
from typing import NamedTuple

from glamas import checks
from glamas.errors import UserError


class Payoffs(NamedTuple):
    """:class:`Rewards` as the kernels read them (``World.payoffs``), named as there."""

    goal: float
    move: float
    bump: float
    collision: float
    collision_replaces_move: bool


LARGEST = 1e12
"""The largest size of a reward: summed over every step of every agent of a long run (about 1e11
agent-steps) and bootstrapped into Q-values, it stays far from the float64 overflow at 1.8e308."""


@dataclass(frozen=True)
class Rewards:
    """The rewards of one step of an agent; the chapter's (Section 5.3) as defaults."""

    goal: float = 100.0
    """Paid on the step an agent enters one of its goal cells, besides that move's reward."""
    move: float = 0.0
    """Paid for every move of an acting agent that is not a bump (a cost when negative)."""
    bump: float = -1.0
    """Paid, instead of ``move``, for a move into a wall, a blocked cell or the border (the agent stays)."""
    collision: float = -10.0
    """Paid for a collision (the agent bounces back)."""
    collision_replaces_move: bool = False
    """False: ``collision`` is added to the move's (or bump's) reward once per collision the agent
    is in (the chapter's "-10 per collision"); True: an agent that collided is paid ``collision``
    once for the step, in place of the move's reward (the field's)."""

    def __post_init__(self):
        checks.field_types(self)
        if not isinstance(self.collision_replaces_move, bool):
            raise UserError(f"Rewards.collision_replaces_move must be True or False, got "
                            f"{self.collision_replaces_move!r}")
        for name in ("goal", "move", "bump", "collision"):
            if not (math.isfinite(getattr(self, name)) and abs(getattr(self, name)) <= LARGEST):
                raise UserError(f"Rewards.{name} must be a number from {-LARGEST:g} to {LARGEST:g} (sums over a "
                                f"run's steps and the Q-values must stay finite), got {getattr(self, name)!r}")

    def kernel_bundle(self) -> Payoffs:
        """These rewards as the kernels read them."""
        return Payoffs(float(self.goal), float(self.move), float(self.bump), float(self.collision),
                       self.collision_replaces_move)


CHAPTER = Rewards()
"""The chapter's formulation (Section 5.3)."""
FIELD = Rewards(goal=0.0, move=-1.0, bump=-1.0, collision=-10.0, collision_replaces_move=True)
"""The step-cost formulation of the public implementation of the field's maps (module docstring)."""
PRESETS = {"chapter": CHAPTER, "field": FIELD}
"""The named formulations."""


def preset(name: str) -> Rewards:
    """The formulation named ``name`` (:data:`PRESETS`)."""
    if name not in PRESETS:
        raise UserError(f"rewards must be one of {sorted(PRESETS)}, got {name!r}")
    return PRESETS[name]
