"""The sine drive's engine: Mathieu's characteristic values by Sturm counts, its Floquet data and zones.

The public face is :mod:`kapitza.mathieu` (characteristic values, the sine's zone edges) and
:class:`kapitza.SineWave`, whose methods call these (validated input only).

``y'' + (a - 2 q cos 2z) y = 0`` (DLMF 28.2.1). Its periodic solutions exist on the
characteristic curves ``a = a_n(q)`` (even in ``z``) and ``a = b_n(q)`` (odd); with Fourier
series they are the eigenvalues of four symmetric tridiagonal matrices (DLMF 28.4), here
with ``d_r`` on the diagonal and ``q`` beside it:

    a_{2k}:    d = (0, 4, 16, 36, ...),   the first off-diagonal q sqrt(2)   (cos 2rz)
    a_{2k+1}:  d = (1 + q, 9, 25, ...)                                      (cos (2r+1)z)
    b_{2k+1}:  d = (1 - q, 9, 25, ...)                                      (sin (2r+1)z)
    b_{2k+2}:  d = (4, 16, 36, ...)                                         (sin (2r+2)z)

The ``k``-th eigenvalue (ascending) of each is the characteristic value of that order (the
curves of one family do not cross). Each is found by bisection with the Sturm count of the
*infinite* matrix (:func:`_count`: the LDL^T pivots stop where they provably stay positive), so
no truncation is chosen and no eigensolver (nor BLAS) runs. ``scipy.special.mathieu_a/b`` are not
used: they are known to return wrong values and to jump branches (scipy issues 4479, 14526).

**The sine drive.** With ``z = pi t/(2T) - pi/4`` the upright's linearisation under the
acceleration ``A sin(pi t/T)`` is Mathieu's equation with ``q = 16 eps^2/pi^2`` and
``a = -2 mu^2 q`` (``docs/mathieu.md``). Zone ``n`` is ``a_n(q) < a < b_{n+1}(q)`` on that ray,
and along it ``a_0 < b_1 < a_1 < b_2 < ...``: the number of characteristic values below the ray
point is odd (``2n + 1``) on zone ``n`` and even (``2k``) in the gap where the rotation angle is
locked at ``k pi``. Verdicts are that count (four Sturm sequences at the point); edges are the
doubles where it changes, bisected with the same count. Where an edge lies within the rounding
band of the point (:func:`_band`), the exact trace decides (:func:`_exact_tau`).

**Floquet data.** ``tr M / 2 = w_I(pi) = 2 w_I(pi/2) w_II'(pi/2) - 1 = 1 + 2 w_I'(pi/2) w_II(pi/2)``
(DLMF 28.2.(iv); ``w_I``, ``w_II`` the even and odd solutions), by Taylor series over half a
period: in double precision for the reported trace (:func:`_sine_traces`), in fixed-point
integers with as many bits as the growth needs where a verdict must be certified.
"""
from __future__ import annotations

import threading

import numpy as np

from .. import _validate as _v
from .._certify import LONG_DOUBLE, growth_good, small_eps_bits


PI = np.pi


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
                    what=f"dense eigenproblems, order n and |q| set the rows; "
                         f"here n ~ {2 * int(k)}, q = {float(q):.4g}")
    return N


def characteristic(kind, n, q):
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
    """The k-th characteristic value of a family at each ``q >= 0``: bisection on ``x`` with the
    Sturm count of the infinite matrix (:func:`_count`), no eigensolver and no truncation to
    choose; the rows it takes are bounded as those of a truncated matrix would be (:func:`_size`).

    The bracket is Weyl's: the k-th eigenvalue of ``D + q O`` lies within ``||q O|| <= 3 q`` of
    ``D_k``. Bisected to a relative width of 2 ulp (1e-17 absolute near 0)."""
    code = _CODE[(kind, parity)]
    kmax, qmax = int(np.max(k, initial=0)), float(np.max(q, initial=0.0))
    _size(kmax, qmax)  # the same bounds on the work as before: order and |q|
    Dk = (2.0 * k + _OFF[code]) ** 2
    lo = Dk - 3.0 * q - 1.0 - np.abs(_SHIFT[code]) * q
    hi = Dk + 3.0 * q + 1.0 + np.abs(_SHIFT[code]) * q
    live = np.flatnonzero(q > 0)
    while live.size:
        l, h = lo[live], hi[live]
        mid = l + 0.5 * (h - l)
        go = (mid > l) & (mid < h) & (h - l > np.maximum(2.0 * 2.0**-52 * np.maximum(np.abs(l), np.abs(h)), 1e-17))
        live, mid = live[go], mid[go]
        if not live.size:
            break
        up = _count(code, q[live], mid) >= k[live] + 1
        hi[live[up]] = mid[up]
        lo[live[~up]] = mid[~up]
    # q = 0: the diagonal itself (n^2, exactly)
    return np.where(q > 0, 0.5 * (lo + hi), Dk)






# ---------------------------------------------------------------- Sturm counts
#: a pivot of exactly zero in a Sturm sequence is replaced by minus this (LAPACK's pivmin)
_PIVMIN = 1e-290


#: the four families as codes: (kind, parity) -> code; per code the diagonal ``(2r + off)^2``, the
#: multiple of ``q`` added to the first diagonal entry and the square of the first off-diagonal / q
_CODE = {("a", 0): 0, ("a", 1): 1, ("b", 0): 2, ("b", 1): 3}
_OFF = np.array([0.0, 1.0, 2.0, 1.0])
_SHIFT = np.array([0.0, 1.0, 0.0, -1.0])
_FIRST = np.array([2.0, 1.0, 1.0, 1.0])


def _count(fam, q, x):
    """How many characteristic values of family ``fam`` (a code of :data:`_CODE`) lie below ``x`` at
    ``q`` (flat arrays that broadcast, ``q >= 0``).

    The count of negative pivots of ``T(q) - x I = L D L^T`` (Sylvester's law of inertia) with the
    pivots ``d_r = (D_r - x) - e_{r-1}^2 / d_{r-1}``, ``D_r`` the diagonal of the family matrix
    (module notes). No truncation is chosen beforehand: the sequence stops at the row ``r`` where
    ``d_r >= (D_r - x)/2 > 0`` and ``(D_{r+1} - x)(D_r - x) >= 4 q^2``, beyond which every pivot of
    the infinite matrix stays above half its diagonal (by induction: ``d_{r+1} >= D_{r+1} - 2 q^2/D_r
    >= D_{r+1}/2``), so the count is that of the infinite matrix -- about ``sqrt(q/2)`` rows where a
    fixed truncation needs ``2 sqrt(q)``. In floating point the count is exact for a matrix whose
    entries differ from ``T(q)`` by a few ulp (Kahan's backward analysis of the Sturm sequence): a
    characteristic value compares with ``x`` correctly unless they agree to a few ulp of ``|x| + q``.
    All four families go through one loop (one numpy call per row for every point at once).
    """
    fam, q, x = np.asarray(fam), np.asarray(q), np.asarray(x)
    if q.dtype != LONG_DOUBLE:  # (long double stays long double: the second tier of counts)
        q, x = q.astype(float, copy=False), x.astype(float, copy=False)
    if not (fam.shape == q.shape == x.shape and q.ndim == 1):
        fam, q, x = np.broadcast_arrays(fam, q, x)
        fam, q, x = fam.reshape(-1), q.reshape(-1), x.reshape(-1)
    off = _OFF[fam]
    out = np.zeros(q.size, np.int64)
    if not q.size:
        return out
    if q.dtype == np.float64:
        from ..engines.magnus import compiled_sine

        kernels = compiled_sine()
        if kernels is not None:   # (the same pivots, one point at a time)
            return kernels.count(off, _SHIFT[fam], _FIRST[fam], q, x, _PIVMIN)
    q2 = q * q
    d = off * off + _SHIFT[fam] * q - x
    d[d == 0.0] = -_PIVMIN
    cnt = (d < 0.0).astype(np.int64)
    idx = None  # all points live
    e2 = _FIRST[fam] * q2
    r = 1
    # a pivot that comes out exactly zero makes the next one -inf (counted) and the one after
    # positive: the count of a pivot -pivmin, as in LAPACK's dstebz
    with np.errstate(divide="ignore", over="ignore"):
        while True:
            t = off + 2.0 * r
            Dr = t * t - x
            d = Dr - e2 / d
            cnt += d < 0.0
            e2 = q2
            if r % 4 == 0 or r == 2:  # half the points are done after two rows, nearly all after four
                t = t + 2.0
                done = (Dr > 0.0) & (d >= 0.5 * Dr) & ((t * t - x) * Dr >= 4.0 * q2)
                if done.any():
                    where = np.flatnonzero(done) if idx is None else idx[done]
                    out[where] = cnt[done]
                    keep = ~done
                    if not keep.any():
                        break
                    idx = np.flatnonzero(keep) if idx is None else idx[keep]
                    x, d, q2, cnt, off = x[keep], d[keep], q2[keep], cnt[keep], off[keep]
                    e2 = q2
            r += 1
    return out


