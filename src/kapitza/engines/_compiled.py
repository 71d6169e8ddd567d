"""The period of :mod:`kapitza.engines.magnus` as one compiled loop (numba, the ``fast`` extra).

The same steps (the coefficient arrays of :class:`~kapitza.engines.magnus.Grid` are the input
of both paths: one definition of the step), multiplied one after another instead of in a
tree, the Pruefer angle advanced by the principal value of each step's turn; then the
half-trace, the rotation angle and the zone index of :func:`~kapitza.engines.magnus.half_trace`
and :func:`~kapitza.engines.magnus.rotation`, per point. A test runs both paths against each
other. This module is imported only when the engine first runs (``import kapitza`` stays
light); numba caches the compiled code on disk, so a command pays the compilation once.
"""
from __future__ import annotations

import math

import numpy as np

try:
    import numba

    jit = numba.njit(cache=True, nogil=True)
except ImportError:  # pragma: no cover - depends on the installation
    numba = None  # type: ignore[assignment]

    def jit(f):
        return f

LN2 = 0.6931471805599453
SQRT8 = math.sqrt(8.0)
PI = math.pi


@jit
def _one(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, E, m2, angle):
    """``(a, b, c, d, L, turn)`` of one period: ``M = e^L [[a, b], [c, d]]``."""
    a = 1.0
    b = 0.0
    c = 0.0
    d = 1.0
    L = 0.0
    turn = 0.0
    for j in range(h.size):
        hj = h[j]
        if hj == 0.0:
            continue
        p = E * (p1[j] + E * (p2[j] + m2 * p2m[j]))
        q = hj + E * (q1[j] + E * q2[j])
        r = E * (hj * m2 + r1[j] + E * ((r2[j] + m2 * r2m[j]) + E * (r3[j] + m2 * r3m[j])))
        w2 = p * p + q * r
        if abs(w2) <= 0.01:
            # cosh(w) and sinh(w) / w as series in w^2 (cos and sin / w for w^2 < 0), to 2e-21
            # relative at |w| <= 0.1: the steps' phase is about PHASE = 0.05 (no libm call a step)
            ch = 1.0 + w2 * (0.5 + w2 * (1.0 / 24.0 + w2 * (1.0 / 720.0 + w2 * (1.0 / 40320.0
                                                                             + w2 * (1.0 / 3628800.0)))))
            shw = 1.0 + w2 * (1.0 / 6.0 + w2 * (1.0 / 120.0 + w2 * (1.0 / 5040.0 + w2 * (1.0 / 362880.0
                                                                                  + w2 * (1.0 / 39916800.0)))))
        elif w2 > 0.0:
            w = math.sqrt(w2)
            if w > 0.5:  # e^{-w} exp(Omega): the scale goes to L
                ch = 0.5 * (1.0 + math.exp(-2.0 * w))
                shw = -0.5 * math.expm1(-2.0 * w) / w
                L += w
            else:
                ch = math.cosh(w)
                shw = math.sinh(w) / w
        else:
            w = math.sqrt(-w2)
            ch = math.cos(w)
            shw = math.sin(w) / w
        sa = ch + shw * p
        sb = shw * q
        sc = shw * r
        sd = ch - shw * p
        na = sa * a + sb * c
        nb = sa * b + sb * d
        nc = sc * a + sd * c
        nd = sc * b + sd * d
        if angle:
            # the turn of the first column (the image of (1, 0)) in the Pruefer angle arg(x, -y)
            turn += math.atan2(c * na - a * nc, a * na + c * nc)
        a = na
        b = nb
        c = nc
        d = nd
        big = max(max(abs(a), abs(b)), max(abs(c), abs(d)))
        if big > 1e100 or big < 1e-100:
            e = math.frexp(big)[1]
            s = math.ldexp(1.0, -e)
            a *= s
            b *= s
            c *= s
            d *= s
            L += e * LN2
    big = max(max(abs(a), abs(b)), max(abs(c), abs(d)))
    e = math.frexp(big)[1]
    s = math.ldexp(1.0, -e)
    return a * s, b * s, c * s, d * s, L + e * LN2, turn


