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

import functools
from dataclasses import dataclass

import numpy as np

from .. import _validate as _v

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


def log_cosh(k):
    """log cosh k for k >= 0 without overflow, to a few ulp relative (``log1p(2 sinh^2(k/2))`` below 1)."""
    with np.errstate(over="ignore"):
        small = np.log1p(2.0 * np.sinh(0.5 * np.minimum(k, 1.0)) ** 2)
    return np.where(k < 1.0, small, k + np.log1p(np.exp(-2.0 * k)) - LOG2)


def acosh_from_log(log_tau, tau):
    """acosh|tau| for |tau| >= 1 from ``log|tau|`` (finite where ``tau`` overflows)."""
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        e = np.abs(tau) - 1.0
        small = np.log1p(np.where((e >= 0) & (e < 1.0), e + np.sqrt(np.abs(e) * (e + 2.0)), 0.0))
        big = log_tau + np.log1p(np.sqrt(-np.expm1(-2.0 * np.maximum(log_tau, 0.0))))
    return np.where(e < 1.0, small, big)


class Drive:
    """A pivot motion over one period ``2T``: ``a(t) = A s(t/T)``, ``s`` zero-mean.

    This is the public contract of a drive. Everything kapitza answers about a pivot motion
    (verdicts, multipliers, growth, rotation number, zone index, zone edges, margins, charts,
    motion, basins, sweeps, reports) is built on the few methods below.

    **A subclass must give** only

    1. ``_shape(tau)``: the acceleration shape ``s`` over one period, ``tau = t/T`` in
       ``[0, 2)`` (a numpy array in, an array of the same shape out), with zero mean over the
       period and ``s`` bounded. ``A`` is the acceleration scale: ``a(t) = A s(t/T)``, so that
       ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` keep their meaning for every drive
       (choose ``s`` with ``max|s| = 1`` to make ``A`` the peak acceleration);
    2. ``name``: a short name (class attribute) for reports; ``as_dict()`` when the drive has
       parameters (it also defines equality).

    From that alone the defaults here give: the velocity and displacement shapes (zero-mean
    periodic integrals, computed once to rounding on a grid and cached), the stroke
    coefficient, the mean-square velocity, the trough ``-min s`` (hence :attr:`mu_max`),
    the undamped Floquet data (:meth:`_floquet0`) and zone edges (:meth:`_edges0`) from the
    generic engine :mod:`kapitza.engines` (a sixth-order Magnus product over one period with
    the Pruefer rotation angle; ``docs/drives.md``, "The drive contract"), and damping on top.

    **A subclass may give**, for speed or exactness:

    - ``_breakpoints``: the ``tau`` in ``(0, 2)`` where ``s`` jumps or has a kink. The engine's
      grid is aligned with them, which keeps its sixth order (piecewise-linear and
      piecewise-constant shapes are then integrated to rounding); ``_min_steps`` the steps per
      period that resolve a smooth shape (default 256);
    - exact kinematics: ``_velocity_shape(tau)``, ``_displacement_shape(tau)``,
      ``_stroke_coefficient``, ``_mean_square_velocity``, ``_trough``;
    - segments: subclass :class:`~kapitza.drives._piecewise.PiecewiseConstant` for the exact
      product of closed-form segment matrices (certified verdicts);
    - closed forms or characteristic values: override ``_floquet0(eps, mu, certify=True)``
      (returning :class:`Floquet0`), ``_edges0(mu, n)``, ``_log_tau0(eps, mu)``,
      ``_tau_minus_one0(eps, mu)``, ``_zone_window(mu)`` and ``_candidate_zones(mu, e0, e1)``
      (see each).

    Conventions: in ``tau`` the undamped linearisation is
    ``phi'' = 8 eps^2 (mu^2 + s(tau)) phi`` (module notes); zone ``n`` is where the rotation
    angle per period lies in ``(n pi, (n + 1) pi)``; inputs of these methods are trusted,
    broadcast float arrays (the public functions validate them).

    Examples
    --------
    A drive of one's own needs its shape and a name::

        class Triangle(kapitza.Drive):
            name = "my-triangle"
            _breakpoints = (0.5, 1.5)

            def _shape(self, tau):
                return np.where(tau < 0.5, 2 * tau, np.where(tau < 1.5, 2 - 2 * tau, 2 * tau - 4))

        kapitza.analyze(T=0.15, A=100, drive=Triangle())
    """

    #: short name used by the command line and in reports
    name = "drive"

    #: jumps and kinks of the shape inside (0, 2), in tau (the engine's grid is aligned with them)
    _breakpoints: tuple = ()
    #: steps per period that resolve the shape itself (the engine adds steps as the phase grows)
    _min_steps: int = 256

    # ------------------------------------------------------------ what a subclass gives
    def _shape(self, tau):  # pragma: no cover - protocol
        raise NotImplementedError(
            f"{type(self).__name__} must define _shape(tau), its acceleration shape over one period")

    # ------------------------------------------------------------ defaults from the shape
    @functools.cached_property
    def _kinematics(self):
        """The velocity and displacement shapes as piecewise polynomials (computed once)."""
        return _Kinematics(self._shape, self._breakpoints)

    def _velocity_shape(self, tau):
        """``V(tau)``: the zero-mean periodic integral of ``s`` (default: cached, to rounding)."""
        return self._kinematics.velocity(tau)

    def _displacement_shape(self, tau):
        """``Z(tau)``: the zero-mean periodic integral of ``V``."""
        return self._kinematics.displacement(tau)

    @functools.cached_property
    def _stroke_coefficient(self) -> float:
        """Peak-to-peak of the displacement shape: stroke = coefficient * A T^2."""
        return self._kinematics.stroke

    @functools.cached_property
    def _mean_square_velocity(self) -> float:
        """Mean of the squared velocity shape: <v^2> = coefficient * A^2 T^2."""
        return self._kinematics.mean_square_velocity

    @functools.cached_property
    def _trough(self) -> float:
        """The largest downward acceleration of the shape, ``-min s``, in units of ``A``."""
        return -self._engine.s_min

    @functools.cached_property
    def _engine(self):
        from ..engines import Engine

        return Engine(self._shape, self._breakpoints, self._min_steps)

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

    def _floquet0(self, eps, mu, certify=True) -> Floquet0:
        """Undamped Floquet data at ``(eps, mu)`` (default: the generic engine).

        ``certify`` asks for verdicts settled to the last bit where a drive can (the exact
        product does so in mpmath); the generic engine's ``tr M / 2`` is accurate to about
        1e-13 relative and its verdicts are those of that value.
        """
        eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
        tau, log_tau, theta, zone, growth = self._engine.floquet(eps.ravel(), mu.ravel(), growth=True)
        sh = eps.shape
        return Floquet0(tau=tau.reshape(sh), log_tau=log_tau.reshape(sh), growth=growth.reshape(sh),
                        theta=theta.reshape(sh), zone=zone.reshape(sh))

    def _edges0(self, mu, n):
        """``(eps_lo, eps_hi)`` of undamped zone ``n`` at ``mu`` (NaN where there is none).

        Default: bracketed by the rotation angle of the generic engine and solved on
        ``|tr M / 2| = 1`` to adjacent doubles (:mod:`kapitza.engines.edges`).
        """
        from ..engines import zone_edges

        mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
        sh = mu.shape
        mu, n = mu.ravel(), n.ravel()
        rate, B = self._zone_window(mu)
        ok = (rate > 0) & (n >= 0)
        lo = np.full(mu.size, np.nan)
        hi = np.full(mu.size, np.nan)
        if ok.any():
            eng = self._engine
            lo[ok], hi[ok] = zone_edges(eng.floquet, eng.log_tau, mu[ok], n[ok], rate[ok], B[ok])
        return lo.reshape(sh), hi.reshape(sh)

    def _zone_window(self, mu):
        """``(rate, B)``: the elliptic angle per period grows like ``rate * eps`` and zone ``n``
        lies where ``|n pi - rate eps| <~ B`` (the candidates a chart or a margin looks at).

        ``rate = sqrt(8) * integral of sqrt(max(-(mu^2 + s), 0)) d tau`` over the period (the
        WKB phase of the attracting part); ``B = (1 + j) pi`` with ``j`` the number of
        attracting intervals of the period (each may cost the angle up to ``pi``).
        """
        mu = np.asarray(mu, float)
        g = self._engine.grid(self._engine.min_steps)
        s = g.s_nodes  # (m, 3) on the Gauss nodes
        wts = g.h[: g.m, None] * np.array([5.0, 8.0, 5.0])[None, :] / 18.0
        m2 = (mu * mu).reshape(-1, 1, 1)
        neg = np.sqrt(np.maximum(-(m2 + s[None]), 0.0))
        rate = SQRT8 * np.sum(neg * wts[None], axis=(1, 2))
        att = (m2[:, :, 0] + s[None, :, 1]) < 0  # attracting at the middle nodes, cyclic
        j = np.maximum(np.sum(att & ~np.roll(att, 1, axis=1), axis=1), 1)
        return rate.reshape(mu.shape), ((1.0 + j) * PI).reshape(mu.shape)

    def _candidate_zones(self, mu, e0, e1, damped=False):
        """``(n_lo, n_hi)``: the zones a chart of ``[e0, e1]`` or a margin at ``e0 = e1`` needs.

        Read from the rotation angle at the ends (the angle does not decrease along ``eps``):
        a window ``e0 < e1`` meets exactly the zones from the one at or above ``e0`` to the
        last one whose lower edge lies below ``e1``; a point (``e0 = e1``) needs its own zone,
        or the two beside its gap. With damping (``mu`` is then ``mu_c``, the ``phi``-system's)
        one more zone each side. ``n_hi < n_lo`` where there is none.
        """
        mu, e0, e1 = np.broadcast_arrays(np.asarray(mu, float), np.asarray(e0, float), np.asarray(e1, float))
        sh = mu.shape
        mu, e0, e1 = mu.ravel(), e0.ravel(), e1.ravel()
        point = e0 >= e1
        ends = np.concatenate([e0, e1])
        f = self._floquet0(np.maximum(ends, 1e-300), np.concatenate([mu, mu]), certify=False)
        level = np.where(f.zone >= 0, f.zone + 0.5, np.rint(f.theta / PI))
        l0, l1 = level[: mu.size], level[mu.size:]
        n_lo = np.where(point, np.ceil(l0) - 1, np.floor(l0))
        n_hi = np.where(point, np.floor(l1), np.floor(l1 - 0.25))
        if damped:
            n_lo, n_hi = n_lo - 1, n_hi + 1
        n_lo = np.maximum(n_lo, 0).astype(np.int64)
        return n_lo.reshape(sh), n_hi.astype(np.int64).reshape(sh)

    def _log_tau0(self, eps, mu):
        """``log|tr M / 2|`` of the undamped drive (default: the engine's product, no angle)."""
        if type(self)._floquet0 is not Drive._floquet0:
            return self._floquet0(eps, mu, certify=False).log_tau
        eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
        return self._engine.log_tau(eps.ravel(), mu.ravel())[1].reshape(eps.shape)

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
        return np.broadcast_arrays(T, A)

    def kapitza_eps(self, mu):
        """``eps`` of the averaging criterion ``<v_pivot^2> = g l`` at ``mu``.

        ``<v^2> = k A^2 T^2`` gives ``8 k eps^2 = mu^2``: the classical high-frequency
        threshold ``eps = mu / sqrt(8 k)`` (``sqrt(3/2) mu`` for the square wave,
        ``pi mu / 2`` for the sine).
        """
        mu = _v.positive("mu", mu)
        return mu / np.sqrt(8.0 * self._mean_square_velocity)

    # ------------------------------------------------------------ damping layer
    def _floquet(self, eps, mu, zeta):
        """Floquet data with damping ratio ``zeta`` (trusted, broadcast arrays).

        Returns ``(tau, growth, theta, stable, zone, kappa)``: ``tau`` the half-trace of the
        undamped ``phi``-system, ``growth = log max|lambda|`` of the damped one (negative:
        decay), ``kappa = c T``.
        """
        eps, mu, zeta = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float),
                                            np.asarray(zeta, float))
        damped = np.any(zeta > 0)
        mu_c = mu * np.sqrt(1.0 + zeta * zeta) if damped else mu
        f = self._floquet0(eps, mu_c)
        if not damped:
            return f.tau, f.growth, f.theta, f.zone >= 0, f.zone, np.zeros(eps.shape)
        kappa = 2.0 * SQRT8 * zeta * mu * eps
        # |tr M_phi| < 2 cosh(kappa), compared in logarithms (both sides may overflow), or
        # without cancellation where tr M_phi / 2 is near 1 (_damped_excess).
        with np.errstate(divide="ignore"):
            G = _damped_excess(self, eps, mu_c, kappa, f.log_tau, f.zone < 0).reshape(eps.shape)
            stable = (f.zone >= 0) | (G < 0)
        growth = f.growth - kappa
        zone = np.where(f.zone >= 0, f.zone, -1)
        gap = stable & (f.zone < 0)
        if np.any(gap):
            # Stable only thanks to the damping: the point sits in the gap between zones
            # k - 1 and k (theta = k pi). It belongs to the zone whose edge it is nearer,
            # i.e. to k - 1 while |tau| still rises with eps, to k once it falls again.
            k = np.rint(f.theta / PI).astype(np.int64)
            e, m, z = eps[gap], mu[gap], zeta[gap]
            h = 1e-7 * e
            rising = _excess(self, e + h, m, z) > _excess(self, e - h, m, z)
            zone[gap] = np.maximum(np.where(rising, k[gap] - 1, k[gap]), 0)
        return f.tau, growth, f.theta, stable, zone, kappa

    def _edges(self, mu, n, zeta):
        """``(eps_lo, eps_hi)`` of zone ``n`` with damping ratio ``zeta`` (trusted arrays)."""
        mu, n, zeta = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64),
                                          np.asarray(zeta, float))
        if not np.any(zeta > 0):
            return self._edges0(mu, n)
        return _damped_edges(self, mu, n, zeta)


