"""Piecewise-constant drives: the exact monodromy as a product of closed-form segment matrices.

On a segment where the acceleration is the constant ``A s_i`` for a time ``2 T f_i`` the
linearised equation (in ``tau = t/T``) is ``theta'' = k_i theta``, ``k_i = 8 eps^2 (mu^2 + s_i)``,
with the exact flow over ``h_i = 2 f_i``, ``r_i = sqrt|k_i| h_i``, ``w_i = sqrt|k_i|``:

    k_i > 0:  [[cosh r, sinh r / w], [w sinh r, cosh r]]   (the upright repels)
    k_i < 0:  [[cos r,  sin r / w], [-w sin r, cos r]]     (it attracts)
    k_i = 0:  [[1, h], [0, 1]]                              (free flight)

``M = S_K ... S_1``. Each hyperbolic factor is carried as ``e^{r} N`` with ``N`` bounded, the
product is renormalised by powers of two after every factor and its logarithmic scale ``L``
kept apart, so ``tr M = e^L tr N`` never overflows (``eps`` up to 1000 and beyond). The
rounding error of ``tr N`` is bounded by the same product taken over ``|N_i|`` (a standard
bound for products of matrices); a verdict the bound cannot settle is recomputed in
``mpmath`` at a precision that covers the cancellation (``docs/drives.md``).

The rotation angle per period comes from a Pruefer angle carried through the segments: in an
elliptic segment the angle of ``(theta, -theta'/w)`` advances by exactly ``r``; in hyperbolic
and free-flight segments a direction never crosses an invariant line, so its turn is the
principal value of the change of angle. On a zone ``tr M / 2 = cos(theta_rot)`` and the
sign of ``M_12`` is that of ``sin(theta_rot)``; the carried angle of any direction lies
within ``pi`` of ``theta_rot``, which fixes the whole turns. Off the zones the carried angle
of an eigenvector is an exact multiple of ``pi``.
"""
from __future__ import annotations

import functools
import math
from fractions import Fraction

import numpy as np

from .. import _validate as _v
from .._certify import LONG_DOUBLE, MAX_PHASE, TRACE_RTOL, growth_good, tau_mp
from .._exact import gap_of_turn
from ._base import Drive, Floquet0, PI, acosh_from_log

_U = np.finfo(float).eps / 2.0
LOG2 = np.log(2.0)


def _segments(eps, mu, levels, durations):
    """Per segment: (kind, w, r, h); kind +1 hyperbolic, -1 elliptic, 0 free flight."""
    out = []
    e2 = 8.0 * eps * eps
    m2 = mu * mu
    for s, h in zip(levels, durations):
        k = e2 * (m2 + s)
        w = np.sqrt(np.abs(k))
        out.append((np.sign(k), w, w * h, h))
    return out


def _uniform(kind):
    """+1, -1 or 0 when every point's segment is of that kind (hyperbolic, elliptic, free flight): the
    usual case (the kind depends on ``mu`` and the level only), computed without the other kinds'
    branches; None when the kinds differ."""
    k0 = kind.flat[0] if kind.size else 0.0
    return float(k0) if kind.size and bool(np.all(kind == k0)) else None


def _factor(kind, w, r, h):
    """Entries (a, b, c, d) of ``e^{-r} S`` (hyperbolic) or ``S`` (otherwise), and log scale."""
    u = _uniform(kind)
    if u is not None and u != 0.0:  # (w > 0 there: the same doubles as the general branch below)
        if u > 0:
            with np.errstate(over="ignore", under="ignore"):
                ch = 0.5 * (1.0 + np.exp(-2.0 * r))
                sn = -0.5 * np.expm1(-2.0 * r)
            return ch, sn / w, w * sn, ch, r
        ch, sn = np.cos(r), np.sin(r)
        return ch, sn / w, -w * sn, ch, np.zeros_like(r)
    hyp = kind > 0
    ell = kind < 0
    ws = np.where(w > 0, w, 1.0)
    with np.errstate(over="ignore", under="ignore"):
        E2 = np.exp(-2.0 * np.where(hyp, r, 0.0))
        ch = np.where(hyp, 0.5 * (1.0 + E2), np.where(ell, np.cos(r), 1.0))
        sh_h = -0.5 * np.expm1(-2.0 * np.where(hyp, r, 0.0))  # e^{-r} sinh r
        sn = np.where(hyp, sh_h, np.where(ell, np.sin(r), 0.0))
        b = np.where(w > 0, sn / ws, h)  # sinh r / w -> h as w -> 0
        c = np.where(hyp, w * sn, np.where(ell, -w * sn, 0.0))
    return ch, b, c, ch, np.where(hyp, r, 0.0)


def _renorm(a, b, c, d):
    m = np.maximum(np.maximum(np.abs(a), np.abs(b)), np.maximum(np.abs(c), np.abs(d)))
    _, e = np.frexp(np.where(m > 0, m, 1.0))
    return np.ldexp(a, -e), np.ldexp(b, -e), np.ldexp(c, -e), np.ldexp(d, -e), e


def _product(segs):
    """Normalised product ``N`` (a, b, c, d), its log scale ``L`` (``M = e^L N``), and the
    trace of the product of ``|N_i|`` in the same scale (for the rounding bound)."""
    a = b = c = d = None
    for kind, w, r, h in segs:
        fa, fb, fc, fd, lr = _factor(kind, w, r, h)
        if a is None:
            a, b, c, d = fa, fb, fc, fd
            pa, pb, pc, pd = np.abs(fa), np.abs(fb), np.abs(fc), np.abs(fd)
            L = lr.copy()
            continue
        a, b, c, d = fa * a + fb * c, fa * b + fb * d, fc * a + fd * c, fc * b + fd * d
        pa, pb, pc, pd = (np.abs(fa) * pa + np.abs(fb) * pc, np.abs(fa) * pb + np.abs(fb) * pd,
                          np.abs(fc) * pa + np.abs(fd) * pc, np.abs(fc) * pb + np.abs(fd) * pd)
        a, b, c, d, e = _renorm(a, b, c, d)
        pa, pb, pc, pd = (np.ldexp(x, -e) for x in (pa, pb, pc, pd))
        L = L + lr + e * (LOG2 if a.dtype == np.float64 else np.log(np.asarray(2.0, a.dtype)))
    return (a, b, c, d), L, pa + pd


