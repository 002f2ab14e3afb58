"""What a result depends on beyond its configuration: the map files it read and the library's
version.

A config names its map (its field ``map``, with ``{n}`` for each of its ``agents`` in the
scaling study), not its content; an edited map or library would otherwise serve an old result as if it were current.
The library is recorded by its version, ``glamas.__version__``, which a change that alters what
an experiment computes must raise (the tests that recompute the committed results catch a change
that forgets to): a hash of the sources would make every committed result stale at every edit of a
comment.
"""

import dataclasses

import glamas
from glamas.gridworld.maps import MapError, map_hash

MISSING = "missing"


def record(config) -> dict:
    """``{"version": glamas.__version__, "maps": {field: hash of the map file's bytes}}``."""
    return {"version": glamas.__version__, "maps": {field: file_hash(name) for field, name in map_files(config)}}


def map_files(config, prefix: str = "") -> list[tuple[str, str]]:
    """(field, map name or path) of every map file a config (and the configs inside it) reads: its
    field ``map``, one per number of agents where it holds ``{n}``, or each of its field ``maps``."""
    found = []
    for field in dataclasses.fields(config):
        value, name = getattr(config, field.name), prefix + field.name
        if dataclasses.is_dataclass(value):
            found += map_files(value, f"{name}.")
        elif field.name == "map" and isinstance(value, str) and "{n}" in value:
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
    changed_maps = sorted(field for field in set(stored.get("maps", {})) | set(current["maps"])
                          if stored.get("maps", {}).get(field) != current["maps"].get(field))
    if changed_maps:
        return f"the map file of {', '.join(changed_maps)} changed since it was made"
    if stored.get("version") != current["version"]:
        return f"it was made by glamas {stored.get('version')}, this is glamas {current['version']}"
    return None
