"""Invariants, property-based (hypothesis): det M = 1, Corollary 4.1's interlacing, the
symmetries of f and of the angle map, scalar = vectorised, verdict = |tr M| < 2,
stability_grid = is_stable pixel by pixel, rotation number = half the zeros per period."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import kapitza as K
from kapitza import phase_plane as PP

SET = settings(max_examples=60, deadline=None)
ULP = np.finfo(float).eps


def logu(lo, hi):
    """Floats log-uniformly spread over [lo, hi]."""
    return st.floats(math.log(lo), math.log(hi)).map(math.exp)


mu_ell = st.one_of(st.floats(1e-6, 1 - 1e-9), logu(1e-8, 0.5), st.floats(0.5, 1.0, exclude_max=True))
eps_any = logu(1e-4, 50.0)


# ---------------------------------------------------------------- det M = 1
@SET
@given(T=logu(1e-3, 3.0), A=logu(0.5, 1e5), l=logu(0.1, 10.0), g=logu(1.0, 30.0))
def test_det_M_is_1(T, A, l, g):
    M = K.monodromy(T, A, l, g)
    assume(np.all(np.isfinite(M)))
    a, b, c, d = M.ravel()
    # Each entry of E H is a sum of two products and carries rounding relative to their
    # sizes S; ad - bc then cancels terms of size S00 S11 + S01 S10 (~ e^{2x}).
    wh = math.sqrt((A + g) / l)
    x = wh * T
    assume(x < 300)  # the rounding scale below is formed in doubles
    if A > g:
        we = math.sqrt((A - g) / l)
        E = np.abs([[math.cos(we * T), math.sin(we * T) / we], [we * math.sin(we * T), math.cos(we * T)]])
    else:
        v = math.sqrt((g - A) / l) * T
        shc = math.sinh(v) / v if v else 1.0  # sinh(v)/v; free flight (A = g) has v = 0
        E = np.array([[math.cosh(v), T * shc], [abs(g - A) / l * T * shc, math.cosh(v)]])
    H = np.array([[math.cosh(x), math.sinh(x) / wh], [wh * math.sinh(x), math.cosh(x)]])
    S = E @ H
    assert abs((a * d - b * c) - 1.0) <= 16 * ULP * (S[0, 0] * S[1, 1] + S[0, 1] * S[1, 0])
    # and the closed-form trace is the trace of the matrix
    eps, mu = K.to_arnold(T, A, l, g)
    tr = K.floquet(eps, mu).trace
    # (mu = sqrt(g/A) rounded to a double cannot carry A - g when A is within 1e-6 of g)
    if np.isfinite(tr) and abs(A / g - 1) > 1e-6:
        assert abs(tr - (a + d)) <= 64 * ULP * (abs(a) + abs(d) + abs(a * d) ** 0.5 * (1 + math.sqrt((A + g) / l) * T))


# ---------------------------------------------------------------- Corollary 4.1
@SET
@given(ratio=st.one_of(logu(1e-9, 1e-2), logu(1e-2, 1e6)), l=logu(0.05, 20.0), g=logu(0.5, 30.0))
def test_interlacing_of_corollary_4_1(ratio, l, g):
    A = g * (1 + ratio)
    assume(A > g)
    count = 8
    T, Tt = K.boundary_periods(A, count, l=l, g=g)
    # T_1 < T~_1 < T~_2 < T_2 < T_3 < T~_3 < T~_4 < T_4 < ...
    seq = []
    for j in range(count):
        seq += [T[j], Tt[j]] if j % 2 == 0 else [Tt[j], T[j]]
    seq = np.array(seq)
    assert np.all(np.diff(seq) >= 0)
    # strict wherever a double can tell the two edges of a zone apart
    mu = math.sqrt(g / A)
    w = K.zone_width(mu, np.arange(count)) * math.sqrt(8 * l / A)
    for j in range(count):
        lo, hi = seq[2 * j], seq[2 * j + 1]
        if w[j] > 8 * np.spacing(hi):
            assert lo < hi
        if j + 1 < count:
            assert hi < seq[2 * j + 2]  # the gaps between zones are wide
    # and the edges are the solutions of (3.10)-(3.13): 2T edges are T_j, 4T edges T~_j
    rows = K.boundary_table(A, count, l, g)
    assert [r.T for r in rows] == list(seq)


# ---------------------------------------------------------------- f and the angle map
phis = st.floats(-20.0, 20.0)
ds = st.one_of(logu(1e-3, 1e3), st.just(1.0))


@SET
@given(phi=phis, d=ds, k=st.integers(-6, 6))
def test_f_is_even_and_pi_periodic(phi, d, k):
    f0 = PP.f(phi, d)
    assert PP.f(-phi, d) == f0
    # |df/dphi| <= max(1, d^2) / f: the rounding of phi + k pi moves f by that much
    tol = 8 * ULP * (f0 + (1 + abs(phi) + abs(k) * math.pi) * max(1.0, d * d) / f0)
    assert abs(PP.f(phi + k * math.pi, d) - f0) <= tol
    # f is the stretch factor |(cos phi, d sin phi)|, to a few ulps of itself
    assert abs(f0 - math.hypot(math.cos(phi), d * math.sin(phi))) <= 4 * ULP * f0


@SET
@given(phi=phis, d=ds, k=st.integers(-6, 6))
def test_angle_map_symmetries_of_the_paper(phi, d, k):
    p = PP.angle_map(phi, d)
    # the map's slope is up to max(d, 1/d): rounding of phi + k pi is amplified by that much
    scale = 8 * ULP * (1 + abs(phi) + abs(k) * math.pi) * max(d, 1 / d)
    assert PP.angle_map(-phi, d) == -p  # odd
    assert abs(PP.angle_map(phi + k * math.pi, d) - (p + k * math.pi)) <= scale
    assert abs(PP.angle_map(p, 1.0 / d) - phi) <= scale  # phi(phi(.; d); 1/d) = id
    # the image point (cos phi, d sin phi) of the stretch has the angle p (mod 2 pi), in the same half-plane
    diff = math.remainder(math.atan2(d * math.sin(phi), math.cos(phi)) - p, 2 * math.pi)
    assert abs(diff) <= scale
    assert abs(p - phi) < math.pi / 2  # the result stays in the quadrant of phi


# ---------------------------------------------------------------- scalar = vectorised
FUNCS_EPS_MU = [K.is_stable, K.zone_index, K.growth_rate, K.rotation_number]


@settings(max_examples=25, deadline=None)
@given(eps=st.lists(eps_any, min_size=2, max_size=12),
       mu=st.lists(st.one_of(mu_ell, logu(1.0, 5.0)), min_size=2, max_size=12))
def test_scalar_and_vectorised_calls_agree(eps, mu):
    n = min(len(eps), len(mu))
    e = np.array(eps[:n])
    m = np.array(mu[:n])
    for f in FUNCS_EPS_MU:
        vec = f(e, m)
        grid = f(e[:, None], m[None, :])
        for i in range(n):
            s = f(e[i], m[i])
            assert np.ndim(s) == 0
            np.testing.assert_allclose(s, vec[i], rtol=4 * ULP, atol=0)
            np.testing.assert_allclose(grid[i, i], vec[i], rtol=4 * ULP, atol=0)
    F = K.floquet(e, m)
    for i in range(n):
        Fi = K.floquet(e[i], m[i])
        assert Fi.stable == F.stable[i] and Fi.zone == F.zone[i]
        np.testing.assert_allclose(Fi.multipliers, F.multipliers[i], rtol=4 * ULP)
    ell = m < 1
    if ell.any():
        lo, hi = K.zone_edges(m[ell], 3)
        for j, mj in enumerate(m[ell]):
            lj, hj = K.zone_edges(mj, 3)
            assert lj == lo[j] and hj == hi[j]
        wv = K.zone_width(m[ell], 2, log=True)
        for j, mj in enumerate(m[ell]):
            np.testing.assert_allclose(K.zone_width(mj, 2, log=True), wv[j], rtol=4 * ULP)


# ---------------------------------------------------------------- verdict = |tr M| < 2
@settings(max_examples=200, deadline=None)
@given(eps=logu(1e-3, 8.0), mu=st.floats(1e-3, 3.0))
def test_is_stable_agrees_with_the_plain_trace_away_from_edges(eps, mu):
    x = 2 * math.sqrt(2) * eps * math.sqrt(1 + mu * mu)
    if mu < 1:
        u = 2 * math.sqrt(2) * eps * math.sqrt(1 - mu * mu)
        D = x / u
        tr = 2 * math.cosh(x) * math.cos(u) + (D - 1 / D) * math.sinh(x) * math.sin(u)
        size = 2 * math.cosh(x) + (D + 1 / D) * math.sinh(x)
    else:
        v = 2 * math.sqrt(2) * eps * math.sqrt(mu * mu - 1)
        shv = math.sinh(v) / v if v > 0 else 1.0
        tr = 2 * math.cosh(x) * math.cosh(v) + (x + v * v / x) * math.sinh(x) * shv
        size = abs(tr)
    # the plain formula cancels terms of size ~ e^x: only trust it well away from |tr| = 2
    assume(abs(abs(tr) - 2) > 1e-9 * size)
    assert bool(K.is_stable(eps, mu)) == (abs(tr) < 2)
    assert (K.zone_index(eps, mu) >= 0) == (abs(tr) < 2)
    assert bool(K.floquet(eps, mu).stable) == (abs(tr) < 2)


# ---------------------------------------------------------------- stability_grid
def _grid_by_points(eps, mu):
    return K.is_stable(np.asarray(eps)[None, :], np.asarray(mu)[:, None])


def test_stability_grid_is_pixel_exact_on_the_figure_7_window():
    eps = np.linspace(0.0, 4.0, 1025)[1:]
    mu = np.linspace(0.0, 1.0, 513)[1:-1]
    grid = K.stability_grid(eps, mu)
    assert grid.shape == (mu.size, eps.size) and grid.dtype == bool
    ref = _grid_by_points(eps, mu)
    assert np.array_equal(grid, ref)
    assert 0.05 < grid.mean() < 0.6
    out = np.ones_like(grid)
    got = K.stability_grid(eps, mu, out=out)
    assert got is out and np.array_equal(out, ref)


@settings(max_examples=30, deadline=None)
@given(eps=st.lists(st.one_of(logu(1e-4, 12.0), st.floats(0.01, 4.0)), min_size=1, max_size=80),
       mu=st.lists(st.one_of(mu_ell, logu(1.0, 4.0), st.just(1.0)), min_size=1, max_size=30),
       seed=st.integers(0, 2**16))
def test_stability_grid_matches_is_stable_unsorted_and_with_mu_at_least_1(eps, mu, seed):
    eps = np.array(eps)
    np.random.default_rng(seed).shuffle(eps)
    mu = np.array(mu)
    grid = K.stability_grid(eps, mu)
    ref = _grid_by_points(eps, mu)
    assert not grid[mu >= 1].any()
    bad = np.argwhere(grid != ref)
    # documented: identical except within ~1e-13 relative of an edge
    for i, j in bad:
        n = max(int(K.phase_angles(eps[j], mu[i])[1] // math.pi), 0)
        lo, hi = K.zone_edges(mu[i], [max(n - 1, 0), n, n + 1])
        d = np.min(np.abs(np.concatenate([lo, hi]) / eps[j] - 1))
        assert d < 1e-13, (eps[j], mu[i])
    # the out= buffer gives the same image, whatever it held before
    out = np.random.default_rng(seed).random((mu.size, eps.size)) < 0.5
    assert np.array_equal(K.stability_grid(eps, mu, out=out), grid)


def test_stability_grid_rejects_a_wrong_out_buffer():
    with pytest.raises(K.KapitzaValueError, match="out"):
        K.stability_grid([1.0, 2.0], [0.3], out=np.zeros((2, 1), bool))
    with pytest.raises(K.KapitzaValueError, match="out"):
        K.stability_grid([1.0, 2.0], [0.3], out=np.zeros((1, 2), float))


# ---------------------------------------------------------------- rotation number
def _zeros_per_period(eps, mu, periods):
    """Zeros of theta(t) per period, counted phase by phase from the exact solution
    (plain 2x2 matrices in Arnold's time unit, renormalised each period)."""
    x = 2 * math.sqrt(2) * eps * math.sqrt(1 + mu * mu)
    u = 2 * math.sqrt(2) * eps * math.sqrt(1 - mu * mu)
    # time unit T = 1: w_h = x, w_e = u
    H = np.array([[math.cosh(x), math.sinh(x) / x], [x * math.sinh(x), math.cosh(x)]])
    E = np.array([[math.cos(u), math.sin(u) / u], [-u * math.sin(u), math.cos(u)]])
    y = np.array([1.0, 0.37])
    zeros = 0
    for _ in range(periods):
        th, dth = y
        # hyperbolic phase: theta(s) = th cosh(x s) + dth/x sinh(x s), s in (0, 1]
        if dth != 0:
            r = -th * x / dth
            zeros += int(0 < r <= math.tanh(x))
        y = H @ y
        th, dth = y
        # elliptic phase: theta(s) = R cos(u s - p), s in (0, 1]: zeros where u s - p = pi/2 mod pi
        p = math.atan2(dth / u, th)
        zeros += math.floor((u - p - math.pi / 2) / math.pi) - math.floor((-p - math.pi / 2) / math.pi)
        y = E @ y
        y = y / np.hypot(y[0], y[1] / x)
    return zeros / periods


@settings(max_examples=40, deadline=None)
@given(eps=st.floats(0.02, 5.0), mu=st.floats(0.01, 0.98))
def test_rotation_number_is_half_the_mean_number_of_zeros_per_period(eps, mu):
    periods = 800
    rho = float(K.rotation_number(eps, mu))
    z = _zeros_per_period(eps, mu, periods)
    # zeros of theta = half-turns of the phase point: 2 rho per period, up to end effects
    assert abs(z - 2 * rho) <= 3.0 / periods, (eps, mu, z, rho)
