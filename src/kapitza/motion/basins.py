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
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from .._display import Summary, num
from ..drives import as_drive
from ..parameters import G_EARTH
from ._maps import AMPLITUDES, STEPS, bound_ensemble, chunk_results, phases
from .nonlinear import MAX_PERIODS, MODELS, _check_speed, _choice, _physical

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


def _sub_steps(s, dur, scaled=1.0):
    """``(s, h, count)`` of one phase cut into ``count`` sub-steps of scaled length ``w h <= scaled``
    (scalars, or arrays with one entry per state)."""
    count = np.maximum(1, np.ceil(np.sqrt(np.abs(s)) * dur / scaled))
    if np.ndim(count) == 0:
        return s, dur / max(1, int(count)), max(1, int(count))
    return s, dur / count, count.astype(np.int64)


def _one_period(th, om, subs, tol, model):
    """Advance states by one period; also say which left the window during it.

    ``subs``: the ``(s, h, count)`` sub-steps of each phase (:func:`_sub_steps`), scalars or
    arrays aligned with the states. Each state keeps its own sub-step length and count, so its
    result does not depend on the other states.
    """
    step = STEPS[model]
    amplitude = AMPLITUDES[model]
    left = np.zeros(th.shape, dtype=bool)
    for s, h, count in subs:
        per_state = np.ndim(count) > 0
        neg = s < 0
        for j in range(int(np.max(count, initial=1)) if per_state else count):
            th1, om1 = step(th, om, s, h)
            if per_state and j > 0:
                idle = count <= j  # these states have finished this phase's sub-steps
                if idle.any():
                    th1, om1 = np.where(idle, th, th1), np.where(idle, om, om1)
            out = np.abs(th1) > tol
            if np.any(neg):
                turned = (np.sign(om1) * np.sign(om)) < 0
                if per_state:
                    turned &= neg
                if turned.any():
                    w = np.sqrt(np.abs(s[turned] if per_state else s))
                    out[turned] |= amplitude(th[turned], om[turned], w) > tol
            left |= out
            th, om = th1, om1
    return th, om, left


def _survival_chunk(theta, dtheta, plan, periods, tol, model, scaled=1.0):
    """Periods completed with ``|theta| <= tol`` throughout, for one chunk (trusted input).

    ``plan``: the ``(s, duration)`` phases of one period, each a scalar or an array with one
    entry per state (members with different parameters then advance together). States that
    leave are dropped from the working arrays after the period they left in. ``scaled``: the
    longest sub-step in scaled time ``w h``; the test is exact for any ``scaled < pi`` (module
    notes: turning points are at least ``pi`` apart, and a return from beyond ``pi`` takes at
    least ``pi``).
    """
    n = theta.size
    survived = np.full(n, periods, dtype=np.int64)
    alive = np.flatnonzero(np.abs(theta) <= tol)
    survived[np.abs(theta) > tol] = 0
    th, om = theta[alive], dtheta[alive]
    subs = [_sub_steps(s, dur, scaled) for s, dur in plan]
    per_state = any(np.ndim(c) > 0 for _, _, c in subs)
    for k in range(periods):
        if alive.size == 0:
            break
        subs_a = [tuple(v[alive] if np.ndim(v) else v for v in sub) for sub in subs] if per_state else subs
        th, om, out = _one_period(th, om, subs_a, tol, model)
        if out.any():
            survived[alive[out]] = k
            keep = ~out
            alive, th, om = alive[keep], th[keep], om[keep]
    return survived


