"""What every learner promises, checked on any learner spec: ``check(learner)``, in the manner of
PettingZoo's ``parallel_api_test``. A new learner calls it in its tests (docs/extending.md); every
registered learner passes it (``tests/test_learner_contract.py``).

The promises, each a :class:`ContractError` naming the learner and the promise when broken:

* **the spec**: a name and a label; run kernels compiled by numba with ``cache=True`` and
  ``nogil=True`` (cached: compiled once per machine; without the GIL: threads run them at once);
  ``table_shape`` one table or one per agent, over the cells or the joint cells, of the four
  actions or the joint actions (checked before any run: a kernel indexes its tables unchecked);
* **outputs by name**: ``q`` first, then the learner's own outputs by name, then ``log``, each an
  array whose first axis is the run;
* **seeds**: the same master seed gives the same outputs, bit for bit, whether the runs go one
  after the other or on two workers in chunks of one run; another seed gives another log;
* **the log**: finite, each agent's steps from 1 to the cap, the episode's length their largest,
  the capped share in [0, 1], collisions and coordinations not negative;
* **freeze and evaluation**: the kernel played from a run's learned outputs with the Q-learning
  rate zero and its own bundles frozen (:attr:`glamas.learners.spec.Learner.freeze`) changes none
  of them (its :attr:`~glamas.learners.spec.Learner.counters` aside), and plays the same episodes
  from the same state;
* **the two-agent kernel**, where there is one: the same outputs as the general kernel on two agents.

Each promise is checked on a map of two agents and on one of three (the shapes of the chapter and
of many agents), for a few episodes.
"""

import os

import numpy as np
from numba.core.caching import NullCache

from glamas import parallel, rng, sources, training
from glamas.errors import UserError
from glamas.gridworld import GridMap, load_map
from glamas.gridworld.rules import N_ACTIONS
from glamas.learners import episode as ep

from glamas.learners.spec import Learner

MAPS = ("tunnel_to_goal", "warehouse_3")
"""The maps a learner is checked on: two agents sharing a goal behind a tunnel, three on an aisle."""


class ContractError(UserError, AssertionError):
    """A learner that breaks a promise of :mod:`glamas.learners.contract`."""


def check(learner: Learner, maps: tuple = MAPS, runs: int = 2, episodes: int = 20, max_steps: int = 200) -> None:
    """Check every promise of the module docstring for ``learner`` (at its default settings) on each
    of ``maps``, with ``runs`` runs of ``episodes`` episodes capped at ``max_steps`` steps; raise
    :class:`ContractError` at the first one broken."""
    _spec(learner)
    for name in maps:
        gridmap = load_map(name) if isinstance(name, str) else name
        _runs(learner, gridmap, runs, episodes, max_steps)


def _fail(learner: Learner, promise: str) -> None:
    raise ContractError(f"learner {learner.name!r} breaks its contract: {promise}")


def _spec(learner: Learner) -> None:
    if not isinstance(learner, Learner):
        raise ContractError(f"a learner is a glamas.learners.spec.Learner, got {type(learner).__name__}")
    if not (isinstance(learner.name, str) and learner.name and isinstance(learner.label, str) and learner.label):
        _fail(learner, "its name and label must be non-empty strings")
    for kernel in (learner.kernel, learner.two_agent_kernel):
        if kernel is None:
            continue
        options = getattr(kernel, "targetoptions", None)
        if options is None:
            _fail(learner, f"its kernel {kernel!r} is not compiled by numba (@njit(cache=True, nogil=True))")
        if not (_cached(kernel) and options.get("nogil")):
            _fail(learner, f"its kernel {kernel.py_func.__qualname__} must be compiled with cache=True and nogil=True")
    for cells, agents in ((25, 2), (35, 3)):
        shape = learner.table_shape(cells, agents)
        if not (isinstance(shape, tuple) and len(shape) == 3 and all(isinstance(k, int) and k >= 1 for k in shape)):
            _fail(learner, f"table_shape(cells, agents) must be three whole numbers >= 1, got {shape!r}")
        tables, states, actions = shape
        if tables not in (1, agents) or states not in (cells, cells ** agents) or actions not in (N_ACTIONS,
                                                                                               N_ACTIONS ** agents):
            _fail(learner, f"table_shape({cells}, {agents}) must be (1 or {agents} tables, {cells} or {cells}**{agents} "
                           f"states, {N_ACTIONS} or {N_ACTIONS}**{agents} actions), got {shape!r}: the kernels "
                           "index the tables by agent, cell (or joint cell) and action without bounds checks")


def _cached(kernel) -> bool:
    """Whether numba caches ``kernel`` (``cache=True``); taken as so where glamas turned numba's
    caching off for this process (:func:`glamas.sources.turn_caching_off`), which no kernel can show."""
    return not isinstance(kernel._cache, NullCache) or os.environ.get(sources.CACHE_OFF_VARIABLE) is not None


