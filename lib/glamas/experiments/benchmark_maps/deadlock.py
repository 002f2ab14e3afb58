"""CQ-learning's greedy policy caught in a cycle, read from its learned values (notebook 07).

The benchmark keeps what its runs measure, not their tables. Here the benchmark's CQ-learning runs
on one two-agent map are trained again from their own seeds (the same streams, so the same tables
as the runs whose greedy evaluations the benchmark stores), and each run's greedy episode is
replayed step by step through the environment until every agent is in or it is caught in a cycle.
Learning off, the greedy policy is deterministic except where two actions tie (the kernel then
draws one at random; so does the replay): a joint state that comes back with no tie met since its
last visit repeats forever, and the episode never ends. At every step the replay keeps what each
agent acted on (its augmented row Q_aug(s_k, s_l, .) or its own Q_k(s_k, .),
:mod:`glamas.learners.cq`) and the values of its four actions.
"""

from dataclasses import dataclass

import numpy as np

from glamas import seeds, training
from glamas.errors import UserError
from glamas.experiments.benchmark_maps.experiment import BenchmarkConfig, case_names
from glamas.gridworld import GridworldEnv
from glamas.learners import registry

MOVES = "NESW"
"""The actions' letters, in the rules' order (glamas.gridworld.rules)."""


def trained(config: BenchmarkConfig, map_name: str, seed: int = 0) -> dict:
    """The benchmark's CQ-learning runs on ``map_name`` under ``config`` (its seeds), trained
    again with their tables kept: ``q``, ``q_aug`` and ``marked``, runs first."""
    learner, gridmap = registry.get("cq"), config.gridmap(map_name)
    if gridmap.n_agents != 2:
        raise UserError(f"map {map_name!r} has {gridmap.n_agents} agents: the replay reads two agents' tables")
    return training.train(learner, config.setup("cq"), gridmap, config.schedule(), config.runs,
                          seeds.named(*case_names(seed, map_name), "cq"), bounce=config.bounce,
                          rewards=config.rewards)


@dataclass(frozen=True)
class Decision:
    """What one agent acted on at one step of a greedy replay."""

    agent: int
    """The agent (0-based)."""
    cell: tuple
    """Its (row, col)."""
    augmented: bool
    """Whether it acted on its augmented row (the other agent's cell augments its own), else on Q_k."""
    values: np.ndarray
    """float (4,): the row's values of N, E, S, W."""
    action: int
    """The greedy action."""
    tied: bool
    """Whether another action had the same value (the tie was broken at random)."""

    @property
    def margin(self) -> float:
        """How much the greedy action's value exceeds the next best."""
        return float(self.values[self.action] - np.max(np.delete(self.values, self.action)))


@dataclass(frozen=True)
class Replay:
    """One run's greedy episode: its decisions step by step, and where it stopped."""

    steps: list
    """Per step, the live agents' Decisions."""
    collisions: int
    """Collisions on the way."""
    arrived: bool
    """Whether every agent reached its goal."""
    cycle_start: int | None
    """The step whose joint state came back with no tie since (the cycle is ``steps[cycle_start:]``);
    None when the episode ended (every agent in, or the step cap)."""

    @property
    def cycle(self) -> list:
        return [] if self.cycle_start is None else self.steps[self.cycle_start:]

    @property
    def ties(self) -> int:
        """Ties broken on the way."""
        return sum(d.tied for step in self.steps for d in step)


def decision(tables: dict, run: int, k: int, cells: np.ndarray, done: np.ndarray, gridmap, generator) -> Decision:
    """Agent k's greedy choice from run ``run``'s tables, as the kernel's step 1 makes it with two
    agents: on Q_aug(s_k, s_l, .) where the other agent l is present and its cell augments s_k; a
    tie broken by ``generator``."""
    l, s = 1 - k, int(cells[k])
    augmented = bool(not done[l] and tables["marked"][run, k, s, cells[l]])
    values = tables["q_aug"][run, k, s, cells[l]] if augmented else tables["q"][run, k, s]
    best = np.flatnonzero(values == values.max())
    return Decision(k, gridmap.row_col(s), augmented, values.copy(), int(generator.choice(best)), best.size > 1)


