"""Zone edges, widths, verdicts and boundary periods against the 50-digit reference.

The reference (``tests/oracle.py``) evaluates the plain trace
``2 cosh x cos u + (D - 1/D) sinh x sin u`` at the exact double inputs, with as many
digits as ``cosh x`` needs, and finds edges with a bracketing solver.
"""
import math

import mpmath as mp
import numpy as np
import pytest

import kapitza as K
import oracle as O

EDGE_RTOL = 1e-13

# mu -> 0, mu -> 1, the switch of the small-mu edge solver at mu = 0.6 (formerly 0.15), and the rest.
MUS = [1e-8, 3e-7, 1e-5, 1e-3, 0.01, 0.05, 0.1, np.nextafter(0.15, 0), 0.15, 0.2, 0.3, 0.45, np.nextafter(0.6, 0),
       0.6, 0.75, 0.9, 0.99, 0.999, 1 - 1e-6]
ZONES = list(range(11))


def _x_of(mu, eps):
    return 2 * math.sqrt(2) * eps * math.sqrt(1 + mu * mu)


# ---------------------------------------------------------------- edges
def test_zone_edges_match_the_reference_to_1e_13():
    rng = np.random.default_rng(20)
    mus = np.array(MUS + list(rng.uniform(0, 1, 12)))
    n = np.array(ZONES)
    lo, hi = K.zone_edges(mus[:, None], n[None, :])
    assert lo.shape == hi.shape == (mus.size, n.size)
    worst = 0.0
    for i, mu in enumerate(mus):
        for j in n:
            for got, upper in ((lo[i, j], False), (hi[i, j], True)):
                err = O.rel_err(got, O.edge_eps(mu, int(j), upper))
                worst = max(worst, err)
                assert err <= EDGE_RTOL, (mu, j, upper, err)
    print(f"worst relative error of zone_edges: {worst:.2e}")


@pytest.mark.slow
def test_zone_edges_match_the_reference_dense_sweep():
    mus = np.concatenate([np.geomspace(1e-10, 0.5, 60), 1 - np.geomspace(1e-9, 0.5, 60)])
    n = np.arange(0, 41)
    lo, hi = K.zone_edges(mus[:, None], n[None, :])
    for i, mu in enumerate(mus):
        for j in n:
            assert O.rel_err(lo[i, j], O.edge_eps(mu, int(j), False)) <= EDGE_RTOL, (mu, j)
            assert O.rel_err(hi[i, j], O.edge_eps(mu, int(j), True)) <= EDGE_RTOL, (mu, j)


def test_zone_edges_scalar_calls_match_the_broadcast_call():
    mus = np.array([1e-6, 0.3, 0.97])
    lo, hi = K.zone_edges(mus[:, None], np.arange(4)[None, :])
    for i, mu in enumerate(mus):
        for n in range(4):
            l1, h1 = K.zone_edges(float(mu), n)
            assert np.ndim(l1) == 0 and l1 == lo[i, n] and h1 == hi[i, n]


def test_edges_are_ordered_and_straddle_G_n():
    # Both edges of zone n lie in n pi < u < (n + 1) pi (docs/theory.md section 5).
    mus = np.linspace(0.01, 0.99, 50)[:, None]
    n = np.arange(12)[None, :]
    lo, hi = K.zone_edges(mus, n)
    q = np.sqrt(1 - mus**2)
    u_lo, u_hi = 2 * np.sqrt(2) * lo * q, 2 * np.sqrt(2) * hi * q
    assert np.all(lo <= hi)  # equal where the zone is thinner than a double's spacing
    assert np.all((lo < hi) | (K.zone_width(mus, n) < 4e-16 * hi))
    assert np.all(u_lo > n * np.pi) and np.all(u_hi < (n + 1) * np.pi)
    assert np.all(hi[:, :-1] < lo[:, 1:])  # zones do not overlap


def test_G_m_curve_is_u_equal_odd_multiple_of_half_pi():
    mu = np.array([1e-6, 0.3, 0.9, 1 - 1e-9])
    for m in range(5):
        eps = K.G_m_curve(mu, m)
        _, u, _ = K.phase_angles(eps, mu)
        np.testing.assert_allclose(u, (2 * m + 1) * np.pi / 2, rtol=4e-16)


# ---------------------------------------------------------------- widths
def _width_tol(mu, n):
    # The width ~ e^{-x} inherits x times the relative rounding of x (its condition number).
    x = _x_of(mu, float(O.edge_eps(mu, n, True)))
    return 1e-13 * max(1.0, x / 100.0)


