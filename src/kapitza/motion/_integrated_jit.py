"""The integrated path's survival searches, compiled per state (numba): the twin of the DOP853 loop.

The numpy path (:class:`kapitza.motion.basins._IntegratedPeriod`, driven by
:func:`kapitza.sweeps.kernel.ray_radii` and :func:`kapitza.motion.basins.survival_chunk`) advances
all the states of a block together, one ``solve_ivp`` call per segment of the drive and per period,
so its cost per state is set by scipy's per-step overhead once few states remain. Here each state
(one start, or one radius search: a scan then a bisection, as in :mod:`._survival_jit`) runs to its
end inside compiled code, one state at a time.

It is one definition of the same mathematics, scalar by scalar:

* the equation in the period's own time ``x = t / (2T)``, ``0 <= x <= 1``:
  ``theta_x = 2T theta'``, ``theta'_x = 2T (s(x) sin(theta) - c theta')``, ``s = (g + A shape)/l``;
* **DOP853** as :class:`scipy.integrate.DOP853` does it: its coefficients (imported from scipy,
  not copied), its error norm (the 5th- and 3rd-order estimates combined), its step control
  (safety 0.9, factors 0.2 to 10, exponent ``-1/8``, no growth right after a rejection), its
  initial step (Hairer, Norsett and Wanner II.4) and its 7th-order dense output;
* the tolerances of the numpy path, ``INTEGRATED_RTOL`` and ``INTEGRATED_ATOL`` per component
  (imported from :mod:`kapitza.motion.basins`): the error norm over the state's two components
  ``(theta, theta')`` is scipy's with ``n = 1``, i.e. the bound ``sqrt(sum (e_i / sc_i)^2) <= 1``,
  ``sc_i = atol + rtol max(|y_i|, |y_i new|)``, with ``rtol / sqrt 2``, ``atol / sqrt 2`` as the numpy
  path scales them for one state. (The numpy path applies the same bound to the sum over all the
  states of a call, with one step for all: its local errors are at most these, often smaller);
* never a step across a segment of the drive: every period restarts at each jump (piecewise-constant
  drives) or kink (piecewise-linear ones), the step size proposed for each segment carried over from
  the previous period (scipy restarts each ``solve_ivp`` call with its initial-step guess);
* the window test of :class:`~kapitza.motion.basins._IntegratedPeriod`, unchanged: ``|theta| <= tol``
  at the instants ``x = j / m`` of the period and at the segments' ends (from the dense output, as
  ``solve_ivp``'s ``t_eval``), and between consecutive instants on the cubic Hermite interpolant
  through ``(theta, theta')`` (its interior extrema by the same quadratic). ``m`` is chosen as there,
  ``m >= MIN_SAMPLES`` and ``(w_h + c) 2T / m <= SAMPLE_SPACING`` (imported), but for each point on
  its own rather than for the block's largest ``w_h 2T``: the test meets the same stated accuracy,
  and a point's value does not depend on the block it is computed in. Where the numpy path's block
  has a larger ``m`` it checks more instants (by at most the Hermite interpolant's error, about
  ``(w dt)^4 / 384`` of the swing, ``< 5e-6`` at the spacing 0.2, the two tests can differ);
* the scan and bisection of :func:`kapitza.sweeps.kernel.ray_radii`, candidate by candidate.

The drive must be evaluated in compiled code, so it is given as a table of segments over
``0 <= x <= 1`` (:func:`drive_table`), on each ``shape = a + b (x - x_k) + d sin(2 pi x)``:

* piecewise-constant drives (``levels``, ``fractions``: square, rectangular, steps, a measured drive
  held between samples): the levels, exact;
* the sine drive (:class:`kapitza.SineWave`, ``shape = sin(pi tau)``, ``tau = 2x``): one segment;
* piecewise-linear drives whose breakpoints are known: :class:`kapitza.TriangleWave` (linear between
  its ``_breakpoints``) and a measured drive linear between samples (its interpolation table), exact.

Any other drive (a registered one given only by ``_shape``) has no table here and stays on the numpy
path: sampling its shape on a grid would not be the same drive.

How the two paths relate: both integrate the same equation to the same per-component tolerance with
the same method and the same window test, restarted at the same jumps, so they agree to the
integration error (local errors below ``1e-9`` relative per step, growing along the unstable
directions over the periods): the largest safe tilt to its stated ``accuracy`` (1 %) except at
points where the safe set is ragged at that scale, where a start that grazes the window's edge can
be judged differently and the bisection lands on another boundary point (the tests compare both).

Needs numba (the ``fast`` extra), imported with this module: import it only where it is used
(:func:`kapitza.sweeps.kernel.compiled_available` says whether it can be). Compiled functions are
cached on disk (``cache=True``).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as _dc

from ._survival_jit import ray_step

__all__ = ["drive_table", "pack_plan", "ray_radii_compiled", "survival_compiled", "advance"]

_jit = njit(cache=True, nogil=True, error_model="numpy")
TWO_PI = 2.0 * math.pi

# scipy's DOP853 tableau (scipy.integrate._ivp.rk.DOP853 takes the same slices)
NS = _dc.N_STAGES  # 12 stages per step, the 13th the next step's first (FSAL)
NSE = _dc.N_STAGES_EXTENDED  # 16: three more for the dense output
RK_A = np.ascontiguousarray(_dc.A, dtype=float)  # rows NS + 1 ... for the dense output (A_EXTRA)
RK_B = np.ascontiguousarray(_dc.B, dtype=float)
RK_C = np.ascontiguousarray(_dc.C, dtype=float)
RK_E3 = np.ascontiguousarray(_dc.E3, dtype=float)
RK_E5 = np.ascontiguousarray(_dc.E5, dtype=float)
RK_D = np.ascontiguousarray(_dc.D, dtype=float)
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
EXPONENT = -1.0 / 8.0  # -1 / (error estimator order 7 + 1)
#: a Hermite interval whose crude bound ``max|p| + 4/27 (|m0| + |m1|)`` is below ``tol`` by this
#: relative margin cannot reach it: the quadratic for its extrema is skipped
BOUND_MARGIN = 1e-12


def drive_table(drive):
    """``(XS, SA, SB, SD)``: the drive's shape as segments of ``0 <= x <= 1`` (``x = tau / 2``), on
    segment ``k`` ``shape = SA[k] + SB[k] (x - XS[k]) + SD[k] sin(2 pi x)``; ``None`` for a drive
    known only by its ``_shape`` (:meth:`kapitza.drives.Drive._shape_table`)."""
    return drive._shape_table()


def pack_plan(period):
    """The compiled plan of an :class:`~kapitza.motion.basins._IntegratedPeriod` (its points' ``2T``,
    ``A``, samples per period, the drive's table, ``l, g, c``, the model, the tolerances per
    component for one state), or ``None`` where its drive has no table (:func:`drive_table`)."""
    from .basins import MIN_SAMPLES, SAMPLE_SPACING

    table = drive_table(period.drive)
    if table is None:
        return None
    T2 = np.ascontiguousarray(period.T2, float)
    A = np.ascontiguousarray(period.A, float)
    peak = float(period.drive.peak)  # as _IntegratedPeriod's w_h
    w = np.sqrt((period.g + peak * A) / period.l) + period.c
    m = np.maximum(MIN_SAMPLES, np.ceil(w * T2 / SAMPLE_SPACING)).astype(np.int64)
    scale = 1.0 / math.sqrt(2.0)  # as _IntegratedPeriod scales them for one state
    rtol, atol = max(period.rtol * scale, 1e-13), period.atol * scale
    xs, sa, sb, sd = (np.ascontiguousarray(v, float) for v in table)
    return (T2, A, m, xs, sa, sb, sd, float(period.l), float(period.g), float(period.c),
            period.model == "linear", float(rtol), float(atol))


def _check(out):
    if np.any(out < 0):
        raise RuntimeError("DOP853 (compiled) failed: step size less than spacing between numbers")
    return out


def ray_radii_compiled(point, cos, sin_omega, plan, periods, tol, accuracy, floor):
    """Largest safe radius of each search (as :func:`kapitza.sweeps.kernel.ray_radii`): search ``i``
    starts at ``r (cos[i], sin_omega[i])`` on the parameters of point ``point[i]`` of the plan."""
    out = np.empty(np.size(point))
    ray_radii_kernel(np.ascontiguousarray(point, np.int64), np.ascontiguousarray(cos, float),
                     np.ascontiguousarray(sin_omega, float), *plan, int(periods), float(tol), float(accuracy),
                     float(floor), out)
    return _check(out)


def survival_compiled(theta, dtheta, point, plan, periods, tol):
    """Periods each start stays within ``tol`` (as :func:`kapitza.motion.basins.survival_chunk`)."""
    out = np.empty(np.size(theta), dtype=np.int64)
    survival_kernel(np.ascontiguousarray(theta, float), np.ascontiguousarray(dtheta, float),
                    np.ascontiguousarray(point, np.int64), *plan, int(periods), float(tol), out)
    return _check(out)


def advance(theta, dtheta, point, plan, periods):
    """``(theta, dtheta)`` of each state after ``periods`` whole periods (no window), for tests."""
    th = np.array(theta, float, ndmin=1)
    om = np.array(dtheta, float, ndmin=1)
    advance_kernel(th, om, np.ascontiguousarray(point, np.int64), *plan, int(periods))
    return th, om


# ----------------------------------------------------------------------------- compiled core
@_jit
def rhs(x, th, om, k0, k1, x0, kd, T2c, T2, linear):
    """``(theta_x, theta'_x)``: ``k0 + k1 (x - x0) + kd sin(2 pi x)`` is ``2T s(x)`` on the segment."""
    s = k0
    if k1 != 0.0:
        s += k1 * (x - x0)
    if kd != 0.0:
        s += kd * math.sin(TWO_PI * x)
    f = th if linear else math.sin(th)
    return T2 * om, s * f - T2c * om


@_jit
def error_norm(K0, K1, h, sc0, sc1):
    """scipy's DOP853 error norm of the step (two components)."""
    e50 = 0.0
    e51 = 0.0
    e30 = 0.0
    e31 = 0.0
    for j in range(NS + 1):
        e50 += K0[j] * RK_E5[j]
        e51 += K1[j] * RK_E5[j]
        e30 += K0[j] * RK_E3[j]
        e31 += K1[j] * RK_E3[j]
    e50 /= sc0
    e51 /= sc1
    e30 /= sc0
    e31 /= sc1
    n5 = e50 * e50 + e51 * e51
    n3 = e30 * e30 + e31 * e31
    if n5 == 0.0 and n3 == 0.0:
        return 0.0
    denom = n5 + 0.01 * n3
    if not denom > 0.0:  # both underflowed: nothing left to control
        return 0.0
    return abs(h) * n5 / math.sqrt(denom * 2.0)


@_jit
def initial_step(x, th, om, f0, f1, span, k0, k1, x0, kd, T2c, T2, linear, rtol, atol):
    """scipy's ``select_initial_step`` (order 7) for one state."""
    sc0 = atol + abs(th) * rtol
    sc1 = atol + abs(om) * rtol
    d0 = math.sqrt(0.5 * ((th / sc0) ** 2 + (om / sc1) ** 2))
    d1 = math.sqrt(0.5 * ((f0 / sc0) ** 2 + (f1 / sc1) ** 2))
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, span)
    g0, g1 = rhs(x + h0, th + h0 * f0, om + h0 * f1, k0, k1, x0, kd, T2c, T2, linear)
    d2 = math.sqrt(0.5 * (((g0 - f0) / sc0) ** 2 + ((g1 - f1) / sc1) ** 2)) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100.0 * h0, h1, span)


