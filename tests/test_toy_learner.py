"""A learner added without editing the library: a module of its own, outside the package, with a
setting and an output of its own, named by GLAMAS_LEARNERS, is trained by an existing figure script
from the command line (--learners, --set), its output stored in the result file by its name, and it
keeps the learner contract."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from glamas.experiments import gridworld as gw
from glamas.learners import contract, registry
from glamas.paths import REPO

TOY = '''
"""Agents that walk at random, each step with probability ``rate`` as their Q-learners would act,
counting their visits per cell (an output of their own)."""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from glamas import rng
from glamas.gridworld import rules
from glamas.learners import episode as ep
from glamas.learners.registry import register
from glamas.learners.spec import Learner
from glamas.qlearning import epsilon_greedy, q_update


@dataclass(frozen=True)
class Settings:
    rate: float = 0.5
    """Probability of acting on the Q-learner rather than at random."""

    def __post_init__(self):
        if not 0.0 <= self.rate <= 1.0:
            raise ValueError(f"rate must be in [0, 1], got {self.rate!r}")


class Walk(NamedTuple):
    rate: float


@njit(cache=True, nogil=True)
def run(world, learning, walk, schedule, q, visits, log, state):
    n = world.starts.shape[0]
    cells, done, actions, new_cells, rewards, bumped, collided, reached, acc = ep.buffers(n)
    for episode in range(schedule.episodes):
        ep.start_episode(world.starts, cells, done, acc)
        t = 0
        while t < schedule.max_steps and not ep.all_done(done):
            for i in range(n):
                if rng.uniform(state) < walk.rate:
                    actions[i] = epsilon_greedy(q[i, cells[i]], learning.exploit_prob, state)
                else:
                    actions[i] = rng.integer(state, rules.N_ACTIONS)
                visits[i, cells[i]] += 1.0
            collisions = rules.step(world, cells, done, actions, new_cells, rewards, bumped, collided, reached)
            for i in range(n):
                if not done[i]:
                    q_update(q[i], cells[i], actions[i], rewards[i], new_cells[i], reached[i],
                             learning.q_learning_rate, learning.discount)
            t += 1
            ep.end_step(t, cells, done, new_cells, rewards, reached, collisions, acc)
        ep.end_episode(log, episode, schedule.edges, acc, t, done)


LEARNER = register(Learner(
    name="toy_walk", label="toy walkers", kernel=run, table_shape=lambda cells, agents: (agents, cells, rules.N_ACTIONS),
    defaults=Settings(), inputs=lambda setup, gridmap: (Walk(setup.own.rate),),
    outputs=lambda setup, gridmap: {"visits": np.zeros((gridmap.n_agents, gridmap.n_cells))}, counters=("visits",)))
'''


@pytest.fixture(scope="module")
def toy(tmp_path_factory):
    """The toy learner's module in a directory of its own, imported here as GLAMAS_LEARNERS would."""
    directory = tmp_path_factory.mktemp("toy")
    (directory / "toy_walk.py").write_text(textwrap.dedent(TOY))
    sys.path.insert(0, str(directory))
    try:
        import toy_walk
        yield directory, toy_walk.LEARNER
    finally:
        sys.path.remove(str(directory))
        registry.unregister("toy_walk")
        sys.modules.pop("toy_walk", None)


def test_a_learner_of_ones_own_is_trained_from_the_command_line_with_its_setting_and_output(toy, tmp_path):
    directory, _ = toy
    env = {"PYTHONPATH": str(directory), "GLAMAS_LEARNERS": "toy_walk", "PATH": "/usr/bin:/bin"}
    done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig11a.py"), "--runs", "2", "--episodes", "40",
                           "--learners", "independent,toy_walk", "--set", "toy_walk.rate=0.2",
                           "--out", str(tmp_path / "figures"), "--results", str(tmp_path)],
                          capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    config = gw.GridworldConfig(runs=2, episodes=40, learners=("independent", "toy_walk"))
    with np.load(tmp_path / "gridworld.npz") as archive:
        assert '"rate": 0.2' in str(archive["__config__"])
        visits = archive["toy_walk.visits"]
    assert visits.shape == (2, 2, 25) and visits.sum() > 0  # runs, agents, cells
    assert config.own("toy_walk").rate == 0.5  # its default, held by its name


def test_a_learner_of_ones_own_keeps_the_contract(toy):
    _, learner = toy
    contract.check(learner)


