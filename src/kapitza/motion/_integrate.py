"""What the motion functions share (:mod:`~kapitza.motion.nonlinear`, :mod:`~kapitza.motion.strobe`,
:mod:`~kapitza.motion.basins` and the sweep): the checks of their arguments, the bounds on their work,
the exact reduction of large angles, and DOP853 restarted at every switch of the drive (trusted input)."""
from __future__ import annotations

import functools

import numpy as np

from .. import _validate as _v

#: ``exact``: closed-form phase maps (undamped only); ``dop853``: solve_ivp, phase by phase.
METHODS = ("exact", "dop853")

_EPS = np.finfo(float).eps


# ------------------------------------------------------------------ validation helpers
def _choice(name, value, allowed):
    if value not in allowed:
        raise _v.KapitzaValueError(f"{name} must be one of {', '.join(map(repr, allowed))}; got {value!r}")
    return value


def _damping(damping, zeta, l, g):
    """The damping coefficient ``c`` [1/s] of the motion, given as ``damping`` (``c``) or as ``zeta``
    (the ratio ``c / (2 sqrt(g/l))``), not both: :func:`kapitza._validate.damping`."""
    return _v.damping(damping, zeta, l, g)[0]


def _one_damping(damping, zeta, l, g):
    """:func:`_damping` of a motion that takes one coefficient: a single number, refused by the name
    it was given as."""
    return float(_v.one("zeta" if zeta is not None else "damping", _damping(damping, zeta, l, g)))


def _tolerances(rtol, atol):
    rtol = _v.one("rtol", _v.in_range("rtol", rtol, 1e-13, 1.0, lo_open=False))
    atol = _v.one("atol", _v.positive("atol", atol))
    return rtol, atol


def _method(method, c, drive):
    """The method asked for, or the default: ``'exact'`` (step by step in closed form) for an undamped
    piecewise-constant drive, else ``'dop853'``."""
    stepped = drive._steps() is not None
    if method is None:
        return "exact" if stepped and not np.any(c > 0) else "dop853"
    _choice("method", method, METHODS)
    if method == "exact" and not stepped:
        raise _v.KapitzaValueError(f"method='exact' needs a piecewise-constant drive; got {drive.describe()} "
                                   "(use method='dop853')")
    if method == "exact" and np.any(c > 0):
        raise _v.KapitzaValueError(
            f"method='exact' solves the undamped motion only; got c = {float(np.max(c))!r} "
            "(use method='dop853' for damping)")
    return method


def _single_set(**values):
    """The parameters as floats, for DOP853, which follows one parameter set at a time."""
    for name, v in values.items():
        if np.size(v) != 1:
            raise _v.KapitzaValueError(f"method='dop853' needs a single parameter set; got {name} of shape "
                                       f"{np.shape(v)}")
    return tuple(float(np.asarray(v).flat[0]) for v in values.values())


def _physical(T, A, l, g, eps=None, mu=None):
    T, A, l, g = _v.physical_parameters(T, A, l, g, eps, mu)
    _v.finite_rate(A, l, g)
    return T, A, l, g


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
    return float(drive.peak)


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
        _v.bounded_work("(w_h + |dtheta0| + c) * duration (w_h = sqrt((g + A) / l))", (w + cmax) * float(t_end),
                        MAX_DOP853_SWEEP, what=what)


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


# ------------------------------------------------------------------ DOP853, piecewise
def _chunk_size(rtol):
    """Trajectories per solve_ivp call such that the solver's RMS error norm over the
    ``2n`` components bounds every component by ``rtol`` (it is ``sqrt(2n)`` looser),
    while keeping the tolerance handed to scipy above its floor of ``100 eps``."""
    n = int((rtol / (100.0 * _EPS)) ** 2 / 2.0)
    return max(1, min(256, n))


def _last_state(rhs, t0, t1, y, rtol, atol):
    return _solve(rhs, t0, t1, y, rtol, atol).y[:, -1]


#: Below this ``max |y|`` the state is rescaled by a power of two before DOP853 sees it.
_TINY = 1e-100


def _identity(z):
    return z


def _solve(rhs, t0, t1, y, rtol, atol, t_eval=None):
    """DOP853 over ``[t0, t1]`` of ``y' = rhs(t, y, f)``, ``f`` the sine of the angles (the identity
    for the linear model); a failure raises.

    A damped motion decays without end; once every component is below ``1e-100``,
    ``sin(theta) = theta`` exactly in doubles, the equation is linear and homogeneous, and
    the state is scaled by a power of two (exact) to order one for the step, with ``f`` the
    identity (the same equation there): otherwise DOP853's error norm underflows (``0/0``) near
    ``|theta| ~ 1e-150`` and it stops with "step size less than spacing"."""
    from scipy.integrate import solve_ivp

    peak = float(np.max(np.abs(y))) if y.size else 0.0
    factor = 1.0
    fun = rhs
    if 0.0 < peak < _TINY:
        factor = float(2.0 ** -np.frexp(peak)[1])
        fun = functools.partial(rhs, f=_identity)
    sol = solve_ivp(fun, (t0, t1), y * factor, method="DOP853", rtol=rtol, atol=atol, t_eval=t_eval)
    if sol.status != 0:
        raise RuntimeError(f"DOP853 failed on [{t0:g}, {t1:g}] s: {sol.message}")
    if factor != 1.0:
        sol.y = sol.y / factor
    return sol


# ------------------------------------------------------------------ other drives
def _drive_of(drive):
    """The drive object (the paper's square wave for ``None``)."""
    from ..drives import as_drive

    return as_drive(drive)


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
    steps = drive._steps()
    if steps is not None:
        marks = np.concatenate([[0.0], np.cumsum([2.0 * f * T for f in steps[1]])])
    else:
        marks = np.array([0.0, T, 2.0 * T])
    period = 2.0 * T
    n_per = int(np.floor(t_end / period)) + 1
    bounds = np.unique(np.concatenate([k * period + marks for k in range(n_per)]))
    bounds = np.concatenate([bounds[bounds < t_end], [t_end]])
    chunk = _chunk_size(rtol)
    sin = _identity if linear else np.sin
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
            if steps is not None:  # constant on the step: its level at the step's middle
                s_c = (g + A * float(drive._shape(np.array([np.mod(mid / T, 2.0)]))[0])) / l

                def rhs(_, z, s_c=s_c, f=sin):
                    return np.concatenate([z[n:], s_c * f(z[:n]) - c * z[n:]])
            else:
                def rhs(tt, z, f=sin):  # type: ignore[misc]  # (the other branch binds its constant)
                    s_t = (g + A * drive._shape(np.mod(tt / T, 2.0))) / l
                    return np.concatenate([z[n:], s_t * f(z[:n]) - c * z[n:]])
            sel = np.flatnonzero((tu > t0) & (tu <= t1))
            sol = _solve(rhs, t0, t1, y, rtol * scale, atol * scale, t_eval=tu[sel] if sel.size else None)
            if sel.size:
                Y[sel, a:b] = sol.y[:n].T
                W[sel, a:b] = sol.y[n:].T
            y = sol.y[:, -1] if sel.size and sol.t[-1] == t1 else \
                _last_state(rhs, t0, t1, y, rtol * scale, atol * scale)
    ic = np.broadcast_to(np.arange(n_all).reshape(traj), full).ravel()
    return Y[inv.ravel(), ic].reshape(full), W[inv.ravel(), ic].reshape(full)
