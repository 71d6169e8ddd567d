"""The generic engine: every stability question asked of any drive, with damping.

These are the bodies behind the methods of :class:`kapitza.drives.Drive` (and so behind the
public functions of :mod:`kapitza.zones`, :mod:`kapitza.propagation` and
:mod:`kapitza.analysis`); a drive that knows better (the square wave's closed forms) overrides
the method, and this module never learns of it. A drive is asked here only for its undamped
data -- :meth:`~kapitza.drives.Drive._floquet0`, :meth:`~kapitza.drives.Drive._edges0` and
their helpers -- and the damping layer, the searches and the motion are built on top.

Inputs are trusted (validated by the public functions). Damping enters as the damping ratio
``zeta = c / (2 sqrt(g/l))`` of the hanging pendulum, which keeps it dimensionless and fixed
along Arnold's plane for a given rod; ``kappa = c T = 2 sqrt(8) zeta mu eps``
(:mod:`kapitza.drives._base`, ``docs/drives.md`` section 3).

This module imports no drive: the drive classes import it (one direction, no cycle).
"""
from __future__ import annotations

import functools
import math

import numpy as np

from .._exact import log_cosh
from .._square import _chebyshev_pair, _flow

PI = np.pi
SQRT8 = np.sqrt(8.0)


def zeta_of(c, l, g):
    """Damping ratio ``zeta = c / (2 sqrt(g/l))`` of the hanging pendulum (``c`` in 1/s)."""
    return 0.5 * c * np.sqrt(l / g)


def damping_of(zeta, l, g):
    """Viscous damping ``c = 2 zeta sqrt(g/l)`` [1/s] of the damping ratio ``zeta`` (inverse of :func:`zeta_of`)."""
    return 2.0 * zeta * np.sqrt(g / l)


# ---------------------------------------------------------------- the damping layer
def _traced(drive):
    """Whether the drive's ``_floquet0`` takes ``trace`` and ``phi`` (a subclass written to the older
    contract, ``_floquet0(eps, mu, certify=True)``, reports no error bound)."""
    return _traced_class(type(drive))


@functools.lru_cache(maxsize=None)
def _traced_class(cls):
    import inspect

    return "trace" in inspect.signature(cls._floquet0).parameters


def damped_floquet(drive, eps, mu, zeta, certify=True, trace=False):
    """Floquet data with damping ratio ``zeta`` (trusted, broadcast arrays).

    Returns ``(tau, growth, theta, stable, zone, kappa)``: ``tau`` the half-trace of the
    undamped ``phi``-system, ``growth = log max|lambda|`` of the damped one (negative:
    decay), ``kappa = c T``.

    ``trace``: the trace is reported: a seventh item, ``tau_error``, bounds the absolute error of
    ``tau`` (``inf`` where the drive gives no bound), and the drive recomputes ``tau`` in extended
    precision where it is ill-conditioned (:meth:`~kapitza.drives.Drive._floquet0`), with damping
    at ``mu^2 (1 + zeta^2)`` formed exactly (``mu_c`` rounded would move a cancelling trace by more
    than its size).
    """
    eps, mu, zeta = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float),
                                        np.asarray(zeta, float))
    damped = np.any(zeta > 0)
    mu_c = mu * np.sqrt(1.0 + zeta * zeta) if damped else mu
    # certified damped verdicts about as cheap as the doubles: the points whose phi-verdict the
    # doubles leave open are settled with the damped excess's (one extended product for both)
    exact_all = bool(certify and damped and not trace and drive._damped_certified
                     and drive._certified_cheap(True))
    phi = (mu.reshape(-1), zeta.reshape(-1)) if damped else None
    if trace and _traced(drive):
        f = drive._floquet0(eps, mu_c, certify, trace=True, phi=phi)
    elif exact_all or phi is None or not _traced(drive):
        f = drive._floquet0(eps, mu_c, False if exact_all else certify)
        if exact_all and f.unsure is None:   # (a drive that does not say which: its own certified verdicts)
            f, exact_all = drive._floquet0(eps, mu_c, certify), False
    else:   # (certified phi-verdicts; a drive may mark those whose trace is too rough for G: settled below)
        f = drive._floquet0(eps, mu_c, certify, phi=phi)
    rough = None if exact_all or f.unsure is None else f.unsure.reshape(-1)
    extra = ()
    if trace:
        extra = (np.full(eps.shape, np.inf) if f.tau_error is None else f.tau_error,)
    if not damped:
        return (f.tau, f.growth, f.theta, f.zone >= 0, f.zone, np.zeros(eps.shape)) + extra
    kappa = 2.0 * SQRT8 * zeta * mu * eps
    # |tr M_phi| < 2 cosh(kappa), compared in logarithms (both sides may overflow), or
    # without cancellation where tr M_phi / 2 is near 1 (_damped_excess).
    with np.errstate(divide="ignore"):
        # (with exact_all every G near 0 is settled exactly below: no cancellation-free form needed)
        G = _damped_excess(drive, eps, mu_c, kappa, f.log_tau, f.zone < 0,
                           cancel_free=not exact_all).reshape(eps.shape)
        stable = (f.zone >= 0) | (G < 0)
    growth = f.growth - kappa
    if certify and drive._damped_certified:
        # where rounding may decide, the exact doubles decide in extended precision
        # (kapitza._certify.damped_mp): G near 0 by less than it moves over 32 ulp of eps (its own
        # rounding, and that of mu_c, move it by the like of a few ulp of eps); a drive whose exact
        # verdicts cost about what the doubles do is asked for every G near 0, and for every point
        # whose phi-verdict the doubles left open
        Gf = G.reshape(-1)
        near0 = np.abs(Gf) < 1e-4
        if exact_all:
            near0 |= f.unsure.reshape(-1)
        cand = np.flatnonzero(near0)
        unsure = cand
        if cand.size and not drive._certified_cheap(True):
            e, m, z = eps.reshape(-1)[cand], mu.reshape(-1)[cand], zeta.reshape(-1)[cand]
            h = 16.0 * np.finfo(float).eps * e
            with np.errstate(invalid="ignore"):
                up, down = _excess(drive, np.stack([e + h, e - h]), m, z)
                swing = np.abs(up - down)
            # G's own accuracy: 1e-13 from exact products, the engine's error relative to |tau_phi|
            # for a drive given by its shape
            acc = 1e-13 if not drive._from_shape else drive._trace_error(
                e, m * np.sqrt(1.0 + z * z)) / np.maximum(np.abs(f.tau.reshape(-1)[cand]), 1.0)
            unsure = cand[~(np.abs(Gf[cand]) > swing + acc)]
        if rough is not None and rough.any():
            unsure = np.union1d(unsure, np.flatnonzero(rough))
        res = drive._damped_exact(eps.reshape(-1)[unsure], mu.reshape(-1)[unsure],
                                  zeta.reshape(-1)[unsure], growth=trace) if unsure.size else None
        if res is not None:
            stable, growth = np.array(stable, bool, copy=True), np.array(growth, float, copy=True)
            stable.reshape(-1)[unsure] = [r[0] for r in res]
            growth.reshape(-1)[unsure] = [r[1] for r in res]
    # (a phi-zone the doubles gave where the exact verdict says unstable: the point is past its edge)
    zone = np.where((f.zone >= 0) & stable, f.zone, -1)
    gap = stable & (f.zone < 0)
    if np.any(gap):
        # Stable only thanks to the damping: the point sits in the gap between zones
        # k - 1 and k (theta = k pi). It belongs to the zone whose edge it is nearer,
        # i.e. to k - 1 while |tau| still rises with eps, to k once it falls again.
        # (below zone 0, k = 0, there is nothing to ask)
        k = np.rint(f.theta / PI).astype(np.int64)
        zone[gap & (k <= 0)] = 0
        ask = gap & (k > 0)
        if np.any(ask):
            e, m, z = eps[ask], mu[ask], zeta[ask]
            h = 1e-7 * e
            up, down = _excess(drive, np.stack([e + h, e - h]), m, z)   # (one call for both sides)
            zone[ask] = np.where(up > down, k[ask] - 1, k[ask])
    return (f.tau, growth, f.theta, stable, zone, kappa) + extra


def damped_edges(drive, mu, n, zeta):
    """``(eps_lo, eps_hi)`` of zone ``n`` with damping ratio ``zeta`` (trusted arrays)."""
    mu, n, zeta = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64),
                                      np.asarray(zeta, float))
    if not np.any(zeta > 0):
        return drive._edges0(mu, n)
    return _damped_edges(drive, mu, n, zeta)


def _excess(drive, eps, mu, zeta):
    """G = log|tau_phi| - log cosh(kappa): the damped upright is stable iff G < 0 (or on a zone)."""
    eps, mu, zeta = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float))
    shape = eps.shape
    eps, mu, zeta = eps.reshape(-1), mu.reshape(-1), zeta.reshape(-1)
    mu_c = mu * np.sqrt(1.0 + zeta * zeta)
    kappa = 2.0 * SQRT8 * zeta * mu * eps
    # where the phases are short, tau_phi - 1 itself (no product needed); elsewhere log|tau_phi|
    G = _damped_excess(drive, eps, mu_c, kappa)
    rest = np.isnan(G)
    if rest.any():
        # on a phi-zone log|tau_phi| < 0 <= log cosh(kappa): G < 0 there without asking for the zone
        G[rest] = drive._log_tau0(eps[rest], mu_c[rest]) - log_cosh(kappa[rest])
    return G.reshape(shape)


def _damped_excess(drive, eps, mu_c, kappa, log_tau=None, where=None, cancel_free=True):
    """``G = log|tau_phi| - log cosh(kappa)``, without cancellation where ``tau_phi > 0`` and the
    drive gives ``y = tau_phi - 1`` accurately (short phases): there
    ``G = log1p((y - 2 sinh^2(kappa/2)) / cosh(kappa))``, whose terms are of the size of the result.

    Below zone 0 at small ``mu`` both logarithms are of order ``eps^2 mu^2`` and ``G`` of order
    ``eps^4`` (``docs/drives.md``, section 3). With ``log_tau`` given, ``G`` is formed from it
    except at the rows (of ``where``, all by default) with ``tau_phi`` near 1 (``cancel_free=False``:
    at none); without it, rows the drive cannot form are NaN. Flat arrays.
    """
    eps, mu_c, kappa = (np.asarray(v, float).reshape(-1) for v in np.broadcast_arrays(eps, mu_c, kappa))
    if log_tau is None:
        G = np.full(eps.shape, np.nan)
        near = kappa < 1.0
    else:
        log_tau = np.asarray(log_tau, float).reshape(-1)
        with np.errstate(divide="ignore"):
            G = log_tau - log_cosh(kappa)
        near = (log_tau < 0.5) & (kappa < 1.0)
        if not cancel_free:
            return G
    if where is not None:
        near &= np.asarray(where).reshape(-1)
    if not near.any():
        return G
    idx = np.flatnonzero(near)
    y = drive._tau_minus_one0(eps[idx], mu_c[idx])
    ok = np.isfinite(y) & (y > -1.0)
    sh2 = 2.0 * np.sinh(0.5 * kappa[idx[ok]]) ** 2
    G[idx[ok]] = np.log1p((y[ok] - sh2) / (1.0 + sh2))
    return G


