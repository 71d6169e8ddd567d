"""The safe tilt: how far from the upright the real pendulum may start and still stand.

The linear verdict (``stable (zone n)``) is a statement about small tilts. How small is
answered by the **safe tilt** ``theta*``: the largest starting tilt from rest
(``theta(0) = theta0``, ``theta'(0) = 0``, at the start of the period) whose nonlinear motion
stays above the horizontal (``|theta(t)| <= tol``, ``tol = pi/2`` by default: the test of
``Trajectory.summary()['stays_up']``) on the whole of ``[0, 2NT]``. It is the sweep's
``max_safe_tilt`` (:mod:`kapitza.sweeps.kernel`, the same one-period steps and window test),
found by a search that follows many starts at once: ``K`` starts spaced geometrically from
``floor`` to ``tol``, then ``K`` evenly spaced between the largest survivor and the failing start
above it, and so on until that bracket is narrower than ``accuracy`` of its lower end, which is
reported (a start seen to stay; one ``accuracy`` above it falls). Where the safe starts form
one segment ``[0, theta*)`` this is the sweep's value to ``accuracy``; a few DOP853 runs over
many states cost little more than one, so the sine drive and damping answer in about a second.
A start below ``floor`` is not tried and 0 is reported. An undamped piecewise-constant drive is followed
exactly (the window checked on the continuous motion); the sine drive or damping by DOP853.

Where the upright is linearly unstable the safe tilt is 0 by definition (no start but the
upright itself stays for ever; a short ``N`` may still let a small start survive, which is
not what a verdict means), and the search is skipped.
"""
from __future__ import annotations

import math

import numpy as np

from . import _validate as _v
from .parameters import G_EARTH

__all__ = ["safe_tilt", "safe_tilt_sentence", "with_safe_tilt", "SAFE_TILT_PERIODS", "SAFE_TILT_TOL"]

#: Periods ``2T`` a start must survive, by default.
SAFE_TILT_PERIODS = 50
#: The window: above the horizontal.
SAFE_TILT_TOL = float(np.pi / 2)


def _extreme_mu(mu):
    """Whether some ``mu`` lies beyond ``1e+-50``, where the pivot's acceleration and the rod's rate at
    ``g = 9.81``, ``l = 1`` would differ by a hundred orders of magnitude (beyond DOP853's error norm):
    such a point's motion is integrated on a scale of its own."""
    mu = np.asarray(mu, float)
    return not np.all((mu > 1e-50) & (mu < 1e50))


