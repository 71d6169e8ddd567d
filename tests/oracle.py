"""High-precision reference values (mpmath) from the plain definitions.

Nothing here imports kapitza. The inputs are the exact double values handed to
the library, converted to ``mpf``; the working precision grows with ``x`` so that
``tr M -+ 2`` is resolved even where ``cosh x`` is far beyond a double.

Definitions (``docs/theory.md`` sections 2-3)::

    x = 2 sqrt2 eps sqrt(1 + mu^2),   u = 2 sqrt2 eps sqrt(1 - mu^2),   D = x / u,
    tr M = 2 cosh x cos u + (D - 1/D) sinh x sin u.

For ``mu >= 1`` the same formula is used with ``u^2 <= 0`` (``cos u -> cosh v``,
``sin u / u -> sinh v / v``): written through ``u^2`` it needs no case split.

Zone edges solve ``tan(w/2) = D tanh(x/2)`` (lower) and ``tan(w/2) = D coth(x/2)``
(upper), ``w = u - n pi``, ``x = D u`` -- the zeros of ``tr M -+ 2``: with
``c = tan(u/2)``, ``t = tanh(x/2)`` the plain trace gives
``tr M - 2 = -4 (c - D t)(c + t/D) / ((1 - t^2)(1 + c^2))`` (the identity itself is
checked against the plain trace in ``test_oracle_selfcheck``). They are solved with a
bracketing ``mpmath.findroot`` (bisection as a fallback) for the offset of ``w`` from
``2 atan D``, which lies strictly inside every zone; the offset keeps full relative accuracy
however thin the zone (:func:`edge_offset`), and the edges found are checked to be zeros of
the plain ``tr M -+ 2`` in ``test_oracle_selfcheck``.
"""
from __future__ import annotations

import functools

import mpmath as mp

BASE_DPS = 50
# Arithmetic done by the tests on reference values happens at this precision too.
mp.mp.dps = BASE_DPS


def _dps_for(x) -> int:
    """Digits needed to resolve tr M -+ 2 when terms of size e^x cancel."""
    return BASE_DPS + int(float(abs(x)) * 0.4343) + 10


def mpf(v):
    """The exact value of a double (or int) as an mpf."""
    return mp.mpf(float(v)) if not isinstance(v, mp.mpf) else v


def _shape(eps, mu):
    e, m = mpf(eps), mpf(mu)
    x = 2 * mp.sqrt(2) * e * mp.sqrt(1 + m * m)
    u2 = 8 * e * e * (1 - m) * (1 + m)
    return e, m, x, u2


def _cos_sinc(u2):
    """(cos u, sin u / u) as functions of u^2 (any sign)."""
    if u2 > 0:
        u = mp.sqrt(u2)
        return mp.cos(u), mp.sin(u) / u
    if u2 < 0:
        v = mp.sqrt(-u2)
        return mp.cosh(v), mp.sinh(v) / v
    return mp.mpf(1), mp.mpf(1)


def trace(eps, mu, dps=None):
    """tr M at the exact doubles eps, mu (an mpf at the working precision used)."""
    e, m = mpf(eps), mpf(mu)
    with mp.workdps(dps or _dps_point(e, m)):
        e, m, x, u2 = _shape(e, m)
        c, s = _cos_sinc(u2)
        # (D - 1/D) sin u = (x/u - u/x) sin u = x sinc(u) - u^2 sinc(u) / x
        tr = 2 * mp.cosh(x) * c + mp.sinh(x) * (x * s - u2 * s / x)
        return +tr


def _dps_point(eps, mu) -> int:
    return _dps_for(2.9 * float(eps) * max(1.0, float(mu)) + 5)


def trace_checked(eps, mu):
    """tr M, recomputed with 30 more digits; asserts the two agree.

    The result carries ``_dps_point + 30`` digits: do arithmetic on it inside
    ``mp.workdps`` of at least that (mpmath rounds every operation, even ``abs``,
    to the current precision).
    """
    t1 = trace(eps, mu)
    d = _dps_point(eps, mu) + 30
    t2 = trace(eps, mu, dps=d)
    with mp.workdps(d):
        assert abs(t1 - t2) <= mp.mpf(10) ** (-40) * max(1, abs(t2)), (eps, mu, t1, t2)
    return t2


