"""Experiment 1 of Section 4.2: one 2-action GLA per agent in the line world (Fig. 5 and Fig. 6).

Both agents see a context built from the joint position (Fig. 6 compares three encodings), act
with eq. 15, get experiment 1's common 0/1 feedback and learn with eq. 13; then both restart at
new random positions. A run records the average feedback per window of iterations and the final
GLA parameters; :func:`evaluate` turns those into exact expected rewards over the state square.
Fig. 6's runs also record the parameters at checkpoints, and its claims read the expected reward
there (:func:`expected_curves`), never the plot's windows.
"""

from dataclasses import dataclass, field, replace

import numpy as np
from numba import njit

from glamas import checks, claims, gla, lineworld, memory, parallel
from glamas.curves import BOOTSTRAP_DRAWS, final_per_run
from glamas.errors import UserError
from glamas.experiments.registry import Experiment, register
from glamas.learners import single_gla as learner
from glamas.plotting import legend_below, plot_mean_band

ENCODING_NAMES = ("joint", "absolute", "deictic")
PARAMETERS = 2 * 2 * 3
"""GLA parameters of a run at most: 2 agents, 2 actions, the longest context (joint, 3 inputs)."""

BOX_READINGS = ("fig5", "two", "input_range")
"""Readings of Fig. 6's box L (eq. 14), which the chapter does not restate (:class:`EncodingConfig`)."""
INPUT_RANGE = {"joint": 1.0, "absolute": 2.0, "deictic": 2.0}
"""The largest |input| of each context's non-bias inputs: positions lie in [-1, 1], so
|xA - xB| lies in [0, 2] and x_self - x_other in [-2, 2]."""


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

    def arrays(self) -> dict:
        """The arrays a result file stores; the checkpoints only when there are any."""
        arrays = {"iteration": self.iteration, "reward": self.reward, "params": self.params}
        if self.checkpoint.size:
            arrays.update(checkpoint=self.checkpoint, checkpoint_params=self.checkpoint_params)
        return arrays


def run(config: SingleGLAConfig, seed: int = 0, workers=None, progress: str | None = None,
        checkpoint_at: np.ndarray = learner.NO_CHECKPOINTS) -> SingleGLAResult:
    """All runs of experiment 1 for ``config``; identical for any number of workers. The
    parameters are also recorded after each of ``checkpoint_at`` iterations, which changes
    nothing else."""
    memory.check(config)
    n_inputs = lineworld.CONTEXT_LENGTH[lineworld.encoding_code(config.context)]
    params = np.zeros((config.runs, 2, 2, n_inputs))
    reward = np.zeros((config.runs, config.record_points))
    checkpoints = np.zeros((config.runs, len(checkpoint_at), 2, 2, n_inputs))
    parallel.run_batches(learner.learn, learner.kernel_inputs(config, checkpoint_at), (params, reward, checkpoints),
                         seed, workers=workers, progress=progress)
    points = np.arange(1, config.record_points + 1)
    return SingleGLAResult(config, points * config.iterations // config.record_points, reward, params,
                           np.asarray(checkpoint_at, dtype=np.int64), checkpoints)


@njit(cache=True)
def correct_probabilities(u, encoding, region3, agent, x1, x2, temperature, L, mode, out):
    """out[i]: probability (eq. 15) that the agent plays its part of the rewarded joint action
    at (x1[i], x2[i]) (region 3 read as ``region3``)."""
    context = np.empty(u.shape[1])
    probs = np.empty(2)
    for i in range(x1.shape[0]):
        lineworld.context(encoding, agent, x1[i], x2[i], context)
        gla.boltzmann(u, context, temperature, L, mode, probs)
        out[i] = probs[lineworld.best_action(x1[i], x2[i], agent, region3)]


@njit(cache=True)
def best_actions(x1, x2, agent, region3=lineworld.MOVE_APART):
    """The agent's part of the rewarded joint action at every point (region 3 read as ``region3``)."""
    out = np.empty(x1.shape[0], dtype=np.int64)
    for i in range(x1.shape[0]):
        out[i] = lineworld.best_action(x1[i], x2[i], agent, region3)
    return out


@njit(cache=True)
def regions(x1, x2):
    """The region of Fig. 5a (1, 2 or 3) of every point."""
    out = np.empty(x1.shape[0], dtype=np.int64)
    for i in range(x1.shape[0]):
        out[i] = lineworld.region(x1[i], x2[i])
    return out


def contexts(encoding: int, agent: int, x1: np.ndarray, x2: np.ndarray) -> np.ndarray:
    """(points, context length) the agent's contexts at the given positions."""
    out = np.empty((x1.shape[0], lineworld.CONTEXT_LENGTH[encoding]))
    for i in range(x1.shape[0]):
        lineworld.context(encoding, agent, x1[i], x2[i], out[i])
    return out


