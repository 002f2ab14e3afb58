"""Result files: NumPy ``.npz`` archives that carry the configuration that produced them.

Files are written atomically (temporary file, then rename) under a lock of their directory, never
replace a file made by a different configuration without ``overwrite`` (checked again at the
moment of writing, so two runs cannot silently replace each other's result), and are read with
``allow_pickle=False``. Besides the configuration, a file records what the result depends on
beyond it (:mod:`glamas.provenance`: the map files' hashes, the digests of the code that computed
it, the library's version) and is refused when that changed, or when it records nothing of the
kind (made by an older glamas); and the digests of its arrays, checked on loading, so that a
damaged or edited array is refused, naming it, before anything is drawn.
"""

import dataclasses
import json
import zipfile
import zlib
from pathlib import Path

import numpy as np

from glamas import atomic, committed, provenance
from glamas.errors import UserError

FORMAT = 1
_CONFIG_KEY = "__config__"
_PROVENANCE_KEY = "__provenance__"
_RESERVED = (_CONFIG_KEY, _PROVENANCE_KEY)
# What a damaged, truncated or foreign archive raises while it is read.
_UNREADABLE = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error, NotImplementedError)


class ResultFileError(UserError):
    """A result file is missing, unreadable, or was made by another configuration."""


class StaleResultError(ResultFileError):
    """A result file of the same configuration, made with other map files or library sources."""


class UnreadableResultError(ResultFileError):
    """A file that is not a readable glamas result file: damaged, truncated or foreign."""


def config_json(config, seed: int | None = None) -> str:
    """The canonical JSON text of a dataclass config and seed (with its type name and the file format)."""
    fields = dict(dataclasses.asdict(config), seed=seed)
    body = {"type": type(config).__name__, "format": FORMAT, "fields": fields}
    return json.dumps(body, sort_keys=True)


def save(path, config, arrays: dict, *, seed: int | None = None, overwrite: bool = False,
         replace_unreadable: bool = False) -> Path:
    """Write ``arrays`` with ``config`` (and the master ``seed``) to ``path`` atomically.

    An existing file made by a different configuration, or unreadable, is kept and an error
    raised, unless ``overwrite`` is set (or, for an unreadable file, ``replace_unreadable``); the
    check is made under the directory's lock, just before the write.
    """
    path = Path(path)
    reserved = sorted(set(_RESERVED) & set(arrays))
    if reserved:
        raise UserError(f"{reserved} are reserved for the configuration and its provenance")
    header = {_CONFIG_KEY: np.array(config_json(config, seed)),
              _PROVENANCE_KEY: np.array(json.dumps(provenance.record(config, arrays), sort_keys=True))}
    with atomic.locked(path.parent):
        if not overwrite:
            check_writable(path, config, seed=seed, replace_unreadable=replace_unreadable)
        atomic.write(path, lambda handle: np.savez_compressed(handle, **header, **arrays))
    return path


def check_writable(path, config, *, seed: int | None = None, replace_unreadable: bool = False) -> None:
    """Raise unless ``path`` is absent or already holds results of ``config`` (or, with
    ``replace_unreadable``, is unreadable).

    Call it before a long computation so that a refusal comes before the work, not after it.
    """
    path = Path(path)
    if not path.exists():
        return
    try:
        existing = stored_config(path, kept=True)
    except UnreadableResultError:
        if replace_unreadable:
            return
        raise
    if existing != config_json(config, seed):
        raise ResultFileError(
            f"{path} holds results of a different configuration and was not overwritten; " + _advice(
                path, "remove it, choose another results directory, or force the overwrite (--force)", "--force"))


