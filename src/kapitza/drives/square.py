"""The paper's drive (2.2): ``+A`` for ``T``, then ``-A`` for ``T``.

Undamped, every question is answered from the closed forms of Theorems 3.3-3.4 and
Corollary 4.1 (:mod:`kapitza._square`, certified to the last bit by :mod:`kapitza._certify`;
one point of :func:`kapitza.analyze` first from their scalar twins, :mod:`kapitza._point`):
these methods override the generic ones of :class:`~kapitza.drives.Drive`. With damping the
generic layer applies these same closed forms at ``mu_c = mu sqrt(1 + zeta^2)``
(``docs/drives.md``, "The damped square wave").
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from .. import _square as S
from .. import _validate as _v
from ._base import Floquet0, log_cosh
from ._piecewise import PiecewiseConstant, floquet_product


def _undamped(zeta) -> bool:
    return not np.any(np.asarray(zeta) > 0)


class SquareWave(PiecewiseConstant):
    """The paper's symmetric square wave: acceleration ``+A`` on ``[0, T)``, ``-A`` on ``[T, 2T)``.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> drive = kapitza.SquareWave()
    >>> drive.describe()
    'square wave (+A for T, -A for T)'
    >>> drive.acceleration(np.array([0.0, 0.05, 0.1, 0.15]), T=0.1, A=100.0)
    array([ 100.,  100., -100., -100.])
    >>> drive.from_rig(40.0, stroke=0.02)
    (np.float64(0.0125), np.float64(511.9999...))
    >>> kapitza.zone_edges(0.3, 0, drive=drive) == kapitza.zone_edges(0.3, 0)
    True
    """

    name = "square"
    title = "square wave (the paper's)"
    #: zones one by one from their closed-form edges (a few Newton steps each), not by a window
    _windowed = False

    def __init__(self):
        super().__init__((1.0, -1.0), (0.5, 0.5))

    # ------------------------------------------------------------ kinematics: the closed forms
    # (one rule for which phase a time is in, ``floor(t/T)``, shared with the exact motion's checks)
    def acceleration(self, t, T, A):
        return S._acceleration(*self._checked(t, T, A))

    def velocity(self, t, T, A):
        return S._velocity(*self._checked(t, T, A))

    def displacement(self, t, T, A):
        return S._displacement(*self._checked(t, T, A))

    # ------------------------------------------------------------ undamped data (the damping layer's input)
    def _certified_cheap(self, damped):
        # undamped, its closed forms are certified in mpmath (kapitza._certify)
        return damped and super()._certified_cheap(damped)

    def _floquet0(self, eps, mu, certify=True, trace=False, phi=None):
        # the closed forms are certified at no cost off a band a few ulp wide about each edge; in it
        # a verdict is the step product's (long double, then mpmath: floquet_product), a reported
        # trace mpmath's to the last bit
        if certify and not trace:
            eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
            f = self._floquet0(eps, mu, certify=False)
            if f.unsure is None or not np.any(f.unsure):
                return replace(f, unsure=None)
            band = np.flatnonzero(f.unsure.ravel())
            g = floquet_product(eps.ravel()[band], mu.ravel()[band], self.levels, self._durations, True)

            def settled(name):   # the closed forms' values with the band's from the product
                v = np.array(getattr(f, name), copy=True)
                v.ravel()[band] = getattr(g, name)
                return v

            fields = ("tau", "log_tau", "growth", "theta", "zone")
            return replace(f, unsure=None, **{name: settled(name) for name in fields})
        tau, growth, theta, stable, zone, *extra = S._floquet(eps, mu, bool(certify), trace, phi,
                                                             with_unsure=not (certify or trace))
        with np.errstate(divide="ignore"):
            log_tau = np.where(np.isfinite(tau), np.log(np.abs(tau)), log_cosh(growth))
        return Floquet0(tau=tau, log_tau=log_tau, growth=growth, theta=theta, zone=zone,
                        tau_error=extra[0] if trace else None,
                        unsure=None if (certify or trace) else extra[0])

    def _log_tau0(self, eps, mu):
        return self._floquet0(eps, mu, certify=False).log_tau

    def _edges0(self, mu, n):
        mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
        ok = mu < 1.0
        lo, hi = S._edges_eps(np.where(ok, mu, 0.5), n)
        return np.where(ok, lo, np.nan), np.where(ok, hi, np.nan)

    # ------------------------------------------------------------ the questions, undamped
    def closed_form(self, zeta=0.0) -> bool:
        return _undamped(zeta)

    def floquet_data(self, eps, mu, zeta):
        if not _undamped(zeta):
            return super().floquet_data(eps, mu, zeta)
        tau, growth, theta, stable, zone, err = S._floquet(eps, mu, trace=True)
        with np.errstate(over="ignore"):  # tr M is +-inf where it overflows a double (documented)
            trace = 2.0 * tau
            err = np.where(np.isfinite(trace), 2.0 * err, np.inf)
        return (trace, 1.0, S._multipliers(tau, growth, theta, stable), growth, theta / (2.0 * np.pi), stable, zone,
                err)

    def verdict(self, eps, mu, zeta, want_zone=True):
        if not _undamped(zeta):
            return super().verdict(eps, mu, zeta, want_zone)
        stable, n = S._verdict(eps, mu, want_n=want_zone)
        return stable, (np.where(stable, n, -1).astype(np.int64) if want_zone else None)

    def growth(self, eps, mu, zeta):
        return super().growth(eps, mu, zeta) if not _undamped(zeta) else S._floquet(eps, mu, trace=True)[1]

    def rotation(self, eps, mu, zeta):
        return (super().rotation(eps, mu, zeta) if not _undamped(zeta) else
                S._floquet(eps, mu, trace=True)[2] / (2.0 * np.pi))

    def edges(self, mu, n, zeta, certify=True):
        # undamped, the closed forms' edges (within 4 ulp of the exact ones, either side; mu < 1),
        # moved like every drive's to the doubles the certified verdict puts them at
        if _undamped(zeta):
            mu = _v.in_range("mu", mu, 0.0, 1.0)
        return super().edges(mu, n, zeta, certify)

    def margin(self, eps, mu, zeta):
        return super().margin(eps, mu, zeta) if not _undamped(zeta) else S.margin(eps, mu)

    def paint(self, eps, mu, zeta, out):
        return super().paint(eps, mu, zeta, out) if not _undamped(zeta) else S.grid(eps, mu, out)

    def period_edges(self, A, n, l, g, c):
        return super().period_edges(A, n, l, g, c) if not _undamped(c) else S.period_edges(A, n, l, g)

    def amplitude_edges(self, T, n, l, g, c):
        if not _undamped(c):
            return super().amplitude_edges(T, n, l, g, c)
        return S.amplitude_edges(*np.broadcast_arrays(T, n, l, g))

    def monodromy(self, T, A, l, g, c):
        return super().monodromy(T, A, l, g, c) if not _undamped(c) else S._monodromy(*np.broadcast_arrays(T, A, l, g))

    def linear_motion(self, t, theta0, dtheta0, T, A, l, g, c):
        if not _undamped(c):
            return super().linear_motion(t, theta0, dtheta0, T, A, l, g, c)
        return S.linear_motion(t, theta0, dtheta0, T, A, l, g)

    # ------------------------------------------------------------ one point, undamped
    # Each part is first asked of its scalar twin (:mod:`kapitza._point`: Python floats, where
    # numpy's overhead per call on one-element arrays was most of the time); the array kernels
    # answer wherever a twin declines -- within the rounding bound of an edge, where the verdict
    # is decided in extended precision, or near a threshold of the nonlinear verdict -- and
    # everywhere with ``pointwise=False``, the path the twins are tested against.
    def point_floquet(self, eps, mu, zeta, pointwise=True):
        if not _undamped(zeta):
            return super().point_floquet(eps, mu, zeta, pointwise)
        from .. import _point

        fl = _point.floquet(eps, mu) if pointwise else None
        if fl is None:
            tau, growth, theta, stable, zone = (np.asarray(a)[()] for a in S._floquet(eps, mu, trace=True)[:5])
            mult = tuple(complex(z) for z in S._multipliers(tau, growth, theta, stable))
            tau, growth, theta, stable, zone = float(tau), float(growth), float(theta), bool(stable), int(zone)
        else:
            tau, growth, theta, stable, zone = fl
            mult = _point.multipliers(tau, growth, theta, stable)
        return 2.0 * tau, 1.0, mult, growth, theta / (2.0 * np.pi), stable, zone, theta, fl is None

    def _joint_edges(self, zeta):
        return not _undamped(zeta)   # undamped, the closed forms answer each part

    def point_margin(self, eps, mu, zeta, pointwise=True):
        if not _undamped(zeta):
            return super().point_margin(eps, mu, zeta, pointwise)
        from .. import _point

        mg = _point.stability_margin(eps, mu) if pointwise else None
        if mg is None:
            st, zone, lo, hi, m = (np.asarray(a)[()] for a in S.margin(np.asarray(eps, float), np.asarray(mu, float)))
            mg = (bool(st), int(zone), float(lo), float(hi), float(m))
        return mg

    def point_intervals(self, eps, mu, zone, zeta, T, A, l, g, c, pointwise=True, eps_edges=None):
        if not _undamped(zeta):
            return super().point_intervals(eps, mu, zone, zeta, T, A, l, g, c, pointwise, eps_edges)
        from .. import _point

        rig = _point.rig_intervals(eps, mu, zone, T, A, l, g) if pointwise else None
        if rig is None:
            Tlo, Thi = S.period_edges(*(np.asarray(v, float) for v in (A, zone, l, g)))
            Alo, Ahi = S.amplitude_edges(*np.broadcast_arrays(*(np.asarray(v, float) for v in (T, zone, l, g))))
            stroke = 0.25 * A * T * T
            rig = dict(T_lo=float(Tlo), T_hi=float(Thi), A_lo=float(Alo), A_hi=float(Ahi),
                       stroke_lo=float(stroke * Alo / A), stroke_hi=float(stroke * Ahi / A))
            rig.update(S.rig_margins(eps, mu, zone, T, stroke))
        return rig

    def point_sentence(self, mu, zeta, zone, eps_lo):
        if _undamped(zeta) and mu >= 1.0:
            return "always unstable: no elliptic phase (A <= g)"
        return super().point_sentence(mu, zeta, zone, eps_lo)

    def point_nonlinear(self, eps, mu, zeta, theta, zone, exact_theta, pointwise=True):
        if not _undamped(zeta):
            return None
        from .. import _point

        sentence = _point.nonlinear(eps, mu, theta, zone, exact_theta=exact_theta) if pointwise else None
        if sentence is None:
            from ..normal_form import nonlinear_stability, sentence_of

            sentence = sentence_of(eps, mu) if pointwise else str(nonlinear_stability(eps, mu))
        return sentence

    # ------------------------------------------------------------ descriptions
    def as_dict(self) -> dict:
        return {"drive": self.name}

    @property
    def label(self) -> str:
        return "square wave"

    def describe(self) -> str:
        return "square wave (+A for T, -A for T)"