@dataclass(frozen=True)
class Evaluation:
    """Expected rewards of every run's final policies, averaged over the evaluation grid."""

    agent_reward: np.ndarray
    """(runs, 2) expected feedback of each agent's Boltzmann policy when the other agent plays
    its part of the rewarded joint action (i.e. the agent's probability of playing its part)."""
    line_reward: np.ndarray
    """(runs, 2) the same for the agent's learned line: the greedy (most probable) action."""
    team_reward: np.ndarray
    """(runs,) expected feedback when both agents play their Boltzmann policies."""


def _correct_on_grid(params: np.ndarray, config: SingleGLAConfig) -> np.ndarray:
    """(2 agents, grid points) each agent's probability of playing its part of the rewarded
    joint action, for parameters (2 agents, 2 actions, context length)."""
    encoding, mode = lineworld.encoding_code(config.context), config.gla_params().bounding_code
    region3 = lineworld.region3_code(config.region3_reward)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    correct = np.empty((2, x1.shape[0]))
    for agent in range(2):
        correct_probabilities(params[agent], encoding, region3, agent, x1, x2, config.temperature,
                              config.L, mode, correct[agent])
    return correct


def team_reward(params: np.ndarray, config: SingleGLAConfig) -> float:
    """Expected feedback of both agents' Boltzmann policies with the given parameters
    (2 agents, 2 actions, context length): the mean over the grid of P_A(right) P_B(right)."""
    correct = _correct_on_grid(params, config)
    return float((correct[0] * correct[1]).mean())


def evaluate(result: SingleGLAResult) -> Evaluation:
    """Exact-on-a-grid expected rewards of the learned policies (no sampling noise)."""
    return _evaluation(_correct_runs(result.params, result.config))


def _evaluation(correct: np.ndarray) -> Evaluation:
    """The expected rewards from every run's probabilities of playing each agent's part."""
    return Evaluation(correct.mean(axis=2), (correct > 0.5).mean(axis=2),
                      (correct[:, 0] * correct[:, 1]).mean(axis=1))


def _correct_runs(params: np.ndarray, config: SingleGLAConfig) -> np.ndarray:
    """(runs, 2 agents, grid points) :func:`_correct_on_grid` for every run's parameters."""
    return np.stack([_correct_on_grid(u, config) for u in params])


def best_line_reward(encoding_name: str, agent: int, grid: int = 200, angles: int = 720,
                     region3_reward: str = "move_apart") -> float:
    """The best expected reward a single line (a fixed threshold on a linear function of the
    context, i.e. a deterministic 2-action GLA policy) gives the agent, the other agent playing
    its part of the rewarded joint action (exhaustive search, :func:`best_line_shares`)."""
    encoding, region3 = lineworld.encoding_code(encoding_name), lineworld.region3_code(region3_reward)
    x1, x2 = lineworld.state_grid(grid)
    return float(best_line_shares(encoding, region3, agent, x1, x2, np.ones((1, x1.shape[0])), angles)[0])


def best_line_shares(encoding: int, region3: int, agent: int, x1: np.ndarray, x2: np.ndarray,
                     counts: np.ndarray, angles: int = 720) -> np.ndarray:
    """(rows of ``counts``,) the largest share of the points (x1, x2) a single line of the agent
    plays its part of the rewarded joint action at (region 3 read as ``region3``), counting point
    i with weight counts[row, i] (1 everywhere: the agent's best line; 1 where the other agent
    plays its part: the agent's best line given the other's policy, its best response among lines).

    Exhaustive search: for each direction w of the non-bias inputs (``angles`` directions over the
    circle when there are two, +-1 when there is one), every threshold between consecutive
    distinct projections w.x is tried, with L on the side of larger projections.
    """
    features, directions, wants_left = _line_search(encoding, region3, agent, x1, x2, angles)
    counts = np.asarray(counts, dtype=np.float64)
    return _best_threshold(features, directions, wants_left, counts)[0] / x1.shape[0]


def best_line_plays(encoding: int, region3: int, agent: int, x1: np.ndarray, x2: np.ndarray,
                    angles: int = 720) -> np.ndarray:
    """(points,) True where the agent's best single line (:func:`best_line_shares` with weight 1
    everywhere; of tied lines the first found) plays its part of the rewarded joint action."""
    features, directions, wants_left = _line_search(encoding, region3, agent, x1, x2, angles)
    _, direction, threshold = _best_threshold(features, directions, wants_left, np.ones((1, x1.shape[0])))
    if direction[0] < 0:  # no threshold beats playing L everywhere
        return wants_left.copy()
    return (_projection(features, directions[direction[0]]) > threshold[0]) == wants_left


def _line_search(encoding, region3, agent, x1, x2, angles):
    """The inputs of :func:`_best_threshold`: the agent's contexts without the bias input, the
    directions to try, and where the agent's part of the rewarded joint action is L."""
    features = np.ascontiguousarray(contexts(encoding, agent, x1, x2)[:, :-1])
    wants_left = best_actions(x1, x2, agent, region3) == lineworld.LEFT
    if features.shape[1] == 1:
        directions = np.array([[1.0], [-1.0]])
    else:
        theta = np.arange(angles) * (2 * np.pi / angles)
        directions = np.column_stack([np.cos(theta), np.sin(theta)])
    return features, directions, wants_left


