"""Rotation numbers of the exact nonlinear stroboscopic map, measured from long runs.

The twist coefficient (:func:`kapitza.twist_coefficient`) predicts how the rotation number of
the invariant curves around the upright changes with their size, ``rho(r) = w/(2 pi) + tau r^2 +
O(r^4)``. Here the rotation number is *measured*: the exact period map (Jacobi elliptic phase
flows, ``docs/theory.md`` section 6) is iterated from ``theta = r`` on the linear map's
invariant ellipse, and the angle gained per period in the linear map's normal coordinate
``z`` (``docs/nonlinear.md`` section 3) is averaged with a smooth window (a weighted Birkhoff
average, which converges faster than any power of ``1/N`` on a smooth invariant curve).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from .._normal_form import _normal_coordinate, _normal_form, _stable_arnold, _taylor
from ..parameters import G_EARTH, to_physical
from ._elliptic import _phase_step
from ..drives import SquareWave
from ._maps import bound_ensemble, step_plan
from .nonlinear import MAX_PERIODS

__all__ = ["RotationRun", "measured_rotation_number"]


@dataclass(frozen=True)
class RotationRun:
    """Measured rotation numbers of orbits started at ``theta = r`` (arrays of the shape of ``r``).

    Attributes
    ----------
    r : ndarray
        Starting amplitude ``theta(0) = r`` [rad] on the linear map's invariant ellipse.
    rotation_number : ndarray
        Mean turns per period ``2T``, counted like ``w/(2 pi)`` (the linear map's direction).
    max_theta : ndarray
        Largest ``|theta|`` seen at the sampling instants ``t = 2kT``.
    bounded : ndarray of bool
        The orbit stayed within ``|theta| < pi/2`` (the number is meaningful only there).
    predicted : ndarray
        ``w/(2 pi) + tau r^2``, the normal form's prediction.
    eps, mu, w, twist : ndarray
        The parameters, the linear rotation ``w`` and the twist ``tau`` of each orbit.
    periods : int

    Examples
    --------
    >>> from kapitza.motion import measured_rotation_number
    >>> run = measured_rotation_number(0.5, 0.3, 0.1, periods=100)
    >>> run.rotation_number, run.predicted, run.bounded
    (np.float64(0.1282...), np.float64(0.1282...), np.True_)
    """

    r: np.ndarray
    rotation_number: np.ndarray
    max_theta: np.ndarray
    bounded: np.ndarray
    predicted: np.ndarray
    eps: np.ndarray
    mu: np.ndarray
    w: np.ndarray
    twist: np.ndarray
    periods: int

    def __post_init__(self):
        _v.scalar_fields(self)  # scalar in, numpy scalars out


def _window(n):
    t = (np.arange(n) + 0.5) / n
    g = np.exp(-1.0 / (t * (1.0 - t)))
    return g / g.sum()


@_v.shapes_named
def measured_rotation_number(eps, mu, r, *, periods=4000):
    """Rotation numbers of the exact nonlinear period map on orbits through ``max|theta| = r``.

    Parameters
    ----------
    eps, mu, r : array_like, broadcast together
        Arnold's parameters of linearly stable points, and starting amplitudes [rad],
        ``1e-150 <= r < pi/2``.
    periods : int, optional
        Number of periods ``2T`` iterated (>= 16).

    Returns
    -------
    RotationRun

    Raises
    ------
    ValueError
        If a point is not linearly stable, ``r`` is outside ``[1e-150, pi/2)``, or ``periods`` is
        below 16 or beyond its bound.

    Notes
    -----
    The start is the point of largest ``theta`` on the linear map's invariant ellipse through
    ``theta = r``: ``(theta, T theta') = (r, r (cos w - m11) / m12)``. The nonlinear invariant
    curve through it differs from the ellipse at relative order ``r^2``, which changes
    ``rho`` at order ``r^4``. The result depends on ``eps, mu`` only (the run uses ``l = 1``,
    ``g = 9.81``).

    Examples
    --------
    The twist at work: orbits further out turn more slowly (``tau < 0`` here), as the normal form
    predicts:

    >>> from kapitza.motion import measured_rotation_number
    >>> run = measured_rotation_number(0.5, 0.3, [0.01, 0.1], periods=100)
    >>> run.rotation_number
    array([0.1289..., 0.1282...])
    >>> run.predicted
    array([0.1289..., 0.1282...])
    """
    eps, mu = _stable_arnold(eps, mu)
    # below 1e-150 the orbit is the linear one, and its normal coordinates leave the normal doubles
    r = _v.in_range("r", r, 1e-150, 0.5 * np.pi, lo_open=False)
    periods = _v.bounded_count("periods", periods, MAX_PERIODS, minimum=16)
    eps, mu, r = np.broadcast_arrays(eps, mu, r)
    bound_ensemble(periods, r.size)
    shape = r.shape
    eps, mu, r = (a.ravel() for a in (eps, mu, r))
    nf, _ = _normal_form(eps, mu)
    M, _ = _taylor(eps, mu)
    m11, m12 = M[..., 0, 0], M[..., 0, 1]
    w = nf.w
    lam = np.exp(1j * w)
    T, A = to_physical(eps, mu, 1.0, G_EARTH)
    plan = step_plan(SquareWave(), T, A, 1.0, G_EARTH)  # (the normal form is the square wave's)
    f = _normal_coordinate(M, lam)[2]
    f1, f2 = f[..., 0], f[..., 1]
    th = r.copy()
    om = th * (np.cos(w) - m11) / m12 / T
    z = f1 * th + f2 * om * T
    weights = _window(periods)
    acc = np.zeros(th.size)
    top = np.abs(th)
    for k in range(periods):
        for s, dur in plan:
            th, om = _phase_step(th, om, s, dur)
        znew = f1 * th + f2 * om * T
        # the angle gained beyond the linear rotation is small: no branch ambiguity
        acc += weights[k] * (w + np.angle(znew / (lam * z)))
        z = znew
        top = np.maximum(top, np.abs(th))
    rho = acc / (2.0 * np.pi)
    out = dict(r=r, rotation_number=rho, max_theta=top, bounded=top < 0.5 * np.pi,
               predicted=w / (2.0 * np.pi) + nf.twist * r * r, eps=eps, mu=mu, w=w, twist=nf.twist)
    return RotationRun(periods=periods, **{k: v.reshape(shape) for k, v in out.items()})
