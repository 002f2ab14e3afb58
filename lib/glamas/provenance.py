"""What a result depends on beyond its configuration: the map files it read, the code that computed
it, and the arrays it holds.

A config names its map (its field ``map``, with ``{n}`` for each of its ``agents`` in the
scaling study), not its content, and an experiment is named by its configuration, not by the code
that runs it: an edited map or an edited kernel would otherwise serve an old result as if it were
current. So a result records a digest of every map file it read and of every module of the code
that computed it (:func:`code_files`: the module of its configuration, the compiled kernels, and
every module of glamas they import, each digested without its comments and docstrings:
:func:`glamas.sources.code_digest`), with the library's version; a difference in any of them makes
it stale. It also records a digest of each of its arrays, which :mod:`glamas.results` checks on
loading, so that a damaged or edited array is found before anything is drawn from it.
"""

import dataclasses
import hashlib
import inspect
import sys
from pathlib import Path

import numpy as np

import glamas
from glamas import sources
from glamas.gridworld.maps import MapError, map_hash

MISSING = "missing"


def record(config, arrays: dict | None = None) -> dict:
    """``{"version", "maps": {field: hash of the map file}, "code": {module: digest}, "code_form",
    "python", "arrays": {name: digest}}`` of a result of ``config`` holding ``arrays`` (``code_form``:
    :data:`glamas.sources.CODE_FORM`; ``python``: the version that recorded the code, for messages)."""
    found = {"version": glamas.__version__, "maps": {field: file_hash(name) for field, name in map_files(config)},
             **current_code(config)}
    if arrays is not None:
        found["arrays"] = array_digests(arrays)
    return found


def current_code(config) -> dict:
    """The part of a record that says which code computes a result of ``config``, as it is now."""
    return {"code": code_record(config), "code_form": sources.CODE_FORM, "python": python_version()}


def python_version() -> str:
    return "{}.{}".format(*sys.version_info[:2])


def code_files(config) -> list[Path]:
    """The modules whose code computes a result of ``config``: its configuration's module, the
    module of every learner of glamas it trains (:func:`kernel_modules`), and every module of glamas
    these import, directly or not, but those that read or keep a result rather than make it
    (:func:`computes`). A learner it does not train is left out: the registry finds learners by
    name, not by import."""
    module = Path(inspect.getfile(type(config))).resolve()
    start = ([module] if module.is_relative_to(sources.PACKAGE) else [])
    start += [path for _, path in kernel_modules(config) if path.is_relative_to(sources.PACKAGE)]
    return sources.import_closure([path for path in start if computes(path)], follow=computes)


KEEPING = ("atomic.py", "committed.py", "errors.py", "paths.py", "provenance.py", "results.py", "sources.py",
           "tables.py", "experiments/registry.py", "experiments/faces.py", "learners/contract.py",
           "learners/__init__.py", "learners/registry.py")
"""Modules that keep, name, check or lay out results, find or check learners, keep numba's cache in
step with the sources or report errors, but compute nothing of a result (the learner contract runs
learners to test them, never for a result; the registry finds a learner by its name, and the
module of each learner a result trains is in its record: :func:`code_files`; the sources' module
digests the code and empties a stale cache, and a kernel it let through stale would still show in
the small runs that ``make test`` checks)."""
READING = ("__init__.py", "analysis.py", "plots.py")
"""The modules of an experiment's package that read its result: its face, its analysis, its plots."""


RUNNING = "parallel/"
"""The package that puts runs on workers (:mod:`glamas.parallel`): it decides who runs a run, never
its bits (a run draws from the stream :func:`glamas.rng.chunk_states` derives from the master seed and
its index, whatever the backend, the number of workers or the chunking: tests/test_backends.py), so
an edit there (a message, a backend) stales no result. A change of behaviour that slipped through it
would still show in the small runs that ``make test`` checks (:mod:`glamas.small_runs`)."""


def computes(path: Path) -> bool:
    """Whether module ``path`` can change what a result holds: not one of KEEPING, nor of RUNNING,
    nor a module of an experiment's package that reads its result (READING)."""
    relative = path.relative_to(sources.PACKAGE).as_posix()
    reading = relative.startswith("experiments/") and relative.count("/") == 2 and path.name in READING
    return relative not in KEEPING and not relative.startswith(RUNNING) and not reading


def code_record(config) -> dict:
    """{module's path in the package: :func:`glamas.sources.code_digest`} of :func:`code_files`, and
    the digest of the module of every learner of one's own (outside the package) that ``config``
    trains, by its module's name (:func:`own_learner_files`)."""
    record = {path.relative_to(sources.PACKAGE).as_posix(): sources.code_digest(path) for path in code_files(config)}
    record.update({f"{module} (a learner of one's own)": sources.code_digest(path)
                   for module, path in own_learner_files(config)})
    return record


