"""The notebooks under nbval in the same pytest session as the unit tests (``make test``): each
notebook is one unit of work of pytest-xdist, so that its cells run in order on one worker, in one
kernel, and every unit test is a unit of its own; the notebooks go first, being the longest units,
so that the workers end together."""

from xdist.scheduler import LoadScopeScheduling


class NotebooksWhole(LoadScopeScheduling):
    """xdist's scheduling by scope, a notebook's scope its file and a test's scope itself (xdist's
    own ``--dist loadgroup`` cannot group nbval's cells: it renames tests in a way pytest 9 ignores)."""

    def _split_scope(self, nodeid: str) -> str:
        return nodeid.split("::")[0] if ".ipynb::" in nodeid else nodeid


def pytest_xdist_make_scheduler(config, log):
    return NotebooksWhole(config, log)


def pytest_collection_modifyitems(config, items):
    notebooks = [item for item in items if ".ipynb::" in item.nodeid]
    chosen = set(map(id, notebooks))
    items[:] = notebooks + [item for item in items if id(item) not in chosen]