@_jit
def hermite_exceeds(p0, p1, m0, m1, tol):
    """Whether the cubic Hermite interpolant (values ``p0, p1``, slopes ``m0, m1`` per unit ``x`` on
    ``0 <= x <= 1``) reaches ``|p| > tol`` (:func:`kapitza.motion.basins._hermite_peak`)."""
    peak = max(abs(p0), abs(p1))
    if peak > tol:
        return True
    if peak + (4.0 / 27.0) * (abs(m0) + abs(m1)) <= tol * (1.0 - BOUND_MARGIN):
        return False  # |h10|, |h11| <= 4/27 on [0, 1]: the extrema cannot reach tol
    a = 6.0 * (p0 - p1) + 3.0 * (m0 + m1)
    b = -6.0 * (p0 - p1) - 4.0 * m0 - 2.0 * m1
    disc = b * b - 4.0 * a * m0
    if not disc >= 0.0:
        return False
    sq = math.sqrt(disc)
    q = -0.5 * (b + (sq if b >= 0.0 else -sq))
    lin = -m0 / b
    for r in range(2):
        if r == 0:
            x = q / a if a != 0.0 else lin
        else:
            x = m0 / q if q != 0.0 else lin
        if math.isfinite(x) and 0.0 < x < 1.0:
            x2 = x * x
            x3 = x2 * x
            p = ((2 * x3 - 3 * x2 + 1) * p0 + (x3 - 2 * x2 + x) * m0 + (-2 * x3 + 3 * x2) * p1 + (x3 - x2) * m1)
            if abs(p) > tol:
                return True
    return False


