"""The tower (linked pendulums) in the explorer's API, through real HTTP: ``/api/tower/chart``,
``/api/tower/point`` and ``/api/tower/motion`` answer the library's numbers, and each bad parameter
is a 422 naming it."""
from __future__ import annotations

import httpx
import numpy as np
import pytest

import kapitza
from web_server import running_server


@pytest.fixture(scope="module")
def server():
    with running_server() as (base, _first, _):
        with httpx.Client(base_url=base, timeout=120.0) as client:
            yield client


def test_tower_routes_are_in_the_schema(server):
    paths = server.get("/openapi.json").json()["paths"]
    for p in ("/api/tower/chart", "/api/tower/point", "/api/tower/motion"):
        assert p in paths


def test_tower_band_is_the_library_band(server):
    q = dict(chain="0.2,0.3", masses="1,0.5", links="point", f_min=5, f_max=2000, stroke_min=1e-4, stroke_max=0.1,
             grid=40, points=60)
    d = server.get("/api/tower/chart", params=q).json()
    tower = kapitza.Chain([0.2, 0.3], [1, 0.5], links="point")
    ref = kapitza.tower_curves(tower, frequency_range=(5, 2000), stroke_range=(1e-4, 0.1), points=60, grid=40)
    assert d["n_links"] == 2 and d["links"] == "point"
    np.testing.assert_allclose(d["modal_lengths"], tower.modal_lengths, rtol=1e-15)
    np.testing.assert_array_equal(np.array(d["band"]["stable"], dtype=bool), ref.stable)
    np.testing.assert_allclose(d["band"]["frequency"], ref.frequency, rtol=1e-15)
    for k, mode in enumerate(d["modes"]):
        lo = np.array([np.nan if v is None else v for v in mode["lower"]["frequency"]])
        ok = np.isfinite(ref.frequency_lo[k])
        np.testing.assert_allclose(lo[ok], ref.frequency_lo[k][ok], rtol=1e-15)
    assert 0.05 < np.mean(d["band"]["stable"]) < 0.95


def test_tower_default_window_holds_the_whole_band(server):
    d = server.get("/api/tower/chart", params=dict(chain="0.2,0.2,0.2")).json()
    fr, sr = kapitza.chain.default_window(kapitza.Chain([0.2, 0.2, 0.2]))
    assert d["view"] == dict(f_min=fr[0], f_max=fr[1], stroke_min=sr[0], stroke_max=sr[1])
    assert len(d["band"]["stable"]) == 120 and len(d["modes"]) == 3


def test_tower_point_is_analyze_chain(server):
    for f, stable in ((200.0, True), (60.0, False)):
        r = server.get("/api/tower/point", params=dict(chain="0.2,0.2,0.2", frequency=f, stroke=0.005)).json()
        ref = kapitza.analyze_chain(kapitza.Chain([0.2, 0.2, 0.2]), frequency=f, stroke=0.005)
        assert r["stable"] is stable is ref.stable
        assert r["verdict"] == ref.verdict and r["critical_mode"] == ref.critical_mode
        assert ["verdict", ref.verdict] in r["lines"]


def test_one_link_tower_is_the_single_rod(server):
    r = server.get("/api/tower/point", params=dict(chain="0.3", T=0.004, A=2000.0)).json()
    p = server.get("/api/point", params=dict(rod=0.3, T=0.004, A=2000.0)).json()
    assert r["modal_lengths"] == [pytest.approx(0.2, rel=1e-14)]
    assert r["stable"] == p["stable"]


