"""The notebooks under nbval in the same pytest session as the unit tests (``make test``): each
notebook's cells form one xdist group (``--dist loadgroup``), so that they run in order on one
worker, in one kernel; the notebooks go first, being the longest units of work, so that the
workers end together."""

import pytest


def pytest_collection_modifyitems(config, items):
    notebooks = [item for item in items if ".ipynb::" in item.nodeid]
    for item in notebooks:
        item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::")[0]))
    chosen = set(map(id, notebooks))
    items[:] = notebooks + [item for item in items if id(item) not in chosen]
