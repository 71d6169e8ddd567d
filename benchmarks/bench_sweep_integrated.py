"""Cost of the sweep's integrated path (DOP853: the sine drive, damping) against its exact path.

On one block of points over the chart, the largest safe tilt to 1 % is searched by the same in-flight
bisection (:func:`kapitza.sweeps.kernel.ray_radii`) driven by

* the exact period step (undamped square wave: step flows, the window on the continuous motion) -- the
  baseline, measured in the same run;
* the integrated period step on the same undamped square wave (the twin: the values must agree to 1 %);
* the integrated step with damping (square wave, zeta = 0.05) and on the sine drive (undamped);

and each prints seconds per point, state-periods per point, microseconds per state-period and the ratio to
the exact path. Run: ``python benchmarks/bench_sweep_integrated.py [--n 8 --periods 100]``; ``--tiny``
for a seconds-long smoke run.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header  # noqa: E402

import kapitza  # noqa: E402
from kapitza.drives import parse_drive  # noqa: E402
from kapitza.motion._periods import _IntegratedPeriod  # noqa: E402
from kapitza.sweeps.kernel import period_step, ray_radii  # noqa: E402

EPS, MU = (0.1, 1.2), (0.05, 0.8)
G = kapitza.parameters.G_EARTH
TOL, ACC, FLOOR = 0.5, 0.01, 1e-4


class Counting:
    """A period step that counts the state-periods it advances."""

    def __init__(self, step):
        self.step, self.state_periods = step, 0

    def __call__(self, th, om, idx):
        self.state_periods += th.size
        return self.step(th, om, idx)


def run(name, step, T, periods, baseline=None):
    c = Counting(step)
    t0 = time.perf_counter()
    tilt = ray_radii(T, c, np.array([0.0]), periods, TOL, ACC, FLOOR)[:, 0]
    dt = time.perf_counter() - t0
    line = (f"  {name:44s} {dt:7.2f} s, {1e3 * dt / T.size:8.1f} ms per point, "
            f"{c.state_periods / T.size:7.0f} state-periods per point, {1e6 * dt / max(c.state_periods, 1):6.1f} us "
            f"per state-period")
    if baseline is not None:
        line += f"; ratio (this / exact) = {dt / baseline:.0f}"
    print(line)
    return dt, tilt


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=8, help="grid points per side, one block (default 8)")
    ap.add_argument("--periods", type=int, default=100, help="periods (default 100)")
    ap.add_argument("--tiny", action="store_true", help="seconds-long smoke run")
    a = ap.parse_args(argv)
    if a.tiny:
        a.n, a.periods = 2, 5
    header("bench_sweep_integrated")
    eps, mu = np.meshgrid(np.linspace(*EPS, a.n), np.linspace(*MU, a.n))
    T, A = (np.asarray(v, float).ravel() for v in kapitza.to_physical(eps, mu))
    sq, sine = parse_drive("square"), parse_drive("sine")
    c = 2.0 * 0.05 * np.sqrt(G)
    print(f"\nmax safe tilt to {100 * ACC:g} %, {a.n} x {a.n} points over eps {EPS}, mu {MU}, {a.periods} periods, "
          f"one block, one process")
    t_exact, exact = run("exact path (square, undamped) -- baseline", period_step(T, A, 1.0, G, 0.0, sq, TOL), T,
                         a.periods)
    _, twin = run("integrated path (square, undamped)", _IntegratedPeriod(T, A, 1.0, G, 0.0, sq, TOL), T, a.periods,
                  t_exact)
    run("integrated path (square, zeta = 0.05)", period_step(T, A, 1.0, G, c, sq, TOL), T, a.periods, t_exact)
    run("integrated path (sine, undamped)", period_step(T, A, 1.0, G, 0.0, sine, TOL), T, a.periods, t_exact)
    both = exact > 0
    rel = np.abs(twin[both] - exact[both]) / exact[both]
    print(f"\nundamped square wave, integrated vs exact: {int(np.count_nonzero(both))} points with a safe tilt, "
          f"largest relative difference {100 * (rel.max() if rel.size else 0.0):.3f} % (stated accuracy "
          f"{100 * ACC:g} %); points where only one finds a tilt: {int(np.count_nonzero((exact > 0) != (twin > 0)))}")


if __name__ == "__main__":
    main()