def safe_tilt(eps=None, mu=None, *, T=None, A=None, l=1.0, g=G_EARTH, drive=None, damping=0.0, zeta=None,
              periods=SAFE_TILT_PERIODS, tol=SAFE_TILT_TOL, accuracy=0.01, floor=1e-9, linear_check=True):
    """Largest starting tilt from rest [rad] that stays within ``tol`` for ``periods`` periods.

    Parameters
    ----------
    eps, mu : float or array_like
        Arnold's parameters (or give ``T`` and ``A`` with ``l`` and ``g``).
    T, A, l, g : float or array_like
        Half-period [s], acceleration scale [m/s^2], equivalent length [m], gravity [m/s^2].
    drive : Drive or str, optional
        The pivot's motion; the paper's square wave by default.
    damping : float
        Viscous damping ``c`` [1/s] (with ``T, A``).
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))`` (with ``eps, mu``).
    periods : int
        ``N``: the start must stay for ``[0, 2NT]``.
    tol : float
        The window [rad], ``0 < tol < pi`` (default ``pi/2``: above the horizontal).
    accuracy : float
        Relative accuracy of the answer (a start that much above it falls).
    floor : float
        Smallest start tried [rad]; below it 0 is reported.
    linear_check : bool
        Report 0 without searching where the upright is linearly unstable (default).

    Returns
    -------
    float or ndarray
        ``theta*`` [rad] (numpy scalar for scalar input), ``tol`` when ``tol`` itself survives.

    Raises
    ------
    ValueError
        If neither or both of ``(eps, mu)`` and ``(T, A)`` are given, a value is out of range
        (``tol`` outside ``(0, pi)``, ``periods`` beyond its bound), or ``drive`` names no drive.

    Examples
    --------
    Zone 0 has a wide core; zone 2 is stable too, but only for tiny tilts; outside the zones
    nothing is safe:

    >>> from kapitza import safe_tilt
    >>> round(float(safe_tilt(0.5, 0.3)), 2)
    0.23
    >>> safe_tilt(2.9442806, 0.3)
    np.float64(3.7...e-06)
    >>> safe_tilt(1.2, 0.3)
    np.float64(0.0)
    """
    from .drives import as_drive, parse_drive
    from .parameters import to_arnold, to_physical

    periods = _v.bounded_count("periods", periods, 100_000, minimum=1)
    tol = _v.one("tol", _v.in_range("tol", tol, 0.0, np.pi))
    accuracy = _v.one("accuracy", _v.in_range("accuracy", accuracy, 1e-6, 1.0, lo_open=False))
    floor = _v.floor_below(floor, tol)
    d = parse_drive(drive) if isinstance(drive, str) else as_drive(drive)
    arnold = _v.parameter_set(eps, mu, T, A) == "arnold"
    if arnold:
        if np.any(_v.nonnegative("damping", damping) != 0):
            raise _v.KapitzaValueError("with eps and mu give the damping as zeta = c / (2 sqrt(g/l)), not damping")
        e, m = _v.broadcast(eps=_v.positive("eps", eps), mu=_v.positive("mu", mu))
        z = _v.one("zeta", _v.nonnegative("zeta", 0.0 if zeta is None else zeta))
        l_, g_ = 1.0, G_EARTH
        mc = m
        if np.size(m) == 1 and _extreme_mu(m) and 1e-100 < float(np.ravel(e)[0]) < 1e100:
            # an extreme mu: g = mu and l = 1 / mu (A = l) keep the scales together. The motion is
            # integrated at mu clamped to 1e+-150 (mu^2 is lost beside the shape already at 1e-9); the
            # verdict below is the point's own
            mc = np.full(np.shape(m), min(max(float(np.ravel(m)[0]), 1e-150), 1e150))
            l_, g_ = 1.0 / float(np.ravel(mc)[0]), float(np.ravel(mc)[0])
        Tv, Av = to_physical(e, mc, l_, g_)
        c = 2.0 * z * np.sqrt(g_ / l_)
    else:
        if zeta is not None and np.any(_v.nonnegative("zeta", zeta) != 0):
            raise _v.KapitzaValueError("with T and A give the damping as damping = c [1/s], not zeta")
        Tv, Av, l_, g_ = _v.broadcast(T=_v.positive("T", T), A=_v.positive("A", A), l=_v.positive("l", l),
                                       g=_v.positive("g", g))
        if np.ndim(l) or np.ndim(g):
            # one length and gravity per point: scale to Arnold's parameters (the answer depends on nothing else)
            e, m = to_arnold(Tv, Av, l_, g_)
            if _extreme_mu(m):
                # an extreme mu has no common scale with the others (see the scalar case): point by point
                flat = [np.ravel(v) for v in (Tv, Av, l_, g_)]
                out = np.array([safe_tilt(T=float(t), A=float(a), l=float(ll), g=float(gg), drive=d, damping=damping,
                                          periods=periods, tol=tol, accuracy=accuracy, floor=floor,
                                          linear_check=linear_check) for t, a, ll, gg in zip(*flat)], float)
                return out.reshape(np.shape(Tv))
            c0 = _v.one("damping", _v.nonnegative("damping", damping))
            if c0 > 0:
                with np.errstate(over="ignore"):   # (l / g beyond a double where g is subnormal)
                    z = 0.5 * c0 * np.sqrt(l_ / g_)
                if not np.all(np.isfinite(z)):
                    raise _v.KapitzaValueError(f"damping c / (2 sqrt(g/l)) must be finite; got damping={c0!r} "
                                               f"with the smallest g/l {float(np.min(g_ / l_))!r}")
                if np.ndim(z) and np.ptp(z) > 0:
                    raise _v.KapitzaValueError("damping with arrays of l or g: give the points as eps, mu and zeta")
                z = float(np.ravel(z)[0]) if np.size(z) else 0.0
            else:
                z = 0.0
            l_, g_ = 1.0, G_EARTH
            Tv, Av = to_physical(e, m, l_, g_)
            c = 2.0 * z * np.sqrt(g_ / l_)
        else:
            l_, g_ = _v.one("l", _v.positive("l", l)), _v.one("g", _v.positive("g", g))
            c = _v.one("damping", _v.nonnegative("damping", damping))
            e, m = to_arnold(Tv, Av, l_, g_)
    shape = np.shape(Tv)
    Tf, Af = np.asarray(Tv, float).ravel(), np.asarray(Av, float).ravel()
    out = np.zeros(Tf.size)
    todo = np.ones(Tf.size, dtype=bool)
    if linear_check:
        from .zones import is_stable

        with np.errstate(over="ignore"):   # (l / g beyond a double where g is subnormal)
            zz = 0.5 * c * np.sqrt(l_ / g_) if c > 0 else 0.0
        if not np.isfinite(zz):
            raise _v.KapitzaValueError(f"damping c / (2 sqrt(g/l)) must be finite; got damping={c!r}, g={g_!r}, "
                                       f"l={l_!r}")
        todo = np.asarray(is_stable(np.ravel(e), np.ravel(m), drive=d, zeta=float(zz)), bool).ravel()
    if todo.any():
        out[todo] = _search(Tf[todo], Af[todo], l_, g_, float(c), d, periods, tol, accuracy, floor)
    out = out.reshape(shape)
    return out[()] if out.ndim == 0 else out


