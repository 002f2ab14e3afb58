"""One ledger of every claim of every experiment, computed from the committed results.

``python -m glamas.ledger`` prints it as Markdown; ``--write`` writes it whole to docs/ledger.md
and its count of verdicts into README.md between the verdict markers; ``--check`` exits 1 when
either is stale. Each registered experiment with claims (:mod:`glamas.experiments.registry`)
gives its rows from the result file the figure scripts wrote (its configuration checked).
"""

import argparse
import math
from pathlib import Path

from glamas import claims, errors
from glamas.errors import UserError
from glamas.experiments import registry
from glamas.experiments.registry import Experiment
from glamas.paths import REPO, RESULTS

SEED = 0
"""The master seed of the committed results (the figure scripts' default)."""
README = REPO / "README.md"
"""Holds the count of verdicts (:func:`verdict_count`) between START and END."""
START, END = "<!-- verdicts:start -->", "<!-- verdicts:end -->"
LEDGER = REPO / "docs" / "ledger.md"
"""The ledger's page, generated whole (:func:`page`)."""
LEDGER_LINK = LEDGER.relative_to(README.parent).as_posix()
"""The ledger's page as README.md links to it."""
VERDICTS = (claims.REPRODUCED, claims.NOT_REPRODUCED, claims.UNDECIDABLE)


def paper_result(experiment: Experiment, results_dir: Path = RESULTS):
    """The paper-scale result of ``experiment`` and SEED in ``results_dir``, its configuration
    checked (computed instead, for an experiment whose result is not stored)."""
    return experiment.load(results_dir, experiment.paper_scale(), SEED)


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
    # Every result read before any claim is judged: a missing, stale or damaged file stops the
    # ledger at once, not after the judging of the experiments before it.
    read = [(name, paper_result(known[name], results_dir)) for name in names]
    lines = [_HEADER]
    for name, result in read:
        lines.extend(_row(name, row) for row in known[name].claim_rows(result, known[name].paper_scale()))
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


def page(ledger: str) -> str:
    """docs/ledger.md: a title, what the table is, the table ``ledger``."""
    return ("# Claim ledger\n\n"
            "Every claim of every experiment and its verdict, computed from the committed results in "
            "`data/results/` by `python -m glamas.ledger --write` (`make ledger`): do not edit this "
            "page by hand.\n\n"
            f"{ledger}\n")


def verdict_count(ledger: str) -> str:
    """One line: how many claims the table ``ledger`` holds and how many have each verdict, with
    a link to the ledger's page."""
    rows = [line for line in ledger.splitlines()[2:] if line.startswith("| ")]
    last = [row.removesuffix(" |").rsplit(" | ", 1)[-1].removeprefix("**") for row in rows]
    counts = {verdict: sum(cell.startswith(verdict) for cell in last) for verdict in VERDICTS}
    if sum(counts.values()) != len(rows):
        raise ValueError("a row of the ledger has no verdict of " + ", ".join(VERDICTS))
    parts = ", ".join(f"{n} {verdict.lower()}" for verdict, n in counts.items())
    return f"{len(rows)} claims: {parts} — see [the claim ledger]({LEDGER_LINK})."


def readme_with(count: str, text: str) -> str:
    """``text`` (README.md) with the part between the verdict markers replaced by ``count``."""
    check_markers(text)
    head, rest = text.split(START)
    return f"{head}{START}\n{count}\n{END}{rest.split(END, 1)[1]}"


def check_markers(text: str) -> None:
    """Raise UserError unless ``text`` (README.md) holds the verdict markers once each, in order."""
    if text.count(START) != 1 or text.count(END) != 1 or text.index(START) > text.index(END):
        raise UserError(f"README.md must hold one {START} ... {END} pair, in this order, around the count "
                        "of verdicts; put the two lines back (git diff README.md shows what changed)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.ledger", description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--write", action="store_true", help="write docs/ledger.md and README.md's count of verdicts")
    mode.add_argument("--check", action="store_true", help="exit 1 if docs/ledger.md or README.md's count is stale")
    args = parser.parse_args(argv)
    if not (args.write or args.check):
        print(markdown())
        return 0
    text = README.read_text()
    check_markers(text)  # before the seconds of reading every result and judging every claim
    ledger = markdown()
    wanted = {LEDGER: page(ledger), README: readme_with(verdict_count(ledger), text)}
    if args.check:
        stale = [path for path, content in wanted.items() if not path.is_file() or path.read_text() != content]
        if stale:
            names = " and ".join(path.name for path in stale)
            print(f"the claim ledger in {names} is stale: run `make ledger` and commit the result")
            return 1
        return 0
    LEDGER.parent.mkdir(exist_ok=True)
    for path, content in wanted.items():
        path.write_text(content)
    return 0


if __name__ == "__main__":
    errors.run(main)
