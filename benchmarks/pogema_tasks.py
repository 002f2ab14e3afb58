"""The glamas half of the POGEMA cross-check (``make pogema-crosscheck``; POGEMA: Skrynnik et al.,
ICLR 2025): the many-agent study's warehouses (glamas.gridworld.generate.warehouse(N, seed 0)),
each with its prioritized plan (glamas.gridworld.prioritized), written as POGEMA tasks and
actions (glamas.gridworld.export) into one JSON file, with the plan's sum of costs and makespan
and glamas's cost per agent-step of the independent learners and 2observe learning there
(benchmarks.bench_many_agents, each run without its setup). benchmarks/pogema_replay.py, run in
POGEMA's own virtual environment, replays the plans in POGEMA and times its environment step.

Usage: python -m benchmarks.pogema_tasks OUT.json [--quick]
"""

import argparse
import json
from pathlib import Path

from glamas import errors
from glamas.errors import UserError
from glamas.gridworld import export, generate, prioritized

from benchmarks import bench_many_agents

AGENTS = (8, 32, 128, 1024)
"""The numbers of agents of the cross-check: the study's N and the largest of bench_many_agents."""
TIMED = ("independent", "two_observe")
EPISODES = {"full": {8: 1000, 32: 200, 128: 50, 1024: 20}, "quick": {8: 100, 32: 20, 128: 5, 1024: 2}}
"""Episodes of each timed glamas run per N (step cap 1000): a million agent-steps or more at full size."""
REPEATS = 3
"""Timed glamas runs per learner and N (and runs of no steps, whose median time is taken off)."""


def task(n_agents: int, episodes: int) -> dict:
    """One warehouse's POGEMA task, its plan as actions, the plan's costs and glamas's ns per agent-step."""
    gridmap = generate.warehouse(n_agents, bench_many_agents.MAP_SEED)
    plan = prioritized.plan(gridmap)
    return {"agents": n_agents, **export.pogema_task(gridmap, plan), "actions": export.pogema_actions(gridmap, plan),
            "cells": [[list(gridmap.row_col(int(c))) for c in row] for row in plan.cells],
            "sum_of_costs": plan.sum_of_costs, "makespan": plan.makespan,
            "lower_bounds": list(prioritized.lower_bounds(gridmap)),
            "glamas_ns": {name: bench_many_agents.kernel_ns(name, n_agents, episodes, REPEATS, setup=False)[0]
                          for name in TIMED}}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="the JSON file to write (its directory must exist)")
    parser.add_argument("--quick", action="store_true", help="few episodes of glamas: its times then say little")
    args = parser.parse_args(argv)
    if not args.out.parent.is_dir():
        raise UserError(f"{args.out.parent} is not a directory; create it or give another OUT")
    episodes = EPISODES["quick" if args.quick else "full"]
    tasks = [task(n, episodes[n]) for n in AGENTS]
    args.out.write_text(json.dumps({"map_seed": bench_many_agents.MAP_SEED, "tasks": tasks}))
    print(f"wrote {len(tasks)} POGEMA tasks (N = {', '.join(map(str, AGENTS))}) with their plans to {args.out}")


if __name__ == "__main__":
    errors.run(main)
