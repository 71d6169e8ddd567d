"""The stability questions asked of any drive, with damping: the bodies behind the public
functions of :mod:`kapitza.zones`, :mod:`kapitza.propagation` and :mod:`kapitza.analysis`
when they are given a drive other than the paper's undamped square wave.

Inputs are trusted (validated by the public functions). Damping enters as the damping ratio
``zeta = c / (2 sqrt(g/l))`` of the hanging pendulum, which keeps it dimensionless and fixed
along Arnold's plane for a given rod; ``kappa = c T = 2 sqrt(8) zeta mu eps``
(:mod:`kapitza.drives._base`).
"""
from __future__ import annotations

import numpy as np

from ._base import PI
from ._piecewise import PiecewiseConstant, _bisect_bits, _window_margin, window_zones


def zeta_of(c, l, g):
    """Damping ratio ``zeta = c / (2 sqrt(g/l))`` of the hanging pendulum (``c`` in 1/s)."""
    return 0.5 * c * np.sqrt(l / g)


def damping_of(zeta, l, g):
    """Viscous damping ``c = 2 zeta sqrt(g/l)`` [1/s] of the damping ratio ``zeta`` (inverse of :func:`zeta_of`)."""
    return 2.0 * zeta * np.sqrt(g / l)


def floquet(eps, mu, drive, zeta):
    """``(trace, determinant, multipliers, growth, rotation_number, stable, zone)``.

    ``trace`` and ``determinant`` are those of the damped monodromy ``M_theta`` over ``2T``:
    ``tr M_theta = exp(-kappa) tr M_phi``, ``det M_theta = exp(-2 kappa)``; the multipliers are
    ``exp(-kappa)`` times those of the undamped ``phi``-system, largest modulus first;
    ``growth = log max|lambda|`` (negative where the damped motion decays).
    """
    tau, growth, theta, stable, zone, kappa = drive._floquet(eps, mu, zeta)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        trace = 2.0 * tau * np.exp(-kappa)
        trace = np.where(np.isfinite(tau) | (kappa == 0), trace,
                         np.sign(tau) * np.exp(np.minimum(growth + np.log1p(np.exp(-2.0 * (growth + kappa))), 709.0)))
        det = np.exp(-2.0 * kappa)
        phi_growth = growth + kappa
        elliptic = (zone >= 0) & (phi_growth <= 0)
        sgn = np.where(tau < 0, -1.0, 1.0)
        big = sgn * np.exp(growth)
        small = sgn * np.exp(-phi_growth - kappa)
        rot1 = np.exp(-kappa + 1j * theta)
        rot2 = np.exp(-kappa - 1j * theta)
    lam1 = np.where(elliptic, rot1, big + 0j)
    lam2 = np.where(elliptic, rot2, small + 0j)
    mult = np.stack([lam1, lam2], axis=-1)
    growth = np.where(elliptic, 0.0 - kappa, growth)
    return trace, det, mult, growth, theta / (2.0 * PI) + 0.0, stable, zone


def verdict(eps, mu, drive, zeta):
    """``(stable, zone)`` (zone -1 where unstable)."""
    _, _, _, stable, zone, _ = drive._floquet(eps, mu, zeta)
    return stable, np.where(stable, zone, -1).astype(np.int64)


def edges(mu, n, drive, zeta):
    """``(eps_lo, eps_hi)`` of zone ``n``; NaN where the drive has no such zone at this ``mu``."""
    return drive._edges(mu, n, zeta)


