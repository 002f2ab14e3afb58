"""What the readings of Fig. 10 give: every reading judged by the same Section 5.3 claims against
the same baselines (the independent, joint-state and MMDP learners of
:mod:`glamas.experiments.gridworld`, which do not depend on the reading), so a reader sees which
readings of the lost figure give the chapter's reported outcome and which do not."""

import math

import numpy as np

from glamas import claims as chapter
from glamas.experiments.fig10_readings.experiment import ReadingsConfig, ReadingsResult
from glamas.experiments.gridworld import analysis as gw_analysis
from glamas.experiments.gridworld.experiment import GridworldConfig, GridworldResult
from glamas.learners import two_observe
from glamas.tables import Table


def deltas(config: GridworldConfig) -> np.ndarray:
    """The distances at which the learned P(coordinate | delta) is reported: 1 to the map's largest
    (TunnelToGoal: 1 to 8)."""
    return np.arange(1, two_observe.largest_distance(config.gridmap()) + 1)


def with_baselines(result: ReadingsResult, k: int, baselines: GridworldResult) -> GridworldResult:
    """``baselines`` (the four learners' result) with 2observe replaced by reading k's."""
    return gw_analysis.with_learner(baselines, result.gridworld_result(k), "two_observe")


def summary(result: ReadingsResult, config: ReadingsConfig, baselines: GridworldResult | None = None) -> list[dict]:
    """Per reading: final steps, reward, collisions and coordinations, the share of final GLAs that
    coordinate (P(coordinate) > 1/2) at each of :func:`deltas`, the shares of GLAs stuck on a saturated
    wrong choice at the start and at the end (as :func:`glamas.experiments.gridworld.measure` finds
    them) and, given the ``baselines``, the Section 5.3 claim rows."""
    rows = []
    for k, name in enumerate(config.readings):
        alone = result.gridworld_result(k)
        reading = config.reading(name)
        m = gw_analysis.measure(alone)
        learns = reading.own("two_observe").rule_distance is None
        row = {"reading": name, "steps": m["steps_two_observe"], "reward": m["reward_two_observe"],
               "collisions": m["collisions_two_observe"], "coordinations": m["coordinations_two_observe"],
               "greedy_collisions": m["greedy_collisions_two_observe"],
               "deltas": deltas(reading), "coordinating": coordinating_share(alone, reading),
               "stuck_at_start": m["stuck_at_start_share_two_observe"] if learns else math.nan,
               "stuck_at_end": m["stuck_at_end_share_two_observe"] if learns else math.nan}
        if baselines is not None:
            row["claims"] = gw_analysis.claim_rows(with_baselines(result, k, baselines))
        rows.append(row)
    return rows


def coordinating_share(result: GridworldResult, config: GridworldConfig) -> np.ndarray:
    """At each of :func:`deltas`, the share of 2observe's final GLAs that coordinate (probability above
    1/2; the fixed rule's 0 or 1): how many GLAs learned to coordinate there, not an average
    probability, which would read a mix of GLAs at 0 and at 1 as one soft GLA."""
    return (gw_analysis.coordination_probability(result, config, deltas(config)) > 0.5).mean(axis=(0, 1))


def table(rows: list[dict]) -> Table:
    """The readings side by side, numbered: final values, the share of GLAs coordinating at each
    distance, the shares of stuck GLAs at the start and the end, and the claim count."""
    header = ["#", "reading", "steps", "reward", "collisions", "coord.",
              f"coordinating at delta = {', '.join(str(d) for d in rows[0]['deltas'])}", "stuck start/end"]
    if "claims" in rows[0]:
        header.append("claims reproduced")
    lines = []
    for k, row in enumerate(rows):
        stuck = "-" if math.isnan(row["stuck_at_start"]) else f"{row['stuck_at_start']:.2f}/{row['stuck_at_end']:.2f}"
        line = [k + 1, row["reading"], f"{row['steps']:.2f}", f"{row['reward']:.1f}", f"{row['collisions']:.3f}",
                f"{row['coordinations']:.2f}", " ".join(f"{v:.2f}" for v in row["coordinating"]), stuck]
        if "claims" in row:
            line.append(f"{sum(r['holds'] for r in row['claims'])} of {len(row['claims'])}")
        lines.append(line)
    return Table(header, lines)


def verdict_table(rows: list[dict]) -> Table:
    """Claim by reading, the readings numbered as in :func:`table`: R reproduced, - not reproduced,
    ? undecidable, ~ turns on a measurement choice of its rule (:func:`glamas.claims.verdicts`)."""
    claims = [r["claim"].id for r in rows[0]["claims"]]
    return Table(["claim", *(str(k + 1) for k in range(len(rows)))],
                 [[claim, *(_mark(row["claims"][c]) for row in rows)] for c, claim in enumerate(claims)])


_MARKS = {chapter.REPRODUCED: "R", chapter.NOT_REPRODUCED: "-", chapter.UNDECIDABLE: "?", chapter.TURNS: "~"}


def _mark(row: dict) -> str:
    return _MARKS[row["verdict"]]
