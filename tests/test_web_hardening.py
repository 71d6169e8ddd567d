"""The explorer under a careless or hostile client: hang-ups, half-sent requests, foreign Host
headers, views that grow after refinement, and the schema of its errors.

Each test talks to a real ``kapitza serve`` process over loopback sockets (a bounded number of
them, for a bounded time) or calls the app's pieces in-process. Nothing is asserted about wall
time: where work must stop, the server's CPU time is measured instead, which a loaded machine
does not inflate.
"""
from __future__ import annotations

import socket
import time

import httpx
import numpy as np
import psutil
import pytest

from kapitza import KapitzaValueError
from kapitza.web import app as web_app
from kapitza.web import server as web_server
from web_server import running_server


@pytest.fixture(scope="module")
def served():
    with running_server("--workers", "1") as (base, _, proc):
        yield base, proc


def _port(base):
    return int(base.rstrip("/").rsplit(":", 1)[1])


def _raw(port, data: bytes, timeout=60.0) -> bytes:
    """Send ``data`` on a fresh connection, read the whole answer."""
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as s:
        s.sendall(data)
        out = b""
        while True:
            chunk = s.recv(65536)
            if not chunk:
                return out
            out += chunk


# ------------------------------------------------------------------ Host header (DNS rebinding)
@pytest.mark.parametrize("host", ["127.0.0.1:{port}", "localhost:{port}", "[::1]:{port}", "LOCALHOST", "127.0.0.1"])
def test_loopback_host_names_are_answered(served, host):
    base, _ = served
    r = httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), headers={"Host": host.format(port=_port(base))},
                  timeout=60)
    assert r.status_code == 200 and r.json()["stable"] is True


@pytest.mark.parametrize("host", ["evil.example", "evil.example:{port}", "127.0.0.1.evil.example", "localhost.",
                                  "[::2]:{port}", "10.0.0.1"])
def test_other_host_names_are_refused_as_misdirected(served, host):
    # a page of evil.example whose name was re-pointed at 127.0.0.1 sends Host: evil.example
    base, _ = served
    r = httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), headers={"Host": host.format(port=_port(base))},
                  timeout=60)
    assert r.status_code == 421
    assert "answers to" in r.json()["detail"] and "--host" in r.json()["detail"]
    assert httpx.get(base, headers={"Host": host.format(port=_port(base))}, timeout=60).status_code == 421


def test_a_request_without_host_is_refused(served):
    base, _ = served
    answer = _raw(_port(base), b"GET /api/point?eps=0.5&mu=0.3 HTTP/1.0\r\n\r\n")
    assert answer.startswith(b"HTTP/1.1 421")


def test_the_host_given_to_serve_is_answered_too():
    # 127.0.0.2 is a loopback address but not one of the names answered by default
    with running_server("--workers", "1", "--host", "127.0.0.2") as (base, _, _proc):
        assert base.startswith("http://127.0.0.2:")
        assert httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), timeout=60).status_code == 200
        r = httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), headers={"Host": "evil.example"}, timeout=60)
        assert r.status_code == 421


def test_host_names_parse_ports_and_brackets(monkeypatch):
    assert web_app.host_name(b"[::1]:8000") == "::1"
    assert web_app.host_name(b"LocalHost:80") == "localhost"
    assert web_app.host_name(b"::1") == "::1"
    assert web_app.host_name(b"") == ""
    monkeypatch.setenv(web_app.HOSTS_ENV, "Pendulum.Lab, [fe80::1]")
    assert {"pendulum.lab", "fe80::1", "127.0.0.1", "localhost", "::1"} == set(web_app.allowed_hosts())
    # a wildcard bind answers to this machine's own names
    assert socket.gethostname() in web_server.host_names("0.0.0.0")


# ------------------------------------------------------------------ half-sent requests
def test_half_sent_requests_do_not_lock_others_out(served):
    """300 connections that send part of a request's head and stall (slowloris): others are still
    answered, the stalled ones are closed (the oldest at once beyond MAX_WAITING, the rest at the
    head deadline)."""
    base, _ = served
    port = _port(base)
    stalled = []
    try:
        for _ in range(300):
            s = socket.create_connection(("127.0.0.1", port), timeout=60)
            s.sendall(b"GET /api/point?eps=0.5&mu=0.3 HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
            stalled.append(s)
        r = httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), timeout=120)
        assert r.status_code == 200
        # every stalled connection is closed by the server, within the head deadline (plus slack
        # for a loaded machine), without an answer
        for s in stalled:
            s.settimeout(web_server.HEAD_SECONDS + 120)
            try:
                assert s.recv(1024) == b""
            except ConnectionResetError:
                pass
    finally:
        for s in stalled:
            s.close()
    assert httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), timeout=120).status_code == 200


