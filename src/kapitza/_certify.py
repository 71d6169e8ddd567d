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
    return near & affordable(u, x)


def affordable(u, x=None):
    """Where an exact decision is affordable: ``|u| + |x| <= MAX_PHASE``, asked without forming the
    sum (phases near the largest double would overflow it)."""
    u = np.abs(u)
    if x is None:
        return u <= MAX_PHASE
    return (u <= MAX_PHASE) & (np.abs(x) <= MAX_PHASE - np.minimum(u, MAX_PHASE))


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
    # (e, not e^2, which underflows below 1e-162)
    rsum = sum(np.sqrt(8.0) * e * np.sqrt(abs(m2 + s)) * h for s, h in zip(levels, durations))
    return 40 + int(rsum / np.log(10.0)) + int(4.0 * max(0.0, -np.log10(max(rsum, 1e-323))))


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


def small_eps_bits(eps, scale):
    """At small ``eps``, ``|tau| - 1`` is of order ``(scale eps^2)^2`` times the distance to the edge of
    zone 0 (``scale eps^2`` the drive's strength: ``8 eps^2`` for linear pieces, ``q`` for the sine):
    the bits that takes, with which an exact trace starts, and beyond which it goes past the 3,000."""
    import math

    return int(max(0.0, -2.0 * (math.log2(scale) + 2.0 * math.log2(eps)))) if eps > 0 else 0


def _isqrt_scaled(n, shift):
    """``sqrt(n) / 2^shift`` for a positive integer ``n``, to a double (its top 64 bits rounded once)."""
    import math

    r = math.isqrt(n)
    k = max(r.bit_length() - 64, 0)
    return math.ldexp(float(r >> k), k - shift)


def pieces_mp(eps, mu, zeta, pieces):
    """Verdicts at the exact doubles of a drive linear on each of ``pieces``, decided in extended
    precision (flat arrays; :func:`_pieces_half_trace`): ``[(tau, log|tau|, stable, growth)]``.

    ``zeta`` None: the undamped system, ``stable`` iff ``|tr M / 2| < 1``, ``growth = acosh|tau|``
    off the zones (0 on them). Otherwise the damped one: ``tau`` that of the ``phi``-system at
    ``mu^2 (1 + zeta^2)``, ``stable`` iff ``|tau| < cosh(kappa)`` (``kappa = 2 sqrt 8 zeta mu eps``),
    ``growth = log max|lambda|``. The precision starts at 96 bits beyond the growth ``e^G`` of the
    solutions and doubles until ``|tau|`` is resolved from the threshold by more than ``2^44`` times
    the series' rounding (to 3,000 bits, more at small ``eps``; beyond, the last answer stands)."""
    import math

    import mpmath

    out = []
    zs = [0.0] * np.size(eps) if zeta is None else np.asarray(zeta, float).tolist()
    for e, m, z in zip(np.asarray(eps, float).tolist(), np.asarray(mu, float).tolist(), zs):
        bits = _pieces_growth_bits(e, m * m * (1.0 + z * z), pieces)
        small = small_eps_bits(e, 8.0)
        P = 96 + bits + small
        cap = 1500 + small
        while True:
            num = _pieces_half_trace(e, m, z, pieces, P)
            if z == 0.0:
                # undamped: |tau| against 1 in integers (tau = num / 2^(2P)), the logarithms from
                # the correctly rounded quotient of the integers
                one = 1 << (2 * P)
                gap = abs(num) - one
                if abs(gap) > 1 << (P + bits + 44) or P > cap:
                    if gap.bit_length() < 2 * P + 1000:
                        x = gap / one  # |tau| - 1, correctly rounded
                        log_tau = math.log1p(x) if x > -1.0 else -np.inf
                        growth = math.log1p(x + math.sqrt(x * (x + 2.0))) if x > 0.0 else 0.0
                        if not math.isfinite(growth):  # acosh t = log 2t to rounding
                            growth = log_tau + math.log(2.0)
                        elif 0 < gap and x < 1e-300:
                            # acosh(1 + x) = sqrt(2x) (1 - x/12 + ...) with x below the normal doubles
                            # (a period of tiny phase): the square root from the integers
                            growth = _isqrt_scaled(2 * gap, P)
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
                if abs(diff) > mpmath.mpf(2) ** (-(P - bits - 44)) * bar or P > cap:
                    growth = (mpmath.acosh(abs(t)) if abs(t) > 1 else mpmath.mpf(0)) - kappa
                    log_tau = float(mpmath.log(abs(t))) if num else -np.inf
                    out.append((float(t), log_tau, bool(diff < 0), float(growth)))
                    break
            P *= 2
    return out


