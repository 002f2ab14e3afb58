"""The scaling study (beyond the chapter): the Section 5.3 learners on warehouse maps with 2 to 6
agents, to measure the argument of Table 1 and Section 3.1 that the joint learners' tables grow
exponentially in the number of agents while independent learners and 2observe stay linear.

Every map ``warehouse_N.txt`` is the same 5 x 7 warehouse (one one-track aisle to the shared goal,
entered from the right end) with N agents starting along the top and bottom rows, so only the
number of agents changes between the maps. Every learner runs through its registered spec
(:mod:`glamas.learners.registry`), so a new learner joins the study by its name. ``run`` allocates
a learner's tables only when they fit the memory budget (computed from its spec before allocating;
otherwise the learner is skipped at that N and the reason recorded), trains it and keeps
agent-mean learning curves. ``measure`` turns the curves
and the table sizes into per-(method, N) numbers and growth rates fitted over N, from
which the claims of ``data/chapter/scaling.json`` get their verdicts.

The related-work learners of :mod:`glamas.experiments.related_work` join the study in their N-agent
forms: sparse tabular MAQ with pairwise coordination (:mod:`glamas.learners.sparse_maq`)
and CQ-learning observing the nearest other agent (:mod:`glamas.learners.cq`). Besides their local
Q tables they store joint values (sparse MAQ: every pair's joint table; CQ: 4 per marked joint
state, measured) and CQ its reward windows; all of it counts in their values per run.
"""

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from glamas import checks, memory, parallel
from glamas import claims as chapter
from glamas.curves import convergence_episode, final
from glamas.errors import UserError
from glamas.experiments.registry import Experiment, register
from glamas.gridworld import GridMap, load_map
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.learners.settings import LearnerSettings, LearningSettings, RelatedSettings, combine
from glamas.learners.spec import BYTES_PER_VALUE, Learner
from glamas.paths import MAPS, RESULTS
from glamas.plotting import BAND_DRAWS, learner_style, legend_right, plot_mean_band


@dataclass(frozen=True)
class Variant:
    """A method of the study that is a registered learner with one setting changed."""

    learner: str
    """The learner it runs."""
    label: str
    """Its name in figures and tables."""


VARIANTS = {"two_observe_rule": Variant("two_observe", "2observe, fixed rule")}
"""The study's variants: 'two_observe_rule' is a diagnostic outside the chapter, 2observe with its
GLAs replaced by the rule "coordinate when delta < ScalingConfig.rule_distance"."""
CHAPTER_METHODS = registry.family("chapter") + tuple(VARIANTS)
RELATED_METHODS = registry.family("related")
METHODS = CHAPTER_METHODS + RELATED_METHODS
"""The study's methods by default."""


def known_methods() -> tuple:
    """What a ScalingConfig can train, and what a ScalingResult's codes index: METHODS, then every
    other registered learner."""
    return METHODS + registry.family("other")
MAX_AGENTS = 9
"""The map format numbers agents 1-9."""
MACHINE_MEMORY_GIB = 24
"""A workstation's memory, 24 GiB, drawn for scale: one run's tables beyond it fit no such machine."""
METRICS = ("steps", "reward", "collisions", "coordinations", "capped")
"""What the study keeps of each episode log (glamas.learners.episode.METRICS, agent means)."""


