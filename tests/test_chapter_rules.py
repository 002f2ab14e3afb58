"""The gridworld rules' constants are the values the chapter states (data/chapter/gridworld_optimum.json)."""

from glamas import claims
from glamas.gridworld import rules
from glamas.gridworld.rewards import CHAPTER


def test_reward_constants_and_actions_are_the_chapters():
    stated = claims.parameters("gridworld_optimum")
    assert CHAPTER.goal == stated["goal_reward"]["value"]
    assert CHAPTER.collision == stated["collision_penalty"]["value"]
    assert CHAPTER.bump == stated["bump_penalty"]["value"]
    assert ", ".join(rules.ACTION_NAMES) == stated["actions"]["value"]
