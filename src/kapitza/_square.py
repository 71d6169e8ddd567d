"""The paper's square wave in closed form: the kernels behind :class:`kapitza.SquareWave`.

Floquet data, certified verdicts, zone edges in ``eps``, ``T`` and ``A``, stability margins,
pixel-exact grids, the monodromy and the exact linear motion of the undamped square wave
(2.2), from Theorems 3.3-3.4 and Corollary 4.1 (``docs/theory.md`` sections 3 and 5) with
the factored forms of :mod:`kapitza._exact` and the last-bit certificate of
:mod:`kapitza._certify`. Inputs are trusted (validated by the public functions of
:mod:`kapitza.zones`, :mod:`kapitza.propagation` and :mod:`kapitza.analysis`, which reach this
module through the drive's methods, :mod:`kapitza.drives.square`).

The edges are found by Newton's method on ``F(u) = u - n pi - alpha(D u)`` (convex, iterated
from the right of its root) and ``u - n pi - beta(D u)`` (concave and increasing, iterated
from the left): both sequences are monotone, so they cannot overshoot into a neighbouring
branch, and they stop at machine precision.
"""
from __future__ import annotations

import math

import numpy as np

from . import _certify
from . import _exact as X
from . import _validate as _v
from .parameters import SQRT8, arnold_trusted, phase_angles_trusted as _phase_angles, time_scale

PI = np.pi

_MAX_NEWTON = 200


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



# ---------------------------------------------------------------- Floquet data and motion
def _tau_error(x, u, mu, tau):
    """A bound on the absolute error of the closed forms' ``tau`` (elliptic: ``mu < 1``).

    ``tau = -sin(u - gamma) / sin(delta)``: ``u`` and the angle ``pi - gamma`` are each formed to a
    few units of ``u + 4`` in absolute terms, which the division by ``sin(delta)`` (about
    ``e^{-x}`` far out) carries into ``tau``; ``sin(delta)`` itself is good to a few units of
    ``x + 4`` relative. Where ``tau`` is far smaller than ``1 / sin(delta)`` (next to a thin zone,
    or where ``tau`` passes 0) the first term is most of ``|tau|``: the trace has lost its digits.
    """
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        lsd = X.log_sin_delta(x, X.s4_of(mu))
        return (np.exp(np.minimum(np.log(_certify.TOL * (np.abs(u) + 4.0)) - lsd, 710.0))
                + _certify.TOL * (x + 4.0) * np.abs(tau))


