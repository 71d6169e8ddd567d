"""Verdicts to the last bit for the paper's square wave.

The closed forms give ``a = w - alpha`` and ``b = w - beta`` (``docs/theory.md`` section 5)
with an absolute error of a few units in the last place of ``u = w_e T`` (``u`` is formed from
the rounded ``eps`` and ``sqrt(1 - mu^2)``; ``alpha`` and ``beta`` are flat in ``x`` far out).
Where ``|a|`` or ``|b|`` is inside that bound the sign, and with it the verdict, the zone and
the growth, is not determined by the double computation: there ``tr M / 2`` is evaluated for
the exact double inputs in mpmath, at a precision that covers the cancellation of
``e^x``-sized terms (:func:`tau_mp`, the product of the two phase matrices, which serves every
piecewise-constant drive). Such points are rare (a band a few ulp wide about each edge), so the fast path
keeps its speed.
"""
from __future__ import annotations

import operator

import numpy as np

_TOL = 16.0 * np.finfo(float).eps
#: A few units of rounding, as the bounds on the closed forms count them.
TOL = _TOL


#: Beyond this phase angle the exact decision would need more than ~2,000 digits: the double
#: verdict stands there (the phase ``u`` itself is then known to ``1e-16 u`` only).
MAX_PHASE = 4000.0

#: Where the error bound of ``tr M`` exceeds this fraction of it, a trace that is reported
#: (:func:`kapitza.floquet`, the growth, the multipliers) of a piecewise-constant drive is
#: recomputed in extended precision. Without cancellation the segment product's bound is about
#: ``u (16 K + 6 sum r)`` relative (the square wave's closed forms, ``16 u (x + 4)``), below 3e-12
#: up to ``MAX_PHASE``: 1e-10 sends to ``mpmath`` only the points where cancellation has cost
#: digits (a band where ``|tr M| < 1e-2 e^L`` or so, about each zone and each zero of the trace),
#: and leaves every other trace and multiplier good to 1e-10 relative, the growth to 1e-10 absolute.
TRACE_RTOL = 1e-10


def unsure(u, a, b, x=None):
    """Where the signs of ``a`` or ``b`` are within rounding of zero (and an exact decision is
    affordable: ``x + u <= MAX_PHASE``)."""
    bound = _TOL * (np.abs(u) + 4.0)
    near = (np.abs(a) <= bound) | (np.abs(b) <= bound)
    size = np.abs(u) if x is None else np.abs(u) + np.abs(x)
    return near & (size <= MAX_PHASE)


def exact_half_trace(eps, mu, zeta=None):
    """``(tau, log|tau|, stable, angle)`` of the square wave at the exact double ``(eps, mu)``
    (mpmath): ``stable`` is ``|tau| < 1`` decided in extended precision (the float ``tau`` may
    round to 1); ``angle`` is ``acos(tau)`` on a zone and the growth ``acosh|tau|`` off it.
    ``zeta``: at ``mu^2 (1 + zeta^2)`` formed exactly (:func:`tau_mp`)."""
    res = tau_mp(np.ravel(eps), np.ravel(mu), (1.0, -1.0), (1.0, 1.0), None if zeta is None else np.ravel(zeta))
    shape = np.shape(eps)
    tau = np.array([r[0] for r in res]).reshape(shape)
    log_tau = np.array([r[1] for r in res]).reshape(shape)
    stable = np.array([r[2] for r in res], dtype=bool).reshape(shape)
    angle = np.array([r[3] for r in res]).reshape(shape)
    return tau, log_tau, stable, angle


def _half_trace_mp(E8, MM, levels, durations, prec):
    """``tr M / 2`` (a raw mpmath number) of the segment product with ``k_i = E8 (MM + s_i)``, each
    operation correctly rounded to ``prec`` bits (``E8 = 8 eps^2``, ``MM = mu^2``, raw numbers)."""
    from mpmath import libmp as L

    one, zero = L.fone, L.fzero
    a, b, c, d = one, zero, zero, one
    for s, h in zip(levels, durations):
        k = L.mpf_mul(E8, L.mpf_add(MM, L.from_float(float(s)), prec), prec)
        H = L.from_float(float(h))
        sign = L.mpf_sign(k)
        if sign == 0:
            sa, sb, sc, sd = one, H, zero, one
        else:
            w = L.mpf_sqrt(L.mpf_abs(k), prec)
            x = L.mpf_mul(w, H, prec)
            if sign > 0:
                ch, sh = L.mpf_cosh_sinh(x, prec)
                sa, sb, sc, sd = ch, L.mpf_div(sh, w, prec), L.mpf_mul(w, sh, prec), ch
            else:
                co, si = L.mpf_cos_sin(x, prec)
                sa, sb, sc, sd = co, L.mpf_div(si, w, prec), L.mpf_neg(L.mpf_mul(w, si, prec)), co
        a, b, c, d = (L.mpf_add(L.mpf_mul(sa, a, prec), L.mpf_mul(sb, c, prec), prec),
                      L.mpf_add(L.mpf_mul(sa, b, prec), L.mpf_mul(sb, d, prec), prec),
                      L.mpf_add(L.mpf_mul(sc, a, prec), L.mpf_mul(sd, c, prec), prec),
                      L.mpf_add(L.mpf_mul(sc, b, prec), L.mpf_mul(sd, d, prec), prec))
    return L.mpf_shift(L.mpf_add(a, d, prec), -1)