@dataclass(frozen=True)
class ScalingConfig(RelatedSettings):
    """Settings of the scaling study: the learners' settings (``learning`` and the related-work
    learners' own, :class:`glamas.learners.settings.RelatedSettings`), the maps and the schedule."""

    agents: tuple = (2, 3, 4, 5, 6)
    """Numbers of agents N; map ``map_pattern.format(n=N)`` is used for each."""
    map_pattern: str = "warehouse_{n}.txt"
    """Map file name (in data/maps, or a path) with ``{n}`` for the number of agents."""
    methods: tuple = METHODS
    """Learners to train: distinct names of :func:`known_methods` (the registered learners and VARIANTS)."""
    rule_distance: int = 3
    """The fixed rule's distance for 'two_observe_rule' (3: delta at most 2, where every collision
    of two agents comes from)."""
    episodes: int = 20_000
    """Episodes per run (each until every agent is in the goal, or the step cap)."""
    runs: int = 10
    """Independent runs per (method, N)."""
    bin_size: int = 100
    """Episodes averaged into one point of the learning curves; must divide ``episodes``."""
    memory_budget_gib: float = 4.0
    """Memory the Q tables of all runs of one (method, N) may take, in GiB (a sixth of a 24 GiB
    workstation, leaving room for other work); a learner whose tables would need more is skipped at that N."""
    learning: LearningSettings = field(default_factory=lambda: LearningSettings(max_steps=1000))
    """Q-learning, GLA and collision settings (the Section 5.3 experiment's defaults, with a
    1000-step cap per episode: with three or more agents an agent often gets trapped early on, see
    the notebook)."""

    def __post_init__(self):
        super().__post_init__()
        checks.whole_numbers(self, {"episodes": 1, "runs": 1, "bin_size": 1})
        if self.episodes % self.bin_size:
            raise UserError(f"bin_size ({self.bin_size}) must divide episodes ({self.episodes}); "
                             "choose a bin size such as 100 that divides the episode count")
        agents = tuple(self.agents) if isinstance(self.agents, (tuple, list)) else None
        if (not agents or len(set(agents)) != len(agents)
                or not all(isinstance(n, int) and 2 <= n <= MAX_AGENTS for n in agents)):
            raise UserError(f"agents must be distinct whole numbers from 2 to {MAX_AGENTS}, got {self.agents!r}")
        object.__setattr__(self, "agents", tuple(sorted(agents)))
        methods = tuple(self.methods) if isinstance(self.methods, (tuple, list)) else ()
        if not methods or len(set(methods)) != len(methods) or not set(methods) <= set(known_methods()):
            raise UserError(f"methods must be distinct names from {known_methods()}, got {self.methods!r}")
        object.__setattr__(self, "methods", methods)
        if isinstance(self.rule_distance, bool) or not isinstance(self.rule_distance, int) or self.rule_distance < 0:
            raise UserError(f"rule_distance must be a whole number >= 0, got {self.rule_distance!r}")
        if not (isinstance(self.memory_budget_gib, (int, float)) and self.memory_budget_gib > 0):
            raise UserError(f"memory_budget_gib must be a number > 0, got {self.memory_budget_gib!r}")
        if "{n}" not in self.map_pattern:
            raise UserError(f"map_pattern must contain '{{n}}' for the number of agents, got {self.map_pattern!r}")
        for n in self.agents:
            gridmap = self.gridmap(n)
            if gridmap.n_agents != n:
                raise UserError(f"map {gridmap.name!r} has {gridmap.n_agents} agents, the study expects {n}: "
                                 f"give each map file exactly N starts 1..N")

    def gridmap(self, n: int) -> GridMap:
        """The map with ``n`` agents: ``map_pattern`` as a path, or as a name in data/maps."""
        path = Path(self.map_pattern.format(n=n))
        return load_map(path if path.is_file() or path.parent != Path(".") else MAPS / path)

    def memory_bytes(self) -> int:
        """Bytes of the largest runs held at once and of every log. A run's tables live in the
        worker that fills it, one run per worker at a time: at most the runs of the largest
        learner that fits the budget at once, whatever the number of workers."""
        budget = self.memory_budget_gib * 2 ** 30
        needs = [memory_needed(self, method, self.gridmap(n)) for n in self.agents for method in self.methods]
        largest = max((need for need in needs if need <= budget), default=0)
        logs = len(self.methods) * len(self.agents) * self.runs * self.n_bins * len(METRICS)
        return largest * memory.WORKING_COPIES + logs * memory.BYTES_PER_VALUE

    @property
    def n_bins(self) -> int:
        return self.episodes // self.bin_size

    def schedule(self) -> ep.Schedule:
        """The runs' schedule: ``bin_size`` episodes per block of the learning curves."""
        return ep.Schedule(self.episodes, ep.uniform_edges(self.episodes, self.bin_size), self.learning.max_steps)

    def settings(self, method: str) -> LearnerSettings:
        """The settings ``method`` runs with: ``learning`` and the related-work learners' own, and
        for the fixed-rule variant its rule distance."""
        settings = combine(self.learning, self)
        return replace(settings, rule_distance=self.rule_distance) if method in VARIANTS else settings