def _bisect(drive, mu, zeta, lo, hi, rising):
    """Root of G between ``lo`` and ``hi`` where G changes sign (``rising``: G < 0 at lo)."""
    lo = lo.copy()
    hi = hi.copy()
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if not np.any((mid > lo) & (mid < hi)):
            break
        pos = _excess(drive, mid, mu, zeta) >= 0
        go_hi = pos if rising else ~pos
        hi = np.where(go_hi, mid, hi)
        lo = np.where(go_hi, lo, mid)
    return np.where(rising, hi, lo)


def _gap_argmax(drive, mu, zeta, lo, hi):
    """Golden-section search for the maximum of G on ``(lo, hi)`` (G is one hump there)."""
    r = 0.5 * (np.sqrt(5.0) - 1.0)
    a, b = lo.copy(), hi.copy()
    c = b - r * (b - a)
    d = a + r * (b - a)
    Gc = _excess(drive, c, mu, zeta)
    Gd = _excess(drive, d, mu, zeta)
    best_x = np.where(Gc >= Gd, c, d)
    best_G = np.maximum(Gc, Gd)
    for _ in range(100):
        # an unstable point is all a bracket needs: rows with G > 0 found are done
        live = (best_G <= 0) & (b - a > 4e-16 * b)
        if not live.any():
            break
        left = Gc >= Gd  # the maximum lies in (a, d)
        b = np.where(live & left, d, b)
        a = np.where(live & ~left, c, a)
        p = np.where(left, b - r * (b - a), a + r * (b - a))
        Gp = np.full(p.shape, -np.inf)
        Gp[live] = _excess(drive, p[live], mu[live], zeta[live])
        c, d = np.where(live, np.where(left, p, d), c), np.where(live, np.where(left, c, p), d)
        Gc, Gd = np.where(live, np.where(left, Gp, Gd), Gc), np.where(live, np.where(left, Gc, Gp), Gd)
        better = live & (Gp > best_G)
        best_x = np.where(better, p, best_x)
        best_G = np.where(better, Gp, best_G)
    return best_x, best_G


def _damped_edges(drive, mu, n, zeta, phi=None):
    """Edges of damped zone ``n``: each lies in the gap next to the undamped ``phi``-zone.

    The damped zone ``n`` contains the undamped zone ``n`` of the ``phi``-system (at
    ``mu_c``), on which ``|tau_phi| < 1 <= cosh kappa``. In the gap between ``phi``-zones
    ``n - 1`` and ``n`` the excess ``G = log|tau_phi| - log cosh kappa`` is negative at both
    ends and rises to one maximum: its two roots are the damped upper edge of zone
    ``n - 1`` and the damped lower edge of zone ``n``. Where the maximum is <= 0 the
    damping has joined the two zones; both edges are then reported at that maximum.
    """
    if phi is None:
        # the phi-edges on the doubles the certified verdict puts them at: unique doubles, so that
        # a gap's maximum is searched on the same bracket whichever zone, and whichever call, asks
        # (where damping joins two zones their shared edge is that maximum, which the search
        # locates only to about 1e-8: a bracket an ulp apart would move it by that much)
        mu_c = mu * np.sqrt(1.0 + zeta * zeta)
        m1, n1 = mu_c.reshape(-1), n.reshape(-1)
        m3 = np.concatenate([m1, m1, m1])
        lo3, hi3 = drive._edges0(m3, np.concatenate([n1, np.maximum(n1 - 1, 0), n1 + 1]))
        if not drive._edges_unique:
            lo3, hi3 = certified_sides(drive, m3, lo3, hi3)
        k, sh = m1.size, mu.shape
        lo_n, hi_n = lo3[:k].reshape(sh), hi3[:k].reshape(sh)
        hi_prev, lo_next = hi3[k:2 * k].reshape(sh), lo3[2 * k:].reshape(sh)
    else:  # the phi-system's edges, known already (a chart's window; lo_next may be a cap)
        lo_n, hi_n, hi_prev, lo_next = phi
    # gap below zone n: (hi_{n-1}, lo_n), or (0, lo_0) for zone 0
    gap_lo = np.where(n == 0, 0.0, hi_prev)
    # no phi-zone n (no attracting part left at mu_c): no damped zone either
    ok = np.isfinite(lo_n) & np.isfinite(hi_n) & np.isfinite(gap_lo)
    if not ok.all():
        out_lo = np.full(mu.shape, np.nan)
        out_hi = np.full(mu.shape, np.nan)
        if ok.any():
            nxt = np.where(np.isfinite(lo_next), lo_next, 4.0 * hi_n)
            out_lo[ok], out_hi[ok] = _damped_edges(drive, mu[ok], n[ok], zeta[ok],
                                                   phi=(lo_n[ok], hi_n[ok], hi_prev[ok], nxt[ok]))
        return out_lo, out_hi
    x_lo, G_lo = _gap_argmax(drive, mu, zeta, gap_lo, lo_n)
    x_hi, G_hi = _gap_argmax(drive, mu, zeta, hi_n, lo_next)
    edge_lo = np.where(G_lo > 0, _bisect(drive, mu, zeta, x_lo, lo_n, rising=False), x_lo)
    # zone 0 with the gap entirely stable reaches down to eps -> 0
    edge_lo = np.where((n == 0) & (G_lo <= 0), 0.0, edge_lo)
    edge_hi = np.where(G_hi > 0, _bisect(drive, mu, zeta, hi_n, x_hi, rising=True), x_hi)
    return _kapitza_damped(drive, mu, n, zeta, edge_lo, edge_hi), edge_hi


def _kapitza_damped(drive, mu, n, zeta, lo, hi):
    """``lo`` with zone 0's damped lower edge below the drive's :meth:`~kapitza.drives.Drive._kapitza_mu`
    moved to the double the certified damped verdict puts it at (:func:`kapitza_edge`; a drive whose
    damped verdicts are certified): Kapitza's limit, where ``G`` is of order ``eps^4`` and is lost to
    cancellation (or to underflow, below ``mu`` of about 1e-60, where the gap then looked stable all
    the way down). Searched from the averaging threshold ``mu / sqrt(8 k)``: damping leaves the averaged
    stiffness, and with it that edge, as it is to leading order (``O(mu^2)`` relative). Kept as found
    where that search finds no unstable double below (a drive whose levels, rounded, leave a mean
    that outweighs gravity there: zone 0 reaches ``eps -> 0``)."""
    rows = np.flatnonzero(((n == 0) & (mu < drive._kapitza_mu(True)) & (zeta > 0) & np.isfinite(hi)).reshape(-1))
    if not rows.size or not drive._damped_certified:
        return lo
    m, z, h = mu.reshape(-1)[rows], zeta.reshape(-1)[rows], hi.reshape(-1)[rows]
    start = drive.kapitza_eps(m)
    ok = start < h
    rows, m, z, h, start = rows[ok], m[ok], z[ok], h[ok], start[ok]
    found, _, good = kapitza_edge(drive, m, start, h, z)
    lo = np.array(lo, dtype=float, copy=True)
    lo.reshape(-1)[rows[good]] = found[good]
    return lo


def kapitza_edge(drive, mu, start, hi, zeta=None):
    """Zone 0's lower edge in Kapitza's limit (small ``mu``), where the double computation loses it
    to cancellation (``tau - 1`` is of order ``eps^2 mu^2``): ``(lo, hi, good)``, the edges moved to
    the doubles the certified verdicts put them at (:func:`certified_sides` from ``start``, below
    on to the smallest double: the averaging threshold ``mu / sqrt(8 k)`` is off the edge by
    ``O(mu^2)`` relative, a double search may be binades off), and ``good`` where the lower one is
    found so: unstable, the next double up stable. The one refinement of that edge for every drive
    (:meth:`Drive._edges0`, the step drives' sampled edges, the damping layer)."""
    lo, hi = certified_sides(drive, mu, start, hi, zeta, far=True)
    ends = np.concatenate([lo, np.nextafter(lo, np.inf)])
    mm = np.tile(mu, 2)
    if zeta is None:
        st = np.asarray(drive._verdict0(ends, mm), bool)
    else:
        st = np.asarray(drive._floquet(ends, mm, np.tile(zeta, 2), True)[3], bool)
    return lo, hi, ~st[:lo.size] & st[lo.size:]


# ---------------------------------------------------------------- the questions
def floquet(eps, mu, drive, zeta, trace_error=False):
    """``(trace, determinant, multipliers, growth, rotation_number, stable, zone)``.

    ``trace`` and ``determinant`` are those of the damped monodromy ``M_theta`` over ``2T``:
    ``tr M_theta = exp(-kappa) tr M_phi``, ``det M_theta = exp(-2 kappa)``; the multipliers are
    ``exp(-kappa)`` times those of the undamped ``phi``-system, largest modulus first;
    ``growth = log max|lambda|`` (negative where the damped motion decays). The trace is
    recomputed in extended precision where it is ill-conditioned (:func:`damped_floquet`).

    ``trace_error``: an eighth item, a bound on the absolute error of ``trace`` (that of
    ``tr M_phi / 2`` carried through ``2 exp(-kappa)``, whose ``kappa`` is rounded to a few units).
    """
    tau, growth, theta, stable, zone, kappa, tau_error = drive._floquet(eps, mu, zeta, trace=True)
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
    out = (trace, det, mult, growth, theta / (2.0 * PI) + 0.0, stable, zone)
    if not trace_error:
        return out
    u = 0.5 * np.finfo(float).eps
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        err = np.where(kappa > 0, 2.0 * np.exp(np.log(tau_error) - kappa) + np.abs(trace) * (6.0 * kappa + 4.0) * u,
                       2.0 * tau_error)
        err = np.where(np.isfinite(trace), err, np.inf)
    return out + (err,)