class FloquetRef:
    """Reference Floquet data at one point: trace, verdict, growth, rotation number (mpfs)."""

    def __init__(self, eps, mu):
        tr = trace_checked(eps, mu)
        e, m = mpf(eps), mpf(mu)
        self.eps, self.mu, self.trace = e, m, tr
        with mp.workdps(_dps_point(eps, mu) + 30):
            self.stable = bool(-2 < tr < 2)
            a = abs(tr) / 2
            # log max|lambda| = acosh(|tr| / 2) off the zones, 0 on them
            self.growth = mp.acosh(a) if a > 1 else mp.mpf(0)
            self.rotation_number = self._rotation(tr, e, m)

    @staticmethod
    def _rotation(tr, e, m):
        """Turns per period: (n pi + acos((-1)^n tr/2)) / (2 pi) on zone n = floor(u/pi).

        The lower edge of zone n carries tr = 2 (-1)^n (2T-periodic for even n,
        4T-periodic for odd n), where the angle per period is n pi; it grows to
        (n + 1) pi at the upper edge. Off the zones it is locked: n/2 below zone n,
        (n + 1)/2 above it (told apart by the sign of tr). 0 where mu >= 1.
        """
        if m >= 1:
            return mp.mpf(0)
        u = 2 * mp.sqrt(2) * e * mp.sqrt((1 - m) * (1 + m))
        n = int(mp.floor(u / mp.pi))
        sgn = 1 if n % 2 == 0 else -1
        if abs(tr) < 2:
            return (n * mp.pi + mp.acos(sgn * tr / 2)) / (2 * mp.pi)
        below = sgn * tr > 0
        return mp.mpf(n if below else n + 1) / 2


def stable(eps, mu) -> bool:
    """|tr M| < 2 (strict: an edge is unstable)."""
    return FloquetRef(eps, mu).stable


def growth(eps, mu):
    """log max|lambda| = acosh(|tr M| / 2) where |tr M| >= 2, else 0 (an mpf)."""
    return FloquetRef(eps, mu).growth


def rotation_number(eps, mu):
    """Rotation number in turns per period (see :class:`FloquetRef`)."""
    return FloquetRef(eps, mu).rotation_number


# ---------------------------------------------------------------- edges
# With mid = 2 atan D (alpha < mid < beta for every x) the edge equations are
# solved for the offset d of w from mid, which keeps full relative accuracy even
# where d ~ e^{-x} is far below mid's last digit:
#   mid - alpha = 2 atan(D (1 - t) / (1 + D^2 t)),    1 - t = 2 / (e^x + 1),
#   beta - mid  = 2 atan(D (k - 1) / (1 + D^2 k)),    k - 1 = 2 / (e^x - 1),
# with t = tanh(x/2), k = coth(x/2) (tan of a difference; both angles lie in (0, pi/2)).


def _solve_increasing(F, a, b, rtol):
    """Root of an increasing F with F(a) < 0 <= F(b), 0 < a < b, to relative tolerance.

    Anderson-Bjorck first (certified by a sign change), then geometric/arithmetic
    bisection, which needs no good starting point however many decades [a, b] spans.
    """
    try:
        r = mp.findroot(F, (a, b), solver="anderson", tol=rtol ** 2 * b * b, verify=False)
        if a <= r <= b:
            h = rtol * r
            if F(r - h) < 0 <= F(r + h):
                return r
    except (ValueError, ZeroDivisionError):
        pass
    for _ in range(100_000):
        if b - a <= rtol * b:
            return (a + b) / 2
        m = mp.sqrt(a * b) if b > 4 * a else (a + b) / 2
        if F(m) < 0:
            a = m
        else:
            b = m
    raise RuntimeError("bisection did not converge")