# ---------------------------------------------------------------- default kinematics
class _Kinematics:
    """Velocity and displacement shapes of any shape ``s``, to rounding, computed once.

    On a grid of 4096 steps aligned with the breakpoints, ``s`` is fitted on each step by the
    quadratic through its three Gauss-Legendre nodes (so the step integral is the sixth-order
    Gauss rule); ``V`` (cubic) and ``Z`` (quartic) follow exactly from that fit, their
    constants fixed by zero means over the period. The stroke is ``max Z - min Z`` over the
    step ends and the roots of ``V`` (Newton on the cubic); ``<V^2>`` is exact on the cubics.
    """

    STEPS = 4096

    def __init__(self, shape, breaks):
        from ..engines.magnus import NODES, Grid

        n = self.STEPS
        while n < 2 * (len(breaks) + 1):  # a step per segment at least
            n *= 2
        g = Grid(shape, breaks, n)
        m = g.m
        h = g.h[:m]
        x = g.x[:m]
        van = np.vander(NODES, 3, increasing=True)
        c = g.s_nodes @ np.linalg.inv(van).T  # s(u) = c0 + c1 u + c2 u^2 on each step
        c0, c1, c2 = c[:, 0], c[:, 1], c[:, 2]
        total = np.sum(h * (c0 + c1 / 2.0 + c2 / 3.0))
        scale = np.sum(h * (np.abs(g.s_nodes) @ np.array([5.0, 8.0, 5.0]) / 18.0))
        if not np.isfinite(total) or not np.isfinite(scale) or scale == 0.0:
            raise _v.KapitzaValueError("a drive's shape must be finite and not identically 0 over the period")
        if abs(total) > 1e-9 * scale:
            raise _v.KapitzaValueError(
                f"a drive's shape must have zero mean over the period; its mean is {total / 2.0:.6g} "
                f"(mean |s| {scale / 2.0:.6g})")
        V = np.concatenate([[0.0], np.cumsum(h * (c0 + c1 / 2.0 + c2 / 3.0))])[:-1]
        V = V - np.sum(h * (V + h * (c0 / 2.0 + c1 / 6.0 + c2 / 12.0))) / 2.0
        Z = np.concatenate([[0.0], np.cumsum(h * V + h * h * (c0 / 2.0 + c1 / 6.0 + c2 / 12.0))])[:-1]
        Z = Z - np.sum(h * (Z + h * V / 2.0 + h * h * (c0 / 6.0 + c1 / 24.0 + c2 / 60.0))) / 2.0
        self.x, self.h, self.c0, self.c1, self.c2, self.V, self.Z = x, h, c0, c1, c2, V, Z
        # <V^2>: V is a cubic on each step, V^2 of degree 6: four Gauss nodes are exact
        u4, w4 = np.polynomial.legendre.leggauss(4)
        u4, w4 = 0.5 * (u4 + 1.0), 0.5 * w4
        Vq = self._V(np.arange(m)[:, None], u4[None, :])
        self.mean_square_velocity = float(np.sum(h * (Vq * Vq @ w4)) / 2.0)
        # stroke: Z at the step ends and where V = 0 inside a step
        u = np.linspace(0.0, 1.0, 17)
        j = np.arange(m)[:, None]
        Vs = self._V(j, u[None, :])
        cand = [Z, self._Z(np.arange(m), np.ones(m))]
        jj, kk = np.nonzero(np.signbit(Vs[:, :-1]) != np.signbit(Vs[:, 1:]))
        if jj.size:
            ua, ub = u[kk], u[kk + 1]
            va, vb = Vs[jj, kk], Vs[jj, kk + 1]
            r = ua - va * (ub - ua) / np.where(vb != va, vb - va, 1.0)
            for _ in range(4):  # Newton on the cubic: V' = h s(u)
                d = h[jj] * (c0[jj] + c1[jj] * r + c2[jj] * r * r)
                r = np.clip(r - self._V(jj, r) / np.where(d != 0, d, 1.0), ua, ub)
            cand.append(self._Z(jj, r))
        allz = np.concatenate(cand)
        self.stroke = float(allz.max() - allz.min())

    def _V(self, j, u):
        h, c0, c1, c2 = self.h[j], self.c0[j], self.c1[j], self.c2[j]
        return self.V[j] + h * u * (c0 + u * (c1 / 2.0 + u * c2 / 3.0))

    def _Z(self, j, u):
        h, c0, c1, c2 = self.h[j], self.c0[j], self.c1[j], self.c2[j]
        return self.Z[j] + h * self.V[j] * u + h * h * u * u * (c0 / 2.0 + u * (c1 / 6.0 + u * c2 / 12.0))

    def _locate(self, tau):
        tau = np.asarray(tau, float)
        j = np.clip(np.searchsorted(self.x, tau, side="right") - 1, 0, self.x.size - 1)
        return j, (tau - self.x[j]) / self.h[j]

    def velocity(self, tau):
        return self._V(*self._locate(tau))

    def displacement(self, tau):
        return self._Z(*self._locate(tau))