def verdict(eps, mu, drive, zeta):
    """``(stable, zone)`` (zone -1 where unstable)."""
    _, _, _, stable, zone, _ = drive._floquet(eps, mu, zeta)
    return stable, np.where(stable, zone, -1).astype(np.int64)


def edges(mu, n, drive, zeta):
    """``(eps_lo, eps_hi)`` of zone ``n``; NaN where the drive has no such zone at this ``mu``."""
    return drive._edges(mu, n, zeta)


def _window0(drive, mu, e0, e1):
    """``(rows, zone, lo, hi)`` of the undamped zones meeting ``[e0, e1]``, from the drive's window."""
    return drive._window0(mu, np.full(mu.size, e0), np.full(mu.size, e1))


def window_edges(drive, mu, e0, e1, zeta):
    """``(rows, zone, lo, hi)``: the edges of every zone that may meet ``[e0, e1]`` at each ``mu``."""
    zeta = np.broadcast_to(np.asarray(zeta, float), mu.shape)
    # a drive that finds every zone of a window at once (piecewise-constant: the rotation angle
    # sampled along eps; the sine: Mathieu's characteristic values) gives its own window;
    # damped, its zones follow from the undamped ones (_damped_window); others go zone by zone
    if drive._windowed:
        if not np.any(zeta > 0):
            return _window0(drive, mu, e0, e1)
        return _damped_window(drive, mu, zeta, e0, e1)
    n_lo, n_hi = _zone_range(drive, mu, zeta, e0, e1)
    counts = np.maximum(n_hi - n_lo + 1, 0)
    r_idx = np.repeat(np.arange(mu.size), counts)
    z_idx = n_lo[r_idx] + np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    lo, hi = drive._edges(mu[r_idx], z_idx, zeta[r_idx])
    return r_idx, z_idx, lo, hi


