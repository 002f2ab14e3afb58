"""What a result of the scaling study says: per (method, N) the values stored and the final
performance, per method the growth of the stored values fitted over N (:func:`measure`), from
which the claims of ``data/chapter/scaling.json`` get their verdicts, and the notebook's tables."""

import math

import numpy as np

from glamas import claims as chapter, training
from glamas import portable
from glamas.curves import BAND_DRAWS, convergence_episode, convergence_episodes, final, final_by_run, ratio, resampled_means
from glamas.errors import UserError
from glamas.experiments.gridworld.analysis import COMPLETION
from glamas.experiments.scaling.experiment import RELATED_METHODS, ScalingResult, label
from glamas.gridworld import prioritized
from glamas.tables import Table


def growth(agents, values) -> dict:
    """Least-squares growth of ``values`` over the numbers of agents: the factor per added agent
    (exp of the slope of log value against N: exponential growth has a constant factor) and the
    slope of log value against log N (polynomial growth N^k has slope k); NaN below two points."""
    agents, values = np.asarray(agents, float), np.asarray(values, float)
    if agents.size < 2:
        return {"factor_per_agent": math.nan, "loglog_slope": math.nan}
    slope = portable.line_slope(agents, portable.log(values))
    loglog = portable.line_slope(portable.log(agents), portable.log(values))
    return {"factor_per_agent": float(portable.exp(np.float64(slope))), "loglog_slope": loglog}


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
            m.update(evaluation_measures(result, method, n))
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
        for prefix in ("", "greedy_solution_"):
            m[f"{prefix}collisions_two_observe_minus_mmdp_max"] = max(
                (m[f"{prefix}collisions_two_observe_{n}"] - m[f"{prefix}collisions_mmdp_{n}"] for n in both),
                default=math.nan)
    for method in set(RELATED_METHODS) & set(names):
        k = names.index(method)
        ran_at = [n for n, ok in zip(result.agents, result.ran[k]) if ok]
        for prefix in ("", "greedy_solution_"):
            m[f"{prefix}collisions_{method}_max"] = max((m[f"{prefix}collisions_{method}_{n}"] for n in ran_at),
                                                        default=math.nan)
    if {"cq", "two_observe"} <= set(names):
        ratio = params[names.index("cq")] / params[names.index("two_observe")]
        m["parameters_cq_over_two_observe_min"] = float(ratio.min())
    return m


def evaluation_measures(result: ScalingResult, method: str, n: int) -> dict:
    """What ``method`` learned with ``n`` agents, evaluated with learning off (as
    :func:`glamas.experiments.gridworld.analysis.evaluation_measures`, means over runs): the greedy
    policy's steps, reward, collisions and completion, the collisions per episode of a greedy
    policy that completes (infinite for one that does not), and collisions per perturbation (the
    collisions a random action adds to a greedy policy that completes; NaN for one that does not)."""
    m = {f"greedy_{metric}_{method}_{n}": float(result.evaluation(method, n, metric).mean())
         for metric in ("steps", "reward", "collisions", "coordinations", "completion")}
    m[f"exploring_collisions_{method}_{n}"] = float(result.evaluation(method, n, "collisions", "exploring").mean())
    completed = m[f"greedy_completion_{method}_{n}"] >= COMPLETION
    m[f"greedy_solution_collisions_{method}_{n}"] = m[f"greedy_collisions_{method}_{n}"] if completed else math.inf
    perturbed = training.EVALUATIONS.index("perturbed")
    exploit = training.evaluation_of(1, result.config.q, result.config.gridmap(n)).exploits[perturbed]
    steps, collisions = (result.evaluation(method, n, metric, "perturbed") for metric in ("steps", "collisions"))
    extra = float((collisions - result.evaluation(method, n, "collisions")).sum())
    m[f"collisions_per_perturbation_{method}_{n}"] = (ratio(extra, (1.0 - exploit) * n * float(steps.sum()))
                                                      if completed else math.nan)
    return m


def claim_rows(result: ScalingResult) -> list[dict]:
    """The Table 1 / Section 3.1 claims of data/chapter/scaling.json with computed verdicts."""
    return chapter.verdicts(chapter.load("scaling"), measure(result))


def _label_width(result: ScalingResult) -> int:
    """The width of the tables' first column: the longest label of the result's methods."""
    return max(22, *(len(label(method)) for method in result.names()))


