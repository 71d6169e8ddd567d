"""The sine drive against an oracle of its own: the exact monodromy of the double inputs.

The oracle imports nothing from kapitza. It integrates the project's equation itself,
``theta'' + kappa theta' = 8 eps^2 (mu^2 + sin(pi tau)) theta`` over the whole period
``tau in [0, 2]`` (``kappa = 2 sqrt(8) zeta mu eps``), by Taylor series in fixed-point integer
arithmetic with as many bits as the growth of the solutions needs (the constants from mpmath):
a different variable, period and recurrence from the library's certified path (Mathieu's
``z``, half a period, DLMF 28.2.(iv)). Zone edges near ``mu = 1`` (where ``q`` reaches 1e6 and an
integration is too slow) come from the characteristic polynomial of DLMF's tridiagonal matrices
(28.4) at 60 digits instead.

Checked: the verdicts at doubles within a few ulp of the edges of thin zones (zones up to 8 at
mu 0.3-0.7, zones 0-1 at mu >= 0.9), the two points where the trace was once contradicted, the
edges as mu -> 1 to ``4e-15 + 4u/(1 - mu^2)``, ``eps_lo <= eps_hi`` everywhere, the damped edges to
4e-15 at zeta up to 1, and the chart against ``is_stable`` at the same near-edge doubles.
"""
import math

import mpmath as mp
import numpy as np
import pytest

import kapitza as K

U = 2.0**-53


# ---------------------------------------------------------------- the oracle
def _fx(x, P):
    with mp.workprec(P + 30):
        return int(mp.nint(mp.mpf(x) * mp.mpf(2) ** P))


def oracle_monodromy(eps, mu, zeta=0.0, extra_bits=0):
    """``(tr M, det M)`` of one period 2T at the exact values ``eps, mu, zeta`` (mpf results)."""
    with mp.workprec(200):
        e, m, z = mp.mpf(eps), mp.mpf(mu), mp.mpf(zeta)
        w2 = 8 * e * e
        kappa = 2 * mp.sqrt(8) * z * m * e
        rate = float(mp.sqrt(w2 * (1 + m * m)))
    steps = max(4, math.ceil(2.0 * (rate + math.pi + float(kappa))))
    P = 120 + int(2.0 * 2.0 * rate / math.log(2.0)) + extra_bits
    one = 1 << P
    with mp.workprec(P + 40):
        h = mp.mpf(2) / steps
        base, amp = _fx(w2 * m * m, P), w2
        kh = _fx(kappa * h, P)
        hh = _fx(h * h, P)
        hf = _fx(h, P)
        # Taylor coefficients (scaled by h^k) of w2 sin(pi tau0 + pi s), per step
        K = 0
        t = mp.mpf(1)
        while True:
            K += 1
            t = t * mp.pi * h / K
            if K > 6 and t * amp < mp.mpf(2) ** (-P - 8):
                break
        scale = [_fx(amp * (mp.pi * h) ** k / mp.factorial(k), P) for k in range(K)]
        coef = []
        for j in range(steps):
            # the k-th derivative of sin(x0 + pi s) cycles through sin, cos, -sin, -cos of x0
            sn, cs = _fx(mp.sin(mp.pi * j * h), P), _fx(mp.cos(mp.pi * j * h), P)
            cyc = (sn, cs, -sn, -cs)
            row = [scale[k] * cyc[k % 4] >> P for k in range(K)]
            row[0] += base
            coef.append(row)
    cols = [[one, 0], [0, one]]
    for row in coef:
        for col in cols:
            Y = [col[0], col[1] * hf >> P]
            k = 0
            while True:
                acc = sum(row[i] * Y[k - i] for i in range(min(k, K - 1) + 1)) >> P
                nxt = ((acc * hh >> P) - (k + 1) * (kh * Y[k + 1] >> P)) // ((k + 1) * (k + 2))
                Y.append(nxt)
                k += 1
                if k > 8 and max(abs(Y[-1]), abs(Y[-2]), abs(Y[-3])) < 16:
                    break
            col[0] = sum(Y)
            col[1] = (sum(i * y for i, y in enumerate(Y)) << P) // hf
    with mp.workprec(2 * P + 64):
        s = mp.mpf(2) ** P
        tr = (mp.mpf(cols[0][0]) + mp.mpf(cols[1][1])) / s
        det = (mp.mpf(cols[0][0]) * cols[1][1] - mp.mpf(cols[0][1]) * cols[1][0]) / s**2
    return tr, det


def oracle_stable(eps, mu, zeta=0.0):
    tr, det = oracle_monodromy(eps, mu, zeta)
    return bool(abs(tr) < 1 + det) if zeta > 0 else bool(abs(tr) < 2)


