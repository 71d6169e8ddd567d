"""Edges of zone 0 of general drives, with and without damping, against a 50-digit reference.

The reference builds the damped monodromy of ``theta'' + c theta' = (g + a(t))/l theta`` as the
product of ``expm([[0, 1], [s, -c]] * duration)`` over the drive's steps (``s = (g + A level)/l``,
in mpmath, from the drive's own double levels and fractions) and solves
``tr M - (1 + det M) = 0`` (lower edge of zone 0: a multiplier ``+1``) and ``tr M + 1 + det M = 0``
(upper edge: ``-1``) by a bracketing solver. Nothing of the library's method is used.

Near ``mu -> 0`` the lower edge is where ``tr M - 2`` of order ``eps^2 mu^2`` balances terms of
order ``eps^4`` while the monodromy's entries are of order 1 and ``eps^2``: the sweep goes down to
``mu = 1e-3`` where a product formed without care loses 1e-7 relative. The sine drive's lower
edge is checked against Hill's determinant in mpmath (with damping it lost 1e-6 there too).
"""
import mpmath as mp
import numpy as np
import pytest

import kapitza as K
from kapitza.drives import parse_drive

EDGE_RTOL = 1e-14
DRIVES = ["rectangular:0.3", "rectangular:0.7", "steps:2,-1,1,-1:0.2,0.3,0.2,0.3", "square"]
ZETAS = [0.0, 0.05, 0.1, 1.0]
# log-spaced from 1e-3, and about where the solver changes form (mu^2 = max|level| / 5)
MUS = np.sort(np.r_[np.geomspace(1e-3, 0.9, 7), 0.44, 0.46, 0.55, 0.62])
DPS = 50


def _flow(s, c, t):
    """``expm([[0, 1], [s, -c]] t)``: ``e^{-ct/2} (cosh(w t) I + sinh(w t)/w (J + c/2 I))``,
    ``w^2 = s + c^2/4`` (``(J + c/2 I)^2 = w^2 I``; cos/sin where ``w^2 < 0``)."""
    w2 = s + c * c / 4
    if w2 > 0:
        w = mp.sqrt(w2)
        ch, sh = mp.cosh(w * t), mp.sinh(w * t) / w
    elif w2 < 0:
        w = mp.sqrt(-w2)
        ch, sh = mp.cos(w * t), mp.sin(w * t) / w
    else:
        ch, sh = mp.mpf(1), t
    e = mp.exp(-c * t / 2)
    return mp.matrix([[e * (ch + sh * c / 2), e * sh], [e * sh * s, e * (ch - sh * c / 2)]])


def _monodromy(levels, fractions, eps, mu, zeta, flow=_flow):
    """Damped monodromy over ``2T`` (g = l = 1): the product of the steps' flows."""
    eps, mu, zeta = mp.mpf(eps), mp.mpf(mu), mp.mpf(zeta)
    A = 1 / mu**2
    T = eps * mp.sqrt(8 / A)
    c = 2 * zeta
    M = mp.eye(2)
    for lev, frac in zip(levels, fractions):
        M = flow(1 + mp.mpf(lev) * A, c, 2 * T * mp.mpf(frac)) * M
    return M


def _excess(levels, fractions, eps, mu, zeta, sign):
    """``tr M - sign (1 + det M)``: zero where a multiplier is ``sign``."""
    M = _monodromy(levels, fractions, eps, mu, zeta)
    return M[0, 0] + M[1, 1] - sign * (1 + mp.det(M))


def test_reference_flow_is_the_matrix_exponential():
    with mp.workdps(DPS):
        for s, c, t in ((1e6 + 1, 0.2, 3e-6), (-4e5, 2.0, 1e-5), (-3.0, 0.5, 0.7), (2.5, 0.0, 1.3)):
            J = mp.matrix([[0, 1], [s, -c]])
            E = mp.expm(J * mp.mpf(t))
            F = _flow(mp.mpf(s), mp.mpf(c), mp.mpf(t))
            assert mp.mnorm(E - F, 1) < mp.mpf(10) ** (-45) * mp.mnorm(E, 1)


def _root(levels, fractions, mu, zeta, guess, sign):
    """The reference edge in a bracket of +-1e-9 relative around ``guess`` (widened if needed)."""
    f = lambda e: _excess(levels, fractions, e, mu, zeta, sign)  # noqa: E731
    g = mp.mpf(guess)
    for w in ("1e-9", "1e-6", "1e-3"):
        a, b = g * (1 - mp.mpf(w)), g * (1 + mp.mpf(w))
        fa, fb = f(a), f(b)
        if fa * fb < 0:
            break
    else:
        raise AssertionError(f"no sign change of the reference near {guess!r}")
    for _ in range(200):  # Illinois on the bracket, to ~40 digits
        m = (a * fb - b * fa) / (fb - fa)
        fm = f(m)
        if fm * fb < 0:
            a, fa = b, fb
        else:
            fa = fa / 2
        b, fb = m, fm
        if abs(b - a) < mp.mpf(10) ** (-30) * abs(b):
            break
    return b


