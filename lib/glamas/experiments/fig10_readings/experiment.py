"""Fig. 10 as an inverse problem, configured and run: 2observe trained under several readings of
its lost GLA feedback (:data:`READINGS`), each at the chapter's scale with the same seed.

The chapter's Fig. 10 (the GLAs' rewards) is lost; what survives is the text around it (Sections
5.1-5.3, see :mod:`glamas.learners.two_observe`) and the outcome it reports (Fig. 11-12). Each
reading below fixes what the text leaves open: what "need to coordinate" means, the table's
values, and the GLA's box and context.
"""

from dataclasses import dataclass, replace

import numpy as np

from glamas import parallel
from glamas.experiments.gridworld import experiment as gw_experiment
from glamas.errors import UserError


READINGS = {
    "in_range, L=8": {},
    "in_range, L=8, init 1": {"gla_init_range": 1.0},
    "in_range, L=8, unit delta": {"gla_delta_scale": "unit"},
    "in_range, L=8, unit delta, init 1": {"gla_delta_scale": "unit", "gla_init_range": 1.0},
    "in_range, L=1": {"gla_L": 1.0},
    "in_range, unit delta, L=1": {"gla_delta_scale": "unit", "gla_L": 1.0},
    "in_range, coordinating never wrong": {"gla_feedback": ((1.0, 0.0), (1.0, 1.0))},
    "sampled, L=1": {"gla_need": "sampled", "gla_L": 1.0},
    "sampled, L=8": {"gla_need": "sampled"},
    "outcome, L=8": {"gla_need": "outcome"},
    "no GLA: fixed rule delta <= 2": {"rule_distance": 3},
}
"""Each reading as its changes to 2observe's default settings (glamas.learners.two_observe.GLASettings;
the first is the default: need = in range, L = 8 (the box derived from TunnelToGoal), delta in cells, parameters initialised in [-0.1, 0.1], the
symmetric 1/0 table). 'init 1' starts the parameters in [-1, 1], 'unit delta' divides delta by the
map's largest distance. 'sampled, L=1' is the reading this repository used before the text's own
"range of interference" was read into it. The last is not a reading but the reference: the first
level replaced by the rule the readings aim at, "coordinate when the agents could collide this
step" (delta <= 2 is that rule for an agent that sees only delta)."""


@dataclass(frozen=True)
class ReadingsConfig:
    """The sensitivity study: 2observe's settings and which readings of Fig. 10 to train."""

    gridworld: gw_experiment.GridworldConfig = gw_experiment.GridworldConfig(learners=("two_observe",))
    """2observe's settings (the chapter's, and the default reading) that each reading changes."""
    readings: tuple = tuple(READINGS)
    """Names of the readings to train (keys of READINGS)."""

    def __post_init__(self):
        if not isinstance(self.gridworld, gw_experiment.GridworldConfig) or self.gridworld.learners != ("two_observe",):
            raise UserError("gridworld must be a GridworldConfig with learners=('two_observe',)")
        readings = tuple(self.readings)
        if not readings or len(set(readings)) != len(readings) or not set(readings) <= set(READINGS):
            raise UserError(f"readings must be distinct names from {list(READINGS)}, got {self.readings!r}")
        object.__setattr__(self, "readings", readings)

    def memory_bytes(self) -> int:
        """Bytes of every reading's runs (each a run of 2observe's experiment)."""
        return sum(self.reading(name).memory_bytes() for name in self.readings)

    def reading(self, name: str) -> gw_experiment.GridworldConfig:
        """2observe's configuration under reading ``name``."""
        settings = replace(self.gridworld.own("two_observe"), **READINGS[name])
        return replace(self.gridworld, settings={"two_observe": settings})


@dataclass(frozen=True)
class ReadingsResult:
    """2observe's learning curves and final GLAs under each reading (first axis: ``readings``)."""

    config: ReadingsConfig
    """The configuration that produced the arrays."""
    log: np.ndarray
    """(readings, runs, bins, columns): as GridworldResult.log for 2observe."""
    evaluated: np.ndarray
    """(readings, runs, evaluations, columns): as GridworldResult.evaluated for 2observe."""
    gla_parameters: np.ndarray
    """(readings, runs, agents, 2, 2): the final GLA parameters."""
    gla_initial: np.ndarray
    """(readings, runs, agents, 2, 2): the GLA parameters the runs started from."""
    need_counts: np.ndarray
    """(readings, runs, deltas, 2): observing agent-steps per distance without / with need."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block."""

    def gridworld_result(self, k: int) -> gw_experiment.GridworldResult:
        """Reading k's 2observe as a GridworldResult of one learner."""
        return gw_experiment.GridworldResult(config=self.config.reading(self.config.readings[k]),
                                             learners=np.array(["two_observe"]),
                                             log=self.log[k:k + 1], evaluated=self.evaluated[k:k + 1],
                                             table_shapes=np.zeros((1, 3), np.int64), episodes=self.episodes,
                                             own={"two_observe": {"u": self.gla_parameters[k],
                                                                  "u_initial": self.gla_initial[k],
                                                                  "need_counts": self.need_counts[k]}})


def run(config: ReadingsConfig = ReadingsConfig(), seed: int = 0, workers=None, progress=None) -> ReadingsResult:
    """Train 2observe under every reading of ``config``, each with the same seed (so the readings
    share their random streams and differ only by what they read into Fig. 10), all readings' runs
    on one pool of workers."""
    readings = [config.reading(name) for name in config.readings]
    work = [gw_experiment.trainings(reading, seed) for reading in readings]
    parallel.run_many([batch for trainings in work for batch, _ in trainings], workers=workers, progress=progress)
    parts = [gw_experiment.result_of(reading, [outputs for _, outputs in trainings])
             for reading, trainings in zip(readings, work)]
    first_level = [part.own["two_observe"] for part in parts]
    return ReadingsResult(config=config, log=np.concatenate([p.log for p in parts]),
                          evaluated=np.concatenate([p.evaluated for p in parts]),
                          gla_parameters=np.stack([own["u"] for own in first_level]),
                          gla_initial=np.stack([own["u_initial"] for own in first_level]),
                          need_counts=np.stack([own["need_counts"] for own in first_level]), episodes=parts[0].episodes)


def scaled(runs: int, episodes: int) -> ReadingsConfig:
    """The study at ``runs`` and ``episodes``."""
    return ReadingsConfig(gridworld=gw_experiment.GridworldConfig(learners=("two_observe",), runs=runs,
                                                                  episodes=episodes))