# ---------------------------------------------------------------- damped edges
def _excess(drive, eps, mu, zeta):
    """G = log|tau_phi| - log cosh(kappa): the damped upright is stable iff G < 0 (or on a zone)."""
    eps, mu, zeta = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float))
    shape = eps.shape
    eps, mu, zeta = eps.reshape(-1), mu.reshape(-1), zeta.reshape(-1)
    mu_c = mu * np.sqrt(1.0 + zeta * zeta)
    kappa = 2.0 * SQRT8 * zeta * mu * eps
    # where the phases are short, tau_phi - 1 itself (no product needed); elsewhere log|tau_phi|
    G = _damped_excess(drive, eps, mu_c, kappa)
    rest = np.isnan(G)
    if rest.any():
        # on a phi-zone log|tau_phi| < 0 <= log cosh(kappa): G < 0 there without asking for the zone
        G[rest] = drive._log_tau0(eps[rest], mu_c[rest]) - log_cosh(kappa[rest])
    return G.reshape(shape)


def _damped_excess(drive, eps, mu_c, kappa, log_tau=None, where=None):
    """``G = log|tau_phi| - log cosh(kappa)``, without cancellation where ``tau_phi > 0`` and the
    drive gives ``y = tau_phi - 1`` accurately (short phases): there
    ``G = log1p((y - 2 sinh^2(kappa/2)) / cosh(kappa))``, whose terms are of the size of the result.

    Below zone 0 at small ``mu`` both logarithms are of order ``eps^2 mu^2`` and ``G`` of order
    ``eps^4`` (``docs/drives.md``, section 3). With ``log_tau`` given, ``G`` is formed from it
    except at the rows (of ``where``, all by default) with ``tau_phi`` near 1; without it, rows
    the drive cannot form are NaN. Flat arrays.
    """
    eps, mu_c, kappa = (np.asarray(v, float).reshape(-1) for v in np.broadcast_arrays(eps, mu_c, kappa))
    if log_tau is None:
        G = np.full(eps.shape, np.nan)
        near = kappa < 1.0
    else:
        log_tau = np.asarray(log_tau, float).reshape(-1)
        with np.errstate(divide="ignore"):
            G = log_tau - log_cosh(kappa)
        near = (log_tau < 0.5) & (kappa < 1.0)
    if where is not None:
        near &= np.asarray(where).reshape(-1)
    if not near.any():
        return G
    idx = np.flatnonzero(near)
    y = drive._tau_minus_one0(eps[idx], mu_c[idx])
    ok = np.isfinite(y) & (y > -1.0)
    sh2 = 2.0 * np.sinh(0.5 * kappa[idx[ok]]) ** 2
    G[idx[ok]] = np.log1p((y[ok] - sh2) / (1.0 + sh2))
    return G