def certified_sides(drive, mu, lo, hi, zeta=None, far=False):
    """The edges moved to the doubles the certified verdict puts them at: ``lo`` the last unstable
    double below the zone (the next one up is stable), ``hi`` the first unstable one above it (the
    one below is stable), so that zone ``n`` is ``lo < eps < hi`` as :func:`kapitza.is_stable` says
    at every double. The double search leaves each within its rounding of that (a few ulp, more
    where the trace is formed from large cancelling terms): a bracket of doubles about it is widened
    until the certified verdict changes across it, then bisected on the bit patterns. A zone found
    with no double in it (``lo == hi``, thinner than their spacing), or where the search finds no
    stable double, is put between the two adjacent doubles where the certified trace changes sign
    (or about the stable doubles found there), for a drive whose certified verdicts come from an
    extended-precision product (:func:`_empty_zones`); a zone with no stable double otherwise keeps
    the edges as found. The bracket is widened 2^39 ulp at most; ``far``: below a lower edge on to the
    smallest double (the edges given may be binades off: Kapitza's limit, :meth:`Drive._edges0`)."""
    lo, hi = lo.copy(), hi.copy()
    windowed = drive._steps() is not None or drive._certified_pieces() is not None
    placeable = windowed or zeta is None
    placed = _empty_zones(drive, mu, lo, hi, zeta) if placeable else np.zeros(mu.size, bool)
    live = np.flatnonzero(np.isfinite(lo) & np.isfinite(hi) & (lo < hi) & (lo > 0) & ~placed)
    if not live.size:
        return lo, hi
    m = mu[live]
    L, H = lo[live].view(np.int64), hi[live].view(np.int64)
    half = np.maximum((H - L) // 2, 1)

    z = None if zeta is None else np.broadcast_to(np.asarray(zeta, float), mu.shape)[live]

    def stable(bits, rows):
        if z is None:
            return np.asarray(drive._verdict0(bits.view(np.float64), m[rows]), bool)
        return np.asarray(drive._floquet(bits.view(np.float64), m[rows], z[rows], True)[3], bool)

    def value(bits, rows):
        # tr M_phi / 2 and the threshold it crosses: 1 undamped, cosh(kappa) damped
        if z is None:
            return drive._floquet0(bits.view(np.float64), m[rows], certify=True).tau, 1.0
        f = drive._floquet(bits.view(np.float64), m[rows], z[rows], True)
        return np.asarray(f[0], float), np.cosh(np.asarray(f[5], float))

    # a thin zone (edges found 16 ulp apart or less): every double from 8 below it to 8 above at
    # once, its edges where the certified verdict changes (the search below, doubling its steps,
    # could step over a zone a double or two wide) -- for a drive whose certified verdicts come
    # from an extended-precision product (steps, linear pieces: a window of doubles in one call);
    # the sine's may cost an exact trace of thousands of bits each where its long double counts
    # leave a double open (a few in a window of 33 beside a thin zone at q ~ 2,000: 6 s each);
    # a drive that gives its certified verdicts alone (Drive._verdict0, the sine) is searched 8
    # ulp about each edge, without the window
    thin = np.flatnonzero(H - L <= 16) if windowed else np.zeros(0, np.int64)
    wide = windowed or drive._gives_verdicts
    reach = np.maximum(half, 8) if wide else half
    known = np.zeros(live.size, bool)
    new_L, new_H = L.copy(), H.copy()
    if thin.size:
        offs = np.arange(-8, 25)
        bits = np.maximum(L[thin, None] + offs[None, :], 1)
        st = stable(bits.ravel(), np.repeat(thin, offs.size)).reshape(bits.shape)
        one, out_lo, out_hi = _stable_run(bits, st)
        r = np.flatnonzero(one)
        known[thin[r]] = True
        new_L[thin[r]], new_H[thin[r]] = out_lo[r], out_hi[r]
    todo = np.flatnonzero(~known)

    def search(edge, inside, todo):
        """``(found, out, inn, edge)``: the edge (lower for ``inside`` 1) of the rows ``todo`` searched
        from ``edge`` (bit patterns): ``out`` the last unstable double, ``inn`` its stable neighbour."""
        if drive._from_shape:
            # the engine's edges may lie a thousand ulp off where its trace is flat, or more than
            # a thin zone's width: one secant step first on the certified trace, from the edge and
            # a double a little inside, towards the threshold it crosses there (of its sign if the
            # edge is outside the zone; the one it heads for outwards if inside)
            rows = todo
            d = np.clip(half[rows] // 4, 1, 64)
            e0 = edge[rows]
            t, bar = value(np.concatenate([e0, e0 + inside * d]), np.concatenate([rows, rows]))
            bar = np.broadcast_to(bar, t.shape)[:rows.size]
            t0, t1 = t[:rows.size], t[rows.size:]
            target = np.where(np.abs(t0) >= bar, np.sign(t0), np.sign(t0 - t1)) * bar
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                step = -(t0 - target) * d / (t1 - t0)
            good = np.isfinite(step) & (np.abs(step) < 2.0**20)
            edge = edge.copy()
            edge[rows] = e0 + inside * np.where(good, np.rint(np.where(good, step, 0.0)), 0).astype(np.int64)
        # out: a double outside the zone (unstable), inn: one inside (stable), widened in turns
        k = np.ones(live.size, np.int64)
        out_reach = np.maximum(reach, edge) if far and inside > 0 else np.minimum(reach, 1 << 39)
        out, inn = edge.copy(), edge + inside
        rows = todo
        found = np.zeros(live.size, bool)
        for _ in range(64):
            st = stable(np.concatenate([out[rows], inn[rows]]), np.concatenate([rows, rows]))
            ok = ~st[:rows.size] & st[rows.size:]
            found[rows[ok]] = True
            rows = rows[~ok]
            if not rows.size:
                break
            # (widened to half the zone, or 8 ulp where it is thinner and the verdicts cheap, so
            # that edges a few ulp off about a thin zone are found: left as found beyond; with ``far``
            # below a lower edge on to the smallest double)
            rows = rows[k[rows] < out_reach[rows]]
            k[rows] = np.minimum(2 * k[rows], out_reach[rows])
            out[rows] = np.maximum(edge[rows] - inside * k[rows], 1)
            inn[rows] = edge[rows] + inside * np.minimum(k[rows], reach[rows])
        # bisection: out stays unstable, inn stable, until they are neighbours
        rows = np.flatnonzero(found)
        for _ in range(70):
            rows = rows[np.abs(inn[rows] - out[rows]) > 1]
            if not rows.size:
                break
            mid = out[rows] + (inn[rows] - out[rows]) // 2
            st = stable(mid, rows)
            inn[rows[st]] = mid[st]
            out[rows[~st]] = mid[~st]
        return found, out, inn, edge

    f_lo, out_lo, inn_lo, e_lo = search(L, 1, todo)
    # a lower edge whose stable neighbour lies at or above the upper edge found: the zone lies above
    # both (edges a few ulp off about a zone a double or two wide): its upper edge is searched from
    # just above that double
    f_hi, out_hi, inn_hi, e_hi = search(np.where(f_lo & (inn_lo >= H), inn_lo + 1, H), -1, todo)
    # and the other way about: a zone below both, its lower edge searched from just below the stable
    # neighbour of the upper edge
    redo = todo[f_hi[todo] & ~f_lo[todo] & (inn_hi[todo] <= e_lo[todo])]
    if redo.size:
        f2, out2, _, e2 = search(inn_hi - 1, 1, redo)
        f_lo[redo], out_lo[redo], e_lo[redo] = f2[redo], out2[redo], e2[redo]
    res_lo = np.where(known, new_L, np.where(f_lo, out_lo, e_lo))
    res_hi = np.where(known, new_H, np.where(f_hi, out_hi, e_hi))
    if placeable:
        # no stable double found either side: a zone thinner than a double the search found a few
        # doubles wide (_empty_zones, from where the search began)
        none = np.flatnonzero(~known & ~f_lo & ~f_hi)
        if none.size:
            a, b = L[none].view(np.float64).copy(), L[none].view(np.float64).copy()
            zz = None if z is None else z[none]
            ok = _empty_zones(drive, m[none], a, b, zz)
            res_lo[none[ok]], res_hi[none[ok]] = a[ok].view(np.int64), b[ok].view(np.int64)
    lo[live], hi[live] = res_lo.view(np.float64), res_hi.view(np.float64)
    return lo, hi


def _stable_run(bits, st):
    """``(one, lo, hi)`` for windows of doubles ``bits`` (rows) and their verdicts ``st``: where a row
    holds one run of stable doubles with unstable doubles either side of it inside the window, and
    those two unstable neighbours (bit patterns; meaningful where ``one``)."""
    k = st.shape[1]
    first = np.argmax(st, axis=1)
    last = k - 1 - np.argmax(st[:, ::-1], axis=1)
    run = np.arange(k)[None, :]
    one = st.any(axis=1) & (first > 0) & (last < k - 1)
    one &= np.all(st == ((run >= first[:, None]) & (run <= last[:, None])), axis=1)
    r = np.arange(st.shape[0])
    return one, bits[r, np.maximum(first - 1, 0)], bits[r, np.minimum(last + 1, k - 1)]


#: The largest phase of linear pieces (:func:`kapitza._certify.pieces_phase`) at which :func:`_empty_zones`
#: places a zone thinner than a double (beyond, the long double tier decided none of the triangle's,
#: at growing cost)
EMPTY_PHASE = 400.0
#: ... and up to which a double the long double leaves open there is decided in mpmath (two a row at most)
EMPTY_MP_PHASE = 150.0


def _empty_zones(drive, mu, lo, hi, zeta=None):
    """For :func:`certified_sides` (in place): the zones the double search found with no double in
    them (``lo == hi``: the trace passes from one gap's sign to the next's between two doubles, as
    far as the double computation can tell) placed by the certified data. The trace crosses zero
    inside such a zone: one secant step on the certified trace from the double found towards that
    zero (the double search may be many ulp off where the trace is formed from large cancelling
    terms), then the certified verdicts and trace on 9 doubles about it (65 for a drive that gives
    only the signs, :meth:`~kapitza.drives.Drive._signs0`): a run of stable doubles
    gives the edges as its unstable neighbours, else the adjacent pair the trace changes sign
    between (both unstable: the zone lies between them, thinner than their spacing). Left as found
    where neither is in that window; for linear pieces also where the long double tier leaves more
    than two verdicts or signs of a row open, or any past a phase of :data:`EMPTY_MP_PHASE` (each
    costs an mpmath product), and past a phase of :data:`EMPTY_PHASE` (where it has never decided
    them, and its Taylor steps cost most). Returns where the edges were placed so (final)."""
    from .._certify import pieces_exact, pieces_ld, pieces_phase

    placed = np.zeros(mu.size, bool)
    cand = np.isfinite(lo) & (lo == hi) & (lo > 0)
    pieces = drive._certified_pieces() if drive._steps() is None else None
    phase = np.zeros(mu.size)
    if pieces is not None and cand.any():
        phase = pieces_phase(np.where(cand, lo, 0.0), mu, pieces)
        cand &= phase <= EMPTY_PHASE
    rows = np.flatnonzero(cand)
    if not rows.size:
        return placed
    m, phase = mu[rows], phase[rows]
    z = None if zeta is None else np.broadcast_to(np.asarray(zeta, float), mu.shape)[rows]
    X = lo[rows].view(np.int64)
    # a drive's own certified signs (the sine's Sturm counts), undamped; else steps and linear pieces
    signs = z is None and drive._gives_signs
    if not signs and drive._steps() is None and pieces is None:
        return placed

    def data(bits, idx):
        """Certified verdicts, traces (of M_phi, whose sign is M_theta's), and where both are known."""
        x = bits.ravel().view(np.float64)
        r = np.repeat(idx, bits.shape[1])
        if signs:
            st, t, sure = drive._signs0(x, m[r])
        elif pieces is not None:   # the long double tier; mpmath for a few doubles a row it leaves open
            zr = None if z is None else z[r]
            dec, st, t, _, _, err = pieces_ld(x, m[r], zr, pieces)
            with np.errstate(invalid="ignore"):
                sure = dec & (np.abs(t) > err)
            open_ = ~sure.reshape(bits.shape)
            cheap = (open_.sum(axis=1) <= 2) & (phase[idx] <= EMPTY_MP_PHASE)
            few = np.flatnonzero((open_ & cheap[:, None]).ravel())
            if few.size:
                res = pieces_exact(x[few], m[r][few], None if zr is None else zr[few], pieces, False, True)
                st[few], t[few], sure[few] = [q[2] for q in res], [q[0] for q in res], True
        else:   # steps: the exact product's, its trace recomputed where its sign may be lost
            t, _, _, st, _, _, err = drive._floquet(x, m[r], np.zeros(x.size) if z is None else z[r], True, trace=True)
            with np.errstate(invalid="ignore"):
                sure = np.abs(t) > err
        return tuple(np.asarray(v).reshape(bits.shape) for v in (st, t, sure))

    idx = np.arange(rows.size)
    d = 4
    _, t, _ = data(np.stack([X, X + d], axis=1), idx)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        step = -t[:, 0] * d / (t[:, 1] - t[:, 0])
    good = np.isfinite(step) & (np.abs(step) < 2.0**20)
    C = X + np.where(good, np.rint(np.where(good, step, 0.0)), 0).astype(np.int64)
    # (signs alone give the secant nothing to go on: a wider window, cheap for counts)
    offs = np.arange(-32, 33) if signs else np.arange(-4, 5)
    bits = np.maximum(C[:, None] + offs[None, :], 1)
    st, tv, sure = data(bits, idx)
    one, run_lo, run_hi = _stable_run(bits, st)
    flip = (np.sign(tv[:, :-1]) * np.sign(tv[:, 1:]) < 0) & np.isfinite(tv[:, :-1]) & np.isfinite(tv[:, 1:])
    none = ~st.any(axis=1) & (flip.sum(axis=1) == 1)
    j = np.argmax(flip, axis=1)
    r = np.arange(rows.size)
    new_lo = np.where(one, run_lo, np.where(none, bits[r, j], X))
    new_hi = np.where(one, run_hi, np.where(none, bits[r, j + 1], X))
    ok = (one | none) & sure.all(axis=1)
    new_lo, new_hi = np.where(ok, new_lo, X), np.where(ok, new_hi, X)
    lo[rows], hi[rows] = new_lo.view(np.float64), new_hi.view(np.float64)
    placed[rows] = ok
    return placed


def _damped_window(drive, mu, zeta, e0, e1):
    """Damped zones of a chart ``[e0, e1]``: from the undamped ``phi``-zones in ``[0, 2 e1]``.

    Damped zone ``n`` lies between the ``phi``-zones ``n - 1`` and ``n + 1``; the ``phi``-zones in
    view come from the undamped window method at ``mu_c``. A damped edge beyond ``2 e1`` (in a
    gap that reaches out of that window) is reported as ``inf``: the chart paints to its end.
    """
    mu_c = mu * np.sqrt(1.0 + zeta * zeta)
    cap = 2.0 * e1
    r0, z0, lo0, hi0 = window_edges(drive, mu_c, 0.0, cap, np.zeros(mu.size))
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
    rows, _, lo, hi = window_edges(drive, mu, float(eps[0]), float(eps[-1]), zeta)
    i0 = np.searchsorted(eps, lo, side="right")
    i1 = np.searchsorted(eps, hi, side="left")
    keep = np.isfinite(lo) & np.isfinite(hi) & (i1 > i0)
    flat = out.reshape(-1)
    W = eps.size
    base = rows[keep] * W
    for a, b in zip((base + i0[keep]).tolist(), (base + i1[keep]).tolist()):
        flat[a:b] = True
    from .._paint import settle_near_edges

    return settle_near_edges(eps, out, rows, lo, hi, i0, i1, lambda e, r: verdict(e, mu[r], drive, zeta[r])[0],
                             band=1e-9 if drive._from_shape else None)


def _zone_range(drive, mu, zeta, e0, e1):
    """Zone indices that may meet ``[e0, e1]`` at each ``mu`` (from the elliptic angle)."""
    mu_c = mu * np.sqrt(1.0 + np.asarray(zeta) ** 2)
    if drive._from_shape:  # the generic engine: read from its rotation angle at the ends
        return drive._candidate_zones(mu_c, e0, e1, bool(np.any(np.asarray(zeta) > 0)))
    rate, B = drive._zone_rate(mu_c)
    n_lo = np.maximum(np.floor((rate * e0 - B) / PI) - 1, 0).astype(np.int64)
    n_hi = np.floor((rate * e1 + B) / PI).astype(np.int64) + 1
    return n_lo, np.where(rate > 0, n_hi, n_lo - 1)


def margin(eps, mu, drive, zeta):
    """``(stable, zone, eps_lo, eps_hi, margin)`` as :class:`kapitza.StabilityMargin`: the zone
    containing the point (or the nearest), its edges, and the signed relative distance.

    The search starts where the point is: a stable point's zone is its own; an unstable one
    sits in the gap ``theta = k pi`` of its (undamped ``phi``-system's) rotation angle, between
    zones ``k - 1`` and ``k``, and the nearer of those two is the nearest of all (the zones are
    ordered along ``eps``). At most two zones' edges are solved per point.
    """
    eps, mu, zeta = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float))
    shape = eps.shape
    _, _, theta, stable, zone, _ = drive._floquet(eps, mu, zeta)
    e, m, z = eps.ravel(), mu.ravel(), zeta.ravel()
    st, zn = stable.ravel(), np.asarray(zone).ravel()
    turns = np.nan_to_num(theta.ravel()) / PI
    # past 2^50 zones the doubles near eps are wider than a zone: none is resolvable (the square
    # wave's closed forms stop at a phase of 2^52 alike); such points get no zone and margin -inf
    far = ~(np.abs(turns) < 2.0**50)
    k = np.rint(np.where(far, 0.0, turns)).astype(np.int64)
    upper = np.where(st, zn, np.maximum(k, 0))   # the zone itself, or the one above the gap
    lower = k - 1                                  # the one below the gap (unstable points)
    two = ~st & (lower >= 0) & ~far
    rows = np.concatenate([np.flatnonzero(~far), np.flatnonzero(two)])
    nn = np.concatenate([upper[~far], lower[two]])
    lo_r, hi_r = drive._edges(m[rows], nn, z[rows]) if rows.size else (np.zeros(0), np.zeros(0))
    N = e.size
    near = np.flatnonzero(~far)
    lo = np.full(N + np.count_nonzero(two), np.nan)
    hi = lo.copy()
    lo[near], hi[near] = lo_r[:near.size], hi_r[:near.size]
    lo[N:], hi[N:] = lo_r[near.size:], hi_r[near.size:]
    rows = np.concatenate([np.arange(N), np.flatnonzero(two)])
    with np.errstate(invalid="ignore", over="ignore"):
        d = np.minimum(e[rows] - lo, hi - e[rows]) / e[rows]
    d = np.where(np.isfinite(d), d, -np.inf)
    best, b_zone, b_lo, b_hi = d[:N].copy(), upper.copy(), lo[:N].copy(), hi[:N].copy()
    idx = np.flatnonzero(two)
    better = d[N:] > best[idx]
    sel = idx[better]
    best[sel], b_zone[sel], b_lo[sel], b_hi[sel] = d[N:][better], lower[sel], lo[N:][better], hi[N:][better]
    # the containing zone wins (its margin is the one a user asks for); no zone in reach: -1
    b_zone = np.where(st, zn, np.where(np.isfinite(b_lo) | np.isfinite(b_hi), b_zone, -1))
    return (stable, b_zone.reshape(shape), b_lo.reshape(shape), b_hi.reshape(shape), best.reshape(shape))


