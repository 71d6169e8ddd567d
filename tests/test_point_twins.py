"""The scalar twins of ``kapitza._point`` against the array kernels they stand in for.

``analyze`` answers one point of the undamped square wave in Python floats; wherever a twin
decides, its numbers must be the array path's to within the rounding of the elementary
functions (``math`` against numpy's own), and every decision -- verdict, zone, the sign of
the margin, the kind of nonlinear verdict -- must be the same. Points are drawn over the
plane (small and near-1 ``mu`` included), inside zones 0-2, and at 0 to 2^40 ulp from the
edges of zones 0-30, where the twins hand the certified decision back to the array path.

Tolerances: verdict, zone, nearest zone, verdict text, the sign of the margin and the kind of
nonlinear verdict exactly; zone edges in eps and T to 4-8 ulp, the margin to the edges' ulp;
the amplitude and frequency intervals to what their root solves determine (a few ulp; the
frequency's upper edge divided by its slope in mu); the half-trace, rotation
angle and growth to their conditioning (``tau_tol``, ``angle_tol``); the nonlinear line's
numbers to the 10 digits printed (and identical as printed in 99 % of the points at least).
"""
import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import kapitza as K
from kapitza import _point as P
from kapitza import analysis
from kapitza import normal_form as NF
from kapitza import _normal_form as NFE
from kapitza import _square as Z
from kapitza._square import _floquet

EPS = np.finfo(float).eps


def ulps(a, b):
    """Distance of two doubles in units of the larger one's last place."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.abs(a - b) / np.spacing(np.maximum(np.abs(a), np.abs(b)))


def plane_points(seed, n):
    """``n`` points over the plane: eps in (0, 8], log-spread small eps, mu in (0, 1) and near its ends."""
    rng = np.random.default_rng(seed)
    k = n // 4
    eps = np.concatenate([rng.uniform(0.0, 8.0, n - 2 * k) + 1e-9, 10 ** rng.uniform(-3, 0.5, k),
                          rng.uniform(0.05, 4.0, k)])
    mu = np.concatenate([rng.uniform(0.0, 1.0, n - 2 * k) + 1e-12, rng.uniform(0.0, 1.0, k),
                         np.where(rng.integers(0, 2, k) == 0, 10 ** rng.uniform(-8, -1, k),
                                  1.0 - 10 ** rng.uniform(-8, -1, k))])
    return eps, mu


def edge_points(seed, n_mu):
    """Points 0 to 2^40 ulp either side of both edges of zones 0-30 (as ``tests/test_certified.py``)."""
    rng = np.random.default_rng(seed)
    mus = np.concatenate([rng.uniform(0, 1, n_mu - 8), 10 ** rng.uniform(-6, -1, 4), 1 - 10 ** rng.uniform(-6, -1, 4)])
    ns = rng.integers(0, 31, mus.size)
    ns[: n_mu // 2] = rng.integers(0, 3, n_mu // 2)
    lo, hi = K.zone_edges(mus, ns)
    ks = np.unique(np.concatenate([np.arange(0, 6), np.round(np.geomspace(8, 2.0**40, 12))])).astype(np.int64)
    eps, mu = [], []
    for e0 in (lo, hi):
        for sign in (1, -1):
            eps.append((e0.view(np.int64)[:, None] + sign * ks[None, :]).view(float).ravel())
            mu.append(np.repeat(mus, ks.size))
    return np.concatenate(eps), np.concatenate(mu)


def tau_tol(eps, mu, tau):
    """What the half-trace of either path is good to: ``tau = sin(u + pi - gamma) / sin(delta)``,
    the sine's argument carrying a few ulp of the phase ``u`` (``docs/theory.md`` section 5)."""
    x = 2.0 * math.sqrt(2.0) * eps * math.sqrt(1.0 + mu * mu)
    u = 2.0 * math.sqrt(2.0) * eps * math.sqrt(max((1.0 - mu) * (1.0 + mu), 0.0))
    s4 = math.sqrt(max((1.0 - mu) * (1.0 + mu) * (1.0 + mu * mu), 0.0))
    sd = s4 / math.hypot(s4, math.sinh(min(x, 700.0))) if s4 > 0 else 1.0
    return 16.0 * EPS * ((u + 4.0) / max(sd, 1e-300) + abs(tau))


