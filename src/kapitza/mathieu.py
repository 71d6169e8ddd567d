"""Mathieu's equation: characteristic values, Floquet data, and the zones of the sine drive.

``y'' + (a - 2 q cos 2z) y = 0`` (DLMF 28.2.1). Its periodic solutions exist on the
characteristic curves ``a = a_n(q)`` (even in ``z``) and ``a = b_n(q)`` (odd); with Fourier
series they are the eigenvalues of four symmetric tridiagonal matrices (DLMF 28.4), here
with ``d_r`` on the diagonal and ``q`` beside it:

    a_{2k}:    d = (0, 4, 16, 36, ...),   the first off-diagonal q sqrt(2)   (cos 2rz)
    a_{2k+1}:  d = (1 + q, 9, 25, ...)                                      (cos (2r+1)z)
    b_{2k+1}:  d = (1 - q, 9, 25, ...)                                      (sin (2r+1)z)
    b_{2k+2}:  d = (4, 16, 36, ...)                                         (sin (2r+2)z)

The ``k``-th eigenvalue (ascending) of each is the characteristic value of that order (the
curves of one family do not cross). The matrix is truncated at ``N`` rows, ``N`` chosen from
``q`` (the coefficients decay super-exponentially beyond ``r ~ sqrt(q)``) and raised until two
sizes agree to the requested accuracy. ``scipy.special.mathieu_a/b`` are not used: they are
known to return wrong values and to jump branches (scipy issues 4479, 14526).

**The sine drive.** With ``z = pi t/(2T) - pi/4`` the upright's linearisation under the
acceleration ``A sin(pi t/T)`` is Mathieu's equation with ``q = 16 eps^2/pi^2`` and
``a = -2 mu^2 q`` (``docs/mathieu.md``). Zone ``n`` is ``a_n(q) < a < b_{n+1}(q)`` on that line.
An edge solves ``a_n(q) = -2 mu^2 q``: the eigenvalue equation ``(D + q O) v = -2 mu^2 q v``
is the pencil ``D v = -q B v``, ``B = O + 2 mu^2 I`` (``O``: the ``q``-parts), and with ``D``
diagonal and positive (the ``a_{2k}`` family after eliminating its first coefficient) it is the
symmetric tridiagonal eigenproblem ``D^{-1/2} B D^{-1/2} w = nu w``, ``q = -1/nu``: every edge
of a family at one ``mu`` from one eigenproblem, with no root search.

**Floquet data.** Hill's determinant (Whittaker and Watson, 19.42):
``tr M / 2 = 1 - 2 Delta(0) sin^2(pi sqrt(a)/2)`` over the period ``pi``, ``Delta(0)`` the
determinant of the matrix with 1 on the diagonal and ``q/(4 r^2 - a)`` beside it in row ``r``.
For ``a < 0`` (always, for the sine drive) no denominator vanishes and
``tr M / 2 = 1 + 2 Delta(0) sinh^2(pi sqrt(-a)/2)``.
"""
from __future__ import annotations

import numpy as np

from . import _validate as _v

__all__ = ["characteristic_a", "characteristic_b", "sine_zone_edges"]

PI = np.pi
_TOL = 1e-14


# ---------------------------------------------------------------- the four matrices
def _family(kind, parity):
    """``(diag(r), first_scale, first_shift)`` of a family; ``first_shift`` multiplies q on d_0."""
    if kind == "a" and parity == 0:
        return (lambda r: (2.0 * r) ** 2), np.sqrt(2.0), 0.0
    if kind == "a":
        return (lambda r: (2.0 * r + 1.0) ** 2), 1.0, 1.0
    if parity == 1:
        return (lambda r: (2.0 * r + 1.0) ** 2), 1.0, -1.0
    return (lambda r: (2.0 * r + 2.0) ** 2), 1.0, 0.0


def _decay_rows(q):
    """Rows beyond which the Fourier coefficients of Mathieu functions at ``q`` fall below 1e-18:
    the smallest ``r`` with ``(|q|/4)^r / (r!)^2 < 1e-18`` (their decay, DLMF 28.4(iii))."""
    from scipy.special import gammaln

    # (beyond 1e300 the count exceeds the table anyway, and q rounded up would overflow)
    q = np.clip(np.abs(np.asarray(q, float)), 1e-3, 1e300)
    # the count grows with q: evaluate it on q rounded up to powers of 1.05 (a few distinct values)
    step = np.log(1.05)
    key = np.ceil(np.log(q) / step)
    keys, inv = np.unique(key.ravel(), return_inverse=True)
    qk = np.exp(keys * step)
    r = np.arange(1, 4097, dtype=float)
    logs = r[None, :] * np.log(qk[:, None] / 4.0) - 2.0 * gammaln(r + 1.0)[None, :]
    # the first r past the peak of the terms where they are below 1e-18
    past = (logs < -41.5) & (r[None, :] > 2.0 * np.sqrt(qk)[:, None] + 8.0)
    first = np.where(past.any(axis=1), np.argmax(past, axis=1) + 1, 4096)
    return first[inv].reshape(q.shape)


