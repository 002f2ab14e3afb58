"""One ledger of every claim of every experiment, computed from the committed results.

``python -m glamas.ledger`` prints it as Markdown; ``--write`` writes it whole to docs/ledger.md
and its summary into README.md between the verdict markers (the counts by the claims' source, the
chapter's claims that do not reproduce, and the table of the chapter's figures with their
verdicts); ``--check`` exits 1 when either is stale. Each registered experiment with claims
(:mod:`glamas.experiments.registry`) gives its rows from the result file the figure scripts wrote
(its configuration checked).
"""

import argparse
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

from glamas import atomic, claims, errors
from glamas.errors import UserError
from glamas.experiments import registry
from glamas.experiments.registry import Experiment
from glamas.paths import REPO, RESULTS

README = REPO / "README.md"
"""Holds the summary of verdicts (:func:`summary`) between START and END."""
START, END = "<!-- verdicts:start -->", "<!-- verdicts:end -->"
LEDGER = REPO / "docs" / "ledger.md"
"""The ledger's page, generated whole (:func:`page`)."""
LEDGER_LINK = LEDGER.relative_to(README.parent).as_posix()
"""The ledger's page as README.md links to it."""
VERDICTS = (claims.REPRODUCED, claims.NOT_REPRODUCED, claims.UNDECIDABLE, claims.TURNS)
SOURCES = {"chapter": "the chapter's own", "inferred": "inferred by us", "field": "from the field's papers"}
"""How the summary names the claims of each kind (:data:`glamas.claims.KINDS`)."""


@dataclass(frozen=True)
class Figure:
    """One of the chapter's figures (or a result it states in its text) as the README's table
    lists it, with the claims that test it."""

    name: str
    """The chapter's name for it, e.g. 'Fig. 11'."""
    says: str
    """What the chapter says it shows, paraphrased."""
    experiment: str
    """The experiment whose claims test it."""
    where: str
    """A pattern of the claims' ``where`` that places a claim on this figure."""
    images: tuple
    """The figure scripts that draw it (their PNG in paper_figures/output)."""
    notebook: str
    """The notebook that reads it."""


FIGURES = (
    Figure("Fig. 5", "one GLA per agent learns lines that split the line world into regions, and "
           "each region's most probable joint action is its rewarded one", "single_gla", r"Fig\. 5",
           ("fig5",), "01_single_gla"),
    Figure("Fig. 6", "the context matters: the deictic distance does best, the absolute distance clearly "
           "worst", "state_encoding", r"Fig\. 6", ("fig6",), "02_state_encoding"),
    Figure("Fig. 7", "two GLAs joined by AND per agent approximate the inside of a parabola",
           "and_network", r"Fig\. 7", ("fig7a", "fig7b"), "03_and_network_parabola"),
    Figure("Sec. 4.2 (text)", "a higher reward outside the parabola traps runs in 'R everywhere', and the "
           "outcome depends on the initialisation", "and_network_sweep", r"Sec\. 4\.2", ("fig7_sweep",),
           "03_and_network_parabola"),
    Figure("Fig. 9", "selfish shortest paths collide at the tunnel's entrance", "gridworld_optimum",
           r"Fig\. 9", ("fig9", "fig9_optimum"), "04a_gridworld_optimum"),
    Figure("Alg. 4, Fig. 10", "2observe's GLAs learn to coordinate only where the agents could collide",
           "gridworld", r"5\.1", ("fig10",), "04_gridworld_2observe"),
    Figure("Fig. 11", "2observe needs fewer steps than the independent and MMDP learners, converges faster, "
           "earns almost the MMDP's reward", "gridworld",
           r"Fig\. 11", ("fig11a", "fig11b"), "04_gridworld_2observe"),
    Figure("Fig. 12", "MMDP and 2observe reach zero collisions fast, independent learners about 3 per "
           "episode; 2observe coordinates about 4 times per episode", "gridworld", r"Fig\. 12",
           ("fig12a", "fig12b"), "04_gridworld_2observe"),
    Figure("Table 1", "tables grow linearly with the agents for independent learners, exponentially for the "
           "MMDP; 2observe's are the size of the independent learners'", "scaling", r"Table 1|Sec\. 3\.1",
           ("scaling_sizes",), "05_scaling"),
)
"""The chapter's figures in the README's table, in the chapter's order."""


def paper_result(experiment: Experiment, results_dir: Path = RESULTS):
    """The paper-scale result of ``experiment`` and the committed seed (:data:`registry.SEED`) in
    ``results_dir``, its configuration checked (computed instead, for an experiment whose result is
    not stored)."""
    return experiment.load(results_dir, experiment.paper_scale(), registry.SEED)


