"""Schema-driven fuzz of the explorer's API (schemathesis): no input gives a server error, and
every error body is the one the schema describes.

The OpenAPI schema of a real ``kapitza serve`` drives hypothesis: the default suite sends a
few dozen generated requests to each JSON endpoint; ``pytest -m slow`` sends many more, to the
file exports too. Beside the schema: random ``Host`` headers (only loopback names answered),
clients that send their request in random pieces or stop half-way, and narrow windows far out
in eps whose refinement must stay within the sample cap.
"""
from __future__ import annotations

import socket
import time

import httpx
import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from schemathesis.checks import not_a_server_error, response_schema_conformance

from kapitza.web.app import LIMITS, allowed_hosts, host_name
from web_server import running_server


@pytest.fixture(scope="module")
def served():
    with running_server() as (base, _, _proc):
        yield base


@pytest.fixture(scope="module")
def operations(served):
    schema = schemathesis.openapi.from_url(served + "openapi.json")
    return {op.ok().path: op.ok() for op in schema.get_all_operations()}


def _fuzz(operation, examples):
    @given(case=operation.as_strategy())
    @settings(max_examples=examples, deadline=None, suppress_health_check=list(HealthCheck), database=None)
    def run(case):
        response = case.call(timeout=300)
        case.validate_response(response, checks=[not_a_server_error, response_schema_conformance])
        if response.status_code == 422:
            detail = response.json()["detail"]
            assert isinstance(detail, str) and detail and "Traceback" not in detail

    run()


@pytest.mark.parametrize("path", ["/api/chart", "/api/point", "/api/motion"])
def test_json_endpoints_never_fail_on_the_server(operations, path):
    _fuzz(operations[path], 30)


@pytest.mark.slow
@pytest.mark.parametrize("path", ["/api/chart", "/api/point", "/api/motion", "/api/export/chart.{fmt}",
                                  "/api/export/motion.{fmt}"])
def test_every_endpoint_never_fails_on_the_server(operations, path):
    _fuzz(operations[path], 300)


# ------------------------------------------------------------------ beside the schema
_SETTINGS = dict(deadline=None, suppress_health_check=list(HealthCheck), database=None)


def _port(base):
    return int(base.rstrip("/").rsplit(":", 1)[1])


hosts = st.one_of(
    st.sampled_from(["127.0.0.1", "localhost", "[::1]", "LocalHost", "127.0.0.1.", "127.1", "0.0.0.0", "[::]",
                     "evil.example", "localhost.evil.example", "", " ", "[::1", "::1]", "a:b:c"]),
    st.text(st.characters(min_codepoint=33, max_codepoint=126), min_size=1, max_size=40),
).flatmap(lambda h: st.sampled_from([h, h + ":8000", h + ":" , h + ":99999"]))


@settings(max_examples=60, **_SETTINGS)
@given(host=hosts)
def test_any_host_header_is_answered_only_if_it_names_loopback(served, host):
    with socket.create_connection(("127.0.0.1", _port(served)), timeout=120) as s:
        s.sendall(b"GET /api/point?eps=0.5&mu=0.3 HTTP/1.1\r\nHost: " + host.encode("latin-1") + b"\r\n"
                  b"Connection: close\r\n\r\n")
        answer = b""
        while chunk := s.recv(65536):
            answer += chunk
    status = int(answer.split(b" ", 2)[1])
    assert status < 500, answer[:300]
    if status != 400:  # h11 refuses some texts as a malformed request before the app sees them
        assert status == (200 if host_name(host.encode("latin-1")) in allowed_hosts() else 421), (host, answer[:300])


REQUEST = b"GET /api/point?eps=0.5&mu=0.3 HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n"


@settings(max_examples=8, **_SETTINGS)
@given(cuts=st.lists(st.integers(1, len(REQUEST) - 1), max_size=6, unique=True),
       pause=st.floats(0.0, 0.2), stop=st.booleans())
def test_a_slow_client_is_answered_and_a_stalled_one_is_closed(served, cuts, pause, stop):
    """A request sent in pieces with pauses gets its answer; one that stops half-way is closed by
    the server without an answer (never held open, never a server error)."""
    cuts = sorted(cuts)
    pieces = [REQUEST[a:b] for a, b in zip([0, *cuts], [*cuts, len(REQUEST)])]
    if stop:
        pieces = pieces[:-1] or [REQUEST[:5]]
    with socket.create_connection(("127.0.0.1", _port(served)), timeout=120 + 10) as s:
        for piece in pieces:
            s.sendall(piece)
            time.sleep(pause)
        answer = b""
        while chunk := s.recv(65536):
            answer += chunk
    if stop:
        assert answer == b""  # closed at the head deadline, nothing said
    else:
        assert answer.startswith(b"HTTP/1.1 200") and b'"stable":true' in answer


@settings(max_examples=12, **_SETTINGS)
@given(e0=st.floats(1.0, 59.0), width=st.sampled_from([1e-9, 1e-6, 1e-3, 0.3, 1.0]),
       m0=st.floats(0.0, 0.99), height=st.sampled_from([1e-9, 1e-4, 1e-2, 1.0]),
       samples=st.sampled_from([2, 50, 1000, 4000]))
def test_narrow_windows_stay_within_the_sample_cap_after_refinement(served, e0, width, m0, height, samples):
    params = dict(eps_min=e0, eps_max=min(e0 + width, 60.0), mu_min=m0, mu_max=min(m0 + height, 1.0),
                  samples=samples)
    r = httpx.get(served + "api/chart", params=params, timeout=600)
    assert r.status_code in (200, 422), r.text[:300]
    if r.status_code == 200:
        d = r.json()
        assert d["samples"] == len(d["y_values"]) <= LIMITS["samples"]
        assert len(r.content) < 60 * LIMITS["samples"] * 2 * 25  # zones x samples x 2 edges x digits
