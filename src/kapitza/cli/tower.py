"""``kapitza tower``: the tower of linked pendulums on one shaken pivot -- its band and a point's verdict.

The tower's options and outputs are defined here once and shared with ``kapitza chart --chain``
(the band on the rig plane) and ``kapitza simulate/animate --chain`` (the full motion)."""
from __future__ import annotations

import math

from .. import _io
from ._common import (CLIError, add_drive, angles, count, drive_from, finite_float, out_stem, positive_float,
                      print_json)

DESCRIPTION = """\
The tower: N linked pendulums (uniform rods or point masses) standing on one pivot shaken
vertically (Acheson's pendulums). Without joint friction the tower decouples into N modes,
each the single pendulum of an equivalent length l_k; it stands exactly when every mode does.

Draws the tower's stable band on the rig plane (drive frequency against stroke, log axes) with
each mode's edges, for the towers of the first 1, 2, ..., N links side by side (--only: the
whole tower alone), and writes OUT.png, OUT.svg, the edge curves as OUT.csv and everything as
OUT.json. With --frequency and --stroke (or --amplitude, or --T and --A) it also prints the
tower's verdict at that point: which mode fails first and how, the margins, the band through it.
The same band: 'kapitza chart --chain ...'; the same motion: 'kapitza simulate/animate --chain ...'.
"""

EPILOG = """\
examples:
  kapitza tower --chain 0.2,0.2,0.2 --out tower            # 1, 2 and 3 rods of 0.2 m
  kapitza tower --chain 0.2,0.2,0.2 --frequency 200 --stroke 0.005 --out tower
  kapitza tower --chain 0.3,0.2 --links point --masses 1,0.5 --drive sine --only --json
  kapitza tower --chain 0.2,0.2 --joint-damping 0.002 --T 0.003 --A 3000 --no-chart
"""

#: the tower's defaults (the ``tower`` command's; the other commands take no tower without --chain)
DEFAULT_CHAIN = "0.2,0.2,0.2"
#: seconds of motion followed when no duration is given (the tower's slow modes take a second or so)
DEFAULT_DURATION = 3.0


def _numbers(option, text):
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise CLIError(f"{option} must be comma-separated numbers; got {text!r}") from None
    if not vals:
        raise CLIError(f"{option} must hold at least one number; got {text!r}")
    return vals


# ------------------------------------------------------------------ options shared with chart, simulate, animate
def add_chain_options(group, default=None):
    """--chain, --masses, --links, --joint-damping (read by :func:`chain_from`). ``default``: the
    lengths without --chain (the ``tower`` command's); None: no tower unless --chain is given."""
    group.add_argument("--chain", default=default, metavar="L1,L2,...",
                       help="link lengths in m from the pivot up"
                            + (f" (default {default})" if default else ", e.g. 0.2,0.2,0.2: a tower of three links"))
    group.add_argument("--masses", metavar="M1,M2,...", help="link masses in kg (default: equal)")
    group.add_argument("--links", choices=("rod", "point"), default=None,
                       help="rod: uniform rods (default); point: point masses on massless rods")
    group.add_argument("--joint-damping", type=finite_float, default=None, metavar="C",
                       help="friction at every joint, the pivot included, in N m s/rad (default 0)")


def tower_options_given(args):
    """The tower's options given on the command line (without --chain they are an error)."""
    return [opt for opt, dest in (("--masses", "masses"), ("--links", "links"), ("--joint-damping", "joint_damping"),
                                  ("--along-mode", "along_mode"), ("--only", "only"),
                                  ("--amplitude-axis", "amplitude_axis"), ("--grid", "grid"))
            if getattr(args, dest, None) not in (None, False)]


def refuse_tower_options(args):
    """A one-line error when a tower's option is given without --chain."""
    given = tower_options_given(args)
    if given:
        raise CLIError(f"{', '.join(given)} describe{'s' if len(given) == 1 else ''} a tower: give --chain L1,L2,... "
                       "(link lengths in m) too")


