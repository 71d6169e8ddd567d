"""Certified traces of drives linear on pieces, in double-double arithmetic, compiled (numba).

The Taylor steps and the error analysis of the long double tier (:func:`kapitza._certify.taylor_ld`,
:func:`kapitza._certify.product_ld`; steps :data:`STEP_ROOT` times as long), one point at a time, with
each number a pair of doubles ``hi + lo`` (error-free sums and products, Dekker's splitting; no fused
multiply-add is asked of the compiler). Every operation below has a relative error of at most
:data:`UNIT` ``= 2^-100``, 64 times the largest proven bound of the double-double operations used
(``3 u^2`` for a sum, ``7 u^2`` for a product, ``15 u^2`` for a quotient, ``u = 2^-53``), so the
long double tier's analysis holds with ``UNIT`` in place of the long double's unit roundoff. That
is 2^-36 of the long double's: the verdicts at the doubles next to a zone's edge, which the long
double leaves to mpmath for about half the points, are decided here in microseconds.

:func:`pieces_dd` answers as :func:`kapitza._certify.ld_tier` does; a point it cannot take (a
coefficient too small for the pairs' low parts, more than :data:`MAX_STEPS` steps, a damping
exponent ``kappa`` past :data:`KAPPA_MAX`) is left undecided for the long double and mpmath tiers.
Imported only once the compiled engine is loaded (:func:`kapitza.engines.magnus.load_compiled`).
"""
from __future__ import annotations

import math

import numpy as np

from ._compiled import jit

#: The relative error bound of each double-double operation (see the module's docstring)
UNIT = 2.0**-100
#: A Taylor step's ``h sqrt(max|a + b x|)`` at most (``s <= 16``; the long double tier takes 1): longer
#: steps of more terms cost less per unit of phase (2.3 times less at ``eps`` 3-10 for the triangle,
#: the bound still about 1e-22 of the trace; at 8 it grew to 2e-19)
STEP_ROOT = 4.0
#: Beyond this many Taylor steps a period the tier declines
MAX_STEPS = 1 << 16
#: ... and beyond this damping exponent (its threshold ``cosh(kappa)`` is a Taylor series here)
KAPPA_MAX = 64.0
#: ... and below this size of ``8 eps^2 max|mu^2 + s|`` (the terms' low parts would leave the doubles)
COEF_MIN = 1e-200

_SPLIT = 134217729.0            # 2^27 + 1 (Dekker)
_SQRT2_HI = 1.4142135623730951  # sqrt(2) as a double-double (its error below 1e-32)
_SQRT2_LO = -9.667293313452913e-17
_LN2 = 0.6931471805599453


