"""Kapitza's original drive: a sinusoidal pivot, the Mathieu equation.

Acceleration ``A sin(pi t / T)``; velocity ``-(A T/pi) cos(pi t/T)``; displacement
``-(A T^2/pi^2) sin(pi t/T)``, so the pivot ``z = a cos(w t + phase)`` has amplitude
``a = A T^2/pi^2`` and angular frequency ``w = pi/T``. With ``z = pi t/(2T) - pi/4`` the
linearised equation is Mathieu's ``y'' + (a_M - 2 q cos 2z) y = 0`` with
``q = 16 eps^2/pi^2`` and ``a_M = -2 mu^2 q`` (``docs/mathieu.md``); its zone edges are
characteristic values computed by :mod:`kapitza.mathieu`.
"""
from __future__ import annotations

import numpy as np

from . import _api
from ._base import Drive, Floquet0

PI = np.pi

#: damped zone edges of the last few calls of :meth:`SineWave._edges` with at most four rows
_DAMPED_EDGES: dict = {}


class SineWave(Drive):
    """Sinusoidal pivot: acceleration ``A sin(pi t / T)`` (period ``2T``).

    Examples
    --------
    >>> import kapitza
    >>> drive = kapitza.SineWave()
    >>> drive.describe()
    'sine wave (acceleration A sin(pi t/T))'
    >>> kapitza.zone_edges(0.3, 0, drive=drive)
    (np.float64(0.4746...), np.float64(0.8114...))
    >>> kapitza.is_stable(0.45, 0.3), kapitza.is_stable(0.45, 0.3, drive=drive)
    (np.True_, np.False_)
    >>> drive.from_rig(40.0, stroke=0.02)
    (np.float64(0.0125), np.float64(631.6546...))
    """

    name = "sine"
    title = "sine (Kapitza's shaker)"
    _stroke_coefficient = 2.0 / PI**2
    _mean_square_velocity = 1.0 / (2.0 * PI**2)
    _trough = 1.0
    peak = 1.0

    def _shape(self, tau):
        return np.sin(PI * tau)

    def _velocity_shape(self, tau):
        return -np.cos(PI * tau) / PI

    def _displacement_shape(self, tau):
        return -np.sin(PI * tau) / PI**2

    def _shape_table(self):
        if not self._own("_shape_table"):
            return None
        return np.array([0.0, 1.0]), np.zeros(1), np.zeros(1), np.ones(1)  # sin(pi tau) = sin(2 pi x)

    def _floquet0(self, eps, mu, certify=True, trace=False, phi=None):
        from ._mathieu import sine_floquet0

        # the damped system's phi-equation, its trace not reported: a certified verdict may come with
        # a rough trace, and those points are marked for the damping layer's own exact verdict
        loose = phi is not None and not trace and certify
        tau, log_tau, growth, theta, zone, *more = sine_floquet0(eps, mu, certify, errors=trace, loose=loose)
        return Floquet0(tau=tau, log_tau=log_tau, growth=growth, theta=theta, zone=zone,
                        tau_error=more[0] if trace else None, unsure=more[-1] if loose else None)

    def _certified_steps(self, damped):
        # the certified verdicts are the Sturm counts again, in long double only within the double's
        # band of an edge (the exact trace within the long double's): asked from 2^36 ulp they spare
        # the fast steps to the last bit, whose change lies some thousand ulp from the certified one,
        # and the search of the windows about it (13 calls of the drive -> 7 at an ordinary point)
        return True

    def _joint_search(self, zeta, level0):
        # where the zone is known beforehand (inside it, or below zone 0) the margin's and the rig's six
        # edges share each call of the drive (about half a millisecond, however many points); in a gap
        # between zones the margin's own path (the counts' roots, then their certified sides) asks fewer
        return _api.known_zone(level0) is not None and self._joint_edges(zeta)

    def _eps_reach(self, mu):
        from ._mathieu import eps_reach

        return eps_reach(mu)

    def _verdict0(self, eps, mu):
        from ._mathieu import sine_verdict0

        return sine_verdict0(eps, mu)

    def _signs0(self, eps, mu):
        from ._mathieu import sine_signs0

        return sine_signs0(eps, mu)

    def _log_tau0(self, eps, mu):
        from ._mathieu import sine_log_tau

        return sine_log_tau(eps, mu)

    def _tau_minus_one0(self, eps, mu):
        from ._mathieu import sine_tau_minus_one

        return sine_tau_minus_one(eps, mu)

    def _edges0(self, mu, n):
        from ._mathieu import sine_edges

        mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
        ok = mu < 1.0  # no attracting part of the period when A <= g (mu >= 1)
        lo, hi = sine_edges(np.where(ok, mu, 0.5), n)
        return np.where(ok, lo, np.nan), np.where(ok, hi, np.nan)

    def _edges(self, mu, n, zeta):
        # damped edges of a few zones are searched on the drive's trace (hundreds of calls); one
        # point's report asks for its zone's twice (its margin, then the edges moved to the certified
        # doubles): the answer of the last few calls is kept, by their exact arguments
        mu, n, zeta = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64), np.asarray(zeta, float))
        if mu.size > 4 or not np.any(zeta > 0):
            return super()._edges(mu, n, zeta)
        key = (type(self), mu.ravel().tobytes(), n.ravel().tobytes(), zeta.ravel().tobytes())
        found = _DAMPED_EDGES.get(key)
        if found is None:
            lo, hi = super()._edges(mu, n, zeta)
            found = (np.array(lo, float).ravel(), np.array(hi, float).ravel())
            if len(_DAMPED_EDGES) >= 64:
                _DAMPED_EDGES.clear()
            _DAMPED_EDGES[key] = found
        return found[0].reshape(mu.shape).copy(), found[1].reshape(mu.shape).copy()

    #: every zone of a window at once, from the Sturm counts at its right end
    _windowed = True

    #: edges bisected row by row on the Sturm counts: the same double whichever call asks
    _edges_unique = True

    def _window0(self, mu, e_a, e_b):
        from ._mathieu import sine_window

        ok = np.flatnonzero(mu < 1.0)  # no zone when A <= g (mu >= 1)
        rows, zone, lo, hi = sine_window(mu[ok], e_b[ok])
        return ok[rows], zone, lo, hi

    @property
    def _damped_certified(self) -> bool:
        return True

    def _damped_exact(self, eps, mu, zeta, growth=True):
        from ._mathieu import sine_damped_exact

        return sine_damped_exact(eps, mu, zeta, growth)

    def paint(self, eps, mu, zeta, out):
        if zeta > 0:
            return super().paint(eps, mu, zeta, out)
        from ._mathieu import sine_grid  # crossings bisected only until no pixel is left inside

        return sine_grid(eps, mu, out)

    @property
    def label(self) -> str:
        return "sine wave"

    def describe(self) -> str:
        return "sine wave (acceleration A sin(pi t/T))"
