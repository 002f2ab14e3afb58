"""The POGEMA half of the POGEMA cross-check (``make pogema-crosscheck``): runs in POGEMA's own
virtual environment (benchmarks/requirements-pogema.txt; POGEMA pins numpy, gymnasium and
pydantic releases that glamas's do not meet) and imports nothing of glamas.

For each task benchmarks/pogema_tasks.py wrote (a glamas warehouse and its prioritized plan):
1. the plan replayed in POGEMA's environment, agents leaving at their target (``on_target=
   'finish'``) and its soft collisions (a move into a taken cell or a swap is undone), with every
   agent's cell checked against the plan's at every step: POGEMA's success of all agents (CSR),
   its share of agents in (ISR), and the sum of costs and makespan counted from the agents' steps,
   beside the plan's own;
2. POGEMA's environment step timed on random actions (its observations of radius 5 included, as
   its benchmark runs it), in nanoseconds per agent-step of CPU time, beside glamas's cost per
   agent-step of the independent learners and 2observe learning on the same map, and the ratio.

Usage: python benchmarks/pogema_replay.py TASKS.json
"""

import argparse
import json
import sys
import time

import numpy as np
from pogema import GridConfig, pogema_v0

TIMED_AGENT_STEPS = 200_000
"""Agent-steps of POGEMA's environment timed per task (at least 20 steps)."""
TIMING_EPISODE = 256
"""Steps of an episode of random actions before POGEMA resets it."""


def environment(task: dict, max_steps: int):
    """POGEMA's environment on the task's grid, starts and targets."""
    config = GridConfig(map=task["map"], agents_xy=task["agents_xy"], targets_xy=task["targets_xy"], seed=0,
                        on_target="finish", collision_system="soft", obs_radius=5, max_episode_steps=max_steps)
    return pogema_v0(grid_config=config)


def replay(task: dict) -> dict:
    """Play the plan's actions; count the steps until each agent leaves and the steps on which an
    agent's cell is not the plan's."""
    env = environment(task, task["makespan"] + 1)
    env.reset(seed=0)
    n, steps, off_plan, metrics = task["agents"], [None] * task["agents"], 0, {}
    for t, actions in enumerate(task["actions"]):
        _, _, terminated, truncated, infos = env.step(list(actions))
        cells = env.unwrapped.grid.get_agents_xy(ignore_borders=True)
        for i in range(n):
            if steps[i] is None:
                off_plan += list(cells[i]) != task["cells"][t + 1][i]
                if not infos[i]["is_active"]:
                    steps[i] = t + 1
        metrics.update(infos[0].get("metrics", {}))
        if all(terminated) or all(truncated):
            break
    arrived = [s for s in steps if s is not None]
    return {"CSR": metrics.get("CSR", float(len(arrived) == n)), "ISR": metrics.get("ISR", len(arrived) / n),
            "sum_of_costs": sum(arrived) if len(arrived) == n else None,
            "makespan": max(arrived) if len(arrived) == n else None, "off_plan": off_plan}


def step_ns(task: dict) -> float:
    """POGEMA's CPU time per agent-step of random actions (episodes of TIMING_EPISODE steps)."""
    env, rng = environment(task, TIMING_EPISODE), np.random.default_rng(0)
    n = task["agents"]
    n_steps = max(20, TIMED_AGENT_STEPS // n)
    actions = rng.integers(0, 5, size=(n_steps, n)).tolist()
    env.reset(seed=0)
    seconds = 0.0
    for row in actions:
        start = time.thread_time()
        _, _, terminated, truncated, _ = env.step(row)
        seconds += time.thread_time() - start
        if all(terminated) or all(truncated):
            env.reset(seed=0)
    return seconds / (n_steps * n) * 1e9


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tasks", help="the JSON file benchmarks/pogema_tasks.py wrote")
    args = parser.parse_args(argv)
    try:
        with open(args.tasks) as f:
            tasks = json.load(f)["tasks"]
    except (OSError, ValueError, KeyError) as error:
        print(f"error: cannot read the tasks of {args.tasks} ({error}); write them with "
              "python -m benchmarks.pogema_tasks FILE", file=sys.stderr)
        return 2
    print("glamas's prioritized plans replayed in POGEMA (on_target='finish', soft collisions)")
    print(f"{'N':>5s} {'CSR':>5s} {'ISR':>6s} {'SoC (POGEMA)':>13s} {'SoC (plan)':>11s} {'makespan':>9s} "
          f"{'(plan)':>7s} {'cells off the plan':>19s}")
    for task in tasks:
        r = replay(task)
        print(f"{task['agents']:5d} {r['CSR']:5.2f} {r['ISR']:6.2f} {str(r['sum_of_costs']):>13s} "
              f"{task['sum_of_costs']:11d} {str(r['makespan']):>9s} {task['makespan']:7d} {r['off_plan']:19d}")
    print("\nns per agent-step (CPU time): POGEMA's environment step on random actions, observations of "
          "radius 5 included; glamas's kernels, learning included (without the run's setup)")
    names = list(tasks[0]["glamas_ns"])
    print(f"{'N':>5s} {'POGEMA':>9s}" + "".join(f"{name:>14s}" for name in names)
          + "".join(f"{'POGEMA / ' + name:>26s}" for name in names))
    for task in tasks:
        pogema = step_ns(task)
        glamas = [task["glamas_ns"][name] for name in names]
        print(f"{task['agents']:5d} {pogema:9.0f}" + "".join(f"{ns:14.1f}" for ns in glamas)
              + "".join(f"{pogema / ns:25.0f}x" for ns in glamas))
    return 0


if __name__ == "__main__":
    sys.exit(main())