@jit
def two_sum(a, b):
    """``(s, e)``: ``s = fl(a + b)`` and ``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@jit
def _fast_two_sum(a, b):
    s = a + b
    return s, b - (s - a)


@jit
def two_prod(a, b):
    """``(p, e)``: ``p = fl(a b)`` and ``a b = p + e`` exactly (Dekker; ``|a|, |b| < 2^995``)."""
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@jit
def dd_add(ah, al, bh, bl):
    """The sum of two double-doubles (Joldes, Muller and Popescu's AccurateDWPlusDW: ``3 u^2``)."""
    sh, sl = two_sum(ah, bh)
    th, tl = two_sum(al, bl)
    sl += th
    sh, sl = _fast_two_sum(sh, sl)
    sl += tl
    return _fast_two_sum(sh, sl)


@jit
def dd_mul(ah, al, bh, bl):
    """The product of two double-doubles (DWTimesDW1: ``7 u^2``)."""
    p, e = two_prod(ah, bh)
    e += ah * bl + al * bh
    return _fast_two_sum(p, e)


@jit
def dd_mul_d(ah, al, b):
    """A double-double times a double (DWTimesFP1: ``2 u^2``)."""
    p, e = two_prod(ah, b)
    e += al * b
    return _fast_two_sum(p, e)


@jit
def dd_div_d(ah, al, b):
    """A double-double over a double (DWDivFP3: ``3 u^2``)."""
    th = ah / b
    ph, pl = two_prod(th, b)
    d = (ah - ph) + (al - pl)
    return _fast_two_sum(th, d / b)


@jit
def dd_div(ah, al, bh, bl):
    """A double-double over a double-double (DWDivDW2: ``15 u^2``)."""
    th = ah / bh
    rh, rl = dd_mul_d(bh, bl, th)
    d = (ah - rh) + (al - rl)
    return _fast_two_sum(th, d / bh)


@jit
def _norm2(a, b, c, d):
    """The spectral norm of ``[[a, b], [c, d]]`` (doubles), raised by a few units for its rounding."""
    f2 = a * a + b * b + c * c + d * d
    det = a * d - b * c
    return math.sqrt(0.5 * (f2 + math.sqrt(max(f2 * f2 - 4.0 * det * det, 0.0)))) * (1.0 + 1e-14)


@jit
def _step(ah, al, bh, bl, delta, hh_, hl_, kw, W, S):
    """One Taylor step of ``y'' = (a + b u) y`` over ``u`` in ``[0, 1]`` (``a, b`` the coefficients
    times ``h^2``, double-doubles; ``h = hh_ + hl_``; ``delta`` bounds the coefficients' own rounding),
    in the basis ``(y, y' / 2^kw)``, as :func:`kapitza._certify.taylor_ld` takes it: its matrix into
    ``S`` (:func:`_dd_matmul`'s layout), and the Frobenius bound on its error, the product's rounding
    share counted in, returned (``inf``: the series did not converge in the room of ``W``, scratch
    ``[2, terms, 2]``)."""
    A0 = abs(ah) + abs(al)
    A1 = abs(bh) + abs(bl)
    s = A0 + A1
    W[:, :2, :] = 0.0
    W[0, 0, 0] = 1.0
    W[1, 1, 0] = 1.0
    # W_(k+2) = (a W_k + b W_(k-1)) / ((k + 1)(k + 2)) for both columns; r_k >= |W_k| the majorant's
    # terms (the recursion on |a|, |b|); past K each next term is at most s / (K (K + 1)) of the largest
    # of the last two, so the tail is below 2 s max(r) / (K (K + 1))
    rp = 0.0   # r_(K-2), r_(K-1), r_K
    r0 = 1.0
    r1 = 1.0
    K = 1
    while True:
        k = K - 1
        den = float((k + 1) * (k + 2))
        for c in range(2):
            xh, xl = dd_mul(ah, al, W[c, k, 0], W[c, k, 1])
            if k >= 1:
                yh, yl = dd_mul(bh, bl, W[c, k - 1, 0], W[c, k - 1, 1])
                xh, xl = dd_add(xh, xl, yh, yl)
            xh, xl = dd_div_d(xh, xl, den)
            W[c, K + 1, 0] = xh
            W[c, K + 1, 1] = xl
        r2 = (A0 * r0 + A1 * rp) / den   # r_(K+1) from r_(K-1), r_(K-2)
        K += 1
        if K > 8 and 4.0 * max(s, 1e-300) * max(max(r0, r1), r2) / (K * (K + 1)) < UNIT / 64.0:
            break
        if K + 2 >= W.shape[1]:
            return math.inf
        rp = r0
        r0 = r1
        r1 = r2
    # the sums, smallest terms first: val = sum W_k, der = sum k W_k, per column
    v0h, v0l = W[0, K, 0], W[0, K, 1]
    v1h, v1l = W[1, K, 0], W[1, K, 1]
    d0h, d0l = dd_mul_d(v0h, v0l, float(K))
    d1h, d1l = dd_mul_d(v1h, v1l, float(K))
    for i in range(K - 1, -1, -1):
        v0h, v0l = dd_add(v0h, v0l, W[0, i, 0], W[0, i, 1])
        v1h, v1l = dd_add(v1h, v1l, W[1, i, 0], W[1, i, 1])
        if i > 0:
            th, tl = dd_mul_d(W[0, i, 0], W[0, i, 1], float(i))
            d0h, d0l = dd_add(d0h, d0l, th, tl)
            th, tl = dd_mul_d(W[1, i, 0], W[1, i, 1], float(i))
            d1h, d1l = dd_add(d1h, d1l, th, tl)
    # the entries (val_1, h val_2 2^kw, der_1 / h 2^-kw, der_2)
    s01h, s01l = dd_mul(hh_, hl_, v1h, v1l)
    s01h, s01l = math.ldexp(s01h, kw), math.ldexp(s01l, kw)
    s10h, s10l = dd_div(d0h, d0l, hh_, hl_)
    s10h, s10l = math.ldexp(s10h, -kw), math.ldexp(s10l, -kw)
    # their errors (taylor_ld's bounds with UNIT): the majorant y'' = s y gives the sums of |W_k|,
    # k |W_k|, k^2 |W_k| as (cosh, sqrt s sinh, s cosh + sqrt s sinh) of sqrt s for the first column,
    # (sinh / sqrt s, cosh, sqrt s sinh + cosh) for the second; a coefficient's change moves the values
    # by its Green's function (a quarter more for the second order)
    sig = math.sqrt(s)
    ch = math.cosh(sig)
    sh = math.sinh(sig) / sig if sig > 0.0 else 1.0
    tail = UNIT / 64.0
    grow = 3.5   # (n_c + 3) / 2 units per unit of k, and one
    ev0 = UNIT * (grow * s * sh + ch) + 1.25 * delta * 0.5 * sh + tail * ch
    ed0 = UNIT * (grow * (s * ch + s * sh) + 3.0 * s * sh) + 1.25 * delta * 0.5 * (ch + sh) + tail * s * sh
    ev1 = UNIT * (grow * ch + sh) + 1.25 * delta * 0.25 * ch + tail * sh
    ed1 = UNIT * (grow * (s * sh + ch) + 3.0 * ch) + 1.25 * delta * 0.5 * sh + tail * ch
    h = hh_ + hl_
    e01 = math.ldexp(h * ev1, kw) * (1.0 + 1e-14) + 2.0 * UNIT * abs(s01h)
    e10 = math.ldexp(ed0 / h, -kw) * (1.0 + 1e-14) + 2.0 * UNIT * abs(s10h)
    fro = (math.sqrt(ev0 * ev0 + e01 * e01 + e10 * e10 + ed1 * ed1)
           + 2.0 * UNIT * math.sqrt(v0h * v0h + s01h * s01h + s10h * s10h + d1h * d1h)) * (1.0 + 1e-12)
    S[0], S[1], S[2], S[3], S[4], S[5], S[6], S[7] = v0h, v0l, s01h, s01l, s10h, s10l, d1h, d1l
    return fro


@jit
def _dd_matmul(S, P):
    """``P <- S P`` in place for 2x2 matrices of double-doubles, each an array ``(00h, 00l, 01h, 01l,
    10h, 10l, 11h, 11l)``."""
    for r in range(2):
        sah, sal, sbh, sbl = S[4 * r], S[4 * r + 1], S[4 * r + 2], S[4 * r + 3]
        for c in range(2):
            xh, xl = dd_mul(sah, sal, P[2 * c], P[2 * c + 1])
            yh, yl = dd_mul(sbh, sbl, P[4 + 2 * c], P[5 + 2 * c])
            S[8 + 4 * r + 2 * c], S[9 + 4 * r + 2 * c] = dd_add(xh, xl, yh, yl)
    P[:] = S[8:16]


@jit
def _rescale(P):
    """Scale the double-double matrix ``P`` in place by a power of two to a largest entry in ``[1/2, 1)``;
    return ``(the exponent taken out, whether P is not 0)``."""
    big = max(max(abs(P[0]), abs(P[2])), max(abs(P[4]), abs(P[6])))
    if not big > 0.0:
        return 0, False
    sc = math.frexp(big)[1]
    for i in range(8):
        P[i] = math.ldexp(P[i], -sc)
    return sc, True


@jit
def _cosh(kh, kl):
    """``(cosh(kappa), bound)`` for the double-double ``kappa`` (``kappa <= KAPPA_MAX``) by its Taylor
    series (positive terms): each term's relative error grows by at most 12 units a term (``kappa^2``
    to 10, a product and a quotient), the sum's by one a term; the tail after a term below 2^-110 of
    the sum, with the ratio of terms below 1/2, under twice that term."""
    qh, ql = dd_mul(kh, kl, kh, kl)
    sh_, sl_ = 1.0, 0.0
    th, tl = 1.0, 0.0
    i = 0
    while True:
        i += 1
        th, tl = dd_mul(th, tl, qh, ql)
        th, tl = dd_div_d(th, tl, float((2 * i - 1) * (2 * i)))
        sh_, sl_ = dd_add(sh_, sl_, th, tl)
        if th < 2.0**-110 * sh_ and qh < float((2 * i + 1) * (2 * i + 2)) * 0.5:
            break
    return sh_, sl_, (UNIT * (13.0 * i + 8.0) + 2.0**-108) * sh_


@jit
def _point(px0, px1, ps0, ps1, e, m, z, damped, W, out):
    """:func:`pieces_dd` at one point: ``out[:7]`` = ``(decided, stable, tau, log_tau, growth,
    tau_error, tau_lo)`` (``tau + tau_lo`` the double-double ``tau``); ``out[0] = 0`` where the point
    is declined."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = math.nan
    out[3] = math.nan
    out[4] = math.nan
    out[5] = math.inf
    out[6] = 0.0
    if not (e > 0.0 and e < 1e100 and abs(m) < 1e100 and abs(z) < 1e100):
        return
    Eh, El = two_prod(e, e)
    Eh *= 8.0
    El *= 8.0
    mh, ml = two_prod(m, m)
    if damped:
        zh, zl = two_prod(z, z)
        oh, ol = dd_add(1.0, 0.0, zh, zl)
        mh, ml = dd_mul(mh, ml, oh, ol)
    n = px0.size
    smax0 = 0.0
    smax1 = 0.0
    peak = 0.0
    total = 0
    for p in range(n):
        smax0 = max(smax0, abs(ps0[p]))
        smax1 = max(smax1, abs(ps1[p]))
        w = px1[p] - px0[p]
        if w > 0.0:
            pk = Eh * max(abs(mh + ps0[p]), abs(mh + ps1[p]))
            peak = max(peak, pk)
            total += max(1, int(math.ceil(w * math.sqrt(pk) / STEP_ROOT * (1.0 + 1e-9))))
    if peak < COEF_MIN or total > MAX_STEPS:
        return
    kw = math.frexp(math.sqrt(Eh * (mh + smax0 + smax1)))[1]
    Sh = np.empty((total, 4))
    fro = np.empty(total)
    npre = np.empty(total)
    epre = np.empty(total, np.int64)
    # the product P (double-doubles) over 2^ex; S a step's matrix, then the product's scratch
    P = np.zeros(8)
    P[0] = 1.0
    P[6] = 1.0
    S = np.empty(16)
    ex = 0
    j = 0
    for p in range(n):
        if not px1[p] > px0[p]:
            continue
        wh, wl = two_sum(px1[p], -px0[p])
        dh, dl = two_sum(ps1[p], -ps0[p])
        pk = Eh * max(abs(mh + ps0[p]), abs(mh + ps1[p]))
        k = max(1, int(math.ceil((wh + wl) * math.sqrt(pk) / STEP_ROOT * (1.0 + 1e-9))))
        hh_, hl_ = dd_div_d(wh, wl, float(k))
        h2h, h2l = dd_mul(hh_, hl_, hh_, hl_)
        bh, bl = dd_mul(Eh, El, dh, dl)
        bh, bl = dd_div_d(bh, bl, float(k))
        bh, bl = dd_mul(bh, bl, h2h, h2l)
        base = 16.0 * UNIT * Eh * (mh + abs(ps0[p]) + abs(dh)) * h2h
        for jj in range(k):
            th, tl = dd_mul_d(dh, dl, float(jj))
            th, tl = dd_div_d(th, tl, float(k))
            th, tl = dd_add(ps0[p], 0.0, th, tl)
            th, tl = dd_add(mh, ml, th, tl)
            th, tl = dd_mul(Eh, El, th, tl)
            ah, al = dd_mul(th, tl, h2h, h2l)
            delta = (base + 24.0 * UNIT * (abs(ah) + abs(bh))) * (1.0 + 1e-12)
            fro[j] = _step(ah, al, bh, bl, delta, hh_, hl_, kw, W, S)
            if not fro[j] < math.inf:
                return
            Sh[j, 0], Sh[j, 1], Sh[j, 2], Sh[j, 3] = S[0], S[2], S[4], S[6]
            npre[j] = _norm2(P[0], P[2], P[4], P[6])
            epre[j] = ex
            _dd_matmul(S, P)
            big = max(max(abs(P[0]), abs(P[2])), max(abs(P[4]), abs(P[6])))
            if big > 2.0**60 or big < 2.0**-60:
                sc, nonzero = _rescale(P)
                if not nonzero:
                    return
                ex += sc
            j += 1
    sc, nonzero = _rescale(P)
    if not nonzero:
        return
    ex += sc
    # the error: sum_j |S_m ... S_(j+1)| fro_j |S_(j-1) ... S_1| (first order, a millionth more), the
    # suffixes' norms from a backward product in doubles kept near 1 by powers of two
    q00, q01, q10, q11 = 1.0, 0.0, 0.0, 1.0
    qe = 0
    acc = 0.0
    for jj in range(total - 1, -1, -1):
        acc += math.ldexp(_norm2(q00, q01, q10, q11) * fro[jj] * npre[jj], qe + epre[jj] - ex)
        a0 = q00 * Sh[jj, 0] + q01 * Sh[jj, 2]
        a1 = q00 * Sh[jj, 1] + q01 * Sh[jj, 3]
        a2 = q10 * Sh[jj, 0] + q11 * Sh[jj, 2]
        a3 = q10 * Sh[jj, 1] + q11 * Sh[jj, 3]
        big = max(max(abs(a0), abs(a1)), max(abs(a2), abs(a3)))
        sc = math.frexp(big)[1] if big > 0.0 else 0
        q00, q01, q10, q11 = math.ldexp(a0, -sc), math.ldexp(a1, -sc), math.ldexp(a2, -sc), math.ldexp(a3, -sc)
        qe += sc
    acc = acc * (1.0 + 1e-6) + 2.0 * UNIT * math.sqrt(P[0] * P[0] + P[2] * P[2] + P[4] * P[4] + P[6] * P[6])
    trh, trl = dd_add(P[0], P[1], P[6], P[7])
    trh *= 0.5
    trl *= 0.5
    err = 0.5 * (1.4142135623730951 * (1.0 + 1e-15) * acc + 1.01 * UNIT * abs(2.0 * trh))
    if ex > 900 or ex < -900 or not math.isfinite(acc):
        return
    # |tau| against the threshold (1 undamped, cosh(kappa) damped), unscaled
    ah, al = (trh, trl) if trh >= 0.0 else (-trh, -trl)
    ah, al = math.ldexp(ah, ex), math.ldexp(al, ex)
    err = math.ldexp(err, ex)
    kh = 0.0
    thr_h, thr_l, thr_err = 1.0, 0.0, 0.0
    if damped:
        kh, kl = dd_mul_d(_SQRT2_HI, _SQRT2_LO, z)
        kh, kl = dd_mul_d(kh, kl, m)
        kh, kl = dd_mul_d(kh, kl, e)
        kh, kl = abs(4.0 * kh), (4.0 * kl if kh >= 0.0 else -4.0 * kl)
        if kh > KAPPA_MAX:
            return
        thr_h, thr_l, thr_err = _cosh(kh, kl)
        thr_err += 8.0 * UNIT * kh * thr_h
    dfh, dfl = dd_add(ah, al, -thr_h, -thr_l)
    xh, xl = dd_add(ah, al, -1.0, 0.0)
    tau = math.ldexp(trh, ex)
    out[0] = 1.0 if (abs(dfh) > (err + thr_err) * (1.0 + 1e-9) and trh != 0.0) else 0.0
    out[1] = 1.0 if dfh < 0.0 else 0.0
    out[2] = tau
    out[3] = math.log1p(xh) if xh > -1.0 else -math.inf
    if xh > 0.0:
        gr = math.log1p(xh + math.sqrt(xh * (xh + 2.0))) if xh < 1e150 else out[3] + _LN2
    else:
        gr = 0.0
    gr -= kh
    if damped and xh > 0.0 and kh > 0.0 and abs(dfh) < 0.25 * thr_h:
        # near the damped edge acosh|tau| - kappa cancels: y solves cosh(kappa + y) = cosh(kappa) + d
        # (d = |tau| - cosh(kappa), known to the pairs' digits), c (cosh y - 1) + s sinh y = d, by Newton
        sk = math.sinh(kh)
        y = dfh / sk
        for _ in range(8):
            sy = math.sinh(y)
            y -= (2.0 * thr_h * math.sinh(0.5 * y) ** 2 + sk * sy - dfh) / (thr_h * sy + sk * math.cosh(y))
        gr = y
    out[4] = gr
    out[5] = err
    out[6] = math.ldexp(trl, ex)


@jit
def _points(px0, px1, ps0, ps1, eps, mu, zeta, damped, out):
    W = np.zeros((2, 128, 2))
    for i in range(eps.size):
        _point(px0, px1, ps0, ps1, eps[i], mu[i], zeta[i], damped, W, out[i])


def warm() -> None:
    """Load the tier's compiled code (from numba's cache, compiled there the first time)."""
    pieces_dd(np.array([1.0]), np.array([0.5]), np.array([0.1]), ((0.0, 1.0, 1.0, -1.0), (1.0, 2.0, -1.0, 1.0)))


def pieces_dd(eps, mu, zeta, pieces, low=False):
    """The double-double tier of the linear pieces' verdicts (flat ``eps, mu``; ``zeta`` None:
    undamped): ``(decided, stable, tau, log_tau, growth, tau_error)`` as
    :func:`kapitza._certify.ld_tier` gives them (``low``: a seventh item, ``tau``'s low part)."""
    eps = np.ascontiguousarray(eps, float).ravel()
    mu = np.ascontiguousarray(mu, float).ravel()
    z = np.zeros(eps.size) if zeta is None else np.ascontiguousarray(zeta, float).ravel()
    px0, px1, ps0, ps1 = (np.array([float(q[i]) for q in pieces]) for i in range(4))
    out = np.empty((eps.size, 7))
    if eps.size:
        _points(px0, px1, ps0, ps1, eps, mu, z, zeta is not None, out)
    res = (out[:, 0] > 0.5, out[:, 1] > 0.5, out[:, 2].copy(), out[:, 3].copy(), out[:, 4].copy(),
           out[:, 5].copy())
    return (*res, out[:, 6].copy()) if low else res
