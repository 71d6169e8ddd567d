"""``kapitza sweep``: nonlinear stability maps over a window of the parameter plane."""
from __future__ import annotations

import sys
from pathlib import Path

from ._common import CLIError, add_damping, add_drive, damping_from, drive_from, finite_float, print_json
from ..parameters import G_EARTH

#: Figures drawn, in order: variable -> (file suffix, colour-bar label, what).
_FIGURES = {
    "max_safe_tilt": ("", "largest safe tilt at rest [rad]", "largest safe starting tilt at rest"),
    "basin_area": ("-basin", "basin area (fraction of the start window)", "basin of the upright"),
    "max_safe_radius": ("-radius", "largest safe radius over all directions [rad]", "largest safe radius"),
    "median_escape": ("-escape", "median escape time [periods]", "median escape time"),
}


def register(sub):
    p = sub.add_parser(
        "sweep",
        help="nonlinear stability map over a window of the chart (Dask, Zarr, resumable)",
        description="For every point of a grid over (--eps, --mu), (--T, --A) or a rig's (--frequency, --stroke):\n"
        "the largest safe starting tilt at rest (tilt), the largest safe radius over all directions of the\n"
        "phase plane (radius), the basin area and median escape time (basin) of the upright for --periods\n"
        "periods, beside the exact linear verdict, zone, growth and margin (linear).\n"
        "Chunks of the grid run on a local Dask cluster (one worker per\n"
        "core) or on --scheduler ADDRESS; each finished chunk is written to the Zarr store --out at once, so\n"
        "an interrupted sweep continues with --resume and recomputes only unfinished chunks. Writes a figure\n"
        "of the map with the exact zone edges (STEM.png/.svg, STEM = --out without .zarr); --netcdf exports.\n"
        "Radii are bisected to --accuracy (relative). An undamped square, rectangular or steps drive is followed\n"
        "by exact step flows, the window checked on the continuous motion; --drive sine, --damping or --zeta by\n"
        "DOP853 (rtol 1e-9), the window checked at sampled instants: far slower, and refused beyond about an\n"
        "hour of work unless KAPITZA_ALLOW_LARGE=1. The rig plane (--frequency Hz, --stroke m, peak-to-peak\n"
        "travel of the pivot) is spaced geometrically and drawn on log axes as `kapitza chart --plane rig`\n"
        "draws it; each point is T = 1/(2 f), A = s / (k T^2) with the drive's stroke coefficient k. See\n"
        "docs/sweeps.md.",
        epilog="examples:\n"
        "  kapitza sweep --eps 0.1 1.6 --mu 0.02 0.9 --resolution 40 30 --periods 100 --out small.zarr\n"
        "  kapitza sweep --eps 0.1 1.6 --mu 0.02 0.9 --resolution 40 30 --periods 100 --out small.zarr --resume\n"
        "  kapitza sweep --T 0.05 0.4 --A 20 200 --l 0.5 --quantities tilt,basin,linear --netcdf map.nc\n"
        "  kapitza sweep --eps 0.1 1.2 --mu 0.05 0.8 --resolution 12 10 --periods 50 --drive sine --zeta 0.05\n"
        "  kapitza sweep --frequency 20 200 --stroke 0.002 0.05 --rod 0.25 --resolution 24 20 --periods 100 "
        "--out shaker.zarr\n"
        "  kapitza sweep --eps 0.1 3 --mu 0.01 0.99 --resolution 512 --periods 1000 --scheduler tcp://head:8786",
    )
    w = p.add_argument_group("window (give --eps and --mu, --T and --A, or --frequency and --stroke)")
    for name, help_ in (("eps", "Arnold's eps range"), ("mu", "Arnold's mu range"), ("T", "half-period range [s]"),
                        ("A", "acceleration amplitude range [m/s^2]"),
                        ("frequency", "drive frequency range [Hz] (the rig plane, geometric grid, log axes)"),
                        ("stroke", "stroke range [m]: peak-to-peak travel of the pivot (the rig plane)")):
        w.add_argument(f"--{name}", nargs=2, type=finite_float, metavar=("LO", "HI"), help=help_)
    w.add_argument("--l", type=finite_float, default=1.0, metavar="M", help="rod length (default 1)")
    w.add_argument("--rod", type=finite_float, default=None, metavar="M",
                   help="a uniform rod of this length pivoted at one end (l = 2/3 of it), instead of --l")
    w.add_argument("--g", type=finite_float, default=G_EARTH, metavar="M/S^2", help=f"gravity (default {G_EARTH})")
    w.add_argument("--resolution", nargs="+", type=int, default=[32, 24], metavar="N",
                   help="grid points along x (eps, T or frequency) and y (mu, A or stroke); one number for both "
                        "(default 32 24)")
    rig = p.add_argument_group("the pivot's motion and the damping (an undamped square, rectangular or steps drive\n"
                               "is followed exactly; the sine drive or damping by DOP853, far slower)")
    add_drive(rig)
    add_damping(rig, physical="with --T/--A or --frequency/--stroke",
                arnold="with any window (c = 2 zeta sqrt(g/l) with --l or --rod, and --g)")
    q = p.add_argument_group("what is computed")
    q.add_argument("--quantities", default="tilt,linear",
                   help="comma-separated: tilt, radius, basin, linear (default tilt,linear)")
    q.add_argument("--periods", type=int, default=200, help="periods 2T each start must stay (default 200)")
    q.add_argument("--tol", type=finite_float, default=0.5, metavar="RAD", help="window |theta| <= RAD (default 0.5)")
    q.add_argument("--accuracy", type=finite_float, default=0.01, help="relative bisection accuracy (default 0.01)")
    q.add_argument("--floor", type=finite_float, default=1e-4, metavar="RAD",
                   help="smallest radius tried; below it 0 is reported (default 1e-4)")
    q.add_argument("--directions", type=int, default=8, help="directions of the phase plane for radius (default 8)")
    q.add_argument("--basin-resolution", type=int, default=21, help="start grid n x n for basin (default 21)")
    r = p.add_argument_group("running")
    r.add_argument("--out", default="kapitza-sweep.zarr", metavar="STORE.zarr",
                   help="Zarr store (default kapitza-sweep.zarr)")
    r.add_argument("--resume", action="store_true", help="continue the interrupted sweep in --out")
    r.add_argument("--chunk", type=int, default=None,
                   help="grid points per side of a chunk (default: about 16 chunks, 8 to 64 points per side)")
    r.add_argument("--workers", type=int, default=None, help="local Dask workers (default: one per core)")
    r.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://host:8786")
    r.add_argument("--serial", action="store_true", help="no Dask: compute in this process")
    r.add_argument("--netcdf", metavar="FILE.nc", help="also export the result as NetCDF")
    r.add_argument("--figure", metavar="STEM", help="figure stem (default: --out without .zarr)")
    r.add_argument("--no-figure", dest="draw", action="store_false", help="no figure")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=cmd_sweep)