#: The largest value a one-point search's ladder of doublings climbs to (8 eps^2 and the products stay doubles).
_LADDER_TOP = 1e150


#: From this many engine steps a period at the point (about 0.4 ms a point with the compiled loop),
#: one point's searches ask four points a row a step instead of the drive's number
_COSTLY_STEPS = 1 << 14


def _ways(drive, point):
    """Points per row and step of one point's searches (:attr:`Drive._search_ways`): four where each
    costs a long period of the generic engine (:data:`_COSTLY_STEPS`; far up the zones the calls'
    own cost is small against their points, and fewer points in all win: a triangle report at
    ``eps = 5,300`` took 40 s with 16 points a row a step, 17 s with 4)."""
    ways = drive._search_ways
    if point is None or not drive._from_shape:
        return ways
    try:
        steps = drive._engine.steps_for(*(np.array([float(v)]) for v in point))[0]
    except ValueError:   # (beyond the engine's reach: the search refuses it by name)
        return ways
    return min(ways, 4) if steps >= _COSTLY_STEPS else ways


class _Levels:
    """The level of points ``(eps, mu)`` at one damping ratio, as the one-point searches read it:
    ``n + 1/2`` on zone ``n``, ``k`` in the gap ``theta = k pi``; with ``tau / cosh(kappa)`` (``|.| < 1``
    where stable, damped or not; damped and off the zones, ``cosh(kappa + growth) / cosh(kappa)`` with
    ``tau``'s sign, as exact as the growth). Certified answers are remembered: a search's final pair is asked again."""

    def __init__(self, drive, zeta, point=None):
        self.drive, self.zeta = drive, float(zeta)
        self.known: dict[tuple[float, float], tuple[float, float]] = {}
        self.ways = _ways(drive, point)

    def __call__(self, e, m, certify, with_tau=False):
        e, m = np.broadcast_arrays(np.asarray(e, float), np.asarray(m, float))
        shape = e.shape
        size = e.size
        if certify:
            keys = list(zip(e.ravel().tolist(), m.ravel().tolist()))
            todo = np.fromiter((k not in self.known for k in keys), bool, size)
        else:   # (only certified answers are remembered)
            todo = np.ones(size, bool)
        lv, tau = np.empty(size), np.empty(size)
        if todo.any():
            count = int(todo.sum())
            t, g, theta, st, zn, kappa = self.drive._floquet(e.ravel()[todo], m.ravel()[todo],
                                                             np.full(count, self.zeta), certify)
            lv[todo] = np.where(st, zn + 0.5, np.rint(theta / PI))
            with np.errstate(over="ignore", invalid="ignore"):
                ratio = t / np.cosh(kappa)
                if self.zeta > 0:
                    # off the zones |tau| = cosh(kappa + growth): from the damped growth, settled in
                    # extended precision near the edges where the trace is the engine's (the searches'
                    # secant then places the change within an ulp or two)
                    cosh_ratio = (np.exp(g) + np.exp(-2.0 * kappa - g)) / (1.0 + np.exp(-2.0 * kappa))
                    ratio = np.where(g > -kappa, np.sign(t) * cosh_ratio, ratio)
                tau[todo] = ratio
            if certify:
                self.known.update(zip((k for k, d in zip(keys, todo) if d), zip(lv[todo].tolist(), tau[todo].tolist())))
        if certify:
            for i in np.flatnonzero(~todo):
                lv[i], tau[i] = self.known[keys[i]]
        lv, tau = lv.reshape(shape), tau.reshape(shape)
        return (lv, tau) if with_tau else lv


#: A line's kinds in :class:`_Rows`: ``eps`` at a fixed ``mu``, ``A`` at a fixed ``T`` (``eps = T sqrt(A /
#: 8l)``, ``mu = sqrt(g / A)``), ``mu`` at a fixed ``eps``
LINE_EPS, LINE_A, LINE_MU = 0, 1, 2
#: A row's predicates on the level ``lv`` at its points: ``lv >= n + 1``, ``lv > n``, ``lv < n + 1``,
#: ``lv <= n``
PAST, INTO, BACK, BELOW = 0, 1, 2, 3


def _line_points(kind, c0, c1, c2, x):
    """The points ``(eps, mu)`` at values ``x`` of lines ``kind`` (broadcast arrays): ``(x, c0)``;
    ``(c0 sqrt(x / c2), sqrt(c1 / x))`` with ``c0 = T``, ``c1 = g``, ``c2 = 8 l``; ``(c0, x)``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.where(kind == LINE_EPS, x, np.where(kind == LINE_A, c0 * np.sqrt(x / c2), c0))
        m = np.where(kind == LINE_EPS, c0, np.where(kind == LINE_A, np.sqrt(c1 / x), x))
    return e, m


class _Rows:
    """Rows of a one-point search: their brackets ``[lo, hi]``; each row a line of points (``kind``,
    ``c0, c1, c2``: :func:`_line_points`) and a predicate on the levels there (``op``: :data:`PAST`,
    ...; about zone ``n``), whose change the search finds, with ``f = fm (tau (-1)^(n + fu) - 1)``
    (``fm``, ``fu``: the half-trace at the edge sought, ``+-1``) changing sign with it; ``answer(a, b,
    ends)``, what the pairs found mean (``ends``: the certified predicate at them, where ``checked``).
    ``zone``: the zone the point is in, if known. The compiled engine narrows the same rows
    (:func:`_narrowed_compiled`)."""

    FIELDS = ("kind", "c0", "c1", "c2", "n", "op", "fm", "fu")

    def __init__(self, lo, hi, lines, answer, zone=None, checked=False):
        self.lo, self.hi, self.answer = lo, hi, answer
        self.zone, self.checked = zone, checked
        size = len(lo)
        self.lines = {k: np.broadcast_to(np.asarray(v, float), (size,)) for k, v in zip(self.FIELDS, lines)}
        n, op, fm, fu = (self.lines[k] for k in ("n", "op", "fm", "fu"))
        # (the levels are whole or half numbers: lv > n is lv >= n + 1/2, lv <= n is lv < n + 1/2)
        self._rising = (op == PAST) | (op == INTO)
        self._threshold = np.where((op == PAST) | (op == BACK), n + 1.0, n + 0.5)
        self._sign = fm * _parity(n + fu)   # (f = sign tau - fm)

    def where(self, x, rows):
        """The points ``(eps, mu)`` the values ``x`` (shape ``(len(rows), k)``) of rows ``rows`` stand for."""
        kind, c0 = self.lines["kind"][rows], self.lines["c0"][rows][:, None]
        if np.all(kind == LINE_EPS):   # (a margin's rows: no square roots to form and throw away)
            return x, np.broadcast_to(c0, x.shape)
        return _line_points(kind[:, None], c0, self.lines["c1"][rows][:, None], self.lines["c2"][rows][:, None], x)

    def test(self, lv, tau, rows):
        """The predicate ``(ok, f)`` of :func:`search_bits` (guided) from the levels and half-traces there."""
        rising, thr = self._rising[rows][:, None], self._threshold[rows][:, None]
        ok = np.where(rising, lv >= thr, lv < thr)
        with np.errstate(invalid="ignore", over="ignore"):
            f = self._sign[rows][:, None] * tau - self.lines["fm"][rows][:, None]
        return ok, f


#: One point's searches narrow their brackets to this many bit patterns on the compiled engine's own
#: verdicts (one call a row, no numpy between the points), then go on as :func:`search_bits` does
#: (certified steps from there, where the drive's certified verdicts are cheap)
_COMPILED_WIDTH = 1 << 36
#: ... or to this many either side of the engine's own change, once its secant has found it (the exact
#: change lies within a thousand patterns of it where the trace is flat)
_COMPILED_ABOUT = 1 << 16


def _narrowed_compiled(drive, zeta, sets, lo, hi):
    """``(lo, hi, f_ends)``: the brackets of the row sets ``sets`` narrowed on the compiled engine
    (:func:`kapitza.engines._compiled.narrow_rows`), or None where that does not apply: the compiled
    engine not loaded, a drive whose verdicts are not the generic engine's (:attr:`Drive._engine_verdicts`),
    a bracket beyond the engine's reach."""
    from ..engines.magnus import compiled_loop

    fast = compiled_loop()
    if fast is None or not drive._engine_verdicts:
        return None
    lines = {k: np.concatenate([r.lines[k] for r in sets]) for k in _Rows.FIELDS}
    # (a bracket from 0, which the ladders leave only in odd cases, stays with the numpy steps: its
    # first points would lie far beyond the grid's reach)
    todo = np.flatnonzero((hi.view(np.int64) - lo.view(np.int64) > _COMPILED_WIDTH) & (lo > 0))
    lo, hi = lo.copy(), hi.copy()
    fa, fb = np.full(lo.size, np.nan), np.full(lo.size, np.nan)
    if not todo.size:
        return lo, hi, (fa, fb)
    # each row on the grid of the larger step count of its bracket's ends (the engine's steps grow
    # along each line; a finer grid only makes the verdicts more accurate), at the phi-system's mu
    e, m = _line_points(*(np.concatenate([lines[k][todo]] * 2) for k in ("kind", "c0", "c1", "c2")),
                        np.concatenate([lo[todo], hi[todo]]))
    try:
        both = drive._engine.steps_for(e, m * math.sqrt(1.0 + zeta * zeta))
    except ValueError:   # (beyond the engine's reach: the search refuses it by name)
        return None
    steps = np.maximum(both[:todo.size], both[todo.size:])
    eng = drive._engine
    for nv in np.unique(steps).tolist():
        rows = todo[steps == nv]
        lo[rows], hi[rows], fa[rows], fb[rows] = fast.narrow_rows(
            eng.grid(nv), *(lines[k][rows] for k in _Rows.FIELDS), lo[rows], hi[rows], _COMPILED_WIDTH,
            _COMPILED_ABOUT, zeta)
    return lo, hi, (fa, fb)


