"""One parameter set of the paper's undamped square wave in Python floats.

:func:`kapitza.analyze` answers one point; on one-element arrays numpy spends most of its
time on the overhead of each call (a Newton solve or a regula falsi is a few hundred of them).
The functions here are the scalar twins of the array kernels :func:`analyze` uses -- the same
formulas, closed forms and iterations, in the same order of operations, on ``float`` with
:mod:`math` -- and each one's answer is compared with its array twin's on thousands of points
(``tests/test_point_twins.py``). They differ from the array kernels only by the rounding of
the elementary functions (``math`` against numpy's vectorised ones, each good to an ulp or
two), never in a decision:

* the verdict keeps its certificate: wherever the array kernels would consult their rounding
  bound (:mod:`kapitza._certify`, :func:`kapitza._square._verdict`), the scalar twin does not
  decide and the caller takes the array path, which decides there in extended precision;
* likewise every other decision taken on rounded numbers (which zone is nearer, whether a
  frequency interval has ends, the 1:4 and 1:3 crossings, a vanishing twist, Markeev's
  comparison, the rounding estimate that sends a point to the averaged or extended-precision
  normal form) is left to the array path wherever the scalar value lies near its threshold;
* where a number is ill-conditioned -- the rotation angle or the growth near an edge or in a
  thin zone (:func:`_conditioned`), the twist where the jets' terms cancel -- its trailing
  printed digits are rounding noise in either path, and the array path gives it, so that the
  report prints the digits it always printed.

Each function returns ``None`` (or raises :class:`Careful`) where the array path must answer;
a float that leaves the doubles (``math`` raises where numpy returns ``inf``) does the same.
"""
from __future__ import annotations

import cmath
import math

from . import _certify
from . import _square
from ._exact import _TAN3_REVERSED, _TAN3_SWITCH

PI = math.pi
SQRT8 = math.sqrt(8.0)
LOG2 = math.log(2.0)
_EPS = float(_square._EPS)
# the array kernels' own constants (one definition each), as Python floats
_TOL = float(_certify._TOL)
_MAX_NEWTON = int(_square._MAX_NEWTON)
_SMALL_MU = float(_square._SMALL_MU)
_MU_MIN = float(_square._MU_MIN)
_EPS_SERIES = float(_square._EPS_SERIES)
_TINY_MU = float(_square._TINY_MU)
_SQRT_3_2 = math.sqrt(1.5)
_INF = math.inf


class Careful(Exception):
    """This point needs the array path (a rounding bound is reached, or a float left the doubles)."""


#: What makes a twin decline a point (the array path then answers it).
_DECLINE = (Careful, OverflowError, ValueError, ZeroDivisionError)


def _elliptic_only(fn):
    """A twin of one point with ``0 < mu < 1``: None for ``mu >= 1`` or wherever it declines."""
    import functools

    @functools.wraps(fn)
    def twin(eps, mu):
        if not mu < 1.0:
            return None
        try:
            return fn(eps, mu)
        except _DECLINE:
            return None
    return twin


def _cosh(x):
    try:
        return math.cosh(x)
    except OverflowError:
        return _INF


def _sinh(x):
    try:
        return math.sinh(x)
    except OverflowError:
        return math.copysign(_INF, x)


def _sign(v):
    if v != v:
        raise Careful("NaN")
    return (v > 0.0) - (v < 0.0)


# ---------------------------------------------------------------- kernels of kapitza._exact
def alpha_x(x, D):
    return 2.0 * math.atan(D * math.tanh(0.5 * x))


def beta_x(x, D):
    return 2.0 * math.atan2(D, math.tanh(0.5 * x))


def dalpha_dx(x, D):
    return 2.0 * D / ((1.0 + D * D) * _cosh(x) + 1.0 - D * D)


def dbeta_dx(x, D):
    return -2.0 * D / ((1.0 + D * D) * _cosh(x) + D * D - 1.0)


def tan3(z, sign):
    """:func:`kapitza._exact.tan3` of one float."""
    if z > _TAN3_SWITCH:
        return (math.tan(z) - z) / z**3 if sign > 0 else (z - math.tanh(z)) / z**3
    w = sign * z * z
    acc = 0.0
    for c in _TAN3_REVERSED:
        acc = acc * w + c
    return acc