@_jit
def one_period(th, om, p, T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol, tol, check, hs, K0, K1, F0, F1):
    """One period of point ``p`` from ``(th, om)``: ``(th, om, status)``, status 0 inside, 1 the
    window was left (``check``), -1 the step size fell below the spacing of doubles. ``hs``: the
    step proposed for each segment, carried from period to period (0: choose one)."""
    T2 = T2s[p]
    A = As[p]
    m = Ms[p]
    T2c = T2 * c
    for seg in range(SA.size):
        a = XS[seg]
        b = XS[seg + 1]
        x0 = a
        k0 = T2 * (g + A * SA[seg]) / l
        k1 = T2 * A * SB[seg] / l
        kd = T2 * A * SD[seg] / l
        f0, f1 = rhs(a, th, om, k0, k1, x0, kd, T2c, T2, linear)
        h = hs[seg]
        if h <= 0.0:
            h = initial_step(a, th, om, f0, f1, b - a, k0, k1, x0, kd, T2c, T2, linear, rtol, atol)
        # the next check instant: the first j / m above a, or b
        j = int(math.floor(a * m)) + 1
        while j / m <= a:
            j += 1
        xe = j / m if j / m < b else b
        xp = a  # the last checked instant and its state
        thp = th
        omp = om
        x = a
        while x < b:
            min_step = 10.0 * abs(np.nextafter(x, np.inf) - x)
            h_abs = h if h >= min_step else min_step
            rejected = False
            while True:
                if h_abs < min_step:
                    return th, om, -1
                xn = x + h_abs
                clipped = False
                if xn > b:
                    xn = b
                    clipped = True
                hh = xn - x
                K0[0] = f0
                K1[0] = f1
                for s in range(1, NS):
                    d0 = 0.0
                    d1 = 0.0
                    for i in range(s):
                        d0 += K0[i] * RK_A[s, i]
                        d1 += K1[i] * RK_A[s, i]
                    K0[s], K1[s] = rhs(x + RK_C[s] * hh, th + d0 * hh, om + d1 * hh, k0, k1, x0, kd, T2c, T2, linear)
                d0 = 0.0
                d1 = 0.0
                for i in range(NS):
                    d0 += K0[i] * RK_B[i]
                    d1 += K1[i] * RK_B[i]
                thn = th + hh * d0
                omn = om + hh * d1
                g0, g1 = rhs(xn, thn, omn, k0, k1, x0, kd, T2c, T2, linear)
                K0[NS] = g0
                K1[NS] = g1
                sc0 = atol + max(abs(th), abs(thn)) * rtol
                sc1 = atol + max(abs(om), abs(omn)) * rtol
                err = error_norm(K0, K1, hh, sc0, sc1)
                if err < 1.0:
                    if err == 0.0:
                        factor = MAX_FACTOR
                    else:
                        factor = min(MAX_FACTOR, SAFETY * err ** EXPONENT)
                    if rejected:
                        factor = min(1.0, factor)
                    # a step cut short by the segment's end says nothing against the longer one
                    h = max(h_abs, hh * factor) if clipped else hh * factor
                    break
                h_abs = hh * max(MIN_FACTOR, SAFETY * err ** EXPONENT)
                rejected = True
            # check instants in (x, xn]: the dense output inside, the step's end at it
            dense = False
            while check and xe <= xn:
                if xe == xn:
                    the = thn
                    ome = omn
                else:
                    if not dense:
                        for s in range(NS + 1, NSE):
                            d0 = 0.0
                            d1 = 0.0
                            for i in range(s):
                                d0 += K0[i] * RK_A[s, i]
                                d1 += K1[i] * RK_A[s, i]
                            K0[s], K1[s] = rhs(x + RK_C[s] * hh, th + d0 * hh, om + d1 * hh, k0, k1, x0, kd, T2c,
                                               T2, linear)
                        F0[0] = thn - th
                        F1[0] = omn - om
                        F0[1] = hh * f0 - F0[0]
                        F1[1] = hh * f1 - F1[0]
                        F0[2] = 2.0 * F0[0] - hh * (g0 + f0)
                        F1[2] = 2.0 * F1[0] - hh * (g1 + f1)
                        for r in range(4):
                            d0 = 0.0
                            d1 = 0.0
                            for i in range(NSE):
                                d0 += RK_D[r, i] * K0[i]
                                d1 += RK_D[r, i] * K1[i]
                            F0[3 + r] = hh * d0
                            F1[3 + r] = hh * d1
                        dense = True
                    u = (xe - x) / hh
                    the = 0.0
                    ome = 0.0
                    for r in range(7):
                        the += F0[6 - r]
                        ome += F1[6 - r]
                        if r % 2 == 0:
                            the *= u
                            ome *= u
                        else:
                            the *= 1.0 - u
                            ome *= 1.0 - u
                    the += th
                    ome += om
                dx = xe - xp
                if hermite_exceeds(thp, the, dx * T2 * omp, dx * T2 * ome, tol):
                    return thn, omn, 1
                xp = xe
                thp = the
                omp = ome
                if xe >= b:
                    xe = 2.0  # past the segment: no more instants
                else:
                    j += 1
                    xe = j / m if j / m < b else b
            x = xn
            th = thn
            om = omn
            f0 = g0
            f1 = g1
        hs[seg] = h
    return th, om, 0


