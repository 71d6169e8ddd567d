"""Does the upright survive? Inside a zone small motions stay up in the linear and the
nonlinear model; outside one they fall in both. The window test sees excursions between
samples."""
import numpy as np
import pytest

import kapitza as K
from kapitza import KapitzaValueError
from kapitza.drives import as_drive
from kapitza.motion import basin, nonlinear_motion, survival
from kapitza.motion._periods import _IntegratedPeriod, _hermite_peak
from kapitza.motion.basins import survival_chunk

A, L, G = 100.0, 1.0, 9.81


def zone_of(T):
    return K.analyze(T=T, A=A, l=L, g=G)


@pytest.mark.parametrize("T", [0.12, 0.15, 0.19])
@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_inside_zone_0_a_small_tilt_survives(T, model):
    assert zone_of(T).zone == 0
    n = survival([0.01, -0.02], [0.0, 0.05], T, A, L, G, periods=300, tol=0.5, model=model)
    assert np.all(n == 300)


@pytest.mark.parametrize("T", [0.08, 0.25, 0.3, 0.45])
@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_outside_every_zone_the_upright_falls(T, model):
    assert not zone_of(T).stable
    n = survival([0.01, -0.02, 1e-4], [0.0, 0.05, 0.0], T, A, L, G, periods=300, tol=0.5, model=model)
    assert np.all(n < 300)


def test_linear_fall_time_follows_the_floquet_growth():
    """Outside a zone the linear motion grows by exp(growth) per period: from 1e-6 the window
    0.5 is left after about log(0.5/1e-6)/growth periods."""
    T = 0.3
    rep = zone_of(T)
    n = int(survival(1e-6, 0.0, T, A, L, G, periods=1000, tol=0.5, model="linear"))
    expected = np.log(0.5 / 1e-6) / rep.growth
    assert abs(n - expected) < 0.25 * expected + 3


def test_window_is_checked_between_the_samples():
    """Compare with a dense sampling of the exact motion: the counts agree wherever the
    sampled maximum is not within a hair of the window."""
    T, tol, periods = 0.15, 0.3, 6
    rng = np.random.default_rng(8)
    th0 = rng.uniform(-0.3, 0.3, 150)
    om0 = -8.0 * th0 + rng.uniform(-1.5, 1.5, 150)  # about the basin's sheared band
    n = survival(th0, om0, T, A, L, G, periods=periods, tol=tol)
    t = np.linspace(0, 2 * T * periods, 6001)
    th, _ = nonlinear_motion(t[:, None], th0, om0, T, A, L, G)
    out = np.abs(th) > tol
    first = np.where(out.any(axis=0), np.argmax(out, axis=0), t.size)
    dense = np.where(first < t.size, np.floor(t[np.minimum(first, t.size - 1)] / (2 * T)), periods).astype(int)
    peak_gap = np.abs(np.max(np.abs(th), axis=0) - tol)
    agree = (n == dense) | (peak_gap < 1e-3)
    assert agree.all(), np.flatnonzero(~agree)
    assert (n < periods).sum() > 20 and (n == periods).sum() > 20  # both outcomes are exercised


def test_an_excursion_inside_one_elliptic_phase_is_caught():
    """From the upright with a push, the elliptic phase turns round between its ends: |theta|
    at t = 0, T, 2T stays below a window that the turning point exceeds."""
    T = 0.15
    th0, om0 = 0.0, 1.0
    t = np.linspace(0, 2 * T, 20001)
    th, _ = nonlinear_motion(t, th0, om0, T, A, L, G)
    ends = np.abs(nonlinear_motion(np.array([0.0, T, 2 * T]), th0, om0, T, A, L, G)[0])
    peak = np.max(np.abs(th))
    assert T < t[np.argmax(np.abs(th))] < 2 * T
    assert ends.max() < 0.97 * peak  # a check at the switches alone would pass the window below
    tol = 0.5 * (ends.max() + peak)
    assert survival(th0, om0, T, A, L, G, periods=1, tol=tol) == 0
    assert survival(th0, om0, T, A, L, G, periods=1, tol=1.001 * peak) == 1


def test_basin_grid_and_fraction():
    b = basin(0.15, A, L, G, periods=20, tol=0.5, n_theta=31, n_dtheta=21)
    assert b.periods_survived.shape == (21, 31)
    assert b.theta0[0] == -0.5 and b.theta0[-1] == 0.5
    assert b.dtheta0[-1] == pytest.approx(2 * 0.5 / 0.15)
    assert b.survived[10, 15]  # the upright itself
    assert 0.02 < b.fraction < 0.5
    rows = list(b.rows())
    assert len(rows) == 31 * 21 and rows[0][:2] == (-0.5, b.dtheta0[0])
    s = b.summary()
    assert s["fraction"] == b.fraction and s["shape"] == [21, 31]
    lin = basin(0.15, A, L, G, periods=20, tol=0.5, n_theta=31, n_dtheta=21, model="linear")
    # For a window this wide the two basins are close but not identical.
    assert abs(lin.fraction - b.fraction) < 0.3 * b.fraction
    out = basin(0.3, A, L, G, periods=20, tol=0.5, n_theta=30, n_dtheta=30)  # even grid: no upright point
    assert out.fraction == 0.0


