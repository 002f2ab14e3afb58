"""What the face of every experiment package shares: it hands on the package's plotting functions
without importing them, so that running and measuring an experiment import no matplotlib; a
plotting function's module (``<package>.plots``, and matplotlib with it) is imported the first
time one of them is asked for."""

import importlib


def plots_on_first_use(package: str, names: tuple):
    """The module ``__getattr__`` of the face of ``package``: each of ``names`` is the function of
    that name in ``package.plots``, imported when it is first asked for."""
    def __getattr__(name: str):
        if name not in names:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f"{package}.plots"), name)
    return __getattr__
