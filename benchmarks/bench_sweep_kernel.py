"""The compiled survival kernel (numba) against the numpy loops it replaces, and what a whole map costs.

Run by hand (``python benchmarks/bench_sweep_kernel.py``); ``--tiny`` is a seconds-long smoke run.
Measured in the same run, as CPU time of this process (``time.process_time``: on a machine shared
with other work the wall time measures the load, the CPU time much less so):

* the largest safe tilt to 1 % for ``--periods`` periods on an ``--n x --n`` grid over the chart
  ``0.05 <= eps <= 3``, ``0.02 <= mu <= 0.98``, in blocks of ``--chunks`` points per side (as the
  sweep's chunks run): the compiled kernel and, as the baseline, the numpy path on the same blocks;
  cost per point, the ratio, and how many values are identical;
* the whole command, ``kapitza sweep --resolution --cli-n --periods ... --workers 2`` (default chunk,
  the store, no figure), wall time, extrapolated to the 512 x 512 map by the number of points;
* the integrated path (the sine drive, and the square wave with damping ``zeta = 0.05``) on an
  ``--int-n x --int-n`` block: the compiled DOP853 per state (:mod:`kapitza.motion._integrated_jit`)
  and, as the baseline, the numpy DOP853 loop on the same block; cost per point, the ratio, how many
  safe tilts agree within the stated 1 %, and the 512 x 512 map extrapolated to two cores; with
  ``--int-big-n`` also the compiled path alone on that larger grid in 64 x 64 blocks (the command's
  chunk for 512 x 512), a larger sample of the chart for the extrapolation.

The two integrated paths solve the same equation by the same method (scipy's DOP853 coefficients,
error norm and step control) to the same tolerances per component, with the same window test
(``|theta| <= tol`` at ``x = j/m`` and on the cubic Hermite interpolant between) and searches; the
compiled one steps each state alone (its own step sizes, ``m`` chosen per point rather than per
block), so they agree to the integration error: the safe tilt to 1 % except at ragged-edge points.
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, load_line  # noqa: E402

import kapitza  # noqa: E402
from kapitza.sweeps.kernel import block_quantities  # noqa: E402

EPS, MU = (0.05, 3.0), (0.02, 0.98)
G = kapitza.parameters.G_EARTH
KW = dict(plane="arnold", l=1.0, g=G, tol=0.5, quantities=("tilt",), directions=1, basin_resolution=5,
          accuracy=0.01, floor=1e-4)
FULL = 512 * 512


def tilt_map(eps, mu, periods, chunk, compiled, drive="square", c=0.0):
    out = np.empty((mu.size, eps.size))
    for i in range(0, mu.size, chunk):
        for j in range(0, eps.size, chunk):
            out[i:i + chunk, j:j + chunk] = block_quantities(
                eps[j:j + chunk], mu[i:i + chunk], drive=drive, c=c, periods=periods, compiled=compiled,
                **KW)["max_safe_tilt"]
    return out


def cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=48, help="grid side of the kernel comparison (default 48)")
    ap.add_argument("--periods", type=int, default=1000, help="periods (default 1000)")
    ap.add_argument("--chunks", default="10,32,64", help="block sides compared (default 10,32,64)")
    ap.add_argument("--cli-n", type=int, default=128, help="grid side of the whole command (default 128)")
    ap.add_argument("--int-n", type=int, default=8, help="grid side of the integrated-path runs (default 8)")
    ap.add_argument("--int-periods", type=int, default=1000, help="periods of the integrated runs (default 1000)")
    ap.add_argument("--int-big-n", type=int, default=0,
                    help="grid side of a compiled-only integrated run in 64 x 64 blocks (default 0: none)")
    ap.add_argument("--parts", default="kernel,command,integrated", help="what to run (default: all three)")
    ap.add_argument("--tiny", action="store_true", help="seconds-long smoke run")
    a = ap.parse_args(argv)
    if a.tiny:
        a.n, a.periods, a.chunks, a.cli_n, a.int_n, a.int_periods, a.int_big_n = 6, 30, "3,6", 8, 2, 10, 0
    chunks = [int(v) for v in a.chunks.split(",")]
    header("bench_sweep_kernel")
    print(f"  kapitza {kapitza.__version__} (2 cores; CPU times below are this process's own)")
    parts = set(a.parts.split(","))
    eps, mu = np.linspace(*EPS, a.n), np.linspace(*MU, a.n)
    tilt_map(eps[:2], mu[:2], 5, 2, True)  # compile or load the cache once, outside the timings
    if "kernel" in parts:
        kernel(a, eps, mu, chunks)
    if "command" in parts:
        command_run(a)
    if "integrated" in parts:
        integrated(a)
    print(f"\n{load_line('at the end')}")


def kernel(a, eps, mu, chunks):
    print(f"\nmax safe tilt to 1 %, {a.n} x {a.n} points of the chart, {a.periods} periods, CPU per point:")
    best_numpy = np.inf
    for chunk in chunks:
        t_c, got = cpu(lambda: tilt_map(eps, mu, a.periods, chunk, True))
        t_n, want = cpu(lambda: tilt_map(eps, mu, a.periods, chunk, False))
        best_numpy = min(best_numpy, t_n)
        same = np.mean(got == want)
        print(f"  chunk {chunk:3d}: compiled kernel {1e3 * t_c / got.size:8.3f} ms, baseline numpy path "
              f"{1e3 * t_n / got.size:8.3f} ms, ratio (numpy / compiled) {t_n / t_c:6.1f}x; identical values "
              f"{100 * same:.2f} % ({int(round((1 - same) * got.size))} of {got.size} differ)")
    per_point = t_c / got.size
    print(f"  compiled kernel against the numpy path at its best chunk: {best_numpy / t_c:.1f}x")
    print(f"  512 x 512 map from the kernel's CPU per point: {FULL * per_point:.0f} s on one core, "
          f"{FULL * per_point / 2:.0f} s on two")


def command_run(a):

    run_on = ["--serial"] if a.tiny else ["--workers", "2"]  # the smoke run starts no cluster
    print(f"\nthe whole command, {a.cli_n} x {a.cli_n} points, {a.periods} periods, {' '.join(run_on)}, default chunk:")
    root = tempfile.mkdtemp(prefix="kapitza-bench-")
    try:
        def command(n, periods, out):
            cmd = [sys.executable, "-m", "kapitza", "sweep", "--eps", *map(str, EPS), "--mu", *map(str, MU),
                   "--resolution", str(n), "--periods", str(periods), *run_on, "--quiet", "--no-figure",
                   "--out", os.path.join(root, out)]
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True)
            if proc.returncode != 0:
                raise SystemExit(proc.stderr)
            wall = time.perf_counter() - t0
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)

        fixed, fixed_cpu = command(2, 1, "fixed.zarr")  # start-up: imports, the cluster, the store, the cache
        before = load_line()
        wall, cpu_s = command(a.cli_n, a.periods, "m.zarr")
        per, per_cpu = (wall - fixed) / a.cli_n ** 2, (cpu_s - fixed_cpu) / a.cli_n ** 2
        print(f"  {wall:.1f} s wall ({before} before, {load_line()} after), of which {fixed:.1f} s fixed (the same "
              f"command on 2 x 2 points, 1 period): {1e3 * per:.3f} ms per point;")
        print(f"  CPU of the command and its workers: {cpu_s:.1f} s, of which {fixed_cpu:.1f} s fixed: "
              f"{1e3 * per_cpu:.3f} ms per point")
        print(f"  extrapolated to 512 x 512: {fixed:.0f} + {per * FULL:.0f} = {fixed + per * FULL:.0f} s wall at this "
              f"load; from the CPU, on two otherwise idle cores: {fixed_cpu / 2:.0f} + {per_cpu * FULL / 2:.0f} = "
              f"{(fixed_cpu + per_cpu * FULL) / 2:.0f} s")
    finally:
        shutil.rmtree(root, ignore_errors=True)


def integrated(a):
    print(f"\nintegrated path (DOP853), {a.int_n} x {a.int_n} points in one block, {a.int_periods} periods, CPU:")
    ie, im = np.linspace(*EPS, a.int_n), np.linspace(*MU, a.int_n)
    zeta = 0.05
    cases = (("sine drive", "sine", 0.0), (f"square wave, zeta = {zeta}", "square", 2 * zeta * np.sqrt(G)))
    for _, drive, c in cases:  # compile or load the cache once, outside the timings
        tilt_map(ie[:2], im[:2], 3, 2, True, drive=drive, c=c)
    t_sq, _ = cpu(lambda: tilt_map(ie, im, a.int_periods, a.int_n, True))
    n_pts = ie.size * im.size
    print(f"  (square wave, undamped, exact path compiled, same points: {1e3 * t_sq / n_pts:.3f} ms per point)")
    for name, drive, c in cases:
        t_c, got = cpu(lambda: tilt_map(ie, im, a.int_periods, a.int_n, True, drive=drive, c=c))
        t_n, want = cpu(lambda: tilt_map(ie, im, a.int_periods, a.int_n, False, drive=drive, c=c))
        pc, pn = t_c / n_pts, t_n / n_pts
        off = np.abs(got - want) > 0.01 * np.maximum(got, want) + 1e-12
        print(f"  {name}: compiled {1e3 * pc:.2f} ms per point, baseline numpy DOP853 {1e3 * pn:.2f} ms, ratio "
              f"(numpy / compiled) {t_n / max(t_c, 1e-9):.1f}x; safe tilts within 1 %: {n_pts - int(off.sum())} of "
              f"{n_pts} ({int(np.count_nonzero(want > 0))} with a safe tilt)")
        print(f"    512 x 512 at {a.int_periods} periods, two cores: compiled {FULL * pc / 2 / 60:.1f} min, numpy "
              f"{FULL * pn / 2 / 3600:.2f} h")
    if a.int_big_n:
        n = a.int_big_n
        be, bm = np.linspace(*EPS, n), np.linspace(*MU, n)
        print(f"\ncompiled integrated path alone, {n} x {n} points in blocks of 64 x 64, {a.int_periods} periods:")
        for name, drive, c in cases:
            t_c, got = cpu(lambda: tilt_map(be, bm, a.int_periods, 64, True, drive=drive, c=c))
            pc = t_c / got.size
            print(f"  {name}: {1e3 * pc:.2f} ms per point ({int(np.count_nonzero(got > 0))} of {got.size} with a safe "
                  f"tilt); 512 x 512: {FULL * pc / 60:.1f} min on one core, {FULL * pc / 2 / 60:.1f} min on two")


if __name__ == "__main__":
    main()