def sin_half_a0(u, D, mu, d2m1=None):
    z = 0.5 * u
    y = D * z
    if d2m1 is None:
        d2m1 = 2.0 * mu * mu / ((1.0 - mu) * (1.0 + mu))
    diff = z**3 * (tan3(z, 1) + D**4 * tan3(y, -1)) - z * d2m1
    Dt = D * math.tanh(y)
    return diff * math.cos(z) / math.sqrt(1.0 + Dt * Dt)


def lower_gap(x, u, w, n, D, mu):
    a = w - alpha_x(x, D)
    if n == 0.0 and u < 1.0 and abs(a) < 2.0:
        s = sin_half_a0(u, D, mu)
        a = 2.0 * math.asin(min(max(s, -1.0), 1.0))
    return a


def log_sinh(x):
    if x > 20.0:
        return x - LOG2 + math.log1p(-math.exp(-2.0 * x))
    return math.log(math.sinh(x))


def phase_angles(eps, mu):
    """``(x, u, D)`` of :func:`kapitza.parameters._phase_angles` (``mu < 1``)."""
    p = math.sqrt(1.0 + mu * mu)
    q = math.sqrt((1.0 - mu) * (1.0 + mu))
    return SQRT8 * eps * p, SQRT8 * eps * q, p / q


def _unsure(u, a, b):
    """:func:`kapitza._certify.unsure` without its phase limit: beyond it too the array path
    answers (it lets the double verdict stand there), so that the two never differ."""
    bound = _TOL * (abs(u) + 4.0)
    return abs(a) <= bound or abs(b) <= bound


#: Largest relative rounding of the rotation angle (or the growth) the scalar path reports.
COND_MAX = 1e-13


def _conditioned(m, u, sd):
    """Raise :class:`Careful` where the angle ``m`` off an edge (``w`` or ``pi - w`` on a zone, the
    growth beside one) is known only to worse than :data:`COND_MAX` relative.

    ``a = w - alpha`` and ``b = w - beta`` carry about ``2 eps max(u, 1)`` absolute; near an edge
    ``P ~ a / sin(delta)`` and ``m ~ sqrt(2 P)``, so ``m`` is known to about
    ``2 eps max(u, 1) / (m^2 sin(delta))`` relative (an overestimate by one to two orders), in either
    path. Where that is large -- close to an edge, or anywhere in a thin zone, where
    ``sin(delta)`` is tiny -- the trailing digits of the rotation number, the growth and the
    nonlinear line are rounding noise, and the array path answers, with the digits it always gave.
    """
    if not 4.0 * _EPS * max(u, 1.0) <= COND_MAX * m * m * sd:
        raise Careful("the angle is ill-conditioned here")


# ---------------------------------------------------------------- kapitza._square._floquet
@_elliptic_only
def floquet(eps, mu):
    """``(tau, growth, theta, stable, zone)`` of :func:`kapitza._square._floquet`, or None
    where the array path must decide (``mu >= 1`` too, where no zone is to be had)."""
    x, u, D = phase_angles(eps, mu)
    n = float(math.floor(u / PI))
    w = u - n * PI
    t2 = math.tanh(0.5 * x)
    a = lower_gap(x, u, w, n, D, mu)
    b = w - 2.0 * math.atan2(D, t2)
    if _unsure(u, a, b):
        raise Careful("within the rounding bound of an edge")
    stable = a > 0.0 and b < 0.0
    s4 = math.sqrt((1.0 - mu) * (1.0 + mu) * (1.0 + mu * mu))
    sh = _sinh(x)
    sd = math.sin(math.atan2(s4, sh))
    num = math.sin(u + math.atan2(s4, mu * mu * math.tanh(x)))
    # the trace cancels (its bound _square._tau_error, about 16 u (u + 4) / sin(delta), is a large
    # part of it): the array path takes it from the exact product
    if _TOL * (u + 4.0) > _certify.TRACE_RTOL * abs(num) and bool(_certify.affordable(u, x)):
        raise Careful("the trace cancels here")
    tau = num / sd if sd > 0.0 else math.copysign(_INF, num)
    sdp = sd if sd > 0.0 else _INF
    cos_half_b = math.sin(0.5 * (w + 2.0 * math.atan2(t2, D)))
    P = 2.0 * math.sin(0.5 * a) * cos_half_b / sdp
    if stable:
        zeta = min(max(P, 0.0), 2.0)
        half = 2.0 * math.asin(math.sqrt(0.5 * zeta))
        _conditioned(min(half, PI - half), u, sd)
        theta = n * PI + half
        return tau, 0.0, theta, True, int(n)
    below = a <= 0.0
    if below:
        excess = -P
    else:
        excess = 2.0 * math.cos(0.5 * a) * math.sin(0.5 * b) / sdp
    if excess < 1.0 and sd > 1e-300:
        e = excess if excess >= 0.0 else 0.0
        growth = math.log1p(e + math.sqrt(e * (e + 2.0)))
        _conditioned(growth, u, sd)
    else:
        # log|tau| = log|num| - log sin(delta), kapitza._exact.log_sin_delta
        ls = log_sinh(x)
        corr = math.log1p(s4 * s4 * math.exp(-2.0 * max(ls, -300.0)))
        lsd = math.log(s4) - ls - 0.5 * corr
        log_abs_tau = math.log(abs(num)) - lsd
        growth = log_abs_tau + math.log1p(math.sqrt(-math.expm1(-2.0 * max(log_abs_tau, 0.0))))
    growth = max(growth, 0.0)
    if not growth > 0.0:
        raise Careful("an unstable point whose excess rounded to zero")
    theta = n * PI if below else (n + 1.0) * PI
    return tau, growth, theta, False, -1