def learner_of(method: str) -> Learner:
    """The registered learner a method runs (a variant's learner, or the method itself)."""
    return registry.get(VARIANTS[method].learner if method in VARIANTS else method)


def label(method: str) -> str:
    """A method's name in figures and tables (its N-agent form's, where that differs)."""
    return VARIANTS[method].label if method in VARIANTS else (learner_of(method).n_agent_label or registry.label(method))


def memory_needed(config: ScalingConfig, method: str, gridmap: GridMap) -> int:
    """Bytes the tables of all of ``config.runs`` runs on ``gridmap`` take together (CQ: with its marks)."""
    return config.runs * learner_of(method).bytes_per_run(config.settings(method), gridmap)


@dataclass(frozen=True)
class ScalingResult:
    """Agent-mean learning curves and table sizes for every (method, N), all arrays."""

    config: ScalingConfig
    """The configuration that produced the arrays."""
    methods: np.ndarray
    """int (methods,): index into :func:`known_methods` of each method, in the order of the other arrays."""
    agents: np.ndarray
    """int (agents,): the numbers of agents N."""
    ran: np.ndarray
    """bool (methods, agents): whether the learner ran (False: its tables exceed the budget)."""
    table_shapes: np.ndarray
    """int (methods, agents, 3): (tables, states, actions) of the Q tables per run, from the
    learner's spec: the tables its runs fill, or would fill where it was skipped."""
    gla_parameters: np.ndarray
    """int (methods, agents): GLA parameters per run (2observe: 4 per agent)."""
    joint_entries: np.ndarray
    """float (methods, agents): joint values per run beyond the Q tables of ``table_shapes``:
    sparse MAQ every pair's joint table, CQ 4 per marked joint state (mean over runs; where skipped,
    its room for every joint state); 0 for the chapter's learners."""
    reward_samples: np.ndarray
    """int (methods, agents): immediate rewards kept per run for CQ's test (0 for the others)."""
    bytes_needed: np.ndarray
    """int (methods, agents): bytes of Q tables for all runs together."""
    log: np.ndarray
    """(methods, agents, runs, bins, METRICS): block means of steps to goal and reward (means
    over the agents), collisions, coordinations, capped episodes; NaN where skipped."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block."""

    def names(self) -> list[str]:
        known = known_methods()
        return [known[k] for k in self.methods]

    def curves(self, method: str, n: int, metric: str) -> np.ndarray:
        """(runs, bins) block means of one of METRICS for one method and number of agents."""
        return self.log[self.names().index(method), list(self.agents).index(n), :, :, METRICS.index(metric)]

    def q_entries(self) -> np.ndarray:
        """(methods, agents): Q-table entries per run (all agents' tables together)."""
        return self.table_shapes.prod(axis=2, dtype=float)  # exact below 2^53; int64 would wrap for many agents

    def parameters(self) -> np.ndarray:
        """(methods, agents): values stored per run: Q entries, GLA parameters, joint values and
        reward samples."""
        return self.q_entries() + self.gla_parameters + self.joint_entries + self.reward_samples


def seed_of(seed: int, method: str, n_agents: int) -> int:
    """Master seed of one (method, N) (:func:`glamas.learners.registry.master_seed` with the key
    ``16 seed + N``): distinct for every (seed, method, N), and a method gets the same streams at a
    given N whatever else is trained with it."""
    family = learner_of(method).family
    members = RELATED_METHODS if family == "related" else CHAPTER_METHODS
    return registry.master_seed(seed * 16 + n_agents, members, method, family)