def angle_tol(eps, mu, tau):
    """What the rotation angle (on a zone) or the growth (off it) is good to: ``acos`` or
    ``acosh`` of ``+-tau``, with condition ``1 / sqrt|1 - tau^2|``, plus the ``n pi`` part."""
    u = 2.0 * math.sqrt(2.0) * eps * math.sqrt(max((1.0 - mu) * (1.0 + mu), 0.0))
    room = max(abs(1.0 - tau * tau), 1e-30) if math.isfinite(tau) else 1.0
    return tau_tol(eps, mu, tau if math.isfinite(tau) else 0.0) / math.sqrt(room) + 16.0 * EPS * (u + 4.0)


def amplitude_tol(A_lo, T, n, l, g=9.81):
    """What zone ``n``'s lower edge in ``A`` at fixed ``T`` is good to in either path: within 5 ulp
    of the 50-digit reference (``tests/test_rig_edges_oracle.py``; zone 0's lower edge is solved
    on its cancellation-free gap), so the two paths agree to 10 ulp."""
    return 10.0 * float(np.spacing(A_lo))


def mu_root_tol(eps, n, mu, upper):
    """What the root ``mu`` of zone ``n``'s edge at fixed ``eps`` (the frequency interval) is good
    to, relative, in either path: the gap ``u - n pi - alpha`` (or ``beta``) carries a few ulp of
    ``u + n pi + 4``; divided by its slope in ``mu`` (from a central difference)."""
    def gap(m):
        x, u, D = P.phase_angles(eps, m)
        return u - n * math.pi - (P.beta_x(x, D) if upper else P.alpha_x(x, D))

    h = 1e-6 * min(mu, 1.0 - mu)
    slope = abs(gap(mu + h) - gap(mu - h)) / (2.0 * h)
    x, u, _ = P.phase_angles(eps, mu)
    return 1e-14 + 32.0 * EPS * (u + n * math.pi + 4.0) / max(slope * mu, 1e-300)


# ---------------------------------------------------------------- Floquet data
@pytest.mark.parametrize("points, share", [(plane_points(1, 6000), 0.85), (edge_points(2, 60), 0.02)],
                         ids=["plane", "edges"])
def test_floquet_twin_matches_the_array_kernel(points, share):
    from kapitza._square import _multipliers

    eps, mu = points
    tau, growth, theta, stable, zone = _floquet(eps, mu)
    decided = 0
    for i in range(eps.size):
        e, m = float(eps[i]), float(mu[i])
        got = P.floquet(e, m)
        if got is None:
            continue
        decided += 1
        t, gr, th, st, zn = got
        assert (st, zn) == (bool(stable[i]), int(zone[i])), (e, m)
        if math.isfinite(tau[i]):
            assert abs(t - tau[i]) <= tau_tol(e, m, float(tau[i])), (e, m, t, tau[i])
        else:  # tr M beyond the doubles
            assert t == tau[i]
        at = angle_tol(e, m, float(tau[i]))
        assert abs(th - theta[i]) <= at, (e, m, th, theta[i])
        assert abs(gr - growth[i]) <= at, (e, m, gr, growth[i])
        assert (gr > 0) == (growth[i] > 0) == (not st)
        lam = np.array(P.multipliers(t, gr, th, st))
        ref = _multipliers(tau[i], growth[i], theta[i], stable[i])
        with np.errstate(invalid="ignore"):  # inf - inf where exp(growth) overflows in both
            assert np.all((lam == ref) | (np.abs(lam - ref) <= 1.01 * at * np.maximum(np.abs(ref), 1.0))), (e, m)
    # the twin declines near edges and in thin zones, where the angle is ill-conditioned, where
    # the trace cancels (beside every edge far out: most of the edge points), which the array path
    # takes from the exact product, and for mu >= 1: most points of the plane it answers itself
    assert decided >= share * eps.size


# ---------------------------------------------------------------- margins and edges
@pytest.mark.parametrize("points, share", [(plane_points(3, 6000), 0.99), (edge_points(4, 60), 0.5)],
                         ids=["plane", "edges"])
