"""Experiment 2 of Section 4.2: each agent is an AND network of two GLAs, the rewarded regions
are split by a parabola (Fig. 7), and raising region II's reward traps runs in 'R everywhere'.

Both agents see the joint context [x1, x2, 1]. Each agent's two 2-action units act on it; the
agent plays L only when both units output 1 (``glamas.gla.and_network``). Inside the parabola
(region I) (L, L) pays 0.9, outside it (region II) (R, R) pays 0.5, anything else 0.1.
"""

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace

import numpy as np
from numba import njit

from glamas import checks, claims, gla, lineworld, memory, parallel
from glamas.errors import UserError
from glamas.experiments.registry import Experiment, register
from glamas.learners import and_network as learner
from glamas.learners.and_network import CONTEXT_LENGTH, NETWORK, left_probability
from glamas.plotting import legend_below



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
    unit parameters and Fig. 7b's curve."""
    c = config
    shape = (c.runs, 2, NETWORK.n_units, max(NETWORK.unit_actions), NETWORK.n_inputs)
    outputs = (np.zeros((c.runs, c.probe_points, 2)), np.zeros(shape), np.zeros((c.runs, c.record_points, 2)))
    return parallel.Batch(learner.learn, learner.kernel_inputs(config), outputs, seed)


def result_of(config: ANDNetworkConfig, work: parallel.Batch) -> ANDNetworkResult:
    """The result of ``config`` once its :func:`batch` has run."""
    _, params, prob_left = work.outputs
    n = config.record_points
    iteration = np.arange(n) * config.iterations // (n - 1) if n > 1 else np.array([0])
    return ANDNetworkResult(config, iteration, prob_left, params)


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
    return _region_means(_left_maps(result), result.config)


def _region_means(p_left: np.ndarray, config: ANDNetworkConfig) -> tuple[np.ndarray, np.ndarray]:
    """(runs, 2 agents) mean P(L) in region I and in region II from every run's P(L) maps."""
    _, _, inside = _evaluation_points(config)
    return p_left[:, :, inside].mean(axis=2), p_left[:, :, ~inside].mean(axis=2)


def _agreement(p_left: np.ndarray, config: ANDNetworkConfig) -> np.ndarray:
    """(runs,) how well the learned L-region matches region I (Fig. 7a), from every run's P(L)
    maps (runs, 2 agents, points): the share of the evaluation grid where 'both agents'
    P(L) > 1/2' agrees with 'inside the parabola', rescaled so that 0 is what the best constant
    guess (all I or all II) gets and 1 is the parabola itself: the fraction of the constant
    guess's errors the learned boundaries remove."""
    _, _, inside = _evaluation_points(config)
    trivial = max(inside.mean(), 1.0 - inside.mean())
    agreement = ((p_left > 0.5).all(axis=1) == inside).mean(axis=1)
    return (agreement - trivial) / (1.0 - trivial)


def _left_maps(result: ANDNetworkResult) -> np.ndarray:
    """(runs, 2 agents, points) every run's final P(L) on the evaluation grid, the runs' maps
    drawn on one thread per core (the kernel releases the GIL)."""
    x1, x2, _ = _evaluation_points(result.config)
    with ThreadPoolExecutor(parallel.cores()) as pool:
        return np.stack(list(pool.map(lambda r: left_map(result, r, x1, x2), range(result.params.shape[0]))))


def _evaluation_points(config: ANDNetworkConfig):
    """The evaluation grid (x1, x2) and which of its points lie in region I."""
    x1, x2 = lineworld.state_grid(config.eval_grid)
    return x1, x2, x2 >= config.parabola_curvature * x1 ** 2 + config.parabola_offset


