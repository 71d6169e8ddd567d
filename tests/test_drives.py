"""Drives: kinematics, validation, and the exact product engine against the paper's closed forms."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import kapitza
import kapitza.drives as kd
from kapitza._validate import KapitzaValueError
from kapitza.drives._piecewise import floquet_product

SQ = kd.SquareWave()
TWO_STEP = kd.StepDrive([1.0, -1.0], [0.5, 0.5])
HALF = kd.RectangularWave(0.5)


def test_square_kinematics_match_the_pivot_module():
    from kapitza.motion.pivot import pivot_acceleration, pivot_displacement, pivot_velocity, pivot_stroke

    t = np.linspace(-1.0, 3.0, 2001)
    for drive in (SQ, TWO_STEP, HALF):
        np.testing.assert_allclose(drive.acceleration(t, 0.3, 50.0), pivot_acceleration(t, 0.3, 50.0))
        np.testing.assert_allclose(drive.velocity(t, 0.3, 50.0), pivot_velocity(t, 0.3, 50.0), atol=1e-12)
        np.testing.assert_allclose(drive.displacement(t, 0.3, 50.0), pivot_displacement(t, 0.3, 50.0), atol=1e-13)
        assert drive.stroke(0.3, 50.0) == pytest.approx(float(pivot_stroke(0.3, 50.0)), rel=1e-14)


@pytest.mark.parametrize("drive", [kd.SquareWave(), kd.RectangularWave(0.3), kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3]), kd.SineWave()])
def test_kinematics_are_consistent_integrals(drive):
    """v is the integral of a and z of v (trapezoid over a fine grid), both periodic with zero mean."""
    T, A = 0.2, 30.0
    t = np.linspace(0.0, 2 * T, 200001)
    a, v, z = drive.acceleration(t, T, A), drive.velocity(t, T, A), drive.displacement(t, T, A)
    dt = t[1] - t[0]
    v_int = v[0] + np.concatenate([[0], np.cumsum(0.5 * (a[1:] + a[:-1]) * dt)])
    z_int = z[0] + np.concatenate([[0], np.cumsum(0.5 * (v[1:] + v[:-1]) * dt)])
    scale_v, scale_z = A * T, A * T * T
    # a jump of a at a sample costs the trapezoid rule up to A dt per switch
    assert np.max(np.abs(v_int - v)) < 8 * A * dt
    assert np.max(np.abs(z_int - z)) < 8 * A * dt * T
    assert abs(np.trapezoid(v, t)) < 1e-8 * scale_v * T
    assert abs(np.trapezoid(z, t)) < 1e-8 * scale_z * T
    assert drive.stroke(T, A) == pytest.approx(z.max() - z.min(), rel=1e-6)
    assert float(drive.rms_velocity(T, A)) == pytest.approx(np.sqrt(np.trapezoid(v * v, t) / (2 * T)), rel=1e-6)


def test_kapitza_thresholds_of_square_and_sine():
    assert float(SQ.kapitza_eps(0.1)) == pytest.approx(np.sqrt(1.5) * 0.1, rel=1e-15)
    assert float(kd.SineWave().kapitza_eps(0.1)) == pytest.approx(np.pi * 0.1 / 2, rel=1e-15)


def test_from_rig_sine_shaker():
    """A shaker moving 1 cm (amplitude) at 40 Hz: A = a w^2, T = 1/(2 f)."""
    T, A = kd.SineWave().from_rig(40.0, amplitude=0.01)
    assert float(T) == pytest.approx(1 / 80, rel=1e-15)
    assert float(A) == pytest.approx(0.01 * (2 * np.pi * 40) ** 2, rel=1e-14)
    T2, A2 = kd.SineWave().from_rig(40.0, stroke=0.02)
    assert float(A2) == pytest.approx(float(A), rel=1e-15)
    with pytest.raises(KapitzaValueError, match="exactly one"):
        kd.SineWave().from_rig(40.0, stroke=0.02, amplitude=0.01)
    with pytest.raises(KapitzaValueError, match="frequency"):
        kd.SineWave().from_rig(-1.0, stroke=0.02)


@pytest.mark.parametrize("make, match", [
    (lambda: kd.RectangularWave(0.0), "duty"),
    (lambda: kd.RectangularWave(1.0), "duty"),
    (lambda: kd.RectangularWave(float("nan")), "duty"),
    (lambda: kd.RectangularWave([0.3, 0.4]), "duty"),
    (lambda: kd.StepDrive([1, -1], [0.6, 0.6]), "sum to 1"),
    (lambda: kd.StepDrive([1, 1], [0.5, 0.5]), "zero mean"),
    (lambda: kd.StepDrive([1, -1], [1.2, -0.2]), "fractions must each be > 0"),
    (lambda: kd.StepDrive([], []), "levels"),
    (lambda: kd.StepDrive([1], [1]), "at least 2"),
    (lambda: kd.StepDrive([1, -1, 0], [0.5, 0.5]), "same length"),
    (lambda: kd.StepDrive([0, 0], [0.5, 0.5]), "not all be 0"),
    (lambda: kd.StepDrive([1, float("inf")], [0.5, 0.5]), "levels"),
    (lambda: kd.as_drive("sawtooth"), "drive"),
])
def test_bad_drive_definitions_name_the_parameter(make, match):
    with pytest.raises(KapitzaValueError, match=match):
        make()


def test_product_engine_equals_the_closed_forms():
    """The generic product (two steps, 50 % duty) reproduces the paper's closed forms."""
    rng = np.random.default_rng(7)
    eps = np.concatenate([rng.uniform(0.01, 4.0, 20000), 10 ** rng.uniform(-3, 3, 5000)])
    mu = np.concatenate([rng.uniform(0.01, 0.99, 20000), rng.uniform(0.01, 0.99, 5000)])
    ref = SQ._floquet0(eps, mu)
    for drive in (TWO_STEP, HALF):
        f = floquet_product(eps, mu, drive.levels, drive._durations)
        np.testing.assert_array_equal(f.zone, ref.zone)
        np.testing.assert_allclose(f.theta, ref.theta, atol=1e-9)
        ok = np.isfinite(ref.tau)
        assert np.all(np.abs(f.log_tau - ref.log_tau) <= 1e-9 * np.maximum(1, np.abs(ref.log_tau)))
        np.testing.assert_allclose(f.growth, ref.growth, rtol=1e-9, atol=1e-9)
        assert np.all(np.isfinite(f.growth)) and np.all(np.isfinite(f.log_tau))
        assert ok.sum() > 1000


