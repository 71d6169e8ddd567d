"""A Ctrl-C while the ``kapitza`` command starts: one line and exit status 130, not a traceback.

Imported first by the package. Only when the process is the command line itself
(``kapitza ...`` or ``python -m kapitza ...``) does it install a SIGINT handler for the
imports (numpy, scipy); :func:`kapitza.cli.main` restores Python's own handler once they
are done, so an interrupted run is handled as before (and files stay atomic).
"""
from __future__ import annotations

import os
import signal
import sys

__all__ = ["started_as_command", "done"]


def started_as_command() -> bool:
    """Whether this process is the ``kapitza`` command (script or ``python -m kapitza``)."""
    argv = list(getattr(sys, "orig_argv", []))
    if "-m" in argv:
        return argv[argv.index("-m") + 1:argv.index("-m") + 2] in (["kapitza"], ["kapitza.cli"])
    return os.path.basename(sys.argv[0] if sys.argv else "") == "kapitza"


def _interrupted(signum, frame):
    sys.stderr.write("kapitza: interrupted\n")
    raise SystemExit(130)


def done() -> None:
    """Put Python's own SIGINT handler back (the start-up is over)."""
    if signal.getsignal(signal.SIGINT) is _interrupted:
        signal.signal(signal.SIGINT, signal.default_int_handler)


if started_as_command():
    try:
        signal.signal(signal.SIGINT, _interrupted)
    except ValueError:  # not the main thread: leave signals alone
        pass
