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
from glamas.learners import cq, registry, spec
from glamas.learners.settings import LearnerSettings, RelatedSettings, combine
from glamas.errors import UserError


RELATED_LEARNERS = registry.family("related")
"""The related-work learners (glamas.learners.registry), in the order their seeds are drawn."""
CHAPTER_LEARNERS = ("independent", "mmdp", "two_observe")
"""The chapter's learners the comparison trains by default (the joint-state learners are left out)."""


@dataclass(frozen=True)
class RelatedWorkConfig(RelatedSettings):
    """The comparison's settings: the chapter's experiment plus the related-work learners' own
    (:class:`glamas.learners.settings.RelatedSettings`)."""

    gridworld: gw_experiment.GridworldConfig = gw_experiment.GridworldConfig(learners=CHAPTER_LEARNERS)
    """The chapter's experiment (map, episodes, runs, Q-learning settings) and which of its learners
    to train; the related-work learners use the same map, schedule and Q-learning settings."""
    learners: tuple = RELATED_LEARNERS
    """Which learners beyond the chapter's to train: distinct names of registered learners, such
    as sparse_maq and cq (may be empty)."""

    def __post_init__(self):
        super().__post_init__()
        learners = tuple(self.learners)
        if len(set(learners)) != len(learners) or not set(learners) <= set(registry.beyond_the_chapter()):
            raise UserError(f"learners must be distinct names from {registry.beyond_the_chapter()}, "
                             f"got {self.learners!r}")
        object.__setattr__(self, "learners", learners)
        # two agents: GridworldConfig already rejects other maps

    def settings(self) -> LearnerSettings:
        """Every learner's settings: the chapter experiment's and the related-work learners' own."""
        return combine(self.gridworld, self)

    def gridmap(self) -> GridMap:
        return self.gridworld.gridmap()

    def memory_bytes(self) -> int:
        """Bytes of the chapter's learners' runs and of the related-work learners' runs."""
        base, gridmap, settings = self.gridworld, self.gridmap(), self.settings()
        related = base.runs * sum(gw_experiment.learner_bytes(name, settings, gridmap, base.bins)
                                  for name in self.learners)
        return base.memory_bytes() + related


def learner_codes() -> tuple:
    """The learners a :class:`RelatedWorkResult`'s codes index: the chapter's four (codes 0-3),
    then every registered learner beyond them (the related-work learners 4 and 5)."""
    return gw_experiment.LEARNERS + registry.beyond_the_chapter()


@dataclass(frozen=True)
class RelatedWorkResult(gw_experiment.GridworldResult):
    """A :class:`~glamas.experiments.gridworld.GridworldResult` over the chapter's and other
    learners (codes into :func:`learner_codes`), with what each learner stores."""

    config: RelatedWorkConfig
    """The configuration that produced the arrays."""
    local_entries: np.ndarray
    """float (n_learners,): Q entries per agent over its own cells."""
    joint_entries: np.ndarray
    """float (n_learners, runs): Q entries per agent over joint states (joint actions for the
    MMDP and sparse learners, counted in the final tables; CQ: 4 per marked joint state)."""
    reward_samples: np.ndarray
    """int (n_learners,): immediate rewards each agent keeps for a statistical test (CQ only)."""
    cq_marked: np.ndarray
    """bool (runs, agents, own cell, other's cell): the joint states each CQ agent learned to
    observe (all False if CQ did not run)."""

    def names(self) -> list[str]:
        codes = learner_codes()
        return [codes[k] for k in self.learners]


def run(config: RelatedWorkConfig = RelatedWorkConfig(), seed: int = 0, workers=None,
        progress=None) -> RelatedWorkResult:
    """Train the chapter's learners as :func:`glamas.experiments.gridworld.run` does (same seeds, so
    the same results) and the related-work learners of ``config``, ``config.gridworld.runs`` runs
    each, all on one pool of workers."""
    base, settings = config.gridworld, config.settings()
    gridmap, schedule = base.gridmap(), base.schedule()
    chapter = gw_experiment.trainings(base, seed)
    related = [spec.batch(registry.get(name), settings, gridmap, schedule, base.runs,
                          registry.master_seed(seed, RELATED_LEARNERS, name, registry.get(name).family))
               for name in config.learners]
    parallel.run_many([batch for batch, _ in chapter + related], workers=workers, progress=progress)
    chapter_result = gw_experiment.result_of(base, [outputs for _, outputs in chapter], seed)
    shapes = np.array([outputs["q"].shape[1:] for _, outputs in related], dtype=np.int64).reshape(-1, 3)
    learned = np.array([registry.get(name).joint_learned(outputs, settings, gridmap)
                        for name, (_, outputs) in zip(config.learners, related)]).reshape(-1, base.runs)
    log = np.array([outputs["log"] for _, outputs in related]).reshape((-1,) + chapter_result.log.shape[1:])
    marked = next((outputs["marked"] for _, outputs in related if "marked" in outputs),
                  np.stack([cq.outputs(settings, gridmap)["marked"]] * base.runs))
    names = chapter_result.names() + list(config.learners)
    shapes = np.concatenate([chapter_result.table_shapes, shapes])
    learned = np.concatenate([np.zeros((len(chapter_result.names()), base.runs)), learned])
    return RelatedWorkResult(
        config=config, learners=np.array([learner_codes().index(name) for name in names], dtype=np.int64),
        log=np.concatenate([chapter_result.log, log]), table_shapes=shapes,
        gla_parameters=chapter_result.gla_parameters, gla_initial=chapter_result.gla_initial,
        need_counts=chapter_result.need_counts,
        episodes=chapter_result.episodes, **storage(names, shapes, learned, settings, gridmap), cq_marked=marked)


def storage(names: list, shapes: np.ndarray, learned: np.ndarray, settings, gridmap: GridMap) -> dict:
    """What each agent stores, per learner: its Q entries over its own cells, its Q entries over
    joint states per run (its joint Q tables, and the joint values ``learned`` beyond them), and
    its reward samples."""
    n_agents = gridmap.n_agents
    joint = [registry.get(name).joint_tables for name in names]
    local = [0.0 if is_joint else float(np.prod(shape[1:])) for is_joint, shape in zip(joint, shapes)]
    tables = [np.prod(shape) / n_agents if is_joint else 0.0 for is_joint, shape in zip(joint, shapes)]
    samples = [registry.get(name).reward_samples(settings, gridmap) // n_agents for name in names]
    return {"local_entries": np.array(local), "joint_entries": np.array(tables)[:, None] + learned / n_agents,
            "reward_samples": np.array(samples, dtype=np.int64)}


def scaled(runs: int, episodes: int) -> RelatedWorkConfig:
    """The comparison at ``runs`` and ``episodes``, beside the chapter's learners it trains by default."""
    return RelatedWorkConfig(gridworld=gw_experiment.GridworldConfig(learners=CHAPTER_LEARNERS, runs=runs,
                                                                     episodes=episodes))
