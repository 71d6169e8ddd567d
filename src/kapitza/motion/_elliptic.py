"""Exact flow of one phase: the pendulum ``theta'' = s sin(theta)`` in Jacobi elliptic functions.

Within each phase of the drive the full equation is autonomous (``docs/theory.md``
section 6). Both phases are the ordinary pendulum ``q'' = -sin q`` in the scaled
time ``w t``:

* elliptic phase, ``s = -w^2 < 0``: ``q = theta`` (the upright is the bottom of
  this pendulum's potential);
* hyperbolic phase, ``s = +w^2 > 0``: ``q = theta + pi`` (the upright is this
  pendulum's top, a saddle);
* ``s = 0`` (``A = g``): free flight.

How the flow is evaluated, and why
----------------------------------
With the half-angle state ``S = sin(q/2)``, ``Dn = cos(q/2)``, ``C = q'/2``, the
energy is ``m = k^2 = S^2 + C^2`` and ``(S, C, Dn) = (k sn a, k cn a, dn a)`` for
some phase ``a``. The addition theorems of ``sn, cn, dn`` then give the state at
``a + s`` from the functions of ``s`` alone: no inverse elliptic integral
(``ellipkinc``) is needed and the state is never divided by ``k``, so tiny
amplitudes keep their relative accuracy. ``1 - m = (Dn - C)(Dn + C)`` is formed
as a product, exact near the separatrix, and carried instead of ``m``
wherever ``m`` is close to 1:

* ``m <= 1/2``: :func:`scipy.special.ellipj` (accurate there);
* ``1/2 < m <= 1``: Jacobi's imaginary transformation and theta series in the
  complementary nome ``q1 = q(1 - m) <= 0.044`` (DLMF 22.2, 22.6.iv, 19.5.5).
  ``ellipj`` takes ``m`` itself and loses ``1e-16/(1 - m)`` relative accuracy
  in ``cn`` and ``dn`` there (measured: 2.5e-11 at ``1 - m = 1e-13``);
* rotation, ``m > 1``: the reciprocal-modulus transformation
  ``sn(u|m) = sn(k u|1/m)/k``, ``cn(u|m) = dn(k u|1/m)``, ``dn(u|m) = cn(k u|1/m)``;
* the separatrix ``m = 1`` is the series with ``q1 = 0``: ``tanh`` and ``sech``.

Arguments are reduced to ``|u| <= K/2`` by the quarter-period shifts
``sn(u + K) = cd u``, ``cn(u + K) = -k' sd u``, ``dn(u + K) = k' nd u``, so no
function is evaluated where it is small and must be found by cancellation.

One state or many
-----------------
:func:`_phase_step` takes arrays; one state (a motion takes one step per phase, one after
another) goes to :func:`_phase_step_one`, which chooses each branch with ``if`` instead of
masks and calls the same formula functions (:func:`_nome`, :func:`_theta_quotients`,
:func:`_addition`, :func:`_quarter_shift`, the two unwrappings of ``q/2``, :func:`_phase_flow`)
on one float: numpy's own ufuncs, so the doubles are the array path's to the last bit (tested),
in 13-20 us a step instead of about 150 us of per-call overhead on one-element arrays.
"""
from __future__ import annotations

import numpy as np

from .. import _validate as _v

PI = np.pi
TWO_PI = 2.0 * np.pi
FOUR_PI = 4.0 * np.pi

#: Above this ``m`` the complementary-nome series replaces ``scipy.special.ellipj``.
_SERIES_M = 0.5


