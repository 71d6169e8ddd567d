"""Classical approximations of the first stability zone, compared with the exact one in Figure 8.

Three approximations, each derived here (and checked in :mod:`kapitza.paper.checks`):

1. **Kapitza's averaging criterion.** Writing ``theta = Theta + xi`` with a fast
   part ``xi = (z(t)/l) sin Theta`` (``z`` the pivot displacement, ``z'' = a``) and
   averaging ``theta'' = (g + a)/l sin theta`` over one period gives
   ``Theta'' = (g/l) sin Theta - (<v^2>/l^2) sin Theta cos Theta`` with ``v = z'``
   (``<a z> = <z'' z> = -<v^2>``). The upright position is stable iff
   ``<v^2> > g l``. For the square wave (2.2) the zero-mean pivot velocity is a
   triangle wave of amplitude ``A T / 2``, so ``<v^2> = A^2 T^2 / 12`` and, since
   ``A^2 T^2 / (12 g l) = (2/3) eps^2 / mu^2``, the criterion is
   ``eps > sqrt(3/2) mu``: a straight line through the origin of the
   ``eps``-``mu`` plane, with no upper edge.

2. **The small-``eps`` expansion of the trace.** With ``s = 2 sqrt 2 eps``,
   ``x = s sqrt(1 + mu^2)``, ``u = s sqrt(1 - mu^2)`` one has
   ``cosh x cos u = Re cosh(s w)`` and ``sinh x sin u = Im cosh(s w)`` with
   ``w^2 = 2 (mu^2 + i sqrt(1 - mu^4)) = 2 e^{i psi}``, ``cos psi = mu^2``. Hence
   the exact, everywhere convergent series ::

       tr M / 2 = sum_{j >= 0} (4 eps)^{2j} / (2j)! * U_j(mu^2),

   ``U_j`` the Chebyshev polynomials of the second kind (``U_j(cos psi) =
   sin((j+1) psi) / sin psi``). Truncated after ``eps^4`` (the order at which
   Arnold [1] estimates the zones) it reads
   ``1 + 16 mu^2 eps^2 - (32/3)(1 - 4 mu^4) eps^4`` and gives both edges in closed
   form: ``tr M = 2`` at ``eps^2 = (3/2) mu^2 / (1 - 4 mu^4)`` and ``tr M = -2`` at
   the positive root of ``(32/3)(1 - 4 mu^4) E^2 - 16 mu^2 E - 2 = 0``,
   ``E = eps^2`` (both need ``mu < 1/sqrt 2``).

3. **The lower edge as a series in mu.** Inverting the series of ``tr M = 2`` term
   by term gives ``eps^2 = (3/2) mu^2 (1 + (8/7) mu^4 + (16848/13475) mu^8 + ...)``
   (odd powers of ``mu^2`` in the bracket vanish). Its first term is Kapitza's
   criterion, whose relative error along the lower edge is therefore
   ``-(4/7) mu^4 + O(mu^8)``.

References: [1] V. I. Arnold, *Ordinary Differential Equations*; [14] P. L. Kapitsa,
*Dynamical stability of a pendulum when its point of suspension vibrates* (numbers
as in the paper's bibliography).
"""
from __future__ import annotations

import numpy as np

from .. import _validate as _v

__all__ = [
    "KAPITZA_SLOPE",
    "kapitza_edge",
    "mean_square_velocity",
    "trace_series",
    "series4_edges",
    "lower_edge_series",
    "LOWER_EDGE_COEFFS",
]

#: Kapitza's criterion is ``eps > KAPITZA_SLOPE * mu``.
KAPITZA_SLOPE = float(np.sqrt(1.5))

#: ``eps_lo^2 = (3/2) mu^2 (1 + sum_k c_k mu^(4k))``: the coefficients ``c_1, c_2``.
LOWER_EDGE_COEFFS = (8.0 / 7.0, 16848.0 / 13475.0)


def kapitza_edge(mu):
    """Lower edge ``eps = sqrt(3/2) mu`` of the first zone by Kapitza's averaging criterion.

    Parameters
    ----------
    mu : array_like
        ``mu = sqrt(g/A)``, finite and > 0.

    Returns
    -------
    ndarray
        The ``eps`` above which ``<v^2> = A^2 T^2 / 12`` exceeds ``g l``.

    Notes
    -----
    Derived in the module docstring; it is the high-frequency limit of the exact
    lower edge of zone 0 (eq. 3.10 with ``k = 0``), with relative error
    ``-(4/7) mu^4 + O(mu^8)``.
    """
    mu = _v.positive("mu", mu)
    return KAPITZA_SLOPE * mu