def _bisect(drive, mu, zeta, lo, hi, rising):
    """Root of G between ``lo`` and ``hi`` where G changes sign (``rising``: G < 0 at lo)."""
    lo = lo.copy()
    hi = hi.copy()
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if not np.any((mid > lo) & (mid < hi)):
            break
        pos = _excess(drive, mid, mu, zeta) >= 0
        go_hi = pos if rising else ~pos
        hi = np.where(go_hi, mid, hi)
        lo = np.where(go_hi, lo, mid)
    return np.where(rising, hi, lo)


def _gap_argmax(drive, mu, zeta, lo, hi):
    """Golden-section search for the maximum of G on ``(lo, hi)`` (G is one hump there)."""
    r = 0.5 * (np.sqrt(5.0) - 1.0)
    a, b = lo.copy(), hi.copy()
    c = b - r * (b - a)
    d = a + r * (b - a)
    Gc = _excess(drive, c, mu, zeta)
    Gd = _excess(drive, d, mu, zeta)
    best_x = np.where(Gc >= Gd, c, d)
    best_G = np.maximum(Gc, Gd)
    for _ in range(100):
        # an unstable point is all a bracket needs: rows with G > 0 found are done
        live = (best_G <= 0) & (b - a > 4e-16 * b)
        if not live.any():
            break
        left = Gc >= Gd  # the maximum lies in (a, d)
        b = np.where(live & left, d, b)
        a = np.where(live & ~left, c, a)
        p = np.where(left, b - r * (b - a), a + r * (b - a))
        Gp = np.full(p.shape, -np.inf)
        Gp[live] = _excess(drive, p[live], mu[live], zeta[live])
        c, d = np.where(live, np.where(left, p, d), c), np.where(live, np.where(left, c, p), d)
        Gc, Gd = np.where(live, np.where(left, Gp, Gd), Gc), np.where(live, np.where(left, Gc, Gp), Gd)
        better = live & (Gp > best_G)
        best_x = np.where(better, p, best_x)
        best_G = np.where(better, Gp, best_G)
    return best_x, best_G