def _survival_integrated(theta, dtheta, T, A, l, g, drive, periods, tol, model, chunk, progress,
                         samples=64, rtol=1e-9):
    """Survival for a smooth drive (the sine): DOP853 over each half-period, the window
    checked at ``samples`` evenly spaced instants per period and at every half-period."""
    from scipy.integrate import solve_ivp

    n_all = theta.size
    survived = np.full(n_all, periods, dtype=np.int64)
    survived[np.abs(theta) > tol] = 0
    bounds = [(a, min(a + chunk, n_all)) for a in range(0, n_all, chunk)]
    f = (lambda z: z) if model == "linear" else np.sin
    for ci, (a, b) in enumerate(bounds):
        alive = np.arange(a, b)[np.abs(theta[a:b]) <= tol]
        th, om = theta[alive], dtheta[alive]
        for k in range(periods):
            if alive.size == 0:
                break
            for half in (0, 1):
                t0 = (2 * k + half) * T
                t_eval = t0 + np.linspace(0.0, T, samples // 2 + 1)[1:]
                n = th.size

                def rhs(t, z, n=n):
                    s = (g + A * drive._shape(np.mod(t / T, 2.0))) / l
                    return np.concatenate([z[n:], s * f(z[:n])])

                sol = solve_ivp(rhs, (t0, t0 + T), np.concatenate([th, om]), method="DOP853", rtol=rtol,
                                atol=1e-12, t_eval=t_eval)
                out = np.any(np.abs(sol.y[:n]) > tol, axis=1)
                survived[alive[out]] = k
                keep = ~out
                alive = alive[keep]
                th, om = sol.y[:n, -1][keep], sol.y[n:, -1][keep]
                if alive.size == 0:
                    break
        if progress is not None:
            progress(ci + 1, len(bounds))
    return survived


def _run_chunks(theta, dtheta, plan, periods, tol, model, chunk, workers, progress):
    bounds = [(a, min(a + chunk, theta.size)) for a in range(0, theta.size, chunk)]
    out = np.empty(theta.size, dtype=np.int64)
    for a, b, res in chunk_results(_survival_chunk, bounds,
                                   lambda a, b: (theta[a:b], dtheta[a:b], plan, periods, tol, model), workers, progress):
        out[a:b] = res
    return out


@_v.shapes_named
def survival(theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=50, tol=0.5,
             model="nonlinear", chunk=4096, workers=1, progress=None, drive=None):
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
        The full, undamped equation (exact phase flows) or its linearisation (2.3).
    chunk, workers, progress
        As in :func:`kapitza.motion.stroboscopic_map`.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default. A
        piecewise-constant drive is followed by exact step flows and the window checked on the
        continuous motion; the sine drive by DOP853 (rtol 1e-9), the window checked at 64
        instants per period.

    Returns
    -------
    ndarray of int
        ``N`` where ``|theta(t)| <= tol`` on all of ``[0, 2NT]``, otherwise the
        number of whole periods completed before the first exit (0 if it leaves
        during the first period or starts outside).

    Notes
    -----
    The window is checked on the continuous motion (see the module notes), not only
    at sampled instants.
    """
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    theta0, dtheta0 = np.broadcast_arrays(theta0, dtheta0)
    T, A, l, g = _scalar_parameters(T, A, l, g, eps, mu)
    periods = _v.bounded_count("periods", periods, MAX_PERIODS, minimum=1)
    tol = _tolerance(tol)
    _choice("model", model, MODELS)
    chunk = _v.bounded_count("chunk", chunk, 10**7, minimum=1)
    _v.bounded_count("workers", workers, 1024, minimum=1)
    th = np.ascontiguousarray(theta0, dtype=float).ravel()
    om = np.ascontiguousarray(dtheta0, dtype=float).ravel()
    d = as_drive(drive)
    # Sub-steps of scaled length <= 1 per phase: the work grows with w T as well.
    per_period = sum(max(1.0, np.ceil(np.sqrt(abs(s_)) * dur)) for s_, dur in
                     (phases(T, A, l, g) if not hasattr(d, "levels") or d.name == "square" else d.phases(T, A, l, g)))
    bound_ensemble(periods * per_period, th.size,
                   name="periods * (sub-steps w T per phase, from T, A, l, g) * (members + 1000)")
    if model == "nonlinear" and hasattr(d, "levels"):
        _check_speed(om, [s_ for s_, _ in (phases(T, A, l, g) if d.name == "square" else d.phases(T, A, l, g))])
    if not hasattr(d, "levels"):
        out = _survival_integrated(th, om, T, A, l, g, d, periods, tol, model, min(chunk, 1024), progress)
        return _v.scalars(out.reshape(theta0.shape))
    plan = phases(T, A, l, g) if d.name == "square" else d.phases(T, A, l, g)
    out = _run_chunks(th, om, plan, periods, tol, model, chunk, workers, progress)
    return _v.scalars(out.reshape(theta0.shape))


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
    drive: object = None

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
        from ..drives import as_drive

        eps, mu = self.T * np.sqrt(self.A / (8.0 * self.l)), np.sqrt(self.g / self.A)
        return [("model", self.model), ("drive", as_drive(self.drive).describe()),
                ("parameters", f"T = {num(self.T)} s, A = {num(self.A)} m/s^2, l = {num(self.l)} m, "
                               f"g = {num(self.g)} m/s^2 (eps = {num(eps)}, mu = {num(mu)})"),
                ("grid", f"{self.theta0.size} theta0 in [{num(self.theta0[0])}, {num(self.theta0[-1])}] rad x "
                         f"{self.dtheta0.size} dtheta0 in [{num(self.dtheta0[0])}, {num(self.dtheta0[-1])}] rad/s"),
                ("window", f"|theta| <= {num(self.tol)} rad for {self.periods} periods 2T"),
                ("stays", f"{100 * self.fraction:.4g}% of the grid ({int(np.count_nonzero(self.survived)):,} of "
                          f"{self.survived.size:,} starts)")]

    def summary(self) -> dict:
        """JSON-ready description (no grids)."""
        return dict(model=self.model, T=self.T, A=self.A, l=self.l, g=self.g, periods=self.periods, tol=self.tol,
                    theta0_range=[float(self.theta0[0]), float(self.theta0[-1])],
                    dtheta0_range=[float(self.dtheta0[0]), float(self.dtheta0[-1])],
                    shape=list(self.periods_survived.shape), fraction=self.fraction)


@_v.shapes_named
def basin(T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=50, tol=0.5, theta_max=None,
          dtheta_max=None, n_theta=121, n_dtheta=121, model="nonlinear", chunk=4096, workers=1, progress=None,
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
        wider starts leave at once).
    dtheta_max : float, optional
        The grid spans ``-dtheta_max <= dtheta0 <= dtheta_max`` [rad/s] (default
        ``2 tol / T``, a swing across the window in one half-period).
    n_theta, n_dtheta : int, optional
        Grid points (>= 2 each).
    model : {'nonlinear', 'linear'}
    chunk, workers, progress, drive
        As in :func:`survival`.

    Returns
    -------
    Basin
    """
    T, A, l, g = _scalar_parameters(T, A, l, g, eps, mu)
    tol = _tolerance(tol)
    theta_max = tol if theta_max is None else _v.one("theta_max", _v.positive("theta_max", theta_max))
    dtheta_max = 2.0 * tol / T if dtheta_max is None else _v.one("dtheta_max", _v.positive("dtheta_max", dtheta_max))
    n_theta = _v.bounded_count("n_theta", n_theta, MAX_GRID, minimum=2)
    n_dtheta = _v.bounded_count("n_dtheta", n_dtheta, MAX_GRID, minimum=2)
    _v.bounded_work("n_theta * n_dtheta", n_theta * n_dtheta, 25_000_000, what="grid points held in memory")
    th = np.linspace(-theta_max, theta_max, n_theta)
    om = np.linspace(-dtheta_max, dtheta_max, n_dtheta)
    grid = survival(th[None, :], om[:, None], T, A, l, g, periods=periods, tol=tol, model=model,
                    chunk=chunk, workers=workers, progress=progress, drive=drive)
    d = as_drive(drive)
    return Basin(theta0=th, dtheta0=om, periods_survived=grid, periods=int(periods), tol=tol, model=model,
                 T=T, A=A, l=l, g=g, drive=None if d.name == "square" else d)
