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

from . import _validate as _v
from ._display import Summary, multipliers, num, shape_of, span, stable_share
from ._square import _apply, _chebyshev_pair, _floquet, _flow, _monodromy, _multipliers  # noqa: F401  (the kernels' old home)
from .drives import as_drive
from .parameters import G_EARTH

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
    trace_error : ndarray
        A bound on ``|trace - tr M|``, ``tr M`` the exact trace at the double inputs given
        (``inf`` where ``trace`` overflows, or for a drive that gives no bound). Where the
        trace cancels (its terms are far larger than itself: strongly hyperbolic segments, next to
        thin zones) piecewise-constant drives, the square wave included, recompute it in extended
        precision, and the bound is then a few units of rounding of ``trace``; elsewhere it is the
        a-priori rounding bound of the exact product (``docs/drives.md``, "Accuracy of the trace and
        the growth"), and for drives integrated numerically (sine, triangle, sampled) the engine's
        own error estimate. Off the zones the growth errs by at most about
        ``trace_error / sqrt(trace^2 - 4 det M)``.

    Examples
    --------
    >>> import kapitza
    >>> f = kapitza.floquet(0.5, 0.3)
    >>> f
    <Floquet: stable, zone 0, tr M = 1.3786..., growth 0, rotation number 0.1289...>
    >>> f.stable, f.zone
    (np.True_, np.int64(0))
    >>> f.multipliers
    array([0.6893...+0.7244...j, 0.6893...-0.7244...j])
    >>> abs(f.multipliers)
    array([1., 1.])
    """

    trace: np.ndarray
    multipliers: np.ndarray
    growth: np.ndarray
    rotation_number: np.ndarray
    stable: np.ndarray
    zone: np.ndarray
    determinant: np.ndarray | float = 1.0
    trace_error: np.ndarray | float = 0.0

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

    Raises
    ------
    ValueError
        If ``eps`` or ``mu`` is not finite and > 0, ``zeta`` is negative, or they do not broadcast.

    Notes
    -----
    ``tr M = 2 cosh x cos u + (D - 1/D) sinh x sin u`` (``docs/theory.md`` section 3)
    is evaluated in its factored form ``tau = tr M/2 = -sin(u - gamma)/sin(delta)``,
    ``tau -+ 1`` as products of sines of ``(u - alpha)/2`` and ``(u - beta)/2``
    (see :mod:`kapitza._exact`); the growth ``acosh|tau|`` is formed from
    ``log|tau|`` far out, so it is finite for every input.

    Examples
    --------
    >>> import kapitza
    >>> f = kapitza.floquet([0.5, 1.2], 0.3)
    >>> f.stable
    array([ True, False])
    >>> f.trace
    array([  1.3786..., -34.7585...])
    >>> f.growth
    array([0.        , 3.5475...])
    >>> kapitza.floquet(0.5, 0.3, zeta=0.1).growth
    np.float64(-0.0848...)
    """
    eps, mu = _v.arnold(eps, mu)
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    trace, det, mult, growth, rho, stable, zone, err = d.floquet_data(eps, mu, zeta)
    return Floquet(trace=trace, multipliers=mult, growth=growth, rotation_number=rho, stable=stable,
                   zone=zone, determinant=det, trace_error=err)


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

    Raises
    ------
    ValueError
        As in :func:`floquet`.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.floquet_multipliers(0.5, 0.3)
    array([0.6893...+0.7244...j, 0.6893...-0.7244...j])
    >>> kapitza.floquet_multipliers(1.2, 0.3)
    array([-3.4729...e+01+0.j, -2.8793...e-02+0.j])
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

    Raises
    ------
    ValueError
        As in :func:`floquet`.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.growth_rate([0.5, 1.2, 40.0], 0.3)
    array([  0.        ,   3.5475..., 117.4725...])
    >>> kapitza.growth_rate(0.5, 0.3, zeta=0.1)
    np.float64(-0.0848...)
    """
    eps, mu = _v.arnold(eps, mu)
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    return _v.scalars(np.asarray(d.growth(eps, mu, zeta)))


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

    Raises
    ------
    ValueError
        As in :func:`floquet`.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.rotation_number([0.5, 1.2, 1.5], 0.3)
    array([0.1289..., 0.5       , 0.5       ])
    """
    eps, mu = _v.arnold(eps, mu)
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    return _v.scalars(np.asarray(d.rotation(eps, mu, zeta)))


@_v.shapes_named
def monodromy(T, A, l=1.0, g=G_EARTH, drive=None, damping=None, zeta=None):
    """The one-period matrix ``M = E(T) H(T)`` acting on ``(theta, theta')``.

    Parameters
    ----------
    T, A, l, g : array_like, broadcast together
        Half-period [s], acceleration amplitude, rod length, gravity; each > 0.
        ``A <= g`` is accepted (the second phase is then hyperbolic or free flight).
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    damping : array_like, optional
        Viscous damping ``c`` >= 0 [1/s]; broadcasts. Or
    zeta : array_like, optional
        its damping ratio ``c / (2 sqrt(g/l))`` (give one of the two).

    Returns
    -------
    ndarray, shape ``(..., 2, 2)``
        ``det M = exp(-2 c T)`` (1 undamped). Entries overflow to ``inf`` once ``w_h T > 710``.

    Raises
    ------
    ValueError
        If ``T``, ``A``, ``l`` or ``g`` is not finite and > 0, both ``damping`` and ``zeta`` are given,
        or the arguments do not broadcast.

    Notes
    -----
    ``docs/theory.md`` section 3; the phase matrices solve (2.4) and (2.5).

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> M = kapitza.monodromy(0.15, 100.0, 1.0)
    >>> M
    array([[  2.8811...,   0.2936...],
           [-20.0788...,  -1.6996...]])
    >>> round(float(np.linalg.det(M)), 12)
    1.0
    >>> float(np.trace(M)), float(kapitza.floquet(*kapitza.to_arnold(0.15, 100.0, 1.0)).trace)
    (1.1815..., 1.1815...)
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
    c, _ = _v.damping(damping, zeta, l, g)
    return as_drive(drive).monodromy(T, A, l, g, c)


@_v.shapes_named
def linear_motion(t, theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, drive=None, damping=None, *, eps=None,
                  mu=None, zeta=None):
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
        Viscous damping ``c`` >= 0 [1/s]. Or
    zeta : array_like, optional
        its damping ratio ``c / (2 sqrt(g/l))`` (keyword; give one of the two).

    Returns
    -------
    theta, dtheta : ndarray
        ``theta(t)`` and ``theta'(t)``; both are continuous across the switches.

    Raises
    ------
    ValueError
        If a time is negative, a parameter is not finite and > 0, neither or both of ``(T, A)``
        and ``(eps, mu)`` are given, or both ``damping`` and ``zeta``.
    OverflowError
        Where the motion grows beyond the range of a double.

    Notes
    -----
    Whole periods use ``M^k = U_{k-1}(tau) M - U_{k-2}(tau) I`` (Cayley-Hamilton,
    Chebyshev polynomials of the second kind of ``tau = tr M / 2``, evaluated in
    closed form from the exact rotation angle or growth), so the cost does not
    depend on ``t``; the remainder of the period applies the phase flows of
    (2.4)-(2.5).

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> t = np.array([0.0, 0.3, 3.0, 30.0])
    >>> theta, dtheta = kapitza.linear_motion(t, 0.01, 0.0, T=0.15, A=100.0, l=1.0)
    >>> theta
    array([ 0.01      ,  0.0288..., -0.0089..., -0.0008...])
    >>> theta, dtheta = kapitza.linear_motion(t, 0.01, 0.0, T=0.3, A=100.0, l=1.0)
    >>> theta
    array([ 1.0000...e-02,  1.1616...e-01, -1.5954...e+04,  1.5854...e+64])
    """
    t = _v.finite("t", t)
    if np.any(t < 0):
        raise _v.KapitzaValueError(f"t must be >= 0; got {float(t[t < 0].flat[0])!r}")
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    T, A, l, g = _v.physical_parameters(T, A, l, g, eps, mu)
    _v.finite_rate(A, l, g)
    c, _ = _v.damping(damping, zeta, l, g)
    _v.phase_resolved(t, T)
    th, dth = as_drive(drive).linear_motion(t, theta0, dtheta0, T, A, l, g, c)
    return _v.scalars(np.asarray(th), np.asarray(dth))