def _nome(m1):
    """Nome ``q1`` of the complementary parameter ``m1 = 1 - m`` (``0 <= m1 <= 1/2``), with
    ``theta_3(0)``, ``theta_4(0)``, ``theta_2(0)/(2 q1^(1/4))`` at ``q1`` and ``K(m1)``.

    Arithmetic and square roots only, on arrays or on one float: the compiled twin
    (:mod:`kapitza.motion._survival_jit`) compiles this same function."""
    m = 1.0 - m1
    r2 = np.sqrt(m)
    r4 = np.sqrt(r2)
    # lambda = (1 - m^(1/4)) / (2 (1 + m^(1/4))), with the difference written without cancellation.
    p4 = 1.0 + r4
    lam = m1 / (2.0 * (1.0 + r2) * (p4 * p4))
    l2 = lam * lam
    l4 = l2 * l2
    q = lam * (1.0 + l4 * (2.0 + l4 * (15.0 + l4 * (150.0 + l4 * 1707.0))))  # DLMF 19.5.5
    q2 = q * q
    q4 = q2 * q2
    q9 = q4 * q4 * q
    q16 = q9 * q4 * q2 * q
    th3 = 1.0 + 2.0 * (q + q4 + q9 + q16)
    th4 = 1.0 + 2.0 * (-q + q4 - q9 + q16)
    q6 = q4 * q2
    th2n = 1.0 + q2 + q6 + q6 * q6 + q16 * q4
    K1 = 0.5 * PI * th3 * th3
    return q, th3, th4, th2n, K1


def _complementary_nome(m1):
    """:func:`_nome` with ``log q1`` and ``K(m)`` (``inf`` at ``m1 = 0``)."""
    q, th3, th4, th2n, K1 = _nome(m1)
    with np.errstate(divide="ignore"):
        logq = np.log(q)
    return q, logq, th3, th4, th2n, K1, _quarter_period(K1, logq)


def _quarter_period(K1, logq):
    """``K(m)`` from ``K(m1)`` and the complementary nome: ``q1 = exp(-pi K(m) / K(m1))``
    (``-log 0 = inf`` on the separatrix)."""
    return K1 * (-logq) / PI


def _series(t, m1):
    """``sn, cn, dn, K`` and the quarter-period count ``j`` of ``(t | 1 - m1)`` for
    ``0 <= m1 <= 1/2``: theta series of the complementary nome at ``t - j K``,
    ``|t - j K| <= K/2`` (any ``t`` on the separatrix, where ``K = inf``)."""
    q, logq, th3, th4, th2n, K1, K = _complementary_nome(m1)
    finite = np.isfinite(K)
    Ks = np.where(finite, K, 1.0)
    j = np.where(finite, np.rint(t / Ks), 0.0)
    t = t - j * np.where(finite, K, 0.0)
    y, e = _series_exponent(t, K1)
    with np.errstate(invalid="ignore"):
        # r = q1 exp(2y) <= k'/4 for |t| <= K/2; written through the logarithm so that
        # q1 = 0 (the separatrix) gives 0 for any y.
        r = np.where(q > 0, _series_ratio(logq, y), 0.0)
    sn, cn, dn = _theta_quotients(t, e, q, r, th3, th4, th2n)
    return sn, cn, dn, K, j


def _series_exponent(t, K1):
    """``y = |t| pi / (2 K(m1))`` and ``e = exp(-2 y)`` of the theta series at the reduced ``t``."""
    y = np.abs(t) * (0.5 * PI / K1)
    return y, np.exp(-2.0 * y)


def _series_ratio(logq, y):
    """``r = q1 exp(2 y)`` (``<= k'/4`` for ``|t| <= K/2``), from ``log q1``."""
    return np.exp(np.minimum(logq + 2.0 * y, 0.0))


