"""The triangle-wave drive against independent numerics (DOP853 on its own shape)."""
import json

import numpy as np
import pytest

import kapitza
from kapitza import TriangleWave

from drive_ivp import edge, half_trace


def tri(tau):
    """The triangle's shape, written out here again (not taken from kapitza)."""
    tau = np.asarray(tau, float)
    return np.where(tau < 0.5, 2 * tau, np.where(tau < 1.5, 2 - 2 * tau, 2 * tau - 4))


BREAKS = (0.5, 1.5)
D = TriangleWave()


@pytest.mark.parametrize("eps, mu", [(0.3, 0.2), (0.8, 0.3), (1.5, 0.5), (3.0, 0.1), (6.0, 0.6), (0.7, 0.95)])
def test_trace_against_dop853(eps, mu):
    ref = half_trace(tri, eps, mu, BREAKS)
    f = kapitza.floquet(eps, mu, drive=D)
    assert abs(0.5 * f.trace - ref) <= 1e-9 * max(1.0, abs(ref))
    assert bool(f.stable) == (abs(ref) < 1.0)


@pytest.mark.parametrize("mu, n", [(0.2, 0), (0.5, 0), (0.3, 1), (0.4, 2), (0.1, 3), (0.8, 0)])
def test_edges_against_dop853(mu, n):
    lo, hi = kapitza.zone_edges(mu, n, drive=D)
    lo, hi = float(lo), float(hi)
    assert 0 < lo < hi
    # tr M / 2 = (-1)^n at the lower edge, -(-1)^n at the upper one
    s = (-1.0) ** n
    ref_lo = edge(tri, mu, lo * (1 - 1e-6), lo * (1 + 1e-6), s, BREAKS)
    ref_hi = edge(tri, mu, hi * (1 - 1e-6), hi * (1 + 1e-6), -s, BREAKS)
    assert abs(lo - ref_lo) <= 1e-10 * lo
    assert abs(hi - ref_hi) <= 1e-10 * hi
    # the verdicts a hair inside and outside the zone, and the zone index from the angle
    inside = np.array([lo * (1 + 1e-7), 0.5 * (lo + hi), hi * (1 - 1e-7)])
    outside = np.array([lo * (1 - 1e-7), hi * (1 + 1e-7)])
    assert kapitza.is_stable(inside, mu, drive=D).all()
    assert (kapitza.zone_index(inside, mu, drive=D) == n).all()
    assert not kapitza.is_stable(outside, mu, drive=D).any()
    for e in outside:
        assert abs(half_trace(tri, e, mu, BREAKS)) > 1.0


def test_zone_index_counts_turns_at_large_eps():
    # a stable point far out: its zone index agrees with the count of stable zones below it
    mu = 0.3
    edges = [tuple(map(float, kapitza.zone_edges(mu, n, drive=D))) for n in range(8)]
    for n, (lo, hi) in enumerate(edges):
        assert int(kapitza.zone_index(0.5 * (lo + hi), mu, drive=D)) == n
        if n:
            assert lo > edges[n - 1][1]


def test_kinematics_closed_forms_against_integrals():
    tau = np.linspace(0.0, 2.0, 200001)
    s = D._shape(tau)
    V = D._velocity_shape(tau)
    Z = D._displacement_shape(tau)
    dt = tau[1] - tau[0]
    # V' = s, Z' = V (central differences), zero means (trapezoid rule)
    assert np.max(np.abs(np.gradient(V, dt)[1:-1] - s[1:-1])) < 1e-4
    assert np.max(np.abs(np.gradient(Z, dt)[1:-1] - V[1:-1])) < 1e-8
    assert abs(np.trapezoid(V, tau)) < 1e-9 and abs(np.trapezoid(Z, tau)) < 1e-9
    assert D._stroke_coefficient == pytest.approx(Z.max() - Z.min(), rel=1e-9)
    assert D._mean_square_velocity == pytest.approx(np.trapezoid(V * V, tau) / 2, rel=1e-9)
    # the generic defaults of the base class reproduce the closed forms
    gen = kapitza.Drive._velocity_shape(D, tau[::97])
    assert np.max(np.abs(gen - V[::97])) < 1e-13
    assert kapitza.Drive._displacement_shape(D, tau[::97]) == pytest.approx(Z[::97], abs=1e-13)
    assert D.mu_max == 1.0
    assert float(D.kapitza_eps(0.2)) == pytest.approx(0.2 * np.sqrt(15) / 2, rel=1e-15)