#: Rows of the largest dense matrix solved for a characteristic value (about a second each;
#: ``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_ROWS = 4200


def _size(k, q):
    """Rows that carry the k-th characteristic value at q to double precision (then checked)."""
    rows = int(np.max(_decay_rows(q), initial=1))
    if rows >= 4096:  # beyond the table of _decay_rows: the truncation is not known
        raise _v.KapitzaValueError(f"q must satisfy |q| <= 4e6 for the characteristic values; got {float(q)!r}")
    N = int(k + 8 + rows)
    _v.bounded_work("the rows of the truncated matrix", N, MAX_ROWS,
                    what=f"dense eigenproblems, order n and |q| set the rows; here n ~ {2 * int(k)}, q = {float(q):.4g}")
    return N


def _eigs(kind, parity, q, N):
    """Ascending eigenvalues, shape ``(len(q), N)``, of the truncated matrices at each q."""
    d_of, s0, shift = _family(kind, parity)
    r = np.arange(N, dtype=float)
    if N > 64:
        # large truncations: the tridiagonal solver, O(N^2) per q instead of O(N^3)
        from scipy.linalg import eigvalsh_tridiagonal

        out = np.empty((q.size, N))
        for i, qi in enumerate(q):
            d = d_of(r).astype(float)
            d[0] += shift * qi
            e = np.full(N - 1, qi)
            e[0] *= s0
            out[i] = eigvalsh_tridiagonal(d, e)
        return out
    M = np.zeros((q.size, N, N))
    idx = np.arange(N)
    M[:, idx, idx] = d_of(r)[None, :]
    M[:, 0, 0] += shift * q
    off = np.broadcast_to(q[:, None], (q.size, N - 1)).copy()
    off[:, 0] *= s0
    M[:, idx[:-1], idx[1:]] = off
    M[:, idx[1:], idx[:-1]] = off
    return np.linalg.eigvalsh(M)


def _characteristic(kind, n, q):
    n, q = np.broadcast_arrays(np.asarray(n, np.int64), np.asarray(q, float))
    shape = n.shape
    n, q = n.ravel(), q.ravel()
    out = np.empty(n.size)
    # q -> -q: a_{2k}, b_{2k+2} are even in q; a_{2k+1}(-q) = b_{2k+1}(q) (DLMF 28.2.26)
    neg = q < 0
    qa = np.abs(q)
    kinds = np.where(neg & (n % 2 == 1), "b" if kind == "a" else "a", kind)
    for kd in ("a", "b"):
        for parity in (0, 1):
            sel = np.flatnonzero((kinds == kd) & (n % 2 == parity))
            if sel.size == 0:
                continue
            # a_{2k}, a_{2k+1}: k = (n - parity) / 2;  b_{2k+1}: k = (n - 1) / 2;  b_{2k+2}: k = (n - 2) / 2
            k = (n[sel] - parity) // 2 if kd == "a" else (n[sel] - (1 if parity else 2)) // 2
            out[sel] = _converged(kd, parity, k, qa[sel])
    return out.reshape(shape)


def _converged(kind, parity, k, q):
    """The k-th eigenvalue of each family matrix, with the truncation raised until two sizes agree."""
    res = np.empty(q.size)
    todo = np.arange(q.size)
    N = np.array([_size(kk, qq) for kk, qq in zip(k, q)])
    for _ in range(12):
        if todo.size == 0:
            break
        nxt = []
        for Nv in np.unique(N[todo]):
            grp = todo[N[todo] == Nv]
            e1 = _eigs(kind, parity, q[grp], Nv)[np.arange(grp.size), k[grp]]
            e2 = _eigs(kind, parity, q[grp], Nv + 16)[np.arange(grp.size), k[grp]]
            ok = np.abs(e1 - e2) <= _TOL * np.maximum(1.0, np.abs(e2))
            res[grp[ok]] = e2[ok]
            nxt.append(grp[~ok])
        todo = np.concatenate(nxt) if nxt else np.zeros(0, np.int64)
        N[todo] = 2 * N[todo]
    if todo.size:
        raise _v.KapitzaValueError(f"q is too large for the characteristic value to converge; got {float(q[todo[0]])!r}")
    return res


