"""The engineer's damped sine rig as a user runs it: the whole command, in fresh processes.

Run by hand (``python benchmarks/bench_sine_rig.py``); ``--tiny`` is a smoke run for CI.

* the command ``kapitza stability --drive sine --frequency 50 --amplitude 0.003 --rod 0.25
  --damping 0.1`` as a whole process (start-up, imports, the report, printing), run in turns with
  the baseline, the command's start-up alone: ``kapitza stability --eps 0.5 --mu 0.3 --no-safe-tilt``
  (the same imports and parser; the square wave's report costs a millisecond). Medians of wall time
  and of the child's CPU time (user + system), and their ratio to the baseline's;
* the report alone, ``Rig(Pendulum.uniform_rod(0.25, damping=0.1), SineWave()).analyze(frequency=50,
  amplitude=0.003)``, timed in a fresh process after its imports: the first call, which is what the
  command pays (a second call in the same process reuses the extended-precision verdicts the first
  one decided, and reads lower).

Bytecode: Python caches compiled modules unless ``PYTHONDONTWRITEBYTECODE`` is set; an installed
package has them. Without the cache every run compiles kapitza's sources (a few hundred ms): the
script says which it measured.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
import resource
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header  # noqa: E402

RIG = ["stability", "--drive", "sine", "--frequency", "50", "--amplitude", "0.003", "--rod", "0.25",
       "--damping", "0.1"]
BASE = ["stability", "--eps", "0.5", "--mu", "0.3", "--no-safe-tilt"]
REPORT = """
import json, time
t0, c0 = time.perf_counter(), time.process_time()
from kapitza import Pendulum, Rig, SineWave
t1, c1 = time.perf_counter(), time.process_time()
Rig(Pendulum.uniform_rod(0.25, damping=0.1), SineWave()).analyze(frequency=50, amplitude=0.003)
t2, c2 = time.perf_counter(), time.process_time()
print(json.dumps(dict(import_wall=t1 - t0, wall=t2 - t1, cpu=c2 - c1)))
"""


def run(args):
    """``(wall, cpu)`` seconds of one child process (its CPU from the kernel's accounting)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable] + args, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed: {proc.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc.stdout


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tiny", action="store_true", help="a quick smoke run")
    p.add_argument("--runs", type=int, default=9, help="runs of each command, in turns (default 9)")
    args = p.parse_args(argv)
    runs = 1 if args.tiny else args.runs
    header('bench_sine_rig')
    origin = importlib.util.find_spec("kapitza").origin
    cached = os.path.exists(importlib.util.cache_from_source(origin)) or not os.environ.get("PYTHONDONTWRITEBYTECODE")
    print(f"  kapitza from {os.path.dirname(origin)}; bytecode cache: "
          f"{'present' if cached else 'absent and not written (PYTHONDONTWRITEBYTECODE): every run compiles'}")

    run(["-m", "kapitza"] + BASE)  # warm-up: the disk cache, and the bytecode if it is written
    rig, base, report = [], [], []
    for _ in range(runs):
        base.append(run(["-m", "kapitza"] + BASE)[:2])
        rig.append(run(["-m", "kapitza"] + RIG)[:2])
        report.append(json.loads(run(["-c", REPORT])[2]))

    def med(rows, i):
        return statistics.median(r[i] for r in rows)

    print(f"\nwhole command, {runs} run(s) each in turns: median wall / CPU")
    bw, bc = med(base, 0), med(base, 1)
    rw, rc = med(rig, 0), med(rig, 1)
    print(f"  start-up alone (square, --no-safe-tilt)   {1e3 * bw:8.0f} ms   CPU {1e3 * bc:8.0f} ms")
    print(f"  damped sine rig                           {1e3 * rw:8.0f} ms   CPU {1e3 * rc:8.0f} ms"
          f"   ratio {rw / bw:5.2f}x wall, {rc / bc:5.2f}x CPU the start-up")
    print(f"\nthe report alone, first call in a fresh process: median of {runs}")
    wall, cpu, imp = (statistics.median(r[k] for r in report) for k in ("wall", "cpu", "import_wall"))
    print(f"  Rig(...).analyze(frequency=50, amplitude=0.003)  {1e3 * wall:8.0f} ms   CPU {1e3 * cpu:8.0f} ms"
          f"   (import kapitza {1e3 * imp:.0f} ms)")


if __name__ == "__main__":
    main()