# ---------------------------------------------------------------- long double tiers
#: numpy's long double where it carries more bits than a double (x86's 80-bit format), else None: the
#: tiers between the doubles and mpmath (step products, linear pieces, the sine's Taylor steps and counts)
LONG_DOUBLE = np.longdouble if np.finfo(np.longdouble).nmant >= 60 else None
#: whether those tiers are there
HAS_LONG_DOUBLE = LONG_DOUBLE is not None
#: its unit roundoff
LD_UNIT = float(np.finfo(np.longdouble).eps) / 2.0

#: Points times Taylor steps handled at once by :func:`pieces_ld` (its terms are kept for the sums)
_LD_CHUNK = 16384

#: Beyond this many Taylor steps a period the long double tier declines (mpmath decides)
_LD_MAX_STEPS = 4096


def _pieces_ld_chunk(e, m2, pieces, steps, unit):
    """``(tau, bound)``: ``tr M / 2`` of the ``phi``-equation and a bound on its error (long double) of
    the linear pieces at long double ``e = eps`` and ``m2 = mu^2 (1 + zeta^2)``, with ``steps[i]``
    Taylor steps on piece ``i`` (see :func:`pieces_ld`)."""
    LD = e.dtype.type
    E = 8.0 * e * e
    a_l, b_l, h_l, da_l = [], [], [], []
    for (x0, x1, s0, s1), k in zip(pieces, steps):
        width = LD(x1) - LD(x0)
        if not width > 0:
            continue
        S0, dS = LD(s0), LD(s1) - LD(s0)
        h = width / k
        hh = h * h
        j = np.arange(k, dtype=LD)[:, None]
        A = E * (m2 + (S0 + dS * j / k))                 # c at each step's start
        a = A * hh
        b = np.broadcast_to(E * dS / k * hh, a.shape)   # c' h, times h^2
        # the coefficients' own rounding (from the exact doubles): A to 8 units of E (m2 + |s0| + |dS|),
        # h^2 to 5, b to 9 of itself, and the time steps' lengths (2 units each) as a coefficient's change
        da = (8.0 * unit * E * (m2 + abs(S0) + abs(dS)) * hh + 12.0 * unit * np.abs(a)) + 12.0 * unit * np.abs(b)
        a_l.append(a)
        b_l.append(b)
        h_l.append(np.full((k, 1), h, LD))
        da_l.append(da)
    a, b, h, da = np.concatenate(a_l), np.concatenate(b_l), np.concatenate(h_l), np.concatenate(da_l)
    # the basis (y, y' / w), w a power of two near the largest sqrt|c| (the trace does not depend on the
    # basis; in this one the steps are near rotations where c < 0)
    _, kw = np.frexp(np.sqrt(E * (m2 + max(abs(float(p[2])) for p in pieces) + max(abs(float(p[3])) for p in pieces))))
    S, fro = taylor_ld([a, b], da, h, kw, unit)
    (p00, _, _, p11), acc, ex = product_ld(S, fro, unit)
    tr = p00 + p11
    # |tr dP| <= sqrt(2) |dP|_F; back to scale (the long double's range holds 2^ex)
    return np.ldexp(0.5 * tr, ex), np.ldexp(0.5 * (np.sqrt(LD(2.0)) * acc + unit * np.abs(tr)), ex)


