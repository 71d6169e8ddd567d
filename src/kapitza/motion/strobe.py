"""The stroboscopic map: ensembles of initial states, seen once per drive period ``2T``.

Sampled at ``t = 2kT`` the motion is a map of the plane. For the undamped pendulum
it is the composition of the two exact phase flows (``docs/theory.md`` section 6),
evaluated on whole numpy arrays at once; its linearisation at the upright is the
monodromy matrix ``M`` (section 3). Large ensembles are cut into cache-sized chunks,
optionally spread over worker processes.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from .._display import Summary, num, span
from ..parameters import G_EARTH
from ._integrate import (MAX_PERIODS, MAX_SAMPLES, _add_turns, _budget, _check_speed, _choice, _drive_of, _one_damping,
                         _integrated_drive, _method, _peak, _physical, _reduce_angle, _tolerances)
from ._maps import STEPS, bound_ensemble, chunk_results, step_plan
from .nonlinear import MODELS

__all__ = ["StrobeOrbits", "stroboscopic_map"]


@dataclass(frozen=True, repr=False)
class StrobeOrbits(Summary):
    """Ensemble states at the recorded periods (prints as a summary, never the arrays).

    Attributes
    ----------
    n : ndarray of int, shape ``(m,)``
        Period numbers ``k`` recorded (times ``2kT``), starting with 0.
    theta, dtheta : ndarray, shape ``(m, *shape)``
        Angle [rad, unwrapped] and angular velocity [rad/s] of every member at
        each recorded period; ``shape`` is that of the initial states.
    T, A, l, g, c : float
        Parameters.
    model : str

    Examples
    --------
    >>> import kapitza
    >>> orbits = kapitza.stroboscopic_map([0.1, 0.2], 0.0, T=0.15, A=100.0, periods=10)
    >>> orbits
    <StrobeOrbits: nonlinear, T = 0.15 s, A = 100 m/s^2, 2 members, 11 records up to period 10, 2 stay up>
    >>> orbits.n[-1], orbits.theta.shape
    (np.int64(10), (11, 2))
    """

    n: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    T: float
    A: float
    l: float
    g: float
    c: float = 0.0
    model: str = "nonlinear"

    @property
    def t(self) -> np.ndarray:
        """Times ``2 k T`` of the records [s]."""
        return 2.0 * self.T * self.n

    @property
    def final(self):
        """``(theta, dtheta)`` after the last period."""
        return self.theta[-1], self.dtheta[-1]

    def _up(self):
        """Members above the horizontal (``|theta| < pi/2``) at every recorded period."""
        return np.all(np.abs(self.theta) < 0.5 * np.pi, axis=0)

    def headline(self) -> str:
        members = int(np.prod(self.theta.shape[1:], dtype=np.int64))
        return (f"{self.model}, T = {num(self.T)} s, A = {num(self.A)} m/s^2, {members:,} members, "
                f"{self.n.size} records up to period {int(self.n[-1]) if self.n.size else 0}, "
                f"{int(np.count_nonzero(self._up())):,} stay up")

    def lines(self) -> list[tuple[str, str]]:
        members = int(np.prod(self.theta.shape[1:], dtype=np.int64))
        th, om = self.final
        model = self.model + (f", damping c = {num(self.c)} 1/s" if self.c else "")
        return [("model", model),
                ("parameters", f"T = {num(self.T)} s, A = {num(self.A)} m/s^2, l = {num(self.l)} m, "
                               f"g = {num(self.g)} m/s^2"),
                ("members", f"{members:,} (shape {self.theta.shape[1:]})"),
                ("records",
                 f"{self.n.size} periods 2T from {int(self.n[0])} to {int(self.n[-1])}" if self.n.size else "none"),
                ("final theta", f"{span(th)} rad"), ("final dtheta", f"{span(om)} rad/s"),
                ("stay up", f"{int(np.count_nonzero(self._up())):,} of {members:,} members keep |theta| < pi/2 "
                            "at every record")]


def _record_list(periods, every):
    if every is None:
        n = [0, periods] if periods > 0 else [0]
    else:
        n = list(range(0, periods + 1, every))
        if n[-1] != periods:
            n.append(periods)
    return np.asarray(n, dtype=np.int64)


def _map_chunk(theta, dtheta, plan, record, model):
    """Iterate the period map on one chunk; ``plan``: the two ``(s, duration)`` phases."""
    step = STEPS[model]
    out_th = np.empty((record.size, theta.size))
    out_om = np.empty((record.size, theta.size))
    th, om = theta.copy(), dtheta.copy()
    i = 0
    if record[0] == 0:
        out_th[0], out_om[0] = th, om
        i = 1
    for k in range(1, int(record[-1]) + 1):
        for s, dur in plan:
            th, om = step(th, om, s, dur)
        if k == record[i]:
            out_th[i], out_om[i] = th, om
            i += 1
    return out_th, out_om


@_v.shapes_named
def stroboscopic_map(theta0, dtheta0, T=None, A=None, l=1.0, g=G_EARTH, *, eps=None, mu=None, periods=1, every=None,
                     model="nonlinear", damping=None, zeta=None, method=None, rtol=1e-10, atol=1e-12, chunk=16384,
                     workers=1, progress=None, drive=None):
    """Map an ensemble of initial states over ``periods`` drive periods ``2T``.

    Parameters
    ----------
    theta0, dtheta0 : array_like
        Initial angles from the upright [rad] and angular velocities [rad/s] at
        ``t = 0``; broadcast together to the ensemble's shape.
    T, A, l, g : float
        Half-period [s], amplitude [m/s^2], rod length [m], gravity [m/s^2]; > 0.
    eps, mu : float, optional
        Arnold's parameters instead of ``T`` and ``A`` (keywords; with ``l`` and ``g``):
        ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``. Give ``(eps, mu)`` or ``(T, A)``.
    periods : int, optional
        Number of periods, ``>= 0``.
    every : int, optional
        Record every ``every``-th period (and the last). By default every period, so that
        :func:`kapitza.figures.plot_strobe` shows the islands and chains a map exists to show;
        for ensembles too large to hold every period the smallest ``every`` that fits in memory.
    model : {'nonlinear', 'linear'}
    damping, zeta : float, optional
        The damping, as ``c`` [1/s] (``theta'' + c theta' = ...``) or as the ratio
        ``zeta = c / (2 sqrt(g/l))``, not both; damping uses DOP853 (``method='dop853'``).
    method : {None, 'exact', 'dop853'}
        As in :func:`kapitza.motion.nonlinear_motion`.
    rtol, atol : float, optional
        Tolerances of ``'dop853'``.
    chunk : int, optional
        Members mapped together (the arrays then stay in cache).
    workers : int, optional
        Worker processes for the exact map (1: none); no more are started than there are CPUs
        available to this process or chunks to share.
    progress : callable, optional
        ``progress(done, total)`` is called as chunks finish.
    drive : Drive or str, optional
        The pivot's motion; the paper's square wave by default. A piecewise-constant drive is
        mapped exactly step by step; the sine drive uses DOP853.

    Returns
    -------
    StrobeOrbits

    Raises
    ------
    OverflowError
        For the linear model, where a member grows beyond the range of a double.

    Notes
    -----
    Each period is ``H`` then ``E`` (the hyperbolic, then the elliptic phase,
    (2.4)-(2.5) for the linear model and their nonlinear counterparts); with
    ``method='exact'`` it has no step-size error, so the map may be iterated for
    as long as the motion's own sensitivity allows.

    Examples
    --------
    >>> import kapitza
    >>> orb = kapitza.stroboscopic_map([0.05, 0.1], 0.0, 0.15, 100.0, periods=100, every=1)
    >>> orb.theta.shape
    (101, 2)
    """
    theta0 = _v.finite("theta0", theta0)
    dtheta0 = _v.finite("dtheta0", dtheta0)
    theta0, dtheta0 = np.broadcast_arrays(theta0, dtheta0)
    T, A, l, g = (float(np.asarray(v).flat[0]) if np.size(v) == 1 else v for v in _physical(T, A, l, g, eps, mu))
    for name, v in (("T", T), ("A", A), ("l", l), ("g", g)):
        if not isinstance(v, float):
            raise _v.KapitzaValueError(f"{name} must be a single value for the stroboscopic map; got shape "
                                       f"{np.shape(v)}")
    periods = _v.bounded_count("periods", periods, MAX_PERIODS)
    if every is not None:
        every = _v.bounded_count("every", every, MAX_PERIODS, minimum=1)
    _choice("model", model, MODELS)
    c = _one_damping(damping, zeta, l, g)
    drive = _drive_of(drive)
    method = _method(method, c, drive)
    chunk = _v.bounded_count("chunk", chunk, 10**7, minimum=1)
    _v.bounded_count("workers", workers, 1024, minimum=1)
    shape = theta0.shape
    th0 = np.ascontiguousarray(theta0, dtype=float).ravel()
    om0 = np.ascontiguousarray(dtheta0, dtype=float).ravel()
    if every is None:  # every period, or as many as fit in memory
        cap = max(1, int(MAX_SAMPLES // max(th0.size, 1)) - 2)
        every = max(1, -(-periods // cap))
    n_records = periods // every + 2
    _v.bounded_work("recorded periods * members", float(n_records) * th0.size, MAX_SAMPLES,
                    what="states held in memory")
    record = _record_list(periods, every)
    if method == "exact" and model == "nonlinear":
        _check_speed(om0, [s_ for s_, _ in step_plan(drive, T, A, l, g)])
    if method == "dop853":
        _budget(2.0 * T * periods, T, A, l, g, c, method, _peak(drive), om0)
    else:
        bound_ensemble(periods, th0.size)
    turns = None
    if model == "nonlinear":
        th0, turns = _reduce_angle(th0)
    if method == "dop853":
        rtol, atol = _tolerances(rtol, atol)
        th, om = _integrated_drive(2.0 * T * record[:, None], th0[None, :], om0[None, :], T, A, l, g, c,
                                   rtol, atol, model == "linear", drive)
    else:
        plan = step_plan(drive, T, A, l, g)
        bounds = [(a, min(a + chunk, th0.size)) for a in range(0, th0.size, chunk)]
        th = np.empty((record.size, th0.size))
        om = np.empty((record.size, th0.size))
        for a, b, (th_c, om_c) in chunk_results(_map_chunk, bounds, lambda a, b: (th0[a:b], om0[a:b], plan, record,
                                                                                  model), workers, progress):
            th[:, a:b], om[:, a:b] = th_c, om_c
    th = _add_turns(th, turns)
    bad = ~(np.isfinite(th) & np.isfinite(om))
    if bad.any():
        k, i = np.argwhere(bad)[0]
        raise OverflowError(f"the motion grows beyond the range of a double (member {int(i)}, period {int(record[k])})")
    return StrobeOrbits(n=record, theta=th.reshape((record.size,) + shape), dtheta=om.reshape((record.size,) + shape),
                        T=T, A=A, l=l, g=g, c=c, model=model)