def _floquet(eps, mu, certify=True, trace=False, phi=None, with_unsure=False):
    """(tau, growth, theta, stable, n) for trusted eps > 0, mu > 0 (any mu). ``certify``: decide
    the points within the rounding bound of an edge in extended precision
    (:func:`kapitza._certify.exact_half_trace`; a search that needs the predicate only away from its
    last few ulp switches it off, and certifies its final bracket). ``with_unsure`` (without
    ``certify`` or ``trace``): a sixth item marks those points, where the verdict of the doubles
    may not be the exact one.

    ``trace``: the trace is reported: a sixth item bounds the absolute error of ``tau``
    (:func:`_tau_error`), and where that exceeds :data:`kapitza._certify.TRACE_RTOL` ``|tau|`` the
    trace, growth and angle are those of the exact product (as at the points certified); ``phi``:
    ``(mu, zeta)`` when ``mu`` is the damped system's rounded ``mu_c``, the exact trace of those
    points then taken at ``mu^2 (1 + zeta^2)`` (:func:`kapitza._certify.tau_mp`)."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    ell = mu < 1.0
    x, u, D = _phase_angles(eps, np.where(ell, mu, 0.5))
    n, a, b, tau, growth, theta = X.floquet_elliptic(x, u, D, np.where(ell, mu, 0.5))
    stable_e = (a > 0) & (b < 0)
    check = ell & (_certify.unsure(u, a, b, x) | (~stable_e & (growth <= 0.0) & _certify.affordable(u, x)))
    certify = certify or trace
    m_x, z_x = mu, None
    verdict_check = check
    if trace:
        err = _tau_error(x, u, np.where(ell, mu, 0.5), tau)
        with np.errstate(invalid="ignore"):
            ill = ell & (err > _certify.TRACE_RTOL * np.abs(tau)) & _certify.affordable(u, x)
        if phi is not None:
            # the verdict's points at the mu given, the trace's at the exact phi-system
            only = ill & ~check
            m_x = np.where(only, np.reshape(phi[0], mu.shape), mu)
            z_x = np.where(only, np.reshape(phi[1], mu.shape), 0.0)
        check = check | ill
    if certify and np.any(check):
        # signs lost to rounding (or an unstable point whose excess rounded to zero):
        # the exact trace decides the verdict, the growth and the angle
        tau, growth, theta, a, b = (np.array(v, dtype=float) for v in (tau, growth, theta, a, b))
        t_e, _, st, acos_e = _certify.exact_half_trace(eps[check], m_x[check], None if z_x is None else z_x[check])
        nn = n[check]
        even = np.mod(nn, 2.0) == 0.0
        acos_t = np.where(st, acos_e, 0.0)
        # just below zone n tr M has the sign (-1)^n, just above it the other sign
        below = np.sign(t_e) == np.where(even, 1.0, -1.0)
        theta[check] = np.where(st, nn * PI + np.where(even, acos_t, PI - acos_t),
                                np.where(below, nn * PI, (nn + 1.0) * PI))
        with np.errstate(over="ignore"):
            tau[check] = t_e
        growth[check] = np.where(st, 0.0, acos_e)
        # a > 0 > b exactly where stable (the signs the rest of the code reads)
        a[check] = np.where(st, 1.0, np.where(below, -1.0, 1.0))
        b[check] = np.where(st, -1.0, np.where(below, -1.0, 1.0))
    if not ell.all():
        # sqrt(1 + mu^2) and sqrt(mu^2 - 1) without squaring mu (it may be ~1e300)
        r = 1.0 / np.maximum(mu, 1.0)
        with np.errstate(over="ignore"):  # eps mu beyond 1e308: x and v are inf, and so is the growth
            xh = SQRT8 * eps * np.where(mu > 1.0, mu * np.sqrt(1.0 + r * r), np.hypot(1.0, mu))
            v = SQRT8 * eps * np.where(mu > 1.0, mu * np.sqrt(np.maximum((1.0 - r) * (1.0 + r), 0.0)), 0.0)
        tau_h, growth_h = X.floquet_hyperbolic(xh, v)
        tau = np.where(ell, tau, tau_h)
        growth = np.where(ell, growth, growth_h)
        theta = np.where(ell, theta, 0.0)
    stable = ell & (a > 0) & (b < 0)
    out = tau, growth, theta, stable, np.where(stable, n, -1).astype(np.int64)
    if not trace:
        return out + (check,) if with_unsure else out
    # exact product: tau correctly rounded; no elliptic phase: every term of tau is positive
    # (docs/theory.md section 3), each good to a few units of the phases
    # (damped, the verdict's points were decided at the rounded mu_c: their bound stays the closed forms')
    exact = check & ~verdict_check if phi is not None else check
    with np.errstate(over="ignore", invalid="ignore"):
        u_half = 0.5 * np.finfo(float).eps
        h_err = _certify.TOL * (np.where(ell, 0.0, xh + v) + 4.0) * np.abs(tau) if not ell.all() else 0.0
        tau_error = np.where(ell, np.where(exact, u_half * np.abs(tau), err), h_err)
    return out + (tau_error,)


def _flow(s, tau):
    """Entries ``(c, sd, ds)`` of the flow matrix ``[[c, sd], [ds, c]]`` of ``theta'' = s theta``
    over a time ``tau`` (``s`` of any sign; ``s = 0`` is free flight)."""
    r = np.sqrt(np.abs(s)) * tau
    pos, neg = s > 0, s < 0
    rs = np.where(r > 0, r, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        c = np.where(pos, np.cosh(r), np.where(neg, np.cos(r), 1.0))
        shc = np.where(r > 0, np.where(pos, np.sinh(rs), np.sin(rs)) / rs, 1.0)  # sinh(r)/r or sin(r)/r
        sd = tau * shc
        ds = np.where(pos, 1.0, -1.0) * (r * r / np.where(tau > 0, tau, 1.0)) * shc
    ds = np.where(s == 0, 0.0, ds)
    return c, sd, ds


def _apply(c, sd, ds, th, dth):
    return c * th + sd * dth, ds * th + c * dth


def _monodromy(T, A, l, g):
    ch, sdh, dsh = _flow((g + A) / l, T)
    ce, sde, dse = _flow((g - A) / l, T)
    H = np.stack([np.stack([ch, sdh], -1), np.stack([dsh, ch], -1)], -2)
    E = np.stack([np.stack([ce, sde], -1), np.stack([dse, ce], -1)], -2)
    with np.errstate(over="ignore", invalid="ignore"):
        M = E @ H
    bad = np.isnan(M)
    if np.any(bad):
        # cosh overflowed and inf - inf appeared. A hyperbolic flow over r is (e^r / 2) P + O(e^-r),
        # P = [[1, 1/w], [w, 1]], so those entries are infinite with the sign of the leading product.
        def lead(s, F):
            w = np.sqrt(np.abs(s))
            one = np.ones_like(w)
            P = np.stack([np.stack([one, 1.0 / np.where(w > 0, w, 1.0)], -1), np.stack([w, one], -1)], -2)
            return np.where((s > 0)[..., None, None] & ~np.isfinite(F), P, F)

        with np.errstate(over="ignore", invalid="ignore"):
            sign = np.sign(lead((g - A) / l, E) @ lead((g + A) / l, H))
        M = np.where(bad, sign * np.inf, M)
    return M



def _multipliers(tau, growth, theta, stable):
    sgn = np.where(tau < 0, -1.0, 1.0)
    with np.errstate(over="ignore"):
        big = sgn * np.exp(growth)
    small = sgn * np.exp(-growth)
    lam1 = np.where(stable, np.exp(1j * theta), big + 0j)
    lam2 = np.where(stable, np.exp(-1j * theta), small + 0j)
    return np.stack([lam1, lam2], axis=-1)



def _chebyshev_pair(k, tau, growth, theta, stable):
    """``U_{k-1}(tau), U_{k-2}(tau)`` so that ``M^k = U_{k-1} M - U_{k-2} I``."""

    def U(m):  # U_{m-1}(tau) for integer m >= 0
        sgn = np.where(tau < 0, -1.0, 1.0)
        with np.errstate(over="ignore", invalid="ignore"):
            st = np.sin(theta)
            s_stab = np.where(np.abs(st) > 1e-300, np.sin(m * theta) / np.where(st == 0, 1.0, st),
                              m * np.cos((m - 1) * theta))
            sh = np.sinh(growth)
            s_uns = np.where(growth > 0, np.sinh(m * growth) / np.where(sh > 0, sh, 1.0), m) * sgn ** (m - 1)
        return np.where(stable, s_stab, s_uns)

    return U(k), U(k - 1.0)




# ---------------------------------------------------------------- the public questions' bodies
def margin(eps, mu):
    """``(stable, zone, eps_lo, eps_hi, margin)`` of :func:`kapitza.stability_margin` (validated
    arrays; any ``mu``): the zone containing the point, or the nearer of the two zones about the
    gap it sits in (one edge solve each)."""
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
        m = np.where(use_b, d_b, d_n) / eps
    # Edges are good to a few ulp; the certified verdict decides the sign of the margin.
    tiny = np.finfo(float).smallest_subnormal
    m = np.where(stable, np.maximum(m, tiny), np.minimum(m, -tiny))
    nan = np.full(eps.shape, np.nan)
    return (stable, np.where(ell, zone, -1), np.where(ell, lo, nan), np.where(ell, hi, nan),
            np.where(ell, m, -np.inf))


def grid(eps, mu, out):
    """Paint ``out[i, j] = stable(eps[j], mu[i])`` (``eps`` sorted ascending, ``out`` zeroed, shape
    ``(len(mu), len(eps))``) from the edges of every zone in view (:func:`kapitza.stability_grid`)."""
    W = eps.size
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
        from ._paint import settle_near_edges

        settle_near_edges(eps, out, rows[r_idx], lo, hi, i0, i1, lambda e, r: _verdict(e, mu[r], want_n=False)[0])
    return out


def period_edges(A, n, l, g):
    """``(T_lo, T_hi)`` of zone ``n`` at fixed ``A`` (:func:`kapitza.period_edges`; validated arrays).
    ``A <= g`` is refused by name: the square wave has no zone there."""
    with np.errstate(over="ignore", under="ignore"):  # mu = inf (A <= g) or 0 at the ends of the doubles
        mu = np.sqrt(g / A)
    if np.any(mu >= 1.0):
        bad = np.broadcast_to(A, mu.shape)[mu >= 1.0].flat[0]
        raise _v.KapitzaValueError(
            f"A must exceed g (A > g) for stability zones to exist; got A={bad!r} with g={float(np.max(g))!r}"
        )
    lo, hi = _edges_eps(mu, n, np.sqrt((A - g) / A))  # A - g is exact as A -> g
    scale = time_scale(l, A)
    return lo * scale, hi * scale


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


def amplitude_edges(T, n, l, g):
    """``(A_lo, A_hi)`` of zone ``n`` at fixed ``T`` (:func:`kapitza.amplitude_edges`; validated arrays)."""
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
    return A[0], A[1]


def linear_motion(t, theta0, dtheta0, T, A, l, g):
    """``theta(t), theta'(t)`` of :func:`kapitza.linear_motion` (undamped; validated arrays)."""
    # one Floquet analysis and monodromy per parameter set, not per sample time
    T, A, l, g = np.broadcast_arrays(T, A, l, g)
    eps, mu = arnold_trusted(T, A, l, g)
    tau, growth, theta, stable, _ = _floquet(eps, mu)
    M = _monodromy(T, A, l, g)
    t, theta0, dtheta0 = np.broadcast_arrays(t, theta0, dtheta0, T)[:3]
    k = np.floor(t / (2.0 * T))
    r = t - 2.0 * k * T
    # Rounding can put r a hair outside [0, 2T).
    over = r >= 2.0 * T
    k = np.where(over, k + 1.0, k)
    r = np.where(over, r - 2.0 * T, np.maximum(r, 0.0))
    u1, u2 = _chebyshev_pair(k, tau, growth, theta, stable)
    with np.errstate(over="ignore", invalid="ignore"):
        th = (u1 * M[..., 0, 0] - u2) * theta0 + u1 * M[..., 0, 1] * dtheta0
        dth = u1 * M[..., 1, 0] * theta0 + (u1 * M[..., 1, 1] - u2) * dtheta0
        # M^0 = I: keep 0 * M out of the first period (M may be inf there)
        th = np.where(k == 0, theta0, th)
        dth = np.where(k == 0, dtheta0, dth)
        hyper = r < T
        c, sd, ds = _flow((g + A) / l, np.where(hyper, r, T))
        th, dth = _apply(c, sd, ds, th, dth)
        c, sd, ds = _flow((g - A) / l, np.where(hyper, 0.0, r - T))
        th, dth = _apply(c, sd, ds, th, dth)
    bad = ~(np.isfinite(th) & np.isfinite(dth))
    if bad.any():
        i = np.argwhere(bad)[0]
        raise OverflowError(
            "the motion grows beyond the range of a double "
            f"(growth {float(np.broadcast_to(growth, bad.shape)[tuple(i)]):.4g} per period, "
            f"t = {float(t[tuple(i)]):.6g} s)"
        )
    return th, dth


