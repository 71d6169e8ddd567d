"""Exact, cancellation-free kernels shared by the zone, propagation and
periodic-solution modules. Inputs are trusted (validated by the callers).

Notation (``docs/theory.md``): ``x = w_h T``, ``u = w_e T``, ``D = w_h / w_e``,
``s4 = sqrt(1 - mu^4)``. The two angles of Theorems 3.3-3.4 are

    alpha = 2 atan(D tanh(x/2)),     beta = 2 atan(D coth(x/2)),

with half-sum and half-difference

    gamma = (alpha + beta)/2 = pi/2 + atan(mu^2 tanh(x) / s4),
    delta = (beta - alpha)/2 = atan(s4 / sinh(x)).

With ``tau = tr M / 2`` the trace of the monodromy factors exactly::

    tau     = -sin(u - gamma) / sin(delta)
    tau - 1 = -2 sin((u - alpha)/2) cos((u - beta)/2) / sin(delta)
    tau + 1 = -2 cos((u - alpha)/2) sin((u - beta)/2) / sin(delta)

(substitute ``tan(u/2)`` and ``t = tanh(x/2)`` in
``2 cosh x cos u + (D - 1/D) sinh x sin u``; the numerators factor as
``(tan(u/2) - D t)(tan(u/2) + t/D)`` and ``(D t tan(u/2) + 1)(t tan(u/2)/D - 1)``).
The zeros of the factors are exactly the conditions (3.10)-(3.13), and no
``e^x``-sized terms are ever subtracted.
"""
from __future__ import annotations

import numpy as np

SQRT2 = np.sqrt(2.0)
LOG2 = np.log(2.0)
PI = np.pi


def gap_of_turn(turn, negative):
    """``k`` of the gap ``theta = k pi`` of an unstable point from the turn of any direction over the
    period: it lies within ``pi`` of ``k pi`` (the circle map keeps the order between its two fixed
    directions), and ``k`` is odd where the multipliers are ``negative`` (``tr M < 0``), even
    elsewhere: of the two integers about ``turn / pi``, the one of that parity."""
    k0 = np.floor(turn / PI)
    return np.where((np.remainder(k0, 2.0) == 1.0) == negative, k0, k0 + 1.0)


def s4_of(mu):
    """sqrt(1 - mu^4) with full relative accuracy as mu -> 1."""
    return np.sqrt((1.0 - mu) * (1.0 + mu) * (1.0 + mu * mu))


def alpha_x(x, D):
    """alpha = 2 atan(D tanh(x/2)) (section 4 of the paper)."""
    return 2.0 * np.arctan(D * np.tanh(0.5 * x))


def beta_x(x, D):
    """beta = 2 atan(D coth(x/2)); atan2 keeps x -> 0 exact (beta -> pi)."""
    return 2.0 * np.arctan2(D, np.tanh(0.5 * x))


def dalpha_dx(x, D):
    """d alpha/dx = 2D / ((1 + D^2) cosh x + 1 - D^2); 0 where cosh overflows."""
    with np.errstate(over="ignore"):
        return 2.0 * D / ((1.0 + D * D) * np.cosh(x) + 1.0 - D * D)


def dbeta_dx(x, D):
    """d beta/dx = -2D / ((1 + D^2) cosh x + D^2 - 1); 0 where cosh overflows."""
    with np.errstate(over="ignore"):
        return -2.0 * D / ((1.0 + D * D) * np.cosh(x) + D * D - 1.0)


def dgamma_dx(x, mu, s4):
    """d gamma/dx = mu^2 s4 sech^2 x / (s4^2 + mu^4 tanh^2 x) (tiny for large x)."""
    with np.errstate(over="ignore"):
        sech2 = 1.0 / np.cosh(x) ** 2
    th = np.tanh(x)
    return mu * mu * s4 * sech2 / (s4 * s4 + mu**4 * th * th)


def log_sinh(x):
    """log(sinh x) for x > 0, without overflow."""
    big = x > 20.0
    small = np.log(np.sinh(np.where(big, 1.0, x)))
    large = x - LOG2 + np.log1p(-np.exp(-2.0 * np.where(big, x, 21.0)))
    return np.where(big, large, small)


def delta_x(x, s4):
    """Half-width delta = (beta - alpha)/2 = atan(s4 / sinh x), as atan2 (no overflow)."""
    with np.errstate(over="ignore"):
        return np.arctan2(s4, np.sinh(x))


def log_sin_delta(x, s4):
    """log sin(delta) = log s4 - log sqrt(sinh^2 x + s4^2), finite for every x > 0."""
    ls = log_sinh(x)
    with np.errstate(over="ignore", under="ignore"):
        corr = np.log1p(s4 * s4 * np.exp(-2.0 * np.maximum(ls, -300.0)))
    return np.log(s4) - ls - 0.5 * corr


