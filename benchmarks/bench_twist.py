"""Speed of the twist coefficient: vectorised closed forms against integrating the variational equations.

Run by hand (``python benchmarks/bench_twist.py``); ``--tiny`` is a seconds-long smoke run.
Measured in the same run, medians over repeats:

* :func:`kapitza.twist_coefficient` on ``--n`` points spread over zones 0-2 (closed-form cubic
  jets of both phases, their composition and the normal form, on whole arrays; the thin-zone
  points whose rounding estimate is too large are taken from the averaged quartic potential or,
  far out, from the closed forms in extended precision; counted);
* the baseline: per point, :func:`scipy.integrate.solve_ivp` (DOP853, rtol 1e-12) of the
  variational equations ``th1'' = k th1, th3'' = k th3 - k th1^3/6`` from four starting
  directions over both phases, the cubic map read off and put through the same normal form,
  timed on ``--sample`` points and extrapolated per point;
* their agreement on the sample.
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, median_time  # noqa: E402

import kapitza as K  # noqa: E402
from kapitza import _normal_form as NFE  # noqa: E402


def points(n, seed=0):
    rng = np.random.default_rng(seed)
    zone = rng.integers(0, 3, n)
    mu = rng.uniform(0.02, 0.6, n)
    lo, hi = K.zone_edges(mu, zone)
    return lo + rng.uniform(0.05, 0.95, n) * (hi - lo), mu


def ivp_twist(eps, mu):
    """Baseline: the cubic jet by DOP853 on the variational equations, then the same normal form."""
    x, u, _ = K.phase_angles(eps, mu)
    cols = []
    for q, p in [(1, 0), (0, 1), (1, 1), (1, -1)]:
        y = np.array([q, p, 0.0, 0.0])
        for k in (x * x, -u * u):
            sol = solve_ivp(lambda _, z, k=k: [z[1], k * z[0], z[3], k * z[2] - k * z[0] ** 3 / 6], (0, 1), y,
                            method="DOP853", rtol=1e-12, atol=1e-14)
            y = sol.y[:, -1]
        cols.append(y)
    M = np.array([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])
    C = []
    for i in (2, 3):
        a, d = cols[0][i], cols[1][i]
        s1, s2 = cols[2][i] - a - d, cols[3][i] - a + d
        C.append([a, (s1 - s2) / 2, (s1 + s2) / 2, d])
    w = np.arccos(np.trace(M) / 2)
    lam = np.exp(1j * w)
    coef = NFE._coefficients(M, np.array(C), lam)
    return (coef[1] / lam).imag / (8 * np.pi * M[0, 1] ** 2)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=20000)
    ap.add_argument("--sample", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--tiny", action="store_true")
    a = ap.parse_args(argv)
    if a.tiny:
        a.n, a.sample, a.repeats = 200, 3, 1
    header("bench_twist")
    eps, mu = points(a.n)
    redo = int(np.sum(NFE._normal_form(eps, mu)[0].area_defect == 0))
    t, tmin, tmax = median_time(lambda: K.twist_coefficient(eps, mu), a.repeats)
    print(f"twist_coefficient: {a.n} points in zones 0-2: {t:.4g} s (min {tmin:.4g}, max {tmax:.4g}); "
          f"{1e6 * t / a.n:.3g} us per point; {redo} points not from the composed jets (rounding estimate "
          "too large: averaged quartic potential, or extended precision)")
    es, ms = eps[:a.sample], mu[:a.sample]
    tb, _, _ = median_time(lambda: [ivp_twist(e, m) for e, m in zip(es, ms)], 1, warmup=0)
    per_b = tb / a.sample
    print(f"baseline: solve_ivp DOP853 variational equations, {a.sample} points: {tb:.4g} s; "
          f"{1e6 * per_b:.4g} us per point")
    ref = np.array([ivp_twist(e, m) for e, m in zip(es, ms)])
    got = K.twist_coefficient(es, ms)
    zone = K.zone_index(es, ms)
    for z in range(3):
        if np.any(zone == z):
            print(f"agreement on the sample, zone {z}: max relative difference "
                  f"{np.max(np.abs(got[zone == z] / ref[zone == z] - 1)):.2e}")
    print(f"ratio (baseline / closed forms) per point: {per_b / (t / a.n):.4g}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
