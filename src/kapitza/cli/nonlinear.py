"""``kapitza nonlinear``: Lyapunov stability of the real (nonlinear) upright, its chart and its twist."""
from __future__ import annotations

import numpy as np

from .. import _io
from ._common import CLIError, add_parameters, drive_from, finite_float, out_stem, parameters_from, print_json


def register(sub):
    p = sub.add_parser(
        "nonlinear",
        help="nonlinear (Lyapunov) stability of the upright: twist, resonances, Moser/Markeev verdict, chart",
        description="Inside a linear zone the upright is an elliptic fixed point of the period map of the full\n"
        "equation theta'' = (g + a(t))/l sin(theta). Whether it is Lyapunov stable is decided by the\n"
        "Birkhoff normal form of that map (docs/nonlinear.md): Moser's twist theorem where the twist\n"
        "tau != 0 (the odd map makes 1:3 no obstacle), Markeev's criterion |tau| vs |c4| on 1:4 (tr M = 0).\n"
        "tau: the invariant curve of largest |theta| = r turns rho(r) = w/(2 pi) + tau r^2 times per period.\n\n"
        "For a point: the verdict with its numbers. --chart: the nonlinear chart (zones, 1:3 and 1:4\n"
        "curves, twist zeros) as OUT.png, OUT.svg, OUT.csv and OUT.json. --rotation: the measured\n"
        "rotation number of long exact runs against rho_0 + tau r^2 at the point, as OUT-rotation.*.\n\n"
        "The normal form is the undamped square wave's. With --damping or --zeta the first approximation\n"
        "decides: multipliers inside the unit circle make the real upright asymptotically stable. Another\n"
        "--drive is refused (its nonlinear answer: the safe tilt of 'kapitza stability', or 'kapitza sweep').",
        epilog="examples:\n  kapitza nonlinear --eps 0.5 --mu 0.3\n  kapitza nonlinear --T 0.15 --A 100 --json\n"
        "  kapitza nonlinear --frequency 40 --amplitude 0.05 --rod 0.3\n"
        "  kapitza nonlinear --frequency 40 --amplitude 0.05 --rod 0.3 --damping 0.5\n"
        "  kapitza nonlinear --chart --out nonlinear\n"
        "  kapitza nonlinear --eps 0.5 --mu 0.3 --rotation --out run",
    )
    add_parameters(p, required=False, units=True, drive_options=True, damping_options=True)
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.add_argument("--chart", action="store_true", help="draw the nonlinear chart (needs no point)")
    p.add_argument("--zones", type=int, default=3, metavar="N", help="zones 0..N-1 on the chart (default 3, at most 6)")
    p.add_argument("--points", type=int, default=60, help="mu samples of the chart (default 60, at most 2000)")
    p.add_argument("--scan", type=int, default=30,
                   help="points across each zone and mu searched for twist zeros (default 30; 0: none)")
    p.add_argument("--rotation", action="store_true", help="measure rho(r) on long exact runs at the point")
    p.add_argument("--r-max", type=finite_float, default=None,
                   help="largest starting amplitude [rad] of --rotation (default from the twist)")
    p.add_argument("--periods", type=int, default=2000, help="periods of each --rotation run (default 2000)")
    p.add_argument("--pdf", action="store_true", help="also write PDF")
    p.add_argument("--out", default="kapitza-nonlinear", metavar="STEM", help="output path without suffix")
    p.set_defaults(func=cmd_nonlinear)


def _point(args):
    from ..parameters import to_arnold

    kw = parameters_from(args)
    if "T" in kw:
        eps, mu = to_arnold(kw["T"], kw["A"], kw["l"], kw["g"])
        return float(eps), float(mu)
    return kw["eps"], kw["mu"]


def _given(args):
    return any(getattr(args, k, None) is not None for k in ("T", "A", "eps", "mu", "frequency", "rpm", "stroke",
                                                             "amplitude"))


def _square_and_damped(args):
    """Whether damping is given; another drive than the square wave is refused (the normal form is its)."""
    d = drive_from(args)
    if not d.closed_form(0.0):
        shown = ("--drive-file" if getattr(args, "drive_file", None) is not None else
                 f"--duty {args.duty:g}" if getattr(args, "duty", None) is not None else f"--drive {args.drive}")
        raise CLIError(f"the nonlinear verdict (Birkhoff normal form, Moser's twist) is computed for the square wave "
                       f"only, not for {shown}: see the safe tilt of 'kapitza stability' or 'kapitza sweep'")
    damped = bool(args.damping) or bool(args.zeta)
    if damped and (args.chart or args.rotation):
        raise CLIError("--chart and --rotation are the undamped pendulum's; drop --damping/--zeta")
    return damped