def window_edges(drive, mu, e0, e1, zeta):
    """``(rows, zone, lo, hi)``: the edges of every zone that may meet ``[e0, e1]`` at each ``mu``."""
    zeta = np.broadcast_to(np.asarray(zeta, float), mu.shape)
    if isinstance(drive, PiecewiseConstant) and not np.any(zeta > 0) and drive.name != "square":
        return window_zones(drive, mu, np.full(mu.size, e0), np.full(mu.size, e1))
    if drive.name == "sine" and not np.any(zeta > 0):
        from ..mathieu import _sine_window

        ok = np.flatnonzero(mu < 1.0)
        rows, zone, lo, hi = _sine_window(mu[ok], e1)
        return ok[rows], zone, lo, hi
    if np.any(zeta > 0) and drive.name != "square":
        return _damped_window(drive, mu, zeta, e0, e1)
    n_lo, n_hi = _zone_range(drive, mu, zeta, e0, e1)
    counts = np.maximum(n_hi - n_lo + 1, 0)
    r_idx = np.repeat(np.arange(mu.size), counts)
    z_idx = n_lo[r_idx] + np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    lo, hi = drive._edges(mu[r_idx], z_idx, zeta[r_idx])
    return r_idx, z_idx, lo, hi


def _damped_window(drive, mu, zeta, e0, e1):
    """Damped zones of a chart ``[e0, e1]``: from the undamped ``phi``-zones in ``[0, 2 e1]``.

    Damped zone ``n`` lies between the ``phi``-zones ``n - 1`` and ``n + 1``; the ``phi``-zones in
    view come from the undamped window method at ``mu_c``. A damped edge beyond ``2 e1`` (in a
    gap that reaches out of that window) is reported as ``inf``: the chart paints to its end.
    """
    from ._base import _damped_edges

    mu_c = mu * np.sqrt(1.0 + zeta * zeta)
    live = np.flatnonzero(mu_c < 1.0) if drive.name == "sine" else np.arange(mu.size)
    cap = 2.0 * e1
    r0, z0, lo0, hi0 = window_edges(drive, mu_c[live], 0.0, cap, np.zeros(live.size))
    r0 = live[r0]
    keep = np.isfinite(lo0) & (lo0 <= cap)
    r0, z0, lo0, hi0 = r0[keep], z0[keep], lo0[keep], hi0[keep]
    # phi-edges by (row, zone)
    key = r0 * 100000 + z0
    order = np.argsort(key)
    key, lo0, hi0 = key[order], lo0[order], hi0[order]

    def look(rows, zones, arr, default):
        k = rows * 100000 + zones
        i = np.clip(np.searchsorted(key, k), 0, max(key.size - 1, 0))
        hit = (key.size > 0) & (key[i] == k) if key.size else np.zeros(k.shape, bool)
        return np.where(hit, arr[i] if key.size else default, default)

    rows, zones = r0[order], key % 100000
    lo_n = lo0
    hi_n = np.minimum(hi0, cap)
    hi_prev = np.where(zones == 0, 0.0, look(rows, zones - 1, hi0, np.nan))
    lo_next = look(rows, zones + 1, lo0, cap)
    ok = np.isfinite(hi_prev)
    rows, zones, lo_n, hi_n, hi_prev, lo_next = (x[ok] for x in (rows, zones, lo_n, hi_n, hi_prev, lo_next))
    lo, hi = _damped_edges(drive, mu[rows], zones, zeta[rows], phi=(lo_n, hi_n, hi_prev, lo_next))
    hi = np.where((hi >= cap) | (lo_next >= cap) & (hi >= lo_next), np.inf, hi)
    return rows, zones, lo, hi


def grid(eps, mu, drive, zeta, out):
    """Paint ``out[i, j] = stable(eps[j], mu[i])`` from the exact edges of every zone in view.

    ``eps`` sorted ascending, ``out`` zeroed, shape ``(len(mu), len(eps))``.
    """
    if drive.name == "sine" and not np.any(zeta > 0):
        from ..mathieu import _sine_grid  # crossings bisected only until no pixel is left inside

        return _sine_grid(eps, mu, out)
    rows, _, lo, hi = window_edges(drive, mu, float(eps[0]), float(eps[-1]), zeta)
    i0 = np.searchsorted(eps, lo, side="right")
    i1 = np.searchsorted(eps, hi, side="left")
    keep = np.isfinite(lo) & np.isfinite(hi) & (i1 > i0)
    flat = out.reshape(-1)
    W = eps.size
    base = rows[keep] * W
    for a, b in zip((base + i0[keep]).tolist(), (base + i1[keep]).tolist()):
        flat[a:b] = True
    return out


