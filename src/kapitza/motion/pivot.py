"""Where the pivot is: a drive's acceleration and its integrals (the paper's square wave (2.2) by default).

With the square wave the pivot moves vertically with acceleration ``a(t) = +A`` on ``[2kT, (2k+1)T)`` and
``-A`` on ``[(2k+1)T, (2k+2)T)``. Its velocity and displacement are the periodic,
zero-mean integrals of ``a``: the displacement is a parabola in each phase, lowest
(``-A T^2/8``) at the middle of the hyperbolic phase and highest (``+A T^2/8``) at
the middle of the elliptic one, so the stroke is ``A T^2 / 4``.
"""
from __future__ import annotations

import numpy as np

from .. import _validate as _v
from ..drives import as_drive
from ._pivot import _checked, _stroke_checked

__all__ = ["pivot_acceleration", "pivot_velocity", "pivot_displacement", "pivot_stroke"]


@_v.shapes_named
def pivot_acceleration(t, T, A, *, drive=None):
    """The pivot's acceleration ``a(t)`` [m/s^2] (eq. 2.2).

    Parameters
    ----------
    t : array_like
        Times [s] (any real; the drive is periodic).
    T, A : array_like
        Half-period [s] and amplitude [m/s^2], each > 0. All arguments broadcast.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.

    Returns
    -------
    ndarray
        ``A s(t/T)`` of the drive's shape ``s``; for the square wave ``+A`` on
        ``[2kT, (2k+1)T)``, ``-A`` on ``[(2k+1)T, (2k+2)T)``.

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
    return _v.scalars(np.asarray(as_drive(drive).acceleration(*_checked(t, T, A))))


@_v.shapes_named
def pivot_velocity(t, T, A, *, drive=None):
    """The pivot's velocity [m/s]: periodic, zero mean, ``d/dt`` of it is ``a(t)``.

    Parameters
    ----------
    t, T, A, drive
        As in :func:`pivot_acceleration`.

    Returns
    -------
    ndarray
        For the square wave ``A (t - T/2)`` on the hyperbolic phase, ``-A (t - 3T/2)`` on the elliptic one
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
    return _v.scalars(np.asarray(as_drive(drive).velocity(*_checked(t, T, A))))


@_v.shapes_named
def pivot_displacement(t, T, A, *, drive=None):
    """The pivot's height [m] above its mean position: periodic, zero mean, piecewise parabolic.

    Parameters
    ----------
    t, T, A, drive
        As in :func:`pivot_acceleration`.

    Returns
    -------
    ndarray
        For the square wave ``A (t - T/2)^2 / 2 - A T^2/8`` on ``[0, T)`` and ``A T^2/8 - A (t - 3T/2)^2 / 2``
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
    return _v.scalars(np.asarray(as_drive(drive).displacement(*_checked(t, T, A))))


@_v.shapes_named
def pivot_stroke(T, A, *, drive=None):
    """Peak-to-peak travel of the pivot [m]: ``A T^2 / 4`` for the square wave.

    Parameters
    ----------
    T, A : array_like
        Each > 0; broadcast together.
    drive : Drive or str, optional
        As in :func:`pivot_acceleration`.

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
    return _v.scalars(np.asarray(as_drive(drive)._stroke_coefficient * A * T * T))
