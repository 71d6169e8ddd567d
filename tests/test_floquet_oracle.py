"""Floquet data (trace, growth, rotation number, multipliers, monodromy, report) against the reference."""
import math

import mpmath as mp
import numpy as np
import pytest

import kapitza as K
import oracle as O

GROWTH_RTOL = 1e-10
ROTATION_RTOL = 1e-12
TRACE_RTOL = 1e-11  # where no condition number is at hand (moderate x, away from tr = 0)


def _points(seed, N, eps_lo=1e-6, eps_hi=1000.0):
    """Generic points: eps log-uniform, mu spread over (0, 1), towards 0, towards 1, and beyond 1."""
    rng = np.random.default_rng(seed)
    eps = np.exp(rng.uniform(np.log(eps_lo), np.log(eps_hi), N))
    k = N // 4
    mu = np.concatenate([
        rng.uniform(0.0, 1.0, k),
        np.exp(rng.uniform(np.log(1e-8), 0.0, k)),
        1 - np.exp(rng.uniform(np.log(1e-9), np.log(0.5), k)),
        np.exp(rng.uniform(0.0, np.log(5.0), N - 3 * k)),
    ])
    mu[mu <= 0] = 0.5
    return eps, mu


def _rel(value, ref):
    with mp.workdps(60):
        if ref == 0:
            return abs(float(value))
        return float(abs(mp.mpf(float(value)) - ref) / abs(ref))


def _trace_condition(eps, mu, tr):
    """|d log tr M / d log eps| from the reference (a float)."""
    with mp.workdps(O._dps_point(eps, mu) + 30):
        h = mp.mpf(10) ** -25
        tr2 = O.trace(mp.mpf(eps) * (1 + h), mu, dps=O._dps_point(eps, mu) + 30)
        return float(abs((tr2 - tr) / (h * tr)))


def test_growth_rate_rotation_number_and_trace_at_generic_points():
    eps, mu = _points(11, 500)
    F = K.floquet(eps, mu)
    g = K.growth_rate(eps, mu)
    rho = K.rotation_number(eps, mu)
    assert np.array_equal(g, F.growth) and np.array_equal(rho, F.rotation_number)
    worst = {"growth": 0.0, "rotation": 0.0, "trace": 0.0}
    n_stable = 0
    for i in range(eps.size):
        r = O.FloquetRef(eps[i], mu[i])
        n_stable += r.stable
        eg = _rel(g[i], r.growth)
        er = _rel(rho[i], r.rotation_number)
        assert eg <= GROWTH_RTOL, (eps[i], mu[i], g[i], r.growth)
        assert er <= ROTATION_RTOL, (eps[i], mu[i], rho[i], r.rotation_number)
        worst["growth"] = max(worst["growth"], eg)
        worst["rotation"] = max(worst["rotation"], er)
        if np.isfinite(F.trace[i]):
            et = _rel(F.trace[i], r.trace)
            # tr M ~ e^x sin(u - gamma): its relative condition number d log tr / d log eps
            # is ~ x, and large where tr M passes through 0; rounding eps into x and u costs that
            cond = _trace_condition(eps[i], mu[i], r.trace)
            assert et <= 16 * np.finfo(float).eps * (1 + cond), (eps[i], mu[i], et, cond)
            worst["trace"] = max(worst["trace"], et)
            worst["trace/cond"] = max(worst.get("trace/cond", 0.0), et / (1 + cond))
        else:
            assert abs(r.trace) > mp.mpf("1.7e308") and np.sign(F.trace[i]) == mp.sign(r.trace)
    assert 30 < n_stable < 470
    print("worst relative errors:", {k: f"{v:.2e}" for k, v in worst.items()})