def chain_from(args):
    """The :class:`kapitza.Chain` of --chain, --masses, --links and --joint-damping."""
    from ..chain import Chain

    lengths = _numbers("--chain", args.chain)
    masses = None if args.masses is None else _numbers("--masses", args.masses)
    damping = 0.0 if args.joint_damping is None else args.joint_damping
    return Chain(lengths, masses, links=args.links or "rod", joint_damping=damping)


def refuse_pendulum_options(args, options):
    """A one-line error for a single pendulum's option (``(flag, dest, default, what to give instead)``)
    given with --chain."""
    for flag, dest, default, instead in options:
        v = getattr(args, dest, default)
        if v is not None and v is not False and v != default:
            raise CLIError(f"{flag} is the single pendulum's, not the tower's: {instead}")


def add_band_options(group):
    """--only, --amplitude-axis and --grid: how the band is drawn (the ``tower`` command's and ``chart --chain``'s)."""
    group.add_argument("--only", action="store_true", help="draw the whole tower alone, not its 1..N-link prefixes")
    group.add_argument("--amplitude-axis", action="store_true",
                       help="vertical axis in displacement amplitude, not stroke")
    group.add_argument("--grid", type=int, default=None, metavar="N",
                       help="grid points per axis of the band (default 200, at most 2000; with --joint-damping "
                            "60, at most 400: each point a 2N monodromy)")


def add_tower_start(group):
    """--along-mode: the starting tilt's shape."""
    group.add_argument("--along-mode", action="store_true",
                       help="tilt along the longest mode's shape instead of every link alike (--theta0 for its most "
                            "tilted link)")


# ------------------------------------------------------------------ the band on the rig plane
def band_window(chains, drive, g, frequency_range=(None, None), stroke_range=(None, None), mark=None):
    """The rig-plane window: each end given, or the towers' default windows joined (and widened to
    hold the point ``mark = (frequency, stroke)``)."""
    from ..chain import default_window

    wins = [default_window(c, drive, g) for c in chains]
    fr = [min(w[0][0] for w in wins), max(w[0][1] for w in wins)]
    sr = [min(w[1][0] for w in wins), max(w[1][1] for w in wins)]
    if mark is not None:
        for rng, v in ((fr, mark[0]), (sr, mark[1])):
            rng[0], rng[1] = min(rng[0], v / 1.5), max(rng[1], v * 1.5)
    out = []
    for name, unit, given, auto in (("frequency", "Hz", frequency_range, fr), ("stroke", "m", stroke_range, sr)):
        lo = auto[0] if given[0] is None else given[0]
        hi = auto[1] if given[1] is None else given[1]
        if given[0] is not None and given[1] is None and not hi > lo:
            hi = 100.0 * lo
        if given[1] is not None and given[0] is None and not hi > lo:
            lo = hi / 100.0
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
            raise CLIError(f"need 0 < --{name}-min < --{name}-max (in {unit}); got {lo:g} .. {hi:g}")
        out.append((lo, hi))
    return tuple(out)


def band_chart(chain, drive, g, *, only=False, amplitude=False, frequency_range=(None, None),
               stroke_range=(None, None), points=600, grid=None, mark=None, title=None):
    """The figure and :class:`~kapitza.chain.TowerCurves` of the tower's band (its prefixes of 1..N
    links side by side unless ``only``); ``mark``: ``(frequency, stroke)``."""
    from ..figures.tower import tower_chart_figure, tower_family
    from ..chain import tower_curves

    count("--points", points, 20_000, minimum=2)
    # None: the library's default (200, or 60 with joint friction: each point a 2N monodromy)
    grid = None if grid is None else count("--grid", grid, 400 if chain.joint_damping > 0 else 2000, minimum=2)
    chains = [chain] if only or chain.n == 1 else tower_family(
        chain.lengths, chain.masses, links=chain.links, joint_damping=chain.joint_damping, n_max=chain.n)
    fr, sr = band_window(chains, drive, g, frequency_range, stroke_range, mark)
    curves = [tower_curves(c, drive=drive, g=g, frequency_range=fr, stroke_range=sr, points=points, grid=grid)
              for c in chains]
    fig, _ = tower_chart_figure(chains, drive=drive, g=g, frequency_range=fr, stroke_range=sr, amplitude=amplitude,
                                mark=mark, curves=curves, title=title)
    return fig, curves