def multipliers(tau, growth, theta, stable):
    """:func:`kapitza._square._multipliers` of one point."""
    if stable:
        return cmath.exp(1j * theta), cmath.exp(-1j * theta)
    sgn = -1.0 if tau < 0 else 1.0
    try:
        big = sgn * math.exp(growth)
    except OverflowError:
        big = sgn * _INF
    return complex(big), complex(sgn * math.exp(-growth))


# ---------------------------------------------------------------- kapitza.zones
def _verdict(eps, mu):
    """``(stable, n)`` of :func:`kapitza._square._verdict` (tan form, same rounding bound); raises
    :class:`Careful` inside the bound, where the array path decides in extended precision."""
    p = math.sqrt(mu * mu + 1.0)
    q = math.sqrt((1.0 - mu) * (1.0 + mu))
    y = eps * SQRT8
    u = y * q
    y = y * p * 0.5
    D = p / q
    t = math.tanh(y)
    n = float(math.floor(u * (1.0 / PI)))
    s = math.tan((n * -PI + u) * 0.5)
    bound = (u + n) * (4.0 * _EPS) * (s * s + 1.0) + s * (32.0 * _EPS)
    r = s - D * t
    g = D / t - s
    if min(abs(r), abs(g)) <= bound:
        raise Careful("within the rounding bound of an edge")
    return (r > 0.0 and g > 0.0), n


def _lower0_small_mu(mu):
    if mu < _TINY_MU:
        return 2.0 * math.sqrt(3.0) * mu
    d2m1 = 2.0 * mu * mu / ((1.0 - mu) * (1.0 + mu))
    D2 = 1.0 + d2m1
    D = math.sqrt(D2)

    def fixed(z):
        return math.sqrt(d2m1 / (tan3(z, 1) + D2 * D2 * tan3(D * z, -1)))

    z0 = math.sqrt(3.0 * d2m1 / (1.0 + D2 * D2))
    z1 = fixed(z0)
    h0 = z0 - z1
    for _ in range(60):
        h1 = z1 - fixed(z1)
        try:
            step = h1 * (z1 - z0) / (h1 - h0)
        except ZeroDivisionError:
            step = _INF
        if not math.isfinite(step):
            step = h1
        z0, h0, z1 = z1, h1, z1 - step
        if not abs(step) > 8.0 * _EPS * z1:
            break
    return 2.0 * fixed(z1)


def edge_u(mu, n, upper, q=None):
    """``(u, q)`` of :func:`kapitza._square._edge_u` for one ``mu`` and zone ``n``."""
    p = math.sqrt(1.0 + mu * mu)
    if q is None:
        q = math.sqrt((1.0 - mu) * (1.0 + mu))
    D = p / q
    npi = n * PI
    if not upper and n == 0 and mu < _SMALL_MU:
        return _lower0_small_mu(mu), q
    u = npi + 2.0 * math.atan(D)
    fn, dfn = (beta_x, dbeta_dx) if upper else (alpha_x, dalpha_dx)
    for _ in range(_MAX_NEWTON):
        x = D * u
        F = u - npi - fn(x, D)
        dF = 1.0 - D * dfn(x, D)
        step = F / dF
        u = u - step
        moving = (step < 0) if upper else (step > 0)
        if not (moving and abs(step) > 4.0 * _EPS * abs(u)):
            break
    return u, q


