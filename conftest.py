"""The test session of ``make test``: the unit tests and the notebooks under nbval share the
workers of pytest-xdist.

* Each notebook is one unit of work, so that its cells run in order on one worker, in one kernel,
  and so is each test function with all its parameters: the compiled pieces a test calls from
  Python (2observe's steps, the coordination graph's maximisers) compile once, on one worker, where
  parameters spread over both workers compiled each on both at once (about 5 of the 45 seconds
  the tests spent compiling on a fresh cache). The notebooks go first, being the longest units, then the unit
  tests marked ``long`` (many seconds each), so that the workers end together. (xdist's own
  ``--dist loadgroup`` cannot group nbval's cells: it renames tests in a way pytest 9 ignores.)
* With a worker per core, each worker keeps to a core of its own, and so do the processes it
  starts: an experiment a test or a notebook runs at its default of one worker per core then runs
  in the test's process instead of starting worker processes that would only wait for the other
  test worker's core.
"""

import os

from xdist.scheduler import LoadScopeScheduling


class NotebooksWhole(LoadScopeScheduling):
    """xdist's scheduling by scope, a notebook's scope its file and a test's scope its function
    (all its parameters)."""

    def _split_scope(self, nodeid: str) -> str:
        return nodeid.split("::")[0] if ".ipynb::" in nodeid else nodeid.split("[")[0]


def pytest_xdist_make_scheduler(config, log):
    return NotebooksWhole(config, log)


def pytest_configure(config):
    worker = getattr(config, "workerinput", None)
    if worker is None or not hasattr(os, "sched_setaffinity"):
        return
    cores = sorted(os.sched_getaffinity(0))
    if worker["workercount"] >= len(cores):
        os.sched_setaffinity(0, {cores[int(worker["workerid"].removeprefix("gw")) % len(cores)]})


def pytest_collection_modifyitems(config, items):
    notebooks = [item for item in items if ".ipynb::" in item.nodeid]
    long = [item for item in items if item.get_closest_marker("long")]
    chosen = set(map(id, notebooks + long))
    items[:] = notebooks + long + [item for item in items if id(item) not in chosen]