_MU_MIN = 1e-6  # A = 1e12 g: a zone still open there has no upper frequency
_EPS_SERIES = 1e-5  # below this zone 0's lower edge is eps = sqrt(3/2) mu to rounding
_SQRT_3_2 = math.sqrt(1.5)


def rig_margins(eps, mu, zone, T, stroke):
    """The frequency interval of zone ``zone`` at this stroke (:func:`kapitza.analyze`), from the closed forms.

    At fixed ``eps`` both ``w - alpha`` and ``w - beta`` (``w = u - n pi``, ``docs/theory.md``
    section 5) decrease as ``mu`` grows (``u`` falls, ``alpha`` and ``beta`` rise), so zone ``n``
    is ``mu_b < mu < mu_a`` with ``w - alpha = 0`` at ``mu_a`` and ``w - beta = 0`` at ``mu_b``;
    both are found by regula falsi (:func:`kapitza._exact.illinois`) to an ulp or two of the
    gaps' rounding. Zone 0's lower gap is taken from :func:`kapitza._exact.lower_gap`, free of
    the cancellation of ``u`` against ``alpha`` as ``u -> 0``; that edge reaches every ``eps``
    (``eps_lo = sqrt(3/2) mu (1 + 4 mu^4 / 7 + ...)`` as ``mu -> 0``), so its search starts
    below ``eps / 2``, and below ``eps = 1e-5`` the series' first term is its value to rounding.
    """
    n = float(zone)

    def gap(m, upper):
        p = np.sqrt(1.0 + m * m)
        q = np.sqrt((1.0 - m) * (1.0 + m))
        x, u = SQRT8 * eps * p, SQRT8 * eps * q
        with np.errstate(divide="ignore"):
            D = p / q
        w = u - n * np.pi
        return np.where(upper, w - X.beta_x(x, D), X.lower_gap(x, u, w, n, D, m))

    upper = np.array([False, True])
    lo = np.array([min(_MU_MIN, 0.5 * eps) if n == 0 else _MU_MIN, _MU_MIN])
    hi = np.full(2, 1.0 - 1e-12)
    f_lo = gap(lo, upper)
    out = dict(stroke=float(stroke))
    series = n == 0 and eps < _EPS_SERIES  # (then the gap at lo may underflow; its sign is known)
    if f_lo[0] <= 0.0 and not series:  # below the zone's lower edge at every mu: no frequency reaches it
        return out
    open_top = f_lo[1] < 0.0  # still in the zone at the smallest mu
    if series:
        roots = np.array([eps / _SQRT_3_2, X.illinois(lambda m: gap(m, upper[1:]), lo[1:], hi[1:], ulps=1.0)[0]])
    else:
        roots = X.illinois(lambda m: gap(m, upper), lo, hi, ulps=1.0)
    mu_a, mu_b = float(roots[0]), (0.0 if open_top else float(roots[1]))
    if mu_b < mu_a:
        f = 0.5 / T
        out.update(frequency_lo=float(f * mu / mu_a), frequency_hi=float("inf") if open_top else float(f * mu / mu_b))
    return out


