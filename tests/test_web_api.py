"""The explorer's JSON API through real HTTP: a ``kapitza serve`` process on a loopback port.

Numbers must equal the library's (the routes only parse and call it), bad input must be a 422
naming the parameter, and every size a request may ask for is bounded.
"""
from __future__ import annotations

import io
import json
import subprocess
import sys

import httpx
import numpy as np
import pytest

import kapitza
from kapitza.cli import main
from web_server import running_server


@pytest.fixture(scope="module")
def server():
    with running_server() as (base, first, _):
        with httpx.Client(base_url=base, timeout=60.0) as client:
            client.first_response = first
            yield client


def test_serve_answers_with_page_and_schema(server):
    # How soon kapitza serve answers after starting is measured by benchmarks/bench_web.py, not here:
    # on a busy shared machine any wall-clock bound either fails or proves nothing.
    assert server.first_response > 0.0
    page = server.get("/")
    assert page.status_code == 200 and "kapitza explorer" in page.text
    assert server.get("/static/app.js").status_code == 200
    schema = server.get("/openapi.json").json()
    for path in ("/api/chart", "/api/point", "/api/motion", "/api/export/chart.{fmt}", "/api/export/motion.{fmt}"):
        assert path in schema["paths"]


def test_chart_edges_are_the_library_edges(server):
    d = server.get("/api/chart", params=dict(eps_min=0, eps_max=4, mu_min=0, mu_max=1, samples=300)).json()
    assert d["x"] == "eps" and d["y"] == "mu"
    mu = np.array(d["y_values"])
    assert [z["n"] for z in d["zones"]] == [0, 1, 2, 3]
    for z in d["zones"]:
        lo, hi = kapitza.zone_edges(mu, z["n"])
        np.testing.assert_allclose(z["lo"], lo, rtol=1e-15, atol=0)
        np.testing.assert_allclose(z["hi"], hi, rtol=1e-15, atol=0)
        assert (z["lower_edge"], z["upper_edge"]) == (("2T", "4T") if z["n"] % 2 == 0 else ("4T", "2T"))


def test_chart_deep_zoom_draws_a_tongue_thinner_than_a_pixel_grid(server):
    # Zone 3 at mu = 0.7 is about 1e-9 wide; a view a few widths across still gets its edges, exactly.
    lo, hi = (float(v) for v in kapitza.zone_edges(0.7, 3))
    w = hi - lo
    assert w < 1e-8
    d = server.get("/api/chart", params=dict(eps_min=lo - 2 * w, eps_max=hi + 2 * w, mu_min=0.7 - 1e-9,
                                             mu_max=0.7 + 1e-9, samples=400)).json()
    z3 = [z for z in d["zones"] if z["n"] == 3]
    assert len(z3) == 1
    mu = np.array(d["y_values"])
    zlo, zhi = np.array(z3[0]["lo"]), np.array(z3[0]["hi"])
    ref_lo, ref_hi = kapitza.zone_edges(mu, 3)
    np.testing.assert_allclose(zlo, ref_lo, rtol=1e-15)
    np.testing.assert_allclose(zhi, ref_hi, rtol=1e-15)
    inside = (zhi > lo - 2 * w) & (zlo < hi + 2 * w)
    assert inside.sum() >= 100            # many samples where the tongue crosses the view
    assert np.all(zhi - zlo > 0.5 * w)     # the tongue keeps its width: no rounding collapse


def test_chart_physical_plane_edges_are_period_edges(server):
    d = server.get("/api/chart", params=dict(plane="physical", l=0.5, g=9.81, samples=200)).json()
    assert d["x"] == "T" and d["y"] == "A"
    A = np.array(d["y_values"])
    # Near A = g the edges run off to T -> inf and the rounding of A = g / mu^2 is amplified there.
    ok = A > 1.01 * 9.81
    for z in d["zones"][:3]:
        T_lo, T_hi = kapitza.period_edges(A[ok], z["n"], 0.5, 9.81)
        np.testing.assert_allclose(np.array(z["lo"])[ok], T_lo, rtol=1e-12)
        np.testing.assert_allclose(np.array(z["hi"])[ok], T_hi, rtol=1e-12)


def test_chart_other_drive_is_the_library_drive(server):
    d = server.get("/api/chart", params=dict(drive="rectangular:0.3", zeta=0.1, eps_max=2, samples=40)).json()
    mu = np.array(d["y_values"])
    z0 = d["zones"][0]
    lo, hi = kapitza.zone_edges(mu, 0, drive=kapitza.RectangularWave(0.3), zeta=0.1)
    web = np.array([np.nan if v is None else v for v in z0["lo"]])
    shown = np.isfinite(web)
    assert shown.sum() > 20
    # The chart takes the window method (as kapitza chart does); edge by edge the damped lower edge
    # near mu = 0 agrees to about 1e-6 only (a few 1e-7 at mu = 1e-3), elsewhere to 1e-9.
    np.testing.assert_allclose(web[shown], lo[shown], rtol=1e-5)
    np.testing.assert_allclose(web[shown][mu[shown] > 0.05], lo[shown][mu[shown] > 0.05], rtol=1e-9)
    assert np.all(~np.isfinite(lo[~shown]) | (lo[~shown] >= 2.0))   # left out only beyond the view