@pytest.mark.parametrize("text", DRIVES)
def test_zone0_edges_and_verdicts_match_the_reference(text):
    d = parse_drive(text)
    with mp.workdps(DPS):
        for zeta in ZETAS:
            lo, hi = K.zone_edges(MUS, 0, drive=d, zeta=zeta)
            mu_c = MUS * np.sqrt(1 + zeta * zeta)
            exists = mu_c**2 + min(d.levels) < 0
            assert np.array_equal(np.isfinite(lo), exists) and np.array_equal(np.isfinite(hi), exists)
            # where damping has joined zones 0 and 1 the shared edge is no multiplier -1
            joined = hi == K.zone_edges(MUS, 1, drive=d, zeta=zeta)[0]
            below, inside = [], []
            for mu, l, h, j in zip(MUS[exists], lo[exists], hi[exists], joined[exists]):
                r_lo = _root(d.levels, d.fractions, mu, zeta, l, +1)
                err_lo = float(abs(l - r_lo) / r_lo)
                assert err_lo < EDGE_RTOL, (text, zeta, mu, "lower", err_lo)
                below.append(float(r_lo * (1 - mp.mpf("1e-12"))))
                inside.append(float(r_lo * (1 + mp.mpf("1e-12"))))
                if not j:
                    r_hi = _root(d.levels, d.fractions, mu, zeta, h, -1)
                    err_hi = float(abs(h - r_hi) / r_hi)
                    assert err_hi < EDGE_RTOL, (text, zeta, mu, "upper", err_hi)
            # the verdict next to the reference's lower edge: unstable 1e-12 below, stable 1e-12 above
            m = MUS[exists]
            st_below = K.is_stable(np.array(below), m, drive=d, zeta=zeta)
            st_inside = K.is_stable(np.array(inside), m, drive=d, zeta=zeta)
            assert not st_below.any(), (text, zeta, m[st_below])
            assert st_inside.all(), (text, zeta, m[~st_inside])


def _sine_excess(eps, mu, zeta, R=40):
    """``tau_phi - cosh(kappa)`` of the sine drive from Hill's determinant, in mpmath.

    Mathieu's ``y'' + (a - 2 q cos 2z) y = 0`` with ``q = 16 eps^2 / pi^2``,
    ``a = -2 mu^2 (1 + zeta^2) q`` (the ``phi``-system); ``tau_phi = 1 + 2 Delta(0) sinh^2(pi sqrt(-a)/2)``,
    ``Delta(0)`` the continuant of ``xi_r = q / (4 r^2 - a)`` over ``|r| <= R`` times the far tails
    ``exp(-2 sum_{r > R} xi_r xi_{r-1})`` (the neglected terms are of order ``xi^4``).
    """
    eps, mu, zeta = mp.mpf(eps), mp.mpf(mu), mp.mpf(zeta)
    q = 16 * eps**2 / mp.pi**2
    a = -2 * mu**2 * (1 + zeta**2) * q

    def xi(r):
        return q / (4 * mp.mpf(r) ** 2 - a)

    D_prev, D = mp.mpf(1), mp.mpf(1)
    for r in range(-R + 1, R + 1):
        D, D_prev = D - xi(r) * xi(r - 1) * D_prev, D
    D = D * mp.exp(-2 * mp.nsum(lambda r: xi(r) * xi(r - 1), [R + 1, mp.inf]))
    tau = 1 + 2 * D * mp.sinh(mp.pi * mp.sqrt(-a) / 2) ** 2
    return tau - mp.cosh(2 * mp.sqrt(8) * zeta * mu * eps)


@pytest.mark.parametrize("zeta, mu", [(0.0, 1e-3), (0.1, 1e-3), (1.0, 0.01), (1.0, 0.3)])
def test_sine_zone0_lower_edge_matches_hill(zeta, mu):
    lo, _ = K.zone_edges(mu, 0, drive="sine", zeta=zeta)
    with mp.workdps(40):
        g = mp.mpf(float(lo))
        a, b = g * (1 - mp.mpf("1e-9")), g * (1 + mp.mpf("1e-9"))
        fa, fb = _sine_excess(a, mu, zeta), _sine_excess(b, mu, zeta)
        assert fa * fb < 0
        for _ in range(100):
            m = (a * fb - b * fa) / (fb - fa)
            fm = _sine_excess(m, mu, zeta)
            if fm * fb < 0:
                a, fa = b, fb
            else:
                fa = fa / 2
            b, fb = m, fm
            if abs(b - a) < mp.mpf(10) ** -25 * b:
                break
        assert float(abs(lo - b) / b) < EDGE_RTOL
