"""Commands of the motion: simulate, animate, basin."""
from __future__ import annotations

import sys

import numpy as np

from .. import _io
from .. import _validate as _v
from ..analysis import analyze
from ._common import (CLIError, add_parameters, angles, count, finite_float, format_table, out_stem, parameters_from,
                      positive_float, print_json)


def register(sub):
    p = sub.add_parser(
        "simulate",
        help="simulate the motion (nonlinear and linear): time series, phase portrait, stroboscopic map",
        description="Simulate the pendulum from an initial angle and angular velocity (at the start of a\n"
        "hyperbolic phase, a = +A). The undamped nonlinear motion is exact (Jacobi elliptic functions in each\n"
        "phase); the linear one is the exact solution of (2.3); damping --damping C uses DOP853 phase by phase.\n"
        "With --out STEM writes STEM.csv (the motion), STEM-strobe.csv (an ensemble's stroboscopic map),\n"
        "STEM.json (summary) and the figures STEM-series, STEM-phase, STEM-strobe (.png and .svg).\n\n"
        "With --chain L1,L2,...: a tower of linked pendulums on the pivot instead, its full motion by DOP853\n"
        "(every link tilted by --theta0, or along the longest mode with --along-mode) until a link passes\n"
        "--tol (pi/2 by default); --out STEM writes STEM.csv (t, pivot, angles, rates), STEM-series\n"
        "(.png, .svg: the angles over time) and STEM.json (the tower's verdict at the point and the outcome).",
        epilog="examples:\n  kapitza simulate --T 0.15 --A 100 --theta0 0.1\n"
        "  kapitza simulate --T 0.3 --A 100 --theta0 0.05 --periods 30 --out fall\n"
        "  kapitza simulate --eps 0.53 --mu 0.31 --theta0 0.2 --damping 0.5 --json\n"
        "  kapitza simulate --chain 0.2,0.2,0.2 --frequency 150 --stroke 0.008 --theta0 0.1 --out tower  # stands\n"
        "  kapitza simulate --chain 0.2,0.2 --frequency 20 --stroke 0.02 --along-mode --json             # falls",
    )
    add_parameters(p, rig=True)
    _add_start(p)
    _add_chain(p)
    p.add_argument("--periods", type=finite_float, default=None,
                   help="duration in drive periods 2T (default 20; with --chain as many as fill 3 s)")
    p.add_argument("--points-per-period", type=int, default=None,
                   help="samples per period (default 200; with --chain about 2000 samples in all)")
    p.add_argument("--model", choices=["nonlinear", "linear", "both"], default="both",
                   help="equation of motion; 'both': nonlinear, with the linear one for comparison (default)")
    _add_solver(p)
    p.add_argument("--tol", type=positive_float, default=None, metavar="RAD",
                   help="draw the window |theta| <= RAD (with --chain: a link beyond it has fallen, default pi/2)")
    p.add_argument("--orbits", type=int, default=12,
                   help="initial states in the stroboscopic-map ensemble (default 12)")
    p.add_argument("--strobe-periods", type=int, default=300,
                   help="periods each orbit of the map is followed (default 300)")
    p.add_argument("--out", metavar="STEM", help="write data and figures under this stem")
    p.add_argument("--no-figures", dest="figures", action="store_false", help="with --out: data only")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser(
        "animate",
        help="animate the pendulum on its vibrating pivot (GIF; MP4 when ffmpeg is present)",
        description="Render the motion as an animation: the pendulum on its moving pivot beside theta(t).\n"
        "Each frame is the exact state at its time. MP4 needs ffmpeg; without it a GIF is written and a\n"
        "message says so. A progress bar is shown on standard error (--quiet hides it).\n\n"
        "With --chain L1,L2,...: a tower of linked pendulums on the pivot, standing or toppling, in real\n"
        "time by default (--slowdown 1: the fast shaking is aliased, the tower's slow swaying is not).",
        epilog="examples:\n  kapitza animate --T 0.15 --A 100 --theta0 0.1 --out upright.gif   # stays up (zone 0)\n"
        "  kapitza animate --T 0.3 --A 100 --theta0 0.1 --out falls.gif      # falls\n"
        "  kapitza animate --T 0.15 --A 100 --theta0 0.1 --out upright.mp4 --fps 30\n"
        "  kapitza animate --chain 0.2,0.2,0.2 --frequency 150 --stroke 0.008 --out tower.gif   # the tower stands\n"
        "  kapitza animate --chain 0.2,0.2,0.2 --frequency 60 --stroke 0.008 --out topple.gif  # too slow: it falls",
    )
    add_parameters(p, rig=True)
    _add_start(p)
    _add_chain(p)
    p.add_argument("--periods", type=finite_float, default=None,
                   help="duration in drive periods 2T (default 10; with --chain as many as fill 3 s)")
    p.add_argument("--model", choices=["nonlinear", "linear"], default="nonlinear")
    p.add_argument("--compare-linear", action="store_true", help="also draw the linear theta(t) in the time panel")
    _add_solver(p)
    p.add_argument("--tol", type=positive_float, default=None, metavar="RAD", help="draw the window |theta| <= RAD")
    p.add_argument("--fps", type=finite_float, default=25.0, help="playback frames per second (default 25)")
    p.add_argument("--slowdown", type=finite_float, default=None,
                   help="playback seconds per second of motion (default: 24 frames per drive period; with --chain 1)")
    p.add_argument("--dpi", type=int, default=100, help="resolution (default 100: 900 x 460 pixels)")
    p.add_argument("--out", default="kapitza-motion.gif", metavar="FILE",
                   help="FILE.gif or FILE.mp4 (default kapitza-motion.gif)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=cmd_animate)

    p = sub.add_parser(
        "basin",
        help="which initial states keep the pendulum within a window of the upright for N periods",
        description="The basin of the upright: initial (theta, theta') whose motion keeps |theta| <= --tol on the\n"
        "whole of [0, 2NT] (checked on the continuous motion). Linear and nonlinear side by side by default:\n"
        "inside a stability zone both keep a region about the upright, outside one both lose it. Writes\n"
        "OUT.png, OUT.svg, OUT.csv (every grid point) and OUT.json (summary).",
        epilog="examples:\n  kapitza basin --T 0.15 --A 100 --out basin-zone0      # stable: "
               "the upright keeps a basin\n"
        "  kapitza basin --T 0.3 --A 100 --out basin-unstable     # unstable: nothing stays\n"
        "  kapitza basin --T 0.15 --A 100 --model nonlinear --resolution 301 --workers 2 --json",
    )
    add_parameters(p, rig=True)
    p.add_argument("--tol", type=finite_float, default=0.5, metavar="RAD", help="window half-width (default 0.5 rad)")
    p.add_argument("--periods", type=int, default=50, help="periods 2T to follow (default 50)")
    p.add_argument("--theta-max", type=finite_float, default=None, metavar="RAD",
                   help="grid half-width in theta (default tol)")
    p.add_argument("--dtheta-max", type=finite_float, default=None, metavar="RAD/S",
                   help="grid half-width in theta' (default 2 tol / T)")
    p.add_argument("--resolution", type=int, default=121, help="grid points per axis (default 121)")
    p.add_argument("--model", choices=["nonlinear", "linear", "both"], default="both")
    p.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--out", default="kapitza-basin", metavar="STEM", help="output stem (default kapitza-basin)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=cmd_basin)


