"""What every benchmark here shares: medians over repeats and a description of the machine."""
from __future__ import annotations

import os
import platform
import statistics
import time

import numpy as np
import scipy


def median_time(fn, repeats, warmup=1):
    """``(median, min, max)`` wall time of ``fn()`` over ``repeats`` calls, after ``warmup`` calls."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), max(times)


def median_cpu_time(fn, repeats, warmup=1):
    """Median CPU time of this process over ``repeats`` calls of ``fn()`` (after ``warmup``): on a
    busy machine the fairer figure, since it leaves out the time other processes held the cores."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times)


def machine():
    """Lines describing the machine and the numerical stack."""
    lines = [f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}",
             f"{platform.machine()}, {os.cpu_count()} logical CPUs, {platform.system()} {platform.release()}"]
    try:
        with open("/proc/cpuinfo") as fh:
            model = next((ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name")), None)
        if model:
            lines.insert(1, model)
    except OSError:
        pass
    return lines


def load_line(when=""):
    """The load average as one line: ``"load average at the end: 0.52 0.61 0.70"`` for
    ``when="at the end"``, ``"load average 0.52 0.61 0.70"`` without ``when``; ``"load average
    unknown"`` where the platform has none."""
    try:
        values = " ".join(f"{x:.2f}" for x in os.getloadavg())
    except (AttributeError, OSError):   # (no load average on this platform)
        return "load average unknown"
    return f"load average {when}: {values}" if when else f"load average {values}"


def header(name):
    """Print a benchmark's first lines: its name and the time, the machine, the load average."""
    import datetime

    print(f"{name}  {datetime.datetime.now().isoformat(timespec='seconds')}")
    for line in machine():
        print("  " + line)
    print("  " + load_line())