def _theta_quotients(t, e, q, r, th3, th4, th2n):
    """``sn, cn, dn`` at the reduced ``t`` from the theta series in the nome ``q`` (four terms),
    with ``e = exp(-2y)``, ``r = q exp(2y)`` and ``y = |t| pi / (2 K(m1))`` (DLMF 22.2, 22.6.iv).

    Arithmetic, a square root and a sign only, on arrays or on one float: the compiled twin
    compiles this same function."""
    q2 = q * q
    qr = q * r
    q2r = q2 * r
    q3r = q2r * q
    a1 = qr  # q^(n(n+1)) exp(2ny) = (q^n r)^n
    a2 = q2r * q2r
    a3 = q3r * q3r * q3r
    e3 = e * e * e
    e5 = e3 * e * e
    e7 = e5 * e * e
    num = (1.0 - e) - a1 * (1.0 - e3) + a2 * (1.0 - e5) - a3 * (1.0 - e7)
    den = (1.0 + e) + a1 * (1.0 + e3) + a2 * (1.0 + e5) + a3 * (1.0 + e7)
    b2 = qr * qr  # q^(n^2) exp(2ny) = (q^(n-1) r)^n
    b3 = a2 * q2r
    b4 = a3 * q3r
    c1 = q * e  # q^(n^2) exp(-2ny) = (q^n e)^n
    q2e = q2 * e
    q3e = q2e * q
    q4e = q3e * q
    c2 = q2e * q2e
    c3 = q3e * q3e * q3e
    c4 = q4e * q4e
    c4 = c4 * c4
    odd = r + c1 + b3 + c3
    even = b2 + c2 + b4 + c4
    sech_like = 2.0 * np.sqrt(e) / den
    sn = np.copysign(th3 / th4 * num / den, t)
    cn = th2n / th4 * (1.0 - odd + even) * sech_like
    dn = th2n / th3 * (1.0 + odd + even) * sech_like
    return sn, cn, dn


def _ellipj_reduced(u, m):
    """``sn, cn, dn, K, j`` from :func:`scipy.special.ellipj` at ``u - j K``, ``|u - j K| <= K/2``."""
    # Imported here: scipy.special costs a quarter of a second at import, and
    # ``import kapitza.motion`` should stay as light as ``import kapitza``.
    from scipy.special import ellipj, ellipk

    K = ellipk(m)
    j = np.rint(u / K)
    sn, cn, dn, _ = ellipj(u - j * K, m)
    return sn, cn, dn, K, j


def _jacobi(u, m1):
    """``sn, cn, dn`` of ``(u | m)`` and ``K(m)``, for ``m = 1 - m1`` with ``0 <= m1 <= 1``.

    Parameters
    ----------
    u, m1 : ndarray, same shape
        Any real ``u``; the complementary parameter ``m1`` carries the accuracy near
        ``m = 1``.
    """
    near = m1 < 1.0 - _SERIES_M
    if near.all():
        sn, cn, dn, K, j = _series(u, m1)
    elif not near.any():
        sn, cn, dn, K, j = _ellipj_reduced(u, 1.0 - m1)
    else:
        sn, cn, dn, K, j = (np.empty(u.shape) for _ in range(5))
        far = ~near
        for sel, vals in ((near, _series(u[near], m1[near])), (far, _ellipj_reduced(u[far], 1.0 - m1[far]))):
            for arr, v in zip((sn, cn, dn, K, j), vals):
                arr[sel] = v
    jm = np.mod(j, 4.0)
    if np.any(jm != 0.0):
        odd = (jm == 1.0) | (jm == 3.0)
        sgn = np.where(jm >= 2.0, -1.0, 1.0)  # j = 2, 3 carry a sign
        with np.errstate(divide="ignore", invalid="ignore"):  # (rows not shifted may have dn = 0: k = 1)
            sn_o, cn_o, dn_o = _quarter_shift(sn, cn, dn, m1)
        sn, cn, dn = (sgn * np.where(odd, sn_o, sn), sgn * np.where(odd, cn_o, cn), np.where(odd, dn_o, dn))
    return sn, cn, dn, K


def _quarter_shift(sn, cn, dn, m1):
    """``sn, cn, dn`` of ``u + K`` from those of ``u``: ``cd u``, ``-k' sd u``, ``k' nd u``."""
    kp = np.sqrt(m1)
    rdn = 1.0 / dn
    return cn * rdn, -kp * sn * rdn, kp * rdn