def measure(result: ANDNetworkResult) -> dict:
    """Fig. 7's metrics: how well the learned L-region matches region I, final P(L) in region I
    (Fig. 7b's last point and on the evaluation grid), P(R) in region II, the lower of P(L) in
    I and P(R) in II, and the fraction of stuck runs."""
    p_left = _left_maps(result)
    in_I, in_II = _region_means(p_left, result.config)
    curve_end = result.prob_left[:, -1, :].mean(axis=0)
    left_I, right_II = in_I.mean(axis=0), 1.0 - in_II.mean(axis=0)
    return {
        "region_I_error_removed": _agreement(p_left, result.config).mean(),
        "final_prob_left_I_a": curve_end[0],
        "final_prob_left_I_b": curve_end[1],
        "final_prob_left_I_min": curve_end.min(),
        "grid_prob_left_I_a": left_I[0],
        "grid_prob_left_I_b": left_I[1],
        "grid_prob_right_II_a": right_II[0],
        "grid_prob_right_II_b": right_II[1],
        "grid_prob_right_II_min": right_II.min(),
        "grid_prob_region_action_min": min(left_I.min(), right_II.min()),
        "stuck_fraction": (in_I < result.config.stuck_threshold).all(axis=1).mean(),
    }


def claim_rows(result: ANDNetworkResult) -> list[dict]:
    """The Fig. 7 claims (data/chapter/section4.json) with verdicts computed from ``result``."""
    return claims.verdicts(claims.load("and_network"), measure(result))


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


DEFAULT_SWEEP = (0.5, 0.625, 0.75, 0.875, 1.0)
"""Region II rewards of the stuck sweep: from the chapter's 0.5 up to the largest feedback, 1."""
RERUN_STREAM = 1
"""The stream (ANDNetworkConfig.stream) of the rerun at the highest region II reward."""
BOOTSTRAP_DRAWS = 10_000
"""Resamples of the runs for the 95 % interval of the initialisation's share of the outcome."""


def sweep(config: ANDNetworkConfig, rewards_outside=DEFAULT_SWEEP, seed: int = 0,
          workers=None, progress: str | None = None) -> SweepResult:
    """Run experiment 2 for each region II reward (same seed for each, so the runs share their
    initialisation and positions until their actions differ) and record which runs got stuck;
    then rerun the highest reward's runs from the same initial parameters on stream RERUN_STREAM."""
    values = np.array(rewards_outside, dtype=np.float64)
    if values.ndim != 1 or values.size < 2:
        raise UserError(f"rewards_outside needs at least two values, got {rewards_outside!r}")
    configs = [replace(config, reward_outside=float(value)) for value in values]
    configs.append(replace(configs[-1], stream=RERUN_STREAM))
    memory.check(config, copies=len(configs))  # every reward's arrays are held at once
    batches = [batch(c, seed) for c in configs]
    parallel.run_many(batches, workers=workers, progress=progress)  # every reward's runs on one pool
    left_I = np.array([final_left_by_region(result_of(c, work))[0] for c, work in zip(configs, batches)])
    stuck = (left_I[:-1] < config.stuck_threshold).all(axis=2)
    return SweepResult(config, values, stuck, left_I[:-1], left_I[-1])


def measure_sweep(result: SweepResult) -> dict:
    """Stuck fraction at each reward, at the chapter's 0.5, at the highest value, and the rise;
    at the highest reward, how far the initialisation decides the outcome (:func:`init_dependence`)."""
    fractions = result.stuck.mean(axis=1)
    measured = {f"stuck_fraction_{value:g}": f for value, f in zip(result.reward_outside, fractions)}
    measured["stuck_fraction_lowest"] = fractions[0]
    measured["stuck_fraction_highest"] = fractions[-1]
    measured["stuck_fraction_rise"] = fractions[-1] - fractions[0]
    threshold = result.config.stuck_threshold
    first = (result.prob_left_I[-1] < threshold).all(axis=1)
    measured["stuck_fraction_rerun"] = (result.rerun_prob_left_I < threshold).all(axis=1).mean()
    return measured | init_dependence(first, (result.rerun_prob_left_I < threshold).all(axis=1))


