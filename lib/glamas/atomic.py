"""Output files written whole or not at all, one writer of a directory at a time.

A file is written to a temporary file beside it and renamed over the target, so a reader (or a
run killed mid-write) never sees half a file. Writers of one directory hold an exclusive lock on
the directory itself, so that a check of what a file holds and its replacement happen together.
A writer waits for such a lock at most LOCK_WAIT_SECONDS, then gives up naming who holds it.
"""

import contextlib
import fcntl
import os
import tempfile
import time
from pathlib import Path

from glamas.errors import UserError

LOCK_WAIT_SECONDS = 60.0
"""How long to wait for another process to release a lock: a lock is held for the seconds it
takes to check and write a file, so one held longer belongs to a process that is stuck or stopped
(suspended by Ctrl-Z, say), and waiting on would wait for ever."""
_LOCK_POLL_SECONDS = 0.05
written: list = []
"""Every file this process has written (:func:`write`), in order: what a command stopped midway
says it had written (:func:`glamas.errors.interrupted`)."""


class LockTimeoutError(UserError):
    """A lock another process has held for longer than LOCK_WAIT_SECONDS."""


@contextlib.contextmanager
def locked(directory):
    """Hold an exclusive lock on ``directory`` (created if missing) while the block runs; the
    lock goes with the process if it dies."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    fd = os.open(directory, os.O_RDONLY)
    try:
        wait_for_lock(fd, f"the directory {directory}")
        yield directory
    finally:
        os.close(fd)


def wait_for_lock(fd: int, what: str, seconds: float | None = None) -> None:
    """Take an exclusive lock on the open file ``fd`` (released when it is closed), waiting at
    most ``seconds`` (None: LOCK_WAIT_SECONDS) for another holder to release it;
    :class:`LockTimeoutError` naming ``what`` and the holder (:func:`lock_holder`) after that."""
    seconds = LOCK_WAIT_SECONDS if seconds is None else seconds
    deadline = time.monotonic() + seconds
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return
        except BlockingIOError:
            if time.monotonic() > deadline:
                raise LockTimeoutError(f"{what} has been locked by {lock_holder(fd)} for more than "
                                       f"{seconds:g} s; let it finish, or stop it and run again") from None
            time.sleep(_LOCK_POLL_SECONDS)


CHECK_SECONDS = 2.0
"""How long :func:`check_unlocked` waits: longer than a save holds a lock."""


def check_unlocked(directory) -> None:
    """Before a long computation whose result goes to ``directory``: refuse at once, naming the
    holder, when another process holds its lock for longer than a save takes (CHECK_SECONDS), so
    that the refusal does not come after the computation. Nothing is held afterwards: the save
    takes the lock again (:func:`locked`)."""
    directory = Path(directory)
    if not directory.is_dir():
        return
    fd = os.open(directory, os.O_RDONLY)
    try:
        wait_for_lock(fd, f"the directory {directory}", CHECK_SECONDS)
    finally:
        os.close(fd)


def lock_holder(fd: int) -> str:
    """Who holds the lock on the open file ``fd``: 'process PID (its command)', read from
    /proc/locks, or 'another process' where that cannot be known (no /proc; a file system that
    names the file differently there)."""
    status = os.fstat(fd)
    file = f"{os.major(status.st_dev):02x}:{os.minor(status.st_dev):02x}:{status.st_ino}"
    try:
        with open("/proc/locks") as locks:
            # '1: FLOCK  ADVISORY  WRITE PID MAJOR:MINOR:INODE 0 EOF'; a waiter's line has '->' after the number
            holders = [fields[4] for fields in map(str.split, locks) if len(fields) > 5 and fields[5] == file]
        with open(f"/proc/{holders[0]}/cmdline", "rb") as cmdline:
            command = cmdline.read().replace(b"\0", b" ").decode(errors="replace").strip()
    except (OSError, IndexError):
        return "another process"
    return f"process {holders[0]} ({command})"


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
    except BaseException as error:
        Path(tmp).unlink(missing_ok=True)
        if isinstance(error, OSError) and error.errno is not None and error.filename is None:
            raise OSError(error.errno, error.strerror, str(path)) from None  # a full disk, say: name the file
        raise
    written.append(path.resolve())
    return path


def write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (:func:`write`)."""
    return write(path, lambda handle: handle.write(text.encode()))


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
