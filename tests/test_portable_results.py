"""Results portable by test: a small run of every stored experiment (`glamas.small_runs`) gives the
bits committed in data/small_runs.json, on whatever machine the tests run. The committed paper-scale
results came from the same kernels, which use IEEE arithmetic without fastmath; a processor or C
library on which a kernel gives other bits fails here (and ``make verify`` would then differ)."""

import pytest

from glamas import small_runs


@pytest.mark.parametrize("name", sorted(small_runs.sizes()))
def test_a_small_run_gives_the_committed_bits(name):
    assert small_runs.small_digest(name, workers=1) == small_runs.committed()[name], (
        f"{name}'s small run gives other bits than data/small_runs.json records: if the code changed what the "
        "experiment computes, recompute its committed results and run `python -m glamas.small_runs --write`; "
        "otherwise this machine computes differently from the one that made the results")


def test_every_stored_experiment_has_a_small_run():
    assert [name for name, small in small_runs.sizes().items() if not {"runs", "iterations"} <= set(small or {})] == []
    assert sorted(small_runs.committed()) == sorted(small_runs.sizes())
