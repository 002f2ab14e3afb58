"""Whether the small runs see a change of behaviour: each mutation of a kernel below (a reward, a
learning rate, a tie rule, a bounce, ...) is made in a copy of the package, and there the small
run of every experiment whose result records the mutated module (glamas.provenance) is computed
again and compared with the committed digest (data/small_runs.json). A small run that gives the
committed bits after a mutation would let ``python -m glamas.small_runs --adopt`` re-record a
result the mutation changed, if the experiment's paper-scale run takes the mutated path.

``python -m benchmarks.small_run_mutations`` (``make mutations``); each mutation compiles its
experiments' kernels afresh, in all about 18 minutes on 2 cores. Prints one row per mutation: the
experiments whose small run changed, and those whose small run did not.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import NamedTuple

from glamas import errors, small_runs, sources
from glamas.paths import REPO


class Mutation(NamedTuple):
    module: str
    """The module's path in the package."""
    old: str
    """Text found exactly once in it."""
    new: str
    """What replaces it."""
    what: str
    """The change, in words."""


MUTATIONS = (
    Mutation("gridworld/rules.py", "return payoffs.bump if bump else payoffs.move",
             "return payoffs.move if bump else payoffs.move", "a bump pays a move's reward"),
    Mutation("gridworld/rules.py", "penalty = payoffs.collision\n", "penalty = 0.5 * payoffs.collision\n",
             "half the collision penalty among three or more acting agents (rules.step_indexed)"),
    Mutation("gridworld/rules.py", "new_cells[a] = cells[a] if bounce == BOUNCE_PREVIOUS else starts[a]",
             "new_cells[a] = starts[a] if bounce == BOUNCE_PREVIOUS else cells[a]",
             "a collision among three or more acting agents bounces to the start (rules.step_indexed)"),
    Mutation("gridworld/rules.py", "(cell_i, cell_j) if bounce == BOUNCE_PREVIOUS else (start_i, start_j)",
             "(start_i, start_j) if bounce == BOUNCE_PREVIOUS else (cell_i, cell_j)",
             "a collision of two acting agents bounces to the start (rules.step_pair)"),
    Mutation("qlearning.py", "q[s, a] = (1.0 - alpha) * q[s, a] + alpha * target",
             "q[s, a] = (1.0 - 0.9 * alpha) * q[s, a] + 0.9 * alpha * target", "a Q-learning rate 0.9 alpha"),
    Mutation("qlearning.py", "pick = 0 if ties == 1 else rng.integer(state, ties)", "pick = 0",
             "greedy ties go to the first best action, without a draw"),
    Mutation("gla.py", "u[j, k] += learning_rate * beta * gradient", "u[j, k] += 0.9 * learning_rate * beta * gradient",
             "a GLA learning rate 0.9 lambda (Eq. 13)"),
    Mutation("lineworld.py", "        return 1.0\n    return 0.0", "        return 0.9\n    return 0.0",
             "the line world's reward 0.9 instead of 1"),
    Mutation("learners/two_observe.py", "return beta - (penalty_per_cell * delta if both & (not need) else 0.0)",
             "return beta - (0.5 * penalty_per_cell * delta if both & (not need) else 0.0)",
             "2observe's coordination penalty per cell halved"),
    Mutation("learners/cq.py", "q_aug[s, other, a] += alpha * (target - q_aug[s, other, a])",
             "q_aug[s, other, a] += 0.9 * alpha * (target - q_aug[s, other, a])",
             "CQ-learning's augmented update at 0.9 alpha"),
    Mutation("learners/sparse_maq.py", "target = r if reached[i] else r + gamma * after[i]",
             "target = r if reached[i] else r + 0.9 * gamma * after[i]", "sparse MAQ's discount 0.9 gamma"),
)

DIGESTS = """
import json, sys
from glamas import small_runs
print(json.dumps({name: small_runs.small_digest(name) for name in sys.argv[1:]}))
"""


def recording(module: str) -> list[str]:
    """The experiments whose result records ``module``, as the code is."""
    return [name for name in small_runs.sizes() if module in small_runs.current_code(name)]


def mutated_digests(mutation: Mutation, names: list[str], scratch: Path) -> dict:
    """The small runs' digests of ``names`` in a copy of the repository's code and maps with ``mutation`` made."""
    shutil.copytree(REPO / "lib", scratch / "lib", ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    shutil.copytree(REPO / "data", scratch / "data", ignore=shutil.ignore_patterns("results"))
    path = scratch / "lib" / sources.PACKAGE.name / mutation.module
    text = path.read_text()
    if text.count(mutation.old) != 1:
        raise errors.UserError(f"{mutation.module}: the text to mutate is found {text.count(mutation.old)} times, "
                               "not once: update MUTATIONS in benchmarks/small_run_mutations.py")
    path.write_text(text.replace(mutation.old, mutation.new))
    env = {**os.environ, "PYTHONPATH": str(scratch / "lib"), "NUMBA_CACHE_DIR": str(scratch / "cache")}
    out = subprocess.run([sys.executable, "-c", DIGESTS, *names], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def check(mutation: Mutation) -> tuple[list, list]:
    """(experiments whose small run changed, experiments whose small run did not) under ``mutation``."""
    names = recording(mutation.module)
    with tempfile.TemporaryDirectory() as scratch:
        digests = mutated_digests(mutation, names, Path(scratch))
    committed = small_runs.committed()
    return ([name for name in names if digests[name] != committed[name]],
            [name for name in names if digests[name] == committed[name]])


def main():
    print(f"{'mutation':90s} caught by the small runs of / missed by")
    with ThreadPoolExecutor(2) as pool:  # each check runs in its own process
        for mutation, (caught, missed) in zip(MUTATIONS, pool.map(check, MUTATIONS)):
            print(f"{mutation.module + ': ' + mutation.what:90s} {', '.join(caught) or '-'} / {', '.join(missed) or '-'}")


if __name__ == "__main__":
    errors.run(main)
