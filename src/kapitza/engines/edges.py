"""Zone edges of any drive from a period map with a rotation angle.

Zone ``n`` is where the rotation angle per period lies in ``(n pi, (n + 1) pi)``; off the zones
the angle is a whole multiple of ``pi``. Along ``eps`` at fixed ``mu`` the angle does not
decrease (oscillation theory of ``phi'' = 8 eps^2 (mu^2 + s) phi``: the restoring part grows
with ``eps^2``), so the lower edge of zone ``n`` is where the angle leaves ``n pi`` and the upper
edge where it reaches ``(n + 1) pi``. Each edge is found in three stages, batched over all the
``(mu, n)`` asked at once:

1. *bracket by the angle*: the angle is sampled every ``pi/3`` of elliptic angle over the span
   where the zones asked at one ``mu`` lie (``|theta - rate eps| < B``), once per distinct
   ``mu`` for all its zones; each task's bracket is the last sample below its level and the
   first above (doubling or halving where the samples do not reach);
2. *a point of the gap and a point of the zone*: bisection on the angle; but a bracket from
   gap ``n`` to gap ``n + 1`` holds all of zone ``n``, where ``tr M / 2 = cos theta`` changes
   sign: secant (Illinois) iterations on ``sign(tau) max(asinh|tau| - asinh 1, 0)``, zero on
   the zone and growing like the growth rate outside it, land in the zone however thin it is
   (a zone thinner than the spacing of doubles gets both edges at its zero);
3. *Illinois iterations* on ``asinh(+-tr M / 2) - asinh(1)``, which changes sign exactly once
   between a point of the gap and a point of the zone, to adjacent doubles.

The edge is reported on its unstable side, as every edge of kapitza is.
"""
from __future__ import annotations

import numpy as np

PI = np.pi
A1 = float(np.arcsinh(1.0))


def _level(tau, theta, zone):
    """The angle in units of ``pi``, with ``k + 1/2`` standing for all of zone ``k``."""
    return np.where(zone >= 0, zone + 0.5, np.rint(theta / PI))


def _F(tau, log_tau, sgn):
    """``asinh(sgn tau) - asinh(1)``, from ``log|tau|`` where ``tau`` is large."""
    x = sgn * tau
    with np.errstate(over="ignore", invalid="ignore"):
        big = np.sign(x) * (log_tau + np.log1p(np.sqrt(1.0 + np.exp(-2.0 * np.maximum(log_tau, 0.0)))))
        small = np.arcsinh(np.where(log_tau < 30.0, x, 0.0))
    return np.where(log_tau < 30.0, small, big) - A1


