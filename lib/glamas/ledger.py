"""One ledger of every claim of every experiment, computed from the committed results.

``python -m glamas.ledger`` prints it as Markdown; ``--write`` puts it into README.md between the
ledger markers; ``--check`` exits 1 when README.md's copy is stale. Each registered experiment
with claims (:mod:`glamas.experiments.registry`) gives its rows from the result file the figure
scripts wrote (its configuration checked).
"""

import argparse
import math
import sys
from pathlib import Path

from glamas.experiments import registry
from glamas.experiments.registry import Experiment
from glamas.paths import REPO, RESULTS

SEED = 0
"""The master seed of the committed results (the figure scripts' default)."""
README = REPO / "README.md"
START, END = "<!-- ledger:start -->", "<!-- ledger:end -->"


def claim_rows(experiment: Experiment, results_dir: Path = RESULTS) -> list[dict]:
    """The claim rows of ``experiment`` from its paper-scale result and SEED in ``results_dir``, its
    configuration checked (computed instead, for an experiment whose result is not stored)."""
    config = experiment.paper_scale()
    return experiment.claim_rows(experiment.load(results_dir, config, SEED), config)


def with_claims() -> dict:
    """Every registered experiment that has claims, by name (:mod:`glamas.experiments.registry`)."""
    return {experiment.name: experiment for experiment in registry.experiments() if experiment.claim_rows}


_HEADER = ("| experiment | claim | where | the chapter (paraphrased) | kind | metric, threshold | measured | verdict |\n"
           "|---|---|---|---|---|---|---|---|")


def markdown(*experiments: str, results_dir: Path = RESULTS) -> str:
    """The ledger as a Markdown table: the given experiments' part, or all of it."""
    known = with_claims()
    names = list(experiments or known)
    unknown = [name for name in names if name not in known]
    if unknown:
        raise KeyError(f"no experiment with claims named {unknown}; known: {list(known)}")
    lines = [_HEADER]
    for name in names:
        lines.extend(_row(name, row) for row in claim_rows(known[name], results_dir))
    return "\n".join(lines)


def _row(experiment: str, row: dict) -> str:
    c = row["claim"]
    value = "NaN" if math.isnan(row["value"]) else f"{row['value']:.{c.digits}f}"
    verdict = row["verdict"] if row["verdict"] == "reproduced" else f"**{row['verdict']}**"
    if row.get("why_undecidable"):
        verdict += f" ({row['why_undecidable']})"
    cells = [experiment, f"`{c.id}`", c.where, c.chapter, c.kind, f"`{c.metric}` {c.op} {c.threshold:g}",
             value, verdict]
    return "| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |"


def readme_with(ledger: str, text: str) -> str:
    """``text`` (README.md) with the part between the ledger markers replaced by ``ledger``."""
    if text.count(START) != 1 or text.count(END) != 1 or text.index(START) > text.index(END):
        raise ValueError(f"README.md must hold one {START} ... {END} pair")
    head, rest = text.split(START)
    return f"{head}{START}\n{ledger}\n{END}{rest.split(END, 1)[1]}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--write", action="store_true", help="replace the ledger in README.md")
    mode.add_argument("--check", action="store_true", help="exit 1 if README.md's ledger is stale")
    args = parser.parse_args(argv)
    ledger = markdown()
    if not (args.write or args.check):
        print(ledger)
        return 0
    text = README.read_text()
    updated = readme_with(ledger, text)
    if args.check:
        if updated != text:
            print("README.md's claim ledger is stale: run `make ledger` and commit README.md")
            return 1
        return 0
    README.write_text(updated)
    return 0


if __name__ == "__main__":
    sys.exit(main())