def _train(learner, setup, gridmap, schedule, runs, seed, workers, chunk=None, kernel=None) -> dict:
    """The filled outputs of ``runs`` runs (as :func:`glamas.training.train`, with ``kernel``
    in place of the learner's own where given)."""
    work, outputs = training.batch(learner, setup, gridmap, schedule, runs, seed)
    if kernel is not None:
        work = parallel.Batch(kernel, work.inputs, work.outputs, work.seed)
    parallel.run_many([work], workers=workers, chunk=chunk)
    return outputs


def _same(first: dict, second: dict) -> bool:
    return first.keys() == second.keys() and all(np.array_equal(first[k], second[k]) for k in first)


def _runs(learner: Learner, gridmap: GridMap, runs: int, episodes: int, max_steps: int) -> None:
    setup = learner.setup()
    schedule = ep.Schedule(episodes, ep.uniform_edges(episodes, 1), max_steps)
    where = f"on {gridmap.name}"
    outputs = _train(learner, setup, gridmap, schedule, runs, 7, parallel.Threads(1))
    own = list(learner.outputs(setup, gridmap))
    if list(outputs) != ["q", *own, "log"] or "q" in own or "log" in own:
        _fail(learner, f"its outputs must be q, its own by name, then log; got {list(outputs)} {where}")
    if any(not isinstance(outputs[k], np.ndarray) or outputs[k].shape[0] != runs for k in own):
        _fail(learner, f"each of its own outputs must be an array with one row per run {where}")
    if not _same(outputs, _train(learner, setup, gridmap, schedule, runs, 7, parallel.Threads(2), chunk=1)):
        _fail(learner, f"the same seed gives other outputs on two workers than on one {where}")
    if np.array_equal(outputs["log"], _train(learner, setup, gridmap, schedule, runs, 8, parallel.Threads(1))["log"]):
        _fail(learner, f"another master seed gives the same log: its runs do not draw from their own stream {where}")
    _log(learner, outputs["log"], gridmap.n_agents, max_steps, where)
    _frozen(learner, setup, gridmap, outputs, max_steps, where)
    if learner.two_agent_kernel is not None and gridmap.n_agents == 2:
        general = _train(learner, setup, gridmap, schedule, runs, 7, parallel.Threads(1), kernel=learner.kernel)
        if not _same(outputs, general):
            _fail(learner, f"its two-agent kernel and its general kernel give other outputs for two agents {where}")


def _log(learner: Learner, log: np.ndarray, n: int, max_steps: int, where: str) -> None:
    if not np.isfinite(log).all():
        _fail(learner, f"its log holds NaN or infinite values {where}")
    steps, length = log[..., :n], log[..., ep.column(n, ep.LENGTH)]
    if not ((steps >= 1) & (steps <= max_steps)).all() or not np.array_equal(length, steps.max(axis=-1)):
        _fail(learner, f"its log's steps must lie from 1 to the cap, the episode's length their largest {where}")
    capped = log[..., ep.column(n, ep.CAPPED)]
    counts = log[..., [ep.column(n, ep.COLLISIONS), ep.column(n, ep.COORDINATIONS)]]
    if not (((capped >= 0) & (capped <= 1)).all() and (counts >= 0).all()):
        _fail(learner, f"its log's capped share must lie in [0, 1], its collisions and coordinations >= 0 {where}")


def _frozen(learner: Learner, setup, gridmap: GridMap, outputs: dict, max_steps: int, where: str) -> None:
    """Run 0's learned outputs played twice as the experiments evaluate them, learning off
    (:func:`glamas.training.evaluations`): unchanged, the same episodes."""
    evaluation = training.Evaluation(5, (1.0,), per_episode=True)
    (played,) = training.evaluations(learner, setup, gridmap, evaluation, max_steps, 3)
    learned = [outputs[k][0] for k in outputs if k != "log"]
    kept = [k not in learner.counters for k in outputs if k != "log"]
    logs = []
    for _ in range(2):
        copies = [np.array(array) for array in learned]
        log = np.zeros((evaluation.episodes, ep.n_columns(gridmap.n_agents)))
        learner.kernel_for(gridmap.n_agents)(*played.inputs, *copies, log, rng.run_states(3, 1)[0])
        if not all(np.array_equal(copy, array) for copy, array, keep in zip(copies, learned, kept) if keep):
            _fail(learner, f"played with learning off (Q-learning rate 0, freeze), it changes what it learned {where}")
        logs.append(log)
    if not np.array_equal(*logs):
        _fail(learner, f"played with learning off from the same state, it plays other episodes {where}")