def init_dependence(first: np.ndarray, rerun: np.ndarray, draws: int = BOOTSTRAP_DRAWS) -> dict:
    """How far the initialisation decides whether a run gets stuck, from the outcomes (runs,) of
    the same initial parameters on two streams: the agreement of run r's two outcomes (same
    initialisation), the agreement of run r's first with run s's rerun for every s != r (another
    initialisation), and the initialisation's share of the outcome, (same - other) / (1 - other):
    the fraction of the disagreement between unrelated initialisations that keeping the
    initialisation removes (close to Cohen's kappa of the two streams; 0: the stream alone
    decides, 1: the initialisation does), with its 95 % bootstrap interval over runs (in a
    resample, copies of one run count as other initialisations, which can only lower the share).
    NaN when every run ends alike (no disagreement to remove)."""
    pairs = np.stack([first, rerun]).astype(np.float64)
    boot = np.random.default_rng(0).integers(0, first.shape[0], (draws, first.shape[0]))
    same, other = _agreements(pairs[None])
    shares = _init_share(*_agreements(pairs[:, boot].transpose(1, 0, 2)))
    low, high = np.nanpercentile(shares, [2.5, 97.5]) if np.isfinite(shares).any() else (np.nan, np.nan)
    measured = {"init_agreement_same": same[0], "init_agreement_other": other[0],
                "init_share_of_outcome": _init_share(same, other)[0],
                "init_share_of_outcome_low": low, "init_share_of_outcome_high": high}
    if np.isnan(measured["init_share_of_outcome"]):
        measured["init_share_of_outcome" + claims.WHY_UNDECIDABLE] = (
            "every run ends alike on both streams: no disagreement for the initialisation to explain")
    return measured


