"""Cost of a nonlinear stability sweep per parameter point, its accuracy, and its scaling on Dask.

Run by hand (``python benchmarks/bench_sweep.py``); ``--tiny`` is a seconds-long smoke run.
Measured in the same run:

* the sweep kernel (:func:`kapitza.sweeps.kernel.block_quantities`): largest safe tilt at rest to
  1 % (scan + bisection, every point of a block and every candidate in one array, escaped starts
  dropped at once) on an ``--n x --n`` grid over the chart ``0.05 <= eps <= 3``, ``0.02 <= mu <= 0.98``
  for ``--periods`` periods; cost per point and state-periods per point;
* baselines on a sample of points: the brute-force basin (:func:`kapitza.basin`, 121 x 121 starts,
  the picture ``kapitza basin`` draws) and a brute-force line of starts at rest fine enough for 1 %
  (:func:`kapitza.survival`), which is also the accuracy reference; and solve_ivp (DOP853) per
  state-period, times the state-periods the sweep needed;
* Dask: the same sweep on a LocalCluster with 1 and 2 workers (and serially), and the overhead per
  chunk of trivial chunks;
* the extrapolation of the 512 x 512 x 1,000-period map of the largest safe tilt to 2, 64 and
  1,024 cores from the measured per-point rate.
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header  # noqa: E402

import kapitza  # noqa: E402
import kapitza.motion._periods as B  # noqa: E402
import kapitza.sweeps.kernel as K  # noqa: E402
from kapitza.sweeps import SweepSpec, sweep  # noqa: E402

EPS, MU = (0.05, 3.0), (0.02, 0.98)
G = kapitza.parameters.G_EARTH
TOL, ACC, FLOOR = 0.5, 0.01, 1e-4


class Counter:
    """Counts the state-periods the radius searches advance (states x periods)."""

    def __init__(self):
        self.state_periods = 0
        self._orig = B._one_period

    def __enter__(self):
        def counted(th, *args, **kw):
            self.state_periods += th.size
            return self._orig(th, *args, **kw)

        B._one_period = counted
        return self

    def __exit__(self, *exc):
        B._one_period = self._orig


def kernel_tilt(eps, mu, periods, chunk):
    """Largest safe tilt on the grid, block by block (as the sweep's chunks run)."""
    out = np.empty((mu.size, eps.size))
    for i in range(0, mu.size, chunk):
        for j in range(0, eps.size, chunk):
            out[i:i + chunk, j:j + chunk] = K.block_quantities(
                eps[j:j + chunk], mu[i:i + chunk], plane="arnold", l=1.0, g=G, drive=None, periods=periods, tol=TOL,
                quantities=("tilt",), directions=1, basin_resolution=5, accuracy=ACC, floor=FLOOR)["max_safe_tilt"]
    return out


def brute_line(eps, mu, periods, step):
    """Largest tilt of a line of starts at rest (spacing ``step``) below which all survive."""
    T, A = (float(v) for v in kapitza.to_physical(eps, mu))
    th = np.arange(0.0, TOL + 0.5 * step, step)
    ok = kapitza.survival(th, 0.0, T, A, periods=periods, tol=TOL) >= periods
    first = int(np.argmin(ok)) if not ok.all() else th.size
    return th[first - 1] if first > 0 else 0.0


def ivp_cost_per_state_period(eps, mu, periods, starts=3):
    """Seconds per state-period of solve_ivp (DOP853, rtol 1e-10), restarted at each switch."""
    T, A = (float(v) for v in kapitza.to_physical(eps, mu))
    t0 = time.perf_counter()
    for th0 in np.linspace(0.01, 0.05, starts):
        y = np.array([th0, 0.0])
        for k in range(2 * periods):
            s = G + A if k % 2 == 0 else G - A
            y = solve_ivp(lambda _, z, s=s: [z[1], s * np.sin(z[0])], (0.0, T), y, method="DOP853", rtol=1e-10,
                          atol=1e-12).y[:, -1]
    return (time.perf_counter() - t0) / (starts * periods)


def dask_sweep(spec, workers, root, tag):
    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=50)
    client = Client(cluster)
    start = time.perf_counter() - t0
    try:
        t0 = time.perf_counter()
        sweep(spec, os.path.join(root, f"{tag}.zarr"), client=client, progress=False)
        run = time.perf_counter() - t0
        trivial = SweepSpec(plane="arnold", x=spec.x, y=spec.y, periods=1, quantities=("linear",), chunk=spec.chunk)
        t0 = time.perf_counter()
        sweep(trivial, os.path.join(root, f"{tag}-trivial.zarr"), client=client, progress=False)
        trivial_t = time.perf_counter() - t0
    finally:
        client.close()
        cluster.close()
    return start, run, trivial_t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=64, help="grid points per side of the kernel run (default 64)")
    ap.add_argument("--periods", type=int, default=1000, help="periods (default 1000)")
    ap.add_argument("--chunk", type=int, default=64, help="points per side of a block (default 64)")
    ap.add_argument("--sample", type=int, default=4, help="points of the brute-force comparison (default 4)")
    ap.add_argument("--dask-n", type=int, default=32, help="grid side of the Dask scaling run (default 32)")
    ap.add_argument("--dask-periods", type=int, default=100, help="periods of the Dask scaling run (default 100)")
    ap.add_argument("--tiny", action="store_true", help="seconds-long smoke run")
    a = ap.parse_args(argv)
    if a.tiny:
        a.n, a.periods, a.chunk, a.sample, a.dask_n, a.dask_periods = 4, 20, 4, 2, 4, 10
    header("bench_sweep")

    # 1. the sweep kernel over the chart
    eps, mu = np.linspace(*EPS, a.n), np.linspace(*MU, a.n)
    with Counter() as c:
        t0 = time.perf_counter()
        tilt = kernel_tilt(eps, mu, a.periods, a.chunk)
        t_kernel = time.perf_counter() - t0
    per_point = t_kernel / tilt.size
    print(f"\nsweep kernel: max safe tilt to {100 * ACC:g} %, {a.n} x {a.n} points over eps {EPS}, mu {MU}, "
          f"{a.periods} periods, blocks of {a.chunk} x {a.chunk}")
    print(f"  {t_kernel:.2f} s, {1e3 * per_point:.2f} ms per point (1 process); "
          f"{c.state_periods / tilt.size:.0f} state-periods per point, "
          f"{1e6 * t_kernel / max(c.state_periods, 1):.2f} us per state-period")
    print(f"  linearly stable points: {int(np.count_nonzero(kapitza.is_stable(*np.meshgrid(eps, mu))))} of {tilt.size}; "
          f"points with a safe tilt >= {FLOOR:g} rad: {int(np.count_nonzero(tilt > 0))}")

    # 2. baselines and accuracy on a sample of points with a safe tilt
    rng = np.random.default_rng(1)
    cand = np.argwhere(tilt > 0.01)
    sample = cand[rng.choice(len(cand), size=min(a.sample, len(cand)), replace=False)] if len(cand) else []
    print(f"\nbaselines on {len(sample)} sampled points with a safe tilt (same periods):")
    worst = 0.0
    t_basin = t_line = 0.0
    for i, j in sample:
        e, m = eps[j], mu[i]
        T, A = (float(v) for v in kapitza.to_physical(e, m))
        step = 0.002 * tilt[i, j]  # 0.2 % of the value: the reference for the 1 % claim
        t0 = time.perf_counter()
        ref = brute_line(e, m, a.periods, step)
        t_line += time.perf_counter() - t0
        t0 = time.perf_counter()
        kapitza.basin(T, A, periods=a.periods, tol=TOL, n_theta=121, n_dtheta=121)
        t_basin += time.perf_counter() - t0
        rel = (ref - tilt[i, j]) / ref if ref > 0 else np.inf
        worst = max(worst, abs(rel))
        print(f"  eps {e:.3f} mu {m:.3f}: sweep {tilt[i, j]:.5f} rad, brute-force line {ref:.5f} rad "
              f"(step {step:.1e}), (line - sweep)/line = {100 * rel:+.2f} %")
    if len(sample):
        n = len(sample)
        print(f"  worst |relative difference| = {100 * worst:.2f} % (stated accuracy {100 * ACC:g} %, "
              f"the reference line's step 0.2 %)")
        t0 = time.perf_counter()
        for i, j in sample:  # the sweep at these points alone: one-point blocks, the numpy overhead unshared
            kernel_tilt(eps[j:j + 1], mu[i:i + 1], a.periods, 1)
        t_alone = (time.perf_counter() - t0) / n
        print(f"  the sweep at these points alone (one-point blocks): {t_alone:.2f} s per point")
        print(f"  brute-force basin 121 x 121: {t_basin / n:.2f} s per point; "
              f"ratio (basin per point / sweep per point) = {t_basin / n / per_point:.1f} against the chart's "
              f"average point, {t_basin / n / t_alone:.1f} against these points alone")
        print(f"  brute-force line at 0.2 %: {t_line / n:.2f} s per point; "
              f"ratio (line per point / sweep per point) = {t_line / n / per_point:.1f} against the chart's "
              f"average point, {t_line / n / t_alone:.1f} against these points alone")
        i, j = sample[0]
        ivp = ivp_cost_per_state_period(eps[j], mu[i], max(2, min(a.periods, 20)))
        ivp_point = ivp * c.state_periods / tilt.size
        print(f"  solve_ivp DOP853: {1e6 * ivp:.0f} us per state-period; the sweep's "
              f"{c.state_periods / tilt.size:.0f} state-periods per point would take {ivp_point:.2f} s; "
              f"ratio (solve_ivp / sweep) = {ivp_point / per_point:.0f}")

    # 3. Dask: 1 and 2 workers, overhead per chunk
    spec = SweepSpec.window(EPS, MU, a.dask_n, periods=a.dask_periods, quantities=("tilt",), chunk=max(1, a.dask_n // 4))
    nchunks = len(spec.all_chunks())
    root = tempfile.mkdtemp(prefix="bench-sweep-")
    try:
        warm = SweepSpec(plane="arnold", x=(1.0,), y=(0.5,), periods=1, quantities=("linear",))
        sweep(warm, os.path.join(root, "warm.zarr"), serial=True, progress=False)  # imports, not timed
        t0 = time.perf_counter()
        sweep(spec, os.path.join(root, "serial.zarr"), serial=True, progress=False)
        t_serial = time.perf_counter() - t0
        triv = SweepSpec(plane="arnold", x=spec.x, y=spec.y, periods=1, quantities=("linear",), chunk=spec.chunk)
        t0 = time.perf_counter()
        sweep(triv, os.path.join(root, "serial-trivial.zarr"), serial=True, progress=False)
        t_triv_serial = time.perf_counter() - t0
        res = {w: dask_sweep(spec, w, root, f"w{w}") for w in (1, 2)}
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print(f"\nDask: {a.dask_n} x {a.dask_n} points, {a.dask_periods} periods, {nchunks} chunks of "
          f"{spec.chunk} x {spec.chunk} (cluster start-up not counted)")
    print(f"  serial (no Dask):     {t_serial:.2f} s")
    for w, (start, run, trivial) in res.items():
        print(f"  LocalCluster {w} worker{'s' if w > 1 else ' '}: {run:.2f} s (start-up {start:.1f} s)")
    speedup = res[1][1] / res[2][1]
    print(f"  speed-up 1 -> 2 workers: {speedup:.2f}x; ratio (serial / 1 worker) = {t_serial / res[1][1]:.2f}")
    over = (res[1][2] - t_triv_serial) / nchunks
    print(f"  overhead per chunk (trivial chunks, 1 worker vs serial): {1e3 * over:.1f} ms")

    # 4. extrapolation of the 512 x 512 x 1,000-period map
    pts, periods = 512 * 512, 1000
    core_s = per_point * pts * periods / a.periods  # cost grows about linearly with the periods
    eff = min(1.0, speedup / 2.0)
    print(f"\nextrapolation: 512 x 512 points x 1,000 periods, max safe tilt to {100 * ACC:g} %, from "
          f"{1e3 * per_point:.2f} ms per point at {a.periods} periods (x {periods / a.periods:g} for 1,000 periods):")
    print(f"  {core_s / 3600:.1f} core-hours; wall time with ideal scaling, and with the 1 -> 2 worker "
          f"efficiency measured above ({100 * eff:.0f} %) assumed on every size; + Dask overhead per 32 x 32 chunk")
    for cores in (2, 64, 1024):
        extra = over * (pts / 32 ** 2) / cores
        ideal, measured = core_s / cores + extra, core_s / (cores * eff) + extra
        print(f"  {cores:5d} cores: {ideal / 60:8.1f} min ideal, {measured / 60:8.1f} min at {100 * eff:.0f} %"
              + ("   (goal: < 30 min)" if cores == 2 else ""))

if __name__ == "__main__":
    main()
