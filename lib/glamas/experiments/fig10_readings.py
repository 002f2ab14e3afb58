"""Fig. 10 as an inverse problem: 2observe under several readings of its lost GLA feedback.

The chapter's Fig. 10 (the GLAs' rewards) is lost; what survives is the text around it (Sections
5.1-5.3, see :mod:`glamas.learners.two_observe`) and the outcome it reports (Fig. 11-12). Each
reading below fixes what the text leaves open: what "need to coordinate" means, the table's
values, and the GLA's box and context. Every reading is trained at the chapter's scale and judged
by the same Section 5.3 claims against the same baselines (the independent, joint-state and MMDP
learners of :mod:`glamas.experiments.gridworld`, which do not depend on the reading), so a reader
sees which readings of the lost figure give the chapter's reported outcome and which do not.
"""

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from glamas import parallel
from glamas.errors import UserError
from glamas.experiments import gridworld as gw
from glamas.experiments.registry import Experiment, register
from glamas.paths import RESULTS
from glamas.plotting import legend_below

READINGS = {
    "in_range, L=8": {},
    "in_range, L=8, init 1": {"gla_init_range": 1.0},
    "in_range, L=8, unit delta": {"gla_delta_scale": "unit"},
    "in_range, L=8, unit delta, init 1": {"gla_delta_scale": "unit", "gla_init_range": 1.0},
    "in_range, L=1": {"gla_L": 1.0},
    "in_range, unit delta, L=1": {"gla_delta_scale": "unit", "gla_L": 1.0},
    "in_range, coordinating never wrong": {"gla_feedback": ((1.0, 0.0), (1.0, 1.0))},
    "sampled, L=1": {"gla_need": "sampled", "gla_L": 1.0},
    "sampled, L=8": {"gla_need": "sampled"},
    "outcome, L=8": {"gla_need": "outcome"},
    "no GLA: fixed rule delta <= 2": {"rule_distance": 3},
}
"""Each reading as its changes to the 2observe defaults of GridworldConfig (the first is the
default: need = in range, L = 8, delta in cells, parameters initialised in [-0.1, 0.1], the
symmetric 1/0 table). 'init 1' starts the parameters in [-1, 1], 'unit delta' divides delta by the
map's largest distance. 'sampled, L=1' is the reading this repository used before the text's own
"range of interference" was read into it. The last is not a reading but the reference: the first
level replaced by the rule the readings aim at, "coordinate when the agents could collide this
step" (delta <= 2 is that rule for an agent that sees only delta)."""

DELTAS = np.arange(1, 9)
"""The distances at which the learned P(coordinate | delta) is reported (TunnelToGoal: 1 to 8)."""


@dataclass(frozen=True)
class ReadingsConfig:
    """The sensitivity study: 2observe's settings and which readings of Fig. 10 to train."""

    gridworld: gw.GridworldConfig = gw.GridworldConfig(learners=("two_observe",))
    """2observe's settings (the chapter's, and the default reading) that each reading changes."""
    readings: tuple = tuple(READINGS)
    """Names of the readings to train (keys of READINGS)."""

    def __post_init__(self):
        if not isinstance(self.gridworld, gw.GridworldConfig) or self.gridworld.learners != ("two_observe",):
            raise UserError("gridworld must be a GridworldConfig with learners=('two_observe',)")
        readings = tuple(self.readings)
        if not readings or len(set(readings)) != len(readings) or not set(readings) <= set(READINGS):
            raise UserError(f"readings must be distinct names from {list(READINGS)}, got {self.readings!r}")
        object.__setattr__(self, "readings", readings)

    def memory_bytes(self) -> int:
        """Bytes of every reading's runs (each a run of 2observe's experiment)."""
        return sum(self.reading(name).memory_bytes() for name in self.readings)

    def reading(self, name: str) -> gw.GridworldConfig:
        """2observe's configuration under reading ``name``."""
        return replace(self.gridworld, **READINGS[name])


