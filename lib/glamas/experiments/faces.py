"""What the face (``__init__``) of every experiment package shares: it hands on every public name its
:mod:`.experiment`, :mod:`.analysis` and :mod:`.plots` modules define, so that a package lists none
of them, and it imports ``plots`` (and matplotlib with it) only when one of its names is first asked
for, so that running and measuring an experiment import no matplotlib."""

import ast
import functools
import importlib
import sys
from pathlib import Path

MODULES = ("experiment", "analysis", "plots")
"""The modules of a package whose names its face hands on; a name in two is the first's."""


def defined_names(path: Path) -> list:
    """The public names a module's top level defines (functions, classes, assigned names), read
    from its source, so that the module is not imported to know them."""
    names = []
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.append(node.name)
        elif isinstance(node, ast.Assign):
            names += [target.id for target in node.targets if isinstance(target, ast.Name)]
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.append(node.target.id)
    return [name for name in names if not name.startswith("_")]


def handed_on(package: str, directory: Path) -> dict:
    """Each name the face of ``package`` (its source in ``directory``) hands on -> its module's name."""
    found: dict = {}
    for module in MODULES:
        if (directory / f"{module}.py").exists():
            for name in defined_names(directory / f"{module}.py"):
                found.setdefault(name, f"{package}.{module}")
    return found


def face(package: str, file: str):
    """The module ``__getattr__`` and ``__dir__`` of the face of ``package`` (its ``__init__`` at
    ``file``): each name of :func:`handed_on` is looked up in its module, imported when first asked
    for. The names are read on first use too: finding every experiment parses no module."""
    names = functools.cache(lambda: handed_on(package, Path(file).parent))

    def __getattr__(name: str):
        if name not in names():
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(names()[name]), name)

    def __dir__():
        return sorted(set(vars(sys.modules[package])) | set(names()))
    return __getattr__, __dir__