def zone_edges(floquet, trace, mu, n, rate, B=None, noise=None, reach=None):
    """``(eps_lo, eps_hi)`` of zone ``n`` at each ``mu`` (flat arrays; every row has zones).

    ``floquet(eps, mu) -> (tau, log_tau, theta, zone)`` and ``trace(eps, mu) -> (tau, log_tau)``
    evaluate the period at flat arrays; ``rate > 0`` is the elliptic angle per unit ``eps`` and
    ``B`` (optional) bounds ``|theta - rate eps|``: with it the angle is first sampled over
    the span where the zones lie, once per distinct ``mu`` for all the zones asked there.
    ``noise(eps, mu)`` (optional) is the logarithm of a bound on the error of ``tau``: where it
    exceeds 1 and ``|tau|``, the search for a point inside a zone stops (the trace cannot tell it
    from its gaps there). ``reach``: ``(eps_max, refuse)``, the largest ``eps`` ``floquet`` answers at
    each ``mu`` and ``refuse(eps, mu)``, which raises the error for an edge past it (no point beyond
    it is asked).
    """
    mu = np.asarray(mu, float)
    n = np.asarray(n, np.int64)
    P = mu.size
    # tasks: P lower edges (threshold n: the angle has left n pi), P upper (threshold n + 1/2)
    m = np.concatenate([mu, mu])
    c = np.concatenate([n.astype(float), n + 0.5])
    upper = np.arange(2 * P) >= P
    nn = np.concatenate([n, n])
    x0 = (nn + np.where(upper, 1.0, 0.0)) * PI / np.concatenate([rate, rate])
    x0 = np.maximum(x0, 0.5 * PI / np.concatenate([rate, rate]))
    R = np.full(2 * P, np.inf) if reach is None else np.concatenate([reach[0], reach[0]])
    x0 = np.minimum(x0, R)

    def pred(x, rows):
        tau, lt, th, z = floquet(x, m[rows])
        lev = _level(tau, th, z)
        return lev > c[rows], lev, tau, lt

    def pred_at(x, mus):
        tau, lt, th, z = floquet(x, mus)
        return _level(tau, th, z)

    # 1. bracket: the angle sampled every pi/3 of elliptic angle over the span where the
    # zones asked for at each mu lie, shared by every task of that mu; then doubling or halving
    # for the tasks the samples do not bracket
    a = np.zeros(2 * P)
    b = np.full(2 * P, np.inf)
    la = np.full(2 * P, np.nan)
    lb = np.full(2 * P, np.nan)
    if B is not None:
        _prescan(pred_at, m, c, nn, np.concatenate([rate, rate]), np.concatenate([B, B]), a, b, la, lb, R)
    x = np.where(np.isfinite(b), 0.5 * b, x0)
    x = np.minimum(np.where(a > 0, 2.0 * a, x), R)
    todo = np.flatnonzero(~(np.isfinite(b) & np.isfinite(la)))
    for _ in range(80):
        if todo.size == 0:
            break
        ok, lev, _, _ = pred(x[todo], todo)
        t_in, t_out = todo[ok], todo[~ok]
        b[t_in] = np.minimum(b[t_in], x[t_in])
        lb[t_in] = np.where(x[t_in] <= b[t_in], lev[ok], lb[t_in])
        a[t_out] = np.maximum(a[t_out], x[t_out])
        la[t_out] = np.where(x[t_out] >= a[t_out], lev[~ok], la[t_out])
        x[t_in] = 0.5 * x[t_in]
        x[t_out] = np.minimum(2.0 * x[t_out], R[t_out])
        beyond = ~np.isfinite(b) & (a >= R)
        if beyond.any():   # asked at the reach and still below the level: the edge lies past it
            i = np.flatnonzero(beyond)[:1]
            reach[1](R[i], m[i])
        done = np.isfinite(b) & (np.isfinite(la) | (b < 1e-300))
        todo = np.flatnonzero(~done)
    # rows still true at the smallest eps tried: the zone reaches eps -> 0 (mu = 0)
    la = np.where(np.isnan(la), c, la)
    # 2. bisection on the angle until the false end is in the gap and the true end in the zone;
    # a bracket from gap n to gap n + 1 holds all of zone n, where tr M changes sign (tr M / 2 =
    # cos theta passes 0 at theta = (n + 1/2) pi): that zero, found by Illinois iterations, is
    # a point of the zone however thin it is (bisection would need to land in it)
    want_a = c  # lower: the gap's level n; upper: zone n, level n + 1/2
    want_b = c + 0.5
    thin = np.zeros(2 * P, bool)
    for _ in range(1100):
        good = (la == want_a) & (lb == want_b)
        straddle = ~good & ~thin & (la == nn) & (lb == nn + 1)
        if straddle.any():
            # the lower and upper edge of one zone often share the bracket: solve it once
            twin = np.zeros(2 * P, bool)
            twin[P:] = straddle[:P] & straddle[P:] & (a[:P] == a[P:]) & (b[:P] == b[P:])
            i = np.flatnonzero(straddle & ~twin)
            z, fz = _illinois(trace, m[i], np.ones(i.size), a[i], b[i], target=0.0, plateau=True, noise=noise)
            k = np.flatnonzero(twin)
            src = np.searchsorted(i, k - P)
            i = np.concatenate([i, k])
            z = np.concatenate([z, z[src]])
            fz = np.concatenate([fz, fz[src]])
            inside = fz == 0.0  # |tr M / 2| < 1: in zone n
            lower = ~upper[i]
            j = i[inside & lower]
            b[j], lb[j] = z[inside & lower], nn[j] + 0.5
            j = i[inside & ~lower]
            a[j], la[j] = z[inside & ~lower], nn[j] + 0.5
            # a zone thinner than the spacing of doubles: both edges at the zero
            j = i[~inside]
            thin[j] = True
            a[j] = b[j] = z[~inside]
            good = (la == want_a) & (lb == want_b)
        live = ~good & ~thin & (b > np.nextafter(a, np.inf)) & (a > 0)
        live |= ~good & ~thin & (a == 0) & (b > 1e-300)
        idx = np.flatnonzero(live)
        if idx.size == 0:
            break
        mid = 0.5 * (a[idx] + b[idx])
        ok, lev, _, _ = pred(mid, idx)
        a[idx] = np.where(ok, a[idx], mid)
        la[idx] = np.where(ok, la[idx], lev)
        b[idx] = np.where(ok, mid, b[idx])
        lb[idx] = np.where(ok, lev, lb[idx])
    good = (la == want_a) & (lb == want_b) & (a > 0)
    # 3. Illinois on asinh(sgn tau) - asinh(1): > 0 in the gap, < 0 in the zone
    # (tr M = +2 at the edges of the gap below an even zone, -2 below an odd one)
    gap_level = np.where(upper, nn + 1, nn)
    sgn = np.where(gap_level % 2 == 0, 1.0, -1.0)
    res = np.where(upper, b, a)
    idx = np.flatnonzero(good)
    if idx.size:
        res[idx] = _illinois(trace, m[idx], sgn[idx], a[idx], b[idx])
    return res[:P], res[P:]