def _dps(e, m2, levels, durations):
    """Digits that cover the cancellation of ``e^{sum r}`` terms (and, near ``eps -> 0``, the
    ``O(rsum^4)`` size of ``tr M/2 - 1``)."""
    rsum = sum(np.sqrt(8.0 * e * e * abs(m2 + s)) * h for s, h in zip(levels, durations))
    return 40 + int(rsum / np.log(10.0)) + int(4.0 * max(0.0, -np.log10(max(rsum, 1e-300))))


def tau_mp(eps, mu, levels, durations, zeta=None):
    """``tr M / 2`` in mpmath, at a precision that covers the cancellation of ``e^{sum r}`` terms:
    ``[(tau, log|tau|, stable, angle)]`` per point (``angle`` as in :func:`exact_half_trace`).

    ``zeta`` (flat, optional): the half-trace of the damped system's ``phi``-equation instead, taken at
    ``mu^2 (1 + zeta^2)`` formed exactly from the doubles ``mu`` and ``zeta`` (not at their rounded
    ``mu_c``: where the trace cancels, one rounding of ``mu_c`` moves it by more than its size).

    The segment matrices and their product are formed on mpmath's raw binary numbers
    (``mpmath.libmp``), each operation correctly rounded at the working precision."""
    import mpmath
    from mpmath import libmp as L

    one, zero = L.fone, L.fzero
    out = []
    zs = [0.0] * np.size(eps) if zeta is None else np.asarray(zeta, float).tolist()
    for e, m, z in zip(eps.tolist(), mu.tolist(), zs):
        prec = L.dps_to_prec(_dps(e, m * m * (1.0 + z * z), levels, durations))
        E8 = L.mpf_mul(L.from_int(8), L.mpf_mul(L.from_float(e), L.from_float(e), prec), prec)
        MM = L.mpf_mul(L.from_float(m), L.from_float(m), prec)
        if z:
            ZZ = L.mpf_mul(L.from_float(z), L.from_float(z), prec)
            MM = L.mpf_mul(MM, L.mpf_add(one, ZZ, prec), prec)
        t = _half_trace_mp(E8, MM, levels, durations, prec)
        # the verdict |t| < 1 is decided here, in extended precision; the float of t may
        # round to +-1 on either side
        at = L.mpf_abs(t)
        st = L.mpf_lt(at, one)
        # on a zone the rotation angle acos(t), off it the growth acosh|t|, each to full
        # relative accuracy (t may round to +-1)
        with mpmath.workprec(prec):
            T = mpmath.mpf(t)
            angle = float(mpmath.acos(T)) if st else float(mpmath.acosh(abs(T)))
        near = L.round_nearest
        out.append((L.to_float(t, rnd=near), L.to_float(L.mpf_log(at, prec, near), rnd=near) if t != zero else -np.inf,
                    bool(st), angle))
    return out


