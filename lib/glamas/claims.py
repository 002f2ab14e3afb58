"""The chapter's claims as data (``data/chapter/*.json``) and their verdicts, computed from results.

Each claim names a metric that an experiment's analysis measures, a comparison and a threshold.
The verdict is the comparison applied to the measured value: nothing here is typed in by hand.
Each claim names the rule of docs/verdicts.md for its kind of sentence (:mod:`glamas.verdict_rules`)
and is judged at every point of its multiverse: every documented reading of its setting, every
value of its rule's measurement choices and every threshold of its band.
A claim is of one of three kinds: what the chapter says, what we infer from it (our reading of a
lost figure, or a consequence we derive), or what the sparse-interaction literature reports on the
maps it shares with the chapter; ``why`` says which sentence it tests and why the metric measures it.
"""

import itertools
import json
import math
import operator
from collections.abc import Callable
from dataclasses import dataclass, fields

from glamas.errors import UserError
from glamas.paths import DATA
from glamas.verdict_rules import RULES

_OPS = {">": operator.gt, ">=": operator.ge, "<": operator.lt, "<=": operator.le}
KINDS = ("chapter", "inferred", "field")
REPRODUCED, NOT_REPRODUCED, UNDECIDABLE = "reproduced", "NOT reproduced", "undecidable"
TURNS = "turns on a reading or choice"
"""The verdict of a claim whose points do not all agree."""
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
    """Name of the measured quantity (a key of the experiment's measurements), of its rule's family."""
    rule: str
    """The key of the rule of docs/verdicts.md that judges it (:data:`glamas.verdict_rules.RULES`)."""
    op: str
    """How the measurement is compared with the threshold: one of > >= < <=."""
    threshold: float
    """The value the measurement is compared with."""
    band: tuple = ()
    """Further thresholds the claim's rule admits for the chapter's word (docs/verdicts.md); the
    claim is judged at ``threshold`` and at each of them."""
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

    @property
    def thresholds(self) -> tuple:
        """The claim's threshold, then the others of its band."""
        return (self.threshold, *self.band)

    def holds(self, value: float, threshold: float | None = None) -> bool:
        return bool(_OPS[self.op](value, self.threshold if threshold is None else threshold))

    def verdict(self, value: float, threshold: float | None = None) -> str:
        """'reproduced', 'NOT reproduced', or 'undecidable' when the measurement is NaN."""
        if math.isnan(value):
            return UNDECIDABLE
        return REPRODUCED if self.holds(value, threshold) else NOT_REPRODUCED


_REQUIRED = [f.name for f in fields(Claim) if f.name not in ("digits", "source", "band")]


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
    band = entry.get("band", ())
    claim = Claim(**{**entry, "band": tuple(band) if isinstance(band, list) else band})
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
    if claim.rule not in RULES:
        raise UserError(f"{where}: claim {name!r} of {experiment}: rule must be one of docs/verdicts.md's "
                        f"{sorted(RULES)}, got {claim.rule!r}")
    if not isinstance(claim.band, tuple) or not all(isinstance(t, (int, float)) and not isinstance(t, bool)
                                                     and math.isfinite(t) for t in claim.band):
        raise UserError(f"{where}: claim {name!r} of {experiment}: band must be a list of finite numbers, "
                        f"got {entry.get('band')!r}")
    if not RULES[claim.rule].takes(claim.metric):
        raise UserError(f"{where}: claim {name!r} of {experiment}: metric {claim.metric!r} is not of rule "
                        f"{claim.rule!r}'s family ({RULES[claim.rule].metrics}); correct the rule or the metric")
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


Measure = dict | Callable[..., dict]
"""An experiment's measurements: a dict (judged at its rule's default choices only) or a function
of the measurement choices (keywords of :class:`glamas.verdict_rules.Choice`) giving them."""


def verdicts(claims: list[Claim], measured: Measure, readings: dict | None = None,
             reading: str = "the default reading") -> list[dict]:
    """One row per claim: the claim, its measured value at the default point, whether it holds and
    the verdict over its multiverse (:func:`multiverse_verdict`), with the reason a NaN measurement
    is undecidable, when the measurements give one.

    The points are every reading (``reading`` names the default one; ``readings`` maps the name of
    each documented alternative reading of the chapter to its measurements) times every value of
    the claim's rule's choices (where the measurements are a function of them) times every
    threshold of the claim's band. Each row keeps its ``points``: (labels, value, threshold, verdict)."""
    sources = {reading: measured, **(readings or {})}
    cache = {}

    def at(name: str, choice: dict) -> dict:
        key = (name, tuple(sorted(choice.items())))
        if key not in cache:
            source = sources[name]
            cache[key] = source(**choice) if callable(source) else source
        return cache[key]

    default = at(reading, {})
    missing = [f"{c.id} ({c.metric})" for c in claims if c.metric not in default]
    if missing:
        raise UserError(f"no measurement for the claims {', '.join(missing)}: a claim's metric must be one the "
                        "experiment's analysis measures; correct its metric in data/chapter")
    rows = []
    for c in claims:
        value = float(default[c.metric])
        points = _points(c, sources, at)
        verdict = multiverse_verdict(points)
        rows.append({"claim": c, "value": value, "holds": verdict == REPRODUCED, "verdict": verdict,
                     "why_undecidable": default.get(c.metric + WHY_UNDECIDABLE, ""), "points": points})
    return rows


