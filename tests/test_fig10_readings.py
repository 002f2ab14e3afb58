"""The Fig. 10 readings study: its configuration, a small run, and its tie to the committed results."""

import numpy as np
import pytest

from glamas import results
from glamas.experiments import fig10_readings as fr
from glamas.experiments import gridworld as gw
from glamas.paths import RESULTS


def test_every_reading_is_a_valid_2observe_configuration():
    config = fr.ReadingsConfig()
    assert config.readings[0] == next(iter(fr.READINGS))
    assert config.reading(config.readings[0]) == config.gridworld  # the first reading is the default
    for name in config.readings:
        assert config.reading(name).learners == ("two_observe",)
    assert len(fr.READINGS) - 1 >= 6  # at least six readings besides the reference rule


@pytest.mark.parametrize("changes, message", [
    ({"readings": ("sampled, L=1", "nonsense")}, "readings must be distinct names from"),
    ({"readings": ()}, "readings must be distinct names from"),
    ({"gridworld": gw.GridworldConfig()}, "learners=('two_observe',)"),
])
def test_bad_configurations_are_rejected(changes, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        fr.ReadingsConfig(**changes)


def test_a_small_study_runs_and_summarises():
    config = fr.ReadingsConfig(gridworld=gw.GridworldConfig(learners=("two_observe",), runs=2, episodes=300),
                               readings=("in_range, L=8", "no GLA: fixed rule delta <= 2"))
    result = fr.run(config, seed=1, workers=1)
    assert result.log.shape[:2] == (2, 2) and result.need_counts.shape == (2, 2, 9, 2)
    rows = fr.summary(result, config)
    assert rows[1]["coordinating"].tolist() == [1.0, 1.0] + [0.0] * 6  # the rule, not its idle GLAs
    assert "in_range, L=8" in fr.table(rows)


def test_the_committed_study_shares_the_committed_gridworld_2observe():
    """The default reading of data/results/fig10_readings.npz is data/results/gridworld.npz's 2observe."""
    study = fr.load(fr.ReadingsConfig())
    stored = results.load(RESULTS / "gridworld.npz", gw.GridworldConfig(), seed=0)
    k = list(stored["learners"]).index("two_observe")
    assert np.array_equal(study.log[0], stored["log"][k])
    assert np.array_equal(study.gla_parameters[0], stored["two_observe.u"])
    assert np.array_equal(study.gla_initial[0], stored["two_observe.u_initial"])
