"""Verdicts that measure the chapter, not a yardstick of ours: the convergence definitions on
made-up curves, and every learning-curve claim's verdict on the committed results unchanged by the
block width of the curves and, for the convergence claims, by the tolerance (3 % to 15 %).
The first-level and zero-collision metrics can fail through the measure function."""

import dataclasses
import math

import numpy as np
import pytest

from glamas import claims, curves
from glamas.experiments import gridworld as gw
from glamas.experiments import related_work as rw
from glamas.experiments import scaling
from glamas.learners import episode as ep

# ---- the definitions, on made-up curves ----

EPISODES = np.arange(1, 101)


def _steps(settle_at: np.ndarray) -> np.ndarray:
    """One run per entry: 50 steps until episode ``settle_at``, then 10."""
    return np.where(EPISODES[None, :] < np.asarray(settle_at)[:, None], 50.0, 10.0)


def test_per_run_convergence_is_each_runs_own():
    assert curves.convergence_episodes(_steps([10, 30, 60]), EPISODES).tolist() == [9.0, 29.0, 59.0]


def test_a_flat_mean_over_drifting_runs_is_not_per_run_convergence():
    """Runs that swap between two levels late, in opposite phases: the mean is flat from the start
    (run-mean convergence at once), every run drifts until episode 80 (per-run convergence late)."""
    drift = np.where((EPISODES // 10) % 2 == 0, 12.0, 8.0)
    drift[EPISODES >= 80] = 10.0
    runs = np.stack([drift, 20.0 - drift])
    assert curves.convergence_episode(runs, EPISODES) == 0.0
    assert curves.convergence_episodes(runs, EPISODES).tolist() == [79.0, 79.0]


def test_shared_level_times_both_learners_to_the_worse_final_value():
    fast, slow = _steps([10] * 4), _steps([60] * 4) + 2.0  # slow ends at 12
    assert curves.shared_level(fast, slow, EPISODES, 0.05) == pytest.approx(12.6)
    point, _, _ = curves.convergence_ratio(fast, slow, EPISODES, "shared_level")
    assert point == pytest.approx(9 / 59)


def test_earlier_share_counts_pairs_of_runs_and_ties_by_half():
    assert curves.earlier_share(_steps([10, 10]), _steps([60, 10]), EPISODES) == pytest.approx(0.75)


def test_an_unknown_definition_is_refused():
    with pytest.raises(ValueError, match="definition must be one of"):
        curves.convergence_ratio(_steps([10]), _steps([20]), EPISODES, "eventually")


def test_coarsened_blocks_keep_the_mean_over_episodes():
    episodes = np.array([1, 2, 4, 8, 16, 50, 100])
    values = np.array([[9.0, 7, 5, 3, 1, 4, 2]])
    merged, ends = curves.coarsened(values, episodes, 2)
    widths = np.diff(episodes, prepend=0)
    assert ends.tolist() == [2, 8, 50, 100]
    assert merged @ np.diff(ends, prepend=0) == pytest.approx(values @ widths)
    assert curves.final(merged, ends) == curves.final(values, episodes) == 2.0


# ---- the committed results: verdicts that no block width or tolerance moves ----

def _coarsened_log(log: np.ndarray, episodes: np.ndarray, factor: int):
    """A result's log (..., blocks, columns) on blocks ``factor`` times wider."""
    merged, ends = curves.coarsened(np.moveaxis(log, -2, -1), episodes, factor)
    return np.moveaxis(merged, -1, -2), ends


@pytest.fixture(scope="module")
def gridworld():
    return gw.load(gw.GridworldConfig())


@pytest.fixture(scope="module")
def related():
    return rw.load(rw.RelatedWorkConfig())


def _verdicts(rows) -> dict:
    """Each claim's verdict, but for the claims whose rule judges them at every block width anyway."""
    return {row["claim"].id: row["verdict"] for row in rows if row["claim"].rule != "converges_faster"}


@pytest.mark.parametrize("factor", [2, 4])
def test_gridworld_verdicts_do_not_move_with_the_block_width(gridworld, factor):
    log, ends = _coarsened_log(gridworld.log, gridworld.episodes, factor)
    wider = dataclasses.replace(gridworld, log=log, episodes=ends)
    assert _verdicts(gw.claim_rows(wider)) == _verdicts(gw.claim_rows(gridworld))


@pytest.mark.parametrize("factor", [2, 4])
def test_related_work_verdicts_do_not_move_with_the_block_width(related, factor):
    config = rw.RelatedWorkConfig()
    log, ends = _coarsened_log(related.log, related.episodes, factor)
    wider = dataclasses.replace(related, log=log, episodes=ends)
    assert _verdicts(rw.claim_rows(wider, config)) == _verdicts(rw.claim_rows(related, config))


@pytest.mark.parametrize("factor", [2, 4])
def test_scaling_verdicts_do_not_move_with_the_block_width(factor):
    config = scaling.ScalingConfig()
    result = scaling.load(config)
    log, ends = _coarsened_log(result.log, result.episodes, factor)
    wider = dataclasses.replace(result, log=log, episodes=ends)
    assert _verdicts(scaling.claim_rows(wider)) == _verdicts(scaling.claim_rows(result))


CONVERGENCE_CLAIMS = [("gridworld", "two_observe", "independent"), ("gridworld", "two_observe", "mmdp"),
                      ("related_work", "cq", "mmdp")]


@pytest.mark.parametrize("experiment, name, base", CONVERGENCE_CLAIMS)
def test_a_convergence_verdict_is_judged_at_every_tolerance_and_block_width(gridworld, related, experiment, name,
                                                                            base):
    result = gridworld if experiment == "gridworld" else related
    rows = gw.claim_rows(result) if experiment == "gridworld" else rw.claim_rows(result, rw.RelatedWorkConfig())
    row = next(row for row in rows if row["claim"].metric == f"convergence_{name}_over_{base}")
    grid = curves.convergence_grid(result.steps(name), result.steps(base), result.episodes)
    said = {"faster": claims.REPRODUCED, "slower": claims.NOT_REPRODUCED, "undecidable": claims.UNDECIDABLE}
    assert len(row["points"]) == len(grid) == len(curves.TOLERANCES) * len(curves.BLOCK_FACTORS)
    assert sorted(verdict for *_, verdict in row["points"]) == sorted(said[curves.interval_verdict(low, high)]
                                                                      for *_, low, high in grid)
    found = {verdict for *_, verdict in row["points"]}
    assert row["verdict"] == (found.pop() if len(found) == 1 else claims.TURNS)


# ---- the new metrics can fail through the measure function ----

def test_glas_that_coordinate_everywhere_fail_the_out_of_range_claim(gridworld):
    first_level = gridworld.own["two_observe"]
    u = np.zeros_like(first_level["u"])
    u[..., 1, 1] = 8.0  # the bias of "coordinate": P(coordinate) near 1 at every distance
    everywhere = dataclasses.replace(gridworld, own={"two_observe": {**first_level, "u": u, "u_initial": u}})
    measured = gw.measure(everywhere)
    assert measured["coordinates_in_range_share_two_observe"] == 1.0
    assert measured["alone_out_of_range_share_two_observe"] == 0.0
    assert measured["stuck_at_start_share_two_observe"] == measured["stuck_at_end_share_two_observe"] == 1.0
    rows = {row["claim"].id: row["verdict"] for row in gw.claim_rows(everywhere)}
    assert rows["two_observe_alone_out_of_range"] == claims.NOT_REPRODUCED


def test_collisions_that_never_settle_fail_the_fast_claim_and_pass_never(gridworld):
    log = gridworld.log.copy()
    collisions = ep.column(gridworld.config.gridmap().n_agents, ep.COLLISIONS)
    log[..., collisions] = 1.0
    measured = gw.measure(dataclasses.replace(gridworld, log=log))
    assert measured["zero_collisions_after_mmdp"] == measured["zero_collisions_after_two_observe"] == 1.0
    log[..., collisions] = 0.0
    measured = gw.measure(dataclasses.replace(gridworld, log=log))
    assert measured["zero_collisions_after_independent"] == 0.0
    assert not math.isnan(measured["zero_collisions_after_independent"])
