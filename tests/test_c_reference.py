"""The plain-C reference of the benchmarks (benchmarks/reference_gridworld.c) does the kernels' work:
on the same random stream it plays the very same episodes, so its log (mean steps, rewards,
collisions and coordinations per block) equals the compiled kernel's. Built only where there is a
C compiler."""

import shutil
import sys

import numpy as np
import pytest

from glamas.experiments import gridworld as gw
from glamas.learners import episode as ep
from glamas.learners import registry, spec
from glamas.paths import REPO
from glamas.rng import run_states

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    sys.path.insert(0, str(REPO / "benchmarks"))
    try:
        import c_reference
    finally:
        sys.path.pop(0)
    return c_reference.load(tmp_path_factory.mktemp("c-reference"))


def _outputs(name, config):
    """One run's outputs of learner ``name``, in kernel order."""
    outputs = spec.allocate(registry.get(name), config, config.gridmap(), config.schedule(), 1)
    return tuple(array[0] for array in outputs.values())


@pytest.mark.parametrize("name", gw.LEARNERS)
@pytest.mark.parametrize("bounce", ["previous", "start"])
def test_c_reference_plays_the_kernels_episodes(reference, name, bounce):
    config = gw.GridworldConfig(learners=(name,), episodes=1500, runs=1, bins=20, bounce=bounce)
    inputs = spec.kernel_inputs(registry.get(name), config, config.gridmap(), config.schedule())
    kernel, c = _outputs(name, config), _outputs(name, config)
    state = run_states(11, 1)[0]
    registry.get(name).kernel(*inputs, *kernel, state.copy())
    reference.run(name)(*inputs, *c, state.copy())
    log = kernel[-1]
    assert ep.metric(log, "length").min() >= 1 and ep.metric(log, "collisions").sum() > 0  # episodes with collisions
    for got, expected in zip(c, kernel):  # log, Q tables (and 2observe's GLAs and need counts)
        np.testing.assert_array_equal(got, expected)
