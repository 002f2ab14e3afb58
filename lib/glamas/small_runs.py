"""A small run of every stored experiment and the digest of its arrays, committed in
``data/small_runs.json``: a check, on any machine, that the kernels give the bits they gave where
the results were computed.

The kernels use IEEE arithmetic without fastmath and call the C library for exp and log, and the
analyses compute what decides a verdict portably (:mod:`glamas.portable`): every committed result
should come out bit for bit on any processor. ``make verify`` proves it for the paper-scale runs
in ten minutes; these small runs take seconds, so that ``make test`` finds a processor, a C library
or a change of code that gives other bits: its compile step checks them (``python -m
glamas.precompile --check``), and ``tests/test_portable_results.py`` does where pytest runs alone.

``python -m glamas.small_runs --write`` recomputes them and rewrites the file (after a change that
alters what an experiment computes, with its committed results); ``--check`` compares.
"""

import argparse
import dataclasses
import hashlib
import json

import numpy as np

from glamas import errors
from glamas.experiments import registry
from glamas.paths import DATA

DIGESTS = DATA / "small_runs.json"
SIZES = {"single_gla": (2, 2000, {}), "state_encoding": (2, 2000, {}), "and_network": (2, 2000, {}),
         "and_network_sweep": (2, 2000, {}), "gridworld": (2, 300, {}), "fig10_readings": (2, 300, {}),
         "related_work": (2, 300, {}),
         "scaling": (1, 100, {"agents": (2, 3), "evaluation_episodes": 5}),
         "many_agents": (1, 10, {"agents": (2, 8, 32), "evaluation_episodes": 2, "max_steps": 200}),
         "benchmark_maps": (2, 100, {"evaluation_episodes": 5, "memory_budget_gib": 0.1}),
         "benchmark_maps_field": (2, 100, {"evaluation_episodes": 5, "memory_budget_gib": 0.1,
                                           "maps": ("isr", "tunnel_to_goal_4")}),
         "benchmark_maps_budgets": (1, 100, {"evaluation_episodes": 5, "memory_budget_gib": 0.1,
                                             "maps": ("isr", "tunnel_to_goal_4")}),
         "warehouses": (2, 100, {"agents": (3, 8), "evaluation_episodes": 2, "max_steps": 200}),
         "crowd": (1, 5, {})}
"""Each experiment's small run: its ``configure(runs, iterations)`` with these fields replaced, so
that every kernel the experiment runs (the N-agent ones included) runs, in a second or two (the
map benchmark's budget leaves out the joint learners' tables of TunnelToGoal with 3 agents, 85 MB
a run, which its evaluations would copy for most of the time). The benchmark under the field's
formulation and its budget axis run the same kernels on a two-agent map and on TunnelToGoal 4
only: the exact plans of TunnelToGoal 3, which the benchmark's own small run computes, took
most of their time."""
SEED = 0


def digest(arrays: dict) -> str:
    """sha256 over the arrays by name: each name, dtype, shape and bytes."""
    total = hashlib.sha256()
    for name in sorted(arrays):
        array = np.ascontiguousarray(arrays[name])
        total.update(f"{name}\0{array.dtype.str}\0{array.shape}\0".encode())
        total.update(array.tobytes())
    return total.hexdigest()


def small_digest(name: str, workers=None) -> str:
    """The digest of experiment ``name``'s small run (:data:`SIZES`, master seed :data:`SEED`)."""
    experiment = next(e for e in registry.experiments() if e.name == name)
    runs, iterations, fields = SIZES[name]
    config = dataclasses.replace(experiment.configure(runs, iterations), **fields)
    return digest(experiment.arrays(experiment.run(config, seed=SEED, workers=workers)))


def committed() -> dict:
    """The committed digests by experiment name."""
    return json.loads(DIGESTS.read_text())["digests"]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.small_runs",
                                     description=" ".join(__doc__.split("\n\n")[0].split()))
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--write", action="store_true", help=f"recompute every small run and rewrite {DIGESTS.name}")
    action.add_argument("--check", action="store_true", help=f"recompute every small run and compare with {DIGESTS.name}")
    args = parser.parse_args(argv)
    found = {name: small_digest(name) for name in SIZES}
    if args.write:
        sizes = {name: {"runs": runs, "iterations": iterations, **fields} for name, (runs, iterations, fields) in SIZES.items()}
        DIGESTS.write_text(json.dumps({"seed": SEED, "sizes": sizes, "digests": found}, indent=1) + "\n")
        print(f"wrote {len(found)} digests to {DIGESTS}")
        return 0
    return report(found)


def report(found: dict) -> int:
    """Print which of the digests ``found`` (by experiment) differ from the committed ones; the
    exit status: 1 if any does, else 0."""
    differing = [name for name, value in found.items() if committed().get(name) != value]
    for name in differing:
        print(f"{name}: its small run gives other bits than {DIGESTS.name} records: if the code changed what "
              "the experiment computes, recompute its committed results and run `python -m glamas.small_runs "
              "--write`; otherwise this machine computes differently from the one that made the results")
    print(f"{len(differing)} of {len(found)} small runs differ" if differing else f"all {len(found)} small runs agree")
    return 1 if differing else 0


if __name__ == "__main__":
    errors.run(main)
