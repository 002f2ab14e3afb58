"""The library's source hash, and the compiled-kernel cache kept in step with it.

numba's on-disk cache (``cache=True``) keys a kernel on its own file only: after an edit to a
function it calls in *another* file, it would serve the old machine code. :func:`refresh_kernel_cache`
keeps a stamp file with the hash of every ``lib/glamas/**/*.py`` beside the cache
(``lib/glamas/__pycache__``, or numba's directory for the package under ``NUMBA_CACHE_DIR``);
when the sources no longer match it, the cached kernels (``*.nbi`` index and ``*.nbc`` data files)
are deleted and the stamp rewritten. glamas calls it on import, under a file lock, so that worker
processes importing at once do it once.
"""

import fcntl
import hashlib
import os
from pathlib import Path

PACKAGE = Path(os.path.abspath(os.path.dirname(__file__)))  # as numba names the cached files' sources
STAMP_NAME = "glamas-sources.sha256"
_LOCK_NAME = "glamas-sources.lock"
_CACHE_SUFFIXES = (".nbi", ".nbc")


def source_files(package: Path = PACKAGE) -> list[Path]:
    """The package's Python sources, in a fixed order."""
    return sorted(package.rglob("*.py"))


def source_hash(package: Path = PACKAGE) -> str:
    """SHA-256 over the package's sources (relative paths and contents): it changes with any edit."""
    digest = hashlib.sha256()
    for path in source_files(package):
        digest.update(path.relative_to(package).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()


def refresh_kernel_cache(package: Path = PACKAGE) -> bool:
    """Delete numba's cached kernels of ``package`` if its sources changed since the stamp was
    written; returns whether it did. A cache directory that cannot be written (an installed,
    read-only copy) is left alone."""
    home = cache_directory(package)
    try:
        home.mkdir(parents=True, exist_ok=True)
        lock = os.open(home / _LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
    except OSError:
        return False
    try:
        fcntl.flock(lock, fcntl.LOCK_EX)  # one importer checks and deletes; the others then find the new stamp
        return _refresh_locked(package, home / STAMP_NAME)
    finally:
        os.close(lock)  # releases the lock


def _refresh_locked(package: Path, stamp: Path) -> bool:
    current = source_hash(package)
    try:
        if stamp.read_text() == current:
            return False
    except OSError:
        pass  # no stamp yet: whatever is cached may predate it
    for path in cached_kernels(package):
        path.unlink(missing_ok=True)
    tmp = stamp.with_name(f"{stamp.name}.{os.getpid()}.tmp")
    tmp.write_text(current)
    os.replace(tmp, stamp)
    return True


def cache_directory(directory: Path) -> Path:
    """Where numba caches the kernels of the sources in ``directory``: its ``__pycache__``, or
    under ``NUMBA_CACHE_DIR`` the subdirectory numba names after the directory and its path's SHA-1."""
    root = os.environ.get("NUMBA_CACHE_DIR")
    if not root:
        return directory / "__pycache__"
    return Path(root) / f"{directory.name}_{hashlib.sha1(str(directory).encode()).hexdigest()}"


def cached_kernels(package: Path = PACKAGE) -> list[Path]:
    """numba's cache files (index and data) of the package's sources."""
    directories = {cache_directory(path.parent) for path in source_files(package)}
    return [path for directory in directories if directory.is_dir() for path in directory.iterdir()
            if path.suffix in _CACHE_SUFFIXES]
