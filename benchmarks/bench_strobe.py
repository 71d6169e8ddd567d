"""Speed of the nonlinear stroboscopic map on large ensembles.

Run by hand (``python benchmarks/bench_strobe.py``); ``--tiny`` is a seconds-long smoke run.
Measured in the same run, medians over repeats:

* the exact ensemble map (:func:`kapitza.motion.stroboscopic_map`, undamped, Jacobi
  elliptic phase flows on whole numpy arrays): ``--n`` initial states over ``--periods``
  periods, single process and with ``--workers`` processes;
* the baseline: a loop of :func:`scipy.integrate.solve_ivp` (DOP853, rtol 1e-10,
  restarted at every switch) over the same initial states, timed on ``--sample`` of them
  and extrapolated per trajectory;
* their agreement on the sample (the two are independent solutions of the same map).

The target of the issue, 100,000 initial states for 1,000 periods on two cores, is
extrapolated from the per-trajectory-period cost; ``--full`` also runs it once.
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

from kapitza.motion import stroboscopic_map

T, A, L, G = 0.15, 100.0, 1.0, 9.81   # zone 0: islands about the upright in a chaotic sea




def ensemble(n, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(-0.6, 0.6, n), rng.uniform(-6.0, 6.0, n)


def ivp_map(th0, om0, periods, rtol=1e-10, atol=1e-12):
    """Baseline: one solve_ivp per trajectory and phase."""
    out = np.empty((2, th0.size))
    for i in range(th0.size):
        y = np.array([th0[i], om0[i]])
        for k in range(2 * periods):
            s = (G + A) / L if k % 2 == 0 else (G - A) / L
            sol = solve_ivp(lambda _, z, s=s: [z[1], s * np.sin(z[0])], (k * T, (k + 1) * T), y,
                            method="DOP853", rtol=rtol, atol=atol)
            y = sol.y[:, -1]
        out[:, i] = y
    return out




def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=100_000, help="ensemble size (default 100000)")
    ap.add_argument("--periods", type=int, default=20, help="periods per timed map call (default 20)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--sample", type=int, default=20, help="trajectories in the solve_ivp baseline (default 20)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--full", action="store_true", help="also run n x 1000 periods once with --workers")
    ap.add_argument("--tiny", action="store_true", help="smoke run: seconds")
    args = ap.parse_args(argv)
    if args.tiny:
        args.n, args.periods, args.repeats, args.sample, args.full = 2000, 3, 1, 3, False
    header("bench_strobe")
    print(f"  parameters T = {T} s, A = {A} m/s^2, l = {L} m, g = {G} m/s^2 (zone 0); "
          f"states uniform in |theta| <= 0.6 rad, |theta'| <= 6 rad/s")
    th0, om0 = ensemble(args.n)

    print(f"\nexact ensemble map: {args.n} states x {args.periods} periods, median of {args.repeats}")
    med1, lo1, hi1 = median_time(lambda: stroboscopic_map(th0, om0, T, A, L, G, periods=args.periods), args.repeats)
    per1 = med1 / (args.n * args.periods)
    print(f"  1 process          {med1:8.3f} s  (min {lo1:.3f}, max {hi1:.3f})   {per1 * 1e9:8.1f} ns per state and period")
    medw, low, hiw = median_time(lambda: stroboscopic_map(th0, om0, T, A, L, G, periods=args.periods,
                                                          workers=args.workers), args.repeats)
    perw = medw / (args.n * args.periods)
    print(f"  {args.workers} workers          {medw:8.3f} s  (min {low:.3f}, max {hiw:.3f})   {perw * 1e9:8.1f} ns per state and period")

    m = min(args.sample, args.n)
    print(f"\nbaseline: solve_ivp DOP853 loop (rtol 1e-10), {m} of the states x {args.periods} periods, median of {args.repeats}")
    medb, lob, hib = median_time(lambda: ivp_map(th0[:m], om0[:m], args.periods), args.repeats, warmup=0)
    perb = medb / (m * args.periods)
    print(f"  loop               {medb:8.3f} s  (min {lob:.3f}, max {hib:.3f})   {perb * 1e9:8.0f} ns per state and period")
    print(f"  extrapolated to {args.n} states x {args.periods} periods: {perb * args.n * args.periods:,.0f} s")

    for p in (1, args.periods):
        exact = stroboscopic_map(th0[:m], om0[:m], T, A, L, G, periods=p).final
        ref = ivp_map(th0[:m], om0[:m], p)
        diff = np.abs(np.asarray(exact) - ref)
        print(f"  agreement on the sample after {p:3d} period(s): max |d theta| = {diff[0].max():.2e} rad, "
              f"max |d theta'| = {diff[1].max():.2e} rad/s")
    print("  (over many periods chaotic members amplify the solver's local errors)")

    print("\nratio (baseline / exact), per state and period")
    print(f"  1 process: {perb / per1:,.0f}x    {args.workers} workers: {perb / perw:,.0f}x")
    target = 100_000 * 1000
    print(f"\n100,000 states x 1,000 periods, extrapolated: exact {per1 * target:,.0f} s (1 process), "
          f"{perw * target:,.0f} s ({args.workers} workers); solve_ivp loop {perb * target / 86400:,.1f} days")
    if args.full:
        th_f, om_f = ensemble(100_000, seed=1)
        t0 = time.perf_counter()
        orb = stroboscopic_map(th_f, om_f, T, A, L, G, periods=1000, workers=args.workers)
        dt = time.perf_counter() - t0
        assert np.all(np.isfinite(orb.theta))
        print(f"  measured once with {args.workers} workers: {dt:,.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