@njit(cache=True)
def _projection(features, direction):
    """features @ direction by hand: numba's matmul needs scipy, and the search and
    :func:`best_line_plays` must round alike."""
    projection = np.zeros(features.shape[0])
    for k in range(features.shape[1]):
        projection += features[:, k] * direction[k]
    return projection


@njit(cache=True)
def _best_threshold(features, directions, wants_left, counts):
    """Per row of ``counts``: the largest weighted count of points a rule 'L iff w.x is above the
    threshold' gets right, over every direction w and every threshold between two distinct
    projections (or beyond all of them); with the first best direction's index (-1: L everywhere)
    and its threshold."""
    best = np.zeros(counts.shape[0])
    best_direction = np.full(counts.shape[0], -1, dtype=np.int64)
    best_threshold = np.full(counts.shape[0], -np.inf)
    left_total = np.zeros(counts.shape[0])
    for r in range(counts.shape[0]):
        for j in range(counts.shape[1]):
            if wants_left[j]:
                left_total[r] += counts[r, j]
        best[r] = left_total[r]
    for d in range(directions.shape[0]):
        projection = _projection(features, directions[d])
        order = np.argsort(projection, kind="mergesort")
        for r in range(counts.shape[0]):
            right_below, left_above = 0.0, left_total[r]
            for i in range(order.shape[0]):
                j = order[i]
                if wants_left[j]:
                    left_above -= counts[r, j]
                else:
                    right_below += counts[r, j]
                if (i + 1 == order.shape[0] or projection[order[i + 1]] != projection[j]) \
                        and right_below + left_above > best[r]:
                    best[r] = right_below + left_above
                    best_direction[r], best_threshold[r] = d, projection[j]
    return best, best_direction, best_threshold


REGIONS = (1, 2, 3)
"""The regions of Fig. 5a: 1 (A left of B), 2 (A right of B), 3 (closer than 0.5)."""


def region_shares(correct: np.ndarray, x1: np.ndarray, x2: np.ndarray) -> np.ndarray:
    """(runs, 3) per region of Fig. 5a, the share of its points where the most probable joint
    action is the region's rewarded one, from ``correct`` (runs, 2 agents, points): each agent's
    probability of playing its part. The agents act independently, so the most probable joint
    action is the pair of each agent's most probable action (a tie counts as not playing it):
    the label Fig. 5b gives the cell of the learned lines the point lies in."""
    both = (correct > 0.5).all(axis=1)
    labels = regions(x1, x2)
    return np.column_stack([both[:, labels == k].mean(axis=1) for k in REGIONS])


def best_lines_region_shares(config: SingleGLAConfig, angles: int = 720) -> np.ndarray:
    """(3,) :func:`region_shares` of each agent's best single line (:func:`best_line_plays`, on
    the evaluation grid): what Fig. 5b would show for the best lines the context allows under
    this reward, the ceiling of the learned lines' shares. A's best line is perfect under either
    reading of region 3, so the pair is also the team's best; under 'move_apart' B's two best
    lines (x2 = x1 +- 0.5) tie and, by symmetry, give the same shares. The best lines maximise
    the whole square's share, so in one region a learned pair can exceed them (by giving up
    another, or by the grid's rounding at the borders): a share of the ceiling can pass 1."""
    encoding, region3 = lineworld.encoding_code(config.context), lineworld.region3_code(config.region3_reward)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    plays = np.stack([best_line_plays(encoding, region3, agent, x1, x2, angles) for agent in range(2)])
    return region_shares(plays[None].astype(np.float64), x1, x2)[0]


def best_response_gap(params: np.ndarray, config: SingleGLAConfig, agent: int, grid: int = 100,
                      angles: int = 180) -> np.ndarray:
    """(runs,) how much the agent's learned line loses against the best line it could draw given
    the other agent's learned line (params: runs, 2 agents, 2 actions, inputs): the share of the
    points of a grid x grid grid where both lines play their parts, for the agent's best line
    (exhaustive search, :func:`best_line_shares`) minus for its learned line. The search is over
    every run, so it uses a coarser grid and fewer directions than :func:`best_line_reward`."""
    correct = _correct_runs(params, replace(config, eval_grid=grid)) > 0.5
    x1, x2 = lineworld.state_grid(grid)
    best = best_line_shares(lineworld.encoding_code(config.context), lineworld.region3_code(config.region3_reward),
                            agent, x1, x2, correct[:, 1 - agent].astype(np.float64), angles)
    return best - (correct[:, 0] & correct[:, 1]).mean(axis=1)


