"""The reproduction of the paper: the data behind each figure, and the whole command.

These tests check numbers, not pixels: each figure's marked points and curves must be
what the paper's construction says they are, computed independently here from the
plain formulas and the one-period matrix.
"""
import csv
import json
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from PIL import Image

import kapitza as K
from cli_util import run
from kapitza.paper import data as D
from kapitza.paper import approximations as ap


def plain_alpha_beta(T, A, l=1.0, g=9.81):
    """alpha, beta straight from the paper's definitions (with e^{w_h T})."""
    w_h, w_e = math.sqrt((A + g) / l), math.sqrt((A - g) / l)
    e = math.exp(w_h * T)
    Dd = w_h / w_e
    return 2 * math.atan(Dd * (e - 1) / (e + 1)), 2 * math.atan(Dd * (e + 1) / (e - 1)), w_e


# ------------------------------------------------------------------ Figure 1
def test_figure1_curves_are_level_sets_and_arrows_follow_the_flow():
    d = D.figure1_data()
    hyp = d.series_with(role="hyperbola")
    circ = d.series_with(role="circle")
    assert len(hyp) == 4 * len(circ) and circ
    for s in hyp:   # x_h^2 - y_h^2 is a first integral of (2.6)
        np.testing.assert_allclose(np.asarray(s.x) ** 2 - np.asarray(s.y) ** 2, s.meta["H"], atol=1e-12)
    for s in circ:  # x_e^2 + y_e^2 is a first integral of (2.12)
        np.testing.assert_allclose(np.asarray(s.x) ** 2 + np.asarray(s.y) ** 2, s.meta["H"], rtol=1e-13)
        # clockwise: the angle decreases along the curve
        assert np.all(np.diff(np.unwrap(np.arctan2(s.y, s.x))) < 0)
    for p in d.points:
        dx, dy = p.meta["dx"], p.meta["dy"]
        if p.panel == "hyperbolic":
            assert (dx, dy) == pytest.approx((p.y, p.x))          # (2.6) with w_h = 1
        else:
            assert (dx, dy) == pytest.approx((p.y, -p.x))         # (2.12) with w_e = 1


# ------------------------------------------------------------------ Figure 6
def test_figure6_points_are_roots_of_the_equation_that_labels_them():
    d = D.figure6_data()
    A = d.parameters["A"]
    main = d.points_on("main")
    assert [p.label for p in main] == ["T_1", "T~_1", "T~_2", "T_2", "T_3", "T~_3", "T~_4", "T_4"]
    eq_of = {("alpha", 0): "3.10", ("beta", 1): "3.11", ("alpha", 1): "3.12", ("beta", 0): "3.13"}
    for p in main:
        m = p.meta
        a, b, w_e = plain_alpha_beta(m["T"], A)
        lhs = (a if m["curve"] == "alpha" else b) + m["shift"] * math.pi
        assert abs(lhs - w_e * m["T"]) < 1e-12 * lhs                       # a root of its equation
        assert eq_of[(m["curve"], m["shift"] % 2)] == m["equation"]       # the right equation number
        assert m["k"] == m["shift"] // 2
        assert p.label.startswith("T~") == (m["period"] == "4T")          # T~ <-> 4T-periodic
        assert p.x == pytest.approx(w_e * m["T"], rel=1e-14)
    # labelled by Corollary 4.1's numbering
    T, Tt = K.boundary_periods(A, 4)
    for p in main:
        j = int(p.label.split("_")[1]) - 1
        assert p.meta["T"] == pytest.approx((Tt if "~" in p.label else T)[j], rel=1e-15)


def test_figure6_a_wrong_period_is_not_a_root():
    # the check above can fail: a period off by 1e-6 misses its equation by far more than 1e-12
    a, _, w_e = plain_alpha_beta(0.10910018565087798 * (1 + 1e-6), 100.0)
    assert abs(a - w_e * 0.10910018565087798 * (1 + 1e-6)) > 1e-8


