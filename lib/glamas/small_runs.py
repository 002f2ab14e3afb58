"""A small run of every stored experiment and the digest of its arrays, committed in
``data/small_runs.json``: a check, on any machine, that the kernels give the bits they gave where
the results were computed.

The kernels use IEEE arithmetic without fastmath and call the C library for exp and log, and the
analyses compute what decides a verdict portably (:mod:`glamas.portable`): every committed result
should come out bit for bit on any processor. ``make verify`` proves it for the paper-scale runs
in about an hour (docs/usage.md); these small runs take seconds, so that ``make test`` finds a
processor, a C library or a change of code that gives other bits: its compile step checks them
(``python -m glamas.precompile --check``), and ``tests/test_portable_results.py`` does where
pytest runs alone.

They also decide, by behaviour rather than by syntax, whether a committed result is still what
the code computes. A result records the code that computed it (:mod:`glamas.provenance`), and so
does each small run's digest here. After a change of code, ``--adopt`` recomputes the small run
of every experiment whose committed result the change made stale: where the result and the digest
were recorded with the same code and the small run still gives the committed digest bit for bit,
the change kept the experiment's behaviour, and the result (its arrays untouched) and the digest
are recorded again with the code as it is; where the small run differs, the result stays stale and
the command says how to recompute it. Its limit: a change that shows only at paper scale passes
here, which is what ``make verify`` is for. ``--status`` lists every committed result with what
would make it current and what that costs.

``python -m glamas.small_runs --write`` recomputes them and rewrites the file (after a change that
alters what an experiment computes, with its committed results); ``--check`` compares.
"""

import argparse
import dataclasses
import hashlib
import json
import sys

import numpy as np

from glamas import atomic, errors, provenance, results
from glamas.committed import PYTHON, computing_script, shown
from glamas.errors import UserError
from glamas.experiments import registry
from glamas.paths import DATA, RESULTS

DIGESTS = DATA / "small_runs.json"
SEED = 0
WRITE_MINUTES = 5
"""About how long ``--write`` takes on 2 cores (measured: every small run)."""


def digest(arrays: dict) -> str:
    """sha256 over the arrays by name: each name, dtype, shape and bytes."""
    total = hashlib.sha256()
    for name in sorted(arrays):
        array = np.ascontiguousarray(arrays[name])
        total.update(f"{name}\0{array.dtype.str}\0{array.shape}\0".encode())
        total.update(array.tobytes())
    return total.hexdigest()


def sizes() -> dict:
    """Each stored experiment's small run (:attr:`~glamas.experiments.registry.Experiment.small_run`) by name."""
    return {e.name: e.small_run for e in registry.experiments() if e.stored}


def small_digest(name: str, workers=None) -> str:
    """The digest of experiment ``name``'s small run (:func:`sizes`, master seed :data:`SEED`)."""
    experiment = experiment_named(name)
    small = dict(experiment.small_run)
    config = dataclasses.replace(experiment.configure(small.pop("runs"), small.pop("iterations")), **small)
    return digest(experiment.arrays(experiment.run(config, seed=SEED, workers=workers)))


def small_digests(names: list) -> dict:
    """:func:`small_digest` of each experiment of ``names``, by name, saying on stderr which small
    run is computing (they take minutes together)."""
    found = {}
    for number, name in enumerate(names, 1):
        print(f"small run {number} of {len(names)}: {name}", file=sys.stderr, flush=True)
        found[name] = small_digest(name)
    return found


def committed() -> dict:
    """The committed digests by experiment name."""
    return recorded()["digests"]


def committed_code() -> dict:
    """The record of the code each committed digest was computed with, by experiment name."""
    return recorded().get("code", {})


def recorded() -> dict:
    """What the digests file holds, checked to be what :func:`write` writes: one line naming the
    file and how to make it again otherwise (cut short by a killed writer, say)."""
    try:
        content = json.loads(DIGESTS.read_text())
        damage = None if isinstance(content, dict) else f"a JSON {type(content).__name__} where an object belongs"
    except json.JSONDecodeError as error:
        damage = f"not JSON, cut short or edited ({error.msg}, line {error.lineno})"
    if damage is None and not (isinstance(content.get("digests"), dict) and isinstance(content.get("code", {}), dict)):
        damage = "its digests or records of code are missing"
    if damage:
        raise UserError(f"{shown(DIGESTS)} is damaged ({damage}): restore the committed one with `git checkout -- "
                        f"{shown(DIGESTS)}`, or rewrite it with `{PYTHON} -m glamas.small_runs --write` (about "
                        f"{WRITE_MINUTES} min on 2 cores)")
    return content


def update(change, *, replace_damaged: bool = False) -> None:
    """Rewrite the digests file with ``change(what it holds)`` (with ``replace_damaged``, a damaged
    file holds nothing), read and written under the results' lock and written whole
    (:mod:`glamas.atomic`): two commands recording different experiments at once both keep their
    records, and a killed one leaves the file as it was."""
    with atomic.locked(RESULTS):
        try:
            content = recorded()
        except (UserError, FileNotFoundError):
            if not replace_damaged:
                raise
            content = {}
        atomic.write_text(DIGESTS, json.dumps(change(content), indent=1) + "\n")


def experiment_named(name: str) -> registry.Experiment:
    return next(e for e in registry.experiments() if e.name == name)