def test_growth_rate_far_out_where_cosh_overflows():
    # eps up to 1000 (x up to ~4000): tr M ~ e^4000, the growth ~ x stays exact.
    rng = np.random.default_rng(12)
    eps = rng.uniform(250.0, 1000.0, 40)
    mu = np.concatenate([rng.uniform(0.0, 1.0, 25), rng.uniform(1.0, 3.0, 15)])
    g = K.growth_rate(eps, mu)
    assert np.all(np.isfinite(g)) and np.all(g > 700)
    for i in range(eps.size):
        assert _rel(g[i], O.growth(eps[i], mu[i])) <= GROWTH_RTOL, (eps[i], mu[i])
    # and the rotation number is locked to a multiple of 1/2
    rho = K.rotation_number(eps[:25], mu[:25])
    for i in range(25):
        r = O.rotation_number(eps[i], mu[i])
        assert 2 * r == int(2 * r) and _rel(rho[i], r) <= 1e-15


def test_growth_rate_and_rotation_number_as_eps_goes_to_0():
    # tr M -> 2: the growth ~ 4 sqrt(2) eps mu and the rotation number vanish; both keep
    # their relative accuracy (the factored trace subtracts no O(1) terms).
    for eps in (1e-3, 1e-5, 1e-8):
        for mu in (1e-6, 1e-3, 0.3, 0.9, 0.999999, 1.0, 1.5):
            r = O.FloquetRef(eps, mu)
            assert _rel(K.growth_rate(eps, mu), r.growth) <= 1e-13, (eps, mu)
            assert _rel(K.rotation_number(eps, mu), r.rotation_number) <= 1e-13, (eps, mu)


def test_growth_near_edges_is_small_and_accurate_to_its_conditioning():
    # growth ~ sqrt(2 |tau -+ 1|) near an edge: relative error grows like 1/distance.
    for mu in (0.05, 0.4, 0.9):
        for n in range(4):
            for upper in (False, True):
                e0 = O.edge_eps(mu, n, upper)
                for rel in (1e-6, 1e-10):
                    e = float(e0 * (1 + rel if upper else 1 - rel))
                    r = O.FloquetRef(e, mu)
                    assert not r.stable
                    assert _rel(K.growth_rate(e, mu), r.growth) <= 1e-15 / rel + 1e-12, (mu, n, upper, rel)


def test_floquet_multipliers():
    eps, mu = _points(13, 120, eps_hi=30.0)
    F = K.floquet(eps, mu)
    lam = K.floquet_multipliers(eps, mu)
    assert lam.shape == eps.shape + (2,) and np.array_equal(lam, F.multipliers)
    for i in range(eps.size):
        l1, l2 = lam[i]
        assert abs(l1) >= abs(l2)
        if F.stable[i]:
            assert abs(abs(l1) - 1) < 1e-15 and abs(abs(l2) - 1) < 1e-15
            assert abs(l1 - np.conj(l2)) < 1e-15
            np.testing.assert_allclose(np.angle(l1) % (2 * np.pi), (2 * np.pi * F.rotation_number[i]) % (2 * np.pi),
                                       atol=1e-12)
        else:
            assert l1.imag == 0 and l2.imag == 0
            np.testing.assert_allclose(l1.real * l2.real, 1.0, rtol=1e-14)
            np.testing.assert_allclose(abs(l1.real), math.exp(F.growth[i]), rtol=1e-14)
        # lambda_1 + lambda_2 = tr M
        r = O.trace_checked(eps[i], mu[i])
        if abs(r) < 1e300:
            assert _rel((l1 + l2).real, r) <= TRACE_RTOL + 1e-15 / max(1e-300, float(abs(r)))