def oracle_edge(mu, n, side):
    """The edge of zone ``n`` (``side`` 0: on ``a_n``, 1: on ``b_{n+1}``) at the exact double ``mu``:
    the root in eps of det(T_N(q) - a), a = -2 mu^2 q, q = 16 eps^2/pi^2, for DLMF's matrix of that
    family (28.4), near the asymptotic guess refined by the library's value ``guess``."""
    order = n if side == 0 else n + 1
    even = order % 2 == 0
    kind = "a" if side == 0 else "b"

    def det(e):
        q = 16 * e * e / mp.pi**2
        x = -2 * mp.mpf(mu) ** 2 * q
        N = int(2 * math.sqrt(float(q))) + 40
        if kind == "a" and even:   # cos 2rz: 0, 4, 16, ...; sqrt2 q in the first off-diagonal
            D = [(2 * r) ** 2 for r in range(N)]
            e2 = [2 * q * q] + [q * q] * N
            d0 = D[0]
        elif kind == "a":          # cos (2r+1)z: 1 + q, 9, 25, ...
            D = [(2 * r + 1) ** 2 for r in range(N)]
            e2, d0 = [q * q] * N, 1 + q
        elif not even:             # sin (2r+1)z: 1 - q, 9, 25, ...
            D = [(2 * r + 1) ** 2 for r in range(N)]
            e2, d0 = [q * q] * N, 1 - q
        else:                      # sin (2r+2)z: 4, 16, ...
            D = [(2 * r + 2) ** 2 for r in range(N)]
            e2, d0 = [q * q] * N, D[0]
        p_prev, p = mp.mpf(1), d0 - x
        for r in range(1, N):
            p_prev, p = p, (D[r] - x) * p - e2[r - 1] * p_prev
        return p

    return det


def oracle_edge_root(mu, n, side, guess, rel=1e-9):
    f = oracle_edge(mu, n, side)
    with mp.workdps(60):
        a, b = mp.mpf(guess) * (1 - rel), mp.mpf(guess) * (1 + rel)
        fa, fb = f(a), f(b)
        assert fa * fb < 0, "no sign change within the bracket"
        for _ in range(200):  # Illinois regula falsi to 1e-40 relative
            c = b - fb * (b - a) / (fb - fa)
            fc = f(c)
            if fc * fb < 0:
                a, fa = b, fb
            else:
                fa = fa / 2
            b, fb = c, fc
            if abs(b - a) < mp.mpf(10) ** -40 * abs(b):
                break
        return b


def near(x, k):
    """The double k ulp from x."""
    for _ in range(abs(k)):
        x = np.nextafter(x, np.inf if k > 0 else -np.inf)
    return float(x)


# ---------------------------------------------------------------- the oracle checks itself
def test_oracle_agrees_with_its_own_higher_precision_and_the_closed_limit():
    tr1, det1 = oracle_monodromy(3.0, 0.5)
    tr2, _ = oracle_monodromy(3.0, 0.5, extra_bits=64)
    assert abs(tr1 - tr2) < mp.mpf(10) ** -30 * abs(tr2)
    assert abs(det1 - 1) < mp.mpf(10) ** -30
    _, det = oracle_monodromy(2.0, 0.4, zeta=0.3)  # det M = exp(-2 kappa)
    with mp.workdps(50):
        kappa = 2 * mp.sqrt(8) * mp.mpf(0.3) * mp.mpf(0.4) * mp.mpf(2.0)
        assert abs(det - mp.exp(-2 * kappa)) < mp.mpf(10) ** -30


# ---------------------------------------------------------------- verdicts against the trace
@pytest.mark.parametrize("eps, mu", [(12.232648531796508, 0.9), (12.896867618716339, 0.5)])
def test_points_beside_thin_zones_follow_their_trace(eps, mu):
    tr, _ = oracle_monodromy(eps, mu)
    f = K.floquet(eps, mu, drive="sine")
    assert abs(tr) > 2 and not f.stable and f.zone == -1
    assert float(f.trace) == pytest.approx(float(tr), rel=1e-12)
    assert float(f.growth) == pytest.approx(float(mp.acosh(abs(tr) / 2)), rel=1e-12)