def current_code(name: str) -> dict:
    """The record of the code that computes experiment ``name`` now (:func:`glamas.provenance.code_record`)."""
    return provenance.code_record(experiment_named(name).paper_scale())


def write(found: dict) -> None:
    """Rewrite the digests file with the digests ``found`` and the code that computes each now,
    except where a digest is the committed one: its record of code stays, since that code gives the
    same bits, and a committed result it computed stays one that ``--adopt`` can re-record."""
    def rewritten(content):
        digests, code = content.get("digests", {}), content.get("code", {})
        return {"seed": SEED, "sizes": sizes(), "digests": found,
                "code": {name: code[name] if digest == digests.get(name) and name in code else current_code(name)
                         for name, digest in found.items()}}
    update(rewritten, replace_damaged=True)


def stored_record(name: str) -> dict:
    """The provenance record the committed result of ``name`` holds (unchecked against the code)."""
    return results.stored_provenance(experiment_named(name).file(RESULTS))


def recompute_command(name: str) -> str:
    """The commands that recompute ``name``'s committed result with the code as it is and record
    its small run's new digest, with their cost."""
    experiment = experiment_named(name)
    script = computing_script(experiment.file(".").name)
    cost = "" if experiment.recompute_minutes is None else f" (about {experiment.recompute_minutes:g} min on 2 cores)"
    return f"`{PYTHON} paper_figures/{script}.py --rerun`{cost}, then `{PYTHON} -m glamas.small_runs --write`"


def status(name: str) -> tuple[str, str]:
    """('current' | 're-record' | 'recompute', why and what to run) of ``name``'s committed result."""
    experiment = experiment_named(name)
    stored = stored_record(name)
    changed = provenance.mismatch(stored, provenance.record(experiment.paper_scale()))
    if changed is None:
        return "current", "nothing to do"
    same_but_code = provenance.mismatch({**stored, **provenance.current_code(experiment.paper_scale())},
                                        provenance.record(experiment.paper_scale()))
    if same_but_code is not None or stored.get("code") != committed_code().get(name):
        return "recompute", f"{changed}: recompute it with {recompute_command(name)}"
    return "re-record", (f"{changed}: if its small run still gives the committed bits, `{PYTHON} -m "
                         f"glamas.small_runs --adopt {name}` records it with this code (seconds); else recompute it with "
                         f"{recompute_command(name)}")


def adopt(names) -> int:
    """Re-record the committed result and small-run digest of each experiment of ``names`` whose
    small run gives the committed bits with the code as it is (see the module's text); print one
    line per experiment; returns 1 if any is left stale, else 0."""
    left = 0
    for name in names:
        state, why = status(name)
        if state == "recompute":
            print(f"{name}: stale, not re-recorded: {why}")
            left += 1
            continue
        if state == "current":
            print(f"{name}: current")
            continue
        if small_digest(name) != committed()[name]:
            now, then = current_code(name), committed_code()[name]
            modules = sorted(m for m in set(then) | set(now) if then.get(m) != now.get(m))
            print(f"{name}: stale, its small run gives other bits with the changed code "
                  f"({', '.join('glamas/' + m for m in modules[:3])}): recompute it with {recompute_command(name)}")
            left += 1
            continue
        _rerecord(name)
        record_code(name)  # at once: a result and its digest never stay recorded with different code
        print(f"{name}: re-recorded (its small run gives the committed bits)")
    return 1 if left else 0


def _rerecord(name: str) -> None:
    """Save the committed result of ``name`` again, the same arrays (their digests checked) with the
    record of the code as it is."""
    experiment = experiment_named(name)
    path, config = experiment.file(RESULTS), experiment.paper_scale()
    stored = results.stored_config(path)
    seed = json.loads(stored)["fields"].get("seed")
    if stored != results.config_json(config, seed):
        raise UserError(f"{shown(path)} is not the paper-scale result of {name}: recompute it with "
                        f"{recompute_command(name)}")
    results.save(path, config, results.load_unchecked_code(path, config), seed=seed, overwrite=True)


def record_code(name: str) -> None:
    """Record in the digests file that the code as it is computes ``name``'s digest, the other
    records and the digests as they are there now (another command may have changed them)."""
    now = current_code(name)
    update(lambda content: {**content, "code": {**content.get("code", {}), name: now}})


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.small_runs",
                                     description=" ".join(__doc__.split("\n\n")[0].split()))
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--write", action="store_true", help=f"recompute every small run and rewrite {DIGESTS.name}")
    action.add_argument("--check", action="store_true", help=f"recompute every small run and compare with {DIGESTS.name}")
    action.add_argument("--status", action="store_true", help="list every committed result: current, or what "
                        "makes it current and what that costs")
    action.add_argument("--adopt", nargs="*", metavar="EXPERIMENT", help="re-record the committed results the code "
                        "change left stale whose small runs still give the committed bits (all, or those named)")
    args = parser.parse_args(argv)
    if not args.write:
        recorded()  # a damaged file is named before any work (--write replaces it)
    names = list(sizes())
    if args.status:
        for name in names:
            state, why = status(name)
            print(f"{name}: {state}" + ("" if state == "current" else f": {why}"))
        return 0
    if args.adopt is not None:
        unknown = sorted(set(args.adopt) - set(names))
        if unknown:
            raise UserError(f"no stored experiment named {', '.join(unknown)}; the experiments: {', '.join(names)}")
        return adopt(args.adopt or names)
    found = small_digests(names)
    if args.write:
        write(found)
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