#: ``plane -> (x option, y option)`` of the window.
_WINDOWS = {"arnold": ("eps", "mu"), "physical": ("T", "A"), "rig": ("frequency", "stroke")}


def _window(args):
    given = [plane for plane, names in _WINDOWS.items() if any(getattr(args, n) is not None for n in names)]
    if len(given) > 1:
        raise CLIError("give the window as --eps and --mu, as --T and --A, or as --frequency and --stroke, not both "
                       "(got " + " and ".join("--{}/--{}".format(*_WINDOWS[p]) for p in given) + ")")
    if not given:
        raise CLIError("give the window: --eps LO HI --mu LO HI (Arnold), --T LO HI --A LO HI (physical) or "
                       "--frequency LO HI --stroke LO HI (a rig, Hz and m)")
    plane = given[0]
    xn, yn = _WINDOWS[plane]
    x, y = getattr(args, xn), getattr(args, yn)
    if x is None or y is None:
        raise CLIError(f"--{xn} LO HI and --{yn} LO HI must be given together")
    if plane == "rig":
        for name, unit, (lo, hi) in ((xn, "Hz", x), (yn, "m", y)):
            if not 0.0 < lo <= hi:
                raise CLIError(f"--{name} must be LO HI with 0 < LO <= HI [{unit}]; got {lo!r} {hi!r}")
    return plane, x, y


def _damping_from(args, plane):
    """``c`` [1/s] of --damping (with --T/--A) or --zeta (with --eps/--mu), as the other commands take them."""
    for flag, v in (("--damping", args.damping), ("--zeta", args.zeta)):
        if v is not None and v < 0:
            raise CLIError(f"{flag} must be >= 0; got {v!r}")
    if plane != "arnold" and args.zeta is not None:
        from .._validate import positive

        positive("l", args.l), positive("g", args.g)
    given = damping_from(args, physical=plane != "arnold", l=args.l, g=args.g)
    if "zeta" not in given:
        return given.get("damping", 0.0)
    from ..drives._api import damping_of
    from .._validate import positive

    import numpy as np

    positive("l", args.l), positive("g", args.g)
    with np.errstate(over="ignore"):
        c = float(damping_of(args.zeta, args.l, args.g))
    if not np.isfinite(c):
        raise CLIError(f"--zeta must give a finite c = 2 zeta sqrt(g/l); got --zeta {args.zeta!r}")
    return c


