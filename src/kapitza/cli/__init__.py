"""The ``kapitza`` command line.

Each command group lives in its own module with a ``register(subparsers)``
function; this module only assembles them and turns user errors into a
one-line message with exit status 2.
"""
from __future__ import annotations

import argparse
import sys

from ._common import CLIError, Parser

#: Command modules, in the order their commands appear in ``kapitza --help``.
COMMAND_MODULES = ["engine", "drives", "motion", "nonlinear", "sweep", "paper", "web", "tower"]

DESCRIPTION = """\
Exact stability of the inverted pendulum whose pivot is shaken up and down with an
acceleration of amplitude A and half-period T (period 2T), by the paper's square wave
or another drive, with viscous damping (--damping, --zeta):
  --drive {drives}
  --drive-file FILE.csv (a measured drive)

Parameters are given either physically, --T (s) and --A (m/s^2) with --l (m) and
--g (m/s^2), or in Arnold's dimensionless form --eps = T sqrt(A/(8 l)) and
--mu = sqrt(g/A), or as a rig: --frequency (Hz) or --rpm with --stroke or --amplitude
(m) and --rod (m). For the square wave the upright position is stable exactly inside
the zones alpha + n pi < w_e T < beta + n pi (n = 0, 1, ...).
"""

EPILOG = """\
examples:
  kapitza stability --T 0.15 --A 100          # stable? zone, multipliers, margins
  kapitza stability --eps 0.5 --mu 0.3 --json
  kapitza periods --A 100 --count 5           # T_n, T~_n of Corollary 4.1
  kapitza zones --zones 4 --out zones.csv     # edge curves as data
  kapitza chart --out chart                   # Figure-7-style chart: chart.png, chart.svg
  kapitza chart --plane physical --l 0.5 --out rod   # zones as T vs A for a 0.5 m rod
  kapitza simulate --T 0.15 --A 100 --theta0 0.1 --out run   # motion: data + figures
  kapitza animate --T 0.15 --A 100 --out upright.gif         # the pendulum stays up (zone 0)
  kapitza basin --T 0.3 --A 100 --out basin                  # which starts stay up
  kapitza nonlinear --eps 0.5 --mu 0.3                       # the real pendulum: Lyapunov stable? (twist)
  kapitza sweep --eps 0.1 1.6 --mu 0.02 0.9 --out map.zarr   # nonlinear map over the chart (Dask, --resume)

  kapitza tower --chain 0.2,0.2,0.2 --frequency 200 --stroke 0.005   # a tower of three rods: verdict and band
  kapitza chart --chain 0.2,0.2,0.2 --out tower                      # the tower's band (PNG, SVG, CSV, JSON)
  kapitza animate --chain 0.2,0.2,0.2 --frequency 150 --stroke 0.008 --out tower.gif   # the tower stands

  kapitza paper --out out/paper               # every figure and numbered claim of the paper, with a report
  kapitza serve                               # the explorer in a web browser (needs the 'web' extra)

Run 'kapitza COMMAND --help' for each command's options.
"""


class _Version(argparse.Action):
    """``--version``: the version read when asked (reading the installed metadata costs every other
    command tens of ms)."""

    def __call__(self, parser, namespace, values, option_string=None):
        from .. import __version__

        print(f"kapitza {__version__}")
        parser.exit()


def build_parser() -> Parser:
    import importlib

    from ..drives import text_forms

    parser = Parser(prog="kapitza", description=DESCRIPTION.format(drives=", ".join(text_forms())), epilog=EPILOG)
    parser.add_argument("--version", action=_Version, nargs=0, help="show program's version number and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for name in COMMAND_MODULES:
        importlib.import_module(f".{name}", __name__).register(sub)
    return parser


def main(argv=None) -> int:
    from .._interrupt import Terminated, done

    done()  # the imports are over: a Ctrl-C (or SIGTERM) from here on is caught below
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "func", None) is None:
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except (CLIError, ValueError) as exc:  # KapitzaValueError is a ValueError
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"kapitza {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # the reader went away (``kapitza ... | head``): nothing is wrong, say nothing
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except OverflowError as exc:
        print(f"kapitza {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # an output path that cannot be created or written
        print(f"kapitza {args.command}: error: {_cannot_write(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("kapitza: interrupted", file=sys.stderr)
        return 130
    except Terminated:  # SIGTERM (a CI timeout, systemctl stop): files stay atomic, as for Ctrl-C
        print("kapitza: terminated", file=sys.stderr)
        return 143


def _cannot_write(exc: OSError) -> str:
    """One line: the path as given (control characters escaped, bytes that are not UTF-8 shown as
    ``\\xff``) and the reason."""
    import os

    from .._io import shown_path

    name = getattr(exc, "filename", None)
    reason = str(exc.strerror or exc).splitlines()[0] if str(exc.strerror or exc) else type(exc).__name__
    if not name:
        return f"cannot write ({reason})"
    text = os.fsdecode(name) if isinstance(name, bytes) else str(name)
    note = ""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        note = "; the name is not valid UTF-8"
    return f"cannot write: {shown_path(text)} ({reason}{note})"


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
