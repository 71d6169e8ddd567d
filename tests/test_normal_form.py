"""The period map to third order and its Birkhoff normal form (docs/nonlinear.md).

Evidence: the closed-form Taylor coefficients against mpmath integration of the variational
equations and against finite differences of the exact (Jacobi elliptic) nonlinear flow; the
twist against rotation numbers measured on long exact runs; the Kapitza limit against the
averaged effective potential; symplecticity and oddness as properties.
"""
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import kapitza as K
from kapitza import _normal_form as NFE
from kapitza.motion import measured_rotation_number
from kapitza.motion._elliptic import _phase_step
from kapitza.motion._maps import step_plan


def zone_point(n, mu, frac):
    """A point a fraction ``frac`` of the way across zone ``n`` at this ``mu``."""
    lo, hi = K.zone_edges(mu, n)
    return float(lo + frac * (hi - lo)), mu


# ---------------------------------------------------------------- the Taylor map
def variational_jet_mp(eps, mu):
    """Linear and cubic parts of the period map by mpmath integration of
    th1'' = k th1, th3'' = k th3 - k th1^3/6 over each phase (restarted at the switch)."""
    e, m = mp.mpf(eps), mp.mpf(mu)
    x = 2 * mp.sqrt(2) * e * mp.sqrt(1 + m * m)
    u = 2 * mp.sqrt(2) * e * mp.sqrt(1 - m * m)
    out = []
    for q, p in [(1, 0), (0, 1), (1, 1), (1, -1)]:
        y = [mp.mpf(q), mp.mpf(p), mp.mpf(0), mp.mpf(0)]
        for k in (x * x, -u * u):
            f = mp.odefun(lambda t, y, k=k: [y[1], k * y[0], y[3], k * y[2] - k * y[0] ** 3 / 6], 0, y)
            y = f(1)
        out.append(y)
    L = np.array([[out[0][0], out[1][0]], [out[0][1], out[1][1]]], dtype=float)
    C = []
    for i in (2, 3):
        a, d = out[0][i], out[1][i]
        s1, s2 = out[2][i] - a - d, out[3][i] - a + d
        C.append([a, (s1 - s2) / 2, (s1 + s2) / 2, d])
    return L, np.array(C, dtype=float)


@pytest.mark.parametrize("n, mu, frac", [(0, 0.3, 0.4), (0, 0.05, 0.8), (1, 0.2, 0.5),
                                         pytest.param(2, 0.1, 0.3, marks=pytest.mark.slow)])
def test_taylor_map_matches_mpmath_variational_equations(n, mu, frac):
    eps, mu = zone_point(n, mu, frac)
    with mp.workdps(22):
        L, C = variational_jet_mp(eps, mu)
    jet = K.period_map_taylor(eps, mu)
    np.testing.assert_allclose(jet.linear, L, rtol=1e-10, atol=0)
    np.testing.assert_allclose(jet.cubic, C, rtol=1e-8, atol=1e-12 * np.abs(C).max())


def exact_period_map(eps, mu, q, p):
    """The exact nonlinear period map in the scaled variables (theta, T theta')."""
    T, A = (float(v) for v in K.to_physical(eps, mu))
    th, om = np.asarray(q, float), np.asarray(p, float) / T
    for s, d in step_plan(K.SquareWave(), T, A, 1.0, K.G_EARTH):
        th, om = _phase_step(th, om, s, d)
    return th, om * T


@pytest.mark.parametrize("eps, mu", [(0.5, 0.3), (0.3, 0.1), (0.4, 0.05)])
def test_taylor_map_matches_finite_differences_of_the_exact_flow(eps, mu):
    """(P(h v) - h M v) / h^3 = C(v) + O(h^2), Richardson-extrapolated over three scales."""
    jet = K.period_map_taylor(eps, mu)
    dirs = np.array([(1, 0), (0, 1), (1, 1), (1, -1)], float)
    R = []
    for h in (0.04, 0.02, 0.01):
        Q, P = exact_period_map(eps, mu, h * dirs[:, 0], h * dirs[:, 1])
        lin = jet.linear @ (h * dirs.T)
        R.append(np.stack([(Q - lin[0]) / h**3, (P - lin[1]) / h**3]))
    R1, R2 = (4 * R[1] - R[0]) / 3, (4 * R[2] - R[1]) / 3
    F = (16 * R2 - R1) / 15
    a, d = F[:, 0], F[:, 1]
    s1, s2 = F[:, 2] - a - d, F[:, 3] - a + d
    C = np.stack([a, (s1 - s2) / 2, (s1 + s2) / 2, d], -1)
    np.testing.assert_allclose(C, jet.cubic, rtol=1e-8, atol=1e-10 * np.abs(C).max())