def with_safe_tilt(report, drive=None, periods=None):
    """``report`` (a :class:`kapitza.StabilityReport`) with its ``safe_tilt`` filled in: the safe tilt
    of its ``(eps, mu)``, damping ratio and ``drive`` over ``periods`` (default
    :data:`SAFE_TILT_PERIODS`); 0 where the upright is not stable.

    Parameters
    ----------
    report : StabilityReport
    drive : Drive or str, optional
        The pivot's motion; the paper's square wave by default.
    periods : int, optional
        How long a start must stand, in drive periods ``2T``.

    Returns
    -------
    StabilityReport

    Raises
    ------
    ValueError
        If ``periods`` is out of range or ``drive`` names no drive.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.safety import with_safe_tilt
    >>> report = with_safe_tilt(kapitza.analyze(eps=0.5, mu=0.3), periods=3)
    >>> report.safe_tilt, report.safe_tilt_periods
    (0.2575..., 3)
    """
    from dataclasses import replace

    periods = SAFE_TILT_PERIODS if periods is None else periods
    theta = safe_tilt(report.eps, report.mu, drive=drive, zeta=report.zeta, periods=periods) if report.stable else 0.0
    return replace(report, safe_tilt=float(theta), safe_tilt_periods=int(periods))


#: Starts followed together in each round of the search.
_K = 24


def _search(T, A, l, g, c, drive, periods, tol, accuracy, floor):
    """The safe tilt of each point ``(T[i], A[i])`` (validated, linearly stable ones)."""
    from .motion.basins import survival_chunk
    from .sweeps.kernel import period_step

    P = T.size
    step = period_step(T, A, l, g, c, drive, tol)
    lo = np.zeros(P)                       # the largest start seen to stay (0: none yet)
    hi = np.full(P, np.nan)                # the smallest failing start above it
    grid = np.geomspace(floor, tol, _K)    # round 1: floor .. tol, geometric
    cand = np.tile(grid, (P, 1))
    cand[:, -1] = tol
    active = np.ones(P, dtype=bool)
    for _ in range(64):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        starts = cand[idx]
        ok = survival_chunk(starts.ravel(), np.zeros(starts.size), _Subset(step, idx), periods, tol,
                             idx=np.repeat(np.arange(idx.size), _K)).reshape(idx.size, _K) >= periods
        for j, p in enumerate(idx):
            good = np.flatnonzero(ok[j])
            if good.size == 0:   # every start of this round fell: the bracket's lower end stands
                hi[p] = starts[j, 0]
                if lo[p] == 0:   # nothing from floor up stays
                    active[p] = False
                    continue
            else:
                k = good[-1]
                lo[p] = starts[j, k]
                if k + 1 < _K:
                    hi[p] = starts[j, k + 1]
                elif np.isnan(hi[p]):  # tol itself stays
                    active[p] = False
                    continue
            if hi[p] - lo[p] <= accuracy * lo[p]:
                active[p] = False
                continue
            cand[p] = lo[p] + (hi[p] - lo[p]) * np.arange(1, _K + 1) / (_K + 1)
    return lo


class _Subset:
    """A block's one-period step restricted to some of its points (``idx`` local to them)."""

    def __init__(self, step, points):
        self.step, self.points = step, points

    def __call__(self, th, om, idx):
        return self.step(th, om, self.points[idx])


def safe_tilt_sentence(theta, periods, stable) -> str:
    """The safe tilt ``theta`` [rad] over ``periods`` periods in words, as the report gives it
    (``stable``: the linear verdict; an unstable upright has none).

    Parameters
    ----------
    theta : float
        The safe tilt [rad].
    periods : int
        Periods ``2T`` it was tested over.
    stable : bool
        The linear verdict.

    Returns
    -------
    str

    Examples
    --------
    >>> from kapitza.safety import safe_tilt_sentence
    >>> safe_tilt_sentence(0.4, 50, True)
    'stands for starting tilts from rest below 0.4 rad (22.9 deg) over 50 periods; a larger start falls'
    >>> safe_tilt_sentence(0.0, 50, False)
    'none: the upright is not stable, any tilt grows'
    """
    over = f" over {periods} periods" if periods else ""
    if not stable or not theta > 0:
        return "none: the upright is not stable, any tilt grows"
    return (f"stands for starting tilts from rest below {theta:.3g} rad ({math.degrees(theta):.3g} deg){over}; "
            "a larger start falls")
