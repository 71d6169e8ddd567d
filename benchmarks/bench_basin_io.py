"""Speed of ``kapitza basin``: writing its CSV, its worker processes, the whole command.

Run by hand (``python benchmarks/bench_basin_io.py``); ``--tiny`` is a seconds-long smoke run.
Measured in one run, min and median over repeats (the machine may be shared):

* the CSV of two 512 x 512 basins (linear and nonlinear, 524,288 rows): the baseline is the
  row-at-a-time writer the command used before (a Python tuple and a ``repr`` call per cell,
  through :mod:`csv`), against ``_io.write_csv(columns=...)``; the two files must be identical;
* the basins themselves with 1 and 2 worker processes;
* the whole command ``kapitza basin --resolution 512 --quiet`` (a fresh process each time,
  imports and figures included) with ``--workers 1`` and ``--workers 2``.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import header, load_line, median_time  # noqa: E402

import kapitza as K  # noqa: E402
from kapitza import _io  # noqa: E402
from kapitza.motion import basin  # noqa: E402

T, A = 0.15, 100.0
HEADER = ["model", "theta0", "dtheta0", "survived", "periods_survived"]


def rows_baseline(basins):
    """The rows as the command produced them before: one tuple per grid point."""
    for b in basins:
        for i, om in enumerate(b.dtheta0):
            for j, th in enumerate(b.theta0):
                yield b.model, th, om, int(b.survived[i, j]), int(b.periods_survived[i, j])


def columns(basins):
    return [np.concatenate([np.full(b.periods_survived.size, b.model) for b in basins])] + \
        [np.concatenate(c) for c in zip(*(b.columns() for b in basins))]


def command(res, workers, out):
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "kapitza", "basin", "--T", str(T), "--A", str(A), "--resolution", str(res),
                    "--workers", str(workers), "--quiet", "--out", str(out)], check=True, capture_output=True)
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="a seconds-long smoke run")
    args = ap.parse_args(argv)
    res = 48 if args.tiny else 512
    repeats = 2 if args.tiny else 3
    header("bench_basin_io")
    print(f"  kapitza {K.__version__} basin benchmark{' (--tiny)' if args.tiny else ''}")
    print()

    print(f"basins: T = {T} s, A = {A} m/s^2, {res} x {res} grid, 50 periods; min and median of {repeats}")
    basins = []
    for model in ("linear", "nonlinear"):
        for workers in (1, 2):
            med, lo, _ = median_time(lambda: basin(T, A, n_theta=res, n_dtheta=res, model=model, workers=workers),
                                     repeats, warmup=0)
            print(f"  {model:9s} workers {workers}: min {lo:7.3f} s  median {med:7.3f} s")
        basins.append(basin(T, A, n_theta=res, n_dtheta=res, model=model))
    n_rows = sum(b.periods_survived.size for b in basins)

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        print()
        print(f"CSV of both basins ({n_rows:,} rows); min and median of {repeats}")
        t_base = median_time(lambda: _io.write_csv(tmp / "base.csv", HEADER, rows_baseline(basins)), repeats, warmup=0)
        t_cols = median_time(lambda: _io.write_csv(tmp / "cols.csv", HEADER, columns=columns(basins)), repeats)
        same = (tmp / "base.csv").read_bytes() == (tmp / "cols.csv").read_bytes()
        size = (tmp / "cols.csv").stat().st_size
        print(f"  baseline: row at a time    min {t_base[1]:7.3f} s  median {t_base[0]:7.3f} s")
        print(f"  columns=                   min {t_cols[1]:7.3f} s  median {t_cols[0]:7.3f} s"
              f"  ({size / 2**20:.1f} MiB, {size / 2**20 / t_cols[0]:.0f} MiB/s)")
        print(f"  files identical: {same}")
        print(f"  ratio baseline / columns: {t_base[1] / t_cols[1]:.1f}x (min), {t_base[0] / t_cols[0]:.1f}x (median)")

        print()
        print(f"the whole command: kapitza basin --resolution {res} --quiet (fresh process); min and median of {repeats}")
        whole = {}
        for workers in (1, 2):
            times = [command(res, workers, tmp / f"w{workers}") for _ in range(repeats)]
            whole[workers] = (min(times), statistics.median(times))
            print(f"  --workers {workers}: min {whole[workers][0]:7.3f} s  median {whole[workers][1]:7.3f} s")
        print(f"  ratio workers 1 / workers 2: {whole[1][0] / whole[2][0]:.2f}x (min)")
    print(load_line("at the end"))
    if args.tiny:
        print("(--tiny: sizes too small for the target to mean anything; not checked)")
    else:
        best = min(whole[1][0], whole[2][0])
        print(f"  [{'met' if best < 5.0 else 'NOT MET'}] whole command < 5 s (best {best:.2f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