def _agreements(pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per sample of ``pairs`` (samples, 2 streams, runs) of 0/1 outcomes: the share of runs whose
    two outcomes agree, and the share of ordered pairs of positions r != s where the first
    stream's outcome of r agrees with the second's of s."""
    a, b = pairs[:, 0], pairs[:, 1]
    n = a.shape[1]
    same = (a == b).sum(axis=1)
    ones_a, ones_b = a.sum(axis=1), b.sum(axis=1)
    every_pair = ones_a * ones_b + (n - ones_a) * (n - ones_b)  # agreeing (r, s) over all r, s
    return same / n, (every_pair - same) / (n * (n - 1))


def _init_share(same: np.ndarray, other: np.ndarray) -> np.ndarray:
    """(same - other) / (1 - other), NaN where other is 1."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(other < 1, (same - other) / (1 - other), np.nan)


def sweep_claim_rows(result: SweepResult) -> list[dict]:
    """The stuck-runs claim (data/chapter/section4.json) with its verdict computed from ``result``."""
    return claims.verdicts(claims.load("and_network_sweep"), measure_sweep(result))


def scaled(runs: int, iterations: int) -> ANDNetworkConfig:
    """The chapter's experiment 2 at ``runs`` and ``iterations``, with no more points of the
    Fig. 7b curve than iterations."""
    return ANDNetworkConfig(runs=runs, iterations=iterations,
                            record_points=min(ANDNetworkConfig.record_points, iterations))


FIG7 = register(Experiment("and_network", ANDNetworkConfig, run, scaled, ANDNetworkConfig.runs,
                           ANDNetworkConfig.iterations, ANDNetworkResult,
                           claim_rows=lambda result, config: claim_rows(result), figures=("fig7a", "fig7b")))
"""Fig. 7a and 7b's experiment (one run for both)."""
FIG7_SWEEP = register(Experiment("and_network_sweep", ANDNetworkConfig, sweep, scaled, ANDNetworkConfig.runs,
                                 ANDNetworkConfig.iterations, SweepResult,
                                 claim_rows=lambda result, config: sweep_claim_rows(result), figures=("fig7_sweep",),
                                 chapter=False, copies=len(DEFAULT_SWEEP) + 1))
"""The stuck sweep: experiment 2 at each region II reward of DEFAULT_SWEEP, and the highest
reward's rerun on another stream."""


# ---- plots (each draws on a given Axes) ----

def plot_parabola(ax, config: ANDNetworkConfig):
    """Region I (inside the parabola) shaded, with its border."""
    x = np.linspace(-1.0, 1.0, 401)
    border = config.parabola_curvature * x ** 2 + config.parabola_offset
    ax.fill_between(x, np.clip(border, -1, 1), 1.0, color="tab:blue", alpha=0.2, linewidth=0)
    ax.plot(x, np.where(border <= 1, border, np.nan), color="k", lw=1.5)
    ax.text(0.0, 0.4, "I: (L, L) 0.9", ha="center")
    ax.text(0.98, -0.95, f"II: (R, R) {config.reward_outside:g}", ha="right")
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x1 (position of agent A)")
    ax.set_ylabel("x2 (position of agent B)")


AGENT_COLOURS = (("A", "tab:red"), ("B", "tab:purple"))
"""Each agent's name and colour in Fig. 7a and 7b."""


def plot_boundaries(ax, result: ANDNetworkResult, run_index: int, grid: int = 200, title: str | None = None):
    """Fig. 7a: over the parabola, each agent's learned boundary P(L) = 1/2 for one run; ``title``
    says which run it is (default: its index), the index then goes to the legend's title."""
    plot_parabola(ax, result.config)
    centres = -1.0 + (np.arange(grid) + 0.5) * (2.0 / grid)
    x1, x2 = np.meshgrid(centres, centres, indexing="xy")
    p_left = left_map(result, run_index, x1.ravel(), x2.ravel())
    for agent, (name, colour) in enumerate(AGENT_COLOURS):
        ax.contour(x1, x2, p_left[agent].reshape(x1.shape), levels=[0.5], colors=colour,
                   linewidths=2)
        ax.plot([], [], color=colour, lw=2, label=f"agent {name}: P(L) = 1/2")
    legend_below(ax, title=None if title is None else f"run {run_index}", title_fontsize="small")
    ax.set_title(f"run {run_index}" if title is None else title, fontsize="medium")


def stuck_runs(result: ANDNetworkResult) -> np.ndarray:
    """(runs,) True where the run ended stuck in 'R everywhere' (as :func:`measure` counts them)."""
    in_I, _ = final_left_by_region(result)
    return (in_I < result.config.stuck_threshold).all(axis=1)


def plot_prob_left(ax, result: ANDNetworkResult):
    """Fig. 7b: P(L) in region I of both agents over iterations: every run faint (the runs split
    into those that learned and those stuck in 'R everywhere', which a mean over all runs would
    hide), and each group's mean per agent, A solid and wide under B dashed, so both show."""
    stuck = stuck_runs(result)
    for agent, (name, colour) in enumerate(AGENT_COLOURS):
        ax.plot(result.iteration, result.prob_left[:, :, agent].T, color=colour, alpha=0.12, linewidth=0.6)
    for group, label in ((~stuck, "that learned"), (stuck, "that got stuck")):
        for agent, (name, colour) in enumerate(AGENT_COLOURS):
            if group.any():
                ax.plot(result.iteration, result.prob_left[group, :, agent].mean(axis=0), color=colour,
                        linewidth=2.8 if agent == 0 else 1.4, linestyle="-" if agent == 0 else "--",
                        label=f"agent {name}, mean of the {group.sum()} runs {label}")
    ax.plot([], [], color="0.5", alpha=0.4, linewidth=0.6, label="one run (per agent)")
    ax.set_title(f"stuck in 'R everywhere' at the end: {stuck.sum()} of {stuck.size} runs "
                 f"({stuck.mean():.0%})", fontsize="medium")
    ax.set_xlabel("iteration")
    ax.set_ylabel("P(L) in region I")
    ax.set_ylim(0, 1)
    legend_below(ax)


def plot_stuck_fraction(ax, result: SweepResult):
    """Fraction of runs stuck in 'R everywhere' against region II's reward, with 95 % Wilson bands."""
    n = result.stuck.shape[1]
    fractions = result.stuck.mean(axis=1)
    low, high = _wilson(fractions, n)
    ax.errorbar(result.reward_outside, fractions, yerr=[fractions - low, high - fractions],
                marker="o", capsize=3)
    ax.set_xlabel("reward of (R, R) in region II")
    ax.set_ylabel("fraction of runs stuck in 'R everywhere'")
    ax.set_ylim(-0.02, 1.02)


def typical_runs(result: ANDNetworkResult, count: int = 2) -> list[int]:
    """Runs around the median final P(L) in region I (both agents): Fig. 7a's 'typical results'."""
    in_I, _ = final_left_by_region(result)
    order = np.argsort(in_I.mean(axis=1), kind="stable")
    middle = (order.shape[0] - count) // 2
    return [int(i) for i in order[middle:middle + count]]


def _wilson(fractions: np.ndarray, n: int, z: float = 1.96):
    centre = (fractions + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(fractions * (1 - fractions) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half
