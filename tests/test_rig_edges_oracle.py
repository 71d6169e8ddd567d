"""The rig's intervals -- zone edges along A at fixed T (``amplitude_edges``) and along the
frequency at fixed stroke (``analyze``'s ``frequency_lo``, ``frequency_hi``) -- against the
50-digit reference (``tests/oracle.py``: ``amplitude_edge``, ``frequency_edge``, which solve
the plain edge equations with the digits their cancellation as ``u -> 0`` costs).

Zone 0's lower edge is the hard one: its equation's terms agree to ``O(u^2)`` relative, and at
small ``kappa = 2 g T^2 / l`` (small ``eps`` along the frequency) the plain solve lost
``eps_machine / u^2``. Bounds reached, array path and scalar twin alike: amplitude edges within
5 ulp of the reference (4.3 seen), the lower frequency edge within 6 ulp on zone 0 (5.6 seen:
``u`` formed from the rounded eps carries 3 ulp, and ``f mu / mu_a`` two more roundings) and
within 64 ulp on zones 1-2 (1 seen; that edge is flatter in mu) and, everywhere, the edge in eps at the returned mu
within 4 ulp of eps (the backward error; the forward error of an edge that is flat in mu is
that divided by its slope). And every interval agrees with the verdict.
"""
import math

import mpmath as mp
import numpy as np
import pytest

import kapitza as K
import oracle as O
from kapitza import _point as P
from kapitza import _square as S
from kapitza import analysis as An

G = 9.81


def ulps(got, ref):
    """|got - ref| in units of got's last place (ref an mpf)."""
    got = float(got)
    return float(abs(mp.mpf(got) - ref) / mp.mpf(float(np.spacing(abs(got)))))


def _T_of_kappa(kappa, l=1.0, g=G):
    return math.sqrt(kappa * l / (2.0 * g))


# rigs: ordinary ones, and T at kappa = 2 g T^2 / l from 1e-6 down to 1e-30 and beyond
_rng = np.random.default_rng(41)
RIGS = ([(T, l, G) for T in (1e-3, 0.01, 0.05, 0.15, 0.5, 2.0) for l in (1.0, 0.3)]
        + [(_T_of_kappa(k), 1.0, G) for k in (1e-6, 1e-8, 1e-10, 1e-15, 1e-20, 1e-25, 1e-30, 1e-100, 1e-299)]
        + [(float(10 ** _rng.uniform(-6, 0.5)), float(10 ** _rng.uniform(-2, 1)), float(_rng.uniform(1.0, 25.0)))
           for _ in range(12)]
        + [(1e-200, 1e-100, G), (1e-5, 1e-12, 1.62)])


@pytest.mark.parametrize("T, l, g", RIGS)
def test_amplitude_edges_within_5_ulp_of_the_reference(T, l, g):
    ns = np.arange(3)
    lo, hi = K.amplitude_edges(T, ns, l, g)
    for n in ns:
        twin = P.amplitude_edges(T, int(n), l, g)
        for upper, got, got_twin in ((False, lo[n], twin[0]), (True, hi[n], twin[1])):
            ref = O.amplitude_edge(T, int(n), l, g, upper)
            assert ulps(got, ref) <= 5.0, (T, l, g, n, upper, float(got), ref)
            assert ulps(got_twin, ref) <= 5.0, (T, l, g, n, upper, got_twin, ref)
        assert g < lo[n] <= hi[n]  # (equal where the zone is thinner than an ulp of A)


def _frequency_cases():
    eps = np.concatenate([np.geomspace(1e-9, 4.0, 30), [3.5355339059327373e-26, 1e-300, 0.31, 0.62, 0.9]])
    return [(float(e), n) for e in eps for n in (0, 1, 2)]


@pytest.mark.parametrize("eps, n", _frequency_cases())
def test_frequency_edges_against_the_reference(eps, n):
    mu, T = 0.3, 0.15  # the frequency interval scales with f mu; the edges in mu do not depend on them
    f = 0.5 / T
    got_arr = S.rig_margins(eps, mu, n, T, 1.0)
    try:
        got_pt = P.square_rig_margins(eps, mu, n, T, 1.0)
    except P.Careful:
        got_pt = None
    mu_a, mu_b = O.frequency_edge(eps, n, False), O.frequency_edge(eps, n, True)
    for got in (got_arr, got_pt):
        if got is None:
            continue
        if mu_a is None:  # the lower edge stays above eps at every mu: no frequency reaches the zone
            assert "frequency_lo" not in got
            continue
        ref_lo = f * mp.mpf(mu) / mu_a
        assert ulps(got["frequency_lo"], ref_lo) <= (6.0 if n == 0 else 64.0), (eps, n, got, ref_lo)
        # backward error: the zone's lower edge at the mu found is eps to a few ulp
        m = mp.mpf(f) * mu / mp.mpf(got["frequency_lo"])
        if m > 1e-280:
            assert ulps(eps, O.edge_eps(m, n, False)) <= 4.0 + 2.0 * _slope_ulps(m, n, False), (eps, n)
        if mu_b is None:  # the upper edge stays above eps: the zone is open towards high frequencies
            assert got["frequency_hi"] == math.inf
        else:
            m = mp.mpf(f) * mu / mp.mpf(got["frequency_hi"])
            assert ulps(eps, O.edge_eps(m, n, True)) <= 4.0 + 2.0 * _slope_ulps(m, n, True), (eps, n)


