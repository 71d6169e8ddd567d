"""Load test of the explorer on loopback: latency of the chart and point endpoints under load.

Run by hand (``python benchmarks/bench_web.py``); ``--tiny`` is a seconds-long smoke run.
Starts ``kapitza serve`` on a free loopback port (one process, as a user runs it) and measures,
in the same run:

* the time from starting ``kapitza serve`` to its first answered request (median of 3 starts);
* p50 / p99 latency at 1, 10 and 50 concurrent clients (threads, each with its own keep-alive
  connection) for: the full chart view the page asks for first (every zone in ``0 <= eps <= 4``,
  ``0 <= mu <= 1`` at 1000 samples; the server keeps recent views, up to 64 MiB of them, so
  repeats of it are answered from memory), the same view moved by 1e-12 at every request (computed every time), a
  deep-zoom view of zone 2 (1e-5 wide), the stability report of one point (what
  ``kapitza stability --json`` prints), and the motion the page asks for a click (square wave; the
  server keeps it with the views) and the same moved by 1e-12 at every request;
* for the motion, its nonlinear part in this process with the steps on one state (the route's path)
  against the same steps each through the array function on one-element arrays, and whether both
  give the same doubles;
* the baseline: the same library call in this process, without HTTP (the chart's curves and
  their JSON; ``analyze``), median over repeats; the ratio of the 1-client p50 to it is the
  cost of the web layer;
* a class at once: ``--mixed-clients`` (50) clients for ``--seconds``, each sending charts,
  points and motions of four drives in turn (the mix of ``tests/test_web_load.py``): p50 / p99
  per kind, server errors, and the server's resident memory after a warm-up and after the load.

Every level is bounded in requests (``--requests``) and time (``--seconds``).
"""
from __future__ import annotations

import argparse
import itertools
import os
import statistics
import sys
import threading
import time

import httpx
import numpy as np
import orjson

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from _timing import header, load_line, median_time  # noqa: E402
from web_server import running_server  # noqa: E402

import kapitza  # noqa: E402
from kapitza.curves import window_curves  # noqa: E402

LO2, HI2 = (float(v) for v in kapitza.zone_edges(0.6, 2))
W2 = HI2 - LO2
_FRESH = itertools.count(1)
FULL = dict(plane="arnold", eps_min=0, eps_max=4, mu_min=0, mu_max=1, samples=1000)
# what the page asks for a click at T = 0.15 s: 27 periods at 60 samples, nonlinear and linear
MOTION = dict(T=0.15, A=100, l=1, g=9.81, drive="square", zeta=0, theta0=0.1, periods=27, points_per_period=60)
QUERIES = {
    "chart, full view": ("/api/chart", FULL),
    "chart, full view moved by 1e-12 each request (never cached)": (
        "/api/chart", lambda: {**FULL, "eps_max": 4.0 + 1e-12 * next(_FRESH)}),
    "chart, zone 2 zoomed (1e-5 wide)": ("/api/chart", dict(eps_min=LO2 - 5 * W2, eps_max=HI2 + 5 * W2,
                                                           mu_min=0.6 - 2e-5, mu_max=0.6 + 2e-5, samples=1000)),
    "point (stability report)": ("/api/point", dict(T=0.15, A=100, l=1, g=9.81)),
    "motion (square wave, the page's request)": ("/api/motion", MOTION),
    "motion, start moved by 1e-12 each request (never cached)": (
        "/api/motion", lambda: {**MOTION, "theta0": 0.1 + 1e-12 * next(_FRESH)}),
}


