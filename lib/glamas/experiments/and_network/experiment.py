"""Experiment 2 of Section 4.2, its configuration and its runs: each agent is an AND network of
two GLAs, the rewarded regions are split by a parabola (Fig. 7), and the stuck sweep raises
region II's reward.

Both agents see the joint context [x1, x2, 1]. Each agent's two 2-action units act on it; the
agent plays L only when both units output 1 (``glamas.gla.and_network``). Inside the parabola
(region I) (L, L) pays 0.9, outside it (region II) (R, R) pays 0.5, anything else 0.1. The final
P(L) maps over the evaluation grid are here too: the sweep keeps each run's mean P(L) in region I.
"""

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, fields, replace

import numpy as np
from numba import njit

from glamas import checks, gla, lineworld, memory, parallel, seeds
from glamas.learners import and_network as learner
from glamas.learners.and_network import CONTEXT_LENGTH, NETWORK, left_probability
from glamas.errors import UserError


@dataclass(frozen=True)
class ANDNetworkConfig:
    """Experiment 2 (Section 4.2, Fig. 7); defaults are the chapter's values where it has them."""

    iterations: int = 100_000
    """Learning iterations per run (chapter silent). P(L) in region I rises within ~20,000
    iterations, then creeps up as a few stuck runs escape late."""
    runs: int = 100
    """Independent runs (Fig. 7b: average over 100 runs)."""
    learning_rate: float = 0.005
    """lambda of eq. 13 (Fig. 7 caption)."""
    temperature: float = 0.5
    """T of eq. 15 (Fig. 7 caption)."""
    K: float = 1.0
    """K_i of eq. 13 (Fig. 7 caption)."""
    L: float = 1.0
    """L_i of eq. 14 (Fig. 7 caption)."""
    bounding: str = "clip"
    """h of eq. 14: 'clip' (the original algorithm) or 'printed' (zero inside the box)."""
    reward_inside: float = 0.9
    """Feedback for (L, L) in region I, inside the parabola (Sec. 4.2)."""
    reward_outside: float = 0.5
    """Feedback for (R, R) in region II, outside the parabola (Sec. 4.2; the stuck sweep raises it)."""
    reward_other: float = 0.1
    """Feedback for every other joint action (Sec. 4.2)."""
    parabola_curvature: float = 1.0
    """Region I is x2 >= curvature * x1**2 + offset (chapter silent): convex, so that the AND of
    two half-planes can approximate it; x2 >= x1**2 - 0.5 covers 58 % of the square. The
    notebook shows why flatter or steeper choices make the experiment degenerate."""
    parabola_offset: float = -0.5
    """See parabola_curvature: the parabola's lowest point is (0, offset)."""
    init_scale: float = 0.5
    """Initial unit parameters are uniform in [-init_scale, init_scale] (chapter silent; it says
    the outcome depends on the initialisation, so runs start from different random points;
    0 would start every unit at P(1) = 1/2, each agent at P(L) = 1/4)."""
    stream: int = 0
    """Which random stream a run follows once its initial parameters are drawn: 0 continues the
    generator that drew them; k > 0 reseeds it with k (glamas.rng.reseed), so run r keeps run
    r's initial parameters and meets other positions, probes and actions (the rerun that tests
    whether the initialisation decides the outcome)."""
    record_points: int = 100
    """Points of the Fig. 7b curve (the chapter's plot has 100)."""
    probe_points: int = 100
    """Uniform points in region I over which P(L) is averaged for Fig. 7b (chapter: 100),
    drawn afresh for every run."""
    eval_grid: int = 200
    """Final P(L) per region is averaged over the midpoints of an eval_grid x eval_grid grid."""
    stuck_threshold: float = 0.5
    """A run is stuck in 'R everywhere' when both agents' final mean P(L) in region I is below
    this (neither has a usable approximation of the parabola)."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"iterations": 1, "runs": 1, "record_points": 1, "probe_points": 1,
                                    "eval_grid": 1, "stream": 0})
        if self.record_points > self.iterations:
            raise UserError(f"record_points ({self.record_points}) cannot exceed iterations "
                             f"({self.iterations}); lower record_points or raise iterations")
        for name in ("reward_inside", "reward_outside", "reward_other", "stuck_threshold"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not 0 <= value <= 1:
                raise UserError(f"{name} must be in [0, 1] (GLA feedback is in [0, 1]), got {value!r}")
        for name in ("parabola_curvature", "parabola_offset"):
            if not isinstance(getattr(self, name), (int, float)) or not np.isfinite(getattr(self, name)):
                raise UserError(f"{name} must be a finite number, got {getattr(self, name)!r}")
        if self.parabola_curvature < 0:
            raise UserError(f"parabola_curvature must be >= 0 so that region I is convex, "
                             f"got {self.parabola_curvature!r}")
        if self.parabola_offset >= 1:
            raise UserError(f"parabola_offset must be < 1 so that region I meets the square, "
                             f"got {self.parabola_offset!r}")
        if not isinstance(self.init_scale, (int, float)) or not 0 <= self.init_scale <= self.L:
            raise UserError(f"init_scale must be a number in [0, L={self.L}], got {self.init_scale!r}")
        self.gla_params()  # validates learning_rate, temperature, K, L and bounding

    def gla_params(self) -> gla.GLAParams:
        return gla.GLAParams(self.learning_rate, self.temperature, self.K, self.L, self.bounding)

    def memory_bytes(self) -> int:
        """Bytes of a run's arrays: the P(L) curve and probe points per agent, and the parameters
        (agents, units, unit actions, inputs)."""
        return memory.per_run(self.runs, 2 * self.record_points + 2 * self.probe_points + 2 * 2 * 2 * 3)


@dataclass(frozen=True)
class ANDNetworkResult:
    """What the runs of :func:`run` produced."""

    config: ANDNetworkConfig
    """The configuration that produced the arrays."""
    iteration: np.ndarray
    """(record_points,) iteration at which each point of the curve was taken."""
    prob_left: np.ndarray
    """(runs, record_points, 2 agents) P(L) averaged over the run's probe points in region I."""
    params: np.ndarray
    """(runs, 2 agents, 2 units, 2 unit actions, inputs) final unit parameters."""