def _pendulum(S, C, Dn, h0, s):
    """Advance ``q'' = -sin q`` by the scaled time ``s >= 0``.

    Parameters
    ----------
    S, C, Dn : ndarray
        ``sin(q/2)``, ``q'/2``, ``cos(q/2)`` of the initial state.
    h0 : ndarray
        ``q/2`` itself (unwrapped), used only to choose the branch of the result.
    s : ndarray or float

    Returns
    -------
    S1, C1, Dn1 : ndarray
        The half-angle state at ``s``.
    h1 : ndarray
        ``q(s)/2`` unwrapped (absolute accuracy only; the caller takes the fine
        value from ``S1, Dn1``).
    """
    S, C, Dn, h0 = np.broadcast_arrays(S, C, Dn, h0)
    s = np.broadcast_to(np.asarray(s, dtype=float), S.shape)
    m = S * S + C * C
    m1 = (Dn - C) * (Dn + C)
    lib = m1 >= 0.0
    if lib.all():
        sn, cn, dn, _ = _jacobi(s, m1)
        rot = None
    else:
        sn = np.empty(S.shape)
        cn = np.empty(S.shape)
        dn = np.empty(S.shape)
        if lib.any():
            sn[lib], cn[lib], dn[lib], _ = _jacobi(s[lib], m1[lib])
        rot = ~lib
        mr = m[rot]
        k = np.sqrt(mr)
        snr, cnr, dnr, Kr = _jacobi(k * s[rot], -m1[rot] / mr)
        sn[rot] = snr / k
        cn[rot] = dnr
        dn[rot] = cnr
        half_period = 2.0 * Kr / k  # q advances by exactly 2 pi in this time
    S1, C1, D1 = _addition(S, C, Dn, sn, cn, dn)
    h1 = _libration_branch(h0, S1, D1)
    if rot is not None:
        h1[rot] = _rotation_branch(h0[rot], C[rot], S1[rot], D1[rot], s[rot], half_period)
    return S1, C1, D1, h1


def _addition(S, C, Dn, sn, cn, dn):
    """The state ``(k sn, k cn, dn)`` at ``a + s`` from ``(S, C, Dn) = (k sn a, k cn a, dn a)`` and
    ``sn, cn, dn`` of ``s`` (the addition theorems, DLMF 22.8.1-3)."""
    # The denominator 1 - k^2 sn^2 a sn^2 s = 1 - S^2 sn^2 is written as cn^2 + Dn^2 sn^2
    # (no cancellation).
    den = cn * cn + Dn * Dn * sn * sn
    tiny = den < 1e-290
    if tiny.any():
        # the squares underflow only beside the saddle of the separatrix (cn = dn = sech(s) with
        # Dn, C small): the saddle itself (Dn = C = 0) stays where it is; a state near it but not on
        # it has a modulus whose complement 1 - k^2 = Dn^2 is below the doubles' range
        if ((Dn != 0.0) | (C != 0.0))[tiny].any() if np.ndim(tiny) else (Dn != 0.0 or C != 0.0):
            raise _v.KapitzaValueError(
                "the state is within 1e-150 of the upright without being on it: its motion over this time "
                "leaves the range of doubles (start exactly upright, or further from it)")
        with np.errstate(invalid="ignore", divide="ignore"):
            out = ((S * cn * dn + sn * C * Dn) / den, (C * cn - S * Dn * sn * dn) / den,
                   (Dn * dn - S * C * sn * cn) / den)
        return tuple(np.where(tiny, v0, v) for v0, v in zip((S, C, Dn), out))
    return (S * cn * dn + sn * C * Dn) / den, (C * cn - S * Dn * sn * dn) / den, (Dn * dn - S * C * sn * cn) / den


def _libration_branch(h0, S1, D1):
    """``q/2`` unwrapped from ``sin(q/2) = S1``, ``cos(q/2) = D1`` on the branch of ``h0``: a libration
    keeps ``cos(q/2)`` of one sign on its branch ``nb`` (``dn >= k' > 0``)."""
    nb = np.rint(h0 / PI)
    sg = 1.0 - 2.0 * np.mod(nb, 2.0)
    return nb * PI + np.arctan2(sg * S1, sg * D1)


