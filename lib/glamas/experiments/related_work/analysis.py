"""What a result of the related-work comparison says: the gridworld experiment's measurements for
every learner, what each learner stores, the joint states CQ-learning marked, and the comparisons
the claims of ``data/chapter/related_work.json`` are about."""

import functools

import numpy as np

from glamas import claims as chapter
from glamas.curves import final, mean_and_band, ratio
from glamas.experiments.gridworld import analysis as gw_analysis
from glamas.experiments.related_work.experiment import RELATED_LEARNERS, RelatedWorkConfig, RelatedWorkResult
from glamas.learners import cq, registry
from glamas.tables import Table


def usable_joint_states(config: RelatedWorkConfig) -> int:
    """Joint states in which both agents act: ordered pairs of distinct cells, neither the goal nor blocked."""
    g = config.gridmap()
    usable = int((~(g.is_goal | g.blocked)).sum())
    return usable * (usable - 1)


def marked_distances(result: RelatedWorkResult, config: RelatedWorkConfig) -> np.ndarray:
    """Manhattan distance of every joint state a CQ agent marked (all runs and agents pooled)."""
    n_cols = config.gridmap().n_cols
    _, _, own, other = np.nonzero(result.output("cq", "marked"))
    return np.abs(own // n_cols - other // n_cols) + np.abs(own % n_cols - other % n_cols)


def measure(result: RelatedWorkResult, config: RelatedWorkConfig, **choice) -> dict:
    """:func:`glamas.experiments.gridworld.measure` for every learner, plus each learner's stored
    values and the related-work comparisons (data/chapter/related_work.json), at the measurement
    choices ``choice`` (:func:`glamas.experiments.gridworld.analysis.measure`'s keywords)."""
    m = gw_analysis.measure(result, **choice)
    names = result.names()
    for k, name in enumerate(names):
        m[f"q_entries_{name}"] = float(result.local_entries[k] + result.joint_entries[k].mean())
    if "cq" in names:
        per_agent = result.output("cq", "marked").sum(axis=(2, 3)).mean()
        m["marked_joint_states_cq"] = float(per_agent)
        m["marked_fraction_cq"] = float(per_agent / usable_joint_states(config))
        distances = marked_distances(result, config)
        within = distances <= config.setup("sparse_maq").own.coordination_distance
        m["marked_within_coordination_distance_cq"] = float(within.mean()) if distances.size else 0.0
    for name in set(names) & set(RELATED_LEARNERS):
        if "mmdp" in names:
            m[f"reward_{name}_over_mmdp"] = ratio(m[f"reward_{name}"], m["reward_mmdp"])
            m[f"greedy_reward_{name}_over_mmdp"] = ratio(m[f"greedy_reward_{name}"], m["greedy_reward_mmdp"])
            m[f"q_entries_{name}_over_mmdp"] = m[f"q_entries_{name}"] / m["q_entries_mmdp"]
            m.update(gw_analysis.convergence_metrics(result, name, "mmdp", choice.get("tolerance"),
                                                     choice.get("blocks", 1)))
        if "independent" in names:
            m[f"reward_{name}_minus_independent"] = m[f"reward_{name}"] - m["reward_independent"]
            m[f"greedy_reward_{name}_minus_independent"] = m[f"greedy_reward_{name}"] - m["greedy_reward_independent"]
    return m


def claim_rows(result: RelatedWorkResult, config: RelatedWorkConfig) -> list[dict]:
    """The related-work claims (data/chapter/related_work.json) with verdicts computed from ``result``."""
    return chapter.verdicts(chapter.load("related_work"), functools.partial(measure, result, config))


def final_interval(result: RelatedWorkResult, name: str, metric: str = "collisions") -> tuple[float, float, float]:
    """Learner ``name``'s final value of one metric (:func:`glamas.curves.final`, last 10 % of the episodes)
    as (mean over runs, 95 % bootstrap interval of that mean: runs resampled, as the figures' bands)."""
    per_run = np.array([final(curve[None], result.episodes) for curve in result.curves(name, metric)])
    mean, low, high = mean_and_band(per_run[:, None])
    return float(mean[0]), float(low[0]), float(high[0])


def fewest_flagged_collisions(config: RelatedWorkConfig) -> int:
    """The fewest collisions among the ``cq_window`` rewards of a full window that CQ-learning's test
    flags against a state-action that never collided alone (:func:`glamas.learners.cq.fewest_flagged_collisions`)."""
    return cq.fewest_flagged_collisions(config.setup("cq").own, config.rewards)


def summary_table(result: RelatedWorkResult, config: RelatedWorkConfig) -> Table:
    """Per learner: final steps, reward, collisions and coordinations (last 10 % of the episodes,
    mean over runs), convergence episode, and what each agent stores (measured)."""
    m, gridmap = measure(result, config), config.gridmap()
    header = ["learner", "steps", "reward", "collisions", "coordinations", "converged by", "Q entries/agent",
              "samples/agent", "GLA params/agent"]
    return Table(header, [[registry.label(name), f"{m[f'steps_{name}']:.2f}", f"{m[f'reward_{name}']:.1f}",
                           f"{m[f'collisions_{name}']:.3f}", f"{m[f'coordinations_{name}']:.2f}",
                           f"{m[f'convergence_{name}']:.0f}", f"{m[f'q_entries_{name}']:.0f}", result.reward_samples[k],
                           registry.get(name).gla_parameters(config.setup(name), gridmap) // gridmap.n_agents]
                          for k, name in enumerate(result.names())])