def _searched(drive, zeta, levels, sets):
    """The answers of the row sets ``sets``, searched together: one call of the drive per step for
    every row of every set."""
    sizes = [len(r.lo) for r in sets]
    starts = np.concatenate([[0], np.cumsum(sizes)])

    def pred(x, rows, certify=False):
        x = np.asarray(x, float)
        e, m = np.empty(x.shape), np.empty(x.shape)
        parts = []
        for r, a, b in zip(sets, starts[:-1], starts[1:]):
            sel = (rows >= a) & (rows < b)
            parts.append((r, sel, rows[sel] - a))
            if sel.any():
                e[sel], m[sel] = r.where(x[sel], rows[sel] - a)
        lv, tau = levels(e, m, certify, True)
        ok, f = np.empty(x.shape, bool), np.empty(x.shape)
        for r, sel, local in parts:
            if sel.any():
                ok[sel], f[sel] = r.test(lv[sel], tau[sel], local)
        return ok, f

    lo = np.concatenate([r.lo for r in sets])
    hi = np.concatenate([r.hi for r in sets])
    narrowed = _narrowed_compiled(drive, zeta, sets, lo, hi)
    a, b = _search(drive, zeta > 0, pred, lo, hi, levels.ways,
                   *(() if narrowed is None else (narrowed[:2], narrowed[2])))
    # the certified predicate at the pairs found, for the sets that read it (remembered from the
    # search, where it asked it there)
    want = np.concatenate([np.full(n, r.checked) for r, n in zip(sets, sizes)])
    ends = np.ones((lo.size, 2), bool)
    if want.any():
        rows = np.flatnonzero(want)
        ends[rows] = pred(np.stack([a[rows], b[rows]], axis=1), rows, True)[0]
    return [r.answer(a[i:j], b[i:j], ends[i:j]) for r, i, j in zip(sets, starts[:-1], starts[1:])]


def _narrowed(lo, hi, xs, ok):
    """Each row's bracket ``[lo, hi]`` shrunk to the points ``xs`` already asked (``ok[row, j]`` the
    row's predicate at ``xs[j]``, False below its change and True above): the largest point inside
    it where ``ok`` is False, the smallest where it is True. (A fast predicate wrong at a point a few
    ulp from a change leaves the certified check of the final pair to find that out.)"""
    inside = (xs[None, :] > lo[:, None]) & (xs[None, :] < hi[:, None])
    new_lo = np.maximum(lo, np.max(np.where(inside & ~ok, xs[None, :], -np.inf), axis=1))
    new_hi = np.minimum(hi, np.min(np.where(inside & ok, xs[None, :], np.inf), axis=1))
    good = new_lo < new_hi
    return np.where(good, new_lo, lo), np.where(good, new_hi, hi)


#: Points per row and step of a one-point search's certified steps where each point costs (Taylor steps
#: of linear pieces: the secant of certified ends places the change within a few ulp, and fewer
#: points a step cost less than the step or two more they may take).
_CERTIFIED_WAYS = 8


def _search(drive, damped, pred, lo, hi, ways, start=None, f_ends=None):
    """:func:`search_bits` (guided) of the one-point searches, ``pred(x, rows, certify)`` returning
    ``(ok, f)``: where the drive's certified verdicts serve the last steps (:meth:`Drive._certified_steps`)
    those steps ask them, and the pair found is final; elsewhere the steps ask the fast predicate and the
    final pair is certified."""
    return search_bits(pred, lo, hi, ways=ways, certified=lambda x, rows: pred(x, rows, True),
                       guided=True, certified_steps=drive._certified_steps(damped),
                       certified_ways=_CERTIFIED_WAYS if drive._far_cost else ways, start=start, f_ends=f_ends)


def _parity(n):
    """``(-1)^n`` of integers held as floats."""
    return 1.0 - 2.0 * np.mod(n, 2.0)


def point_margin(drive, eps, mu, zeta, levels=None):
    """:func:`margin` of one point (floats), the edges found together by :func:`search_bits` on the
    zone index read from the rotation angle (one call of the drive per step for all of them, each
    final pair decided to the last bit), or None where that search cannot answer (no zone within
    reach, or a fast predicate off by more than the certified search's window): then
    :func:`margin` does. ``levels``: a :class:`_Levels` of this drive and ``zeta`` to share.

    Along ``eps`` at fixed ``mu`` the level ``n + 1/2`` on zone ``n``, ``k`` in the gap ``theta = k pi``,
    rises: zone ``n``'s lower edge is the last ``eps`` with level ``<= n``, its upper edge the
    first with level ``>= n + 1``; each is reported on its unstable side, as :func:`margin`'s.
    """
    levels = levels or _Levels(drive, zeta, (eps, mu))
    rows, = _prepared(levels, [_margin_rows(drive, eps, mu, zeta=zeta)])
    return None if rows is None else _searched(drive, zeta, levels, [rows])[0]


def _prepared(levels, builders):
    """Run the row builders ``builders`` (generators that yield the points ``(eps, mu)`` whose certified
    levels they need and return a :class:`_Rows` or None) together: one call of the drive a round
    for all the points they ask."""
    out = [None] * len(builders)
    asks = []

    def advance(i, value=None, first=False):
        try:
            asks.append((i, next(builders[i]) if first else builders[i].send(value)))
        except StopIteration as stop:
            out[i] = stop.value

    for i in range(len(builders)):
        advance(i, first=True)
    while asks:
        now, asks[:] = list(asks), []
        lv = levels(np.concatenate([e for _, (e, _) in now]), np.concatenate([m for _, (_, m) in now]), True)
        cuts = np.cumsum([len(e) for _, (e, _) in now])[:-1]
        for (i, _), part in zip(now, np.split(lv, cuts)):
            advance(i, part)
    return out


def _margin_rows(drive, eps, mu, L0=None, zeta=0.0):
    """The rows of :func:`point_margin`'s search (a :class:`_Rows`), or None where it cannot answer: a
    builder for :func:`_prepared`. ``L0``: the level at ``(eps, mu)``, when known. The ladder climbs
    to the drive's reach (:meth:`Drive._eps_reach`) at ``mu``, damped at the ``phi``-system's ``mu sqrt(1 +
    zeta^2)`` the levels are taken at, fewer rungs a call where the drive's verdicts cost more the larger
    ``eps`` (:attr:`Drive._far_cost`)."""
    if L0 is None:
        L0 = float((yield np.array([eps]), np.array([mu]))[0])
    if not abs(L0) < 2.0**50 or mu >= drive.mu_max:
        # no zone resolvable so far out (see margin), or none at all at this mu: the array margin says so
        return None
    stable = L0 != np.rint(L0)
    k = int(np.floor(L0)) if stable else int(L0)
    zones = [k] if stable else ([k - 1, k] if k >= 1 else [k])
    # rows: (zone, upper edge?, searched above eps?)
    rows = []
    for n in zones:
        above = not stable and n == k
        rows += [(n, False, above), (n, True, above or stable)]
    # a top past the highest zone's upper edge, eight doublings a call (the first call also asks
    # eight halvings below eps: the rungs then narrow every row's bracket to about a binade); a drive
    # whose cost grows with eps climbs two doublings first, then three (rungs far above the zones a
    # point is near would cost more than the whole search)
    need = zones[-1] + 1
    top = None
    climb = iter((2, 3) if drive._far_cost else ())
    ladder = eps * 2.0 ** np.arange(1.0, 1.0 + next(climb, 8))
    rungs, rung_levels = [np.array([eps]), eps * 2.0 ** -np.arange(1.0, 9.0)], [np.array([L0])]
    limit = min(_LADDER_TOP, float(_reach(drive, mu, zeta)))
    while ladder[0] <= limit:
        ladder = ladder[ladder <= limit]
        rungs.append(ladder)
        ask = np.concatenate(rungs[1:]) if len(rung_levels) == 1 else ladder
        lv = yield ask, np.full(ask.shape, mu)
        rung_levels.append(lv)
        up = np.flatnonzero(lv[-ladder.size:] >= need)
        if up.size:
            top = ladder[up[0]]
            break
        ladder = ladder[-1] * 2.0 ** np.arange(1.0, 1.0 + next(climb, 8))
    if top is None:  # not within the doubles' comfortable range: the array margin answers
        return None
    n_of = np.array([r[0] for r in rows], float)
    upper = np.array([r[1] for r in rows])
    lo = np.array([eps if r[2] else 0.0 for r in rows])
    hi = np.array([top if r[2] else eps for r in rows])
    xs, lvs = np.concatenate(rungs), np.concatenate(rung_levels)
    lo, hi = _narrowed(lo, hi, xs, np.where(upper[:, None], lvs >= n_of[:, None] + 1, lvs > n_of[:, None]))

    def answer(a, b, ends):
        if ends[:, 0].any() or not ends[:, 1].all():
            return None
        edge = np.where(upper, b, a)   # the unstable side: below a lower edge, at or above an upper one
        best = None
        for i, n in enumerate(zones):
            e_lo, e_hi = float(edge[2 * i]), float(edge[2 * i + 1])
            d = min(eps - e_lo, e_hi - eps) / eps
            if best is None or d > best[3]:
                best = (n, e_lo, e_hi, d)
        n, e_lo, e_hi, d = best
        return stable, int(n), e_lo, e_hi, float(d)

    # zone n's edges along eps: its lower edge where the level passes n (tau = (-1)^n there), its upper
    # where it reaches n + 1 (tau = (-1)^(n + 1))
    lines = (LINE_EPS, mu, 0.0, 0.0, n_of, np.where(upper, PAST, INTO), np.where(upper, 1.0, -1.0), upper)
    return _Rows(lo, hi, lines, answer, zone=k if stable else None, checked=True)


