"""The full (nonlinear) motion of the tower on its moving pivot, and its largest safe tilt.

The pivot moves vertically, ``z(t)`` with ``z'' = a(t)``. With the constant matrices of
:class:`kapitza.Chain` (``M``, diagonal ``K``, ``C``; ``docs/tower.md``) the Lagrangian is,
up to a total time derivative,

    L = 1/2 sum_{i,k} M_ik cos(theta_i - theta_k) theta_i' theta_k' - (g + a(t)) sum_i K_i cos theta_i

(the pivot's velocity enters the kinetic energy only through ``z' d/dt sum K_i cos theta_i``,
which is ``-a sum K_i cos theta_i`` plus a total derivative). With the joint friction
``R = c/2 sum (theta_i' - theta_{i-1}')^2`` Lagrange's equations are

    sum_k M_ik [cos(theta_i - theta_k) theta_k'' + sin(theta_i - theta_k) theta_k'^2]
        = (g + a(t)) K_i sin theta_i - (C theta')_i,

whose linearisation is ``M theta'' + C theta' = (g + a) K theta``. Where ``a`` is constant
(a segment of a piecewise-constant drive, or no drive)

    E = 1/2 theta'^T M(theta) theta' + (g + a) sum_i K_i cos theta_i,     dE/dt = -theta'^T C theta',

so ``E`` is conserved without friction: the check of the integration (``ChainMotion.energy``).
Integration: DOP853, restarted at every switch of a piecewise-constant drive (the acceleration
jumps there), in one span with a step of at most 1/64 period for a smooth drive.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _validate as _v
from .._display import Summary, num
from ..parameters import G_EARTH

__all__ = ["ChainMotion", "chain_motion", "SafeTilt", "tower_safe_tilt"]

#: at most this many drive periods in one motion (a bound on the work)
MAX_PERIODS = 100_000


@dataclass(frozen=True, repr=False)
class ChainMotion(Summary):
    """One motion of the tower.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times [s].
    theta, dtheta : ndarray, shape (N, n)
        Link angles from the upright [rad] and their rates [rad/s].
    pivot : ndarray, shape (n,)
        The pivot's height [m] (the drive's displacement).
    energy : ndarray, shape (n,)
        ``E = 1/2 theta'^T M(theta) theta' + (g + a(t)) sum K_i cos theta_i`` [J] with the
        acceleration of the segment in force (conserved within a segment without friction).
    acceleration : ndarray, shape (n,)
        The pivot's acceleration ``a`` each sample was taken under (at a switch: the segment it
        was integrated in).
    toppled : bool
        A link passed ``tol`` from the upright (the motion stops there when ``stop=True``).
    t_topple : float or None
    lengths : tuple
        Link lengths (for drawing).
    T, A, g : float
    drive : str

    Examples
    --------
    >>> import kapitza
    >>> tower = kapitza.Chain([0.2, 0.2, 0.2])
    >>> m = kapitza.chain_motion(tower, 0.05, T=0.0025, A=3200.0, periods=10, points_per_period=8)
    >>> m
    <ChainMotion: stands: every link within 1.571 rad for 0.05 s>
    >>> m.theta.shape, m.toppled
    ((3, 81), False)
    >>> x, y = m.joints()
    >>> x.shape
    (4, 81)
    """

    t: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    pivot: np.ndarray
    energy: np.ndarray
    acceleration: np.ndarray
    toppled: bool
    t_topple: float | None
    lengths: tuple
    T: float
    A: float
    g: float
    drive: str
    tol: float

    def joints(self):
        """``(x, y)``, each of shape ``(N + 1, n)``: the pivot and every link's upper end [m]."""
        L = np.array(self.lengths)[:, None]
        x = np.vstack([np.zeros(self.t.size), np.cumsum(L * np.sin(self.theta), axis=0)])
        y = np.vstack([np.zeros(self.t.size), np.cumsum(L * np.cos(self.theta), axis=0)]) + self.pivot
        return x, y

    def lines(self):
        end = f"toppled at t = {num(self.t_topple)} s (a link beyond {num(self.tol, 4)} rad)" if self.toppled else (
            f"stands: every link within {num(self.tol, 4)} rad for {num(self.t[-1])} s")
        return [("motion",
                 f"{self.theta.shape[0]}-link tower, T = {num(self.T)} s, A = {num(self.A)} m/s^2, {self.drive}"),
                ("outcome", end),
                ("largest tilt", f"{num(np.max(np.abs(self.theta)))} rad")]

    def headline(self):
        return self.lines()[1][1]