@jit
def _half_trace(a, d, L):
    """``(tau, log|tau|)`` of ``M = e^L [[a, b], [c, d]]`` (:func:`~kapitza.engines.magnus.half_trace`)."""
    trN = a + d
    if trN == 0.0:
        return 0.0, -math.inf
    log_tau = L + math.log(abs(0.5 * trN))
    return math.copysign(math.exp(log_tau) if log_tau < 709.0 else math.inf, trN), log_tau


@jit
def _rotation(tau, b, turn):
    """``(theta, zone)`` from the half-trace, the monodromy's ``b`` and the turn of ``(1, 0)``
    (:func:`~kapitza.engines.magnus.rotation`; ``zone`` -1 off the zones)."""
    if abs(tau) < 1.0:
        sig = 1.0 if b >= 0.0 else -1.0
        base = sig * math.acos(tau)
        kk = np.rint((turn - base) / (2.0 * PI))
        return 2.0 * PI * kk + base, (2.0 * kk if b >= 0.0 else 2.0 * kk - 1.0)
    k0 = math.floor(turn / PI)
    odd = k0 - 2.0 * math.floor(0.5 * k0)
    return PI * (k0 if (odd == 0.0) == (tau > 0.0) else k0 + 1.0), -1.0


@jit
def _loop(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, eps, mu, angle, finish, out):
    """Row ``i`` of ``out``: ``(a, b, c, d, L, turn)``, or with ``finish``
    ``(tau, log_tau, theta, zone, growth, 0)`` (:func:`~kapitza.engines.magnus.rotation`)."""
    for i in range(eps.size):
        a, b, c, d, L, turn = _one(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m,
                                   8.0 * eps[i] * eps[i], mu[i] * mu[i], angle)
        if not finish:
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
            out[i, 3] = d
            out[i, 4] = L
            out[i, 5] = turn
            continue
        tau, log_tau = _half_trace(a, d, L)
        theta, zone = _rotation(tau, b, turn)
        # growth acosh|tau| off the zones (from log|tau| where tau is large), 0 on them
        growth = 0.0
        if zone < 0.0:
            ex = abs(tau) - 1.0
            if ex < 1.0:
                growth = math.log1p(ex + math.sqrt(ex * (ex + 2.0)))
            else:
                growth = log_tau + math.log1p(math.sqrt(-math.expm1(-2.0 * log_tau)))
        out[i, 0] = tau
        out[i, 1] = log_tau
        out[i, 2] = theta
        out[i, 3] = zone
        out[i, 4] = growth
        out[i, 5] = 0.0


@jit
def _level_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e, m):
    """``(level, tau, log|tau|)`` of one point, as :func:`_loop` with ``finish`` reads them: ``zone +
    1/2`` on a zone, ``theta / pi`` (a whole number) off the zones."""
    a, b, c, d, L, turn = _one(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, 8.0 * e * e, m * m, True)
    tau, log_tau = _half_trace(a, d, L)
    theta, zone = _rotation(tau, b, turn)
    return (zone + 0.5 if zone >= 0.0 else np.rint(theta / PI)), tau, log_tau


@jit
def _log_cosh(k):
    """:func:`kapitza._exact.log_cosh`."""
    if k < 1.0:
        return math.log1p(2.0 * math.sinh(0.5 * k) ** 2)
    return k + math.log1p(math.exp(-2.0 * k)) - LN2


@jit
def _excess_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e, m, zeta):
    """``G = log|tau_phi| - log cosh(kappa)`` at ``(e, m)`` with damping ratio ``zeta`` (the damping
    layer's ``_excess`` of a drive given by its shape)."""
    mc = m * math.sqrt(1.0 + zeta * zeta)
    a, _, _, d, L, _ = _one(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, 8.0 * e * e, mc * mc, False)
    return _half_trace(a, d, L)[1] - _log_cosh(2.0 * SQRT8 * zeta * m * e)