def test_a_head_never_finished_is_closed_after_the_deadline(served):
    base, _ = served
    with socket.create_connection(("127.0.0.1", _port(base)), timeout=web_server.HEAD_SECONDS + 120) as s:
        s.sendall(b"GET / HTTP/1.1\r\n")
        assert s.recv(1024) == b""  # closed (the old server kept it open for ever: this timed out)
    with socket.create_connection(("127.0.0.1", _port(base)), timeout=web_server.HEAD_SECONDS + 120) as s:
        # a keep-alive connection: the first request answered, the second never finished
        s.sendall(b"GET /api/point?eps=0.5&mu=0.3 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\nGET / HTTP/1.1\r\n")
        data = b""
        while True:
            chunk = s.recv(65536)
            if not chunk:
                break
            data += chunk
        assert data.startswith(b"HTTP/1.1 200") and data.count(b"HTTP/1.1") == 1


# ------------------------------------------------------------------ work after the client hangs up
def test_work_stops_when_the_client_hangs_up(served):
    """Four damped-chart requests abandoned by their clients: the server stops computing them
    (measured by its CPU time, not by a clock) and then answers a point at once."""
    base, proc = served
    port = _port(base)
    server = psutil.Process(proc.pid)
    request = (b"GET /api/chart?zeta=1e-300&samples=400&eps_max=12 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
    socks = []
    for _ in range(4):
        s = socket.create_connection(("127.0.0.1", port), timeout=60)
        s.sendall(request)
        socks.append(s)
    cpu0 = sum(server.cpu_times()[:2])
    while sum(server.cpu_times()[:2]) - cpu0 < 0.5:  # the work has started
        time.sleep(0.1)
    for s in socks:
        s.close()
    hung_up = sum(server.cpu_times()[:2])
    # wait until the server is idle: less than 0.05 s of CPU over a second of wall time
    last = hung_up
    for _ in range(600):
        time.sleep(1.0)
        now = sum(server.cpu_times()[:2])
        if now - last < 0.05:
            break
        last = now
    spent = now - hung_up
    # each request stops within a block of 8 samples (a few tenths of a CPU second); four charts
    # run to the end (or to their CPU budget) would have spent minutes of CPU
    assert spent < 6.0, spent
    assert httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), timeout=120).status_code == 200


def test_a_chart_past_its_cpu_budget_is_refused_by_name(monkeypatch):
    # the default view with any damping (zeta = 1e-300) computed for 31-171 s
    monkeypatch.setitem(web_app.LIMITS, "chart_cpu_seconds", 0.2)
    with pytest.raises(KapitzaValueError, match=r"takes more than 0.2 s of computing"):
        web_app._chart_json("arnold", 0.0, 4.0, 0.0, 1.0, 0.0, None, None, None, 1.0, 9.81, "square", 1e-300, 300)


def test_a_gone_client_stops_the_chart_between_blocks():
    calls = []

    def gone():
        calls.append(1)
        if len(calls) > 2:
            raise web_app._Cancelled

    with pytest.raises(web_app._Cancelled):
        web_app._chart_json("arnold", 0.0, 4.0, 0.0, 1.0, 0.0, None, None, None, 1.0, 9.81, "sine", 0.0, 300, gone)
    assert len(calls) == 3


# ------------------------------------------------------------------ sizes after refinement
def test_chart_samples_are_capped_after_refinement(served):
    # 54 zones cross eps 59..60 near mu = 1: the refinement multiplied the samples (440 MB of JSON
    # for one request with samples=4000)
    base, _ = served
    for samples in (200, 4000):
        r = httpx.get(base + "api/chart", params=dict(eps_min=59, eps_max=60, samples=samples), timeout=300)
        assert r.status_code == 200
        d = r.json()
        assert samples <= d["samples"] <= web_app.LIMITS["samples"] == 4000
        assert len(d["y_values"]) == d["samples"] and all(len(z["lo"]) == d["samples"] for z in d["zones"])
        assert len(d["zones"]) == 54 and len(r.content) < 12e6


def test_other_drives_and_damping_have_their_own_sample_cap(served):
    base, _ = served
    r = httpx.get(base + "api/chart", params=dict(zeta=0.01, samples=1000), timeout=60)
    assert r.status_code == 422 and "samples must satisfy 2 <= samples <= 400" in r.json()["detail"]


