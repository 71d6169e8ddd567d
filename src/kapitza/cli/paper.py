"""``kapitza paper``: regenerate every figure of the paper and check every numbered result."""
from __future__ import annotations

import sys


def register(sub):
    p = sub.add_parser(
        "paper",
        help="reproduce the paper: Figures 1-8, the checks of its numbered results, and a report",
        description="Regenerate Csizmadia & Hatvani's paper with kapitza and check each numbered result\n"
        "(Lemmas 3.1-3.2, Theorems 3.3-3.4, Corollary 4.1, the stability zones of section 4).\n\n"
        "Writes into OUT:\n"
        "  figure1.png ... figure8.png, .svg   the eight figures\n"
        "  figure1.json/.csv ... figure8.*     the data behind each figure, to re-plot elsewhere\n"
        "  checks.json                         every check: claim, method, reference, worst error, verdict\n"
        "  periods.csv                         T_n, T~_n for A = 15, 30, 100, 1000 m/s^2, with tr M there\n"
        "  report.html                         self-contained report (figures inline); open it first\n"
        "  report.md                           the same report in Markdown\n\n"
        "Exit status 0 when every check passes, 1 when one fails (the report says which), 2 on bad input.",
        epilog="examples:\n  kapitza paper --out out/paper\n  kapitza paper --out /tmp/paper --quick   # "
               "fewer cases per check",
    )
    p.add_argument("--out", default="kapitza-paper", metavar="DIR", help="output folder (default kapitza-paper)")
    p.add_argument("--quick", action="store_true", help="fewer parameter sets in each check")
    p.add_argument("--quiet", action="store_true", help="print only the summary")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="processes rendering figures and running checks side by side (default: CPUs, at most 2)")
    p.set_defaults(func=cmd_paper)


def cmd_paper(args):
    from ..paper.build import build_paper

    progress = None if args.quiet else (lambda msg: print(f"  {msg}", file=sys.stderr, flush=True))
    res = build_paper(args.out, quick=args.quick, progress=progress, workers=args.workers)
    width = max((len(r.key) for r in res.checks), default=0)
    for r in res.checks:
        bound = f"{'<=' if r.sense == '<=' else '>'} {r.tolerance:.1e}"
        print(f"{r.status}  {r.key:<{width}}  worst {r.worst:9.2e} (must be {bound}), {r.cases} cases")
    print(f"wrote {len(res.files)} files to {res.out}; open {res.out / 'report.html'}")
    if not res.passed:
        print("kapitza paper: some checks FAILED (see the report)", file=sys.stderr)
        return 1
    return 0