def test_chart_of_a_drive_that_holds_the_rod_up_below_g(server):
    """The chart says where the drive can hold the rod up (mu_max), accepts a view up to it, draws
    zone 0 above mu = 1 for a duty of 0.8, and refuses a view beyond it with a 422."""
    d = server.get("/api/chart", params=dict(drive="rectangular:0.8", mu_min=0.9, mu_max=2.0, eps_max=3,
                                             samples=40)).json()
    assert d["mu_max"] == pytest.approx(2.0, rel=1e-15)
    mu = np.array(d["y_values"])
    z0 = np.array([np.nan if v is None else v for v in d["zones"][0]["lo"]])
    lo, _ = kapitza.zone_edges(mu, 0, drive=kapitza.RectangularWave(0.8))
    shown = np.isfinite(z0) & (mu > 1.0)
    assert shown.sum() > 10
    np.testing.assert_allclose(z0[shown], lo[shown], rtol=1e-9)
    assert server.get("/api/chart", params=dict(drive="square")).json()["mu_max"] == 1.0
    r = server.get("/api/chart", params=dict(drive="rectangular:0.8", mu_max=2.5))
    assert r.status_code == 422 and "mu_max <= 2" in r.json()["detail"] and "2.5" in r.json()["detail"]
    phys = server.get("/api/chart", params=dict(plane="physical", drive="rectangular:0.8", samples=40)).json()
    assert phys["view"]["A_min"] == pytest.approx(9.81 / 4.0, rel=1e-12)


def _cli_json(argv):
    out = io.StringIO()
    old, sys.stdout = sys.stdout, out
    try:
        assert main(argv) == 0
    finally:
        sys.stdout = old
    return json.loads(out.getvalue())


@pytest.mark.parametrize("query, argv", [
    (dict(T=0.15, A=100), ["--T", "0.15", "--A", "100"]),
    (dict(T=0.3, A=100, l=0.5), ["--T", "0.3", "--A", "100", "--l", "0.5"]),
    (dict(eps=0.5, mu=0.3, drive="rectangular:0.3", zeta=0.1), ["--eps", "0.5", "--mu", "0.3", "--duty", "0.3", "--zeta", "0.1"]),
    (dict(eps=1.7, mu=0.2, drive="sine"), ["--eps", "1.7", "--mu", "0.2", "--drive", "sine"]),
])
def test_point_is_what_kapitza_stability_json_prints(server, query, argv):
    web = server.get("/api/point", params=query).json()
    lines = web.pop("lines")
    cli = _cli_json(["stability", *argv, "--no-safe-tilt", "--json"])  # /api/point gives it on request
    assert web == cli
    assert ["verdict", cli["verdict"]] in lines
    if "A" in query:  # A in units of g, the field beside the text's "(10.19 g)"
        assert web["A_g"] == pytest.approx(query["A"] / kapitza.parameters.G_EARTH)
        assert any(f"({web['A_g']:.4g} g)" in text for _, text in lines)
    else:
        assert web["A_g"] is None


def test_motion_is_the_library_simulation(server):
    q = dict(T=0.15, A=100, theta0=0.2, periods=5, points_per_period=40)
    d = server.get("/api/motion", params=q).json()
    nl = kapitza.simulate(0.2, 0.0, 0.15, 100.0, periods=5, points_per_period=40)
    lin = kapitza.simulate(0.2, 0.0, 0.15, 100.0, periods=5, points_per_period=40, model="linear")
    np.testing.assert_array_equal(d["t"], nl.t)
    np.testing.assert_array_equal(d["theta"], nl.theta)
    np.testing.assert_array_equal(d["theta_linear"], lin.theta)
    np.testing.assert_array_equal(d["pivot"], nl.pivot)
    tk, th, om = nl.strobe()
    np.testing.assert_array_equal(d["strobe"]["t"], tk)
    np.testing.assert_array_equal(d["strobe"]["theta"], th)
    assert len(d["strobe"]["t"]) == 6


