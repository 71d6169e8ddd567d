"""Speed of ``kapitza animate`` (GIF) and ``kapitza chart`` against the plain matplotlib/Pillow way of
drawing the same pictures, in the same run.

Run by hand (``python benchmarks/bench_renders.py``); ``--tiny`` is a smoke run for CI.

* animate: :func:`kapitza.figures.animation.animate` of a 10-period motion (241 frames, 900 x 460
  pixels). Baseline: the same function with ``animation._LEGACY = True`` -- every glyph of the clock
  rasterised by FreeType anew each frame, every GIF frame quantised to its own palette by Pillow
  (what matplotlib's ``PillowWriter`` does). The two GIFs are compared frame by frame.

* chart: the whole ``kapitza chart`` command (default chart: PNG and SVG, and the CSV), called in
  this process after its imports, and as a new process. Baseline: the same command with
  ``_style._LEGACY = True`` -- the constrained layout run inside the first ``savefig`` and kept,
  the ticks and titles worked out anew on every pass, the PNG at zlib's default level. The PNGs
  are compared pixel by pixel, the SVGs byte by byte.

Medians of the wall time and of the CPU time (steadier on a shared machine; for the chart
the runs of the two ways alternate).
"""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import kapitza as K  # noqa: E402
from kapitza.figures import animation as anim  # noqa: E402


def timed(fn, repeats):
    """``(wall median, cpu median)`` of ``fn()`` over ``repeats`` calls."""
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def cpu_all():
    """CPU seconds of this process and of its children waited for so far (the new processes)."""
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def timed_all(fn, repeats):
    """``(wall median, cpu median)`` of ``fn()``, the CPU time of the processes it ran included."""
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), cpu_all()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(cpu_all() - c0)
    return statistics.median(wall), statistics.median(cpu)


def chart_bench(tmp, reps, tiny):
    """The ``kapitza chart`` part: in this process and as a new process, both ways."""
    from PIL import Image

    from kapitza.cli import main
    from kapitza.figures import _style

    matplotlib.rcParams["svg.hashsalt"] = "bench"  # the same SVG ids both ways, to compare the files
    extra = ["--points", "200"] if tiny else []

    def run(stem):
        with contextlib.redirect_stdout(io.StringIO()):
            assert main(["chart", "--out", str(stem), *extra]) == 0

    def both(make):
        """Medians of ``make(legacy)()`` both ways, the two alternating (the load on a shared
        machine changes from minute to minute; alternating spreads it over both alike)."""
        wall, cpu = {True: [], False: []}, {True: [], False: []}
        for i in range(reps):
            for legacy in ((True, False) if i % 2 == 0 else (False, True)):
                _style._LEGACY = legacy
                w, c = timed_all(make(legacy), 1)
                wall[legacy].append(w)
                cpu[legacy].append(c)
        _style._LEGACY = False
        return {k: (statistics.median(wall[k]), statistics.median(cpu[k])) for k in (True, False)}

    def warm(legacy):
        stem = tmp / ("chart-old" if legacy else "chart-new")
        return lambda: run(stem)

    for legacy in (True, False):  # warm-up (fonts, the mathtext grammar)
        _style._LEGACY = legacy
        warm(legacy)()
    results = both(warm)

    def cold(legacy):
        code = ("import sys; from kapitza.figures import _style; _style._LEGACY = %r; from kapitza.cli import main; "
                "sys.exit(main(sys.argv[1:]))" % legacy)
        cmd = [sys.executable, "-c", code, "chart", "--out", str(tmp / "chart-cold"), *extra]
        return lambda: subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)

    colds = both(cold)

    old = np.asarray(Image.open(tmp / "chart-old.png")).astype(np.int16)
    new = np.asarray(Image.open(tmp / "chart-new.png")).astype(np.int16)
    diff = np.abs(old - new).max(axis=-1)
    svg = [re.sub(r"<dc:date>.*?</dc:date>", "", (tmp / f"chart-{w}.svg").read_text()) for w in ("old", "new")]
    print(f"\nchart: the default chart, PNG {new.shape[1]} x {new.shape[0]} pixels and SVG"
          f"{' (--points 200)' if tiny else ''}")
    for label, res in (("in this process, after the imports", results), ("as a new process, imports included", colds)):
        print(f"  {label}")
        print(f"    baseline (layout in savefig, ticks redone) wall {res[True][0]:7.2f} s   cpu {res[True][1]:7.2f} s")
        print(f"    kapitza (layout once, ticks fixed)         wall {res[False][0]:7.2f} s   cpu {res[False][1]:7.2f} s")
        print(f"    ratio (baseline / kapitza)                 wall {res[True][0] / res[False][0]:6.2f}x   "
              f"cpu {res[True][1] / res[False][1]:6.2f}x")
    print(f"  PNG pixels differing: {int(np.count_nonzero(diff))} of {diff.size} (largest channel difference "
          f"{int(diff.max())}); SVG files {'identical' if svg[0] == svg[1] else 'DIFFERENT'}")


def gif_frames(path):
    from PIL import Image, ImageSequence

    with Image.open(path) as im:
        return [np.asarray(f.convert("RGB")).astype(np.int16) for f in ImageSequence.Iterator(im)]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tiny", action="store_true", help="a smoke run at a tiny size")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--only", choices=("animate", "chart"), help="run one part only")
    args = p.parse_args(argv)
    reps = 1 if args.tiny else args.repeats
    header('bench_renders')
    tmp = Path(tempfile.mkdtemp(prefix="kapitza-bench-"))

    if args.only != "animate":
        chart_bench(tmp, reps, args.tiny)
    if args.only == "chart":
        return
    periods, dpi = (2, 40) if args.tiny else (10, 100)
    traj = K.simulate(0.1, 0.0, 0.15, 100.0, periods=periods)
    results = {}
    for legacy in (True, False):
        anim._LEGACY = legacy
        path = tmp / ("old.gif" if legacy else "new.gif")
        anim.animate(traj, path, dpi=dpi)  # warm-up (fonts, imports)
        results[legacy] = timed(lambda path=path: anim.animate(traj, path, dpi=dpi), reps)
    anim._LEGACY = False
    old, new = gif_frames(tmp / "old.gif"), gif_frames(tmp / "new.gif")
    diff = [np.abs(a - b).max(axis=-1) for a, b in zip(old, new)]
    print(f"\nanimate: {len(new)} frames, {new[0].shape[1]} x {new[0].shape[0]} pixels, GIF")
    print(f"  baseline (glyphs rasterised and a palette per frame)  wall {results[True][0]:8.2f} s   "
          f"cpu {results[True][1]:8.2f} s")
    print(f"  kapitza (glyph cache, one palette)                    wall {results[False][0]:8.2f} s   "
          f"cpu {results[False][1]:8.2f} s")
    print(f"  ratio (baseline / kapitza)                            wall {results[True][0] / results[False][0]:7.2f}x   "
          f"cpu {results[True][1] / results[False][1]:7.2f}x")
    print(f"  frames: {len(old)} and {len(new)}; pixels differing: {np.mean([np.mean(d > 0) for d in diff]):.2%} "
          f"(largest channel difference {max(int(d.max()) for d in diff)} of 255, mean "
          f"{np.mean([np.abs(a - b).mean() for a, b in zip(old, new)]):.3f})")



if __name__ == "__main__":
    main()