def write_band(fig, curves, stem, out, *, command, formats=("png", "svg")):
    """Write the figure (``formats``), the edge curves as ``stem.csv`` and ``out`` with the curves as
    ``stem.json``; close the figure; return the paths."""
    import matplotlib.pyplot as plt

    from ..figures import _style

    try:
        written = _style.save(fig, stem, formats)
    finally:  # an unwritable path must not leave the figure open
        plt.close(fig)
    rows = ([c.n_links, *r] for c in curves for r in c.rows())
    written.append(_io.write_csv(stem.with_suffix(".csv"), ["links", "mode", "l", "edge", "mu", "frequency", "stroke"],
                                 rows, comments=[f"zone-0 edges of each mode on the rig plane ({command}): "
                                                 f"{out['chain']['description']}; {out['drive']['description']}; "
                                                 f"g = {out['g']:g} m/s^2",
                                                 "frequency in Hz, stroke (peak to peak) in m, l in m"]))
    out["curves"] = [c.as_dict() for c in curves]
    written.append(_io.write_json(stem.with_suffix(".json"), out))
    return written


def _header(chain, drive, g):
    return {"chain": chain.as_dict() | {"description": chain.describe()},
            "drive": drive.as_dict() | {"description": drive.describe()}, "g": g}


# ------------------------------------------------------------------ the full motion
def per_link(chain, name, value):
    """``--theta0`` or ``--dtheta0`` as one value per link: one number for every link, or a list of
    one per link (:func:`kapitza.cli._common.angles`)."""
    import numpy as np

    if not isinstance(value, tuple):
        return np.full(chain.n, float(value))
    if len(value) != chain.n:
        raise CLIError(f"--{name} must be one number or one per link ({chain.n} for --chain "
                       f"{','.join(f'{x:g}' for x in chain.lengths)}); got {len(value)}")
    return np.array(value, dtype=float)


def angles_text(value):
    """``--theta0``/``--dtheta0`` as given: ``0.1`` or ``(0.1, -0.05)``."""
    return f"({', '.join(f'{x:g}' for x in value)})" if isinstance(value, tuple) else f"{value:g}"


def start_tilt(chain, theta0, along_mode):
    """The starting angles: every link at ``theta0`` (or each its own, a list), or the longest
    mode's shape scaled so that its most tilted link is at ``theta0``."""
    import numpy as np

    if not along_mode:
        return per_link(chain, "theta0", theta0)
    if isinstance(theta0, tuple):
        raise CLIError("--along-mode scales the longest mode's shape to one --theta0; a list of angles, one per "
                       "link, goes without it")
    v = chain.mode_shapes[:, 0]
    return theta0 * v / np.max(np.abs(v))


def tower_motion(chain, drive, report, g, *, theta0, dtheta0=0.0, along_mode=False, periods=None,
                 points_per_period=None, tol=None, rtol=1e-10, atol=1e-12):
    """:func:`kapitza.chain_motion` at the report's point; ``periods`` by default fill
    :data:`DEFAULT_DURATION` seconds, sampled at about 2000 times."""
    from ..motion.chain import chain_motion

    if periods is None:
        periods = max(1.0, DEFAULT_DURATION / (2.0 * report.T))
    if points_per_period is None:
        points_per_period = max(8, min(200, int(2000 / periods) + 1))
    return chain_motion(chain, start_tilt(chain, theta0, along_mode), per_link(chain, "dtheta0", dtheta0),
                        T=report.T, A=report.A, g=g, drive=drive, periods=periods,
                        points_per_period=points_per_period, tol=math.pi / 2 if tol is None else tol,
                        rtol=rtol, atol=atol)


def motion_summary(motion):
    import numpy as np

    e = motion.energy
    return {"toppled": motion.toppled, "t_topple": motion.t_topple, "duration": float(motion.t[-1]),
            "largest_tilt": float(np.max(np.abs(motion.theta))), "tol": motion.tol,
            "final": {"theta": motion.theta[:, -1].tolist(), "dtheta": motion.dtheta[:, -1].tolist()},
            "samples": int(motion.t.size), "energy_range": float(np.ptp(e)) if e.size else 0.0}


