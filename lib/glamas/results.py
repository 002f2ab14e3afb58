"""Result files: NumPy ``.npz`` archives that carry the configuration that produced them.

Files are written atomically (temporary file, then rename) under a lock of their directory, never
replace a file made by a different configuration without ``overwrite`` (checked again at the
moment of writing, so two runs cannot silently replace each other's result), and are read with
``allow_pickle=False``. Besides the configuration, a file records what the result depends on
beyond it (:mod:`glamas.provenance`: the map files' hashes, the library's version) and is
refused when that changed, or when it records nothing of the kind (made by an older glamas).
"""

import dataclasses
import json
import zipfile
import zlib
from pathlib import Path

import numpy as np

from glamas import atomic, provenance

FORMAT = 1
_CONFIG_KEY = "__config__"
_PROVENANCE_KEY = "__provenance__"
_RESERVED = (_CONFIG_KEY, _PROVENANCE_KEY)
# What a damaged, truncated or foreign archive raises while it is read.
_UNREADABLE = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error, NotImplementedError)


class ResultFileError(Exception):
    """A result file is missing, unreadable, or was made by another configuration."""


class StaleResultError(ResultFileError):
    """A result file of the same configuration, made with other map files or library sources."""


def config_json(config, seed: int | None = None) -> str:
    """The canonical JSON text of a dataclass config and seed (with its type name and the file format)."""
    fields = dict(dataclasses.asdict(config), seed=seed)
    body = {"type": type(config).__name__, "format": FORMAT, "fields": fields}
    return json.dumps(body, sort_keys=True)


def save(path, config, arrays: dict, *, seed: int | None = None, overwrite: bool = False) -> Path:
    """Write ``arrays`` with ``config`` (and the master ``seed``) to ``path`` atomically.

    An existing file made by a different configuration is kept and an error raised, unless
    ``overwrite`` is set; the check is made under the directory's lock, just before the write.
    """
    path = Path(path)
    reserved = sorted(set(_RESERVED) & set(arrays))
    if reserved:
        raise ValueError(f"{reserved} are reserved for the configuration and its provenance")
    header = {_CONFIG_KEY: np.array(config_json(config, seed)),
              _PROVENANCE_KEY: np.array(json.dumps(provenance.record(config), sort_keys=True))}
    with atomic.locked(path.parent):
        if not overwrite:
            check_writable(path, config, seed=seed)
        atomic.write(path, lambda handle: np.savez_compressed(handle, **header, **arrays))
    return path


def check_writable(path, config, *, seed: int | None = None) -> None:
    """Raise unless ``path`` is absent or already holds results of ``config``.

    Call it before a long computation so that a refusal comes before the work, not after it.
    """
    path = Path(path)
    if not path.exists():
        return
    try:
        existing = _read_text(path, _CONFIG_KEY)
    except ResultFileError as error:
        raise ResultFileError(f"{error}; it was not overwritten (--force replaces it)") from None
    if existing != config_json(config, seed):
        raise ResultFileError(
            f"{path} holds results of a different configuration and was not overwritten; remove "
            "it, choose another results directory, or force the overwrite (--force)"
        )


def load(path, config, *, seed: int | None = None) -> dict:
    """The arrays stored in ``path``, after checking they were made by ``config`` and ``seed``
    with the map files and library sources there are now."""
    path = Path(path)
    if not path.exists():
        raise ResultFileError(f"no result file at {path}; run the experiment to create it")
    stored = _read_text(path, _CONFIG_KEY)
    expected = config_json(config, seed)
    if stored != expected:
        raise ResultFileError(
            f"{path} is stale: it was made by another configuration "
            f"({_difference(stored, expected)}); run the experiment again to refresh it"
        )
    _check_provenance(path, config)
    try:
        with np.load(path, allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files if key not in _RESERVED}
    except _UNREADABLE as error:
        raise _unreadable(path, error) from None


def _check_provenance(path: Path, config) -> None:
    try:
        stored = json.loads(_read_text(path, _PROVENANCE_KEY))
    except ResultFileError:
        raise StaleResultError(f"{path} records neither the maps nor the glamas version it was made "
                               "with (an older glamas made it); run the experiment again to refresh it (--rerun)") from None
    changed = provenance.mismatch(stored, provenance.record(config))
    if changed:
        raise StaleResultError(f"{path} is stale: {changed}; run the experiment again to refresh it (--rerun)")


def _read_text(path: Path, key: str) -> str:
    try:
        with np.load(path, allow_pickle=False) as archive:
            if key not in archive.files:
                raise KeyError(key)
            return str(archive[key])
    except _UNREADABLE as error:
        raise _unreadable(path, error) from None


def _unreadable(path: Path, error: Exception) -> ResultFileError:
    reason = str(error).splitlines()[0] if str(error) else type(error).__name__
    return ResultFileError(f"{path} is not a readable glamas result file ({reason}); "
                           "delete it and run the experiment again")


def _difference(stored: str, expected: str) -> str:
    old, new = json.loads(stored), json.loads(expected)
    if old.get("type") != new["type"] or old.get("format") != new["format"]:
        return f"file type {old.get('type')} format {old.get('format')}, expected {new['type']} format {new['format']}"
    changed = sorted(k for k in set(old["fields"]) | set(new["fields"])
                     if old["fields"].get(k) != new["fields"].get(k))
    return ", ".join(f"{k}: file {old['fields'].get(k)!r}, now {new['fields'].get(k)!r}" for k in changed)
