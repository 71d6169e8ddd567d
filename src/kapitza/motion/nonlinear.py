"""The motion itself: ``theta(t)`` of the full and the linearised equation, exact or integrated.

The full equation is ``theta'' = (g + a(t))/l sin(theta) - c theta'`` with ``theta``
the angle from the upright, counted counter-clockwise, and ``a(t)`` the drive's acceleration
(the paper's square wave (2.2) by default). Without damping each step of a piecewise-constant
drive is solved exactly in Jacobi elliptic functions (:mod:`kapitza.motion._elliptic`,
``docs/theory.md`` section 6): the result at any time is a finite sequence of closed-form phase
maps, with no step-size error. The general path (damping, smooth drives, and the independent
cross-check) integrates with :func:`scipy.integrate.solve_ivp` (DOP853) and restarts at every
switch, never stepping across a jump of ``a``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _validate as _v
from .._display import Summary, num
from ..parameters import G_EARTH
from ..propagation import linear_motion
from ._elliptic import _phase_step, _phase_step_one
from ._integrate import (MAX_DOP853_SWEEP as MAX_DOP853_SWEEP, MAX_PERIODS as MAX_PERIODS, MAX_SAMPLES,
                         MAX_SCALED_PHASE, MAX_TRAJECTORY_PERIODS as MAX_TRAJECTORY_PERIODS, METHODS, _SPEED_LIMIT,
                         _add_turns, _budget, _check_speed, _choice, _damping, _drive_of, _integrated_drive,
                         _method, _one_damping, _peak, _physical, _reduce_angle, _single_set, _tolerances)
from ._maps import step_plan
from ._pivot import _checked

if TYPE_CHECKING:
    from ..drives import Drive

__all__ = [
    "phase_flow",
    "nonlinear_motion",
    "phase_energy",
    "Trajectory",
    "simulate",
    "MODELS",
    "METHODS",
]

#: The equations of motion: the full one and its linearisation (2.3) about the upright.
MODELS = ("nonlinear", "linear")


# ------------------------------------------------------------------ validation helpers


def _times(t):
    t = _v.finite("t", t)
    if np.any(t < 0):
        raise _v.KapitzaValueError(f"t must be >= 0 (0 <= t < inf); got {t[t < 0].flat[0]!r}")
    return t


# ------------------------------------------------------------------ one phase
@_v.shapes_named
def phase_flow(t, theta0, dtheta0, s):
    """Exact flow of one phase, the autonomous pendulum ``theta'' = s sin(theta)``.

    Parameters
    ----------
    t : array_like
        Duration [s], any sign (the flow is reversible), with ``sqrt|s| |t| <= 1e5``.
    theta0, dtheta0 : array_like
        Initial angle from the upright [rad] (any real; turns are kept, not
        wrapped) and angular velocity [rad/s].
    s : array_like
        ``(g + a)/l`` [1/s^2]: ``w_h^2 > 0`` in the hyperbolic phase (the upright
        is a saddle), ``-w_e^2 < 0`` in the elliptic one (the upright is the
        bottom of the potential), 0 for free flight. All arguments broadcast.

    Returns
    -------
    theta, dtheta : ndarray
        The state after the time ``t``.

    Raises
    ------
    ValueError
        If an argument is not finite, ``sqrt|s| |t|`` exceeds ``1e5``, or the arguments do not
        broadcast.

    Notes
    -----
    ``docs/theory.md`` section 6. With ``q = theta`` (``s < 0``) or
    ``q = theta + pi`` (``s > 0``) this is ``q'' = -w^2 sin q``; the state
    ``(sin(q/2), q'/(2w), cos(q/2)) = (k sn a, k cn a, dn a)`` is advanced by the
    addition theorems of the Jacobi functions of ``w t``. Librating (``k < 1``),
    rotating (``k > 1``, reciprocal modulus) and separatrix (``k = 1``,
    ``tanh``/``sech``) motions are all covered; ``1 - k^2`` is computed as a
    product and drives the functions near ``k = 1`` through the complementary
    nome (see :mod:`kapitza.motion._elliptic`).

    Examples
    --------
    >>> from kapitza.motion import phase_flow
    >>> phase_flow(0.3, 0.5, 1.0, 109.81)
    (np.float64(4.1005...), np.float64(17.8853...))
    """
    t = _v.finite("t", t)
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    s = _v.finite("s", s)
    t, theta0, dtheta0, s = _v.broadcast(t=t, theta0=theta0, dtheta0=dtheta0, s=s)
    _check_speed_pointwise(dtheta0, s)
    with np.errstate(over="ignore"):
        wt = np.sqrt(np.abs(s)) * np.abs(t)
    long = ~(wt <= MAX_SCALED_PHASE)
    if np.any(long):
        raise _v.KapitzaValueError(
            f"t and s must keep sqrt|s| |t| <= {MAX_SCALED_PHASE:g} rad for the exact flow (its elliptic functions "
            f"lose the motion's digits beyond); got t = {float(t[long].flat[0])!r} with s = {float(s[long].flat[0])!r}")
    back = t < 0
    # Time reversal: run the mirrored state forward and mirror back.
    om = np.where(back, -dtheta0, dtheta0)
    r, k = _reduce_angle(theta0)
    th1, om1 = _phase_step(r, om, s, np.abs(t))
    return _v.scalars(np.asarray(_add_turns(th1, k)), np.where(back, -om1, om1))


def _check_speed_pointwise(dtheta, s):
    """:func:`_check_speed` element by element (``s`` broadcast with ``dtheta``)."""
    lim = 2.0 * _SPEED_LIMIT * np.sqrt(np.abs(s))
    big = (np.abs(dtheta) > lim) & (s != 0)
    if big.any():
        raise _v.KapitzaValueError(
            f"dtheta0 must satisfy |dtheta0| <= 2e150 sqrt|s| (beyond it the energy of the motion overflows a "
            f"double); got dtheta0 = {float(dtheta[big].flat[0])!r} with s = {float(s[big].flat[0])!r}")


@_v.shapes_named
def nonlinear_motion(t, theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, damping=None,
                     zeta=None, method=None, rtol=1e-10, atol=1e-12, drive=None):
    """Motion of the full equation ``theta'' = (g + a(t))/l sin(theta) - c theta'``.

    Parameters
    ----------
    t : array_like
        Times ``>= 0`` [s], any shape and order.
    theta0, dtheta0 : array_like
        Angle from the upright [rad] and angular velocity [rad/s] at ``t = 0``, the
        start of a hyperbolic phase (``a = +A``).
    T, A, l, g : array_like
        Drive half-period [s], acceleration amplitude [m/s^2], rod length [m],
        gravity [m/s^2]; each > 0 (``A <= g`` is accepted: the second phase is then
        hyperbolic or free flight). All arguments broadcast together.
    eps, mu : float, optional
        Arnold's parameters instead of ``T`` and ``A`` (keywords; with ``l`` and ``g``):
        ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``. Give ``(eps, mu)`` or ``(T, A)``.
    damping, zeta : float, optional
        The damping, as ``c`` [1/s] (``theta'' + c theta' = ...``) or as the ratio
        ``zeta = c / (2 sqrt(g/l))``, not both.
    method : {None, 'exact', 'dop853'}
        ``'exact'``: closed-form phase maps (``c = 0`` and a piecewise-constant drive only).
        ``'dop853'``: scipy's DOP853 restarted at every switch (scalar parameters only).
        ``None``: ``'exact'`` when ``c = 0`` and the drive is piecewise constant, else ``'dop853'``.
    rtol, atol : float, optional
        Tolerances of ``'dop853'``, met by every component: for an ensemble the
        solver's RMS norm is tightened by ``sqrt(2n)``. ``rtol >= 1e-13``.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.

    Returns
    -------
    theta, dtheta : ndarray
        Of the broadcast shape. ``theta`` is not wrapped: a full turn adds
        ``2 pi``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``docs/theory.md`` sections 1 and 6. The exact path maps the state through
    each whole phase with :func:`phase_flow` and finishes the current phase from
    its start, so the error does not grow with the number of steps taken: there
    are none.

    Examples
    --------
    >>> import numpy as np
    >>> from kapitza.motion import nonlinear_motion
    >>> theta, dtheta = nonlinear_motion(np.linspace(0, 0.3, 3), 0.1, 0.0, 0.15, 100.0)
    >>> theta
    array([0.1       , 0.2506..., 0.2916...])
    """
    t = _times(t)
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    T, A, l, g = _physical(T, A, l, g, eps, mu)
    c = _damping(damping, zeta, l, g)
    _v.shape_check(t=t, theta0=theta0, dtheta0=dtheta0, T=T, A=A, l=l, g=g)
    drive = _drive_of(drive)
    plan = step_plan(drive, T, A, l, g)
    method = _method(method, c, drive=drive)
    if method == "exact":
        _check_speed(dtheta0, [s_ for s_, _ in plan])
    _budget(float(np.max(t)), T, A, l, g, c, method, _peak(drive), dtheta0=dtheta0)
    r, k = _reduce_angle(theta0)
    if method == "exact":
        th, om = _exact_motion_plan(t, r, dtheta0, plan)
    else:
        rtol, atol = _tolerances(rtol, atol)
        # (the damping named as it was given)
        T, A, l, g, c = _single_set(T=T, A=A, l=l, g=g, **{"zeta" if zeta is not None else "damping": c})
        th, om = _integrated_drive(t, r, dtheta0, T, A, l, g, c, rtol, atol, False, drive)
    return _v.scalars(np.asarray(_add_turns(th, k)), np.asarray(om))


@_v.shapes_named
def phase_energy(t, theta, dtheta, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, drive=None):
    """The energy of the current phase, ``theta'^2/2 + (g + a(t))/l cos(theta)`` [1/s^2].

    Parameters
    ----------
    t : array_like
        Times [s].
    theta, dtheta : array_like
        States at those times.
    T, A, l, g, eps, mu : array_like
        As in :func:`nonlinear_motion`. All arguments broadcast.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.

    Returns
    -------
    ndarray
        Constant within each undamped phase; with damping ``c`` its rate is
        ``-c theta'^2 <= 0``. It jumps at the switches, where ``a`` does.

    Raises
    ------
    ValueError
        As in :func:`nonlinear_motion`.

    Notes
    -----
    Energy per unit ``m l^2`` in the frame of the pivot, where gravity is
    ``g + a(t)``: ``d/dt (theta'^2/2 + s cos theta) = theta' (theta'' - s sin theta)``.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> from kapitza.motion import phase_energy
    >>> traj = kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=1)
    >>> E = phase_energy(traj.t, traj.theta, traj.dtheta, T=0.15, A=100.0)
    >>> E[0]
    np.float64(109.2614...)
    >>> first = traj.t < 0.15  # the hyperbolic phase: E is conserved there
    >>> bool(np.ptp(E[first]) < 1e-9 * E[0])
    True
    """
    t = _v.finite("t", t)
    theta = _v.finite("theta", theta)
    dtheta = _v.finite("dtheta", dtheta)
    T, A, l, g = _physical(T, A, l, g, eps, mu)
    _checked(t, T, A)  # t / T must resolve the phase
    if np.any(np.abs(dtheta) > _SPEED_LIMIT):
        raise _v.KapitzaValueError(f"dtheta must satisfy |dtheta| <= 1e150 (the energy dtheta^2 / 2 must be a "
                                   f"double); got {float(np.max(np.abs(dtheta)))!r}")
    s = (g + _drive_of(drive).acceleration(t, T, A)) / l
    return 0.5 * dtheta * dtheta + s * np.cos(theta)


# ------------------------------------------------------------------ other drives


def _exact_motion_plan(t, theta0, dtheta0, plan):
    """Exact flows through the steps ``plan = ((s, duration), ...)`` of each period (trusted input:
    ``t``, the initial states and each step's ``s`` and duration broadcast together; a trajectory
    for each broadcast initial state and parameter set, sampled at its times)."""
    S = [np.asarray(s_, float) for s_, _ in plan]
    D = [np.asarray(d_, float) for _, d_ in plan]
    shapes = [x.shape for x in S + D]
    full = np.broadcast_shapes(t.shape, theta0.shape, dtheta0.shape, *shapes)
    traj = np.broadcast_shapes(theta0.shape, dtheta0.shape, *shapes)
    th = np.broadcast_to(theta0, traj).ravel().copy()
    om = np.broadcast_to(dtheta0, traj).ravel().copy()
    K = len(plan)
    S = np.stack([np.broadcast_to(x, traj).ravel() for x in S])
    D = np.stack([np.broadcast_to(x, traj).ravel() for x in D])
    starts = np.zeros_like(D)                  # each step's start within the period
    starts[1:] = np.cumsum(D[:-1], axis=0)
    period = np.sum(D, axis=0)
    ic = np.broadcast_to(np.arange(th.size).reshape(traj), full).ravel()
    tf = np.broadcast_to(t, full).ravel()
    P = period[ic]
    k = np.floor(tf / P)
    r = tf - k * P
    over = r >= P
    k = np.where(over, k + 1.0, k)
    r = np.where(over, r - P, np.maximum(r, 0.0))
    # the step a time is in: the last whose start it has reached
    i = np.sum(r[None, :] >= starts[1:, ic], axis=0) if K > 1 else np.zeros(tf.size, np.int64)
    rr = r - starts[i, ic]
    p_all = (k * K + i).astype(np.int64)
    order = np.argsort(p_all, kind="stable")
    ps = p_all[order]
    last = int(ps[-1]) if ps.size else 0
    # the state at the start of each sample's step, gathered while the steps are taken one after
    # another; then every sample is one flow from there, all in one call
    th0 = np.empty(tf.size)
    om0 = np.empty(tf.size)
    s0 = np.empty(tf.size)
    lo = 0
    # one trajectory (a motion): its steps on one state, each in microseconds (the same doubles)
    step = _phase_step_1 if th.size == 1 else _phase_step
    for p in range(last + 1):
        s, d = S[p % K], D[p % K]
        hi = int(np.searchsorted(ps, p, side="right"))
        if hi > lo:
            sel = order[lo:hi]
            kk = ic[sel]
            th0[sel], om0[sel], s0[sel] = th[kk], om[kk], s[kk]
            lo = hi
        if p < last:
            th, om = step(th, om, s, d)
    th1, om1 = _phase_step(th0, om0, s0, rr)
    # At a switch itself the state is the boundary state, not a zero-length step of it.
    at = rr == 0.0
    return np.where(at, th0, th1).reshape(full), np.where(at, om0, om1).reshape(full)


def _phase_step_1(th, om, s, d):
    """:func:`~kapitza.motion._elliptic._phase_step` of arrays of one element each."""
    th1, om1 = _phase_step_one(th[0], om[0], s[0], d[0])
    return np.array([th1]), np.array([om1])


# ------------------------------------------------------------------ a trajectory
@dataclass(frozen=True, repr=False)
class Trajectory(Summary):
    """One simulated motion, sampled at the times ``t``.

    Prints as a summary (``print(traj)``; an HTML table in Jupyter): model, drive, parameters,
    span, samples, largest ``|theta|`` and whether it stays up; :meth:`summary` gives the same
    as a JSON-ready dictionary (what ``kapitza simulate --json`` prints).

    Attributes
    ----------
    t, theta, dtheta : ndarray, shape ``(n,)``
        Times [s], angle from the upright [rad, unwrapped] and angular velocity [rad/s].
    theta0, dtheta0 : float
        Initial state at ``t = 0`` (start of a hyperbolic phase).
    T, A, l, g, c : float
        Parameters (``c``: damping [1/s]).
    model : str
        ``'nonlinear'`` or ``'linear'``.
    method : str
        ``'exact'`` or ``'dop853'``.
    drive : Drive
        The pivot's motion (the paper's square wave unless another was given).

    Examples
    --------
    >>> import kapitza
    >>> traj = kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=10)
    >>> traj
    <Trajectory: nonlinear (exact), T = 0.15 s, A = 100 m/s^2, 10 periods, 2001 samples,
     max |theta| = 0.4013 rad, stays up>
    >>> traj.t.shape, float(abs(traj.theta).max())
    ((2001,), 0.4012...)
    >>> traj.summary()["stays_up"]
    True
    """

    t: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    theta0: float
    dtheta0: float
    T: float
    A: float
    l: float
    g: float
    c: float = 0.0
    model: str = "nonlinear"
    method: str = "exact"
    rtol: float = field(default=1e-10, repr=False)
    atol: float = field(default=1e-12, repr=False)
    drive: Drive = None  # type: ignore[assignment]  # (None: the square wave, set in __post_init__)

    def __post_init__(self):
        object.__setattr__(self, "drive", _drive_of(self.drive))

    @property
    def pivot(self) -> np.ndarray:
        """Pivot height above its mean position [m] at ``t`` (:func:`pivot_displacement`)."""
        return self.drive.displacement(self.t, self.T, self.A)

    @property
    def energy(self) -> np.ndarray:
        """:func:`phase_energy` along the samples (nonlinear model)."""
        s = (self.g + self.drive.acceleration(self.t, self.T, self.A)) / self.l
        return 0.5 * self.dtheta**2 + s * np.cos(self.theta)

    @property
    def periods(self) -> float:
        """Duration in drive periods ``2T``."""
        return float(self.t[-1] / (2.0 * self.T)) if self.t.size else 0.0

    def at(self, t):
        """The same motion (same model and method) at other times ``t >= 0``."""
        return _motion(self.model, self.method, _times(t), self.theta0, self.dtheta0,
                       self.T, self.A, self.l, self.g, self.c, self.rtol, self.atol, self.drive)

    def strobe(self):
        """``(t_k, theta_k, dtheta_k)`` at ``t_k = 2 k T`` within the sampled span."""
        k = np.arange(int(np.floor(self.t[-1] / (2.0 * self.T) + 1e-12)) + 1)
        tk = 2.0 * self.T * k
        i = np.minimum(np.searchsorted(self.t, tk), self.t.size - 1)
        if np.all(self.t[i] == tk):  # sampled already (simulate puts whole periods on the grid)
            return tk, self.theta[i], self.dtheta[i]
        th, om = self.at(tk)
        return tk, th, om

    def as_rows(self):
        """``(t, theta, dtheta, pivot)`` rows for CSV."""
        return zip(self.t, self.theta, self.dtheta, self.pivot)

    # ------------------------------------------------------------ the summary
    @property
    def eps_mu(self) -> tuple[float, float]:
        """Arnold's ``(eps, mu)`` of the parameters."""
        return float(self.T * np.sqrt(self.A / (8.0 * self.l))), float(np.sqrt(self.g / self.A))

    def _fall(self):
        """Index of the first sample past the horizontal (``|theta| >= pi/2``), or None."""
        past = np.flatnonzero(np.abs(self.theta) >= 0.5 * np.pi)
        return int(past[0]) if past.size else None

    def summary(self) -> dict:
        """JSON-ready description (no arrays): model, method, damping, span, samples, final
        state, largest ``|theta|``, whether the pendulum stays above the horizontal
        (``|theta| < pi/2`` at every sample; ``falls_at``: the first sample time past it) and,
        for the nonlinear model, the whole turns of the final angle (none for the linear one,
        whose angle is not an angle once it has grown)."""
        fall = self._fall()
        t_end = float(self.t[-1]) if self.t.size else 0.0
        return dict(model=self.model, method=self.method, c=self.c, duration=t_end, periods=self.periods,
                    samples=int(self.t.size),
                    final=dict(t=t_end, theta=float(self.theta[-1]), dtheta=float(self.dtheta[-1])),
                    max_abs_theta=float(np.max(np.abs(self.theta))),
                    stays_up=fall is None, falls_at=None if fall is None else float(self.t[fall]),
                    turns=int(np.trunc(self.theta[-1] / (2 * np.pi))) if self.model == "nonlinear" else None,
                    **self._linear_growth())

    def _linear_growth(self) -> dict:
        """For the linear model: its growth per period ``2T`` (e-folds, :func:`kapitza.growth_rate`)
        and, where it grows, a note saying so — a linear motion about an unstable upright grows
        without bound, and its angle counts no turns."""
        if self.model != "linear":
            return {}
        from ..propagation import growth_rate

        eps, mu = self.eps_mu
        zeta = self.c / (2.0 * np.sqrt(self.g / self.l))
        growth = float(growth_rate(eps, mu, drive=self.drive, zeta=zeta))
        out: dict[str, Any] = dict(growth_per_period=growth)
        if growth > 0:
            out["note"] = (f"grows without bound: {growth:.3g} e-folds per period 2T "
                           f"(x{np.exp(min(growth, 700.0)):.3g} per period)")
        return out

    def headline(self) -> str:
        s = self.summary()
        up = "stays up" if s["stays_up"] else f"falls at t = {num(s['falls_at'], 4)} s"
        return (f"{self.model} ({self.method}), T = {num(self.T)} s, A = {num(self.A)} m/s^2, "
                f"{num(s['periods'], 4)} periods, {s['samples']} samples, max |theta| = {num(s['max_abs_theta'], 4)} "
                f"rad, {up}")

    def lines(self) -> list[tuple[str, str]]:
        from ..drives import as_drive

        s = self.summary()
        eps, mu = self.eps_mu
        model = f"{self.model} ({self.method})" + (f", damping c = {num(self.c)} 1/s" if self.c else "")
        up = ("stays up: |theta| < pi/2 at every sample" if s["stays_up"] else
              f"falls: passes the horizontal at t = {num(s['falls_at'])} s")
        rows = [("model", model),
                ("drive", as_drive(self.drive).describe()),
                ("parameters", f"T = {num(self.T)} s, A = {num(self.A)} m/s^2, l = {num(self.l)} m, "
                               f"g = {num(self.g)} m/s^2 (eps = {num(eps)}, mu = {num(mu)})"),
                ("start", f"theta0 = {num(self.theta0)} rad, dtheta0 = {num(self.dtheta0)} rad/s"),
                ("span", f"0 <= t <= {num(s['duration'])} s ({num(s['periods'], 4)} periods 2T), "
                         f"{s['samples']} samples"),
                ("final",
                 f"theta = {num(s['final']['theta'], 10)} rad, dtheta = {num(s['final']['dtheta'], 10)} rad/s"),
                ("max |theta|", f"{num(s['max_abs_theta'])} rad"),
                ("upright", up)]
        if s["turns"]:
            rows.append(("turns", f"{s['turns']} whole turns at the end"))
        return rows