@_v.shapes_named
def characteristic_a(n, q):
    """Mathieu characteristic value ``a_n(q)`` (even solutions), ``n >= 0``.

    Parameters
    ----------
    n : int or array_like of int
        Order, ``n >= 0``.
    q : array_like
        Finite; broadcasts with ``n``; ``|q|`` up to about 1e6.

    Returns
    -------
    ndarray
        ``a_n(q)`` to about 1e-14 relative (absolute near 0).

    Notes
    -----
    DLMF 28.2, 28.4: eigenvalues of the symmetric tridiagonal matrices in the module notes;
    ``docs/mathieu.md``.
    """
    n = _v.nonnegative_int("n", n)
    q = _v.finite("q", q)
    return _v.scalars(_characteristic("a", n, q))


@_v.shapes_named
def characteristic_b(n, q):
    """Mathieu characteristic value ``b_n(q)`` (odd solutions), ``n >= 1``.

    Parameters
    ----------
    n : int or array_like of int
        Order, ``n >= 1``.
    q : array_like
        Finite; broadcasts with ``n``.

    Returns
    -------
    ndarray
    """
    n = _v.nonnegative_int("n", n, minimum=1)
    q = _v.finite("q", q)
    return _v.scalars(_characteristic("b", n, q))


# ---------------------------------------------------------------- the sine drive's edges
def _pencil(kind, parity, mu2, N):
    """``C = D^{-1/2} B D^{-1/2}`` for each mu (shape ``(len(mu2), N, N)``): its negative
    eigenvalues ``nu`` give the roots ``q = -1/nu`` of ``char(q) = -2 mu^2 q``."""
    diag, off = _pencil_bands(kind, parity, mu2, N)
    idx = np.arange(N)
    C = np.zeros((mu2.size, N, N))
    C[:, idx, idx] = diag
    C[:, idx[:-1], idx[1:]] = off
    C[:, idx[1:], idx[:-1]] = off
    return C


def _pencil_bands(kind, parity, mu2, N):
    """Diagonal and off-diagonal of :func:`_pencil`'s matrix (rows of ``mu2``)."""
    d_of, s0, shift = _family(kind, parity)
    if kind == "a" and parity == 0:
        # eliminate the first coefficient: row 0 gives c_0 = -c_1 / (sqrt 2 mu^2); what is left
        # is the b_{2k+2}-shaped family with 2 mu^2 - 1/mu^2 in the first diagonal entry of B
        d = (2.0 * np.arange(1, N + 1, dtype=float)) ** 2
        first = 2.0 * mu2 - 1.0 / mu2
        off = np.ones(N - 1)
    else:
        d = d_of(np.arange(N, dtype=float))
        first = 2.0 * mu2 + shift
        off = np.ones(N - 1)
        off[0] = s0
    s = 1.0 / np.sqrt(d)
    diag = np.broadcast_to(2.0 * mu2[:, None], (mu2.size, N)).copy()
    diag[:, 0] = first
    return diag * (s * s)[None, :], off * s[:-1] * s[1:]


def _edge_q(kind, parity, k, mu):
    """The k-th positive root q of ``char_{family}(q) = -2 mu^2 q`` (k = 0, 1, ...), per mu.

    The truncation follows :func:`_decay_rows` at twice the root's asymptotic size
    (``sqrt q ~ (2n + 1)/(1 - mu^2)``, from ``a_n ~ -2q + 2(2n+1) sqrt q``); small matrices go
    in batches through a dense solver, large ones through LAPACK's tridiagonal bisection for the
    one eigenvalue wanted.
    """
    from scipy.linalg import eigvalsh_tridiagonal

    mu2 = mu * mu
    n_eff = 2 * k + parity + 1
    q_est = ((2.0 * n_eff + 1.0) / np.maximum(1.0 - mu2, 1e-300)) ** 2 + 4.0 * n_eff**2
    N = (8 * np.ceil((k + 8 + _decay_rows(2.0 * q_est)) / 8.0)).astype(np.int64)
    if np.any(N > 16384):
        bad = int(np.argmax(N > 16384))
        raise _v.KapitzaValueError(
            f"mu and n need more than 16384 rows for the sine drive's zone edges (mu too close to 1 or the zone n "
            f"too high); got mu={float(mu[bad])!r} with n ~ {2 * int(k[bad]) + parity}")
    res = np.empty(mu.size)
    for Nv in np.unique(N):
        grp = np.flatnonzero(N == Nv)
        diag, off = _pencil_bands(kind, parity, mu2[grp], int(Nv))
        if Nv <= 160:
            ev = np.linalg.eigvalsh(_pencil(kind, parity, mu2[grp], int(Nv)))[np.arange(grp.size), k[grp]]
        else:
            ev = np.array([eigvalsh_tridiagonal(diag[j], off, select="i", select_range=(kk, kk))[0]
                           for j, kk in enumerate(k[grp])])
        res[grp] = np.where(ev < 0, -1.0 / np.where(ev < 0, ev, -1.0), np.nan)
    return res