def test_monodromy_against_the_mp_matrix_product():
    rng = np.random.default_rng(14)
    for _ in range(25):
        A = float(np.exp(rng.uniform(np.log(10.0), np.log(1e4))))
        T = float(np.exp(rng.uniform(np.log(1e-3), np.log(2.0))))
        l = float(rng.uniform(0.2, 3.0))
        M = K.monodromy(T, A, l)
        assert M.shape == (2, 2)
        R, E, H = O.monodromy(T, A, l, 9.81, factors=True)
        x = math.sqrt((A + 9.81) / l) * T
        u = math.sqrt((A - 9.81) / l) * T
        # entry (i, j) sums E[i, k] H[k, j]: rounding is relative to the sizes of those terms,
        # and the rounding of the phase angles x, u costs x and u ulps in cosh, cos, ...
        rtol = 2.2e-16 * (8 + 2 * (x + u))
        with mp.workdps(50):
            for i in range(2):
                for j in range(2):
                    scale = abs(E[i, 0] * H[0, j]) + abs(E[i, 1] * H[1, j])
                    assert abs(mp.mpf(float(M[i, j])) - R[i, j]) <= rtol * scale, (T, A, l, i, j)


def test_monodromy_for_A_at_most_g_is_hyperbolic_then_hyperbolic_or_free():
    T, l, g = 0.4, 1.0, 9.81
    for A in (9.81, 5.0):
        M = K.monodromy(T, A, l, g)
        assert abs(np.linalg.det(M) - 1) < 1e-13
        tr = np.trace(M)
        eps, mu = K.to_arnold(T, A, l, g)
        with mp.workdps(60):
            assert _rel(tr, O.trace(float(eps), float(mu))) <= 1e-13
        assert tr > 2


@pytest.mark.parametrize("eps,mu", [(0.5, 0.3), (0.05, 0.3), (1.2, 0.6), (2.27, 0.1), (40.0, 0.5),
                                    (0.7, 1.0), (0.7, 1.3), (300.0, 0.4)])
def test_analyze_report_against_the_reference(eps, mu):
    rep = K.analyze(eps=eps, mu=mu)
    r = O.FloquetRef(eps, mu)
    assert rep.stable == r.stable
    assert _rel(rep.growth, r.growth) <= GROWTH_RTOL
    assert _rel(rep.rotation_number, r.rotation_number) <= ROTATION_RTOL
    if np.isfinite(rep.trace):
        assert _rel(rep.trace, r.trace) <= TRACE_RTOL
    else:
        assert np.sign(rep.trace) == mp.sign(r.trace)
    if mu >= 1:
        assert rep.verdict.startswith("always unstable") and rep.zone == -1
    elif r.stable:
        assert rep.verdict == f"stable (zone {rep.zone})"
    elif rep.nearest_zone == 0 and rep.eps <= rep.eps_lo:
        # below zone 0 the upright simply falls (a real multiplier > 1): said in those words
        assert r.trace > 0 and rep.verdict.startswith("unstable: the drive is too weak")
    else:
        kind = "2T" if r.trace > 0 else "4T"
        assert rep.verdict.startswith(f"unstable: parametric resonance, {kind}-type")
    assert (rep.trace_margin > 0) == r.stable


def test_analyze_physical_parameters_agree_with_arnold_form():
    rep = K.analyze(T=0.15, A=100.0)
    eps, mu = K.to_arnold(0.15, 100.0)
    rep2 = K.analyze(eps=float(eps), mu=float(mu))
    assert rep.stable and rep2.stable and rep.zone == rep2.zone == 0
    assert rep.growth == rep2.growth and rep.trace == rep2.trace
    # the zone as intervals of T (at this A) is (T_1, T~_1) of theory.md
    assert abs(rep.T_lo - 0.10910018565) < 5e-12 and abs(rep.T_hi - 0.20086632659) < 5e-12
    assert rep.A_lo < 100.0 < rep.A_hi


@pytest.mark.slow
def test_growth_rotation_and_verdicts_dense_sweep():
    eps, mu = _points(99, 4000, eps_lo=1e-8, eps_hi=1000.0)
    F = K.floquet(eps, mu)
    for i in range(eps.size):
        r = O.FloquetRef(eps[i], mu[i])
        assert F.stable[i] == r.stable, (eps[i], mu[i])
        assert _rel(F.growth[i], r.growth) <= GROWTH_RTOL, (eps[i], mu[i])
        assert _rel(F.rotation_number[i], r.rotation_number) <= ROTATION_RTOL, (eps[i], mu[i])
