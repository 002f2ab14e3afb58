"""What an experiment needs to know of a learner, declared once in the learner's own module.

A :class:`Learner` names the learner, points at its run kernel and says how the kernel's tables,
inputs and outputs are made from the settings (:class:`glamas.learners.settings.LearnerSettings`)
and the map. Every run kernel has the same shape::

    kernel(world, learning, *inputs, schedule, q, *outputs, log, state)

``world`` (:class:`glamas.gridworld.rules.World`), ``learning``
(:class:`glamas.qlearning.QLearning`) and ``schedule`` (:class:`glamas.learners.episode.Schedule`)
are the same for every learner; ``inputs`` are the learner's own settings bundles, ``q`` its Q
tables (filled with ``q_initial``), ``outputs`` what else it learns, ``log`` the binned episode log
and ``state`` the run's generator state. :func:`train` runs any learner this way, so an experiment
loops over learners without knowing any of them; :mod:`glamas.learners.registry` lists them.
"""

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from glamas import parallel
from glamas.gridworld import GridMap, rules
from glamas.learners import episode as ep
from glamas.qlearning import QLearning


BYTES_PER_VALUE = 8
"""Q values, joint values and reward samples are float64."""


def _nothing(settings, gridmap) -> tuple:
    return ()


def _no_outputs(settings, gridmap) -> dict:
    return {}


def _none(settings, gridmap) -> int:
    return 0


def _none_learned(outputs: dict, settings, gridmap) -> np.ndarray:
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
    inputs: Callable = _nothing
    """(settings, gridmap) -> its own settings bundles, passed between ``learning`` and ``schedule``."""
    outputs: Callable = _no_outputs
    """(settings, gridmap) -> {name: one run's array} of what else it learns, passed between ``q``
    and ``log`` in this order, zeros (or its initial values)."""
    gla_parameters: Callable = _none
    """(settings, gridmap) -> GLA parameters per run."""
    joint_room: Callable = _none
    """(settings, gridmap) -> joint values per run it allocates beyond its Q tables."""
    reward_samples: Callable = _none
    """(settings, gridmap) -> immediate rewards per run it keeps for a statistical test."""
    extra_bytes: Callable = _none
    """(settings, gridmap) -> bytes per run it allocates beyond its float64 values (e.g. flags)."""
    joint_learned: Callable = _none_learned
    """(outputs, settings, gridmap) -> per run, the joint values it actually learned beyond its Q
    tables (the room it allocated, unless it learns only some of it)."""
    family: str = "other"
    """Whose seeds it draws from: 'chapter', 'related' or 'other'
    (:func:`glamas.learners.registry.master_seed`)."""

    def kernel_for(self, n_agents: int) -> Callable:
        """The run kernel for ``n_agents`` agents. Chosen here rather than inside a compiled kernel,
        so that an experiment of two agents compiles only the two-agent kernel."""
        return self.two_agent_kernel if n_agents == 2 and self.two_agent_kernel is not None else self.kernel

    def bytes_per_run(self, settings, gridmap: GridMap) -> int:
        """Bytes one run's tables take: Q tables, joint values and reward samples (float64) and the rest."""
        values = (math.prod(self.table_shape(gridmap.n_cells, gridmap.n_agents))  # Python ints: no overflow
                  + self.joint_room(settings, gridmap) + self.reward_samples(settings, gridmap))
        return int(values) * BYTES_PER_VALUE + self.extra_bytes(settings, gridmap)


def kernel_inputs(learner: Learner, settings, gridmap: GridMap, schedule: ep.Schedule) -> tuple:
    """The kernel's inputs: world, learning, the learner's own bundles, schedule."""
    world = rules.world(gridmap, settings.bounce)
    learning = QLearning(settings.q_learning_rate, settings.discount, settings.exploit_prob)
    return (world, learning) + tuple(learner.inputs(settings, gridmap)) + (schedule,)


def allocate(learner: Learner, settings, gridmap: GridMap, schedule: ep.Schedule, n_runs: int,
             keep_q: bool = True) -> dict:
    """Every run's outputs, in kernel order: q (filled with ``q_initial``; without ``keep_q`` a
    :class:`glamas.parallel.Scratch` that the runs fill and drop), the learner's own, log."""
    shape = (n_runs,) + learner.table_shape(gridmap.n_cells, gridmap.n_agents)
    q = np.full(shape, float(settings.q_initial)) if keep_q else parallel.Scratch(shape, np.dtype(float),
                                                                                   float(settings.q_initial))
    own = {name: np.stack([array] * n_runs) for name, array in learner.outputs(settings, gridmap).items()}
    log = np.zeros((n_runs, schedule.edges.size - 1, ep.n_columns(gridmap.n_agents)))
    return {"q": q, **own, "log": log}


def batch(learner: Learner, settings, gridmap: GridMap, schedule: ep.Schedule, n_runs: int,
          master_seed: int, keep_q: bool = True) -> tuple[parallel.Batch, dict]:
    """``n_runs`` runs of ``learner`` on ``gridmap``, ready to run (:func:`glamas.parallel.run_many`),
    and the outputs they fill, by name (``q``, the learner's own, ``log``; runs on the first axis).
    Without ``keep_q`` the runs' Q tables are not kept (:func:`allocate`): an experiment that
    reads only the learning curves saves their memory and their transport."""
    outputs = allocate(learner, settings, gridmap, schedule, n_runs, keep_q)
    inputs = kernel_inputs(learner, settings, gridmap, schedule)
    return parallel.Batch(learner.kernel_for(gridmap.n_agents), inputs, tuple(outputs.values()), master_seed), outputs


def train(learner: Learner, settings, gridmap: GridMap, schedule: ep.Schedule, n_runs: int, master_seed: int,
          workers=None, progress=None) -> dict:
    """``n_runs`` runs of ``learner`` on ``gridmap``: its outputs by name (``q``, its own, ``log``),
    each with the runs on the first axis."""
    work, outputs = batch(learner, settings, gridmap, schedule, n_runs, master_seed)
    parallel.run_many([work], workers=workers, progress=progress)
    return outputs
