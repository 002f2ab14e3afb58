"""The gridworld rules' constants are the values the chapter states (data/chapter/gridworld_optimum.json)."""

from glamas import claims
from glamas.gridworld import rules


def test_reward_constants_and_actions_are_the_chapters():
    stated = claims.parameters("gridworld_optimum")
    assert rules.GOAL_REWARD == stated["goal_reward"]["value"]
    assert rules.COLLISION_PENALTY == stated["collision_penalty"]["value"]
    assert rules.BUMP_PENALTY == stated["bump_penalty"]["value"]
    assert ", ".join(rules.ACTION_NAMES) == stated["actions"]["value"]
