"""The motion itself: ``theta(t)`` of the full and the linearised equation, exact or integrated.

The full equation is ``theta'' = (g + a(t))/l sin(theta) - c theta'`` with ``theta``
the angle from the upright, counted counter-clockwise, and ``a(t)`` the square wave
(2.2). Without damping each phase is solved exactly in Jacobi elliptic functions
(:mod:`kapitza.motion._elliptic`, ``docs/theory.md`` section 6): the result at any
time is a finite sequence of closed-form phase maps, with no step-size error. The
general path (damping, and the independent cross-check) integrates each phase with
:func:`scipy.integrate.solve_ivp` (DOP853) and restarts at every switch, never
stepping across the jump of ``a``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _validate as _v
from .._display import Summary, num
from ..parameters import G_EARTH
from ..propagation import linear_motion
from ._elliptic import _phase_step
from ._pivot import _acceleration, _checked, _displacement, _phase_index

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
#: ``exact``: closed-form phase maps (undamped only); ``dop853``: solve_ivp, phase by phase.
METHODS = ("exact", "dop853")

_EPS = np.finfo(float).eps


# ------------------------------------------------------------------ validation helpers
def _choice(name, value, allowed):
    if value not in allowed:
        raise _v.KapitzaValueError(f"{name} must be one of {', '.join(map(repr, allowed))}; got {value!r}")
    return value


def _damping(c):
    c = _v.finite("c", c)
    if np.any(c < 0):
        raise _v.KapitzaValueError(f"c must be finite and >= 0 (0 <= c < inf); got {c[c < 0].flat[0]!r}")
    return c


def _tolerances(rtol, atol):
    rtol = _v.one("rtol", _v.in_range("rtol", rtol, 1e-13, 1.0, lo_open=False))
    atol = _v.one("atol", _v.positive("atol", atol))
    return rtol, atol


def _method(method, c, model="nonlinear"):
    if method is None:
        return "exact" if not np.any(c > 0) else "dop853"
    _choice("method", method, METHODS)
    if method == "exact" and np.any(c > 0):
        raise _v.KapitzaValueError(
            f"method='exact' solves the undamped motion only; got c = {float(np.max(c))!r} "
            "(use method='dop853' for damping)")
    return method


def _physical(T, A, l, g, eps=None, mu=None):
    T, A, l, g = _v.physical_parameters(T, A, l, g, eps, mu)
    _v.finite_rate(A, l, g)
    return T, A, l, g


def _times(t):
    t = _v.finite("t", t)
    if np.any(t < 0):
        raise _v.KapitzaValueError(f"t must be >= 0 (0 <= t < inf); got {t[t < 0].flat[0]!r}")
    return t


#: Drive periods a call may follow one by one (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_PERIODS = 1_000_000
#: Drive periods one trajectory may be followed through by the exact flows, phase by phase in
#: Python (about 0.2 ms a period: some 40 s; ``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_TRAJECTORY_PERIODS = 200_000
#: Largest scaled duration ``w_h T`` of one phase followed by the exact flows [rad].
MAX_SCALED_PHASE = 1e5
#: Samples a trajectory may hold (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_SAMPLES = 20_000_000
#: Largest ``(w_h + |dtheta0| + c) * duration`` [rad] handed to DOP853: about 20 steps per radian, so
#: a few million steps (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_DOP853_SWEEP = 1e5
#: Largest ``|dtheta| / (2 sqrt|s|)``: its square, the phase energy, must stay a double.
_SPEED_LIMIT = 1e150
#: Angles beyond this are reduced modulo ``2 pi`` exactly before the motion is followed.
_REDUCE_ABOVE = 1e3


def _peak(drive):
    """Largest ``|a| / A`` of a drive (1 for the square wave and the sine)."""
    return 1.0 if drive is None else float(drive.peak)


def _budget(t_end, T, A, l, g, c, method, peak=1.0, dtheta0=0.0):
    """Refuse spans whose work is not bounded: ``t_end / (2T)`` periods, and for DOP853 the
    angle ``(w_h + |dtheta0| + c) t_end`` it must resolve (large ``c`` makes the equation stiff)."""
    T, A, l, g, c = (np.asarray(v, float) for v in (T, A, l, g, c))
    if method == "exact":
        # the phase flows are Jacobi elliptic functions of the scaled time w T: beyond 1e5 rad in one
        # phase their argument reduction loses the digits of the motion (NaN by 1e150)
        with np.errstate(over="ignore"):
            wT = float(np.max(np.sqrt((g + peak * A) / l) * T))
        if not wT <= MAX_SCALED_PHASE:
            raise _v.KapitzaValueError(
                f"T, A and l must keep w_h T = T sqrt((g + A) / l) <= {MAX_SCALED_PHASE:g} rad for the exact phase "
                f"flows (one phase of the drive); got {wT:.4g}")
    limit = MAX_TRAJECTORY_PERIODS if method == "exact" else MAX_PERIODS
    with np.errstate(over="ignore"):  # a subnormal T: inf periods, refused below with its number
        periods = float(t_end / (2.0 * np.min(T)))
    _v.bounded_work("the duration t / (2 T)", periods, limit, what="drive periods, each followed phase by phase")
    if method == "dop853":
        w = float(np.max(np.sqrt((g + peak * A) / l))) + float(np.max(np.abs(dtheta0)))
        cmax = float(np.max(c))
        what = ("the damping makes the equation stiff: DOP853 needs about c * duration / 3 steps; use a "
                "shorter span or weaker damping" if cmax > w else "DOP853 takes about 20 steps per radian")
        _v.bounded_work("(w_h + |dtheta0| + c) * duration (w_h = sqrt((g + A) / l))", (w + cmax) * float(t_end), MAX_DOP853_SWEEP, what=what)


def _check_speed(dtheta, s_values, name="dtheta0"):
    """Refuse angular velocities whose phase energy overflows a double: ``|dtheta| / (2 sqrt|s|) <= 1e150``
    for every phase ``s = (g + a)/l != 0`` (the limit scales with ``sqrt|s|``)."""
    s = np.abs(np.asarray(s_values, float)).ravel()
    s = s[s > 0]
    if s.size == 0:
        return
    lim = 2.0 * _SPEED_LIMIT * float(np.sqrt(np.min(s)))
    big = np.abs(dtheta) > lim
    if np.any(big):
        v = np.asarray(dtheta)[big].flat[0]
        raise _v.KapitzaValueError(
            f"{name} must satisfy |{name}| <= {lim:.3g} rad/s here (2e150 sqrt|s|, s = (g + a)/l of the slowest "
            f"phase; beyond it the energy of the motion overflows a double); got {float(v)!r}")


def _reduce_angle(theta):
    """``theta = r + 2 pi k`` with ``|r| <= pi``, reduced exactly (in extended precision) where
    ``|theta| > 1e3``; returns ``(r, k)`` (``k`` is ``None`` when nothing was reduced).

    The motion depends on ``theta`` modulo ``2 pi`` only, but a double near ``1e15`` is spaced
    by ``0.125``: carrying the unwrapped angle from phase to phase would lose the digits that
    matter. The turns are added back to the result."""
    theta = np.asarray(theta, float)
    big = np.abs(theta) > _REDUCE_ABOVE
    if not big.any():
        return theta, None
    import mpmath

    r = theta.copy()
    k = np.zeros(theta.shape)
    with mpmath.workprec(1200):  # 2**1024 / (2 pi) to 53 bits after the point
        two_pi = 2 * mpmath.pi
        for i in np.flatnonzero(big.ravel()):
            x = mpmath.mpf(float(theta.flat[i]))
            n = mpmath.nint(x / two_pi)
            r.flat[i] = float(x - n * two_pi)
            k.flat[i] = float(n)
    return r, k


def _add_turns(theta, k):
    return theta if k is None else theta + TWO_PI * k


TWO_PI = 2.0 * np.pi


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


# ------------------------------------------------------------------ exact, piecewise
def _exact_motion(t, theta0, dtheta0, T, A, l, g):
    """Trusted input, broadcast together; undamped, closed-form phase maps."""
    full = np.broadcast_shapes(t.shape, theta0.shape, dtheta0.shape, T.shape, A.shape, l.shape, g.shape)
    traj = np.broadcast_shapes(theta0.shape, dtheta0.shape, T.shape, A.shape, l.shape, g.shape)
    th, om, Tp, Ap, lp, gp = (np.broadcast_to(a, traj).ravel() for a in (theta0, dtheta0, T, A, l, g))
    th, om = th.copy(), om.copy()
    s_h = (gp + Ap) / lp
    s_e = (gp - Ap) / lp
    ic = np.broadcast_to(np.arange(th.size).reshape(traj), full).ravel()
    tf = np.broadcast_to(t, full).ravel()
    j, r = _phase_index(tf, Tp[ic])
    order = np.argsort(j, kind="stable")
    js = j[order]
    last = int(js[-1]) if js.size else 0
    out_th = np.empty(tf.size)
    out_om = np.empty(tf.size)
    lo = 0
    for p in range(last + 1):
        hi = int(np.searchsorted(js, p, side="right"))
        s = s_h if p % 2 == 0 else s_e
        if hi > lo:
            sel = order[lo:hi]
            k = ic[sel]
            th1, om1 = _phase_step(th[k], om[k], s[k], r[sel])
            # At a switch itself the state is the boundary state, not a zero-length step of it.
            at = r[sel] == 0.0
            out_th[sel] = np.where(at, th[k], th1)
            out_om[sel] = np.where(at, om[k], om1)
            lo = hi
        if p < last:
            th, om = _phase_step(th, om, s, Tp)
    return out_th.reshape(full), out_om.reshape(full)


# ------------------------------------------------------------------ DOP853, piecewise
def _chunk_size(rtol):
    """Trajectories per solve_ivp call such that the solver's RMS error norm over the
    ``2n`` components bounds every component by ``rtol`` (it is ``sqrt(2n)`` looser),
    while keeping the tolerance handed to scipy above its floor of ``100 eps``."""
    n = int((rtol / (100.0 * _EPS)) ** 2 / 2.0)
    return max(1, min(256, n))


def _integrate(t, theta0, dtheta0, T, A, l, g, c, rtol, atol, linear=False):
    """DOP853 phase by phase. ``t``: sorted unique 1-D times >= 0; ``theta0``, ``dtheta0``:
    1-D; parameters scalars. Returns arrays ``(len(t), n)``."""
    n_all = theta0.size
    out_th = np.empty((t.size, n_all))
    out_om = np.empty((t.size, n_all))
    if t.size == 0:
        return out_th, out_om
    t_end = float(t[-1])
    n_phases = int(np.floor(t_end / T)) + 1
    chunk = _chunk_size(rtol)
    for a in range(0, n_all, chunk):
        b = min(a + chunk, n_all)
        n = b - a
        scale = 1.0 / np.sqrt(2.0 * n)
        y = np.concatenate([theta0[a:b], dtheta0[a:b]])
        for p in range(n_phases):
            t0 = p * T
            t1 = min((p + 1) * T, t_end) if p == n_phases - 1 else (p + 1) * T
            s = (g + A) / l if p % 2 == 0 else (g - A) / l
            lo = np.searchsorted(t, t0, side="left")
            hi = np.searchsorted(t, t1, side="right") if p == n_phases - 1 else np.searchsorted(t, t1, side="left")
            if linear:
                def rhs(_, z, s=s):
                    return np.concatenate([z[n:], s * z[:n] - c * z[n:]])
            else:
                def rhs(_, z, s=s):
                    return np.concatenate([z[n:], s * np.sin(z[:n]) - c * z[n:]])
            if t1 > t0:
                sol = _solve(rhs, t0, t1, y, rtol * scale, atol * scale, t_eval=t[lo:hi] if hi > lo else None)
                if hi > lo:
                    out_th[lo:hi, a:b] = sol.y[:n].T
                    out_om[lo:hi, a:b] = sol.y[n:].T
                y = sol.y[:, -1] if hi <= lo or sol.t[-1] == t1 else _last_state(rhs, t0, t1, y, rtol * scale, atol * scale)
            elif hi > lo:
                out_th[lo:hi, a:b] = y[:n]
                out_om[lo:hi, a:b] = y[n:]
    return out_th, out_om


def _last_state(rhs, t0, t1, y, rtol, atol):
    return _solve(rhs, t0, t1, y, rtol, atol).y[:, -1]


#: Below this ``max |y|`` the state is rescaled by a power of two before DOP853 sees it.
_TINY = 1e-100


def _solve(rhs, t0, t1, y, rtol, atol, t_eval=None):
    """DOP853 over ``[t0, t1]``; a failure raises.

    A damped motion decays without end; once every component is below ``1e-100``,
    ``sin(theta) = theta`` exactly in doubles, the equation is linear and homogeneous, and
    the state is scaled by a power of two (exact) to order one for the step: otherwise
    DOP853's error norm underflows (``0/0``) near ``|theta| ~ 1e-150`` and it stops with
    "step size less than spacing"."""
    from scipy.integrate import solve_ivp

    peak = float(np.max(np.abs(y))) if y.size else 0.0
    factor = 1.0
    if 0.0 < peak < _TINY:
        factor = float(2.0 ** -np.frexp(peak)[1])
    sol = solve_ivp(rhs, (t0, t1), y * factor, method="DOP853", rtol=rtol, atol=atol, t_eval=t_eval)
    if sol.status != 0:
        raise RuntimeError(f"DOP853 failed on [{t0:g}, {t1:g}] s: {sol.message}")
    if factor != 1.0:
        sol.y = sol.y / factor
    return sol


def _integrated_motion(t, theta0, dtheta0, T, A, l, g, c, rtol, atol, linear=False):
    """Any broadcastable ``t`` and initial states; scalar parameters."""
    for name, v in (("T", T), ("A", A), ("l", l), ("g", g), ("c", c)):
        if np.size(v) != 1:
            raise _v.KapitzaValueError(f"method='dop853' needs a single parameter set; got {name} of shape {np.shape(v)}")
    T, A, l, g, c = (float(np.asarray(v).flat[0]) for v in (T, A, l, g, c))
    full = np.broadcast_shapes(t.shape, theta0.shape, dtheta0.shape)
    traj = np.broadcast_shapes(theta0.shape, dtheta0.shape)
    th0 = np.broadcast_to(theta0, traj).ravel()
    om0 = np.broadcast_to(dtheta0, traj).ravel()
    tu, inv = np.unique(np.broadcast_to(t, full).ravel(), return_inverse=True)
    Y, W = _integrate(tu, th0, om0, T, A, l, g, c, rtol, atol, linear)
    ic = np.broadcast_to(np.arange(th0.size).reshape(traj), full).ravel()
    return Y[inv.ravel(), ic].reshape(full), W[inv.ravel(), ic].reshape(full)


@_v.shapes_named
def nonlinear_motion(t, theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, c=0.0, method=None,
                     rtol=1e-10, atol=1e-12):
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
    c : float, optional
        Linear damping coefficient [1/s], ``>= 0``.
    method : {None, 'exact', 'dop853'}
        ``'exact'``: closed-form phase maps (``c = 0`` only). ``'dop853'``: scipy's
        DOP853 restarted at every switch (scalar parameters only). ``None``:
        ``'exact'`` when ``c = 0``, else ``'dop853'``.
    rtol, atol : float, optional
        Tolerances of ``'dop853'``, met by every component: for an ensemble the
        solver's RMS norm is tightened by ``sqrt(2n)``. ``rtol >= 1e-13``.

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
    c = _damping(c)
    _v.shape_check(t=t, theta0=theta0, dtheta0=dtheta0, T=T, A=A, l=l, g=g)
    method = _method(method, c)
    if method == "exact":
        _check_speed(dtheta0, [(g + A) / l, (g - A) / l])
    _budget(float(np.max(t)), T, A, l, g, c, method, dtheta0=dtheta0)
    r, k = _reduce_angle(theta0)
    if method == "exact":
        th, om = _exact_motion(t, r, dtheta0, T, A, l, g)
    else:
        rtol, atol = _tolerances(rtol, atol)
        th, om = _integrated_motion(t, r, dtheta0, T, A, l, g, c, rtol, atol)
    return _v.scalars(np.asarray(_add_turns(th, k)), np.asarray(om))


@_v.shapes_named
def phase_energy(t, theta, dtheta, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None):
    """The energy of the current phase, ``theta'^2/2 + (g + a(t))/l cos(theta)`` [1/s^2].

    Parameters
    ----------
    t : array_like
        Times [s].
    theta, dtheta : array_like
        States at those times.
    T, A, l, g, eps, mu : array_like
        As in :func:`nonlinear_motion`. All arguments broadcast.

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
    s = (g + _acceleration(t, T, A)) / l
    return 0.5 * dtheta * dtheta + s * np.cos(theta)