def _damped(args):
    """With damping the first approximation decides: multipliers inside the unit circle make the fixed
    point of the period map asymptotically stable (Lyapunov's theorem on stability by the first
    approximation), one outside it unstable."""
    from ..analysis import analyze

    rep = analyze(**parameters_from(args))
    growth = float(rep.growth)
    if rep.stable:
        kind = "asymptotically stable"
        verdict = ("asymptotically stable: with damping both multipliers lie inside the unit circle (growth "
                   f"{growth:.6g} per period 2T), so small motions of the real pendulum decay too (Lyapunov's "
                   "theorem on stability by the first approximation)")
    elif growth > 0:
        kind = "linearly unstable"
        verdict = (f"unstable: a multiplier outside the unit circle (growth {growth:.6g} per period 2T), and so is the "
                   "real upright (Lyapunov's theorem on instability by the first approximation)")
    else:
        kind = "edge"
        verdict = "undecided: on a zone edge (a multiplier on the unit circle) the linearisation does not decide"
    record = {"eps": float(rep.eps), "mu": float(rep.mu), "kind": kind, "stable": bool(rep.stable),
              "unstable": kind == "linearly unstable", "verdict": verdict, "trace": float(rep.trace),
              "growth": growth, "zeta": float(rep.zeta), "damping": rep.damping}
    return _first_approximation(args, record, f"eps = {float(rep.eps):.12g}, mu = {float(rep.mu):.12g}, "
                                               f"damping ratio zeta = {float(rep.zeta):.6g}", "")


def cmd_nonlinear(args):
    if not args.chart and not _given(args):
        raise CLIError("give a point (--T and --A, or --eps and --mu), or --chart")
    if _square_and_damped(args):
        if not _given(args):
            raise CLIError("give a point (--T and --A, or --eps and --mu) with --damping/--zeta")
        return _damped(args)
    if args.rotation and not _given(args):
        raise CLIError("--rotation needs a point (--T and --A, or --eps and --mu)")
    if args.chart:  # refuse bad chart options before anything is printed
        if not (1 <= args.zones <= 6):
            raise CLIError(f"--zones must lie in [1, 6]; got {args.zones!r}")
        if not (2 <= args.points <= 2000):
            raise CLIError(f"--points must lie in [2, 2000]; got {args.points!r}")
        if not (0 <= args.scan <= 2000):
            raise CLIError(f"--scan must lie in [0, 2000]; got {args.scan!r}")
    formats = ("png", "svg", "pdf") if args.pdf else ("png", "svg")
    stem = out_stem(args.out)
    record, written = {}, []
    if _given(args):
        from ..normal_form import birkhoff_normal_form, nonlinear_stability

        eps, mu = _point(args)
        from ..zones import is_stable

        if not is_stable(eps, mu):
            return _linearly_unstable(args, eps, mu)
        v = nonlinear_stability(eps, mu)
        nf = birkhoff_normal_form(eps, mu)
        c = nf.coefficients
        record = {
            "eps": float(eps), "mu": float(mu), "kind": str(v.kind), "stable": bool(v.stable),
            "unstable": bool(v.unstable), "verdict": str(v), "w": float(nf.w),
            "rotation_number": float(nf.rotation_number), "trace": float(v.trace), "twist": float(nf.twist),
            "resonant_4": float(nf.resonant_4), "beta": float(nf.beta),
            "coefficients": {k: [float(z.real), float(z.imag)] for k, z in zip(("c30", "c21", "c12", "c03"), c)},
        }
        if not args.json:
            print(f"eps = {eps:.12g}, mu = {mu:.12g}")
            print(f"verdict          {v}")
            print(f"linear rotation  w = {float(nf.w):.12g} rad per period, rho_0 = w/(2 pi) = "
                  f"{float(nf.rotation_number):.12g}")
            print(f"twist            tau = {float(nf.twist):.12g} turns per period per rad^2 "
                  f"(rho(r) = rho_0 + tau r^2 + O(r^4), r = max|theta|)")
            print(f"1:4 term         |c4| = {float(nf.resonant_4):.12g} (same units; decides only on tr M = 0)")
        if args.rotation:
            written += _rotation(args, eps, mu, float(nf.twist), stem, formats, record)
    if args.chart:
        written += _chart(args, stem, formats, record)
    if args.json:
        print_json(record)
    elif written:
        print("wrote " + ", ".join(str(p) for p in written))
    return 0


