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
