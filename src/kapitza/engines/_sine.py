"""The sine drive's two double-precision kernels, compiled (numba, the ``fast`` extra).

- :func:`continuant`: Hill's continuant of :func:`kapitza.drives._mathieu._continuant`, the same
  pairwise product of the steps' 2x2 matrices, renormalised at each level, one row at a time;
- :func:`half_period_steps`: the Taylor steps of :func:`kapitza.drives._mathieu._half_period_steps`
  (the maps and the rescaled state; its error bound ``"quick"`` or none), one point at a time;
- :func:`count`: the Sturm counts of :func:`kapitza.drives._mathieu._count` in doubles, one point
  at a time (the same pivots, and the same rows at which a count is known to be final).

Each is the numpy kernel's own arithmetic in the same order, without numpy's calls on arrays of a
few points: a test runs both against each other. Logarithms, cosines and sines come from the
C library here and from numpy's vector routines there, so results may differ in their last bits
(the verdicts near an edge are decided in extended precision by either path).
"""
from __future__ import annotations

import math

import numpy as np

from ._compiled import numba

# (numpy's error model: a float divided by zero is an infinity, as in the numpy kernels, not an error)
jit = numba.njit(cache=True, nogil=True, error_model="numpy") if numba is not None else (lambda f: f)


@jit
def _nanmax(x, y):
    """``np.maximum``: NaN if either is."""
    if x != x or y != y:
        return math.nan
    return x if x >= y else y


@jit
def _continuant_row(p, size, a, b, c, d, logs):
    n = p.size
    for i in range(size):
        a[i] = 1.0
        b[i] = 0.0
        c[i] = 0.0
        d[i] = 1.0
        logs[i] = 0.0
    for i in range(n):
        b[i] = -p[i]
        c[i] = 1.0
        d[i] = 0.0
    width = size
    first = True
    while width > 1:
        half = width // 2
        for k in range(half):
            a0, b0, c0, d0 = a[2 * k], b[2 * k], c[2 * k], d[2 * k]
            a1, b1, c1, d1 = a[2 * k + 1], b[2 * k + 1], c[2 * k + 1], d[2 * k + 1]
            na = a1 * a0 + b1 * c0
            nb = a1 * b0 + b1 * d0
            nc = c1 * a0 + d1 * c0
            nd = c1 * b0 + d1 * d0
            scale = _nanmax(_nanmax(_nanmax(abs(na), abs(nb)), abs(nc)), abs(nd))
            if not scale > 0.0:
                scale = 1.0
            a[k] = na / scale
            b[k] = nb / scale
            c[k] = nc / scale
            d[k] = nd / scale
            log_scale = math.log(scale)
            logs[k] = log_scale if first else logs[2 * k] + logs[2 * k + 1] + log_scale
        width = half
        first = False
    return a[0] + b[0], logs[0]


@jit
def _continuants(p, size, D, L):
    rows = p.shape[0]
    a = np.empty(size)
    b = np.empty(size)
    c = np.empty(size)
    d = np.empty(size)
    logs = np.empty(size)
    for r in range(rows):
        D[r], L[r] = _continuant_row(p[r], size, a, b, c, d, logs)


def continuant(p):
    """:func:`kapitza.drives._mathieu._continuant` of ``p`` (shape ``(..., N)``, ``N >= 2``)."""
    p = np.asarray(p, float)
    n = p.shape[-1]
    size = 1 << max(n - 1, 0).bit_length()
    flat = np.ascontiguousarray(p.reshape(-1, n))
    D, L = np.empty(flat.shape[0]), np.empty(flat.shape[0])
    _continuants(flat, size, D, L)
    return D.reshape(p.shape[:-1]), L.reshape(p.shape[:-1])