# ------------------------------------------------------------------ other drives
def _drive_of(drive):
    """``None`` for the paper's square wave (its own code path), else the drive object."""
    from ..drives import as_drive

    d = as_drive(drive)
    return None if d.name == "square" else d


def _exact_motion_plan(t, theta0, dtheta0, plan):
    """Exact flows through the steps ``plan = ((s, duration), ...)`` of each period (scalar
    parameters; any ``t`` and initial states, broadcast)."""
    full = np.broadcast_shapes(t.shape, theta0.shape, dtheta0.shape)
    traj = np.broadcast_shapes(theta0.shape, dtheta0.shape)
    th = np.broadcast_to(theta0, traj).ravel().copy()
    om = np.broadcast_to(dtheta0, traj).ravel().copy()
    K = len(plan)
    dur = np.array([d for _, d in plan])
    starts = np.concatenate([[0.0], np.cumsum(dur)[:-1]])
    period = float(np.sum(dur))
    ic = np.broadcast_to(np.arange(th.size).reshape(traj), full).ravel()
    tf = np.broadcast_to(t, full).ravel()
    k = np.floor(tf / period)
    r = tf - k * period
    over = r >= period
    k = np.where(over, k + 1.0, k)
    r = np.where(over, r - period, np.maximum(r, 0.0))
    i = np.clip(np.searchsorted(starts, r, side="right") - 1, 0, K - 1)
    rr = r - starts[i]
    p_all = (k * K + i).astype(np.int64)
    order = np.argsort(p_all, kind="stable")
    ps = p_all[order]
    last = int(ps[-1]) if ps.size else 0
    out_th = np.empty(tf.size)
    out_om = np.empty(tf.size)
    lo = 0
    for p in range(last + 1):
        s, d = plan[p % K]
        hi = int(np.searchsorted(ps, p, side="right"))
        if hi > lo:
            sel = order[lo:hi]
            kk = ic[sel]
            th1, om1 = _phase_step(th[kk], om[kk], np.full(sel.size, s), rr[sel])
            at = rr[sel] == 0.0
            out_th[sel] = np.where(at, th[kk], th1)
            out_om[sel] = np.where(at, om[kk], om1)
            lo = hi
        if p < last:
            th, om = _phase_step(th, om, np.full(th.size, s), np.full(th.size, d))
    return out_th.reshape(full), out_om.reshape(full)