def motion_outcome(motion, theta0, along_mode):
    start = f"a tilt of {angles_text(theta0)} rad" + (
        " along mode 1" if along_mode else " (link by link)" if isinstance(theta0, tuple) else " (every link)")
    state = (f"toppled at t = {motion.t_topple:.4g} s" if motion.toppled else
             f"stands (every link within {motion.tol:.3g} rad for {motion.t[-1]:.4g} s)")
    return f"full motion from {start}: {state}"


def write_motion_csv(path, motion, chain, report, command):
    """The motion as CSV: t, the pivot's height, every link's angle and rate."""
    n = chain.n
    header = ["t", "pivot", *[f"theta{j + 1}" for j in range(n)], *[f"dtheta{j + 1}" for j in range(n)]]
    return _io.write_csv(path, header,
                         columns=[motion.t, motion.pivot, *motion.theta, *motion.dtheta],
                         comments=[f"full motion of the tower ({command}): {chain.describe()}; {report.drive}; "
                                   f"T = {report.T!r} s, A = {report.A!r} m/s^2",
                                   "t in s, pivot height in m, angles from the upright in rad, rates in rad/s"])


def motion_title(report, motion):
    what = "falls" if motion.toppled else "stands"
    return f"{report.frequency:.4g} Hz, stroke {1e3 * report.stroke:.3g} mm: {what}"


def _motion(args, chain, drive, report, out):
    motion = tower_motion(chain, drive, report, args.g, theta0=args.theta0, along_mode=args.along_mode,
                          periods=args.duration / (2.0 * report.T))
    out["motion"] = {k: v for k, v in motion_summary(motion).items() if k in ("toppled", "t_topple", "largest_tilt")}
    written = []
    if args.simulate:
        written.append(write_motion_csv(out_stem(args.simulate).with_suffix(".csv"), motion, chain, report,
                                        "kapitza tower"))
    if args.animate:
        from ..figures.tower import animate_tower

        written.append(animate_tower(motion, args.animate, titles=[motion_title(report, motion)], fps=20.0))
    if not args.json:
        print(motion_outcome(motion, args.theta0, args.along_mode))
    return written


# ------------------------------------------------------------------ the command
def register(sub):
    p = sub.add_parser("tower", help="a tower of N linked pendulums on one shaken pivot: its band and verdict",
                       description=DESCRIPTION, epilog=EPILOG)
    t = p.add_argument_group("the tower")
    add_chain_options(t, default=DEFAULT_CHAIN)
    t.add_argument("--g", type=positive_float, default=9.81, metavar="M/S^2", help="gravity (default 9.81)")
    d = p.add_argument_group("the pivot's motion")
    add_drive(d)
    q = p.add_argument_group("a point (optional): --frequency with --stroke or --amplitude, or --T with --A")
    q.add_argument("--frequency", type=positive_float, metavar="HZ", help="drive frequency 1/(2T)")
    q.add_argument("--stroke", type=positive_float, metavar="M", help="pivot travel, peak to peak")
    q.add_argument("--amplitude", type=positive_float, metavar="M",
                   help="pivot displacement amplitude (half the stroke)")
    q.add_argument("--T", type=positive_float, metavar="S", help="half-period of the drive")
    q.add_argument("--A", type=positive_float, metavar="M/S^2", help="acceleration scale of the drive")
    c = p.add_argument_group("the chart")
    add_band_options(c)
    c.add_argument("--frequency-range", nargs=2, type=positive_float, metavar=("LO", "HI"), help="in Hz")
    c.add_argument("--stroke-range", nargs=2, type=positive_float, metavar=("LO", "HI"), help="in m")
    c.add_argument("--points", type=int, default=600, help="samples per edge curve (default 600, at most 20000)")
    c.add_argument("--no-chart", action="store_true", help="no chart (the point's verdict and motion only)")
    m = p.add_argument_group("the full (nonlinear) motion at the point")
    m.add_argument("--theta0", type=angles, default=0.1, metavar="RAD",
                   help="starting tilt at rest, every link (default 0.1), or one per link: A1,A2,...")
    add_tower_start(m)
    m.add_argument("--duration", type=positive_float, default=DEFAULT_DURATION, metavar="S",
                   help=f"seconds of motion (default {DEFAULT_DURATION:g})")
    m.add_argument("--simulate", metavar="STEM",
                   help="write the motion as STEM.csv (t, pivot height, link angles and rates)")
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


