"""Does the upright survive? Basins of initial states that stay near it for N periods.

A motion *stays within* ``tol`` of the upright for ``N`` periods when
``|theta(t)| <= tol`` for all ``0 <= t <= 2NT`` (``theta`` unwrapped, ``tol < pi``:
a swing over the bottom and back counts as a fall). The test is exact on the
continuous motion, not only at sampled instants: each phase is cut into sub-steps
of scaled length ``w dt <= 1``, and within a sub-step

* hyperbolic phase (``s > 0``): ``theta`` is convex where positive and concave where
  negative (``theta'' = s sin(theta)``, or ``s theta``), so ``|theta|`` has no
  interior maximum below ``pi``; returning from beyond ``pi`` takes at least half a
  libration period about the bottom, ``>= pi`` in scaled time. The end points decide.
* elliptic phase (``s < 0``): at most one turning point per sub-step (they are at
  least ``pi`` apart in scaled time); where ``theta'`` changes sign the turning
  amplitude ``2 asin k`` (nonlinear) or ``sqrt(theta^2 + theta'^2/w^2)`` (linear)
  is the maximum.

Inside a stability zone small motions stay up in both models; outside one the
linear motion grows like ``exp(growth * k)`` and leaves any window, and so does the
nonlinear one, apart from islands the linear model cannot see.

All of this is the **exact path**, for undamped piecewise-constant drives. The sine
drive and any damping ``c > 0`` (``theta'' = s sin(theta) - c theta'``) have no exact
flow: they take the **integrated path** (:class:`~kapitza.motion._periods._IntegratedPeriod`), DOP853 over each
period with the window checked at sampled instants and between them on the cubic
Hermite interpolant through ``(theta, theta')``. Both are one-period steps behind one
survival loop (:func:`survival_chunk`), which :mod:`kapitza.sweeps.kernel` drives too.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from .._display import Summary, num
from ..drives import Drive, as_drive
from ..parameters import G_EARTH
from ._integrate import MAX_PERIODS, _budget, _check_speed, _choice, _one_damping, _peak, _physical
from ._maps import bound_ensemble, chunk_results, step_plan
from ._periods import (INTEGRATED_ATOL as INTEGRATED_ATOL, INTEGRATED_RTOL as INTEGRATED_RTOL,
                       MIN_SAMPLES as MIN_SAMPLES, SAMPLE_SPACING as SAMPLE_SPACING, _ExactPeriod, _IntegratedPeriod)
from .nonlinear import MODELS

__all__ = ["survival", "Basin", "basin"]

#: Grid points per axis of a basin (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_GRID = 5000


def _scalar_parameters(T, A, l, g, eps=None, mu=None):
    T, A, l, g = _physical(T, A, l, g, eps, mu)
    out = []
    for name, v in (("T", T), ("A", A), ("l", l), ("g", g)):
        if v.size != 1:
            raise _v.KapitzaValueError(f"{name} must be a single value here; got shape {v.shape}")
        out.append(float(v.flat[0]))
    return out


def _tolerance(tol):
    return _v.one("tol", _v.in_range("tol", tol, 0.0, np.pi))


def survival_chunk(theta, dtheta, period, periods, tol, idx=None):
    """Periods completed with ``|theta| <= tol`` throughout, for one chunk (trusted input).

    ``period``: a one-period step, :class:`_ExactPeriod` or :class:`_IntegratedPeriod`;
    ``idx``: the parameter set of each state (``None``: one set for all). States that leave are
    dropped from the working arrays after the period they left in.
    """
    n = theta.size
    survived = np.full(n, periods, dtype=np.int64)
    alive = np.flatnonzero(np.abs(theta) <= tol)
    survived[np.abs(theta) > tol] = 0
    th, om = theta[alive], dtheta[alive]
    for k in range(periods):
        if alive.size == 0:
            break
        th, om, out = period(th, om, alive if idx is None else idx[alive])
        if out.any():
            survived[alive[out]] = k
            keep = ~out
            alive, th, om = alive[keep], th[keep], om[keep]
    return survived


def _run_chunks(theta, dtheta, period, periods, tol, chunk, workers, progress):
    bounds = [(a, min(a + chunk, theta.size)) for a in range(0, theta.size, chunk)]
    out = np.empty(theta.size, dtype=np.int64)
    for a, b, res in chunk_results(survival_chunk, bounds,
                                   lambda a, b: (theta[a:b], dtheta[a:b], period, periods, tol), workers, progress):
        out[a:b] = res
    return out


@_v.shapes_named
def survival(theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=50, tol=0.5,
             model="nonlinear", damping=None, zeta=None, chunk=4096, workers=1, progress=None, drive=None):
    """How many whole drive periods each motion stays within ``tol`` of the upright.

    Parameters
    ----------
    theta0, dtheta0 : array_like
        Initial angles [rad] and angular velocities [rad/s] at ``t = 0``; broadcast.
    T, A, l, g : float
        Half-period [s], amplitude [m/s^2], rod length [m], gravity [m/s^2]; > 0.
    eps, mu : float, optional
        Arnold's parameters instead of ``T`` and ``A`` (keywords; with ``l`` and ``g``):
        ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``. Give ``(eps, mu)`` or ``(T, A)``.
    periods : int, optional
        ``N``, the periods ``2T`` to follow (>= 1).
    tol : float, optional
        Half-width of the window about the upright [rad], ``0 < tol < pi``.
    model : {'nonlinear', 'linear'}
        The full equation ``theta'' = s sin(theta) - c theta'`` or its linearisation (2.3).
    damping, zeta : float, optional
        Viscous damping as ``c`` [1/s] or as the ratio ``zeta = c / (2 sqrt(g/l))``, not both (as in
        :func:`kapitza.motion.stroboscopic_map`).
    chunk, workers, progress
        As in :func:`kapitza.motion.stroboscopic_map`.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.

    Returns
    -------
    ndarray of int
        ``N`` where ``|theta(t)| <= tol`` on all of ``[0, 2NT]``, otherwise the
        number of whole periods completed before the first exit (0 if it leaves
        during the first period or starts outside).

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range; also if the work asked for (periods, states) is beyond
        the library's limit (``KAPITZA_ALLOW_LARGE=1`` lifts it).

    Notes
    -----
    Two paths (:func:`exact_path` says which):

    * **exact** (an undamped piecewise-constant drive: square, rectangular, steps): exact step
      flows, the window checked on the continuous motion (module notes), not only at sampled
      instants;
    * **integrated** (the sine drive, or ``c > 0``): DOP853 with ``rtol = 1e-9``,
      ``atol = 1e-12`` per component, restarted at every jump of the drive; the window checked at
      instants evenly spaced over each period (at least 64, and ``(w_h + c) dt <= 0.2``) and
      between them on the cubic Hermite interpolant through ``(theta, theta')`` (error about
      ``(w dt)^4 / 384``, below ``5e-6`` of the swing). Sampled, so an excursion beyond ``tol`` by
      less than that can be missed; far slower (bounded by :func:`bound_integrated`).

    Examples
    --------
    >>> import kapitza
    >>> kapitza.survival([0.01, 0.2], 0.0, 0.15, 100.0, periods=300, tol=0.5)
    array([300,   0])
    """
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    theta0, dtheta0 = np.broadcast_arrays(theta0, dtheta0)
    T, A, l, g = _scalar_parameters(T, A, l, g, eps, mu)
    c = _one_damping(damping, zeta, l, g)
    periods = _v.bounded_count("periods", periods, MAX_PERIODS, minimum=1)
    tol = _tolerance(tol)
    _choice("model", model, MODELS)
    chunk = _v.bounded_count("chunk", chunk, 10**7, minimum=1)
    _v.bounded_count("workers", workers, 1024, minimum=1)
    th = np.ascontiguousarray(theta0, dtype=float).ravel()
    om = np.ascontiguousarray(dtheta0, dtype=float).ravel()
    d = as_drive(drive)
    if exact_path(d, c):
        plan = step_plan(d, T, A, l, g)
        # Sub-steps of scaled length <= 1 per phase: the work grows with w T as well.
        per_period = sum(max(1.0, np.ceil(np.sqrt(abs(s_)) * dur)) for s_, dur in plan)
        bound_ensemble(periods * per_period, th.size,
                       name="periods * (sub-steps w T per phase, from T, A, l, g) * (members + 1000)")
        if model == "nonlinear":
            _check_speed(om, [s_ for s_, _ in plan])
        period = _ExactPeriod(plan, tol, model)
    else:
        _budget(2.0 * T * periods, T, A, l, g, c, "dop853", _peak(d), om)
        bound_integrated(periods, th.size, T, A, l, g, c, d)
        period = _IntegratedPeriod(T, A, l, g, c, d, tol, model)
        chunk = min(chunk, INTEGRATED_CHUNK)
    out = _run_chunks(th, om, period, periods, tol, chunk, workers, progress)
    return _v.scalars(out.reshape(theta0.shape))


def exact_path(drive, c) -> bool:
    """Whether :func:`survival` follows the motion by exact step flows (an undamped piecewise-constant
    drive) rather than by DOP853 (the sine drive, or any damping)."""
    return drive._steps() is not None and not np.any(np.asarray(c) > 0)


#: States the integrated path solves together in one :func:`survival` chunk.
INTEGRATED_CHUNK = 1024
#: Integrated path: the cost of one period's Python work (solver set-up, steps, samples) in state units.
INTEGRATED_STEP_COST = 200
#: Integrated path: work one call may do, in state-periods at ``(w_h + c) 2T <= 3`` (about a minute;
#: ``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_INTEGRATED_STATE_PERIODS = 3_000_000


def integrated_work(periods, states, T, A, l, g, c, drive):
    """Work of the integrated path in state-periods at ``(w_h + c) 2T <= 3``: ``periods * (states + 200)``,
    scaled by ``(w_h + c) 2T / 3`` where the period is longer (DOP853's steps grow with it)."""
    with np.errstate(over="ignore"):  # beyond a double: refused as infinite work
        w = np.sqrt((np.asarray(g, float) + _peak(drive) * np.asarray(A, float)) / np.asarray(l, float)) + c
        factor = np.maximum(1.0, w * 2.0 * np.asarray(T, float) / 3.0)
        return float(np.sum(float(periods) * (np.asarray(states, float) + INTEGRATED_STEP_COST) * factor))


def bound_integrated(periods, states, T, A, l, g, c, drive):
    """Refuse integrated work (:func:`integrated_work`) beyond about a minute."""
    _v.bounded_work("periods * (members + 200) * max(1, (w_h + c) 2T / 3) (DOP853: sine drive or damping)",
                    integrated_work(periods, states, T, A, l, g, c, drive), MAX_INTEGRATED_STATE_PERIODS,
                    what="state-periods integrated by DOP853, about a minute of work")


@dataclass(frozen=True, repr=False)
class Basin(Summary):
    """Initial states that keep the pendulum within ``tol`` of the upright for ``periods`` periods.

    Prints as a summary (model, parameters, grid, fraction that stays); :meth:`summary` is the
    JSON-ready form.

    Attributes
    ----------
    theta0 : ndarray, shape ``(n_theta,)``
        Grid of initial angles [rad].
    dtheta0 : ndarray, shape ``(n_dtheta,)``
        Grid of initial angular velocities [rad/s].
    periods_survived : ndarray of int, shape ``(n_dtheta, n_theta)``
        :func:`survival` on the grid (rows: ``dtheta0``, columns: ``theta0``).
    periods : int
    tol : float
        Window half-width [rad].
    model : str
    T, A, l, g : float
    drive : Drive or None
        ``None`` for the square wave.
    c : float
        Viscous damping [1/s].

    Examples
    --------
    >>> import kapitza
    >>> b = kapitza.basin(T=0.15, A=100.0, periods=10, n_theta=11, n_dtheta=11)
    >>> b
    <Basin: nonlinear, T = 0.15 s, A = 100 m/s^2, 11 x 11 grid, 7.44% stay within 0.5 rad for 10 periods>
    >>> b.periods_survived.shape, int(b.periods_survived.max())
    ((11, 11), 10)
    """

    theta0: np.ndarray
    dtheta0: np.ndarray
    periods_survived: np.ndarray
    periods: int
    tol: float
    model: str
    T: float
    A: float
    l: float
    g: float
    drive: Drive = None  # type: ignore[assignment]  # (None: the square wave, set in __post_init__)
    c: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "drive", as_drive(self.drive))

    @property
    def survived(self) -> np.ndarray:
        """Boolean grid: stayed within ``tol`` for all ``periods``."""
        return self.periods_survived >= self.periods

    @property
    def fraction(self) -> float:
        """Fraction of the grid that survived."""
        return float(np.mean(self.survived))

    def columns(self):
        """``(theta0, dtheta0, survived, periods_survived)`` as flat columns, one entry per grid
        point in the order of :meth:`rows` (``theta0`` fastest), for
        :func:`kapitza._io.write_csv`'s ``columns=``."""
        n_om, n_th = self.periods_survived.shape
        return (np.tile(self.theta0, n_om), np.repeat(self.dtheta0, n_th), self.survived.ravel().astype(np.int64),
                self.periods_survived.ravel())

    def rows(self):
        """``(theta0, dtheta0, survived, periods_survived)`` rows for CSV."""
        th, om, ok, k = self.columns()
        return zip(th.tolist(), om.tolist(), ok.tolist(), k.tolist())

    def headline(self) -> str:
        return (f"{self.model}, T = {num(self.T)} s, A = {num(self.A)} m/s^2, {self.survived.shape[1]} x "
                f"{self.survived.shape[0]} grid, {100 * self.fraction:.3g}% stay within {num(self.tol)} rad "
                f"for {self.periods} periods")

    def lines(self) -> list[tuple[str, str]]:
        eps, mu = self.T * np.sqrt(self.A / (8.0 * self.l)), np.sqrt(self.g / self.A)
        return [("model", self.model + (f", damping c = {num(self.c)} 1/s" if self.c else "")),
                ("drive", self.drive.describe()),
                ("parameters", f"T = {num(self.T)} s, A = {num(self.A)} m/s^2, l = {num(self.l)} m, "
                               f"g = {num(self.g)} m/s^2 (eps = {num(eps)}, mu = {num(mu)})"),
                ("grid", f"{self.theta0.size} theta0 in [{num(self.theta0[0])}, {num(self.theta0[-1])}] rad x "
                         f"{self.dtheta0.size} dtheta0 in [{num(self.dtheta0[0])}, {num(self.dtheta0[-1])}] rad/s"),
                ("window", f"|theta| <= {num(self.tol)} rad for {self.periods} periods 2T"),
                ("stays", f"{100 * self.fraction:.4g}% of the grid ({int(np.count_nonzero(self.survived)):,} of "
                          f"{self.survived.size:,} starts)")]

    def summary(self) -> dict:
        """JSON-ready description (no grids)."""
        return dict(model=self.model, T=self.T, A=self.A, l=self.l, g=self.g, c=self.c, periods=self.periods,
                    tol=self.tol,
                    theta0_range=[float(self.theta0[0]), float(self.theta0[-1])],
                    dtheta0_range=[float(self.dtheta0[0]), float(self.dtheta0[-1])],
                    shape=list(self.periods_survived.shape), fraction=self.fraction)


