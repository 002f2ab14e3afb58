"""Claims: the loader's checks, three-valued verdicts, and that every claim of every chapter file
can fail: a wrong measurement gives NOT reproduced and a NaN one undecidable. For Section 4 the
wrong measurements come from wrong results of the right shape, through the measure functions."""

import json
import math
from dataclasses import replace


import numpy as np
import pytest

from glamas import claims, lineworld
from glamas.errors import UserError
from glamas.experiments import and_network, single_gla, state_encoding

ALL_CLAIMS = [(name, claim) for name in claims.experiments() for claim in claims.load(name)]
SECTION4 = ("single_gla", "state_encoding", "and_network", "and_network_sweep")

CLAIM = {"id": "c", "where": "Fig. 0", "chapter": "x is large", "kind": "chapter", "rule": "exact_property",
         "why": "x measures largeness", "metric": "x", "op": ">", "threshold": 1.0}


def _write_claims(monkeypatch, tmp_path, entries):
    (tmp_path / "chapter").mkdir()
    (tmp_path / "chapter" / "t.json").write_text(json.dumps({"claims": {"t": entries}}))
    monkeypatch.setattr(claims, "DATA", tmp_path)


@pytest.mark.parametrize("change, message", [
    ({"kind": None}, r"claim 'c' of t lacks \['kind'\]"),
    ({"why": None}, r"claim 'c' of t lacks \['why'\]"),
    ({"kind": "ours"}, r"kind must be one of \['chapter', 'inferred', 'field'\], got 'ours'"),
    ({"why": "  "}, "why must be a non-empty text"),
    ({"op": "=="}, "op must be one of"),
    ({"unit": "m"}, r"unknown keys \['unit'\]"),
])
def test_the_loader_names_a_bad_claim(monkeypatch, tmp_path, change, message):
    entry = {key: value for key, value in {**CLAIM, **change}.items() if value is not None}
    _write_claims(monkeypatch, tmp_path, [entry])
    with pytest.raises(ValueError, match=message):
        claims.load("t")


def test_verdicts_are_three_valued():
    claim = claims.Claim(**CLAIM)
    rows = claims.verdicts([claim], {"x": 2.0})
    assert rows[0]["holds"] and rows[0]["verdict"] == "reproduced"
    assert claims.markdown(rows).endswith("| the chapter | 2.00 (needs > 1) | 1 of 1 hold | reproduced |")
    rows = claims.verdicts([claim], {"x": 0.5})
    assert not rows[0]["holds"] and claims.markdown(rows).endswith("| **NOT reproduced** |")
    rows = claims.verdicts([claim], {"x": math.nan, "x:why_undecidable": "no runs"})
    assert not rows[0]["holds"] and rows[0]["verdict"] == "undecidable"
    assert claims.markdown(rows).endswith("| - (needs > 1) | 0 of 1 hold, 1 undecidable | **undecidable (no runs)** |")
    with pytest.raises(UserError, match=r"no measurement for the claims c \(x\)"):
        claims.verdicts([claim], {"y": 1.0})
    with pytest.raises(UserError, match="no claims for experiment 'nonexistent'"):
        claims.load("nonexistent")


@pytest.mark.parametrize("text, message", [
    ('{"claims": {"toy": [', r"toy\.json: not valid JSON at line 1, column 21"),
    ('["claims"]', r"toy\.json: must be an object of sections"),
    ('{"claims": {"toy": {"id": "c"}}}', r"toy\.json: the claims of toy must be a list"),
    ('{"claims": {"toy": ["c"]}}', r"toy\.json: each claim of toy must be an object"),
    ('{"claims": {"toy": [CLAIM]}}'.replace("CLAIM", json.dumps({**CLAIM, "threshold": "high"})),
     r"toy\.json: claim 'c' of toy: threshold must be a finite number, got 'high'"),
    ('{"claims": {"toy": [CLAIM]}}'.replace("CLAIM", json.dumps({**CLAIM, "digits": 2.5})),
     r"claim 'c' of toy: digits must be a whole number"),
    ('{"claims": {"toy": [CLAIM]}}'.replace("CLAIM", json.dumps({**CLAIM, "metric": ""})),
     r"claim 'c' of toy: metric must be a non-empty text"),
])
def test_a_damaged_claim_file_is_one_line_naming_the_file_and_the_place(tmp_path, monkeypatch, text, message):
    (tmp_path / "chapter").mkdir()
    (tmp_path / "chapter" / "toy.json").write_text(text)
    monkeypatch.setattr(claims, "DATA", tmp_path)
    with pytest.raises(UserError, match=message):
        claims.load("toy")