def test_long_double_counts_decide_beside_edges_and_spare_the_exact_trace(monkeypatch):
    # within the double band of an edge the Sturm counts are taken again in long double (where it
    # has more bits than a double): they agree with the oracle, and the exact trace is asked rarely
    from kapitza.drives import _mathieu

    if _mathieu.LONG_DOUBLE is None:
        pytest.skip("long double is a double on this platform")
    calls = []
    exact = _mathieu._exact_tau
    monkeypatch.setattr(_mathieu, "_exact_tau", lambda e, m: calls.append(e) or exact(e, m))
    mu = 0.3
    for n in range(3):
        lo, hi = (float(x) for x in K.zone_edges(mu, n, drive="sine"))
        eps = np.array(sorted({near(lo, k) for k in range(-4, 5)} | {near(hi, k) for k in range(-4, 5)}))
        got = K.floquet(eps, mu, drive="sine")
        for i, e in enumerate(eps):
            tr, _ = oracle_monodromy(e, mu)
            assert bool(got.stable[i]) == bool(-2 < tr < 2), (e, mu, float(tr))  # (abs() would round)
            # the trace stays on its verdict's side of +-2
            assert (abs(float(got.trace[i])) < 2) == bool(got.stable[i])
    assert len(calls) <= 6, len(calls)


CASES = [(0.5, 6), (0.3, 8), (0.7, 4), (0.9, 1), (0.95, 0)]
SLOW_CASES = [(0.3, 4), (0.3, 6), (0.4, 7), (0.5, 4), (0.5, 8), (0.6, 5), (0.7, 3), (0.7, 6), (0.9, 0),
              (0.92, 1), (0.95, 1), (0.97, 0)]


def _check_near_edge_verdicts(mu, n, offsets):
    lo, hi = (float(x) for x in K.zone_edges(mu, n, drive="sine"))
    assert lo <= hi
    eps = np.array(sorted({near(lo, k) for k in offsets} | {near(hi, k) for k in offsets}))
    got = K.floquet(eps, mu, drive="sine")
    grid = K.stability_grid(eps, np.array([mu]), drive="sine")[0]
    for i, e in enumerate(eps):
        tr, _ = oracle_monodromy(e, mu)
        assert bool(got.stable[i]) == bool(abs(tr) < 2), (e, mu, float(tr))
        assert bool(grid[i]) == bool(got.stable[i]), (e, mu)
        if got.stable[i]:
            assert got.zone[i] == n
        else:  # the sign of the trace is that of the locked angle (a multiple of pi)
            assert float(tr) * (-1) ** round(2 * float(got.rotation_number[i])) > 0, (e, mu)


@pytest.mark.parametrize("mu, n", CASES)
def test_near_edge_verdicts_beside_thin_zones(mu, n):
    _check_near_edge_verdicts(mu, n, (-2, 0, 1, 3))


@pytest.mark.slow
@pytest.mark.parametrize("mu, n", SLOW_CASES)
def test_near_edge_verdicts_beside_thin_zones_sweep(mu, n):
    _check_near_edge_verdicts(mu, n, range(-4, 5))


# ---------------------------------------------------------------- edges as mu -> 1
@pytest.mark.parametrize("mu, n", [(0.95, 0), (0.95, 1), (0.99, 0), (0.99, 1), (0.999, 0)])
def test_edges_as_mu_tends_to_one(mu, n):
    lo, hi = (float(x) for x in K.zone_edges(mu, n, drive="sine"))
    assert lo <= hi
    tol = 4e-15 + 4 * U / (1 - mu * mu)
    for side, got in ((0, lo), (1, hi)):
        ref = oracle_edge_root(mu, n, side, got)
        assert abs(got - ref) <= tol * ref, (mu, n, side, got, float(ref))


def test_edges_never_cross():
    mu = np.concatenate([np.linspace(0.9, 0.999, 34), 1 - np.geomspace(1e-2, 1e-3, 12)])
    for n in range(4):
        lo, hi = K.zone_edges(mu, n, drive="sine")
        assert np.all(lo <= hi) and np.all(np.isfinite(lo))
        if n:
            assert np.all(K.zone_edges(mu, n - 1, drive="sine")[1] <= lo)


# ---------------------------------------------------------------- damped edges
@pytest.mark.parametrize("mu, n, zeta", [(0.6, 1, 1.0), (0.3, 0, 0.5), (0.4, 2, 0.2), (0.5, 1, 1.0)])
def test_damped_edges(mu, n, zeta):
    lo, hi = (float(x) for x in K.zone_edges(mu, n, drive="sine", zeta=zeta))

    def excess(e):  # |tr M| - (1 + det M): zero on a damped edge
        tr, det = oracle_monodromy(e, mu, zeta)
        return abs(tr) - 1 - det

    for got in (lo, hi):
        if n == 0 and got == lo and got == 0.0:
            continue
        with mp.workdps(50):
            a, b = mp.mpf(got) * (1 - 1e-12), mp.mpf(got) * (1 + 1e-12)
            fa, fb = excess(a), excess(b)
            assert fa * fb < 0, (mu, n, zeta, got)
            for _ in range(20):  # secant to the root, then one sign check either side
                c = b - fb * (b - a) / (fb - fa)
                a, fa, b, fb = b, fb, c, excess(c)
                if abs(b - a) < mp.mpf(10) ** -25 * abs(b):
                    break
        assert abs(got - b) <= 4e-15 * b, (mu, n, zeta, got, float(b))


