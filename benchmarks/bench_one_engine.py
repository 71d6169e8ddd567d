"""One engine for every drive: the square wave's own paths beside the same physics as other drives.

Run by hand (``python benchmarks/bench_one_engine.py``); ``--tiny`` is a smoke run for CI.
Every figure is a median over repeats, and the square wave, measured in the same run, is the
baseline each other drive is divided by:

* ``analyze(T=0.15, A=100)`` with ``SquareWave()`` (the baseline), ``RectangularWave(0.5)``,
  ``StepDrive([1, -1], [.5, .5])`` and the square wave with ``damping=1e-9`` -- four drives with
  the same physics (their reports agree to an ulp or two) -- and the damped sine rig
  ``Rig(Pendulum.uniform_rod(0.25, damping=0.1), SineWave()).analyze(frequency=50, amplitude=0.003)``,
  as a command runs it and with the compiled engine loaded (its sine kernels);
* ``is_stable(eps, mu)`` of one point (Python floats), square wave and the others;
* ``stability_grid`` of the square wave, 4096 x 4096 (``--tiny``: 256 x 256).
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, median_cpu_time, median_time  # noqa: E402

import kapitza  # noqa: E402
from kapitza import Pendulum, Rig, RectangularWave, SineWave, SquareWave, StepDrive  # noqa: E402

POINT = dict(T=0.15, A=100.0)


def drives():
    """(label, keyword arguments of analyze) of the same physics as the square wave."""
    return [("square wave", dict(drive=SquareWave())),
            ("RectangularWave(0.5)", dict(drive=RectangularWave(0.5))),
            ("StepDrive([1, -1], [.5, .5])", dict(drive=StepDrive([1, -1], [.5, .5]))),
            ("square, damping=1e-9", dict(drive=SquareWave(), damping=1e-9))]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tiny", action="store_true", help="a quick smoke run")
    args = p.parse_args(argv)
    reps = 3 if args.tiny else 15
    header("bench_one_engine")

    print("\nanalyze(T=0.15, A=100): median of", reps, "calls")
    base = cpu_base = None
    reports = {}
    for label, kw in drives():
        t, _, _ = median_time(lambda kw=kw: kapitza.analyze(**POINT, **kw), reps)
        cpu = median_cpu_time(lambda kw=kw: kapitza.analyze(**POINT, **kw), reps)
        reports[label] = kapitza.analyze(**POINT, **kw)
        base = t if base is None else base
        cpu_base = cpu if cpu_base is None else cpu_base
        print(f"  {label:32s} {1e3 * t:10.3f} ms   ratio {t / base:8.1f}x the square wave   "
              f"(CPU {1e3 * cpu:9.3f} ms, ratio {cpu / cpu_base:8.1f}x)")
    # the same, interleaved: each round times the square wave (five calls, their mean) and then one call
    # of every other drive, in CPU time; the ratio of each round, taken under the load of that moment,
    # and their median (a two-core machine's load moves the figures above between drives)
    rounds = 5 if args.tiny else 41
    per_round = {label: [] for label, _ in drives()[1:]}
    took = {label: [] for label, _ in drives()}
    for _ in range(rounds):
        t0 = time.process_time()
        for _ in range(5):
            kapitza.analyze(**POINT, drive=SquareWave())
        square = (time.process_time() - t0) / 5.0
        took["square wave"].append(square)
        for label, kw in drives()[1:]:
            t0 = time.process_time()
            kapitza.analyze(**POINT, **kw)
            took[label].append(time.process_time() - t0)
            per_round[label].append(took[label][-1] / square)
    print(f"  interleaved, CPU ratio per round (median, quartiles of {rounds} rounds):")
    print(f"  {'square wave':32s} {1e3 * np.median(took['square wave']):10.3f} ms")
    for label, r in per_round.items():
        q1, q2, q3 = np.percentile(r, [25, 50, 75])
        print(f"  {label:32s} {1e3 * np.median(took[label]):10.3f} ms   ratio {q2:8.1f}x the square wave   "
              f"({q1:.1f}x-{q3:.1f}x)")
    ref = reports["square wave"]
    worst = max(abs(r.eps_hi / ref.eps_hi - 1.0) for r in reports.values())
    print(f"  largest relative difference of eps_hi from the square wave's: {worst:.2e}")
    if not args.tiny:  # (seconds today: the sine engine's own benchmark follows it)
        rig = Rig(Pendulum.uniform_rod(0.25, damping=0.1), SineWave())
        t, _, _ = median_time(lambda: rig.analyze(frequency=50.0, amplitude=0.003), 3)
        cpu = median_cpu_time(lambda: rig.analyze(frequency=50.0, amplitude=0.003), 3)
        print(f"  {'damped sine rig (50 Hz, 3 mm)':32s} {1e3 * t:10.3f} ms   ratio {t / base:8.1f}x the square wave   "
              f"(CPU {1e3 * cpu:9.3f} ms, ratio {cpu / cpu_base:8.1f}x)")
        from kapitza.engines import load_compiled

        if load_compiled():   # (the sine's compiled kernels: a server, a notebook, a sweep)
            t, _, _ = median_time(lambda: rig.analyze(frequency=50.0, amplitude=0.003), 5)
            cpu = median_cpu_time(lambda: rig.analyze(frequency=50.0, amplitude=0.003), 5)
            print(f"  {'  the same, compiled loaded':32s} {1e3 * t:10.3f} ms   ratio {t / base:8.1f}x the square wave   "
                  f"(CPU {1e3 * cpu:9.3f} ms, ratio {cpu / cpu_base:8.1f}x)")

    print("\nis_stable of one point (Python floats): median of", 20 * reps, "calls")
    eps, mu = float(reports["square wave"].eps), float(reports["square wave"].mu)
    base = None
    for label, kw in drives():
        zeta = {"zeta": 0.5e-9 * np.sqrt(1.0 / 9.80665)} if "damping" in kw else {}
        d = kw["drive"]
        t, _, _ = median_time(lambda d=d, zeta=zeta: kapitza.is_stable(eps, mu, drive=d, **zeta), 20 * reps)
        base = t if base is None else base
        print(f"  {label:32s} {1e6 * t:10.1f} us   ratio {t / base:8.1f}x the square wave")

    n = 256 if args.tiny else 4096
    e = np.linspace(0.0, 4.0, n + 1)[1:]
    m = np.linspace(0.0, 1.0, n + 2)[1:-1]
    out = np.zeros((n, n), bool)
    t, lo, hi = median_time(lambda: kapitza.stability_grid(e, m, out=out), 3 if args.tiny else 7)
    print(f"\nstability_grid {n} x {n}, square wave, out= reused: median {1e3 * t:.1f} ms "
          f"(min {1e3 * lo:.1f}, max {1e3 * hi:.1f}); stable share {out.mean():.4f}")


if __name__ == "__main__":
    main()