def test_every_chapter_file_loads_with_kinds_and_reasons():
    assert set(SECTION4) | {"gridworld_optimum", "gridworld", "related_work", "scaling"} <= set(claims.experiments())
    for _, claim in ALL_CLAIMS:
        assert claim.kind in claims.KINDS and claim.why.strip()


def _wrong_side(claim: claims.Claim) -> float:
    """A measurement just on the wrong side of every threshold of the claim's band, at the claim's resolution."""
    step = 10.0 ** -claim.digits
    low, high = min(claim.thresholds), max(claim.thresholds)
    return {">": low, ">=": low - step, "<": high, "<=": high + step}[claim.op]


@pytest.mark.parametrize("experiment, claim", ALL_CLAIMS, ids=[f"{e}.{c.id}" for e, c in ALL_CLAIMS])
def test_every_claim_can_fail_and_can_be_undecidable(experiment, claim):
    wrong = claims.verdicts([claim], {claim.metric: _wrong_side(claim)})[0]
    assert wrong["verdict"] == "NOT reproduced", f"{experiment}.{claim.id} holds at {_wrong_side(claim)}"
    assert claims.verdicts([claim], {claim.metric: math.nan})[0]["verdict"] == "undecidable"


# ---- Section 4: wrong results of the right shape, through the measure functions ----

FIG5 = single_gla.SingleGLAConfig(runs=3, eval_grid=40)
FIG7 = and_network.ANDNetworkConfig(runs=3, eval_grid=40)


def _fig5_result(params):
    return single_gla.SingleGLAResult(FIG5, np.arange(1, 3), np.zeros((FIG5.runs, 2)), params)


def _plays_everywhere(action):
    """Fig. 5 parameters (runs, agents, actions, [x1, x2, 1]): both agents prefer ``action``."""
    params = np.zeros((FIG5.runs, 2, 2, 3))
    params[:, :, action, 2] = FIG5.L
    return params


def _chapter_lines():
    """Lines like Fig. 5b's: A plays L above x2 = x1 + 0.25, B above x2 = x1 - 0.5 (a best line of B)."""
    params = np.zeros((FIG5.runs, 2, 2, 3))
    params[:, 0, lineworld.LEFT] = [-1.0, 1.0, -0.25]
    params[:, 1, lineworld.LEFT] = [-1.0, 1.0, 0.5]
    return params


def _agent_at_random(agent):
    """Fig. 5b's lines with ``agent``'s parameters drawn at random."""
    params = _chapter_lines()
    params[:, agent] = np.random.default_rng(agent).uniform(-1, 1, (FIG5.runs, 2, 3))
    return params


FIG5_WRONG = {
    "region_1_plays_LL": _plays_everywhere(lineworld.RIGHT),
    "region_2_plays_RR": _plays_everywhere(lineworld.LEFT),
    "region_3_moves_apart": _plays_everywhere(lineworld.RIGHT),
    "agent_a_best_response": _agent_at_random(0),
    "agent_b_best_response": _agent_at_random(1),
    "agent_a_learns_its_line": _agent_at_random(0),
    "agent_b_as_good_as_a_line": _agent_at_random(1),
}


@pytest.mark.parametrize("claim_id", sorted(FIG5_WRONG))
def test_fig5_claims_fail_on_wrong_lines(claim_id):
    rows = single_gla.claim_rows(_fig5_result(FIG5_WRONG[claim_id]))
    assert {row["claim"].id: row["verdict"] for row in rows}[claim_id] == "NOT reproduced"