def extended_verdicts(eps, mu, zeta, levels, durations):
    """The verdict ``|tr M_phi| / 2 < cosh(kappa)`` at the exact doubles ``eps, mu, zeta`` (flat arrays;
    ``zeta`` None: undamped) from the product taken in long double, where its rounding bound
    (:func:`rounding_bound` at the long double's unit) settles it: ``(decided, stable, tau, log_tau,
    growth, tau_error)``, ``tau = tr M_phi / 2`` and ``growth = log max|lambda|`` of the damped system,
    as doubles, and ``tau_error`` a bound on the error of the long double ``tau`` (before its rounding
    to a double). Nothing is decided where numpy's long double is the double."""
    n = np.size(eps)
    if LONG_DOUBLE is None or n == 0:
        return (np.zeros(n, bool), np.zeros(n, bool)) + tuple(np.full(n, np.nan) for _ in range(4))
    e, m = np.asarray(eps, LONG_DOUBLE), np.asarray(mu, LONG_DOUBLE)
    z = np.zeros(n, LONG_DOUBLE) if zeta is None else np.asarray(zeta, LONG_DOUBLE)
    mc = m * np.sqrt(1.0 + z * z)
    segs = _segments(e, mc, levels, durations)
    (a, _, _, d), L, bound_tr = _product(segs)
    unit = float(np.finfo(LONG_DOUBLE).eps) / 2.0
    err = rounding_bound(segs, L, bound_tr, e, mc, levels, unit)
    trN = a + d
    kappa = 2.0 * np.sqrt(np.asarray(8.0, LONG_DOUBLE)) * z * m * e
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        # (cosh(kappa) beyond the long double times e^-L = 0 is NaN: undecided, mpmath decides)
        thr = 2.0 * np.cosh(kappa) * np.exp(-L)
        # (the threshold's own rounding: that of e^-L and of cosh(kappa))
        decided = np.abs(np.abs(trN) - thr) > err + unit * (8.0 + 4.0 * kappa) * thr
        log_tau = L + np.log(np.abs(0.5 * trN))
        tau = np.sign(trN) * np.exp(log_tau)
    decided &= np.isfinite(tau) & (trN != 0)
    stable = np.abs(trN) < thr
    growth = np.where(np.abs(tau) > 1.0, acosh_from_log(log_tau, tau), 0.0) - kappa
    with np.errstate(over="ignore", invalid="ignore"):
        tau_error = 0.5 * err * np.exp(L) + unit * (8.0 + 4.0 * np.abs(L)) * np.abs(tau)
        # (beyond the doubles' range tau and its bound are infinite, as the double product gives them)
        return decided, stable, tau.astype(float), log_tau.astype(float), growth.astype(float), tau_error.astype(float)


def extended_half_trace(eps, mu, levels, durations, errors=False):
    """``[(tau, log|tau|, stable, angle)]`` as :func:`kapitza._certify.tau_mp` gives them, from the long
    double product (:func:`extended_verdicts`) where it decides the verdict and in mpmath elsewhere.
    ``angle`` (``acos(tau)`` on a zone, ``acosh|tau|`` off it) is then as accurate as the long double's
    ``tau`` makes it: to about ``1e-19 / |1 - |tau||`` relative, not to the last bit within a few ulp
    of an edge (the damping layer, which needs only the verdict there, asks for this). ``errors``:
    also a bound on each ``tau``'s error (the long double's bound and the rounding to a double; half
    an ulp where mpmath gave it)."""
    eps, mu = np.asarray(eps, float).ravel(), np.asarray(mu, float).ravel()
    dec, stable, tau, log_tau, _, tau_err = extended_verdicts(eps, mu, None, levels, durations)
    with np.errstate(invalid="ignore"):
        angle = np.where(stable, np.arccos(np.clip(tau, -1.0, 1.0)), acosh_from_log(log_tau, tau))
    out = list(zip(tau.tolist(), log_tau.tolist(), stable.tolist(), angle.tolist()))
    rest = np.flatnonzero(~dec)
    if rest.size:
        for i, r in zip(rest, tau_mp(eps[rest], mu[rest], levels, durations)):
            out[i] = r
    if not errors:
        return out
    err = np.where(dec, tau_err + _U * np.abs(tau), _U * np.abs([r[0] for r in out]))
    return out, err


def _angle(x, y):
    """Pruefer angle of the state (theta, theta') = (x, y): increases clockwise."""
    return np.arctan2(-y, x)


def _carry(segs, x, y):
    """Carry the direction (x, y) through the segments; return the total turn (each segment by its
    kind's flow; where the points' kinds differ, by all three, each point taking its own)."""
    turn = np.zeros(np.shape(x))
    for kind, w, r, h in segs:
        u = _uniform(kind)
        if u is not None:
            x, y, t = (_carry_hyperbolic(w, r, x, y) if u > 0 else
                       _carry_elliptic(w, r, x, y) if u < 0 else _carry_free(h, x, y))
        else:
            hyp, ell = kind > 0, kind < 0
            ws = np.where(w > 0, w, 1.0)
            with np.errstate(all="ignore"):   # (each point keeps only its own kind's values)
                parts = (_carry_hyperbolic(ws, r, x, y), _carry_elliptic(ws, r, x, y), _carry_free(h, x, y))
            x, y, t = (np.where(hyp, ph, np.where(ell, pe, pf)) for ph, pe, pf in zip(*parts))
        turn = turn + t
    return turn


def _wrap(a):
    return np.remainder(a + PI, 2.0 * PI) - PI


def _unit(x, y):
    n = np.hypot(x, y)
    return x / n, y / n


def _carry_elliptic(w, r, x, y):
    """:func:`_carry` through one elliptic segment: the scaled angle of ``(theta, -theta'/w)`` turns by
    exactly ``r``, the Pruefer angle by as much up to the two ends' corrections."""
    psi0 = _angle(x, y)
    s0 = np.arctan2(-y / w, x)
    cr, sr = np.cos(r), np.sin(r)
    x1, y1 = _unit(cr * x + sr / w * y, -w * sr * x + cr * y)
    psi1 = _angle(x1, y1)
    s1 = np.arctan2(-y1 / w, x1)
    ds = r + _wrap(s1 - s0 - r)
    return x1, y1, ds + _wrap(psi1 - s1) - _wrap(psi0 - s0)


def _carry_hyperbolic(w, r, x, y):
    """:func:`_carry` through one hyperbolic segment, split along the eigen-directions ``(1, +-w)``
    so that no term overflows; the angle turns by less than half a turn."""
    psi0 = _angle(x, y)
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        p = x + y / w
        m = x - y / w
        lp = np.log(np.abs(p)) + r
        lm = np.log(np.abs(m)) - r
        top = np.maximum(lp, lm)
        P = np.sign(p) * np.exp(lp - top)
        Mm = np.sign(m) * np.exp(lm - top)
    x1, y1 = _unit(0.5 * (P + Mm), 0.5 * (P - Mm) * w)
    return x1, y1, _wrap(_angle(x1, y1) - psi0)


def _carry_free(h, x, y):
    """:func:`_carry` through one segment of free flight (``s = 0``) of duration ``h``."""
    psi0 = _angle(x, y)
    x1, y1 = _unit(x + h * y, y)
    return x1, y1, _wrap(_angle(x1, y1) - psi0)


def rounding_bound(segs, L, bound_tr, eps, mu, levels, unit=_U):
    """A bound on the rounding error of ``tr N`` (``tr M = e^L tr N``; flat arrays) at unit roundoff
    ``unit`` (the double's, or the long double's for :func:`extended_verdicts`).

    The product of ``K`` factors, each entry correct to a few units ``u``, errs by at most
    ``u (16 K + 4 |L|)`` times the trace of the product of ``|N_i|`` (``bound_tr``). The factors'
    arguments add their own share: ``r_i = sqrt|k_i| h_i`` to ``4 r_i u``, and
    ``k_i = 8 eps^2 (mu^2 + s_i)`` to ``u (2 + 8 mu^2 / |mu^2 + s_i|)`` relative (``mu^2`` taken to
    ``8u``, enough for the damped system's rounded ``mu_c``), which moves the normalised entries by
    ``r_i min(r_i, 1)`` times that: near free flight (``mu^2 + s_i -> 0``) this is
    ``8 eps^2 h_i^2 mu^2`` units, which ``4 r_i`` alone misses.
    """
    m2 = mu * mu
    e2 = 8.0 * eps * eps
    arg = np.zeros(np.shape(L))
    with np.errstate(divide="ignore", invalid="ignore"):
        for s, (_, _, r, h) in zip(levels, segs):
            q = np.abs(m2 + s)
            arg = arg + 4.0 * r + np.where(r < 1.0, e2 * h * h * (2.0 * q + 8.0 * m2), r * (2.0 + 8.0 * m2 / q))
    return unit * (16.0 * len(segs) + arg + 4.0 * np.abs(L)) * bound_tr