def size_table(result: ScalingResult) -> str:
    """Q tables per run (tables x states x actions), the related-work learners' joint values and
    reward samples per run, all values stored per run and memory for all runs, per method and N;
    skipped learners marked with the memory they would need."""
    w = _label_width(result)
    lines = [f"{'method':{w}s} {'N':>2s} {'tables x states x actions':>27s} {'joint':>8s} {'samples':>8s} "
             f"{'parameters/run':>15s} {'GiB (all runs)':>14s}  status"]
    params = result.parameters()
    for k, method in enumerate(result.names()):
        for j, n in enumerate(result.agents):
            t, s, a = (_count(size) for size in result.shape(method, n))
            status = "ran" if result.ran[k, j] else "skipped: exceeds the memory budget"
            lines.append(f"{label(method):{w}s} {n:2d} {f'{t} x {s} x {a}':>27s} {result.joint_entries[k, j]:8.4g} "
                         f"{result.reward_samples[k, j]:8d} {params[k, j]:15.3g} "
                         f"{result.memory_needed(method, n) / 2 ** 30:14.3g}  {status}")
    return "\n".join(lines)


def _count(size: int) -> str:
    """A table's dimension: in full up to a million, else in three digits."""
    return str(size) if size < 10 ** 6 else f"{float(size):.3g}"


def performance_table(result: ScalingResult) -> str:
    """Final values (last 10 % of the episodes, mean over runs and agents; capped: the share of
    those episodes that hit the step cap) and the episode after which the mean steps stay within
    5 % of their final value, per method and N that ran."""
    m, w = measure(result), _label_width(result)
    lines = [f"{'method':{w}s} {'N':>2s} {'steps':>7s} {'reward':>7s} {'collisions':>10s} "
             f"{'coordinations':>13s} {'converged by':>12s} {'capped %':>8s}"]
    for k, method in enumerate(result.names()):
        for j, n in enumerate(result.agents):
            if not result.ran[k, j]:
                continue
            lines.append(f"{label(method):{w}s} {n:2d} {m[f'steps_{method}_{n}']:7.2f} {m[f'reward_{method}_{n}']:7.1f} "
                         f"{m[f'collisions_{method}_{n}']:10.2f} {m[f'coordinations_{method}_{n}']:13.2f} "
                         f"{m[f'convergence_{method}_{n}']:12.0f} {100 * m[f'capped_{method}_{n}']:8.1f}")
    return "\n".join(lines)


PIVOT_METRICS = {"steps": "{:.1f}", "reward": "{:.1f}", "collisions": "{:.2f}", "coordinations": "{:.1f}",
                 "capped": "{:.1%}", "convergence": "{:.0f}", "capped_runs": "{:.0f}",
                 "greedy_completion": "{:.0%}", "greedy_collisions": "{:.2f}", "greedy_solution_collisions": "{:.2f}"}
"""What :func:`pivot_table` shows: the per-(method, N) measurements of :func:`measure` and their format
(``greedy_*``: the greedy policy after training, :func:`evaluation_measures`)."""


def pivot_table(result: ScalingResult, metric: str) -> str:
    """One final measurement per method (rows) and N (columns), '-' where the method did not run,
    'no solution' where its greedy policy does not complete (an infinite measurement);
    'capped_runs' counts the runs in which some of the final 10 % of the episodes hit the step cap."""
    if metric not in PIVOT_METRICS:
        raise UserError(f"metric must be one of {sorted(PIVOT_METRICS)}, got {metric!r}")
    m, w = measure(result), max(_label_width(result), len(metric))
    lines = [f"{metric:{w}s}" + "".join(f"{f'N = {n}':>13s}" for n in result.agents)]
    for k, method in enumerate(result.names()):
        cells = [_pivot_cell(metric, m[f"{metric}_{method}_{n}"]) if ok else "-"
                 for n, ok in zip(result.agents, result.ran[k])]
        lines.append(f"{label(method):{w}s}" + "".join(f"{cell:>13s}" for cell in cells))
    return "\n".join(lines)


def _pivot_cell(metric: str, value: float) -> str:
    """One cell of :func:`pivot_table`: the value in its metric's format, '-' for NaN, 'no solution' for infinity."""
    if math.isnan(value) or math.isinf(value):
        return chapter.value_text(value, 0)
    return PIVOT_METRICS[metric].format(value)