def test_fig5_lines_like_the_learned_ones_pass_all_but_the_diagonal():
    # B's line gives up one half of region 3, as B's best single lines do: all of the ceiling
    rows = single_gla.claim_rows(_fig5_result(_chapter_lines()))
    verdicts = {row["claim"].id: row["verdict"] for row in rows}
    assert verdicts == {"region_1_plays_LL": "reproduced", "region_2_plays_RR": "reproduced",
                        "region_3_moves_apart": "reproduced", "agent_a_best_response": "reproduced",
                        "agent_b_best_response": "reproduced", "agent_a_learns_its_line": "NOT reproduced",
                        "agent_b_as_good_as_a_line": "reproduced"}


def _lines_in_region_3(a_offset, b_offset):
    """Lines parallel to the diagonal: A plays L above x2 = x1 + a_offset, B above x2 = x1 + b_offset."""
    params = np.zeros((FIG5.runs, 2, 2, 3))
    params[:, 0, lineworld.LEFT] = [-1.0, 1.0, -a_offset]
    params[:, 1, lineworld.LEFT] = [-1.0, 1.0, -b_offset]
    return params


def test_region_3_claim_fails_when_the_move_apart_cell_is_too_narrow():
    # the cell between the lines holds (R, L) only where -0.2 < x2 - x1 < 0: well under half the ceiling
    rows = single_gla.claim_rows(_fig5_result(_lines_in_region_3(0.0, -0.2)))
    assert {row["claim"].id: row["verdict"] for row in rows}["region_3_moves_apart"] == "NOT reproduced"


@pytest.mark.parametrize("eval_grid", [40, 80, 160])
@pytest.mark.parametrize("b_offset, verdict", [(-0.45, "reproduced"), (-0.15, "NOT reproduced")])
def test_region_3_share_of_ceiling_does_not_move_with_the_grid(eval_grid, b_offset, verdict):
    config = replace(FIG5, eval_grid=eval_grid)
    result = single_gla.SingleGLAResult(config, np.arange(1, 3), np.zeros((FIG5.runs, 2)),
                                        _lines_in_region_3(0.1, b_offset))
    measured = single_gla.measure(result)
    # the cell (R, L) spans -b_offset of the half band's width 0.5, weighted by the band's length
    expected = {-0.45: 0.91, -0.15: 0.33}[b_offset]
    assert measured["region_3_share_of_ceiling"] == pytest.approx(expected, abs=0.04)
    assert {row["claim"].id: row["verdict"] for row in single_gla.claim_rows(result)}["region_3_moves_apart"] == verdict


@pytest.mark.parametrize("grid, angles", [(60, 90), (100, 180), (140, 360)])
def test_best_response_gap_does_not_move_with_the_search(grid, angles):
    # B on one of its best lines given A's diagonal: no gap; B on the diagonal too: a large one
    best = single_gla.best_response_gap(_lines_in_region_3(0.0, -0.5), FIG5, 1, grid, angles)
    np.testing.assert_allclose(best, 0.0, atol=0.01)
    worse = single_gla.best_response_gap(_lines_in_region_3(0.0, 0.0), FIG5, 1, grid, angles)
    assert (worse > 0.1).all()


CHECKPOINTS = np.array([0, 10, 100, 1000, 10_000, 100_000])
IDEAL_LINES = {"joint": ([-1.0, 1.0, 0.0], [-1.0, 1.0, -0.5]), "deictic": ([-1.0, 0.0], [1.0, -0.5]),
               "absolute": ([1.0, -0.5], [1.0, -0.5])}
"""Per context, each agent's u_L - u_R for lines like the learned ones: A plays L where x1 < x2,
B where x2 - x1 > 0.5 (a best line of B); joint and deictic lines of one sharpness are one policy."""


def _encodings(sharpness: dict):
    """Fig. 6 results whose parameters at the checkpoints are the ideal lines times a sharpness
    (runs, checkpoints) per encoding: the larger, the higher the expected reward (0.25 at 0)."""
    results = {}
    for name, scale in sharpness.items():
        w = np.array(IDEAL_LINES[name])  # (agents, inputs)
        params = np.stack([w / 2, -w / 2], axis=1)  # (agents, actions L and R, inputs)
        at_checkpoints = scale[:, :, None, None, None] * params
        result = single_gla.SingleGLAResult(replace(FIG5, context=name), np.arange(1, 3), np.zeros((scale.shape[0], 2)),
                                            at_checkpoints[:, -1], CHECKPOINTS, at_checkpoints)
        results[name] = replace(result, expected_reward=state_encoding.expected_curves(result))
    return results