@functools.lru_cache(maxsize=None)
def edge_offset(mu, n, upper: bool, dps=BASE_DPS):
    """(u, d): u on the lower/upper edge of zone n, and d = |u - n pi - 2 atan D| > 0.

    mu is the exact double; both are mpfs good to ``dps`` digits. Zone 0's lower edge
    is ill-conditioned in this form as mu -> 0 (the slope of the equation is
    ~ D^2 - 1 ~ 2 mu^2 at a root of size ~ mu): extra digits are carried for that.
    """
    extra = 20 + 3 * max(0, int(-mp.log10(mpf(mu)))) if float(mu) > 0 else 20
    with mp.workdps(dps + extra):
        m = mpf(mu)
        D = mp.sqrt((1 + m * m) / ((1 - m) * (1 + m)))
        npi = n * mp.pi
        mid = 2 * mp.atan(D)
        rtol = mp.mpf(10) ** (-(dps - 10))

        if upper:
            def c(w):  # beta(x) - mid
                x = D * (npi + w)
                return 2 * mp.atan(2 * D / (mp.expm1(x) * (1 + D * D / mp.tanh(x / 2))))

            # H(d) = d - c(mid + d) increases; H(c(mid)) >= 0 > H(0).
            def H(d):
                return d - c(mid + d)

            b = c(mid)
            a = b / 2
            while H(a) >= 0:
                a /= 2
            d = _solve_increasing(H, a, b, rtol)
            return npi + mid + d, d

        def c(w):  # mid - alpha(x)
            x = D * (npi + w)
            return 2 * mp.atan(2 * D / ((mp.exp(x) + 1) * (1 + D * D * mp.tanh(x / 2))))

        # G(d) = d - c(mid - d) increases on the branch; G(c(mid)) <= 0.
        def G(d):
            return d - c(mid - d)

        a = c(mid)
        if n == 0:
            # d = mid (w = 0) is the trivial root: cap b below it, where G > 0 still.
            w_small = mid / 2
            while G(mid - w_small) <= 0:
                w_small /= 4
            cap = mid - w_small
            rtol = rtol * w_small / mid  # the answer is w = mid - d, not d
        else:
            cap = mid  # G(mid) = alpha(D n pi) > 0
        if G(a) >= 0:  # only when c is flat to the working precision
            return npi + mid - a, a
        b = min(2 * a, cap)
        while G(b) < 0:
            a, b = b, min(2 * b, cap)
        d = _solve_increasing(G, a, b, rtol)
        return npi + mid - d, d


def edge_u(mu, n, upper: bool, dps=BASE_DPS):
    """u = w_e T on the lower/upper edge of zone n at the exact double mu (an mpf)."""
    return edge_offset(mu, n, upper, dps)[0]


def edge_eps(mu, n, upper: bool, dps=BASE_DPS):
    """Zone n's lower/upper edge in eps at the exact double mu (an mpf)."""
    with mp.workdps(dps):
        m = mpf(mu)
        u = edge_u(m, n, upper, dps)
        return u / (2 * mp.sqrt(2) * mp.sqrt((1 - m) * (1 + m)))


def zone_width(mu, n, dps=BASE_DPS):
    """eps_hi - eps_lo = (d_lo + d_hi) / (2 sqrt2 sqrt(1 - mu^2)): no subtraction (an mpf)."""
    with mp.workdps(dps):
        m = mpf(mu)
        d = edge_offset(m, n, False, dps)[1] + edge_offset(m, n, True, dps)[1]
        return d / (2 * mp.sqrt(2) * mp.sqrt((1 - m) * (1 + m)))


def boundary_periods(A, count, l=1.0, g=9.81):
    """[(T_j, T~_j)] for j = 1..count at the exact doubles A, l, g (mpfs).

    T_{n+1} is zone n's 2T-periodic edge (lower for even n), T~_{n+1} its 4T one.
    """
    A, l, g = mpf(A), mpf(l), mpf(g)
    out = []
    with mp.workdps(BASE_DPS):
        mu = mp.sqrt(g / A)
        scale = mp.sqrt(8 * l / A)
        for n in range(count):
            lo = edge_eps(mu, n, False) * scale
            hi = edge_eps(mu, n, True) * scale
            out.append((lo, hi) if n % 2 == 0 else (hi, lo))
    return out


def monodromy(T, A, l=1.0, g=9.81, dps=BASE_DPS, factors=False):
    """M = E(T) H(T) on (theta, theta') as a 2x2 mp.matrix (A > g); (M, E, H) if ``factors``."""
    with mp.workdps(dps):
        T, A, l, g = (mpf(v) for v in (T, A, l, g))
        wh = mp.sqrt((A + g) / l)
        we = mp.sqrt((A - g) / l)
        x, u = wh * T, we * T
        H = mp.matrix([[mp.cosh(x), mp.sinh(x) / wh], [wh * mp.sinh(x), mp.cosh(x)]])
        E = mp.matrix([[mp.cos(u), mp.sin(u) / we], [-we * mp.sin(u), mp.cos(u)]])
        return (E * H, E, H) if factors else E * H


def rel_err(value, ref):
    """|value - ref| / |ref| as a float (ref an mpf, value a double)."""
    ref = mp.mpf(ref)
    return float(abs(mpf(value) - ref) / abs(ref))


