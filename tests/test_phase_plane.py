"""The phase-plane machinery of sections 2-3: notable points (3.1), phi_h (2.7)/(2.11), G and G^{-1} (2.9)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import kapitza as K
from kapitza import phase_plane as PP

ULP = np.finfo(float).eps
G_ = 9.81


def _H(x, w):
    return np.array([[math.cosh(x), math.sinh(x) / w], [w * math.sinh(x), math.cosh(x)]])


def _E(u, w):
    return np.array([[math.cos(u), math.sin(u) / w], [-w * math.sin(u), math.cos(u)]])


def _points_by_matrices(phi0, T, A, r0, l=1.0, g=G_):
    """The five notable points from the plain phase matrices: hyperbolic variables
    (theta, theta'/w_h) for i = 0, 1, 4, elliptic (theta, theta'/w_e) for i = 2, 3."""
    wh, we = math.sqrt((A + g) / l), math.sqrt((A - g) / l)
    y0 = np.array([r0 * math.cos(phi0), wh * r0 * math.sin(phi0)])
    y1 = _H(wh * T, wh) @ y0
    y3 = _E(we * T, we) @ y1
    scale = [wh, wh, we, we, wh]
    return [(y[0], y[1] / s) for y, s in zip((y0, y1, y1, y3, y3), scale)]


@settings(max_examples=80, deadline=None)
@given(phi0=st.floats(-2 * math.pi, 0.0, exclude_min=True), T=st.floats(0.01, 1.2),
       A=st.floats(10.5, 2000.0), r0=st.floats(0.1, 10.0))
def test_notable_points_equal_matrix_propagation(phi0, T, A, r0):
    P = PP.notable_points(phi0, T, A, r0)
    assert P.r.shape == P.phi.shape == (5,)
    xs, ys = P.cartesian()
    ref = _points_by_matrices(phi0, T, A, r0)
    wh = math.sqrt(A + G_)
    x = wh * T
    for i, (xr, yr) in enumerate(ref):
        rr = math.hypot(xr, yr)
        # the radius through the hyperbolic phase carries cosh x-sized cancellations
        tol = 64 * ULP * (1 + x) * math.cosh(x) * r0 * math.sqrt(A / G_)
        assert abs(xs[i] - xr) <= tol and abs(ys[i] - yr) <= tol, (i, xs[i], xr, ys[i], yr)
        assert abs(P.r[i] - rr) <= tol
    # the angles are continuous lifts: phi_3 = phi_2 - w_e T exactly as (2.13) says
    we = math.sqrt(A - G_)
    assert P.phi[3] == P.phi[2] - we * T
    # the hyperbolic step never crosses an asymptote (cos 2 phi keeps its sign)
    c0, c1 = math.cos(2 * P.phi[0]), math.cos(2 * P.phi[1])
    assert np.sign(c0) == np.sign(c1) or min(abs(c0), abs(c1)) < 1e-9
    # the stretches keep the quadrant: phi_2 = phi(phi_1; D), phi_4 = phi(phi_3; 1/D)
    D = wh / we
    assert P.phi[2] == PP.angle_map(P.phi[1], D)
    assert P.phi[4] == PP.angle_map(P.phi[3], 1 / D)


def test_notable_points_radii_relative_accuracy_when_the_stretch_contracts_hard():
    # A close to g: D = w_h/w_e is large and f(phi_3; 1/D) ~ 1/D near phi_3 = pi/2
    A, T, r0 = 9.81 * 1.0001, 0.3, 1.0
    for phi0 in np.linspace(-1.5, -0.01, 40):
        P = PP.notable_points(phi0, T, A, r0)
        pts = _points_by_matrices(phi0, T, A, r0)
        for i in (2, 3, 4):
            rr = math.hypot(*pts[i])
            # relative to the radius itself, not to r0 or the largest radius
            assert abs(P.r[i] - rr) <= 1e-12 * rr, (phi0, i, P.r[i], rr)


@settings(max_examples=40, deadline=None)
@given(phi0=st.floats(-3.0, 3.0), w=st.floats(0.5, 30.0))
def test_phi_h_solves_the_ode_of_2_7(phi0, w):
    if abs(math.cos(2 * phi0)) < 1e-6:  # on an asymptote: a fixed point, checked separately
        return
    t = np.linspace(0.0, 3.0 / w, 25)
    sol = solve_ivp(lambda s, p: [w * math.cos(2 * p[0])], (0.0, t[-1]), [phi0], method="DOP853",
                    rtol=1e-12, atol=1e-14, t_eval=t)
    got = PP.phi_h(t, phi0, w)
    # in units of the integrator's tolerance (global error over ~3 / w of stiff-ish decay)
    assert np.max(np.abs(got - sol.y[0])) / 1e-12 < 1e3
    # and it is the polar angle of the hyperbolic flow of (cos phi0, sin phi0)
    for ti, gi in zip(t[::6], got[::6]):
        y = _H(w * ti, w) @ np.array([math.cos(phi0), w * math.sin(phi0)])
        assert abs(math.remainder(math.atan2(y[1] / w, y[0]) - gi, 2 * math.pi)) < 1e-12 * (1 + math.exp(2 * w * ti))


def test_phi_h_tends_to_the_unstable_asymptote_and_keeps_fixed_points():
    for phi0 in (-2.0, -1.0, 0.3, 2.5):
        m = round((phi0 - math.pi / 4) / math.pi)
        assert abs(PP.phi_h(50.0, phi0, 3.0) - (math.pi / 4 + m * math.pi)) < 1e-12
    # the unstable asymptotes attract the angle ...
    for a in (math.pi / 4, -3 * math.pi / 4, 5 * math.pi / 4):
        assert abs(PP.phi_h(7.0, a, 2.0) - a) < 1e-15
    # ... the stable one repels it: the rounding of -pi/4 grows like e^{2 w t}
    a = -math.pi / 4
    for t in (0.5, 2.0, 7.0):
        assert abs(PP.phi_h(t, a, 2.0) - a) <= 2 * ULP * math.exp(4.0 * t)


@settings(max_examples=60, deadline=None)
@given(phi=st.floats(-math.pi / 4, math.pi / 4, exclude_min=True, exclude_max=True))
def test_G_inverse_inverts_G_on_branch_0(phi):
    if abs(abs(phi) - math.pi / 4) < 1e-12:
        return
    s = PP.G(phi)
    assert abs(PP.G_inverse(s, 0) - phi) <= 8 * ULP * (1 + abs(s)) + 1e-15
    assert abs(PP.G(PP.G_inverse(s, 0)) - s) <= 1e-12 * (1 + abs(s))


@settings(max_examples=60, deadline=None)
@given(phi=st.floats(-3 * math.pi / 4, -math.pi / 4, exclude_min=True, exclude_max=True))
def test_G_inverse_inverts_G_on_branch_minus_1(phi):
    if min(abs(phi + math.pi / 4), abs(phi + 3 * math.pi / 4)) < 1e-12:
        return
    s = PP.G(phi)
    assert abs(PP.G_inverse(s, -1) - phi) <= 8 * ULP * (1 + abs(s)) + 1e-15
    assert abs(PP.G(PP.G_inverse(s, -1)) - s) <= 1e-12 * (1 + abs(s))


def test_G_is_a_primitive_of_1_over_cos_2phi_and_gives_2_10():
    phi = np.array([-2.0, -1.0, -0.5, 0.1, 0.6])
    h = 1e-6
    dG = (PP.G(phi + h) - PP.G(phi - h)) / (2 * h)
    np.testing.assert_allclose(dG, 1 / np.cos(2 * phi), rtol=1e-8)
    # (2.10): phi_h(T) = G^{-1}(w_h T + G(phi_0)) on the branch of phi_0
    for phi0, branch in ((-0.5, 0), (0.3, 0), (-1.0, -1), (-2.0, -1)):
        w, T = 4.0, 0.2
        assert abs(PP.phi_h(T, phi0, w) - PP.G_inverse(w * T + PP.G(phi0), branch)) < 1e-13


def test_G_rejects_the_asymptotes():
    for a in (math.pi / 4, -math.pi / 4, -3 * math.pi / 4):
        with pytest.raises(K.KapitzaValueError, match="phi"):
            PP.G(a)


def test_h_symmetry_and_monotonicity_of_lemma_3_1():
    phi = np.linspace(0.0, math.pi / 4, 200)
    for D in (1.5, 4.0):
        hv = PP.h(phi, D)
        np.testing.assert_allclose(PP.h(-phi, D), hv, rtol=0, atol=0)  # even
        np.testing.assert_allclose(PP.h(phi + math.pi, D), hv, rtol=1e-12, atol=1e-15)  # pi-periodic
        np.testing.assert_allclose(hv, np.abs(np.cos(2 * phi)) / PP.f(phi, D) ** 2, rtol=1e-13, atol=1e-16)
        # strictly monotone on [0, pi/4] (down) and [pi/4, pi/2] (up): what Lemma 3.1 uses
        assert np.all(np.diff(hv) < 0)
        assert np.all(np.diff(PP.h(phi + math.pi / 4, D)) > 0)
        # not pi/2-periodic unless D = 1 (the paper says pi/2): h(0) = 1, h(pi/2) = 1/D^2
        assert PP.h(0.0, D) == 1.0 and abs(PP.h(math.pi / 2, D) - 1 / D**2) < 1e-15
    np.testing.assert_allclose(PP.h(phi + math.pi / 2, 1.0), PP.h(phi, 1.0), atol=1e-15)
