"""Independent numerics for any drive: the monodromy of phi'' = 8 eps^2 (mu^2 + s(tau)) phi
over one period by scipy's DOP853, piece by piece between the shape's breakpoints (the
integrator never steps across a kink or a jump). Nothing here imports kapitza."""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def half_trace(shape, eps, mu, breaks=(), rtol=1e-12):
    """``tr M / 2`` of one period ``tau in [0, 2]``."""
    E = 8.0 * eps * eps
    pts = [0.0, *sorted(breaks), 2.0]
    cols = []
    for y0 in ((1.0, 0.0), (0.0, 1.0)):
        y = np.array(y0)
        for a, b in zip(pts[:-1], pts[1:]):
            top = np.nextafter(b, a)  # the piece's own value up to its end (no jump seen inside)

            def f(t, v, a=a, top=top):
                return [v[1], E * (mu * mu + float(shape(np.array(min(max(t, a), top))))) * v[0]]

            sol = solve_ivp(f, (a, b), y, method="DOP853", rtol=rtol, atol=1e-14 * max(1.0, np.abs(y).max()))
            assert sol.success
            y = sol.y[:, -1]
        cols.append(y)
    M = np.array(cols).T
    return 0.5 * (M[0, 0] + M[1, 1])


def edge(shape, mu, lo, hi, sign, breaks=()):
    """Root of ``tr M / 2 = sign`` between ``lo`` and ``hi`` (DOP853 traces)."""
    return brentq(lambda e: half_trace(shape, e, mu, breaks) - sign, lo, hi, xtol=1e-14, rtol=1e-13)