def test_margin_twin_matches_stability_margin(points, share):
    eps, mu = points
    ref = K.stability_margin(eps, mu)
    decided = 0
    for i in range(eps.size):
        got = P.stability_margin(float(eps[i]), float(mu[i]))
        if got is None:
            continue
        decided += 1
        st, zn, lo, hi, margin = got
        assert (st, zn) == (bool(ref.stable[i]), int(ref.zone[i])), (eps[i], mu[i])
        assert (margin > 0) == st  # the margin's sign is the certified verdict
        assert ulps(lo, ref.eps_lo[i]) <= 4 and ulps(hi, ref.eps_hi[i]) <= 4, (eps[i], mu[i], lo, ref.eps_lo[i])
        # margin = (eps - edge) / eps: the edges' few ulp, relative to eps
        assert abs(margin - ref.margin[i]) <= 8.0 * EPS * (lo + hi) / eps[i], (eps[i], mu[i])
    assert decided >= share * eps.size


def test_edge_twins_match_zone_edges_period_and_amplitude_edges():
    rng = np.random.default_rng(5)
    mu = np.concatenate([rng.uniform(0.0, 1.0, 600), 10 ** rng.uniform(-8, -1, 100), 1 - 10 ** rng.uniform(-8, -1, 100)])
    n = rng.integers(0, 25, mu.size)
    n[:400] = rng.integers(0, 3, 400)
    lo, hi = Z._edges_eps(mu, n)
    for i in range(mu.size):
        plo, phi = P.edges_eps(float(mu[i]), int(n[i]))
        assert ulps(plo, lo[i]) <= 4 and ulps(phi, hi[i]) <= 4, (mu[i], n[i], plo, lo[i], phi, hi[i])
    # physical: T and A over the ranges of a rig and beyond
    T = 10 ** rng.uniform(-3, 0.5, 400)
    A = 9.81 * (1.0 + 10 ** rng.uniform(-6, 3, 400))
    l = 10 ** rng.uniform(-2, 1, 400)
    nn = rng.integers(0, 6, 400)
    Tlo, Thi = K.period_edges(A, nn, l)
    Alo, Ahi = K.amplitude_edges(T, nn, l)
    for i in range(T.size):
        a, b = P.period_edges(float(A[i]), int(nn[i]), float(l[i]), 9.81)
        assert ulps(a, Tlo[i]) <= 8 and ulps(b, Thi[i]) <= 8, (A[i], nn[i], l[i])
        a, b = P.amplitude_edges(float(T[i]), int(nn[i]), float(l[i]), 9.81)
        assert abs(a - Alo[i]) <= amplitude_tol(Alo[i], T[i], nn[i], l[i]), (T[i], nn[i], l[i], a, Alo[i])
        assert ulps(b, Ahi[i]) <= 16, (T[i], nn[i], l[i], b, Ahi[i])


# ---------------------------------------------------------------- nonlinear verdict
_NUM = re.compile(r"[-+]?\d+\.?\d*(?:e[-+]?\d+)?")


def same_sentence(a, b):
    """Same verdict in the same words, numbers equal to the 10 digits printed (one unit of the
    last digit apart at most: the two paths round the same number differently by a few ulp)."""
    words_a, words_b = _NUM.sub("#", a), _NUM.sub("#", b)
    if words_a != words_b:
        return False
    for x, y in zip(_NUM.findall(a), _NUM.findall(b)):
        x, y = float(x), float(y)
        if abs(x - y) > 1.001e-9 * max(abs(x), abs(y)) + 1e-300:
            return False
    return True


def zone_points(seed, n):
    """``n`` points inside zones 0-2 (uniform across each zone at random mu)."""
    rng = np.random.default_rng(seed)
    mu = rng.uniform(0.01, 0.99, n)
    lo, hi = K.zone_edges(mu, rng.integers(0, 3, n))
    return lo + rng.uniform(0.0, 1.0, n) * (hi - lo), mu