def _linearly_unstable(args, eps, mu):
    """Outside the zones the question is settled by the linearisation: a multiplier outside the unit
    circle makes the upright of the real pendulum unstable too (Lyapunov's theorem on instability
    by the first approximation, for the period map); on an edge itself (|tr M| = 2) it is not."""
    from ..propagation import floquet

    f = floquet(eps, mu)
    hyperbolic = float(f.growth) > 0
    verdict = ("unstable: the linearised upright is unstable (a multiplier outside the unit circle, growth "
               f"{float(f.growth):.6g} per period 2T), and so is the real one (Lyapunov's theorem on instability "
               "by the first approximation)" if hyperbolic else
               "undecided: on a zone edge (|tr M| = 2) the linearisation does not decide")
    record = {"eps": float(eps), "mu": float(mu), "kind": "linearly unstable" if hyperbolic else "edge",
              "stable": False, "unstable": hyperbolic, "verdict": verdict, "trace": float(f.trace),
              "growth": float(f.growth)}
    return _first_approximation(args, record, f"eps = {eps:.12g}, mu = {mu:.12g}",
                                "   (linearly stable iff |tr M| < 2)")


def _first_approximation(args, record, head, trace_note):
    """Print a verdict of the first approximation (``record``) as JSON or as text lines; exit status 0."""
    if args.json:
        print_json(record)
    else:
        print(head)
        print(f"verdict          {record['verdict']}")
        print(f"trace tr M       {record['trace']:.12g}{trace_note}")
    return 0


def _chart(args, stem, formats, record):
    from ..resonances import CSV_HEADER, nonlinear_chart

    chart = nonlinear_chart(np.linspace(0.01, 0.95, args.points), tuple(range(args.zones)), scan=args.scan)
    import matplotlib.pyplot as plt

    from ..figures import _style
    from ..figures.nonlinear import nonlinear_chart_figure

    fig = nonlinear_chart_figure(chart)
    paths = _style.save(fig, stem, formats)
    plt.close(fig)
    paths.append(_io.write_csv(stem.with_suffix(".csv"), CSV_HEADER, chart.rows(),
                               comments=["nonlinear chart of the upright (kapitza nonlinear --chart): zone edges, "
                                         "1:3 and 1:4 curves, twist tau and |c4| on 1:4 with Markeev's verdict"]))
    data = chart.as_dict()
    paths.append(_io.write_json(stem.with_suffix(".json"), data))
    record["chart"] = {"files": [str(p) for p in paths],
                       "twist_zeros": sum(len(z["twist_zeros"]) for z in data["zones"]),
                       "markeev_unstable_points": sum(int(np.sum(~np.asarray(z["markeev_stable"])))
                                                      for z in data["zones"])}
    return paths


def _rotation(args, eps, mu, tau, stem, formats, record):
    from ..motion.rotation import measured_rotation_number

    if not (16 <= args.periods <= 10**6):
        raise CLIError(f"--periods must lie in [16, 1000000]; got {args.periods!r}")
    r_max = args.r_max if args.r_max is not None else min(0.6, 0.3 / np.sqrt(abs(tau)))
    if not (0 < r_max < np.pi / 2):
        raise CLIError(f"--r-max must lie in (0, pi/2); got {r_max!r}")
    run = measured_rotation_number(eps, mu, np.linspace(r_max / 24, r_max, 24), periods=args.periods)
    import matplotlib.pyplot as plt

    from ..figures import _style
    from ..figures.nonlinear import rotation_growth_figure

    base = stem.parent / (stem.name + "-rotation")
    fig = rotation_growth_figure(run)
    paths = _style.save(fig, base, formats)
    plt.close(fig)
    rows = ([float(r), float(m), float(p), bool(b)] for r, m, p, b in
            zip(run.r, run.rotation_number, run.predicted, run.bounded))
    paths.append(_io.write_csv(base.with_suffix(".csv"), ["r", "rho_measured", "rho_normal_form", "bounded"], rows,
                               comments=[f"eps = {eps!r}, mu = {mu!r}, periods = {run.periods}, twist = {tau!r}"]))
    record["rotation"] = {"files": [str(p) for p in paths], "r": run.r.tolist(),
                          "rho_measured": run.rotation_number.tolist(), "rho_normal_form": run.predicted.tolist()}
    return paths
