"""Speed of the sine drive (Mathieu's equation) against the way a user would build it from scipy.

Run by hand (``python benchmarks/bench_sine.py``); ``--tiny`` is a smoke run for CI. Each figure is
a median over repeats; the baseline is measured in the same run:

* the chart: ``stability_grid`` of the sine drive on ``N x N`` doubles (eps in (0, 4], mu in
  (0, 1); default 1024) against the chart built from ``scipy.special.mathieu_a/b``: per column
  ``q = 16 eps^2/pi^2`` the characteristic values ``a_n(q)``, ``b_{n+1}(q)`` of every zone that
  can meet the column, and a pixel is stable where ``a_n < -2 mu^2 q < b_{n+1}`` for some ``n``;
* the edges: ``zone_edges(mu, n, drive='sine')`` for zones 0-3 at 200 values of mu in
  [0.05, 0.95] against ``scipy.optimize.brentq`` on ``mathieu_a(n, q) + 2 mu^2 q`` (and
  ``mathieu_b(n + 1, q)``) from a bracket 5 % either side of the edge.

Both report where they disagree: scipy's characteristic values are wrong at large ``q`` (its
series jump branches), kapitza's are checked against mpmath in ``tests/test_sine_oracle.py``.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, median_time  # noqa: E402

import kapitza as K  # noqa: E402

PI = np.pi


def cpu_median(fn, repeats):
    """Median CPU time of the process over ``repeats`` calls (steadier than wall time on a shared machine)."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return sorted(times)[len(times) // 2]


def axes(n):
    return np.linspace(0.0, 4.0, n + 1)[1:], np.linspace(0.0, 1.0, n + 2)[1:-1]


def scipy_chart(eps, mu):
    """The chart from scipy's characteristic values, column by column (the baseline)."""
    q = 16.0 * eps * eps / PI**2
    a = -2.0 * (mu * mu)[:, None] * q[None, :]
    out = np.zeros(a.shape, bool)
    # zones whose lower edge can lie in the window: a_n(q_max) below the ray's top (a = 0)
    n = 0
    while float(mathieu_a(n, q[-1])) < 0.0:
        lo = mathieu_a(n, q)
        hi = mathieu_b(n + 1, q)
        out |= (a > lo[None, :]) & (a < hi[None, :])
        n += 1
    return out


def scipy_edges(mu, zones, guess):
    """brentq on scipy's characteristic values, bracket 5 % either side of ``guess``."""
    out = np.empty((2,) + guess[0].shape)
    for side, fn, shift in ((0, mathieu_a, 0), (1, mathieu_b, 1)):
        for i, n in enumerate(zones):
            for j, m in enumerate(mu):
                g = guess[side][i, j]

                def f(e, n=n, m=m):
                    q = 16.0 * e * e / PI**2
                    return fn(n + shift, q) + 2.0 * m * m * q

                try:
                    out[side, i, j] = brentq(f, 0.95 * g, 1.05 * g, xtol=1e-300, rtol=4 * np.finfo(float).eps)
                except ValueError:  # no sign change: scipy's values jumped branches
                    out[side, i, j] = np.nan
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tiny", action="store_true", help="a smoke run at a tiny size")
    p.add_argument("--size", type=int, default=1024)
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args(argv)
    size, n_mu, reps = (32, 8, 1) if args.tiny else (args.size, 200, args.repeats)
    header("bench_sine")

    eps, mu = axes(size)
    ours = K.stability_grid(eps, mu, drive="sine")
    theirs = scipy_chart(eps, mu)
    t_k = median_time(lambda: K.stability_grid(eps, mu, drive="sine"), reps)
    t_s = median_time(lambda: scipy_chart(eps, mu), reps)
    print(f"\nchart {size} x {size} (eps in (0, 4], mu in (0, 1))")
    print(f"  kapitza stability_grid     {t_k[0] * 1e3:9.2f} ms  (min {t_k[1] * 1e3:.2f}, max {t_k[2] * 1e3:.2f})")
    print(f"  scipy mathieu_a/b chart    {t_s[0] * 1e3:9.2f} ms  (min {t_s[1] * 1e3:.2f}, max {t_s[2] * 1e3:.2f})")
    print(f"  ratio scipy / kapitza      {t_s[0] / t_k[0]:9.2f}x  (wall time)")
    c_k = cpu_median(lambda: K.stability_grid(eps, mu, drive="sine"), reps)
    c_s = cpu_median(lambda: scipy_chart(eps, mu), reps)
    print(f"  CPU time kapitza / scipy   {c_k * 1e3:9.2f} ms / {c_s * 1e3:.2f} ms: ratio {c_s / c_k:.2f}x")
    print(f"  pixels that differ         {int(np.count_nonzero(ours != theirs))} of {ours.size}")

    mus = np.linspace(0.05, 0.95, n_mu)
    zones = np.arange(4)
    M, Z = np.meshgrid(mus, zones)
    lo, hi = K.zone_edges(M, Z, drive="sine")
    t_k = median_time(lambda: K.zone_edges(M, Z, drive="sine"), reps)
    ref = scipy_edges(mus, zones, (lo, hi))
    t_s = median_time(lambda: scipy_edges(mus, zones, (lo, hi)), max(1, reps // 2))
    rel = np.abs(np.stack([lo, hi]) - ref) / np.stack([lo, hi])
    print(f"\nzone_edges: zones 0-3 x {n_mu} mu in [0.05, 0.95] ({2 * lo.size} edges)")
    print(f"  kapitza zone_edges         {t_k[0] * 1e3:9.2f} ms  (min {t_k[1] * 1e3:.2f}, max {t_k[2] * 1e3:.2f})")
    print(f"  scipy brentq on mathieu_a/b{t_s[0] * 1e3:9.2f} ms  (min {t_s[1] * 1e3:.2f}, max {t_s[2] * 1e3:.2f})")
    print(f"  ratio scipy / kapitza      {t_s[0] / t_k[0]:9.2f}x  (wall time)")
    c_k = cpu_median(lambda: K.zone_edges(M, Z, drive="sine"), reps)
    c_s = cpu_median(lambda: scipy_edges(mus, zones, (lo, hi)), max(1, reps // 2))
    print(f"  CPU time kapitza / scipy   {c_k * 1e3:9.2f} ms / {c_s * 1e3:.2f} ms: ratio {c_s / c_k:.2f}x")
    bad = ~np.isfinite(rel) | (rel > 1e-12)
    print(f"  edges where they differ by more than 1e-12 relative: {int(np.count_nonzero(bad))} of {rel.size}"
          f" (scipy failed to bracket {int(np.count_nonzero(~np.isfinite(ref)))})")


if __name__ == "__main__":
    main()