def test_product_engine_far_out_is_finite():
    eps = np.array([100.0, 500.0, 1000.0])
    f = floquet_product(eps, np.full(3, 0.3), TWO_STEP.levels, TWO_STEP._durations)
    ref = SQ._floquet0(eps, np.full(3, 0.3))
    np.testing.assert_allclose(f.growth, ref.growth, rtol=1e-12)
    np.testing.assert_allclose(f.log_tau, ref.log_tau, rtol=1e-12)
    assert np.all(np.isinf(f.tau[1:])) and np.all(np.sign(f.tau) == np.sign(ref.tau))


@pytest.mark.parametrize("n", [0, 1, 2, 3, 4])
def test_sampled_edges_equal_the_closed_forms(n):
    # down to mu = 1e-3, where zone 0's lower edge balances tr M - 2 ~ eps^2 mu^2 against eps^4
    mu = np.r_[np.geomspace(1e-3, 0.1, 60, endpoint=False), np.linspace(0.1, 0.99, 300)]
    lo, hi = TWO_STEP._edges0(mu, n)
    l0, h0 = SQ._edges0(mu, n)
    np.testing.assert_allclose(lo, l0, rtol=4e-15)
    np.testing.assert_allclose(hi, h0, rtol=4e-15)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.05, 0.95), st.floats(0.1, 0.6), st.booleans())
def test_edges_of_general_drives_bound_their_zones(duty, mu, four):
    """The reported edges are unstable, the doubles just inside them lie in zone n."""
    a = 0.1 + 0.2 * duty
    x = -(2 * a - 0.3 + 0.2) / (0.5 - a)  # zero mean
    drive = kd.StepDrive([2, -1, 1, x], [a, 0.3, 0.2, 0.5 - a]) if four else kd.RectangularWave(duty)
    for n in range(3):
        lo, hi = drive._edges0(np.array([mu]), n)
        if not np.isfinite(lo[0]):
            continue
        inside = np.array([np.nextafter(lo[0], np.inf), np.nextafter(hi[0], -np.inf)])
        f = drive._floquet0(inside, np.full(2, mu))
        if lo[0] < hi[0] and f.zone[0] >= 0:
            assert f.zone[0] == n
        # each edge is within 16 ulp (3.6e-15 relative) of where the certified verdict turns
        # unstable (zone 0's lower edge too, where tr M - 2 = O(eps^4): formed without cancellation)
        for e, away in ((lo[0], -np.inf), (hi[0], np.inf)):
            steps = [e]
            for _ in range(16):
                steps.append(np.nextafter(steps[-1], away))
            z = drive._floquet0(np.array(steps), np.full(17, mu)).zone
            assert np.any(z == -1), (n, e, z)