def taylor_ld(coef, delta, h, kw, unit):
    """The Taylor steps of ``y'' = c y`` in long double, and their errors: ``coef[i]`` (arrays ``[step,
    point]``) are the coefficients of ``c`` in ``u`` (the step is ``x = x_j + h u``, ``u`` in ``[0, 1]``)
    times ``h^2``, ``delta`` bounds their total rounding (from the exact doubles), ``h`` the step
    lengths (``[step, 1]``), ``kw`` the exponent of the basis ``(y, y' / 2^kw)``. Returns the steps'
    entries ``(s00, s01, s10, s11)`` and a bound on each step's error (Frobenius norm), its share of
    the product's rounding (two units of ``|S| |P|`` an entry) counted in.

    With ``W_k = y^(k) h^k / k!``, ``W_(k+2) = sum_i coef_i W_(k-i) / ((k + 1)(k + 2))``. The series is
    majorised by that of ``y'' = s y``, ``s = sum_i |coef_i|`` (comparison on ``[0, 1]``): the sums of
    ``|W_k|``, ``k |W_k|``, ``k^2 |W_k|`` are at most ``cosh``, ``sqrt s sinh``, ``s cosh + sqrt s sinh`` of
    ``sqrt s`` (first column; the second ``sinh/sqrt s``, ``cosh``, ``s sinh/sqrt s + cosh``)."""
    shape = coef[0].shape
    n_c = len(coef)
    s = sum(np.abs(c) for c in coef)
    s_max = float(np.max(s))
    one, zero = np.ones(shape, coef[0].dtype), np.zeros(shape, coef[0].dtype)
    W = [np.stack([one, zero]), np.stack([zero, one])]
    # terms until the majorant's tail is below unit / 64: the same recursion in scalars, on the largest
    # |coef_i| (R_k >= |W_k| for both columns); past K each next term is at most s_max / (K (K + 1))
    # of the largest of the last n_c, so the tail is below 2 s_max max(R) / (K (K + 1)) (s_max <= 3, K > 8)
    A = [float(np.max(np.abs(c))) for c in coef]
    r = [1.0, 1.0]
    k = 0
    while True:
        acc = coef[0] * W[k]
        for i in range(1, min(k, n_c - 1) + 1):
            acc = acc + coef[i] * W[k - i]
        W.append(acc / ((k + 1) * (k + 2)))
        r.append(sum(A[i] * r[k - i] for i in range(min(k, n_c - 1) + 1)) / ((k + 1) * (k + 2)))
        k += 1
        K = len(W) - 1
        if K > 8 and 4.0 * max(s_max, 1e-300) * max(r[-n_c - 1:]) / (K * (K + 1)) < unit / 64.0:
            break
    K = len(W) - 1
    val = W[K].copy()
    der = K * W[K]
    for i in range(K - 1, -1, -1):   # (smallest terms first: the sums' rounding is u sum (k + 1)|W_k|)
        val = val + W[i]
        der = der + i * W[i]
    sig = np.sqrt(s)
    ch, sh = np.cosh(sig), np.where(sig > 0, np.sinh(sig) / np.where(sig > 0, sig, 1.0), 1.0)  # sinh(sig)/sig
    sums = ((ch, s * sh, s * ch + s * sh), (sh, ch, s * sh + ch))   # col 1: (sum, sum k, sum k^2); col 2
    tail = unit / 64.0
    # each term: n_c products and sums and a division, (n_c + 3)/2 units per unit of k
    grow = 0.5 * (n_c + 3)
    # a change d of the coefficient moves y(1) by at most d int_0^1 G(1, v) |y(v)| dv (G the majorant's
    # Green's function, sinh(sig (1 - v)) / sig, and |y| <= cosh(sig v) or sinh(sig v) / sig), y'(1)
    # likewise with cosh(sig (1 - v)): for the first column sinh(sig)/(2 sig) and (cosh + sinh/sig)/2,
    # for the second (cosh - sinh/sig)/(2 s) <= cosh/4 and sinh(sig)/(2 sig); a quarter more for the
    # second order
    green = ((0.5 * sh, 0.5 * (ch + sh)), (0.25 * ch, 0.5 * sh))
    err_v, err_d = [], []
    for (S, Sk, Sk2), (gv, gd) in zip(sums, green):
        # the terms' recursion, the reverse sums, k W_k, the coefficients' rounding, the tail left out
        err_v.append(unit * ((grow + 1.0) * Sk + S) + 1.25 * delta * gv + tail * S)
        err_d.append(unit * ((grow + 1.0) * Sk2 + 3.0 * Sk) + 1.25 * delta * gd + tail * Sk)
    hv = np.ldexp(h * val[1], kw)
    hd = np.ldexp(der[0] / h, -kw)
    S = (val[0], hv, hd, der[1])
    dS = (err_v[0], np.ldexp(h * err_v[1], kw) + 2.0 * unit * np.abs(hv),
          np.ldexp(err_d[0] / h, -kw) + 2.0 * unit * np.abs(hd), err_d[1])
    fro = np.sqrt(sum(x * x for x in dS)) + 2.0 * unit * np.sqrt(sum(x * x for x in S))
    return S, fro