def test_zone_width_matches_the_reference_where_far_below_eps_resolution():
    mus = [1e-8, 1e-4, 0.01, 0.15, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999]
    worst = worst_log = 0.0
    below_resolution = 0
    for mu in mus:
        n = np.arange(11)
        w = K.zone_width(mu, n)
        lw = K.zone_width(mu, n, log=True)
        for j in n:
            ref = O.zone_width(mu, int(j))
            tol = _width_tol(mu, int(j))
            lo = float(O.edge_eps(mu, int(j), False))
            if ref < mp.mpf(lo) * 2.2e-16:
                below_resolution += 1
            if w[j] >= np.finfo(float).tiny:
                err = O.rel_err(w[j], ref)
                worst = max(worst, err)
                assert err <= tol, (mu, j, err)
            else:
                assert ref < mp.mpf("1e-290")  # underflows; the log form carries it
            lref = mp.log(ref)
            err_log = float(abs(lw[j] - lref))
            worst_log = max(worst_log, err_log / max(1.0, abs(float(lref))))
            assert err_log <= tol + 4 * np.spacing(abs(float(lref))), (mu, j, err_log)
    assert below_resolution > 20  # the test does reach widths a double cannot resolve in eps
    print(f"worst zone_width rel error {worst:.2e}; log form {worst_log:.2e} (relative to |log|)")


def test_zone_width_log_form_far_out_where_the_width_underflows():
    # mu -> 1 and high zones: widths like 1e-5000, beyond any double.
    for mu, n in [(0.99, 100), (0.999, 30), (1 - 1e-6, 1), (1 - 1e-6, 10)]:
        ref = O.zone_width(mu, n)
        assert ref < mp.mpf("1e-400")
        lw = float(K.zone_width(mu, n, log=True))
        lref = float(mp.log(ref))
        assert abs(lw - lref) <= 1e-13 * abs(lref) + 4 * np.spacing(abs(lref)), (mu, n, lw, lref)
        assert K.zone_width(mu, n) == 0.0


def test_zone_width_agrees_with_the_difference_of_the_edges_where_the_zone_is_wide():
    mu = np.linspace(0.05, 0.95, 19)
    for n in range(3):
        lo, hi = K.zone_edges(mu, n)
        # hi - lo carries the rounding of the edges: a few spacings of hi
        slack = 4 * np.spacing(hi)
        assert np.all(np.abs(K.zone_width(mu, n) - (hi - lo)) <= 1e-13 * (hi - lo) + slack)
        assert np.all(np.abs(np.exp(K.zone_width(mu, n, log=True)) - (hi - lo)) <= 1e-13 * (hi - lo) + slack)


# ---------------------------------------------------------------- verdicts
def _check_verdicts(eps, mu):
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    st = K.is_stable(eps, mu)
    zi = K.zone_index(eps, mu)
    fl = K.floquet(eps, mu)
    for i in range(eps.size):
        ref = O.FloquetRef(eps[i], mu[i])
        assert st[i] == ref.stable, (eps[i], mu[i], ref.stable)
        assert fl.stable[i] == ref.stable
        if ref.stable:
            u = 2 * mp.sqrt(2) * mp.mpf(eps[i]) * mp.sqrt(1 - mp.mpf(mu[i]) ** 2)
            assert zi[i] == int(mp.floor(u / mp.pi)) == fl.zone[i]
        else:
            assert zi[i] == -1 == fl.zone[i]
    return st


