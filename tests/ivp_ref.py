"""Independent numerics: the linear equation (2.3) integrated by scipy's DOP853.

Each half-period is integrated separately (the coefficient jumps at t = kT), so the
integrator never steps across a discontinuity; theta and theta' are carried over
unchanged at the switches (2.14). Nothing here imports kapitza.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def _rhs(s):
    def f(t, y):
        return [y[1], s * y[0]]

    return f


def motion(t_eval, theta0, dtheta0, T, A, l=1.0, g=9.81, rtol=1e-12, atol=1e-14):
    """(theta, theta') at the sorted-or-not times ``t_eval >= 0``, one solve_ivp per half-period."""
    t_eval = np.asarray(t_eval, float)
    order = np.argsort(t_eval)
    ts = t_eval[order]
    th = np.empty_like(ts)
    dth = np.empty_like(ts)
    y = np.array([theta0, dtheta0], float)
    k = 0
    i = 0
    while i < ts.size:
        t0, t1 = k * T, (k + 1) * T
        s = (g + A) / l if k % 2 == 0 else (g - A) / l
        sol = solve_ivp(_rhs(s), (t0, t1), y, method="DOP853", rtol=rtol, atol=atol, dense_output=True)
        assert sol.success
        j = i
        while j < ts.size and ts[j] < t1:
            j += 1
        if j > i:
            Y = sol.sol(ts[i:j])
            th[i:j], dth[i:j] = Y[0], Y[1]
        i = j
        y = sol.y[:, -1]
        k += 1
    out_th = np.empty_like(th)
    out_dth = np.empty_like(dth)
    out_th[order], out_dth[order] = th, dth
    return out_th, out_dth


def monodromy(T, A, l=1.0, g=9.81, rtol=1e-12, atol=1e-14):
    """M from two solves over [0, T) and [T, 2T) of the unit initial states."""
    cols = []
    for y0 in ([1.0, 0.0], [0.0, 1.0]):
        y = np.array(y0)
        for k, s in enumerate(((g + A) / l, (g - A) / l)):
            sol = solve_ivp(_rhs(s), (k * T, (k + 1) * T), y, method="DOP853", rtol=rtol, atol=atol)
            assert sol.success
            y = sol.y[:, -1]
        cols.append(y)
    return np.array(cols).T


def survived_periods(theta0, dtheta0, T, A, periods, tol, c=0.0, drive="square", l=1.0, g=9.81, samples=400,
                     rtol=1e-11, atol=1e-13):
    """Whole periods ``2T`` the full damped equation ``theta'' = (g + a(t))/l sin(theta) - c theta'`` keeps
    ``|theta| <= tol``, one trajectory, one solve_ivp per half-period sampled at ``samples`` instants.

    ``drive``: ``"square"`` (``a = +A`` then ``-A``) or ``"sine"`` (``a = A sin(pi t/T)``). Returns
    ``(periods survived, gap)``, ``gap`` the closest approach of a half-period's largest ``|theta|`` to
    ``tol`` up to the exit: a verdict with a small gap is a near miss either way."""
    y = np.array([theta0, dtheta0], float)
    gap = np.inf
    for k in range(periods):
        for half in (0, 1):
            t0, t1 = (2 * k + half) * T, (2 * k + half + 1) * T
            if drive == "square":
                s = (g + (A if half == 0 else -A)) / l

                def rhs(t, z, s=s):
                    return [z[1], s * np.sin(z[0]) - c * z[1]]
            else:
                def rhs(t, z):
                    return [z[1], (g + A * np.sin(np.pi * t / T)) / l * np.sin(z[0]) - c * z[1]]
            sol = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=rtol, atol=atol, dense_output=True)
            assert sol.success
            peak = float(np.max(np.abs(sol.sol(np.linspace(t0, t1, samples))[0])))
            gap = min(gap, abs(peak - tol))
            if peak > tol:
                return k, gap
            y = sol.y[:, -1]
    return periods, gap