def plan_table(result: ScalingResult) -> str:
    """The study's warehouses against a plan of each: per N, the lower bounds (each agent's
    shortest path alone, summed and their largest) and the prioritized plan's sum of costs and
    makespan (:func:`glamas.gridworld.prioritized.plan`, seed 0); per learner and N, its greedy
    policy's completion and its agents' steps summed over the plan's sum of costs (an agent that
    does not arrive counts the episode's steps, so a policy that does not complete is bounded
    from below only), '-' where the learner did not run."""
    plans = {int(n): prioritized.plan(result.config.gridmap(int(n)), result.config.bounce) for n in result.agents}
    bounds = {n: prioritized.lower_bounds(result.config.gridmap(n)) for n in plans}
    greedy = "greedy: completion, steps / plan"
    w = max(_label_width(result), len(greedy))
    lines = [f"{'':{w}s}" + "".join(f"{f'N = {n}':>14s}" for n in plans)]
    for name, values in (("lower bound: sum of costs", [bounds[n][0] for n in plans]),
                         ("plan: sum of costs", [plan.sum_of_costs for plan in plans.values()]),
                         ("lower bound: makespan", [bounds[n][1] for n in plans]),
                         ("plan: makespan", [plan.makespan for plan in plans.values()])):
        lines.append(f"{name:{w}s}" + "".join(f"{value:14d}" for value in values))
    lines.append(greedy)
    for k, method in enumerate(result.names()):
        cells = [f"{result.evaluation(method, n, 'completion').mean():.0%}, "
                 f"{result.evaluation(method, n, 'steps').mean() * n / plan.sum_of_costs:.2f}"
                 if ok else "-" for (n, plan), ok in zip(plans.items(), result.ran[k])]
        lines.append(f"{label(method):{w}s}" + "".join(f"{cell:>14s}" for cell in cells))
    return "\n".join(lines)


def growth_table(result: ScalingResult) -> str:
    """Per method: growth of the learned values per run, fitted over the N it ran at."""
    m, w = measure(result), _label_width(result)
    lines = [f"{'method':{w}s} {'ran for N':>10s} {'factor per agent':>16s} {'log-log slope':>13s}"]
    for k, method in enumerate(result.names()):
        ran_at = [int(n) for n, ok in zip(result.agents, result.ran[k]) if ok]
        span = f"{min(ran_at)}-{max(ran_at)}" if ran_at else "none"
        lines.append(f"{label(method):{w}s} {span:>10s} {m[f'growth_factor_{method}']:16.3g} "
                     f"{m[f'loglog_slope_{method}']:13.2f}")
    return "\n".join(lines)


def final_with_band(result: ScalingResult, method: str, n: int, metric: str) -> tuple[float, float, float]:
    """The final value of ``metric`` (as :func:`measure`) and its 95 % bootstrap interval: runs
    resampled with replacement, the statistic recomputed from each resample's mean curve."""
    curves = result.curves(method, n, "steps" if metric == "convergence" else metric)
    statistic, of_rows = ((convergence_episode, convergence_episodes) if metric == "convergence"
                          else (final, final_by_run))
    draws = np.random.default_rng(0).integers(0, curves.shape[0], (BAND_DRAWS, curves.shape[0]))
    low, high = np.percentile(of_rows(resampled_means(curves, draws), result.episodes), [2.5, 97.5])
    return statistic(curves, result.episodes), float(low), float(high)


def trap_table(traps: dict) -> Table:
    """The trap measured (:func:`glamas.experiments.scaling.experiment.trap`), one row per learner
    of ``traps`` (name -> its measurement)."""
    header = ["learner", "capped", "capped (last tenth)", "trapped agents", "aisle values = 0",
              "best on aisle: trapped", "best on aisle: free", "best elsewhere: trapped"]
    return Table(header, [[label(name), f"{t['capped']:.1%}", f"{t['capped_last']:.1%}",
                           f"{t['trapped']} of {t['agents']}", f"{t['aisle_zero']:.1%}", f"{t['best_trapped']:.1f}",
                           f"{t['best_free']:.1f}", f"{t['elsewhere_trapped']:.1f}"] for name, t in traps.items()])
