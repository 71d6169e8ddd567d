"""``kapitza tower``: the tower of linked pendulums on one shaken pivot -- its band and a point's verdict."""
from __future__ import annotations

from .. import _io
from ._common import CLIError, add_drive, count, drive_from, finite_float, out_stem, positive_float, print_json

DESCRIPTION = """\
The tower: N linked pendulums (uniform rods or point masses) standing on one pivot shaken
vertically (Acheson's pendulums). Without joint friction the tower decouples into N modes,
each the single pendulum of an equivalent length l_k; it stands exactly when every mode does.

Draws the tower's stable band on the rig plane (drive frequency against stroke, log axes) with
each mode's edges, for the towers of the first 1, 2, ..., N links side by side (--only: the
whole tower alone), and writes OUT.png, OUT.svg, the edge curves as OUT.csv and everything as
OUT.json. With --frequency and --stroke (or --amplitude, or --T and --A) it also prints the
tower's verdict at that point: which mode fails first and how, the margins, the band through it.
"""

EPILOG = """\
examples:
  kapitza tower --chain 0.2,0.2,0.2 --out tower            # 1, 2 and 3 rods of 0.2 m
  kapitza tower --chain 0.2,0.2,0.2 --frequency 200 --stroke 0.005 --out tower
  kapitza tower --chain 0.3,0.2 --links point --masses 1,0.5 --drive sine --only --json
  kapitza tower --chain 0.2,0.2 --joint-damping 0.002 --T 0.003 --A 3000 --no-chart
"""


def _numbers(option, text):
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise CLIError(f"{option} must be comma-separated numbers; got {text!r}") from None
    if not vals:
        raise CLIError(f"{option} must hold at least one number; got {text!r}")
    return vals


def register(sub):
    p = sub.add_parser("tower", help="a tower of N linked pendulums on one shaken pivot: its band and verdict",
                       description=DESCRIPTION, epilog=EPILOG)
    t = p.add_argument_group("the tower")
    t.add_argument("--chain", default="0.2,0.2,0.2", metavar="L1,L2,...",
                   help="link lengths in m from the pivot up (default 0.2,0.2,0.2)")
    t.add_argument("--masses", metavar="M1,M2,...", help="link masses in kg (default: equal)")
    t.add_argument("--links", choices=("rod", "point"), default="rod",
                   help="rod: uniform rods (default); point: point masses on massless rods")
    t.add_argument("--joint-damping", type=finite_float, default=0.0, metavar="C",
                   help="friction at every joint, the pivot included, in N m s/rad (default 0)")
    t.add_argument("--g", type=positive_float, default=9.81, metavar="M/S^2", help="gravity (default 9.81)")
    d = p.add_argument_group("the pivot's motion")
    add_drive(d)
    q = p.add_argument_group("a point (optional): --frequency with --stroke or --amplitude, or --T with --A")
    q.add_argument("--frequency", type=positive_float, metavar="HZ", help="drive frequency 1/(2T)")
    q.add_argument("--stroke", type=positive_float, metavar="M", help="pivot travel, peak to peak")
    q.add_argument("--amplitude", type=positive_float, metavar="M", help="pivot displacement amplitude (half the stroke)")
    q.add_argument("--T", type=positive_float, metavar="S", help="half-period of the drive")
    q.add_argument("--A", type=positive_float, metavar="M/S^2", help="acceleration scale of the drive")
    c = p.add_argument_group("the chart")
    c.add_argument("--only", action="store_true", help="draw the whole tower alone, not its 1..N-link prefixes")
    c.add_argument("--amplitude-axis", action="store_true", help="vertical axis in displacement amplitude, not stroke")
    c.add_argument("--frequency-range", nargs=2, type=positive_float, metavar=("LO", "HI"), help="in Hz")
    c.add_argument("--stroke-range", nargs=2, type=positive_float, metavar=("LO", "HI"), help="in m")
    c.add_argument("--points", type=int, default=600, help="samples per edge curve (default 600, at most 20000)")
    c.add_argument("--grid", type=int, default=200, help="grid points per axis of the band (default 200, at most 2000)")
    c.add_argument("--no-chart", action="store_true", help="no chart (the point's verdict and motion only)")
    m = p.add_argument_group("the full (nonlinear) motion at the point")
    m.add_argument("--theta0", type=finite_float, default=0.1, metavar="RAD",
                   help="starting tilt at rest, every link (default 0.1)")
    m.add_argument("--along-mode", action="store_true",
                   help="tilt along the longest mode's shape instead (--theta0 for its most tilted link)")
    m.add_argument("--duration", type=positive_float, default=3.0, metavar="S", help="seconds of motion (default 3)")
    m.add_argument("--simulate", metavar="STEM", help="write the motion as STEM.csv (t, pivot height, link angles)")
    m.add_argument("--animate", metavar="FILE.gif", help="write an animation of the tower at the point")
    m.add_argument("--safe-tilt", action="store_true",
                   help="the largest starting tilts the tower survives for 50 periods (together; along mode 1)")
    p.add_argument("--out", default="kapitza-tower", metavar="STEM", help="output path without suffix")
    p.add_argument("--json", action="store_true", help="print JSON (the point's report, the files written)")
    p.set_defaults(func=cmd_tower)