# ------------------------------------------------------------------ kinematics
def _phase_index(t, T):
    """Phase index ``j = floor(t/T)`` (even: ``a = +A``) and the time ``r`` into it, ``0 <= r < T``.

    The one rule by which every part of the package decides which phase a time is in,
    so that a time a rounding error from a switch is never put in two phases.
    """
    j = np.floor(t / T)
    r = t - j * T
    over = r >= T
    j = np.where(over, j + 1.0, j)
    r = np.where(over, r - T, np.maximum(r, 0.0))
    return j, r


def _phase_time(t, T):
    """Time in ``[0, 2T)`` since the start of the current period, consistent with :func:`_phase_index`."""
    j, r = _phase_index(t, T)
    return np.where(np.mod(j, 2.0) == 0.0, r, r + T)


def _acceleration(t, T, A):
    j, _ = _phase_index(t, T)
    return np.where(np.mod(j, 2.0) == 0.0, A, -A)


def _velocity(t, T, A):
    r = _phase_time(t, T)
    return np.where(r < T, A * (r - 0.5 * T), -A * (r - 1.5 * T))


def _displacement(t, T, A):
    r = _phase_time(t, T)
    quarter = 0.125 * A * T * T
    return np.where(r < T, 0.5 * A * (r - 0.5 * T) ** 2 - quarter, quarter - 0.5 * A * (r - 1.5 * T) ** 2)