def cmd_tower(args):
    chain = chain_from(args)
    drive = drive_from(args)
    point = _point(args)
    report = None
    if point is not None:
        report = chain.analyze(g=args.g, drive=drive, **point)
    out = _header(chain, drive, args.g)
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
        fr = tuple(args.frequency_range) if args.frequency_range else (None, None)
        sr = tuple(args.stroke_range) if args.stroke_range else (None, None)
        if args.frequency_range and not fr[0] < fr[1]:
            raise CLIError(f"need LO < HI in --frequency-range; got {fr[0]:g} {fr[1]:g}")
        if args.stroke_range and not sr[0] < sr[1]:
            raise CLIError(f"need LO < HI in --stroke-range; got {sr[0]:g} {sr[1]:g}")
        mark = None if report is None else (report.frequency, report.stroke)
        fig, curves = band_chart(chain, drive, args.g, only=args.only, amplitude=args.amplitude_axis,
                                 frequency_range=fr, stroke_range=sr, points=args.points, grid=args.grid, mark=mark)
        written += write_band(fig, curves, out_stem(args.out), out, command="kapitza tower")
    if args.json:
        print_json({k: v for k, v in out.items() if k != "curves"} | {"files": [str(p) for p in written]})
    elif written:
        print("wrote " + ", ".join(str(p) for p in written))
    return 0


# ------------------------------------------------------------------ kapitza chart --chain
#: the single pendulum's options of ``chart`` (flag, dest, default, what to give instead), refused with --chain
_LINKS = "with --chain the links are given by --chain, --masses and --links"
_FRICTION = "with --chain the friction is --joint-damping C (N m s/rad, at every joint)"
_MARK = "mark the tower's point by --frequency with --stroke or --amplitude, or by --mark-T and --mark-A"
CHART_PENDULUM_OPTIONS = (("--l", "l", 1.0, _LINKS), ("--rod", "rod", None, _LINKS), ("--zeta", "zeta", 0.0, _FRICTION),
                          ("--damping", "damping", None, _FRICTION), ("--mark-eps", "mark_eps", None, _MARK),
                          ("--mark-mu", "mark_mu", None, _MARK))


def chart_tower(args):
    """``kapitza chart --chain ...``: the tower's band on the rig plane, in the chart's formats."""
    if args.plane not in (None, "rig"):
        raise CLIError(f"--chain draws the tower's band on the rig plane (drive frequency against stroke): give "
                       f"--plane rig or leave --plane out; got --plane {args.plane}")
    refuse_pendulum_options(args, CHART_PENDULUM_OPTIONS)
    chain = chain_from(args)
    drive = drive_from(args)
    point = None
    if args.rpm is not None:
        if args.frequency is not None:
            raise CLIError("give --frequency or --rpm, not both")
        if not args.rpm > 0:
            raise CLIError(f"--rpm must be > 0; got {args.rpm!r}")
        args.frequency = args.rpm / 60.0
    if args.frequency is not None or args.stroke is not None or args.amplitude is not None:
        if args.frequency is None or (args.stroke is None) == (args.amplitude is None):
            raise CLIError("mark a point by --frequency (or --rpm) with one of --stroke, --amplitude")
        if args.mark_T is not None or args.mark_A is not None:
            raise CLIError("give the mark by --frequency with --stroke/--amplitude, or by --mark-T/--mark-A, not both")
        point = dict(frequency=args.frequency, stroke=args.stroke, amplitude=args.amplitude)
    elif args.mark_T is not None or args.mark_A is not None:
        if args.mark_T is None or args.mark_A is None:
            raise CLIError("--mark-T and --mark-A must be given together")
        point = dict(T=args.mark_T, A=args.mark_A)
    report = None if point is None else chain.analyze(g=args.g, drive=drive, **point)
    fig, curves = band_chart(chain, drive, args.g, only=args.only, amplitude=args.amplitude_axis,
                             frequency_range=(args.frequency_min, args.frequency_max),
                             stroke_range=(args.stroke_min, args.stroke_max), points=args.points, grid=args.grid,
                             mark=None if report is None else (report.frequency, report.stroke), title=args.title)
    out = _header(chain, drive, args.g)
    if report is not None:
        out["report"] = report.as_dict()
    written = write_band(fig, curves, out_stem(args.out), out, command="kapitza chart",
                         formats=("png", "svg", "pdf") if args.pdf else ("png", "svg"))
    print(f"tower: {chain.describe()}")
    if report is not None:
        print(f"the point ({report.frequency:.6g} Hz, stroke {1e3 * report.stroke:.6g} mm): {report.verdict}")
    print("wrote " + ", ".join(str(p) for p in written))
    return 0


