"""The chapter's claims as data (``data/chapter/*.json``) and their verdicts, computed from results.

Each claim names a metric that an experiment's analysis measures, a comparison and a threshold.
The verdict is the comparison applied to the measured value: nothing here is typed in by hand.
"""

import json
import operator
from dataclasses import dataclass

from glamas.paths import DATA

_OPS = {">": operator.gt, ">=": operator.ge, "<": operator.lt, "<=": operator.le}


@dataclass(frozen=True)
class Claim:
    """One checkable statement of the chapter."""

    id: str
    """Short name, unique within its experiment."""
    where: str
    """Section, equation or figure of the chapter that makes the claim."""
    chapter: str
    """What the chapter says, paraphrased."""
    metric: str
    """Name of the measured quantity (a key of the experiment's measurements)."""
    op: str
    """How the measurement is compared with the threshold: one of > >= < <=."""
    threshold: float
    """The value the measurement is compared with."""
    digits: int = 2
    """Decimals the experiment can resolve; the table rounds to them."""

    def holds(self, value: float) -> bool:
        return bool(_OPS[self.op](value, self.threshold))


def load(experiment: str) -> list[Claim]:
    """The claims of one experiment (a key of ``claims`` in one of the chapter files)."""
    entries = chapter_section_entry("claims", experiment)
    claims = [Claim(**entry) for entry in entries]
    for claim in claims:
        if claim.op not in _OPS:
            raise ValueError(f"claim {claim.id!r} of {experiment}: op must be one of {sorted(_OPS)}, got {claim.op!r}")
    return claims


def parameters(experiment: str) -> dict:
    """The chapter's stated parameters of one experiment: field -> {"value", "where"}."""
    return chapter_section_entry("parameters", experiment)


def chapter_section_entry(kind: str, experiment: str):
    """``kind`` ('claims' or 'parameters') of ``experiment`` from ``data/chapter/*.json``."""
    found = {}
    for path in sorted((DATA / "chapter").glob("*.json")):
        found.update({key: (path, value) for key, value in json.loads(path.read_text()).get(kind, {}).items()})
    if experiment not in found:
        raise KeyError(f"no {kind} for experiment {experiment!r} in {DATA / 'chapter'}; known: {sorted(found)}")
    return found[experiment][1]


def verdicts(claims: list[Claim], measured: dict) -> list[dict]:
    """One row per claim: the claim, the measured value and whether it holds."""
    missing = [c.metric for c in claims if c.metric not in measured]
    if missing:
        raise KeyError(f"the measurements lack {missing}; the analysis must compute every claimed metric")
    return [{"claim": c, "value": float(measured[c.metric]), "holds": c.holds(measured[c.metric])}
            for c in claims]


def table(rows: list[dict]) -> str:
    """A plain-text claim table: claim, chapter's words, measured vs threshold, verdict."""
    lines = []
    for row in rows:
        c = row["claim"]
        verdict = "reproduced" if row["holds"] else "NOT reproduced"
        lines.append(f"[{verdict}] {c.id} ({c.where})\n    chapter:  {c.chapter}\n"
                     f"    measured: {c.metric} = {row['value']:.{c.digits}f}  (claim: {c.op} {c.threshold:g})")
    return "\n".join(lines)