def _point(args):
    rig = [args.frequency, args.stroke, args.amplitude]
    phys = [args.T, args.A]
    if all(v is None for v in rig + phys):
        return None
    if args.frequency is not None:
        if args.T is not None:
            raise CLIError("give --frequency or --T, not both")
        if (args.stroke is None) == (args.amplitude is None) and args.A is None:
            raise CLIError("--frequency goes with one of --stroke, --amplitude, --A")
        return dict(frequency=args.frequency, stroke=args.stroke, amplitude=args.amplitude, A=args.A)
    if args.stroke is not None or args.amplitude is not None:
        raise CLIError("--stroke and --amplitude go with --frequency")
    if args.T is None or args.A is None:
        raise CLIError("give --T and --A together (or --frequency with --stroke or --amplitude)")
    return dict(T=args.T, A=args.A)


def _motion(args, chain, drive, report, out):
    import numpy as np

    from ..motion.chain import chain_motion

    v = np.ones(chain.n)
    if args.along_mode:
        v = chain.mode_shapes[:, 0] / np.max(np.abs(chain.mode_shapes[:, 0]))
    periods = args.duration / (2.0 * report.T)
    motion = chain_motion(chain, args.theta0 * v, 0.0, T=report.T, A=report.A, g=args.g, drive=drive, periods=periods,
                          points_per_period=max(8, min(200, int(2000 / periods) + 1)))
    out["motion"] = {"toppled": motion.toppled, "t_topple": motion.t_topple,
                     "largest_tilt": float(np.max(np.abs(motion.theta)))}
    written = []
    if args.simulate:
        stem = out_stem(args.simulate)
        cols = [motion.t, motion.pivot, *motion.theta]
        written.append(_io.write_csv(stem.with_suffix(".csv"),
                                     ["t", "pivot", *[f"theta{j + 1}" for j in range(chain.n)]],
                                     columns=cols, comments=[f"full motion of the tower (kapitza tower): {chain.describe()}; "
                                                             f"T = {report.T!r} s, A = {report.A!r} m/s^2; "
                                                             "t in s, pivot height in m, angles from the upright in rad"]))
    if args.animate:
        from ..figures.tower import animate_tower

        what = "falls" if motion.toppled else "stands"
        written.append(animate_tower(motion, args.animate, titles=[
            f"{report.frequency:.4g} Hz, stroke {1e3 * report.stroke:.3g} mm: {what}"], fps=20.0))
    if not args.json:
        state = f"toppled at t = {motion.t_topple:.4g} s" if motion.toppled else "stands"
        print(f"full motion from a tilt of {args.theta0:g} rad: {state}")
    return written


