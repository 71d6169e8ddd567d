"""Periodic solutions at the boundary periods (Theorems 3.3-3.4), alpha and beta."""
import math

import mpmath as mp
import numpy as np
import pytest

import ivp_ref
import kapitza as K
import oracle as O

G = 9.81
ULP = np.finfo(float).eps


def _kappa(T, A, l, g):
    wh = math.sqrt((A + g) / l)
    M = K.monodromy(T, A, l, g)
    return float(np.linalg.norm(np.diag([1.0, 1.0 / wh]) @ M @ np.diag([1.0, wh]), 2))


# A near g (20) makes the boundary motions very non-normal: kappa = ||M|| reaches 1e6 by T_3
CASES = [(100.0, 1.0, G), (20.0, 1.0, G), (1e4, 0.25, G), (30.0, 2.0, 1.62)]


# (the third zone's boundary motions at A = 20 amplify rounding by ~1e11 in a period: left out)
@pytest.mark.parametrize("A,l,g,index", [(A, l, g, j) for (A, l, g) in CASES for j in (1, 2, 3)
                                         if not (A == 20.0 and j == 3)])
@pytest.mark.parametrize("tilde", [False, True])
def test_periodic_solution_returns_after_2T_or_flips_sign(A, l, g, index, tilde):
    ps = K.periodic_solution(A, index, tilde=tilde, l=l, g=g)
    T = ps.T
    assert ps.period == (4 * T if tilde else 2 * T) and ps.sign == (-1 if tilde else 1)
    assert ps.boundary.name == ("T~_" if tilde else "T_") + str(index)
    wh = math.sqrt((A + g) / l)
    assert (ps.theta0, ps.dtheta0) == (math.cos(ps.phi0), wh * math.sin(ps.phi0))
    y0 = np.array([ps.theta0, ps.dtheta0])
    # theta(t + 2T) = sign theta(t) over one period, by the exact propagation
    t = np.linspace(0.0, 2 * T, 41)
    th, dth = ps.motion(t)
    th2, dth2 = ps.motion(t + 2 * T)
    kappa = _kappa(T, A, l, g)
    r = np.hypot(th, dth / wh)
    # Rounding (of T, of the start, inside M) leaves M y0 - sign y0 ~ kappa (1 + x) ulps; the
    # partial flow to time t amplifies that by up to e^x D (hyperbolic phase, then the stretch).
    x = wh * T
    D = math.sqrt((A + g) / (A - g))
    tol = 16 * ULP * (1 + x) * kappa * math.exp(x) * D
    assert tol < 1e-5  # the check can fail
    assert np.max(np.hypot(th2 - ps.sign * th, (dth2 - ps.sign * dth) / wh) / r.max()) <= tol
    # ... and the start is an eigenvector of M with eigenvalue sign = +1 (2T) or -1 (4T)
    M = K.monodromy(T, A, l, g)
    My = M @ y0
    tol0 = 16 * ULP * (1 + x) * kappa
    assert math.hypot(My[0] - ps.sign * y0[0], (My[1] - ps.sign * y0[1]) / wh) <= tol0
    # after the full period (4T: two drive periods) the motion is back at the start
    thP, dthP = ps.motion(ps.period)
    assert math.hypot(thP - y0[0], (dthP - y0[1]) / wh) <= (kappa + 2) * tol0


