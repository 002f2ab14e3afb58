"""The claims re-examined for what a reader can see: each verdict can fail. Fig. 6's comparisons
are read as a gap between curves relative to the plot's height, the initialisation claim is decided
only when its interval clears the threshold, CQ-learning's reward against the independent
learners is read on the learning curves (their greedy policy deadlocks)."""

from types import SimpleNamespace

import numpy as np
import pytest

from glamas import claims
from glamas.experiments.and_network import analysis as and_analysis
from glamas.experiments.state_encoding import analysis as se_analysis


def _fig6_verdicts(lead: float) -> dict:
    """Fig. 6's claims on three encodings' curves: each rises from 0.3 to its level over the run,
    joint to 0.6, deictic to 0.6 + ``lead``, absolute to 0.35; five runs with a little spread."""
    checkpoint = np.linspace(0.0, 100_000.0, 11)
    rise = 1.0 - np.exp(-checkpoint / 20_000.0)
    spread = np.linspace(-0.002, 0.002, 5)[:, None]
    levels = {"joint": 0.6, "deictic": 0.6 + lead, "absolute": 0.35}
    curves = {name: 0.3 + (level - 0.3) * rise[None, :] + spread for name, level in levels.items()}
    results = {name: SimpleNamespace(checkpoint=checkpoint, expected_reward=curves[name]) for name in levels}
    rows = claims.verdicts(claims.load("state_encoding"), se_analysis.measure_encodings(results))
    return {row["claim"].id: row["verdict"] for row in rows}


def test_a_deictic_lead_a_reader_cannot_see_is_no_outperforming():
    tiny = _fig6_verdicts(lead=0.002)  # a lead every run shows: significant, invisible
    assert tiny["deictic_outperforms_joint"] == tiny["same_information_clearly_benefits"] == "NOT reproduced"
    assert tiny["absolute_clearly_worst"] == "reproduced"
    seen = _fig6_verdicts(lead=0.03)  # about a tenth of the plot's height over the run
    assert seen["deictic_outperforms_joint"] == "reproduced"
    clear = _fig6_verdicts(lead=0.08)
    assert clear["same_information_clearly_benefits"] == "reproduced"


def test_an_absolute_distance_close_to_the_others_is_not_clearly_worst():
    checkpoint = np.linspace(0.0, 100_000.0, 11)
    curves = {name: np.tile(np.linspace(0.3, level, 11), (5, 1)) + np.linspace(-0.001, 0.001, 5)[:, None]
              for name, level in {"joint": 0.6, "deictic": 0.6, "absolute": 0.59}.items()}
    results = {name: SimpleNamespace(checkpoint=checkpoint, expected_reward=curves[name]) for name in curves}
    rows = claims.verdicts(claims.load("state_encoding"), se_analysis.measure_encodings(results))
    assert next(row for row in rows if row["claim"].id == "absolute_clearly_worst")["verdict"] == "NOT reproduced"


def _initialisation_verdict(first, rerun, claim_id="initialisation_decides_outcome") -> dict:
    measured = and_analysis.init_dependence(np.array(first, dtype=bool), np.array(rerun, dtype=bool), draws=2000)
    claim = next(c for c in claims.load("and_network_sweep") if c.id == claim_id)
    return claims.verdicts([claim], measured)[0]


def test_the_stronger_initialisation_claim_is_decided_only_when_its_interval_clears_one_half():
    decided = _initialisation_verdict([True] * 30 + [False] * 70, [True] * 30 + [False] * 70)
    assert decided["verdict"] == "reproduced"
    against = _initialisation_verdict([True, False] * 50, [False, True] * 25 + [True, False] * 25)
    assert against["verdict"] == "NOT reproduced"
    few = _initialisation_verdict([True] * 3 + [False] * 7, [True] * 2 + [False] * 8)  # ten runs: too wide
    assert few["verdict"] == "undecidable" and "reaches both sides of 0.5" in few["why_undecidable"]


def test_the_dependence_on_the_initialisation_is_a_share_decided_above_zero():
    # 100 runs, keeping the initialisation keeps 80 of 100 outcomes where other initialisations keep about half
    first = [True] * 50 + [False] * 50
    rerun = [True] * 40 + [False] * 10 + [True] * 10 + [False] * 40
    depends = _initialisation_verdict(first, rerun, "outcome_depends_on_initialisation")
    assert depends["verdict"] == "reproduced" and 0.5 < depends["value"] < 0.7
    assert _initialisation_verdict(first, rerun)["verdict"] == "undecidable"  # 0.6: not clearly above one half
    alike = _initialisation_verdict(first, first[25:] + first[:25], "outcome_depends_on_initialisation")
    assert alike["verdict"] != "reproduced"


@pytest.mark.parametrize("gap, verdict", [(26.7, "reproduced"), (4.0, "NOT reproduced")])
def test_cq_much_above_the_independent_learners_is_read_on_the_learning_curves(gap, verdict):
    claim = next(c for c in claims.load("related_work") if c.id == "cq_reward_far_above_independent")
    assert claim.metric == "reward_cq_minus_independent"
    assert claims.verdicts([claim], {"reward_cq_minus_independent": gap})[0]["verdict"] == verdict
