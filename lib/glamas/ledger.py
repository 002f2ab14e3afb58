"""One ledger of every claim of every experiment, computed from the committed results.

``python -m glamas.ledger`` prints it as Markdown; ``--write`` writes it whole to docs/ledger.md
and its count of verdicts into README.md between the verdict markers; ``--check`` exits 1 when
either is stale. Each experiment's rows come from one entry of :data:`EXPERIMENTS`: a function of
the results directory that reads the result file the figure scripts wrote (its configuration
checked) and returns the experiment's claim rows.
"""

import argparse
import math
import sys
from pathlib import Path

from glamas import claims
from glamas.experiments import and_network, gridworld, gridworld_optimum, related_work, scaling, single_gla
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


def _load(results_dir: Path, experiment):
    """``(result, config)``: the result of ``experiment`` at paper scale and SEED in ``results_dir``,
    its configuration checked."""
    config = experiment.paper_scale()
    return experiment.load(results_dir, config, SEED), config


def _fig5(results_dir: Path) -> list[dict]:
    return single_gla.claim_rows(_load(results_dir, single_gla.FIG5)[0])


def _fig6(results_dir: Path) -> list[dict]:
    return single_gla.encoding_claim_rows(_load(results_dir, single_gla.FIG6)[0])


def _fig7(results_dir: Path) -> list[dict]:
    return and_network.claim_rows(_load(results_dir, and_network.FIG7)[0])


def _fig7_sweep(results_dir: Path) -> list[dict]:
    return and_network.sweep_claim_rows(_load(results_dir, and_network.FIG7_SWEEP)[0])


def _optimum(results_dir: Path) -> list[dict]:
    """Dynamic programming on the map takes a second: computed, not stored."""
    return gridworld_optimum.claim_rows(gridworld_optimum.run(gridworld_optimum.GridworldOptimumConfig()))


def _gridworld(results_dir: Path) -> list[dict]:
    return gridworld.claim_rows(_load(results_dir, gridworld.STUDY)[0])


def _related_work(results_dir: Path) -> list[dict]:
    return related_work.claim_rows(*_load(results_dir, related_work.STUDY))


def _scaling(results_dir: Path) -> list[dict]:
    return scaling.claim_rows(_load(results_dir, scaling.STUDY)[0])


EXPERIMENTS = {
    "single_gla": _fig5,
    "state_encoding": _fig6,
    "and_network": _fig7,
    "and_network_sweep": _fig7_sweep,
    "gridworld_optimum": _optimum,
    "gridworld": _gridworld,
    "related_work": _related_work,
    "scaling": _scaling,
}
"""Experiment (a key of the claims in data/chapter/*.json) -> function(results dir) -> claim rows."""

_HEADER = ("| experiment | claim | where | the chapter (paraphrased) | kind | metric, threshold | measured | verdict |\n"
           "|---|---|---|---|---|---|---|---|")


def markdown(*experiments: str, results_dir: Path = RESULTS) -> str:
    """The ledger as a Markdown table: the given experiments' part, or all of it."""
    names = list(experiments or EXPERIMENTS)
    unknown = [name for name in names if name not in EXPERIMENTS]
    if unknown:
        raise KeyError(f"no ledger entry for {unknown}; known: {list(EXPERIMENTS)}")
    lines = [_HEADER]
    for name in names:
        lines.extend(_row(name, row) for row in EXPERIMENTS[name](results_dir))
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
    if text.count(START) != 1 or text.count(END) != 1 or text.index(START) > text.index(END):
        raise ValueError(f"README.md must hold one {START} ... {END} pair")
    head, rest = text.split(START)
    return f"{head}{START}\n{count}\n{END}{rest.split(END, 1)[1]}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--write", action="store_true", help="write docs/ledger.md and README.md's count of verdicts")
    mode.add_argument("--check", action="store_true", help="exit 1 if docs/ledger.md or README.md's count is stale")
    args = parser.parse_args(argv)
    ledger = markdown()
    if not (args.write or args.check):
        print(ledger)
        return 0
    text = README.read_text()
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
    sys.exit(main())
