"""The gridworld of the chapter's Section 5.3: maps, rules, a Python environment, dynamic programming."""

from glamas.gridworld import rewards, rules
from glamas.gridworld.env import GridworldEnv
from glamas.gridworld.maps import GridMap, MapError, load_map, make_goals, map_text, tunnel_to_goal
from glamas.gridworld.rules import (
    ACTION_NAMES, BOUNCE_MODES, BOUNCE_PREVIOUS, BOUNCE_START, N_ACTIONS, Goals, manhattan, shared_reward, step,
    would_collide,
)
from glamas.gridworld.rewards import Rewards

__all__ = [
    "ACTION_NAMES", "BOUNCE_MODES", "BOUNCE_PREVIOUS", "BOUNCE_START", "Goals", "GridMap", "GridworldEnv",
    "MapError", "N_ACTIONS", "Rewards", "load_map", "make_goals", "map_text", "manhattan", "rewards", "rules", "shared_reward", "step",
    "tunnel_to_goal", "would_collide",
]