def _slope_ulps(m, n, upper):
    """How many ulp of eps the edge moves over the rounding of mu and of f mu / frequency (3 ulp)."""
    h = m * mp.mpf(2) ** -40
    e0, e1 = O.edge_eps(m - h, n, upper), O.edge_eps(m + h, n, upper)
    return float(abs(e1 - e0) / (2 * h) * m / e0) * 3.0


def test_far_out_rig_gets_intervals_around_its_point():
    # eps = 3.5e-26, mu = 3.1e-125: deep in zone 0; A_lo was 2.6e288 (> A), T_lo 0.0, no frequency
    for rep in (K.analyze(T=1e-200, A=1e250, l=1e-100),
                An._analyze(None, None, 1e-200, 1e250, 1e-100, K.G_EARTH, None, 0.0, None, pointwise=False)):
        assert rep.stable and rep.zone == 0 and rep.margin > 0
        assert rep.A_lo < rep.A < rep.A_hi
        assert rep.T_lo < rep.T < rep.T_hi
        assert rep.frequency_lo < rep.frequency < rep.frequency_hi == math.inf
        assert rep.stroke_lo < rep.stroke < rep.stroke_hi
        assert ulps(rep.A_lo, O.amplitude_edge(1e-200, 0, 1e-100, K.G_EARTH, False)) <= 5.0
        # T_lo = eps_lo(mu) sqrt(8 l / A), eps_lo = sqrt(3/2) mu to rounding at this mu
        ref = O.edge_eps(rep.mu, 0, False) * mp.sqrt(8 * mp.mpf(1e-100) / mp.mpf(1e250))
        assert ulps(rep.T_lo, ref) <= 8.0


def _rig_points():
    rng = np.random.default_rng(43)
    pts = []
    for _ in range(400):
        T = float(10 ** rng.uniform(-7, 0.5))
        l = float(10 ** rng.uniform(-2, 1))
        # A across zone 0 and its neighbours at this T: u = T sqrt((A - g)/l) from 1e-4 to 12
        u = float(10 ** rng.uniform(-4, math.log10(12.0)))
        pts.append((T, G + l * (u / T) ** 2, l))
    pts += [(1e-200, 1e250, 1e-100), (1e-150, 1e280, 1e-10), (1e-9, 1e17, 1.0), (1e-6, 3e8, 0.5)]
    return pts


def _inside(lo, v, hi, rel=1e-12):
    """lo < v < hi, or None where v lies within ``rel`` of an edge (the edges' rounding decides)."""
    if lo is None:
        return False
    if abs(v - lo) <= rel * v or (math.isfinite(hi) and abs(hi - v) <= rel * v):
        return None
    return lo < v < hi


@pytest.mark.parametrize("fast", [True, False], ids=["scalar", "array"])
def test_intervals_agree_with_the_verdict(fast):
    checked = 0
    for T, A, l in _rig_points():
        if fast:
            rep = K.analyze(T=T, A=A, l=l)
        else:
            rep = An._analyze(None, None, T, A, l, K.G_EARTH, None, 0.0, None, pointwise=False)
        if rep.nearest_zone < 0:
            continue
        assert (rep.margin > 0) == rep.stable, (T, A, l)
        for lo, v, hi in ((rep.A_lo, rep.A, rep.A_hi), (rep.T_lo, rep.T, rep.T_hi),
                          (rep.frequency_lo, rep.frequency, rep.frequency_hi),
                          (rep.stroke_lo, rep.stroke, rep.stroke_hi)):
            inside = _inside(lo, v, hi)
            if inside is not None:
                assert inside == rep.stable, (T, A, l, rep.stable, lo, v, hi)
                checked += 1
    assert checked > 1200


@pytest.mark.parametrize("mu", [1e-99, 1e-100, 1e-101, 1e-155, 1e-160, 1e-200, 1e-300])
def test_zone0_lower_edge_where_mu_squared_leaves_the_doubles(mu):
    # mu^2 = 2e-320 was subnormal in the fixed point of zone 0's lower edge: eps_lo was 5e-6
    # relative off at mu = 1e-160 and 0.0 at mu = 1e-200 (and so was T_lo of period_edges)
    ref = O.edge_eps(mu, 0, False) if mu > 1e-170 else mp.sqrt(1.5) * mp.mpf(mu)  # (1 + 4 mu^4 / 7 + ...)
    lo, _ = K.zone_edges(mu, 0)
    assert ulps(lo, ref) <= 4.0 and ulps(P.edges_eps(mu, 0)[0], ref) <= 4.0
    if mu < 1e-170:  # T_lo ~ 3.5 mu^2 / sqrt(g) would be subnormal for every g that keeps A a double
        return
    g = 1e-30
    A = g / mu**2
    T_lo, _ = K.period_edges(A, 0, 1.0, g)
    mu_A = mp.sqrt(mp.mpf(g) / mp.mpf(A))
    assert ulps(T_lo, O.edge_eps(mu_A, 0, False) * mp.sqrt(8 / mp.mpf(A))) <= 8.0