# ------------------------------------------------------------------ kapitza simulate/animate --chain
#: the single pendulum's options of ``simulate`` and ``animate`` (flag, dest, default, what to give instead),
#: refused with --chain
_ENSEMBLE = "the tower's motion is one start, without a stroboscopic ensemble"
MOTION_PENDULUM_OPTIONS = (("--l", "l", None, _LINKS), ("--rod", "rod", None, _LINKS),
                           ("--damping", "damping", 0.0, _FRICTION), ("--zeta", "zeta", None, _FRICTION),
                           ("--orbits", "orbits", 12, _ENSEMBLE),
                           ("--strobe-periods", "strobe_periods", 300, _ENSEMBLE),
                           ("--compare-linear", "compare_linear", False,
                            "the tower's linear motion is its modes ('kapitza tower' gives their verdicts)"))


def _motion_point(args):
    """``(chain, drive, report, T, A, g)`` of simulate/animate --chain, from the single pendulum's point
    options (--frequency or --rpm with --stroke, --amplitude or --A; --T with --A; --drive...)."""
    from ._common import parameters_from

    if args.eps is not None or args.mu is not None:
        raise CLIError("--eps and --mu are the single pendulum's (each mode of a tower has its own eps): with --chain "
                       "give --frequency with --stroke or --amplitude, or --T and --A")
    refuse_pendulum_options(args, MOTION_PENDULUM_OPTIONS)
    if args.model == "linear":
        raise CLIError("--chain follows the full (nonlinear) motion only; the tower's linear motion is its modes "
                       "(kapitza tower --chain ... for their verdicts)")
    if args.method == "exact":
        raise CLIError("--method exact is the single pendulum's (elliptic functions); the tower is integrated by "
                       "DOP853 (--rtol, --atol)")
    chain = chain_from(args)
    given = [args.T, args.A, args.frequency, args.rpm, args.stroke, args.amplitude]
    if all(v is None for v in given) and args.drive_file is None:
        raise CLIError("with --chain give the point: --frequency with --stroke or --amplitude, or --T with --A")
    kw = parameters_from(args)
    report = chain.analyze(T=kw["T"], A=kw["A"], g=kw["g"], drive=kw["drive"])
    return chain, kw["drive"], report


def _motion_of(args, chain, drive, report):
    if args.periods is not None and not args.periods > 0:
        raise CLIError(f"--periods must be > 0; got {args.periods!r}")
    return tower_motion(chain, drive, report, args.g, theta0=args.theta0, dtheta0=args.dtheta0,
                        along_mode=args.along_mode, periods=args.periods,
                        points_per_period=getattr(args, "points_per_period", None), tol=args.tol,
                        rtol=args.rtol, atol=args.atol)


def _motion_json(args, chain, drive, report, motion):
    out = _header(chain, drive, args.g)
    out["parameters"] = {"T": report.T, "A": report.A, "frequency": report.frequency, "stroke": report.stroke,
                         "given": args.given}
    out["report"] = report.as_dict()
    th0 = start_tilt(chain, args.theta0, args.along_mode)
    out["start"] = {"theta0": th0.tolist(), "dtheta0": per_link(chain, "dtheta0", args.dtheta0).tolist(),
                    "along_mode": bool(args.along_mode)}
    out["motion"] = motion_summary(motion)
    if args.rig_note:
        out["note"] = args.rig_note
    return out