def floquet_product(eps, mu, levels, durations, certify=True, trace=False, phi=None):
    """Undamped Floquet data of a piecewise-constant drive (trusted input).

    ``certify``: settle verdicts within the rounding bound in mpmath (edge searches, which
    only need the predicate away from the last few ulp, switch it off).

    ``trace``: the trace is reported. The result then carries ``tau_error``, a bound on the
    absolute error of ``tau`` (:func:`rounding_bound`), and where that exceeds
    :data:`TRACE_RTOL` ``|tau|`` (and an exact product is affordable, ``sum r <= MAX_PHASE``),
    ``tau``, ``log|tau|``, the growth and the parity of the rotation angle are those of the
    product in ``mpmath`` (:func:`kapitza._certify.tau_mp`), ``tau`` correctly rounded. ``phi``:
    ``(mu, zeta)`` (flat) when ``mu`` here is the damped system's rounded
    ``mu_c = mu sqrt(1 + zeta^2)``: the extended-precision trace is then taken at
    ``mu^2 (1 + zeta^2)`` exactly (the verdict stays that of the ``mu`` given, as without ``trace``).
    """
    eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
    shape = eps.shape
    eps, mu = eps.ravel(), mu.ravel()
    segs = _segments(eps, mu, levels, durations)
    (a, b, c, d), L, bound_tr = _product(segs)
    trN = a + d
    with np.errstate(divide="ignore", over="ignore"):
        log_tau = L + np.log(np.abs(0.5 * trN))
        tau = np.sign(trN) * np.where(log_tau < 709.0, np.exp(np.minimum(log_tau, 709.0)), np.inf)
    rsum = sum(seg[2] for seg in segs)
    err = rounding_bound(segs, L, bound_tr, eps, mu, levels)
    with np.errstate(under="ignore"):
        thr = 2.0 * np.exp(-np.maximum(L, -700.0))
    unsure = np.abs(np.abs(trN) - thr) <= err + 1e-15 * thr
    # beyond MAX_PHASE the exact decision would need thousands of digits: the double verdict
    # stands there, as the square wave's does (kapitza._certify)
    unsure &= rsum <= MAX_PHASE
    stable = np.abs(trN) < thr
    known = np.full(eps.size, np.nan)   # the error of tau where a certified product gave it
    if certify and np.any(unsure):
        idx = np.flatnonzero(unsure)
        res, res_err = extended_half_trace(eps[idx], mu[idx], levels, durations, errors=True)
        log_tau[idx] = [r[1] for r in res]
        tau[idx] = [r[0] for r in res]
        stable[idx] = [r[2] for r in res]
        if phi is None:
            known[idx] = res_err
    tau_error = None
    exact_growth = None
    if trace:
        with np.errstate(divide="ignore", invalid="ignore"):
            ill = ((np.isnan(known) & (err > TRACE_RTOL * np.abs(trN))) | (known > TRACE_RTOL * np.abs(tau))) \
                & (rsum <= MAX_PHASE)
            # a reported growth acosh|tau| beside an edge: tau's error over sqrt(tau^2 - 1) (a double's
            # rounding alone is a per cent of it a few doubles out): mpmath's angle there
            off = ~stable & ((np.abs(tau) > 1.0) | (log_tau > 0.0)) & (rsum <= MAX_PHASE)
            off &= ~growth_good(tau, np.where(np.isnan(known), 0.0, known) + _U * np.abs(tau),
                                acosh_from_log(log_tau, tau), log_tau=log_tau)
            # (and where log|tau| itself has underflowed, a period of tiny phase: the growth is
            # sqrt(2 log|tau|), far above the doubles' least)
            off |= ~stable & ~(log_tau > 0.0) & ~(np.abs(tau) < 1.0) & (rsum <= MAX_PHASE)
        ill |= off
        if np.any(ill):
            idx = np.flatnonzero(ill)
            m_x, z_x = (mu[idx], None) if phi is None else (np.ravel(phi[0])[idx], np.ravel(phi[1])[idx])
            res = tau_mp(eps[idx], m_x, levels, durations, z_x)
            log_tau[idx] = [r[1] for r in res]
            tau[idx] = [r[0] for r in res]
            known[idx] = _U * np.abs(tau[idx])
            exact_growth = np.full(eps.size, np.nan)
            exact_growth[idx] = [0.0 if r[2] else r[3] for r in res]
        with np.errstate(divide="ignore", over="ignore"):
            tau_error = np.where(np.isnan(known), np.exp(np.minimum(L + np.log(err) - LOG2, 710.0)), known)
    with np.errstate(invalid="ignore"):
        growth = np.where(stable | (np.abs(tau) <= 1.0), 0.0, acosh_from_log(log_tau, tau))
    if exact_growth is not None:
        growth = np.where(np.isnan(exact_growth), growth, exact_growth)
    # Rotation: a generic direction on the zones, an eigenvector off them.
    x0 = np.ones_like(eps)
    y0 = np.zeros_like(eps)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        disc = np.sqrt(np.maximum(trN * trN - 4.0 * np.exp(-2.0 * np.minimum(L, 700.0)), 0.0))
        lam = 0.5 * (trN + np.where(trN >= 0, disc, -disc))
        v1 = (b, lam - a)
        v2 = (lam - d, c)
        use1 = np.hypot(*v1) >= np.hypot(*v2)
        ex = np.where(use1, v1[0], v2[0])
        ey = np.where(use1, v1[1], v2[1])
        nrm = np.hypot(ex, ey)
        good = np.isfinite(nrm) & (nrm > 0)
    x0 = np.where(stable | ~good, 1.0, ex / np.where(good, nrm, 1.0))
    y0 = np.where(stable | ~good, 0.0, ey / np.where(good, nrm, 1.0))
    turn = _carry(segs, x0, y0)
    with np.errstate(invalid="ignore"):
        acos_tau = np.arccos(np.clip(tau, -1.0, 1.0))
    sig = np.where(b >= 0, 1.0, -1.0)
    base = sig * acos_tau
    kk = np.rint((turn - base) / (2.0 * PI))
    theta_stable = 2.0 * PI * kk + base
    zone_stable = np.where(sig > 0, 2 * kk, 2 * kk - 1)
    # off the zones the multipliers are real: theta is k pi with k even for positive ones (tr M > 0)
    # and odd for negative ones; the carried angle picks the nearest such k (far out its own
    # rounding may leave it nearer the other parity)
    odd = tau < 0
    k_gap = 2.0 * np.rint((turn / PI - odd) / 2.0) + odd
    # an eigenvector that did not turn by a multiple of pi of the trace's parity was not one (the
    # doubles' product had lost the trace's sign, which the exact one restored): any direction
    # turns by less than pi from k pi (the circle map keeps the order between its two fixed
    # directions), so (1, 0)'s turn decides k
    k_eig = np.rint(turn / PI)
    astray = ~stable & ~((np.abs(turn / PI - k_eig) < 0.25) & ((np.remainder(k_eig, 2.0) == 1.0) == odd))
    if np.any(astray):
        j = np.flatnonzero(astray)
        seg_j = [tuple(np.broadcast_to(v, eps.shape)[j] for v in seg) for seg in segs]
        k_gap[j] = gap_of_turn(_carry(seg_j, np.ones(j.size), np.zeros(j.size)), odd[j])
    theta = np.where(stable, theta_stable, PI * k_gap)
    zone = np.where(stable, zone_stable, -1).astype(np.int64)
    return Floquet0(tau=tau.reshape(shape), log_tau=log_tau.reshape(shape), growth=growth.reshape(shape),
                    theta=theta.reshape(shape), zone=zone.reshape(shape),
                    tau_error=None if tau_error is None else tau_error.reshape(shape),
                    unsure=None if certify or trace else unsure.reshape(shape))


