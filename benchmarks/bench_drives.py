"""Speed of pixel-exact charts for drives other than the paper's square wave.

Run by hand (``python benchmarks/bench_drives.py``); ``--tiny`` is a smoke run for CI. Each
figure is a median over repeats; the baseline is measured in the same run:

* a 2048 x 2048 chart (eps in (0, 4], mu in (0, 1)) of a four-step drive
  (``StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])``) from its exact edges, against
  numerical Floquet analysis per point (solve_ivp, DOP853, rtol 1e-10, restarted at every
  step of the drive; timed on a sample of points and extrapolated);
* the same chart of the sine drive (Mathieu characteristic values), when available;
* the same for the damped square wave (damping ratio 0.2).
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, median_time  # noqa: E402

import kapitza.drives as kd  # noqa: E402
from kapitza.drives import _api  # noqa: E402

TARGET_S = 0.250
FOUR_STEP = kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])


def axes(n):
    return np.linspace(0.0, 4.0, n + 1)[1:], np.linspace(0.0, 1.0, n + 2)[1:-1]


def chart(drive, eps, mu, zeta=0.0):
    out = np.zeros((mu.size, eps.size), bool)
    return _api.grid(eps, mu, drive, np.full(mu.size, zeta), out)


def ivp_verdict(drive, eps, mu, zeta=0.0, rtol=1e-10):
    """|multipliers| < 1 from a solve_ivp monodromy (per point; the baseline)."""
    C = 2.0 * np.sqrt(8.0) * zeta * mu * eps
    if isinstance(drive, kd.SineWave):
        segs = [(lambda t: np.sin(np.pi * t), 2.0)]
    else:
        segs = [((lambda t, s=s: s), h) for s, h in zip(drive.levels, drive._durations)]
    cols = []
    for y0 in ((1.0, 0.0), (0.0, 1.0)):
        y, t = np.array(y0), 0.0
        for shape, h in segs:
            sol = solve_ivp(lambda tt, v: [v[1], 8 * eps * eps * (mu * mu + shape(tt)) * v[0] - C * v[1]],
                            (t, t + h), y, method="DOP853", rtol=rtol, atol=1e-12)
            y, t = sol.y[:, -1], t + h
        cols.append(y)
    lam = np.abs(np.linalg.eigvals(np.array(cols).T))
    return lam.max() < 1.0 if zeta > 0 else abs(np.trace(np.array(cols).T)) < 2.0


def report(name, drive, n, repeats, sample, zeta=0.0):
    eps, mu = axes(n)
    med, lo, hi = median_time(lambda: chart(drive, eps, mu, zeta), repeats)
    img = chart(drive, eps, mu, zeta)
    rng = np.random.default_rng(0)
    ii = rng.integers(0, mu.size, sample)
    jj = rng.integers(0, eps.size, sample)
    t0 = time.perf_counter()
    ref = np.array([ivp_verdict(drive, eps[j], mu[i], zeta) for i, j in zip(ii, jj)])
    per_point = (time.perf_counter() - t0) / sample
    exact_pts, _ = _api.verdict(eps[jj], mu[ii], drive, np.full(sample, zeta))
    print(f"{name}: {n} x {n} chart from exact edges")
    print(f"  median {med * 1e3:.1f} ms (min {lo * 1e3:.1f}, max {hi * 1e3:.1f}) over {repeats} repeats; "
          f"target {TARGET_S * 1e3:.0f} ms: {'met' if med <= TARGET_S else 'NOT met'}")
    print(f"  pointwise verdicts disagree with the chart: {int(np.sum(img[ii, jj] != exact_pts))} of {sample}")
    print(f"  baseline: numerical Floquet (solve_ivp DOP853 per point) {per_point * 1e3:.2f} ms per point, "
          f"{per_point * n * n:.0f} s for the chart (extrapolated)")
    print(f"  ratio (baseline per point / chart per point): {per_point / (med / (n * n)):,.0f}x")
    print(f"  solve_ivp verdicts differing from the exact ones on the sample: {int(np.sum(ref != exact_pts))} of {sample}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="seconds-long smoke run")
    a = ap.parse_args()
    n, repeats, sample = (128, 2, 10) if a.tiny else (2048, 7, 200)
    header("bench_drives")
    report("four-step drive", FOUR_STEP, n, repeats, sample)
    report("square wave, damping ratio 0.2", kd.SquareWave(), n, repeats, sample, zeta=0.2)
    try:
        import kapitza.mathieu  # noqa: F401
    except ImportError:
        print("sine drive: kapitza.mathieu not available")
    else:
        report("sine drive", kd.SineWave(), n, repeats, sample)


if __name__ == "__main__":
    main()
