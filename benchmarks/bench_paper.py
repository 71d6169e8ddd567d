"""Time of ``kapitza paper``: the whole reproduction (eight figures, every check, the report).

Run by hand (``python benchmarks/bench_paper.py``); ``--tiny`` is a smoke run (one figure,
three checks, quick parameter sets). Measured in the same run, one after the other:

* the baseline, as the figures were saved before: one process, figures then checks, each figure
  laid out (and drawn once more) again for its SVG after its PNG, each caption line one mathtext
  string; the checks are the same in both (the baseline measures the saving of the figures);
* the build as ``kapitza paper`` runs it (:func:`kapitza.paper.build.build_paper`): figures and
  checks side by side in ``--workers`` processes, each figure laid out once.

Wall time (what the user waits) and CPU time (user + system of this process and its workers: what
the build costs, whatever else the machine runs) are printed for both.

Both write the same files; the script checks that the same files come out and that every check
passes in both, then prints both times and their ratio.
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, load_line  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

from kapitza.figures import _style  # noqa: E402
from kapitza.paper import build as B  # noqa: E402
from kapitza.paper import figures as F  # noqa: E402
from kapitza.paper import checks as C  # noqa: E402


def _save_each_format_laid_out(fig, stem, formats=("png", "svg"), dpi=150):
    """The saving of the baseline: the figure laid out anew for every format."""
    from kapitza._io import atomic_path

    paths = []
    for fmt in formats:
        p = Path(stem).with_suffix("." + fmt)
        with atomic_path(p) as tmp:
            fig.savefig(tmp, format=fmt, dpi=dpi)
        paths.append(p)
    return paths


def _cpu():
    """CPU seconds (user + system) of this process and of its finished children."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def _caption_whole_lines(fig, text):
    """The captions of the baseline: each line one mathtext string, text and formulas together."""
    lines = _style.wrap_caption(text, fig.get_figwidth() * 72.0 / (0.52 * _style.CAPTION_SIZE))
    fig.set_figheight(fig.get_figheight() + 1.3 * _style.CAPTION_SIZE / 72.0 * len(lines) + 0.1)
    return fig.supxlabel("\n".join(lines), fontsize=_style.CAPTION_SIZE, ha="center", x=0.5)


def timed_build(out, workers, figures, checks, quick, baseline=False):
    """``(wall seconds, CPU seconds, PaperBuild)`` of one build. The CPU time is what the build
    costs whatever else the machine runs; the wall time is what the user waits."""
    saved = F.save, F.caption
    if baseline:
        F.save, F.caption = _save_each_format_laid_out, _caption_whole_lines
    try:
        c0, t0 = _cpu(), time.perf_counter()
        res = B.build_paper(out, quick=quick, workers=workers, figures=figures, checks=checks)
        return time.perf_counter() - t0, _cpu() - c0, res
    finally:
        F.save, F.caption = saved


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tiny", action="store_true", help="smoke run: Figure 1, three checks, quick sets")
    ap.add_argument("--quick", action="store_true", help="quick parameter sets in the checks (as kapitza paper --quick)")
    ap.add_argument("--workers", type=int, default=2, help="processes of the parallel build (default 2)")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each, alternated (default 1)")
    args = ap.parse_args(argv)
    figures = (1,) if args.tiny else tuple(range(1, 9))
    checks = (0, 1, 2) if args.tiny else None
    quick = args.quick or args.tiny
    header("bench_paper")
    print("  kapitza paper: " + ("tiny run" if args.tiny else "the whole reproduction")
          + f" ({len(figures)} figures, {len(checks) if checks else len(C.CHECKS)} checks, "
          + ("quick" if quick else "full") + " parameter sets)")
    runs = {"base": [], "one": [], "new": []}
    with tempfile.TemporaryDirectory() as tmp:
        # Alternated, so that a change in the machine's load falls on all three alike.
        for r in range(args.repeat):
            runs["base"].append(timed_build(Path(tmp) / f"base{r}", 1, figures, checks, quick, baseline=True))
            runs["one"].append(timed_build(Path(tmp) / f"one{r}", 1, figures, checks, quick))
            runs["new"].append(timed_build(Path(tmp) / f"new{r}", args.workers, figures, checks, quick))
        names = {k: sorted(p.name for p in v[0][2].files) for k, v in runs.items()}
    med = {k: (statistics.median(x[0] for x in v), statistics.median(x[1] for x in v)) for k, v in runs.items()}
    (t_base, c_base), (t_one, c_one), (t_new, c_new) = med["base"], med["one"], med["new"]
    print(f"median of {args.repeat}, wall (what the user waits) and CPU (user + system, workers included):")
    print(f"baseline: one process, as before        wall {t_base:8.2f} s   CPU {c_base:8.2f} s")
    print(f"build: 1 process (layout once, formulas alone)  wall {t_one:8.2f} s   CPU {c_one:8.2f} s")
    print(f"build: {args.workers} processes                   wall {t_new:8.2f} s   CPU {c_new:8.2f} s")
    print(f"ratio (baseline / build): wall {t_base / t_new:.2f}x, CPU {c_base / c_new:.2f}x; "
          f"1 process: wall {t_base / t_one:.2f}x, CPU {c_base / c_one:.2f}x")
    same = names["base"] == names["one"] == names["new"]
    passed = all(x[2].passed for v in runs.values() for x in v)
    print(f"same files written: {same} ({len(names['new'])} files)")
    print(f"every check passed: baseline {passed}, build {passed} ({len(runs['new'][0][2].checks)} checks)")
    print("  " + load_line("after"))
    return 0 if (same and passed) else 1


if __name__ == "__main__":
    sys.exit(main())