def with_claims() -> dict:
    """Every registered experiment that has claims, by name (:mod:`glamas.experiments.registry`)."""
    return {experiment.name: experiment for experiment in registry.experiments() if experiment.claim_rows}


def rows(*experiments: str, results_dir: Path = RESULTS) -> list[tuple[str, dict]]:
    """(experiment, verdict row) of every claim of the given experiments, or of all."""
    known = with_claims()
    names = list(experiments or known)
    unknown = [name for name in names if name not in known]
    if unknown:
        raise KeyError(f"no experiment with claims named {unknown}; known: {list(known)}")
    # Every result read before any claim is judged: a missing, stale or damaged file stops the
    # ledger at once, not after the judging of the experiments before it.
    read = [(name, paper_result(known[name], results_dir)) for name in names]
    return [(name, row) for name, result in read
            for row in known[name].claim_rows(result, known[name].paper_scale())]


def show(*experiments: str, results_dir: Path = RESULTS):
    """The given experiments' claims as a notebook shows them: a rendered table of claim, source,
    measured value and verdict (:func:`glamas.claims.show`)."""
    return claims.show([row for _, row in rows(*experiments, results_dir=results_dir)])


_HEADER = ("| experiment | claim | where | the claim (paraphrased) | source | rule | metric, threshold | measured | "
           "points | verdict |\n|---|---|---|---|---|---|---|---|---|---|")


def markdown(*experiments: str, results_dir: Path = RESULTS) -> str:
    """The ledger as a Markdown table: the given experiments' part, or all of it."""
    return table(rows(*experiments, results_dir=results_dir))


def table(ledger_rows: list[tuple[str, dict]]) -> str:
    """The ledger's Markdown table of ``ledger_rows`` (:func:`rows`)."""
    return "\n".join([_HEADER] + [_row(experiment, row) for experiment, row in ledger_rows])


def _row(experiment: str, row: dict) -> str:
    c = row["claim"]
    verdict = claims.verdict_text(row)
    if row["verdict"] != claims.REPRODUCED:
        verdict = f"**{verdict}**"
    thresholds = " or ".join(f"{t:g}" for t in c.thresholds)
    cells = [experiment, f"`{c.id}`", c.where, c.chapter, c.label, f"[`{c.rule}`](verdicts.md)",
             f"`{c.metric}` {c.op} {thresholds}", claims.value_text(row["value"], c.digits), claims.agreement(row),
             verdict]
    return "| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |"


def page(ledger: str) -> str:
    """docs/ledger.md: a title, what the table is, the table ``ledger``."""
    return ("# Claim ledger\n\n"
            "Every claim of every experiment and its verdict, computed from the committed results in "
            "`data/results/` by `python -m glamas.ledger --write` (`make ledger`) at every point of the claim's "
            "multiverse (its readings, its rule's measurement choices and thresholds: [the rule book](verdicts.md)), "
            "the measured value at the default point, how many points hold, and the verdict: do not edit this "
            "page by hand.\n\n"
            f"{ledger}\n")


def _count(kind_rows: list[dict]) -> str:
    """'20 reproduced, 2 not reproduced, 1 undecidable, 4 turn on a reading or choice'."""
    n = {verdict: sum(row["verdict"] == verdict for row in kind_rows) for verdict in VERDICTS}
    return (f"{n[claims.REPRODUCED]} reproduced, {n[claims.NOT_REPRODUCED]} not reproduced, "
            f"{n[claims.UNDECIDABLE]} undecidable, {n[claims.TURNS]} turn on a reading or choice")


def summary(ledger_rows: list[tuple[str, dict]]) -> str:
    """README.md's verdicts: the counts by source, what the verdicts mean (MARKS), the chapter's
    claims that do not simply reproduce named, and the table of the chapter's figures (:data:`FIGURES`)."""
    by_kind = {kind: [row for _, row in ledger_rows if row["claim"].kind == kind] for kind in claims.KINDS}
    lines = [f"**{len(ledger_rows)} claims**, by who makes them ([the claim ledger]({LEDGER_LINK}) has each "
             "with its metric and threshold):", "",
             *textwrap.wrap(MARKS, WIDTH), ""]
    lines += [f"- {SOURCES[kind]}: {len(kind_rows)}; {_count(kind_rows)}" for kind, kind_rows in by_kind.items()
              if kind_rows]
    lines.append("")
    notable = [row for row in by_kind["chapter"] if row["verdict"] != claims.REPRODUCED]
    if notable:
        lines.append("The chapter's claims that do not simply reproduce:")
        lines += [line for row in notable for line in textwrap.wrap(
            f"- {_without_closing_remark(row['claim'].chapter)} ({row['claim'].where}): {claims.verdict_text(row)}, "
            f"measured {claims.measured_text(row)}.", WIDTH, subsequent_indent="  ", break_on_hyphens=False)]
        lines.append("")
    lines += ["| figure | the chapter says (paraphrased) | verdict of its claims | notebook |", "|---|---|---|---|"]
    lines += [_figure_row(figure, ledger_rows) for figure in FIGURES]
    return "\n".join(lines)


