"""The chapter's claims as data (``data/chapter/*.json``) and their verdicts, computed from results.

Each claim names a metric that an experiment's analysis measures, a comparison and a threshold.
The verdict is the comparison applied to the measured value: nothing here is typed in by hand.
A claim is of one of three kinds: what the chapter says, what we infer from it (our reading of a
lost figure, or a consequence we derive), or what the sparse-interaction literature reports on the
maps it shares with the chapter; ``why`` says which sentence it tests and why the metric measures it.
"""

import json
import math
import operator
from dataclasses import dataclass, fields

from glamas.errors import UserError
from glamas.paths import DATA

_OPS = {">": operator.gt, ">=": operator.ge, "<": operator.lt, "<=": operator.le}
KINDS = ("chapter", "inferred", "field")
REPRODUCED, NOT_REPRODUCED, UNDECIDABLE = "reproduced", "NOT reproduced", "undecidable"
WHY_UNDECIDABLE = ":why_undecidable"
"""Suffix of the measurements key (``metric + WHY_UNDECIDABLE``) that says why a metric is NaN."""


@dataclass(frozen=True)
class Claim:
    """One checkable statement of the chapter."""

    id: str
    """Short name, unique within its experiment."""
    where: str
    """Section, equation or figure of the chapter that makes the claim."""
    chapter: str
    """What the chapter says, paraphrased."""
    kind: str
    """'chapter' (the chapter says it), 'inferred' (our reading, or a consequence we derive) or
    'field' (a result the sparse-interaction literature reports, its source in ``where``)."""
    why: str
    """Which sentence of the chapter the claim tests and why the metric and threshold measure it."""
    metric: str
    """Name of the measured quantity (a key of the experiment's measurements)."""
    op: str
    """How the measurement is compared with the threshold: one of > >= < <=."""
    threshold: float
    """The value the measurement is compared with."""
    digits: int = 2
    """Decimals the experiment can resolve; the table rounds to them."""
    source: str = ""
    """The work a claim of another source comes from (a 'field' claim's paper, or the paper an
    'inferred' claim about a related method reads); empty for the chapter's own."""

    @property
    def label(self) -> str:
        """Who makes the claim, as a reader should see it: 'the chapter', 'inferred by us' (from a
        source, where it reads one) or the field's paper."""
        if self.kind == "chapter":
            return "the chapter"
        if self.kind == "field":
            return self.source
        return f"inferred by us from {self.source}" if self.source else "inferred by us"

    def holds(self, value: float) -> bool:
        return bool(_OPS[self.op](value, self.threshold))

    def verdict(self, value: float) -> str:
        """'reproduced', 'NOT reproduced', or 'undecidable' when the measurement is NaN."""
        if math.isnan(value):
            return UNDECIDABLE
        return REPRODUCED if self.holds(value) else NOT_REPRODUCED


_REQUIRED = [f.name for f in fields(Claim) if f.name not in ("digits", "source")]


def load(experiment: str) -> list[Claim]:
    """The claims of one experiment (a key of ``claims`` in one of the chapter files)."""
    return [_claim(entry, experiment) for entry in chapter_section_entry("claims", experiment)]


def _claim(entry, experiment: str) -> Claim:
    """A validated claim from its JSON entry; a UserError names the claim, its file and the fault."""
    where = f"{_files_of('claims').get(experiment, DATA / 'chapter')}"
    if not isinstance(entry, dict):
        raise UserError(f"{where}: each claim of {experiment} must be an object of its fields, got {entry!r}")
    name = entry.get("id", "<no id>")
    missing = [key for key in _REQUIRED if key not in entry]
    if missing:
        raise UserError(f"{where}: claim {name!r} of {experiment} lacks {missing}")
    unknown = sorted(set(entry) - {f.name for f in fields(Claim)})
    if unknown:
        raise UserError(f"{where}: claim {name!r} of {experiment} has unknown keys {unknown}")
    claim = Claim(**entry)
    if claim.op not in _OPS:
        raise UserError(f"{where}: claim {name!r} of {experiment}: op must be one of {sorted(_OPS)}, got {claim.op!r}")
    if claim.kind not in KINDS:
        raise UserError(f"{where}: claim {name!r} of {experiment}: kind must be one of {list(KINDS)}, got {claim.kind!r}")
    if claim.kind == "field" and not claim.source:
        raise UserError(f"{where}: claim {name!r} of {experiment} is of kind 'field': its source must name the paper")
    if not isinstance(claim.source, str) or (claim.kind == "chapter" and claim.source):
        raise UserError(f"{where}: claim {name!r} of {experiment}: source must be a text, and empty for the "
                        "chapter's own claims")
    for key in ("id", "metric", "where", "chapter", "why"):
        if not isinstance(getattr(claim, key), str) or not getattr(claim, key).strip():
            raise UserError(f"{where}: claim {name!r} of {experiment}: {key} must be a non-empty text")
    if isinstance(claim.threshold, bool) or not isinstance(claim.threshold, (int, float)) \
            or not math.isfinite(claim.threshold):
        raise UserError(f"{where}: claim {name!r} of {experiment}: threshold must be a finite number, "
                        f"got {claim.threshold!r}")
    if isinstance(claim.digits, bool) or not isinstance(claim.digits, int) or not 0 <= claim.digits <= 12:
        raise UserError(f"{where}: claim {name!r} of {experiment}: digits must be a whole number from 0 to 12, "
                        f"got {claim.digits!r}")
    return claim