def _zone_range(drive, mu, zeta, e0, e1):
    """Zone indices that may meet ``[e0, e1]`` at each ``mu`` (from the elliptic angle)."""
    mu_c = mu * np.sqrt(1.0 + np.asarray(zeta) ** 2)
    if isinstance(drive, PiecewiseConstant):
        rate, _ = _window_margin(mu_c, drive.levels, drive._durations)
        B = (len(drive.levels) + 1) * PI
    else:  # sine: zone n lies near sqrt(q) (1 - mu^2) = 2n + 1 (a_n ~ -2q + 2(2n+1) sqrt q), sqrt q = 4 eps/pi
        rate = 2.0 * np.maximum(1.0 - mu_c * mu_c, 0.0)
        B = 2.0 * PI
    n_lo = np.maximum(np.floor((rate * e0 - B) / PI) - 1, 0).astype(np.int64)
    n_hi = np.floor((rate * e1 + B) / PI).astype(np.int64) + 1
    return n_lo, np.where(rate > 0, n_hi, n_lo - 1)


def margin(eps, mu, drive, zeta):
    """``(stable, zone, eps_lo, eps_hi, margin)`` as :class:`kapitza.StabilityMargin`: the zone
    containing the point (or the nearest), its edges, and the signed relative distance."""
    eps, mu, zeta = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float))
    stable, zone = verdict(eps, mu, drive, zeta)
    shape = eps.shape
    e, m, z = eps.ravel(), mu.ravel(), zeta.ravel()
    n_lo, n_hi = _zone_range(drive, m, z, e, e)
    best = np.full(e.size, -np.inf)
    b_zone = np.full(e.size, -1, np.int64)
    b_lo = np.full(e.size, np.nan)
    b_hi = np.full(e.size, np.nan)
    for k in range(int(np.max(n_hi - n_lo, initial=-1)) + 1):
        n = n_lo + k
        live = n <= n_hi
        if not live.any():
            continue
        lo, hi = drive._edges(m[live], n[live], z[live])
        d = np.minimum(e[live] - lo, hi - e[live]) / e[live]
        d = np.where(np.isfinite(d), d, -np.inf)
        idx = np.flatnonzero(live)
        better = d > best[idx]
        sel = idx[better]
        best[sel] = d[better]
        b_zone[sel] = n[live][better]
        b_lo[sel] = lo[better]
        b_hi[sel] = hi[better]
    st = stable.ravel()
    zn = zone.ravel()
    # the containing zone wins (its margin is the one a user asks for)
    b_zone = np.where(st, zn, b_zone)
    return (stable, b_zone.reshape(shape), b_lo.reshape(shape), b_hi.reshape(shape), best.reshape(shape))


def along_amplitude(T, n, l, g, drive, c):
    """``(A_lo, A_hi)`` of zone ``n`` at fixed half-period ``T`` (scalars; bisection on the zone).

    At fixed ``T`` the ``phi``-stiffness ``(T^2/l) (g (1 + zeta^2) + A s)`` grows with ``A`` in
    the attracting segments: the zone index read from the rotation angle is bisected in ``A``
    on the bit patterns of doubles.
    """
    zeta = zeta_of(c, l, g)

    def arnold(A):
        return T * np.sqrt(A / (8.0 * l)), np.sqrt(g / A)

    def reached(A, level, strictly):
        eps, mu = arnold(A)
        st, z = verdict(eps, mu, drive, np.full(np.shape(A), zeta))
        theta = drive._floquet(eps, mu, np.full(np.shape(A), zeta))[2]
        k = np.where(st, z + 0.5, np.rint(theta / PI))
        return k > level if strictly else k >= level

    hi = np.array([max(g, 1.0)])
    for _ in range(1100):
        if reached(hi, n + 1, False).all():
            break
        hi = hi * 2.0
    _, A_hi = _bisect_bits(lambda A: reached(A, n + 1, False), np.zeros(1), hi)
    A_lo, _ = _bisect_bits(lambda A: reached(A, n, True), np.zeros(1), A_hi)
    return float(A_lo[0]), float(A_hi[0])


