"""What an experiment needs to know of a learner, declared once in the learner's own module.

A :class:`Learner` names the learner, points at its run kernel, holds its own settings at their
defaults (a frozen dataclass of its module, or None for a learner that has none beyond Q-learning)
and says how the kernel's tables, inputs and outputs are made from the settings and the map. A
learner runs with a :class:`Setup`: the experiment's Q-learning settings, shared by every
Q-learner (:class:`glamas.qlearning.QSettings`), and its own. Every run kernel has the same shape::

    kernel(world, learning, *inputs, schedule, q, *outputs, log, state)

``world`` (:class:`glamas.gridworld.rules.World`), ``learning``
(:class:`glamas.qlearning.QLearning`) and ``schedule`` (:class:`glamas.learners.episode.Schedule`)
are the same for every learner; ``inputs`` are the learner's own settings bundles, ``q`` its Q
tables (filled with ``q_initial``), ``outputs`` what else it learns, ``log`` the binned episode log
and ``state`` the run's generator state. :func:`glamas.training.train` runs any learner this way,
so an experiment loops over learners without knowing any of them; :mod:`glamas.learners.registry`
lists them. This module, like every learner's, imports only what computes: running the kernels
(in batches, on workers) is :mod:`glamas.training`'s and :mod:`glamas.parallel`'s, above them.
"""

import math
from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np

from glamas.gridworld import GridMap, rules
from glamas.gridworld.rewards import CHAPTER, Rewards
from glamas.learners import episode as ep
from glamas.qlearning import QSettings
from glamas.errors import UserError


BYTES_PER_VALUE = 8
"""Q values, joint values and reward samples are float64."""


class Setup(NamedTuple):
    """What one learner runs with: the experiment's Q-learning settings and the learner's own."""

    q: QSettings
    """Tabular Q-learning, shared by every Q-learner of the experiment."""
    own: Any = None
    """The learner's own settings (an instance of the class of its :attr:`Learner.defaults`), or
    None for a learner that has none."""


def _nothing(setup, gridmap) -> tuple:
    return ()


def _unchanged(inputs: tuple) -> tuple:
    return inputs


def _no_outputs(setup, gridmap) -> dict:
    return {}


def _none(setup, gridmap) -> int:
    return 0


def _none_learned(outputs: dict, setup, gridmap) -> np.ndarray:
    return np.zeros(outputs["q"].shape[0])


@dataclass(frozen=True)
class Learner:
    """One learner: its names, its kernel, and how its tables, inputs and outputs are made."""

    name: str
    """Its name in configs and result files."""
    label: str
    """Its name in figures and tables."""
    kernel: Callable
    """The run kernel (module docstring)."""
    table_shape: Callable[[int, int], tuple]
    """(cells, agents) -> (tables, states, actions) of its Q tables, without allocating them."""
    two_agent_kernel: Callable | None = None
    """A run kernel for exactly two agents, the chapter's case, giving the same results as
    ``kernel`` faster (None: ``kernel`` runs two agents too); see :meth:`kernel_for`."""
    n_agent_label: str = ""
    """Its name where the figures compare numbers of agents, if its N-agent form needs saying."""
    joint_tables: bool = False
    """Whether its Q tables are over joint states (the joint-state and MMDP learners), not over
    each agent's own cell."""
    defaults: Any = None
    """Its own settings at their defaults: an instance of a frozen dataclass of its module (the
    class is what configs accept for it), or None for a learner with no settings of its own."""
    inputs: Callable = _nothing
    """(setup, gridmap) -> its own settings bundles, passed between ``learning`` and ``schedule``."""
    freeze: Callable = _unchanged
    """(its own bundles) -> the same with learning off: a run of its kernel from learned outputs,
    with the Q-learning rate zero, then changes none of them and draws nothing afresh at its start
    (a frozen evaluation, :func:`glamas.training.evaluations`). The identity for a learner whose only learning is
    Q-learning's."""
    outputs: Callable = _no_outputs
    """(setup, gridmap) -> {name: one run's array} of what else it learns, passed between ``q``
    and ``log`` in this order, zeros (or its initial values)."""
    counters: tuple = ()
    """The names of those of its outputs that count what happens (2observe's ``need_counts``) rather
    than hold what it learned: playing with learning off may add to them (:mod:`glamas.learners.contract`)."""
    gla_parameters: Callable = _none
    """(setup, gridmap) -> GLA parameters per run."""
    joint_room: Callable = _none
    """(setup, gridmap) -> joint values per run it allocates beyond its Q tables."""
    reward_samples: Callable = _none
    """(setup, gridmap) -> immediate rewards per run it keeps for a statistical test."""
    extra_bytes: Callable = _none
    """(setup, gridmap) -> bytes per run it allocates beyond its float64 values (e.g. flags)."""
    joint_learned: Callable = _none_learned
    """(outputs, setup, gridmap) -> per run, the joint values it actually learned beyond its Q
    tables (the room it allocated, unless it learns only some of it)."""
    family: str = "other"
    """Where it comes from: 'chapter', 'related' or 'other' (:func:`glamas.learners.registry.family`)."""
    rank: int | None = None
    """Its place among its family's learners in listings (tables, legends), fixed here so that the
    order in which modules register never reorders them; None: after the ranked ones, by name."""

    def kernel_for(self, n_agents: int) -> Callable:
        """The run kernel for ``n_agents`` agents. Chosen here rather than inside a compiled kernel,
        so that an experiment of two agents compiles only the two-agent kernel."""
        return self.two_agent_kernel if n_agents == 2 and self.two_agent_kernel is not None else self.kernel

    def setup(self, q: QSettings = QSettings(), own=None) -> Setup:
        """Its :class:`Setup` from the shared Q-learning settings and its own (None: its defaults);
        settings of another learner's class are refused."""
        own = self.defaults if own is None else own
        if type(own) is not type(self.defaults):
            expected = "none" if self.defaults is None else type(self.defaults).__name__
            raise UserError(f"learner {self.name!r} takes settings of its own of type {expected}, "
                             f"got {type(own).__name__}")
        return Setup(q, own)

    def bytes_per_run(self, setup: Setup, gridmap: GridMap) -> int:
        """Bytes one run's tables take: Q tables, joint values and reward samples (float64) and the
        rest, in Python integers (a table of many agents exceeds any fixed-width integer)."""
        values = (math.prod(self.table_shape(gridmap.n_cells, gridmap.n_agents))
                  + self.joint_room(setup, gridmap) + self.reward_samples(setup, gridmap))
        return int(values) * BYTES_PER_VALUE + self.extra_bytes(setup, gridmap)


def kernel_inputs(learner: Learner, setup: Setup, gridmap: GridMap, schedule: ep.Schedule,
                  bounce: str = "previous", rewards: Rewards = CHAPTER) -> tuple:
    """The kernel's inputs: world (``gridmap`` under the collision rule ``bounce`` and the reward
    formulation ``rewards``), learning, the learner's own bundles, schedule."""
    world = rules.world(gridmap, bounce, rewards)
    return (world, setup.q.kernel_bundle()) + tuple(learner.inputs(setup, gridmap)) + (schedule,)