@dataclass(frozen=True)
class ReadingsResult:
    """2observe's learning curves and final GLAs under each reading (first axis: ``readings``)."""

    config: ReadingsConfig
    """The configuration that produced the arrays."""
    log: np.ndarray
    """(readings, runs, bins, columns): as GridworldResult.log for 2observe."""
    gla_parameters: np.ndarray
    """(readings, runs, agents, 2, 2): the final GLA parameters."""
    gla_initial: np.ndarray
    """(readings, runs, agents, 2, 2): the GLA parameters the runs started from."""
    need_counts: np.ndarray
    """(readings, runs, deltas, 2): observing agent-steps per distance without / with need."""
    episodes: np.ndarray
    """int (bins,): the episode count at the end of each block."""

    def gridworld_result(self, k: int) -> gw.GridworldResult:
        """Reading k's 2observe as a GridworldResult of one learner."""
        return gw.GridworldResult(config=self.config.reading(self.config.readings[k]),
                                  learners=np.array([gw.LEARNERS.index("two_observe")]), log=self.log[k:k + 1],
                                  table_shapes=np.zeros((1, 3), np.int64), gla_parameters=self.gla_parameters[k],
                                  gla_initial=self.gla_initial[k],
                                  need_counts=self.need_counts[k], episodes=self.episodes)


def run(config: ReadingsConfig = ReadingsConfig(), seed: int = 0, workers=None, progress=None) -> ReadingsResult:
    """Train 2observe under every reading of ``config``, each with the same seed (so the readings
    share their random streams and differ only by what they read into Fig. 10), all readings' runs
    on one pool of workers."""
    readings = [config.reading(name) for name in config.readings]
    work = [gw.trainings(reading, seed) for reading in readings]
    parallel.run_many([batch for trainings in work for batch, _ in trainings], workers=workers, progress=progress)
    parts = [gw.result_of(reading, [outputs for _, outputs in trainings], seed)
             for reading, trainings in zip(readings, work)]
    return ReadingsResult(config=config, log=np.concatenate([p.log for p in parts]),
                          gla_parameters=np.stack([p.gla_parameters for p in parts]),
                          gla_initial=np.stack([p.gla_initial for p in parts]),
                          need_counts=np.stack([p.need_counts for p in parts]), episodes=parts[0].episodes)


def load(config: ReadingsConfig = ReadingsConfig(), seed: int = 0, results_dir: Path = RESULTS) -> ReadingsResult:
    """The committed study of ``config`` (``results_dir/fig10_readings.npz``), its configuration checked."""
    return EXPERIMENT.load(results_dir, config, seed)


def with_baselines(result: ReadingsResult, k: int, baselines: gw.GridworldResult) -> gw.GridworldResult:
    """``baselines`` (the four learners' result) with 2observe replaced by reading k's."""
    return gw.with_learner(baselines, result.gridworld_result(k), "two_observe")


def summary(result: ReadingsResult, config: ReadingsConfig, baselines: gw.GridworldResult | None = None) -> list[dict]:
    """Per reading: final steps, reward, collisions and coordinations, the share of final GLAs that
    coordinate (P(coordinate) > 1/2) at each of DELTAS, the shares of GLAs stuck on a saturated
    wrong choice at the start and at the end (as gw.measure finds them) and, given the ``baselines``, the
    Section 5.3 claim rows."""
    rows = []
    for k, name in enumerate(config.readings):
        alone = result.gridworld_result(k)
        reading = config.reading(name)
        m = gw.measure(alone)
        learns = reading.rule_distance is None
        row = {"reading": name, "steps": m["steps_two_observe"], "reward": m["reward_two_observe"],
               "collisions": m["collisions_two_observe"], "coordinations": m["coordinations_two_observe"],
               "coordinating": coordinating_share(alone, reading),
               "stuck_at_start": m["stuck_at_start_share_two_observe"] if learns else math.nan,
               "stuck_at_end": m["stuck_at_end_share_two_observe"] if learns else math.nan}
        if baselines is not None:
            row["claims"] = gw.claim_rows(with_baselines(result, k, baselines))
        rows.append(row)
    return rows


def coordinating_share(result: gw.GridworldResult, config: gw.GridworldConfig) -> np.ndarray:
    """At each of DELTAS, the share of 2observe's final GLAs that coordinate (probability above
    1/2; the fixed rule's 0 or 1): how many GLAs learned to coordinate there, not an average
    probability, which would read a mix of GLAs at 0 and at 1 as one soft GLA."""
    return (gw.coordination_probability(result, config, DELTAS) > 0.5).mean(axis=(0, 1))