def _rhs_factory(chain, g):
    M = chain.mass_matrix()
    K = np.diag(chain.stiffness_matrix())
    C = chain.damping_matrix()
    n = chain.n

    def rhs(acc, y):
        th, om = y[:n], y[n:]
        d = th[:, None] - th[None, :]
        Mt = M * np.cos(d)
        f = (g + acc) * K * np.sin(th) - C @ om - (M * np.sin(d)) @ (om * om)
        return np.concatenate([om, np.linalg.solve(Mt, f)])

    def energy(acc, th, om):
        d = th[:, None, :] - th[None, :, :]
        Mt = M[:, :, None] * np.cos(d)
        kin = 0.5 * np.einsum("in,ikn,kn->n", om, Mt, om)
        return kin + (g + acc) * (K[:, None] * np.cos(th)).sum(axis=0)

    return rhs, energy


def _initial(chain, theta0, dtheta0):
    n = chain.n
    out = []
    for name, v in (("theta0", theta0), ("dtheta0", dtheta0)):
        a = _v.finite(name, v)
        a = np.atleast_1d(a).astype(float)
        if a.size == 1:
            a = np.full(n, float(a[0]))
        if a.shape != (n,):
            raise _v.KapitzaValueError(f"{name} must be one number or one per link ({n}); got {a.size} values")
        out.append(a)
    return out


