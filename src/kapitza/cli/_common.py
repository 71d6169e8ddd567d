"""Pieces shared by every command: the parser, parameter options, output helpers."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .._io import to_jsonable
from ..parameters import G_EARTH

__all__ = ["CLIError", "Parser", "add_parameters", "add_damping", "damping_from", "parameters_from", "print_json",
           "finite_float", "positive_float",
           "format_table", "count"]


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


def angles(text: str):
    """One finite number, or a comma-separated list of them (one per link of a tower) as a tuple."""
    if "," not in text:
        return finite_float(text)
    return tuple(finite_float(x) for x in text.split(","))


def positive_float(text: str) -> float:
    """An option's value that must be a finite number > 0."""
    v = finite_float(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(f"must be > 0: {text!r}")
    return v


def count(option: str, value: int, limit: int, minimum: int = 1) -> int:
    """An integer option ``minimum <= value <= limit`` (the limit lifted by ``KAPITZA_ALLOW_LARGE=1``)."""
    from .._validate import bounded_count

    return bounded_count(option, value, limit, minimum=minimum)


def add_parameters(p: argparse.ArgumentParser, *, required=True, rig=False, units=None, drive_options=None,
                   damping_options=None):
    """The parameter options: --T/--A (with --l, --g) or --eps/--mu, and the units of a rig: --frequency
    (or --rpm) with --stroke, --amplitude or --A, and --rod instead of --l (``units``, on by default
    with ``rig``). With ``rig`` also the drive's options (``drive_options``) and the damping's,
    --damping C or --zeta (``damping_options``). Every command that takes one parameter set reads
    them with :func:`parameters_from`."""
    units = rig if units is None else units
    drive_options = rig if drive_options is None else drive_options
    damping_options = rig if damping_options is None else damping_options
    g = p.add_argument_group(
        "parameters (give --T and --A, or --eps and --mu" + (", or --frequency with --stroke, --amplitude or --A)"
                                                              if units else ")"),
    )
    g.add_argument("--T", type=finite_float, metavar="SECONDS", help="half-period of the drive (period 2T)")
    g.add_argument("--A", type=finite_float, metavar="M/S^2",
                   help="amplitude (scale) of the pivot acceleration")
    g.add_argument("--l", type=finite_float, default=None, metavar="M",
                   help="equivalent length of the pendulum (default 1; a point mass on a massless rod)")
    g.add_argument("--g", type=finite_float, default=G_EARTH, metavar="M/S^2", help=f"gravity (default {G_EARTH})")
    g.add_argument("--eps", type=finite_float, help="Arnold's eps = T sqrt(A/(8 l))")
    g.add_argument("--mu", type=finite_float, help="Arnold's mu = sqrt(g/A); mu >= 1 means A <= g")
    if units or drive_options or damping_options:
        parts = (("drive", drive_options), ("damping", damping_options), ("measured units", units))
        r = p.add_argument_group("the rig (" + ", ".join(w for w, on in parts if on) + ")")
        if drive_options:
            add_drive(r)
        if damping_options:
            add_damping(r)
        if units:
            r.add_argument("--frequency", type=finite_float, metavar="HZ", help="drive frequency, instead of --T")
            r.add_argument("--rpm", type=finite_float, metavar="REV/MIN",
                           help="revolutions per minute of a cam or crank (one drive period each), instead of "
                                "--frequency")
            r.add_argument("--stroke", type=finite_float, metavar="M",
                           help="peak-to-peak travel of the pivot in metres (3 mm: 0.003), with --frequency, "
                                "instead of --A")
            r.add_argument("--amplitude", type=finite_float, metavar="M",
                           help="displacement amplitude in metres (half the stroke), with --frequency, instead of --A")
            r.add_argument("--rod", type=finite_float, metavar="M",
                           help="a uniform rod of this length pivoted at one end (equivalent length 2/3 of it), "
                                "instead of --l")


def damping_from(args, physical, l=None, g=None):
    """``{"damping": c}`` with physical parameters (from --damping C, or --zeta as ``c = 2 zeta sqrt(g/l)``),
    ``{"zeta": z}`` (or nothing) with Arnold's; --damping with --eps/--mu is refused (it needs l and g)."""
    if args.zeta is not None and args.damping:
        raise CLIError("give the damping as --damping C (1/s) or as --zeta, not both")
    if physical:
        if args.zeta is not None:
            if args.zeta < 0:
                raise CLIError(f"--zeta must be >= 0; got {args.zeta!r}")
            from .._validate import damping_ratio
            from ..drives._api import damping_of

            damping_ratio(args.zeta)  # refused as the ratio it was given as, not as the c it becomes

            return {"damping": float(damping_of(args.zeta, l, g))}
        return {"damping": args.damping}
    if args.damping:
        raise CLIError("with --eps/--mu give the damping as --zeta (ratio c / (2 sqrt(g/l))), not --damping")
    return {} if args.zeta is None else {"zeta": args.zeta}


def add_damping(g, physical="with physical parameters", arnold="with --eps/--mu"):
    """--damping C [1/s] and --zeta (the damping ratio); which goes with which parameters is said in
    the help and enforced where they are read."""
    g.add_argument("--damping", type=finite_float, default=0.0, metavar="1/S",
                   help=f"viscous damping c in theta'' + c theta' = ..., {physical} (default 0)")
    g.add_argument("--zeta", type=finite_float, default=None,
                   help=f"damping ratio c / (2 sqrt(g/l)), {arnold}")


def add_drive(g):
    """--drive and --duty (the pivot's motion)."""
    from ..drives import text_forms  # the registry's drives, a user's registered ones too

    g.add_argument("--drive", default="square", metavar="DRIVE",
                   help=f"{', '.join(text_forms())} (square, the paper's, by default; steps:LEVELS:FRACTIONS: "
                        "accelerations LEVELS x A for FRACTIONS of the period, zero mean)")
    g.add_argument("--duty", type=finite_float, metavar="D",
                   help="shortcut for --drive rectangular:D (+A for the fraction D of the period, "
                        "1e-6 <= D <= 1 - 1e-6)")
    g.add_argument("--drive-file", metavar="FILE.csv",
                   help="a measured drive: pivot acceleration samples, columns t,a (header optional), one period "
                        "(uniform times) or several with --drive-period; its mean is removed, A is its peak and T "
                        "half its period unless --T/--A are given")
    g.add_argument("--drive-period", type=positive_float, metavar="SECONDS",
                   help="the period of the samples of --drive-file (default: their span plus one step)")
    g.add_argument("--drive-kind", choices=("linear", "constant"), default="linear",
                   help="the acceleration between samples of --drive-file (default linear)")


def drive_from(args):
    """The drive of --drive/--duty."""
    return _drive_from(args)


def _drive_from(args):
    from ..drives import parse_drive

    if getattr(args, "drive_file", None) is not None:
        if args.drive != "square" or getattr(args, "duty", None) is not None:
            raise CLIError("give --drive-file or --drive/--duty, not both")
        return drive_file(args.drive_file, args.drive_period, args.drive_kind)
    if getattr(args, "drive_period", None) is not None:
        raise CLIError("--drive-period goes with --drive-file")
    if getattr(args, "duty", None) is not None:
        if args.drive not in ("square", "rectangular"):
            raise CLIError(f"--duty goes with a rectangular drive; got --drive {args.drive}")
        return parse_drive(f"rectangular:{args.duty!r}")
    return parse_drive(args.drive)


#: The most characters of a drive file read (``KAPITZA_ALLOW_LARGE=1`` lifts it): a row ``t,a`` takes some 30
DRIVE_FILE_CHARS = 64 << 20


def drive_file(path, period=None, kind="linear"):
    """A measured drive from a CSV file of ``t,a`` rows (:func:`kapitza.drives.from_samples`).

    Blank lines and lines starting with ``#`` are skipped; the first remaining line may be a
    header. A bad row is named by its line number in the file.
    """
    from ..drives import from_samples

    from .. import _validate as _v

    limit = None if _v.allow_large() else DRIVE_FILE_CHARS
    try:
        with open(path, encoding="utf-8-sig") as fh:
            text = fh.read() if limit is None else fh.read(limit + 1)
    except (OSError, UnicodeDecodeError) as exc:
        raise CLIError(f"--drive-file {path}: cannot read it ({exc.strerror if isinstance(exc, OSError) else exc})") \
            from None
    if limit is not None and len(text) > limit:   # (a device that never ends, such as /dev/zero, too)
        raise CLIError(f"--drive-file {path}: a drive file must be at most {limit:,} characters (some two million "
                       f"rows); it is longer. To go past it on purpose, set the environment variable "
                       f"{_v.ALLOW_LARGE_ENV}=1")
    line_of, t, a = [], [], []
    first = True
    for no, line in enumerate(text.splitlines(), start=1):
        body = line.strip()
        if not body or body.startswith("#"):
            continue
        cells = [c.strip() for c in body.replace(";", ",").split(",")] if ("," in body or ";" in body) else body.split()
        if first and len(cells) == 2 and not any(_numeric(c) for c in cells):
            first = False
            continue  # the header
        first = False
        if len(cells) != 2:
            raise CLIError(f"--drive-file {path}, row {no}: expected two columns t,a; got {len(cells)}: {body[:60]!r}")
        line_of.append(no)
        t.append(cells[0])
        a.append(cells[1])
    for col, name in ((t, "t"), (a, "a")):
        for i, v in enumerate(col):
            try:
                col[i] = float(v)
            except ValueError:
                raise CLIError(f"--drive-file {path}, row {line_of[i]}: {name} is not a number: {v[:40]!r}") from None
    try:
        return from_samples(t, a, period=period, kind=kind, rows=lambda i: f"row {line_of[i]}")
    except ValueError as exc:
        raise CLIError(f"--drive-file {path}: {exc}") from None


#: Beyond these a value is most likely in the wrong unit (mm given as m): computed, but said so.
PLAUSIBLE_G = 1000.0     # pivot acceleration in g
PLAUSIBLE_TRAVEL = 1.0   # stroke or amplitude in m


def parameters_from(args, arnold_damping=False) -> dict:
    """Keyword arguments for :func:`kapitza.analyze` from the parsed options.

    Also sets ``args.given`` (``"amplitude"``, ``"stroke"``, ``"A"`` or None: the quantity the answers
    come in), ``args.pendulum`` (a rod's description) and ``args.rig_note`` (one line when a value is
    implausible, also printed to standard error). ``arnold_damping``: --damping C is taken with --eps/--mu
    too (the motion commands, which turn Arnold's parameters into physical ones with --l and --g)."""
    units = hasattr(args, "frequency")
    has_drive = hasattr(args, "drive") and hasattr(args, "duty")
    has_damping = hasattr(args, "zeta") and hasattr(args, "damping")
    args.given, args.rig_note = None, None
    if units and getattr(args, "rpm", None) is not None:
        if args.frequency is not None:
            raise CLIError("give --frequency or --rpm, not both")
        if not args.rpm > 0:
            raise CLIError(f"--rpm must be > 0; got {args.rpm!r}")
        args.frequency = args.rpm / 60.0
    freq = units and (args.frequency is not None or args.stroke is not None or args.amplitude is not None)
    phys = args.T is not None or args.A is not None or freq
    arn = args.eps is not None or args.mu is not None
    if units and args.rod is not None and args.l is not None:
        raise CLIError("give --l or --rod, not both")
    l = args.l if args.l is not None else 1.0
    if units and args.rod is not None:
        from ..system import Pendulum

        l = Pendulum.uniform_rod(args.rod).l
        args.pendulum = Pendulum.uniform_rod(args.rod).describe()
    extra = {}
    from ..drives import as_drive

    drive = _drive_from(args) if has_drive else as_drive(None)   # (the paper's square wave)
    if has_drive:
        extra["drive"] = drive
        if not (phys or arn) and drive.own_scale is not None:
            (args.T, args.A), phys = drive.own_scale, True  # a measured drive's own T and A
    if phys and arn:
        raise CLIError("give either physical parameters (--T/--A or --frequency) or --eps and --mu, not both")
    if phys:
        if freq:
            if args.frequency is None:
                raise CLIError("--stroke and --amplitude go with --frequency (or --rpm)")
            if args.T is not None:
                raise CLIError("give --T or --frequency, not both")
            given = [k for k in ("stroke", "amplitude", "A") if getattr(args, k) is not None]
            if len(given) != 1:
                raise CLIError("with --frequency give exactly one of --stroke, --amplitude, --A")
            T, A = drive.from_rig(args.frequency, stroke=args.stroke, amplitude=args.amplitude, acceleration=args.A)
            T, A = float(T), float(A)
            args.given = given[0]
            args.rig_note = _implausible(args, A)
            if args.rig_note:
                print(f"kapitza: note: {args.rig_note}", file=sys.stderr)
        else:
            if args.T is None or args.A is None:
                raise CLIError("--T and --A must be given together")
            T, A = args.T, args.A
        if has_damping:
            if not (l > 0 and args.g > 0):
                raise CLIError(f"--l and --g must be > 0; got l={l!r}, g={args.g!r}")
            extra.update(damping_from(args, physical=True, l=l, g=args.g))
        return dict(T=T, A=A, l=l, g=args.g, **extra)
    if arn:
        if args.eps is None or args.mu is None:
            raise CLIError("--eps and --mu must be given together")
        if has_damping:
            if arnold_damping and args.damping:
                if args.zeta is not None:
                    raise CLIError("give the damping as --damping C (1/s) or as --zeta, not both")
                extra["damping"] = args.damping
            else:
                extra.update(damping_from(args, physical=False))
        return dict(eps=args.eps, mu=args.mu, **extra)
    raise CLIError("give the parameters: --T and --A (physical), --frequency with --stroke or --amplitude (a rig), "
                   "or --eps and --mu (Arnold)")


def _implausible(args, A):
    """One line when the rig's numbers are most likely in the wrong unit, else None."""
    g = args.g
    ing = A / g if g > 0 else float("inf")
    for name in ("stroke", "amplitude"):
        v = getattr(args, name)
        if v is not None and (ing > PLAUSIBLE_G or v > PLAUSIBLE_TRAVEL):
            return (f"--{name} {v:g} is {v:g} m: with {args.frequency:g} Hz the pivot accelerates at {A:.4g} m/s^2 = "
                    f"{ing:,.0f} g; if you meant {v:g} mm, give --{name} {v / 1000:g}")
    if ing > PLAUSIBLE_G:
        return f"A = {A:.4g} m/s^2 is {ing:,.0f} g: beyond any real shaker"
    return None


def add_zeta_from_rig(g):
    """--damping C [1/s] with the pendulum (--rod or --l, --g), instead of --zeta, for the commands on
    Arnold's plane (the damping ratio is what that plane sees); read by :func:`zeta_from_rig`."""
    g.add_argument("--damping", type=finite_float, default=None, metavar="1/S",
                   help="viscous damping c of a rig, instead of --zeta (with --rod or --l, and --g)")
    g.add_argument("--rod", type=finite_float, default=None, metavar="M",
                   help="with --damping: a uniform rod of this length (l = 2/3 of it)")
    g.add_argument("--l", type=finite_float, default=None, metavar="M",
                   help="with --damping: equivalent length (default 1)")
    g.add_argument("--g", type=finite_float, default=G_EARTH, metavar="M/S^2",
                   help=f"with --damping: gravity (default {G_EARTH})")


def zeta_from_rig(args, zeta):
    """The damping ratio: ``zeta`` (--zeta), or ``c / (2 sqrt(g/l))`` of --damping with the rod."""
    if args.damping is None:
        if args.rod is not None or args.l is not None:
            raise CLIError("--rod and --l go with --damping (the damping ratio needs the pendulum's length)")
        return zeta
    if zeta:
        raise CLIError("give the damping as --zeta or as --damping C (1/s), not both")
    if args.rod is not None and args.l is not None:
        raise CLIError("give --l or --rod, not both")
    l = 2.0 * args.rod / 3.0 if args.rod is not None else (1.0 if args.l is None else args.l)
    if not (args.damping >= 0 and l > 0 and args.g > 0):
        raise CLIError(f"need --damping >= 0 and a length and --g > 0; got damping={args.damping!r}, l={l!r}, "
                       f"g={args.g!r}")
    from ..drives._api import zeta_of

    return float(zeta_of(args.damping, l, args.g))


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
