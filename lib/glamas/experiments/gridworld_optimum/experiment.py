"""The gridworld of Fig. 9 solved exactly, configured and run: dynamic programming (Alg. 1, 2) on
the joint MMDP, and the episodes of the optimal policy and of agents that each follow their own
shortest path without regard for the other."""

from dataclasses import dataclass

import numpy as np

from glamas import checks, memory
from glamas.gridworld import GridMap, dp, load_map, rules
from glamas.errors import UserError


@dataclass(frozen=True)
class GridworldOptimumConfig:
    """Which map to solve and how (the chapter states none of gamma, epsilon or the bounce cell)."""

    map: str = "tunnel_to_goal"
    """A map's name in data/maps or a map file's path (Fig. 9 is 'tunnel_to_goal')."""
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
        self.gridmap()  # a map that is not there or is malformed is refused here (MapError)
        if not isinstance(self.gamma, float) or not 0.0 < self.gamma < 1.0:
            raise UserError(f"gamma must be a float in (0, 1), got {self.gamma!r}")
        if not isinstance(self.epsilon, float) or not 0.0 < self.epsilon <= max_epsilon(self.gamma):
            raise UserError(f"epsilon must be a float > 0 and at most {max_epsilon(self.gamma):.3g} for gamma="
                            f"{self.gamma:g} (V then ends within {VALUE_ERROR:g} of its optimum), got {self.epsilon!r}")
        if self.bounce not in rules.BOUNCE_MODES:
            raise UserError(f"bounce must be one of {sorted(rules.BOUNCE_MODES)}, got {self.bounce!r}")
        if not isinstance(self.selfish_steps, int) or self.selfish_steps < 1:
            raise UserError(f"selfish_steps must be a positive integer, got {self.selfish_steps!r}")

    def gridmap(self) -> GridMap:
        """The map (:func:`glamas.gridworld.load_map`)."""
        return load_map(self.map)

    def memory_bytes(self) -> int:
        """Bytes of glamas.gridworld.dp's tables per joint state and action: next state, reward,
        collisions, each agent's reward (8 bytes) and bumped and reached flags (1 byte), and the Q
        values. They grow as cells ** agents."""
        gridmap = self.gridmap()
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
    gridmap = config.gridmap()
    mdp = dp.joint_mdp(gridmap, config.bounce)
    by_values = dp.value_iteration(mdp, config.gamma, config.epsilon)
    by_policies = dp.policy_iteration(mdp, config.gamma, config.epsilon)
    optimal, by_policy_iteration = dp.rollout(mdp, by_values.policy), dp.rollout(mdp, by_policies.policy)
    for algorithm, episode in (("value", optimal), ("policy", by_policy_iteration)):
        if not episode.finished:  # an epsilon within the bound, still too coarse for this gamma and map
            raise UserError(f"the policy that {algorithm} iteration found with epsilon={config.epsilon:g} does not bring "
                            f"every agent to the goal of {config.map!r}: lower epsilon")
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
