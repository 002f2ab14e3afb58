"""What the exact solution of Fig. 9's map says: the optimal episode's steps, returns, collisions
and bumps, the selfish episode's collisions, and the claims about the map."""

from glamas import claims
from glamas.experiments.gridworld_optimum.experiment import GridworldOptimumResult


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


def claim_rows(result: GridworldOptimumResult) -> list[dict]:
    """The claims about the map (data/chapter/gridworld_optimum.json) with computed verdicts."""
    return claims.verdicts(claims.load("gridworld_optimum"), measure(result))