def _fig6_verdicts(sharpness: dict) -> dict:
    return {row["claim"].id: row for row in state_encoding.encoding_claim_rows(_encodings(sharpness))}


def _rise(final=2.0, iterations=1000.0, runs=20, seed=0, scatter=0.05):
    """(runs, checkpoints) sharpness rising to about ``final`` within about ``iterations``."""
    ends = final + scatter * np.random.default_rng(seed).normal(size=(runs, 1))
    return ends * (1.0 - np.exp(-CHECKPOINTS / iterations))


FAST = _rise(iterations=300.0)
"""A deictic context learning three times as fast as the joint one (_rise()) to the same end."""
FIG6_WRONG = {
    "absolute_clearly_worst": {"joint": -_rise(seed=1), "deictic": -_rise(seed=2), "absolute": _rise(0.0)},
    "deictic_outperforms_joint": {"joint": _rise(seed=1), "deictic": _rise(iterations=3000.0), "absolute": _rise(0.0)},
    "deictic_not_behind_at_end": {"joint": _rise(seed=1), "deictic": _rise(1.2, 300.0), "absolute": _rise(0.0)},
    "same_information_clearly_benefits": {"joint": _rise(seed=1, scatter=0.5),
                                          "deictic": _rise(2.02, seed=2, scatter=0.5), "absolute": _rise(0.0)},
    "deictic_learns_faster": {"joint": _rise(seed=1), "deictic": _rise(2.3, 3000.0), "absolute": _rise(0.0)},
}


@pytest.mark.parametrize("claim_id", sorted(FIG6_WRONG))
def test_fig6_claims_fail_on_wrong_curves(claim_id):
    assert _fig6_verdicts(FIG6_WRONG[claim_id])[claim_id]["verdict"] == "NOT reproduced"


def test_fig6_claims_hold_when_deictic_learns_faster_to_a_visibly_higher_end():
    rows = _fig6_verdicts({"joint": _rise(1.0, seed=1), "deictic": FAST, "absolute": _rise(0.0)})
    assert {row["verdict"] for row in rows.values()} == {"reproduced"}


def test_a_faster_deictic_context_to_the_same_end_is_visibly_better_only_early():
    rows = _fig6_verdicts({"joint": _rise(seed=1), "deictic": FAST, "absolute": _rise(0.0)})
    held = {name for name, row in rows.items() if row["verdict"] == "reproduced"}
    assert {"deictic_learns_faster", "deictic_not_behind_at_end", "absolute_clearly_worst"} <= held
    early = rows["same_information_clearly_benefits"]
    assert early["verdict"] == claims.TURNS
    assert "read" in claims.turns_on(early) or "drawn" in claims.turns_on(early)
    whole = [verdict for labels, *_, verdict in early["points"]
             if labels["read"] == "the drawn run read whole" and labels["drawn"] == "the whole run drawn"]
    assert whole == ["NOT reproduced"]


def test_fig6_claims_on_the_spread_between_runs_are_undecidable_with_one_run():
    rows = _fig6_verdicts({name: _rise(runs=1) for name in state_encoding.ENCODING_NAMES})
    spread = {"deictic_not_behind_at_end", "deictic_learns_faster"}
    assert {rows[name]["verdict"] for name in spread} == {"undecidable"}
    assert all("run-to-run spread" in rows[name]["why_undecidable"] for name in spread)
    assert {row["verdict"] for name, row in rows.items() if name not in spread} <= {"reproduced", "NOT reproduced"}


def _fig7_result(left_bias):
    """Fig. 7 results where every unit's output 1 has bias ``left_bias`` against output 0."""
    params = np.zeros((FIG7.runs, 2, 2, 2, 5))
    params[..., 1, 2] = left_bias / 2
    params[..., 0, 2] = -left_bias / 2
    return and_network.ANDNetworkResult(FIG7, np.arange(2), np.zeros((FIG7.runs, 2, 2)), params)


@pytest.mark.parametrize("left_bias", [-2.0, 2.0], ids=["R everywhere", "L everywhere"])
def test_fig7_claims_fail_when_the_agents_play_one_action_everywhere(left_bias):
    rows = and_network.claim_rows(_fig7_result(left_bias))
    assert {row["verdict"] for row in rows} == {"NOT reproduced"}


