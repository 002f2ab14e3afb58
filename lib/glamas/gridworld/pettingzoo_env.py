"""The chapter's gridworld (Section 5.3) as a PettingZoo ``ParallelEnv`` (optional extra ``pettingzoo``).

A thin adapter over :class:`glamas.gridworld.env.GridworldEnv`: every move goes through the same
compiled :func:`glamas.gridworld.rules.step` as the learners' kernels. What the adapter adds is
gymnasium spaces:

- action of each agent: ``Discrete(4)``, 0=N, 1=E, 2=S, 3=W;
- observation of each agent: an int64 array ``[own row, own col, then the other agents' (row,
  col) in agent order]``, GridworldEnv's ``{"position", "others"}`` dict flattened, in
  ``MultiDiscrete([n_rows, n_cols] * n_agents)``.

An agent that enters its goal is terminated and leaves ``agents`` (its goal is absorbing; each
agent's goal cells are the map's, ``gridmap.goals``, and another agent's goal is an ordinary cell
for it); the live agents are truncated after ``max_steps`` steps. The game is deterministic: ``reset``'s
seed only seeds the spaces' samplers, so a seeded run of sampled actions repeats exactly.
"""

import numpy as np

try:
    from gymnasium import spaces
    from pettingzoo import ParallelEnv
except ImportError as error:
    raise ImportError(
        "glamas.gridworld.pettingzoo_env needs the optional extra 'pettingzoo' (pettingzoo and gymnasium): "
        "pip install -e '.[pettingzoo]' in the glamas repository (or: pip install -r requirements-extras.txt)"
    ) from error

from glamas.errors import UserError
from glamas.gridworld.env import GridworldEnv
from glamas.gridworld.maps import GridMap, load_map, map_text, tunnel_to_goal
from glamas.gridworld.rules import N_ACTIONS


class GridworldParallelEnv(ParallelEnv):
    """The gridworld game for ``gridmap.n_agents`` agents ``agent_1``, ``agent_2``, ...

    ``gridmap`` (a GridMap, or a map's name in ``data/maps``, a map file's path or the map's text:
    :func:`glamas.gridworld.load_map`) defaults to the chapter's TunnelToGoal (Fig. 9); ``bounce``
    and ``max_steps`` as in GridworldEnv; ``render_mode`` None or 'ansi' (``render()`` returns the
    map as text, in the format of ``data/maps``, with each agent on its cell:
    :func:`glamas.gridworld.map_text`).
    """

    metadata = {"name": "glamas_gridworld_v0", "render_modes": ["ansi"], "is_parallelizable": True}

    def __init__(self, gridmap: GridMap | None = None, bounce: str = "previous", max_steps: int = 1000,
                 render_mode: str | None = None):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise UserError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        self._game = GridworldEnv(_as_map(gridmap), bounce, max_steps)
        self.gridmap = self._game.gridmap
        self.render_mode = render_mode
        self.possible_agents = list(self._game.possible_agents)
        self.agents = []
        n = self.gridmap.n_agents
        self._observation_spaces = {name: spaces.MultiDiscrete(np.tile([self.gridmap.n_rows, self.gridmap.n_cols], n))
                                    for name in self.possible_agents}
        self._action_spaces = {name: spaces.Discrete(N_ACTIONS) for name in self.possible_agents}

    def observation_space(self, agent):
        return self._observation_spaces[agent]

    def action_space(self, agent):
        return self._action_spaces[agent]

    def reset(self, seed=None, options=None):
        """All agents on their start cells; returns (observations, infos). ``seed`` (None or a
        whole number >= 0) seeds every agent's action and observation samplers, each with its
        own stream of ``numpy.random.SeedSequence(seed)``, so no two samplers repeat each other
        at any pair of seeds."""
        if seed is not None:
            self._seed_spaces(seed)
        observations, infos = self._game.reset(seed=seed)
        self.agents = list(self._game.agents)
        return self._flatten(observations), infos

    def _seed_spaces(self, seed) -> None:
        if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise UserError(f"seed must be None or a whole number >= 0, got {seed!r}")
        children = iter(np.random.SeedSequence(int(seed)).spawn(2 * len(self.possible_agents)))
        for name in self.possible_agents:
            for space in (self._action_spaces[name], self._observation_spaces[name]):
                space.seed(int(next(children).generate_state(1, np.uint64)[0]))

    def step(self, actions: dict):
        """One joint move of the live agents; returns PettingZoo's five dicts."""
        observations, rewards, terminations, truncations, infos = self._game.step(actions)
        self.agents = list(self._game.agents)
        return self._flatten(observations), rewards, terminations, truncations, infos

    def state(self) -> np.ndarray:
        """Every agent's (row, col) in agent order, flattened."""
        return np.array([self.gridmap.row_col(int(c)) for c in self._game.cells], dtype=np.int64).ravel()

    def render(self):
        if self.render_mode is None:
            raise UserError("render() needs render_mode='ansi' when the environment is made")
        return map_text(self.gridmap, self._game.cells).rstrip("\n")

    def _flatten(self, observations: dict) -> dict:
        return {name: np.array([*obs["position"], *(x for cell in obs["others"] for x in cell)], dtype=np.int64)
                for name, obs in observations.items()}


def _as_map(gridmap) -> GridMap:
    """The map to play on: TunnelToGoal for None, a GridMap as it is, else a map's name, path or text."""
    if gridmap is None:
        return tunnel_to_goal()
    return gridmap if isinstance(gridmap, GridMap) else load_map(gridmap)