def load(path, config, *, seed: int | None = None) -> dict:
    """The arrays stored in ``path``, after checking they were made by ``config`` and ``seed``
    with the map files and library sources there are now."""
    path = Path(path)
    if not path.exists():
        raise ResultFileError(f"no result file at {path}; " + _advice(path, "run the experiment to create it"))
    stored = stored_config(path)
    expected = config_json(config, seed)
    if stored != expected:
        raise ResultFileError(f"{path} is stale: it was made by another configuration "
                              f"({_difference(stored, expected)}); "
                              + _advice(path, "run the experiment again to refresh it", "--force"))
    return _recorded_arrays(path, _check_provenance(path, config))


def _recorded_arrays(path: Path, stored: dict) -> dict:
    """The arrays of ``path``, checked against the digests its record ``stored`` holds."""
    try:
        with open_archive(path) as archive:
            arrays = {key: archive[key] for key in archive.files if key not in _RESERVED}
    except _UNREADABLE as error:
        raise _unreadable(path, error) from None
    _check_arrays(path, stored.get("arrays"), arrays)
    return arrays


def stored_config(path, kept: bool = False) -> str:
    """The configuration's JSON text that ``path`` records (:func:`config_json`), checked to be an
    object of its type, format and fields (one line naming the file otherwise)."""
    path = Path(path)
    text = _read_text(path, _CONFIG_KEY, kept)
    try:
        header = json.loads(text)
    except json.JSONDecodeError:
        header = None
    if not (isinstance(header, dict) and isinstance(header.get("fields"), dict) and "type" in header):
        raise UnreadableResultError(f"{path} is damaged: its configuration is not one glamas writes, and it was "
                                    "kept; " + _advice(path, "run again with --rerun or --force to replace it"))
    return text


def stored_seed(path):
    """The master seed ``path`` records with its configuration."""
    return json.loads(stored_config(path))["fields"].get("seed")


def stored_provenance(path, text: str | None = None) -> dict:
    """The record of what made ``path`` (:mod:`glamas.provenance`; its ``text`` when read already),
    checked to be a JSON object."""
    path = Path(path)
    try:
        stored = json.loads(_read_text(path, _PROVENANCE_KEY) if text is None else text)
    except json.JSONDecodeError:
        stored = None
    if not isinstance(stored, dict):
        raise UnreadableResultError(f"{path} is damaged: its record of what made it is not one glamas writes, and "
                                    "it was kept; " + _advice(path, "run again with --rerun or --force to replace it"))
    return stored


def load_unchecked_code(path, config) -> dict:
    """The arrays of ``path``, its configuration and its arrays' digests checked, but not the code
    that computed it: for re-recording a result whose code changed without a change of behaviour
    (:mod:`glamas.small_runs`)."""
    path = Path(path)
    if json.loads(stored_config(path))["type"] != type(config).__name__:
        raise ResultFileError(f"{path} is not a result of {type(config).__name__}")
    return _recorded_arrays(path, stored_provenance(path))


def _check_provenance(path: Path, config) -> dict:
    """The provenance record of ``path``, after checking it against the current one."""
    try:
        text = _read_text(path, _PROVENANCE_KEY)
    except ResultFileError:
        raise StaleResultError(f"{path} records neither the maps nor the glamas version it was made "
                               "with (an older glamas made it); " + _advice(path, _REFRESH)) from None
    stored = stored_provenance(path, text)
    changed = provenance.mismatch(stored, provenance.record(config))
    if changed:
        code_only = provenance.mismatch({**stored, **provenance.current_code(config)}, provenance.record(config))
        advice = (committed.stale_advice(path.name) if code_only is None and committed.advice(path) is not None
                  else _advice(path, _REFRESH))
        raise StaleResultError(f"{path} is stale: {changed}; " + advice)
    return stored


