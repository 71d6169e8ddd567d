"""Speed of drives that give only their acceleration shape (the generic engine).

Run by hand (``python benchmarks/bench_drives_generic.py``); ``--tiny`` is a smoke run for CI.
Medians over repeats; the baseline, the paper's square wave with its closed forms, is measured
in the same run:

* ``kapitza.analyze`` at an ordinary point (T = 0.15 s, A = 100 m/s^2, l = 1 m) for the
  square wave (baseline), the triangle wave, a measured drive of 1,000 samples
  (``kapitza.drives.from_samples``, linear between samples) and the triangle with damping
  0.1/s; goal: at most 20x the square wave, the measured drive under 0.5 s;
* a 512 x 512 chart (eps in (0, 4], mu in (0, 1)) of the measured drive, from its exact edges,
  against the square wave's chart; goal: under 10 s;
* with the compiled loop loaded, the same reports at 12 ordinary points at random (and the sine
  wave's, damped and not), each over the square wave's at that point: the spread the one point
  above does not show.

The reports are timed twice: as a command runs them (the engine's numpy tree: a report's calls are
too small to pay numba's start-up) and with the compiled loop loaded
(:func:`kapitza.engines.load_compiled`). The first call of each drive (the engine's grid) is timed
apart.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, median_time  # noqa: E402

import kapitza  # noqa: E402
from kapitza.drives import _api, from_samples  # noqa: E402


def measured(n):
    """A 50 Hz accelerometer-like trace: two harmonics, an offset and a little noise."""
    t = 0.02 * np.arange(n) / n
    rng = np.random.default_rng(1)
    a = (0.4 + 300.0 * np.sin(2 * np.pi * 50 * t) + 60.0 * np.sin(2 * np.pi * 150 * t + 0.3)
         + 3.0 * rng.standard_normal(n))
    return from_samples(t, a)


def chart(drive, n):
    eps = np.linspace(0.0, 4.0, n + 1)[1:]
    mu = np.linspace(0.0, 1.0, n + 2)[1:-1]
    out = np.zeros((mu.size, eps.size), bool)
    return _api.grid(eps, mu, drive, np.zeros(mu.size), out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="seconds-long smoke run")
    a = ap.parse_args()
    samples, n_chart, repeats, n_points = (50, 16, 2, 2) if a.tiny else (1000, 512, 7, 12)
    header("bench_drives_generic")
    from kapitza.engines import load_compiled

    point = dict(T=0.15, A=100.0, l=1.0)
    drives = [("square wave (baseline)", kapitza.SquareWave(), {}),
              ("triangle wave", kapitza.TriangleWave(), {}),
              (f"measured drive, {samples} samples", measured(samples), {}),
              ("triangle wave, damping 0.1/s", kapitza.TriangleWave(), {"damping": 0.1})]

    def spread(n, reps):
        # the point above is one; ordinary points at random (T log-uniform in [0.03, 0.3] s, A in
        # [30, 3000] m/s^2, l = 1 m; stable and not), each drive's time over the square wave's there
        rng = np.random.default_rng(3)
        pts = [(float(np.exp(rng.uniform(np.log(0.03), np.log(0.3)))), float(np.exp(rng.uniform(np.log(30.0),
                np.log(3000.0))))) for _ in range(n)]
        all_drives = drives + [("sine wave", kapitza.SineWave(), {}),
                               ("sine wave, damping 0.1/s", kapitza.SineWave(), {"damping": 0.1})]
        times = {name: [] for name, _, _ in all_drives}
        for T, A in pts:
            for name, drive, kw in all_drives:
                kapitza.analyze(drive=drive, T=T, A=A, l=1.0, **kw)
                t0 = time.perf_counter()
                for _ in range(reps):
                    kapitza.analyze(drive=drive, T=T, A=A, l=1.0, **kw)
                times[name].append((time.perf_counter() - t0) / reps)
        base = np.array(times[all_drives[0][0]])
        print(f"\n  at {n} ordinary points at random (T in [0.03, 0.3] s, A in [30, 3000] m/s^2, log-uniform), "
              f"the ratio to the square wave at each:")
        for name, _, _ in all_drives[1:]:
            r = np.array(times[name]) / base
            print(f"  {name:34s} median {np.median(times[name]) * 1e3:7.2f} ms   ratio median {np.median(r):6.1f}x, "
                  f"quartiles {np.percentile(r, 25):.1f}x-{np.percentile(r, 75):.1f}x, largest {r.max():.1f}x")

    def table(first_calls):
        base = cbase = None
        for name, drive, kw in drives:
            t0 = time.perf_counter()
            kapitza.analyze(drive=drive, **point, **kw)
            first = time.perf_counter() - t0
            c0 = time.process_time()
            med, lo, hi = median_time(lambda d=drive, k=kw: kapitza.analyze(drive=d, **point, **k), repeats, warmup=0)
            cpu = (time.process_time() - c0) / repeats
            base = med if base is None else base
            cbase = cpu if cbase is None else cbase
            extra = f"; first call {first * 1e3:.0f} ms" if first_calls else ""
            print(f"  {name:34s} median {med * 1e3:9.2f} ms (min {lo * 1e3:.2f}, max {hi * 1e3:.2f}; "
                  f"CPU {cpu * 1e3:.2f} ms{extra})  ratio to the square wave {med / base:7.1f}x (CPU {cpu / cbase:.1f}x)")

    print("\nanalyze(T=0.15, A=100, l=1), as a command runs it (the engine's numpy tree: one report does "
          "not pay numba's start-up):")
    from kapitza.engines.magnus import Engine

    Engine.COMPILED_FROM, budget = float("inf"), Engine.COMPILED_FROM   # (held on the tree for the table)
    table(True)
    Engine.COMPILED_FROM = budget
    if load_compiled():
        print("\n... with the compiled loop loaded (kapitza.engines.load_compiled(): a server, a notebook, "
              "a sweep):")
        table(False)
        spread(n_points, max(2, repeats // 2))
    else:
        print("\n(numba is not installed: no compiled loop)")
    print(f"\n{n_chart} x {n_chart} chart (eps in (0, 4], mu in (0, 1)) from exact edges:")
    sq = kapitza.SquareWave()
    med_sq, _, _ = median_time(lambda: chart(sq, n_chart), repeats)
    d = measured(samples)
    t0, c0 = time.perf_counter(), time.process_time()
    img = chart(d, n_chart)
    t_meas, c_meas = time.perf_counter() - t0, time.process_time() - c0
    print(f"  square wave (baseline)             median {med_sq * 1e3:9.2f} ms over {repeats} repeats")
    print(f"  measured drive, {samples} samples     {t_meas:9.2f} s wall, {c_meas:.2f} s CPU (one run; stable fraction "
          f"{img.mean():.4f})  ratio {t_meas / med_sq:,.0f}x; goal 10 s: {'met' if t_meas <= 10 else 'NOT met'}")
    # the chart agrees with pointwise verdicts on a sample
    rng = np.random.default_rng(0)
    eps = np.linspace(0.0, 4.0, n_chart + 1)[1:]
    mu = np.linspace(0.0, 1.0, n_chart + 2)[1:-1]
    ii, jj = rng.integers(0, mu.size, 40), rng.integers(0, eps.size, 40)
    pts = kapitza.is_stable(eps[jj], mu[ii], drive=d)
    print(f"  pointwise verdicts disagreeing with the chart: {int(np.sum(pts != img[ii, jj]))} of 40")


if __name__ == "__main__":
    main()