def along_amplitude(T, n, l, g, drive, c):
    """``(A_lo, A_hi)`` of zone ``n`` at fixed half-period ``T`` (scalars; bisection on the zone).

    At fixed ``T`` the ``phi``-stiffness ``(T^2/l) (g (1 + zeta^2) + A s)`` grows with ``A`` in
    the attracting segments: the zone index read from the rotation angle is bisected in ``A``
    on the bit patterns of doubles.
    """
    zeta = zeta_of(c, l, g)

    def arnold(A):
        return T * np.sqrt(A / (8.0 * l)), np.sqrt(g / A)

    def reached(A, level, strictly, certify=False):
        eps, mu = arnold(A)
        _, _, theta, st, z, _ = drive._floquet(eps, mu, np.full(np.shape(A), zeta), certify)
        k = np.where(st, z + 0.5, np.rint(theta / PI))
        return k > level if strictly else k >= level

    # the first power of two (times g) that has reached zone n + 1, eight doublings per call (a
    # drive's cost may grow with A: no rung far beyond the one needed)
    ladder = max(g, 1.0) * 2.0 ** np.arange(8.0)
    hi = ladder[:1]
    for _ in range(138):
        e_l, m_l = arnold(ladder)
        ladder = ladder[:int(np.argmin(np.append(e_l <= _reach(drive, m_l, zeta), False)))]
        if not ladder.size:   # (as far as the drive reaches)
            break
        up = np.flatnonzero(reached(ladder, n + 1, False))
        hi = ladder[up[:1]] if up.size else ladder[-1:]
        if up.size:
            break
        ladder = ladder[-1] * 2.0 ** np.arange(1.0, 9.0)
    _, A_hi = search_bits(lambda A, _: reached(A, n + 1, False), np.zeros(1), hi,
                          certified=lambda A, _: reached(A, n + 1, False, True), ways=drive._search_ways)
    A_lo, _ = search_bits(lambda A, _: reached(A, n, True), np.zeros(1), A_hi,
                          certified=lambda A, _: reached(A, n, True, True), ways=drive._search_ways)
    return float(A_lo[0]), float(A_hi[0])


def rig_intervals(eps, mu, zone, drive, zeta, T, A, l, g, levels=None):
    """Zone ``zone`` of one physical point along ``A`` (at this ``T``) and along the frequency
    (at this stroke): ``A_lo, A_hi`` and, where the zone is reached, ``frequency_lo, frequency_hi``.

    The four edges are searched together (:func:`search_bits`, one call of the drive per step for
    all four): along ``A`` the zone index read from the rotation angle rises with ``A`` at fixed
    ``T`` (:func:`along_amplitude`). At a fixed stroke ``A`` grows like ``f^2`` and ``T = 1/(2f)``,
    so ``eps`` is fixed and ``mu`` falls like ``1/f``; the zone is an interval of ``mu`` there (its
    edges ``eps_lo(mu)``, ``eps_hi(mu)`` both grow with ``mu``), the index falling as ``mu`` grows;
    below ``mu = 1e-6`` nothing is searched (a zone reaching there has no upper frequency).
    ``levels`` as in :func:`point_margin`.
    """
    levels = levels or _Levels(drive, zeta, (eps, mu))
    rows, = _prepared(levels, [_rig_rows(drive, eps, mu, zone, T, A, l, g, zeta)])
    return _searched(drive, zeta, levels, [rows])[0]


def point_edges(drive, eps, mu, zeta, T, A, l, g, level0=None):
    """:func:`point_margin` and :func:`rig_intervals` of the zone it finds, ``(margin, intervals)``
    (``intervals`` None outside every zone's reach), or None where the margin's search cannot
    answer. ``level0``: the certified level at the point (``zone + 1/2`` on a zone, ``theta / pi``
    off them), when known. A point inside a zone has the six edges searched together: one call of
    the drive per step for all of them."""
    levels = _Levels(drive, zeta, (eps, mu))
    # where the margin's zone is known beforehand its rig edges are searched with it, one call a step
    # for all six: inside zone floor(level0), and below zone 0 (the gap theta = 0). In a gap k >= 1 it
    # is k - 1 or k, and searching both zones' rig edges costs more points than the calls it saves
    known = known_zone(level0)
    if known is not None:
        m_rows, r_rows = _prepared(levels, [_margin_rows(drive, eps, mu, level0, zeta),
                                            _rig_rows(drive, eps, mu, known, T, A, l, g, zeta)])
        if m_rows is None:
            return None
        margin, rig = _searched(drive, zeta, levels, [m_rows, r_rows])
        return None if margin is None else (margin, rig if margin[1] == known else None)
    m_rows, = _prepared(levels, [_margin_rows(drive, eps, mu, level0, zeta)])
    margin = None if m_rows is None else _searched(drive, zeta, levels, [m_rows])[0]
    if margin is None:
        return None
    if margin[1] < 0:
        return margin, None
    r_rows, = _prepared(levels, [_rig_rows(drive, eps, mu, margin[1], T, A, l, g, zeta)])
    return margin, _searched(drive, zeta, levels, [r_rows])[0]


def _reach(drive, mu, zeta):
    """:meth:`Drive._eps_reach` where the levels are taken: damped, at the ``phi``-system's ``mu sqrt(1 +
    zeta^2)``."""
    return drive._eps_reach(mu * math.sqrt(1.0 + zeta * zeta))


def known_zone(level0):
    """The zone a point of certified level ``level0`` (``zone + 1/2`` on a zone, ``theta / pi`` off them;
    None where unknown) is searched in before any search: its own inside a zone, 0 below zone 0, else
    None (in a gap ``k >= 1`` it is ``k - 1`` or ``k``)."""
    if level0 is None:
        return None
    return int(np.floor(level0)) if level0 != np.rint(level0) else (0 if level0 == 0 else None)


def _mu_reach(drive, eps, mu, cap, zeta=0.0):
    """The largest ``mu`` up to ``cap`` at which ``eps`` is within the drive's reach
    (:meth:`Drive._eps_reach`, at ``mu sqrt(1 + zeta^2)`` with damping), ``mu`` itself being within it
    (bisected on its logarithm)."""
    if eps <= _reach(drive, cap, zeta):
        return cap
    lo, hi = math.log(mu), math.log(cap)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if eps <= _reach(drive, math.exp(mid), zeta):
            lo = mid
        else:
            hi = mid
    return math.exp(lo)


def _rig_rows(drive, eps, mu, zone, T, A, l, g, zeta=0.0):
    """The rows of :func:`rig_intervals`' search (a :class:`_Rows`): a builder for :func:`_prepared`.
    Its rungs stay within the drive's reach (:meth:`Drive._eps_reach`, damped at the ``phi``-system's
    ``mu sqrt(1 + zeta^2)``): the largest ``mu`` searched at this ``eps`` is 4, or less where the drive's
    reach ends below ``eps`` there."""
    n = zone

    def along_A(A_):
        return _line_points(LINE_A, T, g, 8.0 * l, A_)

    # where the searches start: the first 2^k max(g, 1) past zone n + 1 along A (eight rungs a
    # call), and whether the zone is still reached at the ends of the frequency search
    # (the first call also asks the point itself and eight halvings and doublings of mu at this eps:
    # these rungs then narrow each search's bracket to about a binade)
    mu_top = _mu_reach(drive, eps, mu, 4.0, zeta)
    mu_rungs = mu * 2.0 ** np.concatenate([-np.arange(1.0, 9.0), np.arange(1.0, 9.0)])
    mu_rungs = np.concatenate([[1e-6, mu_top, mu], mu_rungs[(mu_rungs > 1e-6) & (mu_rungs < mu_top)]])
    A_rungs, A_levels = [np.array([A])], []
    ladder = max(g, 1.0) * 2.0 ** np.arange(8.0)
    for _ in range(138):
        e_l, m_l = along_A(ladder)
        within = (ladder <= _LADDER_TOP) & (e_l <= _reach(drive, m_l, zeta))
        if not within.all():  # (as far as along_amplitude goes: the last rung within reach is the top)
            keep = int(np.argmin(within))
            if keep == 0 and A_levels:
                top = A_rungs[-1][-1]
                break
            ladder = ladder[:keep] if keep else np.array([A])
            e_l, m_l = along_A(ladder)
        first = not A_levels
        extra = mu_rungs.size if first else 0
        k = yield np.concatenate([e_l, np.full(extra, eps)]), np.concatenate([m_l, mu_rungs[:extra]])
        if first:
            ends, mu_levels = k[ladder.size:ladder.size + 2], k[ladder.size:]
            A_levels.append(k[ladder.size + 2:ladder.size + 3])   # the point itself
        A_rungs.append(ladder)
        A_levels.append(k[:ladder.size])
        up = np.flatnonzero(k[:ladder.size] >= n + 1)
        if up.size:
            top = ladder[up[0]]
            break
        if ladder.size == 1:
            top = ladder[-1]
            break
        ladder = ladder[-1] * 2.0 ** np.arange(1.0, 9.0)
    else:
        top = ladder[-1]
    above = ends[0] < n + 1     # still in the zone (or below it) at the smallest mu
    capped = not ends[1] <= n   # not yet out of it at the largest

    # (a search whose answer is not needed gets an empty bracket)
    lo = np.array([0.0, 0.0, 1e-6, 1e-6])
    hi = np.array([top, top, 1e-6 if above else mu_top, 1e-6 if capped else mu_top])
    kA = np.concatenate(A_levels)
    lo[:2], hi[:2] = _narrowed(lo[:2], hi[:2], np.concatenate(A_rungs), np.stack([kA >= n + 1, kA > n]))
    lo[2:], hi[2:] = _narrowed(lo[2:], hi[2:], mu_rungs, np.stack([mu_levels < n + 1, mu_levels <= n]))

    def answer(a, b, ends):
        out = dict(A_lo=float(a[1]), A_hi=float(b[0]))
        mu_lo = 1e-6 if above else float(a[2])
        mu_hi = mu_top if capped else float(b[3])
        if mu_lo < mu_hi:
            f = 0.5 / T
            out.update(frequency_lo=float(f * mu / mu_hi),
                       frequency_hi=float("inf") if above else float(f * mu / mu_lo))
        return out

    # rows 0, 1 along A: A_hi the first A past the zone (tau = (-1)^(n + 1) there), A_lo the first in it
    # (or beyond; tau = (-1)^n); rows 2, 3 along mu at this eps: mu_lo the first mu back in the zone or
    # below (tau = (-1)^(n + 1)), mu_hi the first below it (tau = (-1)^n)
    lines = ([LINE_A, LINE_A, LINE_MU, LINE_MU], [T, T, eps, eps], g, 8.0 * l, n, [PAST, INTO, BACK, BELOW],
             [1.0, -1.0, -1.0, 1.0], [1, 0, 1, 0])
    return _Rows(lo, hi, lines, answer)