def test_a_repeated_motion_is_the_same_answer_and_another_start_another(server):
    q = dict(T=0.15, A=100, theta0=0.25, periods=3, points_per_period=30)
    first, again = (server.get("/api/motion", params=q) for _ in range(2))
    assert first.status_code == again.status_code == 200 and first.content == again.content
    other = server.get("/api/motion", params={**q, "theta0": 0.26}).json()
    assert other["theta"][0] == 0.26 and other["theta"] != first.json()["theta"]
    # a refused request is not kept: it is refused again, with its message
    bad = dict(q, periods=1000)
    assert [server.get("/api/motion", params=bad).status_code for _ in range(2)] == [422, 422]


def test_motion_of_an_unstable_point_runs_away_in_the_linear_model(server):
    # T = 0.3 s: the linear motion grows like exp(3.07 per period) to ~1e26 rad; the nonlinear one
    # falls and whirls. Both come back (no server error on the huge numbers).
    d = server.get("/api/motion", params=dict(T=0.3, A=100.1337157672325, periods=20, points_per_period=60)).json()
    assert abs(d["theta_linear"][-1]) > 1e20 and d["summary"]["linear"]["turns"] != 0
    assert d["summary"]["motion"]["max_abs_theta"] > 1.5


def test_exports_are_the_files_the_cli_writes(server, tmp_path):
    q = dict(T=0.15, A=100, theta0=0.1, periods=2, points_per_period=10)
    web_csv = server.get("/api/export/motion.csv", params=q)
    assert web_csv.status_code == 200 and web_csv.headers["content-type"].startswith("text/csv")
    assert main(["simulate", "--T", "0.15", "--A", "100", "--theta0", "0.1", "--periods", "2",
                 "--points-per-period", "10", "--out", str(tmp_path / "run"), "--no-figures"]) == 0
    assert web_csv.text == (tmp_path / "run.csv").read_text()
    summary = server.get("/api/export/motion.json", params=q).json()
    cli = json.loads((tmp_path / "run.json").read_text())
    assert summary["parameters"] == cli["parameters"] and summary["motion"] == cli["motion"]

    chart_csv = server.get("/api/export/chart.csv", params=dict(eps_min=1.65, eps_max=1.8, mu_min=0, mu_max=0.35,
                                                                samples=300)).text
    assert main(["chart", "--eps-min", "1.65", "--eps-max", "1.8", "--mu-min", "0", "--mu-max", "0.35",
                 "--points", "300", "--out", str(tmp_path / "zoom")]) == 0
    strip = lambda text: [r for r in text.splitlines() if not r.startswith("#")]  # noqa: E731
    assert strip(chart_csv) == strip((tmp_path / "zoom.csv").read_text())

    png = server.get("/api/export/chart.png", params=dict(T=0.15, A=100, samples=200))
    assert png.status_code == 200 and png.content[:8] == b"\x89PNG\r\n\x1a\n"
    from PIL import Image

    assert Image.open(io.BytesIO(png.content)).size[0] > 600
    svg = server.get("/api/export/motion.svg", params=q)
    assert svg.status_code == 200 and b"<svg" in svg.content[:2000]


@pytest.mark.parametrize("path, query, words", [
    ("/api/chart", dict(samples=5000), ["samples", "4000", "5000"]),
    ("/api/chart", dict(samples="many"), ["samples", "many"]),
    ("/api/chart", dict(eps_max=1000), ["eps_max", "1000"]),
    ("/api/chart", dict(eps_min=3, eps_max=2), ["eps", "(3, 2)"]),
    ("/api/chart", dict(mu_max=2), ["mu", "2"]),
    ("/api/chart", dict(plane="polar"), ["plane", "polar"]),
    ("/api/chart", dict(drive="sawtooth"), ["drive", "sawtooth"]),
    ("/api/chart", dict(drive="rectangular:1.5"), ["duty", "1.5"]),
    ("/api/chart", dict(zeta=-1), ["zeta", "-1"]),
    ("/api/chart", dict(zeta=1e308), ["zeta", "10", "1e+308"]),
    ("/api/export/chart.png", dict(mu_min=-1e308, zeta=1), ["mu", "mu_min"]),
    ("/api/chart", dict(plane="physical", l=0), ["l", "0"]),
    ("/api/point", dict(eps=-1, mu=0.3), ["eps", "-1"]),
    ("/api/point", dict(T=0.1), ["T and A"]),
    ("/api/point", dict(T=0.1, A=100, eps=0.3, mu=0.3), ["not both"]),
    ("/api/motion", dict(T=0.15, A=100, periods=1000), ["periods", "200", "1000"]),
    ("/api/motion", dict(T=0.15, A=100, periods=200, points_per_period=150), ["periods * points_per_period", "20000"]),
    ("/api/motion", dict(T=0.15, A=100, theta0=10), ["theta0", "10"]),
    ("/api/motion", dict(T=0.15, A=-100), ["A", "-100"]),
    ("/api/export/chart.pdf", {}, ["fmt", "pdf"]),
])
def test_bad_input_is_422_naming_the_parameter(server, path, query, words):
    r = server.get(path, params=query)
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert isinstance(detail, str) and "\n" not in detail and "Traceback" not in detail
    for w in words:
        assert w in detail, (w, detail)


