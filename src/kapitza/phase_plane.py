"""The phase-plane machinery of sections 2-3 of the paper.

In the hyperbolic phase the variables ``(x_h, y_h) = (theta, theta'/w_h)`` turn
along hyperbolae (2.6)-(2.7); in the elliptic phase ``(x_e, y_e) =
(theta, theta'/w_e)`` turn clockwise along circles (2.12)-(2.13). At each switch
``y`` is stretched by ``d = D`` (at ``t = T``) or ``d = 1/D`` (at ``t = 2T``), which
in polar coordinates multiplies ``r`` by ``f(phi; d)`` and maps the angle by
``phi(phi; d)`` (:func:`angle_map`). :func:`notable_points` strings the four steps
together as in (3.1).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as _v
from .parameters import G_EARTH

__all__ = [
    "f",
    "angle_map",
    "G",
    "G_inverse",
    "h",
    "phi_h",
    "NotablePoints",
    "notable_points",
]

PI = np.pi
QPI = 0.25 * np.pi



def _ratio(name, value):
    """A frequency ratio ``0 < value <= 1e150`` (its square must be a double)."""
    v = _v.positive(name, value)
    if np.any(v > 1e150):
        raise _v.KapitzaValueError(f"{name} must be <= 1e150 (its square enters f and h); got {float(v.max())!r}")
    return v

@_v.shapes_named
def f(phi, d):
    """Radial factor of the stretch ``(x, y) -> (x, d y)``: ``f(phi; d) = sqrt(1 + (d^2 - 1) sin^2 phi)``.

    Parameters
    ----------
    phi : array_like
        Polar angle [rad], finite.
    d : array_like
        Stretch factor, > 0; broadcasts with ``phi``.

    Returns
    -------
    ndarray
        ``rho(r, phi; d) = f(phi; d) r``. Even and ``pi``-periodic in ``phi``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    Section 2 of the paper, definition of ``rho`` and ``f``.

    Examples
    --------
    >>> from kapitza.phase_plane import f
    >>> f(0.3, 2.0)
    np.float64(1.1233...)
    """
    phi = _v.finite("phi", phi)
    d = _ratio("d", d)
    return _f(phi, d)


def _f(phi, d):
    # |(cos phi, d sin phi)|: equal to sqrt(1 + (d^2 - 1) sin^2 phi) without its cancellation
    # (relative error ~ 1e-16 / f^2) when d < 1 and phi is near pi/2.
    return np.hypot(np.cos(phi), d * np.sin(phi))


@_v.shapes_named
def angle_map(phi, d):
    """The paper's angle map ``phi(phi; d)`` of the stretch ``(x, y) -> (x, d y)``.

    Parameters
    ----------
    phi : array_like
        Polar angle [rad], finite.
    d : array_like
        Stretch factor, > 0; broadcasts with ``phi``.

    Returns
    -------
    ndarray
        The angle of ``(x, d y)``, continuous in ``phi``: ``tan(result) = d tan(phi)``,
        ``result = phi`` at odd multiples of ``pi/2``, and the result stays in the
        quadrant of ``phi``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    Section 2: ``arctan(d tan phi) + [(phi + pi/2)/pi] pi``. Evaluated as
    ``phi + atan2((d - 1) sin phi cos phi, cos^2 phi + d sin^2 phi)`` (the tangent
    of the difference), which needs no case split, so that the listed properties
    hold to rounding: odd in ``phi``, ``angle_map(phi + k pi) = angle_map(phi) + k pi``,
    ``angle_map(angle_map(phi; d); 1/d) = phi``.

    Examples
    --------
    >>> from kapitza.phase_plane import angle_map
    >>> angle_map(0.3, 2.0)
    np.float64(0.5540...)
    """
    phi = _v.finite("phi", phi)
    d = _ratio("d", d)
    return _angle_map(phi, d)


def _angle_map(phi, d):
    s, c = np.sin(phi), np.cos(phi)
    return phi + np.arctan2((d - 1.0) * s * c, c * c + d * s * s)


@_v.shapes_named
def G(phi):
    """``G(phi) = -1/2 ln|tan(pi/4 - phi)|``, a primitive of ``1 / cos(2 phi)`` (2.9).

    Parameters
    ----------
    phi : array_like
        Polar angle [rad]; ``phi`` must not be an odd multiple of ``pi/4``.

    Returns
    -------
    ndarray
        On ``(-pi/4, pi/4)`` and ``(-3pi/4, -pi/4)`` this is the two-branch
        formula (2.9); it increases on each branch from ``-inf`` to ``+inf``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Examples
    --------
    >>> from kapitza.phase_plane import G, G_inverse
    >>> G(0.3)
    np.float64(0.3198...)
    >>> round(float(G_inverse(G(0.3))), 12)
    0.3
    """
    phi = _v.finite("phi", phi)
    t = np.abs(np.tan(QPI - phi))
    k = (phi - QPI) / (0.5 * PI)
    if np.any(np.isclose(k, np.round(k), rtol=0, atol=1e-15) | (t == 0) | ~np.isfinite(t)):
        raise _v.KapitzaValueError("phi must not be an odd multiple of pi/4 (cos 2 phi = 0): G is infinite there")
    return -0.5 * np.log(t)


@_v.shapes_named
def G_inverse(s, branch=0):
    """Inverse of :func:`G` on one of its two branches.

    Parameters
    ----------
    s : array_like
        Value of ``G``, finite.
    branch : {0, -1}
        0 for ``phi`` in ``(-pi/4, pi/4)``, -1 for ``phi`` in ``(-3pi/4, -pi/4)``.

    Returns
    -------
    ndarray
        ``pi/4 - atan(e^{-2s})`` (branch 0) or ``-3pi/4 + atan(e^{-2s})`` (branch -1).

    Raises
    ------
    ValueError
        If ``s`` is not finite or ``branch`` is neither 0 nor -1.

    Examples
    --------
    >>> from kapitza.phase_plane import G, G_inverse
    >>> s = G(0.3)
    >>> s
    np.float64(0.3198...)
    >>> G_inverse(s)
    np.float64(0.3)
    """
    s = _v.finite("s", s)
    if not (isinstance(branch, (int, np.integer)) and not isinstance(branch, (bool, np.bool_))) \
            or branch not in (0, -1):
        raise _v.KapitzaValueError(f"branch must be 0 or -1; got {branch!r}")
    with np.errstate(over="ignore"):  # e = inf gives atan(e) = pi/2, the limit
        e = np.exp(-2.0 * s)
    return QPI - np.arctan(e) if branch == 0 else -3.0 * QPI + np.arctan(e)


@_v.shapes_named
def h(phi, D):
    """``h(phi) = |cos 2 phi| / (1 + (D^2 - 1) sin^2 phi)`` (3.7).

    Parameters
    ----------
    phi : array_like
        Polar angle [rad].
    D : array_like
        ``w_h / w_e > 0``; broadcasts with ``phi``.

    Returns
    -------
    ndarray
        Even and ``pi``-periodic in ``phi``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    Used in the proof of Lemma 3.1: a 2T-periodic solution needs
    ``h(phi_0) = h(phi_1)``. ``h`` decreases strictly on ``[m pi, pi/4 + m pi]`` (from 1
    to 0) and increases strictly on ``[pi/4 + m pi, pi/2 + m pi]`` (from 0 to ``1/D^2``);
    by evenness the other way round on ``[-pi/2, 0]``. The paper calls ``h`` periodic
    of period ``pi/2``; that holds only for ``D = 1`` (``h(0) = 1``, ``h(pi/2) = 1/D^2``).

    Examples
    --------
    >>> from kapitza.phase_plane import h
    >>> h(0.3, 1.1)
    np.float64(0.8104...)
    """
    phi = _v.finite("phi", phi)
    D = _ratio("D", D)
    # 1 + (D^2 - 1) sin^2 phi = f(phi; D)^2, formed without cancellation (D < 1, phi near pi/2)
    with np.errstate(over="ignore"):
        two_phi = 2.0 * phi
    # beyond 9e307, 2 phi overflows: cos 2 phi = (cos phi - sin phi)(cos phi + sin phi) there
    c2 = np.where(np.isfinite(two_phi), np.cos(np.where(np.isfinite(two_phi), two_phi, 0.0)),
                  (np.cos(phi) - np.sin(phi)) * (np.cos(phi) + np.sin(phi)))
    return np.abs(c2) / _f(phi, D) ** 2


@_v.shapes_named
def phi_h(t, phi0, w_h):
    """Polar angle ``phi_h(t; phi0)`` of the hyperbolic rotation (2.7), solution (2.11).

    Parameters
    ----------
    t : array_like
        Time since the start of the hyperbolic phase [s] (any sign).
    phi0 : array_like
        Initial angle [rad], any real value.
    w_h : array_like
        Hyperbolic frequency, > 0. All broadcast together.

    Returns
    -------
    ndarray
        ``phi_h(t)``, continuous in ``t``, tending to the unstable asymptote
        ``pi/4 (mod pi)`` as ``t -> inf``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``tan(phi - pi/4)`` is multiplied by ``e^{-2 w_h t}`` along the flow, which
    gives (2.11) on the branch of ``phi0``. For ``phi0`` in ``(-3pi/4, -pi/4)`` the
    paper prints ``pi/4 + atan(e^{-2 w_h t} tan(phi0 - pi/4))``, which lies on the
    same line through the origin but at the antipodal point (it equals
    ``phi0 + pi`` at ``t = 0``); this function returns the continuous branch
    ``-3pi/4 + atan(e^{-2 w_h t} tan(phi0 + 3pi/4))``.

    Examples
    --------
    >>> from kapitza.phase_plane import phi_h
    >>> phi_h(0.1, 0.3, 10.5)
    np.float64(0.7208...)
    """
    t = _v.finite("t", t)
    phi0 = _v.finite("phi0", phi0)
    w_h = _v.positive("w_h", w_h)
    return _phi_h(t, phi0, w_h)


def _phi_h(t, phi0, w_h):
    m = np.round((phi0 - QPI) / PI)
    psi0 = phi0 - QPI - m * PI  # in [-pi/2, pi/2]
    with np.errstate(over="ignore"):
        e = np.exp(-2.0 * w_h * t)
    sp = np.sin(psi0)
    with np.errstate(invalid="ignore"):
        y = np.where(sp == 0.0, 0.0, e * sp)  # on the asymptote the angle stays put for every t
    return QPI + m * PI + np.arctan2(y, np.cos(psi0))


@dataclass(frozen=True)
class NotablePoints:
    """The five notable points ``(r_i, phi_i)``, ``i = 0..4``, of (3.1); arrays ``(..., 5)``.

    Attributes
    ----------
    r, phi : ndarray
        Polar coordinates, in hyperbolic variables for ``i = 0, 1, 4`` and in
        elliptic variables for ``i = 2, 3``.

    Examples
    --------
    >>> from kapitza.phase_plane import notable_points
    >>> pts = notable_points(0.3, 0.15, 100.0)
    >>> pts.r
    array([1.        , 4.2604..., 4.4761..., 4.4761..., 4.3418...])
    >>> pts.phi
    array([ 0.3       ,  0.7626...,  0.8118..., -0.6126..., -0.5672...])
    """

    r: np.ndarray
    phi: np.ndarray

    def cartesian(self):
        """``(x, y)`` of the five points, arrays ``(..., 5)``."""
        return self.r * np.cos(self.phi), self.r * np.sin(self.phi)


@_v.shapes_named
def notable_points(phi0, T, A, r0=1.0, l=1.0, g=G_EARTH):
    """The notable points (3.1) of the trajectory starting at ``(r0, phi0)``.

    Parameters
    ----------
    phi0 : array_like
        Initial angle in the hyperbolic variables [rad]; the paper takes
        ``-2 pi < phi0 <= 0``.
    T, A : array_like
        Drive half-period and amplitude, ``A > g``.
    r0 : array_like, optional
        Initial radius, > 0.
    l, g : array_like, optional
        Rod length and gravity. All broadcast together.

    Returns
    -------
    NotablePoints

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    The four steps of section 2: ``phi_1 = phi_h(T; phi_0)`` (2.10) with
    ``r_1 = r_0 sqrt(|cos 2 phi_0| / |cos 2 phi_1|)`` (3.5), evaluated as
    ``r_0 e^x |(cos psi_0, e^{-2x} sin psi_0)|`` with ``psi_0 = phi_0 - pi/4 (mod pi)``
    (the components along the asymptotes scale by ``e^{+-x}``), which stays accurate
    where ``phi_1`` nears the asymptote and ``cos 2 phi_1`` cancels; the stretch
    ``r_2 = f(phi_1; D) r_1``, ``phi_2 = phi(phi_1; D)``; the clockwise rotation
    ``r_3 = r_2``, ``phi_3 = phi_2 - w_e T`` (2.13); the contraction
    ``r_4 = f(phi_3; 1/D) r_3``, ``phi_4 = phi(phi_3; 1/D)``.

    Examples
    --------
    >>> from kapitza.phase_plane import notable_points
    >>> pts = notable_points(0.3, 0.15, 100.0)
    >>> pts.phi.shape
    (5,)
    """
    phi0 = _v.finite("phi0", phi0)
    T = _v.positive("T", T)
    A = _v.positive("A", A)
    r0 = _v.positive("r0", r0)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    if np.any(A <= g):
        raise _v.KapitzaValueError("A must exceed g (A > g) for the elliptic phase to exist")
    phi0, T, A, r0, l, g = np.broadcast_arrays(phi0, T, A, r0, l, g)
    _v.finite_rate(A, l, g)
    w_h = np.sqrt((A + g) / l)
    w_e = np.sqrt((A - g) / l)
    D = w_h / w_e
    with np.errstate(over="ignore"):
        x = w_h * T
    if not np.all(np.isfinite(x)):
        i = np.unravel_index(int(np.argmax(~np.isfinite(x))), x.shape) if x.ndim else ()
        raise _v.KapitzaValueError(
            f"T must satisfy T sqrt((A + g) / l) <= 1.8e308 (the phases of the half period must be doubles); "
            f"got T = {float(T[i])!r} with A = {float(A[i])!r}, l = {float(l[i])!r}, g = {float(g[i])!r}")
    phi1 = _phi_h(T, phi0, w_h)
    psi0 = phi0 - QPI - np.round((phi0 - QPI) / PI) * PI
    with np.errstate(over="ignore", under="ignore"):
        r1 = r0 * np.exp(x) * np.hypot(np.cos(psi0), np.exp(-2.0 * x) * np.sin(psi0))
    phi2 = _angle_map(phi1, D)
    r2 = _f(phi1, D) * r1
    phi3 = phi2 - w_e * T
    r3 = r2
    phi4 = _angle_map(phi3, 1.0 / D)
    r4 = _f(phi3, 1.0 / D) * r3
    return NotablePoints(r=np.stack([r0, r1, r2, r3, r4], -1), phi=np.stack([phi0, phi1, phi2, phi3, phi4], -1))
