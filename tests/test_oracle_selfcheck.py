"""The reference itself: its edges are zeros of the plain trace, and its numbers match docs/theory.md.

Every oracle test leans on ``tests/oracle.py``; these checks make sure it computes
what its docstring says from the plain definitions, independently of kapitza.
"""
import mpmath as mp
import pytest

import oracle as O


@pytest.mark.parametrize("mu", [1e-8, 0.01, 0.3, 0.7, 0.99, 1 - 1e-6])
@pytest.mark.parametrize("n", [0, 1, 2, 5])
def test_oracle_edges_are_zeros_of_the_plain_trace(mu, n):
    # tr M = 2 (-1)^n on the lower edge of zone n and -2 (-1)^n on the upper edge
    # (2T- resp. 4T-periodic solutions, Theorems 3.3-3.4).
    for upper in (False, True):
        e = O.edge_eps(mu, n, upper, dps=60)
        target = 2 if (n % 2 == 0) != upper else -2
        d = O._dps_for(3 * float(e)) + 20
        with mp.workdps(d):
            tr = O.trace(e, mu, dps=d)
            h = e * mp.mpf(10) ** -30
            slope = (O.trace(e + h, mu, dps=d) - tr) / h * e  # d tr / d log eps
            assert abs(tr - target) <= mp.mpf(10) ** -45 * abs(slope), (mu, n, upper)


@pytest.mark.parametrize("mu", [0.2, 0.6, 0.95])
def test_oracle_trace_equals_trace_of_the_mp_monodromy(mu):
    # Two independent routes to tr M: the closed-form trace and the product E(T) H(T).
    l, g = 1.0, 9.81
    A = g / mu**2
    for T in (0.01, 0.3, 1.7):
        eps = T * (A / (8 * l)) ** 0.5
        M = O.monodromy(T, A, l, g, dps=60)
        with mp.workdps(60):
            assert abs(M[0, 0] + M[1, 1] - O.trace(eps, mu, dps=60)) < mp.mpf(10) ** -12 * abs(M[0, 0] + M[1, 1])
            assert abs(mp.det(M) - 1) < mp.mpf(10) ** -40 * (1 + abs(M[0, 0] * M[1, 1]))


def test_oracle_factorisation_of_tr_minus_2():
    # tr M - 2 = -4 (c - D t)(c + t/D) / ((1 - t^2)(1 + c^2)), c = tan(u/2), t = tanh(x/2):
    # the reason the edges solve tan(w/2) = D tanh(x/2).
    with mp.workdps(60):
        for eps, mu in [(0.3, 0.2), (1.1, 0.7), (2.9, 0.45)]:
            e, m = mp.mpf(eps), mp.mpf(mu)
            x = 2 * mp.sqrt(2) * e * mp.sqrt(1 + m * m)
            u = 2 * mp.sqrt(2) * e * mp.sqrt(1 - m * m)
            D = x / u
            c, t = mp.tan(u / 2), mp.tanh(x / 2)
            rhs = -4 * (c - D * t) * (c + t / D) / ((1 - t * t) * (1 + c * c))
            assert abs(O.trace(eps, mu, dps=60) - 2 - rhs) < mp.mpf(10) ** -50


def test_oracle_reproduces_the_reference_values_of_theory_md():
    # docs/theory.md section 5 (l = 1, g = 9.81, A = 100), 11 significant digits.
    (T1, Tt1), (T2, Tt2) = O.boundary_periods(100.0, 2)
    for got, ref in ((T1, "0.10910018565"), (Tt1, "0.20086632659"), (Tt2, "0.50550270119"), (T2, "0.50757833281")):
        assert abs(got - mp.mpf(ref)) <= mp.mpf("5e-12")


def test_oracle_rotation_number_is_continuous_across_zones_and_locked_between():
    mu = 0.4
    for n in range(4):
        lo, hi = O.edge_eps(mu, n, False), O.edge_eps(mu, n, True)
        inside = [lo + (hi - lo) * f for f in (mp.mpf("1e-20"), mp.mpf("0.5"), 1 - mp.mpf("1e-20"))]
        r = [O.rotation_number(e, mu) for e in inside]
        assert abs(r[0] - mp.mpf(n) / 2) < 1e-9 and abs(r[2] - mp.mpf(n + 1) / 2) < 1e-9
        assert n / 2 < r[1] < (n + 1) / 2
        assert O.rotation_number(lo * (1 - mp.mpf("1e-6")), mu) == mp.mpf(n) / 2
        assert O.rotation_number(hi * (1 + mp.mpf("1e-6")), mu) == mp.mpf(n + 1) / 2


def test_oracle_trace_for_A_at_most_g_is_above_2():
    for eps in (1e-3, 0.5, 20.0):
        for mu in (1.0, 1.0 + 1e-12, 1.5, 30.0):
            with mp.workdps(O._dps_point(eps, mu) + 30):
                assert O.trace_checked(eps, mu) > 2
    # free flight (mu = 1): tr M = 2 cosh x + x sinh x
    eps = 0.7
    with mp.workdps(60):
        x = 2 * mp.sqrt(2) * mp.mpf(eps) * mp.sqrt(2)
        assert abs(O.trace(eps, 1.0, dps=60) - (2 * mp.cosh(x) + x * mp.sinh(x))) < mp.mpf(10) ** -45
