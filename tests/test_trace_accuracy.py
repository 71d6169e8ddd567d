"""The trace and the growth where the segment product cancels, and the bound ``Floquet.trace_error``.

The oracle is a segment product written here in mpmath at 60 digits beyond the size of the terms
that cancel (``e^{sum r}``), at the exact doubles given (damped: ``mu^2 (1 + zeta^2)`` and
``kappa = 2 sqrt(8) zeta mu eps`` formed in mpmath). Nothing of kapitza's is used to form it.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import kapitza

from drive_ivp import half_trace as ivp_half_trace

STEP4 = kapitza.StepDrive([1.0, -0.5, 0.7, -0.9], [0.2, 0.3, 0.25, 0.25])
DRIVES = {"rect0.8": kapitza.RectangularWave(0.8), "rect0.3": kapitza.RectangularWave(0.3), "step4": STEP4,
          "square": kapitza.SquareWave()}


def exact(eps, mu, drive, zeta=0.0):
    """``(tr M_theta, growth)`` of the damped drive at the exact doubles (mpmath)."""
    levels = [float(s) for s in drive.levels]
    hs = [2.0 * float(f) for f in drive.fractions]
    phase = sum(math.sqrt(8.0 * eps * eps * abs(mu * mu * (1.0 + zeta * zeta) + s)) * h for s, h in zip(levels, hs))
    with mpmath.workdps(60 + int(phase / math.log(10.0))):
        E, M, Z = mpmath.mpf(eps), mpmath.mpf(mu), mpmath.mpf(zeta)
        m2 = M * M * (1 + Z * Z)
        a, b, c, d = mpmath.mpf(1), mpmath.mpf(0), mpmath.mpf(0), mpmath.mpf(1)
        for s, h in zip(levels, hs):
            k = 8 * E * E * (m2 + mpmath.mpf(s))
            H = mpmath.mpf(h)
            if k > 0:
                w = mpmath.sqrt(k)
                S = (mpmath.cosh(w * H), mpmath.sinh(w * H) / w, w * mpmath.sinh(w * H), mpmath.cosh(w * H))
            elif k < 0:
                w = mpmath.sqrt(-k)
                S = (mpmath.cos(w * H), mpmath.sin(w * H) / w, -w * mpmath.sin(w * H), mpmath.cos(w * H))
            else:
                S = (mpmath.mpf(1), H, mpmath.mpf(0), mpmath.mpf(1))
            a, b, c, d = S[0] * a + S[1] * c, S[0] * b + S[1] * d, S[2] * a + S[3] * c, S[2] * b + S[3] * d
        tau = (a + d) / 2
        kappa = 2 * mpmath.sqrt(8) * Z * M * E
        growth = (mpmath.acosh(abs(tau)) if abs(tau) > 1 else 0) - kappa
        return 2 * tau * mpmath.exp(-kappa), float(growth)


def check_point(f, tr, g):
    """The reported trace within its bound, of the exact sign, the growth to 1e-10 (relative, or
    absolute below 1), the rotation angle's parity off the zones that of the trace's sign."""
    assert abs(mpmath.mpf(float(f.trace)) - tr) <= f.trace_error
    assert np.sign(f.trace) == mpmath.sign(tr)
    assert abs(float(f.growth) - g) <= 1e-10 * max(abs(g), 1.0)
    if not f.stable:
        k = 2.0 * float(f.rotation_number)
        assert abs(k - round(k)) < 1e-9
        assert (-1) ** int(round(k)) == np.sign(f.trace)


def test_the_damped_rectangular_wave_far_out():
    # its trace cancels by e^77: the double product gave growth 63.17 and a positive trace
    f = kapitza.floquet(14.483338627482924, 1.8431253140703037, drive=kapitza.RectangularWave(0.8), zeta=0.3)
    tr, g = exact(14.483338627482924, 1.8431253140703037, kapitza.RectangularWave(0.8), 0.3)
    assert tr < 0 and abs(g - 65.1548257879342) < 1e-12
    check_point(f, tr, g)
    assert f.trace_error <= 1e-12 * abs(f.trace)
    assert kapitza.growth_rate(14.483338627482924, 1.8431253140703037, drive=kapitza.RectangularWave(0.8),
                               zeta=0.3) == f.growth


# (drive, mu_c, zone): zones thin enough that the terms of the trace beside them are e^20 - e^80
# times the trace
THIN = [("rect0.8", 1.6, 6), ("rect0.8", 1.6, 10), ("rect0.3", 0.5, 10), ("step4", 0.6, 6), ("step4", 0.6, 10),
        ("square", 0.7, 6), ("square", 0.7, 10)]


@pytest.mark.parametrize("name, mu_c, n", THIN)
@pytest.mark.parametrize("zeta", [0.0, 0.3])
def test_beside_thin_zones_the_trace_and_growth_are_exact(name, mu_c, n, zeta):
    d = DRIVES[name]
    lo, hi = (float(v) for v in kapitza.zone_edges(mu_c, n, drive=d))
    # the phi-system of the damped drive is the undamped one at mu_c: the same cancellation
    mu = mu_c / math.sqrt(1.0 + zeta * zeta)
    for eps in (lo * (1.0 - 3e-12), hi * (1.0 + 3e-12), hi * (1.0 + 1e-9), lo * (1.0 - 1e-7)):
        f = kapitza.floquet(eps, mu, drive=d, zeta=zeta)
        tr, g = exact(eps, mu, d, zeta)
        check_point(f, tr, g)


def _points(rng, drive, kind, n):
    if kind == "free flight":  # one segment's mu^2 + s_i near 0 (its argument's rounding matters most)
        negs = [-s for s in drive.levels if s < 0]
        mu = np.sqrt(rng.choice(negs, n)) * (1.0 + rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-15, -2, n))
        return np.exp(rng.uniform(0.0, np.log(40.0), n)), mu, np.zeros(n)
    eps = np.exp(rng.uniform(np.log(0.05), np.log(30.0), n))
    mu = rng.uniform(0.02, 2.2, n)
    return eps, mu, (rng.uniform(0.0, 1.0, n) if kind == "damped" else np.zeros(n))


@pytest.mark.parametrize("name", sorted(DRIVES))
@pytest.mark.parametrize("kind", ["undamped", "damped", "free flight"])
def test_trace_error_bounds_the_error_on_random_points(name, kind):
    d = DRIVES[name]
    rng = np.random.default_rng(sum(map(ord, name + kind)))
    eps, mu, zeta = _points(rng, d, kind, 30)
    f = kapitza.floquet(eps, mu, drive=d, zeta=zeta)
    assert f.trace_error.shape == eps.shape
    ratio, rel = [], []
    for i in range(eps.size):
        tr, g = exact(float(eps[i]), float(mu[i]), d, float(zeta[i]))
        if not np.isfinite(f.trace[i]):
            assert f.trace_error[i] == np.inf
            continue
        ratio.append(float(abs(mpmath.mpf(float(f.trace[i])) - tr)) / f.trace_error[i])
        rel.append(f.trace_error[i] / abs(f.trace[i]))
        assert abs(f.growth[i] - g) <= 1e-10 * max(abs(g), 1.0)
    assert max(ratio) <= 1.0
    # a bound to the point: cancellation beyond 1e-10 was recomputed, and it is not loose by more
    # than a few hundred times where nothing cancels
    assert max(rel) <= 1e-10
    assert np.median(rel) < 1e-12
    assert np.median(ratio) > 1e-4


def test_trace_error_is_shaped_like_the_trace():
    f = kapitza.floquet(0.5, 0.3)
    assert isinstance(f.trace_error, np.float64) and 0.0 < f.trace_error < 1e-12
    f = kapitza.floquet([[0.5, 1.2]], 0.3, drive=kapitza.RectangularWave(0.3), zeta=0.1)
    assert f.trace_error.shape == (1, 2) and np.all(f.trace_error > 0)
    # beyond a double the trace is inf, and so is its error; the growth stays finite and exact
    f = kapitza.floquet(400.0, 0.3)
    assert np.isinf(f.trace) and f.trace_error == np.inf and np.isfinite(f.growth)


@pytest.mark.parametrize("drive", ["sine", "triangle"])
def test_integrated_drives_bound_their_trace(drive):
    # the engines' own bounds (the sine's a running bound of its steps' rounding, the shape's
    # engine 1e-10 e^G) against DOP853 (rtol 1e-12, itself good to ~1e-11 here)
    d = kapitza.drives.as_drive(drive)
    for eps, mu in [(0.5, 0.3), (1.2, 0.3), (2.0, 0.7)]:
        f = kapitza.floquet(eps, mu, drive=d)
        ref = 2.0 * ivp_half_trace(d._shape, eps, mu, getattr(d, "_breakpoints", ()) or ())
        assert 0.0 < f.trace_error < 1e-4 * max(abs(f.trace), 1.0)
        assert abs(f.trace - ref) <= f.trace_error + 1e-10 * max(abs(ref), 1.0)


@pytest.mark.parametrize("drive", [kapitza.SquareWave(), kapitza.StepDrive([1.0, -1.0], [0.5, 0.5])])
def test_the_report_gives_the_exact_trace_where_it_cancels(drive):
    # the square wave's report answers from scalar twins of its closed forms: they hand a cancelling
    # trace to the exact path too
    lo, hi = (float(v) for v in kapitza.zone_edges(0.7, 10))
    eps = hi * (1.0 + 3e-12)
    tr, g = exact(eps, 0.7, kapitza.SquareWave())
    r = kapitza.analyze(eps=eps, mu=0.7, drive=drive)
    assert r.trace == kapitza.floquet(eps, 0.7, drive=drive).trace
    assert abs(mpmath.mpf(r.trace) - tr) <= 1e-15 * abs(tr)
    assert abs(r.growth - g) <= 1e-10 * g


def test_a_drive_written_to_the_older_contract_reports_no_bound():
    class Older(kapitza.RectangularWave):
        def _floquet0(self, eps, mu, certify=True):
            return super()._floquet0(eps, mu, certify)

    for zeta in (0.0, 0.1):
        f = kapitza.floquet([0.5, 1.0], 0.3, drive=Older(0.3), zeta=zeta)
        ref = kapitza.floquet([0.5, 1.0], 0.3, drive=kapitza.RectangularWave(0.3), zeta=zeta)
        assert np.all(f.trace == ref.trace) and np.all(f.trace_error == np.inf)