def test_linear_part_is_the_monodromy_matrix():
    T, A = 0.15, 100.0
    eps, mu = K.to_arnold(T, A)
    M = K.monodromy(T, A)
    S = np.diag([1.0, T])  # (theta, theta') -> (theta, T theta')
    np.testing.assert_allclose(K.period_map_taylor(eps, mu).linear, S @ M @ np.linalg.inv(S), rtol=1e-13)


@pytest.mark.parametrize("k", [1.0, -1.0])
def test_series_and_closed_forms_agree_where_they_meet(k):
    """The two evaluations of c, sh, f1, f2, f3 are twins: both sides of |k| = 1."""
    for kk in (k * (1 - 1e-12), k * (1 + 1e-12)):
        a = NFE._entire(np.array(kk))
        with mp.workdps(40):
            b = NFE._entire_mp(mp.mpf(kk))
        np.testing.assert_allclose(np.array(a, float), np.array([float(v) for v in b]), rtol=1e-13)


def test_free_flight_has_no_cubic_terms():
    L, C = NFE._phase_cubic(np.array([0.0, 1e-30, -1e-30]))
    assert np.all(np.abs(C) < 1e-29)
    np.testing.assert_array_equal(L[0], [[1.0, 1.0], [0.0, 1.0]])  # free flight for a unit time


# ---------------------------------------------------------------- properties
arnold_stable = st.tuples(st.integers(0, 2), st.floats(0.02, 0.7), st.floats(0.02, 0.98))


@settings(max_examples=40, deadline=None)
@given(arnold_stable, st.floats(-1, 1), st.floats(-1, 1))
def test_cubic_map_is_symplectic_to_third_order(p, a, b):
    """det DP(v) = 1 + O(|v|^4): tr(adj(M) DC(v)) = 0 for every v."""
    eps, mu = zone_point(*p)
    jet = K.period_map_taylor(eps, mu)
    M, C = jet.linear, jet.cubic
    dq = np.array([3 * a * a, 2 * a * b, b * b, 0.0])
    dp = np.array([0.0, a * a, 2 * a * b, 3 * b * b])
    DC = np.array([[C[0] @ dq, C[0] @ dp], [C[1] @ dq, C[1] @ dp]])
    adj = np.array([[M[1, 1], -M[0, 1]], [-M[1, 0], M[0, 0]]])
    scale = np.abs(adj).max() * np.abs(DC).max() + 1e-300
    assert abs(np.trace(adj @ DC)) <= 1e-10 * scale


@settings(max_examples=30, deadline=None)
@given(arnold_stable)
def test_normal_form_is_area_preserving(p):
    """Re(c21 / lambda) = 0: the z^2 zbar term of an area-preserving map only turns."""
    eps, mu = zone_point(*p)
    nf = K.birkhoff_normal_form(eps, mu)
    assert nf.area_defect <= 1e-9
    assert 0 < nf.w < np.pi


@settings(max_examples=25, deadline=None)
@given(st.floats(0.1, 0.7), st.floats(0.02, 0.5), st.floats(0.001, 0.05), st.floats(0.001, 0.05))
def test_exact_period_map_is_odd(eps, mu, q, p):
    if not K.is_stable(eps, mu):
        return
    a = exact_period_map(eps, mu, q, p)
    b = exact_period_map(eps, mu, -q, -p)
    np.testing.assert_allclose(a, -np.asarray(b), rtol=1e-13, atol=1e-17)


def test_scalar_and_vectorised_calls_agree():
    mu = np.array([0.1, 0.2])
    eps = np.array([[0.3, 0.5], [zone_point(1, 0.1, 0.5)[0], zone_point(1, 0.2, 0.5)[0]]])
    tau = K.twist_coefficient(eps, mu)
    assert tau.shape == (2, 2)
    for i in range(2):
        for j in range(2):
            assert tau[i, j] == K.twist_coefficient(eps[i, j], mu[j])