def chain_motion(chain, theta0, dtheta0=0.0, *, T, A, g=G_EARTH, drive=None, periods=20.0, points_per_period=50,
                 tol=math.pi / 2, stop=True, rtol=1e-10, atol=1e-12) -> ChainMotion:
    """The tower's full motion from ``(theta0, dtheta0)`` on a pivot driven at ``(T, A)``.

    Parameters
    ----------
    chain : kapitza.Chain
    theta0, dtheta0 : float or array_like (N,)
        Initial link angles from the upright [rad] and rates [rad/s] (one number: every link).
    T, A : float
        Half-period [s] and acceleration scale [m/s^2] of the drive; ``A = 0`` is no drive.
    g : float
    drive : Drive or str, optional
        Square wave by default.
    periods : float
        Duration in drive periods ``2T``.
    points_per_period : int
        Samples per period (4 .. 10000).
    tol : float
        A link beyond ``tol`` from the upright has toppled (``0 < tol <= pi``).
    stop : bool
        Stop when it topples.
    rtol, atol : float
        DOP853 tolerances.

    Returns
    -------
    ChainMotion

    Raises
    ------
    ValueError
        If a value is out of range (``theta0`` or ``dtheta0`` of the wrong length, a count or
        tolerance outside its bounds), or ``drive`` names no drive.

    Examples
    --------
    >>> import kapitza
    >>> tower = kapitza.Chain([0.2, 0.2, 0.2])
    >>> kapitza.chain_motion(tower, 0.05, T=0.0025, A=3200.0, periods=10, points_per_period=8)
    <ChainMotion: stands: every link within 1.571 rad for 0.05 s>
    >>> kapitza.chain_motion(tower, 0.05, T=0.0025, A=0.0, periods=200, points_per_period=4)
    <ChainMotion: toppled at t = 0.4515... s (a link beyond 1.571 rad)>
    """
    from scipy.integrate import solve_ivp

    from ..drives import as_drive

    from ..chain import Chain, scale_check

    if not isinstance(chain, Chain):
        raise _v.KapitzaValueError(f"chain must be a kapitza.Chain; got {chain!r}")
    d = as_drive(drive)
    rtol = _v.one("rtol", _v.in_range("rtol", rtol, 1e-14, 1e-3, lo_open=False, hi_open=False))
    atol = _v.one("atol", _v.in_range("atol", atol, 1e-20, 1.0, lo_open=False, hi_open=False))
    T = _v.one("T", _v.in_range("T", T, 1e-9, 1e6, lo_open=False, hi_open=False))
    A = _v.one("A", _v.nonnegative("A", A))
    g = _v.one("g", _v.positive("g", g))
    periods = _v.one("periods", _v.in_range("periods", periods, 1e-3, MAX_PERIODS, lo_open=False, hi_open=False))
    scale_check(chain, T, A, g, d)
    ppp = _v.bounded_count("points_per_period", points_per_period, 10_000, minimum=4)
    tol = _v.one("tol", _v.in_range("tol", tol, 0.0, math.pi, hi_open=False))
    th0, om0 = _initial(chain, theta0, dtheta0)
    if np.max(np.abs(om0)) > 1e6:
        raise _v.KapitzaValueError(f"dtheta0 must lie within +-1e6 rad/s; got {om0.tolist()!r}")
    rhs, energy = _rhs_factory(chain, g)
    t_end = 2.0 * T * periods
    n_samples = int(round(periods * ppp)) + 1
    t_all = np.linspace(0.0, t_end, n_samples)
    levels = getattr(d, "levels", None)
    fractions: Any = getattr(d, "fractions", None)
    if A == 0.0:
        pieces = [(0.0, t_end, 0.0)]
    elif levels is not None:
        # the switching instants over the whole run: the acceleration is constant between them
        starts = np.concatenate([[0.0], np.cumsum(fractions)[:-1]]) * 2.0 * T
        begin, accel = [], []
        k = 0
        while k * 2.0 * T < t_end:
            for s0, lev in zip(starts, levels):
                if k * 2.0 * T + s0 < t_end:
                    begin.append(k * 2.0 * T + s0)
                    accel.append(A * float(lev))
            k += 1
        # each segment ends exactly where the next begins: no sample falls in two of them
        ends = begin[1:] + [t_end]
        pieces = list(zip(begin, ends, accel))
    else:
        pieces = None

    def topple(t, y):
        return tol - np.max(np.abs(y[: chain.n]))

    topple.terminal = bool(stop)  # type: ignore[attr-defined]
    topple.direction = -1  # type: ignore[attr-defined]
    y = np.concatenate([th0, om0])
    ts: Any
    ys: Any
    accs: Any  # lists of the pieces, then their concatenation
    ts, ys, accs = [], [], []
    t_top = None
    if np.max(np.abs(th0)) >= tol:  # beyond the window from the start: fallen already
        pieces, t_top = [], 0.0
        ts, ys, accs = [np.zeros(1)], [y[:, None]], [np.zeros(1)]
    if t_top == 0.0:
        pass
    elif pieces is None:
        def f(t, y):
            return rhs(A * float(d._shape(np.array(np.mod(t / T, 2.0)))), y)

        sol = solve_ivp(f, (0.0, t_end), y, method="DOP853", rtol=rtol, atol=atol, t_eval=t_all, events=topple,
                        max_step=2.0 * T / 64)
        ts, ys = sol.t, sol.y
        accs = A * d._shape(np.mod(ts / T, 2.0))
        if sol.t_events[0].size:
            t_top = float(sol.t_events[0][0])
    else:
        for a0, a1, acc in pieces:
            last = a1 >= t_end
            inside = t_all[(t_all >= a0) & ((t_all < a1) | last)]
            # the end of the segment is asked for too (the next segment starts from it); kept
            # as a sample only at the end of the run, where it is one of the sample times
            sol = solve_ivp(lambda t, y, acc=acc: rhs(acc, y), (a0, a1), y, method="DOP853", rtol=rtol, atol=atol,
                            t_eval=np.append(inside[inside < a1], a1), events=topple)
            done = sol.status == 1  # the event stopped it
            st = np.asarray(sol.t, float)
            sy = np.asarray(sol.y, float).reshape(2 * chain.n, st.size)  # (a list when stopped before any sample)
            keep = st.size if (done or (last and inside.size and inside[-1] >= a1)) else st.size - 1
            ts.append(st[:keep])
            ys.append(sy[:, :keep])
            accs.append(np.full(keep, acc))
            if sol.t_events[0].size and t_top is None:
                t_top = float(sol.t_events[0][0])
            if done:
                break
            y = sy[:, -1]
    if pieces is not None or t_top == 0.0:
        ts = np.concatenate(ts)
        ys = np.concatenate(ys, axis=1) if ys else np.zeros((2 * chain.n, 0))
        accs = np.concatenate(accs)
    n = chain.n
    th, om = ys[:n], ys[n:]
    if A > 0:
        pivot = np.asarray(d.displacement(ts, T, A), float) if ts.size else np.zeros(0)
    else:
        pivot = np.zeros(ts.size)
    return ChainMotion(t=ts, theta=th, dtheta=om, pivot=pivot, energy=energy(accs, th, om) if ts.size else ts,
                       acceleration=np.asarray(accs, float),
                       toppled=t_top is not None, t_topple=t_top, lengths=chain.lengths, T=T, A=A, g=g,
                       drive=d.describe(), tol=tol)



