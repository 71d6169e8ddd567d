"""Speed of the exact engine: stability_grid and zone_edges.

Run by hand (``python benchmarks/bench_engine.py``); ``--tiny`` is a seconds-long smoke run
for CI. Every figure is the median over repeats, and each comparison is measured in the
same run:

* ``stability_grid`` on 4096 x 4096 over eps in (0, 4], mu in (0, 1) -- the default call
  (a fresh result array each repeat, discarded) and the ``out=`` variant (one buffer
  reused) -- against a vectorised numpy evaluation of the plain trace formula
  ``|2 cosh x cos u + (D - 1/D) sinh x sin u| < 2`` over the full grid, and against
  numerical Floquet analysis (solve_ivp, DOP853, per point, timed on a sample and
  extrapolated);
* ``zone_edges`` for 10 zones x 10,000 mu values, the curves (``certify=False``, the closed forms'
  roots) and, on a tenth of the values, the edges moved to the certified verdict's doubles (the
  default);
* ``amplitude_edges`` for 3 zones x 30,000 half-periods, against the earlier solve (zone 0's
  lower edge on the plain gap, which cancels as u -> 0) in the same run;
* ``is_stable`` (with its blocks on every CPU, and on one thread) and ``zone_index`` on 10^7
  random points (eps in (0, 4], mu in (0, 1)) against
  the plain numpy trace formula on the same points and against the closed forms with
  arctangents (``_square._verdict_careful``, the earlier path, now kept for the points inside the
  rounding bound); min and median over repeats (the machine may be shared);
* ``analyze`` for one parameter set, physical and Arnold's: the scalar path against the array
  path (every part on numpy's kernels, as before; ``kapitza.analysis._analyze(pointwise=False)``).
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

import kapitza as K
from kapitza import _square as Z

GRID_TARGET_S = 0.050
EDGES_TARGET_S = 0.050
ANALYZE_TARGET_S = 0.0005
BASELINE_MIN_RATIO = 10.0
POINTS_MIN_RATIO = 5.0  # is_stable on random points against the plain numpy trace formula




def grid_axes(n_eps, n_mu):
    eps = np.linspace(0.0, 4.0, n_eps + 1)[1:]       # (0, 4]
    mu = np.linspace(0.0, 1.0, n_mu + 2)[1:-1]       # (0, 1), both ends excluded
    return eps, mu


def trace_baseline(eps, mu, rows_per_chunk=256):
    """|tr M| < 2 from the plain formula, vectorised with numpy over the whole grid
    (in row blocks so that the temporaries stay in memory)."""
    out = np.empty((mu.size, eps.size), dtype=bool)
    e = eps[None, :]
    for r0 in range(0, mu.size, rows_per_chunk):
        m = mu[r0:r0 + rows_per_chunk, None]
        x = 2.0 * np.sqrt(2.0) * e * np.sqrt(1.0 + m * m)
        u = 2.0 * np.sqrt(2.0) * e * np.sqrt(1.0 - m * m)
        D = x / u
        tr = 2.0 * np.cosh(x) * np.cos(u) + (D - 1.0 / D) * np.sinh(x) * np.sin(u)
        out[r0:r0 + rows_per_chunk] = np.abs(tr) < 2.0
    return out


def amplitude_edges_plain(T, n, l=1.0, g=K.G_EARTH):
    """The earlier ``amplitude_edges`` (square wave): regula falsi on ``u - n pi - alpha`` (or
    ``beta``) over ``[n pi, (n + 1) pi]``, zone 0's lower edge on the plain gap (its terms cancel
    as u -> 0). Kept here as the baseline of the cancellation-free solve's cost."""
    from kapitza import _exact as X

    T, n = np.broadcast_arrays(np.asarray(T, float), np.asarray(n, float))
    kappa = 2.0 * g * T * T / l
    upper = np.stack([np.zeros(n.shape, bool), np.ones(n.shape, bool)])
    nn, kk = np.stack([n, n]), np.stack([kappa, kappa])

    def F(u):
        x = np.sqrt(u * u + kk)
        with np.errstate(divide="ignore"):
            D = x / u
            return u - nn * np.pi - np.where(upper, X.beta_x(x, D), X.alpha_x(x, D))

    u = X.illinois(F, nn * np.pi + 0.0, (nn + 1.0) * np.pi)
    A = g + l * (u / np.stack([T, T])) ** 2
    return A[0], A[1]