def table(rows: list[dict]) -> str:
    """The readings side by side: final values, the share of GLAs coordinating at each distance,
    the shares of stuck GLAs at the start and the end, and the claim count."""
    head = (f"{'reading':36s} {'steps':>6s} {'reward':>6s} {'collis.':>7s} {'coord.':>6s}  "
            f"coordinating at delta = {', '.join(str(d) for d in DELTAS)}   stuck start/end")
    if "claims" in rows[0]:
        head += "   claims reproduced"
    lines = [head]
    for row in rows:
        shares = " ".join(f"{v:4.2f}" for v in row["coordinating"])
        stuck = "   -   " if math.isnan(row["stuck_at_start"]) else f"{row['stuck_at_start']:.2f}/{row['stuck_at_end']:.2f}"
        line = (f"{row['reading']:36s} {row['steps']:6.2f} {row['reward']:6.1f} {row['collisions']:7.3f} "
                f"{row['coordinations']:6.2f}  {shares:48s} {stuck:>9s}")
        if "claims" in row:
            line += f"   {sum(r['holds'] for r in row['claims'])} of {len(row['claims'])}"
        lines.append(line)
    return "\n".join(lines)


def verdict_table(rows: list[dict]) -> str:
    """Claim by reading: R reproduced, - not reproduced, ? undecidable."""
    claims = [r["claim"].id for r in rows[0]["claims"]]
    lines = [f"{'claim':40s} " + " ".join(f"{k + 1:>2d}" for k in range(len(rows)))]
    for c, claim in enumerate(claims):
        marks = [_mark(row["claims"][c]) for row in rows]
        lines.append(f"{claim:40s} " + " ".join(f"{m:>2s}" for m in marks))
    lines.append("readings: " + "; ".join(f"{k + 1} = {row['reading']}" for k, row in enumerate(rows)))
    return "\n".join(lines)


def _mark(row: dict) -> str:
    if math.isnan(row["value"]):
        return "?"
    return "R" if row["holds"] else "-"


def _colour(row: dict) -> str:
    """A reading's colour in both panels: its place in READINGS among the ten of matplotlib's
    cycle; the reference rule, the last reading, in black."""
    k = list(READINGS).index(row["reading"])
    return "black" if k == len(READINGS) - 1 else f"C{k % 10}"


def plot_coordination(ax, rows: list[dict]):
    """The share of final GLAs that coordinate at each distance under each reading, against the
    rule "coordinate when the agents could collide this step" (delta <= 2)."""
    for k, row in enumerate(rows):
        ax.plot(DELTAS, row["coordinating"], "o-", label=f"{k + 1}: {row['reading']}", color=_colour(row),
                linewidth=2.5 if k == 0 else 1.2)
    ax.step(DELTAS, (DELTAS <= 2).astype(float), where="mid", color="black", linestyle="--",
            label="could collide (delta <= 2)")
    ax.set_xlabel("delta (Manhattan distance between the agents)")
    ax.set_ylabel("share of GLAs that coordinate (P > 1/2)")
    ax.set_ylim(-0.03, 1.03)
    legend_below(ax, ncols=2)


def plot_collisions(ax, rows: list[dict]):
    """Final collisions per episode under each reading (log axis), against the chapter's "zero
    collisions" (at most one per 20 episodes, the claim's threshold)."""
    y = np.arange(len(rows))[::-1]
    ax.barh(y, [row["collisions"] for row in rows], color=[_colour(row) for row in rows])
    ax.set_yticks(y, [f"{k + 1}: {row['reading']}" for k, row in enumerate(rows)], fontsize="small")
    ax.axvline(0.05, color="black", linestyle="--", linewidth=1, label="zero collisions (claim: <= 0.05)")
    ax.set_xscale("log")
    ax.set_xlabel("final collisions per episode")
    legend_below(ax, ncols=1)


# --- the experiment of the figure script (paper_figures/fig10_readings.py) ---------------------

def scaled(runs: int, episodes: int) -> ReadingsConfig:
    """The study at ``runs`` and ``episodes``."""
    return ReadingsConfig(gridworld=gw.GridworldConfig(learners=("two_observe",), runs=runs, episodes=episodes))


EXPERIMENT = register(Experiment("fig10_readings", ReadingsConfig, run, scaled, gw.GridworldConfig.runs,
                                 gw.GridworldConfig.episodes, ReadingsResult, figures=("fig10_readings",),
                                 chapter=False))
"""The readings of Fig. 10 (no claims of its own: :func:`summary` judges each reading by Sec. 5.3's)."""