def _rotation_branch(h0, C, S1, D1, s, half_period):
    """``q/2`` unwrapped after the time ``s`` of a rotation: ``q/2`` is monotone and advances by
    ``pi`` in each ``half_period``; count those, then place the remainder (< pi) by the angle itself."""
    sp = 1.0 - 2.0 * (C < 0.0)  # the sense of the rotation (C >= 0: +1)
    n = np.floor(s / half_period)
    par = 1.0 - 2.0 * np.mod(n, 2.0)
    a = np.arctan2(par * S1, par * D1)
    delta = np.mod(sp * (a - h0), TWO_PI)
    delta = delta - TWO_PI * (delta > 1.5 * PI)
    return h0 + sp * (n * PI + delta)


def _phase_step(theta, dtheta, s2, t):
    """Exact flow of ``theta'' = s2 sin(theta)`` over the time ``t >= 0``.

    Parameters
    ----------
    theta, dtheta : ndarray
        State [rad, rad/s], any shape.
    s2 : float or ndarray
        ``(g + a)/l`` of the phase [1/s^2], any sign; broadcasts with the state.
    t : float or ndarray
        Duration [s], ``>= 0``; broadcasts with the state.

    Returns
    -------
    theta1, dtheta1 : ndarray

    Notes
    -----
    One state (every argument of size 1) takes :func:`_phase_step_one`: the same doubles in
    microseconds instead of a few dozen numpy calls on one-element arrays.
    """
    if np.size(theta) == 1 and np.size(dtheta) == 1 and np.size(s2) == 1 and np.size(t) == 1:
        shape = np.broadcast_shapes(np.shape(theta), np.shape(dtheta), np.shape(s2), np.shape(t))
        th1, om1 = _phase_step_one(*(np.ravel(a)[0] for a in (theta, dtheta, s2, t)))
        return np.full(shape, th1), np.full(shape, om1)
    return _phase_step_arrays(theta, dtheta, s2, t)


def _phase_step_arrays(theta, dtheta, s2, t):
    """:func:`_phase_step` on arrays, whatever their size (branches chosen by masks)."""
    theta, dtheta, s2, t = np.broadcast_arrays(
        np.asarray(theta, float), np.asarray(dtheta, float), np.asarray(s2, float), np.asarray(t, float))
    shape = theta.shape
    theta, dtheta, s2, t = (a.reshape(-1) for a in (theta, dtheta, s2, t))
    if s2.size and np.all(s2 == s2[0]):
        th1, om1 = _phase_step_sign(theta, dtheta, float(s2[0]), t)
        return th1.reshape(shape), om1.reshape(shape)
    th1 = np.empty(theta.shape)
    om1 = np.empty(theta.shape)
    for sel in (s2 > 0, s2 < 0, s2 == 0):
        if sel.any():
            th1[sel], om1[sel] = _phase_step_sign(theta[sel], dtheta[sel], s2[sel], t[sel])
    return th1.reshape(shape), om1.reshape(shape)


def _phase_step_sign(theta, dtheta, s2, t):
    """:func:`_phase_step` where every ``s2`` has the same sign (``s2`` scalar or array)."""
    sgn = np.sign(np.asarray(s2).flat[0]) if np.size(s2) else 0.0
    return _phase_flow(theta, dtheta, s2, t, sgn, _pendulum)