def edges_eps(mu, n, q=None):
    """``(eps_lo, eps_hi)`` of :func:`kapitza._square._edges_eps`."""
    ulo, q = edge_u(mu, n, False, q)
    uhi, _ = edge_u(mu, n, True, q)
    uhi = max(uhi, ulo)
    return ulo / (SQRT8 * q), uhi / (SQRT8 * q)


@_elliptic_only
def stability_margin(eps, mu):
    """``(stable, zone, eps_lo, eps_hi, margin)`` of :func:`kapitza.stability_margin` (square
    wave, undamped) for one point with ``0 < mu < 1``, or None where the array path answers."""
    u_all = SQRT8 * eps * math.sqrt(max((1.0 - mu) * (1.0 + mu), 0.0))
    if not u_all < 2.0**52:
        raise Careful("no zone resolvable")
    stable, n = _verdict(eps, mu)
    x, u, D = phase_angles(eps, mu)
    w = u - n * PI
    below = lower_gap(x, u, w, n, D, mu) <= 0
    nb = max(n - 1.0, 0.0) if below else n + 1.0
    lo_n, hi_n = edges_eps(mu, n)
    d_n = min(eps - lo_n, hi_n - eps)
    # the neighbour's edges matter only off the zones, and not below zone 0
    lo_b = hi_b = d_b = -_INF
    if not (stable or (below and n == 0)):
        lo_b, hi_b = edges_eps(mu, nb)
        d_b = min(eps - lo_b, hi_b - eps)
    # decisions the array path takes on the same numbers (which zone is nearer, which side of
    # an edge the point lies) are left to it where the edges' few ulp could turn them
    near = 16.0 * _EPS * eps
    if abs(d_n) <= near or (not stable and d_b > -_INF and (abs(d_b) <= near or abs(d_b - d_n) <= near)):
        raise Careful("as near an edge as the edges' rounding")
    use_b = (not stable) and d_b > d_n
    zone = nb if use_b else n
    lo, hi = (lo_b, hi_b) if use_b else (lo_n, hi_n)
    margin = (d_b if use_b else d_n) / eps
    tiny = 5e-324
    margin = max(margin, tiny) if stable else min(margin, -tiny)
    if not (math.isfinite(lo) and math.isfinite(hi) and math.isfinite(margin)):
        raise Careful("an edge left the doubles")
    return stable, int(zone), lo, hi, margin


def period_edges(A, n, l, g):
    """``(T_lo, T_hi)`` of :func:`kapitza.period_edges` (square wave, undamped, ``A > g``)."""
    mu = math.sqrt(g / A)
    lo, hi = edges_eps(mu, n, math.sqrt((A - g) / A))
    r = 8.0 * l / A
    scale = math.sqrt(r) if r > 1e-300 else SQRT8 * (math.sqrt(l) / math.sqrt(A))
    return lo * scale, hi * scale


def illinois(F, a, b, iterations=60, ulps=4.0):
    """:func:`kapitza._exact.illinois` for one bracket ``[a, b]``."""
    fa, fb = F(a), F(b)
    if fa == 0 or fb == 0 or _sign(fa) == _sign(fb):
        return a if fa == 0 else b
    for _ in range(iterations):
        try:
            c = b - fb * (b - a) / (fb - fa)
        except ZeroDivisionError:
            c = math.nan
        if not math.isfinite(c) or c <= min(a, b) or c >= max(a, b):
            c = 0.5 * (a + b)
        fc = F(c)
        flip = _sign(fc) != _sign(fb)
        stuck = c == b
        if flip:
            a, fa = b, fb
        else:
            fa = 0.5 * fa
        b, fb = c, fc
        if fc == 0 or stuck or abs(b - a) <= ulps * _EPS * abs(c):
            return c
    return c