def _sweep(stuck_first, stuck_rerun, threshold=0.5):
    """A sweep (rewards 0.5 and 1) whose runs end stuck (P(L) in region I 0.05) or learned (0.9)
    as given: ``stuck_first`` (rewards, runs) on the first stream, ``stuck_rerun`` (runs,) rerun."""
    left = lambda stuck: np.where(np.asarray(stuck)[..., None], 0.05, 0.9).repeat(2, axis=-1)
    config = replace(FIG7, stuck_threshold=threshold)
    return and_network.SweepResult(config, np.array([0.5, 1.0]), np.asarray(stuck_first), left(stuck_first),
                                   left(stuck_rerun), np.zeros_like(stuck_first, dtype=bool))


def _sweep_verdicts(result) -> dict:
    return {row["claim"].id: row["verdict"] for row in and_network.sweep_claim_rows(result)}


def test_fig7_sweep_claim_fails_without_a_rise():
    stuck = np.zeros((2, 10), dtype=bool)
    stuck[:, :3] = True
    assert _sweep_verdicts(_sweep(stuck, stuck[1]))["higher_region_II_reward_traps_runs"] == "NOT reproduced"


STUCK_FIRST = np.array([[False] * 10, [True] * 3 + [False] * 7])


@pytest.mark.parametrize("threshold", [0.3, 0.5, 0.7])
def test_init_claim_fails_when_the_stream_decides(threshold):
    # the rerun sticks other runs as often as the first stream: the initialisation explains nothing
    rerun = np.roll(STUCK_FIRST[1], 5)
    verdicts = _sweep_verdicts(_sweep(STUCK_FIRST, rerun, threshold))
    assert verdicts["initialisation_decides_outcome"] == "NOT reproduced"
    assert verdicts["outcome_depends_on_initialisation"] != "reproduced"  # ten runs: no dependence shown
    same = _sweep_verdicts(_sweep(STUCK_FIRST, STUCK_FIRST[1], threshold))
    assert same["outcome_depends_on_initialisation"] == same["initialisation_decides_outcome"] == "reproduced"


def test_the_dependence_claim_fails_when_keeping_the_initialisation_makes_outcomes_disagree():
    # a hundred runs whose rerun always ends the other way: agreement below every other pairing's
    first = np.array([[False] * 100, [True] * 50 + [False] * 50])
    verdicts = _sweep_verdicts(_sweep(first, ~first[1]))
    assert verdicts["outcome_depends_on_initialisation"] == verdicts["initialisation_decides_outcome"] \
        == "NOT reproduced"


def test_init_share_of_outcome_measures_agreement_beyond_other_initialisations():
    first, rerun = STUCK_FIRST[1], np.roll(STUCK_FIRST[1], 5)
    # same: 4 of 10 runs agree; other: of the 90 pairs r != s, 54 agree
    measured = and_network.init_dependence(first, rerun)
    assert measured["init_agreement_same"] == pytest.approx(0.4)
    assert measured["init_agreement_other"] == pytest.approx(0.6)
    assert measured["init_share_of_outcome"] == pytest.approx(-0.5)
    assert measured["init_share_of_outcome_low"] <= -0.5 <= measured["init_share_of_outcome_high"]
    alike = and_network.init_dependence(np.zeros(10, bool), np.zeros(10, bool))
    assert np.isnan(alike["init_share_of_outcome"])
    assert "ends alike" in alike["init_share_of_outcome_decided:why_undecidable"]


def test_every_section4_claim_has_a_wrong_result():
    covered = set(FIG5_WRONG) | set(FIG6_WRONG) | {"approximates_region_I", "plays_L_inside_and_R_outside",
                                                   "higher_region_II_reward_traps_runs",
                                                   "outcome_depends_on_initialisation",
                                                   "initialisation_decides_outcome"}
    assert {claim.id for name in SECTION4 for claim in claims.load(name)} == covered