def _phase_flow(theta, dtheta, s2, t, sgn, pendulum):
    """The flow of one phase, ``sgn`` of the sign of every ``s2``, through ``pendulum``
    (:func:`_pendulum` on arrays, :func:`_pendulum_one` on one state): the one definition
    of the change of variables both paths use."""
    if sgn == 0.0:
        return theta + dtheta * t, dtheta + 0.0 * t
    w = np.sqrt(np.abs(s2))
    half = 0.5 * theta
    sh, ch = np.sin(half), np.cos(half)
    C = dtheta / (2.0 * w)
    if sgn > 0:
        # q = theta + pi: sin(q/2) = cos(theta/2), cos(q/2) = -sin(theta/2).
        S1, C1, D1, h1 = pendulum(ch, C, -sh, half + 0.5 * PI, w * t)
        sin_half, cos_half, coarse = -D1, S1, 2.0 * h1 - PI
    else:
        S1, C1, D1, h1 = pendulum(sh, C, ch, half, w * t)
        sin_half, cos_half, coarse = S1, D1, 2.0 * h1
    # The fine angle keeps the relative accuracy of small theta; the coarse one the branch.
    fine = 2.0 * np.arctan2(sin_half, cos_half)
    theta1 = fine + FOUR_PI * np.rint((coarse - fine) / FOUR_PI)
    return theta1, 2.0 * w * C1


# ------------------------------------------------------------------ one state
# The same flow for one state, branch by branch with ``if`` instead of masks: each call of the
# array path pays numpy's overhead of a few dozen calls on one-element arrays (~0.15 ms), and a
# motion takes one step per phase, one after another. Every formula is the array path's
# function called on one float (numpy's own ufuncs, so the doubles are the same bits); only the
# choice of branch is written twice, and the tests run both on the same states.


def _series_one(t, m1):
    """:func:`_series` of one ``t`` and one ``m1``."""
    q, th3, th4, th2n, K1 = _nome(m1)
    if q > 0.0:
        logq = np.log(q)
        K = _quarter_period(K1, logq)
        j = np.rint(t / K)
        t = t - j * K
        y, e = _series_exponent(t, K1)
        r = _series_ratio(logq, y)
    else:  # the separatrix: K = inf, q1 = 0
        K, j = np.inf, 0.0
        y, e = _series_exponent(t, K1)
        r = 0.0
    sn, cn, dn = _theta_quotients(t, e, q, r, th3, th4, th2n)
    return sn, cn, dn, K, j


def _jacobi_one(u, m1):
    """:func:`_jacobi` of one ``u`` and one ``m1``."""
    if m1 < 1.0 - _SERIES_M:
        sn, cn, dn, K, j = _series_one(u, m1)
    else:
        sn, cn, dn, K, j = _ellipj_reduced(u, 1.0 - m1)
    jm = np.mod(j, 4.0)
    if jm != 0.0:
        sgn = -1.0 if jm >= 2.0 else 1.0  # j = 2, 3 carry a sign
        if jm == 1.0 or jm == 3.0:
            sn, cn, dn = _quarter_shift(sn, cn, dn, m1)
        sn, cn = sgn * sn, sgn * cn
    return sn, cn, dn, K


def _pendulum_one(S, C, Dn, h0, s):
    """:func:`_pendulum` of one state."""
    m1 = (Dn - C) * (Dn + C)
    if m1 >= 0.0:
        sn, cn, dn, _ = _jacobi_one(s, m1)
    else:
        m = S * S + C * C
        k = np.sqrt(m)
        snr, cnr, dnr, Kr = _jacobi_one(k * s, -m1 / m)
        sn, cn, dn = snr / k, dnr, cnr
    S1, C1, D1 = _addition(S, C, Dn, sn, cn, dn)
    if m1 >= 0.0:
        return S1, C1, D1, _libration_branch(h0, S1, D1)
    return S1, C1, D1, _rotation_branch(h0, C, S1, D1, s, 2.0 * Kr / k)


def _phase_step_one(theta, dtheta, s2, t):
    """:func:`_phase_step` of one state: ``theta``, ``dtheta``, ``s2``, ``t`` floats; the same doubles."""
    theta, dtheta, s2, t = np.float64(theta), np.float64(dtheta), np.float64(s2), np.float64(t)
    return _phase_flow(theta, dtheta, s2, t, s2, _pendulum_one)