def _add_start(p):
    g = p.add_argument_group("initial state (at t = 0, the start of a hyperbolic phase)")
    g.add_argument("--theta0", type=angles, default=0.1, metavar="RAD",
                   help="angle from the upright, counter-clockwise (default 0.1; with --chain every link's, or "
                        "one per link: A1,A2,...)")
    g.add_argument("--dtheta0", type=angles, default=0.0, metavar="RAD/S",
                   help="angular velocity (default 0; with --chain every link's, or one per link)")


def _add_chain(p):
    from .tower import add_chain_options, add_tower_start

    g = p.add_argument_group("a tower of linked pendulums instead (--chain; the point as above, not --eps/--mu)")
    add_chain_options(g)
    add_tower_start(g)


def _tower(args, command):
    """The tower's command for --chain (None without it: then no tower option may be given)."""
    from . import tower

    if args.chain is not None:
        return getattr(tower, command)
    for name in ("theta0", "dtheta0"):
        if isinstance(getattr(args, name), tuple):
            raise CLIError(f"--{name} takes one number for the single pendulum; a list, one per link, goes with "
                           "--chain")
    tower.refuse_tower_options(args)
    return None


def _add_solver(p):
    g = p.add_argument_group("solver")
    g.add_argument("--method", choices=["exact", "dop853"], default=None,
                   help="exact phase maps (undamped) or DOP853 (default: exact unless damped)")
    g.add_argument("--rtol", type=finite_float, default=1e-10, help="DOP853 relative tolerance (default 1e-10)")
    g.add_argument("--atol", type=finite_float, default=1e-12, help="DOP853 absolute tolerance (default 1e-12)")