def baseline(name):
    """The library call behind the route, in this process (no HTTP)."""
    path, q = QUERIES[name]
    if path == "/api/point":
        return lambda: kapitza.analyze(T=0.15, A=100.0).as_dict()
    if path == "/api/motion":
        from kapitza.web.app import motion_answer

        return lambda: orjson.dumps(motion_answer(**(q() if callable(q) else q)), option=orjson.OPT_SERIALIZE_NUMPY)

    def chart():
        p = q() if callable(q) else q
        c = window_curves((p["eps_min"], p["eps_max"]), (p["mu_min"], p["mu_max"]), None, 0.0, p["samples"])
        return orjson.dumps(dict(y=c.mu, zones=[dict(lo=c.eps_lo[i], hi=c.eps_hi[i]) for i in range(c.n.size)]),
                            option=orjson.OPT_SERIALIZE_NUMPY)
    return chart


def motion_steps(repeats):
    """The page's nonlinear motion (``kapitza.simulate``) with its steps on one state (what the route
    runs) and, as the baseline, with each step through the array function on one-element arrays:
    ``(median per-state, median arrays, same doubles)`` [s]."""
    import kapitza.motion.nonlinear as nl
    from kapitza.motion._elliptic import _phase_step_arrays

    def run():
        return kapitza.simulate(MOTION["theta0"], 0.0, MOTION["T"], MOTION["A"], MOTION["l"], MOTION["g"],
                                periods=MOTION["periods"], points_per_period=MOTION["points_per_period"])

    one, ref = median_time(run, repeats)[0], run()
    saved = nl._phase_step_1
    nl._phase_step_1 = _phase_step_arrays
    try:
        arrays, got = median_time(run, repeats)[0], run()
    finally:
        nl._phase_step_1 = saved
    return one, arrays, bool(np.array_equal(ref.theta, got.theta) and np.array_equal(ref.dtheta, got.dtheta))