def measure(result: SingleGLAResult) -> dict:
    """Fig. 5's metrics: per region the share where the most probable joint action is the
    region's rewarded one, the same for the best single lines (the ceiling) and the share of the
    ceiling reached; each agent's gap to its best line given the other's; each agent's expected
    reward (policy and learned line) against the best a single line can reach with this context;
    the team's expected and final average reward."""
    config = result.config
    correct = _correct_runs(result.params, config)
    ev = _evaluation(correct)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    per_run = region_shares(correct, x1, x2)
    ceiling = best_lines_region_shares(config)
    of_ceiling = per_run / ceiling
    line_best = [best_line_reward(config.context, agent, config.eval_grid, region3_reward=config.region3_reward)
                 for agent in range(2)]
    measured = {}
    for k, region in enumerate(REGIONS):
        measured[f"region_{region}_share"] = per_run[:, k].mean()
        measured[f"region_{region}_ceiling"] = ceiling[k]
        measured[f"region_{region}_share_of_ceiling"] = of_ceiling[:, k].mean()
        measured[f"region_{region}_share_of_ceiling_lowest_run"] = of_ceiling[:, k].min()
    gaps = [best_response_gap(result.params, config, agent).mean() for agent in range(2)]
    return measured | {
        "agent_a_best_response_gap": gaps[0],
        "agent_b_best_response_gap": gaps[1],
        "agent_a_reward": ev.agent_reward[:, 0].mean(),
        "agent_b_reward": ev.agent_reward[:, 1].mean(),
        "agent_a_line_reward": ev.line_reward[:, 0].mean(),
        "agent_b_line_reward": ev.line_reward[:, 1].mean(),
        "best_line_a": line_best[0],
        "best_line_b": line_best[1],
        "agent_a_line_gap": line_best[0] - ev.line_reward[:, 0].mean(),
        "agent_b_line_gap": line_best[1] - ev.line_reward[:, 1].mean(),
        "team_reward": ev.team_reward.mean(),
        "final_average_reward": final_per_run(result.reward).mean(),
    }