def parameters(experiment: str) -> dict:
    """The chapter's stated parameters of one experiment: field -> {"value", "where"}."""
    return chapter_section_entry("parameters", experiment)


def experiments() -> list[str]:
    """Every experiment that has claims in ``data/chapter/*.json``, in file order."""
    return list(_files_of("claims"))


def _chapter_files() -> list[tuple]:
    """(path, its content) of every ``data/chapter/*.json``, each checked to be an object of
    sections ('claims', 'parameters', ...), each an object by experiment; one line naming the file
    and the place of a fault."""
    files = []
    for path in sorted((DATA / "chapter").glob("*.json")):
        try:
            content = json.loads(path.read_text())
        except json.JSONDecodeError as error:
            raise UserError(f"{path}: not valid JSON at line {error.lineno}, column {error.colno} ({error.msg}); "
                            "correct it, or restore it with git checkout") from None
        except (OSError, UnicodeDecodeError) as error:
            raise UserError(f"{path}: cannot be read ({error}); restore it with git checkout") from None
        if not isinstance(content, dict) or not all(isinstance(section, dict) for section in content.values()):
            raise UserError(f"{path}: must be an object of sections ('claims', 'parameters'), each an object "
                            "by experiment; restore it with git checkout")
        files.append((path, content))
    return files


def _files_of(kind: str) -> dict:
    """Experiment -> the file holding its ``kind`` section, in file order."""
    return {experiment: path for path, content in _chapter_files() for experiment in content.get(kind, {})}


def chapter_section_entry(kind: str, experiment: str):
    """``kind`` ('claims' or 'parameters') of ``experiment`` from ``data/chapter/*.json``."""
    found = {key: value for _, content in _chapter_files() for key, value in content.get(kind, {}).items()}
    if experiment not in found:
        raise UserError(f"no {kind} for experiment {experiment!r} in {DATA / 'chapter'} (those with some: "
                        f"{', '.join(sorted(found))}); restore the file that held them with git checkout")
    if kind == "claims" and not isinstance(found[experiment], list):
        raise UserError(f"{_files_of(kind)[experiment]}: the claims of {experiment} must be a list")
    return found[experiment]


def verdicts(claims: list[Claim], measured: dict, readings: dict | None = None) -> list[dict]:
    """One row per claim: the claim, the measured value, whether it holds and the verdict
    (with the reason a NaN measurement is undecidable, when the measurements give one).

    ``readings`` maps the name of each documented alternative reading of the chapter to its
    measurements; a claim measured under them also gets ``readings`` (name -> verdict), and is
    *fragile* when its verdict there is not the default reading's (:func:`fragility`)."""
    missing = [f"{c.id} ({c.metric})" for c in claims if c.metric not in measured]
    if missing:
        raise UserError(f"no measurement for the claims {', '.join(missing)}: a claim's metric must be one the "
                        "experiment's analysis measures; correct its metric in data/chapter")
    rows = []
    for c in claims:
        value = float(measured[c.metric])
        verdict = c.verdict(value)
        under = {name: c.verdict(float(other[c.metric])) for name, other in (readings or {}).items()
                 if c.metric in other}
        rows.append({"claim": c, "value": value, "holds": verdict == REPRODUCED, "verdict": verdict,
                     "why_undecidable": measured.get(c.metric + WHY_UNDECIDABLE, ""), "readings": under})
    return rows


def fragility(row: dict) -> str:
    """'' when a row's verdict is the same under every documented reading it was measured under,
    else e.g. 'fragile: not under 2 of 3 readings (name, name)'."""
    under = row.get("readings") or {}
    differ = [name for name, verdict in under.items() if verdict != row["verdict"]]
    if not differ:
        return ""
    return f"fragile: not under {len(differ)} of {len(under) + 1} readings ({', '.join(differ)})"


def verdict_text(row: dict) -> str:
    """The verdict as the tables print it: the verdict, its fragility, why it is undecidable."""
    notes = [note for note in (fragility(row), row.get("why_undecidable", "") if row["verdict"] == UNDECIDABLE
                               else "") if note]
    return row["verdict"] + (f" ({'; '.join(notes)})" if notes else "")


def measured_text(row: dict) -> str:
    """The measured value rounded to the claim's digits, beside what the claim needs."""
    c = row["claim"]
    value = "NaN" if math.isnan(row["value"]) else f"{row['value']:.{c.digits}f}"
    return f"{value} (needs {c.op} {c.threshold:g})"


def markdown(rows: list[dict]) -> str:
    """A Markdown claim table for a reader: the claim paraphrased with its place, who makes it, the
    measured value against the claim's threshold, the verdict."""
    lines = ["| claim | source | measured | verdict |", "|---|---|---|---|"]
    for row in rows:
        c = row["claim"]
        verdict = verdict_text(row)
        if row["verdict"] != REPRODUCED or fragility(row):
            verdict = f"**{verdict}**"
        cells = [f"{c.chapter} ({c.where})", c.label, measured_text(row), verdict]
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |")
    return "\n".join(lines)


def show(rows: list[dict]):
    """:func:`markdown` as a notebook displays it (an IPython Markdown object: the table rendered)."""
    from IPython.display import Markdown  # only where a notebook shows it
    return Markdown(markdown(rows))