def gamma_x(x, mu, s4):
    """Centre gamma = (alpha + beta)/2 = pi/2 + atan(mu^2 tanh x / s4) (= pi - atan2(s4, mu^2 tanh x))."""
    return 0.5 * PI + np.arctan(mu * mu * np.tanh(x) / s4)


def reduced(u):
    """Zone candidate ``n = floor(u / pi)`` and ``w = u - n pi`` in [0, pi)."""
    n = np.floor(u / PI)
    return n, u - n * PI


# Taylor coefficients of (tan z - z)/z^3 = sum c_k z^(2k); (y - tanh y)/y^3 = sum (-1)^k c_k y^(2k)
# (from tan's series, mpmath at 40 digits). They fall like (2/pi)^(2k): 30 terms reach 1e-17 of
# the sum at z = 0.8, below which the series is used; above it tan z - z loses at most a factor
# tan z / (tan z - z) < 4.5 of tan's own rounding.
_TAN3 = np.array([0.3333333333333333, 0.13333333333333333, 0.05396825396825397, 0.021869488536155203,
                  0.008863235529902197, 0.003592128036572481, 0.0014558343870513183, 0.000590027440945586,
                  0.00023912911424355248, 9.691537956929451e-05, 3.927832388331683e-05,
                  1.5918905069328964e-05, 6.451689215655431e-06, 2.6147711512907546e-06,
                  1.0597268320104654e-06, 4.294911078273806e-07, 1.7406618963571648e-07,
                  7.054636946400968e-08, 2.859136662305254e-08, 1.1587644432798853e-08,
                  4.6962953982309016e-09, 1.903336833931276e-09, 7.713933635359062e-10,
                  3.126339545892087e-10, 1.26705769303054e-10, 5.135191408039368e-11,
                  2.0812146867700473e-11, 8.434845419094337e-12, 3.4185140868111557e-12,
                  1.385471574294847e-12])
_TAN3_SWITCH = 0.8


_TAN3_REVERSED = _TAN3[::-1].tolist()


def _series(w):
    """``sum_k c_k w^k`` over :data:`_TAN3` by Horner's rule. A few points are summed in Python
    floats (the same IEEE operations, a multiply then an add, so the same bits as the array
    path) to spare sixty array calls on arrays of one or two points."""
    if w.size <= 8:
        out = []
        for x in w.tolist():
            acc = 0.0
            for c in _TAN3_REVERSED:
                acc = acc * x + c
            out.append(acc)
        return np.array(out, dtype=float)
    acc = np.zeros_like(w)
    for c in _TAN3_REVERSED:
        acc = acc * w + c
    return acc


def tan3(z, sign):
    """(tan z - z)/z^3 (sign=+1) or (z - tanh z)/z^3 (sign=-1), accurate for small z."""
    z = np.asarray(z, dtype=float)
    zc = np.minimum(z, _TAN3_SWITCH)  # the series only where it is used (no overflow beyond)
    series = _series((sign * zc * zc).ravel()).reshape(z.shape)
    near = z > _TAN3_SWITCH
    if not np.any(near):
        return series
    zs = np.where(near, z, 1.0)
    direct = (np.tan(zs) - zs) / zs**3 if sign > 0 else (zs - np.tanh(zs)) / zs**3
    return np.where(near, direct, series)


def sin_half_a0(u, D, mu, d2m1=None):
    """sin((u - alpha)/2) on zone 0's branch (``n = 0``) for small ``u``, free of cancellation.

    ``sin(z - atan(D t)) = cos z cos(atan(D t)) (tan z - D t)`` with ``z = u/2``,
    ``t = tanh(D z)``, and ``tan z - D t = z^3 [T3(z) + D^4 H3(D z)] - z (D^2 - 1)``
    (``T3``, ``H3`` as in :func:`tan3`; ``D^2 - 1 = 2 mu^2 / (1 - mu^2)`` exactly). The
    direct ``u - alpha`` subtracts two numbers of size ``u`` whose difference is
    ``O(u max(mu^2, u^2))``. ``d2m1 = D^2 - 1`` may be passed instead of ``mu`` where it is
    known better (``kappa / u^2`` along ``A`` at fixed ``T``).
    """
    z = 0.5 * u
    y = D * z
    if d2m1 is None:
        d2m1 = 2.0 * mu * mu / ((1.0 - mu) * (1.0 + mu))
    diff = z**3 * (tan3(z, 1) + D**4 * tan3(y, -1)) - z * d2m1
    Dt = D * np.tanh(y)
    return diff * np.cos(z) / np.sqrt(1.0 + Dt * Dt)


