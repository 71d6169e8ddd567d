"""Commands about drives: compare the stability charts of several drives."""
from __future__ import annotations

import argparse

import numpy as np

from .. import _io
from ..drives import parse_drive
from ..limits import threshold_table
from ._common import CLIError, add_zeta_from_rig, count, finite_float, format_table, out_stem, print_json, zeta_from_rig

DRIVE_HELP = ("a drive: 'square' (the paper's), 'sine', 'rectangular:DUTY' (e.g. rectangular:0.3), or "
              "'steps:LEVELS:FRACTIONS' (e.g. steps:2,-1,1,-1:0.2,0.3,0.2,0.3: accelerations LEVELS x A for "
              "FRACTIONS of the period, zero mean)")


def drive_arg(text):
    """argparse type: a drive from its text form (a one-line error otherwise)."""
    try:
        return parse_drive(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def register(sub):
    p = sub.add_parser(
        "compare",
        help="overlay the stability charts of several drives, with the averaging thresholds",
        description="Draw the exact stability zones of several drives on one eps-mu chart (all drives share\n"
        "Arnold's axes: T is half the drive period, A the acceleration scale), optionally each also\n"
        "with damping, and tabulate each drive's high-frequency criterion <v_pivot^2> = g l against\n"
        "its exact lower edge of zone 0. Writes OUT.png, OUT.svg, the edges as OUT.csv and the\n"
        "thresholds as OUT-thresholds.csv.",
        epilog="examples:\n  kapitza compare --out drives                        # square, sine, 30 % duty cycle\n"
        "  kapitza compare --drive square --drive rectangular:0.2 --zeta 0.2 --out damped\n"
        "  kapitza compare --drive steps:2,-1,1,-1:0.2,0.3,0.2,0.3 --json",
    )
    p.add_argument("--drive", dest="drives", action="append", type=drive_arg, metavar="DRIVE",
                   help=DRIVE_HELP + "; repeat for several (default: square, sine, rectangular:0.3)")
    p.add_argument("--zeta", type=finite_float, default=0.0,
                   help="also draw each drive with this damping ratio c / (2 sqrt(g/l)) (default 0: none)")
    add_zeta_from_rig(p.add_argument_group("the damping of a rig (instead of --zeta)"))
    p.add_argument("--eps-max", type=finite_float, default=4.0, help="right end of the chart (default 4)")
    p.add_argument("--points", type=int, default=400, help="mu samples per edge curve (default 400, at most 20000)")
    p.add_argument("--mu", type=str, default="0.02,0.05,0.1,0.2,0.3",
                   help="comma-separated mu values of the threshold table (default 0.02,0.05,0.1,0.2,0.3)")
    p.add_argument("--out", default="kapitza-drives", metavar="STEM", help="output path without suffix")
    p.add_argument("--json", action="store_true", help="print the threshold table as JSON")
    p.set_defaults(func=cmd_compare)


def _mu_list(text):
    try:
        return [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise CLIError(f"--mu must be comma-separated numbers; got {text!r}") from None


def cmd_compare(args):
    drives = args.drives or [parse_drive("square"), parse_drive("sine"), parse_drive("rectangular:0.3")]
    args.zeta = zeta_from_rig(args, args.zeta)
    if not (0.0 <= args.zeta < 10.0):
        raise CLIError(f"--zeta must lie in [0, 10); got {args.zeta!r}")
    if not (0.0 < args.eps_max <= 50.0):
        raise CLIError(f"--eps-max must lie in (0, 50]; got {args.eps_max!r}")
    count("--points", args.points, 20_000, minimum=2)
    mu_table = _mu_list(args.mu)
    rows = threshold_table(mu_table, drives)
    table = [r.as_dict() for r in rows]
    if args.json:
        print_json({"thresholds": table})
    else:
        print("High-frequency (averaging) criterion <v_pivot^2> = g l against the exact lower edge of zone 0:")
        print(format_table(["drive", "mu", "eps (averaging)", "eps (exact)", "relative error"],
                           [[r.drive, f"{r.mu:g}", f"{r.eps_averaging:.10g}", f"{r.eps_exact:.10g}",
                             f"{r.relative_error:+.3e}"] for r in rows]))
    from ..figures import _style
    from ..figures.drives import drive_comparison_figure, drive_curves

    mu = np.linspace(0.002, 0.998, args.points)
    curves = []
    for d in drives:
        curves.append(drive_curves(d, mu, args.eps_max))
        if args.zeta > 0:
            curves.append(drive_curves(d, mu, args.eps_max, zeta=args.zeta))
    stem = out_stem(args.out)
    fig = drive_comparison_figure(curves, eps_max=args.eps_max)
    paths = _style.save(fig, stem)
    import matplotlib.pyplot as plt

    plt.close(fig)
    csv_path = _io.write_csv(stem.with_suffix(".csv"), ["drive", "zeta", "zone", "mu", "eps_lo", "eps_hi"],
                             (r for c in curves for r in c.rows()),
                             comments=["exact zone edges of each drive on Arnold's plane (kapitza compare)"])
    t_path = _io.write_csv(stem.parent / (stem.name + "-thresholds.csv"), list(table[0].keys()),
                           ([v for v in t.values()] for t in table))
    if not args.json:
        print("wrote " + ", ".join(str(p) for p in [*paths, csv_path, t_path]))
    return 0
