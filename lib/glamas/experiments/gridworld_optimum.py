"""The gridworld of Fig. 9 solved exactly: dynamic programming (Alg. 1, 2) on the joint MMDP.

This is the yardstick for the learners of Section 5.3: the best the agents can do together, and
what happens when each follows its own shortest path without regard for the other.
"""

from dataclasses import dataclass

import numpy as np

from glamas import claims, memory
from glamas import checks
from glamas.errors import UserError
from glamas.experiments.registry import Experiment, register
from glamas.gridworld import GridMap, dp, draw, load_map, rules
from glamas.paths import MAPS


@dataclass(frozen=True)
class GridworldOptimumConfig:
    """Which map to solve and how (the chapter states none of gamma, epsilon or the bounce cell)."""

    map_name: str = "tunnel_to_goal"
    """Stem of a map file in data/maps (Fig. 9 is 'tunnel_to_goal')."""
    gamma: float = 0.9
    """Discount factor of the DP; the chapter gives none. 0.9 makes a yielding agent bump once
    (-1) rather than detour two steps; from about 0.99 the detour wins (see the notebook)."""
    epsilon: float = 1e-9
    """Alg. 2 stops when the largest change of V is below this (Sec. 2.2); at most :func:`max_epsilon`."""
    bounce: str = "previous"
    """Where collided agents go: 'previous' cell or 'start' cell ("bounced back to their original position")."""
    selfish_steps: int = 20
    """Steps the selfish shortest-path agents are followed (they may never arrive)."""

    def __post_init__(self):
        checks.field_types(self)
        if not (MAPS / f"{self.map_name}.txt").is_file():
            known = sorted(p.stem for p in MAPS.glob("*.txt"))
            raise UserError(f"map_name {self.map_name!r} is not a map in {MAPS}; known maps: {known}")
        if not isinstance(self.gamma, float) or not 0.0 < self.gamma < 1.0:
            raise UserError(f"gamma must be a float in (0, 1), got {self.gamma!r}")
        if not isinstance(self.epsilon, float) or not 0.0 < self.epsilon <= max_epsilon(self.gamma):
            raise UserError(f"epsilon must be a float > 0 and at most {max_epsilon(self.gamma):.3g} for gamma="
                            f"{self.gamma:g} (V then ends within {VALUE_ERROR:g} of its optimum), got {self.epsilon!r}")
        if self.bounce not in rules.BOUNCE_MODES:
            raise UserError(f"bounce must be one of {sorted(rules.BOUNCE_MODES)}, got {self.bounce!r}")
        if not isinstance(self.selfish_steps, int) or self.selfish_steps < 1:
            raise UserError(f"selfish_steps must be a positive integer, got {self.selfish_steps!r}")

    def memory_bytes(self) -> int:
        """Bytes of glamas.gridworld.dp's tables per joint state and action: next state, reward,
        collisions, each agent's reward (8 bytes) and bumped and reached flags (1 byte), and the Q
        values. They grow as cells ** agents."""
        gridmap = load_map(MAPS / f"{self.map_name}.txt")
        n = gridmap.n_agents
        per_pair = 4 * memory.BYTES_PER_VALUE + n * (memory.BYTES_PER_VALUE + 2)
        return gridmap.n_cells ** n * 4 ** n * per_pair


@dataclass(frozen=True, eq=False)
class GridworldOptimumResult:
    """The optimal and the selfish episodes, and how closely Alg. 1 and Alg. 2 agree."""

    gridmap: GridMap
    """The solved map."""
    optimal: dp.Rollout
    """The episode of the value-iteration policy from the starts."""
    selfish: dp.Rollout
    """The episode of agents that each follow their own single-agent optimum."""
    start_value: float
    """V* of the start state (value iteration)."""
    value_gap: float
    """Largest |V_value_iteration - V_policy_iteration| over the joint states."""
    policy_iteration_episode: dp.Rollout
    """The episode of the policy-iteration policy from the starts."""
    sweeps: int
    """Sweeps value iteration needed."""
    improvements: int
    """Policy improvements policy iteration needed."""


VALUE_ERROR = 1e-3
"""The most that value iteration's stopping rule may leave V off its optimum: a thousandth of the
smallest reward (a bump's -1). A looser epsilon (1, 100) stops the sweeps before the values tell
the agents' moves apart, and the "optimal" policy found then need not reach the goal."""


def max_epsilon(gamma: float) -> float:
    """The largest epsilon for discount ``gamma``: stopping when V changes by less than epsilon
    leaves V within epsilon gamma / (1 - gamma) of its optimum (Sec. 2.2), at most VALUE_ERROR."""
    return VALUE_ERROR * (1.0 - gamma) / gamma


