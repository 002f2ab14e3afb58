"""A PettingZoo-shaped Python environment around the compiled gridworld rules (Section 5.3).

For interactive use and for checking learners by hand; the simulation kernels call
:func:`glamas.gridworld.rules.step` directly. Every move goes through that same function.

Observation of each agent (a choice, the chapter does not define one for a general API): a dict
``{"position": (row, col), "others": ((row, col), ...)}`` with its own cell and the other agents'
cells in agent order. The independent learners use only ``position``; the joint-state and MMDP
learners use both.
"""

import numpy as np

from glamas.errors import UserError
from glamas.gridworld import rules
from glamas.gridworld.maps import GridMap
from glamas.gridworld.rewards import CHAPTER, Rewards


class GridworldEnv:
    """The chapter's gridworld game for ``gridmap.n_agents`` agents, named ``agent_1``, ``agent_2``, ...

    ``bounce`` is where collided agents go ('previous' cell or 'start' cell), ``rewards`` what a
    step pays (:mod:`glamas.gridworld.rewards`, the chapter's by default). An agent that enters
    one of its goal cells (``gridmap.goals``; another agent's goal is an ordinary cell for it) is
    terminated and takes no further actions; every agent is truncated after ``max_steps``.
    """

    def __init__(self, gridmap: GridMap, bounce: str = "previous", max_steps: int = 1000, rewards: Rewards = CHAPTER):
        if bounce not in rules.BOUNCE_MODES:
            raise UserError(f"bounce must be one of {sorted(rules.BOUNCE_MODES)}, got {bounce!r}")
        if not isinstance(max_steps, (int, np.integer)) or max_steps < 1:
            raise UserError(f"max_steps must be a positive integer, got {max_steps!r}")
        if not isinstance(rewards, Rewards):
            raise UserError(f"rewards must be a glamas.gridworld.rewards.Rewards, got {rewards!r}")
        self.gridmap = gridmap
        self.bounce = bounce
        self._world = rules.world(gridmap, bounce, rewards)
        self.max_steps = int(max_steps)
        self.possible_agents = [f"agent_{k}" for k in range(1, gridmap.n_agents + 1)]
        self.agents: list[str] = []
        n = gridmap.n_agents
        self._cells, self._done = gridmap.starts.copy(), np.zeros(n, bool)
        self._actions, self._new_cells = np.zeros(n, np.int64), np.zeros(n, np.int64)
        self._rewards = np.zeros(n)
        self._bumped, self._collided, self._reached = (np.zeros(n, bool) for _ in range(3))
        self._steps = 0

    @property
    def cells(self) -> np.ndarray:
        """The cell every agent is on, in agent order (a copy)."""
        return self._cells.copy()

    def reset(self, seed=None):
        """Put every agent on its start cell; ``seed`` is accepted for the API (the game is deterministic)."""
        self.agents = list(self.possible_agents)
        self._cells[:] = self.gridmap.starts
        self._done[:] = False
        self._steps = 0
        return self._observations(), {name: {} for name in self.agents}

    def step(self, actions: dict):
        """Move every live agent by its action (0=N, 1=E, 2=S, 3=W); returns PettingZoo's five dicts."""
        self._check_actions(actions)
        live = list(self.agents)
        for i, name in enumerate(self.possible_agents):
            self._actions[i] = actions[name] if name in actions else 0
        collisions = rules.step(self._world, self._cells, self._done, self._actions,
                                self._new_cells, self._rewards, self._bumped, self._collided, self._reached)
        self._cells[:] = self._new_cells
        self._done |= self._reached
        self._steps += 1
        observations = self._observations(live)
        rewards, terminations, truncations, infos = {}, {}, {}, {}
        for name in live:
            i = self.possible_agents.index(name)
            rewards[name] = float(self._rewards[i])
            terminations[name] = bool(self._done[i])
            truncations[name] = self._steps >= self.max_steps and not self._done[i]
            infos[name] = {"bumped": bool(self._bumped[i]), "collided": bool(self._collided[i]),
                           "collisions_in_step": collisions}
        self.agents = [name for name in live if not (terminations[name] or truncations[name])]
        return observations, rewards, terminations, truncations, infos

    def _check_actions(self, actions):
        if not self.agents:
            raise RuntimeError("no live agents: call reset() before step()")
        if not isinstance(actions, dict):
            raise TypeError(f"actions must be a dict agent name -> action, got {type(actions).__name__}")
        unknown = sorted(set(actions) - set(self.agents))
        if unknown:
            raise UserError(f"actions for agents that are not live: {unknown}; live agents: {self.agents}")
        missing = sorted(set(self.agents) - set(actions))
        if missing:
            raise UserError(f"no action for live agents {missing}: give every agent in env.agents an action")
        for name, action in actions.items():
            if isinstance(action, (bool, np.bool_)) or not isinstance(action, (int, np.integer)) \
                    or not 0 <= action < rules.N_ACTIONS:
                raise UserError(f"action of {name} must be 0 (N), 1 (E), 2 (S) or 3 (W), got {action!r}")

    def _observations(self, names=None):
        positions = [self.gridmap.row_col(int(c)) for c in self._cells]
        return {name: {"position": positions[i], "others": tuple(p for j, p in enumerate(positions) if j != i)}
                for i, name in enumerate(self.possible_agents) if names is None or name in names}