def test_nonlinear_twin_matches_nonlinear_stability():
    pe, pm = plane_points(6, 8000)
    ze, zm = zone_points(7, 2500)
    ee, em = edge_points(8, 24)
    eps, mu = np.concatenate([pe, ze, ee]), np.concatenate([pm, zm, em])
    near_edge = np.arange(eps.size) >= pe.size + ze.size
    _, _, theta, stable, zone = _floquet(eps, mu)
    eps, mu, near_edge, theta, zone = eps[stable], mu[stable], near_edge[stable], theta[stable], zone[stable]
    ref = NF.nonlinear_stability(eps, mu)
    ref_nf, _ = NFE._normal_form(eps, mu)
    sentences = ref.sentences()
    paper_like = (zone == 0) & (mu < 0.5) & ~near_edge
    decided = identical = 0
    for i in range(eps.size):
        fl = P.floquet(float(eps[i]), float(mu[i]))
        # as analyze does: the array path's angle where the scalar one declines
        th, zn = (float(theta[i]), int(zone[i])) if fl is None else (fl[2], fl[4])
        got = P.nonlinear(float(eps[i]), float(mu[i]), th, zn, exact_theta=fl is None)
        if got is None:
            continue
        decided += paper_like[i]
        ours = sentences[i].split(": ", 1)[1] if eps.size > 1 else sentences[i]
        assert same_sentence(got, ours), (eps[i], mu[i], got, ours)
        identical += got == ours
        w, coef, beta, twist, res4 = P.normal_form(float(eps[i]), float(mu[i]), th, zn)
        scale = np.sum(np.abs(ref_nf.coefficients[i]))
        assert abs(beta - ref_nf.beta[i]) <= 64.0 * P.DEFECT_MAX * scale, (eps[i], mu[i])
        if fl is None:
            assert w == ref_nf.w[i]
        else:
            assert abs(w - ref_nf.w[i]) <= 4.0 * P.COND_MAX * min(w, math.pi - w)
    # near edges, in the thinner zones (zone 0 at large mu, zones 1 and 2: the jets' e^{3x}-sized
    # terms cancel there) and near the thresholds the array path answers; zone 0 at mu < 0.5,
    # where the paper's examples lie, is mostly decided here
    assert decided >= 0.6 * np.count_nonzero(paper_like)
    # the printed digits are the same but for a rare last-digit rounding
    assert identical >= 0.99 * decided


# ---------------------------------------------------------------- the whole report
FIELDS_EXACT = ("eps", "mu", "stable", "verdict", "zone", "nearest_zone", "T", "A", "l", "g", "stroke",
                "drive", "pendulum", "damping", "zeta", "determinant")


def assert_same_report(fast, slow):
    where = (fast.eps, fast.mu, fast.T, fast.A)
    for f in FIELDS_EXACT:
        assert getattr(fast, f) == getattr(slow, f), (f, where, getattr(fast, f), getattr(slow, f))
    assert (fast.margin > 0) == (slow.margin > 0) == fast.stable
    for f in ("eps_lo", "eps_hi", "T_lo", "T_hi"):
        a, b = getattr(fast, f), getattr(slow, f)
        assert (a is None) == (b is None), (f, where)
        if a is not None and not (math.isnan(a) and math.isnan(b)):  # NaN: no zone (A <= g)
            assert ulps(a, b) <= 8, (f, where, a, b)
    for f in ("A_lo", "A_hi", "stroke_lo", "stroke_hi"):
        a, b = getattr(fast, f), getattr(slow, f)
        assert (a is None) == (b is None), (f, where)
        if a is not None and f in ("A_lo", "stroke_lo"):
            rel = amplitude_tol(slow.A_lo, slow.T, slow.nearest_zone, slow.l, slow.g) / slow.A_lo
            assert abs(a - b) <= 1.5 * rel * b, (f, where, a, b)
        elif a is not None:
            assert ulps(a, b) <= 24, (f, where, a, b)
    for f in ("frequency_lo", "frequency_hi"):  # regula falsi on mu to about 1e-14
        a, b = getattr(fast, f), getattr(slow, f)
        assert (a is None) == (b is None), (f, where)
        if a is not None and math.isfinite(b):
            root = 0.5 / slow.T * slow.mu / b
            rel = mu_root_tol(slow.eps, slow.nearest_zone, root, f == "frequency_hi")
            assert a == b or abs(a - b) <= rel * abs(b), (f, where, a, b, rel)
        else:
            assert a == b
    if math.isfinite(slow.margin):
        assert abs(fast.margin - slow.margin) <= 8.0 * EPS * (slow.eps_lo + slow.eps_hi) / slow.eps, where
    else:
        assert fast.margin == slow.margin
    tau = slow.trace / 2.0
    if math.isfinite(tau):
        tt = tau_tol(slow.eps, slow.mu, tau)
        assert abs(fast.trace - slow.trace) <= 2.0 * tt, where
        assert abs(fast.trace_margin - slow.trace_margin) <= tt, where
    else:
        assert fast.trace == slow.trace
    at = angle_tol(slow.eps, slow.mu, tau)
    assert abs(fast.rotation_number - slow.rotation_number) <= at / (2.0 * math.pi), where
    assert abs(fast.growth - slow.growth) <= at, where
    lam_f, lam_s = np.array(fast.multipliers), np.array(slow.multipliers)
    assert lam_f.shape == lam_s.shape == (2,)
    with np.errstate(invalid="ignore"):
        assert np.all((lam_f == lam_s) | (np.abs(lam_f - lam_s) <= 1.01 * at * np.maximum(np.abs(lam_s), 1.0))), where
    assert (fast.nonlinear is None) == (slow.nonlinear is None)
    if fast.nonlinear is not None:
        assert same_sentence(fast.nonlinear, slow.nonlinear), (where, fast.nonlinear, slow.nonlinear)


