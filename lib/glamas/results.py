"""Result files: NumPy ``.npz`` archives that carry the configuration that produced them.

Files are written atomically (temporary file, then rename), never replace a file made by a
different configuration, and are read with ``allow_pickle=False``.
"""

import dataclasses
import json
import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

FORMAT = 1
_CONFIG_KEY = "__config__"


class ResultFileError(Exception):
    """A result file is missing, unreadable, or was made by another configuration."""


def config_json(config, seed: int | None = None) -> str:
    """The canonical JSON text of a dataclass config and seed (with its type name and the file format)."""
    fields = dict(dataclasses.asdict(config), seed=seed)
    body = {"type": type(config).__name__, "format": FORMAT, "fields": fields}
    return json.dumps(body, sort_keys=True)


def save(path, config, arrays: dict, *, seed: int | None = None, overwrite: bool = False) -> Path:
    """Write ``arrays`` with ``config`` (and the master ``seed``) to ``path`` atomically.

    An existing file made by a different configuration is kept and an error raised, unless
    ``overwrite`` is set.
    """
    path = Path(path)
    if _CONFIG_KEY in arrays:
        raise ValueError(f"{_CONFIG_KEY!r} is reserved for the configuration")
    if not overwrite:
        check_writable(path, config, seed=seed)
    text = config_json(config, seed)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as handle:
            np.savez_compressed(handle, **{_CONFIG_KEY: np.array(text)}, **arrays)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp's 0600 would make results private
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_writable(path, config, *, seed: int | None = None) -> None:
    """Raise unless ``path`` is absent or already holds results of ``config``.

    Call it before a long computation so that a refusal comes before the work, not after it.
    """
    path = Path(path)
    if not path.exists():
        return
    try:
        existing = _read_config(path)
    except ResultFileError:
        existing = None
    if existing != config_json(config, seed):
        raise ResultFileError(
            f"{path} holds results of a different configuration (or is unreadable); it was not "
            "overwritten. Remove it, choose another results directory, or force the overwrite."
        )


def _read_config(path: Path) -> str:
    try:
        with np.load(path, allow_pickle=False) as archive:
            return str(archive[_CONFIG_KEY])
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError) as error:
        raise ResultFileError(f"{path} is not a readable glamas result file ({error}); "
                              "delete it and run the experiment again") from error


def load(path, config, *, seed: int | None = None) -> dict:
    """The arrays stored in ``path``, after checking they were made by ``config`` and ``seed``."""
    path = Path(path)
    if not path.exists():
        raise ResultFileError(f"no result file at {path}; run the experiment to create it")
    stored = _read_config(path)
    expected = config_json(config, seed)
    if stored != expected:
        raise ResultFileError(
            f"{path} is stale: it was made by another configuration "
            f"({_difference(stored, expected)}); run the experiment again to refresh it"
        )
    with np.load(path, allow_pickle=False) as archive:
        return {key: archive[key] for key in archive.files if key != _CONFIG_KEY}


def _difference(stored: str, expected: str) -> str:
    old, new = json.loads(stored), json.loads(expected)
    if old.get("type") != new["type"] or old.get("format") != new["format"]:
        return f"file type {old.get('type')} format {old.get('format')}, expected {new['type']} format {new['format']}"
    changed = sorted(k for k in set(old["fields"]) | set(new["fields"])
                     if old["fields"].get(k) != new["fields"].get(k))
    return ", ".join(f"{k}: file {old['fields'].get(k)!r}, now {new['fields'].get(k)!r}" for k in changed)