def _damped_edges(drive, mu, n, zeta, phi=None):
    """Edges of damped zone ``n``: each lies in the gap next to the undamped ``phi``-zone.

    The damped zone ``n`` contains the undamped zone ``n`` of the ``phi``-system (at
    ``mu_c``), on which ``|tau_phi| < 1 <= cosh kappa``. In the gap between ``phi``-zones
    ``n - 1`` and ``n`` the excess ``G = log|tau_phi| - log cosh kappa`` is negative at both
    ends and rises to one maximum: its two roots are the damped upper edge of zone
    ``n - 1`` and the damped lower edge of zone ``n``. Where the maximum is <= 0 the
    damping has joined the two zones; both edges are then reported at that maximum.
    """
    if phi is None:
        mu_c = mu * np.sqrt(1.0 + zeta * zeta)
        lo_n, hi_n = drive._edges0(mu_c, n)
        _, hi_prev = drive._edges0(mu_c, np.maximum(n - 1, 0))
        lo_next, _ = drive._edges0(mu_c, n + 1)
    else:  # the phi-system's edges, known already (a chart's window; lo_next may be a cap)
        lo_n, hi_n, hi_prev, lo_next = phi
    # gap below zone n: (hi_{n-1}, lo_n), or (0, lo_0) for zone 0
    gap_lo = np.where(n == 0, 0.0, hi_prev)
    # no phi-zone n (no attracting part left at mu_c): no damped zone either
    ok = np.isfinite(lo_n) & np.isfinite(hi_n) & np.isfinite(gap_lo)
    if not ok.all():
        out_lo = np.full(mu.shape, np.nan)
        out_hi = np.full(mu.shape, np.nan)
        if ok.any():
            nxt = np.where(np.isfinite(lo_next), lo_next, 4.0 * hi_n)
            out_lo[ok], out_hi[ok] = _damped_edges(drive, mu[ok], n[ok], zeta[ok],
                                                   phi=(lo_n[ok], hi_n[ok], hi_prev[ok], nxt[ok]))
        return out_lo, out_hi
    x_lo, G_lo = _gap_argmax(drive, mu, zeta, gap_lo, lo_n)
    x_hi, G_hi = _gap_argmax(drive, mu, zeta, hi_n, lo_next)
    edge_lo = np.where(G_lo > 0, _bisect(drive, mu, zeta, x_lo, lo_n, rising=False), x_lo)
    # zone 0 with the gap entirely stable reaches down to eps -> 0
    edge_lo = np.where((n == 0) & (G_lo <= 0), 0.0, edge_lo)
    edge_hi = np.where(G_hi > 0, _bisect(drive, mu, zeta, hi_n, x_hi, rising=True), x_hi)
    return edge_lo, edge_hi
