"""Per-point quantities of a sweep, for a whole block of parameter points at once.

Every quantity is a question about the survival test of :func:`kapitza.motion.survival`
(``|theta(t)| <= tol`` on the whole of ``[0, 2NT]``), on one of its two paths
(:func:`period_step`): for an undamped piecewise-constant drive the **exact** path (flow exact
in Jacobi elliptic functions, ``docs/theory.md`` section 6, window checked on the continuous
motion); for the sine drive or damping ``c > 0`` the **integrated** path (DOP853, rtol 1e-9
per component, window checked at sampled instants and on the Hermite interpolant between
them). Either is a one-period step, and the searches below drive it through one loop. The
block's points and all their candidate starts are advanced together as one numpy array (one
parameter set per state), and a start is dropped from the working arrays as soon as it leaves
the window, so a failed candidate costs only the periods it survived.

* **max safe radius along a direction** ``phi`` of the phase plane: the start
  ``(theta0, dtheta0) = r (cos phi, Omega sin phi)`` with ``Omega = 2/T`` (the scale of
  :func:`kapitza.motion.basin`'s window: ``r = tol`` reaches its edge). Bracketed by scanning
  ``r = tol, tol/2, tol/4, ...`` downward to the first survivor, then bisected until the
  bracket ``[lo, hi)`` has ``hi - lo <= accuracy * lo``; ``lo`` (a start seen to survive) is
  reported: it stays, and a start less than ``accuracy`` above it does not. Below ``floor`` no
  start is tried and 0 is reported. Where the safe starts along the ray form one segment
  ``[0, r*)`` (a connected core) this is ``r*`` to ``accuracy``; near the zone edges they can be
  ragged at that scale, and the value is then a boundary point of the safe set (the tests
  compare with brute force).
* **max safe tilt** ``theta*``: the radius along ``phi = 0`` (at rest).
* **max safe radius**: the smallest radius over ``directions`` directions evenly spaced in
  ``[0, pi)`` (the motion is odd, so ``phi + pi`` repeats ``phi``).
* **basin area**: the fraction of the ``n x n`` start grid of :func:`kapitza.motion.basin`
  (``|theta0| <= tol``, ``|dtheta0| <= 2 tol / T``) that survives ``N`` periods; by the odd
  symmetry only half the grid is followed and mirrored.
* **median escape**: the median over that grid of the periods completed before leaving
  (``N`` when at least half stayed).
"""
from __future__ import annotations

import numpy as np

from ..drives import as_drive, parse_drive
from ..drives._api import zeta_of
from ..motion._maps import step_plan
from ..motion._periods import _ExactPeriod, _IntegratedPeriod
from ..motion.basins import survival_chunk, exact_path
from ..parameters import to_arnold, to_physical
from ..propagation import growth_rate
from ..zones import stability_margin

__all__ = ["QUANTITIES", "VARIABLES", "block_quantities", "ray_radii", "period_step", "compiled_available",
           "plane_to_physical"]

#: Quantities a sweep can compute, and the variables each one writes.
QUANTITIES = {
    "tilt": ("max_safe_tilt",),
    "radius": ("max_safe_radius",),
    "basin": ("basin_area", "median_escape"),
    "linear": ("stable", "zone", "growth", "margin"),
}

#: ``name -> (long name, units)`` of every variable.
VARIABLES = {
    "max_safe_tilt": ("largest starting tilt at rest that stays within tol for N periods", "rad"),
    "max_safe_radius": ("largest safe radius over all directions of the phase plane (theta, dtheta T/2)", "rad"),
    "basin_area": ("fraction of the start window that stays within tol for N periods", "1"),
    "median_escape": ("median over the start window of the periods completed inside tol", "periods"),
    "stable": ("linear verdict: 1 stable, 0 unstable", "1"),
    "zone": ("stability zone n (-1 where unstable)", "1"),
    "growth": ("linear growth rate log max|multiplier| per period 2T", "1/period"),
    "margin": ("signed relative distance to the nearest zone edge along eps", "1"),
}