def _integrated_drive(t, theta0, dtheta0, T, A, l, g, c, rtol, atol, linear, drive):
    """DOP853 for any drive, restarted at every step of a piecewise-constant drive (or every
    half-period of a smooth one), never across a jump of the acceleration."""
    full = np.broadcast_shapes(t.shape, theta0.shape, dtheta0.shape)
    traj = np.broadcast_shapes(theta0.shape, dtheta0.shape)
    th0 = np.broadcast_to(theta0, traj).ravel()
    om0 = np.broadcast_to(dtheta0, traj).ravel()
    tu, inv = np.unique(np.broadcast_to(t, full).ravel(), return_inverse=True)
    n_all = th0.size
    Y = np.empty((tu.size, n_all))
    W = np.empty((tu.size, n_all))
    t_end = float(tu[-1]) if tu.size else 0.0
    if hasattr(drive, "levels"):
        marks = np.concatenate([[0.0], np.cumsum([2.0 * f * T for f in drive.fractions])])
    else:
        marks = np.array([0.0, T, 2.0 * T])
    period = 2.0 * T
    n_per = int(np.floor(t_end / period)) + 1
    bounds = np.unique(np.concatenate([k * period + marks for k in range(n_per)]))
    bounds = np.concatenate([bounds[bounds < t_end], [t_end]])
    chunk = _chunk_size(rtol)
    sin = (lambda z: z) if linear else np.sin
    for a in range(0, n_all, chunk):
        b = min(a + chunk, n_all)
        n = b - a
        scale = 1.0 / np.sqrt(2.0 * n)
        y = np.concatenate([th0[a:b], om0[a:b]])
        at0 = tu == 0.0
        Y[at0, a:b] = th0[a:b]
        W[at0, a:b] = om0[a:b]
        for t0, t1 in zip(bounds[:-1], bounds[1:]):
            if t1 <= t0:
                continue
            mid = 0.5 * (t0 + t1)
            if hasattr(drive, "levels"):
                s_c = (g + A * float(drive._shape(np.array([np.mod(mid / T, 2.0)]))[0])) / l

                def rhs(_, z, s_c=s_c):
                    return np.concatenate([z[n:], s_c * sin(z[:n]) - c * z[n:]])
            else:
                def rhs(tt, z):
                    s_t = (g + A * drive._shape(np.mod(tt / T, 2.0))) / l
                    return np.concatenate([z[n:], s_t * sin(z[:n]) - c * z[n:]])
            sel = np.flatnonzero((tu > t0) & (tu <= t1))
            sol = _solve(rhs, t0, t1, y, rtol * scale, atol * scale, t_eval=tu[sel] if sel.size else None)
            if sel.size:
                Y[sel, a:b] = sol.y[:n].T
                W[sel, a:b] = sol.y[n:].T
            y = sol.y[:, -1] if sel.size and sol.t[-1] == t1 else _last_state(rhs, t0, t1, y, rtol * scale, atol * scale)
    ic = np.broadcast_to(np.arange(n_all).reshape(traj), full).ravel()
    return Y[inv.ravel(), ic].reshape(full), W[inv.ravel(), ic].reshape(full)


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
    drive : Drive or None
        The pivot's motion (``None``: the paper's square wave).

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
    drive: object = None

    @property
    def pivot(self) -> np.ndarray:
        """Pivot height above its mean position [m] at ``t`` (:func:`pivot_displacement`)."""
        if self.drive is not None:
            return self.drive.displacement(self.t, self.T, self.A)
        return _displacement(self.t, self.T, self.A)

    @property
    def energy(self) -> np.ndarray:
        """:func:`phase_energy` along the samples (nonlinear model)."""
        a = self.drive.acceleration(self.t, self.T, self.A) if self.drive is not None else \
            _acceleration(self.t, self.T, self.A)
        s = (self.g + a) / self.l
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
        out = dict(growth_per_period=growth)
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
                ("final", f"theta = {num(s['final']['theta'], 10)} rad, dtheta = {num(s['final']['dtheta'], 10)} rad/s"),
                ("max |theta|", f"{num(s['max_abs_theta'])} rad"),
                ("upright", up)]
        if s["turns"]:
            rows.append(("turns", f"{s['turns']} whole turns at the end"))
        return rows