def test_tower_motion_is_chain_motion(server):
    q = dict(chain="0.2,0.2", frequency=200.0, stroke=0.005, theta0=0.05, periods=40, points_per_period=10)
    m = server.get("/api/tower/motion", params=q).json()
    tower = kapitza.Chain([0.2, 0.2])
    T, A = kapitza.SquareWave().from_rig(200.0, stroke=0.005)
    ref = kapitza.chain_motion(tower, 0.05, T=T, A=A, periods=40, points_per_period=10)
    assert np.shape(m["theta"]) == ref.theta.shape == (2, 401)
    np.testing.assert_allclose(m["theta"], ref.theta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(m["pivot"], ref.pivot, rtol=0, atol=1e-15)
    assert m["toppled"] is False and m["stable"] is True and m["n_links"] == 2


@pytest.mark.parametrize("route, params, name", [
    ("chart", dict(chain="0.2,0.2,0.2,0.2,0.2"), "chain"),
    ("chart", dict(chain="0.2,abc"), "chain"),
    ("point", dict(chain="0.2,50", frequency=200, stroke=0.005), "chain"),
    ("point", dict(chain="0.2,0.2", masses="1,1e6", frequency=200, stroke=0.005), "masses"),
    ("point", dict(chain="0.2,0.2", masses="1", frequency=200, stroke=0.005), "masses"),
    ("point", dict(chain="0.2,0.2", links="chain", frequency=200, stroke=0.005), "links"),
    ("point", dict(chain="0.2,0.2", drive="hexagon", frequency=200, stroke=0.005), "drive"),
    ("point", dict(chain="0.2,0.2", frequency=-5, stroke=0.005), "frequency"),
    ("point", dict(chain="0.2,0.2", stroke=0.005), "frequency"),
    ("chart", dict(chain="0.2,0.2", grid=5000), "grid"),
    ("chart", dict(chain="0.2,0.2", points=1), "points"),
    ("chart", dict(chain="0.2,0.2", f_min=1e7), "f_min"),
    ("chart", dict(chain="0.2,0.2", f_min=100, f_max=50), "f_min"),
    ("chart", dict(chain="0.2,0.2", stroke_max=1e3), "stroke_max"),
    ("chart", dict(chain="0.2,0.2", g=0), "g"),
    ("motion", dict(chain="0.2,0.2", frequency=200, stroke=0.005, theta0=9), "theta0"),
    ("motion", dict(chain="0.2,0.2", frequency=200, stroke=0.005, periods=1e5), "periods"),
    ("motion", dict(chain="0.2,0.2", frequency=200, stroke=0.005, points_per_period=10**6), "points_per_period"),
    ("point", dict(chain="0.2,0.2", frequency=200, stroke=0.005, joint_damping=-0.01), "joint_damping"),
    ("chart", dict(chain="0.2,0.2", joint_damping="nan"), "joint_damping"),
    # a light, short tower with strong friction: a stiff motion, refused by its decay rate
    ("motion", dict(chain="0.01,0.01", masses="0.001,0.001", frequency=200, stroke=0.005, joint_damping=1),
     "joint_damping"),
    ("chart", dict(chain="0.2,0.2", joint_damping=0.002, grid=120), "grid"),
    ("chart", dict(chain="0.2,0.2", joint_damping=0.002, drive="sine", grid=40), "grid"),
])
def test_tower_bad_input_is_a_422_naming_the_parameter(server, route, params, name):
    r = server.get(f"/api/tower/{route}", params=params)
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert name in detail and "\n" not in detail and "Traceback" not in detail


def test_tower_band_of_the_sine_drive(server):
    q = dict(chain="0.2,0.2", drive="sine", grid=16, points=30, f_min=10, f_max=1000, stroke_min=1e-3, stroke_max=0.1)
    d = server.get("/api/tower/chart", params=q).json()
    ref = kapitza.tower_curves(kapitza.Chain([0.2, 0.2]), drive="sine", frequency_range=(10, 1000),
                               stroke_range=(1e-3, 0.1), points=30, grid=16)
    np.testing.assert_array_equal(np.array(d["band"]["stable"], dtype=bool), ref.stable)
    assert d["stroke_coefficient"] == pytest.approx(2 / np.pi ** 2, rel=1e-15)
    r = server.get("/api/tower/chart", params=dict(q, grid=100))
    assert r.status_code == 422 and "grid" in r.json()["detail"] and "80" in r.json()["detail"]


# ---------------------------------------------------------------- joint friction
def test_tower_with_joint_friction_is_the_2n_monodromy(server):
    """With ``joint_damping`` the point's verdict, multipliers and growth are the library's damped
    tower's (the 2N monodromy), and differ from the frictionless tower's."""
    tower = kapitza.Chain([0.2, 0.15], [1.0, 0.5], joint_damping=0.004)
    q = dict(chain="0.2,0.15", masses="1,0.5", T=0.003, A=3000.0)
    r = server.get("/api/tower/point", params=dict(q, joint_damping=0.004)).json()
    ref = tower.analyze(T=0.003, A=3000.0)
    assert r["stable"] is ref.stable is True and r["verdict"] == ref.verdict
    assert r["joint_damping"] == 0.004 and r["method"] == ref.method != "modes"
    assert r["growth"] == pytest.approx(ref.growth, rel=1e-12) and r["growth"] < 0
    assert len(r["multipliers"]) == 4
    free = server.get("/api/tower/point", params=q).json()
    assert free["method"] == "modes" and free["growth"] == 0.0


def test_tower_band_with_joint_friction_is_the_library_band(server):
    q = dict(chain="0.2,0.2", f_min=10, f_max=1000, stroke_min=1e-3, stroke_max=0.1, grid=20, points=40)
    d = server.get("/api/tower/chart", params=dict(q, joint_damping=0.5)).json()
    tower = kapitza.Chain([0.2, 0.2], joint_damping=0.5)
    ref = kapitza.tower_curves(tower, frequency_range=(10, 1000), stroke_range=(1e-3, 0.1), points=40, grid=20)
    assert d["band_method"] == "2N monodromy" and d["joint_damping"] == 0.5
    np.testing.assert_array_equal(np.array(d["band"]["stable"], dtype=bool), ref.stable)
    free = server.get("/api/tower/chart", params=q).json()
    assert free["band_method"] == "modes"
    # strong friction widens the band: the damped upright stands at points where the free one does not
    stable, free_stable = np.array(d["band"]["stable"], dtype=bool), np.array(free["band"]["stable"], dtype=bool)
    assert (stable & ~free_stable).sum() >= 10
    # the default grid of a damped band
    d = server.get("/api/tower/chart", params=dict(chain="0.2,0.2", joint_damping=0.01, points=40)).json()
    assert len(d["band"]["stable"]) == 60


def test_tower_motion_with_joint_friction_is_chain_motion(server):
    q = dict(chain="0.2,0.2", frequency=200.0, stroke=0.005, theta0=0.05, periods=40, points_per_period=10,
             joint_damping=0.01)
    m = server.get("/api/tower/motion", params=q).json()
    tower = kapitza.Chain([0.2, 0.2], joint_damping=0.01)
    T, A = kapitza.SquareWave().from_rig(200.0, stroke=0.005)
    ref = kapitza.chain_motion(tower, 0.05, T=T, A=A, periods=40, points_per_period=10)
    np.testing.assert_allclose(m["theta"], ref.theta, rtol=0, atol=1e-12)
    assert m["joint_damping"] == 0.01
    free = kapitza.chain_motion(kapitza.Chain([0.2, 0.2]), 0.05, T=T, A=A, periods=40, points_per_period=10)
    assert np.max(np.abs(ref.theta - free.theta)) > 1e-4