# ---------------------------------------------------------------- validation
def test_unstable_points_are_refused_by_name():
    with pytest.raises(ValueError, match="eps must lie inside a stability zone.*0.9"):
        K.twist_coefficient([0.5, 0.9], 0.3)
    with pytest.raises(ValueError, match="mu must lie in"):
        K.twist_coefficient(0.5, 1.3)
    with pytest.raises(ValueError, match="eps"):
        K.nonlinear_stability(-1.0, 0.3)
    with pytest.raises(ValueError, match="mu"):
        K.period_map_taylor(0.5, 1.0)
    with pytest.raises(ValueError, match="tol"):
        K.nonlinear_stability(0.5, 0.3, tol=-1)


def test_no_nan_anywhere_in_the_zones():
    mu = np.linspace(0.01, 0.8, 30)
    for n in range(3):
        lo, hi = K.zone_edges(mu, n)
        eps = lo[:, None] + (hi - lo)[:, None] * np.array([1e-3, 0.3, 0.7, 1 - 1e-3])
        nf = K.birkhoff_normal_form(eps, mu[:, None])
        assert np.all(np.isfinite(nf.twist)) and np.all(np.isfinite(nf.resonant_4))
        # zone n: the twist has the sign (-1)^(n+1) (docs/nonlinear.md section 6)
        assert np.all(np.sign(nf.twist) == (-1) ** (n + 1))


# ---------------------------------------------------------------- twist against long runs
def measured_twist(eps, mu, r=0.02, periods=600):
    """Slope of the measured rotation number, Richardson over r and r/2."""
    run = measured_rotation_number(np.asarray(eps)[..., None], np.asarray(mu)[..., None], [r, r / 2],
                                   periods=periods)
    s = (run.rotation_number - run.w / (2 * np.pi)) / run.r**2
    return (4 * s[..., 1] - s[..., 0]) / 3, run


FAST = [(0, 0.3, 0.4), (0, 0.05, 0.6), (1, 0.1, 0.3), (2, 0.1, 0.6)]
# zone 2 at mu = 0.6 is left out: there x = w_h T ~ 12, and the exact map itself (a product of
# e^x-sized stretches) rounds at ~1e-16 e^x per period, which swamps the r^2 effect being measured
SLOW = [(n, mu, frac) for n in range(3) for mu in ((0.05, 0.3, 0.6) if n < 2 else (0.05, 0.2, 0.3))
        for frac in (0.2, 0.45, 0.8)]


def _check_twist(points, periods):
    eps, mu = np.array([zone_point(*p) for p in points]).T
    tau = K.twist_coefficient(eps, mu)
    # the invariant curves of size r must be small compared with the stable region: r ~ 0.02
    # where |tau| is of order 1, smaller where the twist is large (thin zones)
    r = np.minimum(0.02, 0.01 / np.sqrt(np.abs(tau)))
    got = np.array([measured_twist(e, m, ri, periods)[0] for e, m, ri in zip(eps, mu, r)])
    np.testing.assert_allclose(got, tau, rtol=3e-5)


def test_twist_matches_measured_rotation_numbers():
    _check_twist(FAST, 600)


@pytest.mark.slow
def test_twist_matches_measured_rotation_numbers_across_zones_0_to_2():
    _check_twist(SLOW, 2000)


# ---------------------------------------------------------------- the Kapitza limit
def test_kapitza_limit_twist_is_the_averaged_potentials():
    """eps -> 0 along eps = c mu: the effective well is soft (tau < 0) and tau -> averaged."""
    errs = []
    for eps in (0.1, 0.05, 0.025):
        mu = eps / 1.5  # (2/3) eps^2 / mu^2 = 1.5: the drive is 1.5 times the averaging threshold
        tau = K.twist_coefficient(eps, mu)
        avg = K.averaged_twist(eps, mu)
        assert tau < 0 and avg < 0
        errs.append(abs(tau / avg - 1))
    assert errs[-1] < 1e-6
    # along eps = 1.5 mu the error of averaging falls like eps^4
    assert 12.0 < errs[0] / errs[1] < 20.0 and 12.0 < errs[1] / errs[2] < 20.0