def _motion(model, method, t, theta0, dtheta0, T, A, l, g, c, rtol, atol, drive=None):
    if model == "nonlinear":
        r, k = _reduce_angle(theta0)
        if k is not None:
            th, om = _motion(model, method, t, r, dtheta0, T, A, l, g, c, rtol, atol, drive)
            return _add_turns(th, k), om
    if drive is not None:
        if model == "linear" and method == "exact":
            return linear_motion(t, theta0, dtheta0, T, A, l, g, drive=drive, damping=c)
        if method == "exact":
            return _exact_motion_plan(t, np.asarray(theta0, float), np.asarray(dtheta0, float),
                                      drive.phases(float(T), float(A), float(l), float(g)))
        return _integrated_drive(t, np.asarray(theta0, float), np.asarray(dtheta0, float), float(T), float(A),
                                 float(l), float(g), float(c), rtol, atol, model == "linear", drive)
    if model == "linear":
        if method == "exact":
            return linear_motion(t, theta0, dtheta0, T, A, l, g)
        return _integrated_motion(t, np.asarray(theta0, float), np.asarray(dtheta0, float),
                                  T, A, l, g, c, rtol, atol, linear=True)
    if method == "exact":
        return _exact_motion(t, *(np.asarray(v, float) for v in (theta0, dtheta0, T, A, l, g)))
    return _integrated_motion(t, np.asarray(theta0, float), np.asarray(dtheta0, float),
                              T, A, l, g, c, rtol, atol)


