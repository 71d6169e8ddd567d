"""Limits: Kapitza's high-frequency criterion (mu -> 0), A -> g (mu -> 1 from both sides)."""
import math

import mpmath as mp
import numpy as np
import pytest

import kapitza as K
import oracle as O

SQRT32 = math.sqrt(1.5)


# ---------------------------------------------------------------- Kapitza: mu -> 0
@pytest.mark.parametrize("mu", [1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8])
def test_zone_0_lower_edge_tends_to_kapitza_criterion(mu):
    # Averaging over the fast drive: stable iff the mean square pivot velocity A^2 T^2 / 12
    # exceeds g l, i.e. eps > sqrt(3/2) mu to leading order (docs/theory.md section 7).
    lo, _ = K.zone_edges(mu, 0)
    assert abs(lo / mu - SQRT32) <= 1.0 * mu**2 + 4 * np.finfo(float).eps * SQRT32
    assert O.rel_err(lo, O.edge_eps(mu, 0, False)) <= 1e-13


def test_kapitza_criterion_in_physical_units():
    for A in (1e4, 1e6, 1e8, 1e10):
        T1 = K.boundary_periods(A, 1)[0][0]
        assert abs(A**2 * T1**2 / (12 * 9.81 * 1.0) - 1) < 10 * 9.81 / A
    # a hair either side of the criterion at small mu
    mu = 1e-6
    assert K.is_stable(SQRT32 * mu * (1 + 1e-6), mu) and not K.is_stable(SQRT32 * mu * (1 - 1e-6), mu)


def test_mu_to_0_edges_converge_to_the_mu_0_reference():
    # mu = 0 (g = 0): D = 1, x = u, tr M = 2 cosh u cos u; every edge but zone 0's lower one stays put
    mus = np.array([1e-3, 1e-5, 1e-8])
    for n in range(6):
        lo, hi = K.zone_edges(mus, n)
        ref_hi = O.edge_eps(0.0, n, True)
        assert np.all(np.abs(hi / float(ref_hi) - 1) <= 2 * mus**2 + 1e-15)
        if n > 0:
            ref_lo = O.edge_eps(0.0, n, False)
            assert np.all(np.abs(lo / float(ref_lo) - 1) <= 2 * mus**2 + 1e-15)
    # growth and rotation number are continuous there too
    for eps in (0.3, 1.7, 2.3):
        r0 = O.FloquetRef(eps, 0.0)
        for mu in (1e-5, 1e-8):
            g = K.growth_rate(eps, mu)
            rho = K.rotation_number(eps, mu)
            assert abs(g - float(r0.growth)) <= 100 * mu**2 + 1e-15  # analytic in mu^2
            assert abs(rho - float(r0.rotation_number)) <= 100 * mu**2 + 1e-15


# ---------------------------------------------------------------- A -> g: mu -> 1
def test_always_unstable_for_mu_at_least_1():
    eps = np.geomspace(1e-6, 1e3, 400)
    for mu in (1.0, float(np.nextafter(1.0, 2.0)), 1.0 + 1e-9, 1.5, 10.0, 1e3):
        assert not K.is_stable(eps, mu).any()
        assert np.all(K.zone_index(eps, mu) == -1)
        F = K.floquet(eps, mu)
        assert not F.stable.any() and np.all(F.rotation_number == 0)
        g = K.growth_rate(eps, mu)
        assert np.all(np.isfinite(g)) and np.all(g > 0)
        assert not K.stability_grid(eps, [mu]).any()