def test_basin_workers_agree():
    a = basin(0.15, A, L, G, periods=10, n_theta=40, n_dtheta=40, chunk=300)
    b = basin(0.15, A, L, G, periods=10, n_theta=40, n_dtheta=40, chunk=300, workers=2)
    np.testing.assert_array_equal(a.periods_survived, b.periods_survived)


@pytest.mark.parametrize("kwargs,needle", [
    (dict(tol=4.0), "tol must lie in"),
    (dict(tol=0.0), "tol must lie in"),
    (dict(periods=0), "periods must be an integer >= 1"),
    (dict(model="averaged"), "model must be one of"),
    (dict(damping=-0.5), "damping must be"),
    (dict(damping=float("nan")), "damping must be"),
    (dict(damping=[0.1, 0.2]), "damping must be a single"),
    (dict(zeta=-0.1), "zeta must be"),
    (dict(damping=0.1, zeta=0.1), "not both"),
])
def test_survival_validates(kwargs, needle):
    with pytest.raises(KapitzaValueError, match=needle):
        survival(0.1, 0.0, 0.15, A, **kwargs)


def test_basin_validates():
    with pytest.raises(KapitzaValueError, match="n_theta must be an integer >= 2"):
        basin(0.15, A, n_theta=1)
    with pytest.raises(KapitzaValueError, match="single value"):
        basin([0.15, 0.2], A)


@pytest.mark.parametrize("drive", ["square", "rectangular"])
def test_integrated_path_without_damping_agrees_with_the_exact_one(drive):
    """Twins: the integrated path (DOP853, sampled window) and the exact one (step flows, window
    on the continuous motion) give the same counts wherever the motion does not graze the window."""
    d = as_drive(None) if drive == "square" else K.RectangularWave(0.4)
    T, tol, periods = 0.15, 0.3, 6
    rng = np.random.default_rng(8)
    th0 = rng.uniform(-0.3, 0.3, 150)
    om0 = -8.0 * th0 + rng.uniform(-1.5, 1.5, 150)
    exact = survival(th0, om0, T, A, L, G, periods=periods, tol=tol, drive=d)
    integrated = survival_chunk(th0, om0, _IntegratedPeriod(T, A, L, G, 0.0, d, tol), periods, tol)
    th = np.array([K.simulate(a, b, T, A, L, G, periods=periods, points_per_period=1000, drive=d).theta
                   for a, b in zip(th0, om0)]).T
    gap = np.abs(np.max(np.abs(th), axis=0) - tol)
    agree = (exact == integrated) | (gap < 2e-5)  # the sampled test errs by < 5e-6 of the swing
    assert agree.all(), np.flatnonzero(~agree)
    assert (exact < periods).sum() > 10 and (exact == periods).sum() > 10  # both outcomes are exercised


@pytest.mark.parametrize("drive", ["square", "sine"])
def test_damped_survival_agrees_with_an_independent_integration(drive):
    from ivp_ref import survived_periods

    T, c, tol, periods = 0.15, 1.5, 0.3, 8
    rng = np.random.default_rng(3)
    th0 = rng.uniform(-0.3, 0.3, 12)
    om0 = -8.0 * th0 + rng.uniform(-1.5, 1.5, 12)
    got = survival(th0, om0, T, A, L, G, periods=periods, tol=tol, damping=c, drive=drive)
    ref = [survived_periods(a, b, T, A, periods, tol, c=c, drive=drive, l=L, g=G) for a, b in zip(th0, om0)]
    for n, (m, gap) in zip(got, ref):
        assert n == m or gap < 2e-5, (n, m, gap)
    assert 0 < np.count_nonzero(got == periods) < got.size


def test_damping_keeps_more_of_the_basin():
    """Inside zone 0 viscous damping only drains energy from the small motions: the damped basin
    holds the undamped one's core and more."""
    b0 = basin(0.15, A, L, G, periods=10, tol=0.5, n_theta=15, n_dtheta=15)
    b1 = basin(0.15, A, L, G, periods=10, tol=0.5, n_theta=15, n_dtheta=15, damping=3.0)
    assert b1.c == 3.0 and b1.summary()["c"] == 3.0 and "damping c = 3 1/s" in str(b1)
    assert b1.fraction >= b0.fraction


def test_hermite_peak_finds_the_turning_point():
    x = np.linspace(0, 1, 1001)
    for p0, p1, m0, m1 in [(0.1, 0.1, 0.4, -0.4), (0.0, -0.2, -0.5, 0.3), (0.3, 0.5, 0.2, 0.2), (0.0, 0.0, 0.0, 0.0)]:
        p = ((2 * x**3 - 3 * x**2 + 1) * p0 + (x**3 - 2 * x**2 + x) * m0 + (-2 * x**3 + 3 * x**2) * p1
             + (x**3 - x**2) * m1)
        assert _hermite_peak(np.array(p0), np.array(p1), np.array(m0), np.array(m1)) == pytest.approx(
            np.max(np.abs(p)), abs=1e-6)


def test_integrated_work_is_bounded():
    with pytest.raises(KapitzaValueError, match="KAPITZA_ALLOW_LARGE"):
        survival(np.zeros(10**6), 0.0, 0.15, A, periods=100, damping=0.1)