def run(config: ANDNetworkConfig, seed: int = 0, workers=None,
        progress: str | None = None) -> ANDNetworkResult:
    """All runs of experiment 2 for ``config``; identical for any number of workers."""
    memory.check(config)
    work = batch(config, seed)
    parallel.run_many([work], workers=workers, progress=progress)
    return result_of(config, work)


def batch(config: ANDNetworkConfig, seed: int) -> parallel.Batch:
    """The runs of ``config`` ready to run (:func:`glamas.parallel.run_many`): their outputs probes,
    unit parameters and Fig. 7b's curve; their master seed named by ``seed`` and the experiment
    (:func:`glamas.seeds.named`), the same for every region II reward of the sweep."""
    c = config
    shape = (c.runs, 2, NETWORK.n_units, max(NETWORK.unit_actions), NETWORK.n_inputs)
    outputs = (np.zeros((c.runs, c.probe_points, 2)), np.zeros(shape), np.zeros((c.runs, c.record_points, 2)))
    return parallel.Batch(learner.learn, learner.kernel_inputs(config), outputs, seeds.named(seed, "and_network"))


def result_of(config: ANDNetworkConfig, work: parallel.Batch) -> ANDNetworkResult:
    """The result of ``config`` once its :func:`batch` has run."""
    _, params, prob_left = work.outputs
    n = config.record_points
    iteration = np.arange(n) * config.iterations // (n - 1) if n > 1 else np.array([0])
    return ANDNetworkResult(config, iteration, prob_left, params)


PARABOLA_READINGS = {"x2 >= x1^2 - 0.5": (1.0, -0.5), "x2 >= 2 x1^2 - 1": (2.0, -1.0), "x2 >= x1^2": (1.0, 0.0)}
"""The parabolas the reproduction notes give for region I, the chapter not stating its equation:
name -> (curvature, offset). The first is the default."""


_ARRAYS = tuple(field.name for field in fields(ANDNetworkResult) if field.name != "config")
"""The arrays of a result, in its fields' order."""


def other_readings(config: ANDNetworkConfig, seed: int = 0, workers=None, progress: str | None = None) -> dict:
    """Experiment 2 under each parabola of :data:`PARABOLA_READINGS` other than ``config``'s, from the
    same seed: name -> result. What Fig. 7's claims are also judged under."""
    own = (config.parabola_curvature, config.parabola_offset)
    return {name: run(replace(config, parabola_curvature=a, parabola_offset=b), seed, workers,
                      None if progress is None else f"{progress} ({name})")
            for name, (a, b) in PARABOLA_READINGS.items() if (a, b) != own}


def readings_arrays(readings: dict) -> dict:
    """:func:`other_readings`'s results as one flat dict ('parabola<k>_<array>', k its place in
    :data:`PARABOLA_READINGS`), as its result file stores them."""
    place = {name: k for k, name in enumerate(PARABOLA_READINGS)}
    return {f"parabola{place[name]}_{key}": getattr(result, key) for name, result in readings.items() for key in _ARRAYS}


def readings_from_arrays(config: ANDNetworkConfig, arrays: dict) -> dict:
    """The inverse of :func:`readings_arrays`: name -> result (``config`` under that parabola)."""
    own = (config.parabola_curvature, config.parabola_offset)
    return {name: ANDNetworkResult(replace(config, parabola_curvature=a, parabola_offset=b),
                                   *(arrays[f"parabola{k}_{key}"] for key in _ARRAYS))
            for k, (name, (a, b)) in enumerate(PARABOLA_READINGS.items()) if (a, b) != own}


@njit(cache=True, nogil=True)
def _left_map(params, x1, x2, temperature, L, mode, out):
    """out[agent, i] = P(agent plays L) at (x1[i], x2[i])."""
    inputs = np.zeros((params.shape[1], params.shape[3]))
    probs = np.zeros((params.shape[1], params.shape[2]))
    context = np.empty(CONTEXT_LENGTH)
    for agent in range(2):
        for i in range(x1.shape[0]):
            context[0], context[1], context[2] = x1[i], x2[i], 1.0
            out[agent, i] = left_probability(params[agent], context, temperature, L, mode,
                                             inputs, probs)