def reports(eps, mu, physical=False, T=None, A=None, l=None, g=None):
    c = 0.0 if physical else None
    fast = analysis._report(K.SquareWave(), eps, mu, 0.0, physical, T, A, l, g, c)
    slow = analysis._report(K.SquareWave(), eps, mu, 0.0, physical, T, A, l, g, c, pointwise=False)
    return fast, slow


def test_analyze_twin_matches_the_array_path_in_arnold_parameters():
    eps, mu = plane_points(8, 600)
    ee, mm = edge_points(9, 12)
    pick = np.random.default_rng(10).choice(ee.size, 400, replace=False)
    eps, mu = np.concatenate([eps, ee[pick], [0.5, 0.5301303231328324]]), np.concatenate([mu, mm[pick], [0.3, 0.4247369708803898]])
    for e, m in zip(eps.tolist(), mu.tolist()):
        assert_same_report(*reports(e, m))
    # and the public call takes the fast path for the paper's point
    assert_same_report(K.analyze(eps=0.5, mu=0.3), reports(0.5, 0.3)[1])


def test_analyze_twin_matches_the_array_path_in_physical_parameters():
    rng = np.random.default_rng(12)
    T = np.concatenate([10 ** rng.uniform(-2.5, 0.3, 300), [0.15, 0.5064, 0.01]])
    A = np.concatenate([9.81 * (1.0 + 10 ** rng.uniform(-4, 2.5, 300)), [100.0, 100.0, 100.0]])
    l = np.concatenate([10 ** rng.uniform(-1, 0.5, 300), [1.0, 1.0, 1.0]])
    # and T within a few ulp of the zones' edges in T at fixed A
    A2 = 9.81 * (1.0 + 10 ** rng.uniform(-1, 2, 40))
    n2 = rng.integers(0, 3, 40)
    Tlo, Thi = K.period_edges(A2, n2)
    ks = np.array([-64, -3, -1, 0, 1, 3, 64])
    Te = np.concatenate([(t.view(np.int64)[:, None] + ks[None, :]).view(float).ravel() for t in (Tlo, Thi)])
    T = np.concatenate([T, Te])
    A = np.concatenate([A, np.tile(np.repeat(A2, ks.size), 2)])
    l = np.concatenate([l, np.ones(Te.size)])
    for t, a, ll in zip(T.tolist(), A.tolist(), l.tolist()):
        e, m = (float(v) for v in K.to_arnold(t, a, ll, 9.81))
        assert_same_report(*reports(e, m, True, t, a, ll, 9.81))
    rep = K.analyze(T=0.15, A=100.0)
    e, m = (float(v) for v in K.to_arnold(0.15, 100.0))
    assert_same_report(rep, reports(e, m, True, 0.15, 100.0, 1.0, 9.81)[1])


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(eps=st.floats(1e-6, 30.0), mu=st.floats(1e-9, 1.2))
def test_analyze_twin_matches_the_array_path_hypothesis(eps, mu):
    assert_same_report(*reports(eps, mu))


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(T=st.floats(1e-3, 3.0), A=st.floats(1.0, 1e4), l=st.floats(0.05, 3.0))
def test_analyze_twin_matches_the_array_path_hypothesis_physical(T, A, l):
    e, m = (float(v) for v in K.to_arnold(T, A, l, 9.81))
    assert_same_report(*reports(e, m, True, T, A, l, 9.81))