def cmd_tower(args):
    from ..chain import Chain, tower_curves

    lengths = _numbers("--chain", args.chain)
    masses = None if args.masses is None else _numbers("--masses", args.masses)
    chain = Chain(lengths, masses, links=args.links, joint_damping=args.joint_damping)
    drive = drive_from(args)
    point = _point(args)
    report = None
    if point is not None:
        report = chain.analyze(g=args.g, drive=drive, **point)
    out = {"chain": chain.as_dict(), "drive": drive.as_dict(), "g": args.g}
    if report is not None:
        out["report"] = report.as_dict()
    if not args.json:
        print(f"tower: {chain.describe()}")
        print("modal lengths: " + ", ".join(f"{x:.6g}" for x in chain.modal_lengths) + " m (longest first)")
        if report is not None:
            print(report)
    written = []
    if (args.simulate or args.animate or args.safe_tilt) and report is None:
        raise CLIError("--simulate, --animate and --safe-tilt need a point: --frequency with --stroke, or --T with --A")
    if report is not None and (args.simulate or args.animate):
        written += _motion(args, chain, drive, report, out)
    if report is not None and args.safe_tilt:
        from ..motion.chain import tower_safe_tilt

        tilt = tower_safe_tilt(chain, T=report.T, A=report.A, g=args.g, drive=drive)
        out["safe_tilt"] = {"together": tilt.together, "mode": tilt.mode, "shape": list(tilt.shape),
                            "periods": tilt.periods, "tol": tilt.tol, "accuracy": tilt.accuracy}
        if not args.json:
            print(tilt)
    if not args.no_chart:
        count("--points", args.points, 20_000, minimum=2)
        count("--grid", args.grid, 2000, minimum=2)
        from ..figures import _style
        from ..figures.tower import tower_chart_figure, tower_family

        chains = [chain] if args.only or chain.n == 1 else tower_family(
            chain.lengths, chain.masses, links=chain.links, joint_damping=chain.joint_damping, n_max=chain.n)
        from ..chain import default_window

        wins = [default_window(c, drive, args.g) for c in chains]
        fr = tuple(args.frequency_range) if args.frequency_range else (min(w[0][0] for w in wins), max(w[0][1] for w in wins))
        sr = tuple(args.stroke_range) if args.stroke_range else (min(w[1][0] for w in wins), max(w[1][1] for w in wins))
        curves = [tower_curves(c, drive=drive, g=args.g, frequency_range=fr, stroke_range=sr, points=args.points,
                               grid=args.grid) for c in chains]
        mark = None if report is None else (report.frequency, report.stroke)
        import matplotlib.pyplot as plt

        fig, _ = tower_chart_figure(chains, drive=drive, g=args.g, frequency_range=fr, stroke_range=sr,
                                    amplitude=args.amplitude_axis, mark=mark, curves=curves)
        stem = out_stem(args.out)
        try:
            written += _style.save(fig, stem)
        finally:  # an unwritable path must not leave the figure open
            plt.close(fig)
        rows = ([c.n_links, *r] for c in curves for r in c.rows())
        written.append(_io.write_csv(stem.with_suffix(".csv"), ["links", "mode", "l", "edge", "mu", "frequency", "stroke"],
                                     rows, comments=[f"zone-0 edges of each mode on the rig plane (kapitza tower): "
                                                     f"{chain.describe()}; {drive.describe()}; g = {args.g:g} m/s^2",
                                                     "frequency in Hz, stroke (peak to peak) in m, l in m"]))
        out["curves"] = [c.as_dict() for c in curves]
        written.append(_io.write_json(stem.with_suffix(".json"), out))
    if args.json:
        print_json({k: v for k, v in out.items() if k != "curves"} | {"files": [str(p) for p in written]})
    elif written:
        print("wrote " + ", ".join(str(p) for p in written))
    return 0