@jit
def _damped_level_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e, m, zeta):
    """``(level, tau / cosh(kappa))`` of one point with damping ratio ``zeta`` (``zeta > 0``), as the
    damping layer gives them without certification: the ``phi``-system at ``mu sqrt(1 + zeta^2)``;
    stable on its zones and where ``G = log|tau_phi| - log cosh(kappa) < 0``; a point stable in the
    gap ``theta = k pi`` in zone ``k - 1`` while ``G`` rises with ``eps`` (at ``eps (1 +- 1e-7)``),
    in zone ``k`` where it falls, in zone 0 below it."""
    kappa = 2.0 * SQRT8 * zeta * m * e
    lv, tau, log_tau = _level_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e, m * math.sqrt(1.0 + zeta * zeta))
    ratio = tau / math.cosh(kappa) if kappa < 700.0 else 0.0 * tau
    if lv != math.floor(lv):
        return lv, ratio
    if not log_tau - _log_cosh(kappa) < 0.0:
        return lv, ratio
    if lv <= 0.0:
        return 0.5, ratio
    step = 1e-7 * e
    up = _excess_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e + step, m, zeta)
    down = _excess_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e - step, m, zeta)
    return (lv - 1.0 if up > down else lv) + 0.5, ratio


@jit
def _row_test(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, kind, c0, c1, c2, n, op, fm, par, x, zeta):
    """``(ok, f)`` of one row of :func:`_rows` at the value ``x``."""
    if kind == 0:
        e, m = x, c0
    elif kind == 1:
        e, m = c0 * math.sqrt(x / c2), math.sqrt(c1 / x)
    else:
        e, m = c0, x
    if zeta > 0.0:
        lv, tau = _damped_level_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e, m, zeta)
    else:
        lv, tau, _ = _level_at(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, e, m)
    if op == 0:
        ok = lv >= n + 1.0
    elif op == 1:
        ok = lv > n
    elif op == 2:
        ok = lv < n + 1.0
    else:
        ok = lv <= n
    return ok, fm * (tau * par - 1.0)


@jit
def _rows(h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m, kind, c0, c1, c2, n, op, fm, fu, a, b, fa, fb, width,
          about, zeta):
    """Narrow each row's bracket ``[a, b]`` (bit patterns of non-negative doubles; the row's predicate
    False at ``a``, True at ``b``) on the engine's own verdicts, to at most ``width`` patterns, or to
    ``about`` patterns either side of the secant's estimate of the change: the point of value ``x``
    is ``(x, c0)`` (``kind`` 0, a line of ``eps``), ``(c0 sqrt(x / c2), sqrt(c1 / x))`` (1, a line of
    ``A``: ``c0 = T``, ``c1 = g``, ``c2 = 8 l``) or ``(c0, x)`` (2, a line of ``mu``), as
    :func:`kapitza.drives._api._line_points` gives them; the predicate on its
    level ``lv`` is ``lv >= n + 1``, ``lv > n``, ``lv < n + 1`` or ``lv <= n`` (``op`` 0 to 3), and
    ``f = fm (tau (-1)^(n + fu) - 1)`` changes sign with it about the change (NaN where not
    evaluated); with damping ratio ``zeta > 0`` the level and ``tau / cosh(kappa)`` of
    :func:`_damped_level_at`. Bisection on the patterns; once a bracket is within 2^-6 of its value and ``|f| < 1``
    at both ends, the two points ``about`` patterns either side of the secant's estimate of the change
    (the bracket left for the certified steps: the engine's change may lie a thousand patterns from
    the exact one where its trace is flat)."""
    bits = np.empty(1, np.int64)
    val = bits.view(np.float64)   # (a double and its bit pattern: the same eight bytes)
    coef = (h, p1, p2, p2m, q1, q2, r1, r2, r2m, r3, r3m)
    for i in range(a.size):
        lo = a[i]
        hi = b[i]
        f_lo = fa[i]
        f_hi = fb[i]
        same = 0
        last = 0
        par = 1.0 - 2.0 * ((n[i] + fu[i]) % 2)
        for _ in range(200):
            if hi - lo <= width:
                break
            x_bits = lo + (hi - lo) // 2
            pair = False
            if (same < 2 and hi - lo < (1 << 46) and f_lo < 0.0 and f_hi > 0.0
                    and f_lo > -1.0 and f_hi < 1.0):
                bits[0] = lo
                xa = val[0]
                bits[0] = hi
                xb = val[0]
                val[0] = xa + (xb - xa) * (f_lo / (f_lo - f_hi))
                if lo < bits[0] < hi:
                    x_bits = bits[0]
                    pair = hi - lo > 2 * about + 2
            for j in range(2 if pair else 1):   # (the secant's pair, or one point)
                y_bits = x_bits if not pair else (max(x_bits - about, lo + 1) if j == 0 else
                                                  min(x_bits + about, hi - 1))
                if not lo < y_bits < hi:
                    continue
                bits[0] = y_bits
                ok, f = _row_test(*coef, kind[i], c0[i], c1[i], c2[i], n[i], op[i], fm[i], par, val[0], zeta)
                if ok:
                    hi = y_bits
                    f_hi = f
                    same = same + 1 if last == 1 else 1
                    last = 1
                else:
                    lo = y_bits
                    f_lo = f
                    same = same + 1 if last == -1 else 1
                    last = -1
            if pair:
                if hi - lo <= 2 * about + 2:
                    break
                same = 0
                last = 0
        a[i] = lo
        b[i] = hi
        fa[i] = f_lo
        fb[i] = f_hi