def _prescan(level_at, m, c, n, rate, B, a, b, la, lb, R):
    """Brackets ``[a, b]`` (and their levels) from the angle sampled at each distinct ``mu``.

    At ``mu`` the angle of zone ``n`` lies within ``B`` of ``rate eps``, so its edges lie in
    ``[(n pi - B) / rate, ((n + 1) pi + B) / rate]``; the span of all the zones asked at that
    ``mu`` is sampled every ``pi / 3`` of elliptic angle. The angle does not decrease along
    ``eps``, so each task's bracket is the last sample below its level and the first above.
    """
    keys, inv = np.unique(m, return_inverse=True)
    G = keys.size
    n_min = np.full(G, np.iinfo(np.int64).max)
    n_max = np.full(G, -1)
    np.minimum.at(n_min, inv, n)
    np.maximum.at(n_max, inv, n)
    r = np.zeros(G)
    bb = np.zeros(G)
    r[inv] = rate
    bb[inv] = B
    top = np.full(G, np.inf)
    np.minimum.at(top, inv, R)
    lo = np.minimum(np.maximum(n_min * PI - bb, PI / 3.0) / r, top)
    hi = np.minimum(((n_max + 1) * PI + bb) / r, top)
    K = int(min(np.max(np.ceil((hi - lo) * r / (PI / 3.0))) + 1, 400))
    grid = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, K)[None, :]
    lev = level_at(grid.ravel(), np.repeat(keys, K)).reshape(G, K)
    lev = np.maximum.accumulate(lev, axis=1)  # monotone (guards a rounding wobble at an edge)
    below = lev[inv] <= c[:, None]
    cnt = below.sum(axis=1)  # samples at or below the level: the transition follows them
    rows = np.arange(c.size)
    has_a = cnt > 0
    has_b = cnt < K
    ia = np.maximum(cnt - 1, 0)
    ib = np.minimum(cnt, K - 1)
    g = grid[inv]
    L = lev[inv]
    a[has_a] = g[rows, ia][has_a]
    la[has_a] = L[rows, ia][has_a]
    b[has_b] = g[rows, ib][has_b]
    lb[has_b] = L[rows, ib][has_b]


def _illinois(trace, m, sgn, a, b, target=A1, plateau=False, noise=None):
    """Root of ``F = asinh(sgn tau) - target`` between ``a`` and ``b`` (opposite signs of ``F``).

    Returns the end of the final bracket with ``F >= 0`` (the unstable side of an edge). With
    ``plateau``, ``F = sign(tau) max(|asinh(tau)| - asinh(1), 0)`` instead: 0 on the whole
    zone between two gaps and nearly linear in ``eps`` on either side (the growth), so the
    secant lands in a thin zone in a few steps; returns ``(x, F(x))`` of the first point of the
    zone (``F = 0``), or the better end of the final bracket where no double lies in it. With
    ``noise`` (plateau): a row stops once its bracket is within 1e-9 of its value and a point of it
    has ``|tau|`` within a bound on its error above 1 (the rounding there spans the whole zone:
    further secant steps would follow the noise).
    """
    lost = np.zeros(a.size, bool)   # (plateau rows whose trace is noise about the zone)

    def F(x, rows):
        tau, lt = trace(x, m[rows])
        f = _F(tau, lt, sgn[rows]) + A1
        if plateau:
            if noise is not None:
                log_err = noise(x, m[rows])   # (in logarithms: tau and its bound may overflow)
                with np.errstate(invalid="ignore"):
                    lost[rows] |= (log_err > 0.0) & (lt <= log_err)
            return np.sign(f) * np.maximum(np.abs(f) - A1, 0.0)
        return f - target

    allr = np.arange(a.size)
    x0, x1 = a.copy(), b.copy()
    f0, f1 = F(x0, allr), F(x1, allr)
    g0 = f0.copy()  # the true value at x0 (f0 is halved by the Illinois rule)
    for _ in range(200):
        live = (np.nextafter(x0, x1) != x1) & (f0 != 0) & (f1 != 0) & (np.sign(f0) != np.sign(f1))
        if plateau:
            live &= (g0 != 0) & ~(lost & (np.abs(x1 - x0) < 1e-9 * np.abs(x1)))
        idx = np.flatnonzero(live)
        if idx.size == 0:
            break
        xa, xb, ya, yb = x0[idx], x1[idx], f0[idx], f1[idx]
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            x = xb - yb * (xb - xa) / (yb - ya)
        lo, hi = np.minimum(xa, xb), np.maximum(xa, xb)
        bad = ~np.isfinite(x) | (x <= lo) | (x >= hi)
        x = np.where(bad, 0.5 * (xa + xb), x)
        x = np.where(x <= lo, hi, x)  # adjacent doubles whose mean rounds onto an end
        fx = F(x, idx)
        flip = np.sign(fx) != np.sign(yb)
        # Illinois: the retained end's value is halved when the same end is kept twice
        x0[idx] = np.where(flip, xb, xa)
        f0[idx] = np.where(flip, yb, 0.5 * ya)
        g0[idx] = np.where(flip, f1[idx], g0[idx])
        x1[idx], f1[idx] = x, fx
    if plateau:
        use1 = np.abs(f1) <= np.abs(g0)
        return np.where(use1, x1, x0), np.where(use1, f1, g0)
    return np.where((f1 >= 0) & ((f0 < 0) | (f1 == 0)), x1, x0)