def mean_square_velocity(A, T):
    """``<v^2> = A^2 T^2 / 12``, the mean square of the pivot velocity
    (:func:`kapitza.motion.pivot_velocity`, a triangle wave of amplitude ``A T / 2``) over a period.

    Parameters
    ----------
    A, T : array_like, broadcast together
        Each > 0.

    Returns
    -------
    ndarray
    """
    A = _v.positive("A", A)
    T = _v.positive("T", T)
    return A * A * T * T / 12.0


def _chebyshev_u(j_max, x):
    """``U_0(x) .. U_{j_max}(x)`` stacked on a new first axis."""
    U = [np.ones_like(x), 2.0 * x]
    for _ in range(2, j_max + 1):
        U.append(2.0 * x * U[-1] - U[-2])
    return np.stack(U[: j_max + 1])


def trace_series(eps, mu, order=4):
    """``tr M / 2`` summed up to the power ``eps^order`` of its exact Taylor series.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        ``eps > 0`` and ``0 < mu < 1``.
    order : int
        Even, ``>= 0``: the highest power of ``eps`` kept.

    Returns
    -------
    ndarray
        ``sum_{j <= order/2} (4 eps)^{2j} / (2j)! U_j(mu^2)``.

    Notes
    -----
    The exact trace of ``docs/theory.md`` section 3 is the sum of the whole series
    (module docstring); a high ``order`` reproduces it, ``order = 4`` is the
    Arnold-type truncation used for Figure 8.
    """
    eps = _v.positive("eps", eps)
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    order = int(_v.nonnegative_int("order", order))
    if order % 2:
        raise _v.KapitzaValueError(f"order must be even; got {order}")
    eps, mu = np.broadcast_arrays(eps, mu)
    jmax = order // 2
    U = _chebyshev_u(max(jmax, 1), mu * mu)
    z = 16.0 * eps * eps
    total = np.zeros(eps.shape)
    term = np.ones(eps.shape)
    for j in range(jmax + 1):
        if j:
            term = term * z / ((2 * j - 1) * (2 * j))
        total = total + term * U[j]
    return total


def series4_edges(mu):
    """Edges of the first zone from the ``eps^4`` truncation of ``tr M``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.

    Returns
    -------
    eps_lo, eps_hi : ndarray
        Where ``1 + 16 mu^2 eps^2 - (32/3)(1 - 4 mu^4) eps^4`` equals ``+1``
        respectively ``-1``; NaN where ``mu >= 1/sqrt 2`` (the truncated trace then
        never comes back down).

    Notes
    -----
    ``eps_lo^2 = (3/2) mu^2 / (1 - 4 mu^4)``; ``eps_hi^2`` is the positive root
    ``E`` of ``(32/3) c E^2 - 16 mu^2 E - 2 = 0`` with ``c = 1 - 4 mu^4``
    (``eps_hi -> (3/16)^(1/4) = 0.658`` as ``mu -> 0``).
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    m2 = mu * mu
    c = (1.0 - 2.0 * m2) * (1.0 + 2.0 * m2)
    ok = c > 0
    cs = np.where(ok, c, 1.0)
    lo2 = 1.5 * m2 / cs
    a = 32.0 / 3.0 * cs
    hi2 = (16.0 * m2 + np.sqrt(256.0 * m2 * m2 + 8.0 * a)) / (2.0 * a)
    nan = np.full(np.shape(mu), np.nan)
    return np.where(ok, np.sqrt(lo2), nan), np.where(ok, np.sqrt(hi2), nan)


def lower_edge_series(mu, terms=2):
    """The lower edge of the first zone from its series in ``mu``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1`` (useful for ``mu`` below about 0.5).
    terms : {1, 2, 3}
        Terms of ``eps^2 = (3/2) mu^2 (1 + (8/7) mu^4 + (16848/13475) mu^8)`` kept;
        ``terms = 1`` is Kapitza's criterion.

    Returns
    -------
    ndarray
        ``eps``; relative error ``O(mu^(4 terms))``.

    Notes
    -----
    Obtained by substituting ``eps^2 = (3/2) mu^2 (1 + c_1 mu^2 + c_2 mu^4 + ...)``
    into the series of :func:`trace_series` and setting ``tr M = 2`` (eq. 3.10,
    ``k = 0``) order by order.
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    terms = int(_v.nonnegative_int("terms", terms, minimum=1))
    if terms > 1 + len(LOWER_EDGE_COEFFS):
        raise _v.KapitzaValueError(f"terms must be 1, 2 or 3; got {terms}")
    m4 = mu**4
    bracket = np.ones_like(mu)
    for k, c in enumerate(LOWER_EDGE_COEFFS[: terms - 1], start=1):
        bracket = bracket + c * m4**k
    return KAPITZA_SLOPE * mu * np.sqrt(bracket)