@pytest.mark.parametrize("mu, n, zeta", [(0.6, 0, 1.0), (0.6, 1, 1.0), (0.3, 1, 0.5)])
def test_damped_verdicts_beside_the_edges_follow_the_exact_monodromy(mu, n, zeta):
    """At the doubles beside each damped edge ``is_stable`` is ``|tr M| < 1 + det M`` of the oracle,
    and the reported edge is the unstable double next to the zone."""
    lo, hi = (float(x) for x in K.zone_edges(mu, n, drive="sine", zeta=zeta))
    for edge, inward in ((lo, 1), (hi, -1)):
        eps = (np.array([edge]).view(np.int64) + np.arange(-2, 3)).view(np.float64)
        got = K.is_stable(eps, mu, drive="sine", zeta=zeta)
        want = []
        for e in eps:
            tr, det = oracle_monodromy(float(e), mu, zeta)
            want.append(bool(abs(tr) < 1 + det))
        assert got.tolist() == want, (mu, n, zeta, edge)
        assert not got[2] and got[2 + inward]


# ---------------------------------------------------------------- the trace's error bound
def test_the_trace_error_bounds_the_trace_and_stays_near_its_size():
    """``Floquet.trace_error`` holds against the oracle at random points up to ``eps = 40`` (``q``
    about 2,600), and is within about 1e-9 of the trace where nothing cancels: the solutions grow by
    up to 1e50 over the half period there, which the bound of the largest state alone multiplied
    into the error (1e44 relative at ``eps = 30``)."""
    rng = np.random.default_rng(11)
    eps = np.exp(rng.uniform(np.log(0.05), np.log(40.0), 24))
    mu = rng.uniform(0.0, 0.99, 24)
    f = K.floquet(eps, mu, drive="sine")
    rel = []
    for e, m, t, err in zip(eps.tolist(), mu.tolist(), f.trace.tolist(), f.trace_error.tolist()):
        tr, _ = oracle_monodromy(e, m)
        assert abs(mp.mpf(t) - tr) <= err, (e, m)
        rel.append(err / max(abs(t), 1.0))
    assert max(rel) < 1e-8
    assert np.median(rel) < 1e-10


@pytest.mark.parametrize("mu, n", [(0.5, 6), (0.7, 5), (0.9, 2), (0.95, 1)])
def test_the_double_trace_bound_holds_where_it_cancels(mu, n):
    """The double trace's own bound (before any exact recomputation) beside and inside thin zones,
    where the solutions grow and fall back and the trace loses all its digits: it still holds, and
    says so (it spans the trace at the edges)."""
    from kapitza.drives._mathieu import _sine_traces

    lo, hi = (float(v) for v in K.zone_edges(mu, n, drive="sine"))
    eps = np.array([lo * (1 - 1e-9), lo, 0.5 * (lo + hi), hi, hi * (1 + 1e-9), hi * (1 + 1e-3)])
    tau, _, _, err = _sine_traces(eps, np.full(eps.size, mu))
    for e, t, b in zip(eps.tolist(), tau.tolist(), err.tolist()):
        tr, _ = oracle_monodromy(e, mu)
        assert abs(mp.mpf(t) - tr / 2) <= b, (mu, n, e)
    assert err[1] > 1e-3 * max(abs(tau[1]), 1.0)


@pytest.mark.parametrize("mu, n", [(0.8, 2), (0.8736, 3), (0.9188, 3), pytest.param(0.99, 0, marks=pytest.mark.slow)])
def test_a_zone_thinner_than_a_double_lies_between_its_edges(mu, n):
    """Where no double is stable, the two reported edges are adjacent doubles the exact trace changes
    sign between: ``eps_lo`` in gap ``n`` (sign ``(-1)^n``), ``eps_hi`` in gap ``n + 1``, so the zone
    lies between them as the docstring's interval says (the counts' edges had both in one gap at
    78 of 88 such zones of ``kapitza zones --drive sine``)."""
    lo, hi = (float(v) for v in K.zone_edges(mu, n, drive="sine"))
    assert np.nextafter(lo, np.inf) == hi
    (t_lo, _), (t_hi, _) = oracle_monodromy(lo, mu), oracle_monodromy(hi, mu)
    assert abs(t_lo) > 2 and abs(t_hi) > 2
    assert mp.sign(t_lo) == (-1) ** n and mp.sign(t_hi) == (-1) ** (n + 1)
    assert K.rotation_number([lo, hi], mu, drive="sine").tolist() == [n / 2, (n + 1) / 2]
