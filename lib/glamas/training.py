"""Runs of a learner, above the learners: its tables allocated, the evaluations of what it learned,
and a batch of runs for :mod:`glamas.parallel` (:func:`batch`, :func:`train`).

A learner's module declares the learner (:class:`glamas.learners.spec.Learner`) and its kernel and
imports only what computes; this module puts its runs on workers, so that the learners do not
import the parallel layer and an edit there changes no record of code (:mod:`glamas.provenance`).
"""

from typing import NamedTuple

import numpy as np

from glamas import parallel
from glamas.gridworld import GridMap, dp, rules
from glamas.gridworld.rewards import CHAPTER, Rewards
from glamas.learners import episode as ep
from glamas.learners.spec import Learner, Setup, kernel_inputs
from glamas.qlearning import QLearning, QSettings


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