def replay(config: BenchmarkConfig, map_name: str, tables: dict, run: int) -> Replay:
    """Run ``run``'s greedy episode on ``map_name``, until every agent is in, a cycle (a joint state
    back with no tie since its last visit), or the step cap; ties broken from a generator seeded
    with the run."""
    gridmap, generator = config.gridmap(map_name), np.random.default_rng(run)
    env = GridworldEnv(gridmap, config.bounce, config.max_steps, config.rewards)
    env.reset()
    last_visit, steps, collisions, arrived = {}, [], 0, set()
    while env.agents:
        cells, done = env.cells, np.array([name not in env.agents for name in env.possible_agents])
        state = (tuple(cells.tolist()), tuple(done.tolist()))
        if state in last_visit and not any(d.tied for step in steps[last_visit[state]:] for d in step):
            return Replay(steps, collisions, False, last_visit[state])
        last_visit[state] = len(steps)
        decisions = [decision(tables, run, k, cells, done, gridmap, generator) for k in range(2) if not done[k]]
        _, _, terminations, _, infos = env.step({env.possible_agents[d.agent]: d.action for d in decisions})
        arrived |= {name for name, done in terminations.items() if done}
        collisions += next(iter(infos.values()))["collisions_in_step"]
        steps.append(decisions)
    return Replay(steps, collisions, len(arrived) == gridmap.n_agents, None)


def cycle_table(replay_of_run: Replay) -> str:
    """The steps of one run's cycle: each agent's cell, what it acted on, its four values, its
    greedy action and that action's margin over the next best."""
    lines = [f"{'step':>4s}  {'agent':>5s}  {'cell':>8s}  {'acts on':9s}" + "".join(f"{m:>8s}" for m in MOVES)
             + f"  {'greedy':>6s}  {'margin':>6s}"]
    for t, decisions in enumerate(replay_of_run.cycle, start=replay_of_run.cycle_start):
        for d in decisions:
            row = "".join(f"{v:8.2f}" for v in d.values)
            lines.append(f"{t:4d}  {d.agent + 1:5d}  {str(d.cell):>8s}  {'Q_aug' if d.augmented else 'Q_k':9s}{row}"
                         f"  {MOVES[d.action]:>6s}  {d.margin:6.2f}{'  tie' if d.tied else ''}")
    return "\n".join(lines)


def cycles_summary(replays: list) -> str:
    """Over runs: how many greedy episodes bring every agent in, how many reach the step cap (their
    steps, collisions and the ties broken on the way), and how many are caught in a cycle (its
    length, the share of its decisions on augmented rows, the smallest margin of a greedy action in it)."""
    caught = sum(r.cycle_start is not None for r in replays)
    lines = [f"of {len(replays)} greedy episodes, {sum(r.arrived for r in replays)} bring every agent in, {caught} end "
             f"in a cycle, {len(replays) - caught - sum(r.arrived for r in replays)} reach the step cap"]
    for run, r in enumerate(replays):
        if r.arrived:
            lines.append(f"  run {run}: every agent in after {len(r.steps)} steps, {r.collisions} collisions, "
                         f"{r.ties} ties broken")
            continue
        if r.cycle_start is None:
            lines.append(f"  run {run}: at the step cap, {r.collisions} collisions, {r.ties} ties broken (equal "
                         "values it wanders among)")
            continue
        decisions = [d for step in r.cycle for d in step]
        augmented = sum(d.augmented for d in decisions) / len(decisions)
        lines.append(f"  run {run}: a cycle of {len(r.cycle)} steps from step {r.cycle_start}, {augmented:.0%} of its "
                     f"decisions on augmented rows, smallest margin {min(d.margin for d in decisions):.2f}")
    return "\n".join(lines)

