"""Verdicts of drives given as linear pieces (the triangle wave, measured drives) decided to the last
bit, with and without damping, against an oracle of their own: the exact flow of each piece from
Airy functions (``phi'' = (a + b x) phi`` is Airy's equation in ``z = (a + b x) / b^(2/3)``) at 50
digits, not the Taylor series the library uses.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import kapitza as K

TRIANGLE_PIECES = ((0.0, 0.5, 0.0, 1.0), (0.5, 1.5, 1.0, -1.0), (1.5, 2.0, -1.0, 0.0))


def _flow(a, b, w):
    """The exact flow over ``w`` of ``phi'' = (a + b x) phi`` (mpmath numbers)."""
    if b == 0:
        if a == 0:
            return mpmath.matrix([[1, w], [0, 1]])
        r = mpmath.sqrt(abs(a))
        if a > 0:
            return mpmath.matrix([[mpmath.cosh(r * w), mpmath.sinh(r * w) / r],
                                  [r * mpmath.sinh(r * w), mpmath.cosh(r * w)]])
        return mpmath.matrix([[mpmath.cos(r * w), mpmath.sin(r * w) / r], [-r * mpmath.sin(r * w), mpmath.cos(r * w)]])
    c = mpmath.cbrt(b)  # real, with the sign of b: z = (a + b x) / c^2, dz/dx = c

    def fundamental(x):
        z = (a + b * x) / c**2
        return mpmath.matrix([[mpmath.airyai(z), mpmath.airybi(z)],
                              [c * mpmath.airyai(z, 1), c * mpmath.airybi(z, 1)]])

    return fundamental(w) * mpmath.inverse(fundamental(0))


def _monodromy(eps, mu, pieces, zeta):
    """``(M_phi, kappa)`` at the exact doubles (``mu^2`` raised to ``mu^2 (1 + zeta^2)``), at the
    working precision."""
    e, m, z = (mpmath.mpf(float(v)) for v in (eps, mu, zeta))
    E, m2 = 8 * e * e, m * m * (1 + z * z)
    M = mpmath.eye(2)
    for x0, x1, s0, s1 in pieces:
        x0, x1, s0, s1 = (mpmath.mpf(float(v)) for v in (x0, x1, s0, s1))
        M = _flow(E * (m2 + s0), E * (s1 - s0) / (x1 - x0), x1 - x0) * M
    return M, 2 * mpmath.sqrt(8) * z * m * e


def oracle_stable(eps, mu, pieces, zeta=0.0):
    """``|tr M_phi| / 2 < cosh(kappa)`` at the exact doubles."""
    with mpmath.workdps(50):
        M, kappa = _monodromy(eps, mu, pieces, zeta)
        return bool(abs((M[0, 0] + M[1, 1]) / 2) < mpmath.cosh(kappa))


def _beside(x, k=2):
    """The doubles within ``k`` ulp of ``x``."""
    return (np.asarray([x], float).view(np.int64) + np.arange(-k, k + 1)).view(np.float64)


def _check_edges(drive, pieces, mu, zones, zeta=0.0):
    for n in zones:
        lo, hi = (float(v) for v in K.zone_edges(mu, n, drive=drive, zeta=zeta))
        assert lo < hi, (mu, n, lo, hi)
        for edge in (lo, hi):
            eps = _beside(edge)
            got = np.asarray(K.is_stable(eps, mu, drive=drive, zeta=zeta))
            want = np.array([oracle_stable(x, mu, pieces, zeta) for x in eps])
            assert np.array_equal(got, want), (mu, n, zeta, edge, got, want)
        # the edges lie on the unstable side, one double from the zone
        assert not K.is_stable(lo, mu, drive=drive, zeta=zeta) and K.is_stable(np.nextafter(lo, np.inf), mu, drive=drive, zeta=zeta)
        assert not K.is_stable(hi, mu, drive=drive, zeta=zeta) and K.is_stable(np.nextafter(hi, 0.0), mu, drive=drive, zeta=zeta)


def test_the_oracle_agrees_with_the_square_wave_closed_forms():
    # the square wave as two constant pieces: the oracle and the paper's exact verdict agree
    pieces = ((0.0, 1.0, 1.0, 1.0), (1.0, 2.0, -1.0, -1.0))
    lo, hi = (float(v) for v in K.zone_edges(0.4, 1))
    for x in np.concatenate([_beside(lo), _beside(hi)]):
        assert oracle_stable(x, 0.4, pieces) == bool(K.is_stable(x, 0.4))


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.62])
def test_triangle_verdicts_beside_its_edges_are_exact(mu):
    _check_edges(K.TriangleWave(), TRIANGLE_PIECES, mu, range(3))


def test_a_triangle_zone_thinner_than_the_engines_error_is_found_exactly():
    # zone 7 at mu = 0.3 is about 26 doubles wide, and the engine's trace there is off by more than
    # the zone's width: the certified verdicts move both edges, and the zone's middle is in it
    d = K.TriangleWave()
    _check_edges(d, TRIANGLE_PIECES, 0.3, [7])
    lo, hi = (float(v) for v in K.zone_edges(0.3, 7, drive=d))
    assert int(K.zone_index(0.5 * (lo + hi), 0.3, drive=d)) == 7


@pytest.mark.parametrize("zeta", [0.05, 0.3, 1.0])
def test_damped_triangle_verdicts_beside_its_edges_are_exact(zeta):
    _check_edges(K.TriangleWave(), TRIANGLE_PIECES, 0.3, range(2), zeta=zeta)


def test_a_measured_drive_linear_between_samples_is_exact_beside_its_edges():
    t = np.arange(7) / 7.0 * 0.02
    a = 500.0 * np.sin(2 * np.pi * t / 0.02) + 130.0 * np.cos(6 * np.pi * t / 0.02 + 0.4)
    d = K.drives.from_samples(t, a)
    pieces = d._linear_pieces()
    assert len(pieces) == 7 and pieces[-1][1] == 2.0
    _check_edges(d, pieces, 0.35, range(2))
    _check_edges(d, pieces, 0.35, [0], zeta=0.2)
    _check_edges(d, pieces, 0.35, [0, 1], zeta=1.0)


def test_a_measured_drive_held_between_samples_is_exact_beside_its_edges():
    # held samples: constant pieces, whose exact flows the oracle forms from cosh and cos
    t = np.arange(5) / 5.0 * 0.01
    a = np.array([3.0, 1.0, -2.0, -1.5, -0.5]) * 100.0
    d = K.drives.from_samples(t, a, kind="constant")
    pieces = d._linear_pieces()
    assert all(p[2] == p[3] for p in pieces)
    _check_edges(d, pieces, 0.3, range(2))
    _check_edges(d, pieces, 0.3, [1], zeta=0.1)


def test_a_flipped_verdict_carries_its_zone_and_rotation():
    # at the doubles beside an edge the zone, the rotation number and the growth follow the
    # certified verdict
    d = K.TriangleWave()
    for n in range(3):
        lo, hi = (float(v) for v in K.zone_edges(0.45, n, drive=d))
        inside = np.array([np.nextafter(lo, np.inf), np.nextafter(hi, 0.0)])
        outside = np.array([lo, hi])
        assert np.all(K.zone_index(inside, 0.45, drive=d) == n)
        assert np.all(K.zone_index(outside, 0.45, drive=d) == -1)
        f_in, f_out = K.floquet(inside, 0.45, drive=d), K.floquet(outside, 0.45, drive=d)
        assert np.all(f_in.growth == 0) and np.all(f_out.growth > 0)
        rho_in = np.asarray(f_in.rotation_number)
        assert np.all((rho_in > n / 2) & (rho_in < (n + 1) / 2)), rho_in
        two_rho = 2.0 * np.asarray(f_out.rotation_number)
        assert np.array_equal(two_rho, [n, n + 1]), two_rho


def test_a_long_measured_drive_keeps_the_engines_verdicts():
    # past CERTIFIED_PIECES each exact decision would cost a series per piece: the engine decides
    t = np.arange(200) / 200.0 * 0.02
    d = K.drives.from_samples(t, 400.0 * np.sin(2 * np.pi * t / 0.02))
    assert len(d._linear_pieces()) > d.CERTIFIED_PIECES and d._certified_pieces() is None and not d._damped_certified
    lo, hi = (float(v) for v in K.zone_edges(0.3, 0, drive=d))
    assert K.is_stable(0.5 * (lo + hi), 0.3, drive=d) and not K.is_stable(0.5 * lo, 0.3, drive=d)


def test_a_subclass_that_changes_the_shape_does_not_inherit_the_pieces():
    class Bumpy(K.TriangleWave):
        name = "test-bumpy"

        def _shape(self, tau):
            return np.sin(np.pi * tau) ** 3

    d = K.TriangleWave()
    assert d._exact_pieces() is not None and d._shape_table() is not None
    b = Bumpy()
    assert b._exact_pieces() is None and b._certified_pieces() is None and b._shape_table() is None
    assert not b._damped_certified


def oracle_trace(eps, mu, pieces, zeta=0.0):
    """``tr M_theta = 2 tau_phi exp(-kappa)`` at the exact doubles, with digits beyond the growth of
    the solutions (the terms that cancel in the trace)."""
    G = sum(math.sqrt(8.0 * eps * eps * max(abs(mu * mu * (1 + zeta * zeta) + s0), abs(mu * mu * (1 + zeta * zeta) + s1)))
            * (x1 - x0) for x0, x1, s0, s1 in pieces)
    with mpmath.workdps(40 + int(G / math.log(10.0))):
        M, kappa = _monodromy(eps, mu, pieces, zeta)
        return (M[0, 0] + M[1, 1]) * mpmath.exp(-kappa)


@pytest.mark.parametrize("zeta", [0.0, 0.3])
def test_a_reported_trace_is_recomputed_where_the_engine_leaves_it_rough(zeta):
    """The engine's trace is good to about 1e-13 e^G (``G`` the growth over the repelling pieces),
    and its bound says ten times less; a report recomputes in extended precision wherever that
    bound exceeds 1e-10 of the trace, so ``trace_error`` holds against the Airy oracle and stays
    within 1e-10 of the trace (at ``eps = 5``, ``mu = 0.5`` the engine's bound was 1.4e-4 of it)."""
    rng = np.random.default_rng(12)
    eps = np.concatenate([[5.0, 1.0], np.exp(rng.uniform(np.log(0.3), np.log(12.0), 14))])
    mu = np.concatenate([[0.5, 0.3], rng.uniform(0.05, 0.95, 14)])
    f = K.floquet(eps, mu, drive=K.TriangleWave(), zeta=zeta)
    for e, m, t, err in zip(eps.tolist(), mu.tolist(), f.trace.tolist(), f.trace_error.tolist()):
        tr = oracle_trace(e, m, TRIANGLE_PIECES, zeta)
        assert abs(mpmath.mpf(t) - tr) <= err, (e, m)
        assert err <= 1e-10 * abs(t), (e, m, err / abs(t))
