"""The related-work comparison's configuration and run: sparse tabular multi-agent Q-learning
(Kok and Vlassis 2004, coordination states given in advance, cited in Sec. 5.1) and CQ-learning
(De Hauwere, Vrancx and Nowé 2010, the statistical test the chapter's Sec. 6 proposes instead of
the GLA) beside the chapter's learners on TunnelToGoal.

The chapter's learners run exactly as in :mod:`glamas.experiments.gridworld` (same settings,
same seeds); the related-work learners draw their streams from master seeds of their own, so
adding them changes nothing of the chapter's experiment.
"""

from dataclasses import dataclass

import numpy as np

from glamas import parallel
from glamas.experiments.gridworld import experiment as gw_experiment
from glamas.gridworld import GridMap
from glamas.learners import registry

RELATED_LEARNERS = ("sparse_maq", "cq")
"""The related-work learners."""
CHAPTER_LEARNERS = ("independent", "mmdp", "two_observe")
"""The chapter's learners the comparison trains by default (the joint-state learners are left out)."""


@dataclass(frozen=True)
class RelatedWorkConfig(gw_experiment.GridworldConfig):
    """The comparison's settings: those of the chapter's experiment
    (:class:`glamas.experiments.gridworld.GridworldConfig`), training the chapter's learners and the
    related-work learners by default; every learner uses the same map, schedule and Q-learning settings."""

    learners: tuple = CHAPTER_LEARNERS + RELATED_LEARNERS
    """Which learners to train: distinct names of registered learners."""


@dataclass(frozen=True)
class RelatedWorkResult(gw_experiment.GridworldResult):
    """A :class:`~glamas.experiments.gridworld.GridworldResult` with what each learner stores."""

    config: RelatedWorkConfig
    """The configuration that produced the arrays."""
    local_entries: np.ndarray
    """float (n_learners,): Q entries per agent over its own cells."""
    joint_entries: np.ndarray
    """float (n_learners, runs): Q entries per agent over joint states (joint actions for the
    MMDP and sparse learners, counted in the final tables; CQ: 4 per marked joint state)."""
    reward_samples: np.ndarray
    """int (n_learners,): immediate rewards each agent keeps for a statistical test (CQ only)."""


def run(config: RelatedWorkConfig | None = None, seed: int = 0, workers=None,
        progress=None) -> RelatedWorkResult:
    """Train every learner of ``config`` (None: the comparison's defaults) as
    :func:`glamas.experiments.gridworld.run` does (same seeds, so the chapter's learners give the
    same results), all on one pool of workers, and measure what each stores."""
    config = RelatedWorkConfig() if config is None else config  # built on a call: importing glamas checks no map
    work = gw_experiment.trainings(config, seed)
    parallel.run_many([batch for batch, _ in work], workers=workers, progress=progress)
    outputs = [outputs for _, outputs in work]
    base = gw_experiment.result_of(config, outputs)
    gridmap = config.gridmap()
    learned = np.array([registry.get(name).joint_learned(out, config.setup(name), gridmap)
                        for name, out in zip(config.learners, outputs)]).reshape(-1, config.runs)
    return RelatedWorkResult(**{name: getattr(base, name) for name in base.__dataclass_fields__},
                             **storage(config, base.table_shapes, learned, gridmap))


def storage(config: RelatedWorkConfig, shapes: np.ndarray, learned: np.ndarray, gridmap: GridMap) -> dict:
    """What each agent stores, per learner: its Q entries over its own cells, its Q entries over
    joint states per run (its joint Q tables, and the joint values ``learned`` beyond them), and
    its reward samples."""
    n_agents = gridmap.n_agents
    joint = [registry.get(name).joint_tables for name in config.learners]
    local = [0.0 if is_joint else float(np.prod(shape[1:])) for is_joint, shape in zip(joint, shapes)]
    tables = [np.prod(shape) / n_agents if is_joint else 0.0 for is_joint, shape in zip(joint, shapes)]
    samples = [registry.get(name).reward_samples(config.setup(name), gridmap) // n_agents for name in config.learners]
    return {"local_entries": np.array(local), "joint_entries": np.array(tables)[:, None] + learned / n_agents,
            "reward_samples": np.array(samples, dtype=np.int64)}


def scaled(runs: int, episodes: int) -> RelatedWorkConfig:
    """The comparison at ``runs`` and ``episodes``."""
    return RelatedWorkConfig(runs=runs, episodes=episodes)