@pytest.mark.parametrize("eps", [0.01, 0.5, 3.0, 100.0, 1000.0])
def test_growth_is_finite_and_continuous_across_mu_equal_1(eps):
    g1 = K.growth_rate(eps, 1.0)
    ref = O.growth(eps, 1.0)  # free flight: tr M = 2 cosh x + x sinh x
    assert O.rel_err(g1, ref) <= 1e-13
    x = 4 * eps  # 2 sqrt2 eps sqrt(1 + mu^2) at mu = 1
    slope = None
    for d in (1e-6, 1e-9, 1e-12):
        below, above = K.growth_rate(eps, 1 - d), K.growth_rate(eps, 1 + d)
        assert np.isfinite(below) and np.isfinite(above)
        # the growth is differentiable in mu at 1 (a function of u^2 = 8 eps^2 (1 - mu^2)):
        # the one-sided differences shrink in proportion to d
        s = max(abs(below - g1), abs(above - g1)) / d
        if slope is None:
            slope = s
            assert slope <= 1 + x * x
        else:
            assert s <= 2 * slope + 1e-14 * g1 / d
        for mu in (1 - d, 1 + d):
            assert O.rel_err(K.growth_rate(eps, mu), O.growth(eps, mu)) <= 1e-13, (eps, mu)
    # the last double below 1: A - g one ulp above zero
    mu = float(np.nextafter(1.0, 0.0))
    assert O.rel_err(K.growth_rate(eps, mu), O.growth(eps, mu)) <= 1e-13
    tr = K.floquet(eps, mu).trace
    if np.isfinite(tr):
        assert O.rel_err(tr, O.trace_checked(eps, mu)) <= 1e-13 * max(1.0, x / 10)


def test_zones_recede_as_A_approaches_g():
    # As mu -> 1 (D -> inf) every zone collapses onto u = (n + 1) pi: in physical units
    # T_{n+1} w_e and T~_{n+1} w_e -> (n + 1) pi, i.e. T_n ~ n pi sqrt(l / (A - g)).
    for d in (1e-2, 1e-4, 1e-8, 1e-12):
        A = 9.81 * (1 + d)
        w_e = math.sqrt(A - 9.81)
        T, Tt = K.boundary_periods(A, 3)
        for j in range(3):
            assert abs(T[j] * w_e - (j + 1) * math.pi) <= 3 * math.sqrt(d)
            assert abs(Tt[j] * w_e - (j + 1) * math.pi) <= 3 * math.sqrt(d)
    # and in Arnold's units the zones run off to eps -> inf
    lo = [float(K.zone_edges(1 - d, 0)[0]) for d in (1e-2, 1e-4, 1e-8, 1e-12)]
    assert np.all(np.diff(lo) > 0) and lo[-1] > 1e5


def test_verdict_text_for_A_at_most_g():
    for kw in (dict(eps=0.5, mu=1.0), dict(eps=0.5, mu=2.0), dict(T=0.2, A=9.81), dict(T=0.2, A=3.0)):
        rep = K.analyze(**kw)
        assert rep.verdict == "always unstable: no elliptic phase (A <= g)"
        assert not rep.stable and rep.zone == -1 and rep.nearest_zone == -1
        assert math.isfinite(rep.growth) and rep.growth > 0 and rep.rotation_number == 0
        assert rep.margin == -math.inf
        d = rep.as_dict()
        assert d["eps_lo"] is None and d["eps_hi"] is None
    # just below A = g the zones exist again and the report says which is nearest
    rep = K.analyze(eps=0.5, mu=1 - 1e-9)
    assert rep.verdict.startswith("unstable: ") and rep.nearest_zone == 0


def test_A_just_above_g_is_handled_without_loss():
    # A - g = 1e-9 g: mu = sqrt(g/A) cannot carry A - g, the physical functions still do
    A = 9.81 * (1 + 1e-9)
    T = K.boundary_periods(A, 2)
    ref = O.boundary_periods(A, 2)
    for j in range(2):
        assert O.rel_err(T[0][j], ref[j][0]) <= 1e-13 and O.rel_err(T[1][j], ref[j][1]) <= 1e-13
    with mp.workdps(50):
        Tlo, Thi = K.period_edges(A, 1)
        assert O.rel_err(Tlo, ref[1][1]) <= 1e-13 and O.rel_err(Thi, ref[1][0]) <= 1e-13