def amplitude_edges(T, n, l, g):
    """``(A_lo, A_hi)`` of :func:`kapitza.amplitude_edges` (square wave, undamped)."""
    kappa = 2.0 * g * T * T / l
    if not 0.0 < kappa < _INF:  # kapitza._square._kappa
        kappa = 2.0 * g * (T / l) * T
    npi = n * PI

    def F(u, upper):
        x = math.sqrt(u * u + kappa)
        if x == 0.0:
            raise Careful("kappa underflowed")
        D = x / u if u != 0.0 else _INF
        f = u - npi - (beta_x(x, D) if upper else alpha_x(x, D))
        if not upper and n == 0 and u < 1.0 and abs(f) < 2.0:  # kapitza.zones.amplitude_edges
            s = sin_half_a0(u, D, None, kappa / u / u)
            f = 2.0 * math.asin(min(max(s, -1.0), 1.0))
        return f

    out = []
    for upper in (False, True):
        a, b = npi + 0.0, (n + 1.0) * PI
        if not upper and n == 0:
            guess = math.sqrt(math.sqrt(6.0) * math.sqrt(kappa))
            a0, b0 = min(0.5 * guess, 1.0), min(2.0 * guess, PI)
            if F(a0, False) < 0.0:
                a = a0
            if F(b0, False) > 0.0:
                b = b0
        u = illinois(lambda v: F(v, upper), a, b, ulps=1.0)
        r = u / T
        A = g + l * (r * r)
        if not math.isfinite(A):
            r = math.sqrt(l) * u / T
            A = g + r * r
        out.append(A)
    return out[0], out[1]


def square_rig_margins(eps, mu, zone, T, stroke):
    """:func:`kapitza._square.rig_margins` of one point."""
    n = float(zone)

    def gap(m, upper):
        p = math.sqrt(1.0 + m * m)
        q = math.sqrt((1.0 - m) * (1.0 + m))
        x, u = SQRT8 * eps * p, SQRT8 * eps * q
        D = p / q if q != 0.0 else _INF
        w = u - n * PI
        return w - beta_x(x, D) if upper else lower_gap(x, u, w, n, D, m)

    lo, hi = _MU_MIN, 1.0 - 1e-12
    lo_a = min(_MU_MIN, 0.5 * eps) if n == 0 else _MU_MIN
    out = dict(stroke=float(stroke))
    # the gaps carry a few ulp of u + n pi; a sign or an order within that is the array path's
    # (zone 0's lower gap is positive at lo_a: that edge lies below eps / 2 there)
    noise = 16.0 * _EPS * (SQRT8 * eps + n * PI + 4.0)
    g_lo, g_hi = gap(lo_a, False), gap(lo, True)
    if (n != 0 and abs(g_lo) <= noise) or abs(g_hi) <= noise:
        raise Careful("a zone edge at the end of the frequency range")
    series = n == 0 and eps < _EPS_SERIES  # (then g_lo may underflow; its sign is known)
    if g_lo <= 0.0 and not series:
        return out
    open_top = g_hi < 0.0
    if series:
        mu_a = eps / _SQRT_3_2
    else:
        mu_a = illinois(lambda m: gap(m, False), lo_a, hi, ulps=1.0)
    mu_b = 0.0 if open_top else illinois(lambda m: gap(m, True), lo, hi, ulps=1.0)
    if abs(mu_a - mu_b) <= 1e-8 * mu_a:
        raise Careful("a zone thinner than its edges' rounding in mu")
    if mu_b < mu_a:
        f = 0.5 / T
        out.update(frequency_lo=float(f * mu / mu_a), frequency_hi=float("inf") if open_top else float(f * mu / mu_b))
    return out


def rig_intervals(eps, mu, zone, T, A, l, g):
    """The physical intervals of :func:`kapitza.analyze` for zone ``zone`` (``0 < mu < 1``), or None."""
    try:
        Tlo, Thi = period_edges(A, zone, l, g)
        Alo, Ahi = amplitude_edges(T, zone, l, g)
        stroke = 0.25 * A * T * T
        out = dict(T_lo=Tlo, T_hi=Thi, A_lo=Alo, A_hi=Ahi,
                   stroke_lo=stroke * Alo / A, stroke_hi=stroke * Ahi / A)
        out.update(square_rig_margins(eps, mu, zone, T, stroke))
    except _DECLINE:
        return None
    if not all(math.isfinite(v) for k, v in out.items() if k != "frequency_hi"):
        return None
    return out