@_jit
def periods_inside(th, om, p, T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol, periods, tol, hs, K0,
                   K1, F0, F1):
    """Whole periods completed inside the window (``periods`` if it never leaves; -1 on failure)."""
    if abs(th) > tol:
        return 0
    hs[:] = 0.0
    for k in range(periods):
        th, om, status = one_period(th, om, p, T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol, tol,
                                    True, hs, K0, K1, F0, F1)
        if status > 0:
            return k
        if status < 0:
            return -1
    return periods


@_jit
def workspace(segments):
    """One state's scratch arrays for :func:`one_period`: the step sizes carried from period to period
    on each of the drive's ``segments``, the DOP853 stages of both components and their dense-output
    coefficients."""
    return np.zeros(segments), np.zeros(NSE), np.zeros(NSE), np.zeros(7), np.zeros(7)


@_jit
def survival_kernel(theta, dtheta, point, T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol, periods, tol,
                    out):
    hs, K0, K1, F0, F1 = workspace(SA.size)
    for i in range(theta.size):
        out[i] = periods_inside(theta[i], dtheta[i], point[i], T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol,
                                atol, periods, tol, hs, K0, K1, F0, F1)


@_jit
def advance_kernel(theta, dtheta, point, T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol, periods):
    hs, K0, K1, F0, F1 = workspace(SA.size)
    for i in range(theta.size):
        th = theta[i]
        om = dtheta[i]
        hs[:] = 0.0
        for _ in range(periods):
            th, om, status = one_period(th, om, point[i], T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol,
                                        np.inf, False, hs, K0, K1, F0, F1)
            if status < 0:
                th = np.nan
                om = np.nan
                break
        theta[i] = th
        dtheta[i] = om


@_jit
def ray_radii_kernel(point, cos, sin_omega, T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear, rtol, atol, periods, tol,
                     accuracy, floor, out):
    hs, K0, K1, F0, F1 = workspace(SA.size)
    for i in range(point.size):
        r, lo, hi, scanning, done = tol, 0.0, np.inf, True, False
        while not done:
            got = periods_inside(r * cos[i], r * sin_omega[i], point[i], T2s, As, Ms, XS, SA, SB, SD, l, g, c, linear,
                                 rtol, atol, periods, tol, hs, K0, K1, F0, F1)
            if got < 0:  # the solver failed: flagged for the caller
                lo = -1.0
                break
            done, r, lo, hi, scanning = ray_step(got >= periods, r, lo, hi, scanning, tol, accuracy, floor)
        out[i] = lo