def test_physical_export_applies_the_eps_cap(served):
    # the physical-plane export skipped the bound on the largest eps of the view
    base, _ = served
    for path in ("api/chart", "api/export/chart.csv"):
        r = httpx.get(base + path, params=dict(plane="physical", T_max=100, A_max=1e4), timeout=60)
        assert r.status_code == 422 and "the largest eps in view" in r.json()["detail"], path
    # the export's figure refines up to 4 x its samples: it may ask for a quarter of the cap
    r = httpx.get(base + "api/export/chart.csv", params=dict(samples=2000), timeout=60)
    assert r.status_code == 422 and "samples <= 1000" in r.json()["detail"]


def test_point_reports_of_other_drives_are_bounded_in_eps(served):
    # a triangle-wave report at eps = 5,000 took 15 s (its margins are searches of integrated periods
    # of about eps steps each), at 50,000 minutes: a few such requests held every worker
    base, _ = served
    cap = web_app.LIMITS["general_point_eps"]
    for path, extra in (("api/point", {}), ("api/point", {"zeta": 0.05}), ("api/safe_tilt", {})):
        r = httpx.get(base + path, params=dict(eps=50 * cap, mu=0.1, drive="triangle", **extra), timeout=60)
        assert r.status_code == 422, (path, r.text)
        assert r.json()["detail"] == f"eps must satisfy eps <= {cap:g} in the explorer; got {50 * cap!r}"
    # given as T and A, the message names what it bounds
    r = httpx.get(base + "api/point", params=dict(T=15.0, A=1e6, l=1.0, drive="triangle"), timeout=60)
    assert r.status_code == 422 and "T sqrt(A / (8 l)) (the point's eps) must satisfy" in r.json()["detail"]
    # the sine's reports grow faster (exact traces beside its thin zones: a minute at eps 60): a tighter bound
    own = web_app.LIMITS["own_point_eps"]
    A = 9.81 / 0.5**2
    r = httpx.get(base + "api/point", params=dict(T=3 * own * np.sqrt(8.0 / A), A=A, l=1.0, drive="sine"), timeout=60)
    assert r.status_code == 422 and f"the point's eps) must satisfy T sqrt(A / (8 l)) (the point's eps) <= {own:g}" \
        in r.json()["detail"]
    r = httpx.get(base + "api/point", params=dict(T=0.5 * own * np.sqrt(8.0 / A), A=A, l=1.0, drive="sine"),
                  timeout=120)
    assert r.status_code == 200
    # exact segment products (the square wave, damped or not, a step drive) answer at any eps; a verdict
    # alone at once
    for extra in ({}, {"zeta": 0.05}, {"drive": "rectangular:0.3"}):
        assert httpx.get(base + "api/point", params=dict(eps=50 * cap, mu=0.1, **extra), timeout=60).status_code == 200
    assert httpx.get(base + "api/verdict", params=dict(eps=50 * cap, mu=0.1, drive="triangle"),
                     timeout=60).status_code == 200
    # within the bound a report of another drive is answered
    r = httpx.get(base + "api/point", params=dict(eps=2.5, mu=0.1, drive="triangle"), timeout=120)
    assert r.status_code == 200 and r.json()["eps"] == 2.5


def test_view_cache_is_bounded_in_bytes(monkeypatch):
    monkeypatch.setitem(web_app.LIMITS, "cache_bytes", 10_000)
    cache = web_app._ViewCache()
    for i in range(100):
        cache.put(i, b"x" * 1000)
    assert cache.nbytes <= 10_000 and cache.get(99) is not None and cache.get(0) is None
    cache.put("big", b"x" * 5000)  # more than an eighth of the cache: not kept
    assert cache.get("big") is None and cache.nbytes <= 10_000


# ------------------------------------------------------------------ the schema of an error
def test_openapi_describes_the_422_body_as_sent(served):
    base, _ = served
    schema = httpx.get(base + "openapi.json", timeout=60).json()
    error = schema["components"]["schemas"]["Error"]
    assert error["properties"]["detail"]["type"] == "string" and error["required"] == ["detail"]
    assert "HTTPValidationError" not in schema["components"]["schemas"]
    for path, ops in schema["paths"].items():
        for op in ops.values():
            ref = op["responses"]["422"]["content"]["application/json"]["schema"]["$ref"]
            assert ref == "#/components/schemas/Error", path
    body = httpx.get(base + "api/point", params=dict(eps="x", mu=0.3), timeout=60).json()
    assert set(body) == {"detail"} and isinstance(body["detail"], str)
    import jsonschema

    jsonschema.validate(body, error)
    assert np.isfinite(httpx.get(base + "api/point", params=dict(eps=0.5, mu=0.3), timeout=60).json()["eps"])