def product_ld(S, fro, unit):
    """The product ``S_m ... S_1`` of the steps (entries ``[step, point]``) as ``(p, bound, e)``: entries
    ``p`` with the product ``2^e p``, and ``bound`` on the Frobenius norm of its error at that scale:
    ``sum_j |S_m ... S_(j+1)| |dS_j| |S_(j-1) ... S_1|`` (first order; ``fro`` the steps' errors), the
    partial products' norms from two scans kept near 1 by powers of two."""
    shape = S[0].shape[1:]
    pre, pre_e = _scan(S, False)      # pre[j] = S_(j+1) ... S_1 (j + 1 steps)
    suf, suf_e = _scan(S, True)       # suf[j] = S_m ... S_(j+1)
    p = tuple(x[-1] for x in pre)
    ex = pre_e[-1]
    n_pre, n_suf = _norm2(pre), _norm2(suf)
    # step j (0-based): left factor suf[j + 1] (the identity for the last), right factor pre[j - 1]
    one = np.ones((1,) + shape, S[0].dtype)
    zero = np.zeros((1,) + shape, np.int64)
    left = np.concatenate([n_suf[1:], one])
    left_e = np.concatenate([suf_e[1:], zero])
    right = np.concatenate([one, n_pre[:-1]])
    right_e = np.concatenate([zero, pre_e[:-1]])
    acc = np.sum(np.ldexp(left * fro * right, left_e + right_e - ex[None, :]), axis=0)
    norm_p = np.sqrt(sum(x * x for x in p))
    return p, acc * (1.0 + 1e-6) + 2.0 * unit * norm_p, ex


def _norm2(P):
    """Spectral norms of 2x2 matrices given by entry tuples (arrays), from the Frobenius norm and the
    determinant (raised by a few units for their rounding)."""
    F2 = sum(x * x for x in P)
    det = P[0] * P[3] - P[1] * P[2]
    return np.sqrt(0.5 * (F2 + np.sqrt(np.maximum(F2 * F2 - 4.0 * det * det, 0.0)))) * (1.0 + 1e-15)


def _mul(A, B):
    """2x2 products ``A B`` of entry tuples ``(a00, a01, a10, a11)`` (arrays)."""
    return (A[0] * B[0] + A[1] * B[2], A[0] * B[1] + A[1] * B[3],
            A[2] * B[0] + A[3] * B[2], A[2] * B[1] + A[3] * B[3])


def _renorm(P, e):
    """``P`` scaled by a power of two to entries below 1 in size, and ``e`` raised by it."""
    big = np.maximum(np.maximum(np.abs(P[0]), np.abs(P[1])), np.maximum(np.abs(P[2]), np.abs(P[3])))
    _, sc = np.frexp(np.where(big > 0, big, 1.0))
    return tuple(np.ldexp(x, -sc) for x in P), e + sc


def _scan(S, backward):
    """Inclusive scan of the steps ``S = (s00, s01, s10, s11)`` (arrays ``[step, point]``), each
    partial product as entries over ``2^e``: prefixes ``S_(j+1) ... S_1`` at ``j``, or (``backward``)
    suffixes ``S_m ... S_(j+1)``; in ``log2`` levels (Hillis and Steele)."""
    X, e = _renorm(tuple(np.array(x, copy=True) for x in S), np.zeros(S[0].shape, np.int64))
    m = S[0].shape[0]
    d = 1
    while d < m:
        if backward:   # X[j] <- X[j + d] X[j]
            Y, ey = _renorm(_mul(tuple(x[d:] for x in X), tuple(x[:-d] for x in X)), e[d:] + e[:-d])
            X = tuple(np.concatenate([y, x[m - d:]]) for y, x in zip(Y, X))
            e = np.concatenate([ey, e[m - d:]])
        else:          # X[j] <- X[j] X[j - d]
            Y, ey = _renorm(_mul(tuple(x[d:] for x in X), tuple(x[:-d] for x in X)), e[d:] + e[:-d])
            X = tuple(np.concatenate([x[:d], y]) for y, x in zip(Y, X))
            e = np.concatenate([e[:d], ey])
        d *= 2
    return X, e


