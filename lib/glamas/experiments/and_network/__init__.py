"""Experiment 2 of Section 4.2 (Fig. 7): each agent an AND network of two GLAs, the regions split by a
parabola, and the sweep in which raising region II's reward traps runs in 'R everywhere'. :mod:`.experiment`
configures and runs both, :mod:`.analysis` measures them and :mod:`.plots` draws them; this face hands
their names on (:mod:`glamas.experiments.faces`) and registers both, and experiment 2 under the other
parabolas."""

import functools
from pathlib import Path

from glamas.experiments.and_network.analysis import claim_rows, sweep_claim_rows
from glamas.experiments.and_network.experiment import (DEFAULT_SWEEP, PARABOLA_READINGS, ANDNetworkConfig,
                                                       ANDNetworkResult, SweepResult, other_readings, readings_arrays,
                                                       readings_from_arrays, run, scaled, sweep)
from glamas.experiments.faces import face
from glamas.experiments.registry import SEED, Experiment, register
from glamas.paths import RESULTS

__getattr__, __dir__ = face(__name__, __file__)

SMALL_RUN = {"runs": 2, "iterations": 2000}
"""The small run of each of its experiments."""

FIG7 = register(Experiment("and_network", ANDNetworkConfig, run, scaled, result=ANDNetworkResult,
                           claim_rows=lambda result, config: claim_rows(result, other_parabolas(config)),
                           figures=("fig7a", "fig7b"), small_run=SMALL_RUN, small_run_seconds=4,
                           recompute_minutes=0.5))
"""Fig. 7a and 7b's experiment (one run for both)."""
FIG7_READINGS = register(Experiment("and_network_readings", ANDNetworkConfig, other_readings, scaled,
                                    figures=("fig7_readings",), chapter=False, copies=len(PARABOLA_READINGS) - 1,
                                    to_arrays=readings_arrays, from_arrays=readings_from_arrays, small_run=SMALL_RUN,
                                    recompute_minutes=0.5))
"""Experiment 2 under the parabolas other than the default: what Fig. 7's claims are also judged under."""
FIG7_SWEEP = register(Experiment("and_network_sweep", ANDNetworkConfig, sweep, scaled, result=SweepResult,
                                 claim_rows=lambda result, config: sweep_claim_rows(result), figures=("fig7_sweep",),
                                 chapter=False, copies=len(DEFAULT_SWEEP) + 3, small_run=SMALL_RUN,
                                 recompute_minutes=1))
"""The stuck sweep: experiment 2 at each region II reward of DEFAULT_SWEEP, the highest reward's
rerun on another stream, and the lowest and highest reward from zero parameters."""


def load_sweep(config: ANDNetworkConfig = ANDNetworkConfig(), seed: int = 0, results_dir: Path = RESULTS) -> SweepResult:
    """The committed (or ``results_dir``'s) sweep of ``config`` and ``seed``, its configuration checked."""
    return FIG7_SWEEP.load(results_dir, config, seed)


@functools.cache
def other_parabolas(config: ANDNetworkConfig, seed: int = SEED) -> dict:
    """Experiment 2 under the parabolas other than ``config``'s (name -> result): at paper scale the
    committed result (its configuration and provenance checked), else computed at ``config``'s scale
    from the same seed (seconds). Once per process: the verdicts and the notebook read the same results."""
    return FIG7_READINGS.committed_or_run(config, seed)