def default_chunk(nx, ny):
    """Points per side of a chunk when --chunk is not given: about 16 chunks over the grid (work for
    every core of a small machine, little lost to an interruption), between 8 and 64 per side (the
    per-chunk costs -- a task, the store writes, the linear quantities' numpy calls -- stay small).
    Deterministic in the grid, so a resumed command gets the same chunks."""
    import math

    try:
        side = math.ceil(math.sqrt(max(int(nx), 1) * max(int(ny), 1) / 16.0))
    except (TypeError, ValueError, OverflowError):
        return 32  # the grid itself is refused with its own message
    return min(64, max(8, side))


def spec_from(args):
    """The :class:`kapitza.sweeps.SweepSpec` of the parsed options."""
    from ..sweeps import SweepSpec

    plane, xr, yr = _window(args)
    if args.rod is not None:
        if args.l != 1.0:
            raise CLIError("give --l or --rod, not both")
        if not 0.0 < args.rod < float("inf"):
            raise CLIError(f"--rod must be a length in metres, 0 < rod < inf; got {args.rod!r}")
        from ..system import Pendulum

        args.l = Pendulum.uniform_rod(args.rod).l
    if len(args.resolution) not in (1, 2):
        raise CLIError(f"--resolution takes one or two numbers; got {len(args.resolution)}")
    res = args.resolution * 2 if len(args.resolution) == 1 else args.resolution
    drive = drive_from(args)
    c = _damping_from(args, plane)
    chunk = args.chunk if args.chunk is not None else default_chunk(*res)
    return SweepSpec.window(xr, yr, res, plane=plane, l=args.l, g=args.g, drive=drive, c=c,
                            periods=args.periods, tol=args.tol,
                            quantities=tuple(s.strip() for s in args.quantities.split(",") if s.strip()),
                            directions=args.directions, basin_resolution=args.basin_resolution,
                            accuracy=args.accuracy, floor=args.floor, chunk=chunk)


def cmd_sweep(args):
    import importlib

    for name in ("zarr", "xarray", "tqdm", "dask", "distributed"):
        try:
            importlib.import_module(name)
        except ImportError:  # the optional extra is missing
            raise CLIError(f"kapitza sweep needs the 'sweep' extra (no module {name!r}): "
                           "pip install 'kapitza[sweep]'") from None
    from ..sweeps import open_sweep, sweep, to_netcdf
    spec = spec_from(args)
    if args.serial and (args.scheduler or args.workers is not None):
        raise CLIError("--serial runs without Dask; leave out --workers and --scheduler")
    out = Path(args.out)
    run = sweep(spec, out, resume=args.resume, serial=args.serial, workers=args.workers, scheduler=args.scheduler,
                progress=not args.quiet)
    for note in run.notes:
        print(f"kapitza sweep: {note}", file=sys.stderr)
    if run.damaged:
        names = ", ".join(f"({iy}, {ix})" for iy, ix in run.damaged[:20]) + (" ..." if len(run.damaged) > 20 else "")
        print(f"kapitza sweep: {len(run.damaged)} chunk(s) flagged done had missing or damaged data (checksum "
              f"mismatch or unreadable) and were recomputed: {names}", file=sys.stderr)
    print(f"computed {run.computed} of {run.total} chunks ({run.skipped} already done); store {run.store}",
          file=sys.stderr)
    ds = open_sweep(out).load()
    written = [str(out)]
    if args.netcdf:
        written.append(str(to_netcdf(ds, args.netcdf)))
    if args.draw:
        stem = args.figure or str(out.with_suffix("") if out.suffix == ".zarr" else out)
        written += [str(p) for p in _draw(ds, spec, stem)]
    summary = {"store": str(out), "chunks": run.total, "computed": run.computed, "skipped": run.skipped,
               "damaged": [list(c) for c in run.damaged], "files": written}
    for name in spec.variables:
        v = ds[name].values
        summary[name] = {"min": float(v.min()), "max": float(v.max()), "mean": float(v.mean())}
    if args.json:
        print_json(summary)
    else:
        for f in written:
            print(f)
    return 0


def _draw(ds, spec, stem):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..drives import parse_drive
    from ..figures._style import save
    from ..figures.sweep import sweep_figure

    xn, yn = spec.dims[1], spec.dims[0]
    drive = parse_drive(spec.drive)
    paths = []
    for name, (suffix, label, what) in _FIGURES.items():
        if name not in ds:
            continue
        fig = sweep_figure(ds[xn].values, ds[yn].values, ds[name].values, plane=spec.plane, label=label, what=what,
                           periods=spec.periods, tol=spec.tol, l=spec.l, g=spec.g,
                           drive=drive, damping=spec.c, exact=spec.exact)
        paths += save(fig, f"{stem}{suffix}")
        plt.close(fig)
    return paths