def _slow(**kw):
    full = dict(eps=None, mu=None, T=None, A=None, l=1.0, g=K.G_EARTH, drive=None, damping=0.0, zeta=None)
    full.update(kw)
    return analysis._analyze(**full, pointwise=False)


@pytest.mark.parametrize("kw", [dict(eps=1, mu=0.3), dict(eps=0.5, mu=2), dict(eps=0.5, mu=1.0), dict(T=0.15, A=100),
                                dict(T=0.15, A=100.0, l=2, g=9.81), dict(T=0.15, A=5.0), dict(T=0.15, A=9.81),
                                dict(T=1e-150, A=1e300, l=1e-10), dict(T=1e150, A=100.0),
                                dict(eps=0.5, mu=0.3, l="ignored"), dict(eps=np.float64(0.5), mu=0.3),
                                dict(T=0.15, A=100.0, damping=0), dict(eps=0.5, mu=0.3, zeta=0.0),
                                dict(eps=0.5, mu=0.3, drive="square"), dict(eps=2**60, mu=0.3)])
def test_plain_numbers_get_the_report_of_the_full_validation(kw):
    assert_same_report(K.analyze(**kw), _slow(**kw))


@pytest.mark.parametrize("kw", [dict(eps=-1.0, mu=0.3), dict(eps=0.5, mu=math.nan), dict(eps=True, mu=0.3),
                                dict(T=0.15, A=math.inf), dict(T=0.15, A=100.0, l=0), dict(T=0.15, A=100.0, g=-1),
                                dict(eps=0.5, mu=0.3, damping=1.0), dict(T=0.15, A=100.0, zeta=0.1, damping=0.2),
                                dict(T=1e-300, A=1e-300),
                                dict(eps=0.5, mu=0.3, T=0.15), dict(T=0.15, A=[100.0])])
def test_plain_numbers_are_refused_as_before(kw):
    with pytest.raises(K.KapitzaValueError) as fast:
        K.analyze(**kw)
    with pytest.raises(K.KapitzaValueError) as slow:
        _slow(**kw)
    assert str(fast.value) == str(slow.value)


def test_array_fallback_of_the_nonlinear_line_prints_what_nonlinear_stability_prints():
    # where the scalar twin declines, analyze takes normal_form.sentence_of: the same kernels
    # without the validation and the repeated side evaluations -- the same text, exactly
    ze, zm = zone_points(13, 300)
    ee, em = edge_points(14, 12)
    eps, mu = np.concatenate([ze, ee[::7]]), np.concatenate([zm, em[::7]])
    stable = _floquet(eps, mu)[3]
    assert np.count_nonzero(stable) > 250
    for e, m in zip(eps[stable].tolist(), mu[stable].tolist()):
        assert NF.sentence_of(e, m) == str(NF.nonlinear_stability(e, m)), (e, m)


def test_series_of_the_jets_at_one_point_are_those_of_an_array():
    # _normal_form._polyval sums a few points in Python floats: the same bits as np.polyval
    k = np.concatenate([np.random.default_rng(15).uniform(-1.0, 1.0, 2000), [0.0, -0.0, 1.0, -1.0]])
    big = NFE._entire(k)
    for i in range(k.size):
        for one, many in zip(NFE._entire(k[i]), big):
            assert np.asarray(one).tobytes() == np.asarray(many[i]).tobytes(), k[i]