def load(base, path, params, clients, requests, seconds):
    """Latencies [s] of ``requests`` GETs spread over ``clients`` threads (stops after ``seconds``)."""
    lock = threading.Lock()
    left = [requests]
    times, errors = [], []
    stop = time.perf_counter() + seconds

    def worker():
        with httpx.Client(base_url=base, timeout=120.0) as c:
            c.get(path, params=params() if callable(params) else params)  # open the connection
            while True:
                with lock:
                    if left[0] <= 0 or time.perf_counter() > stop:
                        return
                    left[0] -= 1
                p = params() if callable(params) else params
                t0 = time.perf_counter()
                r = c.get(path, params=p)
                dt = time.perf_counter() - t0
                with lock:
                    (times if r.status_code == 200 else errors).append(dt)

    threads = [threading.Thread(target=worker) for _ in range(clients)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return np.array(times), len(errors), time.perf_counter() - t0


def cpu_seconds(pid):
    """User + system CPU time a process has used so far (Linux /proc), or NaN."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            fields = fh.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return float("nan")


def first_response(starts):
    """``(wall, cpu)`` seconds from starting ``kapitza serve`` to its first answer, per start."""
    out = []
    for _ in range(starts):
        with running_server() as (_, first, proc):
            out.append((first, cpu_seconds(proc.pid)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--requests", type=int, default=400, help="requests per level (default 400)")
    ap.add_argument("--seconds", type=float, default=30.0, help="time budget per level (default 30 s)")
    ap.add_argument("--levels", default="1,10,50", help="concurrent clients (default 1,10,50)")
    ap.add_argument("--starts", type=int, default=3, help="starts of kapitza serve timed (default 3)")
    ap.add_argument("--workers", type=int, default=1, help="server processes (kapitza serve --workers; default 1)")
    ap.add_argument("--mixed-clients", type=int, default=50, help="clients of the mixed load (default 50)")
    ap.add_argument("--only-mixed", action="store_true", help="run the mixed load only")
    ap.add_argument("--only", default=None, help="run only the queries whose name contains this text (no mixed load)")
    ap.add_argument("--tiny", action="store_true", help="a smoke run: few requests, 1 and 2 clients")
    args = ap.parse_args()
    if args.tiny:
        args.requests, args.seconds, args.levels, args.starts, args.mixed_clients = 6, 10.0, "1,2", 1, 4
    levels = [int(x) for x in args.levels.split(",")]

    header("bench_web")
    if args.only_mixed:
        return mixed(args)
    firsts = first_response(args.starts)
    wall = [w for w, _ in firsts]
    print(f"kapitza serve: first request answered {statistics.median(wall):.3f} s after start "
          f"(median of {len(firsts)}; all: {', '.join(f'{t:.3f}' for t in wall)}); CPU time the server "
          f"process used until then: {', '.join(f'{c:.2f}' for _, c in firsts)} s")
    print(f"server: kapitza serve --workers {args.workers}")
    with running_server(*(["--workers", str(args.workers)] if args.workers > 1 else [])) as (base, _, _proc):
        for name, (path, params) in QUERIES.items():
            if args.only is not None and args.only not in name:
                continue
            med, lo, hi = median_time(baseline(name), repeats=5 if args.tiny else 21, warmup=1)
            size = len(httpx.get(base + path.lstrip("/"), params=params() if callable(params) else params,
                                 timeout=120).content)
            print(f"\n{name}: GET {path} ({size / 1024:.0f} KiB)")
            print(f"  baseline: the library call in-process, no HTTP: median {1e3 * med:.2f} ms (min {1e3 * lo:.2f})")
            if path == "/api/motion":
                one, arrays, same = motion_steps(5 if args.tiny else 21)
                print(f"  its nonlinear motion in-process: {1e3 * one:.2f} ms with the steps on one state; "
                      f"baseline, each step on one-element arrays: {1e3 * arrays:.2f} ms; ratio "
                      f"{arrays / one:.2f}x; same doubles: {same}")
            for c in levels:
                t, err, wall = load(base, path, params, c, max(args.requests, c), args.seconds)
                p50, p99 = (1e3 * np.percentile(t, q) for q in (50, 99))
                ratio = f"; p50 / baseline {p50 / (1e3 * med):.2f}x" if c == 1 else ""
                print(f"  {c:3d} clients: {t.size:4d} requests in {wall:5.1f} s ({t.size / wall:6.1f}/s), "
                      f"p50 {p50:7.1f} ms, p99 {p99:7.1f} ms, errors {err}{ratio}")
    if args.only is None:
        mixed(args)


def mixed(args):
    """The mixed load of tests/test_web_load.py: latencies per kind, errors, memory."""
    import psutil
    from test_web_load import mixed_load

    def rss(proc):
        p = psutil.Process(proc.pid)
        return sum(q.memory_info().rss for q in [p, *p.children(recursive=True)]) / 2**20

    with running_server(*(["--workers", str(args.workers)] if args.workers > 1 else [])) as (base, _, proc):
        mixed_load(base, clients=6, seconds=0.0, seed=1)  # warm-up
        before = rss(proc)
        t0 = time.perf_counter()
        result = mixed_load(base, clients=args.mixed_clients, seconds=args.seconds if not args.tiny else 2.0)
        wall = time.perf_counter() - t0
        after = rss(proc)
    n = sum(len(v) for v in result.values())
    print(f"\nmixed load: {args.mixed_clients} clients sending for {args.seconds if not args.tiny else 2.0:g} s "
          f"(each finishing its last request): {n} requests in {wall:.1f} s ({n / wall:.1f}/s), "
          f"server --workers {args.workers}")
    for kind, answers in sorted(result.items()):
        t = np.array([dt for _, dt, _ in answers])
        codes = sorted({s for s, _, _ in answers})
        bad = sum(s >= 500 for s, _, _ in answers)
        print(f"  {kind:6s}: {t.size:4d} requests, p50 {1e3 * np.percentile(t, 50):8.1f} ms, "
              f"p99 {1e3 * np.percentile(t, 99):8.1f} ms, statuses {codes}, 5xx answers: {bad}")
    print(f"  server resident memory: {before:.0f} MiB after the warm-up, {after:.0f} MiB after the load "
          f"({after - before:+.0f} MiB)")
    try:
        print("  " + load_line("at the end"))
    except OSError:
        pass


if __name__ == "__main__":
    main()
