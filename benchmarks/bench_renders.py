"""Speed of ``kapitza animate`` (GIF) against the plain matplotlib/Pillow way of drawing the same
frames, in the same run.

Run by hand (``python benchmarks/bench_renders.py``); ``--tiny`` is a smoke run for CI.

* animate: :func:`kapitza.figures.animation.animate` of a 10-period motion (241 frames, 900 x 460
  pixels). Baseline: the same function with ``animation._LEGACY = True`` -- every glyph of the clock
  rasterised by FreeType anew each frame, every GIF frame quantised to its own palette by Pillow
  (what matplotlib's ``PillowWriter`` does). The two GIFs are compared frame by frame.

Medians of the wall time and of the process's CPU time (steadier on a shared machine).
"""
from __future__ import annotations

import argparse
import datetime
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import machine  # noqa: E402

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


def gif_frames(path):
    from PIL import Image, ImageSequence

    with Image.open(path) as im:
        return [np.asarray(f.convert("RGB")).astype(np.int16) for f in ImageSequence.Iterator(im)]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tiny", action="store_true", help="a smoke run at a tiny size")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args(argv)
    reps = 1 if args.tiny else args.repeats
    print(f"bench_renders  {datetime.datetime.now().isoformat(timespec='seconds')}")
    for line in machine():
        print("  " + line)
    print(f"  load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    tmp = Path(tempfile.mkdtemp(prefix="kapitza-bench-"))

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
