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
    g = config.gridmap()
    q = gw._MODULES[name].new_tables(g.n_cells, g.n_agents)
    log = np.zeros((config.edges().size - 1, ep.N_COLUMNS))
    if name != "two_observe":
        return q, log
    return q, np.zeros((2, 2, 2)), np.zeros((g.n_rows + g.n_cols - 1, 2)), log


@pytest.mark.parametrize("name", gw.LEARNERS)
@pytest.mark.parametrize("bounce", ["previous", "start"])
def test_c_reference_plays_the_kernels_episodes(reference, name, bounce):
    config = gw.GridworldConfig(learners=(name,), episodes=1500, runs=1, bins=20, bounce=bounce)
    inputs = gw._kernel_inputs(name, config, config.gridmap())
    kernel, c = _outputs(name, config), _outputs(name, config)
    state = run_states(11, 1)[0]
    gw._MODULES[name].run(*inputs, *kernel, state.copy())
    reference.run(name)(*inputs, *c, state.copy())
    log = kernel[-1]
    assert log[:, ep.LENGTH].min() >= 1 and log[:, ep.COLLISIONS].sum() > 0  # episodes with collisions
    for got, expected in zip(c, kernel):  # log, Q tables (and 2observe's GLAs and need counts)
        np.testing.assert_array_equal(got, expected)
