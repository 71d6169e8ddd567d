"""Exact propagation of the linear equation (2.3) and its Floquet data.

Over one drive period ``[0, 2T)`` the state ``(theta, theta')`` is multiplied by
``M = E(T) H(T)`` (``docs/theory.md`` section 3). Everything here is in closed
form: no step-size error, continuous ``theta`` and ``theta'`` across the switches
(2.14), and Floquet data (trace, multipliers, growth, rotation number) from the
factored trace of :mod:`kapitza._exact`, which stays finite and accurate where
``cosh x`` overflows a double.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _certify
from . import _exact as X
from . import _validate as _v
from ._display import Summary, multipliers, num, shape_of, span, stable_share
from .drives import _api as _drv
from .parameters import G_EARTH, SQRT8, _arnold, _phase_angles

__all__ = [
    "Floquet",
    "floquet",
    "floquet_multipliers",
    "growth_rate",
    "rotation_number",
    "monodromy",
    "linear_motion",
]

PI = np.pi


# ---------------------------------------------------------------- kernels
def _floquet(eps, mu):
    """(tau, growth, theta, stable, n) for trusted eps > 0, mu > 0 (any mu)."""
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    ell = mu < 1.0
    x, u, D = _phase_angles(eps, np.where(ell, mu, 0.5))
    n, a, b, tau, growth, theta = X.floquet_elliptic(x, u, D, np.where(ell, mu, 0.5))
    stable_e = (a > 0) & (b < 0)
    check = ell & (_certify.unsure(u, a, b, x) | (~stable_e & (growth <= 0.0) & (x + u <= _certify.MAX_PHASE)))
    if np.any(check):
        # signs lost to rounding (or an unstable point whose excess rounded to zero):
        # the exact trace decides the verdict, the growth and the angle
        tau, growth, theta, a, b = (np.array(v, dtype=float) for v in (tau, growth, theta, a, b))
        t_e, _, st, acos_e = _certify.exact_half_trace(eps[check], mu[check])
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
    return tau, growth, theta, stable, np.where(stable, n, -1).astype(np.int64)


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


# ---------------------------------------------------------------- results
@dataclass(frozen=True, repr=False)
class Floquet(Summary):
    """Floquet data of one drive period ``2T``; arrays of the broadcast shape of ``(eps, mu)``.

    Prints as a summary (one point: its values; an array: shape, stable fraction, ranges).

    Attributes
    ----------
    trace : ndarray
        ``tr M`` (``+-inf`` where it overflows a double; ``growth`` stays finite).
    multipliers : ndarray of complex, shape ``(..., 2)``
        Roots of ``lambda^2 - tr M lambda + det M = 0``, largest modulus first.
    growth : ndarray
        ``log max|lambda|``: the exponential growth of the worst motion per period
        ``2T`` (0 where stable without damping, ``-c T`` where stable with it: the
        motion decays).
    rotation_number : ndarray
        Mean clockwise turns of the phase point ``(theta, theta'/w)`` per period:
        in ``(n/2, (n+1)/2)`` on zone ``n``, locked to a multiple of 1/2 elsewhere
        (0 where ``A <= g``).
    stable : ndarray of bool
    zone : ndarray of int
        Zone index, -1 where unstable.
    determinant : ndarray or float
        ``det M = exp(-2 c T)`` (1 without damping; ``docs/drives.md`` section 3).
    """

    trace: np.ndarray
    multipliers: np.ndarray
    growth: np.ndarray
    rotation_number: np.ndarray
    stable: np.ndarray
    zone: np.ndarray
    determinant: np.ndarray | float = 1.0

    def headline(self) -> str:
        if np.ndim(self.stable) == 0:
            return (f"{'stable, zone ' + str(int(self.zone)) if self.stable else 'unstable'}, tr M = "
                    f"{num(self.trace, 10)}, growth {num(self.growth)}, rotation number {num(self.rotation_number)}")
        return stable_share(self.stable)

    def lines(self) -> list[tuple[str, str]]:
        if np.ndim(self.stable) == 0:
            return [("verdict", f"stable (zone {int(self.zone)})" if self.stable else "unstable"),
                    ("trace tr M", num(self.trace, 12)), ("multipliers", multipliers(self.multipliers)),
                    ("growth", f"{num(self.growth, 12)} per period 2T"),
                    ("rotation number", f"{num(self.rotation_number, 12)} turns per period"),
                    ("det M", num(self.determinant, 12))]
        zones = np.unique(self.zone[self.stable]) if np.any(self.stable) else np.array([], int)
        zs = ", ".join(map(str, zones[:12].tolist())) + (", ..." if zones.size > 12 else "")
        return [("points", shape_of(self.stable)),
                ("stable", f"{100 * float(np.mean(self.stable)):.4g}% (zones {zs or 'none'})"),
                ("trace tr M", span(self.trace)), ("growth", f"{span(self.growth)} per period 2T"),
                ("rotation number", span(self.rotation_number)), ("det M", span(self.determinant))]

    def __post_init__(self):
        _v.scalar_fields(self)


def _multipliers(tau, growth, theta, stable):
    sgn = np.where(tau < 0, -1.0, 1.0)
    with np.errstate(over="ignore"):
        big = sgn * np.exp(growth)
    small = sgn * np.exp(-growth)
    lam1 = np.where(stable, np.exp(1j * theta), big + 0j)
    lam2 = np.where(stable, np.exp(-1j * theta), small + 0j)
    return np.stack([lam1, lam2], axis=-1)


@_v.shapes_named
def floquet(eps, mu, drive=None, zeta=0.0):
    """Trace, multipliers, growth and rotation number of one period at ``(eps, mu)``.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        Arnold's parameters, each finite and > 0; ``mu >= 1`` (``A <= g``, no
        elliptic phase) is accepted and is always unstable for the square wave.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    zeta : array_like, optional
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0; broadcasts.

    Returns
    -------
    Floquet

    Notes
    -----
    ``tr M = 2 cosh x cos u + (D - 1/D) sinh x sin u`` (``docs/theory.md`` section 3)
    is evaluated in its factored form ``tau = tr M/2 = -sin(u - gamma)/sin(delta)``,
    ``tau -+ 1`` as products of sines of ``(u - alpha)/2`` and ``(u - beta)/2``
    (see :mod:`kapitza._exact`); the growth ``acosh|tau|`` is formed from
    ``log|tau|`` far out, so it is finite for every input.
    """
    eps, mu = _v.arnold(eps, mu)
    drive, zeta = _v.general_drive(drive, zeta)
    if drive is not None:
        trace, det, mult, growth, rho, stable, zone = _drv.floquet(eps, mu, drive, zeta)
        return Floquet(trace=trace, multipliers=mult, growth=growth, rotation_number=rho, stable=stable,
                       zone=np.where(stable, zone, -1).astype(np.int64), determinant=det)
    tau, growth, theta, stable, zone = _floquet(eps, mu)
    with np.errstate(over="ignore"):  # tr M is +-inf where it overflows a double (documented)
        trace = 2.0 * tau
    return Floquet(
        trace=trace,
        multipliers=_multipliers(tau, growth, theta, stable),
        growth=growth,
        rotation_number=theta / (2.0 * PI),
        stable=stable,
        zone=zone,
    )


@_v.shapes_named
def floquet_multipliers(eps, mu, drive=None, zeta=0.0):
    """Floquet multipliers of one period, shape ``(..., 2)``, largest modulus first.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        As in :func:`floquet`.

    Returns
    -------
    ndarray of complex
        On the unit circle (``exp(+-2 pi i rho)``) where stable; real,
        ``lambda_1 lambda_2 = 1`` otherwise. A modulus beyond a double's range
        is ``inf``; :func:`growth_rate` gives its logarithm.
    """
    return floquet(eps, mu, drive, zeta).multipliers


@_v.shapes_named
def growth_rate(eps, mu, drive=None, zeta=0.0):
    """``log max|lambda|`` per drive period ``2T``; 0 where stable, finite everywhere.

    Parameters
    ----------
    eps, mu, drive, zeta :
        As in :func:`floquet`.

    Returns
    -------
    ndarray
        With damping, negative where the motion decays.
    """
    eps, mu = _v.arnold(eps, mu)
    drive, zeta = _v.general_drive(drive, zeta)
    if drive is not None:
        return _drv.floquet(eps, mu, drive, zeta)[3]
    return _floquet(eps, mu)[1]


@_v.shapes_named
def rotation_number(eps, mu, drive=None, zeta=0.0):
    """Mean clockwise turns per drive period of the phase point (see :class:`Floquet`).

    Parameters
    ----------
    eps, mu, drive, zeta :
        As in :func:`floquet` (with damping: that of the undamped ``phi = exp(c t/2) theta``).

    Returns
    -------
    ndarray
        In ``(n/2, (n+1)/2)`` on zone ``n``. The mean number of zeros of
        ``theta(t)`` per period is twice this.
    """
    eps, mu = _v.arnold(eps, mu)
    drive, zeta = _v.general_drive(drive, zeta)
    if drive is not None:
        return _drv.floquet(eps, mu, drive, zeta)[4]
    return _floquet(eps, mu)[2] / (2.0 * PI)


@_v.shapes_named
def monodromy(T, A, l=1.0, g=G_EARTH, drive=None, damping=0.0):
    """The one-period matrix ``M = E(T) H(T)`` acting on ``(theta, theta')``.

    Parameters
    ----------
    T, A, l, g : array_like, broadcast together
        Half-period [s], acceleration amplitude, rod length, gravity; each > 0.
        ``A <= g`` is accepted (the second phase is then hyperbolic or free flight).
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    damping : array_like, optional
        Viscous damping ``c`` >= 0 [1/s]; broadcasts.

    Returns
    -------
    ndarray, shape ``(..., 2, 2)``
        ``det M = exp(-2 c T)`` (1 undamped). Entries overflow to ``inf`` once ``w_h T > 710``.

    Notes
    -----
    ``docs/theory.md`` section 3; the phase matrices solve (2.4) and (2.5).
    """
    T = _v.positive("T", T)
    A = _v.positive("A", A)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    _v.finite_rate(A, l, g)
    with np.errstate(over="ignore"):
        x = np.sqrt((A + g) / l) * T
    if not np.all(np.isfinite(x)):
        raise _v.KapitzaValueError(f"T and A must give a finite phase w_h T; got T = {float(np.max(T))!r}")
    drive, c = _v.general_drive(drive, damping, "damping", g=g, l=l)
    if drive is not None:
        return _drv.monodromy(T, A, l, g, drive, c)
    return _monodromy(*np.broadcast_arrays(T, A, l, g))


def _chebyshev_pair(k, tau, growth, theta, stable):
    """``U_{k-1}(tau), U_{k-2}(tau)`` so that ``M^k = U_{k-1} M - U_{k-2} I``."""

    def U(m):  # U_{m-1}(tau) for integer m >= 0
        sgn = np.where(tau < 0, -1.0, 1.0)
        with np.errstate(over="ignore", invalid="ignore"):
            st = np.sin(theta)
            s_stab = np.where(np.abs(st) > 1e-300, np.sin(m * theta) / np.where(st == 0, 1.0, st), m * np.cos((m - 1) * theta))
            sh = np.sinh(growth)
            s_uns = np.where(growth > 0, np.sinh(m * growth) / np.where(sh > 0, sh, 1.0), m) * sgn ** (m - 1)
        return np.where(stable, s_stab, s_uns)

    return U(k), U(k - 1.0)


@_v.shapes_named
def linear_motion(t, theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, drive=None, damping=0.0, *, eps=None,
                  mu=None):
    """Exact solution of the linear equation (2.3) at the times ``t``.

    Parameters
    ----------
    t : array_like
        Times ``>= 0`` [s], any shape and order.
    theta0, dtheta0 : array_like
        Initial angle from the upright [rad] and angular velocity [rad/s] at ``t = 0``
        (the start of a hyperbolic phase, as in (2.2)).
    T, A, l, g : array_like
        Drive half-period, acceleration amplitude, rod length, gravity; each > 0.
        All arguments broadcast together.
    drive : Drive or str, optional
        The pivot's motion; the paper's square wave by default. Piecewise-constant drives
        are solved exactly; the sine drive is integrated (DOP853, rtol 1e-11).
    eps, mu : array_like, optional
        Arnold's parameters instead of ``T`` and ``A`` (keywords; with ``l`` and ``g``):
        ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``. Give ``(eps, mu)`` or ``(T, A)``.

    damping : array_like, optional
        Viscous damping ``c`` >= 0 [1/s].

    Returns
    -------
    theta, dtheta : ndarray
        ``theta(t)`` and ``theta'(t)``; both are continuous across the switches.

    Raises
    ------
    OverflowError
        Where the motion grows beyond the range of a double.

    Notes
    -----
    Whole periods use ``M^k = U_{k-1}(tau) M - U_{k-2}(tau) I`` (Cayley-Hamilton,
    Chebyshev polynomials of the second kind of ``tau = tr M / 2``, evaluated in
    closed form from the exact rotation angle or growth), so the cost does not
    depend on ``t``; the remainder of the period applies the phase flows of
    (2.4)-(2.5).
    """
    t = _v.finite("t", t)
    if np.any(t < 0):
        raise _v.KapitzaValueError(f"t must be >= 0; got {float(t[t < 0].flat[0])!r}")
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    T, A, l, g = _v.physical_parameters(T, A, l, g, eps, mu)
    _v.finite_rate(A, l, g)
    drive, c = _v.general_drive(drive, damping, "damping", g=g, l=l)
    _v.phase_resolved(t, T)
    if drive is not None:
        return _drv.linear_motion(t, theta0, dtheta0, T, A, l, g, drive, c)
    t, theta0, dtheta0, T, A, l, g = np.broadcast_arrays(t, theta0, dtheta0, T, A, l, g)
    eps, mu = _arnold(T, A, l, g)
    tau, growth, theta, stable, _ = _floquet(eps, mu)
    k = np.floor(t / (2.0 * T))
    r = t - 2.0 * k * T
    # Rounding can put r a hair outside [0, 2T).
    over = r >= 2.0 * T
    k = np.where(over, k + 1.0, k)
    r = np.where(over, r - 2.0 * T, np.maximum(r, 0.0))
    M = _monodromy(T, A, l, g)
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
            f"(growth {float(growth[tuple(i)]):.4g} per period, t = {float(t[tuple(i)]):.6g} s)"
        )
    return th, dth