# ------------------------------------------------------------------ Figure 7
def test_figure7_curves_are_the_zone_edges():
    d = D.figure7_data(points=200)
    edges = [s for s in d.series if s.role == "edge"]
    assert len(edges) >= 8
    for s in edges:
        n = int(s.name.split()[1])
        eps, mu = np.asarray(s.x), np.asarray(s.y)
        inside = (mu > 0) & (mu < 1)
        lo, hi = K.zone_edges(mu[inside], n)
        ref = lo if s.name.endswith("lower") else hi
        np.testing.assert_allclose(eps[inside], ref, rtol=1e-13)
        # and the edge really is where |tr M| = 2 (plain formula, away from overflow)
        j = np.flatnonzero(inside)[len(mu) // 3]
        tr = K.floquet(eps[j], mu[j]).trace
        assert abs(abs(tr) - 2) < 1e-9 * max(1, abs(tr))


# ------------------------------------------------------------------ Figures 2-5
@pytest.mark.parametrize("n", [2, 3, 4, 5])
def test_figures_2_to_5_points_follow_the_map_31(n):
    d = D.ALL_FIGURES[n]()
    P = d.parameters
    A, T, g, l = P["A"], P["T"], P["g"], P["l"]
    w_h, w_e = math.sqrt((A + g) / l), math.sqrt((A - g) / l)
    Dd = w_h / w_e
    H = np.array([[math.cosh(w_h * T), math.sinh(w_h * T)], [math.sinh(w_h * T), math.cosh(w_h * T)]])
    R = np.array([[math.cos(w_e * T), math.sin(w_e * T)], [-math.sin(w_e * T), math.cos(w_e * T)]])
    pts = {int(p.label): np.array([p.x, p.y]) for p in d.points_on("main")}
    # hyperbolic arc in (x_h, y_h), stretch by D, clockwise rotation by w_e T, contraction by 1/D
    expected = [pts[0]]
    for period in range(P["periods"]):
        z1 = H @ expected[-1]
        z2 = z1 * [1, Dd]
        z3 = R @ z2
        z4 = z3 * [1, 1 / Dd]
        expected += [z1, z2, z3, z4]
    for i, z in pts.items():
        np.testing.assert_allclose(z, expected[i], atol=1e-12)
    last = 4 * P["periods"]
    # the solution closes: 2T-periodic (Fig. 2, 3) or 4T-periodic, not 2T (Fig. 4, 5)
    np.testing.assert_allclose(pts[last], pts[0], atol=1e-12)
    if P["periods"] == 2:
        np.testing.assert_allclose(pts[4], -pts[0], atol=1e-12)
    # the start is (3.19) or (3.22)
    e = math.exp(w_h * T)
    phi0 = math.atan((1 - e) / (1 + e)) if P["equation"] in ("3.10", "3.12") else -math.atan((e + 1) / (e - 1))
    assert math.atan2(pts[0][1], pts[0][0]) == pytest.approx(phi0, abs=1e-14)


# ------------------------------------------------------------------ Figure 8
def test_figure8_kapitza_criterion_tends_to_the_exact_edge():
    mu = np.geomspace(3e-3, 0.3, 25)   # below ~1e-3 the error (4/7) mu^4 meets rounding
    exact, _ = K.zone_edges(mu, 0)
    err = np.abs(ap.kapitza_edge(mu) / exact - 1)
    assert np.all(np.diff(err) > 0)              # shrinks as mu (and eps along the edge) -> 0
    assert err[0] < 1e-9 and err[-1] > 1e-3
    # to leading order the error is (4/7) mu^4
    np.testing.assert_allclose(err[:10] / mu[:10] ** 4, 4 / 7, rtol=0.02)
    # and Kapitza's criterion is the mean square pivot velocity exceeding g l
    A, l, g = 100.0, 1.0, 9.81
    eps_k = ap.kapitza_edge(math.sqrt(g / A))
    T_k = eps_k * math.sqrt(8 * l / A)
    assert ap.mean_square_velocity(A, T_k) == pytest.approx(g * l, rel=1e-12)


def test_figure8_data_has_the_exact_zone_and_the_approximations():
    d = D.figure8_data(points=100)
    lo = d.series_named("exact lower")
    ok = (np.asarray(lo.y) > 0) & (np.asarray(lo.y) < 1)
    np.testing.assert_allclose(np.asarray(lo.x)[ok], K.zone_edges(np.asarray(lo.y)[ok], 0)[0], rtol=1e-13)
    k = d.series_named("error Kapitza")
    assert np.all(np.diff(np.asarray(k.y)) > 0)


# ------------------------------------------------------------------ the command
def test_paper_command_writes_every_promised_file(tmp_path, capsys):
    code, out, err = run(["paper", "--out", str(tmp_path), "--quick", "--quiet"], capsys)
    assert code == 0, err
    for n in range(1, 9):
        with Image.open(tmp_path / f"figure{n}.png") as im:
            assert im.size[0] > 500 and im.size[1] > 300
        ET.parse(tmp_path / f"figure{n}.svg")
        fig = json.loads((tmp_path / f"figure{n}.json").read_text())
        assert fig["figure"] == n and fig["series"]
        with open(tmp_path / f"figure{n}.csv", newline="") as fh:
            rows = list(csv.reader(ln for ln in fh if not ln.startswith("#")))
        assert rows[0] == ["kind", "panel", "name", "index", "x", "y"] and len(rows) > 10
    checks = json.loads((tmp_path / "checks.json").read_text())
    assert checks["passed"] is True and len(checks["checks"]) >= 20
    assert all(c["passed"] and c["status"] == "PASSED" for c in checks["checks"])
    assert {"lemma3.1", "lemma3.2", "thm3.3", "thm3.4", "cor4.1", "sec4.zones"} <= set(checks["claims"])
    html = (tmp_path / "report.html").read_text()
    md = (tmp_path / "report.md").read_text()
    assert html.count("data:image/png;base64,") == 8          # self-contained
    assert "<img" in html and 'src="figure' not in html       # no figure is fetched from disk
    for n in range(1, 9):
        assert f"figure{n}.png" in md
        assert f"Figure {n}." in html
    for name in ("Lemma 3.1", "Lemma 3.2", "Theorem 3.3", "Theorem 3.4", "Corollary 4.1", "stability zones"):
        assert name in html and name in md
    for c in checks["checks"]:                                # every check's verdict is in both reports
        assert c["key"] in md and c["key"] in html
    assert "FAILED" not in md and "All checks passed" in md
    assert "Where the computation differs from the printed paper" in md
    with open(tmp_path / "periods.csv", newline="") as fh:
        prow = list(csv.reader(ln for ln in fh if not ln.startswith("#")))
    assert prow[0][:3] == ["A", "name", "T"] and len(prow) == 1 + 8 * 4
    for row in prow[1:]:   # tr M = +-2 up to the rounding of an edge where the trace has slope ~ e^{w_h T}
        x = float(row[-2])
        assert abs(float(row[-1]) - (-2.0 if row[1].startswith("T~") else 2.0)) < 1e-14 * math.exp(x) * (1 + x)
    assert "PASSED" in out and "FAILED" not in out and "report.html" in out


def test_paper_help_says_what_is_written(capsys):
    code, out, err = run(["paper", "--help"], capsys)
    assert code == 0
    for what in ("figure1.png", ".svg", ".json", "checks.json", "periods.csv", "report.html", "report.md", "--quick"):
        assert what in out


def test_paper_command_exits_1_and_says_so_when_a_check_fails(tmp_path, capsys, monkeypatch):
    from kapitza.paper import checks as C

    failing = C._result("thm3.3-return-matrix", "thm3.3", "a return that does not close", "m", "r", "q",
                        [1.0], ["A=1"], 1e-12)
    monkeypatch.setattr(C, "run_check", lambda i, cases: failing)  # every check fails, in every process
    code, out, err = run(["paper", "--out", str(tmp_path), "--quiet"], capsys)
    assert code == 1 and "FAILED" in out and "FAILED" in err
    md = (tmp_path / "report.md").read_text()
    assert "Some checks FAILED" in md and "thm3.3-return-matrix: FAILED" in md
    assert "FAILED" in (tmp_path / "report.html").read_text()