def damped_mp(eps, mu, zeta, levels, durations):
    """The damped verdict at the exact doubles ``eps, mu, zeta`` of a piecewise-constant drive:
    ``[(stable, growth)]`` per point, ``stable`` iff ``|tr M_phi| / 2 < cosh(kappa)`` decided in
    extended precision (``M_phi`` the monodromy of ``phi = e^{ct/2} theta`` at ``mu^2 (1 + zeta^2)``,
    ``kappa = 2 sqrt 8 zeta mu eps = c T``), ``growth = log max|lambda|`` of the damped system
    (``acosh|tr M_phi / 2| - kappa`` off the phi-zones, ``-kappa`` on them). The precision doubles
    until the difference is resolved (up to 3,000 digits; beyond, the last answer stands)."""
    import mpmath
    from mpmath import libmp as L

    out = []
    for e, m, z in zip(eps.tolist(), mu.tolist(), zeta.tolist()):
        dps = _dps(e, m * m * (1.0 + z * z), levels, durations)
        while True:
            prec = L.dps_to_prec(dps)
            with mpmath.workprec(prec):
                E, M, Z = mpmath.mpf(e), mpmath.mpf(m), mpmath.mpf(z)
                E8 = (8 * E * E)._mpf_
                MM = (M * M * (1 + Z * Z))._mpf_
                t = mpmath.mpf(_half_trace_mp(E8, MM, levels, durations, prec))
                kappa = 2 * mpmath.sqrt(8) * Z * M * E
                diff = abs(t) - mpmath.cosh(kappa)
                resolved = diff != 0 and abs(diff) > mpmath.mpf(2) ** (-(prec - 64)) * mpmath.cosh(kappa)
                if resolved or dps > 3000:
                    growth = (mpmath.acosh(abs(t)) if abs(t) > 1 else mpmath.mpf(0)) - kappa
                    out.append((bool(diff < 0), float(growth)))
                    break
            dps *= 2
    return out


