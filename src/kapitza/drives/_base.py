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
from . import _api
from ..parameters import time_scale
from .._exact import acosh_from_log, gap_of_turn, log_cosh  # noqa: F401  (shared with the drives' engines)

PI = np.pi
SQRT8 = np.sqrt(8.0)
LOG2 = np.log(2.0)


@dataclass(frozen=True)
class Floquet0:
    """Undamped Floquet data of a drive at ``(eps, mu)`` (arrays of one shape).

    ``tau`` is ``tr M / 2`` (``+-inf`` where it overflows), ``log_tau`` is ``log|tau|``
    (finite), ``growth`` is ``acosh|tau|`` off the zones and 0 on them, ``theta`` the
    rotation angle per period (in ``(n pi, (n + 1) pi)`` on zone ``n``, a multiple of
    ``pi`` off the zones), ``zone`` the zone index (-1 where unstable). ``tau_error``, given
    when the trace is asked for (``trace=True``), bounds the absolute error of ``tau`` (``inf``
    where ``tau`` overflows or nothing is known). ``unsure``, which a drive may give with
    ``certify=False``, marks the points whose verdict the rounding of these doubles may have
    decided (those ``certify`` would settle in extended precision); None: not known. With
    ``certify`` and ``phi`` (the damped system's ``phi``-equation) and no ``trace``, a drive may
    instead mark there the points whose verdict is certified but whose ``tau`` is too rough to
    compare with ``cosh(kappa)``: the damping layer settles their damped verdict exactly.
    """

    tau: np.ndarray
    log_tau: np.ndarray
    growth: np.ndarray
    theta: np.ndarray
    zone: np.ndarray
    tau_error: np.ndarray | None = None
    unsure: np.ndarray | None = None


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
    - linear pieces: ``_linear_pieces()``, the shape as pieces linear in ``tau``, for verdicts
      decided to the last bit (with and without damping) where the engine's trace is near the
      threshold (:meth:`_linear_pieces`);
    - closed forms or characteristic values: override ``_floquet0(eps, mu, certify=True)``
      (returning :class:`Floquet0`; with the keywords ``trace=False, phi=None`` as well, it can
      bound the trace's error for :attr:`kapitza.Floquet.trace_error`, ``inf`` otherwise),
      ``_edges0(mu, n)``, ``_log_tau0(eps, mu)``, ``_verdict0(eps, mu)``,
      ``_tau_minus_one0(eps, mu)``, ``_zone_rate(mu)`` and ``_candidate_zones(mu, e0, e1)``
      (see each);
    - exact verdicts: ``_damped_exact(eps, mu, zeta, growth=True)`` and ``_certified_cheap(damped)``
      (see each), and :attr:`Floquet0.unsure` from ``_floquet0`` without ``certify``;
    - a report's searches: ``_certified_steps(damped)`` and ``_joint_search(zeta, level0)`` (see each);
    - its own ``T`` and ``A`` (:attr:`own_scale`), as a measured drive has them.

    Conventions: in ``tau`` the undamped linearisation is
    ``phi'' = 8 eps^2 (mu^2 + s(tau)) phi`` (module notes); zone ``n`` is where the rotation
    angle per period lies in ``(n pi, (n + 1) pi)``; inputs of these methods are trusted,
    broadcast float arrays (the public functions validate them).

    Examples
    --------
    A drive of one's own needs its shape and a name; every function taking ``drive=`` then
    answers for it (here it agrees with the built-in :class:`~kapitza.TriangleWave`):

    >>> import numpy as np
    >>> import kapitza
    >>> class Triangle(kapitza.Drive):
    ...     name = "my-triangle"
    ...     _breakpoints = (0.5, 1.5)
    ...
    ...     def _shape(self, tau):
    ...         return np.where(tau < 0.5, 2 * tau, np.where(tau < 1.5, 2 - 2 * tau, 2 * tau - 4))
    >>> kapitza.zone_edges(0.3, 0, drive=Triangle())
    (np.float64(0.5870...), np.float64(0.9184...))
    >>> kapitza.zone_edges(0.3, 0, drive="triangle")
    (np.float64(0.5870...), np.float64(0.9184...))
    >>> kapitza.is_stable(0.7, 0.3, drive=Triangle())
    np.True_
    """

    #: short name used by the command line and in reports
    name = "drive"
    #: the text form the command line and the web take (``name`` when there are no parameters)
    text_form: str | None = None
    #: what this kind of drive is called in a menu, e.g. the explorer's list (default: ``name``)
    title: str | None = None
    #: the numbers of the text form ``NAME:VALUE``, for a form that offers the drive (the
    #: explorer's page): one dict per number with ``name``, ``min`` and ``max`` (open ends: the
    #: values the constructor accepts lie strictly between), ``default`` and ``examples`` (values
    #: worth listing); ``()`` for a drive without parameters, ``None`` for a text form that no
    #: list of numbers describes (:class:`~kapitza.StepDrive`'s levels and fractions)
    parameters: tuple | None = ()

    @classmethod
    def from_text(cls, parameters, text=None):
        """The drive of the text form ``NAME:PARAMETERS`` (``parameters`` None for a bare ``NAME``;
        ``text`` the whole form, for messages). A drive without parameters takes none; a drive
        with parameters overrides this."""
        if parameters is not None:
            raise _v.KapitzaValueError(f"drive {cls.name!r} takes no parameters; got {text!r}")
        return cls()

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
    def peak(self) -> float:
        """The largest ``|a| / A`` over the period, ``max |s|`` (1 for the square, sine and triangle waves)."""
        return max(-self._engine.s_min, self._engine.s_max)

    @functools.cached_property
    def _engine(self):
        from ..engines import Engine

        return Engine(self._shape, self._breakpoints, self._min_steps)

    @property
    def own_scale(self):
        """``(T, A)`` the drive carries from its own data, or None (then ``T`` and ``A`` are the
        user's). A measured drive (:func:`kapitza.drives.from_samples`) has half its period and its
        peak acceleration: a command given only the drive file takes them."""
        return None

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

    def _floquet0(self, eps, mu, certify=True, trace=False, phi=None) -> Floquet0:
        """Undamped Floquet data at ``(eps, mu)`` (default: the generic engine).

        ``certify`` asks for verdicts settled to the last bit where a drive can (the exact
        product does so in mpmath); the generic engine's ``tr M / 2`` is accurate to about
        1e-13 relative, and its verdicts are those of that value unless the drive gives its shape
        as linear pieces (:meth:`_linear_pieces`): then the points near the threshold are decided
        in extended precision. Without ``certify`` a drive that knows which points those are may
        say so (:attr:`Floquet0.unsure`): the damping layer then settles them with its own.

        ``trace`` says the trace will be reported: the result then carries ``tau_error``, a bound
        on the absolute error of ``tau`` (here :meth:`_trace_error`), and a drive that can
        recomputes ``tau`` in extended precision where that bound exceeds
        :data:`kapitza._certify.TRACE_RTOL` of it (here a drive of linear pieces, in long double or
        mpmath, :meth:`_settle_pieces`; the bound is then the recomputation's). ``phi``:
        ``(mu, zeta)`` when ``mu`` is the damped system's rounded ``mu_c`` (for such a recomputation,
        at ``mu^2 (1 + zeta^2)`` exactly).
        """
        eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
        e, m = eps.ravel(), mu.ravel()
        tau, log_tau, theta, zone, growth = self._engine.floquet(e, m, growth=True)
        pieces = self._certified_pieces() if certify else None
        err = self._trace_error(e, m) if trace else None
        if pieces is not None:
            if phi is not None and trace:   # (a trace recomputed at mu^2 (1 + zeta^2) formed exactly)
                phi = tuple(np.broadcast_to(np.asarray(v, float).ravel(), e.shape) for v in phi)
            else:
                phi = None
            tau, log_tau, theta, zone, growth, err = self._settle_pieces(pieces, e, m, tau, log_tau, theta, zone,
                                                                         growth, exact_growth=trace,
                                                                         trace_error=err, phi=phi)
        sh = eps.shape
        return Floquet0(tau=tau.reshape(sh), log_tau=log_tau.reshape(sh), growth=growth.reshape(sh),
                        theta=theta.reshape(sh), zone=zone.reshape(sh),
                        tau_error=None if err is None else err.reshape(sh))

    def _linear_pieces(self):
        """``((x0, x1, s0, s1), ...)``: the shape as pieces linear in ``tau`` over the period (``s`` from
        ``s0`` at ``x0`` to ``s1`` at ``x1``, constant where ``s0 = s1``), or None. A drive that gives
        them has its verdicts decided in extended precision where the engine's trace is within its
        accuracy of the threshold (:meth:`_settle_pieces`), with and without damping, up to
        :attr:`CERTIFIED_PIECES` pieces; its motion in a sweep is integrated by the compiled kernel
        (:meth:`_shape_table`)."""
        return None

    #: Up to this many linear pieces the verdicts near the threshold are decided in extended precision
    #: (a Taylor series per piece: beyond, each decision would cost more than a whole report).
    CERTIFIED_PIECES = 128

    def _own(self, method):
        """Whether the class that defines ``method`` also gives the ``_shape`` in use (a subclass that
        changes the shape does not inherit its parent's exact description of it)."""
        owner = next(k for k in type(self).__mro__ if method in vars(k))
        return type(self)._shape is owner._shape

    def _exact_pieces(self):
        """:meth:`_linear_pieces`, where they describe this drive's shape (else None)."""
        pieces = self._linear_pieces()
        return pieces if pieces is not None and self._own("_linear_pieces") else None

    def _certified_pieces(self):
        """The linear pieces the verdicts are certified on (at most :attr:`CERTIFIED_PIECES`), or None."""
        pieces = self._exact_pieces()
        return pieces if pieces is not None and len(pieces) <= self.CERTIFIED_PIECES else None

    def _shape_table(self):
        """``(XS, SA, SB, SD)``: the shape as segments of ``x = tau / 2`` in ``[0, 1]``, on segment ``k``
        ``s = SA[k] + SB[k] (x - XS[k]) + SD[k] sin(2 pi x)`` (``XS`` ends with 1): what the compiled
        integrator of the sweeps evaluates. From the steps of a piecewise-constant drive or the
        linear pieces; None for a drive known only by its ``_shape``."""
        steps = self._steps()
        if steps is not None:
            levels, fractions = steps
            marks = np.concatenate([[0.0], np.cumsum(fractions)])
            marks[-1] = 1.0
            keep = marks[1:] > marks[:-1]
            sa = np.asarray(levels, float)[keep]
            return np.concatenate([marks[:-1][keep], [1.0]]), sa, np.zeros(sa.size), np.zeros(sa.size)
        pieces = self._exact_pieces()
        if pieces is None:
            return None
        x0, x1, s0, s1 = (np.array([p[i] for p in pieces], float) for i in range(4))
        x0, x1 = 0.5 * x0, 0.5 * x1
        keep = x1 > x0
        x0, x1, s0, s1 = x0[keep], x1[keep], s0[keep], s1[keep]
        return np.concatenate([x0, [1.0]]), s0, (s1 - s0) / (x1 - x0), np.zeros(s0.size)

    #: The generic engine's ``tr M / 2`` is taken to be within ``_ENGINE_BAND e^G`` of the exact one
    #: (``G`` bounds the growth over the repelling parts of the period: the size of the terms that
    #: cancel in the trace); it is about ``1e-13 e^G`` where measured, ``1e-12`` at the edges of zone 0.
    _ENGINE_BAND = 1e-10

    def _trace_error(self, eps, mu):
        """A bound on the absolute error of the generic engine's ``tr M / 2`` at flat ``eps, mu``
        (:attr:`_ENGINE_BAND` ``e^G``; ``G`` from the linear pieces where the drive gives them,
        else from the largest ``s``; ``G`` capped at 700)."""
        return self._ENGINE_BAND * np.exp(np.minimum(self._engine_growth(eps, mu), 700.0))

    def _engine_growth(self, eps, mu):
        """``G`` of :meth:`_trace_error`: a bound on the growth over the repelling parts of the period
        (``sqrt(8) eps`` times the sum over the linear pieces of their width times
        ``sqrt(max(mu^2 + s, 0))`` at their larger end, where the drive gives them)."""
        eps, mu = np.asarray(eps, float), np.asarray(mu, float)
        m2 = mu * mu
        table = self._growth_table
        with np.errstate(over="ignore", invalid="ignore"):
            if table is not None:
                widths, tops = table
                return SQRT8 * np.abs(eps) * (np.sqrt(np.maximum(m2[..., None] + tops, 0.0)) * widths).sum(axis=-1)
            return 2.0 * SQRT8 * eps * np.sqrt(np.maximum(m2 + self._engine.s_max, 0.0))

    @functools.cached_property
    def _growth_table(self):
        """``(widths, tops)`` of the linear pieces (:meth:`_exact_pieces`; their larger end's ``s``),
        as arrays, for :meth:`_engine_growth`; None without them."""
        pieces = self._exact_pieces()
        if pieces is None:
            return None
        x0, x1, s0, s1 = (np.array([p[i] for p in pieces], float) for i in range(4))
        return x1 - x0, np.maximum(s0, s1)

    def _settle_pieces(self, pieces, eps, mu, tau, log_tau, theta, zone, growth, exact_growth=True,
                       trace_error=None, phi=None):
        """The engine's undamped data with the verdicts near the threshold decided in extended
        precision (:func:`kapitza._certify.pieces_exact`; flat arrays; ``exact_growth``: the growth is
        reported, and is to be good to 1e-12 there). Where the exact verdict differs
        from the engine's, the zone follows it: a point found stable in the gap ``theta = k pi`` lies
        in zone ``k - 1`` while ``|tau|`` rises with ``eps`` there, in zone ``k`` where it falls; one
        found unstable on zone ``n`` lies in the gap its trace's sign gives (``(-1)^k``).

        ``trace_error``: the trace is reported and this bounds the engine's error: a trace it leaves
        worse than :data:`kapitza._certify.TRACE_RTOL` relative is recomputed too (at ``phi =
        (mu, zeta)``'s ``mu^2 (1 + zeta^2)`` where given, the damped system's exact ``phi``-equation),
        and the sixth item is the bound, that of the recomputation where there was one (None
        without; the verdicts near the threshold stay those at ``mu``, as without the trace)."""
        from .._certify import MAX_PHASE, TRACE_RTOL, pieces_exact, pieces_phase

        trace = trace_error is not None
        reach = pieces_phase(eps, mu, pieces) <= MAX_PHASE
        near = (np.abs(np.abs(tau) - 1.0) <= self._trace_error(eps, mu)) & reach
        ill = np.zeros(eps.size, bool)
        if trace:
            with np.errstate(invalid="ignore"):
                ill = ~(trace_error <= TRACE_RTOL * np.abs(tau)) & reach & ~near
        idx = np.flatnonzero(near | ill)
        if not idx.size:
            return tau, log_tau, theta, zone, growth, trace_error
        tau, log_tau, theta, zone, growth = (np.array(v, copy=True) for v in (tau, log_tau, theta, zone, growth))
        res = [None] * idx.size
        # (the verdicts near the threshold at mu; a recomputed trace at phi's exact mu^2 (1 + zeta^2))
        for part, at_phi in ((near[idx], False), (ill[idx], phi is not None)):
            j = idx[part]
            if not j.size:
                continue
            m_j, z_j = (phi[0][j], phi[1][j]) if at_phi else (mu[j], None)
            for k, r in zip(np.flatnonzero(part).tolist(), pieces_exact(eps[j], m_j, z_j, pieces, exact_growth, trace)):
                res[k] = r
        if trace:
            trace_error = np.array(trace_error, float, copy=True)
            trace_error[idx] = [r[4] for r in res]
            res = [r[:4] for r in res]
        t_x, lt_x, st_x, gr_x = (np.array([r[i] for r in res]) for i in range(4))
        st_x = st_x.astype(bool)
        z, k = zone[idx], np.rint(theta[idx] / PI).astype(np.int64)
        # whether |tau| rises with eps, where a point the engine put in a gap is stable (one engine call)
        up = st_x & (z < 0)
        if up.any():
            j = idx[up]
            h = 1e-7 * eps[j]
            lt = self._engine.log_tau(np.concatenate([eps[j] + h, eps[j] - h]), np.concatenate([mu[j], mu[j]]))[1]
            z[up] = np.maximum(k[up] - (lt[:j.size] > lt[j.size:]), 0)
        # (where the engine said unstable with this sign, its theta came from that turn)
        flip = ~st_x & ((z >= 0) | ((k % 2 == 1) != (t_x < 0)))
        z[flip] = -1
        tau[idx], log_tau[idx], zone[idx] = t_x, lt_x, z
        if st_x.any():
            n = z[st_x]
            a = np.arccos(np.clip(t_x[st_x], -1.0, 1.0))
            theta[idx[st_x]] = n * PI + np.where(n % 2 == 0, a, PI - a)
        growth[idx] = np.where(st_x, 0.0, gr_x)
        flips = idx[flip]
        if flips.size:
            # off the zones: theta = k pi with the exact trace's parity, the one such k within pi of
            # the engine's turn of (1, 0) (one engine call; any direction turns by less than pi from
            # k pi, and the turn stays accurate where the trace has lost its digits, with its sign or
            # the engine's zone)
            j = flips
            theta[j] = PI * gap_of_turn(self._engine.period(eps[j], mu[j], True)[2], tau[j] < 0)
        return tau, log_tau, theta, zone, growth, trace_error

    def _edges0(self, mu, n):
        """``(eps_lo, eps_hi)`` of undamped zone ``n`` at ``mu`` (NaN where there is none).

        Default: bracketed by the rotation angle of the generic engine and solved on
        ``|tr M / 2| = 1`` to adjacent doubles (:mod:`kapitza.engines.edges`).
        """
        from ..engines import zone_edges

        mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
        sh = mu.shape
        mu, n = mu.ravel(), n.ravel()
        rate, B = self._zone_rate(mu)
        ok = (rate > 0) & (n >= 0)
        lo = np.full(mu.size, np.nan)
        hi = np.full(mu.size, np.nan)
        if ok.any():
            eng = self._engine
            lo[ok], hi[ok] = zone_edges(eng.floquet, eng.log_tau, mu[ok], n[ok], rate[ok], B[ok],
                                        noise=self._zone_noise, reach=(eng.eps_max(mu[ok]), eng.refuse))
            # Kapitza's limit: zone 0's lower edge from the engine's trace errs by about 1e-16 / mu^4
            # relative (tau - 1 is of order eps^2 mu^2 there); a drive of linear pieces moves it to the
            # double its certified verdict puts it at (binades off at mu = 1e-5 and below)
            low = np.flatnonzero(ok & (n == 0) & (mu < self._kapitza_mu(False)) & np.isfinite(lo) & (lo < hi))
            if low.size and self._certified_pieces() is not None:
                # (searched from the averaging threshold below mu = 1e-3, where it is the nearer: it errs
                # by O(mu^2) relative)
                start = np.where(mu[low] < 1e-3, self.kapitza_eps(mu[low]), lo[low])
                found, top, good = _api.kapitza_edge(self, mu[low], start, hi[low])
                lo[low[good]], hi[low[good]] = found[good], top[good]
        return lo.reshape(sh), hi.reshape(sh)

    def _kapitza_mu(self, damped: bool) -> float:
        """Kapitza's limit: below this ``mu`` zone 0's lower edge (damped or not) is searched on the
        certified verdicts from the averaging threshold (:func:`kapitza.drives._api.kapitza_edge`),
        where the double computation loses it to cancellation. A drive given by its shape: 0.03 (the
        engine's edge errs there by about ``1e-16 / mu^4`` relative, which passes 1e-10: a chart
        settles the pixels within 1e-9 of its edges by their verdicts). Else, damped, 1e-50 (the
        excess keeps its digits while it is a double) and, undamped, the drive's own (0: none; the
        step drives' sheared frame keeps ``tr M / 2 - 1`` to about ``mu = 1e-10``)."""
        if self._from_shape:
            return 0.03
        return 1e-50 if damped else 0.0

    def _zone_noise(self, eps, mu):
        """The logarithm of the engine's trace bound (uncapped) far out, where nothing after the double
        search refines a zone it cannot resolve (:func:`kapitza.engines.edges.zone_edges`' ``noise``):
        past the phase up to which a drive of linear pieces has a zone thinner than a double placed
        by its certified trace (:data:`kapitza.drives._api.EMPTY_PHASE`; for a drive given by its
        shape alone, past that growth). ``-inf`` elsewhere: the bound is pessimistic, and the search
        follows the trace's own digits there."""
        from .._certify import pieces_phase

        grow = self._engine_growth(eps, mu)
        pieces = self._certified_pieces()
        far = (pieces_phase(eps, mu, pieces) if pieces is not None else grow) > _api.EMPTY_PHASE
        return np.where(far, np.log(self._ENGINE_BAND) + grow, -np.inf)

    def _zone_rate(self, mu):
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
        # the gap below zone 0 at e1 with tau within the engine's error of 1 (Kapitza's limit, where
        # tau - 1 is lost to cancellation): zone 0 may begin below e1
        with np.errstate(invalid="ignore"):
            flat = (l1 == 0) & (np.abs(f.tau[mu.size:] - 1.0) <= self._trace_error(e1, mu))
        n_hi = np.where(flat, np.maximum(n_hi, 0), n_hi)
        if damped:
            n_lo, n_hi = n_lo - 1, n_hi + 1
        n_lo = np.maximum(n_lo, 0).astype(np.int64)
        return n_lo.reshape(sh), n_hi.astype(np.int64).reshape(sh)

    def _verdict0(self, eps, mu):
        """The certified undamped verdicts alone (stable where true), for a drive that can settle
        them more cheaply than its Floquet data (default: :meth:`_floquet0` with ``certify``). A
        drive that gives them has its edges about a thin zone moved by a window of doubles at
        once (:func:`~kapitza.drives._api.certified_sides`)."""
        return self._floquet0(eps, mu, certify=True).zone >= 0

    @property
    def _gives_verdicts(self) -> bool:
        """Whether the drive settles its certified verdicts itself (overrides :meth:`_verdict0`)."""
        return type(self)._verdict0 is not Drive._verdict0

    def _signs0(self, eps, mu):
        """``(stable, sign, decided)`` of the undamped system at flat doubles, certified where
        ``decided``: the verdict and the sign of ``tr M`` (off the zones), for placing a zone
        thinner than a double between the two doubles the sign changes between
        (:func:`~kapitza.drives._api.certified_sides`), by a drive that has them cheaper than its
        certified Floquet data (:attr:`_gives_signs`; steps and linear pieces use those)."""
        raise NotImplementedError

    @property
    def _gives_signs(self) -> bool:
        """Whether the drive gives :meth:`_signs0` (overrides it)."""
        return type(self)._signs0 is not Drive._signs0

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

    def text(self) -> str:
        """The text form :func:`kapitza.parse_drive` reads back: the name, for a drive whose
        :meth:`from_text` takes no parameters (a drive with parameters overrides both)."""
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
        ``pi mu / 2`` for the sine); ``inf`` where that exceeds the largest double.
        """
        mu = _v.positive("mu", mu)
        with np.errstate(over="ignore"):
            return mu / np.sqrt(8.0 * self._mean_square_velocity)

    # ------------------------------------------------------------ the questions
    # What the public functions of kapitza ask a drive, on validated float arrays that
    # broadcast (``zeta``: damping ratios >= 0; ``c``: damping in 1/s). Each has one generic
    # body (:mod:`kapitza.drives._api`, built on the undamped data above and the damping layer);
    # a drive with closed forms overrides what it can answer better (the square wave: every
    # one of them, undamped) and hands the rest back with ``super()``.

    #: The drive finds every zone of a window of ``eps`` at once (:meth:`_window0`).
    _windowed = False

    #: Whether :meth:`edges` moves the undamped edges of :meth:`_edges0` to the doubles the
    #: certified verdict puts them at (a drive whose edges come from its verdict itself: False).
    _edges_need_sides = True

    #: Whether :meth:`_edges0` gives each edge as the same double whichever call asks (an edge
    #: solved row by row): the damping layer's brackets then need not be moved to the certified
    #: doubles to be the same for every zone that shares them.
    _edges_unique = False

    @property
    def _batched_points(self) -> bool:
        """Whether one point's margin may be searched with many points of a row at once, spread over
        decades of ``eps``, and together with the rig's edges (:func:`kapitza.drives._api.point_margin`,
        :func:`kapitza.drives._api.point_edges`): where its certified verdicts are cheap (steps or linear
        pieces, decided in long double). The rig's edges alone are searched so for every drive
        (:func:`kapitza.drives._api.rig_intervals`: their ladders stay within a few decades of the point)."""
        return self._certified_cheap(False)

    @property
    def _engine_verdicts(self) -> bool:
        """Whether the verdicts before certification, damped or not, are the generic engine's own (a
        drive given by its shape that keeps :meth:`_floquet0`, :meth:`_floquet`, :meth:`_log_tau0`
        and :meth:`_tau_minus_one0`): one point's searches may then narrow their brackets on the
        compiled engine directly (:func:`kapitza.drives._api._narrowed_compiled`)."""
        kind = type(self)
        return (self._from_shape and kind._floquet0 is Drive._floquet0 and kind._floquet is Drive._floquet
                and kind._log_tau0 is Drive._log_tau0 and kind._tau_minus_one0 is Drive._tau_minus_one0)

    @property
    def _far_cost(self) -> bool:
        """Whether a verdict costs more the larger ``eps`` (the Taylor steps of the linear pieces and
        the engine's grow with it; an exact segment product's do not): one point's searches then ask
        few rungs far above it at a time (:func:`kapitza.drives._api.point_margin`)."""
        return self._steps() is None

    @property
    def _search_ways(self) -> int:
        """Points per row and step of a one-point search (:func:`kapitza.drives._api.search_bits`'s
        ``ways``): many where a call costs about the same for one point as for dozens (an exact
        segment product), fewer where each point costs (Taylor steps, the engine's period: about
        8 us a point against 70 us a call for the triangle)."""
        return 16 if self._far_cost else 64

    def _window0(self, mu, e_a, e_b):
        """``(rows, zone, lo, hi)``: the undamped zones meeting ``[e_a[i], e_b[i]]`` at ``mu[i]``
        (flat arrays, one entry per zone found), for a drive with :attr:`_windowed`."""
        raise NotImplementedError

    def _eps_reach(self, mu):
        """The largest ``eps`` whose Floquet data this drive gives at ``mu`` (array_like): a search
        climbs no further. The generic engine's (:meth:`kapitza.engines.Engine.eps_max`: its steps
        a period are bounded) where the data come from it; else the phase's own bound."""
        if self._from_shape:
            with np.errstate(over="ignore"):
                return self._engine.eps_max(np.minimum(mu, self._engine.MU_MAX))
        return np.full(np.shape(mu), _v.EPS_MAX)

    @property
    def _from_shape(self) -> bool:
        """Whether this drive's Floquet data come from the generic engine (it gives only its shape)."""
        return type(self)._floquet0 is Drive._floquet0

    def _steps(self):
        """``(levels, fractions)`` of a piecewise-constant drive (exact segment products), else None."""
        return None

    @property
    def _damped_certified(self) -> bool:
        """Whether :meth:`_damped_exact` decides damped verdicts in extended precision."""
        return self._steps() is not None or self._certified_pieces() is not None

    def _certified_cheap(self, damped: bool) -> bool:
        """Whether the certified verdicts (:meth:`_floquet0` with ``certify``, and :meth:`_damped_exact`
        where ``damped``) cost about what the double computation does (a long double product, mpmath
        only where that cannot decide): the one-point searches then ask them at every step, and the
        damping layer asks :meth:`_damped_exact` wherever its verdict is near the edge. A drive of
        linear pieces: where the long double tier (:func:`kapitza._certify.pieces_ld`) or the compiled
        double-double one (:func:`kapitza.engines.magnus.compiled_pieces_tier`) is there to decide them."""
        from .._certify import HAS_LONG_DOUBLE
        from ..engines.magnus import compiled_pieces_tier

        return (HAS_LONG_DOUBLE or compiled_pieces_tier() is not None) and self._certified_pieces() is not None

    def _certified_steps(self, damped: bool) -> bool:
        """Whether a one-point search asks the certified verdicts at its last steps, once a bracket is
        within 2^36 ulp (:func:`kapitza.drives._api.search_bits`' ``certified_steps``), rather than the
        fast ones to the last bit, then the certified check of the pair and, where it fails, a search of
        the windows about it: where :meth:`_certified_cheap`, or where certified verdicts cost more only
        near the edge itself (the sine's Sturm counts)."""
        return self._certified_cheap(damped)

    def _damped_exact(self, eps, mu, zeta, growth=True):
        """``[(stable, growth)]`` of the damped system at the exact doubles (flat arrays, points
        where rounding may decide), decided in extended precision; None where the drive has no
        exact monodromy (a drive given by its shape: its damped verdicts are the engine's).
        ``growth``: the growth will be reported (without, only the verdict need be exact, and a
        drive may give a growth only as good as its extended-precision trace, which is cheaper)."""
        steps = self._steps()
        if steps is None:
            pieces = self._certified_pieces()
            if pieces is None:
                return None
            from .._certify import pieces_exact

            return [(st, gr) for _, _, st, gr in pieces_exact(eps, mu, zeta, pieces, growth)]
        from .._certify import damped_mp

        levels, fractions = steps
        return damped_mp(eps, mu, zeta, levels, tuple(2.0 * f for f in fractions))

    def _floquet(self, eps, mu, zeta, certify=True, trace=False):
        """Floquet data with damping ratio ``zeta``: ``(tau, growth, theta, stable, zone, kappa)``
        (:func:`kapitza.drives._api.damped_floquet`; ``certify`` and ``trace`` as in :meth:`_floquet0`;
        with ``trace`` a seventh item, the bound on the error of ``tau``)."""
        return _api.damped_floquet(self, eps, mu, zeta, certify, trace)

    def _edges(self, mu, n, zeta):
        """``(eps_lo, eps_hi)`` of zone ``n`` with damping ratio ``zeta`` (:func:`kapitza.drives._api.damped_edges`)."""
        return _api.damped_edges(self, mu, n, zeta)

    def closed_form(self, zeta=0.0) -> bool:
        """Whether this drive answers from closed forms at damping ratio ``zeta`` (the square
        wave, undamped): its zone edges then cost a few Newton steps, any window of a chart alike."""
        return False

    def floquet_data(self, eps, mu, zeta):
        """``(trace, determinant, multipliers, growth, rotation_number, stable, zone, trace_error)``
        (:func:`kapitza.floquet`; ``trace_error`` bounds the absolute error of ``trace``)."""
        trace, det, mult, growth, rho, stable, zone, err = _api.floquet(eps, mu, self, zeta, trace_error=True)
        return trace, det, mult, growth, rho, stable, np.where(stable, zone, -1).astype(np.int64), err

    def verdict(self, eps, mu, zeta, want_zone=True):
        """``(stable, zone)``, zone -1 where unstable (:func:`kapitza.is_stable`, :func:`kapitza.zone_index`)."""
        return _api.verdict(eps, mu, self, zeta)

    def growth(self, eps, mu, zeta):
        """``log max|lambda|`` per period (:func:`kapitza.growth_rate`)."""
        return _api.floquet(eps, mu, self, zeta)[3]

    def rotation(self, eps, mu, zeta):
        """Rotation number per period (:func:`kapitza.rotation_number`)."""
        return _api.floquet(eps, mu, self, zeta)[4]

    def edges(self, mu, n, zeta, certify=True):
        """``(eps_lo, eps_hi)`` of zone ``n``, NaN where there is none (:func:`kapitza.zone_edges`).

        ``certify``: undamped, move each edge to the double the certified verdict puts it at (the
        last unstable double below the zone, the first above it: :func:`kapitza.is_stable` agrees at
        every double); a chart that needs the curves to a pixel passes False."""
        lo, hi = self._edges(mu, n, zeta)
        return self._sides(mu, zeta, lo, hi) if certify else (lo, hi)

    def _sides(self, mu, zeta, lo, hi):
        """Edges ``lo, hi`` found by :meth:`_edges` moved to the doubles the certified verdict puts them
        at (:func:`kapitza.drives._api.certified_sides`), where this drive needs it (:attr:`_edges_need_sides`;
        damped, where its damped verdicts are certified)."""
        damped = np.any(np.asarray(zeta) > 0)
        if self._damped_certified if damped else self._edges_need_sides:
            shape = np.shape(lo)
            m = np.broadcast_to(np.asarray(mu, float), shape).ravel()
            z = np.broadcast_to(np.asarray(zeta, float), shape).ravel() if damped else None
            lo, hi = _api.certified_sides(self, m, np.asarray(lo, float).ravel(), np.asarray(hi, float).ravel(), z)
            lo, hi = lo.reshape(shape), hi.reshape(shape)
        return lo, hi

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
        trace, det, mult, growth, rho, stable, zone, _ = (np.asarray(a)[()] for a in self.floquet_data(
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
        if zone >= 0 and np.isfinite(lo) and np.isfinite(hi):
            # one point: its edges moved to the doubles the certified verdict puts them at, as
            # zone_edges gives them (the array margin keeps the solver's doubles)
            lo, hi = (float(v) for v in self._sides(np.float64(mu), np.float64(zeta), np.float64(lo), np.float64(hi)))
            m = min(eps - lo, hi - eps) / eps
        return bool(st), int(zone), float(lo), float(hi), float(m)

    def point_edges(self, eps, mu, zeta, phys=None, pointwise=True, level0=None):
        """:meth:`point_margin` and, for a physical point (``phys = (T, A, l, g, c)``) in or beside a zone,
        :meth:`point_intervals` of that zone: ``(margin, intervals)``, ``intervals`` None otherwise. Where
        the one-point searches answer, a point inside a zone has its edges in ``eps`` and along the rig's
        knobs searched together (:func:`kapitza.drives._api.point_edges`); ``level0``: the point's
        certified level there (``zone + 1/2`` on a zone, ``theta / pi`` off them), when known."""
        if phys is not None and pointwise and self._joint_search(zeta, level0):
            found = _api.point_edges(self, eps, mu, zeta, *phys[:4], level0=level0)
            if found is not None:
                margin, rig = found
                # (the generic body: a drive's own point_intervals would search the rig's edges again)
                return margin, (None if rig is None else Drive.point_intervals(
                    self, eps, mu, margin[1], zeta, *phys, pointwise, (margin[2], margin[3]), rig))
        margin = self.point_margin(eps, mu, zeta, pointwise)
        if phys is None or margin[1] < 0:
            return margin, None
        return margin, self.point_intervals(eps, mu, margin[1], zeta, *phys, pointwise, (margin[2], margin[3]))

    def _joint_search(self, zeta, level0) -> bool:
        """Whether :meth:`point_edges` asks the one-point searches for the margin's and the rig's edges
        (:func:`kapitza.drives._api.point_edges`) at a point of certified level ``level0`` (None where
        unknown): where :attr:`_batched_points` and :meth:`_joint_edges`."""
        return self._batched_points and self._joint_edges(zeta)

    def _joint_edges(self, zeta) -> bool:
        """Whether :meth:`point_edges` may search the margin's and the rig's edges together (a drive
        whose one-point answers come from elsewhere, closed forms, says no)."""
        return True

    def point_intervals(self, eps, mu, zone, zeta, T, A, l, g, c, pointwise=True, eps_edges=None, rig=None):
        """Zone ``zone`` of one physical point as intervals a rig is turned along: ``T_lo, T_hi``
        (at this ``A``), ``A_lo, A_hi`` (at this ``T``), ``stroke_lo, stroke_hi`` (at this
        frequency), ``frequency_lo, frequency_hi`` (at this stroke); and the ``stroke``.
        ``eps_edges``: the zone's edges in ``eps`` at this ``mu``, when known (``T`` is ``eps``
        times ``sqrt(8 l / A)`` at this ``A``: no second solve); ``rig``: the edges along ``A`` and the
        frequency, when known (:func:`kapitza.drives._api.rig_intervals`)."""
        stroke = self.point_stroke(T, A)
        if eps_edges is not None:
            scale = np.sqrt(8.0 * np.asarray(l, float) / np.asarray(A, float))
            Tlo, Thi = eps_edges[0] * scale, eps_edges[1] * scale
        else:
            Tlo, Thi = self.period_edges(np.asarray(A, float), np.asarray(zone), np.asarray(l, float),
                                         np.asarray(g, float), np.asarray(c, float))
        out = dict(T_lo=float(Tlo), T_hi=float(Thi))
        if rig is None:
            rig = _api.rig_intervals(eps, mu, zone, self, zeta, T, A, l, g)
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
