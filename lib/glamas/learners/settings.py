"""The learners' settings, each documented once: plain frozen dataclasses that the experiments'
configs extend (:class:`glamas.experiments.gridworld.GridworldConfig`,
:class:`glamas.experiments.related_work.RelatedWorkConfig`) or hold
(:class:`glamas.experiments.scaling.ScalingConfig`), and :class:`LearnerSettings`, all of them
together, which :func:`glamas.learners.spec.train` hands to a learner.

Each learner's module turns the settings it reads into the bundles its kernel takes
(:mod:`glamas.learners.spec`); a bundle's fields keep the settings' names.
"""

import dataclasses
from dataclasses import dataclass

import numpy as np

from glamas import gla
from glamas import checks
from glamas.errors import UserError
from glamas.gridworld import BOUNCE_MODES
from glamas.learners import two_observe


@dataclass(frozen=True)
class LearningSettings:
    """Q-learning, the collision rule and 2observe's GLAs: the settings of the chapter's learners
    (Section 5.3); chapter values as defaults, the rest documented choices."""

    q_learning_rate: float = 0.05
    """alpha of eq. 11 for every Q-learner (Sec. 5.3)."""
    q_initial: float = 0.0
    """Initial value of every Q-table entry (Sec. 5.3)."""
    exploit_prob: float = 0.9
    """Probability of the greedy action; the chapter's "epsilon = 0.9" read as exploitation."""
    discount: float = 0.9
    """gamma of eq. 11 (not stated in the chapter)."""
    max_steps: int = 10_000
    """Step cap per episode, a safeguard (not in the chapter); capped episodes are counted."""
    bounce: str = "previous"
    """Where a collided agent goes: 'previous' cell (re-implementations) or its 'start' cell."""
    gla_learning_rate: float = 0.01
    """lambda of eq. 13 for 2observe's GLAs (Sec. 5.3)."""
    gla_temperature: float = 0.5
    """T of eq. 15 for 2observe's GLAs (not stated for this experiment; Sec. 4.2 uses 0.5)."""
    gla_K: float = 1.0
    """K of eq. 13 (not stated for this experiment; Sec. 4.2 uses 1)."""
    gla_L: float = 8.0
    """L of eq. 14 (not stated for this experiment). Sec. 4.2's L = 1 bounds parameters for inputs
    in [-1, 1]; here delta runs to 8 (the largest distance on TunnelToGoal), and L = 1 x 8 lets
    u.x draw a sharp boundary at any distance the map has."""
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
    would collide; 'outcome', they collided (glamas.learners.two_observe)."""
    gla_feedback: tuple = ((1.0, 0.0), (0.0, 1.0))
    """Fig. 10 (lost), reconstructed: feedback[choice][need], choice 0 = act alone, 1 = coordinate:
    1 for the right choice, 0 for the wrong one."""
    coordination_penalty_per_cell: float = 0.1
    """Added feedback -this * delta when both coordinated without need (Sec. 5.3's 0 - delta/10)."""
    rule_distance: int | None = None
    """None: 2observe's GLAs learn when to coordinate (Alg. 4). A whole number d: a diagnostic, not
    in the chapter, replacing the GLAs by the fixed rule "coordinate when delta < d"."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"max_steps": 1})
        for name in ("q_learning_rate", "exploit_prob", "discount"):
            _check_unit(self, name)
        if not np.isfinite(self.q_initial):
            raise UserError(f"q_initial must be a finite number, got {self.q_initial!r}")
        if self.bounce not in BOUNCE_MODES:
            raise UserError(f"bounce must be one of {sorted(BOUNCE_MODES)}, got {self.bounce!r}")
        self.gla_params()  # validates the GLA settings with glamas.gla's messages
        if not (isinstance(self.gla_init_range, (int, float)) and 0 <= self.gla_init_range <= self.gla_L):
            raise UserError(f"gla_init_range must be in [0, gla_L={self.gla_L}], got {self.gla_init_range!r}")
        table = np.array(self.gla_feedback, dtype=float) if _is_table(self.gla_feedback) else None
        if table is None or table.shape != (2, 2) or not np.isfinite(table).all():
            raise UserError("gla_feedback must be a 2x2 table of numbers, rows = (act alone, "
                             f"coordinate), columns = (no need, need); got {self.gla_feedback!r}")
        object.__setattr__(self, "gla_feedback", tuple(tuple(float(v) for v in row) for row in table))
        if not (isinstance(self.coordination_penalty_per_cell, (int, float)) and self.coordination_penalty_per_cell >= 0):
            raise UserError("coordination_penalty_per_cell must be a number >= 0, "
                             f"got {self.coordination_penalty_per_cell!r}")
        if self.gla_need not in two_observe.NEEDS:
            raise UserError(f"gla_need must be one of {sorted(two_observe.NEEDS)}, got {self.gla_need!r}")
        if self.gla_delta_scale not in two_observe.DELTA_SCALES:
            raise UserError(f"gla_delta_scale must be one of {sorted(two_observe.DELTA_SCALES)}, "
                             f"got {self.gla_delta_scale!r}")
        if self.rule_distance is not None:
            checks.whole_numbers(self, {"rule_distance": 0})

    def gla_params(self) -> gla.GLAParams:
        return gla.GLAParams(learning_rate=self.gla_learning_rate, temperature=self.gla_temperature,
                             K=self.gla_K, L=self.gla_L, bounding=self.gla_bounding)


def _check_unit(config, name):
    value = getattr(config, name)
    if not isinstance(value, (int, float)) or not 0 < value <= 1:
        raise UserError(f"{name} must be a number in (0, 1], got {value!r}")


def _is_table(value) -> bool:
    try:
        np.array(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


@dataclass(frozen=True)
class RelatedSettings:
    """The related-work learners' own settings: sparse tabular MAQ and CQ-learning."""

    coordination_distance: int = 2
    """Sparse tabular MAQ: the agents coordinate in the joint states where their Manhattan distance
    is at most this (given in advance, as Kok and Vlassis require); 2 covers every collision."""
    cq_window: int = 30
    """CQ-learning: rewards kept per state-action, in the baseline and in the recent window."""
    cq_significance: float = 0.05
    """CQ-learning: significance level of the two-sided Student t-test on immediate rewards."""
    cq_solo_episodes: int = 1000
    """CQ-learning: episodes each agent first learns alone (the single-agent phase), not counted
    in the experiment's episodes."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"coordination_distance": 1, "cq_window": 2, "cq_solo_episodes": 1})
        if not (isinstance(self.cq_significance, float) and 0.0 < self.cq_significance < 1.0):
            raise UserError(f"cq_significance must be a number in (0, 1) such as 0.05, got {self.cq_significance!r}")


@dataclass(frozen=True)
class LearnerSettings(LearningSettings, RelatedSettings):
    """Every learner's settings together: what a learner's kernel inputs are made from."""

    def __post_init__(self):
        LearningSettings.__post_init__(self)
        RelatedSettings.__post_init__(self)


def combine(learning: LearningSettings, related: RelatedSettings) -> LearnerSettings:
    """The LearnerSettings with the LearningSettings fields of ``learning`` and the RelatedSettings
    fields of ``related`` (each may be a config that extends them)."""
    values = {f.name: getattr(learning, f.name) for f in dataclasses.fields(LearningSettings)}
    values.update({f.name: getattr(related, f.name) for f in dataclasses.fields(RelatedSettings)})
    return LearnerSettings(**values)
