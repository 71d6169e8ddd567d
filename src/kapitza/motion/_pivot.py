"""The square-wave pivot's kinematics on trusted arrays: which phase a time is in, ``a(t)`` and its
integrals, and the checks of :mod:`kapitza.motion.pivot`'s public functions (shared with the motion
and the animation)."""
from __future__ import annotations

import numpy as np

from .. import _validate as _v


def _phase_index(t, T):
    """Phase index ``j = floor(t/T)`` (even: ``a = +A``) and the time ``r`` into it, ``0 <= r < T``.

    The one rule by which every part of the package decides which phase a time is in,
    so that a time a rounding error from a switch is never put in two phases.
    """
    j = np.floor(t / T)
    r = t - j * T
    over = r >= T
    j = np.where(over, j + 1.0, j)
    r = np.where(over, r - T, np.maximum(r, 0.0))
    return j, r


def _phase_time(t, T):
    """Time in ``[0, 2T)`` since the start of the current period, consistent with :func:`_phase_index`."""
    j, r = _phase_index(t, T)
    return np.where(np.mod(j, 2.0) == 0.0, r, r + T)


def _acceleration(t, T, A):
    j, _ = _phase_index(t, T)
    return np.where(np.mod(j, 2.0) == 0.0, A, -A)


def _velocity(t, T, A):
    r = _phase_time(t, T)
    return np.where(r < T, A * (r - 0.5 * T), -A * (r - 1.5 * T))


def _displacement(t, T, A):
    r = _phase_time(t, T)
    quarter = 0.125 * A * T * T
    return np.where(r < T, 0.5 * A * (r - 0.5 * T) ** 2 - quarter, quarter - 0.5 * A * (r - 1.5 * T) ** 2)


def _checked(t, T, A):
    t = _v.finite("t", t)
    T = _v.positive("T", T)
    A = _v.positive("A", A)
    t, T, A = _v.broadcast(t=t, T=T, A=A)
    _stroke_checked(T, A)
    _v.phase_resolved(t, T)
    return t, T, A


def _stroke_checked(T, A):
    """Refuse ``T``, ``A`` whose stroke ``A T^2 / 4`` (and so the pivot's path) is not a double."""
    with np.errstate(over="ignore"):
        bad = ~np.isfinite(0.25 * A * T * T)
    if np.any(bad):
        T, A = np.broadcast_arrays(T, A)
        raise _v.KapitzaValueError(
            f"T and A must give a finite stroke A T^2 / 4 (the pivot's travel in metres); got T = "
            f"{float(T[bad].flat[0])!r} with A = {float(A[bad].flat[0])!r}")