def _motion(model, method, t, theta0, dtheta0, T, A, l, g, c, rtol, atol, drive):
    if model == "nonlinear":
        r, k = _reduce_angle(theta0)
        if k is not None:
            th, om = _motion(model, method, t, r, dtheta0, T, A, l, g, c, rtol, atol, drive)
            return _add_turns(th, k), om
    if model == "linear" and method == "exact":
        return linear_motion(t, theta0, dtheta0, T, A, l, g, drive=drive, damping=c)
    if method == "exact":
        return _exact_motion_plan(t, np.asarray(theta0, float), np.asarray(dtheta0, float),
                                  step_plan(drive, T, A, l, g))
    return _integrated_drive(t, np.asarray(theta0, float), np.asarray(dtheta0, float), *_single_set(
        T=T, A=A, l=l, g=g, c=c), rtol, atol, model == "linear", drive)


@_v.shapes_named
def simulate(theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=20.0,
             points_per_period=200, t=None, model="nonlinear", damping=None, zeta=None, method=None, rtol=1e-10,
             atol=1e-12, drive=None) -> Trajectory:
    """Simulate one motion from ``(theta0, dtheta0)`` and sample it.

    Parameters
    ----------
    theta0, dtheta0 : float
        Initial angle from the upright [rad] and angular velocity [rad/s].
    T, A, l, g : float
        As in :func:`nonlinear_motion`.
    eps, mu : float, optional
        Arnold's parameters instead of ``T`` and ``A`` (keywords; with ``l`` and ``g``):
        ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``. Give ``(eps, mu)`` or ``(T, A)``.
    periods : float, optional
        Duration in drive periods ``2T`` (ignored when ``t`` is given); >= 0.001.
    points_per_period : int, optional
        Samples per period ``2T``, evenly spaced (>= 4).
    t : array_like, optional
        Explicit sample times ``>= 0``, increasing.
    model : {'nonlinear', 'linear'}
        The full equation, or its linearisation (2.3) (exact:
        :func:`kapitza.linear_motion`).
    damping, zeta : float, optional
        As in :func:`nonlinear_motion` (then ``method='dop853'``).
    method : {None, 'exact', 'dop853'}
        As in :func:`nonlinear_motion`.
    rtol, atol : float, optional
        Tolerances of ``'dop853'``.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
        Piecewise-constant drives are exact step by step (undamped); the sine drive and
        damping use DOP853.

    Returns
    -------
    Trajectory

    Raises
    ------
    OverflowError
        For the linear model, where the motion grows beyond a double.

    Examples
    --------
    >>> import kapitza
    >>> traj = kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=50)
    >>> traj.summary()['stays_up']
    True
    """
    theta0 = _v.one("theta0", _v.finite("theta0", theta0))
    dtheta0 = _v.one("dtheta0", _v.finite("dtheta0", dtheta0))
    T, A, l, g = (_v.one(name, v) for name, v in zip("TAlg", _physical(T, A, l, g, eps, mu)))
    c = _one_damping(damping, zeta, l, g)
    _choice("model", model, MODELS)
    drive = _drive_of(drive)
    method = _method(method, c, drive)
    rtol, atol = _tolerances(rtol, atol)
    if t is None:
        # (a thousandth of a period at least, as for the tower: below it there is no motion to show)
        periods = _v.one("periods", _v.in_range("periods", periods, 1e-3, np.inf, lo_open=False))
        ppp = _v.bounded_count("points_per_period", points_per_period, MAX_SAMPLES, minimum=4)
        _v.bounded_work("periods * points_per_period", np.ceil(periods * ppp), MAX_SAMPLES,
                        what="samples held in memory")
        n = int(np.ceil(periods * ppp))
        t = np.linspace(0.0, 2.0 * T * periods, n + 1)
        if n == periods * ppp:
            # the whole periods on their exact doubles 2 T k (linspace may miss them by an ulp): the
            # stroboscopic points are then samples (Trajectory.strobe reads them, no second run)
            k = np.arange(0, n + 1, ppp)
            t[k] = 2.0 * T * (k // ppp)
    else:
        t = _times(t).ravel()
        _v.bounded_work("len(t)", t.size, MAX_SAMPLES, what="samples held in memory")
        if t.size and np.any(np.diff(t) < 0):
            raise _v.KapitzaValueError("t must be increasing")
    if model == "nonlinear" and method == "exact":
        _check_speed(dtheta0, [s_ for s_, _ in step_plan(drive, T, A, l, g)])
    _budget(float(t[-1]) if t.size else 0.0, T, A, l, g, c, method, _peak(drive), dtheta0)
    th, om = _motion(model, method, t, theta0, dtheta0, T, A, l, g, c, rtol, atol, drive)
    return Trajectory(t=t, theta=np.asarray(th), dtheta=np.asarray(om), theta0=theta0, dtheta0=dtheta0,
                      T=T, A=A, l=l, g=g, c=c, model=model, method=method, rtol=rtol, atol=atol, drive=drive)
