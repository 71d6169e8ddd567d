"""Pieces shared by every command: the parser, parameter options, output helpers."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .._io import to_jsonable
from ..parameters import G_EARTH

__all__ = ["CLIError", "Parser", "add_parameters", "parameters_from", "print_json", "finite_float", "format_table"]


class CLIError(Exception):
    """A user error detected by the command line (printed as one line, exit 2)."""


class Parser(argparse.ArgumentParser):
    """ArgumentParser whose errors are one line and exit with status 2."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def finite_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if v != v or v in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"must be finite: {text!r}")
    return v


def add_parameters(p: argparse.ArgumentParser, *, required=True):
    """The parameter options: --T/--A (with --l, --g) or --eps/--mu."""
    g = p.add_argument_group(
        "parameters (give --T and --A, or --eps and --mu)",
    )
    g.add_argument("--T", type=finite_float, metavar="SECONDS", help="half-period of the square-wave drive (period 2T)")
    g.add_argument("--A", type=finite_float, metavar="M/S^2", help="amplitude of the pivot acceleration")
    g.add_argument("--l", type=finite_float, default=1.0, metavar="M", help="rod length (default 1)")
    g.add_argument("--g", type=finite_float, default=G_EARTH, metavar="M/S^2", help=f"gravity (default {G_EARTH})")
    g.add_argument("--eps", type=finite_float, help="Arnold's eps = T sqrt(A/(8 l))")
    g.add_argument("--mu", type=finite_float, help="Arnold's mu = sqrt(g/A); mu >= 1 means A <= g")


def parameters_from(args) -> dict:
    """Keyword arguments for :func:`kapitza.analyze` from the parsed options."""
    phys = args.T is not None or args.A is not None
    arn = args.eps is not None or args.mu is not None
    if phys and arn:
        raise CLIError("give either --T and --A, or --eps and --mu, not both")
    if phys:
        if args.T is None or args.A is None:
            raise CLIError("--T and --A must be given together")
        return dict(T=args.T, A=args.A, l=args.l, g=args.g)
    if arn:
        if args.eps is None or args.mu is None:
            raise CLIError("--eps and --mu must be given together")
        return dict(eps=args.eps, mu=args.mu)
    raise CLIError("give the parameters: --T and --A (physical) or --eps and --mu (Arnold)")


def print_json(obj):
    json.dump(to_jsonable(obj), sys.stdout, indent=2)
    sys.stdout.write("\n")


def format_table(header, rows) -> str:
    """A plain fixed-width table."""
    cols = [header] + [[str(c) for c in r] for r in rows]
    widths = [max(len(r[i]) for r in cols) for i in range(len(header))]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths)), "  ".join("-" * w for w in widths)]
    lines += ["  ".join(c.rjust(w) if _numeric(c) else c.ljust(w) for c, w in zip(r, widths)) for r in cols[1:]]
    return "\n".join(lines)


def _numeric(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def out_stem(path: str) -> Path:
    """A path without a figure/data suffix (``chart.png`` -> ``chart``)."""
    p = Path(path)
    return p.with_suffix("") if p.suffix.lower() in (".png", ".svg", ".pdf", ".csv", ".json") else p