# ---------------------------------------------------------------- motion of the linear equation
def _segment_flow(s, h, k=None):
    """Entries (a, b, c, d) of the exact flow of ``x'' = s x`` over ``h`` (physical units), times
    ``e^{-k}`` when ``k`` is given: formed as ``e^{r - k}`` where ``r = sqrt(s) h`` is large, so a
    damped step (``s`` raised by ``c^2/4``, ``k = c h / 2``) does not overflow where its product
    with ``e^{-k}`` is a double."""
    from ..propagation import _flow

    s, h = np.asarray(s, float), np.asarray(h, float)
    c, sd, ds = _flow(s, h)
    if k is None:
        return c, sd, ds, c
    with np.errstate(over="ignore", invalid="ignore"):
        e = np.exp(-k)
        c, sd, ds = c * e, sd * e, ds * e
        w = np.sqrt(np.abs(s))
        big = (s > 0) & (w * h > 700.0)  # cosh r = sinh r = e^r / 2 to rounding
        half = 0.5 * np.exp(w * h - k)
        c = np.where(big, half, c)
        sd = np.where(big, half / np.where(big, w, 1.0), sd)
        ds = np.where(big, half * w, ds)
    return c, sd, ds, c


def _mul(P, Q):
    a, b, c, d = P
    e, f, g_, h = Q
    return a * e + b * g_, a * f + b * h, c * e + d * g_, c * f + d * h


def monodromy(T, A, l, g, drive, c):
    """``M_theta`` over one period ``2T`` of ``theta'' + c theta' = (g + a(t))/l theta``, shape ``(..., 2, 2)``.

    Piecewise-constant drives: ``exp(-c T) S^{-1} (prod of phi-flows) S`` with the stiffness of
    each step raised by ``c^2/4`` (``docs/drives.md`` section 3), each step carrying its share of
    ``exp(-c T)``. The sine drive: one period
    integrated by DOP853 (rtol 1e-12).
    """
    T, A, l, g, c = np.broadcast_arrays(*(np.asarray(x, float) for x in (T, A, l, g, c)))
    with np.errstate(over="ignore", invalid="ignore"):
        if isinstance(drive, PiecewiseConstant):
            P = (np.ones(T.shape), np.zeros(T.shape), np.zeros(T.shape), np.ones(T.shape))
            for lev, f in zip(drive.levels, drive.fractions):
                # each step carries its share e^{-c f T} of e^{-c T}: no e^{c T}-sized entries
                P = _mul(_segment_flow((g + A * lev) / l + 0.25 * c * c, 2.0 * f * T, c * f * T), P)
        else:
            P = _ivp_period(T, A, l, g, drive)
        a, b, cc, d = P
        half = 0.5 * c
        # S^{-1} P S with S = [[1, 0], [c/2, 1]]
        m11 = a + b * half
        m12 = b
        m21 = cc + (d - a) * half - b * half * half
        m22 = d - b * half
        if not isinstance(drive, PiecewiseConstant):
            e = np.exp(-c * T)
            m11, m12, m21, m22 = (v * e for v in (m11, m12, m21, m22))
        M = np.stack([np.stack([m11, m12], -1), np.stack([m21, m22], -1)], -2)
    return M


def _ivp_period(T, A, l, g, drive, rtol=1e-12):
    """The undamped-phi flow over one period of a smooth drive (DOP853), entrywise arrays."""
    from scipy.integrate import solve_ivp

    out = [np.empty(T.shape) for _ in range(4)]
    for idx in np.ndindex(T.shape):
        Ti, Ai, li, gi = T[idx], A[idx], l[idx], g[idx]
        cols = []
        for y0 in ((1.0, 0.0), (0.0, 1.0)):
            sol = solve_ivp(lambda t, y: [y[1], (gi + Ai * drive._shape(t / Ti)) / li * y[0]],
                            (0.0, 2.0 * Ti), y0, method="DOP853", rtol=rtol, atol=1e-14 * max(1.0, abs(y0[1])))
            cols.append(sol.y[:, -1])
        out[0][idx], out[2][idx] = cols[0]
        out[1][idx], out[3][idx] = cols[1]
    return tuple(out)


