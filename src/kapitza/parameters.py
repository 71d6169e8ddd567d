"""Parameters of the model and their conversions.

Physical parameters: rod length ``l``, gravity ``g``, pivot-acceleration
amplitude ``A`` and half-period ``T`` of the square wave (2.2). Arnold's
dimensionless parameters (section 4 of the paper, ``docs/theory.md`` section 2)::

    eps = T sqrt(A) / sqrt(8 l),        mu = sqrt(g / A).

Everything about stability depends on ``(eps, mu)`` only, through

    x = w_h T = 2 sqrt(2) eps sqrt(1 + mu^2),
    u = w_e T = 2 sqrt(2) eps sqrt(1 - mu^2),
    D = w_h / w_e = sqrt((1 + mu^2) / (1 - mu^2)).

``mu >= 1`` (``A <= g``) is valid input: there is then no elliptic phase and the
upright position is unstable for every ``T``.
"""
from __future__ import annotations

import numpy as np

from . import _validate as _v

__all__ = [
    "G_EARTH",
    "to_arnold",
    "to_physical",
    "frequencies",
    "phase_angles",
]

#: Standard gravity used by default throughout, in m/s^2 (the paper's examples use 9.81).
G_EARTH = 9.81

SQRT8 = np.sqrt(8.0)


@_v.shapes_named
def to_arnold(T, A, l=1.0, g=G_EARTH):
    """Arnold's parameters ``(eps, mu)`` of physical parameters.

    Parameters
    ----------
    T, A, l, g : array_like, broadcast together
        Half-period of the drive [s], amplitude of the pivot acceleration
        [m/s^2], rod length [m], gravity [m/s^2]; each finite and > 0.

    Returns
    -------
    eps, mu : ndarray
        ``eps = T sqrt(A / (8 l))``, ``mu = sqrt(g / A)``. ``mu >= 1`` means
        ``A <= g``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    Section 4 of the paper ("Stability zones").

    Examples
    --------
    >>> import kapitza
    >>> kapitza.to_arnold(T=0.15, A=100.0, l=1.0)
    (np.float64(0.5303...), np.float64(0.3132...))
    """
    T = _v.positive("T", T)
    A = _v.positive("A", A)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    _v.shape_check(T=T, A=A, l=l, g=g)
    eps, mu = arnold_trusted(T, A, l, g)
    _refuse_outside(dict(T=T, A=A, l=l, g=g), eps=eps, mu=mu)
    return eps, mu


def arnold_trusted(T, A, l, g):
    """``(eps, mu)`` of trusted positive ``T, A, l, g``, with no warning: where ``A / (8 l)`` or
    ``g / A`` overflows or underflows before its square root would, the roots are taken apart."""
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        eps, mu = T * np.sqrt(A / (8.0 * l)), np.sqrt(g / A)
        if not _in_double(eps, mu):
            eps = T * (np.sqrt(A) / np.sqrt(8.0 * l))
            mu = np.sqrt(g) / np.sqrt(A)
    return eps, mu


def _in_double(*arrays) -> bool:
    return all(bool(np.all(np.isfinite(a) & (a > 0))) for a in arrays)


def _refuse_outside(given, **results):
    """Refuse inputs whose derived parameters leave the range of positive doubles, naming them."""
    for name, v in results.items():
        bad = ~(np.isfinite(v) & (v > 0))
        if np.any(bad):
            # (a result may depend on some of the inputs only, and have fewer entries than others)
            shape = np.broadcast_shapes(bad.shape, *(np.shape(x) for x in given.values()))
            i = np.unravel_index(int(np.argmax(np.broadcast_to(bad, shape))), shape) if shape else ()
            shown = ", ".join(f"{k} = {float(np.broadcast_to(x, shape)[i])!r}" for k, x in given.items())
            raise _v.KapitzaValueError(
                f"{', '.join(given)} give {name} = {float(np.broadcast_to(v, shape)[i])!r}, outside the range of "
                f"positive doubles; got {shown}")