@_v.shapes_named
def simulate(theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=20.0,
             points_per_period=200, t=None, model="nonlinear", c=0.0, method=None, rtol=1e-10, atol=1e-12,
             drive=None) -> Trajectory:
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
        Duration in drive periods ``2T`` (ignored when ``t`` is given); > 0.
    points_per_period : int, optional
        Samples per period ``2T``, evenly spaced (>= 4).
    t : array_like, optional
        Explicit sample times ``>= 0``, increasing.
    model : {'nonlinear', 'linear'}
        The full equation, or its linearisation (2.3) (exact:
        :func:`kapitza.linear_motion`).
    c : float, optional
        Damping [1/s], ``>= 0`` (then ``method='dop853'``).
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
    c = _v.one("c", _damping(c))
    _choice("model", model, MODELS)
    drive = _drive_of(drive)
    if drive is not None and not hasattr(drive, "levels"):
        if method == "exact":
            raise _v.KapitzaValueError(f"method='exact' needs a piecewise-constant drive; got {drive.describe()} "
                                       "(use method='dop853')")
        method = "dop853" if method is None else method
    method = _method(method, c, model)
    rtol, atol = _tolerances(rtol, atol)
    if t is None:
        periods = _v.one("periods", _v.positive("periods", periods))
        ppp = _v.bounded_count("points_per_period", points_per_period, MAX_SAMPLES, minimum=4)
        _v.bounded_work("periods * points_per_period", np.ceil(periods * ppp), MAX_SAMPLES,
                        what="samples held in memory")
        n = int(np.ceil(periods * ppp))
        t = np.linspace(0.0, 2.0 * T * periods, n + 1)
    else:
        t = _times(t).ravel()
        _v.bounded_work("len(t)", t.size, MAX_SAMPLES, what="samples held in memory")
        if t.size and np.any(np.diff(t) < 0):
            raise _v.KapitzaValueError("t must be increasing")
    if model == "nonlinear" and method == "exact":
        _check_speed(dtheta0, [s_ for s_, _ in drive.phases(T, A, l, g)] if drive is not None else
                     [(g + A) / l, (g - A) / l])
    _budget(float(t[-1]) if t.size else 0.0, T, A, l, g, c, method, _peak(drive), dtheta0)
    th, om = _motion(model, method, t, theta0, dtheta0, T, A, l, g, c, rtol, atol, drive)
    return Trajectory(t=t, theta=np.asarray(th), dtheta=np.asarray(om), theta0=theta0, dtheta0=dtheta0,
                      T=T, A=A, l=l, g=g, c=c, model=model, method=method, rtol=rtol, atol=atol, drive=drive)