#: the largest mu of the sine drive's Floquet data (``a = -2 mu^2 q`` and ``mu^2`` stay doubles; far
#: beyond mu_max = 1, where the upright is always unstable)
MU_MAX = 1e150


def _qa(eps, mu, pi=PI):
    """Mathieu's ``(q, a)`` of the sine drive at ``(eps, mu)``: one rounding, shared by every path
    (``pi`` in the arguments' precision: the long-double counts pass their own). ``mu`` beyond
    :data:`MU_MAX` is refused by name."""
    if np.size(mu) and not np.max(mu) <= MU_MAX:
        raise _v.KapitzaValueError(f"mu must satisfy mu <= {MU_MAX:g} for the sine drive's Floquet data "
                                   f"(mu^2 must stay a double); got {float(np.max(mu))!r}")
    q = 16.0 * eps * eps / pi**2
    return q, -2.0 * mu * mu * q


#: the lower edge of zone n lies on a_n, the upper on b_{n+1}: the family code of each by n % 2
_LOWER = {0: 0, 1: 1}
_UPPER = {0: 3, 1: 2}


#: Below this ``q`` the count of ``a_0`` comes from its series ``a_0(q) = -q^2/2 + 7 q^4/128 - 29 q^6/2304 + ...``
#: (DLMF 28.6.1): the ray point ``a = -2 mu^2 q`` lies above it iff
#: ``mu^2 < q/4 (1 - 7 q^2/64 + 29 q^4/1152 - ...)``, i.e. ``pi mu < 2 eps sqrt(1 - 7 q^2/64 + 29 q^4/1152)``,
#: the terms left out below 1e-20 relative. The Sturm pivots resolve ``a - a_0`` only to ``u q`` there, an
#: ``eps`` of ``u/q`` relative about the edge (and lose ``q^2`` to underflow below ``q = 1e-154``): the
#: lower edge of zone 0 in Kapitza's limit ``mu -> 0``. The other values lie near 1 and above.
_Q_SERIES = 1e-3


def _series_q(eps, mu, q, count, zero):
    """``count`` with the points of ``q < _Q_SERIES`` recounted from the series of ``a_0`` (in the
    arguments' precision): ``zero`` (bool) marks the entries that count ``a_0`` (the family of even
    ``a`` at ``k = 0``, or all four families together); elsewhere the values near 1 and above lie above
    the ray point there, and none is counted."""
    small = q < _Q_SERIES
    if not np.any(small):
        return count
    count = np.array(count, copy=True)
    pi = PI if q.dtype == np.float64 else _PI_LD
    with np.errstate(under="ignore"):
        q2 = np.where(small, q, 0.0) ** 2
        above_a0 = (pi * mu < 2 * eps * np.sqrt(1 - q2 * (7 / 64) + q2 * q2 * (29 / 1152))).astype(count.dtype)
    count[small] = np.where(np.broadcast_to(zero, small.shape)[small], above_a0[small], 0)
    return count


def _above(fam, k, eps, mu):
    """Whether the ray point ``(q, a)`` at ``eps`` lies above the k-th characteristic value of ``fam``."""
    q, a = _qa(eps, mu)
    fam, k, eps, mu, q, a = np.broadcast_arrays(fam, k, eps, mu, q, a)
    count = _series_q(eps, mu, q, _count(fam, q, a), (fam == 0) & (k == 0))
    return count >= k + 1


def _crossing(fam, k, mu, lo, hi):
    """The crossing of the ray with the k-th characteristic value of family ``fam``, bisected on
    doubles (flat arrays; every family and zone at once).

    ``lo`` below the crossing, ``hi`` above it; returns the adjacent doubles ``(below, above)``
    between which the count of the family changes.
    """
    fam = np.broadcast_to(np.asarray(fam, np.int64), lo.shape)
    lo, hi = lo.copy(), hi.copy()
    live = np.arange(lo.size)
    while live.size:
        l, h = lo[live], hi[live]
        mid = l + 0.5 * (h - l)
        go = (mid > l) & (mid < h)
        live, mid = live[go], mid[go]
        if not live.size:
            break
        up = _above(fam[live], k[live], mid, mu[live])
        hi[live[up]] = mid[up]
        lo[live[~up]] = mid[~up]
    return lo, hi


def _upper_bound(fam, k, mu):
    """An ``eps`` above the k-th crossing of family ``fam``: ``sqrt(q) (1 - mu^2) ~ 2n + 1``
    (``a_n ~ -2q + 2(2n+1) sqrt q``, DLMF 28.8.1) with room, doubled until the count confirms it."""
    n = 2 * k + np.array([0, 1, 2, 1])[fam]
    e = 0.25 * PI * (2.0 * (2.0 * n + 3.0) / (1.0 - mu * mu) + 2.0)
    for _ in range(60):
        bad = ~_above(fam, k, e, mu)
        if not bad.any():
            break
        e = np.where(bad, 2.0 * e, e)
    return e


