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
and ``state`` the run's generator state. :func:`train` runs any learner this way, so an experiment
loops over learners without knowing any of them; :mod:`glamas.learners.registry` lists them.
"""

import math
from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np

from glamas import parallel
from glamas.gridworld import GridMap, dp, rules
from glamas.gridworld.rewards import CHAPTER, Rewards
from glamas.learners import episode as ep
from glamas.qlearning import QLearning, QSettings
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
    (a frozen evaluation, :func:`evaluation`). The identity for a learner whose only learning is
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


def allocate(learner: Learner, setup: Setup, gridmap: GridMap, schedule: ep.Schedule, n_runs: int,
             keep_q: bool = True) -> dict:
    """Every run's outputs, in kernel order: q (filled with ``q_initial``; without ``keep_q`` a
    :class:`glamas.parallel.Scratch` that the runs fill and drop), the learner's own, log."""
    shape = (n_runs,) + learner.table_shape(gridmap.n_cells, gridmap.n_agents)
    initial = float(setup.q.q_initial)
    q = np.full(shape, initial) if keep_q else parallel.Scratch(shape, np.dtype(float), initial)
    own = {name: np.stack([array] * n_runs) for name, array in learner.outputs(setup, gridmap).items()}
    log = np.zeros((n_runs, schedule.edges.size - 1, ep.n_columns(gridmap.n_agents)))
    return {"q": q, **own, "log": log}


class Evaluation(NamedTuple):
    """How the runs' learned tables are evaluated after training (:func:`evaluations`): ``episodes``
    episodes with learning off under each of ``exploits`` (probabilities of the greedy action:
    1 for the greedy policy)."""

    episodes: int
    """Episodes per evaluation."""
    exploits: tuple
    """One evaluation per probability of the greedy action."""
    per_episode: bool = False
    """Whether an evaluation's log keeps each episode in a row of its own (else one row of their means)."""

    def edges(self) -> np.ndarray:
        """The evaluation log's block edges."""
        if self.per_episode:
            return ep.uniform_edges(self.episodes, 1)
        return np.array([0, self.episodes], dtype=np.int64)


EVALUATIONS = ("greedy", "exploring", "perturbed")
"""The evaluations an experiment makes of what each run learned (:func:`evaluation_of`): the greedy
policy (exploitation 1: the learned solution); the training's exploration on frozen tables (so
that a reader sees exploration's share of a learning curve); about one random action per episode
(a perturbation of the greedy policy: collisions per perturbation measure its robustness)."""


def evaluation_of(episodes: int, q: QSettings, gridmap: GridMap) -> Evaluation:
    """The :data:`EVALUATIONS` of ``episodes`` episodes each on ``gridmap``: exploitation 1, the
    training's ``q.exploit_prob``, and 1 - 1 / (agents x their mean shortest path), which takes
    one random action in an episode of the shortest paths on average."""
    moves = gridmap.n_agents * float(dp.shortest_steps(gridmap).mean())
    return Evaluation(episodes, (1.0, float(q.exploit_prob), 1.0 - 1.0 / moves))


EVALUATION_SEEDS = 2 ** 48
"""Where the evaluations' master seeds start (evaluation k of the runs of master seed m draws from
m + (k + 1) * EVALUATION_SEEDS): apart from every training seed."""


def evaluations(learner: Learner, setup: Setup, gridmap: GridMap, evaluation: Evaluation, max_steps: int,
                master_seed: int, bounce: str = "previous", rewards: Rewards = CHAPTER) -> tuple:
    """The :class:`glamas.parallel.Evaluation` s of ``evaluation``: the learner's kernel from each
    run's learned outputs, the Q-learning rate zero, its own bundles frozen (:attr:`Learner.freeze`),
    exploiting with each probability of ``evaluation.exploits``, its log one block of all the
    episodes. Nothing learned changes: the tables are evaluated as they are."""
    world = rules.world(gridmap, bounce, rewards)
    own = learner.freeze(tuple(learner.inputs(setup, gridmap)))
    schedule = ep.Schedule(evaluation.episodes, evaluation.edges(), max_steps)
    log_at = len(learner.outputs(setup, gridmap)) + 1  # q, its own outputs, log
    return tuple(parallel.Evaluation((world, QLearning(0.0, setup.q.discount, float(exploit))) + own + (schedule,),
                                     log_at, master_seed + (k + 1) * EVALUATION_SEEDS)
                 for k, exploit in enumerate(evaluation.exploits))


def batch(learner: Learner, setup: Setup, gridmap: GridMap, schedule: ep.Schedule, n_runs: int,
          master_seed: int, *, bounce: str = "previous", rewards: Rewards = CHAPTER, keep_q: bool = True,
          evaluation: Evaluation | None = None) -> tuple[parallel.Batch, dict]:
    """``n_runs`` runs of ``learner`` on ``gridmap`` (collision rule ``bounce``, reward formulation
    ``rewards``), ready to run
    (:func:`glamas.parallel.run_many`), and the outputs they fill, by name (``q``, the learner's
    own, ``log``; runs on the first axis; with an ``evaluation``, ``evaluated``: the evaluations'
    logs, :func:`evaluated`). Without ``keep_q`` the runs' Q tables are not kept
    (:func:`allocate`): an experiment that reads only the learning curves and the evaluations saves
    their memory and their transport."""
    outputs = allocate(learner, setup, gridmap, schedule, n_runs, keep_q)
    inputs = kernel_inputs(learner, setup, gridmap, schedule, bounce, rewards)
    then = () if evaluation is None else evaluations(learner, setup, gridmap, evaluation, schedule.max_steps,
                                                     master_seed, bounce, rewards)
    rows = 0 if evaluation is None else evaluation.edges().size - 1
    logs = [np.zeros((n_runs, rows, ep.n_columns(gridmap.n_agents))) for _ in then]
    work = parallel.Batch(learner.kernel_for(gridmap.n_agents), inputs, tuple(outputs.values()) + tuple(logs),
                          master_seed, then)
    if then:
        outputs["evaluated"] = tuple(logs)
    return work, outputs


def evaluated(outputs: dict) -> np.ndarray:
    """(runs, evaluations, columns): each run's evaluations (:func:`batch`), one log row each
    (glamas.learners.episode's layout, means over the evaluation's episodes; the first episode's
    for an evaluation kept :attr:`Evaluation.per_episode`)."""
    return np.stack([log[:, 0] for log in outputs["evaluated"]], axis=1)


def train(learner: Learner, setup: Setup, gridmap: GridMap, schedule: ep.Schedule, n_runs: int, master_seed: int,
          *, bounce: str = "previous", rewards: Rewards = CHAPTER, workers=None, progress=None) -> dict:
    """``n_runs`` runs of ``learner`` on ``gridmap``: its outputs by name (``q``, its own, ``log``),
    each with the runs on the first axis."""
    work, outputs = batch(learner, setup, gridmap, schedule, n_runs, master_seed, bounce=bounce, rewards=rewards)
    parallel.run_many([work], workers=workers, progress=progress)
    return outputs