def test_thin_zone_of_an_extreme_duty_cycle():
    """A short strong attracting pulse (duty 0.947) has zones ~450 ulp wide at eps ~ 5.3, where
    tr M cancels 1e12-sized terms: the edges still bound the certified zone."""
    drive = kd.RectangularWave(0.9473483686985562)
    mu = np.array([0.11454894248223582])
    lo, hi = drive._edges0(mu, 2)
    assert hi[0] > lo[0]
    for e, away in ((lo[0], -np.inf), (hi[0], np.inf)):
        steps = [e]
        for _ in range(256):
            steps.append(np.nextafter(steps[-1], away))
        assert np.any(drive._floquet0(np.array(steps), np.full(257, mu[0])).zone == -1)
    mid = 0.5 * (lo + hi)
    assert drive._floquet0(mid, mu).zone[0] == 2


# ---------------------------------------------------------------- where a drive can hold the rod up
def _plain_trace(drive, eps, mu):
    """tr M of the undamped drive by the plain product of its phase matrices (no kapitza code): in
    the time t/T a phase of level s lasts 2 f and has stiffness 8 eps^2 (mu^2 + s), for
    theta'' = (g + A s)/l theta with eps = T sqrt(A/(8l)), mu = sqrt(g/A)."""
    M = np.eye(2)
    for s, f in zip(drive.levels, drive.fractions):
        q, h = 8.0 * eps * eps * (mu * mu + s), 2.0 * f
        w = np.sqrt(abs(q))
        if q > 0:
            P = np.array([[np.cosh(w * h), np.sinh(w * h) / w], [w * np.sinh(w * h), np.cosh(w * h)]])
        elif q < 0:
            P = np.array([[np.cos(w * h), np.sin(w * h) / w], [-w * np.sin(w * h), np.cos(w * h)]])
        else:
            P = np.array([[1.0, h], [0.0, 1.0]])
        M = P @ M
    return float(np.trace(M))


def test_mu_max_is_the_root_of_the_deepest_downward_level():
    assert kd.SquareWave().mu_max == 1.0 and kd.SineWave().mu_max == 1.0
    for d in (0.1, 0.3, 0.5, 0.7, 0.8, 0.95):
        assert kd.RectangularWave(d).mu_max == pytest.approx(np.sqrt(d / (1 - d)), rel=1e-15)
    assert kd.StepDrive([1.0, -3.0, 1.0], [0.5, 0.25, 0.25]).mu_max == pytest.approx(np.sqrt(3.0))


@settings(max_examples=60, deadline=None)
@given(duty=st.floats(0.05, 0.95), over=st.floats(1.0, 3.0), zeta=st.sampled_from([0.0, 0.05, 0.3]))
def test_at_and_beyond_mu_max_the_upright_always_falls(duty, over, zeta):
    """Beyond mu_max the pivot never accelerates down faster than g: unstable at every eps, damped
    or not (kapitza's verdicts, and the plain trace of the undamped drive)."""
    drive = kd.RectangularWave(duty)
    mu = drive.mu_max * over
    eps = np.linspace(1e-3, 6.0, 400)
    assert not np.any(kapitza.is_stable(eps, mu, drive=drive, zeta=zeta))
    assert all(_plain_trace(drive, e, mu) >= 2.0 for e in eps[::20])


@pytest.mark.parametrize("duty", [0.6, 0.8, 0.9])
def test_a_hard_downward_stroke_holds_the_rod_up_below_g(duty):
    """Duty above one half: zone 0 reaches above mu = 1 (A < g), up to mu_max; its edges there are
    the roots of the plain trace (|tr M| = 2), found independently by a scan and bisection."""
    from scipy.optimize import brentq

    drive = kd.RectangularWave(duty)
    assert drive.mu_max > 1.0
    for mu in 1.0 + (drive.mu_max - 1.0) * np.array([0.05, 0.4, 0.7]):  # the zone narrows fast towards mu_max
        lo, hi = kapitza.zone_edges(mu, 0, drive=drive)
        assert 0 < lo < hi < np.inf
        e = np.linspace(lo - 1.013 * (hi - lo), hi + 0.987 * (hi - lo), 601)  # no sample on an edge
        f = np.array([abs(_plain_trace(drive, x, mu)) - 2.0 for x in e])
        roots = [brentq(lambda x: abs(_plain_trace(drive, x, mu)) - 2.0, e[k], e[k + 1])
                 for k in np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))]
        assert len(roots) == 2
        np.testing.assert_allclose(roots, [lo, hi], rtol=1e-8)
        assert kapitza.is_stable(0.5 * (lo + hi), mu, drive=drive)