MARKS = ("A claim is *reproduced* or *NOT reproduced* only where every point of its multiverse agrees (every "
         "reading of its setting, every measurement choice and threshold its [rule](docs/verdicts.md) admits); "
         "*turns on a reading or choice* gives how many points hold and what moves the verdict; *undecidable* "
         "is a claim no point decides.")
"""The sentence of the README's summary that says what the verdicts mean."""
WIDTH = 100
"""The width the summary's prose is wrapped to (a table's rows are not)."""


def _without_closing_remark(text: str) -> str:
    """``text`` without a parenthesis that closes it (a claim's threshold, said in the ledger)."""
    return re.sub(r"\s*\([^()]*\)$", "", text)


def on_figure(figure: Figure, ledger_rows: list[tuple[str, dict]]) -> list[dict]:
    """The rows of the chapter's own and our inferred claims (not those read from another
    source) that test ``figure``."""
    return [row for experiment, row in ledger_rows
            if experiment == figure.experiment and not row["claim"].source
            and re.search(figure.where, row["claim"].where)]


def _figure_row(figure: Figure, ledger_rows: list[tuple[str, dict]]) -> str:
    tested = on_figure(figure, ledger_rows)
    parts = []
    for kind in ("chapter", "inferred"):
        kind_rows = [row for row in tested if row["claim"].kind == kind]
        if kind_rows:
            held = sum(row["verdict"] == claims.REPRODUCED for row in kind_rows)
            turning = sum(row["verdict"] == claims.TURNS for row in kind_rows)
            note = f" ({turning} {'turns' if turning == 1 else 'turn'} on a choice)" if turning else ""
            claims_word = "claim" if len(kind_rows) == 1 else "claims"
            parts.append(f"{held} of {len(kind_rows)} {kind} {claims_word} reproduced{note}")
    verdict = "; ".join(parts) if parts else "no claim"
    images = ", ".join(f"[{image}](paper_figures/output/{image}.png)" for image in figure.images)
    return (f"| {figure.name} ({images}) | {figure.says} | {verdict} | "
            f"[{figure.notebook[:3].rstrip('_')}](notebooks/{figure.notebook}.ipynb) |")


def readme_with(block: str, text: str) -> str:
    """``text`` (README.md) with the part between the verdict markers replaced by ``block``."""
    check_markers(text)
    head, rest = text.split(START)
    return f"{head}{START}\n{block}\n{END}{rest.split(END, 1)[1]}"


def check_markers(text: str) -> None:
    """Raise UserError unless ``text`` (README.md) holds the verdict markers once each, in order."""
    if text.count(START) != 1 or text.count(END) != 1 or text.index(START) > text.index(END):
        raise UserError(f"README.md must hold one {START} ... {END} pair, in this order, around the count "
                        "of verdicts; put the two lines back (git diff README.md shows what changed)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.ledger", description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--write", action="store_true", help="write docs/ledger.md and README.md's summary of verdicts")
    mode.add_argument("--check", action="store_true", help="exit 1 if docs/ledger.md or README.md's summary is stale")
    args = parser.parse_args(argv)
    if not (args.write or args.check):
        print(markdown())
        return 0
    text = README.read_text()
    check_markers(text)  # before the seconds of reading every result and judging every claim
    ledger_rows = rows()
    wanted = {LEDGER: page(table(ledger_rows)), README: readme_with(summary(ledger_rows), text)}
    if args.check:
        stale = [path for path, content in wanted.items() if not path.is_file() or path.read_text() != content]
        if stale:
            names = " and ".join(path.name for path in stale)
            print(f"the claim ledger in {names} is stale: run `make ledger` and commit the result")
            return 1
        return 0
    LEDGER.parent.mkdir(exist_ok=True)
    with atomic.locked(RESULTS):  # the shared records' lock: README.md read again, written whole
        atomic.write_text(LEDGER, wanted[LEDGER])
        atomic.write_text(README, readme_with(summary(ledger_rows), README.read_text()))
    return 0


if __name__ == "__main__":
    errors.run(main)