def lower_gap(x, u, w, n, D, mu):
    """``a = w - alpha(x)``: > 0 above the lower edge of zone ``n = floor(u/pi)``.

    On zone 0's branch at small ``u`` (where ``u`` and ``alpha`` nearly cancel) ``a`` is
    taken from :func:`sin_half_a0`, so that the verdict near zone 0's lower edge is
    right as ``mu -> 0`` and ``a`` keeps its relative accuracy as ``eps -> 0``.
    """
    a = w - alpha_x(x, D)
    small = (n == 0) & (u < 1.0) & (np.abs(a) < 2.0)
    idx = np.flatnonzero(small)
    if idx.size:
        # only the points on that branch (a few percent of a chart) pay for the series
        a = np.array(a, dtype=float)
        uu, DD, mm = (np.broadcast_to(v, a.shape).ravel()[idx] for v in (u, D, mu))
        s = sin_half_a0(uu, DD, mm)
        a.ravel()[idx] = 2.0 * np.arcsin(np.clip(s, -1.0, 1.0))
    return a


def acosh_excess(e):
    """acosh(1 + e) for e >= 0, accurate for small e."""
    return np.log1p(e + np.sqrt(e * (e + 2.0)))


def floquet_elliptic(x, u, D, mu):
    """Floquet data for ``0 < mu < 1`` (there is an elliptic phase).

    Returns
    -------
    n : float ndarray
        ``floor(u / pi)``; the zone index where the point is stable.
    a, b : ndarray
        ``a = w - alpha``, ``b = w - beta`` with ``w = u - n pi``; stable iff ``a > 0 > b``
        (``docs/theory.md`` section 5).
    tau : ndarray
        Half-trace ``tr M / 2`` (``+-inf`` where it overflows a double).
    growth : ndarray
        ``log max|lambda|`` per period, finite for every input; 0 on the zones.
    theta : ndarray
        Rotation angle per period: ``n pi + 2 asin(sqrt(zeta/2))`` on zone ``n``,
        locked to ``n pi`` (below zone n) or ``(n + 1) pi`` (above) off the zones.
    """
    n, w = reduced(u)
    a = lower_gap(x, u, w, n, D, mu)
    b = w - beta_x(x, D)
    s4 = s4_of(mu)
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        sd = np.sin(delta_x(x, s4))
        lsd = log_sin_delta(x, s4)
        # -sin(u - gamma) = sin(u + pi - gamma), pi - gamma = atan2(s4, mu^2 tanh x): as mu -> 1
        # gamma -> pi and u -> 0, and forming u - gamma would leave only ulp(pi) / |u - gamma + pi|.
        num = np.sin(u + np.arctan2(s4, mu * mu * np.tanh(x)))
        tau = np.where(sd > 0, num / np.where(sd > 0, sd, 1.0), np.copysign(np.inf, num))
        # P has the sign of a, Q the sign of b (|a/2|, |b/2| < pi/2 so the cosines are > 0).
        # n even: tau - 1 = -P, tau + 1 = -Q;  n odd: tau - 1 = Q, tau + 1 = P.
        sdp = np.where(sd > 0, sd, np.inf)
        # cos(b/2) = sin((w + pi - beta)/2): accurate where b is near -pi (x and w small).
        cos_half_b = np.sin(0.5 * (w + 2.0 * np.arctan2(np.tanh(0.5 * x), D)))
        P = 2.0 * np.sin(0.5 * a) * cos_half_b / sdp
        Q = 2.0 * np.cos(0.5 * a) * np.sin(0.5 * b) / sdp
    stable = (a > 0) & (b < 0)
    below = a <= 0
    # Off the zones |tau| - 1 is -P below zone n and Q above it, for either parity.
    excess = np.where(below, -P, Q)
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        log_abs_tau = np.log(np.abs(num)) - lsd
        big = log_abs_tau + np.log1p(np.sqrt(-np.expm1(-2.0 * np.maximum(log_abs_tau, 0.0))))
        small = acosh_excess(np.where((excess >= 0) & (excess < 1.0), excess, 0.0))
    use_small = (excess < 1.0) & (sd > 1e-300)
    growth = np.where(stable, 0.0, np.where(use_small, small, big))
    growth = np.maximum(growth, 0.0)
    zeta = np.clip(P, 0.0, 2.0)
    theta = np.where(
        stable,
        n * PI + 2.0 * np.arcsin(np.sqrt(0.5 * zeta)),
        np.where(below, n * PI, (n + 1.0) * PI),
    )
    return n, a, b, tau, growth, theta