def _physical_from(args):
    """``(T, A, l, g, report)`` from any parameter set (--T/--A, --frequency with --stroke/--amplitude,
    or --eps/--mu with --l, --g), validated; sets ``args.drive_obj`` and ``args.damping`` (c in 1/s)."""
    from dataclasses import replace

    kw = parameters_from(args, arnold_damping=True)
    args.drive_obj = kw.pop("drive")
    if "eps" in kw:
        l = 1.0 if args.l is None else args.l
        T, A, l, g = (float(v) for v in _v.physical_parameters(None, None, l, args.g, kw["eps"], kw["mu"]))
        zeta = kw.get("zeta") or 0.0
        from ..drives._api import damping_of

        c = float(damping_of(zeta, l, g)) if zeta else kw.get("damping", 0.0)
        kw = dict(T=T, A=A, l=l, g=g, damping=c)
    args.damping = kw.get("damping", 0.0) or 0.0
    rep = analyze(T=kw["T"], A=kw["A"], l=kw["l"], g=kw["g"], drive=args.drive_obj, damping=args.damping)
    if getattr(args, "pendulum", None) or args.given:
        rep = replace(rep, pendulum=getattr(args, "pendulum", None) or rep.pendulum, given=args.given)
    return kw["T"], kw["A"], kw["l"], kw["g"], rep


def _parameters_line(args, T, A, l, g, rep):
    """The parameters as given (a rig's frequency and stroke or amplitude) and as the formulas use them."""
    rig = ""
    if args.given in ("stroke", "amplitude"):
        rig = f"{0.5 / T:.6g} Hz, {args.given} {1e3 * getattr(args, args.given):.6g} mm; "
    return (f"parameters   {rig}T = {T:.6g} s, A = {A:.6g} m/s^2 ({A / g:.4g} g), l = {l:g} m, g = {g:g} m/s^2 "
            f"(eps = {rep.eps:.6g}, mu = {rep.mu:.6g})")


def _noted(summary, args):
    if args.rig_note:
        summary["note"] = args.rig_note
    return summary