def coefficients(grid):
    """The real steps' coefficient arrays of ``grid``, contiguous (made once per grid)."""
    coef = grid.__dict__.get("_real")
    if coef is None:
        m = grid.m
        coef = grid._real = tuple(np.ascontiguousarray(getattr(grid, k)[:m])
                                  for k in ("h", "p1", "p2", "p2m", "q1", "q2", "r1", "r2", "r2m", "r3", "r3m"))
    return coef


def narrow_rows(grid, kind, c0, c1, c2, n, op, fm, fu, lo, hi, width, about, zeta=0.0):
    """:func:`_rows` on ``grid``: ``(lo, hi, f_lo, f_hi)``, the brackets (doubles) within ``width``
    patterns or ``about`` either side of the secant's estimate, and ``f`` at their ends (NaN where
    not evaluated)."""
    a, b = np.array(lo, float).view(np.int64), np.array(hi, float).view(np.int64)
    fa, fb = np.full(a.size, np.nan), np.full(a.size, np.nan)
    f64 = np.ascontiguousarray
    _rows(*coefficients(grid), f64(kind, np.int64), f64(c0, float), f64(c1, float), f64(c2, float), f64(n, float),
          f64(op, np.int64), f64(fm, float), f64(fu, float), a, b, fa, fb, np.int64(width), np.int64(about),
          float(zeta))
    return a.view(np.float64), b.view(np.float64), fa, fb


def available() -> bool:
    """Whether the compiled loop runs (numba installed)."""
    return numba is not None


def warm() -> None:
    """Load the loop's and the rows' compiled code (from numba's cache, compiled there the first time)."""
    z = np.zeros(1)
    _loop(z, z, z, z, z, z, z, z, z, z, z, z + 0.5, z + 0.3, True, True, np.empty((1, 6)))
    k = np.zeros(1, np.int64)
    a, b = np.array([0.5]).view(np.int64), np.array([1.0]).view(np.int64)
    _rows(z, z, z, z, z, z, z, z, z, z, z, k, z + 0.3, z, z, z, k, z + 1.0, z, a, b, z + np.nan, z + np.nan,
          np.int64(1 << 36), np.int64(1 << 16), 0.1)


def run(grid, eps, mu, angle=True, finish=False):
    """``out`` of :func:`_loop` at flat ``eps, mu`` on ``grid``, shape ``(P, 6)``."""
    coef = coefficients(grid)
    out = np.empty((eps.size, 6))
    _loop(*coef, np.ascontiguousarray(eps, float), np.ascontiguousarray(mu, float), bool(angle), bool(finish), out)
    return out