def motion(t, theta0, dtheta0, T, A, l=1.0, g=9.81, dps=BASE_DPS):
    """(theta, theta') at time t >= 0 by M^k and the partial phase flow (mpfs, A > g)."""
    with mp.workdps(dps + 20):
        t, T, A, l, g = (mpf(v) for v in (t, T, A, l, g))
        M = monodromy(T, A, l, g, dps + 20)
        k = int(mp.floor(t / (2 * T)))
        r = t - 2 * k * T
        y = (M ** k) * mp.matrix([mpf(theta0), mpf(dtheta0)])
        wh = mp.sqrt((A + g) / l)
        we = mp.sqrt((A - g) / l)
        s = min(r, T)
        H = mp.matrix([[mp.cosh(wh * s), mp.sinh(wh * s) / wh], [wh * mp.sinh(wh * s), mp.cosh(wh * s)]])
        y = H * y
        if r > T:
            s = r - T
            E = mp.matrix([[mp.cos(we * s), mp.sin(we * s) / we], [-we * mp.sin(we * s), mp.cos(we * s)]])
            y = E * y
        return y[0], y[1]


# ---------------------------------------------------------------- edges along A and along mu
def _digits_lost(u):
    """Digits the plain ``w - alpha`` loses at a small phase ``u`` (its terms agree to ``u^2``)."""
    return 2 * max(0, int(-mp.log10(u))) if u < 1 else 0


def amplitude_edge(T, n, l, g, upper: bool, dps=BASE_DPS):
    """Zone n's lower/upper edge in A at the exact doubles T, l, g (an mpf).

    At fixed T, ``u = T sqrt((A - g)/l)`` and ``x^2 = u^2 + 2 g T^2 / l``; the edge solves
    ``w - alpha(x) = 0`` (or ``beta``), ``w = u - n pi``, ``D = x / u``, for ``u`` in
    ``(n pi, (n + 1) pi)``, carrying the digits its terms cancel to as ``u -> 0``; then
    ``A = g + l (u / T)^2``.
    """
    T, l, g = mpf(T), mpf(l), mpf(g)
    with mp.workdps(dps + 30):
        kappa = 2 * g * T * T / l
        guess = min(mp.mpf(1), (6 * kappa) ** mp.mpf(0.25))
    with mp.workdps(dps + 30 + _digits_lost(guess)):
        kappa = 2 * g * T * T / l
        npi = n * mp.pi

        def F(u):
            x = mp.sqrt(u * u + kappa)
            D = x / u
            t = mp.tanh(x / 2)
            f = 2 * mp.atan(D / t) if upper else 2 * mp.atan(D * t)
            return u - npi - f

        rtol = mp.mpf(10) ** (-(dps + 5))
        if n == 0:
            a = guess / 2 if not upper else mp.mpf(10) ** -30
            while F(a) >= 0:
                a /= 2
        else:
            a = npi
        u = _solve_increasing(F, a, (n + 1) * mp.pi, rtol)
        return +(g + l * (u / T) ** 2)


def frequency_edge(eps, n, upper: bool, dps=BASE_DPS):
    """The mu at which zone n's lower/upper edge passes the exact double eps (an mpf), or None
    where it passes no mu in (0, 1) (then the zone stays above, or below, eps at every mu).

    At fixed eps, ``u = 2 sqrt2 eps sqrt(1 - mu^2)`` falls and ``alpha``, ``beta`` rise as mu
    grows: ``w - alpha`` (or ``beta``) decreases in mu and changes sign at most once.
    """
    e = mpf(eps)
    with mp.workdps(dps + 30 + _digits_lost(min(mp.mpf(1), 3 * e))):
        npi = n * mp.pi

        def G(m):  # increasing in mu
            q = mp.sqrt((1 - m) * (1 + m))
            p = mp.sqrt(1 + m * m)
            x, u = 2 * mp.sqrt(2) * e * p, 2 * mp.sqrt(2) * e * q
            t = mp.tanh(x / 2)
            D = p / q
            f = 2 * mp.atan(D / t) if upper else 2 * mp.atan(D * t)
            return -(u - npi - f)

        rtol = mp.mpf(10) ** (-(dps + 5))
        a, b = mp.mpf(10) ** -320, 1 - mp.mpf(10) ** -30
        if G(a) >= 0 or G(b) < 0:
            return None
        return _solve_increasing(G, a, b, rtol)