# ---------------------------------------------------------------- kapitza.normal_form
#: The scalar normal form answers only where its own rounding estimate (the area defect) is
#: below this; the array path's threshold for its extended-precision forms is 1e-9
#: (:data:`kapitza.normal_form._DEFECT_MP`), so between the two the array path answers, with
#: the numbers it always gave.
DEFECT_MAX = 1e-12
#: A scalar value this close to a threshold of the nonlinear verdict leaves the decision to
#: the array path (the two differ by the rounding of the elementary functions only, a few ulp).
_NEAR_CURVE = 1e-12
#: Largest relative rounding of the twist the scalar normal form reports.
TWIST_REL = 1e-12
_NEAR_TWIST = 4e-12

_SER_LISTS = None


def _ser_lists():
    global _SER_LISTS
    if _SER_LISTS is None:
        from .normal_form import SERIES

        _SER_LISTS = tuple(SERIES[name].tolist() for name in ("c", "sh", "f1", "f2", "f3"))
    return _SER_LISTS


def _entire(k):
    """``c, sh, f1, f2, f3`` of :func:`kapitza.normal_form._entire` for one ``k``."""
    if abs(k) <= 1.0:
        out = []
        for coef in _ser_lists():
            y = 0.0
            for c in coef:
                y = y * k + c
            out.append(y)
        return out
    r = math.sqrt(abs(k))
    if k > 0:
        c, sh = math.cosh(r), math.sinh(r) / r
    else:
        c, sh = math.cos(r), math.sin(r) / r
    f1 = (c - sh) / k
    f2 = (1.0 - sh * c) / k
    return c, sh, f1, f2, (3.0 * f1 - sh**3) / k


def _phase_cubic(k):
    """``(L, C)`` of :func:`kapitza.normal_form._phase_cubic`: ``L`` as rows, ``C`` as two rows of four."""
    c, sh, f1, f2, f3 = _entire(k)
    sh3 = sh**3
    L = ((c, sh), (k * sh, c))
    row_q = (-k * sh * (3 + sh * c) / 48, -k * (f1 + sh3) / 16, k * sh * f2 / 16, k * f3 / 48)
    row_p = (-k * (3 * c + 5 * sh + 3 * k * sh3) / 48, -k * sh * (1 + 3 * sh * c) / 16,
             k * (f1 - 3 * sh3) / 16, k * sh * f2 / 16)
    return L, (row_q, row_p)


def _mul(a, b):
    out = [0.0] * (len(a) + len(b) - 1)
    for i, ai in enumerate(a):
        for j, bj in enumerate(b):
            out[i + j] += ai * bj
    return out


def _substitute(C, L):
    lq, lp = L
    qq = _mul(lq, lq)
    pp = _mul(lp, lp)
    mono = (_mul(qq, lq), _mul(qq, lp), _mul(lq, pp), _mul(pp, lp))
    return [[row[0] * mono[0][m] + row[1] * mono[1][m] + row[2] * mono[2][m] + row[3] * mono[3][m]
             for m in range(4)] for row in C]


def taylor(eps, mu):
    """``(M, C)`` of :func:`kapitza.normal_form._taylor` for one point (``M`` as rows)."""
    x, u, _ = phase_angles(eps, mu)
    L1, C1 = _phase_cubic(x * x)
    L2, C2 = _phase_cubic(-u * u)
    M = [[L2[i][0] * L1[0][k] + L2[i][1] * L1[1][k] for k in range(2)] for i in range(2)]
    S = _substitute(C2, L1)
    C = [[L2[i][0] * C1[0][m] + L2[i][1] * C1[1][m] + S[i][m] for m in range(4)] for i in range(2)]
    return M, C


def _coefficients(M, C, lam):
    e1 = M[0][1] + 0j
    e2 = lam - M[0][0]
    det = e1 * e2.conjugate() - e1.conjugate() * e2
    f0, f1 = e2.conjugate() / det, -e1.conjugate() / det
    Lz = ((e1, e1.conjugate()), (e2, e2.conjugate()))
    D = _substitute([[c + 0j for c in row] for row in C], Lz)
    return [f0 * D[0][j] + f1 * D[1][j] for j in range(4)]


def _w_of(theta, n):
    return theta - n * PI if n % 2 == 0 else (n + 1) * PI - theta