# ---------------------------------------------------------------- piecewise-linear shapes (Taylor series)
def _pieces_half_trace(e, m, z, pieces, P):
    """``(tr M / 2) * 2^(2P)`` (an integer) for the exact doubles ``eps = e``, ``mu = m`` and
    ``zeta = z`` (``mu^2`` raised to ``mu^2 (1 + zeta^2)``, the damped system's ``phi``-equation) of
    the drive whose shape is linear on each piece ``(x0, x1, s0, s1)`` of the period (``s`` from
    ``s0`` at ``x0`` to ``s1`` at ``x1``; constant where ``s0 = s1``).

    On a piece ``phi'' = (a + b x) phi`` with ``a + b x = 8 eps^2 (mu^2 + s(x))``: each sub-step ``h``
    (``h^2 max|a + b x| <= 1``) is a Taylor series in fixed-point integer arithmetic (values times
    ``2^P``, the doubles taken exactly), ``Y_k = phi^(k) h^k / k!``,
    ``Y_(k+2) = h^2 (a Y_k + b h Y_(k-1)) / ((k + 1)(k + 2))``, summed until three terms in a row
    vanish at ``2^-P``."""
    import math

    def fixed(x):  # a double times 2^P, exactly (to the floor below 2^-P)
        num, den = float(x).as_integer_ratio()
        return (num << P) // den

    one = 1 << P
    E = 8 * fixed(e) ** 2 >> P
    M2 = (fixed(m) ** 2 >> P) * (one + (fixed(z) ** 2 >> P)) >> P
    cols = [[one, 0], [0, one]]
    for x0, x1, s0, s1 in pieces:
        width = float(x1) - float(x0)
        if not width > 0:
            continue
        peak = 8.0 * e * e * max(abs(m * m * (1.0 + z * z) + s0), abs(m * m * (1.0 + z * z) + s1))
        steps = max(1, math.ceil(width * math.sqrt(peak) * (1.0 + 1e-9)))
        S0, dS = fixed(s0), fixed(s1) - fixed(s0)
        hf = fixed(x1) - fixed(x0)
        hf //= steps
        hh = hf * hf >> P
        bh = (E * dS >> P) // steps
        for j in range(steps):
            A = E * (M2 + S0 + dS * j // steps) >> P
            taylor_step(cols, (A, bh), hf, hh, P)
    return (cols[0][0] + cols[1][1]) << (P - 1)


def taylor_step(cols, C, hf, hh, P):
    """One step ``h`` of ``y'' = c(z) y`` for each column ``[y, y']`` of ``cols`` (in place), by Taylor
    series in fixed-point integers (values times ``2^P``; ``hf = h``, ``hh = h^2``): ``C[i]`` are the
    Taylor coefficients of ``c`` at the step's start scaled by ``h^i``, and with
    ``Y_k = y^(k) h^k / k!``, ``Y_(k+2) = h^2 sum_i C[i] Y_(k-i) / ((k + 1)(k + 2))``, summed until three
    terms in a row vanish at ``2^-P``."""
    for col in cols:
        Y = [col[0], col[1] * hf >> P]
        k = 0
        while True:
            # sum_i C[i] Y[k - i] over i <= min(k, len(C) - 1) (integers: exact in any order)
            acc = sum(map(operator.mul, C, Y[k::-1]))
            Y.append(((acc >> P) * hh >> P) // ((k + 1) * (k + 2)))
            k += 1
            if k > 8 and abs(Y[-1]) < 16 and abs(Y[-2]) < 16 and abs(Y[-3]) < 16:
                break
        col[0] = sum(Y)
        col[1] = (sum(i * Yi for i, Yi in enumerate(Y)) << P) // hf


def _pieces_growth_bits(e, m2, pieces):
    """Bits of ``e^G``, ``G`` bounding the growth of the solutions over the period (the integral of
    ``sqrt(max(k, 0))``, taken at each piece's larger end)."""
    G = sum(np.sqrt(8.0 * e * e * max(m2 + s0, m2 + s1, 0.0)) * (x1 - x0) for x0, x1, s0, s1 in pieces)
    return int(G / np.log(2.0)) + 1


def pieces_phase(eps, mu, pieces):
    """The phase ``sum sqrt(|k|) h`` over the period at flat ``eps, mu`` (the cost of an exact decision
    grows with it; beyond :data:`MAX_PHASE` the double verdict stands)."""
    eps, mu = np.asarray(eps, float), np.asarray(mu, float)
    m2 = mu * mu
    return sum(np.sqrt(8.0 * eps * eps * np.maximum(np.abs(m2 + s0), np.abs(m2 + s1))) * (x1 - x0)
               for x0, x1, s0, s1 in pieces)


def pieces_mp(eps, mu, zeta, pieces):
    """Verdicts at the exact doubles of a drive linear on each of ``pieces``, decided in extended
    precision (flat arrays; :func:`_pieces_half_trace`): ``[(tau, log|tau|, stable, growth)]``.

    ``zeta`` None: the undamped system, ``stable`` iff ``|tr M / 2| < 1``, ``growth = acosh|tau|``
    off the zones (0 on them). Otherwise the damped one: ``tau`` that of the ``phi``-system at
    ``mu^2 (1 + zeta^2)``, ``stable`` iff ``|tau| < cosh(kappa)`` (``kappa = 2 sqrt 8 zeta mu eps``),
    ``growth = log max|lambda|``. The precision starts at 96 bits beyond the growth ``e^G`` of the
    solutions and doubles until ``|tau|`` is resolved from the threshold by more than ``2^32`` times
    the series' rounding (to 3,000 bits; beyond, the last answer stands)."""
    import math

    import mpmath

    out = []
    zs = [0.0] * np.size(eps) if zeta is None else np.asarray(zeta, float).tolist()
    for e, m, z in zip(np.asarray(eps, float).tolist(), np.asarray(mu, float).tolist(), zs):
        bits = _pieces_growth_bits(e, m * m * (1.0 + z * z), pieces)
        P = 96 + bits
        while True:
            num = _pieces_half_trace(e, m, z, pieces, P)
            if z == 0.0:
                # undamped: |tau| against 1 in integers (tau = num / 2^(2P)), the logarithms from
                # the correctly rounded quotient of the integers
                one = 1 << (2 * P)
                gap = abs(num) - one
                if abs(gap) > 1 << (P + bits + 32) or P > 1500:
                    if gap.bit_length() < 2 * P + 1000:
                        x = gap / one  # |tau| - 1, correctly rounded
                        log_tau = math.log1p(x) if x > -1.0 else -np.inf
                        growth = math.log1p(x + math.sqrt(x * (x + 2.0))) if x > 0.0 else 0.0
                        if not math.isfinite(growth):  # acosh t = log 2t to rounding
                            growth = log_tau + math.log(2.0)
                        tau = num / one
                    else:  # |tau| beyond 2^1000: its logarithm from the integer
                        log_tau = math.log(abs(num)) - 2 * P * math.log(2.0)
                        growth = log_tau + math.log(2.0)
                        tau = math.copysign(math.inf, num)
                    out.append((tau, log_tau, gap < 0, growth))
                    break
                P *= 2
                continue
            with mpmath.workprec(2 * P + 64):
                t = mpmath.mpf(num) / mpmath.mpf(2) ** (2 * P)
                kappa = 2 * mpmath.sqrt(8) * mpmath.mpf(z) * mpmath.mpf(m) * mpmath.mpf(e)
                bar = mpmath.cosh(kappa)
                diff = abs(t) - bar
                if abs(diff) > mpmath.mpf(2) ** (-(P - bits - 32)) * bar or P > 1500:
                    growth = (mpmath.acosh(abs(t)) if abs(t) > 1 else mpmath.mpf(0)) - kappa
                    log_tau = float(mpmath.log(abs(t))) if num else -np.inf
                    out.append((float(t), log_tau, bool(diff < 0), float(growth)))
                    break
            P *= 2
    return out