def run(config: ScalingConfig = ScalingConfig(), seed: int = 0, workers=None, progress=None) -> ScalingResult:
    """Train every method at every N that fits the memory budget (``config.runs`` runs each), all
    runs on one pool of workers (:func:`glamas.parallel.run_many`). Each run's Q tables stay in the
    worker that fills them (the study keeps learning curves and table sizes), so memory holds
    the tables of the runs in progress only."""
    m, a = len(config.methods), len(config.agents)
    ran = np.zeros((m, a), dtype=bool)
    shapes = np.zeros((m, a, 3), dtype=np.int64)
    glas = np.zeros((m, a), dtype=np.int64)
    joints = np.zeros((m, a))
    samples = np.zeros((m, a), dtype=np.int64)
    needed = np.zeros((m, a), dtype=np.int64)
    log = np.full((m, a, config.runs, config.n_bins, len(METRICS)), np.nan)
    budget = config.memory_budget_gib * 2 ** 30
    schedule = config.schedule()
    trainings = {}
    for j, n in enumerate(config.agents):
        gridmap = config.gridmap(n)
        for k, method in enumerate(config.methods):
            learner, settings = learner_of(method), config.settings(method)
            shapes[k, j] = [_as_int64(size) for size in learner.table_shape(gridmap.n_cells, n)]
            glas[k, j] = learner.gla_parameters(settings, gridmap)
            joints[k, j], samples[k, j] = learner.joint_room(settings, gridmap), learner.reward_samples(settings, gridmap)
            needed[k, j] = _as_int64(memory_needed(config, method, gridmap))
            if needed[k, j] <= budget:
                batch, outputs = spec.batch(learner, settings, gridmap, schedule, config.runs, seed_of(seed, method, n),
                                            keep_q=False)
                trainings[k, j] = learner, settings, gridmap, batch, outputs
    # One run per job: runs differ widely in length (some spend most episodes at the step cap),
    # and small jobs keep every worker busy until the last runs are done.
    parallel.run_many([batch for *_, batch, _ in trainings.values()], workers=workers, progress=progress, chunk=1)
    for (k, j), (learner, settings, gridmap, _, outputs) in trainings.items():
        joints[k, j] = learner.joint_learned(outputs, settings, gridmap).mean()
        ran[k, j] = True
        log[k, j] = agent_means(outputs["log"])
    codes = np.array([known_methods().index(name) for name in config.methods], dtype=np.int64)
    return ScalingResult(config=config, methods=codes, agents=np.array(config.agents, dtype=np.int64), ran=ran,
                         table_shapes=shapes, gla_parameters=glas, joint_entries=joints, reward_samples=samples,
                         bytes_needed=needed, log=log, episodes=schedule.edges[1:])


def _as_int64(count: int) -> int:
    """``count`` as an int64 array can hold it: at most 2^63 - 1. Only the tables of many agents
    count beyond (an MMDP learner's of 9 agents), and the study skips those, far over any budget."""
    return min(int(count), np.iinfo(np.int64).max)


