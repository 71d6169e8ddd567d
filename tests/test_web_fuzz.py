"""Schema-driven fuzz of the explorer's API (schemathesis): no input gives a server error.

The OpenAPI schema of a real ``kapitza serve`` drives hypothesis: the default suite sends a
few dozen generated requests to each JSON endpoint; ``pytest -m slow`` sends many more, to the
file exports too.
"""
from __future__ import annotations

import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from schemathesis.checks import not_a_server_error

from web_server import running_server


@pytest.fixture(scope="module")
def operations():
    with running_server() as (base, _, _proc):
        schema = schemathesis.openapi.from_url(base + "openapi.json")
        yield {op.ok().path: op.ok() for op in schema.get_all_operations()}


def _fuzz(operation, examples):
    @given(case=operation.as_strategy())
    @settings(max_examples=examples, deadline=None, suppress_health_check=list(HealthCheck), database=None)
    def run(case):
        response = case.call(timeout=300)
        case.validate_response(response, checks=[not_a_server_error])
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