def test_requests_are_bounded(server):
    r = server.get("/api/chart", params=dict(drive="x" * 5000))
    assert r.status_code == 414
    r = server.get("/api/chart", params=dict(drive="square" + " " * 300))
    assert r.status_code == 422 and "drive" in r.json()["detail"]
    r = server.request("GET", "/api/point", content=b"x" * 1000)
    assert r.status_code == 413
    r = server.post("/api/chart", content=b"{}")
    assert r.status_code in (405, 413)
    # no route reads a path the client gives
    assert server.get("/static/../../pyproject.toml").status_code == 404
    assert server.get("/static/%2e%2e/app.py").status_code == 404


def test_serve_warns_beyond_loopback_and_needs_the_extra():
    with running_server("--host", "0.0.0.0") as (base, _, proc):
        assert base.startswith("http://0.0.0.0:")
    assert "reachable from other machines" in proc.stderr_text
    code = ("import sys; sys.modules['fastapi'] = None; from kapitza.cli import main; "
            "sys.exit(main(['serve']))")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert res.returncode == 2
    err = res.stderr.strip().splitlines()
    assert len(err) == 1 and "pip install" in err[0] and "web" in err[0]


def test_served_connections_send_small_answers_at_once():
    """Connections accepted on the explorer's socket have TCP_NODELAY (else a small answer
    waits for the client's delayed ACK, about 40 ms a request)."""
    import asyncio
    import socket

    from kapitza.web.server import bind

    async def accepted_nodelay():
        sock = bind("127.0.0.1", 0)
        seen = asyncio.get_running_loop().create_future()

        def connected(reader, writer):
            s = writer.get_extra_info("socket")
            seen.set_result(s.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY))
            writer.close()

        server = await asyncio.start_server(connected, sock=sock)
        async with server:
            _, w = await asyncio.open_connection(*sock.getsockname()[:2])
            value = await asyncio.wait_for(seen, 10)
            w.close()
        return value

    assert asyncio.run(accepted_nodelay()) != 0


def test_the_server_imports_what_its_routes_import_before_it_answers():
    # two first imports of one package in two threads can leave one of them with a half-made module:
    # the modules the routes import where they are first needed are imported when the server starts
    import ast

    from kapitza.web import app as web_app

    tree = ast.parse(open(web_app.__file__).read())
    lazy = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for sub in ast.walk(node):
                if isinstance(sub, ast.ImportFrom) and sub.level == 2 and sub.module:
                    lazy.add("kapitza." + sub.module)
    # (imported by the module itself, or with kapitza: the drives)
    at_top = {"kapitza." + n.module for n in tree.body if isinstance(n, ast.ImportFrom) and n.level == 2 and n.module}
    at_top |= {name for name in lazy if name.startswith("kapitza.drives")}
    assert lazy - at_top <= set(web_app._ROUTE_MODULES), sorted(lazy - at_top - set(web_app._ROUTE_MODULES))
    # and the server's start does import them (a fresh interpreter: nothing imported before)
    code = ("import sys; from fastapi.testclient import TestClient; from kapitza.web.app import create_app, "
            "_ROUTE_MODULES\nbefore = [m for m in _ROUTE_MODULES if m in sys.modules]\n"
            "with TestClient(create_app()):\n    after = [m for m in _ROUTE_MODULES if m not in sys.modules]\n"
            "print(len(before), after)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=True).stdout
    n_before, missing = out.split(" ", 1)
    assert int(n_before) < len(web_app._ROUTE_MODULES) and missing.strip() == "[]", out


def test_a_fresh_servers_first_requests_at_once_all_answer():
    # a page's first load asks the motion, the safe tilt, the report and the chart together; each
    # route imports what it needs where first needed, so the server imports those modules before
    # it answers (two first imports of one package in two threads once left a route failing)
    from concurrent.futures import ThreadPoolExecutor

    q = "T=0.15&A=100&l=1&g=9.81&drive=square"
    paths = [f"/api/motion?{q}&zeta=0&theta0=0.1", f"/api/safe_tilt?{q}&periods=40", f"/api/point?{q}",
             f"/api/verdict?{q}"]
    for _ in range(2):
        with running_server() as (base, _, _proc), httpx.Client(timeout=300) as client:
            with ThreadPoolExecutor(len(paths)) as pool:
                codes = list(pool.map(lambda p: client.get(base.rstrip("/") + p).status_code, paths))
        assert codes == [200] * len(paths), dict(zip(paths, codes))
