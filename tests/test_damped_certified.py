"""Damped verdicts to the last bit for piecewise-constant drives, against an oracle of our own.

The oracle integrates ``theta'' + 2 beta theta' = 8 eps^2 (mu^2 + s_i) theta`` (time in units of
``T``, period 2, ``beta = 2 sqrt 2 zeta mu eps``) segment by segment with mpmath's matrix
exponential at 50 digits -- not through the ``phi = e^{beta t} theta`` transform the library uses --
and calls a point stable iff ``|tr M| < 1 + det M``. At the doubles beside each damped zone edge,
where the double computation cannot decide, ``is_stable`` must agree with it.
"""
import mpmath
import numpy as np
import pytest

import kapitza as K


def oracle_stable(eps, mu, zeta, drive):
    levels, fractions = drive._steps()
    with mpmath.workdps(50):
        e, m, z = mpmath.mpf(eps), mpmath.mpf(mu), mpmath.mpf(zeta)
        beta = 2 * mpmath.sqrt(2) * z * m * e
        M = mpmath.eye(2)
        for s, f in zip(levels, fractions):
            A = mpmath.matrix([[0, 1], [8 * e * e * (m * m + mpmath.mpf(s)), -2 * beta]])
            M = mpmath.expm(A * 2 * mpmath.mpf(f)) * M
        tr, det = M[0, 0] + M[1, 1], mpmath.det(M)
        return bool(abs(tr) < 1 + det)


CASES = [(K.SquareWave(), 0.9, 0.3), (K.SquareWave(), 0.05, 0.05), (K.RectangularWave(0.3), 0.4, 0.3),
         (K.RectangularWave(0.8), 0.9, 1.0), (K.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3]), 0.5, 0.2)]


@pytest.mark.parametrize("drive, mu, zeta", CASES, ids=lambda v: v.text() if hasattr(v, "text") else repr(v))
def test_damped_verdicts_beside_the_edges_are_certified(drive, mu, zeta):
    checked = 0
    for n in (0, 1):
        lo, hi = (float(x) for x in K.zone_edges(mu, n, drive=drive, zeta=zeta))
        for edge in (lo, hi):
            if not (np.isfinite(edge) and edge > 0):
                continue
            eps = (np.array([edge]).view(np.int64) + np.arange(-3, 4)).view(np.float64)
            got = K.is_stable(eps, mu, drive=drive, zeta=zeta)
            want = [oracle_stable(float(x), mu, zeta, drive) for x in eps]
            assert got.tolist() == want, (n, edge)
            assert (np.asarray(K.growth_rate(eps, mu, drive=drive, zeta=zeta)) < 0).tolist() == want
            checked += 1
    assert checked >= 2


def test_the_two_points_that_rounding_decided_wrongly():
    # |tr M_phi| - 2 cosh(cT) = +1.1e-11 (unstable) and -2.0e-20 (stable) at these doubles
    assert not K.is_stable(2.741587136542942, 0.9, zeta=0.3)
    assert K.is_stable(0.06123746457153446, 0.05, zeta=0.05)
    assert K.growth_rate(2.741587136542942, 0.9, zeta=0.3) > 0 > K.growth_rate(0.06123746457153446, 0.05, zeta=0.05)


@pytest.mark.parametrize("drive, mu, zeta", CASES, ids=lambda v: v.text() if hasattr(v, "text") else repr(v))
def test_each_damped_edge_is_the_unstable_double_beside_the_zone(drive, mu, zeta):
    lo, hi = (np.asarray(x, float) for x in K.zone_edges(mu, np.arange(3), drive=drive, zeta=zeta))
    # zones the damping has joined touch or overlap: their shared edges are no edges of stability
    meet = hi[:-1] >= lo[1:]
    joined = set(hi[:-1][meet].tolist()) | set(lo[1:][meet].tolist())
    for n in (0, 1):
        for edge, inward in ((float(lo[n]), np.inf), (float(hi[n]), -np.inf)):
            if not (np.isfinite(edge) and edge > 0) or edge in joined:
                continue
            assert not K.is_stable(edge, mu, drive=drive, zeta=zeta)
            assert K.is_stable(np.nextafter(edge, inward), mu, drive=drive, zeta=zeta)


@pytest.mark.parametrize("drive, mu, zeta", [(K.SquareWave(), 0.5, 1e-9), (K.SquareWave(), 0.95, 1e-12),
                                             (K.RectangularWave(0.3), 0.6, 1e-9),
                                             (K.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3]), 0.5, 1e-10)],
                         ids=lambda v: v.text() if hasattr(v, "text") else repr(v))
def test_light_damping_beside_the_undamped_edges(drive, mu, zeta):
    # with light damping the damped edges lie within an ulp or so of the undamped ones, where the
    # doubles cannot decide the undamped verdict either: both are settled in one exact product, and
    # the zone reported is the one whose edge the point is at (stable) or none (unstable)
    for n in (0, 1, 2):
        lo, hi = (float(x) for x in K.zone_edges(mu, n, drive=drive))
        for edge in (lo, hi):
            eps = (np.array([edge]).view(np.int64) + np.arange(-4, 5)).view(np.float64)
            got = K.is_stable(eps, mu, drive=drive, zeta=zeta)
            want = [oracle_stable(float(x), mu, zeta, drive) for x in eps]
            assert got.tolist() == want, (n, edge)
            zone = np.asarray(K.zone_index(eps, mu, drive=drive, zeta=zeta))
            assert np.array_equal(zone >= 0, got)
            assert set(zone[got].tolist()) <= {n}, (n, edge, zone)