@_v.shapes_named
def time_scale(l, A):
    """``sqrt(8 l / A)``, the half-period ``T`` per unit ``eps`` (trusted arrays). ``8 l / A`` leaves
    the normal doubles before ``T`` does (``l = 1e-100, A = 1e250``: ``T_lo ~ 1e-299``; ``l = 1e308``:
    it overflows): there it is formed as ``sqrt(8) sqrt(l) / sqrt(A)``."""
    with np.errstate(over="ignore", under="ignore"):
        r = 8.0 * l / A
        return np.where(np.isfinite(r) & (r > 1e-300), np.sqrt(r), SQRT8 * (np.sqrt(l) / np.sqrt(A)))


def to_physical(eps, mu, l=1.0, g=G_EARTH):
    """Physical ``(T, A)`` of Arnold's ``(eps, mu)`` for a rod ``l`` under gravity ``g``.

    Parameters
    ----------
    eps, mu, l, g : array_like, broadcast together
        Each finite and > 0.

    Returns
    -------
    T, A : ndarray
        ``A = g / mu^2`` and ``T = eps sqrt(8 l / A)``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.to_physical(0.5, 0.3)
    (np.float64(0.1354...), np.float64(109.0000...))
    """
    eps = _v.positive("eps", eps)
    mu = _v.positive("mu", mu)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    _v.shape_check(eps=eps, mu=mu, l=l, g=g)
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        A = g / mu**2
        T = eps * np.sqrt(8.0 * l / A)
        if not _in_double(T, A):
            A = (np.sqrt(g) / mu) ** 2
            T = eps * mu * (np.sqrt(8.0 * l) / np.sqrt(g))
    _refuse_outside(dict(eps=eps, mu=mu, l=l, g=g), T=T, A=A)
    return T, A


@_v.shapes_named
def frequencies(A, l=1.0, g=G_EARTH):
    """Hyperbolic and elliptic frequencies ``w_h``, ``w_e`` and their ratio ``D``.

    Parameters
    ----------
    A, l, g : array_like, broadcast together
        Each finite and > 0.

    Returns
    -------
    w_h, w_e, D : ndarray
        ``w_h = sqrt((A + g) / l)``, ``w_e = sqrt((A - g) / l)``, ``D = w_h / w_e``.
        Where ``A <= g`` there is no elliptic phase: there ``w_e = 0`` and
        ``D = inf`` are returned, and the upright position is unstable for
        every ``T`` (see :func:`kapitza.analyze`).

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    Equations (2.4)-(2.5) of the paper.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.frequencies(100.0)
    (np.float64(10.4790...), np.float64(9.4968...), np.float64(1.1034...))
    """
    A = _v.positive("A", A)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    _v.finite_rate(A, l, g)
    w_h = np.sqrt((A + g) / l)
    w_e = np.sqrt(np.maximum(A - g, 0.0) / l)
    with np.errstate(divide="ignore"):
        D = np.where(w_e > 0, w_h / np.where(w_e > 0, w_e, 1.0), np.inf)
    return _v.scalars(w_h, w_e, D)


@_v.shapes_named
def phase_angles(eps, mu):
    """The phase angles ``x = w_h T``, ``u = w_e T`` and the ratio ``D`` for Arnold's parameters.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        ``eps > 0`` and ``0 < mu < 1``.

    Returns
    -------
    x, u, D : ndarray

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``docs/theory.md`` section 2. ``1 - mu^2`` is formed as ``(1 - mu)(1 + mu)``
    so that ``u`` and ``D`` keep full relative accuracy as ``mu -> 1``.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.phase_angles(0.5, 0.3)
    (np.float64(1.4764...), np.float64(1.3490...), np.float64(1.0944...))
    """
    eps, _ = _v.arnold(eps, 0.5, together=False)  # eps <= EPS_MAX: x and u stay doubles
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    return phase_angles_trusted(eps, mu)


def phase_angles_trusted(eps, mu):
    """Kernel of :func:`phase_angles` (inputs trusted; ``mu < 1``)."""
    p = np.sqrt(1.0 + mu * mu)
    q = np.sqrt((1.0 - mu) * (1.0 + mu))
    return SQRT8 * eps * p, SQRT8 * eps * q, p / q


# the kernels' earlier names, for callers not yet moved to the public ones
_arnold = arnold_trusted
_phase_angles = phase_angles_trusted
