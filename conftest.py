"""The test session of ``make test``: the unit tests and the notebooks under nbval share the
workers of pytest-xdist.

* Each file is one unit of work (xdist's scheduling by file): a notebook's cells run in order on
  one worker, in one kernel, and the compiled pieces a test file calls from Python (2observe's
  steps, the coordination graph's maximisers) compile once, on one worker, not on both at once
  (docs/speed.md, the tests' time).
  The notebooks go first, being the longest units, then the files of the unit tests marked
  ``long`` (many seconds each), so that the workers end together.
* With a worker per core, each worker keeps to a core of its own, and so do the processes it
  starts: an experiment a test or a notebook runs at its default of one worker per core then runs
  in the test's process instead of starting worker processes that would only wait for the other
  test worker's core.
"""

import os

from xdist.scheduler import LoadFileScheduling


def pytest_xdist_make_scheduler(config, log):
    return LoadFileScheduling(config, log)


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