def floquet_ivp(eps, mu, rtol=1e-10, atol=1e-12):
    """|tr M| < 2 with M from solve_ivp (DOP853), one solve per column and half-period.

    Time unit T = 1: theta'' = x^2 theta on [0, 1), theta'' = -u^2 theta on [1, 2)."""
    x = 2.0 * np.sqrt(2.0) * eps * np.sqrt(1.0 + mu * mu)
    u = 2.0 * np.sqrt(2.0) * eps * np.sqrt(1.0 - mu * mu)
    tr = 0.0
    for j, y0 in enumerate(([1.0, 0.0], [0.0, 1.0])):
        y = np.array(y0)
        for k, s in enumerate((x * x, -u * u)):
            sol = solve_ivp(lambda t, z, s=s: [z[1], s * z[0]], (k, k + 1), y, method="DOP853", rtol=rtol, atol=atol)
            y = sol.y[:, -1]
        tr += y[j]
    return abs(tr) < 2.0


def trace_points(eps, mu):
    """|tr M| < 2 from the plain formula at scattered points (one vectorised pass)."""
    x = 2.0 * np.sqrt(2.0) * eps * np.sqrt(1.0 + mu * mu)
    u = 2.0 * np.sqrt(2.0) * eps * np.sqrt(1.0 - mu * mu)
    D = x / u
    return np.abs(2.0 * np.cosh(x) * np.cos(u) + (D - 1.0 / D) * np.sinh(x) * np.sin(u)) < 2.0


def one_thread(fn, *args):
    """``fn(*args)`` with the fast verdict's blocks on one thread."""
    saved = Z._threads
    Z._threads = lambda blocks: 1
    try:
        return fn(*args)
    finally:
        Z._threads = saved


def fresh_pages(nbytes):
    """Fill a bool array on newly mapped memory: the cost of first-touch page faults."""
    import mmap

    mm = mmap.mmap(-1, nbytes)
    a = np.frombuffer(mm, dtype=bool)
    a.fill(True)
    del a
    mm.close()