def run(config: GridworldOptimumConfig, seed: int = 0, workers=None, progress=None) -> GridworldOptimumResult:
    """Solve the joint MMDP with both DP algorithms and roll out the optimal and the selfish policies.

    Deterministic: ``seed``, ``workers`` and ``progress`` are accepted for the common interface.
    """
    memory.check(config)  # the joint tables grow as cells ** agents
    gridmap = load_map(MAPS / f"{config.map_name}.txt")
    mdp = dp.joint_mdp(gridmap, config.bounce)
    by_values = dp.value_iteration(mdp, config.gamma, config.epsilon)
    by_policies = dp.policy_iteration(mdp, config.gamma, config.epsilon)
    optimal, by_policy_iteration = dp.rollout(mdp, by_values.policy), dp.rollout(mdp, by_policies.policy)
    for algorithm, episode in (("value", optimal), ("policy", by_policy_iteration)):
        if not episode.finished:  # an epsilon within the bound, still too coarse for this gamma and map
            raise UserError(f"the policy that {algorithm} iteration found with epsilon={config.epsilon:g} does not bring "
                            f"every agent to the goal of {config.map_name!r}: lower epsilon")
    return GridworldOptimumResult(
        gridmap=gridmap,
        optimal=optimal,
        selfish=dp.rollout(mdp, dp.selfish_policy(mdp, config.gamma), config.selfish_steps),
        start_value=float(by_values.values[mdp.start_state]),
        value_gap=float(np.abs(by_values.values - by_policies.values).max()),
        policy_iteration_episode=by_policy_iteration,
        sweeps=by_values.iterations,
        improvements=by_policies.iterations,
    )


def measure(result: GridworldOptimumResult) -> dict:
    """Steps, returns, collisions and bumps of the optimal episode; collisions of the selfish one."""
    optimal, selfish = result.optimal, result.selfish
    metrics = {f"optimal_steps_agent_{i + 1}": int(s) for i, s in enumerate(optimal.steps_to_goal)}
    metrics.update({f"optimal_return_agent_{i + 1}": float(r) for i, r in enumerate(optimal.returns)})
    metrics.update(
        optimal_finished=optimal.finished,
        optimal_makespan=int(optimal.steps_to_goal.max()),
        optimal_total_steps=int(optimal.steps_to_goal.sum()),
        optimal_collisions=optimal.collisions,
        optimal_bumps=int(optimal.bumps.sum()),
        selfish_collisions=selfish.collisions,
        selfish_finished=selfish.finished,
        start_value=result.start_value,
        value_gap=result.value_gap,
        policy_iteration_total_steps=int(result.policy_iteration_episode.steps_to_goal.sum()),
    )
    return metrics


WAITS = {"optimal": "waits: bumps into a wall", "selfish": "stays: bounced back by a collision"}
"""Why an agent stays in a cell in each episode (the optimum's yielding agent walks into a wall
once; the selfish agents keep colliding at the passage)."""


def plot_episode(ax, result: GridworldOptimumResult, which: str = "optimal"):
    """The map of Fig. 9 with the agents' paths in the 'optimal' or the 'selfish' episode, the
    step at which each agent enters each cell, and a ring where an agent stays put."""
    episodes = {"optimal": result.optimal, "selfish": result.selfish}
    if which not in episodes:
        raise UserError(f"which must be one of {sorted(episodes)}, got {which!r}")
    draw.draw_map(ax, result.gridmap)
    draw.draw_paths(ax, result.gridmap, episodes[which].cells, numbered=True, wait_label=WAITS[which])
    steps = ", ".join("-" if s < 0 else str(s) for s in episodes[which].steps_to_goal)
    ax.set_title(f"{which}\nsteps to goal: {steps}; collisions: {episodes[which].collisions}", fontsize=9)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), ncols=2, fontsize=8, frameon=False)


def claim_rows(result: GridworldOptimumResult) -> list[dict]:
    """The claims about the map (data/chapter/gridworld_optimum.json) with computed verdicts."""
    return claims.verdicts(claims.load("gridworld_optimum"), measure(result))


EXPERIMENT = register(Experiment("gridworld_optimum", GridworldOptimumConfig, run,
                                 lambda runs, iterations: GridworldOptimumConfig(), 1, 1, GridworldOptimumResult,
                                 claim_rows=lambda result, config: claim_rows(result), figures=("fig9_optimum",),
                                 stored=False))
"""The exact optimum of Fig. 9's map: computed in a second whenever it is needed, never stored."""