#: The largest half-width of a basin's grid, in rad or rad/s
_GRID_MAX = 1e300


@_v.shapes_named
def basin(T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=50, tol=0.5, theta_max=None,
          dtheta_max=None, n_theta=121, n_dtheta=121, model="nonlinear", damping=None, zeta=None, chunk=4096, workers=1,
          progress=None,
          drive=None) -> Basin:
    """The basin of the upright on a grid of initial states.

    Parameters
    ----------
    T, A, l, g : float
        Half-period [s], amplitude [m/s^2], rod length [m], gravity [m/s^2]; > 0.
    eps, mu : float, optional
        Arnold's parameters instead of ``T`` and ``A`` (keywords; with ``l`` and ``g``):
        ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``. Give ``(eps, mu)`` or ``(T, A)``.
    periods : int, optional
        Periods ``2T`` to follow (>= 1).
    tol : float, optional
        Window half-width [rad], ``0 < tol < pi``.
    theta_max : float, optional
        The grid spans ``-theta_max <= theta0 <= theta_max`` [rad] (default ``tol``:
        wider starts leave at once); at most 1e300.
    dtheta_max : float, optional
        The grid spans ``-dtheta_max <= dtheta0 <= dtheta_max`` [rad/s] (default
        ``2 tol / T``, a swing across the window in one half-period); at most 1e300.
    n_theta, n_dtheta : int, optional
        Grid points (>= 2 each).
    model : {'nonlinear', 'linear'}
    damping, zeta : float, optional
        As in :func:`survival`; damping follows the motion by DOP853.
    chunk, workers, progress, drive
        As in :func:`survival`.

    Returns
    -------
    Basin

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range; also if the work asked for (periods, states) is beyond
        the library's limit (``KAPITZA_ALLOW_LARGE=1`` lifts it).

    Examples
    --------
    >>> import kapitza
    >>> b = kapitza.basin(0.15, 100.0, periods=20, n_theta=11, n_dtheta=11)
    >>> b.periods_survived.shape
    (11, 11)
    """
    T, A, l, g = _scalar_parameters(T, A, l, g, eps, mu)
    tol = _tolerance(tol)
    # (the grid's span 2 value, its steps and its axis' ticks must be doubles)
    theta_max = _v.one("theta_max", _v.in_range("theta_max", tol if theta_max is None else theta_max, 0.0, _GRID_MAX,
                                                hi_open=False))
    dtheta_max = _v.one("dtheta_max", _v.in_range("dtheta_max", 2.0 * tol / T if dtheta_max is None else dtheta_max,
                                                  0.0, _GRID_MAX, hi_open=False))
    n_theta = _v.bounded_count("n_theta", n_theta, MAX_GRID, minimum=2)
    n_dtheta = _v.bounded_count("n_dtheta", n_dtheta, MAX_GRID, minimum=2)
    _v.bounded_work("n_theta * n_dtheta", n_theta * n_dtheta, 25_000_000, what="grid points held in memory")
    d = as_drive(drive)
    c = _one_damping(damping, zeta, l, g)
    if model == "nonlinear" and exact_path(d, c):
        # the window's corner speed starts a motion: refuse it here, by this function's name for it
        plan = step_plan(d, T, A, l, g)
        _check_speed(np.asarray(dtheta_max), [s_ for s_, _ in plan], name="dtheta_max")
    th = np.linspace(-theta_max, theta_max, n_theta)
    om = np.linspace(-dtheta_max, dtheta_max, n_dtheta)
    grid = survival(th[None, :], om[:, None], T, A, l, g, periods=periods, tol=tol, model=model, damping=c,
                    chunk=chunk, workers=workers, progress=progress, drive=drive)
    return Basin(theta0=th, dtheta0=om, periods_survived=grid, periods=int(periods), tol=tol, model=model,
                 T=T, A=A, l=l, g=g, drive=d, c=c)