# ------------------------------------------------------------------ simulate
def cmd_simulate(args):
    from ..motion import motion_pair, stroboscopic_map

    if (tower := _tower(args, "simulate_tower")) is not None:
        return tower(args)
    args.periods = 20.0 if args.periods is None else args.periods
    args.points_per_period = 200 if args.points_per_period is None else args.points_per_period

    T, A, l, g, rep = _physical_from(args)
    count("--orbits", args.orbits, 1000)
    count("--strobe-periods", args.strobe_periods, 100_000)
    model = "nonlinear" if args.model == "both" else args.model
    pair = motion_pair(args.theta0, args.dtheta0, T, A, l, g, model=model, compare_linear=args.model == "both",
                       periods=args.periods, points_per_period=args.points_per_period, damping=args.damping,
                       method=args.method, rtol=args.rtol, atol=args.atol, drive=args.drive_obj)
    traj, linear, linear_note = pair.motion, pair.linear, pair.linear_note
    summary = _noted(pair.summary(rep), args)
    files = []
    if args.out:
        stem = out_stem(args.out)
        header, cols, comments = pair.table()
        files.append(_io.write_csv(stem.with_suffix(".csv"), header, columns=cols, comments=comments))
        # An ensemble on the theta axis from near the upright out to the start (or 0.6 rad) for the map.
        reach = max(abs(args.theta0), 0.6) if args.theta0 else 0.6
        th_ens = np.linspace(reach / args.orbits, reach, args.orbits)
        orbits = stroboscopic_map(th_ens, 0.0, T, A, l, g, periods=args.strobe_periods, every=1,
                                  model=model, damping=args.damping, method=args.method, rtol=args.rtol, atol=args.atol,
                                  drive=args.drive_obj)
        cols = [np.repeat(np.arange(args.orbits), orbits.n.size), np.tile(orbits.n, args.orbits),
                orbits.theta.T.ravel(), orbits.dtheta.T.ravel()]
        files.append(_io.write_csv(stem.parent / (stem.name + "-strobe.csv"), ["orbit", "k", "theta", "dtheta"],
                                   columns=cols,
                                   comments=["states at t = 2kT of orbits started at theta0 = " +
                                             ", ".join(f"{v:.6g}" for v in th_ens) + " rad, dtheta0 = 0"]))
        if args.figures:
            files += _simulate_figures(stem, traj, linear, orbits, args.tol)
        summary["files"] = [str(f) for f in files] + [str(stem.with_suffix(".json"))]
        files.append(_io.write_json(stem.with_suffix(".json"), summary))
    if args.json:
        print_json(summary)
        return 0
    print(_parameters_line(args, T, A, l, g, rep))
    print(f"drive        {rep.drive}" + (f", damping c = {args.damping:g} 1/s" if args.damping else ""))
    print(f"upright      {rep.verdict}")
    print(f"start        theta0 = {args.theta0:g} rad, dtheta0 = {args.dtheta0:g} rad/s")
    rows = []
    for tr in [traj] + ([linear] if linear is not None else []):
        s = tr.summary()
        rows.append([tr.model, tr.method, f"{s['duration']:.6g}", f"{s['final']['theta']:.10g}",
                     f"{s['final']['dtheta']:.10g}", f"{s['max_abs_theta']:.6g}",
                     "-" if s["turns"] is None else s["turns"],
                     "stays up" if s["stays_up"] else f"falls at t = {s['falls_at']:.4g} s"])
    print()
    print(format_table(["model", "method", "t_end [s]", "theta(t_end)", "dtheta(t_end)", "max |theta|", "turns",
                        "upright"], rows))
    for tr in [traj] + ([linear] if linear is not None else []):
        if tr.summary().get("note"):
            print(f"{tr.model}: {tr.summary()['note']}")
    if linear_note:
        print(linear_note)
    if files:
        print("\nwrote " + ", ".join(str(f) for f in files))
    return 0


def _simulate_figures(stem, traj, linear, orbits, tol):
    import matplotlib.pyplot as plt

    from ..figures._style import save
    from ..figures.motion import phase_portrait_figure, strobe_figure, time_series_figure

    paths = []
    for suffix, fig in (("-series", time_series_figure(traj, linear=linear, tol=tol)),
                        ("-phase", phase_portrait_figure(traj)),
                        ("-strobe", strobe_figure(orbits, highlight=traj.strobe()[1:]))):
        paths += save(fig, stem.parent / (stem.name + suffix))
        plt.close(fig)
    return paths


