"""Stability zones on Arnold's ``eps``-``mu`` plane and in the physical ``(T, A)`` plane.

Zone ``n`` (``n = 0, 1, 2, ...``) is the set ``alpha + n pi < u < beta + n pi``
(``docs/theory.md`` section 5, from Theorems 3.3-3.4 and Corollary 4.1). At fixed
``mu`` it is one interval ``eps_lo(n) < eps < eps_hi(n)``; the lower edge is
2T-periodic for even ``n`` and 4T-periodic for odd ``n``, the upper edge the
other way round.

The edges are found by Newton's method on ``F(u) = u - n pi - alpha(D u)``
(convex, iterated from the right of its root) and ``u - n pi - beta(D u)``
(concave and increasing, iterated from the left): both sequences are monotone,
so they cannot overshoot into a neighbouring branch, and they stop at machine
precision.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _certify
from . import _exact as X
from . import _validate as _v
from ._display import Summary, num, shape_of, span, stable_share
from .drives import _api as _drv
from .parameters import G_EARTH, SQRT8, _phase_angles

__all__ = [
    "is_stable",
    "zone_index",
    "zone_edges",
    "zone_width",
    "G_m_curve",
    "StabilityMargin",
    "stability_margin",
    "stability_grid",
    "period_edges",
    "amplitude_edges",
]

PI = np.pi
_MAX_NEWTON = 200


# ---------------------------------------------------------------- kernels
_tan3 = X.tan3  # (tan z - z)/z^3 and (z - tanh z)/z^3 by their series for small z


def _lower0_small_mu(mu):
    """u on the lower edge of zone 0 for small mu, free of cancellation.

    The edge ``tan z = D tanh(D z)`` (``z = u/2``, eq. 3.10 with k = 0) is rewritten as
    ``z^2 [T3(z) + D^4 H3(D z)] = D^2 - 1 = 2 mu^2 / (1 - mu^2)`` with
    ``T3 = (tan z - z)/z^3`` and ``H3 = (y - tanh y)/y^3`` from their series, and solved
    by fixed-point iteration (the bracket varies slowly in z). The direct form
    ``u - alpha(D u) = 0`` loses ``1e-16/mu^2`` relative accuracy as mu -> 0: near
    ``mu = 0.15`` that was 30-50 ulp, so this form is used up to ``mu = 0.6`` (``z`` up to
    about 0.9; its terms are all positive, and :func:`kapitza._exact.tan3` keeps its
    series up to 0.8), where Newton's cancellation has fallen to a factor of about 3.
    """
    d2m1 = 2.0 * mu * mu / ((1.0 - mu) * (1.0 + mu))
    D2 = 1.0 + d2m1
    D = np.sqrt(D2)
    def fixed(z):
        return np.sqrt(d2m1 / (_tan3(z, 1) + D2 * D2 * _tan3(D * z, -1)))

    # The map contracts (by up to about 0.3 at mu = 0.6): secant steps on z - fixed(z) reach
    # its fixed point in a few evaluations; one last application of the map gives the answer.
    z0 = np.sqrt(3.0 * d2m1 / (1.0 + D2 * D2))
    z1 = fixed(z0)
    h0 = z0 - z1
    live = np.ones(z1.shape, dtype=bool)
    for _ in range(60):
        h1 = z1 - fixed(z1)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = h1 * (z1 - z0) / (h1 - h0)
        # a point that has converged stays put: its answer does not depend on its neighbours
        step = np.where(live, np.where(np.isfinite(step), step, h1), 0.0)
        z0, h0, z1 = z1, h1, z1 - step
        live &= np.abs(step) > 8.0 * np.finfo(float).eps * z1
        if not live.any():
            break
    # Below mu = 1e-100 mu^2 may leave the normal doubles (1e-154 and less) and the iteration
    # with it; there u = 2 sqrt(3) mu (1 + O(mu^2)) is the edge to rounding.
    return np.where(mu < _TINY_MU, (2.0 * _SQRT3) * mu, 2.0 * fixed(z1))


_TINY_MU = 1e-100
_SQRT3 = np.sqrt(3.0)


_SMALL_MU = 0.6


def _edge_u(mu, n, upper: bool, q=None):
    """Edge of zone ``n`` in ``u = w_e T`` at fixed ``mu`` (arrays broadcast; trusted).

    ``q = sqrt(1 - mu^2)`` may be passed when it is known better than ``mu`` allows:
    from ``(A - g) / A`` as ``A -> g``, where ``1 - mu^2`` formed from a rounded ``mu``
    loses ``1e-16 / (1 - mu)`` of relative accuracy.
    """
    mu, n, q = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, float),
                                   np.asarray(np.nan if q is None else q, float))
    shape = mu.shape
    mu = mu.ravel()
    n = n.ravel()
    p = np.sqrt(1.0 + mu * mu)
    q = np.sqrt((1.0 - mu) * (1.0 + mu)) if np.isnan(q).all() else q.ravel().copy()
    D = p / q
    npi = n * PI
    u = npi + 2.0 * np.arctan(D)  # alpha < 2 atan D < beta: right of the lower root, left of the upper
    active = np.arange(u.size)
    if not upper:
        small = (n == 0) & (mu < _SMALL_MU)
        if small.any():
            u[small] = _lower0_small_mu(mu[small])
            active = np.flatnonzero(~small)
    fn, dfn = (X.beta_x, X.dbeta_dx) if upper else (X.alpha_x, X.dalpha_dx)
    for _ in range(_MAX_NEWTON):
        ua, Da = u[active], D[active]
        xa = Da * ua
        F = ua - npi[active] - fn(xa, Da)
        dF = 1.0 - Da * dfn(xa, Da)
        step = F / dF
        unew = ua - step
        u[active] = unew
        # The exact iterates move monotonically (down for the lower edge, up for the upper):
        # a step against that direction means rounding noise has been reached.
        moving = (step < 0) if upper else (step > 0)
        keep = moving & (np.abs(step) > 4.0 * np.finfo(float).eps * np.abs(unew))
        active = active[keep]
        if active.size == 0:
            break
    return u.reshape(shape), q.reshape(shape)


def _edges_eps(mu, n, q=None):
    """(eps_lo, eps_hi) of zone n (trusted input, 0 < mu < 1; ``q`` as in :func:`_edge_u`)."""
    ulo, q = _edge_u(mu, n, upper=False, q=q)
    uhi, _ = _edge_u(mu, n, upper=True, q=q)
    # Each edge is good to a few ulps; where the zone is thinner than that, keep lo <= hi.
    uhi = np.maximum(uhi, ulo)
    return ulo / (SQRT8 * q), uhi / (SQRT8 * q)


_CHUNK = 1 << 14  # points per block of the fast verdict: its temporaries stay in cache
_BLOCKS_PER_THREAD = 8
_EPS = np.finfo(float).eps


def _verdict(eps, mu, want_n=True):
    """(stable, n) for trusted input; mu >= 1 is unstable; ``n = floor(u / pi)`` (float; only
    where ``want_n``, else None). Certified to the last bit.

    Zone ``n`` is ``alpha < w < beta`` with ``w = u - n pi`` in ``[0, pi)``; since ``tan`` is
    increasing on ``[0, pi/2)`` this is, with ``s = tan(w/2)`` and ``t = tanh(x/2)``,

        D t < s < D / t        (``docs/theory.md`` section 5),

    two comparisons after one ``tan`` and one ``tanh`` (no arctangent). Rounding: ``w`` is off
    by at most ``8 eps (u + n)`` (``u`` to 3 eps relative; ``n pi`` formed with the rounded
    ``pi`` and rounded itself: ``2.1 eps n``; for ``n = 0`` no subtraction), so ``s`` by
    ``4 eps (u + n)(1 + s^2) + eps s``; ``D t`` and ``D/t`` carry about 5 eps relative (``D``
    and ``tanh`` a few ulp each, ``x`` 3 ulp, damped by ``tanh``). Where ``s - D t`` or
    ``D/t - s`` is within ``m = 4 eps (u + n)(1 + s^2) + 32 eps s`` of zero (when either side
    is more than three times the other the sign is plain; otherwise the errors sum to less than
    ``m``, with a factor two to spare on the ``eps s`` terms) the point goes
    to :func:`_verdict_careful` -- the closed forms with their own bound, then mpmath. That is a
    band of a few ulp about each edge (wider, ``~eps / mu^2`` relative, along zone 0's lower edge
    at small ``mu``, where ``s`` and ``D t`` nearly cancel). The blocks of ``_CHUNK`` points are
    computed in place, so a call costs a few passes over memory, not dozens; a large call shares
    its blocks out among threads, one per CPU (the ufuncs release the GIL).
    """
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    shape = eps.shape
    e_all = np.ascontiguousarray(eps).ravel()
    m_all = np.ascontiguousarray(mu).ravel()
    N = e_all.size
    stable = np.empty(N, bool)
    unsure = np.empty(N, bool)
    n_out = np.empty(N) if want_n else None
    blocks = range(0, N, _CHUNK)
    threads = _threads(len(blocks))
    if threads == 1:
        _verdict_blocks(e_all, m_all, stable, unsure, n_out, blocks)
    else:  # numpy's ufuncs release the GIL: the blocks are shared out among the CPUs
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(threads) as pool:
            for f in [pool.submit(_verdict_blocks, e_all, m_all, stable, unsure, n_out, blocks[k::threads])
                      for k in range(threads)]:
                f.result()
    idx = np.flatnonzero(unsure)
    if idx.size:
        st, nn = _verdict_careful(e_all[idx], m_all[idx])
        stable[idx] = st
        if want_n:
            n_out[idx] = nn
    return stable.reshape(shape), (n_out.reshape(shape) if want_n else None)


def _threads(blocks: int) -> int:
    """Threads for ``blocks`` blocks of the fast verdict: one per CPU this process may use, each
    given at least ``_BLOCKS_PER_THREAD`` blocks (below that starting threads costs more than it saves)."""
    if blocks < 2 * _BLOCKS_PER_THREAD:
        return 1
    return _v.workers(_v.cpus(), blocks // _BLOCKS_PER_THREAD)


def _verdict_blocks(e_all, m_all, stable, unsure, n_out, blocks):
    """The fast verdict (:func:`_verdict`) of the blocks starting at ``blocks``, in place."""
    N = e_all.size
    k = max(1, min(_CHUNK, N))
    p, q, y, t, u, n, s, r, g = (np.empty(k) for _ in range(9))
    ok = np.empty(k, bool)
    with np.errstate(all="ignore"):  # mu >= 1 gives NaN (or D = inf): never stable, never unsure
        for i in blocks:
            j = min(i + _CHUNK, N)
            if j - i < k:
                p, q, y, t, u, n, s, r, g = (a[:j - i] for a in (p, q, y, t, u, n, s, r, g))
                ok = ok[:j - i]
            e, m = e_all[i:j], m_all[i:j]
            np.multiply(m, m, out=p); p += 1.0; np.sqrt(p, out=p)                  # sqrt(1 + mu^2)
            np.subtract(1.0, m, out=q); np.add(1.0, m, out=r); q *= r; np.sqrt(q, out=q)
            np.multiply(e, SQRT8, out=y); np.multiply(y, q, out=u); y *= p; y *= 0.5  # u, x/2
            np.divide(p, q, out=p)                                                 # D
            np.tanh(y, out=t)
            np.multiply(u, 1.0 / PI, out=n); np.floor(n, out=n)
            if n_out is not None:
                n_out[i:j] = n
            np.multiply(n, -PI, out=s); s += u; s *= 0.5; np.tan(s, out=s)         # tan(w/2)
            u += n; u *= 4.0 * _EPS; np.multiply(s, s, out=r); r += 1.0; u *= r
            np.multiply(s, 32.0 * _EPS, out=r); u += r                             # the bound m
            np.multiply(p, t, out=r); np.subtract(s, r, out=r)                     # s - D t
            np.divide(p, t, out=g); g -= s                                         # D/t - s
            np.greater(r, 0.0, out=stable[i:j]); np.greater(g, 0.0, out=ok); stable[i:j] &= ok
            np.abs(r, out=r); np.abs(g, out=g); np.minimum(r, g, out=r)
            np.less_equal(r, u, out=unsure[i:j])


def _verdict_careful(eps, mu):
    """(stable, n) for trusted input; mu >= 1 is unstable. Certified: where the signs of
    ``w - alpha``, ``w - beta`` are within rounding, tr M is decided in extended precision."""
    eps, mu = np.broadcast_arrays(eps, mu)
    ell = mu < 1.0
    mus = np.where(ell, mu, 0.5)
    x, u, D = _phase_angles(eps, mus)
    n, w = X.reduced(u)
    a = X.lower_gap(x, u, w, n, D, mus)
    b = w - X.beta_x(x, D)
    stable = ell & (a > 0) & (b < 0)
    check = ell & _certify.unsure(u, a, b, x)
    if np.any(check):
        stable = np.array(stable, dtype=bool)
        stable[check] = _certify.exact_half_trace(eps[check], mu[check])[2]
    return stable, n


# ---------------------------------------------------------------- public API
@_v.shapes_named
def is_stable(eps, mu, drive=None, zeta=0.0):
    """Whether the upright position is (strongly) stable at Arnold's ``(eps, mu)``.

    Parameters
    ----------
    eps : array_like
        ``eps = T sqrt(A / (8 l))``, finite and > 0.
    mu : array_like
        ``mu = sqrt(g / A)``, finite and > 0; ``mu >= 1`` (``A <= g``) is always unstable
        for the square wave. ``eps`` and ``mu`` broadcast together.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    zeta : array_like, optional
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0 (``docs/drives.md`` section 3); broadcasts.

    Returns
    -------
    ndarray of bool
        True where ``alpha + n pi < u < beta + n pi`` for some ``n >= 0`` (square wave,
        undamped); in general where both Floquet multipliers lie strictly inside the unit
        circle, or on it and distinct (``|tr M_phi| < 2 cosh(c T)``).

    Notes
    -----
    Theorems 3.3-3.4 and Corollary 4.1; ``docs/theory.md`` section 5. Points exactly
    on an edge (a 2T- or 4T-periodic solution exists, ``|tr M| = 2``) are unstable.
    Other drives and damping: ``docs/drives.md``.
    """
    eps, mu = _v.arnold(eps, mu)
    drive, zeta = _v.general_drive(drive, zeta)
    if drive is not None:
        return _v.scalars(np.asarray(_drv.verdict(eps, mu, drive, zeta)[0]))
    return _v.scalars(np.asarray(_verdict(eps, mu, want_n=False)[0]))


@_v.shapes_named
def zone_index(eps, mu, drive=None, zeta=0.0):
    """Index ``n`` of the stability zone containing ``(eps, mu)``, or -1 where unstable.

    Parameters
    ----------
    eps, mu, drive, zeta :
        As in :func:`is_stable`.

    Returns
    -------
    ndarray of int
        Zone ``n`` is where the rotation angle per period lies in ``(n pi, (n + 1) pi)``
        (``docs/drives.md`` section 2); for the square wave ``alpha + n pi < u < beta + n pi``.
    """
    eps, mu = _v.arnold(eps, mu)
    drive, zeta = _v.general_drive(drive, zeta)
    if drive is not None:
        return _v.scalars(np.asarray(_drv.verdict(eps, mu, drive, zeta)[1]))
    stable, n = _verdict(eps, mu)
    return _v.scalars(np.where(stable, n, -1).astype(np.int64))


@_v.shapes_named
def zone_edges(mu, n, drive=None, zeta=0.0):
    """Edges ``eps_lo < eps_hi`` of stability zone ``n`` at the given ``mu``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int or array_like of int
        Zone index, ``n >= 0``; broadcasts with ``mu``.
    drive, zeta : optional
        As in :func:`is_stable`. For other drives and with damping the edges are found by
        safeguarded root solves to about 1e-14 relative, zone 0's lower edge included as
        ``mu -> 0`` (Kapitza's regime, formed without cancellation; checked against a 50-digit
        reference for ``mu`` in [1e-3, 0.9] in ``tests/test_drive_edges_oracle.py``;
        ``docs/drives.md``); NaN where the
        drive has no such zone at this ``mu``; where damping has joined zones ``n`` and
        ``n + 1``, ``eps_hi`` of one is ``eps_lo`` of the other.

    Returns
    -------
    eps_lo, eps_hi : ndarray
        Zone ``n`` is ``eps_lo < eps < eps_hi``; both are accurate to a few units
        in the last place (at most 4 ulp against the 50-digit reference on the sweeps of
        ``tests/test_zones_oracle.py``: 201 values of ``mu`` in [0.1, 0.2] for zone 0's
        lower edge, where the solver changes form, and ``mu`` in [0.01, 0.99] for both
        edges of zones 0-2; no proof of a bound is claimed). The lower edge carries a 2T-periodic solution for even
        ``n`` (eq. 3.10) and a 4T-periodic one for odd ``n`` (eq. 3.12); the upper
        edge a 4T- (3.13) respectively 2T-periodic one (3.11).

    Notes
    -----
    ``u = alpha + n pi`` and ``u = beta + n pi`` at fixed ``mu``, ``u = 2 sqrt 2 eps
    sqrt(1 - mu^2)``; ``docs/theory.md`` section 5. Where the zone is narrower than
    a double's resolution of ``eps`` the two edges round to the same number; use
    :func:`zone_width` for the width.
    """
    drive, zeta = _v.general_drive(drive, zeta)
    n = _v.nonnegative_int("n", n)
    if drive is not None:
        mu = _v.positive("mu", mu)
        return _drv.edges(mu, n, drive, zeta)
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    return _edges_eps(mu, n)


@_v.shapes_named
def zone_width(mu, n, log=False):
    """Width ``eps_hi - eps_lo`` of zone ``n``, free of cancellation.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int or array_like of int
        Zone index ``>= 0``; broadcasts with ``mu``.
    log : bool, optional
        Return the natural logarithm of the width, finite even where the width
        underflows a double (``x`` beyond about 700).

    Returns
    -------
    ndarray

    Notes
    -----
    With ``x = D u`` at the two edges (``u_lo = n pi + gamma(x_lo) - delta(x_lo)``,
    ``u_hi = n pi + gamma(x_hi) + delta(x_hi)``, ``docs/theory.md`` section 5)::

        u_hi - u_lo = delta(x_lo) + delta(x_hi) + [gamma(x_hi) - gamma(x_lo)],

    with ``delta = atan(sqrt(1 - mu^4) / sinh x)`` and the bracket written as one
    arctangent of ``mu^2 sinh(x_hi - x_lo) / (s4 cosh x_lo cosh x_hi)``. Where the
    zone is wide the edges are subtracted directly (no cancellation to fear); where
    it is narrow the relation above is solved by fixed-point iteration (it contracts
    by ``D gamma' ~ e^{-2x}``), so the edges are never subtracted.
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    n = _v.nonnegative_int("n", n)
    log = _v.flag("log", log)
    ulo, q = _edge_u(mu, n, upper=False)
    uhi, _ = _edge_u(mu, n, upper=True)
    mu_b = np.broadcast_to(mu, ulo.shape)
    D = np.sqrt(1.0 + mu_b * mu_b) / q
    s4 = X.s4_of(mu_b)
    xlo, xhi = D * ulo, D * uhi
    with np.errstate(over="ignore", under="ignore"):
        dsum = X.delta_x(xlo, s4) + X.delta_x(xhi, s4)
        c = mu_b * mu_b / (s4 * np.cosh(xlo) * np.cosh(xhi))
        du = dsum
        for _ in range(12):
            du = dsum + np.arctan2(c * np.sinh(D * du), 1.0 + (mu_b**4 / s4**2) * np.tanh(xlo) * np.tanh(xhi))
    wide = (uhi - ulo) > 0.05 * uhi
    du = np.where(wide, uhi - ulo, du)
    if not log:
        return du / (SQRT8 * q)

    # Far out delta underflows: log(delta) ~ log s4 - log sinh x, and the bracket is negligible.
    def log_delta(x):
        lz = np.log(s4) - X.log_sinh(x)
        with np.errstate(under="ignore"):
            return np.where(lz < -30.0, lz, np.log(np.arctan(np.exp(np.maximum(lz, -30.0)))))

    with np.errstate(divide="ignore"):
        log_du = np.where(du > 1e-280, np.log(du), np.logaddexp(log_delta(xlo), log_delta(xhi)))
    return log_du - np.log(SQRT8 * q)


@_v.shapes_named
def G_m_curve(mu, m):
    """The curve ``G_m``: ``2 sqrt 2 eps sqrt(1 - mu^2) = (2m + 1) pi / 2``, as ``eps(mu)``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    m : int or array_like of int
        ``m >= 0``; broadcasts with ``mu``.

    Returns
    -------
    ndarray
        ``eps`` on ``G_m``. Zone ``m`` lies along ``G_m`` (section 4 of the paper).
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    m = _v.nonnegative_int("m", m)
    return (2 * m + 1) * PI / (2.0 * SQRT8 * np.sqrt((1.0 - mu) * (1.0 + mu)))


@dataclass(frozen=True, repr=False)
class StabilityMargin(Summary):
    """Distance of ``(eps, mu)`` to the nearest zone edge along ``eps`` (fixed ``mu``,
    i.e. fixed ``A``: only the drive period changes). Arrays of the broadcast shape.

    Attributes
    ----------
    stable : ndarray of bool
    zone : ndarray of int
        The zone containing the point, or the nearest zone where unstable.
    eps_lo, eps_hi : ndarray
        Edges of that zone; NaN where there is none to give (``mu >= 1``, or a phase
        ``u = w_e T`` beyond ``2^52``, whose rounding exceeds a whole zone).
    margin : ndarray
        Signed relative distance to the nearest edge of that zone,
        ``min(eps - eps_lo, eps_hi - eps) / eps``: positive inside a zone
        (the fraction by which ``T`` may change before stability is lost),
        negative outside (the fraction by which ``T`` must change to gain it).
        ``-inf`` where ``mu >= 1`` or ``u > 2^52``.
    """

    stable: np.ndarray
    zone: np.ndarray
    eps_lo: np.ndarray
    eps_hi: np.ndarray
    margin: np.ndarray

    def headline(self) -> str:
        if np.ndim(self.stable) == 0:
            return (f"{'stable in' if self.stable else 'unstable, nearest'} zone {int(self.zone)}, "
                    f"{num(self.eps_lo, 10)} < eps < {num(self.eps_hi, 10)}, margin {100 * float(self.margin):.4g}%")
        return stable_share(self.stable)

    def lines(self) -> list[tuple[str, str]]:
        if np.ndim(self.stable) == 0:
            return [("verdict", "stable" if self.stable else "unstable"),
                    ("zone", f"{int(self.zone)} ({'containing' if self.stable else 'nearest'})"),
                    ("edges", f"{num(self.eps_lo, 12)} < eps < {num(self.eps_hi, 12)}"),
                    ("margin", f"{100 * float(self.margin):.6g}% of eps")]
        return [("points", shape_of(self.stable)), ("stable", f"{100 * float(np.mean(self.stable)):.4g}%"),
                ("margin", f"{span(100 * np.asarray(self.margin))} % of eps")]

    def __post_init__(self):
        _v.scalar_fields(self)



@_v.shapes_named
def stability_margin(eps, mu, drive=None, zeta=0.0):
    """Signed relative distance from ``(eps, mu)`` to the nearest zone edge along ``eps``.

    Parameters
    ----------
    eps, mu, drive, zeta :
        As in :func:`is_stable`.

    Returns
    -------
    StabilityMargin
    """
    eps, mu = _v.arnold(eps, mu)
    drive, zeta = _v.general_drive(drive, zeta)
    if drive is not None:
        stable, zone, lo, hi, margin = _drv.margin(eps, mu, drive, zeta)
        return StabilityMargin(stable=stable, zone=zone, eps_lo=lo, eps_hi=hi, margin=margin)
    eps, mu = np.broadcast_arrays(eps, mu)
    # no zones where A <= g, and none resolvable once the phase u = w_e T exceeds 2^52 (its
    # rounding is then more than a whole zone): the margin is -inf there, as for A <= g
    u_all = SQRT8 * eps * np.sqrt(np.maximum((1.0 - np.minimum(mu, 1.0)) * (1.0 + np.minimum(mu, 1.0)), 0.0))
    ell = (mu < 1.0) & (u_all < 2.0**52)
    mus = np.where(ell, mu, 0.5)
    eps_s = np.where(ell, eps, 1.0)
    stable, n = _verdict(eps_s, mus)
    stable &= ell
    eps = eps_s
    x, u, D = _phase_angles(eps, mus)
    w = u - n * PI
    below = X.lower_gap(x, u, w, n, D, mus) <= 0
    # Candidate zones: n itself, and the neighbour across the gap the point sits in (one solve).
    nb = np.where(below, np.maximum(n - 1, 0), n + 1)
    lo2, hi2 = _edges_eps(np.stack([mus, mus]), np.stack([n, nb]))
    (lo_n, lo_b), (hi_n, hi_b) = lo2, hi2
    d_n = np.minimum(eps - lo_n, hi_n - eps)
    d_b = np.where(below & (n == 0), -np.inf, np.minimum(eps - lo_b, hi_b - eps))
    use_b = ~stable & (d_b > d_n)
    zone = np.where(use_b, nb, n).astype(np.int64)
    lo = np.where(use_b, lo_b, lo_n)
    hi = np.where(use_b, hi_b, hi_n)
    with np.errstate(over="ignore"):  # +-inf for subnormal eps
        margin = np.where(use_b, d_b, d_n) / eps
    # Edges are good to a few ulp; the certified verdict decides the sign of the margin.
    tiny = np.finfo(float).smallest_subnormal
    margin = np.where(stable, np.maximum(margin, tiny), np.minimum(margin, -tiny))
    nan = np.full(eps.shape, np.nan)
    return StabilityMargin(
        stable=stable,
        zone=np.where(ell, zone, -1),
        eps_lo=np.where(ell, lo, nan),
        eps_hi=np.where(ell, hi, nan),
        margin=np.where(ell, margin, -np.inf),
    )


@_v.shapes_named
def stability_grid(eps, mu, out=None, drive=None, zeta=0.0):
    """Exact stability verdicts over the grid ``eps`` x ``mu``.

    Parameters
    ----------
    eps : 1-D array_like
        Finite, > 0; any order.
    mu : 1-D array_like
        Finite, > 0; ``mu >= 1`` rows are all unstable.
    out : ndarray of bool, shape ``(len(mu), len(eps))``, optional
        C-contiguous array to write into (saves allocating a fresh image when
        grids are computed repeatedly).
    drive : Drive or str, optional
        As in :func:`is_stable`.
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0 (one value for the whole grid).

    Returns
    -------
    ndarray of bool, shape ``(len(mu), len(eps))``
        ``grid[i, j] == is_stable(eps[j], mu[i])`` except within about 1e-13
        relative of an edge.

    Notes
    -----
    No per-pixel trigonometry: for each ``mu`` the edges of the zones that meet
    the ``eps`` range are computed (:func:`zone_edges`), located in the sorted
    ``eps`` grid by binary search, and the stable runs are painted row by row.
    The cost is ``O(len(mu) * zones * log len(eps))`` plus writing the output.
    """
    eps, mu = _v.arnold(eps, mu, together=False)  # the grid's two axes
    drive, zeta = _v.general_drive(drive, zeta)
    if zeta is not None and zeta.ndim != 0:
        raise _v.KapitzaValueError(f"zeta must be a single number for a grid; got shape {zeta.shape}")
    if eps.ndim != 1 or mu.ndim != 1:
        raise _v.KapitzaValueError(
            f"eps and mu must be 1-D arrays; got shapes {eps.shape} and {mu.shape}"
        )
    W = eps.size
    order = None
    if W > 1 and not np.all(eps[1:] >= eps[:-1]):
        order = np.argsort(eps, kind="stable")
        eps = eps[order]
    shape = (mu.size, W)
    if out is None:
        out = np.zeros(shape, dtype=bool)
    else:
        if not (isinstance(out, np.ndarray) and out.shape == shape and out.dtype == bool
                and out.flags.c_contiguous and out.flags.writeable):
            raise _v.KapitzaValueError(
                f"out must be a writeable C-contiguous bool array of shape {shape}")
        out.fill(False)
    target = out
    if drive is not None:
        _drv.grid(eps, mu, drive, np.full(mu.size, float(zeta)), out)
        if order is not None:
            target[:, order] = out.copy()
        return target
    rows = np.flatnonzero(mu < 1.0)
    if rows.size:
        m = mu[rows]
        q = np.sqrt((1.0 - m) * (1.0 + m))
        D = np.sqrt(1.0 + m * m) / q
        n_max = np.floor(SQRT8 * q * eps[-1] / PI).astype(np.int64)
        # Zone n has x > D n pi and a width below 8 s4 e^{-x} in u: beyond x = 35 every pixel it
        # could hold lies within 2e-15 (relative) of an edge, inside the documented caveat, so
        # such zones are skipped; so are zones that end below eps[0] (u_hi < (n + 1) pi).
        # Without this a wide eps range costs an edge solve per zone up to n_max on every row.
        n_max = np.minimum(n_max, np.ceil(35.0 / (D * PI)).astype(np.int64))
        n_min = np.maximum(np.ceil(SQRT8 * q * eps[0] / PI).astype(np.int64) - 1, 0)
        counts = np.maximum(n_max - n_min + 1, 0)
        r_idx = np.repeat(np.arange(rows.size), counts)
        z_idx = n_min[r_idx] + np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        lo, hi = _edges_eps(m[r_idx], z_idx)
        i0 = np.searchsorted(eps, lo, side="right")  # first eps > eps_lo
        i1 = np.searchsorted(eps, hi, side="left")  # first eps >= eps_hi
        keep = i1 > i0
        flat = out.reshape(-1)
        base = rows[r_idx[keep]] * W
        for a, b in zip((base + i0[keep]).tolist(), (base + i1[keep]).tolist()):
            flat[a:b] = True
    if order is not None:
        target[:, order] = out.copy()
    return target


@_v.shapes_named
def period_edges(A, n, l=1.0, g=G_EARTH, drive=None, damping=0.0):
    """Half-periods ``T_lo < T_hi`` bounding stability zone ``n`` for fixed ``A > g``.

    Parameters
    ----------
    A : array_like
        Amplitude of the pivot acceleration, ``A > g``.
    n : int or array_like of int
        Zone index ``>= 0``.
    l, g : float or array_like
        Rod length and gravity, > 0. All broadcast together.
    drive : Drive or str, optional
        As in :func:`is_stable`.
    damping : array_like, optional
        Viscous damping ``c`` >= 0 [1/s] (``theta'' + c theta' = ...``).

    Returns
    -------
    T_lo, T_hi : ndarray
        For even ``n``: ``(T_{n+1}, T~_{n+1})``; for odd ``n``: ``(T~_{n+1}, T_{n+1})``
        (Corollary 4.1). NaN where another drive has no zone ``n`` at this ``A``.
    """
    A = _v.positive("A", A)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    n = _v.nonnegative_int("n", n)
    drive, c = _v.general_drive(drive, damping, "damping", g=g, l=l)
    with np.errstate(over="ignore", under="ignore"):  # mu = inf (A <= g) or 0 at the ends of the doubles
        mu = np.sqrt(g / A)
    if drive is not None:
        lo, hi = _drv.edges(mu, n, drive, _drv.zeta_of(c, l, g))
        scale = _time_scale(l, A)
        return lo * scale, hi * scale
    if np.any(mu >= 1.0):
        bad = np.broadcast_to(A, mu.shape)[mu >= 1.0].flat[0]
        raise _v.KapitzaValueError(
            f"A must exceed g (A > g) for stability zones to exist; got A={bad!r} with g={float(np.max(g))!r}"
        )
    lo, hi = _edges_eps(mu, n, np.sqrt((A - g) / A))  # A - g is exact as A -> g
    scale = _time_scale(l, A)
    return lo * scale, hi * scale


def _time_scale(l, A):
    """``sqrt(8 l / A)``, the half-period per unit ``eps``. ``8 l / A`` leaves the normal doubles
    before ``T`` does (``l = 1e-100, A = 1e250``: ``T_lo ~ 1e-299``; ``l = 1e308``: it overflows):
    there it is formed as ``sqrt(8) sqrt(l) / sqrt(A)``."""
    with np.errstate(over="ignore", under="ignore"):
        r = 8.0 * l / A
        return np.where(np.isfinite(r) & (r > 1e-300), np.sqrt(r), SQRT8 * (np.sqrt(l) / np.sqrt(A)))


def _kappa(T, l, g):
    """``2 g T^2 / l`` (``x^2 - u^2``), formed so that it stays a double where it is one: ``T^2``
    alone underflows at ``T = 1e-200`` while ``2 g (T / l) T`` need not. Refused by name where it
    is not a positive double."""
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        k = 2.0 * g * T * T / l
        alt = 2.0 * g * (T / l) * T
        k = np.where((k > 0.0) & np.isfinite(k), k, alt)
    bad = ~((k > 0.0) & np.isfinite(k))
    if np.any(bad):
        i = np.flatnonzero(bad.ravel())[0]
        raise _v.KapitzaValueError(
            f"T, l and g must give a positive, finite 2 g T^2 / l (a double); got T = {float(T.flat[i])!r}, "
            f"l = {float(np.broadcast_to(l, T.shape).flat[i])!r}, g = {float(np.broadcast_to(g, T.shape).flat[i])!r}")
    return k


@_v.shapes_named
def amplitude_edges(T, n, l=1.0, g=G_EARTH, drive=None, damping=0.0):
    """Amplitudes ``A_lo < A_hi`` bounding stability zone ``n`` for fixed half-period ``T``.

    Parameters
    ----------
    T : array_like
        Half-period of the drive, > 0.
    n : int or array_like of int
        Zone index ``>= 0``.
    l, g : float or array_like
        Rod length and gravity, > 0. All broadcast together.
    drive, damping : optional
        As in :func:`period_edges`; other drives and damping are solved by bisection on the
        zone index along ``A`` (``docs/drives.md``).

    Returns
    -------
    A_lo, A_hi : ndarray
        Zone ``n`` at this ``T`` is ``A_lo < A < A_hi``.

    Notes
    -----
    At fixed ``T`` the elliptic phase angle ``u = T sqrt((A - g)/l)`` increases with
    ``A`` and ``x^2 = u^2 + 2 g T^2 / l``; each edge equation ``u - n pi = alpha`` or
    ``beta`` changes sign once on ``n pi <= u <= (n+1) pi`` and is solved there by
    regula falsi (Illinois). Zone 0's lower edge, where ``u`` and ``alpha`` agree to
    ``O(u^3)`` as ``kappa = 2 g T^2 / l -> 0`` (``u ~ (6 kappa)^(1/4)``), is solved on the
    cancellation-free form of that gap (:func:`kapitza._exact.sin_half_a0`). Both edges are
    within 5 ulp of the 50-digit reference on the rigs of ``tests/test_rig_edges_oracle.py``
    (``kappa`` from 1e-299 to about 100, zones 0-2; no proof of a bound is claimed).
    """
    T = _v.positive("T", T)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    n = _v.nonnegative_int("n", n)
    drive, c = _v.general_drive(drive, damping, "damping", g=g, l=l)
    if drive is not None:
        T, n, l, g, c = np.broadcast_arrays(T, n, l, g, c)
        pairs = [_drv.along_amplitude(*args, drive, cc) for *args, cc in
                 zip(T.ravel(), n.ravel(), l.ravel(), g.ravel(), c.ravel())]
        lo = np.array([p[0] for p in pairs]).reshape(T.shape)
        hi = np.array([p[1] for p in pairs]).reshape(T.shape)
        return _v.scalars(np.asarray(lo), np.asarray(hi))
    T, n, l, g = np.broadcast_arrays(T, n, l, g)
    kappa = _kappa(T, l, g)

    # both edges in one solve: index 0 of the stacked arrays is the lower edge, 1 the upper
    upper = np.stack([np.zeros(n.shape, bool), np.ones(n.shape, bool)])
    nn, kk = np.stack([n, n]), np.stack([kappa, kappa])

    # Zone 0's lower edge at small u: u and alpha agree to O(u^3) there (the root carries
    # ``eps / u^2`` of relative rounding, and the old bracket [0, pi] took more steps than
    # regula falsi is given once u is far below 1). Its gap is taken from the
    # cancellation-free form of :func:`kapitza._exact.sin_half_a0` with ``D^2 - 1 = kappa / u^2``
    # (the identity :func:`zone_edges` rests on), and it is bracketed about its small-kappa
    # value ``u ~ (6 kappa)^(1/4)``.
    low0 = ~upper & (nn == 0)

    def F(u):
        with np.errstate(divide="ignore", under="ignore"):
            x = np.sqrt(u * u + kk)
            D = x / u
            f = u - nn * PI - np.where(upper, X.beta_x(x, D), X.alpha_x(x, D))
            small = low0 & (u < 1.0) & (np.abs(f) < 2.0)
            if small.any():
                us = u[small]
                s = X.sin_half_a0(us, D[small], None, kk[small] / us / us)
                f[small] = 2.0 * np.arcsin(np.clip(s, -1.0, 1.0))
        return f

    a, b = nn * PI + 0.0, (nn + 1.0) * PI
    if low0.any():
        guess = np.sqrt(np.sqrt(6.0) * np.sqrt(kk))  # (6 kappa)^(1/4), without overflow
        a0, b0 = np.minimum(0.5 * guess, 1.0), np.minimum(2.0 * guess, PI)
        a = np.where(low0 & (F(a0) < 0.0), a0, a)
        b = np.where(low0 & (F(b0) > 0.0), b0, b)
    u = X.illinois(F, a, b, ulps=1.0)
    TT, ll, gg = np.stack([T, T]), np.stack([l, l]), np.stack([g, g])
    with np.errstate(over="ignore"):  # (u / T)^2 may overflow where l (u / T)^2 does not
        A = gg + ll * (u / TT) ** 2
        A = np.where(np.isfinite(A), A, gg + (np.sqrt(ll) * u / TT) ** 2)
    return _v.scalars(A[0], A[1])
