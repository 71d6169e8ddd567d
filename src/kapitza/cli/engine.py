"""Commands of the exact engine: stability, periods, zones, chart."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .. import _io
from ..analysis import analyze
from ..periodic import boundary_table
from .._validate import bounded_work
from ._common import (CLIError, _implausible, add_drive, add_parameters, add_zeta_from_rig, count, drive_from,
                      finite_float, format_table, out_stem, parameters_from, print_json, zeta_from_rig)


def register(sub):
    p = sub.add_parser(
        "stability",
        help="verdict, zone, Floquet multipliers, growth and margins for one parameter set",
        description="Is the upright position stable for these parameters, in which zone, and by what margin?\n\n"
        "safe tilt: the largest starting tilt from rest the real (nonlinear) pendulum survives above the\n"
        "horizontal for --safe-periods periods; the small-tilt verdict holds only below it.\n"
        "to hold it / room: which knob to turn which way and how far to reach the nearest zone (or how far\n"
        "each may go inside it), in the quantity given (frequency with stroke or amplitude, or T and A).\n"
        "margin (JSON): signed relative distance to the nearest zone edge along eps at fixed mu.",
        epilog="examples:\n  kapitza stability --T 0.15 --A 100\n  kapitza stability --eps 0.5 --mu 0.3 --json\n"
        "  kapitza stability --drive sine --frequency 40 --amplitude 0.01 --rod 0.3 --damping 0.2\n"
        "  kapitza stability --duty 0.3 --T 0.15 --A 100 --check && echo stable",
    )
    add_parameters(p, rig=True)
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.add_argument("--safe-periods", type=int, default=50, metavar="N",
                   help="periods 2T a start must survive for the safe tilt (default 50)")
    p.add_argument("--no-safe-tilt", dest="safe_tilt", action="store_false",
                   help="skip the safe tilt (it follows the real pendulum: up to a second or so)")
    p.add_argument("--check", action="store_true",
                   help="exit with status 1 when the upright is unstable (0 when stable), for scripts (no safe tilt)")
    p.set_defaults(func=cmd_stability)

    p = sub.add_parser(
        "periods",
        help="the boundary half-periods T_n, T~_n of Corollary 4.1 with their equations",
        description="Boundary half-periods for fixed A > g: T_n (a 2T-periodic solution exists) and T~_n\n"
        "(a 4T-periodic one), in the order T_1 < T~_1 < T~_2 < T_2 < T_3 < ..., each with the\n"
        "equation (3.10)-(3.13) and the k that produce it.",
        epilog="example:\n  kapitza periods --A 100 --count 5 --csv periods.csv",
    )
    p.add_argument("--A", type=finite_float, metavar="M/S^2", help="pivot acceleration amplitude (> g)")
    p.add_argument("--mu", type=finite_float, help="Arnold's mu = sqrt(g/A) in (0, 1), instead of --A")
    p.add_argument("--l", type=finite_float, default=1.0, metavar="M", help="rod length (default 1)")
    p.add_argument("--g", type=finite_float, default=9.81, metavar="M/S^2", help="gravity (default 9.81)")
    p.add_argument("--count", type=int, default=4, help="number of zones, each giving one T_n and one T~_n (default 4)")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.add_argument("--csv", metavar="FILE", help="also write the table as CSV")
    p.set_defaults(func=cmd_periods)

    p = sub.add_parser(
        "zones",
        help="zone edge curves eps_lo(mu), eps_hi(mu) as CSV or JSON",
        description="Edges of stability zones 0..N-1 at mu values spread over (mu-min, mu-max).",
        epilog="examples:\n  kapitza zones --zones 4 --out zones.csv\n  kapitza zones --zones 2 --points 5 --json",
    )
    p.add_argument("--zones", type=int, default=4, metavar="N", help="number of zones (default 4)")
    p.add_argument("--mu-min", type=finite_float, default=0.001, help="smallest mu (default 0.001)")
    p.add_argument("--mu-max", type=finite_float, default=0.999,
                   help="largest mu (default 0.999; below the drive's mu_max where that is above 1)")
    p.add_argument("--points", type=int, default=200, help="mu values (default 200)")
    p.add_argument("--out", metavar="FILE", help="write to FILE (.csv or .json)")
    p.add_argument("--json", action="store_true",
                   help="print JSON to standard output (with --out: only a summary of what was written)")
    add_drive(p.add_argument_group("the pivot's motion"))
    p.add_argument("--zeta", type=finite_float, default=0.0, help="damping ratio c / (2 sqrt(g/l)) (default 0)")
    add_zeta_from_rig(p.add_argument_group("the damping of a rig (instead of --zeta)"))
    p.set_defaults(func=cmd_zones)

    p = sub.add_parser(
        "chart",
        help="Figure-7-style chart of the exact stability zones (PNG, SVG, PDF)",
        description="Draw the exact stability zones on the eps-mu plane. Edges are exact curves (each a line,\n"
        "so thin tongues stay visible at any zoom); 2T-periodic edges (T_n) solid, 4T-periodic edges\n"
        "(T~_n) dashed. Zones too thin to see in the window (n = 1-3) are also drawn magnified in panels\n"
        "below (--no-magnify: not). Any window is recomputed exactly: --eps-min .. --mu-max zoom in.\n"
        "Writes OUT.png and OUT.svg (and OUT.pdf with --pdf) plus the curves as OUT.csv.\n\n"
        "With --chain L1,L2,...: the stable band of a tower of linked pendulums on one shaken pivot, on the\n"
        "rig plane (drive frequency against stroke, log axes), each mode's zone-0 edges drawn and labelled,\n"
        "for the towers of its first 1, 2, ..., N links side by side (--only: the whole tower alone); the\n"
        "curves as OUT.csv and everything (with the verdict at a marked point) as OUT.json.",
        epilog="examples:\n  kapitza chart --out chart\n"
        "  kapitza chart --eps-min 1.65 --eps-max 1.8 --mu-min 0 --mu-max 0.35 --out zoom   # zone 1 up close\n"
        "  kapitza chart --mark-T 0.15 --mark-A 100 --out chart   # mark a physical parameter set\n"
        "  kapitza chart --plane physical --l 0.5 --mark-T 0.1 --mark-A 150 --out rod\n"
        "  kapitza chart --plane rig --drive sine --rod 0.25 --frequency 50 --amplitude 0.003 --out shaker\n"
        "  kapitza chart --chain 0.2,0.2,0.2 --plane rig --out tower   # the bands of 1, 2, 3 linked rods "
        "(and OUT.json)\n"
        "  kapitza chart --chain 0.3,0.2 --links point --frequency 60 --stroke 0.02 --only --out double",
    )
    p.add_argument("--out", default="kapitza-chart", metavar="STEM",
                   help="output path without suffix (default kapitza-chart)")
    p.add_argument("--plane", choices=("arnold", "physical", "rig"), default=None,
                   help="arnold: eps-mu plane (default); physical: half-period T vs amplitude A for the rod --l "
                        "under --g; "
                        "rig: drive frequency vs stroke (log axes, the window around --frequency/--stroke when given; "
                        "the default and the only plane with --chain)")
    p.add_argument("--eps-min", type=finite_float, default=0.0, help="arnold plane window (default 0..4)")
    p.add_argument("--eps-max", type=finite_float, default=4.0)
    p.add_argument("--mu-min", type=finite_float, default=0.0,
                   help="arnold plane window (default 0..1, or up to the drive's mu_max where that is larger: "
                        "a rectangular wave of duty above 0.5 holds the rod up with A < g)")
    p.add_argument("--mu-max", type=finite_float, default=None)
    p.add_argument("--T-min", type=finite_float, default=0.0,
                   help="physical plane window in s (default 0 .. 2.5 sqrt(l/g))")
    p.add_argument("--T-max", type=finite_float, default=None)
    p.add_argument("--A-min", type=finite_float, default=None,
                   help="physical plane window in m/s^2 (default g .. 50 g; from g / mu_max^2 where the drive's "
                        "mu_max is "
                        "above 1)")
    p.add_argument("--A-max", type=finite_float, default=None)
    p.add_argument("--no-G", dest="show_G", action="store_false", help="do not draw the curves G_m")
    p.add_argument("--no-magnify", dest="magnify", action="store_false",
                   help="do not add magnified panels of the thin zones 1-3 (arnold plane)")
    p.add_argument("--points", type=int, default=1200, help="mu samples per edge (default 1200)")
    p.add_argument("--pdf", action="store_true", help="also write OUT.pdf")
    p.add_argument("--mark-eps", type=finite_float, help="mark the point (eps, mu) given by --mark-eps/--mark-mu")
    p.add_argument("--mark-mu", type=finite_float)
    p.add_argument("--mark-T", type=finite_float, help="mark the physical point --mark-T/--mark-A (with --l, --g)")
    p.add_argument("--mark-A", type=finite_float)
    p.add_argument("--l", type=finite_float, default=1.0,
                   help="rod length in m, for --plane physical and --mark-T/--mark-A")
    p.add_argument("--g", type=finite_float, default=9.81,
                   help="gravity in m/s^2, for --plane physical and --mark-T/--mark-A")
    p.add_argument("--title", default=None)
    add_drive(p.add_argument_group("the pivot's motion (arnold plane)"))
    p.add_argument("--zeta", type=finite_float, default=0.0,
                   help="damping ratio c / (2 sqrt(g/l)) (default 0; arnold plane)")
    r = p.add_argument_group("the rig (a point to mark in measured units; the rig plane's window)")
    r.add_argument("--frequency", type=finite_float, metavar="HZ", help="mark the rig at this drive frequency ...")
    r.add_argument("--rpm", type=finite_float, metavar="REV/MIN", help="... or at this many cam revolutions per minute")
    r.add_argument("--stroke", type=finite_float, metavar="M", help="... with this stroke (peak-to-peak, metres)")
    r.add_argument("--amplitude", type=finite_float, metavar="M", help="... or this displacement amplitude (metres)")
    r.add_argument("--rod", type=finite_float, metavar="M",
                   help="a uniform rod of this length (l = 2/3 of it), instead of --l")
    r.add_argument("--damping", type=finite_float, default=None, metavar="1/S",
                   help="viscous damping c, instead of --zeta (with the rod's l and g)")
    r.add_argument("--frequency-min", type=finite_float, metavar="HZ", help="rig plane window (default around the rig)")
    r.add_argument("--frequency-max", type=finite_float, metavar="HZ")
    r.add_argument("--stroke-min", type=finite_float, metavar="M", help="rig plane window in metres")
    r.add_argument("--stroke-max", type=finite_float, metavar="M")
    from .tower import add_band_options, add_chain_options

    t = p.add_argument_group("a tower of linked pendulums (--chain; the rig plane)")
    add_chain_options(t)
    add_band_options(t)
    p.set_defaults(func=cmd_chart)


# ------------------------------------------------------------------ stability
#: From this many integration steps a period at the point, ``kapitza stability`` says beforehand that its
#: report takes long (a triangle-wave report: 8 s at 2^18 steps, 20-30 s at 2^20, minutes at 2^22)
LONG_REPORT_STEPS = 1 << 19
#: ... and from this ``eps`` at a physical point, for a drive of its own Floquet data whose cost grows with
#: ``eps`` (the sine: 8 s at eps 30, 18 s at 40, a minute at 60, the rig's edges decided by exact traces)
LONG_REPORT_EPS = 30.0


def long_report_note(kw):
    """One line before a report that will take long (``kw``: :func:`kapitza.analyze`'s keywords), else
    None: where the drive integrates each period in at least :data:`LONG_REPORT_STEPS` steps at the
    point, or a drive of its own Floquet data whose cost grows with ``eps`` has a physical point at
    ``eps >= LONG_REPORT_EPS``."""
    from ..drives import as_drive
    from ..parameters import to_arnold

    drive = as_drive(kw.get("drive"))   # (the square wave where none is given: exact products, no note)
    given = [kw[k] for k in ("T", "A", "l", "g", "eps", "mu") if k in kw]
    if not drive._far_cost or not all(np.isfinite(v) and v > 0 for v in given):
        return None   # (a value out of range is refused by name in the report itself, in one line)
    try:
        eps, mu = (kw["eps"], kw["mu"]) if "eps" in kw else to_arnold(kw["T"], kw["A"], kw["l"], kw["g"])
        eps, mu = float(eps), float(mu)
        if not drive._from_shape:
            if "T" not in kw or not eps >= LONG_REPORT_EPS or not eps <= float(drive._eps_reach(mu)):
                return None
            return (f"eps = {eps:.6g} with the {drive.label}: the report's edges along the rig's knobs are decided by "
                    "exact traces beside its thin zones: it may take tens of seconds to minutes")
        steps = int(drive._engine.steps_for(np.array([eps]), np.array([mu]))[0])
    except (ValueError, ArithmeticError):   # (beyond the drive's reach: refused by name there too)
        return None
    if steps < LONG_REPORT_STEPS:
        return None
    return (f"eps = {eps:.6g} with the {drive.label}: each period is integrated in {steps:,} steps, and the "
            "report's searches ask hundreds of them: it may take tens of seconds to minutes")


def cmd_stability(args):
    from dataclasses import replace

    kw = parameters_from(args)
    note = long_report_note(kw)
    if note:
        print(f"kapitza: note: {note}", file=sys.stderr, flush=True)
    rep = analyze(**kw)
    if getattr(args, "pendulum", None):
        rep = replace(rep, pendulum=args.pendulum)
    if args.given:
        rep = replace(rep, given=args.given)
    if args.safe_tilt and not args.check:  # a script asking --check wants the verdict alone, at once
        from ..safety import with_safe_tilt

        count("--safe-periods", args.safe_periods, 100_000)
        rep = with_safe_tilt(rep, kw.get("drive"), args.safe_periods)
    if args.json:
        d = rep.as_dict()
        if args.rig_note:
            d["warning"] = args.rig_note
        print_json(d)
    else:
        print(rep)
    return 1 if (args.check and not rep.stable) else 0


# ------------------------------------------------------------------ periods
def cmd_periods(args):
    count("--count", args.count, 100_000)
    if (args.A is None) == (args.mu is None):
        raise CLIError("give --A or --mu (one of them)")
    if args.mu is not None:
        if not (0.0 < args.mu < 1.0):
            raise CLIError(f"--mu must lie in (0, 1); got {args.mu!r}")
        args.A = args.g / args.mu**2
    table = boundary_table(args.A, args.count, args.l, args.g)
    header = ["name", "T", "period", "equation", "k", "zone", "edge", "eps", "mu"]
    rows = [[b.name, f"{b.T:.15g}", b.period, b.equation, b.k, b.zone, b.edge, f"{b.eps:.15g}", f"{b.mu:.15g}"]
            for b in table]
    if args.csv:
        _io.write_csv(args.csv, header, [[b.name, b.T, b.period, b.equation, b.k, b.zone, b.edge, b.eps, b.mu]
                                         for b in table],
                      comments=[f"kapitza periods: A = {args.A!r}, l = {args.l!r}, g = {args.g!r}"])
    if args.json:
        print_json(dict(A=args.A, l=args.l, g=args.g, periods=[b.as_dict() for b in table]))
    else:
        print(f"Boundary half-periods for A = {args.A:g} m/s^2, l = {args.l:g} m, g = {args.g:g} m/s^2")
        print("(2T: a 2T-periodic solution exists; 4T: a 4T-periodic one; zone n lies between its two edges)\n")
        print(format_table(header, rows))
    return 0


# ------------------------------------------------------------------ zones
def _zone_rows(n_zones, mu, drive=None, zeta=0.0):
    from ..zones import zone_edges

    n = np.arange(n_zones)
    lo, hi = zone_edges(mu[None, :], n[:, None], drive=drive, zeta=zeta)
    return n, lo, hi


def cmd_zones(args):
    count("--zones", args.zones, 10_000)
    count("--points", args.points, 10_000_000)
    bounded_work("--zones * --points", args.zones * args.points, 2_000_000, what="edges held in memory")
    from ..curves import mu_top, mu_top_note

    drive = drive_from(args)
    top = mu_top(drive)
    if not (0.0 < args.mu_min <= args.mu_max < top):
        raise CLIError(f"need 0 < mu-min <= mu-max < {top:.6g}{mu_top_note(top)}; got mu-min={args.mu_min:g}, "
                       f"mu-max={args.mu_max:g}")
    if args.out and Path(args.out).suffix.lower() not in (".csv", ".json"):
        raise CLIError(f"--out must end in .csv or .json; got {args.out!r}")
    mu = np.linspace(args.mu_min, args.mu_max, args.points)
    args.zeta = zeta_from_rig(args, args.zeta)
    if args.zeta < 0:
        raise CLIError(f"--zeta must be >= 0; got {args.zeta!r}")
    n, lo, hi = _zone_rows(args.zones, mu, drive, args.zeta)
    from ..curves import edge_kinds as kinds

    records = [
        dict(n=int(k), lower_edge=kinds(k)[0], upper_edge=kinds(k)[1], mu=mu, eps_lo=lo[i], eps_hi=hi[i])
        for i, k in enumerate(n)
    ]
    if args.out:
        if args.out.lower().endswith(".json"):
            _io.write_json(args.out, dict(zones=records))
        else:
            rows = ([int(k), m, lo[i, j], hi[i, j], *kinds(k)] for i, k in enumerate(n) for j, m in enumerate(mu))
            _io.write_csv(args.out, ["n", "mu", "eps_lo", "eps_hi", "lower_edge", "upper_edge"], rows,
                          comments=["zone n is eps_lo < eps < eps_hi at fixed mu; "
                                    "eps = T sqrt(A/(8 l)), mu = sqrt(g/A)",
                                    f"drive: {drive.describe()}; damping ratio zeta = {args.zeta!r}"])
    if args.json and args.out:
        print_json(dict(wrote=str(args.out), zones=int(args.zones), points=int(mu.size)))
    elif args.json:
        print_json(dict(zones=records))
    elif not args.out:
        j = np.unique(np.linspace(0, mu.size - 1, min(mu.size, 6)).astype(int))
        rows = [[int(k), f"{mu[jj]:.6g}", f"{lo[i, jj]:.15g}", f"{hi[i, jj]:.15g}"]
                for i, k in enumerate(n) for jj in j]
        print(format_table(["n", "mu", "eps_lo", "eps_hi"], rows))
        print("\n(a sample; use --out FILE.csv or --json for every point)")
    else:
        print(f"wrote {args.out} ({args.zones} zones x {mu.size} mu values)")
    return 0


# ------------------------------------------------------------------ chart
def _chart_rig_options(args):
    """The rig's options of ``chart``: --rod sets --l, --damping sets --zeta, and --frequency (or --rpm)
    with --stroke or --amplitude sets --mark-T/--mark-A (for the drive)."""
    if args.rod is not None:
        if args.l != 1.0:
            raise CLIError("give --l or --rod, not both")
        if not args.rod > 0:
            raise CLIError(f"--rod must be > 0; got {args.rod!r}")
        args.l = 2.0 * args.rod / 3.0
    if args.damping is not None:
        if args.zeta:
            raise CLIError("give the damping as --damping C (1/s) or as --zeta, not both")
        if not (args.damping >= 0 and args.l > 0 and args.g > 0):
            raise CLIError(f"--damping must be >= 0 (with --l, --g > 0); got {args.damping!r}")
        from ..drives._api import zeta_of

        args.zeta = float(zeta_of(args.damping, args.l, args.g))
    if args.rpm is not None:
        if args.frequency is not None:
            raise CLIError("give --frequency or --rpm, not both")
        args.frequency = args.rpm / 60.0
    if args.frequency is None and args.stroke is None and args.amplitude is None:
        return
    if args.frequency is None or (args.stroke is None) == (args.amplitude is None):
        raise CLIError("mark a rig by --frequency (or --rpm) with one of --stroke, --amplitude")
    if args.mark_T is not None or args.mark_A is not None or args.mark_eps is not None:
        raise CLIError("give the mark by --frequency with --stroke/--amplitude, or by --mark-T/--mark-A, not both")
    T, A = drive_from(args).from_rig(args.frequency, stroke=args.stroke, amplitude=args.amplitude)
    args.mark_T, args.mark_A = float(T), float(A)
    note = _implausible(args, float(A))   # drawn as given, flagged in one line as the other commands do
    if note:
        print(f"kapitza: note: {note}", file=sys.stderr)


def cmd_chart(args):
    from ..figures._style import save
    from ..curves import mu_top, mu_top_note
    from ..figures.chart import chart_figure
    from .tower import chart_tower, refuse_tower_options

    if args.chain is not None:
        return chart_tower(args)
    refuse_tower_options(args)
    args.plane = args.plane or "arnold"

    count("--points", args.points, 200_000, minimum=2)
    _chart_rig_options(args)
    mark = None
    if args.mark_eps is not None or args.mark_mu is not None:
        if args.mark_eps is None or args.mark_mu is None:
            raise CLIError("--mark-eps and --mark-mu must be given together")
        rep = analyze(eps=args.mark_eps, mu=args.mark_mu)
        mark = (rep, f"eps = {args.mark_eps:g}, mu = {args.mark_mu:g}")
    if args.mark_T is not None or args.mark_A is not None:
        if mark is not None:
            raise CLIError("give --mark-eps/--mark-mu or --mark-T/--mark-A, not both")
        if args.mark_T is None or args.mark_A is None:
            raise CLIError("--mark-T and --mark-A must be given together")
        rep = analyze(T=args.mark_T, A=args.mark_A, l=args.l, g=args.g)
        mark = (rep, f"T = {args.mark_T:g} s, A = {args.mark_A:g} m/s$^2$")
        if args.frequency is not None:
            given = (f"stroke {1e3 * args.stroke:g} mm" if args.stroke is not None else
                     f"amplitude {1e3 * args.amplitude:g} mm")
            mark = (rep, f"{args.frequency:g} Hz, {given}")
    drive = drive_from(args)
    if args.zeta < 0:
        raise CLIError(f"--zeta must be >= 0; got {args.zeta!r}")
    general = drive.name != "square" or args.zeta > 0
    if general and mark is not None:
        from ..drives._api import damping_of

        if args.mark_T is None:
            rep = analyze(eps=args.mark_eps, mu=args.mark_mu, drive=drive, zeta=args.zeta)
        else:  # l and g were checked by the square wave's report above
            rep = analyze(T=args.mark_T, A=args.mark_A, l=args.l, g=args.g, drive=drive,
                          damping=damping_of(args.zeta, args.l, args.g))
        mark = (rep, mark[1])
    top = mu_top(drive)
    if args.mu_max is None:
        args.mu_max = top
    if args.plane == "arnold":
        if not (0.0 <= args.eps_min < args.eps_max <= (50.0 if general else np.inf)):
            raise CLIError(f"need 0 <= eps-min < eps-max{' <= 50' if general else ''}; got {args.eps_min:g}, "
                           f"{args.eps_max:g}")
        if not (0.0 <= args.mu_min < args.mu_max <= top):
            raise CLIError(f"need 0 <= mu-min < mu-max <= {top:.6g}{mu_top_note(top)}; got {args.mu_min:g}, "
                           f"{args.mu_max:g}")
    elif args.l <= 0 or args.g <= 0:
        raise CLIError(f"--l and --g must be > 0; got l={args.l:g}, g={args.g:g}")
    elif general and args.plane == "physical":  # each edge of another drive is a root solve: bound the eps in view
        from ..curves import physical_window
        from ..parameters import to_arnold

        (_, T_max), (_, A_max) = physical_window((None, args.T_max), (None, args.A_max), args.l, args.g, drive)
        eps_max = float(to_arnold(T_max, A_max, args.l, args.g)[0]) if T_max > 0 and A_max > 0 else 0.0
        if not eps_max <= 50.0:
            raise CLIError(f"need T-max sqrt(A-max / (8 l)) <= 50 (the largest eps in view) for another drive or "
                           f"damping; got {eps_max:g}")
    stem = out_stem(args.out)
    if args.plane == "rig":
        from ..figures.chart import rig_chart_figure

        if mark is not None and mark[0].T is None:
            raise CLIError("on the rig plane mark the rig by --frequency with --stroke or --amplitude "
                           "(or --mark-T/--mark-A)")
        fig, curves, header = rig_chart_figure(
            (args.frequency_min, args.frequency_max), (args.stroke_min, args.stroke_max), l=args.l, g=args.g,
            drive=drive, zeta=args.zeta, points=min(args.points, 2000), mark=mark, title=args.title, rod=args.rod)
    else:
        fig, curves, header = chart_figure(
            args.plane, (args.eps_min, args.eps_max), (args.mu_min, args.mu_max), (args.T_min, args.T_max),
            (args.A_min, args.A_max), l=args.l, g=args.g, drive=drive, zeta=args.zeta, points=args.points, mark=mark,
            show_G=args.show_G, magnify=args.magnify, title=args.title)
    formats = ("png", "svg", "pdf") if args.pdf else ("png", "svg")
    paths = save(fig, stem, formats)
    import matplotlib.pyplot as plt

    plt.close(fig)
    data = stem.with_suffix(".csv")
    _io.write_csv(data, header, curves.rows(),
                  comments=["exact zone edges drawn in " + ", ".join(p.name for p in paths)])
    print("wrote " + ", ".join(str(p) for p in [*paths, data]))
    return 0