def left_map(result: ANDNetworkResult, run_index: int, x1: np.ndarray, x2: np.ndarray) -> np.ndarray:
    """(2 agents, points) each agent's final P(L) of the given run at the given positions."""
    c = result.config
    out = np.empty((2, x1.shape[0]))
    _left_map(result.params[run_index], x1, x2, c.temperature, c.L, c.gla_params().bounding_code, out)
    return out


def final_left_by_region(result: ANDNetworkResult) -> tuple[np.ndarray, np.ndarray]:
    """(runs, 2 agents) final mean P(L) inside region I and outside it (region II), averaged
    over the evaluation grid's points in each region."""
    return region_means(left_maps(result), result.config)


def region_means(p_left: np.ndarray, config: ANDNetworkConfig) -> tuple[np.ndarray, np.ndarray]:
    """(runs, 2 agents) mean P(L) in region I and in region II from every run's P(L) maps."""
    _, _, inside = evaluation_points(config)
    return p_left[:, :, inside].mean(axis=2), p_left[:, :, ~inside].mean(axis=2)


def left_maps(result: ANDNetworkResult) -> np.ndarray:
    """(runs, 2 agents, points) every run's final P(L) on the evaluation grid, the runs' maps
    drawn on one thread per core (the kernel releases the GIL)."""
    x1, x2, _ = evaluation_points(result.config)
    with ThreadPoolExecutor(parallel.cores()) as pool:
        return np.stack(list(pool.map(lambda r: left_map(result, r, x1, x2), range(result.params.shape[0]))))


def evaluation_points(config: ANDNetworkConfig):
    """The evaluation grid (x1, x2) and which of its points lie in region I."""
    x1, x2 = lineworld.state_grid(config.eval_grid)
    return x1, x2, x2 >= config.parabola_curvature * x1 ** 2 + config.parabola_offset


@dataclass(frozen=True)
class SweepResult:
    """Stuck fractions as region II's reward rises."""

    config: ANDNetworkConfig
    """The base configuration; only reward_outside varies."""
    reward_outside: np.ndarray
    """(values,) region II rewards tried."""
    stuck: np.ndarray
    """(values, runs) True where the run ended stuck in 'R everywhere'."""
    prob_left_I: np.ndarray
    """(values, runs, 2 agents) final mean P(L) in region I on the evaluation grid."""
    rerun_prob_left_I: np.ndarray
    """(runs, 2 agents) the same for the highest reward's runs rerun from their own initial
    parameters on another stream (RERUN_STREAM)."""
    zero_start_stuck: np.ndarray
    """(2, runs) ``stuck`` at the lowest and the highest reward for runs that all start from zero
    parameters (init_scale 0) on the same streams: what the random start does."""


DEFAULT_SWEEP = (0.5, 0.625, 0.75, 0.875, 1.0)
"""Region II rewards of the stuck sweep: from the chapter's 0.5 up to the largest feedback, 1."""
RERUN_STREAM = 1
"""The stream (ANDNetworkConfig.stream) of the rerun at the highest region II reward."""


def sweep(config: ANDNetworkConfig, rewards_outside=DEFAULT_SWEEP, seed: int = 0,
          workers=None, progress: str | None = None) -> SweepResult:
    """Run experiment 2 for each region II reward (same seed for each, so the runs share their
    initialisation and positions until their actions differ) and record which runs got stuck;
    then rerun the highest reward's runs from the same initial parameters on stream RERUN_STREAM,
    and the lowest and highest reward's runs from zero parameters."""
    values = np.array(rewards_outside, dtype=np.float64)
    if values.ndim != 1 or values.size < 2:
        raise UserError(f"rewards_outside needs at least two values, got {rewards_outside!r}")
    configs = [replace(config, reward_outside=float(value)) for value in values]
    rerun = replace(configs[-1], stream=RERUN_STREAM)
    zero_starts = [replace(c, init_scale=0.0) for c in (configs[0], configs[-1])]
    configs += [rerun, *zero_starts]
    memory.check(config, copies=len(configs))  # every reward's arrays are held at once
    batches = [batch(c, seed) for c in configs]
    parallel.run_many(batches, workers=workers, progress=progress)  # every reward's runs on one pool
    left_I = np.array([final_left_by_region(result_of(c, work))[0] for c, work in zip(configs, batches)])
    stuck = (left_I < config.stuck_threshold).all(axis=2)
    n = values.size
    return SweepResult(config, values, stuck[:n], left_I[:n], left_I[n], stuck[n + 1:])


def scaled(runs: int, iterations: int) -> ANDNetworkConfig:
    """The chapter's experiment 2 at ``runs`` and ``iterations``, with no more points of the
    Fig. 7b curve than iterations."""
    return ANDNetworkConfig(runs=runs, iterations=iterations,
                            record_points=min(ANDNetworkConfig.record_points, iterations))