# ---------------------------------------------------------------- first-order perturbation theory
@pytest.mark.parametrize("n, mu, frac", [(0, 0.3, 0.4), (0, 0.1, 0.2), (1, 0.05, 0.4), (2, 0.2, 0.7)])
def test_twist_and_1to4_term_are_averages_of_the_quartic_potential(n, mu, frac):
    """beta = int k |xi|^4 ds / (4 m12 sin w), |c03| = |int k xibar^4 ds| / (12 |m12| sin w),
    xi the Floquet solution through (m12, lambda - m11), k(s) = x^2 then -u^2 (docs/nonlinear.md
    section 3): the H4 = k q^4/24 of the Hamiltonian averaged along the linear motion, by quadrature."""
    from scipy.integrate import simpson

    eps, mu = zone_point(n, mu, frac)
    x, u, _ = K.phase_angles(eps, mu)
    M = K.period_map_taylor(eps, mu).linear
    nf = K.birkhoff_normal_form(eps, mu)
    lam = np.exp(1j * nf.w)
    s = np.linspace(0.0, 1.0, 40001)
    xi0, dxi0 = M[0, 1] + 0j, lam - M[0, 0]
    xi1 = xi0 * np.cosh(x * s) + dxi0 * np.sinh(x * s) / x
    a1, b1 = xi0 * np.cosh(x) + dxi0 * np.sinh(x) / x, xi0 * x * np.sinh(x) + dxi0 * np.cosh(x)
    xi2 = a1 * np.cos(u * s) + b1 * np.sin(u * s) / u
    I22 = simpson(x * x * np.abs(xi1) ** 4, x=s) - simpson(u * u * np.abs(xi2) ** 4, x=s)
    I04 = simpson(x * x * np.conj(xi1) ** 4, x=s) - simpson(u * u * np.conj(xi2) ** 4, x=s)
    np.testing.assert_allclose(nf.beta, I22 / (4 * M[0, 1] * np.sin(nf.w)), rtol=1e-9)
    np.testing.assert_allclose(abs(nf.coefficients[3]), abs(I04) / (12 * abs(M[0, 1]) * np.sin(nf.w)), rtol=1e-9)


def test_every_evaluation_path_agrees_with_extended_precision():
    """The twins: composed closed-form jets (double), the averaged quartic potential (double, thin
    zones with x <= 13) and the closed forms in extended precision, against the last in zones 0-2
    (the double-precision rotation angle is good to ~2e-10 in zone 2, ~1e-9 in zone 3)."""
    rng = np.random.default_rng(5)
    for n in range(3):
        mu = rng.uniform(0.01, 0.9, 12)
        lo, hi = K.zone_edges(mu, n)
        eps = lo + rng.uniform(0.02, 0.98, 12) * (hi - lo)
        ok = K.is_stable(eps, mu)
        eps, mu = eps[ok], mu[ok]
        nf, _ = NFE._normal_form(eps, mu)
        ref = [NFE._normal_form_mp(e, m) for e, m in zip(eps, mu)]
        coef = np.array([c for _, c, _ in ref])
        np.testing.assert_allclose(nf.w, [w for w, _, _ in ref], rtol=1e-9)
        np.testing.assert_allclose(nf.coefficients, coef, rtol=1e-8)
        tau = np.array([(c[1] / np.exp(1j * w)).imag / (8 * np.pi * m * m) for w, c, m in ref])
        np.testing.assert_allclose(nf.twist, tau, rtol=1e-8)


@pytest.mark.parametrize("eps", [1e-4, 1e-6, 1e-12, 3.5e-26])
def test_twist_at_small_eps_is_the_averaged_twist(eps):
    """As eps -> 0 the twist tends to the averaged potential's with relative error O(eps^4): below
    eps = 1e-3 the two must agree to rounding. (In double precision the monodromy is I + O(eps^2)
    and the jets' twist was 4e-9 off at eps = 1e-4 and of the wrong sign at 1e-12.)"""
    mu = eps / 10.0
    assert float(K.twist_coefficient(eps, mu)) == pytest.approx(float(K.averaged_twist(eps, mu)), rel=1e-13)
    assert K.nonlinear_stability(eps, mu).kind == "moser"