def normal_form(eps, mu, theta, zone):
    """``(w, coefficients, beta, twist, resonant_4)`` of :func:`kapitza.normal_form._normal_form`
    at a stable point (``theta``, ``zone`` from :func:`floquet`); raises :class:`Careful` where the
    rounding estimate exceeds :data:`DEFECT_MAX`."""
    M, C = taylor(eps, mu)
    w = _w_of(theta, zone)
    lam = cmath.exp(1j * w)
    m12 = M[0][1]
    coef = _coefficients(M, C, lam)
    r21 = coef[1] / lam
    size = abs(r21)
    defect = abs(r21.real) / (size if size > 0 else 1.0)
    if not defect <= DEFECT_MAX:
        raise Careful("the closed-form jets round too much here")
    # The cubic terms are formed from jets of size |C| |M|^3 and read in the normal coordinate,
    # whose row grows like 1 / sin(w) towards an edge: the twist is good to about
    # 4 eps |C| |M|^3 / (|c21| sin w) relative (at least twice what the twins were seen to differ
    # by). Beyond TWIST_REL the array path answers, with the digits it always printed.
    size_c = max(abs(v) for row in C for v in row)
    size_m = max(1.0, max(abs(v) for row in M for v in row))
    if not 4.0 * _EPS * size_c * size_m**3 <= TWIST_REL * abs(coef[1]) * math.sin(w):
        raise Careful("the twist is ill-conditioned here")
    beta = r21.imag
    scale = 8.0 * PI * m12 * m12
    return w, coef, beta, beta / scale, abs(coef[3]) / scale


def _sides(eps, mu, h):
    """``(theta, stable, zone)`` at ``eps - h`` and ``eps + h``, and whether they are the array
    path's own numbers (where the scalar twin declines, they are taken from it)."""
    fm, fp = floquet(eps - h, mu), floquet(eps + h, mu)
    if fm is not None and fp is not None:
        return (fm[2], fm[3], fm[4]), (fp[2], fp[3], fp[4]), False
    import numpy as np

    from ._square import _floquet as _floquet_array

    _, _, th, st, zn = _floquet_array(np.array([eps - h, eps + h]), np.full(2, mu))
    return ((float(th[0]), bool(st[0]), int(zn[0])), (float(th[1]), bool(st[1]), int(zn[1])), True)


def nonlinear(eps, mu, theta, zone, exact_theta=False, tol=1e-15):
    """``str(kapitza.nonlinear_stability(eps, mu))`` at a stable point, or None where the array
    path must answer. ``theta``, ``zone``: the rotation angle and zone at ``(eps, mu)``, from
    :func:`floquet` or (``exact_theta``) from the array path's ``_floquet``, which the array
    path's normal form uses: then the rotation number and trace printed are its own."""
    from .normal_form import KINDS, sentence

    try:
        x = SQRT8 * eps * math.sqrt(1.0 + mu * mu)
        if not x <= 30.0:  # the jets' e^{3x}-sized terms: the averaged or extended forms answer
            return None
        w, coef, beta, twist, res4 = normal_form(eps, mu, theta, zone)
        # on the 1:4 and 1:3 curves: w = target crossed between eps -+ h (kapitza.normal_form._on_curve)
        h = max(tol, 4.0 * _EPS) * eps
        (th_m, st_m, n_m), (th_p, st_p, n_p), exact_sides = _sides(eps, mu, h)
        on = []
        for target in (0.5 * PI, 2.0 * PI / 3.0):
            d_m = _w_of(th_m, n_m) - target if st_m else math.nan
            d_p = _w_of(th_p, n_p) - target if st_p else math.nan
            near = abs(w - target) if not exact_theta else _INF
            if not exact_sides:
                near = min(near, abs(d_m), abs(d_p))  # (NaN never is)
            if near <= _NEAR_CURVE:
                return None
            on.append(d_m * d_p <= 0.0 or abs(w - target) <= 1e-14)
        on4, on3 = on
        scale = abs(coef[0]) + abs(coef[1]) + abs(coef[2]) + abs(coef[3])
        c03 = abs(coef[3])
        if abs(beta) <= _NEAR_TWIST * scale or (on4 and abs(abs(beta) - c03) <= _NEAR_TWIST * scale):
            return None
        code = 1 if on3 else 0
        if on4:
            code = 2 if abs(beta) > c03 else 3
        return sentence(KINDS[code], w / (2.0 * PI), 2.0 * math.cos(w), twist, res4)
    except _DECLINE:
        return None