def test_registered_and_reported():
    assert kapitza.drives.DRIVES["triangle"] is TriangleWave
    r = kapitza.analyze(T=0.2, A=100, drive=D)
    json.dumps(r.as_dict())
    assert "triangle" in r.drive
    v = kapitza.is_stable(0.8, 0.3, drive=D)
    assert isinstance(v, np.bool_)
    assert isinstance(kapitza.zone_index(0.8, 0.3, drive=D), np.integer)


def test_damped_edges_contain_undamped_phi_zone():
    # with damping the zone at mu contains the undamped zone at mu_c = mu sqrt(1 + zeta^2)
    mu, zeta = 0.3, 0.2
    lo, hi = map(float, kapitza.zone_edges(mu, 0, drive=D, zeta=zeta))
    lo0, hi0 = map(float, kapitza.zone_edges(mu * np.sqrt(1 + zeta**2), 0, drive=D))
    assert lo <= lo0 < hi0 <= hi
    assert kapitza.is_stable(0.5 * (lo + hi), mu, drive=D, zeta=zeta)
    assert not kapitza.is_stable(hi * 1.01, mu, drive=D, zeta=zeta)


def _mp_half_trace(eps, mu, dps=40, sub=8):
    """``tr M / 2`` of the triangle in mpmath: on each linear piece phi'' = (p + q t) phi is
    summed as its Taylor series (an entire function), ``sub`` steps per piece, to ``dps`` digits."""
    import mpmath

    with mpmath.workdps(dps):
        E = 8 * mpmath.mpf(eps) ** 2
        m2 = mpmath.mpf(mu) ** 2
        # (start, end, s at start, slope of s) of the three pieces on [0, 2]
        pieces = [(0, mpmath.mpf(1) / 2, 0, 2), (mpmath.mpf(1) / 2, mpmath.mpf(3) / 2, 1, -2),
                  (mpmath.mpf(3) / 2, 2, -1, 2)]
        M = mpmath.eye(2)
        tol = mpmath.mpf(10) ** (-dps)
        for a, b, s0, ds in pieces:
            h = (b - a) / sub
            for j in range(sub):
                p = E * (m2 + s0 + ds * j * h)  # k at the step's start, k' = E ds
                q = E * ds
                cols = []
                for y0, y1 in ((1, 0), (0, 1)):
                    c = [mpmath.mpf(y0), mpmath.mpf(y1)]
                    val, der = c[0] + c[1] * h, c[1]
                    n = 0
                    while True:  # c_{n+2} (n+2)(n+1) = p c_n + q c_{n-1}
                        cn = (p * c[n] + (q * c[n - 1] if n >= 1 else 0)) / ((n + 2) * (n + 1))
                        c.append(cn)
                        term = cn * h ** (n + 2)
                        val += term
                        der += (n + 2) * cn * h ** (n + 1)
                        n += 1
                        if n > 8 and abs(term) < tol * (1 + abs(val)) and abs(c[-2] * h ** n) < tol * (1 + abs(val)):
                            break
                    cols.append((val, der))
                S = mpmath.matrix([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])
                M = S * M
        return float((M[0, 0] + M[1, 1]) / 2)


@pytest.mark.parametrize("eps, mu", [(0.5, 0.3), (1.7, 0.45), (3.2, 0.2)])
def test_trace_against_an_mpmath_taylor_series(eps, mu):
    ref = _mp_half_trace(eps, mu)
    tr = float(kapitza.floquet(eps, mu, drive=D).trace) / 2
    # the engine's measured accuracy: about 1e-12 relative (docs/drives.md, section 7)
    assert abs(tr - ref) <= 2e-12 * max(1.0, abs(ref))


def test_edge_against_the_mpmath_trace():
    # the engine's zone-1 edges at mu = 0.3: tr M / 2 = -1 there to the accuracy of the edge
    mu = 0.3
    lo, hi = map(float, kapitza.zone_edges(mu, 1, drive=D))
    for e, target in ((lo, -1.0), (hi, 1.0)):
        # |tr M/2 - target| at the reported edge is within 1e-12 relative of eps times the slope
        h = 1e-7 * e
        slope = (_mp_half_trace(e + h, mu, dps=30) - _mp_half_trace(e - h, mu, dps=30)) / (2 * h)
        assert abs(_mp_half_trace(e, mu) - target) <= 1e-12 * e * abs(slope) + 1e-15