def trained_learners(config) -> set:
    """The learner names of every ``learners`` field of ``config`` and of the configs inside it."""
    if not dataclasses.is_dataclass(config):
        return set()
    names = set()
    for field in dataclasses.fields(config):
        value = getattr(config, field.name)
        if field.name == "learners" and isinstance(value, (tuple, list)):
            names |= {name for name in value if isinstance(name, str)}
        names |= trained_learners(value)
    return names


def own_learner_files(config) -> list[tuple[str, Path]]:
    """(module name, file) of each learner ``config`` trains whose kernel is defined outside the
    package: a learner of one's own, whose edit must make its results stale as the package's do."""
    return [(name, path) for name, path in kernel_modules(config) if not path.is_relative_to(sources.PACKAGE)]


def kernel_modules(config) -> list[tuple[str, Path]]:
    """(module name, file) of the module defining the kernel of each learner ``config`` trains
    (:func:`trained_learners`)."""
    from glamas.learners import registry  # the registry imports the learners, which keep results

    found = set()
    for name in trained_learners(config):
        learner = registry.LEARNERS.get(name)
        module = sys.modules.get(getattr(getattr(learner, "kernel", None), "__module__", ""), None)
        if module is None:
            continue
        path = Path(getattr(module, "__file__", "") or "")
        if module.__name__.startswith(f"{sources.PACKAGE.name}."):  # read where the package's sources are
            path = sources.PACKAGE.joinpath(*module.__name__.split(".")[1:]).with_suffix(".py")
        if path.suffix == ".py":
            found.add((module.__name__, path.resolve()))
    return sorted(found)


def array_digests(arrays: dict) -> dict:
    """{name: :func:`digest` of the array}."""
    return {name: digest(array) for name, array in arrays.items()}


def digest(array: np.ndarray) -> str:
    """A short key of an array's content (its dtype, shape and bytes)."""
    array = np.ascontiguousarray(array)
    return hashlib.sha1(f"{array.dtype.str}{array.shape}".encode() + array.tobytes()).hexdigest()


def map_files(config, prefix: str = "") -> list[tuple[str, str]]:
    """(field, map name or path) of every map file a config (and the configs inside it) reads: its
    field ``map``, one per number of agents where it holds ``{n}``, or each of its field ``maps``."""
    found = []
    for field in dataclasses.fields(config):
        value, name = getattr(config, field.name), prefix + field.name
        if dataclasses.is_dataclass(value):
            found += map_files(value, f"{name}.")
        elif field.name == "map" and isinstance(value, str) and "{n}" in value and hasattr(config, "agents"):
            found += [(f"{name}[n={n}]", value.format(n=n)) for n in getattr(config, "agents", ())]
        elif field.name == "map" and isinstance(value, str):
            found.append((name, value))
        elif field.name == "maps" and isinstance(value, tuple):
            found += [(f"{name}[{map_name}]", map_name) for map_name in value if isinstance(map_name, str)]
    return found


def file_hash(name: str) -> str:
    """SHA-256 of the bytes of the map file ``name`` (:func:`glamas.gridworld.maps.map_hash`;
    MISSING if there is none or it cannot be read)."""
    try:
        return map_hash(name)
    except MapError:
        return MISSING


def mismatch(stored: dict, current: dict) -> str | None:
    """What differs between a stored and the current record, in words (None: nothing)."""
    if not (isinstance(stored, dict) and all(isinstance(stored.get(key, {}), dict) for key in ("maps", "code"))):
        return "its record of what made it is not one glamas writes"
    changed_maps = sorted(field for field in set(stored.get("maps", {})) | set(current["maps"])
                          if stored.get("maps", {}).get(field) != current["maps"].get(field))
    if changed_maps:
        return f"the map file of {', '.join(changed_maps)} changed since it was made"
    if "code" not in stored:
        return "it records not the code that computed it (an older glamas made it)"
    if stored.get("code_form") != current["code_form"]:
        return (f"its record of the code that computed it is in {stored.get('code_form') or 'an older'} form, not the "
                f"{current['code_form']} form this glamas compares, so whether that code changed is not known")
    changed_code = sorted(module for module in set(stored["code"]) | set(current["code"])
                          if stored["code"].get(module) != current["code"].get(module))
    if changed_code:
        shown = ", ".join(module if module.endswith("own)") else f"glamas/{module}" for module in changed_code[:3])
        more = f" and {len(changed_code) - 3} more" if len(changed_code) > 3 else ""
        python = stored.get("python")
        elsewhere = (f", or reads otherwise on Python {current['python']} than on Python {python}, which recorded it"
                     if python and python != current["python"] else "")
        return f"the code that computes it changed since it was made ({shown}{more}){elsewhere}"
    if stored.get("version") != current["version"]:
        return f"it was made by glamas {stored.get('version')}, this is glamas {current['version']}"
    return None