def load(config: ScalingConfig = ScalingConfig(), seed: int = 0, results_dir: Path = RESULTS) -> ScalingResult:
    """The committed (or ``results_dir``'s) result of ``config`` and ``seed``, its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


def agent_means(log: np.ndarray) -> np.ndarray:
    """(runs, bins, METRICS) from an N-agent log (glamas.learners.episode layout)."""
    return np.stack([ep.metric(log, name) for name in METRICS], axis=-1)


# --- measurements and claims -----------------------------------------------------------------

def growth(agents, values) -> dict:
    """Least-squares growth of ``values`` over the numbers of agents: the factor per added agent
    (exp of the slope of log value against N: exponential growth has a constant factor) and the
    slope of log value against log N (polynomial growth N^k has slope k); NaN below two points."""
    agents, values = np.asarray(agents, float), np.asarray(values, float)
    if agents.size < 2:
        return {"factor_per_agent": math.nan, "loglog_slope": math.nan}
    slope = np.polyfit(agents, np.log(values), 1)[0]
    loglog = np.polyfit(np.log(agents), np.log(values), 1)[0]
    return {"factor_per_agent": float(np.exp(slope)), "loglog_slope": float(loglog)}


def measure(result: ScalingResult) -> dict:
    """Per (method, N): parameters, final steps, reward, collisions, coordinations, convergence
    episode; per method: growth fitted over the N it ran at, the largest such N; and the
    comparisons the claims of data/chapter/scaling.json are about."""
    m = {}
    params = result.parameters()
    for k, method in enumerate(result.names()):
        ran_at = [int(n) for n, ok in zip(result.agents, result.ran[k]) if ok]
        for j, n in enumerate(result.agents):
            m[f"parameters_{method}_{n}"] = float(params[k, j])
            if not result.ran[k, j]:
                continue
            m[f"steps_{method}_{n}"] = final(result.curves(method, n, "steps"), result.episodes)
            m[f"reward_{method}_{n}"] = final(result.curves(method, n, "reward"), result.episodes)
            m[f"collisions_{method}_{n}"] = final(result.curves(method, n, "collisions"), result.episodes)
            m[f"coordinations_{method}_{n}"] = final(result.curves(method, n, "coordinations"), result.episodes)
            m[f"capped_{method}_{n}"] = final(result.curves(method, n, "capped"), result.episodes)
            m[f"convergence_{method}_{n}"] = convergence_episode(result.curves(method, n, "steps"), result.episodes)
            capped = result.curves(method, n, "capped")
            m[f"capped_runs_{method}_{n}"] = float(sum(final(run[None], result.episodes) > 0 for run in capped))
        fit = growth(ran_at, [params[k, list(result.agents).index(n)] for n in ran_at])
        m[f"growth_factor_{method}"] = fit["factor_per_agent"]
        m[f"loglog_slope_{method}"] = fit["loglog_slope"]
        m[f"largest_n_{method}"] = float(max(ran_at)) if ran_at else 0.0
    names = result.names()
    if "independent" in names:
        m["loglog_slope_independent_off_1"] = abs(m["loglog_slope_independent"] - 1.0)
    if {"independent", "two_observe"} <= set(names):
        ratio = params[names.index("two_observe")] / params[names.index("independent")]
        m["parameters_two_observe_over_independent_max"] = float(ratio.max())
    if {"mmdp", "two_observe"} <= set(names):
        both = [n for j, n in enumerate(result.agents)
                if result.ran[names.index("mmdp"), j] and result.ran[names.index("two_observe"), j]]
        m["collisions_two_observe_minus_mmdp_max"] = max(
            (m[f"collisions_two_observe_{n}"] - m[f"collisions_mmdp_{n}"] for n in both), default=math.nan)
    for method in set(RELATED_METHODS) & set(names):
        k = names.index(method)
        ran_at = [n for n, ok in zip(result.agents, result.ran[k]) if ok]
        m[f"collisions_{method}_max"] = max((m[f"collisions_{method}_{n}"] for n in ran_at), default=math.nan)
    if {"cq", "two_observe"} <= set(names):
        ratio = params[names.index("cq")] / params[names.index("two_observe")]
        m["parameters_cq_over_two_observe_min"] = float(ratio.min())
    return m


def claim_rows(result: ScalingResult) -> list[dict]:
    """The Table 1 / Section 3.1 claims of data/chapter/scaling.json with computed verdicts."""
    return chapter.verdicts(chapter.load("scaling"), measure(result))


def size_table(result: ScalingResult) -> str:
    """Q tables per run (tables x states x actions), the related-work learners' joint values and
    reward samples per run, all values stored per run and memory for all runs, per method and N;
    skipped learners marked with the memory they would need."""
    lines = [f"{'method':22s} {'N':>2s} {'tables x states x actions':>27s} {'joint':>8s} {'samples':>8s} "
             f"{'parameters/run':>15s} {'GiB (all runs)':>14s}  status"]
    params = result.parameters()
    for k, method in enumerate(result.names()):
        for j, n in enumerate(result.agents):
            t, s, a = result.table_shapes[k, j]
            status = "ran" if result.ran[k, j] else "skipped: exceeds the memory budget"
            lines.append(f"{label(method):22s} {n:2d} {f'{t} x {s} x {a}':>27s} {result.joint_entries[k, j]:8.4g} "
                         f"{result.reward_samples[k, j]:8d} {params[k, j]:15.3g} "
                         f"{result.bytes_needed[k, j] / 2 ** 30:14.3g}  {status}")
    return "\n".join(lines)


def performance_table(result: ScalingResult) -> str:
    """Final values (last 10 % of the episodes, mean over runs and agents; capped: the share of
    those episodes that hit the step cap) and the episode after which the mean steps stay within
    5 % of their final value, per method and N that ran."""
    m = measure(result)
    lines = [f"{'method':22s} {'N':>2s} {'steps':>7s} {'reward':>7s} {'collisions':>10s} "
             f"{'coordinations':>13s} {'converged by':>12s} {'capped %':>8s}"]
    for k, method in enumerate(result.names()):
        for j, n in enumerate(result.agents):
            if not result.ran[k, j]:
                continue
            lines.append(f"{label(method):22s} {n:2d} {m[f'steps_{method}_{n}']:7.2f} {m[f'reward_{method}_{n}']:7.1f} "
                         f"{m[f'collisions_{method}_{n}']:10.2f} {m[f'coordinations_{method}_{n}']:13.2f} "
                         f"{m[f'convergence_{method}_{n}']:12.0f} {100 * m[f'capped_{method}_{n}']:8.1f}")
    return "\n".join(lines)


PIVOT_METRICS = {"steps": "{:.1f}", "reward": "{:.1f}", "collisions": "{:.2f}", "coordinations": "{:.1f}",
                 "capped": "{:.1%}", "convergence": "{:.0f}", "capped_runs": "{:.0f}"}
"""What :func:`pivot_table` shows: the per-(method, N) measurements of :func:`measure` and their format."""


def pivot_table(result: ScalingResult, metric: str) -> str:
    """One final measurement per method (rows) and N (columns), '-' where the method did not run;
    'capped_runs' counts the runs in which some of the final 10 % of the episodes hit the step cap."""
    if metric not in PIVOT_METRICS:
        raise UserError(f"metric must be one of {sorted(PIVOT_METRICS)}, got {metric!r}")
    m = measure(result)
    lines = [f"{metric:22s}" + "".join(f"{f'N = {n}':>9s}" for n in result.agents)]
    for k, method in enumerate(result.names()):
        cells = [PIVOT_METRICS[metric].format(m[f"{metric}_{method}_{n}"]) if ok else "-"
                 for n, ok in zip(result.agents, result.ran[k])]
        lines.append(f"{label(method):22s}" + "".join(f"{cell:>9s}" for cell in cells))
    return "\n".join(lines)


def growth_table(result: ScalingResult) -> str:
    """Per method: growth of the learned values per run, fitted over the N it ran at."""
    m = measure(result)
    lines = [f"{'method':22s} {'ran for N':>10s} {'factor per agent':>16s} {'log-log slope':>13s}"]
    for k, method in enumerate(result.names()):
        ran_at = [int(n) for n, ok in zip(result.agents, result.ran[k]) if ok]
        span = f"{min(ran_at)}-{max(ran_at)}" if ran_at else "none"
        lines.append(f"{label(method):22s} {span:>10s} {m[f'growth_factor_{method}']:16.3g} "
                     f"{m[f'loglog_slope_{method}']:13.2f}")
    return "\n".join(lines)


# --- plots: each draws on a given Axes -------------------------------------------------------

COINCIDE = 1.1
"""Methods whose stored values stay within this factor of each other at every N draw on one line
on a log axis: :func:`plot_sizes` sets them side by side and says so."""
DODGE = 0.1
"""Horizontal distance, in agents, between methods drawn side by side at one N."""


def plot_sizes(ax, result: ScalingResult, config: ScalingConfig | None = None, legend: bool = True):
    """Values learned per run (Q entries + GLA parameters) against N (log scale): filled markers
    where the learner ran, open markers where its tables were only computed (skipped), with the
    24 GiB workstation's memory for one run and the study's memory budget if ``config`` is given.
    Methods that store nearly the same (within COINCIDE) are drawn side by side, with a note."""
    params = result.parameters()
    shifts, groups = _coinciding_shifts(params)
    for k, method in enumerate(result.names()):
        x = result.agents + shifts[k]
        ax.plot(x, params[k], "-", **learner_style(method))
        ax.plot([], [], "-", label=label(method), **learner_style(method, marker=True))  # the legend's entry
        ok = result.ran[k]
        ax.plot(x[ok], params[k, ok], linestyle="none", **learner_style(method, marker=True))
        ax.plot(x[~ok], params[k, ~ok], linestyle="none", mfc="none", **learner_style(method, marker=True))
    ax.plot([], [], "o", color="0.4", mfc="none", linestyle="none", label="open: skipped (tables computed, not run)")
    ax.axhline(MACHINE_MEMORY_GIB * 2 ** 30 / BYTES_PER_VALUE, color="black", linestyle=":", linewidth=1,
               label=f"a {MACHINE_MEMORY_GIB} GiB workstation, one run")
    if config is not None:
        entries = config.memory_budget_gib * 2 ** 30 / BYTES_PER_VALUE / config.runs
        ax.axhline(entries, color="black", linestyle="--", linewidth=1,
                   label=f"memory budget ({config.memory_budget_gib:g} GiB for {config.runs} runs)")
    ax.set_yscale("log")
    ax.set_xticks(result.agents)
    ax.set_xlabel("agents N")
    ax.set_ylabel("values stored per run")
    if groups:
        names = "; ".join(" = ".join(label(result.names()[k]) for k in group) for group in groups)
        ax.set_title(f"drawn side by side, as they store within {COINCIDE - 1:.0%} of each other at every N:\n{names}",
                     fontsize="small")
    if legend:
        legend_right(ax)


def _coinciding_shifts(params: np.ndarray) -> tuple[np.ndarray, list[list[int]]]:
    """Horizontal shifts (methods,) that set apart the methods storing within COINCIDE of each
    other at every N, and those groups of method indices (groups of two or more)."""
    groups: list[list[int]] = []
    for k in range(params.shape[0]):
        for group in groups:
            if np.all(np.maximum(params[k], params[group[0]]) <= COINCIDE * np.minimum(params[k], params[group[0]])):
                group.append(k)
                break
        else:
            groups.append([k])
    shifts = np.zeros(params.shape[0])
    for group in groups:
        for i, k in enumerate(group):
            shifts[k] = DODGE * (i - (len(group) - 1) / 2)
    return shifts, [group for group in groups if len(group) > 1]


_METRIC_LABELS = {"steps": "final steps to goal (agent mean)", "reward": "final reward (agent mean)",
                  "collisions": "final collisions per episode", "coordinations": "final coordinations per episode",
                  "convergence": "episodes until within 5 % of final steps"}


def plot_final(ax, result: ScalingResult, metric: str, legend: bool = True):
    """One final measurement ('steps', 'reward', 'collisions', 'coordinations' or 'convergence')
    against N for every method, at the N each method ran at: the value of :func:`measure` with its
    95 % bootstrap interval over runs, the methods side by side at each N. Convergence: a method
    still outside 5 % of its final steps in the last block never settled; it is drawn as an open
    triangle above the end of the runs, not as a number of episodes."""
    if metric not in _METRIC_LABELS:
        raise UserError(f"metric must be one of {sorted(_METRIC_LABELS)}, got {metric!r}")
    names = result.names()
    never_settled = False
    for k, method in enumerate(names):
        ns = np.array([int(n) for n, ok in zip(result.agents, result.ran[k]) if ok], dtype=float)
        if not ns.size:
            continue
        value, low, high = np.array([_final_with_band(result, method, int(n), metric) for n in ns]).T
        x = ns + DODGE * 0.5 * (k - (len(names) - 1) / 2)
        unsettled = (value >= result.episodes[-1]) if metric == "convergence" else np.zeros(ns.size, bool)
        shown = np.where(unsettled, np.nan, value)
        # a statistic that is not a mean (the convergence episode) can lie outside its percentile
        # interval: the bar then ends at the value
        below = np.fmax(shown - np.where(unsettled, np.nan, low), 0.0)
        above = np.fmax(np.where(unsettled, np.nan, high) - shown, 0.0)
        ax.errorbar(x, shown, yerr=[below, above],
                    capsize=2, linewidth=1.2, label=label(method), **learner_style(method, marker=True))
        if unsettled.any():
            never_settled = True
            ax.plot(x[unsettled], np.full(unsettled.sum(), result.episodes[-1] * 1.05), linestyle="none",
                    mfc="none", markersize=7, **{**learner_style(method), "marker": "^"})
    if never_settled:
        _mark_never_settled(ax, result.episodes[-1])
    ax.set_xticks(result.agents)
    ax.set_xlabel("agents N")
    ax.set_ylabel(_METRIC_LABELS[metric])
    if legend:
        legend_right(ax)


def _mark_never_settled(ax, last: int):
    """The end of the runs as a line, and what the open triangles above it mean."""
    ax.axhline(last, color="black", linestyle=":", linewidth=1)
    ax.set_ylim(top=last * 1.18)
    ax.text(0.01, last * 1.13, "open triangles: never settled within 5 % (not a number of episodes)",
            transform=ax.get_yaxis_transform(), fontsize="x-small", va="center")


def _final_with_band(result: ScalingResult, method: str, n: int, metric: str) -> tuple[float, float, float]:
    """The final value of ``metric`` (as :func:`measure`) and its 95 % bootstrap interval: runs
    resampled with replacement, the statistic recomputed from each resample's mean curve."""
    curves = result.curves(method, n, "steps" if metric == "convergence" else metric)
    statistic = convergence_episode if metric == "convergence" else final
    draws = np.random.default_rng(0).integers(0, curves.shape[0], (BAND_DRAWS, curves.shape[0]))
    values = [statistic(curves[pick], result.episodes) for pick in draws]
    low, high = np.percentile(values, [2.5, 97.5])
    return statistic(curves, result.episodes), float(low), float(high)