def _check_arrays(path: Path, recorded: dict | None, arrays: dict) -> None:
    """Refuse, naming them, arrays that are not those the file recorded when it was written
    (added, missing, or with other contents: a damaged or edited file)."""
    if recorded is None:
        raise StaleResultError(f"{path} records no digests of its arrays (an older glamas made it); "
                               + _advice(path, _REFRESH))
    found = provenance.array_digests(arrays)
    missing, extra = sorted(set(recorded) - set(found)), sorted(set(found) - set(recorded))
    changed = sorted(name for name in set(found) & set(recorded) if found[name] != recorded[name])
    problems = ([f"arrays missing: {', '.join(missing)}"] if missing else []) \
        + ([f"arrays it did not record: {', '.join(extra)}"] if extra else []) \
        + ([f"arrays whose contents differ from those it recorded: {', '.join(changed)}"] if changed else [])
    if problems:
        raise UnreadableResultError(f"{path} is damaged or was edited ({'; '.join(problems)}) and was kept; "
                                    + _advice(path, "run again with --rerun or --force to replace it"))


def _read_text(path: Path, key: str, kept: bool = False) -> str:
    try:
        with open_archive(path) as archive:
            if key not in archive.files:
                raise KeyError(key)
            return str(archive[key])
    except _UNREADABLE as error:
        raise _unreadable(path, error, kept) from None


_ARCHIVE_STARTS = (b"PK\x03\x04", b"PK\x05\x06")
"""How a zip archive, the form of an .npz file, begins (the second: an empty one)."""


class NotAnArchiveError(UserError):
    """A file that is no zip archive: the message says what it is, for the caller's message about
    the file to give as the reason."""


def open_archive(path):
    """``np.load`` of ``path`` (pickled arrays refused) when it is a zip archive, the form of an
    .npz file; otherwise :class:`NotAnArchiveError` saying what the file is, which NumPy would call
    pickled data or load as something else."""
    with open(path, "rb") as handle:
        head = handle.read(64)
    if not head.startswith(_ARCHIVE_STARTS):
        raise NotAnArchiveError(f"it is {_kind(head)}, not a NumPy archive of arrays (.npz)")
    return np.load(path, allow_pickle=False)


def _kind(head: bytes) -> str:
    """What a file that begins with ``head`` holds, as far as its first bytes tell."""
    if not head:
        return "an empty file"
    if head.startswith(b"\x93NUMPY"):
        return "a single NumPy array (.npy)"
    if head.startswith(b"\x80"):
        return "pickled Python data"
    text = head.decode(errors="replace")
    if any(c == "\ufffd" or not (c.isprintable() or c.isspace()) for c in text[:-3]):  # 64 bytes may cut a character
        return "binary data of another format"
    return f"a text file beginning {text.strip().splitlines()[0][:40]!r}" if text.strip() else "a text file of blanks"


def _unreadable(path: Path, error: Exception, kept: bool = False) -> UnreadableResultError:
    """The error for ``path``, unreadable as ``error`` says; ``kept``: say that it was not overwritten."""
    reason = str(error).splitlines()[0] if str(error) else type(error).__name__
    return UnreadableResultError(
        f"{path} is not a readable glamas result file ({reason}){' and was not overwritten' if kept else ''}; "
        + _advice(path, "run again with --rerun or --force to replace it, or delete it"))


_REFRESH = "run the experiment again to refresh it (--rerun)"


def _advice(path: Path, usual: str, option: str = "--rerun") -> str:
    """What a message about result file ``path`` advises: ``usual``, or for a committed file its
    figure script run with ``option``, or git checkout (:mod:`glamas.committed`)."""
    return committed.advice(path, option) or usual


def _difference(stored: str, expected: str) -> str:
    old, new = json.loads(stored), json.loads(expected)
    if old.get("type") != new["type"] or old.get("format") != new["format"]:
        return f"file type {old.get('type')} format {old.get('format')}, expected {new['type']} format {new['format']}"
    changed = sorted(k for k in set(old["fields"]) | set(new["fields"])
                     if old["fields"].get(k) != new["fields"].get(k))
    return ", ".join(f"{k}: file {old['fields'].get(k)!r}, now {new['fields'].get(k)!r}" for k in changed)
