"""A triangle-wave acceleration: linear between ``+A`` and ``-A``, zero mean.

``s(tau)`` rises from 0 to 1 on ``[0, 1/2]``, falls to -1 at ``tau = 3/2`` and returns to 0 at
``tau = 2``: the sine's phase, with straight flanks (``docs/drives.md``, "The triangle wave").
Its kinematics are exact piecewise polynomials::

    V = tau^2 - 1/4,  -tau^2 + 2 tau - 3/4,  (tau - 2)^2 - 1/4
    Z = tau^3/3 - tau/4,  1/12 - tau^3/3 + tau^2 - 3 tau/4,  1/2 + (tau - 2)^3/3 - tau/4

on ``[0, 1/2]``, ``[1/2, 3/2]``, ``[3/2, 2]``: stroke ``A T^2 / 6``, ``<v^2> = (A T)^2 / 30``,
averaging edge ``eps_K = mu sqrt(15)/2``. The stability data come from the generic engine
(:mod:`kapitza.engines`) on a grid aligned with the kinks at ``tau = 1/2, 3/2``: the acceleration
is linear on every step, where the sixth-order Magnus step is accurate to rounding; where that
trace lies within its accuracy of the threshold, the verdict is decided in extended precision on
the three linear pieces (:func:`kapitza._certify.pieces_exact`: long double, mpmath where that
cannot decide), with and without damping.
"""
from __future__ import annotations

import numpy as np

from ._base import Drive


class TriangleWave(Drive):
    """Triangle-wave pivot acceleration: linear between ``+A`` (at ``t = T/2``) and ``-A``
    (at ``t = 3T/2``), period ``2T``, zero mean.

    Examples
    --------
    >>> import kapitza
    >>> drive = kapitza.TriangleWave()
    >>> drive.describe()
    'triangle wave (acceleration linear between +A and -A)'
    >>> kapitza.zone_edges(0.3, 0, drive=drive)
    (np.float64(0.5870...), np.float64(0.9184...))
    >>> drive.stroke(T=0.0125, A=768.0)
    np.float64(0.0200...)
    """

    name = "triangle"
    title = "triangle wave"
    _breakpoints = (0.5, 1.5)
    _min_steps = 128
    _stroke_coefficient = 1.0 / 6.0
    _mean_square_velocity = 1.0 / 30.0
    _trough = 1.0
    peak = 1.0

    def _shape(self, tau):
        tau = np.asarray(tau, float)
        return np.where(tau < 0.5, 2.0 * tau, np.where(tau < 1.5, 2.0 - 2.0 * tau, 2.0 * tau - 4.0))

    def _velocity_shape(self, tau):
        tau = np.asarray(tau, float)
        return np.where(tau < 0.5, tau * tau - 0.25,
                        np.where(tau < 1.5, -tau * tau + 2.0 * tau - 0.75, (tau - 2.0) ** 2 - 0.25))

    def _displacement_shape(self, tau):
        tau = np.asarray(tau, float)
        return np.where(tau < 0.5, tau**3 / 3.0 - 0.25 * tau,
                        np.where(tau < 1.5, 1.0 / 12.0 - tau**3 / 3.0 + tau * tau - 0.75 * tau,
                                 0.5 + (tau - 2.0) ** 3 / 3.0 - 0.25 * tau))

    def _linear_pieces(self):
        return ((0.0, 0.5, 0.0, 1.0), (0.5, 1.5, 1.0, -1.0), (1.5, 2.0, -1.0, 0.0))

    @property
    def label(self) -> str:
        return "triangle wave"

    def describe(self) -> str:
        return "triangle wave (acceleration linear between +A and -A)"