def _motion_lines(args, chain, report, motion):
    rig = ""
    if args.given in ("stroke", "amplitude"):
        rig = f"{report.frequency:.6g} Hz, {args.given} {1e3 * getattr(args, args.given):.6g} mm; "
    start = ("link by link" if isinstance(args.theta0, tuple) else "every link") if not args.along_mode \
        else "along mode 1, " + ", ".join(
        f"{x:+.4g}" for x in start_tilt(chain, args.theta0, True))
    return [f"tower        {chain.describe()}",
            f"parameters   {rig}T = {report.T:.6g} s, A = {report.A:.6g} m/s^2 ({report.A / args.g:.4g} g), "
            f"g = {args.g:g} m/s^2",
            f"drive        {report.drive}",
            f"upright      {report.verdict}",
            f"start        theta0 = {angles_text(args.theta0)} rad ({start}), "
            f"dtheta0 = {angles_text(args.dtheta0)} rad/s",
            "outcome      " + motion_outcome(motion, args.theta0, args.along_mode).split(": ", 1)[1]
            + f"; largest tilt {float(abs(motion.theta).max()):.4g} rad"]


def simulate_tower(args):
    """``kapitza simulate --chain ...``: the tower's full motion as data, a figure and a summary."""
    chain, drive, report = _motion_point(args)
    motion = _motion_of(args, chain, drive, report)
    summary = _motion_json(args, chain, drive, report, motion)
    files = []
    if args.out:
        stem = out_stem(args.out)
        files.append(write_motion_csv(stem.with_suffix(".csv"), motion, chain, report, "kapitza simulate"))
        if args.figures:
            import matplotlib.pyplot as plt

            from ..figures._style import save
            from ..figures.tower import tower_motion_figure

            fig, _ = tower_motion_figure(motion, title=f"{chain.n}-link tower, " + motion_title(report, motion))
            try:
                files += save(fig, stem.parent / (stem.name + "-series"))
            finally:
                plt.close(fig)
        summary["files"] = [str(f) for f in files] + [str(stem.with_suffix(".json"))]
        files.append(_io.write_json(stem.with_suffix(".json"), summary))
    if args.json:
        print_json(summary)
        return 0
    print("\n".join(_motion_lines(args, chain, report, motion)))
    if files:
        print("\nwrote " + ", ".join(str(f) for f in files))
    return 0


def animate_tower_motion(args):
    """``kapitza animate --chain ...``: the tower standing or toppling, as GIF (MP4 with ffmpeg)."""
    import sys
    from pathlib import Path

    from ..figures.animation import ProgressBar
    from ..figures.tower import animate_tower

    chain, drive, report = _motion_point(args)
    if Path(args.out).suffix.lower() not in (".gif", ".mp4"):
        raise CLIError(f"--out must end in .gif or .mp4; got {args.out!r}")
    motion = _motion_of(args, chain, drive, report)
    slowdown = 1.0 if args.slowdown is None else args.slowdown
    progress = None if args.quiet else ProgressBar(f"rendering {Path(args.out).name}")
    # a tower that toppled is shown lying where it fell for a second more
    shown = float(motion.t[-1]) + (1.0 if motion.toppled else 0.0)
    path = animate_tower(motion, args.out, titles=[motion_title(report, motion)], fps=args.fps, slowdown=slowdown,
                         dpi=args.dpi, progress=progress, duration=shown)
    message = ""
    if Path(args.out).suffix.lower() == ".mp4" and path.suffix.lower() != ".mp4":
        message = (f"ffmpeg was not found, so MP4 cannot be written; wrote the GIF {path} instead "
                   "(install ffmpeg for MP4)")
        print(f"kapitza animate: {message}", file=sys.stderr)
    frames = int(shown * args.fps * slowdown) + 1
    summary = _motion_json(args, chain, drive, report, motion) | {
        "file": str(path), "format": path.suffix.lstrip(".").lower(), "frames": frames, "fps": args.fps,
        "slowdown": slowdown, "message": message}
    if args.json:
        print_json(summary)
    else:
        print("\n".join(_motion_lines(args, chain, report, motion)))
        print(f"wrote {path} ({frames} frames at {args.fps:g} fps, {slowdown:.3g} s of video per s of motion)")
    return 0