def test_a_module_glamas_learners_cannot_import_is_one_warning_and_its_learners_are_unknown(tmp_path):
    env = {"GLAMAS_LEARNERS": "no_such_module", "PATH": "/usr/bin:/bin"}
    done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig11a.py"), "--learners", "toy_walk",
                           "--out", str(tmp_path), "--results", str(tmp_path)],
                          capture_output=True, text=True, env=env, timeout=120)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert lines[0] == ("warning: GLAMAS_LEARNERS names the module 'no_such_module', which cannot be imported (No "
                        "module named 'no_such_module'); put its directory on PYTHONPATH or correct the name; its learners are unknown")
    assert "error: --learners toy_walk: learners must be distinct names of registered learners" in lines[-1]


@pytest.mark.parametrize("source, fault", [
    ("def broken(:\n", "which has a syntax error (invalid syntax, "),
    ("raise RuntimeError('no licence for this learner')\n",
     "which fails on import (RuntimeError: no licence for this learner); correct it"),
    (TOY.replace('name="toy_walk"', 'name="independent"'),
     "which fails on import (UserError: a learner named 'independent' is registered already"),
])
def test_a_module_of_ones_own_that_fails_on_import_is_one_warning(tmp_path, source, fault):
    (tmp_path / "mine.py").write_text(textwrap.dedent(source))
    env = {"PYTHONPATH": str(tmp_path), "GLAMAS_LEARNERS": "mine", "PATH": "/usr/bin:/bin"}
    done = subprocess.run([sys.executable, "-c", "import glamas.learners.registry as r; print(sorted(r.LEARNERS)[:1])"],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    warning, = done.stderr.strip().splitlines()
    assert warning.startswith("warning: GLAMAS_LEARNERS names the module 'mine', " + fault)
    assert warning.endswith("; its learners are unknown")


def test_a_result_records_the_code_of_a_learner_of_ones_own(toy):
    """An edit of one's own learner makes its results stale, as an edit of the package's does."""
    from glamas import provenance, sources
    directory, _ = toy
    config = gw.GridworldConfig(runs=2, episodes=40, learners=("independent", "toy_walk"))
    recorded = provenance.code_record(config)
    assert "toy_walk (a learner of one's own)" in recorded
    assert "toy_walk (a learner of one's own)" not in provenance.code_record(gw.GridworldConfig())
    module = directory / "toy_walk.py"
    original = module.read_text()
    try:
        module.write_text(original.replace("rate: float = 0.5", "rate: float = 0.25"))
        form = {"code_form": sources.CODE_FORM, "python": provenance.python_version()}
        assert provenance.mismatch({"maps": {}, "code": recorded, "version": "x", **form},
                                   {"maps": {}, "code": provenance.code_record(config), "version": "x", **form}) \
            == "the code that computes it changed since it was made (toy_walk (a learner of one's own))"
    finally:
        module.write_text(original)


def test_a_learner_of_ones_own_whose_kernel_mistypes_its_arrays_is_the_users_fault(tmp_path):
    """Its kernel indexes its visits as (agents, cells), its outputs hand it one dimension: numba's
    typing error names the module, and the one line says the fault is there, not in glamas."""
    source = textwrap.dedent(TOY).replace('name="toy_walk"', 'name="toy_bad"').replace(
        '"visits": np.zeros((gridmap.n_agents, gridmap.n_cells))', '"visits": np.zeros(gridmap.n_cells)')
    (tmp_path / "toy_bad.py").write_text(source)
    env = {"PYTHONPATH": str(tmp_path), "GLAMAS_LEARNERS": "toy_bad", "PATH": "/usr/bin:/bin"}
    done = subprocess.run([sys.executable, str(REPO / "paper_figures" / "fig11a.py"), "--runs", "1", "--episodes", "2",
                           "--learners", "toy_bad", "--workers", "1", "--out", str(tmp_path / "figures"),
                           "--results", str(tmp_path / "results")],
                          capture_output=True, text=True, env=env, timeout=300, cwd=REPO)
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    line = done.stderr.strip().splitlines()[-1]
    named, _, rest = line.removeprefix("error: ").partition(" fails (")
    assert (REPO / named).resolve() == (tmp_path / "toy_bad.py").resolve()  # numba names it from the cwd
    assert rest.startswith("TypingError") and line.endswith("the fault is in that module, not in glamas; correct it")