#: Longest sub-step of a phase in scaled time ``w h`` on the exact path: the window test of
#: :mod:`kapitza.motion.basins` is exact for any value below ``pi``; 3 keeps one step per
#: phase wherever ``w T <= 3`` (zone 0 and most of zone 1).
SCALED_STEP = 3.0


def plane_to_physical(plane, x, y, l, g, drive=None):
    """``(T [s], A [m/s^2])`` of grid values ``x``, ``y`` (broadcast) on a sweep's plane.

    ``arnold``: ``(eps, mu)`` (:func:`kapitza.to_physical`); ``physical``: ``(T, A)`` themselves;
    ``rig``: drive frequency ``f`` [Hz] and stroke ``s`` [m] (peak-to-peak travel of the pivot), so
    ``T = 1 / (2 f)`` and ``A = s / (k T^2)`` with the drive's stroke coefficient ``k``
    (:func:`kapitza.rig_plane.stroke_coefficient`: 1/4 for the square wave).

    Examples
    --------
    >>> from kapitza.sweeps.kernel import plane_to_physical
    >>> T, A = plane_to_physical("rig", 50.0, 0.01, 1.0, 9.81)
    >>> float(T), float(A)
    (0.01, 400.0)
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    if plane == "arnold":
        return to_physical(x, y, l, g)
    if plane == "rig":
        from ..rig_plane import stroke_coefficient

        T = 0.5 / x
        return T, y / (stroke_coefficient(drive) * T * T)
    return x, y


def period_step(T, A, l, g, c, drive, tol):
    """The one-period step of a block's points (arrays ``T``, ``A`` of shape ``(P,)``), called
    ``(theta, dtheta, point) -> (theta, dtheta, left)``: exact step flows for an undamped
    piecewise-constant drive, otherwise DOP853 (:mod:`kapitza.motion.basins`)."""
    if exact_path(drive, c):
        plan = [(np.asarray(s, float) * np.ones_like(T), np.asarray(d, float) * np.ones_like(T))
                for s, d in step_plan(drive, T, A, l, g)]
        return _ExactPeriod(plan, tol, "nonlinear", SCALED_STEP)
    return _IntegratedPeriod(T, A, l, g, c, drive, tol, "nonlinear")


def compiled_available() -> bool:
    """Whether the compiled survival kernel (numba, the ``fast`` extra) can be used."""
    from importlib.util import find_spec

    return find_spec("numba") is not None


def _compiled_plan(period, n_points, compiled):
    """``(S, H, CNT)`` of an exact period for the compiled kernel, or ``None`` for the numpy path."""
    if not compiled or not isinstance(period, _ExactPeriod) or period.model != "nonlinear":
        return None
    from ..motion._survival_jit import pack_plan

    return pack_plan(period.subs, n_points)


def _compiled_integrated(period, compiled):
    """The plan of an integrated period for its compiled twin (:mod:`kapitza.motion._integrated_jit`),
    or ``None`` for the numpy path (not asked for, or a drive known only by its shape)."""
    if not compiled or not isinstance(period, _IntegratedPeriod):
        return None
    from ..motion._integrated_jit import pack_plan

    return pack_plan(period)


def ray_radii(T, period, phis, periods, tol, accuracy, floor, compiled=False):
    """Largest safe radius along each direction of ``phis`` for every point.

    Every search (point x direction) always has exactly one candidate start in flight; all of
    them advance together, one period per step of ``period`` (exact or integrated, the same
    loop), and as soon as a candidate leaves the window or completes ``periods`` its search
    takes its next candidate, which starts from period 0 in the same arrays. The arrays stay
    full, and a point's searches cost the sum of its candidates' lives rather than a whole round
    of ``periods`` per candidate.

    Parameters
    ----------
    T : ndarray, shape ``(P,)``
        Half-periods [s] of the points (they set ``Omega = 2/T``).
    period : callable
        The points' one-period step, :func:`period_step`.
    phis : ndarray, shape ``(K,)``
        Directions [rad] in the plane ``(theta, dtheta / Omega)``.
    periods, tol, accuracy, floor :
        ``N``, the window [rad], the relative width of the final bracket, the smallest radius tried.

    compiled : bool
        Run each search to its end in the compiled kernel, one state at a time: where ``period`` is
        exact :mod:`kapitza.motion._survival_jit` (the same searches and the same phase flows), where
        it is integrated :mod:`kapitza.motion._integrated_jit` (the same searches, DOP853 per state;
        a drive given only by its shape stays here); otherwise this numpy loop.

    Returns
    -------
    ndarray, shape ``(P, K)``
        ``lo`` of each search (0 below ``floor``; ``tol`` when ``tol`` itself survives).
    """
    P, K = T.size, phis.size
    M = P * K
    point = np.repeat(np.arange(P), K)
    cos, sin = np.tile(np.cos(phis), P), np.tile(np.sin(phis), P)
    omega = 2.0 / T[point]
    plan = _compiled_plan(period, P, compiled)
    if plan is not None:
        from ..motion._survival_jit import ray_radii_compiled

        return ray_radii_compiled(point, cos, sin * omega, *plan, periods, tol, accuracy, floor).reshape(P, K)
    iplan = _compiled_integrated(period, compiled)
    if iplan is not None:
        from ..motion._integrated_jit import ray_radii_compiled as integrated_radii

        return integrated_radii(point, cos, sin * omega, iplan, periods, tol, accuracy, floor).reshape(P, K)
    lo = np.zeros(M)
    hi = np.full(M, np.inf)
    scanning = np.ones(M, dtype=bool)  # 1. r = tol, tol/2, ... down to the first survivor, 2. bisection
    # the searches in flight: index, candidate radius, state, periods completed
    act = np.arange(M)
    r = np.full(M, tol)
    th, om = r * cos, r * sin * omega
    k = np.zeros(M, dtype=np.int64)
    while act.size:
        th, om, left = period(th, om, point[act])
        k += 1
        fail = left
        ok = ~left & (k >= periods)
        if not (fail.any() or ok.any()):
            continue
        i = act[ok]
        lo[i] = r[ok]
        scanning[i] = False
        hi[act[fail]] = r[fail]
        # the next candidate of every finished search, or its end
        nxt = r.copy()
        fin = ok | fail
        scan_fail = fail & scanning[act]
        nxt[scan_fail] = 0.5 * r[scan_fail]
        bis = fin & ~scan_fail
        j = act[bis]
        nxt[bis] = 0.5 * (lo[j] + hi[j])
        done = (scan_fail & (nxt < floor)) | (bis & ((lo[act] >= tol) | (hi[act] - lo[act] <= accuracy * lo[act])))
        restart = fin & ~done
        r = np.where(restart, nxt, r)
        th = np.where(restart, r * cos[act] * 1.0, th)
        om = np.where(restart, r * sin[act] * omega[act], om)
        k[restart] = 0
        keep = ~done
        act, r, th, om, k = act[keep], r[keep], th[keep], om[keep], k[keep]
    return lo.reshape(P, K)


def _basin_grid(T, period, n, periods, tol, compiled=False):
    """``(area, median escape)`` of each point over the ``n x n`` start grid of :func:`kapitza.basin`."""
    P = T.size
    th = np.linspace(-tol, tol, n)
    half = (n * n + 1) // 2  # the grid is symmetric about its centre: follow the first half only
    q = np.arange(half)
    th_q = th[q % n]
    om_unit = np.linspace(-2.0 * tol, 2.0 * tol, n)[q // n]
    point = np.repeat(np.arange(P), half)
    theta0 = np.tile(th_q, P)
    dtheta0 = np.tile(om_unit, P) / T[point]
    plan = _compiled_plan(period, P, compiled)
    if plan is not None:
        from ..motion._survival_jit import survival_compiled

        got = survival_compiled(theta0, dtheta0, point, *plan, periods, tol).reshape(P, half)
    elif (iplan := _compiled_integrated(period, compiled)) is not None:
        from ..motion._integrated_jit import survival_compiled as integrated_survival

        got = integrated_survival(theta0, dtheta0, point, iplan, periods, tol).reshape(P, half)
    else:
        got = survival_chunk(theta0, dtheta0, period, periods, tol, idx=point).reshape(P, half)
    full = np.concatenate([got, got[:, : n * n - half][:, ::-1]], axis=1)
    area = np.mean(full >= periods, axis=1)
    median = np.median(full, axis=1).astype(float)
    return area, median


def block_quantities(x, y, *, plane, l, g, drive, periods, tol, quantities, directions, basin_resolution,
                     accuracy, floor, c=0.0, compiled=None):
    """Every requested variable on the grid ``y x x`` (rows ``y``: mu, A [m/s^2] or stroke [m]; columns
    ``x``: eps, T [s] or drive frequency [Hz], as :func:`plane_to_physical` maps them).

    ``compiled``: run the searches in the compiled kernels (numba) -- ``None``: where numba is
    installed; ``True``: required; ``False``: the numpy loops. On the exact path the two agree to
    rounding (:mod:`kapitza.motion._survival_jit`); on the integrated path to the integration error,
    the safe tilt to ``accuracy`` but at ragged edges (:mod:`kapitza.motion._integrated_jit`; a drive
    given only by its shape takes the numpy loop either way).

    ``c``: viscous damping [1/s] (trusted, ``>= 0``); the linear quantities take the damping ratio
    ``zeta = c / (2 sqrt(g/l))``. An undamped piecewise-constant drive takes the exact path, the
    sine drive or ``c > 0`` the integrated one (:func:`period_step`).

    Returns
    -------
    dict
        ``variable -> ndarray of shape (y.size, x.size)``.
    """
    X, Y = np.meshgrid(np.asarray(x, float), np.asarray(y, float))
    X, Y = X.ravel(), Y.ravel()
    d = parse_drive(drive) if isinstance(drive, str) else as_drive(drive)
    T, A = plane_to_physical(plane, X, Y, l, g, d)
    eps, mu = (X, Y) if plane == "arnold" else to_arnold(T, A, l, g)
    shape = (np.size(y), np.size(x))
    out = {}
    if "linear" in quantities:
        z = float(zeta_of(c, l, g))
        # One certified verdict for all three: the margin carries the verdict and its zone.
        m = stability_margin(eps, mu, drive=d, zeta=z)
        out["stable"] = np.asarray(m.stable).astype(np.int8)
        out["zone"] = np.where(m.stable, m.zone, -1).astype(np.int16)
        out["growth"] = np.asarray(growth_rate(eps, mu, drive=d, zeta=z), float)
        out["margin"] = np.asarray(m.margin, float)
    period = period_step(T, A, l, g, c, d, tol)
    if compiled is None:
        compiled = compiled_available()
    elif compiled and not compiled_available():
        raise ImportError("the compiled survival kernel needs numba: pip install 'kapitza[fast]'")
    if "tilt" in quantities or "radius" in quantities:
        K = directions if "radius" in quantities else 1
        radii = ray_radii(T, period, np.pi * np.arange(K) / K, periods, tol, accuracy, floor, compiled)
        if "tilt" in quantities:
            out["max_safe_tilt"] = radii[:, 0]
        if "radius" in quantities:
            out["max_safe_radius"] = radii.min(axis=1)
    if "basin" in quantities:
        out["basin_area"], out["median_escape"] = _basin_grid(T, period, basin_resolution, periods, tol, compiled)
    return {k: v.reshape(shape) for k, v in out.items()}