@jit
def _steps(qq, mm, m, h, scale, sign, terms, y_out, dy_out, logs_big):
    b = qq.size
    C = np.empty(terms)
    Y = np.empty((terms + 2, 2))
    for i in range(b):
        y0, y1 = 1.0, 0.0      # y of the solutions from (1, 0) and from (0, 1)
        dy0, dy1 = 0.0, 1.0
        base = 2.0 * qq[i] * mm[i] * mm[i]
        for j in range(m):
            cj = math.cos(2.0 * j * h)
            sj = math.sin(2.0 * j * h)
            for k in range(terms):
                trig = cj if k % 2 == 0 else sj
                C[k] = scale[k, i] * (trig * sign[k % 4])
            C[0] += base
            Y[0, 0] = 1.0
            Y[0, 1] = 0.0
            Y[1, 0] = 0.0
            Y[1, 1] = h
            for k in range(terms):
                f = h * h / ((k + 1) * (k + 2))
                for col in range(2):
                    acc = 0.0
                    for s in range(k + 1):
                        acc += C[s] * Y[k - s, col]
                    Y[k + 2, col] = acc * f
            ty0 = 0.0
            ty1 = 0.0
            td0 = 0.0
            td1 = 0.0
            for k in range(terms + 2):
                ty0 += Y[k, 0]
                ty1 += Y[k, 1]
                td0 += k * Y[k, 0]
                td1 += k * Y[k, 1]
            td0 /= h
            td1 /= h
            # (y, y') <- the map applied to each solution's state
            ny0 = ty0 * y0 + ty1 * dy0
            ny1 = ty0 * y1 + ty1 * dy1
            nd0 = td0 * y0 + td1 * dy0
            nd1 = td0 * y1 + td1 * dy1
            big = _nanmax(_nanmax(abs(ny0), abs(ny1)), _nanmax(abs(nd0), abs(nd1)))
            y0 = ny0 / big
            y1 = ny1 / big
            dy0 = nd0 / big
            dy1 = nd1 / big
            logs_big[j, i] = math.log(big)
        y_out[i, 0] = y0
        y_out[i, 1] = y1
        dy_out[i, 0] = dy0
        dy_out[i, 1] = dy1


def half_period_steps(qq, mm, m, scale, sign, h):
    """``(y, dy, logs_big)`` of :func:`kapitza.drives._mathieu._half_period_steps` without the running
    bound: the states (shape ``(points, 2)``) after the ``m`` steps of length ``h`` and each step's
    rescaling logarithm (shape ``(m, points)``). ``scale``: the coefficients ``2q (2h)^k / k!``,
    shape ``(terms, points)``; ``sign``: the four signs of the trigonometric factor."""
    qq = np.ascontiguousarray(qq, float)
    b = qq.size
    y, dy, logs = np.empty((b, 2)), np.empty((b, 2)), np.empty((m, b))
    _steps(qq, np.ascontiguousarray(mm, float), int(m), float(h), np.ascontiguousarray(scale, float),
           np.ascontiguousarray(sign, float), scale.shape[0], y, dy, logs)
    return y, dy, logs


@jit
def _counts(off, shift, first, q, x, pivmin, out):
    for i in range(q.size):
        o = off[i]
        q2 = q[i] * q[i]
        xi = x[i]
        d = o * o + shift[i] * q[i] - xi
        if d == 0.0:
            d = -pivmin
        cnt = 1 if d < 0.0 else 0
        e2 = first[i] * q2
        r = 1
        # (a pivot that comes out exactly zero makes the next one -inf, counted, as in the numpy form)
        while True:
            t = o + 2.0 * r
            Dr = t * t - xi
            d = Dr - e2 / d
            if d < 0.0:
                cnt += 1
            e2 = q2
            if r % 4 == 0 or r == 2:
                t = t + 2.0
                if Dr > 0.0 and d >= 0.5 * Dr and (t * t - xi) * Dr >= 4.0 * q2:
                    out[i] = cnt
                    break
            r += 1


def count(off, shift, first, q, x, pivmin):
    """The Sturm counts of :func:`kapitza.drives._mathieu._count` at flat double arrays (each point's
    family given by its diagonal offset, shift and first off-diagonal factor)."""
    out = np.zeros(q.size, np.int64)
    c = np.ascontiguousarray
    _counts(c(off, float), c(shift, float), c(first, float), c(q, float), c(x, float), float(pivmin), out)
    return out


def warm() -> None:
    """Load both kernels' compiled code (from numba's cache, compiled there the first time)."""
    continuant(np.full((1, 3), 0.01))
    half_period_steps(np.array([0.1]), np.array([0.3]), 2, np.ones((3, 1)), np.ones(4), 0.5)
    one = np.ones(1)
    count(one, one, one, one, one, 1e-290)