def test_a_verdict_is_plain_only_where_every_point_of_its_multiverse_agrees():
    claim = claims.Claim(**{**CLAIM, "band": (2.5,)})
    rows = claims.verdicts([claim], {"x": 3.0}, readings={"one": {"x": 0.5}, "two": {"x": 3.0}, "three": {"x": 0.0}},
                           reading="zero")
    assert rows[0]["verdict"] == claims.TURNS and rows[0]["value"] == 3.0
    assert claims.agreement(rows[0]) == "4 of 8 hold"
    assert claims.turns_on(rows[0]) == "holds at zero or two, not at one or three"
    assert "**turns on a reading or choice (4 of 8 hold: holds at zero or two, not at one or three)**" \
        in claims.markdown(rows)
    band = claims.verdicts([claim], {"x": 2.0})[0]
    assert band["verdict"] == claims.TURNS and claims.turns_on(band) == "holds at threshold > 1, not at threshold > 2.5"
    steady = claims.verdicts([claim], {"x": 3.0}, readings={"one": {"x": 4.0}})
    assert steady[0]["verdict"] == "reproduced" and claims.agreement(steady[0]) == "4 of 4 hold"


def test_a_rule_s_measurement_choices_are_points_of_the_multiverse():
    claim = claims.Claim(**{**CLAIM, "metric": "zero_collisions_after_x", "rule": "level_fast", "op": "<=",
                            "threshold": 0.1})
    rows = claims.verdicts([claim], lambda zero_level=0.05: {"zero_collisions_after_x": {0.05: 0.13, 0.02: 0.5,
                                                                                          0.1: 0.03}[zero_level]})
    assert rows[0]["verdict"] == claims.TURNS and claims.agreement(rows[0]) == "1 of 3 hold"
    assert claims.turns_on(rows[0]) == ("holds at one collision per 10 episodes, not at one collision per 20 "
                                        "episodes or one collision per 50 episodes")
    assert claims.varied(rows[0]) == {"zero_level"}


@pytest.mark.parametrize("value, text", [(math.nan, "-"), (math.inf, "no solution"), (0.0404, "0.04")])
def test_a_measured_value_is_never_shown_as_nan_or_inf(value, text):
    assert claims.value_text(value, 2) == text


@pytest.mark.parametrize("kind, source, label", [("chapter", "", "the chapter"), ("inferred", "", "inferred by us"),
                                                 ("inferred", "Kok and Vlassis 2004", "inferred by us from Kok and Vlassis 2004"),
                                                 ("field", "ICAART 2011", "ICAART 2011")])
def test_a_claim_is_labelled_by_its_source(kind, source, label):
    assert claims.Claim(**{**CLAIM, "kind": kind, "source": source}).label == label


@pytest.mark.parametrize("change, message", [({"kind": "field"}, "its source must name the paper"),
                                             ({"source": "Kok and Vlassis 2004"}, "empty for the chapter's own")])
def test_the_loader_refuses_a_claim_without_its_source_or_the_chapter_with_one(monkeypatch, tmp_path, change, message):
    _write_claims(monkeypatch, tmp_path, [{**CLAIM, **change}])
    with pytest.raises(ValueError, match=message):
        claims.load("t")


# ---- the rule book: every claim names a rule of docs/verdicts.md ----

def test_every_claim_names_a_rule_of_the_rule_book_and_takes_its_metric_from_it():
    from glamas.paths import REPO
    from glamas.verdict_rules import RULES
    book = (REPO / "docs" / "verdicts.md").read_text()
    for _, claim in ALL_CLAIMS:
        assert claim.rule in RULES and RULES[claim.rule].takes(claim.metric), claim.id
    assert {f"### `{key}`" for key in RULES} <= {line.split(":")[0] for line in book.splitlines()}
    assert {claim.rule for _, claim in ALL_CLAIMS} == set(RULES)


@pytest.mark.parametrize("change, message", [
    ({"rule": "taste"}, r"rule must be one of docs/verdicts.md's"),
    ({"rule": "level_greedy"}, r"metric 'x' is not of rule 'level_greedy'"),
    ({"band": ["high"]}, r"band must be a list of finite numbers"),
])
def test_the_loader_refuses_a_claim_without_a_rule_of_the_book(monkeypatch, tmp_path, change, message):
    _write_claims(monkeypatch, tmp_path, [{**CLAIM, **change}])
    with pytest.raises(UserError, match=message):
        claims.load("t")
