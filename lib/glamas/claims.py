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

    def holds(self, value: float) -> bool:
        return bool(_OPS[self.op](value, self.threshold))

    def verdict(self, value: float) -> str:
        """'reproduced', 'NOT reproduced', or 'undecidable' when the measurement is NaN."""
        if math.isnan(value):
            return UNDECIDABLE
        return REPRODUCED if self.holds(value) else NOT_REPRODUCED


_REQUIRED = [f.name for f in fields(Claim) if f.name != "digits"]


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


def verdicts(claims: list[Claim], measured: dict) -> list[dict]:
    """One row per claim: the claim, the measured value, whether it holds and the verdict
    (with the reason a NaN measurement is undecidable, when the measurements give one)."""
    missing = [f"{c.id} ({c.metric})" for c in claims if c.metric not in measured]
    if missing:
        raise UserError(f"no measurement for the claims {', '.join(missing)}: a claim's metric must be one the "
                        "experiment's analysis measures; correct its metric in data/chapter")
    rows = []
    for c in claims:
        value = float(measured[c.metric])
        verdict = c.verdict(value)
        rows.append({"claim": c, "value": value, "holds": verdict == REPRODUCED, "verdict": verdict,
                     "why_undecidable": measured.get(c.metric + WHY_UNDECIDABLE, "")})
    return rows


def table(rows: list[dict]) -> str:
    """A plain-text claim table: claim, chapter's words, measured vs threshold, verdict."""
    lines = []
    for row in rows:
        c = row["claim"]
        lines.append(f"[{row['verdict']}] {c.id} ({c.where})\n    chapter:  {c.chapter}\n"
                     f"    measured: {c.metric} = {row['value']:.{c.digits}f}  (claim: {c.op} {c.threshold:g})")
        if row["verdict"] == UNDECIDABLE and row.get("why_undecidable"):
            lines.append(f"    undecidable: {row['why_undecidable']}")
    return "\n".join(lines)
