"""The safe tilt of one point: many starts followed together (kapitza.safe_tilt) against the
sweep's one-candidate-at-a-time bisection (kapitza.sweeps.kernel.ray_radii) on the same steps.

The page asks for it beside every verdict, so it must answer in about a second. On the exact path
(square wave) a period of one state and of 24 states cost about the same numpy calls; on the
integrated path (sine drive, or damping) each DOP853 call has a large fixed cost, so following
24 starts at once in a few rounds beats some 15 sequential candidates.

    python benchmarks/bench_safe_tilt.py [--tiny]
"""
from __future__ import annotations

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _timing import header, median_time  # noqa: E402

from kapitza.drives import parse_drive  # noqa: E402
from kapitza.parameters import to_physical  # noqa: E402
from kapitza.safety import safe_tilt  # noqa: E402
from kapitza.sweeps.kernel import period_step, ray_radii  # noqa: E402


def baseline(eps, mu, drive, zeta, periods, tol=np.pi / 2):
    T, A = (np.atleast_1d(v) for v in to_physical(eps, mu, 1.0, 9.81))
    c = 2.0 * zeta * np.sqrt(9.81)
    step = period_step(T, A, 1.0, 9.81, c, parse_drive(drive), tol)
    return float(ray_radii(T, step, np.zeros(1), periods, tol, 0.01, 1e-9)[0, 0])


def main():
    tiny = "--tiny" in sys.argv
    periods, repeats = (10, 1) if tiny else (50, 3)
    header("bench_safe_tilt")
    print("  (the machine is shared: timings are under that load)\n")
    print(f"{'case':<34} {'safe_tilt':>10} {'bisection':>10} {'ratio':>7}   theta* (ours / bisection)")
    for name, eps, mu, drive, zeta in [("zone 0, square wave", 0.5, 0.3, "square", 0.0),
                                       ("zone 1, square wave", 1.78, 0.3, "square", 0.0),
                                       ("zone 0, sine", 0.5, 0.3, "sine", 0.0),
                                       ("zone 0, square, damping 0.1", 0.5, 0.3, "square", 0.1)]:
        ours = float(safe_tilt(eps, mu, drive=drive, zeta=zeta, periods=periods))
        base = baseline(eps, mu, drive, zeta, periods)
        t1 = median_time(lambda: safe_tilt(eps, mu, drive=drive, zeta=zeta, periods=periods), repeats, warmup=0)[0]
        t0 = median_time(lambda: baseline(eps, mu, drive, zeta, periods), repeats, warmup=0)[0]
        print(f"{name:<34} {t1:>9.3f}s {t0:>9.3f}s {t0 / t1:>6.2f}x   {ours:.4g} / {base:.4g}")


if __name__ == "__main__":
    main()
