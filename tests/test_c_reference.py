"""The plain-C reference of the benchmarks (benchmarks/reference_gridworld.c) does the kernels' work:
on the same random stream it plays the very same episodes, so its log (steps, rewards, collisions
and coordinations per block) and its learned tables equal the compiled kernel's. Built only where
there is a C compiler."""

import dataclasses
import shutil

import numpy as np
import pytest

from benchmarks import c_reference, kernels
from glamas.gridworld.rewards import CHAPTER, FIELD, Rewards
from glamas.learners import episode as ep
from glamas.learners import two_observe

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    return c_reference.load(tmp_path_factory.mktemp("c-reference"))


@pytest.mark.parametrize("name", c_reference.LEARNERS)
@pytest.mark.parametrize("bounce", ["previous", "start"])
@pytest.mark.parametrize("map_file", ["tunnel_to_goal", "isr"])  # one goal shared, or each its own
@pytest.mark.parametrize("rewards", [CHAPTER, FIELD], ids=["chapter", "field"])  # read from Rewards, as the kernels'
def test_c_reference_plays_the_kernels_episodes(reference, name, bounce, map_file, rewards):
    workload = kernels.Workload(name, 1500, map_file, block=75, bounce=bounce, rewards=rewards)
    kernel, c = kernels.run_compiled(workload, seed=11), reference.run(workload, seed=11)
    log = kernel.log[0]
    assert ep.metric(log, "length").min() >= 1 and ep.metric(log, "collisions").sum() > 0  # episodes with collisions
    assert list(c.arrays) == list(kernel.arrays)  # log, Q tables (and 2observe's GLAs and need counts)
    for got, expected in zip(c.arrays.values(), kernel.arrays.values()):
        np.testing.assert_array_equal(got, expected)


def test_c_reference_reads_the_collision_reward(reference):
    """Another collision reward (the chapter's -10 in both presets) gives other rewards, the kernel's."""
    workload = kernels.Workload("independent", 1500, block=75, rewards=Rewards(collision=-25.0))
    c = reference.run(workload, seed=11).log[0]
    np.testing.assert_array_equal(c, kernels.run_compiled(workload, seed=11).log[0])
    chapter = reference.run(dataclasses.replace(workload, rewards=CHAPTER), seed=11).log[0]
    assert (ep.metric(c, "reward") < ep.metric(chapter, "reward")).any()


def test_c_reference_refuses_settings_it_does_not_implement(reference):
    workload = kernels.Workload("two_observe", 10, own=two_observe.GLASettings(gla_need="outcome"))
    with pytest.raises(ValueError, match="gla_need"):
        reference.run(workload)
