"""The drive protocol: what every pivot motion provides, and the damping layer on top of it.

A drive is the shape of the pivot's vertical acceleration over one period ``2T``:
``a(t) = A s(t/T)`` with ``s`` a dimensionless, zero-mean, ``2``-periodic function of
``tau = t/T``. ``T`` is half the drive period and ``A`` the acceleration scale for every
drive, so Arnold's ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` keep one meaning and
charts of different drives share their axes (``docs/drives.md``).

In ``tau`` the linearised equation about the upright with viscous damping ``c``,
``theta'' + c theta' = (g + a(t))/l theta``, reads

    theta_tau,tau + (c T) theta_tau = 8 eps^2 (mu^2 + s(tau)) theta.

The substitution ``theta = exp(-c t/2) phi`` removes the damping exactly:

    phi_tau,tau = 8 eps^2 (mu^2 (1 + zeta^2) + s(tau)) phi,     zeta = c / (2 sqrt(g/l)),

the undamped equation of the same drive at ``mu_c = mu sqrt(1 + zeta^2)``. Over one
period ``M_theta = exp(-kappa) S^{-1} M_phi S`` with ``kappa = c T = 2 sqrt(8) zeta mu eps``
and ``S`` the constant shear ``[[1, 0], [c/2, 1]]``, so

    tr M_theta = exp(-kappa) tr M_phi,        det M_theta = exp(-2 kappa),

and the multipliers are ``exp(-kappa)`` times those of the undamped ``phi``-system. Both
lie strictly inside the unit circle iff ``|tr M_theta| < 1 + det M_theta``, that is

    |tr M_phi| < 2 cosh(kappa).

A drive therefore only has to provide the undamped Floquet data and zone edges
(:meth:`Drive._floquet0`, :meth:`Drive._edges0`); damping is one generic layer here.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from . import _api
from ..parameters import time_scale
from .._exact import acosh_from_log, log_cosh  # noqa: F401  (shared with the drives' engines)

PI = np.pi
SQRT8 = np.sqrt(8.0)
LOG2 = np.log(2.0)


@dataclass(frozen=True)
class Floquet0:
    """Undamped Floquet data of a drive at ``(eps, mu)`` (arrays of one shape).

    ``tau`` is ``tr M / 2`` (``+-inf`` where it overflows), ``log_tau`` is ``log|tau|``
    (finite), ``growth`` is ``acosh|tau|`` off the zones and 0 on them, ``theta`` the
    rotation angle per period (in ``(n pi, (n + 1) pi)`` on zone ``n``, a multiple of
    ``pi`` off the zones), ``zone`` the zone index (-1 where unstable).
    """

    tau: np.ndarray
    log_tau: np.ndarray
    growth: np.ndarray
    theta: np.ndarray
    zone: np.ndarray


class Drive:
    """A pivot motion over one period ``2T``: ``a(t) = A s(t/T)``, ``s`` zero-mean.

    Subclasses provide the shape (:meth:`_shape`, :meth:`_velocity_shape`,
    :meth:`_displacement_shape`, :attr:`_stroke_coefficient`, :attr:`_mean_square_velocity`)
    and the undamped stability data (:meth:`_floquet0`, :meth:`_edges0`). Everything else
    — physical units, damping, verdicts — is built here once.
    """

    #: short name used by the command line and in reports
    name = "drive"
    #: the text form the command line and the web take (``name`` when there are no parameters)
    text_form: str | None = None

    @classmethod
    def from_text(cls, parameters, text=None):
        """The drive of the text form ``NAME:PARAMETERS`` (``parameters`` None for a bare ``NAME``;
        ``text`` the whole form, for messages). A drive without parameters takes none; a drive
        with parameters overrides this."""
        if parameters is not None:
            raise _v.KapitzaValueError(f"drive {cls.name!r} takes no parameters; got {text!r}")
        return cls()

    # ------------------------------------------------------------ what a subclass gives
    def _shape(self, tau):  # pragma: no cover - protocol
        raise NotImplementedError

    def _velocity_shape(self, tau):  # pragma: no cover - protocol
        raise NotImplementedError

    def _displacement_shape(self, tau):  # pragma: no cover - protocol
        raise NotImplementedError

    #: peak-to-peak of the displacement shape: stroke = coefficient * A T^2
    _stroke_coefficient: float = float("nan")
    #: mean of the squared velocity shape: <v^2> = coefficient * A^2 T^2
    _mean_square_velocity: float = float("nan")

    #: the largest downward acceleration of the shape, ``-min s``, in units of ``A``
    _trough: float = 1.0

    @property
    def mu_max(self) -> float:
        """The ``mu`` at and above which the upright is unstable for every ``T`` and damping.

        ``mu >= mu_max`` means ``A (-min s) <= g``: the pivot never accelerates downward faster
        than gravity, so ``g + a(t) >= 0`` all period and nothing ever pulls the rod back
        (the monodromy maps the cone ``theta, theta' >= 0`` into itself and its largest
        multiplier exceeds 1, with or without damping). ``sqrt(-min s)``: 1 for the square
        and sine waves; ``sqrt(duty / (1 - duty))`` for a rectangular wave, above 1 for a duty
        above one half (a short, hard downward stroke holds the rod up with ``A < g``).
        Stable zones lie at ``mu < mu_max`` only; charts and sweeps accept ``mu`` up to it.
        """
        return float(np.sqrt(self._trough))

    def _floquet0(self, eps, mu, certify=True) -> Floquet0:  # pragma: no cover - protocol
        raise NotImplementedError

    def _edges0(self, mu, n):  # pragma: no cover - protocol
        raise NotImplementedError

    def _log_tau0(self, eps, mu):
        """``log|tr M / 2|`` of the undamped drive (a drive may give it more cheaply)."""
        return self._floquet0(eps, mu, certify=False).log_tau

    def _tau_minus_one0(self, eps, mu):
        """``tr M / 2 - 1`` of the undamped drive free of cancellation where the phases are short
        (near the lower edge of zone 0, where ``tr M / 2 - 1`` is far smaller than 1); NaN
        where the drive does not provide it."""
        return np.full(np.shape(eps), np.nan)

    # ------------------------------------------------------------ descriptions
    def describe(self) -> str:
        """A one-line description for reports."""
        return self.name

    @property
    def label(self) -> str:
        """A short name for legends."""
        return self.name

    def as_dict(self) -> dict:
        """JSON-ready description: ``{"drive": name, ...parameters}``."""
        return {"drive": self.name}

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items() if k != "drive")
        return f"{type(self).__name__}({args})"

    def __eq__(self, other):
        return type(self) is type(other) and self.as_dict() == other.as_dict()

    def __hash__(self):
        return hash((type(self).__name__, repr(self)))

    # ------------------------------------------------------------ kinematics
    @staticmethod
    def _checked(t, T, A):
        t = _v.finite("t", t)
        T = _v.positive("T", T)
        A = _v.positive("A", A)
        return np.broadcast_arrays(t, T, A)

    @staticmethod
    def _reduce(t, T):
        """``tau = t/T`` reduced to ``[0, 2)``."""
        tau = np.mod(t / T, 2.0)
        return np.where(tau >= 2.0, 0.0, tau)

    def acceleration(self, t, T, A):
        """The pivot's acceleration ``a(t) = A s(t/T)`` [m/s^2] (any real ``t``; periodic)."""
        t, T, A = self._checked(t, T, A)
        return A * self._shape(self._reduce(t, T))

    def velocity(self, t, T, A):
        """The pivot's velocity [m/s]: the periodic, zero-mean integral of ``a``."""
        t, T, A = self._checked(t, T, A)
        return A * T * self._velocity_shape(self._reduce(t, T))

    def displacement(self, t, T, A):
        """The pivot's height [m] above its mean position: periodic, zero mean."""
        t, T, A = self._checked(t, T, A)
        return A * T * T * self._displacement_shape(self._reduce(t, T))

    def stroke(self, T, A):
        """Peak-to-peak travel of the pivot [m]."""
        T = _v.positive("T", T)
        A = _v.positive("A", A)
        return self._stroke_coefficient * A * T * T

    def rms_velocity(self, T, A):
        """Root-mean-square velocity of the pivot over a period [m/s]."""
        T = _v.positive("T", T)
        A = _v.positive("A", A)
        return np.sqrt(self._mean_square_velocity) * A * T

    def from_rig(self, frequency, *, stroke=None, amplitude=None, acceleration=None):
        """``(T, A)`` from what is measured on a rig: the drive frequency and one amplitude.

        Parameters
        ----------
        frequency : array_like
            Drive frequency [Hz], > 0; the period is ``2T = 1/frequency``.
        stroke : array_like, optional
            Peak-to-peak travel of the pivot [m].
        amplitude : array_like, optional
            Displacement amplitude, half the stroke [m].
        acceleration : array_like, optional
            The acceleration scale ``A`` [m/s^2] itself.

        Exactly one of ``stroke``, ``amplitude``, ``acceleration`` is given.

        Returns
        -------
        T, A : ndarray
        """
        f = _v.positive("frequency", frequency)
        given = {k: v for k, v in (("stroke", stroke), ("amplitude", amplitude), ("acceleration", acceleration))
                 if v is not None}
        if len(given) != 1:
            raise _v.KapitzaValueError(
                "give exactly one of stroke, amplitude, acceleration with the frequency; "
                f"got {', '.join(given) or 'none'}")
        (key, value), = given.items()
        value = _v.positive(key, value)
        T = 0.5 / f
        if key == "acceleration":
            A = value
        else:
            s = value if key == "stroke" else 2.0 * value
            A = s / (self._stroke_coefficient * T * T)
        return _v.scalars(*np.broadcast_arrays(T, A))

    def kapitza_eps(self, mu):
        """``eps`` of the averaging criterion ``<v_pivot^2> = g l`` at ``mu``.

        ``<v^2> = k A^2 T^2`` gives ``8 k eps^2 = mu^2``: the classical high-frequency
        threshold ``eps = mu / sqrt(8 k)`` (``sqrt(3/2) mu`` for the square wave,
        ``pi mu / 2`` for the sine).
        """
        mu = _v.positive("mu", mu)
        return mu / np.sqrt(8.0 * self._mean_square_velocity)

    # ------------------------------------------------------------ the questions
    # What the public functions of kapitza ask a drive, on validated float arrays that
    # broadcast (``zeta``: damping ratios >= 0; ``c``: damping in 1/s). Each has one generic
    # body (:mod:`kapitza.drives._api`, built on the undamped data above and the damping layer);
    # a drive with closed forms overrides what it can answer better (the square wave: every
    # one of them, undamped) and hands the rest back with ``super()``.

    #: The drive finds every zone of a window of ``eps`` at once (:meth:`_window0`).
    _windowed = False

    #: One point's searches (margin, rig intervals) may ask the drive for many points of a row at
    #: once, spread over decades of ``eps`` and ``A`` (:func:`kapitza.drives._api.point_margin`).
    _batched_points = False

    def _window0(self, mu, e_a, e_b):
        """``(rows, zone, lo, hi)``: the undamped zones meeting ``[e_a[i], e_b[i]]`` at ``mu[i]``
        (flat arrays, one entry per zone found), for a drive with :attr:`_windowed`."""
        raise NotImplementedError

    def _zone_rate(self, mu):
        """``(rate, B)``: the rotation angle per period lies within ``B`` of ``rate * eps``
        (the elliptic angle of the WKB phase, ``int sqrt(8 max(-(mu^2 + s), 0)) dtau``; ``B``
        bounds what the turning points and the repelling parts add). A drive may give it
        more tightly."""
        tau = (np.arange(4096) + 0.5) / 2048.0
        s = np.asarray(self._shape(tau), float)
        mu = np.asarray(mu, float)
        k = np.multiply.outer(mu * mu, np.ones(s.size)) + s
        rate = np.sqrt(8.0 * np.maximum(-k, 0.0)).sum(axis=-1) / 2048.0
        return rate, 4.0 * PI

    def _steps(self):
        """``(levels, fractions)`` of a piecewise-constant drive (exact segment products), else None."""
        return None

    def _floquet(self, eps, mu, zeta, certify=True):
        """Floquet data with damping ratio ``zeta``: ``(tau, growth, theta, stable, zone, kappa)``
        (:func:`kapitza.drives._api.damped_floquet`; ``certify`` as in :meth:`_floquet0`)."""
        return _api.damped_floquet(self, eps, mu, zeta, certify)

    def _edges(self, mu, n, zeta):
        """``(eps_lo, eps_hi)`` of zone ``n`` with damping ratio ``zeta`` (:func:`kapitza.drives._api.damped_edges`)."""
        return _api.damped_edges(self, mu, n, zeta)

    def closed_form(self, zeta=0.0) -> bool:
        """Whether this drive answers from closed forms at damping ratio ``zeta`` (the square
        wave, undamped): its zone edges then cost a few Newton steps, any window of a chart alike."""
        return False

    def floquet_data(self, eps, mu, zeta):
        """``(trace, determinant, multipliers, growth, rotation_number, stable, zone)`` (:func:`kapitza.floquet`)."""
        trace, det, mult, growth, rho, stable, zone = _api.floquet(eps, mu, self, zeta)
        return trace, det, mult, growth, rho, stable, np.where(stable, zone, -1).astype(np.int64)

    def verdict(self, eps, mu, zeta, want_zone=True):
        """``(stable, zone)``, zone -1 where unstable (:func:`kapitza.is_stable`, :func:`kapitza.zone_index`)."""
        return _api.verdict(eps, mu, self, zeta)

    def growth(self, eps, mu, zeta):
        """``log max|lambda|`` per period (:func:`kapitza.growth_rate`)."""
        return _api.floquet(eps, mu, self, zeta)[3]

    def rotation(self, eps, mu, zeta):
        """Rotation number per period (:func:`kapitza.rotation_number`)."""
        return _api.floquet(eps, mu, self, zeta)[4]

    def edges(self, mu, n, zeta):
        """``(eps_lo, eps_hi)`` of zone ``n``, NaN where there is none (:func:`kapitza.zone_edges`)."""
        return self._edges(mu, n, zeta)

    def margin(self, eps, mu, zeta):
        """``(stable, zone, eps_lo, eps_hi, margin)`` (:func:`kapitza.stability_margin`)."""
        return _api.margin(eps, mu, self, zeta)

    def paint(self, eps, mu, zeta, out):
        """Paint the verdicts of the grid ``eps`` (sorted) x ``mu`` into ``out`` (zeroed), one
        damping ratio ``zeta`` for all (:func:`kapitza.stability_grid`)."""
        return _api.grid(eps, mu, self, np.full(mu.size, float(zeta)), out)

    def period_edges(self, A, n, l, g, c):
        """``(T_lo, T_hi)`` of zone ``n`` at fixed ``A`` (:func:`kapitza.period_edges`)."""
        with np.errstate(over="ignore", under="ignore"):
            mu = np.sqrt(g / A)
        lo, hi = self.edges(mu, n, _api.zeta_of(c, l, g))
        scale = time_scale(l, A)
        return lo * scale, hi * scale

    def amplitude_edges(self, T, n, l, g, c):
        """``(A_lo, A_hi)`` of zone ``n`` at fixed ``T`` (:func:`kapitza.amplitude_edges`; bisection
        on the zone index read from the rotation angle)."""
        T, n, l, g, c = np.broadcast_arrays(T, n, l, g, c)
        pairs = [_api.along_amplitude(*args, self, cc) for *args, cc in
                 zip(T.ravel(), n.ravel(), l.ravel(), g.ravel(), c.ravel())]
        lo = np.array([p[0] for p in pairs]).reshape(T.shape)
        hi = np.array([p[1] for p in pairs]).reshape(T.shape)
        return lo, hi

    def monodromy(self, T, A, l, g, c):
        """``M`` over one period, shape ``(..., 2, 2)`` (:func:`kapitza.monodromy`)."""
        return _api.monodromy(T, A, l, g, self, c)

    def linear_motion(self, t, theta0, dtheta0, T, A, l, g, c):
        """``theta(t), theta'(t)`` of the linear equation (:func:`kapitza.linear_motion`)."""
        return _api.linear_motion(t, theta0, dtheta0, T, A, l, g, self, c)

    # ------------------------------------------------------------ one point (kapitza.analyze)
    def point_floquet(self, eps, mu, zeta, pointwise=True):
        """The Floquet data of one point as Python numbers: ``(trace, determinant, multipliers,
        growth, rotation_number, stable, zone, theta, exact)`` (``theta`` the rotation angle,
        ``exact`` whether it is the array path's own). ``pointwise``: a drive may answer from
        scalar twins of its kernels (the square wave), checked against the arrays' answers."""
        trace, det, mult, growth, rho, stable, zone = (np.asarray(a)[()] for a in self.floquet_data(
            np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float)))
        return (float(trace), float(det), tuple(complex(x) for x in mult), float(growth), float(rho), bool(stable),
                int(zone), 2.0 * PI * float(rho), True)

    def point_margin(self, eps, mu, zeta, pointwise=True):
        """:meth:`margin` of one point as ``(stable, zone, eps_lo, eps_hi, margin)`` Python numbers
        (``pointwise``: from one batched search of its zones' edges where it answers)."""
        if pointwise and self._batched_points:
            found = _api.point_margin(self, eps, mu, zeta)
            if found is not None:
                return found
        st, zone, lo, hi, m = (np.asarray(a)[()] for a in self.margin(
            np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float)))
        return bool(st), int(zone), float(lo), float(hi), float(m)

    def point_intervals(self, eps, mu, zone, zeta, T, A, l, g, c, pointwise=True, eps_edges=None):
        """Zone ``zone`` of one physical point as intervals a rig is turned along: ``T_lo, T_hi``
        (at this ``A``), ``A_lo, A_hi`` (at this ``T``), ``stroke_lo, stroke_hi`` (at this
        frequency), ``frequency_lo, frequency_hi`` (at this stroke); and the ``stroke``.
        ``eps_edges``: the zone's edges in ``eps`` at this ``mu``, when known (``T`` is ``eps``
        times ``sqrt(8 l / A)`` at this ``A``: no second solve)."""
        stroke = self.point_stroke(T, A)
        if eps_edges is not None:
            scale = np.sqrt(8.0 * np.asarray(l, float) / np.asarray(A, float))
            Tlo, Thi = eps_edges[0] * scale, eps_edges[1] * scale
        else:
            Tlo, Thi = self.period_edges(np.asarray(A, float), np.asarray(zone), np.asarray(l, float),
                                         np.asarray(g, float), np.asarray(c, float))
        out = dict(T_lo=float(Tlo), T_hi=float(Thi))
        if self._batched_points:
            rig = _api.rig_intervals(eps, mu, zone, self, zeta, T, A, l, g)
        else:
            Alo, Ahi = self.amplitude_edges(*(np.asarray(v, float) for v in (T, zone, l, g, c)))
            rig = dict(A_lo=float(Alo), A_hi=float(Ahi))
            rig.update(_api.rig_margins(eps, mu, zone, self, zeta, T, stroke))
        out.update(A_lo=rig["A_lo"], A_hi=rig["A_hi"], stroke_lo=stroke * rig["A_lo"] / A,
                   stroke_hi=stroke * rig["A_hi"] / A, stroke=stroke)
        out.update({k: v for k, v in rig.items() if k.startswith("frequency")})
        return out

    def point_stroke(self, T, A) -> float:
        """:meth:`stroke` of one validated point (Python floats; ``inf`` beyond the doubles)."""
        return float(self._stroke_coefficient) * A * T * T

    def point_sentence(self, mu, zeta, zone, eps_lo):
        """Why an unstable point can never be stable, in words, or None (then the way it is
        unstable is told from its multipliers)."""
        if mu >= self.mu_max:
            return (f"always unstable: the pivot never accelerates down faster than g (mu >= {self.mu_max:.6g}, "
                    f"the drive's mu_max)")
        mu_c = np.array([mu * np.sqrt(1.0 + zeta * zeta)])
        if np.isnan(eps_lo) and zone < 0 and not np.any(self._zone_rate(mu_c)[0] > 0):
            return "always unstable: the drive has no attracting phase at this mu"
        return None

    def point_nonlinear(self, eps, mu, zeta, theta, zone, exact_theta, pointwise=True):
        """The verdict on the full equation's upright at a linearly stable point, or None where the
        drive gives none (the square wave, undamped: :func:`kapitza.nonlinear_stability`)."""
        return None
