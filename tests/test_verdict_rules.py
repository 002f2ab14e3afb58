"""The rule book (docs/verdicts.md) applied: each rule's metric fails on made-up results at every
point of its multiverse, every claim is judged at every measurement choice of its rule, the ledger's
points and verdicts are the ones the committed results give, and the README's counts are the ledger's."""

import dataclasses
import math
import re

import pytest

from glamas import claims, ledger
from glamas.experiments import gridworld as gw
from glamas.paths import REPO
from glamas.verdict_rules import RULES


@pytest.fixture(scope="module")
def gridworld():
    return gw.load(gw.GridworldConfig())


def _as(result, learner: str, copy_of: str):
    """``result`` with ``learner``'s curves and evaluations those of ``copy_of``."""
    names = result.names()
    log, evaluated = result.log.copy(), result.evaluated.copy()
    log[names.index(learner)] = result.log[names.index(copy_of)]
    evaluated[names.index(learner)] = result.evaluated[names.index(copy_of)]
    return dataclasses.replace(result, log=log, evaluated=evaluated)


def _verdicts(result) -> dict:
    return {row["claim"].id: row for row in gw.claim_rows(result)}


def test_a_two_observe_that_learns_as_the_independent_learners_fails_at_every_point(gridworld):
    rows = _verdicts(_as(gridworld, "two_observe", "independent"))
    failing = ["fewer_steps_than_independent", "reward_close_to_mmdp", "reward_far_above_independent",
               "two_observe_no_collisions", "two_observe_zero_collisions_fast", "two_observe_about_4_coordinations"]
    for claim_id in failing:
        row = rows[claim_id]
        assert row["verdict"] == claims.NOT_REPRODUCED, (claim_id, claims.verdict_text(row))
        assert claims.varied(row) >= {choice.name for choice in RULES[row["claim"].rule].choices}
    assert {rows[claim_id]["claim"].rule for claim_id in failing} == {
        "final_gap", "almost_as_good", "much_more", "level_on_curve", "level_fast", "about_n"}


def test_independent_learners_that_learn_as_the_mmdp_learner_fail_at_every_point(gridworld):
    rows = _verdicts(_as(gridworld, "independent", "mmdp"))
    for claim_id in ("independent_about_3_collisions", "independent_reward_at_most_about_70",
                     "independent_never_zero_collisions"):
        assert rows[claim_id]["verdict"] == claims.NOT_REPRODUCED, claim_id


def test_a_greedy_policy_that_collides_fails_every_level_of_zero(gridworld):
    names = gridworld.names()
    evaluated = gridworld.evaluated.copy()
    evaluated[names.index("mmdp")] = gridworld.evaluated[names.index("independent")]
    rows = _verdicts(dataclasses.replace(gridworld, evaluated=evaluated))
    assert rows["mmdp_greedy_no_collisions"]["verdict"] == claims.NOT_REPRODUCED
    assert claims.value_text(rows["mmdp_greedy_no_collisions"]["value"], 3) == "no solution"  # it never completes


# ---- the committed results: the ledger is the multiverse they give ----

def _ledger_cells() -> dict:
    """(experiment, claim id) -> (points, verdict) as docs/ledger.md shows them."""
    cells = {}
    for line in (REPO / "docs" / "ledger.md").read_text().splitlines():
        parts = [cell.strip() for cell in re.split(r"(?<!\\)\|", line)[1:-1]]
        if len(parts) == 10 and parts[1].startswith("`"):
            cells[(parts[0], parts[1].strip("`"))] = (parts[8], parts[9].strip("*"))
    return cells


@pytest.mark.long
def test_every_claims_multiverse_verdict_from_the_committed_results_is_the_ledgers():
    shown = _ledger_cells()
    rows = ledger.rows()
    assert len(shown) == len(rows)
    for experiment, row in rows:
        c = row["claim"]
        assert shown[(experiment, c.id)] == (claims.agreement(row), claims.verdict_text(row)), c.id
        labels = [labels for labels, *_ in row["points"]]
        for choice in RULES[c.rule].choices:  # every value of every choice of its rule was judged
            assert {lab[choice.name] for lab in labels} == set(choice.labels), (c.id, choice.name)
        assert len(row["points"]) % (math.prod(len(choice.values) for choice in RULES[c.rule].choices)
                                     * len(c.thresholds)) == 0


def _block_counts(text: str) -> dict:
    """Source -> (claims, reproduced, not reproduced, undecidable, turning) from the README's summary."""
    found = re.findall(r"^- (.+?): (\d+); (\d+) reproduced, (\d+) not reproduced, (\d+) undecidable, "
                       r"(\d+) turn on a reading or choice$", text, flags=re.M)
    return {source: tuple(int(n) for n in numbers) for source, *numbers in found}


def test_the_readme_counts_are_the_ledgers():
    readme = (REPO / "README.md").read_text()
    counts = _block_counts(readme)
    verdicts = {}
    for line in (REPO / "docs" / "ledger.md").read_text().splitlines():
        parts = [cell.strip() for cell in re.split(r"(?<!\\)\|", line)[1:-1]]
        if len(parts) == 10 and parts[1].startswith("`"):
            kind = {"the chapter": "chapter", "inferred by us": "inferred"}.get(parts[4].split(" from ")[0], "field")
            verdicts.setdefault(kind, []).append(parts[9].strip("*").split(" (")[0])
    for kind, source in ledger.SOURCES.items():
        found = verdicts[kind]
        assert counts[source] == (len(found), *(found.count(v) for v in ledger.VERDICTS)), kind
    chapter = counts[ledger.SOURCES["chapter"]]
    headline = " ".join(readme[readme.index("**Scope and outcome.**"):readme.index(ledger.START)].split())
    said = re.search(r"Of the chapter's (\d+) claims, (\d+) hold at every one of them", headline)
    assert (int(said[1]), int(said[2])) == chapter[:2]
    assert int(re.search(r"(\d+) fails? at every one", headline)[1]) == chapter[2]
    assert int(re.search(r"(\d+) turns? on a (?:reading or )?choice", headline)[1]) == chapter[4]
    assert chapter[3] == 0 or "undecidable" in headline


def test_no_nan_or_inf_where_a_reader_looks():
    for path in (REPO / "README.md", REPO / "docs" / "ledger.md", REPO / "docs" / "verdicts.md"):
        assert not re.search(r"\b(nan|inf)\b", path.read_text(), flags=re.I), path.name
