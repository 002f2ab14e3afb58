"""What glamas reports as the user's to fix, and the one way every command reports an error.

A :class:`UserError` is bad input or a fault outside the program (a damaged file, an unwritable
directory, an unreachable cluster). A command stops on one with one line ``error: ...`` on stderr
and exit status 2, without a traceback: the traceback would point into glamas while the fix lies
outside it, and the message says what the fix is. An OSError (a file that cannot be read or
written) is reported the same way. Anything else is a bug in glamas: it keeps its traceback,
followed by one line asking for a report.

An interrupt (Ctrl-C) or a SIGTERM stops a command the same way wherever it is: the workers of
its run stopped, no file half-written, one line saying what it had written (exit status 130 or
143, the shell's for the signal).

Every entry point (the figure scripts, ``python -m glamas.reproduce``, ``glamas.verify``,
``glamas.ledger``, the benchmarks) ends with ``errors.run(main)``.
"""

import contextlib
import re
import shlex
import signal
import sys
import threading
import traceback
from pathlib import Path

EXIT_USER_ERROR = 2
"""Exit status of a user error (argparse's for a bad option)."""
EXIT_BUG = 70
"""Exit status of a bug in glamas (sysexits' EX_SOFTWARE): apart from the statuses a command gives
on purpose, such as glamas.verify's 1 for a difference."""


class UserError(ValueError):
    """Bad input or a fault outside the program: reported as one line without a traceback.

    A ValueError, so that code and tests that catch ValueError for bad input keep catching it."""


class Reported(SystemExit):
    """A user error already reported on stderr: exit status 2; ``str()`` is the message."""

    def __init__(self, message: str):
        super().__init__(EXIT_USER_ERROR)
        self.message = message

    def __str__(self) -> str:
        return self.message


@contextlib.contextmanager
def reported():
    """A user error (or OSError) inside becomes one line ``error: ...`` on stderr and exit status 2
    (:class:`Reported`); anything else passes through."""
    try:
        yield
    except (UserError, OSError) as error:
        message = one_line(error)
        print(f"error: {message}", file=sys.stderr)
        raise Reported(message) from None


class Stopped(KeyboardInterrupt):
    """A SIGTERM, raised where the main thread is, so that a command stops as on Ctrl-C: the
    ``finally`` clauses on the way stop the workers and remove half-written files."""


def _stop(signum, frame):
    raise Stopped()


def run(main) -> None:
    """Call an entry point's ``main()`` and exit with the status it returns (None: 0). A user error
    exits with status 2 and one line; an interrupt or SIGTERM with one line saying what was
    written (:func:`interrupted`); any other exception prints its traceback, then one line saying
    that it is a bug in glamas, and exits with EXIT_BUG."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _stop)
    try:
        with reported():
            status = main()
    except KeyboardInterrupt as interrupt:
        signum = signal.SIGTERM if isinstance(interrupt, Stopped) else signal.SIGINT
        print(interrupted(signum), file=sys.stderr)
        sys.exit(128 + signum)
    except Exception as error:
        module = outside_fault(error)
        if module is not None:  # a learner of one's own, say: its fix lies in that module
            print(f"error: {module} fails ({type(error).__name__}: {_first_line(error)}): the fault is in that module, "
                  "not in glamas; correct it", file=sys.stderr)
            sys.exit(EXIT_USER_ERROR)
        traceback.print_exc()
        print(bug_report(), file=sys.stderr)
        sys.exit(EXIT_BUG)
    sys.exit(status)


def interrupted(signum: int) -> str:
    """The line of a command stopped by ``signum``: what it had written (:data:`glamas.atomic.written`)."""
    from glamas import atomic  # below this module: its errors are UserErrors
    from glamas.committed import shown

    how = "interrupted" if signum == signal.SIGINT else f"stopped ({signal.Signals(signum).name})"
    if not atomic.written:
        return f"{how}; nothing was written"
    return f"{how}; it had written {', '.join(dict.fromkeys(shown(path) for path in atomic.written))}"


def outside_fault(error: BaseException) -> str | None:
    """The Python file of the user's where ``error`` arose, outside glamas, the repository and the
    Python installation: the innermost frame of its traceback that is not in the installation (numba,
    numpy), or else the source a numba typing error names; None when that is glamas's."""
    from glamas.paths import REPO  # the repository's scripts, tests and benchmarks are glamas's

    installed = {Path(sys.prefix).resolve(), Path(sys.base_prefix).resolve()}
    ours = (REPO, Path(__file__).resolve().parent)  # the package, wherever it is installed

    def inside(name: str, places) -> bool:
        return name.startswith("<") or any(Path(name).resolve().is_relative_to(place) for place in places)

    def kept(name: str) -> bool:
        return inside(name, ours) or not inside(name, installed)

    frames = [frame.filename for frame in traceback.extract_tb(error.__traceback__) if kept(frame.filename)]
    named = [name for name in re.findall(r'File "([^"]+\.py)"', str(error)) if kept(name)]
    for name in frames[-1:] + named[-1:]:
        if not inside(name, ours):
            return name
    return None


def _first_line(error: BaseException) -> str:
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return lines[0] if lines else type(error).__name__


def bug_report() -> str:
    """The line that follows the traceback of a bug: what to report, the command included."""
    return (f"this is a bug in glamas, not in your input: please report it with the traceback above "
            f"and the command: {shlex.join(sys.orig_argv)}")


def one_line(error: BaseException) -> str:
    """The message of ``error`` on one line (an OSError with the file it concerns)."""
    if isinstance(error, OSError) and error.strerror:
        text = f"{error.strerror}: {error.filename}" if error.filename else error.strerror
    else:
        text = str(error) or type(error).__name__
    return " ".join(text.split())