def floquet_hyperbolic(x, v):
    """Half-trace and growth when ``A <= g``: both phases hyperbolic (``v >= 0``), or the
    second is free flight (``v = 0``).

    ``tau = cosh x cosh v + (x^2 + v^2)/(2x) sinh x sinh(v)/v > 1``; the excess
    ``tau - 1 = 2 sinh^2(x/2) cosh v + 2 sinh^2(v/2) + (x^2 + v^2)/(2x) sinh x sinh(v)/v``
    is a sum of positive terms, and ``log tau`` is formed with ``e^{-x}``, ``e^{-v}``
    only, so the growth stays finite for every input.
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        vs = np.where(v > 0, v, 1.0)
        shc_v = np.where(v > 0, np.sinh(vs) / vs, 1.0)
        cfac = 0.5 * (x + v * (v / x))  # (x^2 + v^2)/(2x), without squaring x (x may be ~1e154)
        excess = 2.0 * np.sinh(0.5 * x) ** 2 * np.cosh(v) + 2.0 * np.sinh(0.5 * v) ** 2 + cfac * np.sinh(x) * shc_v
        ex = np.exp(-2.0 * x)
        ev = np.exp(-2.0 * v)
        one_minus_ev_over_v = np.where(v > 0, -np.expm1(-2.0 * vs) / vs, 2.0)
        log_tau = x + v - 2.0 * LOG2 + np.log((1.0 + ex) * (1.0 + ev) + cfac * (1.0 - ex) * one_minus_ev_over_v)
        tau = np.where(np.isfinite(excess), 1.0 + excess, np.inf)
        big = log_tau + np.log1p(np.sqrt(-np.expm1(-2.0 * log_tau)))
        small = acosh_excess(np.where(excess < 1.0, excess, 0.0))
    growth = np.where(excess < 1.0, small, big)
    # x and v below 1e-150: the excess x^2 + v^2 + O(x^4) leaves the normal doubles, and the growth
    # sqrt(2 excess) is sqrt(2) hypot(x, v) to far below rounding
    growth = np.where(np.maximum(x, v) < 1e-150, SQRT2 * np.hypot(x, v), growth)
    # x or v beyond a double (eps mu > 1e308): the growth, about x + v, is too
    growth = np.where(np.isinf(x) | np.isinf(v), np.inf, growth)
    return tau, growth


def illinois(F, a, b, iterations=60, ulps=4.0):
    """Roots of ``F`` on the brackets ``[a, b]`` (arrays; ``F(a)`` and ``F(b)`` of opposite
    signs), by the Illinois variant of regula falsi, vectorised: superlinear, never leaving the
    bracket, about ten evaluations of ``F`` to a few ulp (it stops once the bracket is ``ulps``
    units of the iterate wide, or makes no progress). Returns the last iterate."""
    a, b = np.array(a, float), np.array(b, float)
    fa, fb = F(a), F(b)
    # no sign change: nothing to find there (the caller decides what that means)
    done = (fa == 0) | (fb == 0) | (np.sign(fa) == np.sign(fb))
    root = np.where(fa == 0, a, b)
    for _ in range(iterations):
        with np.errstate(divide="ignore", invalid="ignore"):
            c = b - fb * (b - a) / (fb - fa)
        bad = ~np.isfinite(c) | (c <= np.minimum(a, b)) | (c >= np.maximum(a, b))
        c = np.where(bad, 0.5 * (a + b), c)  # a step outside the bracket: bisect instead
        fc = F(c)
        flip = np.sign(fc) != np.sign(fb)
        stuck = c == b  # rounding noise of F reached: no further progress
        a, fa = np.where(flip, b, a), np.where(flip, fb, 0.5 * fa)
        b, fb = c, fc
        root = np.where(done, root, c)
        done |= (fc == 0) | stuck | (np.abs(b - a) <= ulps * np.finfo(float).eps * np.abs(c))
        if done.all():
            break
    return root


# ---------------------------------------------------------------- shared by every drive
def log_cosh(k):
    """log cosh k for k >= 0 without overflow, to a few ulp relative (``log1p(2 sinh^2(k/2))`` below 1)."""
    with np.errstate(over="ignore"):
        small = np.log1p(2.0 * np.sinh(0.5 * np.minimum(k, 1.0)) ** 2)
    return np.where(k < 1.0, small, k + np.log1p(np.exp(-2.0 * k)) - LOG2)


def acosh_from_log(log_tau, tau):
    """acosh|tau| for |tau| >= 1 from ``log|tau|`` (finite where ``tau`` overflows)."""
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        e = np.abs(tau) - 1.0
        small = np.log1p(np.where((e >= 0) & (e < 1.0), e + np.sqrt(np.abs(e) * (e + 2.0)), 0.0))
        big = log_tau + np.log1p(np.sqrt(-np.expm1(-2.0 * np.maximum(log_tau, 0.0))))
    return np.where(e < 1.0, small, big)