def typical_run(result: SingleGLAResult) -> int:
    """The run whose team reward is the median one (the 'typical result' of Fig. 5b)."""
    team = evaluate(result).team_reward
    return int(np.argsort(team, kind="stable")[(team.shape[0] - 1) // 2])


def box_L(box: str, encoding: str, fig5_L: float) -> float:
    """L of eq. 14 for one encoding under a reading of Fig. 6's box (:data:`BOX_READINGS`):
    'fig5' Fig. 5's L for every encoding, 'two' L = 2 for every one, 'input_range' Fig. 5's L
    times the encoding's input range (:data:`INPUT_RANGE`: joint 1, absolute and deictic 2), the
    rule 2observe's box follows (a box that scales with the largest input)."""
    if box not in BOX_READINGS:
        raise UserError(f"box must be one of {list(BOX_READINGS)}, got {box!r}")
    return {"fig5": fig5_L, "two": 2.0, "input_range": fig5_L * INPUT_RANGE[encoding]}[box]


@dataclass(frozen=True)
class EncodingConfig:
    """Fig. 6 (Section 4.2): experiment 1 once per context encoding. Fig. 6 restates no setting:
    ``experiment`` holds Fig. 5's."""

    experiment: SingleGLAConfig = SingleGLAConfig()
    """Experiment 1's settings; each encoding's runs take its context and the L that ``box`` gives."""
    box: str = "fig5"
    """Fig. 6's box L (:func:`box_L`): 'fig5' (default), 'two' or 'input_range'. Fig. 6 is the same
    experiment with other contexts and was run without tuning the Boltzmann exploration, which the
    box caps (it bounds u.x / T); every encoding's best boundaries (x1 = x2, |x1 - x2| = 0.5) lie
    where L = 1 already lets them be sharp, so the reason for 2observe's wider box does not arise."""
    checkpoints: int = 48
    """Checkpoints log-spaced from iteration 10 to the last (with the start), where the GLA
    parameters are recorded and the expected reward of the learning curve is evaluated."""

    def __post_init__(self):
        checks.field_types(self)
        checks.whole_numbers(self, {"checkpoints": 2})
        for name in ENCODING_NAMES:
            self.encoding(name)  # validates box, and init_scale against each encoding's L

    def encoding(self, name: str) -> SingleGLAConfig:
        """Experiment 1's configuration for the context ``name`` under this box reading."""
        return replace(self.experiment, context=name, L=box_L(self.box, name, self.experiment.L))

    def checkpoint_iterations(self) -> np.ndarray:
        """The iterations after which the parameters are recorded: 0 and ``checkpoints`` log-spaced
        ones from 10 (or the last iteration, if fewer) to the last (rounded, duplicates dropped)."""
        last = self.experiment.iterations
        spaced = np.rint(np.geomspace(min(10, last), last, self.checkpoints)).astype(np.int64)
        return np.unique(np.concatenate([[0], spaced]))

    def memory_bytes(self) -> int:
        """Bytes of one encoding's runs: experiment 1's arrays and the parameters at the start and
        at the checkpoints."""
        checkpoints = memory.per_run(self.experiment.runs, (self.checkpoints + 1) * PARAMETERS)
        return self.experiment.memory_bytes() + checkpoints


def compare_encodings(config: EncodingConfig, seed: int = 0, workers=None,
                      progress: str | None = None) -> dict:
    """Fig. 6: the same experiment with each context encoding (same seed, so run r of every
    encoding sees the same positions until their actions differ), the parameters recorded at the
    checkpoints."""
    return {name: run(config.encoding(name), seed, workers, None if progress is None else f"{progress} ({name})",
                      config.checkpoint_iterations())
            for name in ENCODING_NAMES}


@njit(cache=True)
def team_rewards(params, contexts_a, contexts_b, part_a, part_b, weight, temperature, L, mode, out):
    """out[m]: the expected feedback of both agents' Boltzmann policies (eq. 15 at h(u), two
    actions: P(L) = 1 / (1 + exp(-(h(u_L) - h(u_R)).x / T))) with parameters params[m] (2 agents,
    2 actions, inputs): the weighted mean over the points of P_A(part) P_B(part), from each
    point's contexts, parts of the rewarded joint action and weight (:func:`grid_points`)."""
    n_inputs = contexts_a.shape[1]
    w = np.empty((2, n_inputs))
    for m in range(params.shape[0]):
        for agent in range(2):
            for k in range(n_inputs):
                w[agent, k] = (gla.bound(params[m, agent, lineworld.LEFT, k], L, mode)
                               - gla.bound(params[m, agent, lineworld.RIGHT, k], L, mode)) / temperature
        total = 0.0
        for i in range(contexts_a.shape[0]):
            z_a, z_b = 0.0, 0.0
            for k in range(n_inputs):
                z_a += w[0, k] * contexts_a[i, k]
                z_b += w[1, k] * contexts_b[i, k]
            p_a = 1.0 / (1.0 + np.exp(-z_a if part_a[i] == lineworld.LEFT else z_a))
            p_b = 1.0 / (1.0 + np.exp(-z_b if part_b[i] == lineworld.LEFT else z_b))
            total += weight[i] * p_a * p_b
        out[m] = total / weight.sum()


EDGE_NUDGE = 1e-9
"""How far :func:`grid_points` moves a point to read the rewarded action on each side of it."""


def grid_points(config: SingleGLAConfig) -> tuple:
    """The evaluation grid as :func:`team_rewards` reads it: (contexts of A, contexts of B, A's
    part, B's part, weight). Each point counts half with the rewarded joint action just left and
    half with the one just right of it (x1 -+ EDGE_NUDGE): the same inside a region, and on a
    region's edge (the grid puts points on x1 = x2 and |x1 - x2| = 0.5) an even split, as the edge
    splits the point's cell. Counting such a point wholly on one side would bias each run's
    expected reward by up to a cell's width times its policy's jump there, a run-to-run scatter
    that halves with every doubling of the grid. Points with the same contexts and parts are
    merged, their weights added (the distance contexts see about 2 eval_grid distinct points)."""
    encoding = lineworld.encoding_code(config.context)
    x1, x2 = lineworld.state_grid(config.eval_grid)
    n = lineworld.CONTEXT_LENGTH[encoding]
    seen = np.column_stack([contexts(encoding, lineworld.AGENT_A, x1, x2), contexts(encoding, lineworld.AGENT_B, x1, x2)])
    rows = np.vstack([np.column_stack([seen, best_actions(x1 + side, x2, lineworld.AGENT_A),
                                       best_actions(x1 + side, x2, lineworld.AGENT_B)])
                      for side in (-EDGE_NUDGE, EDGE_NUDGE)])
    _, first, counts = np.unique(np.round(rows, 12), axis=0, return_index=True, return_counts=True)
    rows = rows[first]
    return (np.ascontiguousarray(rows[:, :n]), np.ascontiguousarray(rows[:, n:2 * n]), rows[:, 2 * n].astype(np.int64),
            rows[:, 2 * n + 1].astype(np.int64), counts / 2.0)


def expected_curves(result: SingleGLAResult) -> np.ndarray:
    """(runs, checkpoints) the team's expected feedback (:func:`team_rewards` on the evaluation
    grid) at every checkpoint of every run: Fig. 6's learning curve without sampling noise."""
    config = result.config
    runs, points = result.checkpoint_params.shape[:2]
    out = np.empty(runs * points)
    team_rewards(result.checkpoint_params.reshape(runs * points, *result.checkpoint_params.shape[2:]),
                 *grid_points(config), config.temperature, config.L, config.gla_params().bounding_code, out)
    return out.reshape(runs, points)


def curve_mean(curves: np.ndarray, iteration: np.ndarray) -> np.ndarray:
    """(runs,) each curve's mean over the iterations from the first to the last checkpoint
    (trapezoids between checkpoints): the height of the learning curve averaged over the run."""
    widths = np.diff(iteration)
    return (curves[:, 1:] + curves[:, :-1]) @ widths / (2.0 * widths.sum())


REACH_TOLERANCE = 0.05
"""Learning speed: the iteration at which the expected reward first reaches 95 % of its final value."""


def reach_iteration(curves: np.ndarray, iteration: np.ndarray, tolerance: float = REACH_TOLERANCE) -> np.ndarray:
    """(runs,) the iteration at which each curve (runs, checkpoints) first reaches (1 - tolerance)
    times its last value, linear between the checkpoints that bracket it (0 if the first does)."""
    target = (1.0 - tolerance) * curves[:, -1]
    out = np.empty(curves.shape[0])
    for r, (curve, level) in enumerate(zip(curves, target)):
        c = int(np.argmax(curve >= level))
        if c == 0:
            out[r] = iteration[0]
            continue
        share = (level - curve[c - 1]) / (curve[c] - curve[c - 1])
        out[r] = iteration[c - 1] + share * (iteration[c] - iteration[c - 1])
    return out


COMPARISONS = (("deictic", "joint"), ("joint", "absolute"), ("deictic", "absolute"))
"""Fig. 6's pairs of encodings (better, worse) in the chapter's ordering."""


def measure_encodings(results: dict, tolerance: float = REACH_TOLERANCE) -> dict:
    """Fig. 6's metrics, all from the expected reward at the checkpoints (:func:`expected_curves`),
    none from the plot windows: per encoding the mean over runs of the learning curve's mean
    (:func:`curve_mean`) and final value; per pair of encodings (run r of each shares its seed) the
    paired difference of both with its 95 % interval and Cohen's d; the absolute distance's
    smaller d against the others; deictic against joint, the iterations to reach 1 - ``tolerance``
    of the final value (:func:`speed_comparison`)."""
    curves = {name: expected_curves(res) for name, res in results.items()}
    per_run = {name: {"mean": curve_mean(curve, results[name].checkpoint), "final": curve[:, -1]}
               for name, curve in curves.items()}
    measured = {f"{name}_expected_{key}": values.mean() for name, rows in per_run.items() for key, values in rows.items()}
    for better, worse in COMPARISONS:
        for key in ("mean", "final"):
            a, b = per_run[better][key], per_run[worse][key]
            label = f"{better}_minus_{worse}_{key}"
            measured[label], measured[f"{label}_low"], measured[f"{label}_high"] = paired_interval(a, b)
            measured[f"{label}_effect"] = cohen_d(a, b)
    for key in ("mean", "final"):
        measured[f"absolute_worst_{key}_effect"] = min(measured[f"joint_minus_absolute_{key}_effect"],
                                                       measured[f"deictic_minus_absolute_{key}_effect"])
    iteration = results["deictic"].checkpoint
    measured.update(speed_comparison(reach_iteration(curves["deictic"], iteration, tolerance),
                                     reach_iteration(curves["joint"], iteration, tolerance)))
    for key in [k for k in measured if np.isnan(measured[k])]:
        measured[key + claims.WHY_UNDECIDABLE] = ("no run-to-run spread or no paired runs to judge by "
                                                  "(fewer than two runs, identical ones, or a curve at its "
                                                  "final value from the start)")
    return measured


def paired_interval(better: np.ndarray, worse: np.ndarray) -> tuple[float, float, float]:
    """The mean of the per-run differences and its 95 % confidence interval (normal; NaN ends
    with one run)."""
    diff = better - worse
    half = 1.96 * diff.std(ddof=1) / np.sqrt(diff.shape[0]) if diff.shape[0] > 1 else np.nan
    return float(diff.mean()), float(diff.mean() - half), float(diff.mean() + half)


def cohen_d(better: np.ndarray, worse: np.ndarray) -> float:
    """Cohen's d: the difference of the means over runs in units of the runs' pooled standard
    deviation (NaN with one run or no spread)."""
    if better.shape[0] < 2:
        return float("nan")
    spread = np.sqrt((better.var(ddof=1) + worse.var(ddof=1)) / 2)
    return float((better.mean() - worse.mean()) / spread) if spread > 0 else float("nan")


def speed_comparison(deictic: np.ndarray, joint: np.ndarray, seed: int = 0) -> dict:
    """Deictic against joint from the paired iterations to reach the level (runs,): the share of
    runs where the deictic context gets there first (ties count half), and the median of the
    per-run ratios deictic / joint with its 95 % bootstrap interval (run pairs resampled)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(joint > 0, deictic / np.where(joint > 0, joint, 1.0), np.nan)
    share = float(np.mean((deictic < joint) + 0.5 * (deictic == joint)))
    if ratio.shape[0] < 2 or np.isnan(ratio).any():
        return {"deictic_earlier_share": share, "deictic_joint_reach_ratio": float(np.median(ratio)),
                "deictic_joint_reach_ratio_low": float("nan"), "deictic_joint_reach_ratio_high": float("nan")}
    draws = np.random.default_rng(seed).integers(0, ratio.shape[0], (BOOTSTRAP_DRAWS, ratio.shape[0]))
    low, high = np.percentile(np.median(ratio[draws], axis=1), [2.5, 97.5])
    return {"deictic_earlier_share": share, "deictic_joint_reach_ratio": float(np.median(ratio)),
            "deictic_joint_reach_ratio_low": float(low), "deictic_joint_reach_ratio_high": float(high)}


def paired_curve(results: dict, better: str, worse: str) -> tuple:
    """(iterations, mean, low, high): the paired difference of two encodings' expected rewards at
    every checkpoint, with its 95 % interval over runs."""
    a, b = expected_curves(results[better]), expected_curves(results[worse])
    rows = np.array([paired_interval(a[:, c], b[:, c]) for c in range(a.shape[1])])
    return results[better].checkpoint, rows[:, 0], rows[:, 1], rows[:, 2]


def encoding_arrays(results: dict) -> dict:
    """Fig. 6's result arrays as one flat dict ('<encoding>_<array>'), as its result file stores them."""
    return {f"{name}_{key}": value for name, res in results.items() for key, value in res.arrays().items()}


def encodings_from_arrays(config: EncodingConfig, arrays: dict) -> dict:
    """The inverse of :func:`encoding_arrays`: encoding name -> result (``config``'s for the encoding)."""
    return {name: SingleGLAResult(config.encoding(name), *(arrays[f"{name}_{key}"] for key in
                                  ("iteration", "reward", "params", "checkpoint", "checkpoint_params")))
            for name in ENCODING_NAMES}


def scaled(runs: int, iterations: int, **settings) -> SingleGLAConfig:
    """The chapter's experiment 1 (with ``settings`` changed) at ``runs`` and ``iterations``,
    with no more points of the learning curve than iterations."""
    return SingleGLAConfig(runs=runs, iterations=iterations, record_points=min(SingleGLAConfig.record_points, iterations),
                           **settings)


def scaled_encodings(runs: int, iterations: int, **settings) -> EncodingConfig:
    """Fig. 6 (with ``settings`` of :class:`EncodingConfig` changed) at ``runs`` and ``iterations``."""
    return EncodingConfig(scaled(runs, iterations), **settings)


def claim_rows(result: SingleGLAResult) -> list[dict]:
    """The Fig. 5 claims (data/chapter/section4.json) with verdicts computed from ``result``."""
    return claims.verdicts(claims.load("single_gla"), measure(result))


def encoding_claim_rows(results: dict) -> list[dict]:
    """The Fig. 6 claims (data/chapter/section4.json) with verdicts computed from ``results``."""
    return claims.verdicts(claims.load("state_encoding"), measure_encodings(results))


FIG5 = register(Experiment(
    "single_gla", SingleGLAConfig, run, scaled, SingleGLAConfig.runs, SingleGLAConfig.iterations, SingleGLAResult,
    claim_rows=lambda result, config: claim_rows(result), figures=("fig5",), to_arrays=SingleGLAResult.arrays))
"""Fig. 5's experiment: experiment 1 with the joint context."""
FIG6 = register(Experiment(
    "state_encoding", EncodingConfig, compare_encodings, scaled_encodings, SingleGLAConfig.runs,
    SingleGLAConfig.iterations, claim_rows=lambda results, config: encoding_claim_rows(results), figures=("fig6",),
    copies=len(ENCODING_NAMES), to_arrays=encoding_arrays, from_arrays=encodings_from_arrays))
"""Fig. 6's experiment: experiment 1 with each context, in Fig. 6's default box."""


# ---- plots (each draws on a given Axes) ----

def plot_regions(ax, region3_reward: str = "move_apart"):
    """Fig. 5a: the three regions of experiment 1 and their rewarded joint actions (A, B), region 3
    read as ``region3_reward``."""
    x = np.linspace(-1.0, 1.0, 401)
    upper = np.clip(x + lineworld.CLOSE_DISTANCE, -1.0, 1.0)
    lower = np.clip(x - lineworld.CLOSE_DISTANCE, -1.0, 1.0)
    ax.fill_between(x, upper, 1.0, color="tab:blue", alpha=0.35, linewidth=0)
    ax.fill_between(x, -1.0, lower, color="tab:orange", alpha=0.35, linewidth=0)
    ax.fill_between(x, lower, upper, color="tab:green", alpha=0.35, linewidth=0)
    ax.text(-0.55, 0.7, "1: (L, L)", ha="center", va="center")
    ax.text(0.55, -0.7, "2: (R, R)", ha="center", va="center")
    label = {"move_apart": "3: move apart", "fixed_joint_action": "3: (L, R)"}[region3_reward]
    ax.text(0.0, 0.0, label, ha="center", va="center", rotation=45)
    _square(ax)


def plot_learned_lines(ax, result: SingleGLAResult, run_index: int, grid: int = 200):
    """Fig. 5b: each agent's learned line (u_L - u_R).x = 0 (joint context) and the most
    probable joint action in each cell of the partition the two lines make."""
    if result.config.context != "joint":
        raise UserError(f"learned lines are drawn in the (x1, x2) plane: they need the joint "
                         f"context, this result used {result.config.context!r}")
    u = result.params[run_index]
    x1, x2 = lineworld.state_grid(grid)
    xs = np.column_stack([x1, x2, np.ones_like(x1)])
    hu = _bounded(u, result.config)
    prefers_left = [(xs @ (hu[agent, 0] - hu[agent, 1])) > 0 for agent in range(2)]
    t = np.linspace(-1.0, 1.0, 401)
    _draw_reference_lines(ax, t, result.config.region3_reward)
    for agent, (name, colour) in enumerate((("A", "tab:red"), ("B", "tab:purple"))):
        w = hu[agent, 0] - hu[agent, 1]
        _draw_line(ax, w, t, colour, f"agent {name}")
    for left_a in (True, False):
        for left_b in (True, False):
            cell = (prefers_left[0] == left_a) & (prefers_left[1] == left_b)
            if cell.mean() > 0.02:  # label cells large enough to hold text
                label = f"({'L' if left_a else 'R'}, {'L' if left_b else 'R'})"
                ax.text(x1[cell].mean(), x2[cell].mean(), label, ha="center", va="center")
    legend_below(ax, ncols=2)
    _square(ax)


B_BEST_LINE_OFFSETS = (-0.5, 0.5)
"""Agent B's best single lines in the joint context are x2 = x1 + c for these c (tied): B's
rewarded action depends only on x2 - x1 (L above 0.5 and in (-0.5, 0), R elsewhere), and a
threshold at either band edge gets all but one band of width 0.5 right (share 25/32; the
exhaustive search of :func:`best_line_reward` finds no better line)."""


REFERENCE_LINES = {
    "move_apart": (((0.0,), "x1 = x2: agent A's ideal line"),
                   (B_BEST_LINE_OFFSETS, "x2 = x1 ± 0.5: agent B's best single lines (tied)")),
    "fixed_joint_action": (((-0.5,), "x2 = x1 - 0.5: agent A's ideal line"),
                           ((0.5,), "x2 = x1 + 0.5: agent B's ideal line")),
}
"""Per reading of region 3, each agent's best single lines x2 = x1 + c (offsets c) and their
label: under 'fixed_joint_action' A plays L where x2 - x1 > -0.5 and B where x2 - x1 > 0.5."""


def _draw_reference_lines(ax, t, region3_reward: str):
    """Where each agent's best single lines lie (:data:`REFERENCE_LINES`)."""
    for (offsets, label), colour, style in zip(REFERENCE_LINES[region3_reward], ("black", "0.4"), ("--", ":")):
        for k, c in enumerate(offsets):
            inside = np.abs(t + c) <= 1
            ax.plot(t[inside], t[inside] + c, color=colour, linestyle=style, linewidth=1.3,
                    label=label if k == 0 else None)


def learned_line(result: SingleGLAResult, run_index: int, agent: int) -> tuple[float, float]:
    """(slope, intercept) of the agent's learned line (h(u_L) - h(u_R)).x = 0 (eq. 14-15) as
    x2 = slope x1 + intercept, for the joint context; the agent prefers L above it when the x2
    weight is positive."""
    if result.config.context != "joint":
        raise UserError(f"learned lines live in the (x1, x2) plane: they need the joint context, "
                         f"this result used {result.config.context!r}")
    hu = _bounded(result.params[run_index, agent], result.config)
    w = hu[0] - hu[1]
    return float(-w[0] / w[1]), float(-w[2] / w[1])


def plot_reward_curves(ax, results: dict):
    """Fig. 6: average feedback over iterations per context encoding, mean and 95 % band over runs."""
    for name, res in results.items():
        plot_mean_band(ax, res.iteration, res.reward, label=name)
    ax.set_xlabel("iteration")
    ax.set_ylabel("average reward")
    legend_below(ax, ncols=3)


def plot_expected_curves(ax, results: dict):
    """Fig. 6 without sampling noise: the expected reward at the checkpoints (:func:`expected_curves`)
    per context encoding over log-scaled iterations, mean and 95 % band over runs."""
    for name, res in results.items():
        after_start = res.checkpoint > 0  # the start has no place on a log axis
        plot_mean_band(ax, res.checkpoint[after_start], expected_curves(res)[:, after_start], label=name)
    ax.set_xscale("log")
    ax.set_xlabel("iteration")
    ax.set_ylabel("expected reward")
    legend_below(ax, ncols=3)


def _bounded(u: np.ndarray, config: SingleGLAConfig) -> np.ndarray:
    """h(u) of eq. 14, the parameters eq. 15 actually uses."""
    clipped = np.clip(u, -config.L, config.L)
    if config.bounding == "clip":
        return clipped
    return np.where(np.abs(u) >= config.L, clipped, 0.0)


def _draw_line(ax, w, t, colour, label):
    """The line w[0] x1 + w[1] x2 + w[2] = 0 inside the square (nothing if it misses it)."""
    if abs(w[1]) >= abs(w[0]) and w[1] != 0:
        x, y = t, -(w[0] * t + w[2]) / w[1]
    elif w[0] != 0:
        x, y = -(w[1] * t + w[2]) / w[0], t
    else:
        return
    inside = (np.abs(x) <= 1) & (np.abs(y) <= 1)
    ax.plot(np.where(inside, x, np.nan), np.where(inside, y, np.nan), color=colour, lw=2, label=label)


def _square(ax):
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x1 (position of agent A)")
    ax.set_ylabel("x2 (position of agent B)")