def linear_motion(t, theta0, dtheta0, T, A, l, g, drive, c):
    """Exact ``theta(t), theta'(t)`` of the damped linear equation for a piecewise-constant drive.

    Whole periods by ``M^k = exp(-k c T) S^{-1} (U_{k-1}(tau) M_phi - U_{k-2}(tau) I) S``
    (Cayley-Hamilton with Chebyshev polynomials of the half-trace of the undamped
    ``phi``-system), then the steps of the last, partial period; the sine drive is
    integrated by DOP853 (rtol 1e-11) instead.
    """
    from ..propagation import _chebyshev_pair

    t, theta0, dtheta0, T, A, l, g, c = np.broadcast_arrays(
        *(np.asarray(x, float) for x in (t, theta0, dtheta0, T, A, l, g, c)))
    if not isinstance(drive, PiecewiseConstant):
        return _ivp_motion(t, theta0, dtheta0, T, A, l, g, drive, c)
    eps = T * np.sqrt(A / (8.0 * l))
    mu = np.sqrt(g / A)
    zeta = zeta_of(c, l, g)
    mu_c = mu * np.sqrt(1.0 + zeta * zeta)
    f = drive._floquet0(eps, mu_c)
    period = 2.0 * T
    k = np.floor(t / period)
    r = t - k * period
    over = r >= period
    k = np.where(over, k + 1.0, k)
    r = np.where(over, r - period, np.maximum(r, 0.0))
    half = 0.5 * c
    # phi-state at t = 0
    p0 = theta0
    q0 = dtheta0 + half * theta0
    Mphi = (np.ones(T.shape), np.zeros(T.shape), np.zeros(T.shape), np.ones(T.shape))
    for lev, fr in zip(drive.levels, drive.fractions):
        Mphi = _mul(_segment_flow((g + A * lev) / l + half * half, fr * period), Mphi)
    u1, u2 = _chebyshev_pair(k, f.tau, f.growth, f.theta, f.zone >= 0)
    with np.errstate(over="ignore", invalid="ignore"):
        a, b, cc, d = Mphi
        p = np.where(k == 0, p0, (u1 * a - u2) * p0 + u1 * b * q0)
        q = np.where(k == 0, q0, u1 * cc * p0 + (u1 * d - u2) * q0)
        start = 0.0
        for lev, fr in zip(drive.levels, drive.fractions):
            h = fr * period
            dt = np.clip(r - start, 0.0, h)
            fa, fb, fc, fd = _segment_flow((g + A * lev) / l + half * half, dt)
            p, q = fa * p + fb * q, fc * p + fd * q
            start = start + h
        decay = np.exp(-half * t)
        th = decay * p
        dth = decay * (q - half * p)
    bad = ~(np.isfinite(th) & np.isfinite(dth))
    if bad.any():
        i = tuple(np.argwhere(bad)[0])
        raise OverflowError(f"the motion grows beyond the range of a double (t = {float(t[i]):.6g} s)")
    return th, dth


def _ivp_motion(t, theta0, dtheta0, T, A, l, g, drive, c, rtol=1e-11):
    from scipy.integrate import solve_ivp

    th = np.empty(t.shape)
    dth = np.empty(t.shape)
    for idx in np.ndindex(t.shape):
        if t[idx] == 0:
            th[idx], dth[idx] = theta0[idx], dtheta0[idx]
            continue
        Ti, Ai, li, gi, ci = T[idx], A[idx], l[idx], g[idx], c[idx]
        sol = solve_ivp(lambda tt, y: [y[1], (gi + Ai * drive._shape(np.mod(tt / Ti, 2.0))) / li * y[0] - ci * y[1]],
                        (0.0, t[idx]), (theta0[idx], dtheta0[idx]), method="DOP853", rtol=rtol, atol=1e-13)
        th[idx], dth[idx] = sol.y[:, -1]
    return th, dth