def test_verdicts_at_random_points():
    rng = np.random.default_rng(7)
    N = 300
    eps = np.exp(rng.uniform(np.log(1e-4), np.log(60.0), N))
    mu = np.concatenate([
        rng.uniform(0.0, 1.0, N // 3),
        np.exp(rng.uniform(np.log(1e-8), 0.0, N // 3)),
        1 - np.exp(rng.uniform(np.log(1e-9), np.log(0.5), N // 6)),
        np.exp(rng.uniform(0.0, np.log(3.0), N - 2 * (N // 3) - N // 6)),
    ])
    mu[mu == 0] = 0.5
    st = _check_verdicts(eps, mu)
    assert 20 < st.sum() < N - 20  # both verdicts are exercised


def test_verdicts_far_out_where_cosh_overflows():
    # x > 710: tr M is beyond a double; every zone is far thinner than a double's spacing.
    rng = np.random.default_rng(8)
    eps = rng.uniform(260.0, 1000.0, 30)
    mu = np.concatenate([rng.uniform(0.0, 1.0, 20), rng.uniform(1.0, 2.0, 10)])
    assert np.all(2 * np.sqrt(2) * eps * np.sqrt(1 + mu**2) > 710)
    st = _check_verdicts(eps, mu)
    assert not st.any()
    # the sign of tr M (which kind of resonance) is still right
    tr = K.floquet(eps, mu).trace
    for i in range(eps.size):
        ref = O.trace_checked(eps[i], mu[i])
        assert np.isinf(tr[i]) or abs(tr[i]) > 1e300
        assert np.sign(tr[i]) == (1 if ref > 0 else -1)


def _near_edge_points(mus, zones, rel, x_max=3000.0):
    """(eps, mu, expected) a relative distance ``rel`` either side of each edge.

    Points inside thin zones are placed at a quarter of the width instead, and left
    out where that is closer to an edge than 1e-13 relative (below what a double
    can decide).
    """
    pts = []
    for mu in mus:
        for n in zones:
            lo, hi = O.edge_eps(mu, n, False), O.edge_eps(mu, n, True)
            if _x_of(mu, float(hi)) > x_max:
                continue
            width = O.zone_width(mu, n)
            for e0, upper in ((lo, False), (hi, True)):
                out = -1 if not upper else 1  # direction out of the zone
                pts.append((float(e0 * (1 + out * rel)), mu, False))
                d = min(rel * e0, width / 4)
                if d >= 1e-13 * e0:
                    e = float(e0 - out * d)
                    assert lo < e < hi
                    pts.append((e, mu, True))
    return pts


@pytest.mark.parametrize("rel", [1e-9, 1e-12])
def test_verdicts_a_hair_either_side_of_every_edge(rel):
    pts = _near_edge_points(MUS, ZONES, rel)
    eps = np.array([p[0] for p in pts])
    mu = np.array([p[1] for p in pts])
    expected = np.array([p[2] for p in pts])
    for e, m, ex in pts:
        assert O.stable(e, m) == ex  # the reference agrees with the geometry
    st = K.is_stable(eps, mu)
    wrong = np.flatnonzero(st != expected)
    assert wrong.size == 0, [(eps[i], mu[i], expected[i]) for i in wrong[:5]]
    assert np.array_equal(K.floquet(eps, mu).stable, expected)
    assert np.array_equal(K.zone_index(eps, mu) >= 0, expected)
    # stability_grid (edges located by search) agrees point by point as well
    for e, m, ex in pts:
        assert K.stability_grid([e], [m])[0, 0] == ex
    assert expected.sum() > 150 and (~expected).sum() > 150


@pytest.mark.slow
def test_verdicts_near_edges_high_zones_and_mu_near_1():
    mus = [1e-8, 1e-3, 0.3, 0.8, 0.99, 0.9999, 1 - 1e-7]
    pts = _near_edge_points(mus, list(range(0, 40, 3)), 1e-10, x_max=20000.0)
    for e, m, ex in pts:
        assert O.stable(e, m) == ex
        assert bool(K.is_stable(e, m)) == ex, (e, m, ex)


# ---------------------------------------------------------------- boundary periods
def test_boundary_periods_reproduce_the_reference_values_of_theory_md():
    T, Tt = K.boundary_periods(100.0, 2, l=1.0, g=9.81)
    for got, ref in ((T[0], 0.10910018565), (Tt[0], 0.20086632659), (Tt[1], 0.50550270119), (T[1], 0.50757833281)):
        assert abs(got - ref) <= 5e-12


@pytest.mark.parametrize("A,l,g", [
    (100.0, 1.0, 9.81), (12.0, 0.3, 9.81), (1e4, 2.5, 9.81), (1e8, 1.0, 9.81), (50.0, 1.0, 1.62),
    (9.81 * (1 + 1e-9), 1.0, 9.81), (float(np.nextafter(9.81, 10)), 1.0, 9.81),  # A -> g: A - g is exact
])
def test_boundary_periods_match_the_reference_to_1e_13(A, l, g):
    count = 10
    T, Tt = K.boundary_periods(A, count, l=l, g=g)
    assert T.shape == Tt.shape == (count,)
    ref = O.boundary_periods(A, count, l=l, g=g)
    for j in range(count):
        assert O.rel_err(T[j], ref[j][0]) <= EDGE_RTOL, (A, j)
        assert O.rel_err(Tt[j], ref[j][1]) <= EDGE_RTOL, (A, j)
    # period_edges gives the same numbers as zone intervals
    for n in range(count):
        lo, hi = K.period_edges(A, n, l, g)
        assert (lo, hi) == ((T[n], Tt[n]) if n % 2 == 0 else (Tt[n], T[n]))


def test_boundary_table_labels_and_order():
    rows = K.boundary_table(100.0, 4)
    names = [r.name for r in rows]
    assert names == ["T_1", "T~_1", "T~_2", "T_2", "T_3", "T~_3", "T~_4", "T_4"]
    Ts = [r.T for r in rows]
    assert Ts == sorted(Ts)
    eqs = [(r.equation, r.k, r.period) for r in rows]
    assert eqs == [("3.10", 0, "2T"), ("3.13", 0, "4T"), ("3.12", 0, "4T"), ("3.11", 0, "2T"),
                   ("3.10", 1, "2T"), ("3.13", 1, "4T"), ("3.12", 1, "4T"), ("3.11", 1, "2T")]
    ref = O.boundary_periods(100.0, 4)
    for r in rows:
        j = r.index - 1
        assert O.rel_err(r.T, ref[j][1 if r.tilde else 0]) <= EDGE_RTOL


def test_amplitude_edges_lie_on_the_reference_edges():
    l, g = 1.0, 9.81
    for T in (0.05, 0.2, 0.7):
        for n in range(4):
            for A_edge, upper in zip(K.amplitude_edges(T, n, l, g), (False, True)):
                # at that A, the half-period T sits exactly on zone n's edge
                mu = mp.sqrt(mp.mpf(g) / mp.mpf(float(A_edge)))
                eps = mp.mpf(T) * mp.sqrt(mp.mpf(float(A_edge)) / (8 * mp.mpf(l)))
                assert abs(eps / O.edge_eps(mu, n, upper) - 1) <= 2e-13, (T, n, upper)
            A_lo, A_hi = K.amplitude_edges(T, n, l, g)
            assert g < A_lo < A_hi


# ---------------------------------------------------------------- margins
def test_stability_margin_against_reference_edges():
    rng = np.random.default_rng(3)
    eps = rng.uniform(0.05, 4.0, 60)
    mu = rng.uniform(0.02, 0.98, 60)
    m = K.stability_margin(eps, mu)
    for i in range(eps.size):
        e = mp.mpf(eps[i])
        u = 2 * mp.sqrt(2) * e * mp.sqrt(1 - mp.mpf(mu[i]) ** 2)
        n0 = int(mp.floor(u / mp.pi))
        best = None
        for n in {max(n0 - 1, 0), n0, n0 + 1}:
            lo, hi = O.edge_eps(mu[i], n, False), O.edge_eps(mu[i], n, True)
            d = min(e - lo, hi - e) / e
            if best is None or d > best[0]:
                best = (d, n, lo, hi)
        d, n, lo, hi = best
        assert m.zone[i] == n and m.stable[i] == (d > 0)
        assert abs(m.margin[i] - d) <= 1e-13
        assert O.rel_err(m.eps_lo[i], lo) <= EDGE_RTOL and O.rel_err(m.eps_hi[i], hi) <= EDGE_RTOL


def _ulps(got, ref):
    return abs(float(mp.mpf(float(got)) - ref)) / float(np.spacing(abs(float(got))))


def test_zone0_lower_edge_within_4_ulp_across_the_solver_switch():
    # The small-mu form (fixed point in z) and Newton on u - alpha meet at mu = 0.6; Newton used
    # to start at 0.15, where its cancellation cost up to 50 ulp.
    mus = np.concatenate([np.linspace(0.1, 0.2, 201), np.linspace(0.55, 0.65, 21), [np.nextafter(0.6, 0), 0.6]])
    lo, _ = K.zone_edges(mus, 0)
    worst = max(_ulps(l, O.edge_eps(float(m), 0, False)) for m, l in zip(mus, lo))
    assert worst <= 4.0, worst


def test_edges_of_zones_0_to_2_within_4_ulp():
    mus = np.linspace(0.01, 0.99, 50)
    for n in range(3):
        lo, hi = K.zone_edges(mus, n)
        for upper, arr in ((False, lo), (True, hi)):
            worst = max(_ulps(e, O.edge_eps(float(m), n, upper)) for m, e in zip(mus, arr))
            assert worst <= 4.0, (n, upper, worst)