class PiecewiseConstant(Drive):
    """A drive whose acceleration is ``A levels[i]`` for the fraction ``fractions[i]`` of ``2T``.

    The common machinery of :class:`~kapitza.SquareWave`, :class:`~kapitza.RectangularWave`
    and :class:`~kapitza.StepDrive`: exact kinematics (piecewise-parabolic displacement) and
    the exact monodromy as a product of segment matrices.
    """

    name = "steps"

    def __init__(self, levels, fractions):
        levels, fractions = _check_steps(levels, fractions)
        self.levels = levels
        self.fractions = fractions
        self._durations = tuple(2.0 * f for f in fractions)
        self._trough = -float(min(levels))
        self.peak = float(max(abs(v) for v in levels))
        # Kinematics in tau = t/T: velocity V_i and displacement Z_i at the segment starts,
        # with the constants fixed by zero mean over the period.
        h = np.array(self._durations)
        s = np.array(levels)
        V = np.concatenate([[0.0], np.cumsum(s * h)])[:-1]
        mean_V = np.sum(V * h + 0.5 * s * h * h) / 2.0
        V = V - mean_V
        Z = np.concatenate([[0.0], np.cumsum(V * h + 0.5 * s * h * h)])[:-1]
        mean_Z = np.sum(Z * h + 0.5 * V * h * h + s * h**3 / 6.0) / 2.0
        Z = Z - mean_Z
        self._starts = np.concatenate([[0.0], np.cumsum(h)])[:-1]
        self._V = V
        self._Z = Z
        ends_Z = Z + V * h + 0.5 * s * h * h
        cand = list(Z) + list(ends_Z)
        with np.errstate(divide="ignore", invalid="ignore"):
            tstar = np.where(s != 0, -V / np.where(s != 0, s, 1.0), -1.0)
        inside = (tstar > 0) & (tstar < h)
        cand += list((Z + V * tstar + 0.5 * s * tstar**2)[inside])
        self._stroke_coefficient = float(max(cand) - min(cand))
        self._mean_square_velocity = float(np.sum(V * V * h + V * s * h * h + s * s * h**3 / 3.0) / 2.0)
        if not self._mean_square_velocity > 1e-100:  # Arnold's eps divides by its root
            raise _v.KapitzaValueError(
                "levels and fractions must move the pivot: their rms velocity must be at least 1e-50 A T; got "
                f"{np.sqrt(max(self._mean_square_velocity, 0.0)):.3g} A T (a step too narrow, or levels too small)")

    @functools.cached_property
    def _exact_mean(self):
        """The mean level over the period, exactly (a :class:`fractions.Fraction` of the doubles)."""
        return sum(Fraction(v) * Fraction(h) for v, h in zip(self.levels, self._durations)) / 2

    # ------------------------------------------------------------ kinematics
    def _locate(self, tau):
        i = np.searchsorted(self._starts, tau, side="right") - 1
        i = np.clip(i, 0, len(self.levels) - 1)
        return i, tau - self._starts[i]

    def _shape(self, tau):
        i, _ = self._locate(tau)
        return np.asarray(self.levels)[i]

    def _velocity_shape(self, tau):
        i, r = self._locate(tau)
        return self._V[i] + np.asarray(self.levels)[i] * r

    def _displacement_shape(self, tau):
        i, r = self._locate(tau)
        return self._Z[i] + self._V[i] * r + 0.5 * np.asarray(self.levels)[i] * r * r

    # ------------------------------------------------------------ stability
    def _floquet0(self, eps, mu, certify=True, trace=False, phi=None):
        return floquet_product(eps, mu, self.levels, self._durations, certify, trace, phi)

    def _edges0(self, mu, n):
        return sampled_edges(self, mu, n)

    _windowed = True
    _batched_points = True

    def _window0(self, mu, e_a, e_b):
        return window_zones(self, mu, e_a, e_b)

    def _zone_rate(self, mu):
        rate, _ = _window_margin(mu, self.levels, self._durations)
        return rate, (len(self.levels) + 1) * PI

    def _steps(self):
        return self.levels, self.fractions

    def _kapitza_mu(self, damped):
        return 1e-50 if damped else 1e-8

    def _certified_cheap(self, damped):
        return LONG_DOUBLE is not None

    def _damped_exact(self, eps, mu, zeta, growth=True):
        # long double first; mpmath where its rounding bound leaves the verdict open (or, for a
        # reported growth, where the long double's is not good to 1e-12)
        eps, mu, zeta = (np.asarray(v, float).ravel() for v in (eps, mu, zeta))
        dec, stable, tau, log_tau, rate, err = extended_verdicts(eps, mu, zeta, self.levels, self._durations)
        if growth:
            dec &= growth_good(tau, err, rate, log_tau=log_tau)
        out = [(bool(st), float(gr)) for st, gr in zip(stable, rate)]
        rest = np.flatnonzero(~dec)
        if rest.size:
            for i, r in zip(rest, super()._damped_exact(eps[rest], mu[rest], zeta[rest])):
                out[i] = r
        return out

    def _log_tau0(self, eps, mu):
        # the product alone: no rotation angle, no certification (the damped excess needs no more)
        eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
        (a, _, _, d), L, _ = _product(_segments(eps.ravel(), mu.ravel(), self.levels, self._durations))
        with np.errstate(divide="ignore"):
            return (L + np.log(np.abs(0.5 * (a + d)))).reshape(eps.shape)

    def _tau_minus_one0(self, eps, mu):
        eps, mu = np.broadcast_arrays(np.asarray(eps, float), np.asarray(mu, float))
        rsum = eps * (_elliptic_rate(mu, self.levels, self._durations)
                      + _hyperbolic_rate(mu, self.levels, self._durations))
        out = np.full(eps.shape, np.nan)
        short = (rsum < 3.0) & _cancels(mu, self.levels)
        if short.any():
            out[short] = _tau_minus_one(eps[short], mu[short], self.levels, self._durations)
        return out

    def as_dict(self) -> dict:
        return {"drive": self.name, "levels": list(self.levels), "fractions": list(self.fractions)}

    @property
    def label(self) -> str:
        return f"{len(self.levels)}-step drive"

    def describe(self) -> str:
        steps = ", ".join(f"{lev:+.4g} A for {f:.4g}" for lev, f in zip(self.levels, self.fractions))
        return f"{len(self.levels)}-step drive ({steps} of the period)"


