"""One-period steps of the survival loop (:func:`kapitza.motion.basins.survival_chunk`), shared by the
basins and the sweep's kernel: the exact path (:class:`_ExactPeriod`, the window checked on the
continuous motion) and the integrated path (:class:`_IntegratedPeriod`, DOP853, the window checked at
samples and between them on a Hermite interpolant); :mod:`kapitza.motion.basins` says when each holds."""
from __future__ import annotations

import numpy as np

from ._integrate import _identity, _peak, _solve
from ._maps import AMPLITUDES, STEPS


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


class _ExactPeriod:
    """One period of exact step flows (undamped, piecewise-constant drive), the window checked on
    the continuous motion (module notes).

    ``plan``: the ``(s, duration)`` phases of one period, each a scalar or an array with one entry
    per parameter set. ``scaled``: the longest sub-step in scaled time ``w h``; the test is exact
    for any ``scaled < pi``. Calling it with ``(theta, dtheta, idx)`` advances the states by one
    period (``idx``: the parameter set of each state; ignored for scalar parameters) and returns
    ``(theta, dtheta, left)``, ``left`` true where the state left the window during the period.
    """

    def __init__(self, plan, tol, model="nonlinear", scaled=1.0):
        self.subs = [_sub_steps(s, dur, scaled) for s, dur in plan]
        self.per_state = any(np.ndim(c) > 0 for _, _, c in self.subs)
        self.tol = tol
        self.model = model

    def __call__(self, th, om, idx):
        subs = ([tuple(v[idx] if np.ndim(v) else v for v in sub) for sub in self.subs] if self.per_state
                else self.subs)
        return _one_period(th, om, subs, self.tol, self.model)


#: Integrated path: DOP853 tolerances (per component: scaled by ``1/sqrt(2n)`` for ``n`` states
#: solved together, as the RMS error norm of scipy is looser by that factor).
INTEGRATED_RTOL = 1e-9
INTEGRATED_ATOL = 1e-12
#: Integrated path: the window is checked at instants evenly spaced over the period, at least
#: this many per period, and dense enough that ``(w_h + c) dt <= SAMPLE_SPACING``.
MIN_SAMPLES = 64
SAMPLE_SPACING = 0.2


def _hermite_peak(p0, p1, m0, m1):
    """Largest ``|p(x)|`` on ``0 <= x <= 1`` of the cubic Hermite interpolant with values ``p0, p1``
    and slopes ``m0, m1`` (per unit ``x``) at the ends; arrays broadcast together."""
    a = 6.0 * (p0 - p1) + 3.0 * (m0 + m1)  # p'(x) = a x^2 + b x + m0
    b = -6.0 * (p0 - p1) - 4.0 * m0 - 2.0 * m1
    peak = np.maximum(np.abs(p0), np.abs(p1))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        disc = b * b - 4.0 * a * m0
        sq = np.sqrt(np.maximum(disc, 0.0))
        q = -0.5 * (b + np.where(b >= 0, sq, -sq))
        lin = -m0 / b  # a = 0: one root of the linear p'
        for x in (np.where(a != 0, q / a, lin), np.where(q != 0, m0 / q, lin)):
            ok = (disc >= 0) & np.isfinite(x) & (x > 0) & (x < 1)
            x = np.where(ok, x, 0.0)
            x2, x3 = x * x, x * x * x
            p = ((2 * x3 - 3 * x2 + 1) * p0 + (x3 - 2 * x2 + x) * m0 + (-2 * x3 + 3 * x2) * p1
                 + (x3 - x2) * m1)
            peak = np.where(ok, np.maximum(peak, np.abs(p)), peak)
    return peak