def _points(c: Claim, sources: dict, at: Callable) -> list[tuple]:
    """(labels, value, threshold, verdict) at every point of claim ``c``'s multiverse."""
    choices = RULES[c.rule].choices
    points = []
    for name, source in sources.items():
        varied = choices if callable(source) else ()
        for values in itertools.product(*(choice.values for choice in varied)):
            choice = {k.name: v for k, v in zip(varied, values) if v != k.values[0]}
            measured = at(name, choice)
            if c.metric not in measured:
                continue
            labels = {"reading": name} | {k.name: k.text(v) for k, v in zip(varied, values)}
            value = float(measured[c.metric])
            points += [({**labels, "threshold": f"threshold {c.op} {t:g}"}, value, t, c.verdict(value, t))
                       for t in c.thresholds]
    return points


def multiverse_verdict(points: list[tuple]) -> str:
    """The verdict every point gives, or TURNS when they differ."""
    found = {verdict for *_, verdict in points}
    return found.pop() if len(found) == 1 else TURNS


def varied(row: dict) -> set:
    """The names of what a row's points vary (readings, choices, thresholds)."""
    labels = [labels for labels, *_ in row["points"]]
    return {key for key in labels[0] if len({lab[key] for lab in labels}) > 1} if labels else set()


def agreement(row: dict) -> str:
    """How many of a row's points hold, e.g. '6 of 18 hold' (with how many are undecidable)."""
    verdicts = [verdict for *_, verdict in row["points"]]
    undecided = verdicts.count(UNDECIDABLE)
    return (f"{verdicts.count(REPRODUCED)} of {len(verdicts)} hold"
            + (f", {undecided} undecidable" if undecided else ""))


_SAYS = {REPRODUCED: "holds at", NOT_REPRODUCED: "not at", UNDECIDABLE: "undecidable at"}


def turns_on(row: dict) -> str:
    """What a row's verdict turns on: '' when every point agrees; else the reading, choice or
    threshold that alone decides it, e.g. 'holds at one collision per 10 episodes, not at one
    collision per 20 episodes or one collision per 50 episodes'; failing one, how many points hold
    at each value of the two that split them most."""
    if row["verdict"] != TURNS:
        return ""
    points = row["points"]
    keys = sorted(varied(row))
    deciding = [key for key in keys if all(len(set(found)) == 1 for found in _by_value(points, key).values())]
    if deciding:
        by_value = _by_value(points, deciding[0])
        return ", ".join(f"{_SAYS[verdict]} {_or([v for v, found in by_value.items() if found[0] == verdict])}"
                         for verdict in _SAYS if any(found[0] == verdict for found in by_value.values()))
    spread = {key: _spread(points, key) for key in keys}
    ranked = sorted(keys, key=lambda key: -spread[key])
    return "; ".join("holds at " + ", ".join(f"{value} in {found.count(REPRODUCED)} of {len(found)}"
                                             for value, found in _by_value(points, key).items())
                     for key in ranked[:2] if spread[key] > 0)


def _by_value(points: list[tuple], key: str) -> dict:
    """Per value of ``key`` (in the points' order): the verdicts of its points."""
    out = {}
    for labels, *_, verdict in points:
        out.setdefault(labels[key], []).append(verdict)
    return out


def _spread(points: list[tuple], key: str) -> float:
    """How far the values of ``key`` differ in the shares of their points that hold and that are undecidable."""
    shares = [(found.count(REPRODUCED) / len(found), found.count(UNDECIDABLE) / len(found))
              for found in _by_value(points, key).values()]
    return sum(max(share[k] for share in shares) - min(share[k] for share in shares) for k in (0, 1))


def _or(items: list) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " or " + items[-1]


def turning_text(row: dict) -> str:
    """'' when every point of a row agrees, else how many hold and what the verdict turns on."""
    if row["verdict"] != TURNS:
        return ""
    return f"{agreement(row)}: {turns_on(row)}"


def verdict_text(row: dict) -> str:
    """The verdict as the tables print it: the verdict, what it turns on, why it is undecidable."""
    if row["verdict"] == TURNS:
        return f"{TURNS} ({turning_text(row)})"
    why = row.get("why_undecidable", "") if row["verdict"] == UNDECIDABLE else ""
    return row["verdict"] + (f" ({why})" if why else "")


def value_text(value: float, digits: int, missing: str = "-") -> str:
    """A measured value as a reader sees it: rounded, ``missing`` when there is none (NaN), 'no
    solution' when it is infinite (a greedy policy that does not complete its episodes)."""
    if math.isnan(value):
        return missing
    if math.isinf(value):
        return "no solution"
    return f"{value:.{digits}f}"


def measured_text(row: dict) -> str:
    """The measured value at the default point rounded to the claim's digits, beside what the claim needs."""
    c = row["claim"]
    return f"{value_text(row['value'], c.digits)} (needs {c.op} {c.threshold:g})"


def markdown(rows: list[dict]) -> str:
    """A Markdown claim table for a reader: the claim paraphrased with its place, who makes it, the
    measured value at the default point against the claim's threshold, how many points of its
    multiverse hold, the verdict."""
    lines = ["| claim | source | measured | points | verdict |", "|---|---|---|---|---|"]
    for row in rows:
        c = row["claim"]
        verdict = verdict_text(row)
        if row["verdict"] != REPRODUCED:
            verdict = f"**{verdict}**"
        cells = [f"{c.chapter} ({c.where})", c.label, measured_text(row), agreement(row), verdict]
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |")
    return "\n".join(lines)


def show(rows: list[dict]):
    """:func:`markdown` as a notebook displays it (an IPython Markdown object: the table rendered)."""
    from IPython.display import Markdown  # only where a notebook shows it
    return Markdown(markdown(rows))