# ---------------------------------------------------------------- motion of the linear equation
def _segment_flow(s, h, k=None):
    """Entries (a, b, c, d) of the exact flow of ``x'' = s x`` over ``h`` (physical units), times
    ``e^{-k}`` when ``k`` is given: formed as ``e^{r - k}`` where ``r = sqrt(s) h`` is large, so a
    damped step (``s`` raised by ``c^2/4``, ``k = c h / 2``) does not overflow where its product
    with ``e^{-k}`` is a double."""
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
    steps = drive._steps()
    with np.errstate(over="ignore", invalid="ignore"):
        if steps is not None:
            P = (np.ones(T.shape), np.zeros(T.shape), np.zeros(T.shape), np.ones(T.shape))
            for lev, f in zip(*steps):
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
        if steps is None:
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
    t, theta0, dtheta0, T, A, l, g, c = np.broadcast_arrays(
        *(np.asarray(x, float) for x in (t, theta0, dtheta0, T, A, l, g, c)))
    steps = drive._steps()
    if steps is None:
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
    with np.errstate(over="ignore", invalid="ignore"):
        for lev, fr in zip(*steps):
            Mphi = _mul(_segment_flow((g + A * lev) / l + half * half, fr * period), Mphi)
    if not all(np.all(np.isfinite(x)) for x in Mphi):
        # damping so heavy that the phi = e^{ct/2} theta transform leaves the doubles within one
        # period (c T beyond ~700): the motion itself decays, and DOP853 follows it
        return _ivp_motion(t, theta0, dtheta0, T, A, l, g, drive, c)
    u1, u2 = _chebyshev_pair(k, f.tau, f.growth, f.theta, f.zone >= 0)
    with np.errstate(over="ignore", invalid="ignore"):
        a, b, cc, d = Mphi
        p = np.where(k == 0, p0, (u1 * a - u2) * p0 + u1 * b * q0)
        q = np.where(k == 0, q0, u1 * cc * p0 + (u1 * d - u2) * q0)
        start = 0.0
        for lev, fr in zip(*steps):
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


def _secant_points(m, al, bl, fal, fbl, half):
    """For :func:`search_bits` (guided): replace in place the even points ``m`` of the rows whose
    bracket ``[al, bl]`` (bit patterns) is narrow with points about the secant's root of ``f``."""
    width = bl - al
    # (an end where f rounds to 0 counts: the secant's root is then that end)
    use = ((width < (1 << 46)) & (width > 2 * m.shape[1]) & (fal <= 0) & (fbl >= 0) & (fal < fbl) & (fal > -1)
           & (fbl < 1))
    if not use.any():
        return
    xa, xb = al[use].view(np.float64), bl[use].view(np.float64)
    est = np.asarray(xa + (xb - xa) * (fal[use] / (fal[use] - fbl[use])), float)
    ie = np.clip(est.view(np.int64), al[use] + 1, bl[use] - 1)
    ratio = (0.5 * width[use].astype(float)) ** (1.0 / (half - 1))
    offs = np.rint(ratio[:, None] ** np.arange(half)[None, :]).astype(np.int64)
    pts = np.concatenate([ie[:, None] - offs[:, ::-1], ie[:, None], ie[:, None] + offs], axis=1)
    pts = np.clip(pts, (al[use] + 1)[:, None], (bl[use] - 1)[:, None])
    m[use, :pts.shape[1]] = pts
    m[use, pts.shape[1]:] = pts[:, -1:]


def search_bits(pred, lo, hi, ways=64, certified=None, guided=False, certified_steps=False, f_ends=None,
                certified_ways=None, start=None):
    """Bisection on the bit patterns of non-negative doubles taking ``ways - 1`` points per row at each
    step: the pair of adjacent doubles where a predicate changes (once, False below and True above),
    in about ``64 / log2(ways)`` calls of ``pred`` instead of the 64 of halving. ``pred(x, rows)`` is
    elementwise, ``x`` of shape ``(len(rows), k)`` holding points of the rows ``rows`` (indices into
    ``lo``): a call on a few dozen points costs about what a call on one does.

    ``guided``: ``pred`` returns ``(ok, f)``, ``f`` a smooth function negative where ``ok`` is False
    and positive where it is True about the change (a half-trace minus its value at the edge). Once a
    row's bracket is within 1/64 of its value and ``|f| < 1`` at both ends, its points are placed about
    the secant's root of ``f``, geometrically spaced from one ulp to half the bracket: the bracket
    then shrinks to about three times the secant's error, quadratically, in about four calls fewer
    than the even steps. The pair found is the same.

    ``certified``: the same predicate decided to the last bit (``pred`` may err within a few ulp of
    its change, at a fraction of the cost). The final pair is checked with it; where it is not
    False below and True above, the change is searched with it (seven points a row a call, guided
    like the steps, from the ends' ``f``: each of its points may cost an extended-precision product)
    in the narrowest window that holds the change, of 4 ulp either side widened sixteenfold to
    2^20 ulp (their ends asked in one call: a drive given by its shape may err by a thousand ulp
    where its trace is flat), and kept where found there. Guided, ``certified`` returns ``(ok, f)``
    too.

    ``certified_steps``: the certified predicate costs about what ``pred`` does (a long double
    product): once a row's bracket is within 2^36 ulp (2^-16 of its value; the fast steps'
    secant points have then come within a few thousand ulp) the steps ask it instead for every row,
    so the final pair is certified as found (the check above then costs nothing where ``certified``
    remembers its points); those steps take ``certified_ways`` points a row (default ``ways``; fewer
    where each certified point costs an extended-precision product).

    ``start``: ``(a, b)``, brackets within
    ``[lo, hi]`` already narrowed on the fast predicate, to start from (the certified check of the
    final pair may still widen its windows to ``[lo, hi]``); ``f_ends``: ``f`` at the starting
    brackets' ends, where known (guided), for the first step's secant.
    """
    a = (lo if start is None else start[0]).view(np.int64).copy()
    b = (hi if start is None else start[1]).view(np.int64).copy()
    certified_ways = certified_ways or ways
    j = np.arange(1, max(ways, certified_ways), dtype=np.int64)
    # f at the bracket's ends, where evaluated (guided)
    fa, fb = ((np.full(a.size, np.nan), np.full(a.size, np.nan)) if f_ends is None else
              (np.array(f_ends[0], float), np.array(f_ends[1], float)))
    for _ in range(70):
        live = np.flatnonzero(b - a > 1)
        if not live.size:
            break
        al, bl = a[live], b[live]
        narrow = certified_steps and bool(np.any(bl - al < (1 << 36)))
        w = certified_ways if narrow else ways
        step = np.maximum((bl - al) // w, 1)
        m = np.minimum(al[:, None] + step[:, None] * j[None, :w - 1], (bl - 1)[:, None])
        if guided:
            _secant_points(m, al, bl, fa[live], fb[live], (w - 2) // 2)
        res = (certified if narrow else pred)(m.view(np.float64), live)
        ok = np.asarray(res[0] if guided else res, bool)
        first = np.argmax(ok, axis=1)
        r = np.arange(live.size)
        hit = ok[r, first]
        below = np.maximum(first - 1, 0)
        b[live] = np.where(hit, m[r, first], bl)
        a[live] = np.maximum(np.where(hit, np.where(first > 0, m[r, below], al), m[:, -1]), al)
        if guided:
            f = np.asarray(res[1], float)
            fb[live] = np.where(hit, f[r, first], fb[live])
            fa[live] = np.where(hit, np.where(first > 0, f[r, below], fa[live]), f[:, -1])
    if certified is None:
        return a.view(np.float64), b.view(np.float64)
    lo_i, hi_i = lo.view(np.int64), hi.view(np.int64)
    inner = np.flatnonzero(b > a)
    def decided(x, rows):
        res = certified(x, rows)
        return np.asarray(res[0] if guided else res, bool)

    ends = decided(np.stack([a[inner], b[inner]], axis=1).view(np.float64), inner)
    # (an end of the given bracket carries no claim: the predicate may hold all the way)
    bad = inner[(ends[:, 0] & (a[inner] > lo_i[inner])) | (~ends[:, 1] & (b[inner] < hi_i[inner]))]
    if bad.size:
        # the windows about each bad pair, widening sixteenfold, asked in one call: the narrowest that
        # holds the certified change (False at its lower end, True at its upper) is searched
        widths = np.array([4, 64, 1024, 1 << 14, 1 << 18, 1 << 20], np.int64)
        ca = np.maximum(a[bad][:, None] - widths[None, :], lo_i[bad][:, None])
        cb = np.minimum(b[bad][:, None] + widths[None, :], hi_i[bad][:, None])
        res = certified(np.concatenate([ca, cb], axis=1).view(np.float64), bad)
        w_ok = np.asarray(res[0] if guided else res, bool)
        w_f = np.asarray(res[1], float) if guided else None
        k = widths.size
        holds = ~w_ok[:, :k] & w_ok[:, k:]
        # (a window at both ends of the bracket cannot grow: past it its row keeps the pair found)
        stuck = (ca <= lo_i[bad][:, None]) & (cb >= hi_i[bad][:, None])
        first = np.argmax(holds, axis=1)
        r = np.arange(bad.size)
        keep = holds[r, first] & ~np.array([stuck[i, :first[i]].any() for i in r.tolist()], bool)
        if keep.any():   # the change in each window: seven certified points a row a call (guided)
            rows, sel = bad[keep], (r[keep], first[keep])
            wa, wb = ca[sel], cb[sel]
            f_ends = None if w_f is None else (w_f[:, :k][sel], w_f[:, k:][sel])
            wa, wb = search_bits(lambda x, r: certified(x, rows[r]), wa.view(np.float64), wb.view(np.float64),
                                 ways=8, guided=guided, f_ends=f_ends)
            a[rows], b[rows] = wa.view(np.int64), wb.view(np.int64)
    return a.view(np.float64), b.view(np.float64)