def _check_steps(levels, fractions):
    lev = _v.finite("levels", levels)
    frac = _v.finite("fractions", fractions)
    if lev.ndim != 1 or frac.ndim != 1:
        raise _v.KapitzaValueError(
            f"levels and fractions must be 1-D sequences; got shapes {lev.shape} and {frac.shape}")
    if lev.size != frac.size:
        raise _v.KapitzaValueError(
            f"levels and fractions must have the same length; got {lev.size} and {frac.size}")
    if lev.size < 2:
        raise _v.KapitzaValueError(f"a step drive needs at least 2 steps; got {lev.size}")
    if lev.size > 64:
        raise _v.KapitzaValueError(f"a step drive may have at most 64 steps; got {lev.size} (a longer measured "
                                   "signal: kapitza.from_samples(t, a, kind='constant'))")
    if np.any(np.abs(lev) > 1e6):  # multiples of A: beyond this A itself should carry the scale
        raise _v.KapitzaValueError(f"levels must satisfy |level| <= 1e6 (multiples of A; scale A instead); got "
                                   f"{float(lev[np.argmax(np.abs(lev))])!r}")
    bad = ~(frac > 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise _v.KapitzaValueError(
            f"fractions must each be > 0 (0 < fraction <= 1); got {float(frac[i])!r} (at index {i})")
    total = float(np.sum(frac))
    if abs(total - 1.0) > 1e-9:
        raise _v.KapitzaValueError(f"fractions must sum to 1; got sum {total!r}")
    frac = frac / total
    scale = float(np.sum(np.abs(lev) * frac))
    if scale == 0.0:
        raise _v.KapitzaValueError("levels must not all be 0 (the pivot would not move)")
    mean = float(np.sum(lev * frac))
    if abs(mean) > 1e-9 * scale:
        raise _v.KapitzaValueError(
            "levels must have zero mean over the period (sum(levels * fractions) = 0, so that the "
            f"pivot's velocity and displacement are periodic); got mean {mean!r}")
    return tuple(float(x) for x in lev), tuple(float(x) for x in frac)


def _asinh_tau(eps, mu, levels, durations):
    """``asinh(tr M / 2)``: a smooth, overflow-free stand-in for the half-trace in root solves."""
    segs = _segments(eps, mu, levels, durations)
    (a, _, _, d), L, _ = _product(segs)
    half = 0.5 * (a + d)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        log_tau = L + np.log(np.abs(half))
        # |tau| < e^30: asinh of tau itself (L may be large while tau, after cancellation, is not)
        small = np.arcsinh(np.sign(half) * np.exp(np.minimum(log_tau, 30.0)))
        big = np.sign(half) * (log_tau + np.log1p(np.sqrt(1.0 + np.exp(-2.0 * np.maximum(log_tau, 0.0)))))
    return np.where(log_tau <= 30.0, small, big)


@functools.lru_cache(maxsize=64)
def _frame(levels, durations):
    """Constants of the shear frame used by :func:`_tau_minus_one`, exact for the drive's doubles.

    ``W_i`` (doubles) is the zero-mean velocity shape at the start of step ``i`` (``W_K = W_0``);
    ``dW_i = W_{i+1} - W_i`` rounded, and ``rest_i = s_i h_i - (W_{i+1} - W_i)`` evaluated exactly
    (rational arithmetic on the doubles) and rounded: the ``rest_i`` sum to the drive's own
    ``sum s_i h_i``, which is zero up to the rounding of its levels and fractions.
    """
    from fractions import Fraction

    s = [Fraction(x) for x in levels]
    h = [Fraction(x) for x in durations]
    V = [Fraction(0)]
    for si, hi in zip(s, h):
        V.append(V[-1] + si * hi)
    V = V[:-1]
    mean = sum(v * hi + si * hi * hi / 2 for v, si, hi in zip(V, s, h)) / sum(h)
    W = [float(v - mean) for v in V]
    Wf = [Fraction(w) for w in W]
    nxt = Wf[1:] + Wf[:1]
    dW = [float(b - a) for a, b in zip(Wf, nxt)]
    rest = [float(si * hi - (b - a)) for si, hi, a, b in zip(s, h, Wf, nxt)]
    return tuple(W), tuple(W[1:] + W[:1]), tuple(dW), tuple(rest)


# Taylor coefficients 1/(2n+3)! and 1/(2n+4)!, n = 0..12, for |x| <= 2
_S2 = tuple(1.0 / math.factorial(2 * n + 3) for n in range(13))
_C2 = tuple(1.0 / math.factorial(2 * n + 4) for n in range(13))


def _step_series(x):
    """``(S1, S2, C1, C2)`` of ``x = k h^2`` (either sign), each to a few ulp:

    ``S1 = sinh(r)/r``, ``C1 = (cosh r - 1)/r^2`` for ``x = r^2 > 0`` (``sin``, ``cos`` for
    ``x = -r^2``), ``S1 = 1 + x S2``, ``C1 = 1/2 + x C2``: the series tails, formed without
    subtracting their leading terms where ``|x| <= 2``.
    """
    small = np.abs(x) <= 2.0
    xs = np.where(small, x, 0.0)
    # terms up to x^n with n the first where |x|^(n+1) / (2n + 5)! < 2^-60 (13 at |x| = 2)
    big_x = float(np.max(np.abs(xs), initial=0.0))
    n = next((k for k, c in enumerate(_C2) if big_x ** (k + 1) * c * (1.0 / ((2 * k + 5) * (2 * k + 6)))
              < 2.0 ** -60), len(_C2) - 1)
    S2 = np.full(x.shape, _S2[n])
    C2 = np.full(x.shape, _C2[n])
    for cs, cc in zip(_S2[n - 1::-1], _C2[n - 1::-1]):
        S2 = S2 * xs + cs
        C2 = C2 * xs + cc
    if not small.all():
        big = ~small
        xb = x[big]
        r = np.sqrt(np.abs(xb))
        hyp = xb > 0
        S1b = np.where(hyp, np.sinh(r), np.sin(r)) / r
        C1b = 2.0 * np.where(hyp, np.sinh(0.5 * r), np.sin(0.5 * r)) ** 2 / np.abs(xb)
        S2[big] = (S1b - 1.0) / xb
        C2[big] = (C1b - 0.5) / xb
    return 1.0 + x * S2, S2, 0.5 + x * C2, C2


def _tau_minus_one(eps, mu, levels, durations):
    """``tr M / 2 - 1`` free of cancellation (see :func:`_tau_minus_one_scaled`)."""
    return eps * eps * _tau_minus_one_scaled(eps, mu, levels, durations)


def _tau_minus_one_scaled(eps, mu, levels, durations):
    """``(tr M / 2 - 1) / eps^2`` free of cancellation, for phases of moderate size (``sum r <~ 40``).

    Near ``eps, mu -> 0`` (Kapitza's limit, the lower edge of zone 0) ``tr M - 2`` is of order
    ``a mu^2`` and ``a^2`` (``a = 8 eps^2``) while the product's entries carry terms of order
    ``a`` that cancel only because the drive has zero mean. Here the product is taken in the
    frame ``(theta, theta' - a W(tau) theta)`` with ``W`` the zero-mean velocity shape (the
    trace does not change: ``W`` is periodic). In that frame each step is ``I + F_i`` with
    ``F_21 = a mu^2 h S1 + a s h x S2 + a rest - a dW e11 - a^2 W W' e12`` and
    ``tr F_i = a mu^2 h^2 + a rest h S1 + a x h^2 (2 (mu^2 + s) C2 - s S2)`` (``x = k h^2``,
    the series tails of :func:`_step_series`, ``rest`` the exact rounding residue of the drive's
    zero mean, :func:`_frame`), so neither holds a term of order ``a`` that cancels; the product
    ``I + D`` carries ``tr D`` by its own recurrence ``tr D' = tr F + tr D + tr(F D)``, whose
    terms are all of order ``a mu^2`` or ``a^2``. The result is accurate to a few ulp relative
    to ``a mu^2 + a^2`` (``tests/test_drive_edges_oracle.py``), not merely to ``a`` or to 1.
    Every entry but ``D_12`` is carried divided by ``a`` (no underflow for ``mu`` down to 1e-150).
    """
    W0, W1, dW, rest = _frame(tuple(levels), tuple(durations))
    a = 8.0 * eps * eps
    m = mu * mu
    D = None
    for s, h, w0, w1, dw, rs in zip(levels, durations, W0, W1, dW, rest):
        ms = m + s
        x = a * ms * h * h
        S1, S2, C1, C2 = _step_series(x)
        # the step I + F in the sheared frame; F_11, F_22, F_21 and tr F divided by a
        e11 = ms * h * h * C1
        e12 = h * S1
        f11 = e11 + w0 * e12
        f22 = e11 - w1 * e12
        f21 = m * h * S1 + s * h * x * S2 + rs - dw * x * C1 - a * (w0 * w1) * e12
        trF = m * h * h + rs * h * S1 + x * h * h * (2.0 * ms * C2 - s * S2)
        if D is None:
            D = (f11, e12, f21, f22, trF)
            continue
        d11, d12, d21, d22, t = D  # D_11, D_21, D_22, tr D over a; D_12 itself
        D = (f11 + d11 + a * (f11 * d11) + e12 * d21, e12 + d12 + a * (f11 * d12 + e12 * d22),
             f21 + d21 + a * (f21 * d11 + f22 * d21), f22 + d22 + f21 * d12 + a * (f22 * d22),
             trF + t + a * (f11 * d11 + f22 * d22) + (e12 * d21 + f21 * d12))
    return 4.0 * D[4]  # tr D / 2 / eps^2 = (a / 2) (tr D / a) / eps^2


def _cancels(mu, levels):
    """Where ``tr M / 2 - 1`` near zone 0's lower edge must be formed by :func:`_tau_minus_one`:
    its terms of order ``8 eps^2 |s|`` cancel to ``8 eps^2 mu^2`` (lose ``max|s| / mu^2``)."""
    return mu * mu < 0.2 * max(abs(s) for s in levels)


def _illinois(f, a, b, fa, fb, iters=60, enough=None):
    """Vectorised Illinois (modified regula falsi) on brackets with ``fa * fb <= 0``.

    Returns the end of the final bracket on the side of ``a``'s sign and the other end,
    adjacent or within a few ulp, so callers can choose the side they report. ``enough``: a
    bound (per bracket) below which ``|f|`` at a new point ends the search for that bracket.
    """
    a, b, fa, fb = a.copy(), b.copy(), fa.copy(), fb.copy()
    side = np.zeros(a.shape, np.int8)
    for _ in range(iters):
        live = np.abs(b - a) > 2.0 * np.finfo(float).eps * np.maximum(np.abs(a), np.abs(b))
        live &= (fa != 0) & (fb != 0)
        if not live.any():
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            c = np.where(live, (a * fb - b * fa) / (fb - fa), a)
        lo_, hi_ = np.minimum(a, b), np.maximum(a, b)
        bad = ~((c > lo_) & (c < hi_))
        c = np.where(bad, 0.5 * (a + b), c)
        fc = np.where(live, f(c, live), fa)
        if enough is not None:  # (fa, fb may carry Illinois weights; fc is a true value)
            hit = live & (np.abs(fc) < enough)
            a, b, fa, fb = (np.where(hit, c, a), np.where(hit, c, b), np.where(hit, fc, fa), np.where(hit, fc, fb))
            live &= ~hit
        same = np.sign(fc) == np.sign(fb)
        # (a, b) -> (b, c) when c replaces b's side, else keep a and halve its weight (Illinois)
        new_a = np.where(same, a, b)
        new_fa = np.where(same, np.where(side == 1, 0.5 * fa, fa), fb)
        side = np.where(same, 1, -1).astype(np.int8)
        a = np.where(live, new_a, a)
        fa = np.where(live, new_fa, fa)
        b = np.where(live, c, b)
        fb = np.where(live, fc, fb)
    return a, b, fa, fb


def _elliptic_rate(mu, levels, durations):
    """d(sum of elliptic angles)/d eps = sum over attracting segments of sqrt(8 |mu^2 + s|) h."""
    rate = np.zeros(np.shape(mu))
    for s, h in zip(levels, durations):
        k = mu * mu + s
        rate = rate + np.sqrt(8.0 * np.maximum(-k, 0.0)) * h
    return rate


def _hyperbolic_rate(mu, levels, durations):
    """d(sum of hyperbolic r_i)/d eps."""
    rate = np.zeros(np.shape(mu))
    for s, h in zip(levels, durations):
        k = mu * mu + s
        rate = rate + np.sqrt(8.0 * np.maximum(k, 0.0)) * h
    return rate


def window_zones(drive, mu, e_a, e_b):
    """``(rows, zone, lo, hi)`` of every zone that meets ``[e_a, e_b]`` (undamped; for charts).

    A narrow margin is sampled first; a row whose window ends are stable but not covered by
    a zone found is done again with the full margin of :func:`_window_margin`.
    """
    mu, e_a, e_b = (np.ravel(x).astype(float) for x in np.broadcast_arrays(mu, e_a, e_b))
    rows, zone, lo, hi = zones_in_window(drive, mu, e_a, e_b, margin=2.0, keep_all=True)
    ends = drive._floquet0(np.concatenate([e_a, e_b]), np.concatenate([mu, mu]), certify=False).zone >= 0
    covered = np.zeros(2 * mu.size, bool)
    for k, e in ((0, e_a), (1, e_b)):
        inside = (lo <= e[rows]) & (hi >= e[rows])
        covered[k * mu.size + rows[inside]] = True
    redo = np.flatnonzero((ends & ~covered).reshape(2, -1).any(axis=0))
    if redo.size:
        r2, z2, l2, h2 = zones_in_window(drive, mu[redo], e_a[redo], e_b[redo], keep_all=True)
        drop = np.isin(rows, redo)
        rows = np.concatenate([rows[~drop], redo[r2]])
        zone = np.concatenate([zone[~drop], z2])
        lo = np.concatenate([lo[~drop], l2])
        hi = np.concatenate([hi[~drop], h2])
    return rows, zone, lo, hi


def _window_margin(mu, levels, durations):
    """``(rate, W)``: the elliptic angle grows like ``rate * eps``; a zone's zero and edges lie
    within ``W`` of each other in ``eps`` (``|theta_rot - sum r_ell| < (K + 1) pi``)."""
    rate = _elliptic_rate(mu, levels, durations)
    B = (len(levels) + 1) * PI
    return rate, (0.5 * PI + 2.0 * B) / np.where(rate > 0, rate, 1.0)


def _sample(drive, eps, mu):
    """``(asinh(tr M / 2), theta_rot / pi)`` at sample points (exact rotation angle)."""
    f = drive._floquet0(eps, mu, certify=False)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        big = np.sign(f.tau) * (f.log_tau + np.log1p(np.sqrt(1.0 + np.exp(-2.0 * np.maximum(f.log_tau, 0.0)))))
        F = np.where(f.log_tau < 30.0, np.arcsinh(np.where(f.log_tau < 30.0, f.tau, 0.0)), big)
    return F, f.theta / PI


def _zeros_between(t1, t2):
    """How many points theta = (k + 1/2) pi lie between two rotation angles (in units of pi)."""
    return np.floor(t2 - 0.5) - np.floor(t1 - 0.5)


def zones_in_window(drive, mu, e_a, e_b, per_turn=3, margin=None, keep_all=False):
    """Every zone whose ``tr M = 0`` point lies in ``[e_a, e_b]``, row by row (trusted arrays).

    Returns ``(rows, zone, lo, hi)``, flat arrays with one entry per zone found.

    ``tr M / 2 = cos(theta_rot)`` on a zone, so zone ``k`` contains the point where its angle
    passes ``(k + 1/2) pi``, a sign change of ``tr M``, however thin the zone. The rotation
    angle is sampled ``per_turn`` times per ``pi`` of elliptic angle over the window widened
    by ``W`` each side (where the edges of the zones found must lie; ``margin``, in units of
    ``pi`` of elliptic angle, narrows it, and ``keep_all`` keeps the zones whose zero lies in
    the widened window too); an interval across which
    the angle passes two or more such points (zones that come in close pairs) is subdivided
    until each holds one. Each sign change is solved to a zero; the edges are solved between
    the zero and the nearest samples whose angle is ``<= k pi`` (lower) or ``>= (k + 1) pi``
    (upper), by Illinois iterations on ``asinh(tr M / 2) -+ asinh 1`` (or on ``tr M / 2 - 1``
    formed without cancellation near ``eps = 0``), each edge reported on its unstable side.
    The angle is taken to grow with ``eps`` (oscillation theory); a stable island entered and
    left on the same side, if a drive had one, would not be seen.
    """
    levels, durations = drive.levels, drive._durations
    mu, e_a, e_b = (np.ravel(x).astype(float) for x in np.broadcast_arrays(mu, e_a, e_b))
    rate, W = _window_margin(mu, levels, durations)
    has = rate > 0
    rate_s = np.where(has, rate, 1.0)
    if margin is not None:
        W = margin * PI / rate_s
    g_a = np.maximum(e_a - W, 0.0)
    g_b = e_b + W
    m = int(np.ceil(np.max(np.where(has, (g_b - g_a) * rate_s / PI, 0.0)) * per_turn)) + 2
    grid = g_a[:, None] + (g_b - g_a)[:, None] * np.linspace(0.0, 1.0, m)[None, :]
    # eps = 0 is the trivial root (M = I); start just above it, where every drive is unstable
    # (the mean stiffness 8 eps^2 mu^2 > 0 repels) and tr M / 2 - 1 > 0 is formed accurately:
    # far below the averaging edge mu / sqrt(8 <V^2>), near which zone 0 begins as mu -> 0.
    from0 = g_a == 0.0
    eps_avg = mu / np.sqrt(8.0 * drive._mean_square_velocity)
    grid[:, 0] = np.where(from0, np.minimum(1e-3 * grid[:, 1], 1e-2 * eps_avg), grid[:, 0])
    R = np.broadcast_to(np.arange(mu.size)[:, None], grid.shape)
    F, th = _sample(drive, grid, np.broadcast_to(mu[:, None], grid.shape))
    A1 = np.arcsinh(1.0)
    F[:, 0] = np.where(from0, np.maximum(F[:, 0], A1), F[:, 0])
    th[:, 0] = np.where(from0, 0.0, th[:, 0])
    P_r, P_e, P_F, P_t = [R[has].ravel()], [grid[has].ravel()], [F[has].ravel()], [th[has].ravel()]
    # subdivide intervals that hold two or more zeros
    cnt = _zeros_between(th[:, :-1], th[:, 1:])
    rr, cc = np.nonzero((cnt >= 2) & has[:, None])
    ia, ib, ta, tb = grid[rr, cc], grid[rr, cc + 1], th[rr, cc], th[rr, cc + 1]
    sub = np.linspace(0.0, 1.0, 17)[1:-1]
    for _ in range(12):
        if rr.size == 0:
            break
        pts = ia[:, None] + (ib - ia)[:, None] * sub[None, :]
        Fs, ts = _sample(drive, pts, np.broadcast_to(mu[rr][:, None], pts.shape))
        P_r.append(np.repeat(rr, sub.size))
        P_e.append(pts.ravel())
        P_F.append(Fs.ravel())
        P_t.append(ts.ravel())
        e_all = np.concatenate([ia[:, None], pts, ib[:, None]], axis=1)
        t_all = np.concatenate([ta[:, None], ts, tb[:, None]], axis=1)
        c2 = _zeros_between(t_all[:, :-1], t_all[:, 1:]) >= 2
        i, j = np.nonzero(c2)
        rr, ia, ib, ta, tb = rr[i], e_all[i, j], e_all[i, j + 1], t_all[i, j], t_all[i, j + 1]
    r_all = np.concatenate(P_r)
    e_all = np.concatenate(P_e)
    F_all = np.concatenate(P_F)
    t_all = np.concatenate(P_t)
    order = np.lexsort((e_all, r_all))
    r_all, e_all, F_all, t_all = r_all[order], e_all[order], F_all[order], t_all[order]
    same_row = r_all[:-1] == r_all[1:]
    one = same_row & (_zeros_between(t_all[:-1], t_all[1:]) == 1) & (np.signbit(F_all[:-1]) != np.signbit(F_all[1:]))
    j = np.flatnonzero(one)
    empty = (np.zeros(0, np.int64),) * 2 + (np.zeros(0),) * 2
    if j.size == 0:
        return empty
    rows = r_all[j]
    zone = np.floor(t_all[j + 1] - 0.5).astype(np.int64)

    def solve(r, a, b, fa, fb, target, near_one=None, enough=None):
        mr = mu[r]
        if near_one is None:
            near_one = np.zeros(r.size, bool)

        def near(x, m):
            # (tr M / 2 - 1) / eps^2: nearly linear in eps^2 from eps = 0 to the edge
            return _tau_minus_one_scaled(x, m, levels, durations)

        def f(x, live):
            out = np.zeros(x.shape)
            use = live & near_one
            rest = live & ~near_one
            if rest.any():
                out[rest] = _asinh_tau(x[rest], mr[rest], levels, durations) - target[rest]
            if use.any():
                out[use] = near(x[use], mr[use])
            return out

        fa, fb = fa - target, fb - target
        if near_one.any():
            u = near_one
            fa, fb = fa.copy(), fb.copy()
            fa[u] = near(a[u], mr[u])
            fb[u] = near(b[u], mr[u])
        return _illinois(f, a, b, fa, fb, enough=enough)

    # Any point inside the zone will do as the inner end of the edges' brackets: stop there.
    # Where both samples are unstable the interval holds this zone and no part of another, so
    # a point with |tr M| < 2 found in it is in this zone.
    outside = (np.abs(F_all[j]) >= A1) & (np.abs(F_all[j + 1]) >= A1)
    za, zb, fza, fzb = solve(rows, e_all[j], e_all[j + 1], F_all[j], F_all[j + 1], np.zeros(rows.size),
                             enough=np.where(outside, 0.5 * A1, 0.0))
    z = np.where(np.abs(fza) <= np.abs(fzb), za, zb)
    Fz = np.where(np.abs(fza) <= np.abs(fzb), fza, fzb)
    keep = np.ones(rows.size, bool) if keep_all else (z >= e_a[rows]) & (z <= e_b[rows])
    rows, zone, z, j, Fz = rows[keep], zone[keep], z[keep], j[keep], Fz[keep]
    if rows.size == 0:
        return empty
    # Brackets for the edges: the largest |tr M| between this zero and its neighbours' (the
    # gap, where |tr M| >= 2 unless two zones touch), found by golden-section search; for
    # zone 0 on the left, the first sample just above eps = 0 (tr M / 2 - 1 > 0 there).
    order = np.lexsort((z, rows))
    rows, zone, z, Fz = rows[order], zone[order], z[order], Fz[order]
    same_prev = np.r_[False, (rows[1:] == rows[:-1]) & (zone[1:] == zone[:-1] + 1)]
    same_next = np.r_[same_prev[1:], False]
    prev = np.where(same_prev, np.r_[0.0, z[:-1]], grid[rows, 0])
    nxt = np.where(same_next, np.r_[z[1:], 0.0], grid[rows, -1])
    xl, FL = _gap_peak(lambda x, live: _asinh_tau(x, mu[rows][live], levels, durations), prev, z)
    xr, FR = _gap_peak(lambda x, live: _asinh_tau(x, mu[rows][live], levels, durations), z, nxt)
    first0 = (zone == 0) & ~same_prev & from0[rows]
    xl = np.where(first0, grid[rows, 0], xl)
    FL = np.where(first0, F[rows, 0], FL)
    ok = (np.abs(FL) >= A1) & (np.abs(FR) >= A1)
    rows, zone, z, xl, xr, FL, FR, Fz = rows[ok], zone[ok], z[ok], xl[ok], xr[ok], FL[ok], FR[ok], Fz[ok]
    if rows.size == 0:
        return empty
    tl = np.where(zone % 2 == 0, A1, -A1)  # tr M = +2 below an even zone, -2 below an odd one
    tr_ = -tl
    rsum = _elliptic_rate(mu[rows], levels, durations) + _hyperbolic_rate(mu[rows], levels, durations)
    # the lower edge of zone 0 (and of any even zone while the phases are short): on
    # tr M / 2 - 1 formed without cancellation (its terms are of order a mu^2 and a^2, a = 8 eps^2)
    near_one = (tl > 0) & (((zone == 0) & _cancels(mu[rows], levels) & (rsum * z < 40.0)) | (rsum * z < 3.0))
    a, b, fa, fb = solve(rows, xl, z, FL, Fz, tl, near_one)
    lo = _unstable_end(a, b, fa, fb, FL - tl)
    a, b, fa, fb = solve(rows, z, xr, Fz, FR, tr_)
    hi = _unstable_end(a, b, fa, fb, FR - tr_)
    # a zone thinner than the spacing of doubles has no stable double: tr M jumps across its
    # zero from one sign to the other, and both edges round to that zero
    thin = np.abs(Fz) >= A1
    lo = np.where(thin, z, lo)
    hi = np.where(thin, z, hi)
    return rows, zone, _kapitza_zone0(drive, mu, rows, zone, lo, hi), hi


def _kapitza_zone0(drive, mu, rows, zone, lo, hi):
    """``lo`` with zone 0's lower edge below the drive's :meth:`~kapitza.drives.Drive._kapitza_mu` moved
    to the double the certified verdict puts it at (:func:`kapitza.drives._api.kapitza_edge`), searched
    from the averaging threshold ``sqrt(mu^2 + s) / sqrt(8 k)`` (off it by ``O(mu^2)`` relative; ``s`` the
    mean that the rounded levels leave, duty 0.3: -1.4e-17); 0 where that mean holds the rod up
    (``mu^2 + s <= 0``: the mean stiffness attracts, zone 0 reaches ``eps -> 0``)."""
    from ._api import kapitza_edge

    k0 = np.flatnonzero((zone == 0) & (mu[rows] < drive._kapitza_mu(False)) & np.isfinite(hi))
    if not k0.size:
        return lo
    lo = lo.copy()
    m = mu[rows[k0]]
    # mu^2 + s, exactly: the mean stiffness is 8 eps^2 (mu^2 + s); its root from the integers' logarithms
    # (it may lie beyond the doubles' range as a square)
    g = [Fraction(v) ** 2 + drive._exact_mean for v in m.tolist()]
    holds = np.array([x <= 0 for x in g], bool)
    lo[k0[holds]] = 0.0
    if holds.all():
        return lo
    k0, m = k0[~holds], m[~holds]
    root = np.array([math.exp(0.5 * (math.log(x.numerator) - math.log(x.denominator))) for x in g if x > 0])
    start = root / np.sqrt(8.0 * drive._mean_square_velocity)
    ok = (start > 0) & (start < hi[k0])
    if ok.any():
        found, _, good = kapitza_edge(drive, m[ok], start[ok], hi[k0[ok]])
        lo[k0[ok][good]] = found[good]
    return lo


def sampled_edges(drive, mu, n, per_turn=3):
    """Edges of zone ``n`` at each ``mu`` (undamped; NaN where the drive has no such zone).

    The window is where zone ``n``'s zero can lie: ``|theta_rot - rate eps| < (K + 1) pi``
    (see :func:`zones_in_window`).
    """
    mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
    shape = mu.shape
    mu, n = mu.ravel(), n.ravel()
    rate, _ = _window_margin(mu, drive.levels, drive._durations)
    B = (len(drive.levels) + 1) * PI
    rs = np.where(rate > 0, rate, 1.0)
    e_a = np.maximum((n * PI - B) / rs, 0.0)
    e_b = ((n + 1) * PI + B) / rs
    lo_out = np.full(mu.size, np.nan)
    hi_out = np.full(mu.size, np.nan)
    rows, zone, lo, hi = zones_in_window(drive, mu, e_a, e_b, per_turn)
    want = zone == n[rows]
    lo_out[rows[want]] = lo[want]
    hi_out[rows[want]] = hi[want]
    return lo_out.reshape(shape), hi_out.reshape(shape)


def _gap_peak(F, a, b):
    """Golden-section search for the largest ``|F|`` on ``(a, b)`` (one hump); returns (x, F(x))."""
    r = 0.5 * (np.sqrt(5.0) - 1.0)
    a, b = a.copy(), b.copy()
    everywhere = np.ones(a.shape, bool)
    c = b - r * (b - a)
    d = a + r * (b - a)
    Fc = F(c, everywhere)
    Fd = F(d, everywhere)
    best_x = np.where(np.abs(Fc) >= np.abs(Fd), c, d)
    best_F = np.where(np.abs(Fc) >= np.abs(Fd), Fc, Fd)
    A1 = np.arcsinh(1.0)
    for _ in range(60):
        live = (np.abs(best_F) < A1) & (b - a > 4e-16 * b)
        if not live.any():
            break
        left = np.abs(Fc) >= np.abs(Fd)
        b = np.where(live & left, d, b)
        a = np.where(live & ~left, c, a)
        p = np.where(left, b - r * (b - a), a + r * (b - a))
        Fp = np.zeros(p.shape)
        Fp[live] = F(p[live], live)
        c, d = np.where(live, np.where(left, p, d), c), np.where(live, np.where(left, c, p), d)
        Fc, Fd = np.where(live, np.where(left, Fp, Fd), Fc), np.where(live, np.where(left, Fc, Fp), Fd)
        better = live & (np.abs(Fp) > np.abs(best_F))
        best_x = np.where(better, p, best_x)
        best_F = np.where(better, Fp, best_F)
    return best_x, best_F


def _unstable_end(a, b, fa, fb, f_out):
    """Of the final bracket ends, the one where f has the sign it has outside the zone
    (an exact zero of f is the edge itself, which counts as unstable)."""
    out_a = (fa == 0) | (np.sign(fa) == np.sign(f_out))
    out_b = (fb == 0) | (np.sign(fb) == np.sign(f_out))
    return np.where(out_b & ~(fa == 0), b, np.where(out_a, a, b))