def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="a seconds-long smoke run (small sizes, few repeats)")
    args = ap.parse_args(argv)
    tiny = args.tiny

    n_grid = 64 if tiny else 4096
    repeats = 3 if tiny else 21
    base_repeats = 1 if tiny else 3
    n_ivp = 4 if tiny else 40
    n_mu_edges = 100 if tiny else 10_000
    edge_repeats = 3 if tiny else 21

    header("bench_engine")
    print(f"  kapitza {K.__version__} engine benchmark{' (--tiny)' if tiny else ''}")
    print()

    # ------------------------------------------------------------ stability grid
    eps, mu = grid_axes(n_grid, n_grid)
    px = eps.size * mu.size
    print(f"stability_grid: {mu.size} x {eps.size} = {px:,} pixels, eps in (0, 4], mu in (0, 1); "
          f"median of {repeats} repeats")
    t0 = time.perf_counter()
    K.stability_grid(eps, mu)
    t_cold = time.perf_counter() - t0
    t_def = median_time(lambda: K.stability_grid(eps, mu), repeats)
    buf = np.empty((mu.size, eps.size), dtype=bool)
    t_out = median_time(lambda: K.stability_grid(eps, mu, out=buf), repeats)
    t_alloc = median_time(lambda: np.ones((mu.size, eps.size), dtype=bool), repeats)
    t_fresh = median_time(lambda: fresh_pages(px), min(repeats, 7), warmup=0)
    print(f"  default call (new result array each repeat, discarded): {t_def[0] * 1e3:8.2f} ms"
          f"  (min {t_def[1] * 1e3:.2f}, max {t_def[2] * 1e3:.2f})")
    print(f"  out= buffer reused:                                      {t_out[0] * 1e3:8.2f} ms"
          f"  (min {t_out[1] * 1e3:.2f}, max {t_out[2] * 1e3:.2f})")
    print(f"  first call in this process (cold):                       {t_cold * 1e3:8.2f} ms")
    print(f"  for scale, {px / 2**20:.0f} MiB of bools: np.ones (allocator reuses pages): {t_alloc[0] * 1e3:6.2f} ms;"
          f" filling never-touched pages: {t_fresh[0] * 1e3:.2f} ms")
    print("    (repeated default calls get their result memory back from the allocator; a result on")
    print("     fresh pages -- a first call, or a new process -- pays the second figure in page faults)")

    t_base = median_time(lambda: trace_baseline(eps, mu), base_repeats, warmup=0 if not tiny else 1)
    grid = K.stability_grid(eps, mu)
    base = trace_baseline(eps, mu)
    differ = int(np.count_nonzero(grid != base))
    print(f"  baseline: numpy trace formula over the full grid:        {t_base[0] * 1e3:8.2f} ms"
          f"  (median of {base_repeats})")
    print(f"    pixels where the baseline disagrees with the exact grid: {differ} of {px:,} "
          f"(stable fraction {grid.mean():.4f})")
    r_def, r_out = t_base[0] / t_def[0], t_base[0] / t_out[0]
    print(f"  speed-up over the baseline: {r_def:.1f}x (default call), {r_out:.1f}x (out=)")

    rng = np.random.default_rng(0)
    sample = [(float(rng.choice(eps)), float(rng.choice(mu))) for _ in range(n_ivp)]
    t0 = time.perf_counter()
    ivp_verdicts = [floquet_ivp(e, m) for e, m in sample]
    t_ivp = (time.perf_counter() - t0) / n_ivp
    agree = sum(v == bool(K.is_stable(e, m)) for v, (e, m) in zip(ivp_verdicts, sample))
    print(f"  numerical Floquet (solve_ivp DOP853, rtol 1e-10, 4 solves per point): "
          f"{t_ivp * 1e3:.2f} ms per point on a sample of {n_ivp} ({agree}/{n_ivp} verdicts agree)")
    print(f"    extrapolated to the grid: {t_ivp * px:,.0f} s; speed-up of stability_grid: "
          f"{t_ivp * px / t_def[0]:,.0f}x (default call)")

    # ------------------------------------------------------------ zone edges
    mu_e = np.linspace(0.0, 1.0, n_mu_edges + 2)[1:-1]
    n = np.arange(10)
    print()
    print(f"zone_edges(certify=False): 10 zones x {mu_e.size:,} mu values; median of {edge_repeats} repeats")
    t_edges = median_time(lambda: K.zone_edges(mu_e[None, :], n[:, None], certify=False), edge_repeats)
    print(f"  zone_edges: {t_edges[0] * 1e3:8.2f} ms  (min {t_edges[1] * 1e3:.2f}, max {t_edges[2] * 1e3:.2f})"
          f"  = {t_edges[0] / (2 * 10 * mu_e.size) * 1e9:.0f} ns per edge")
    mu_c = mu_e[::10]
    t0 = time.perf_counter()
    K.zone_edges(mu_c[None, :], n[:, None])
    t_cert = time.perf_counter() - t0
    print(f"  certified (the default), 10 zones x {mu_c.size:,} mu values, one run: {t_cert * 1e3:8.1f} ms"
          f"  = {t_cert / (2 * 10 * mu_c.size) * 1e6:.1f} us per edge, {t_cert / (2 * 10 * mu_c.size) * 1e9 / max(t_edges[0] / (2 * 10 * mu_e.size) * 1e9, 1e-9):.0f}x the curves")

    # ------------------------------------------------------------ amplitude edges
    n_T = 2_000 if tiny else 30_000
    T_a = np.geomspace(1e-4, 3.0, n_T)
    n_a = np.arange(3)
    print()
    print(f"amplitude_edges: 3 zones x {n_T:,} half-periods T in [1e-4, 3] (l = 1, g = 9.81); median of "
          f"{edge_repeats} repeats, against the earlier solve (zone 0's lower edge on the plain gap)")
    t_amp = median_time(lambda: K.amplitude_edges(T_a[None, :], n_a[:, None]), edge_repeats)
    t_plain = median_time(lambda: amplitude_edges_plain(T_a[None, :], n_a[:, None]), edge_repeats)
    print(f"  amplitude_edges:         {t_amp[0] * 1e3:8.2f} ms  (min {t_amp[1] * 1e3:.2f})"
          f"  = {t_amp[0] / (2 * 3 * n_T) * 1e9:.0f} ns per edge")
    print(f"  earlier plain solve:     {t_plain[0] * 1e3:8.2f} ms  (min {t_plain[1] * 1e3:.2f})")
    print(f"  ratio amplitude_edges / earlier: {t_amp[0] / t_plain[0]:.2f}x (median), {t_amp[1] / t_plain[1]:.2f}x (min)")

    # ------------------------------------------------------------ pointwise verdicts

    n_pts = 20_000 if tiny else 10_000_000
    pt_repeats = 3 if tiny else 7
    rng = np.random.default_rng(1)
    pe = rng.uniform(0.0, 4.0, n_pts) + 1e-12
    pm = rng.uniform(0.0, 1.0, n_pts)
    print()
    print(f"is_stable / zone_index on {n_pts:,} random points, eps in (0, 4], mu in (0, 1); "
          f"min and median of {pt_repeats} repeats, ns per point")
    per = {}
    for name, fn in (("baseline: numpy trace formula", lambda: trace_points(pe, pm)),
                     ("closed forms with arctangents (earlier path)", lambda: Z._verdict_careful(pe, pm)),
                     ("is_stable, one thread", lambda: one_thread(K.is_stable, pe, pm)),
                     ("is_stable", lambda: K.is_stable(pe, pm)),
                     ("zone_index", lambda: K.zone_index(pe, pm))):
        med, lo, _ = median_time(fn, pt_repeats)
        per[name] = (lo / n_pts * 1e9, med / n_pts * 1e9)
        print(f"  {name:46s} min {per[name][0]:7.1f}  median {per[name][1]:7.1f}")
    agree = int(np.count_nonzero(K.is_stable(pe, pm) == Z._verdict_careful(pe, pm)[0]))
    print(f"  is_stable agrees with the earlier path on {agree:,} of {n_pts:,} points")
    b_min, b_med = per["baseline: numpy trace formula"]
    s_min, s_med = per["is_stable"]
    c_min, c_med = per["closed forms with arctangents (earlier path)"]
    print(f"  ratio baseline / is_stable: {b_min / s_min:.2f}x (min), {b_med / s_med:.2f}x (median); "
          f"earlier path / is_stable: {c_min / s_min:.2f}x (min), {c_med / s_med:.2f}x (median)")
    o_min, o_med = per["is_stable, one thread"]
    print(f"  ratio baseline / is_stable with one thread: {b_min / o_min:.2f}x (min), {b_med / o_med:.2f}x (median); "
          f"is_stable uses {Z._threads(-(-n_pts // Z._CHUNK))} threads here")
    print(f"  against the 357 ns per point recorded before the tan form: {357.0 / s_min:.1f}x (min)")

    # ------------------------------------------------------------ analyze
    from kapitza import analysis

    def analyze_array(eps=None, mu=None, T=None, A=None, l=1.0, g=K.G_EARTH):
        """analyze with every part on the array kernels: the path before the scalar twins."""
        return analysis._analyze(eps, mu, T, A, l, g, None, 0.0, None, pointwise=False)

    print()
    a_repeats = 20 if tiny else 200
    print(f"analyze, one parameter set; min and median of {a_repeats} calls, the array path (every part on")
    print("numpy's kernels, as before the scalar twins) measured in the same run, alternating in 4 rounds")
    a_min = {}
    for label, kw in (("analyze(T=0.15, A=100) (with the rig's intervals)", dict(T=0.15, A=100.0)),
                      ("analyze(eps=0.5, mu=0.3)", dict(eps=0.5, mu=0.3))):
        same = str(K.analyze(**kw)) == str(analyze_array(**kw))
        new, old = [], []
        for _ in range(4):
            new.append(median_time(lambda: K.analyze(**kw), a_repeats // 4))
            old.append(median_time(lambda: analyze_array(**kw), a_repeats // 4))
        n_med, n_min = sorted(t[0] for t in new)[1], min(t[1] for t in new)
        o_med, o_min = sorted(t[0] for t in old)[1], min(t[1] for t in old)
        a_min[label] = n_min
        print(f"  {label}: printed reports {'identical' if same else 'DIFFER'}")
        print(f"    scalar path (analyze):   min {n_min * 1e3:7.3f} ms  median {n_med * 1e3:7.3f} ms")
        print(f"    array path (baseline):   min {o_min * 1e3:7.3f} ms  median {o_med * 1e3:7.3f} ms")
        print(f"    ratio array / scalar:    {o_min / n_min:.1f}x (min), {o_med / n_med:.1f}x (median)")

    # ------------------------------------------------------------ targets
    print()
    if tiny:
        print("(--tiny: sizes too small for the targets to mean anything; not checked)")
        return 0
    checks = [
        (f"stability_grid 4096^2 default call <= {GRID_TARGET_S * 1e3:.0f} ms", t_def[0] <= GRID_TARGET_S),
        (f"stability_grid 4096^2 out= <= {GRID_TARGET_S * 1e3:.0f} ms", t_out[0] <= GRID_TARGET_S),
        (f"speed-up over the numpy trace baseline >= {BASELINE_MIN_RATIO:.0f}x (default call)",
         r_def >= BASELINE_MIN_RATIO),
        (f"zone_edges(certify=False) 10 x 10,000 <= {EDGES_TARGET_S * 1e3:.0f} ms", t_edges[0] <= EDGES_TARGET_S),
        (f"is_stable >= {POINTS_MIN_RATIO:.0f}x faster than the numpy trace baseline (min)",
         b_min / s_min >= POINTS_MIN_RATIO),
    ] + [(f"{label.split(' (')[0]} <= {ANALYZE_TARGET_S * 1e3:.1f} ms (min)", t <= ANALYZE_TARGET_S)
         for label, t in a_min.items()]
    for text, ok in checks:
        print(f"  [{'met' if ok else 'NOT MET'}] {text}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