CURVE_LABELS = {"steps": "steps to goal (agent mean)", "reward": "reward (agent mean)",
                "collisions": "collisions per episode", "coordinations": "coordinations per episode",
                "capped": "capped episodes"}
"""The y axis of :func:`plot_curves` for each of METRICS."""


def plot_curves(ax, result: ScalingResult, n: int, metric: str = "steps", legend: bool = True):
    """Learning curves (mean and 95 % band over runs) of every method that ran with ``n`` agents."""
    if n not in result.agents:
        raise UserError(f"no results for N = {n}; the study has N in {result.agents.tolist()}")
    j = list(result.agents).index(n)
    for k, method in enumerate(result.names()):
        if result.ran[k, j]:
            plot_mean_band(ax, result.episodes, result.curves(method, n, metric), label(method),
                           **learner_style(method))
    ax.set_xscale("log")
    ax.set_xlabel("episode")
    ax.set_ylabel(f"{CURVE_LABELS[metric]}, N = {n}")
    if legend:
        legend_right(ax)


# --- the experiment of the figure scripts (paper_figures/scaling_*.py) --------------------------

def scaled(runs: int, episodes: int) -> ScalingConfig:
    """The study at ``runs`` and ``episodes``, in blocks that divide the episodes."""
    return ScalingConfig(runs=runs, episodes=episodes, bin_size=math.gcd(episodes, ScalingConfig.bin_size))


EXPERIMENT = register(Experiment("scaling", ScalingConfig, run, scaled, ScalingConfig.runs, ScalingConfig.episodes,
                                 ScalingResult, claim_rows=lambda result, config: claim_rows(result),
                                 figures=("scaling_performance", "scaling_sizes"), chapter=False))
"""The scaling study (its result file is shared by the scaling_* figure scripts)."""
