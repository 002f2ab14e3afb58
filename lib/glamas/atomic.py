"""Output files written whole or not at all, one writer of a directory at a time.

A file is written to a temporary file beside it and renamed over the target, so a reader (or a
run killed mid-write) never sees half a file. Writers of one directory hold an exclusive lock on
the directory itself, so that a check of what a file holds and its replacement happen together.
"""

import contextlib
import fcntl
import os
import tempfile
from pathlib import Path

from glamas.errors import UserError


@contextlib.contextmanager
def locked(directory):
    """Hold an exclusive lock on ``directory`` (created if missing) while the block runs; the
    lock goes with the process if it dies."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    fd = os.open(directory, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield directory
    finally:
        os.close(fd)


def write(path, write_to) -> Path:
    """Write ``path`` atomically: ``write_to(handle)`` fills a temporary file in the same directory,
    which then replaces ``path``. Call it with the directory :func:`locked`."""
    path = Path(path)
    remove_leftovers(path)  # under the lock, any temporary file of this name is a dead writer's
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f"{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as handle:
            write_to(handle)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp's 0600 would make the file private
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def remove_leftovers(path) -> None:
    """Delete the temporary files that writers of ``path`` killed mid-write left behind."""
    path = Path(path)
    for leftover in path.parent.glob(f"{path.name}*.tmp"):  # also the older '<name>XXXX.tmp' form
        leftover.unlink(missing_ok=True)


def check_writable_directory(directory, option: str) -> None:
    """Raise UserError unless ``directory`` is (or can be created as) a directory this process
    can write to; ``option`` names it in the message (e.g. '--out')."""
    directory = Path(directory)
    if directory.exists() and not directory.is_dir():
        raise UserError(f"{option} {directory} exists and is not a directory; give a directory path")
    try:
        directory.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):
            pass
    except OSError as error:
        raise UserError(f"{option} {directory} is not a writable directory ({error.strerror}); "
                         "give a directory you can write to") from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
