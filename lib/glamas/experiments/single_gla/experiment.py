"""Experiment 1 of Section 4.2, its configuration and its run: one 2-action GLA per agent in the
line world. Both agents see a context built from the joint position, act with eq. 15, get
experiment 1's common 0/1 feedback and learn with eq. 13; then both restart at new random
positions. A run records the average feedback per window of iterations and the final GLA
parameters (and, for Fig. 6, the parameters at checkpoints)."""

from dataclasses import dataclass, field

import numpy as np

from glamas import checks, gla, lineworld, memory, parallel, seeds
from glamas.learners import single_gla as learner
from glamas.errors import UserError


PARAMETERS = 2 * 2 * 3
"""GLA parameters of a run at most: 2 agents, 2 actions, the longest context (joint, 3 inputs)."""


@dataclass(frozen=True)
class SingleGLAConfig:
    """Experiment 1 (Section 4.2, Fig. 5 and 6); defaults are the chapter's values."""

    iterations: int = 100_000
    """Learning iterations per run (Sec. 4.2: 100.000)."""
    runs: int = 100
    """Independent runs (the chapter does not say how many it averages; 100 as in Fig. 7b)."""
    learning_rate: float = 0.01
    """lambda of eq. 13 (Fig. 5 caption)."""
    temperature: float = 0.5
    """T of eq. 15 (Fig. 5 caption)."""
    K: float = 1.0
    """K_i of eq. 13 (Fig. 5 caption)."""
    L: float = 1.0
    """L_i of eq. 14 (Fig. 5 caption)."""
    bounding: str = "clip"
    """h of eq. 14: 'clip' (the original algorithm) or 'printed' (zero inside the box)."""
    context: str = "joint"
    """Context encoding (Fig. 6): 'joint' [x1, x2, 1], 'absolute' [|xA - xB|, 1] or
    'deictic' [x_self - x_other, 1]."""
    region3_reward: str = "move_apart"
    """Region 3's rewarded joint action (Sec. 4.2: +1 when both agents move apart):
    'move_apart', the left agent L and the right one R (the text; B's map is then not linearly
    separable), or 'fixed_joint_action', (L, R) everywhere in region 3 (both maps separable, but
    the agents then move towards each other where A is right of B: not the text)."""
    init_scale: float = 0.0
    """Initial GLA parameters are uniform in [-init_scale, init_scale] (chapter silent; 0 = all
    zeros, both actions equally likely everywhere)."""
    record_points: int = 200
    """Points of the learning curve: the average feedback over this many equal windows."""
    eval_grid: int = 200
    """Expected rewards are averages over the midpoints of an eval_grid x eval_grid grid."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"iterations": 1, "runs": 1, "record_points": 1, "eval_grid": 1})
        if self.record_points > self.iterations:
            raise UserError(f"record_points ({self.record_points}) cannot exceed iterations "
                             f"({self.iterations}); lower record_points or raise iterations")
        if not isinstance(self.init_scale, (int, float)) or not 0 <= self.init_scale <= self.L:
            raise UserError(f"init_scale must be a number in [0, L={self.L}], got {self.init_scale!r}")
        lineworld.encoding_code(self.context)
        lineworld.region3_code(self.region3_reward)
        self.gla_params()  # validates learning_rate, temperature, K, L and bounding

    def gla_params(self) -> gla.GLAParams:
        return gla.GLAParams(self.learning_rate, self.temperature, self.K, self.L, self.bounding)

    def memory_bytes(self) -> int:
        """Bytes of a run's arrays: the reward curve and the parameters (agents, actions, longest context)."""
        return memory.per_run(self.runs, self.record_points + PARAMETERS)


@dataclass(frozen=True)
class SingleGLAResult:
    """What the runs of :func:`run` produced."""

    config: SingleGLAConfig
    """The configuration that produced the arrays."""
    iteration: np.ndarray
    """(record_points,) the last iteration of each recording window."""
    reward: np.ndarray
    """(runs, record_points) average feedback in each window."""
    params: np.ndarray
    """(runs, 2 agents, 2 actions, context length) final GLA parameters u (actions L, R)."""
    checkpoint: np.ndarray = field(default_factory=lambda: learner.NO_CHECKPOINTS)
    """(checkpoints,) the iterations after which the parameters were recorded (Fig. 5: none)."""
    checkpoint_params: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 2, 2, 0)))
    """(runs, checkpoints, 2 agents, 2 actions, context length) the parameters at the checkpoints."""
    expected_reward: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    """(runs, checkpoints) the team's expected feedback at each checkpoint, from its parameters
    (Fig. 6's learning curve without sampling noise: glamas.experiments.state_encoding.expected_curves)."""

    def arrays(self) -> dict:
        """The arrays a result file stores; the checkpoints only when there are any."""
        arrays = {"iteration": self.iteration, "reward": self.reward, "params": self.params}
        if self.checkpoint.size:
            arrays.update(checkpoint=self.checkpoint, checkpoint_params=self.checkpoint_params,
                          expected_reward=self.expected_reward)
        return arrays


def run(config: SingleGLAConfig, seed: int = 0, workers=None, progress: str | None = None,
        checkpoint_at: np.ndarray = learner.NO_CHECKPOINTS) -> SingleGLAResult:
    """All runs of experiment 1 for ``config``; identical for any number of workers. The
    parameters are also recorded after each of ``checkpoint_at`` iterations, which changes
    nothing else. The runs' master seed is named by ``seed`` and the experiment
    (:func:`glamas.seeds.named`); Fig. 6 runs it under each encoding on the same streams."""
    memory.check(config)
    n_inputs = lineworld.CONTEXT_LENGTH[lineworld.encoding_code(config.context)]
    params = np.zeros((config.runs, 2, 2, n_inputs))
    reward = np.zeros((config.runs, config.record_points))
    checkpoints = np.zeros((config.runs, len(checkpoint_at), 2, 2, n_inputs))
    parallel.run_batches(learner.learn, learner.kernel_inputs(config, checkpoint_at), (params, reward, checkpoints),
                         seeds.named(seed, "single_gla"), workers=workers, progress=progress)
    points = np.arange(1, config.record_points + 1)
    return SingleGLAResult(config, points * config.iterations // config.record_points, reward, params,
                           np.asarray(checkpoint_at, dtype=np.int64), checkpoints)


def scaled(runs: int, iterations: int, **settings) -> SingleGLAConfig:
    """The chapter's experiment 1 (with ``settings`` changed) at ``runs`` and ``iterations``,
    with no more points of the learning curve than iterations."""
    return SingleGLAConfig(runs=runs, iterations=iterations, record_points=min(SingleGLAConfig.record_points, iterations),
                           **settings)