@pytest.mark.parametrize("A,l,g", [CASES[0], CASES[2], (20.0, 1.0, G)])
@pytest.mark.parametrize("index,tilde", [(1, False), (1, True), (2, True), (2, False)])
def test_periodic_solution_is_periodic_for_solve_ivp_too(A, l, g, index, tilde):
    ps = K.periodic_solution(A, index, tilde=tilde, l=l, g=g)
    T = ps.T
    t = np.linspace(0.0, ps.period, 41)
    rtol = 1e-12
    th_i, dth_i = ivp_ref.motion(t, ps.theta0, ps.dtheta0, T, A, l, g, rtol=rtol, atol=1e-16)
    wh = math.sqrt((A + g) / l)
    kappa = _kappa(T, A, l, g)
    back = math.hypot(th_i[-1] - ps.theta0, (dth_i[-1] - ps.dtheta0) / wh)
    # in units of rtol, with the amplification kappa of one period
    assert back / rtol < 20 * kappa, (back / rtol, kappa)
    # the exact motion along the way agrees with the integrator too
    th, dth = ps.motion(t)
    err = np.max(np.hypot(th - th_i, (dth - dth_i) / wh)) / rtol
    assert err < 20 * kappa
    if tilde:  # 4T: at 2T the state is minus the start
        th2, dth2 = ivp_ref.motion([2 * T], ps.theta0, ps.dtheta0, T, A, l, g, rtol=rtol, atol=1e-16)
        assert math.hypot(th2[0] + ps.theta0, (dth2[0] + ps.dtheta0) / wh) / rtol < 20 * kappa


def test_initial_angles_are_3_19_and_3_22():
    for index in (1, 2, 3, 4):
        for tilde in (False, True):
            ps = K.periodic_solution(100.0, index, tilde=tilde)
            x = mp.sqrt(mp.mpf(100.0) + mp.mpf(G)) * mp.mpf(ps.T)
            if ps.boundary.equation in ("3.10", "3.12"):
                ref = mp.atan((1 - mp.exp(x)) / (1 + mp.exp(x)))  # (3.19)
                assert -math.pi / 4 < ps.phi0 < 0
            else:
                ref = -mp.atan((mp.exp(x) + 1) / (mp.exp(x) - 1))  # (3.22)
                assert -math.pi / 2 < ps.phi0 < -math.pi / 4
            assert abs(ps.phi0 - ref) <= 4 * ULP


def test_boundary_periods_solve_their_equations_3_10_to_3_13():
    A, l, g = 100.0, 1.0, G
    w_e = math.sqrt((A - g) / l)
    for row in K.boundary_table(A, 6, l, g):
        u = w_e * row.T
        a, b = K.alpha(row.T, A, l, g), K.beta(row.T, A, l, g)
        k = row.k
        rhs = {"3.10": a + 2 * k * math.pi, "3.11": b + (2 * k + 1) * math.pi,
               "3.12": a + (2 * k + 1) * math.pi, "3.13": b + 2 * k * math.pi}[row.equation]
        assert abs(u - rhs) <= 16 * ULP * u, row
        # the label matches the kind of solution: 2T <=> tr M = 2, 4T <=> tr M = -2
        tr = O.trace(row.eps, row.mu)
        assert abs(tr - (2 if row.period == "2T" else -2)) < 1e-9 * (1 + abs(O.trace(row.eps * 1.001, row.mu)))


def test_alpha_and_beta_shape_and_reference_values():
    A, l, g = 100.0, 1.0, G
    T = np.linspace(1e-3, 1.5, 400)
    a, b = K.alpha(T, A, l, g), K.beta(T, A, l, g)
    D = math.sqrt((A + g) / (A - g))
    assert np.all(0 < a) and np.all(a < b) and np.all(b < math.pi)
    assert np.all(a < 2 * math.atan(D)) and np.all(2 * math.atan(D) < b)
    assert np.all(np.diff(a) > 0) and np.all(np.diff(b) < 0)  # alpha increasing, beta decreasing
    assert np.all(np.diff(a, 2) < 1e-15) and np.all(np.diff(b, 2) > -1e-15)  # concave, convex
    for Ti in (1e-3, 0.1, 0.7, 3.0):
        x = mp.sqrt(mp.mpf(A + g) / l) * mp.mpf(Ti)
        Dm = mp.sqrt(mp.mpf(A + g) / mp.mpf(A - g))
        assert abs(K.alpha(Ti, A, l, g) - 2 * mp.atan(Dm * mp.tanh(x / 2))) <= 8 * ULP
        assert abs(K.beta(Ti, A, l, g) - 2 * mp.atan(Dm / mp.tanh(x / 2))) <= 8 * ULP


def test_periodic_solution_rejects_A_at_most_g():
    for A in (9.81, 5.0):
        with pytest.raises(K.KapitzaValueError, match="A must exceed g"):
            K.periodic_solution(A, 1)
