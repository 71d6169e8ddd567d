"""The exact path's survival searches, compiled per state (numba): the twin of the numpy loops.

The numpy path (:func:`kapitza.motion.basins.survival_chunk`, :func:`kapitza.sweeps.kernel.ray_radii`)
advances every state of a chunk together, one period per Python iteration, so its cost per state is
set by numpy's per-call overhead once few states remain. Here each state (one start, or one radius
search: a scan then a bisection) runs to its end inside compiled code, one state at a time, so the
cost per state does not depend on how many are in a chunk.

It is one definition of the same mathematics, scalar by scalar:

* the phase flow of :func:`kapitza.motion._elliptic._phase_step` (the pendulum in half-angle
  variables advanced by the addition theorems of ``sn, cn, dn``; ``docs/theory.md`` section 6),
  with the same branches: the complementary-nome theta series for ``1 - m < 1/2``, the
  arithmetic-geometric mean (DLMF 22.20(ii), the algorithm of :func:`scipy.special.ellipj`) for
  ``m <= 1/2``,
  the reciprocal-modulus transformation for rotations and the same quarter-period reductions;
* the window test of :func:`kapitza.motion._periods._one_period` (end points of each sub-step, and the
  turning amplitude ``2 asin k`` where ``theta'`` changes sign in an elliptic phase);
* the scan and bisection of :func:`kapitza.sweeps.kernel.ray_radii`, candidate by candidate.

The two paths agree to rounding: ``K(m)`` is computed here by the AGM rather than by Cephes'
polynomial, and the elementary functions are the C library's rather than numpy's, so a trajectory can
differ in its last bits, and a start that leaves the window by less than that can be judged
differently (the tests compare both paths on maps and on single starts). Compiled functions are
cached on disk (``cache=True``), so only the first run on a machine pays the compilation.

Needs numba (the ``fast`` extra), imported with this module: import it only where it is used
(:func:`kapitza.sweeps.kernel.compiled_available` says whether it can be).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._elliptic import _nome, _theta_quotients

__all__ = ["pack_plan", "ray_radii_compiled", "survival_compiled", "phase_step"]

#: Every kernel: compiled at first use, and cached on disk (``__pycache__`` beside this file, or
#: numba's user cache where that is not writable), so later runs load it in milliseconds.
_jit = njit(cache=True, nogil=True, error_model="numpy")
PI = math.pi
TWO_PI = 2.0 * math.pi
FOUR_PI = 4.0 * math.pi
MACHEP = 1.11022302462515654042e-16


def pack_plan(subs, n_points):
    """``(S, H, CNT)`` arrays of shape ``(n_points, phases)`` from the ``(s, h, count)`` sub-steps of
    :class:`kapitza.motion._periods._ExactPeriod` (scalars, or arrays with one entry per point)."""
    nph = len(subs)
    S = np.empty((n_points, nph))
    H = np.empty((n_points, nph))
    CNT = np.empty((n_points, nph), dtype=np.int64)
    for j, (s, h, count) in enumerate(subs):
        S[:, j] = np.broadcast_to(np.asarray(s, float), (n_points,))
        H[:, j] = np.broadcast_to(np.asarray(h, float), (n_points,))
        CNT[:, j] = np.broadcast_to(np.asarray(count, np.int64), (n_points,))
    return S, H, CNT


def ray_radii_compiled(point, cos, sin_omega, S, H, CNT, periods, tol, accuracy, floor):
    """Largest safe radius of each search (as :func:`kapitza.sweeps.kernel.ray_radii`): search ``i``
    starts at ``r (cos[i], sin_omega[i])`` on the parameters of row ``point[i]`` of the plan."""
    out = np.empty(np.size(point))
    ray_radii_kernel(np.ascontiguousarray(point, np.int64), np.ascontiguousarray(cos, float),
                     np.ascontiguousarray(sin_omega, float), S, H, CNT, int(periods), float(tol), float(accuracy),
                     float(floor), out)
    return out


def survival_compiled(theta, dtheta, point, S, H, CNT, periods, tol):
    """Periods each start stays within ``tol`` (as :func:`kapitza.motion.basins.survival_chunk`)."""
    out = np.empty(np.size(theta), dtype=np.int64)
    survival_kernel(np.ascontiguousarray(theta, float), np.ascontiguousarray(dtheta, float),
                    np.ascontiguousarray(point, np.int64), S, H, CNT, int(periods), float(tol), out)
    return out


@_jit
def rint(x):
    return np.rint(x)

@_jit
def fmod_pos(x, y):
    # numpy's mod: the result has the sign of y
    r = x - math.floor(x / y) * y
    if r >= y:
        r -= y
    return r

#: the theta-series arithmetic of the numpy path, compiled from the same functions
nome = _jit(_nome)
theta_quotients = _jit(_theta_quotients)


@_jit
def series(t, m1):
    """``sn, cn, dn, K, j`` for ``0 <= m1 <= 1/2`` (:func:`kapitza.motion._elliptic._series`)."""
    q, th3, th4, th2n, K1 = nome(m1)
    if q > 0.0:
        logq = math.log(q)
        K = K1 * (-logq) / PI
        j = rint(t / K)
        t = t - j * K
    else:
        logq = -np.inf
        K = np.inf
        j = 0.0
    y = abs(t) * (0.5 * PI / K1)
    e = math.exp(-2.0 * y)
    r = math.exp(min(logq + 2.0 * y, 0.0)) if q > 0.0 else 0.0
    sn, cn, dn = theta_quotients(t, e, q, r, th3, th4, th2n)
    return sn, cn, dn, K, j

@_jit
def ellipk_agm(m):
    """``K(m) = pi / (2 AGM(1, sqrt(1 - m)))``, ``0 <= m <= 1/2``."""
    a = 1.0
    b = math.sqrt(1.0 - m)
    for _ in range(10):
        if abs(a - b) <= 1e-16 * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return PI / (a + b)

@_jit
def ellpj(u, m, work):
    """``sn, cn, dn`` of ``(u | m)``, ``0 <= m <= 1/2``: the descending Landen (AGM) scale of
    :func:`scipy.special.ellipj` (Cephes ``ellpj``, DLMF 22.20(ii))."""
    if m < 1e-9:
        t = math.sin(u)
        b = math.cos(u)
        ai = 0.25 * m * (u - t * b)
        return t - ai * b, b + ai * t, 1.0 - 0.5 * m * t * t
    a = work[:9]  # scratch of the caller: no allocation per call
    c = work[9:18]
    a[0] = 1.0
    b = math.sqrt(1.0 - m)
    c[0] = math.sqrt(m)
    twon = 1.0
    i = 0
    while abs(c[i] / a[i]) > MACHEP and i < 8:
        ai = a[i]
        i += 1
        c[i] = (ai - b) / 2.0
        t = math.sqrt(ai * b)
        a[i] = (ai + b) / 2.0
        b = t
        twon *= 2.0
    phi = twon * a[i] * u
    b = phi
    while i > 0:
        t = c[i] * math.sin(phi) / a[i]
        b = phi
        phi = (math.asin(t) + phi) / 2.0
        i -= 1
    sn = math.sin(phi)
    cn = math.cos(phi)
    dnfac = math.cos(phi - b)
    if abs(dnfac) < 0.1:
        dn = math.sqrt(1.0 - m * sn * sn)
    else:
        dn = cn / dnfac
    return sn, cn, dn

@_jit
def jacobi(u, m1, work):
    """``sn, cn, dn, K`` of ``(u | 1 - m1)`` (:func:`kapitza.motion._elliptic._jacobi`)."""
    if m1 < 0.5:
        sn, cn, dn, K, j = series(u, m1)
    else:
        m = 1.0 - m1
        K = ellipk_agm(m)
        j = rint(u / K)
        sn, cn, dn = ellpj(u - j * K, m, work)
    jm = fmod_pos(j, 4.0)
    if jm != 0.0:
        kp = math.sqrt(m1)
        odd = jm == 1.0 or jm == 3.0
        sgn = -1.0 if jm >= 2.0 else 1.0
        rdn = 1.0 / dn
        if odd:
            sn, cn, dn = sgn * cn * rdn, sgn * (-kp * sn * rdn), kp * rdn
        else:
            sn, cn = sgn * sn, sgn * cn
    return sn, cn, dn, K

@_jit
def pendulum(S, C, Dn, h0, s, work):
    """Advance ``q'' = -sin q`` by the scaled time ``s`` (:func:`kapitza.motion._elliptic._pendulum`)."""
    m = S * S + C * C
    m1 = (Dn - C) * (Dn + C)
    rot = m1 < 0.0
    half_period = 0.0
    if not rot:
        sn, cn, dn, _ = jacobi(s, m1, work)
    else:
        k = math.sqrt(m)
        snr, cnr, dnr, Kr = jacobi(k * s, -m1 / m, work)
        sn = snr / k
        cn = dnr
        dn = cnr
        half_period = 2.0 * Kr / k
    den = cn * cn + Dn * Dn * sn * sn
    S1 = (S * cn * dn + sn * C * Dn) / den
    C1 = (C * cn - S * Dn * sn * dn) / den
    D1 = (Dn * dn - S * C * sn * cn) / den
    nb = rint(h0 / PI)
    sg = 1.0 - 2.0 * fmod_pos(nb, 2.0)
    h1 = nb * PI + math.atan2(sg * S1, sg * D1)
    if rot:
        sp = 1.0 if C >= 0.0 else -1.0
        n = math.floor(s / half_period)
        par = 1.0 - 2.0 * fmod_pos(n, 2.0)
        a = math.atan2(par * S1, par * D1)
        delta = fmod_pos(sp * (a - h0), TWO_PI)
        if delta > 1.5 * PI:
            delta -= TWO_PI
        h1 = h0 + sp * (n * PI + delta)
    return S1, C1, D1, h1

@_jit
def phase_step(theta, dtheta, s2, t, work):
    """Exact flow of ``theta'' = s2 sin(theta)`` over ``t`` (:func:`kapitza.motion._elliptic._phase_step`)."""
    if s2 == 0.0:
        return theta + dtheta * t, dtheta
    w = math.sqrt(abs(s2))
    half = 0.5 * theta
    sh = math.sin(half)
    ch = math.cos(half)
    C = dtheta / (2.0 * w)
    if s2 > 0.0:
        S1, C1, D1, h1 = pendulum(ch, C, -sh, half + 0.5 * PI, w * t, work)
        sin_half, cos_half, coarse = -D1, S1, 2.0 * h1 - PI
    else:
        S1, C1, D1, h1 = pendulum(sh, C, ch, half, w * t, work)
        sin_half, cos_half, coarse = S1, D1, 2.0 * h1
    fine = 2.0 * math.atan2(sin_half, cos_half)
    return fine + FOUR_PI * rint((coarse - fine) / FOUR_PI), 2.0 * w * C1

@_jit
def sign(x):
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)

@_jit
def one_period(th, om, S, H, CNT, p, tol, work):
    """One period of the parameters of row ``p``; ``left``: the window was left during it
    (:func:`kapitza.motion._periods._one_period`, nonlinear model)."""
    for j in range(S.shape[1]):
        s = S[p, j]
        h = H[p, j]
        for _ in range(CNT[p, j]):
            th1, om1 = phase_step(th, om, s, h, work)
            if abs(th1) > tol:
                return th1, om1, True
            if s < 0.0 and sign(om1) * sign(om) < 0.0:
                w = math.sqrt(-s)
                k = math.hypot(math.sin(0.5 * th), om / (2.0 * w))
                if 2.0 * math.asin(min(k, 1.0)) > tol:
                    return th1, om1, True
            th, om = th1, om1
    return th, om, False

@_jit
def periods_inside(th, om, S, H, CNT, p, periods, tol, work):
    """Whole periods completed inside the window (``periods`` if it never leaves)."""
    if abs(th) > tol:
        return 0
    for k in range(periods):
        th, om, left = one_period(th, om, S, H, CNT, p, tol, work)
        if left:
            return k
    return periods

@_jit
def survival_kernel(theta, dtheta, point, S, H, CNT, periods, tol, out):
    work = np.empty(18)
    for i in range(theta.size):
        out[i] = periods_inside(theta[i], dtheta[i], S, H, CNT, point[i], periods, tol, work)

@_jit
def ray_step(inside, r, lo, hi, scanning, tol, accuracy, floor):
    """One step of the search for the largest start radius along a ray that stays inside (both compiled
    kernels' ``ray_radii_kernel``): from ``r = tol`` halve ``r`` until a start stays inside (none above
    ``floor``: the radius is 0), then bisect ``[lo, hi]`` to the relative ``accuracy``. ``inside``:
    whether the start at ``r`` stayed. Returns ``(done, r, lo, hi, scanning)`` with the next ``r``;
    the radius is ``lo`` when done."""
    if inside:
        lo = r
        scanning = False
    elif scanning:
        hi = r
        r = 0.5 * r
        return r < floor, r, lo, hi, scanning
    else:
        hi = r
    if lo >= tol or hi - lo <= accuracy * lo:
        return True, r, lo, hi, scanning
    return False, 0.5 * (lo + hi), lo, hi, scanning


@_jit
def ray_radii_kernel(point, cos, sin_omega, S, H, CNT, periods, tol, accuracy, floor, out):
    work = np.empty(18)
    for i in range(point.size):
        r, lo, hi, scanning, done = tol, 0.0, np.inf, True, False
        while not done:
            inside = periods_inside(r * cos[i], r * sin_omega[i], S, H, CNT, point[i], periods, tol, work) >= periods
            done, r, lo, hi, scanning = ray_step(inside, r, lo, hi, scanning, tol, accuracy, floor)
        out[i] = lo