# ------------------------------------------------------------------ animate
def cmd_animate(args):
    from ..figures.animation import animate
    from ..motion import simulate

    if (tower := _tower(args, "animate_tower_motion")) is not None:
        return tower(args)
    args.periods = 10.0 if args.periods is None else args.periods

    T, A, l, g, rep = _physical_from(args)
    common = dict(periods=args.periods, damping=args.damping, method=args.method, rtol=args.rtol, atol=args.atol,
                  drive=args.drive_obj)
    traj = simulate(args.theta0, args.dtheta0, T, A, l, g, model=args.model, **common)
    linear = None
    if args.compare_linear and args.model != "linear":
        try:
            linear = simulate(args.theta0, args.dtheta0, T, A, l, g, model="linear", **common)
        except OverflowError:
            linear = None
    res = animate(traj, args.out, fps=args.fps, slowdown=args.slowdown, dpi=args.dpi, progress=not args.quiet,
                  linear=linear, tol=args.tol)
    if res.message:
        print(f"kapitza animate: {res.message}", file=sys.stderr)
    from ..motion.pair import parameters_summary  # (the motion package only for the commands that move)

    summary = dict(parameters=parameters_summary(T, A, l, g, rep), theta0=args.theta0, dtheta0=args.dtheta0,
                   motion=traj.summary(), file=str(res.path), format=res.format, frames=res.frames,
                   fps=res.fps, slowdown=res.slowdown, message=res.message)
    if args.json:
        print_json(summary)
    else:
        print(f"wrote {res.path} ({res.frames} frames at {res.fps:g} fps, {res.slowdown:.3g} s of video per s of "
              f"motion); upright {rep.verdict}")
    return 0


# ------------------------------------------------------------------ basin
def cmd_basin(args):
    import matplotlib.pyplot as plt

    from ..figures._style import save
    from ..figures.animation import ProgressBar
    from ..figures.motion import basin_figure
    from ..motion import basin, survival

    T, A, l, g, rep = _physical_from(args)
    count("--resolution", args.resolution, 5000, minimum=2)
    count("--workers", args.workers, 1024)
    models = ["linear", "nonlinear"] if args.model == "both" else [args.model]
    basins = []
    for m in models:
        bar = ProgressBar(f"basin ({m})", enabled=not args.quiet)
        basins.append(basin(T, A, l, g, periods=args.periods, tol=args.tol, theta_max=args.theta_max,
                            dtheta_max=args.dtheta_max, n_theta=args.resolution, n_dtheta=args.resolution, model=m,
                            damping=args.damping, workers=args.workers, progress=bar, drive=args.drive_obj))
    # The demonstration: a small tilt from rest, a tenth of the window.
    probe = 0.1 * args.tol
    demo = {m: int(survival(probe, 0.0, T, A, l, g, periods=args.periods, tol=args.tol, model=m, damping=args.damping,
                            drive=args.drive_obj)) for m in models}
    stem = out_stem(args.out)
    fig = basin_figure(basins)
    paths = save(fig, stem)
    plt.close(fig)
    header = ["model", "theta0", "dtheta0", "survived", "periods_survived"]
    cols = [np.concatenate([np.full(b.periods_survived.size, b.model) for b in basins])] + \
        [np.concatenate(c) for c in zip(*(b.columns() for b in basins))]
    paths.append(_io.write_csv(stem.with_suffix(".csv"), header, columns=cols, comments=[
        f"kapitza basin: T = {T!r} s, A = {A!r} m/s^2, l = {l!r} m, g = {g!r} m/s^2, damping c = {args.damping!r} 1/s; "
        f"window |theta| <= {args.tol!r} rad "
        f"for {args.periods} periods 2T (survived = 1)"]))
    from ..motion.pair import parameters_summary

    summary = dict(parameters=parameters_summary(T, A, l, g, rep), tol=args.tol, periods=args.periods,
                   basins=[b.summary() for b in basins],
                   small_tilt=dict(theta0=probe, dtheta0=0.0, periods_survived=demo,
                                   stays_up={m: v >= args.periods for m, v in demo.items()}))
    summary["files"] = [str(p) for p in paths] + [str(stem.with_suffix(".json"))]
    paths.append(_io.write_json(stem.with_suffix(".json"), summary))
    if args.json:
        print_json(summary)
        return 0
    print(_parameters_line(args, T, A, l, g, rep))
    print(f"upright      {rep.verdict}")
    for b in basins:
        print(f"{b.model:10s}   {100 * b.fraction:.3g}% of the {b.survived.shape[1]} x {b.survived.shape[0]} "
              "grid stays "
              f"within {args.tol:g} rad for {args.periods} periods")
    for m, v in demo.items():
        verdict = "stays up" if v >= args.periods else f"falls (leaves the window in period {v + 1})"
        print(f"{m:10s}   start {probe:g} rad from the upright at rest: {verdict}")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0
