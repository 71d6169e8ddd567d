"""Where the pivot is: the square-wave acceleration (2.2) and its integrals.

The pivot moves vertically with acceleration ``a(t) = +A`` on ``[2kT, (2k+1)T)`` and
``-A`` on ``[(2k+1)T, (2k+2)T)``. Its velocity and displacement are the periodic,
zero-mean integrals of ``a``: the displacement is a parabola in each phase, lowest
(``-A T^2/8``) at the middle of the hyperbolic phase and highest (``+A T^2/8``) at
the middle of the elliptic one, so the stroke is ``A T^2 / 4``.
"""
from __future__ import annotations

import numpy as np

from .. import _validate as _v
from ._pivot import _acceleration, _checked, _displacement, _stroke_checked, _velocity

__all__ = ["pivot_acceleration", "pivot_velocity", "pivot_displacement", "pivot_stroke"]


@_v.shapes_named
def pivot_acceleration(t, T, A):
    """The pivot's acceleration ``a(t)`` [m/s^2] (eq. 2.2).

    Parameters
    ----------
    t : array_like
        Times [s] (any real; the drive is periodic).
    T, A : array_like
        Half-period [s] and amplitude [m/s^2], each > 0. All arguments broadcast.

    Returns
    -------
    ndarray
        ``+A`` on ``[2kT, (2k+1)T)``, ``-A`` on ``[(2k+1)T, (2k+2)T)``.

    Raises
    ------
    ValueError
        If ``T`` or ``A`` is not finite and > 0, or the arguments do not broadcast.

    Examples
    --------
    >>> from kapitza.motion import pivot_acceleration
    >>> pivot_acceleration([0.05, 0.2], 0.15, 100.0)
    array([ 100., -100.])
    """
    return _v.scalars(np.asarray(_acceleration(*_checked(t, T, A))))


@_v.shapes_named
def pivot_velocity(t, T, A):
    """The pivot's velocity [m/s]: periodic, zero mean, ``d/dt`` of it is ``a(t)``.

    Parameters
    ----------
    t, T, A : array_like
        As in :func:`pivot_acceleration`.

    Returns
    -------
    ndarray
        ``A (t - T/2)`` on the hyperbolic phase, ``-A (t - 3T/2)`` on the elliptic one
        (``t`` taken modulo ``2T``).

    Raises
    ------
    ValueError
        As in :func:`pivot_acceleration`.

    Examples
    --------
    >>> from kapitza.motion import pivot_velocity
    >>> pivot_velocity([0.0, 0.075, 0.15], 0.15, 100.0)
    array([-7.5,  0. ,  7.5])
    """
    return _v.scalars(np.asarray(_velocity(*_checked(t, T, A))))


@_v.shapes_named
def pivot_displacement(t, T, A):
    """The pivot's height [m] above its mean position: periodic, zero mean, piecewise parabolic.

    Parameters
    ----------
    t, T, A : array_like
        As in :func:`pivot_acceleration`.

    Returns
    -------
    ndarray
        ``A (t - T/2)^2 / 2 - A T^2/8`` on ``[0, T)`` and ``A T^2/8 - A (t - 3T/2)^2 / 2``
        on ``[T, 2T)`` (``t`` modulo ``2T``); continuous with a continuous first
        derivative, second derivative ``a(t)``.

    Raises
    ------
    ValueError
        As in :func:`pivot_acceleration`.

    Notes
    -----
    The two integration constants are fixed by periodicity of the velocity and a
    zero mean of the displacement over one period.

    Examples
    --------
    >>> from kapitza.motion import pivot_displacement
    >>> pivot_displacement([0.075, 0.225], 0.15, 100.0)
    array([-0.2812...,  0.2812...])
    """
    return _v.scalars(np.asarray(_displacement(*_checked(t, T, A))))


@_v.shapes_named
def pivot_stroke(T, A):
    """Peak-to-peak travel of the pivot, ``A T^2 / 4`` [m].

    Parameters
    ----------
    T, A : array_like
        Each > 0; broadcast together.

    Returns
    -------
    ndarray

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Examples
    --------
    >>> from kapitza.motion import pivot_stroke
    >>> pivot_stroke(0.15, 100.0)
    np.float64(0.5625)
    """
    T = _v.positive("T", T)
    A = _v.positive("A", A)
    _stroke_checked(T, A)
    return _v.scalars(np.asarray(0.25 * A * T * T))