class _IntegratedPeriod:
    """One period by DOP853, for any drive and damping ``c >= 0``; the window checked at samples.

    All states advance in one ``solve_ivp`` call per segment of the drive (one for a smooth drive,
    one per step of a piecewise-constant one: never across a jump), in the period's own time
    ``x = t / (2T)``, so states with different ``T`` advance together:
    ``theta_x = 2T theta'``, ``theta'_x = 2T (s(x) f(theta) - c theta')``, ``s = (g + a)/l``.
    The tolerances ``rtol``, ``atol`` hold per component. ``|theta| <= tol`` is checked at the
    instants ``x = j / m`` (``m >= MIN_SAMPLES``, ``(w_h + c) 2T / m <= SAMPLE_SPACING`` for every
    parameter set, ``w_h = sqrt((g + peak A)/l)``) and between them on the cubic Hermite
    interpolant through ``(theta, theta')``, whose error is about ``(w dt)^4 / 384`` of the swing
    (``< 5e-6`` at the spacing 0.2): sampled, not exact.

    ``T``, ``A``: scalars or arrays with one entry per parameter set (``idx`` of the call picks
    them); ``l``, ``g``, ``c``: scalars. Calling it as :class:`_ExactPeriod`.
    """

    def __init__(self, T, A, l, g, c, drive, tol, model="nonlinear", rtol=INTEGRATED_RTOL, atol=INTEGRATED_ATOL):
        T, A = np.broadcast_arrays(np.atleast_1d(np.asarray(T, float)), np.atleast_1d(np.asarray(A, float)))
        self.T2, self.A = 2.0 * T, A
        self.l, self.g, self.c = float(l), float(g), float(c)
        self.drive, self.tol, self.model = drive, tol, model
        self.rtol, self.atol = rtol, atol
        steps = drive._steps()
        if steps is not None:
            marks = np.concatenate([[0.0], np.cumsum(steps[1])])
            marks[-1] = 1.0
            self.segments = [(float(a), float(b), float(lev)) for a, b, lev in zip(marks[:-1], marks[1:], steps[0])
                             if b > a]
        else:
            self.segments = [(0.0, 1.0, None)]
        w = np.sqrt((self.g + _peak(drive) * A) / self.l) + self.c
        m = max(MIN_SAMPLES, int(np.ceil(float(np.max(w * self.T2)) / SAMPLE_SPACING)))
        grid = np.linspace(0.0, 1.0, m + 1)
        self.samples = m
        self.evals = [np.unique(np.concatenate([grid[(grid > a) & (grid < b)], [b]])) for a, b, _ in self.segments]

    def __call__(self, th, om, idx):
        n = th.size
        left = np.zeros(n, dtype=bool)
        if n == 0:
            return th, om, left
        one = self.T2.size == 1
        T2 = self.T2[0] if one else self.T2[idx]
        A = self.A[0] if one else self.A[idx]
        sin = _identity if self.model == "linear" else np.sin
        g, l, c, drive = self.g, self.l, self.c, self.drive
        scale = 1.0 / np.sqrt(2.0 * n)
        rtol, atol = max(self.rtol * scale, 1e-13), self.atol * scale
        y = np.concatenate([th, om])
        for (a, b, lev), x_eval in zip(self.segments, self.evals):
            if lev is not None:
                k = T2 * (g + A * lev) / l

                def rhs(_, z, k=k, f=sin):
                    return np.concatenate([T2 * z[n:], k * f(z[:n]) - (T2 * c) * z[n:]])
            else:
                def rhs(x, z, f=sin):  # type: ignore[misc]  # (the other branch binds its constant)
                    s = (g + A * drive._shape(np.mod(2.0 * x, 2.0))) / l
                    return np.concatenate([T2 * z[n:], T2 * (s * f(z[:n]) - c * z[n:])])
            sol = _solve(rhs, a, b, y, rtol, atol, t_eval=x_eval)
            ths = np.concatenate([y[:n, None], sol.y[:n]], axis=1)
            slopes = np.concatenate([y[n:, None], sol.y[n:]], axis=1) * np.reshape(T2, (-1, 1))
            h = np.diff(np.concatenate([[a], x_eval]))
            left |= np.max(_hermite_peak(ths[:, :-1], ths[:, 1:], h * slopes[:, :-1], h * slopes[:, 1:]),
                           axis=1) > self.tol
            y = sol.y[:, -1]
        return y[:n], y[n:], left