def _sine_edges(mu, n):
    """``(eps_lo, eps_hi)`` of the sine drive's zone n (trusted 0 < mu < 1)."""
    mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
    if np.any(mu < 1e-150):  # the pencil divides by mu^2
        raise _v.KapitzaValueError(f"mu must be >= 1e-150 for the sine drive's zones (mu^2 must be a double); "
                                   f"got {float(np.min(mu))!r}")
    shape = mu.shape
    mu, n = mu.ravel(), n.ravel()
    q_lo = np.empty(mu.size)
    q_hi = np.empty(mu.size)
    k = n // 2
    even = n % 2 == 0
    for sel, fam_lo, fam_hi in ((np.flatnonzero(even), ("a", 0), ("b", 1)),
                                (np.flatnonzero(~even), ("a", 1), ("b", 0))):
        if sel.size:
            q_lo[sel] = _edge_q(*fam_lo, k[sel], mu[sel])
            q_hi[sel] = _edge_q(*fam_hi, k[sel], mu[sel])
    scale = PI / 4.0  # q = 16 eps^2 / pi^2
    return (scale * np.sqrt(q_lo)).reshape(shape), (scale * np.sqrt(q_hi)).reshape(shape)


@_v.shapes_named
def sine_zone_edges(mu, n):
    """Edges ``eps_lo < eps_hi`` of zone ``n`` of the sine drive (acceleration ``A sin(pi t/T)``).

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int or array_like of int
        Zone index ``>= 0``; broadcasts with ``mu``.

    Returns
    -------
    eps_lo, eps_hi : ndarray
        Zone ``n`` is ``a_n(q) < -2 mu^2 q < b_{n+1}(q)``, ``q = 16 eps^2 / pi^2``; the lower
        edge carries a 2T-periodic motion for even ``n`` (4T for odd), the upper the other.

    Notes
    -----
    Each family's edges are the eigenvalues of one symmetric tridiagonal matrix (module
    notes; ``docs/mathieu.md``). Damped zones: :func:`kapitza.zone_edges` with
    ``drive=SineWave()`` and ``zeta``.
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    n = _v.nonnegative_int("n", n)
    return _v.scalars(*_sine_edges(mu, n))


# ---------------------------------------------------------------- Floquet data (Hill)
def _hill_half_trace(a, q, minus_one=False):
    """``(tau, log|tau|)`` of Mathieu's monodromy over z in [0, pi] for ``a < 0`` (Hill);
    with ``minus_one``, ``tau - 1 = 2 Delta(0) sinh^2(pi sqrt(-a) / 2)`` itself (no 1 added and
    taken away: accurate where ``tau`` is near 1).

    ``Delta(0)`` is the continuant of ``xi_r = q/(4 r^2 - a)``, ``r`` in Z, computed by the
    three-term recurrence over ``|r| <= R`` (``R = 200 + 4 sqrt q``) and the far tails as
    ``log p_r = -xi_r xi_{r-1} - xi_r xi_{r-1}^2 xi_{r-2} - (xi_r xi_{r-1})^2 / 2 + O(xi^6)`` summed to
    ``|r| = 2 R`` and integrated beyond: a plain truncation would leave a relative error
    ``q^2 / (24 R^3)``.
    """
    a = np.asarray(a, float)
    q = np.asarray(q, float)
    R = int(200 + np.ceil(4.0 * np.sqrt(np.max(np.abs(q), initial=0.0))))
    r = np.arange(-R, R + 1, dtype=float)
    xi = q[..., None] / (4.0 * r * r - a[..., None])
    D_prev = np.ones(a.shape)
    D = np.ones(a.shape)
    logs = np.zeros(a.shape)
    for i in range(1, 2 * R + 1):
        D, D_prev = D - xi[..., i] * xi[..., i - 1] * D_prev, D
        m = np.maximum(np.abs(D), np.abs(D_prev))
        big = m > 1e100
        if np.any(big):
            s = np.where(big, m, 1.0)
            D, D_prev = D / s, D_prev / s
            logs = logs + np.log(s)
    # both tails (r > R and r < -R are the same by symmetry)
    R1 = 2 * R
    rt = np.arange(R + 1, R1 + 1, dtype=float)
    x0 = q[..., None] / (4.0 * rt * rt - a[..., None])
    x1 = q[..., None] / (4.0 * (rt - 1.0) ** 2 - a[..., None])
    x2 = q[..., None] / (4.0 * (rt - 2.0) ** 2 - a[..., None])
    tail = -np.sum(x0 * x1 + x0 * x1 * x1 * x2 + 0.5 * (x0 * x1) ** 2, axis=-1)
    # beyond R1 the terms are q^2 / (16 r^2 (r - 1)^2) to 1e-15: their sum is the integral from
    # X = R1 + 1/2 (midpoint rule, error ~ q^2 / (19 R1^6)), which has the closed form
    # 1/(X - 1) + 1/X - 2 log(X / (X - 1))
    X = R1 + 0.5
    tail = tail - q * q / 16.0 * (1.0 / (X - 1.0) + 1.0 / X + 2.0 * np.log1p(-1.0 / X))
    logs = logs + 2.0 * tail
    x = 0.5 * PI * np.sqrt(-a)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        delta0 = D * np.exp(np.minimum(logs, 700.0))
        sh2 = np.sinh(x) ** 2
        if minus_one:
            return 2.0 * delta0 * sh2
        tau = 1.0 + 2.0 * delta0 * sh2
    with np.errstate(divide="ignore", invalid="ignore"):
        log_big = np.log(2.0 * np.abs(D)) + logs + 2.0 * x - 2.0 * np.log(2.0) + 2.0 * np.log1p(-np.exp(-2.0 * x))
        log_tau = np.where(np.isfinite(tau) & (np.abs(tau) < 1e300), np.log(np.abs(tau)), log_big)
        tau = np.where(np.isfinite(tau), tau, np.sign(D) * np.inf)
    return tau, log_tau


def _sine_floquet0(eps, mu):
    """``(tau, log|tau|, growth, theta, zone)`` of the undamped sine drive over the period 2T."""
    from ._exact import acosh_from_log

    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    shape = eps.shape
    e, m = eps.ravel(), mu.ravel()
    q = 16.0 * e * e / PI**2
    a = -2.0 * m * m * q
    tau = np.empty(e.size)
    log_tau = np.empty(e.size)
    for i in range(0, e.size, 2048):  # bounded memory: (points x 4R) temporaries
        tau[i:i + 2048], log_tau[i:i + 2048] = _hill_half_trace(a[i:i + 2048], q[i:i + 2048])
    zone, below = _sine_zone_of(e, m)
    stable = zone >= 0
    growth = np.where(stable, 0.0, acosh_from_log(log_tau, tau))
    acos_t = np.arccos(np.clip(tau, -1.0, 1.0))
    z = np.maximum(zone, 0)
    theta = np.where(stable, np.where(z % 2 == 0, z * PI + acos_t, z * PI + PI - acos_t), below * PI)
    return (tau.reshape(shape), log_tau.reshape(shape), growth.reshape(shape), theta.reshape(shape),
            zone.reshape(shape))


def _family_roots(kind, parity, mu, q_max):
    """All roots ``q <= q_max`` of ``char(q) = -2 mu^2 q`` of one family, per mu: shape ``(rows, K)``,
    ascending, NaN-padded.

    The truncation is :func:`_decay_rows` of ``q_max`` plus a margin: the Fourier coefficients
    of the eigenvectors beyond it are below 1e-18 of the largest, so the roots kept are exact
    to rounding (``tests/test_mathieu.py`` checks them against a doubled truncation and mpmath).
    """
    mu2 = mu * mu
    # a few sizes only (multiples of 8), so that the eigenproblems go in large batches
    N = (8 * np.ceil((_decay_rows(q_max) + 8) / 8.0)).astype(np.int64)
    if np.any(N > 8192):
        bad = int(np.argmax(N > 8192))
        raise _v.KapitzaValueError(f"the sine drive's zones reach beyond q = 1e6 here; got mu={float(mu[bad])!r}")
    K = 0
    found = []
    for Nv in np.unique(N):
        grp = np.flatnonzero(N == Nv)
        ev = np.linalg.eigvalsh(_pencil(kind, parity, mu2[grp], int(Nv)))
        with np.errstate(divide="ignore"):
            qs = np.where(ev < 0, -1.0 / ev, np.inf)  # ascending eigenvalues: q ascending
        qs = np.where(qs <= q_max[grp][:, None], qs, np.nan)
        K = max(K, int(np.max(np.sum(np.isfinite(qs), axis=1), initial=0)))
        found.append((grp, qs))
    res = np.full((mu.size, K), np.nan)
    for grp, qs in found:
        res[grp] = qs[:, :K]
    return res


def _sine_window(mu, q_max):
    """``(rows, zone, q_lo, q_hi)``: every zone of the sine drive whose lower edge lies at
    ``q <= q_max``; an upper edge beyond ``q_max`` is reported as ``inf`` (what lies in the
    window is all a chart or a count of edges below a point needs)."""
    fams = {f: _family_roots(*f, mu, q_max) for f in (("a", 0), ("a", 1), ("b", 0), ("b", 1))}
    rows, zone, q_lo, q_hi = [], [], [], []
    # zone 2k: a_{2k} .. b_{2k+1};  zone 2k + 1: a_{2k+1} .. b_{2k+2}
    for par, upper in ((0, ("b", 1)), (1, ("b", 0))):
        lo_f, hi_f = fams[("a", par)], fams[upper]
        r, k = np.nonzero(np.isfinite(lo_f))
        hi = np.full(r.size, np.inf)
        ok = k < hi_f.shape[1]
        hi[ok] = np.where(np.isfinite(hi_f[r[ok], k[ok]]), hi_f[r[ok], k[ok]], np.inf)
        rows.append(r)
        zone.append(2 * k + par)
        q_lo.append(lo_f[r, k])
        q_hi.append(hi)
    return np.concatenate(rows), np.concatenate(zone), np.concatenate(q_lo), np.concatenate(q_hi)


def _sine_log_tau(eps, mu):
    """``log|tr M / 2|`` of the undamped sine drive over 2T (Hill's determinant only)."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    e, m = eps.ravel(), mu.ravel()
    q = 16.0 * e * e / PI**2
    out = np.empty(e.size)
    for i in range(0, e.size, 2048):
        out[i:i + 2048] = _hill_half_trace(-2.0 * m[i:i + 2048] ** 2 * q[i:i + 2048], q[i:i + 2048])[1]
    return out.reshape(eps.shape)


def _sine_tau_minus_one(eps, mu):
    """``tr M / 2 - 1`` of the undamped sine drive over 2T, free of the cancellation of the 1
    (Hill's determinant; non-finite where it overflows)."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    e, m = eps.ravel(), mu.ravel()
    q = 16.0 * e * e / PI**2
    out = np.empty(e.size)
    for i in range(0, e.size, 2048):
        out[i:i + 2048] = _hill_half_trace(-2.0 * m[i:i + 2048] ** 2 * q[i:i + 2048], q[i:i + 2048], minus_one=True)
    return out.reshape(eps.shape)


def _sine_zone_of(eps, mu):
    """Zone index (-1 off the zones) and the rotation angle / pi off them, from the edges below:
    ``lo_0 < hi_0 < lo_1 < hi_1 < ...``, so an odd count of edges below ``eps`` means zone
    ``(count - 1)/2``, an even count ``2k`` the gap where the angle is locked at ``k pi``."""
    zone = np.full(eps.size, -1, np.int64)
    locked = np.zeros(eps.size)
    ok = np.flatnonzero(mu < 1.0)
    if ok.size == 0:
        return zone, locked
    q = 16.0 * eps[ok] ** 2 / PI**2
    rows, zn, q_lo, q_hi = _sine_window(mu[ok], q)
    count = np.zeros(ok.size, np.int64)
    np.add.at(count, rows, (q_lo < q[rows]).astype(np.int64))
    np.add.at(count, rows, (q_hi < q[rows]).astype(np.int64))
    inside = count % 2 == 1
    zone[ok[inside]] = (count[inside] - 1) // 2
    locked[ok] = np.where(inside, 0.0, count // 2)
    return zone, locked
