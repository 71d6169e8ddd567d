"""Verdicts to the last bit for the paper's square wave.

The closed forms give ``a = w - alpha`` and ``b = w - beta`` (``docs/theory.md`` section 5)
with an absolute error of a few units in the last place of ``u = w_e T`` (``u`` is formed from
the rounded ``eps`` and ``sqrt(1 - mu^2)``; ``alpha`` and ``beta`` are flat in ``x`` far out).
Where ``|a|`` or ``|b|`` is inside that bound the sign, and with it the verdict, the zone and
the growth, is not determined by the double computation: there ``tr M / 2`` is evaluated for
the exact double inputs in mpmath, at a precision that covers the cancellation of
``e^x``-sized terms (:func:`kapitza.drives._piecewise._tau_mp`, the product of the two phase
matrices). Such points are rare (a band a few ulp wide about each edge), so the fast path
keeps its speed.
"""
from __future__ import annotations

import numpy as np

_TOL = 16.0 * np.finfo(float).eps


#: Beyond this phase angle the exact decision would need more than ~2,000 digits: the double
#: verdict stands there (the phase ``u`` itself is then known to ``1e-16 u`` only).
MAX_PHASE = 4000.0


def unsure(u, a, b, x=None):
    """Where the signs of ``a`` or ``b`` are within rounding of zero (and an exact decision is
    affordable: ``x + u <= MAX_PHASE``)."""
    bound = _TOL * (np.abs(u) + 4.0)
    near = (np.abs(a) <= bound) | (np.abs(b) <= bound)
    size = np.abs(u) if x is None else np.abs(u) + np.abs(x)
    return near & (size <= MAX_PHASE)


def exact_half_trace(eps, mu):
    """``(tau, log|tau|, stable, angle)`` of the square wave at the exact double ``(eps, mu)``
    (mpmath): ``stable`` is ``|tau| < 1`` decided in extended precision (the float ``tau`` may
    round to 1); ``angle`` is ``acos(tau)`` on a zone and the growth ``acosh|tau|`` off it."""
    from .drives._piecewise import _tau_mp

    res = _tau_mp(np.ravel(eps), np.ravel(mu), (1.0, -1.0), (1.0, 1.0))
    shape = np.shape(eps)
    tau = np.array([r[0] for r in res]).reshape(shape)
    log_tau = np.array([r[1] for r in res]).reshape(shape)
    stable = np.array([r[2] for r in res], dtype=bool).reshape(shape)
    angle = np.array([r[3] for r in res]).reshape(shape)
    return tau, log_tau, stable, angle