@dataclass(frozen=True, repr=False)
class SafeTilt(Summary):
    """The largest tilts from rest that the tower survives for ``periods`` drive periods.

    Attributes
    ----------
    together : float
        Every link tilted by the same angle [rad] (the tower leaning as one rigid body).
    mode : float
        Tilted along the longest mode's shape, its most tilted link by this angle [rad].
    shape : tuple
        That mode shape, scaled to a largest ``|theta_j|`` of 1.
    periods, tol, accuracy : float
        The test: every link within ``tol`` of the upright for ``periods`` periods ``2T``; a
        value ``v`` survives and ``v + accuracy`` does not (0: not even ``accuracy``; ``tol``:
        capped, the tilt ``tol`` itself survives).

    Examples
    --------
    >>> import kapitza
    >>> tilt = kapitza.tower_safe_tilt(kapitza.Chain([0.2, 0.2, 0.2]), T=0.0025, A=3200.0, periods=3, accuracy=0.1)
    >>> tilt
    <SafeTilt: safe tilt 1.178 rad together, 1.473 rad along mode 1>
    >>> round(tilt.together, 2), round(tilt.mode, 2)
    (1.18, 1.47)
    """

    together: float
    mode: float
    shape: tuple
    periods: float
    tol: float
    accuracy: float
    T: float
    A: float

    def lines(self):
        return [("safe tilt",
                 f"{num(self.together, 4)} rad ({num(math.degrees(self.together), 3)} deg), all links together"),
                ("", f"{num(self.mode, 4)} rad ({num(math.degrees(self.mode), 3)} deg) along mode 1, shape "
                     "(" + ", ".join(f"{x:+.3f}" for x in self.shape) + ")"),
                ("test", f"every link within {num(self.tol, 4)} rad for {num(self.periods)} periods 2T; "
                         f"to {num(self.accuracy, 2)} rad")]

    def headline(self):
        return f"safe tilt {num(self.together, 4)} rad together, {num(self.mode, 4)} rad along mode 1"


def tower_safe_tilt(chain, *, T, A, g=G_EARTH, drive=None, periods=50.0, tol=math.pi / 2, accuracy=1e-3,
                    rtol=1e-9, atol=1e-11) -> SafeTilt:
    """The largest starting tilt at rest that the tower survives, all links together and along
    the longest mode's shape (the tower's counterpart of the single pendulum's safe tilt).

    Bisection on the tilt in ``(0, tol]``: each trial is a :func:`chain_motion` stopped when a
    link passes ``tol``; where the safe starts do not form one segment from the upright the
    value is the edge of the first one met by the bisection.

    Parameters
    ----------
    chain : kapitza.Chain
    T, A : float
        Half-period [s] and acceleration scale [m/s^2] of the drive.
    g : float
        Gravity [m/s^2].
    drive : Drive or str, optional
        Square wave by default.
    periods : float
        How long the tower must stand, in drive periods ``2T``.
    tol : float
        A link beyond ``tol`` from the upright has fallen (``0 < tol <= pi``).
    accuracy : float
        The bisection stops when the bracket is this narrow [rad].
    rtol, atol : float
        DOP853 tolerances of each trial motion.

    Returns
    -------
    SafeTilt

    Raises
    ------
    ValueError
        If a value is out of range, or ``drive`` names no drive.

    Examples
    --------
    >>> import kapitza
    >>> tilt = kapitza.tower_safe_tilt(kapitza.Chain([0.2, 0.2, 0.2]), T=0.0025, A=3200.0, periods=3, accuracy=0.1)
    >>> round(tilt.together, 2)
    1.18
    """
    from ..chain import Chain

    if not isinstance(chain, Chain):
        raise _v.KapitzaValueError(f"chain must be a kapitza.Chain; got {chain!r}")
    accuracy = _v.one("accuracy", _v.in_range("accuracy", accuracy, 0.0, 1.0))
    periods = _v.one("periods", _v.positive("periods", periods))
    tol = _v.one("tol", _v.in_range("tol", tol, 0.0, math.pi, hi_open=False))
    T = _v.one("T", _v.positive("T", T))
    A = _v.one("A", _v.positive("A", A))
    V = chain.mode_shapes[:, 0]
    v1 = V / np.max(np.abs(V))

    def survives(direction, t):
        m = chain_motion(chain, t * direction, 0.0, T=T, A=A, g=g, drive=drive, periods=periods, points_per_period=4,
                         tol=tol, rtol=rtol, atol=atol)
        return not m.toppled

    out = []
    for direction in (np.ones(chain.n), v1):
        if survives(direction, tol):
            out.append(tol)
            continue
        lo, hi = 0.0, tol
        while hi - lo > accuracy:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if survives(direction, mid) else (lo, mid)
        out.append(lo)
    return SafeTilt(together=float(out[0]), mode=float(out[1]), shape=tuple(float(x) for x in v1),
                    periods=float(periods), tol=float(tol), accuracy=float(accuracy), T=float(T), A=float(A))