def sine_edges(mu, n):
    """``(eps_lo, eps_hi)`` of the sine drive's zone n (trusted ``0 < mu < 1``).

    Each edge is where the ray ``a = -2 mu^2 q`` crosses its characteristic value (``a_n`` below,
    ``b_{n+1}`` above), bisected on doubles with the Sturm count: the reported double is the
    last one on the unstable side (``eps_lo`` below the crossing, ``eps_hi`` above it), so zone
    ``n`` is ``eps_lo < eps < eps_hi``. Where the zone is thinner than the spacing of doubles the
    two crossings may round to the same pair or swap; then ``eps_lo == eps_hi`` (no double inside).
    """
    mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
    shape = mu.shape
    mu, n = mu.ravel(), n.ravel()
    # the crossing lies near sqrt(q) (1 - mu^2) = 2n + 1; the Sturm counts there take sqrt(q/2) rows
    q_est = ((2.0 * n + 1.0) / np.maximum(1.0 - mu * mu, 1e-300)) ** 2 + 4.0 * n * n
    if np.any(q_est > 1e8):
        bad = int(np.argmax(q_est > 1e8))
        raise _v.KapitzaValueError(
            f"mu and n put the sine drive's zone edge beyond q = 1e8 (mu too close to 1 or the zone n too high); "
            f"got mu={float(mu[bad])!r} with n={int(n[bad])}")
    k = np.concatenate([n // 2, n // 2])
    fam = np.concatenate([np.where(n % 2 == 0, _LOWER[0], _LOWER[1]), np.where(n % 2 == 0, _UPPER[0], _UPPER[1])])
    m = np.concatenate([mu, mu])
    below, above = _crossing(fam, k, m, np.zeros(m.size), _upper_bound(fam, k, m))
    lo = below[:mu.size]
    hi = np.maximum(above[mu.size:], lo)
    return lo.reshape(shape), hi.reshape(shape)




# ---------------------------------------------------------------- Floquet data
def sine_floquet0(eps, mu, certify=True, errors=False, loose=False, exact=True):
    """``(tau, log|tau|, growth, theta, zone)`` of the undamped sine drive over the period 2T
    (``errors``: and a sixth item, the bound on the error of ``tau``: :func:`_sine_traces`' running
    bound, a half ulp where the exact trace decided, the long double's bound where it did; without,
    the quick bound alone serves the choices below; ``loose``: the
    verdicts alone are certified, and a seventh item marks the points whose trace is rougher than
    1e-13 (those decided by the long double counts where the double trace has lost its digits, or
    by a long double trace however loose, see :func:`_certify`)); ``exact=False``: no exact trace
    (see :func:`_certify`).

    The verdict and the zone come from the Sturm counts (:func:`_sine_zone_of`); the trace from
    :func:`_sine_traces`. Where an edge lies within the rounding band of the point, or where the
    trace is accurate enough to say ``|tau| < 1`` or ``> 1`` and says otherwise than the count,
    the exact trace decides (:func:`_certify`): no verdict contradicts the monodromy.
    ``certify=False`` (the steps of a search, whose final bracket is certified) keeps the count
    of one side of the band instead.
    """
    from .._exact import acosh_excess, acosh_from_log

    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    shape = eps.shape
    e, m = eps.ravel(), mu.ravel()
    tau, log_tau, tau_m1, err = _sine_traces(e, m, "running" if errors else "quick")
    fresh = np.ones(e.size, bool)   # (the points whose tau - 1 is still the double trace's)
    c_lo, c_hi, unsure = _sine_zone_of(e, m)
    count = c_lo.copy()
    with np.errstate(invalid="ignore"):
        says = np.abs(np.abs(tau) - 1.0) > err  # the double trace decides |tau| vs 1 by itself
    mismatch = says & ((np.abs(tau) < 1.0) != (count % 2 == 1))
    with np.errstate(invalid="ignore"):
        accurate = err <= 1e-6 * np.maximum(np.abs(tau), 1.0)
    rough = np.zeros(e.size, bool)
    if certify and LONG_DOUBLE is not None and np.any(unsure & ~mismatch & (accurate | loose)):
        # an edge within the double band: the counts again in long double, in a band 2,048 times
        # narrower; where they agree they decide, and the trace (accurate to err, which spans 1
        # there) is put on the verdict's side of +-1; the rest, and every point whose double trace
        # has lost its digits (beside the thin zones), goes to the exact trace -- unless ``loose``:
        # then the counts decide those too, and their trace is marked rough
        rows = np.flatnonzero(unsure & ~mismatch & (accurate | loose))
        l_lo, l_hi = _counts_ld(e[rows], m[rows])
        ok = l_lo == l_hi
        rows, c = rows[ok], l_lo[ok]
        rough[rows] = ~accurate[rows]
        count[rows] = c
        st = c % 2 == 1
        t = tau[rows]
        sgn = np.where(t < 0, -1.0, 1.0)
        t = np.where(st & (np.abs(t) >= 1.0), sgn * np.nextafter(1.0, 0.0),
                     np.where(~st & (np.abs(t) <= 1.0), sgn * np.nextafter(1.0, 2.0), t))
        log_tau[rows] = np.where(t == tau[rows], log_tau[rows], np.log(np.abs(t)))
        fresh[rows] &= t == tau[rows]
        tau[rows] = t
        unsure[rows] = False
    unsure |= mismatch
    idx = np.flatnonzero(unsure) if certify else np.zeros(0, np.int64)
    err = np.array(err, float, copy=True)
    err[rough] = np.inf
    if idx.size:
        tau[idx], log_tau[idx], count[idx], err[idx] = _certify(e[idx], m[idx], c_lo[idx], c_hi[idx], loose, exact)
        rough[idx] = ~(err[idx] <= 1e-13 * np.abs(tau[idx]))
        fresh[idx] = False
    stable = count % 2 == 1
    zone = np.where(stable, (count - 1) // 2, -1)
    growth = np.where(stable, 0.0, acosh_from_log(log_tau, tau))
    # just past tau = +1 (below zone 0 at small q, or mu > 1 where the whole period repels) the growth
    # acosh(1 + x) from tau - 1 itself: tau rounds to 1 there (x of 1e-17 gave a growth of 0)
    with np.errstate(invalid="ignore"):
        near = fresh & ~stable & (tau_m1 > 0.0) & (tau_m1 < 0.5)
    if near.any():
        growth[near] = acosh_excess(tau_m1[near])
    # where q is negligible (below 1e-30) the half period is cosh(pi sqrt(-a)) to O(q), and the growth
    # pi sqrt(2 mu^2 q - q^2/2) = sqrt(32) eps sqrt(mu^2 - s^2), s = sqrt(q)/2 = 2 eps/pi; formed from
    # eps and mu where q is below the normal doubles (eps under 1e-154: q may be subnormal or 0) or
    # tau - 1 is (eps mu under 1e-154)
    with np.errstate(invalid="ignore", under="ignore"):
        q = _qa(e, m)[0]
        tiny = ~stable & (q < 1e-30) & ((q < 1e-300) | ~(tau_m1 >= 1e-290))
    if tiny.any():
        et, mt = e[tiny], m[tiny]
        s_ = 2.0 * et / PI
        growth[tiny] = np.sqrt(32.0) * et * np.sqrt(np.maximum(mt - s_, 0.0)) * np.sqrt(mt + s_)
    acos_t = np.arccos(np.clip(tau, -1.0, 1.0))
    z = np.maximum(zone, 0)
    theta = np.where(stable, np.where(z % 2 == 0, z * PI + acos_t, z * PI + PI - acos_t), (count // 2) * PI)
    out = (tau.reshape(shape), log_tau.reshape(shape), growth.reshape(shape), theta.reshape(shape),
           zone.reshape(shape))
    if errors:
        out += (err.reshape(shape),)
    if loose:
        out += (rough.reshape(shape),)
    return out


def sine_verdict0(eps, mu):
    """The undamped verdicts alone (stable where true) for the edges' sides: :func:`sine_floquet0`'s
    with ``loose`` (beside the thin zones the long double counts decide where the double trace has
    lost its digits) and the exact trace only where it is cheap (products growing by at most
    2^160, three precisions): beside a zone thinner than the long double's band (1/16 ulp and less)
    at larger ``q`` the count may stand uncertified, where the exact trace would take tens of
    seconds a double. Beyond the trace's reach (``eps > EPS_TRACE``, where the edges still are)
    the counts alone, in long double where an edge lies within the double band."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    e, m = eps.ravel(), mu.ravel()
    out = np.zeros(e.size, bool)
    near = e <= EPS_TRACE
    if near.any():
        out[near] = sine_floquet0(e[near], m[near], True, loose=True, exact=False)[4] >= 0
    far = np.flatnonzero(~near)
    if far.size:
        c_lo, _, unsure = _sine_zone_of(e[far], m[far])
        if LONG_DOUBLE is not None and unsure.any():
            u = np.flatnonzero(unsure)
            c_lo[u] = _counts_ld(e[far[u]], m[far[u]])[0]
        out[far] = c_lo % 2 == 1
    return out.reshape(eps.shape)


#: The points a call of :func:`sine_signs0` may settle with the exact trace, and the growth of its
#: products they may reach (``2^600``: half a second a point at ``q ~ 2,500``; beyond, each takes seconds)
_SIGNS_EXACT = 4
_SIGNS_EXACT_BITS = 600


def sine_signs0(eps, mu):
    """``(stable, sign, decided)`` from the Sturm counts (flat arrays): a count ``2k`` is the gap
    ``theta = k pi``, where ``tr M`` has the sign ``(-1)^k``; an odd count a zone. Where an edge lies
    within the double band the long double counts decide; where they too differ (a double within
    their band of a zone thinner than it), the exact trace, for at most :data:`_SIGNS_EXACT` points,
    three precisions each, products growing by at most ``2^_SIGNS_EXACT_BITS``; the rest is left
    undecided."""
    eps, mu = np.asarray(eps, float).ravel(), np.asarray(mu, float).ravel()
    count, c_hi, unsure = _sine_zone_of(eps, mu)
    decided = ~unsure
    if LONG_DOUBLE is not None and unsure.any():
        u = np.flatnonzero(unsure)
        l_lo, l_hi = _counts_ld(eps[u], mu[u])
        count[u] = l_lo
        decided[u] = l_lo == l_hi
    stable = count % 2 == 1
    sign = np.where(stable, 0.0, np.where((count // 2) % 2 == 0, 1.0, -1.0))
    rest = np.flatnonzero(~decided)
    if 0 < rest.size <= _SIGNS_EXACT:
        for i in rest.tolist():
            if _growth_bits(eps[i], mu[i]) > _SIGNS_EXACT_BITS:
                continue
            r = _exact_tau(float(eps[i]), float(mu[i]), rounds=3)
            if r is not None:
                stable[i], sign[i], decided[i] = r[2], 0.0 if r[2] else np.sign(r[0]), True
    return stable, sign, decided


def sine_log_tau(eps, mu):
    """``log|tr M / 2|`` of the undamped sine drive over 2T."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    return _sine_traces(eps.ravel(), mu.ravel(), bound=None)[1].reshape(eps.shape)


def sine_tau_minus_one(eps, mu):
    """``tr M / 2 - 1`` of the undamped sine drive over 2T, free of the cancellation of the 1
    (non-finite where it overflows), for the short phases where the damping layer asks for it
    (``tr M / 2`` near 1): Hill's determinant, ``2 Delta(0) sinh^2(pi sqrt(-a)/2)``, keeps its
    relative accuracy there, where the half-period integration's ``w_I'(pi/2)`` is a sum of terms
    of size ``q`` cancelling to ``pi mu^2 q``."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    e, m = eps.ravel(), mu.ravel()
    q = 16.0 * e * e / PI**2
    out = np.empty(e.size)
    # below q = 1e-30: pi^2 q (mu^2 - q/4), to O(q) relative (the continuant 1 - q/(4 mu^2), the sinh^2
    # pi^2 mu^2 q / 2); Hill's xi_0 = q / (2 mu^2 q) there is 0/0 once q underflows
    tiny = q < _Q_TINY_HILL
    out[tiny] = PI**2 * q[tiny] * (m[tiny] * m[tiny] - 0.25 * q[tiny])
    # a = -2 mu^2 q below the doubles' range (mu tiny against eps: deep in zone 0, tau - 1 of order q
    # or q^2, not near the cancellation Hill's form avoids): the integrated half period's
    flat = ~tiny & ~(2.0 * m * m * q > 1e-280)
    if flat.any():
        out[flat] = _sine_traces(e[flat], m[flat], bound=None)[2]
    rest = np.flatnonzero(~tiny & ~flat)
    for i in range(0, rest.size, 2048):
        j = rest[i:i + 2048]
        out[j] = _hill_half_trace(-2.0 * m[j] ** 2 * q[j], q[j], minus_one=True)
    return out.reshape(eps.shape)


#: Below this ``q`` :func:`sine_tau_minus_one` takes the leading terms of Hill's determinant
_Q_TINY_HILL = 1e-30


def _continuant(p):
    """``(D, log_scale)`` with ``D e^log_scale`` the last term of ``D_i = D_{i-1} - p_i D_{i-2}``
    (``D_0 = D_{-1} = 1``; ``p`` of shape ``(..., N)``): the product of the steps' 2x2 matrices
    ``[[1, -p_i], [1, 0]]`` taken pairwise (log2 N rounds of products of all pairs at once, each
    renormalised by its largest entry), not N rounds of the recurrence. (Each round's products,
    sums and scaling are formed in place: half the temporaries of the plain expressions, the same
    roundings.)"""
    from ..engines.magnus import compiled_sine

    kernels = compiled_sine()
    if kernels is not None:   # (the same products, one row at a time)
        return kernels.continuant(p)
    n = p.shape[-1]
    size = p.shape[:-1] + (1 << max(n - 1, 0).bit_length(),)   # identities fill up to a power of two
    a, b, c, d = np.ones(size), np.zeros(size), np.zeros(size), np.ones(size)
    b[..., :n] = -p
    c[..., :n] = 1.0
    d[..., :n] = 0.0
    logs = None
    while a.shape[-1] > 1:
        # later step (odd index) times earlier (even index)
        a0, b0, c0, d0 = a[..., 0::2], b[..., 0::2], c[..., 0::2], d[..., 0::2]
        a1, b1, c1, d1 = a[..., 1::2], b[..., 1::2], c[..., 1::2], d[..., 1::2]
        a = a1 * a0
        a += b1 * c0
        b = a1 * b0
        b += b1 * d0
        c = c1 * a0
        c += d1 * c0
        d = c1 * b0
        d += d1 * d0
        scale = np.abs(a)
        np.maximum(scale, np.abs(b), out=scale)
        np.maximum(scale, np.abs(c), out=scale)
        np.maximum(scale, np.abs(d), out=scale)
        scale[~(scale > 0)] = 1.0
        a /= scale
        b /= scale
        c /= scale
        d /= scale
        log_scale = np.log(scale)
        logs = log_scale if logs is None else logs[..., 0::2] + logs[..., 1::2] + log_scale
    return a[..., 0] + b[..., 0], logs[..., 0]


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
    D, logs = _continuant(xi[..., 1:] * xi[..., :-1])
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




def sine_window(mu, e1):
    """``(rows, zone, eps_lo, eps_hi)``: every zone of the sine drive whose lower edge lies at
    ``eps <= e1``, per ``mu`` (flat; ``e1`` broadcasts with it); an upper edge beyond ``e1`` is
    reported as ``inf`` (what lies in the window is all a chart needs).

    The Sturm count at ``e1`` says how many crossings of each family lie below it; each is
    bisected on doubles as in :func:`sine_edges`, all of a chart's rows at once.
    """
    mu = np.asarray(mu, float).reshape(-1)
    e1 = np.broadcast_to(np.asarray(e1, float), mu.shape).reshape(-1)
    q1, a1 = _qa(e1, mu)
    # crossings of each family below e1, then all of them bisected together
    K = _count(np.arange(4)[:, None], q1[None, :], a1[None, :]).reshape(4, mu.size)
    Kf = K.reshape(-1)
    r = np.repeat(np.tile(np.arange(mu.size), 4), Kf)
    fam = np.repeat(np.repeat(np.arange(4), mu.size), Kf)
    k = np.arange(r.size) - np.repeat(np.cumsum(Kf) - Kf, Kf)
    below, above = _crossing(fam, k, mu[r], np.zeros(r.size), e1[r])
    first = np.cumsum(Kf) - Kf  # where the crossings of (family, row) start
    rows, zone, lo, hi = [], [], [], []
    for par in (0, 1):
        sel = fam == _LOWER[par]
        rl, kl = r[sel], k[sel]
        fu = _UPPER[par]
        has = kl < K[fu, rl]
        up = np.full(rl.size, np.inf)
        up[has] = above[first[fu * mu.size + rl[has]] + kl[has]]
        rows.append(rl)
        zone.append(2 * kl + par)
        lo.append(below[sel])
        hi.append(np.maximum(up, below[sel]))
    return np.concatenate(rows), np.concatenate(zone), np.concatenate(lo), np.concatenate(hi)


def _band(mu, eps=None, u=2.0**-53):
    """Relative half-width around an edge inside which a Sturm count may be decided by rounding:
    the crossing moves by about ``2u / (1 - mu^2)`` relative for an error of ``u (|a| + q)`` in a
    characteristic value (``d(a_n + 2 mu^2 q)/dq -> -2 (1 - mu^2)`` at large ``q``), and by about
    ``u / q`` at the lower edge of zone 0 for small ``q`` (there ``a - a_0`` is of order ``q^2``, where
    the count is not replaced by the series, :data:`_Q_SERIES`); eight times those (``eps`` given:
    with the second term). ``u``: the unit roundoff of the counts."""
    mu = np.asarray(mu)
    with np.errstate(divide="ignore"):
        d = 64 * u + 16 * u / np.maximum(1 - mu * mu, 1e-300) * (mu < 1)
        if eps is not None:
            q = 16 * np.asarray(eps) ** 2 / PI**2
            d = d + 16 * u / np.maximum(q, _Q_SERIES) * ((q >= _Q_SERIES) & (q < 2))
    return d


def _total_count(eps, mu):
    """Characteristic values of all four families below the ray point at ``eps`` (flat arrays)."""
    q, a = _qa(eps, mu)
    count = _count(np.arange(4)[:, None], q[None, :], a[None, :]).reshape(4, -1).sum(axis=0)
    return _series_q(eps, mu, q, count, True)


_PI_LD = np.longdouble("3.141592653589793238462643383279502884") if LONG_DOUBLE is not None else None


def _counts_ld(eps, mu):
    """``(c_lo, c_hi)``: :func:`_total_count` at ``eps (1 -+ delta)`` in long double (flat arrays),
    ``q`` and ``a`` formed there from the exact doubles, ``delta`` the band of :func:`_band` for the
    long double's unit roundoff (``2^-64``): 2,048 times narrower than the double one."""
    u = np.finfo(LONG_DOUBLE).eps / 2
    e, m = eps.astype(LONG_DOUBLE), mu.astype(LONG_DOUBLE)
    d = _band(m, e, u).astype(LONG_DOUBLE)
    out = []
    for x in (e * (1 - d), e * (1 + d)):
        q, a = _qa(x, m, _PI_LD)
        count = _count(np.arange(4)[:, None], q[None, :], a[None, :]).reshape(4, -1).sum(axis=0)
        out.append(_series_q(x, m, q, count, True))
    return out


def _sine_zone_of(eps, mu):
    """``(count, unsure)`` per point (flat arrays): ``count`` characteristic values lie below the ray
    point -- ``a_0 < b_1 < a_1 < b_2 < ...`` along it, so an odd count ``2n + 1`` is zone ``n``
    (``a_n < a < b_{n+1}``) and an even count ``2k`` the gap where the rotation angle is locked at
    ``k pi`` -- taken at ``eps (1 -+ delta)`` (:func:`_band`); ``unsure`` where the two differ, i.e.
    an edge within ``delta`` of ``eps``, where rounding may decide and the verdict is certified."""
    d = _band(mu, eps)
    c_lo = _total_count(eps * (1.0 - d), mu)
    c_hi = _total_count(eps * (1.0 + d), mu)
    return c_lo, c_hi, c_lo != c_hi


# ---------------------------------------------------------------- certified trace (exact arithmetic)
def _fixed(x, P):
    """``x`` (an mpf or a double) times ``2^P``, rounded to an integer."""
    import mpmath

    with mpmath.workprec(P + 24):
        return int(mpmath.nint(mpmath.ldexp(mpmath.mpf(x), P)))  # (times 2^P exactly, no power formed)


#: ``(h, h^2, h, trig, t, fixed t)`` per ``(steps, P)`` (:func:`_step_constants`): a search's final
#: pairs and their neighbours share them
_STEP_CONSTANTS: dict = {}
_STEP_LOCK = threading.Lock()


def _step_constants(steps, P):
    """What the exact half-period's Taylor steps share at ``steps`` steps and ``P`` bits, whatever
    ``eps`` and ``mu``: ``h = (pi/2)/steps`` (an mpf at ``P + 40`` bits), ``h^2`` and ``h`` over
    ``2^P``, the ``(cos 2jh, sin 2jh)`` of each step's start over ``2^P``, and the lists ``t_j =
    (2h)^j / j!`` (mpf) and ``t_j`` over ``2^P``, extended on demand by :func:`_exact_half_period`.
    Kept, so that the points of one search pay the extended-precision trigonometry once."""
    import mpmath

    key = (steps, P)
    c = _STEP_CONSTANTS.get(key)
    if c is None:
        with mpmath.workprec(P + 40):
            h = mpmath.pi / 2 / steps
            trig = [(_fixed(mpmath.cos(2 * j * h), P), _fixed(mpmath.sin(2 * j * h), P)) for j in range(steps)]
            one = mpmath.mpf(1)
            c = (h, _fixed(h * h, P), _fixed(h, P), trig, [one], [_fixed(one, P)])
        if len(_STEP_CONSTANTS) >= 256:
            _STEP_CONSTANTS.clear()
        _STEP_CONSTANTS[key] = c
    return c


def _exact_half_period(eps, mu, P, zeta=0.0):
    """``(w_I, w_I', w_II, w_II')`` at ``z = pi/2`` as integers over ``2^P`` for the exact doubles
    ``eps, mu``: Mathieu's ``y'' = 2q (mu^2 + cos 2z) y`` with ``q = 16 eps^2/pi^2`` from ``y(0) = 1,
    y'(0) = 0`` (even, ``w_I``) and ``y(0) = 0, y'(0) = 1`` (odd, ``w_II``), by Taylor series in
    fixed-point integer arithmetic (each step ``h`` with ``h sqrt(max c) <= 1``; terms to ``2^-P``).
    ``zeta``: the damped system's ``phi``-equation, ``mu^2`` raised to ``mu^2 (1 + zeta^2)`` exactly."""
    import math

    import mpmath

    from .._certify import taylor_step

    one = 1 << P
    with mpmath.workprec(P + 40):
        e, m = mpmath.mpf(float(eps)), mpmath.mpf(float(mu))
        m2 = m * m * (1 + mpmath.mpf(float(zeta)) ** 2)
        q = 16 * e * e / mpmath.pi**2
        L = math.sqrt(2.0 * float(q) * (1.0 + float(m2))) + 2.0
        steps = max(1, math.ceil(0.5 * math.pi * L))
        h, hh, hf, trig, ts, fx = _step_constants(steps, P)
        twoq, c0 = _fixed(2 * q, P), _fixed(2 * q * m2, P)
        # 2q (2h)^j / j!: the scaled Taylor coefficients of 2q cos(2 z0 + 2 s) without the trig factor
        scale, j = [], 0
        tiny = mpmath.mpf(2) ** (-P - 8)
        while True:
            scale.append(twoq * fx[j] >> P)
            j += 1
            if j == len(fx):
                with _STEP_LOCK:  # (the lists are shared: one thread extends them at a time)
                    while len(fx) <= j:
                        ts.append(ts[len(fx) - 1] * 2 * h / len(fx))
                        fx.append(_fixed(ts[len(fx)], P))
            if j > 4 and ts[j] * 2 * q < tiny:
                break
    K = len(scale)
    cols = [[one, 0], [0, one]]
    for cj, sj in trig:
        # c(z0 + s) = 2q mu^2 + 2q cos(2 z0 + 2 s): derivatives of cos cycle through -sin, -cos, sin, cos
        C = [c0 + (scale[0] * cj >> P)]
        for k in range(1, K):
            r = k % 4
            C.append((scale[k] * (sj if r % 2 else cj) >> P) * (1 if r in (0, 3) else -1))
        taylor_step(cols, C, hf, hh, P)
    return cols[0][0], cols[0][1], cols[1][0], cols[1][1]


def _growth_bits(eps, mu):
    """Bits by which the half period's products may grow, ``2 G / log 2`` with ``G = (pi/2)
    sqrt(2q (1 + mu^2))`` (scalars)."""
    import math

    q = 16.0 * float(eps) ** 2 / math.pi**2
    return int(math.pi * math.sqrt(2.0 * q * (1.0 + float(mu) ** 2)) / math.log(2.0)) + 1


def _exact_tau(eps, mu, rounds=8):
    """``(tau, log|tau|, stable)`` of the sine drive at the exact doubles ``eps, mu`` (scalars);
    ``rounds`` below 8: None where the precision's first ``rounds`` settings leave ``|tau| - 1``
    unresolved (a point within a sliver of a thin zone at large ``q``, where the next take seconds).

    ``tau = tr M / 2 = w_I(pi) = 2 w_I(pi/2) w_II'(pi/2) - 1`` (DLMF 28.2.(iv): the equation is even
    in ``z``) from :func:`_exact_half_period`, with ``P`` bits beyond the growth ``exp(2 G)``
    of the products (``G = (pi/2) sqrt(2q (1 + mu^2))`` bounds the growth over the half period),
    doubled until ``|tau| - 1`` is resolved."""
    import math

    import mpmath

    growth = _growth_bits(eps, mu)
    small = small_eps_bits(eps, 16.0 / PI**2)   # (q = 16 eps^2 / pi^2)
    P = 96 + growth + small
    cap = 1500 + small
    for r in range(8):
        wI, dwI, wII, dwII = _exact_half_period(eps, mu, P)
        num = 2 * wI * dwII - (1 << 2 * P)  # tau * 2^(2P)
        gap = abs(abs(num) - (1 << 2 * P))  # | |tau| - 1 | * 2^(2P)
        # each truncation costs at most 2^-P; a few thousand of them per step (steps x terms^2), grown
        # by at most e^(2G) in the products: tau is known to 2^-(P - growth - 32), num to 2^(P + growth + 32)
        if gap > (1 << (P + growth + 32)) or P > cap:  # beyond 2^-3000 (more at small q) the count decides
            break
        if r + 1 >= rounds:
            return None
        P *= 2
    with mpmath.workprec(64):
        tau = mpmath.mpf(num) / mpmath.mpf(2) ** (2 * P)
        log_tau = float(mpmath.log(abs(tau))) if num else -math.inf
    return float(tau), log_tau, abs(num) < (1 << 2 * P)


#: the damped verdicts decided so far, by their exact doubles ``(eps, mu, zeta)``
_DAMPED_EXACT: dict = {}


def sine_damped_exact(eps, mu, zeta, growth=True):
    """``[(stable, growth)]`` of the damped sine drive at the exact doubles (flat arrays): stable iff
    ``|tr M_phi| / 2 < cosh(kappa)`` (``M_phi`` at ``mu^2 (1 + zeta^2)``, ``kappa = 2 sqrt 8 zeta mu
    eps``), from the long double tier (:func:`sine_ld`) where it decides, else from the fixed-point
    trace of :func:`_exact_half_period`, its precision doubled until the difference is resolved beyond
    the trace's error bound (to 3,000 bits). ``growth``: the growth is to be good to 1e-12 (reported);
    without, only the verdict need be exact, and a long double growth stands (as good as its trace)."""
    import math

    import mpmath

    out = []
    eps, mu, zeta = (np.asarray(v, float).ravel() for v in (eps, mu, zeta))
    keys = list(zip(eps.tolist(), mu.tolist(), zeta.tolist()))

    def known(key):   # (a search asks its final pair again, and the report its edges)
        hit = _DAMPED_EXACT.get(key)
        return None if hit is None or (growth and not hit[2]) else hit[:2]

    todo = np.array([known(k) is None for k in keys], bool)
    if _ld_pays(eps[todo], mu[todo]):   # the long double tier first; mpmath where it cannot decide
        dec, st, tau, log_tau, gr, err = sine_ld(eps[todo], mu[todo], zeta[todo])
        good = growth_good(tau, err, gr, log_tau=log_tau)
        for key, d, s_, g, ok in zip((k for k, t in zip(keys, todo) if t), dec, st, gr, good):
            if d and (ok or not growth):
                _remember(key, (bool(s_), float(g), bool(ok)))
    for key in keys:
        hit = known(key)
        if hit is not None:
            out.append(hit)
            continue
        e, m, z = key
        growth_bits = _growth_bits(e, m * math.sqrt(1.0 + z * z))   # (the phi-system's mu_c)
        small = small_eps_bits(e, 16.0 / PI**2)
        P = 96 + growth_bits + small
        cap = 1500 + small
        for _ in range(8):
            wI, dwI, wII, dwII = _exact_half_period(e, m, P, z)
            num = 2 * wI * dwII - (1 << 2 * P)  # tau_phi * 2^(2P)
            with mpmath.workprec(2 * P + 64):
                t = mpmath.mpf(num) / mpmath.mpf(2) ** (2 * P)
                kappa = 2 * mpmath.sqrt(8) * mpmath.mpf(z) * mpmath.mpf(m) * mpmath.mpf(e)
                ck = mpmath.cosh(kappa)
                diff = abs(t) - ck
                err = mpmath.mpf(2) ** (-(P - growth_bits - 32))
                if abs(diff) > err or P > cap:
                    break
            P *= 2
        with mpmath.workprec(2 * P + 64):
            g = (mpmath.acosh(abs(t)) if abs(t) > 1 else mpmath.mpf(0)) - kappa
            out.append((bool(diff < 0), float(g)))
        _remember(key, out[-1] + (True,))
    return out


def _remember(key, value):
    if len(_DAMPED_EXACT) >= 4096:
        _DAMPED_EXACT.clear()
    _DAMPED_EXACT[key] = value


def _certify(eps, mu, c_lo, c_hi, loose=False, exact=True):
    """``(tau, log|tau|, count, err)`` at points where rounding may decide (flat arrays): the exact
    trace decides; the count is the one in ``[c_lo, c_hi]`` it allows -- odd if ``|tau| < 1``, else
    even with the sign of ``tau`` that of the locked angle ``(count/2) pi``; ``err`` bounds the error
    of ``tau``. ``loose``: a long double trace that decides the verdict is kept however loose its
    bound (the damping layer's ``phi``-system, which settles the damped verdict itself where that
    bound could decide it); otherwise only one good to 1e-13, which is reported. ``exact=False``:
    where the long double cannot decide and the exact trace is dear (growth beyond 2^160) or not
    resolved at its first three precisions, the count ``c_lo`` stands uncertified (``err`` inf,
    ``tau`` NaN) instead of an exact trace of thousands of bits."""
    tau = np.empty(eps.size)
    log_tau = np.empty(eps.size)
    count = np.empty(eps.size, np.int64)
    err = np.empty(eps.size)
    # the long double tier first (for a few points or more), mpmath where it cannot decide
    ld = sine_ld(eps, mu) if (not exact or _ld_pays(eps, mu)) else None
    for i in range(eps.size):
        if ld is not None and ld[0][i] and (loose or ld[5][i] <= 1e-13 * abs(ld[2][i])):
            t, lt, stable = ld[2][i], ld[3][i], bool(ld[1][i])
            err[i] = ld[5][i]
        else:
            # (without ``exact``: only where the products grow by at most 2^160, q of a few hundred,
            # and at three precisions at most -- beyond, one exact trace takes seconds to minutes --
            # or at all five where they grow by at most 2^16: a step or two at small q, where |tau| - 1
            # is of order q^2 and the first three may not resolve it)
            bits = _growth_bits(eps[i], mu[i])
            r = _exact_tau(eps[i], mu[i], 8) if exact or bits <= 16 else (
                _exact_tau(eps[i], mu[i], 3) if bits <= 160 else None)
            if r is None:
                tau[i], log_tau[i], count[i], err[i] = np.nan, np.nan, c_lo[i], np.inf
                continue
            t, lt, stable = r
            err[i] = 0.5 * np.finfo(float).eps * abs(t)
        tau[i], log_tau[i] = t, lt
        lo, hi = int(min(c_lo[i], c_hi[i])), int(max(c_lo[i], c_hi[i]))
        if stable:
            cands = [c for c in range(lo - 1, hi + 2) if c % 2 == 1 and c >= 1]
        else:
            cands = [c for c in range(lo - 2, hi + 3) if c % 2 == 0 and c >= 0 and (-1) ** (c // 2) == np.sign(t)]
        # the candidate nearest the counts either side (several only if edges crowd within the band)
        count[i] = min(cands, key=lambda c: (max(lo - c, c - hi, 0), abs(2 * c - lo - hi)))
    return tau, log_tau, count, err


# ---------------------------------------------------------------- the trace in double precision
_TERMS = 22  # Taylor terms per step: h sqrt(max c) <= 1 and 2h <= 1 leave 1/22! ~ 1e-21


def _half_period(eps, mu, bound="running"):
    """``(w_I, w_I', w_II, w_II', s, E, ds)`` at ``z = pi/2`` (see :func:`_exact_half_period`) in
    double precision for flat arrays, the four values times ``exp(s)``; ``E`` bounds the error of
    either product ``w_I w_II'`` or ``w_I' w_II`` at the scale ``exp(2 s)``, ``ds`` that of ``s``.
    ``bound``: ``"running"`` (below), ``"quick"`` (the largest state's rounding only, at no cost:
    close where the solutions stay small, pessimistic by as much as the products' size where
    they grow), None (``E`` NaN).

    Taylor series of ``_TERMS`` terms over steps with ``h sqrt(2q (1 + mu^2)) <= 1``; the state is
    rescaled after every step (``s`` keeps the scale), so it never overflows. Each step is an
    accurate map of the true step (the series is truncated far below rounding), so the result
    carries the rounding of the steps' maps and of their products. ``E`` comes from the first-order
    running bound of that rounding, ``sum_j |Q_j| d_j``: ``d_j = _STEP_ROUNDING |M_j| |P_(j-1)|`` (a
    few hundred units of the map ``M_j`` and of its product with the steps before, ``P_(j-1)``),
    carried to the end by the norm of the steps after, ``Q_j`` (computed by a second, backward
    product of the maps); the norms are Frobenius norms in the balanced basis ``(y, y' / w)``,
    ``w = sqrt(2q (1 + mu^2))`` the largest ``sqrt|c|``, where the steps are near rotations and
    hyperbolic turns of size one. Where the solutions grow (off the zones) that is some thousand
    units of the result;
    deep in the thin zones of large ``q``, where they grow and fall back, the largest state's
    rounding survives, amplified by ``|Q_j| |P_(j-1)| / |P|`` (the cancellation the exact trace
    then recomputes).
    """
    eps = np.asarray(eps, float).reshape(-1)
    mu = np.asarray(mu, float).reshape(-1)
    q, _ = _qa(eps, mu)
    L = np.sqrt(2.0 * q * (1.0 + mu * mu)) + 2.0
    # steps rounded up to powers of two (multiples of 64 beyond): a few batches, each with the
    # step of its largest q
    steps = np.maximum(np.ceil(0.5 * PI * L), 8.0)
    steps = np.where(steps <= 64.0, 2.0 ** np.ceil(np.log2(steps)), 64.0 * np.ceil(steps / 64.0)).astype(np.int64)
    out = np.full((7, eps.size), np.nan)
    fact = np.cumprod(np.concatenate([[1.0], np.arange(1.0, _TERMS + 2)]))
    sign = np.array([1.0, -1.0, -1.0, 1.0])  # d^k/ds^k cos(x + s): cos, -sin, -cos, sin
    for m in sorted(set(steps.tolist())):  # (np.unique would load numpy.ma: 15 ms of a first call)
        group = np.flatnonzero(steps == m)
        # (with the bound, every step's map is kept for the backward product: points in batches)
        per = max(1, _MAPS_KEPT // m) if bound == "running" else group.size
        for c0 in range(0, group.size, per):
            sel = group[c0:c0 + per]
            out[:, sel] = _half_period_steps(q[sel], mu[sel], m, fact, sign, bound)
    return out


#: Points times steps whose maps the error bound of :func:`_half_period` keeps at once
_MAPS_KEPT = 1 << 18

#: The rounding of one step of :func:`_half_period`, relative to ``|M_j| |P_(j-1)|`` (Frobenius
#: norms in the balanced basis): the map's Taylor sums (22 terms of about ``k + 8`` units each, their
#: coefficients' rounding; the majorant of the terms is ``cosh 1`` at the step's ``h sqrt|c| <= 1``),
#: the state's product and rescaling; 256 units, about twice what they add up to
_STEP_ROUNDING = 2.0**-45


def _half_period_steps(qq, mm, m, fact, sign, bound):
    """:func:`_half_period` of points that take ``m`` steps."""
    h = 0.5 * PI / m
    b = qq.size
    y = np.zeros((b, 2))
    dy = np.zeros((b, 2))
    y[:, 0] = 1.0
    dy[:, 1] = 1.0
    kk = np.arange(_TERMS)
    # 2q (2h)^k / k! (the scaled coefficients without their trig factor)
    scale = 2.0 * qq[None, :] * ((2.0 * h) ** kk / fact[:_TERMS])[:, None]
    logs_big = np.empty((m, b))     # log of each step's rescaling (s is their sum)
    running = bound == "running"
    if running:   # the state before each step, and the maps
        states, kept = np.empty((m, 2, b, 2)), []
    from ..engines.magnus import compiled_sine

    kernels = None if running else compiled_sine()
    if kernels is not None:   # (the same steps, one point at a time)
        y, dy, logs_big = kernels.half_period_steps(qq, mm, m, scale, sign, h)
    else:
        # the steps' 2x2 maps (y, y') -> (y, y'), all steps of a block at once (their series do not
        # depend on the state), then applied in order
        block = max(1, 16384 // b)
        t_all = 0
        for j0 in range(0, m, block):
            jj = np.arange(j0, min(j0 + block, m))
            cj, sj = np.cos(2.0 * jj * h), np.sin(2.0 * jj * h)
            trig = np.where((kk % 2 == 0)[:, None], cj[None, :], sj[None, :]) * sign[kk % 4][:, None]
            C = scale[:, None, :] * trig[:, :, None]           # (terms, steps, points)
            C[0] += 2.0 * qq * mm * mm
            Y = np.zeros((_TERMS + 2, jj.size, b, 2))          # last axis: from (1, 0) and from (0, 1)
            Y[0, ..., 0] = 1.0
            Y[1, ..., 1] = h
            for k in range(_TERMS):
                Y[k + 2] = np.einsum("ijb,ijbc->jbc", C[:k + 1], Y[k::-1]) * (h * h / ((k + 1) * (k + 2)))
            T_y = Y.sum(axis=0)                                # (steps, points, 2): row y of each map
            T_dy = np.einsum("k,kjbc->jbc", np.arange(_TERMS + 2.0), Y) / h
            # the maps as (steps, 2, points, 1): (y, y') from y (M0) and from y' (M1); the state S
            # holds y and y' (S[0], S[1]) of both solutions: one step is a few numpy calls
            TT = np.stack([T_y, T_dy], axis=1)
            if running:
                kept.append(TT)
            M0, M1 = TT[..., 0, None], TT[..., 1, None]
            S = np.stack([y, dy])
            for t in range(jj.size):
                if running:
                    states[t_all] = S
                S = M0[t] * S[0] + M1[t] * S[1]
                big = np.abs(S).max(axis=(0, 2))
                S /= big[:, None]
                logs_big[t_all] = np.log(big)
                t_all += 1
            y, dy = S[0], S[1]
    # s and a bound on its rounding (log's, within an ulp, and the sum's)
    partial = np.cumsum(logs_big, axis=0)
    s = partial[-1].copy()
    ds = 0.5 * np.finfo(float).eps * np.sum(np.abs(partial) + 2.0 * np.abs(logs_big), axis=0)
    E = np.full(b, np.nan)
    if bound:
        # at once: the rounding of the largest state, 2^-48 (8 + 2 s_max) e^(2 s_max) of the products
        # (an error there is amplified by at most its norm, the determinant being 1), close enough
        # where the solutions stay small (2e-12 at eps = 1.2); elsewhere the running bound
        s_max = np.maximum(partial.max(axis=0), 0.0)
        size = np.abs(dy[:, 0] * y[:, 1]) + np.abs(y[:, 0] * dy[:, 1])
        with np.errstate(over="ignore"):
            E = 2.0**-47 * (8.0 + 2.0 * s_max) * np.exp(np.minimum(2.0 * s_max, 700.0)) * size
        loose = np.flatnonzero(~(E <= 2.0**-40 * size)) if running else np.zeros(0, np.int64)
        if loose.size:
            R = _rounding_bound(np.concatenate(kept)[:, :, loose], states[:, :, loose], (partial - logs_big)[:, loose],
                                s[loose], qq[loose], mm[loose])
            # (either product of two entries moves by at most R (|a| + |b| + R), a and b its factors in
            # the balanced basis: w_I, w_II' and w_II w, w_I' / w)
            w = _balance(qq[loose], mm[loose])
            yl, dyl = y[loose], dy[loose]
            R = R * (np.abs(yl[:, 0]) + np.abs(dyl[:, 1]) + np.abs(yl[:, 1]) * w + np.abs(dyl[:, 0]) / w + R)
            E[loose] = np.minimum(E[loose], R)
        E = np.where(np.isfinite(E), E, np.inf)
    return y[:, 0], dy[:, 0], y[:, 1], dy[:, 1], s, E, ds


def _balance(qq, mm):
    """``w = sqrt(2q (1 + mu^2))`` (at least 1): the balanced basis ``(y, y' / w)`` of :func:`_half_period`."""
    return np.maximum(np.sqrt(2.0 * qq * (1.0 + mm * mm)), 1.0)


def _rounding_bound(maps, states, s_before, s, qq, mm):
    """:func:`_half_period`'s ``sum_j |Q_j| d_j`` relative to the result's scale ``e^s`` (the Frobenius
    norm of the error of the four values at that scale, in the balanced basis): ``maps[j][r, :, c]``
    the steps' maps, ``states[j]`` the (rescaled) product before step ``j``, ``e^s_before[j]`` its scale.
    The products after each step, ``Q_j``, by a backward product of the maps, rescaled every few
    steps; the sum in logarithms (each term may overflow, their sum relative to ``e^s`` does not)."""
    m, b = s_before.shape
    w = _balance(qq, mm)
    R = np.stack([np.stack([np.ones(b), w], axis=1), np.stack([1.0 / w, np.ones(b)], axis=1)])
    after, q_scale = np.empty((m, 2, b, 2)), np.empty((m, b))
    Q = np.zeros((2, b, 2))
    Q[0, :, 0] = Q[1, :, 1] = 1.0                          # Q[r, :, c]
    qs = np.zeros(b)
    for j in range(m - 1, -1, -1):
        after[j], q_scale[j] = Q, qs
        Mj = maps[j]
        # Q <- Q M_j: (Q M)[r, c] = Q[r, 0] M[0, c] + Q[r, 1] M[1, c]
        Q = Q[:, :, 0, None] * Mj[None, 0] + Q[:, :, 1, None] * Mj[None, 1]
        if j % 4 == 0:   # (four steps grow a norm by e^6 at most)
            big = np.abs(Q).max(axis=(0, 2))
            Q /= big[:, None]
            qs = qs + np.log(big)

    def norms(X):
        return np.sqrt(np.sum((X * R[None]) ** 2, axis=(1, 3)))

    with np.errstate(divide="ignore"):
        logs = q_scale + s_before + np.log(norms(after) * norms(maps) * norms(states))
    top = logs.max(axis=0)
    return _STEP_ROUNDING * np.exp(top - s + np.log(np.sum(np.exp(logs - top), axis=0)))


#: the largest eps whose sine-drive trace is integrated (q = 16 eps^2/pi^2 = 1e6), at mu = 0
EPS_TRACE = 0.25 * PI * 1000.0


def eps_reach(mu):
    """The largest ``eps`` whose sine-drive trace is integrated at ``mu``: :data:`EPS_TRACE` up to
    ``mu = 1``, beyond it ``EPS_TRACE sqrt(2 / (1 + mu^2))`` (the half period's phase
    ``sqrt(2 q (1 + mu^2))`` at most that of ``q = 1e6`` at ``mu = 1``)."""
    return np.minimum(EPS_TRACE, EPS_TRACE * np.sqrt(2.0) / np.hypot(1.0, np.asarray(mu, float)))


def _sine_traces(eps, mu, bound="running"):
    """``(tau, log|tau|, tau - 1, err)`` of the undamped sine drive over ``2T`` (flat arrays):
    ``tau = tr M/2 = 1 + 2 w_I' w_II = 2 w_I w_II' - 1`` at ``z = pi/2`` (DLMF 28.2.(iv)); ``tau - 1``
    free of the cancellation of the 1; ``err`` a bound on the error of ``tau`` from rounding (from
    :func:`_half_period`'s ``bound``: ``"running"``, ``"quick"`` or None, then NaN)."""
    eps = np.asarray(eps, float).reshape(-1)
    mu = np.broadcast_to(np.asarray(mu, float).reshape(-1), eps.shape)
    # the integration's steps grow like its phase sqrt(2 q (1 + mu^2)): at most that of q = 1e6
    reach = eps_reach(mu)
    over = ~(eps <= reach)
    if over.any():
        i = int(np.argmax(over))
        raise _v.ReachError(float(eps[i]), float(mu[i]), float(reach[i]),
                            "Floquet data (Mathieu's q = 16 eps^2 / pi^2 up to 1e6, q (1 + mu^2) up to 2e6)")
    wI, dwI, wII, dwII, s, E, ds = _half_period(eps, mu, bound)
    m1, p1 = 2.0 * dwI * wII, 2.0 * wI * dwII  # (tau - 1) e^{-2s}, (tau + 1) e^{-2s}
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):   # (log|tau| = -inf where tau is 0)
        e2s = np.exp(2.0 * s)
        tau_m1 = m1 * e2s
        tau = np.where(np.abs(m1) <= np.abs(p1), 1.0 + tau_m1, p1 * e2s - 1.0)
        tau = np.where(np.isfinite(e2s), tau, np.sign(m1 + p1) * np.inf)
        # |tau| = |m1 + p1| e^{2s} / 2, formed in logarithms where it overflows
        log_big = np.log(0.5 * np.abs(m1 + p1)) + 2.0 * s
        log_tau = np.where(np.isfinite(tau) & (np.abs(tau) < 1e300), np.log(np.abs(tau)), log_big)
        # the products' error 2 E, their and the exponential's rounding (e^{2s} also carries s's), the 1's
        unit = 0.5 * np.finfo(float).eps
        prod = np.maximum(np.abs(m1), np.abs(p1))
        err = (2.0 * E + (6.0 * unit + 2.2 * ds) * prod) * e2s + unit * (np.abs(tau) + 1.0)
    return tau, log_tau, tau_m1, err


def sine_grid(eps, mu, out):
    """Paint ``out[i, j] = stable(eps[j], mu[i])`` for the undamped sine drive (``eps`` ascending,
    ``out`` zeroed), equal to ``is_stable`` at the same doubles.

    Each crossing of a row with a characteristic value in view is bisected on the *pixels*: ten
    steps for 1024 columns find the two neighbouring pixels it lies between (the Sturm count
    at each pixel itself). A pixel within twice the rounding band (:func:`_band`) of the crossing
    -- seen by probing just inside the pair -- is decided point by point as
    :func:`sine_floquet0` decides it (certified where rounding may decide).
    """
    ok = np.flatnonzero(mu < 1.0)
    if not ok.size:
        return out
    W = eps.size
    m = mu[ok]
    # crossings up to just past eps[-1]: one within the rounding band above the last pixel is in view
    # (the pixel beside it is then decided point by point, below)
    q1, a1 = _qa(float(eps[-1]) * (1.0 + 4.0 * _band(m)), m)
    K = _count(np.arange(4)[:, None], q1[None, :], a1[None, :]).reshape(-1)
    r = np.repeat(np.tile(np.arange(m.size), 4), K)
    fam = np.repeat(np.repeat(np.arange(4), m.size), K)
    k = np.arange(r.size) - np.repeat(np.cumsum(K) - K, K)
    # pixel indices either side: -1 stands for eps = 0 (below every crossing), W - 1 is above
    lo = np.full(r.size, -1, np.int64)
    hi = np.full(r.size, W - 1, np.int64)
    live = np.flatnonzero(hi - lo > 1)
    while live.size:
        mid = (lo[live] + hi[live]) // 2
        up = _above(fam[live], k[live], eps[mid], m[r[live]])
        hi[live[up]] = mid[up]
        lo[live[~up]] = mid[~up]
        live = live[hi[live] - lo[live] > 1]
    # pixels too close to their crossing to be sure of their side
    e_lo = np.where(lo >= 0, eps[np.maximum(lo, 0)], 0.0)
    d = 2.0 * _band(m[r], np.where(lo >= 0, e_lo, eps[hi]))
    probe = np.concatenate([e_lo * (1.0 + d), eps[hi] * (1.0 - d)])
    sure = _above(np.tile(fam, 2), np.tile(k, 2), probe, np.tile(m[r], 2)) == np.repeat([False, True], r.size)
    # zones: from the crossing of a_n (lower) to that of b_{n+1} (upper; _LOWER, _UPPER)
    first = np.cumsum(K) - K
    flat = out.reshape(-1)
    starts, stops = [], []
    for par in (0, 1):
        sel = np.flatnonzero(fam == _LOWER[par])
        rl, kl = r[sel], k[sel]
        fu = _UPPER[par]
        has = kl < K[fu * m.size + rl]
        stop = np.full(sel.size, W - 1, np.int64)  # an upper edge beyond the chart
        stop[has] = lo[first[fu * m.size + rl[has]] + kl[has]]
        starts.append((ok[rl] * W + hi[sel]))
        stops.append((ok[rl] * W + stop + 1))
    starts, stops = np.concatenate(starts), np.concatenate(stops)
    for a, b in zip(starts[stops > starts].tolist(), stops[stops > starts].tolist()):
        flat[a:b] = True
    # every pixel within the band of a crossing is decided point by point: near a crossing the
    # counts of neighbouring doubles may disagree with each other (rounding), so the bisection's
    # pair need not be the last pair whose side the counts get wrong; a normal grid has no pixel
    # there but the pair itself
    a = np.searchsorted(eps, e_lo * (1.0 - d), side="left")
    b = np.searchsorted(eps, eps[hi] * (1.0 + d), side="right")
    near = (~sure[:r.size]) | (~sure[r.size:]) | (b - a > 2)
    cnt = np.where(near, b - a, 0)
    if cnt.any():
        rr = np.repeat(ok[r], cnt).astype(np.int64)
        jj = np.repeat(a, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        key = np.unique(rr * W + jj)
        rr, jj = key // W, key % W
        out[rr, jj] = sine_floquet0(eps[jj], mu[rr])[4] >= 0
    return out


# ---------------------------------------------------------------- the exact trace in long double first
#: Points times Taylor steps of one call of :func:`_sine_ld_chunk`
_LD_CHUNK = 8192
#: Beyond this many steps a half period the long double tier declines (mpmath decides)
_LD_MAX_STEPS = 2048
#: Fewer points than this go to mpmath directly, unless the half period takes more than
#: ``_LD_MIN_STEPS`` steps: the tier costs a few ms a call whatever the points, and beside a damped
#: edge at small ``eps`` or a thin zone it often cannot decide, where mpmath takes a few ms a point;
#: at large ``q`` mpmath takes seconds a point (thousands of bits over hundreds of steps)
_LD_MIN_POINTS = 4
_LD_MIN_STEPS = 40


def _ld_pays(eps, mu):
    """Whether :func:`sine_ld` is worth asking first for these points."""
    if eps.size >= _LD_MIN_POINTS:
        return True
    if not eps.size:
        return False
    q = 16.0 * float(np.max(eps)) ** 2 / PI**2
    return 0.5 * PI * (np.sqrt(2.0 * q * (1.0 + float(np.max(mu)) ** 2)) + 2.0) > _LD_MIN_STEPS


def _sine_ld_chunk(e, m2, steps, unit):
    """``(tau, bound)`` at long double ``e = eps``, ``m2 = mu^2 (1 + zeta^2)``: ``tau = tr M / 2 =
    2 w_I(pi/2) w_II'(pi/2) - 1`` and a bound on its error, from the half period in ``steps`` Taylor
    steps (:func:`kapitza._certify.taylor_ld`; the Mathieu form of :func:`_exact_half_period`)."""
    from .._certify import product_ld, taylor_ld

    LD = e.dtype.type
    q2 = 32.0 * e * e / (_PI_LD * _PI_LD)               # 2q
    h = _PI_LD / (2 * steps)
    hh = h * h
    z2 = (2.0 * np.arange(steps, dtype=LD) * h)[:, None]   # 2 z at each step's start
    cj, sj = np.cos(z2), np.sin(z2)
    # c(z0 + h u) = 2q m2 + 2q cos(2 z0 + 2 h u): its Taylor coefficients in u, times h^2, until the
    # rest of the series is below unit / 256 of the first (its tail goes to the coefficients' error)
    coef = [q2 * (m2 + cj) * hh]
    t, i = LD(1.0), 0
    while True:
        i += 1
        t = t * (2.0 * h) / i
        if float(t) < unit / 256.0 and i > 2:
            break
        trig = (cj, -sj, -cj, sj)[i % 4]
        coef.append(q2 * t * trig * hh)
    rest = q2 * hh * t * 2.0                                # sum_(k >= i) (2h)^k / k! <= 2 (2h)^i / i! (2h <= 1)
    # the coefficients' rounding: 2q to 6 units, m2 to 4, each trigonometric value to 2 + 2 pi (its
    # argument), each (2h)^i / i! to 2 i, h^2 to 5 (and the steps' lengths, 12 units of the whole)
    delta = (unit * q2 * hh * (20.0 * (m2 + 1.0) + 16.0 * np.exp(2.0 * h)) + rest
             + 12.0 * unit * sum(np.abs(c) for c in coef))
    _, kw = np.frexp(np.sqrt(q2 * (m2 + 1.0)))
    coef = [np.broadcast_to(c, (steps, e.size)) for c in coef]
    S, fro = taylor_ld(coef, np.broadcast_to(delta, (steps, e.size)), np.full((steps, 1), h, LD), kw, unit)
    (p00, _, _, p11), bound, ex = product_ld(S, fro, unit)
    prod = p00 * p11
    err = (np.abs(p00) + np.abs(p11)) * bound + bound * bound + 2.0 * unit * np.abs(prod)
    t = 2.0 * np.ldexp(prod, 2 * ex) - 1.0
    return t, 2.0 * np.ldexp(err, 2 * ex) + unit * (np.abs(t) + 1.0)


def sine_ld(eps, mu, zeta=None):
    """The exact sine verdicts in long double (flat arrays): ``(decided, stable, tau, log_tau, growth,
    tau_error)`` as :func:`kapitza._certify.ld_tier` gives them, from the half period's Taylor steps
    (:func:`_exact_half_period`'s, with ``tau = 2 w_I w_II' - 1``) and their rounding bound. ``zeta``:
    the damped system's ``phi``-equation and its verdict ``|tau_phi| < cosh(kappa)``."""
    from .._certify import LD_UNIT, ld_tier

    def counts(eps, m2):
        # (steps of at most 1/8: fewer Taylor terms of the steps and of the coefficient, and the steps
        # are taken all at once)
        return np.maximum(np.ceil(0.5 * PI * (np.sqrt(32.0 * eps * eps / PI**2 * (1.0 + m2)) + 2.0)), 13.0)

    return ld_tier(eps, mu, zeta, counts, lambda e, m2, rows: _sine_ld_chunk(e, m2, rows[0], LD_UNIT),
                   _LD_MAX_STEPS, _LD_CHUNK)
