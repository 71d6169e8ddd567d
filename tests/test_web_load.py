"""The explorer under a class: 50 clients at once on loopback, mixing charts, points and motions
of several drives, for a bounded time. No answer may be a server error, and the server's memory
must stay flat (its resident size after the load within a bound of its size after a warm-up).

The default suite runs a few seconds of it; ``pytest -m slow`` the 30-second version.
``benchmarks/bench_web.py`` runs the same mix and reports its latencies.
"""
from __future__ import annotations

import collections
import random
import threading
import time

import httpx
import psutil
import pytest

from kapitza.web.app import LIMITS
from web_server import running_server

DRIVES = ["square", "sine", "rectangular:0.3", "steps:1,-1,0:0.25,0.25,0.5"]


def _chart(rng):
    drive = rng.choice(DRIVES)
    if drive == "square" and rng.random() < 0.5:
        return "/api/chart", dict(samples=1000)  # the view every page asks for first (cached)
    if drive == "square":  # a view dragged a little (computed)
        e0 = rng.uniform(0.0, 3.0)
        return "/api/chart", dict(eps_min=e0, eps_max=e0 + rng.uniform(0.5, 4.0), samples=300)
    return "/api/chart", dict(drive=drive, eps_max=rng.uniform(2.0, 4.0), samples=16,
                              zeta=0.0 if drive == "sine" else rng.choice([0.0, 0.0, 0.05]))


def _point(rng):
    drive = rng.choice(DRIVES)
    # a damped sine-wave point bisects its edges with Hill determinants (seconds of CPU): undamped here
    return "/api/point", dict(eps=rng.uniform(0.05, 3.0), mu=rng.uniform(0.05, 0.95), drive=drive,
                              zeta=0.0 if drive == "sine" else rng.choice([0.0, 0.0, 0.02]))


def _motion(rng):
    return "/api/motion", dict(T=rng.uniform(0.05, 0.4), A=rng.uniform(20.0, 400.0), drive=rng.choice(DRIVES),
                               theta0=rng.uniform(-1.0, 1.0), periods=rng.choice([5, 10]), points_per_period=30,
                               zeta=rng.choice([0.0, 0.1]))


KINDS = {"chart": _chart, "point": _point, "motion": _motion}


def mixed_load(base, clients=50, seconds=30.0, seed=0):
    """``clients`` threads, each with a keep-alive connection, sending requests of the three kinds
    in turn (client ``i`` starts with kind ``i mod 3``) until ``seconds`` have passed; each
    finishes the request it has sent. Returns ``{kind: [(status, seconds), ...]}``."""
    out = collections.defaultdict(list)
    lock = threading.Lock()
    stop = time.perf_counter() + seconds
    kinds = list(KINDS)

    def client(i):
        rng = random.Random(seed * 1000 + i)
        k = i % len(kinds)
        with httpx.Client(base_url=base, timeout=600.0) as c:
            while True:
                kind = kinds[k % len(kinds)]
                path, params = KINDS[kind](rng)
                t0 = time.perf_counter()
                r = c.get(path, params=params)
                dt = time.perf_counter() - t0
                with lock:
                    out[kind].append((r.status_code, dt, r.text[:300] if r.status_code != 200 else ""))
                k += 1
                if time.perf_counter() > stop:
                    return

    threads = [threading.Thread(target=client, args=(i,)) for i in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return dict(out)


def _rss(proc) -> int:
    """Resident bytes of the server: its process and the worker processes it started."""
    p = psutil.Process(proc.pid)
    return sum(q.memory_info().rss for q in [p, *p.children(recursive=True)])


def _run(seconds):
    with running_server() as (base, _, proc):
        mixed_load(base, clients=6, seconds=0.0, seed=1)  # warm up: imports, first views, caches
        before = _rss(proc)
        result = mixed_load(base, clients=50, seconds=seconds)
        after = _rss(proc)
        processes = 1 + len(psutil.Process(proc.pid).children(recursive=True))
    statuses = collections.Counter(s for answers in result.values() for s, _, _ in answers)
    bad = [(kind, s, text) for kind, answers in result.items() for s, _, text in answers if s != 200]
    assert not bad, bad[:5]
    assert set(result) == set(KINDS) and all(len(v) >= 10 for v in result.values()), statuses
    # flat: what the view cache may hold, and 100 MB of allocator slack, over all processes
    assert after - before < processes * LIMITS["cache_bytes"] + 100e6, (before / 1e6, after / 1e6)
    return result


def test_fifty_clients_get_no_server_error_and_memory_stays_flat():
    _run(seconds=3.0)


@pytest.mark.slow
def test_fifty_clients_for_thirty_seconds():
    _run(seconds=30.0)
