"""A Ctrl-C or SIGTERM while the ``kapitza`` command runs: one line, not a traceback.

Imported first by the package. Only when the process is the command line itself
(``kapitza ...`` or ``python -m kapitza ...``) does it install handlers: for the imports
(numpy, scipy) SIGINT and SIGTERM end the process at once with ``kapitza: interrupted`` (status
130) or ``kapitza: terminated`` (143); :func:`done`, called by :func:`kapitza.cli.main` once they
are over, puts back Python's SIGINT handler (a ``KeyboardInterrupt``) and makes SIGTERM raise
:class:`Terminated`, so that either unwinds the run: a file being written is never left
half-written, nor its temporary file (:mod:`kapitza._io`), and ``main`` prints the one line.
"""
from __future__ import annotations

import os
import signal
import sys

__all__ = ["started_as_command", "done", "Terminated"]


class Terminated(BaseException):
    """SIGTERM arrived (a ``BaseException``, like ``KeyboardInterrupt``: no ``except Exception``
    swallows it, and cleanup in ``finally`` and ``except BaseException`` runs)."""


def started_as_command() -> bool:
    """Whether this process is the ``kapitza`` command (script or ``python -m kapitza``)."""
    argv = list(getattr(sys, "orig_argv", []))
    if "-m" in argv:
        return argv[argv.index("-m") + 1:argv.index("-m") + 2] in (["kapitza"], ["kapitza.cli"])
    return os.path.basename(sys.argv[0] if sys.argv else "") == "kapitza"


def _end_now(message: str, status: int) -> None:
    # os._exit, not SystemExit: an exception raised inside an import may meet a bare ``except:`` in
    # a third-party module and be swallowed, and the command would then run on and end with 0.
    # Nothing needs unwinding yet: the command has written nothing before :func:`done`.
    try:
        sys.stderr.write(message + "\n")
        sys.stderr.flush()
    finally:
        os._exit(status)


def _interrupted(signum, frame):
    _end_now("kapitza: interrupted", 130)


def _terminated_at_start(signum, frame):
    _end_now("kapitza: terminated", 143)


_PID = os.getpid()


def _terminated(signum, frame):
    if os.getpid() != _PID:  # a forked worker: end as SIGTERM ends a process by default
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTERM)
        return
    raise Terminated


def done() -> None:
    """The start-up is over: Python's own SIGINT handler back, SIGTERM raising :class:`Terminated`."""
    if signal.getsignal(signal.SIGINT) is _interrupted:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if signal.getsignal(signal.SIGTERM) is _terminated_at_start:
        signal.signal(signal.SIGTERM, _terminated)


if started_as_command():
    try:
        signal.signal(signal.SIGINT, _interrupted)
        signal.signal(signal.SIGTERM, _terminated_at_start)
    except ValueError:  # not the main thread: leave signals alone
        pass