def ld_tier(eps, mu, zeta, counts, evaluate, max_steps, chunk):
    """The frame of the long double tiers (:func:`pieces_ld`, :func:`kapitza.drives._mathieu.sine_ld`):
    flat ``eps, mu, zeta`` (``zeta`` None: undamped), each point's Taylor steps ``counts(eps, m2)``
    (rows of counts summed per point, ``m2 = mu^2 (1 + zeta^2)``; past ``max_steps`` in all the tier
    declines), points of like totals (within a factor 1.25) taken together at their largest counts, at
    most ``chunk`` points times steps a call of ``evaluate(e, m2, rows)`` on long doubles, which gives
    ``tau`` and a bound on its error. Where the bound decides ``|tau| < cosh(kappa)``, that is the exact
    verdict. Returns ``(decided, stable, tau, log_tau, growth, tau_error)``: ``tau``, ``log|tau|`` and
    the growth ``acosh|tau| - kappa`` (0 on a zone, undamped) are the long double's, as doubles
    (``tau_error`` ``inf`` where nothing is known). Nothing is decided where numpy's long double is the
    double."""
    eps = np.asarray(eps, float).ravel()
    mu = np.asarray(mu, float).ravel()
    z = np.zeros(eps.size) if zeta is None else np.asarray(zeta, float).ravel()
    n = eps.size
    out = (np.zeros(n, bool), np.zeros(n, bool), np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan),
           np.full(n, np.inf))
    if not HAS_LONG_DOUBLE or n == 0:
        return out
    decided, stable, tau, log_tau, growth, tau_error = out
    LD = LONG_DOUBLE
    with np.errstate(over="ignore", invalid="ignore"):
        per = np.atleast_2d(counts(eps, mu * mu * (1.0 + z * z)))
    total = per.sum(axis=0)
    usable = np.isfinite(total) & (total <= max_steps)
    bucket = np.where(usable, np.ceil(np.log(np.where(usable, total, 1.0)) / np.log(1.25)), -1)
    if usable.any() and usable.sum() * total[usable].max() <= chunk // 4:
        # (a small call: its fixed cost, some hundreds of array operations, outweighs the extra
        # steps of taking every point at the largest counts)
        bucket = np.where(usable, 0.0, -1.0)
    for b in np.unique(bucket[usable]):
        idx = np.flatnonzero(bucket == b)
        rows = [int(x) for x in per[:, idx].max(axis=1)]
        size = max(1, chunk // sum(rows))
        for c0 in range(0, idx.size, size):
            sub = idx[c0:c0 + size]
            e, m, zz = eps[sub].astype(LD), mu[sub].astype(LD), z[sub].astype(LD)
            with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
                t, err = evaluate(e, m * m * (1.0 + zz * zz), rows)
                kappa = 2.0 * np.sqrt(LD(8.0)) * zz * m * e
                thr = np.cosh(kappa)
                # (the threshold's own rounding: cosh(kappa)'s)
                ok = ((np.abs(np.abs(t) - thr) > err + LD_UNIT * (4.0 + 4.0 * kappa) * thr)
                      & np.isfinite(t) & np.isfinite(err) & (t != 0))
                lt = np.log(np.abs(t))
                gr = np.where(np.abs(t) > 1.0, lt + np.log1p(np.sqrt(-np.expm1(-2.0 * lt))), 0.0) - kappa
            decided[sub] = ok
            stable[sub] = np.abs(t) < thr
            with np.errstate(over="ignore"):   # (beyond the doubles' range: +-inf, as Floquet0 has it)
                tau[sub], log_tau[sub], growth[sub] = t.astype(float), lt.astype(float), gr.astype(float)
                tau_error[sub] = np.where(np.isfinite(err), err, np.inf).astype(float)
    return out


def pieces_ld(eps, mu, zeta, pieces):
    """The long double tier of :func:`pieces_mp`: the same Taylor steps in numpy's long double, with a
    bound on their rounding (the terms' recursion and sums, the coefficients' rounding, the products),
    for flat arrays: ``(decided, stable, tau, log_tau, growth, tau_error)`` as :func:`ld_tier` gives
    them; nothing is decided past :data:`_LD_MAX_STEPS` steps."""

    def counts(eps, m2):   # pieces_mp's steps on each piece
        rows = []
        for x0, x1, s0, s1 in pieces:
            width = float(x1) - float(x0)
            peak = 8.0 * eps * eps * np.maximum(np.abs(m2 + s0), np.abs(m2 + s1))
            rows.append(np.maximum(1.0, np.ceil(width * np.sqrt(peak) * (1.0 + 1e-9))) if width > 0
                        else np.zeros(eps.size))
        return rows

    def ld(eps, mu, zeta):
        return ld_tier(eps, mu, zeta, counts, lambda e, m2, rows: _pieces_ld_chunk(e, m2, pieces, rows, LD_UNIT),
                       _LD_MAX_STEPS, _LD_CHUNK)

    from .engines.magnus import compiled_pieces_tier

    dd = compiled_pieces_tier()
    if dd is None:
        return ld(eps, mu, zeta)
    # the compiled double-double tier first; the long double for the points it declines
    out = dd(eps, mu, zeta, pieces)
    rest = np.flatnonzero(~out[0])
    if rest.size:
        flat = (np.asarray(v, float).ravel()[rest] for v in (eps, mu))
        for a, b in zip(out, ld(*flat, None if zeta is None else np.asarray(zeta, float).ravel()[rest])):
            a[rest] = b
    return out


def growth_good(tau, tau_error, growth, rtol=1e-12, log_tau=None):
    """Where a growth ``acosh|tau| (- kappa)`` from an extended-precision ``tau`` is good to ``rtol``:
    it moves by ``tau``'s error over ``sqrt(tau^2 - 1)`` (0 on a zone). ``log_tau``, ``log|tau|`` of
    that precision, gives ``sqrt(tau^2 - 1)`` where the double ``tau`` has rounded to +-1 (just past
    the threshold, where the growth is most sensitive)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if log_tau is None:
            off, room = np.abs(tau) > 1.0, np.sqrt(np.abs(tau * tau - 1.0))
        else:
            off, room = log_tau > 0.0, np.sqrt(np.abs(np.expm1(2.0 * np.asarray(log_tau, float))))
        err = np.where(off, tau_error / room, 0.0)
    return err <= rtol * np.abs(growth)


def pieces_exact(eps, mu, zeta, pieces, growth=True, trace=False):
    """:func:`pieces_mp`'s answers, from the long double tier (:func:`pieces_ld`) where it decides and
    from mpmath elsewhere (``growth``: also where the long double's growth is not good to 1e-12, for a
    growth that is reported). ``trace``: the trace is reported too: also where the long double's
    ``tau`` is not good to :data:`TRACE_RTOL`, and each answer carries a fifth item, a bound on the
    error of ``tau`` (the long double's bound and the rounding to a double; a half ulp from mpmath)."""
    dec, st, tau, log_tau, rate, err = pieces_ld(eps, mu, zeta, pieces)
    if growth:
        dec &= growth_good(tau, err, rate, log_tau=log_tau)
    if trace:
        with np.errstate(invalid="ignore"):
            dec &= err <= TRACE_RTOL * np.abs(tau)
    half_ulp = 0.5 * np.finfo(float).eps
    out = list(zip(tau.tolist(), log_tau.tolist(), st.tolist(), rate.tolist(),
                   (err + half_ulp * np.abs(tau)).tolist()))
    rest = np.flatnonzero(~dec)
    if rest.size:
        eps, mu = np.asarray(eps, float).ravel(), np.asarray(mu, float).ravel()
        z = None if zeta is None else np.asarray(zeta, float).ravel()[rest]
        for i, r in zip(rest, pieces_mp(eps[rest], mu[rest], z, pieces)):
            out[i] = (*r, half_ulp * abs(r[0]))
    return out if trace else [r[:4] for r in out]
