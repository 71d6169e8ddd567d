"""The checks of :mod:`kapitza.motion.pivot`'s public functions (shared with the motion and the
animation); the square wave's kinematics are :class:`kapitza.SquareWave`'s own
(:mod:`kapitza._square`)."""
from __future__ import annotations

import numpy as np

from .. import _validate as _v


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
