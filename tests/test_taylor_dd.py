"""The compiled double-double tier of the certified verdicts of linear pieces
(:mod:`kapitza.engines._taylor_dd`): its arithmetic against exact rationals, its traces and their
error bounds against the Airy-function oracle of ``test_pieces_certified``, its verdicts at the
doubles beside zone edges, and the tiers it sits in front of (long double, mpmath) agreeing with it.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import numpy as np
import pytest

pytest.importorskip("numba")

import kapitza as K  # noqa: E402
from kapitza import _certify  # noqa: E402
from kapitza.engines import load_compiled  # noqa: E402
from test_pieces_certified import TRIANGLE_PIECES, _beside, _check_edges, _monodromy  # noqa: E402


@pytest.fixture(scope="module")
def dd():
    assert load_compiled()
    from kapitza.engines import _taylor_dd

    return _taylor_dd


def _random_doubles(rng, n):
    return rng.uniform(-1, 1, n) * np.exp2(rng.integers(-40, 40, n))


def _split(x):
    """A double-double's value (hi, lo) as an exact rational."""
    return Fraction(x[0]) + Fraction(x[1])


def test_error_free_transformations_are_exact(dd):
    rng = np.random.default_rng(3)
    a, b = _random_doubles(rng, 2000), _random_doubles(rng, 2000)
    for x, y in zip(a.tolist(), b.tolist()):
        s, e = dd.two_sum(x, y)
        assert Fraction(s) + Fraction(e) == Fraction(x) + Fraction(y)
        p, e = dd.two_prod(x, y)
        assert Fraction(p) + Fraction(e) == Fraction(x) * Fraction(y)   # (no fused multiply-add: exact)


def test_double_double_operations_stay_within_the_unit(dd):
    rng = np.random.default_rng(4)
    worst = 0.0
    for _ in range(2000):
        xh, yh = _random_doubles(rng, 2).tolist()
        xl, yl = (v * 2.0**-53 * rng.uniform(-1, 1) for v in (xh, yh))
        xh, xl = dd.two_sum(xh, xl)
        yh, yl = dd.two_sum(yh, yl)
        X, Y = _split((xh, xl)), _split((yh, yl))
        c = float(rng.uniform(1, 100))
        for got, want in ((dd.dd_add(xh, xl, yh, yl), X + Y), (dd.dd_mul(xh, xl, yh, yl), X * Y),
                          (dd.dd_div(xh, xl, yh, yl), X / Y), (dd.dd_mul_d(xh, xl, c), X * Fraction(c)),
                          (dd.dd_div_d(xh, xl, c), X / Fraction(c))):
            if want != 0:
                worst = max(worst, float(abs(_split(got) - want) / abs(want)))
    assert worst <= dd.UNIT / 16, worst   # (the proven bounds are 3 to 15 u^2; UNIT is 64 u^2)


def _oracle_tau(eps, mu, pieces, zeta):
    """``tr M_phi / 2`` by the Airy oracle, with digits beyond the solutions' growth (mpmath)."""
    with mpmath.workdps(60 + int(0.5 * _certify._pieces_growth_bits(eps, mu * mu * (1 + zeta * zeta), pieces))):
        M, _ = _monodromy(eps, mu, pieces, zeta)
        return (M[0, 0] + M[1, 1]).real / 2


@pytest.mark.parametrize("zeta", [None, 0.3])
def test_traces_and_their_bounds_against_the_airy_oracle(dd, zeta):
    rng = np.random.default_rng(5)
    eps = np.exp(rng.uniform(np.log(0.05), np.log(20.0), 24))
    mu = rng.uniform(0.02, 0.98, 24)
    z = None if zeta is None else np.full(24, zeta)
    dec, st, tau, _, _, err, lo = dd.pieces_dd(eps, mu, z, TRIANGLE_PIECES, low=True)
    for i in range(24):
        want = _oracle_tau(eps[i], mu[i], TRIANGLE_PIECES, 0.0 if zeta is None else zeta)
        with mpmath.workdps(60):
            miss = abs(mpmath.mpf(tau[i]) + mpmath.mpf(lo[i]) - want)
        assert miss <= err[i], (eps[i], mu[i], float(miss), err[i])
        # the bound is tight enough to matter: far below a double's rounding of the trace
        assert err[i] <= 1e-20 * max(1.0, abs(tau[i])), (eps[i], mu[i], err[i])


@pytest.mark.parametrize("zeta", [None, 0.05, 1.0])
def test_verdicts_beside_the_edges_match_mpmath(dd, zeta):
    d = K.TriangleWave()
    rows = []
    for mu in (0.15, 0.45, 0.8):
        for n in range(3):
            lo, hi = (float(v) for v in K.zone_edges(mu, n, drive=d, zeta=0.0 if zeta is None else zeta))
            if np.isfinite(lo):
                rows += [(x, mu) for x in np.concatenate([_beside(lo, 3), _beside(hi, 3)])]
    eps, mu = np.array(rows).T
    z = None if zeta is None else np.full(eps.size, zeta)
    dec, st, tau, log_tau, growth, err = dd.pieces_dd(eps, mu, z, TRIANGLE_PIECES)
    assert dec.all()
    ref = _certify.pieces_mp(eps, mu, z, TRIANGLE_PIECES)
    assert st.tolist() == [r[2] for r in ref]
    assert np.allclose(tau, [r[0] for r in ref], rtol=1e-15, atol=0)
    # the growths (acosh|tau| - kappa; about 1e-8 beside an edge, where tau - 1 is 1e-17): against the
    # Airy oracle (pieces_mp resolves the verdict, its growth there only to about 2^-32)
    for i in range(0, eps.size, 5):
        zi = 0.0 if zeta is None else zeta
        with mpmath.workdps(80):
            t = abs(_oracle_tau(eps[i], mu[i], TRIANGLE_PIECES, zi))
            kappa = 2 * mpmath.sqrt(8) * mpmath.mpf(zi) * mpmath.mpf(mu[i]) * mpmath.mpf(eps[i])
            want = (mpmath.acosh(t) if t > 1 else 0) - kappa
        assert abs(growth[i] - want) <= 1e-13 * abs(want) + 1e-300, (eps[i], mu[i], growth[i], float(want))


def test_a_measured_drive_of_many_pieces(dd):
    t = np.arange(40) / 40.0 * 0.02
    a = 500.0 * np.sin(2 * np.pi * t / 0.02) + 130.0 * np.cos(6 * np.pi * t / 0.02 + 0.4)
    pieces = K.drives.from_samples(t, a)._linear_pieces()
    eps = np.array([0.3, 1.1, 2.7, 6.0])
    mu = np.array([0.2, 0.5, 0.35, 0.7])
    dec, st, tau, _, _, err, lo = dd.pieces_dd(eps, mu, None, pieces, low=True)
    assert dec.all()
    for i in range(eps.size):
        want = _oracle_tau(eps[i], mu[i], pieces, 0.0)
        with mpmath.workdps(60):
            assert abs(mpmath.mpf(tau[i]) + mpmath.mpf(lo[i]) - want) <= err[i]


def test_it_declines_what_it_cannot_take(dd):
    # eps too small for the pairs' low parts, too many steps, kappa past its series, eps not positive
    eps = np.array([1e-120, 1e5, 80.0, 0.0, np.nan])
    mu = np.array([0.5, 0.5, 0.9, 0.5, 0.5])
    z = np.array([0.1, 0.0, 1.0, 0.1, 0.1])
    dec = dd.pieces_dd(eps, mu, z, TRIANGLE_PIECES)[0]
    assert not dec.any()
    # (and the same points brought back within its range are decided: the refusals are those limits')
    back = dd.pieces_dd(np.array([1e-3, 100.0, 10.0, 0.5, 0.5]), mu, np.array([0.1, 0.0, 1.0, 0.1, 0.1]),
                        TRIANGLE_PIECES)[0]
    assert back.all()


def test_the_tiers_answer_alike_with_and_without_it(dd, monkeypatch):
    # the long double tier alone (the engine not loaded) and the double-double tier in front of it
    # give the same verdicts; where both decide, traces agree to their bounds
    d = K.TriangleWave()
    lo, hi = (float(v) for v in K.zone_edges(0.3, 1, drive=d))
    eps = np.concatenate([_beside(lo, 4), _beside(hi, 4), [0.7, 2.0, 9.0]])
    mu = np.full(eps.size, 0.3)
    with_dd = _certify.pieces_exact(eps, mu, None, TRIANGLE_PIECES, growth=True, trace=True)
    from kapitza.engines import magnus

    monkeypatch.setattr(magnus, "compiled_pieces_tier", lambda: None)
    without = _certify.pieces_exact(eps, mu, None, TRIANGLE_PIECES, growth=True, trace=True)
    assert [r[2] for r in with_dd] == [r[2] for r in without]
    for a, b in zip(with_dd, without):
        assert abs(a[0] - b[0]) <= a[4] + b[4]


def test_edges_with_the_tier_loaded_match_the_oracle(dd):
    _check_edges(K.TriangleWave(), TRIANGLE_PIECES, 0.3, [7])
    _check_edges(K.TriangleWave(), TRIANGLE_PIECES, 0.55, range(2), zeta=0.3)


@pytest.mark.parametrize("seed", range(6))
def test_random_measured_drives_beside_their_edges_agree_with_mpmath(dd, seed):
    """Property: for a random drive linear between 5-16 samples, random mu and damping, the tier's
    verdicts at the doubles beside zone edges are mpmath's, and its traces lie within its bound of
    mpmath's fixed-point product (resolved far beyond the doubles)."""
    rng = np.random.default_rng(100 + seed)
    n = int(rng.integers(5, 17))
    t = np.sort(rng.uniform(0.0, 1.0, n))
    t[0] = 0.0
    a = rng.normal(size=n)
    pieces = K.drives.from_samples(t, a, period=1.0)._linear_pieces()
    drive = K.drives.from_samples(t, a, period=1.0)
    mu = float(rng.uniform(0.05, 0.6))
    zeta = float(rng.choice([0.0, rng.uniform(0.01, 0.5)]))
    rows = []
    for n_zone in range(2):
        lo, hi = (float(v) for v in K.zone_edges(mu, n_zone, drive=drive, zeta=zeta))
        for x in (lo, hi):
            if np.isfinite(x) and x > 0:
                rows += _beside(x, 2).tolist()
    eps = np.array(rows)
    assert eps.size
    z = None if zeta == 0.0 else np.full(eps.size, zeta)
    dec, st, tau, _, _, err, low = dd.pieces_dd(eps, np.full(eps.size, mu), z, pieces, low=True)
    assert dec.all()
    ref = _certify.pieces_mp(eps, np.full(eps.size, mu), z, pieces)
    assert st.tolist() == [r[2] for r in ref]
    m2 = mu * mu * (1.0 + zeta * zeta)
    for i in range(eps.size):
        P = 200 + _certify._pieces_growth_bits(eps[i], m2, pieces)
        num = _certify._pieces_half_trace(eps[i], mu, zeta, pieces, P)
        with mpmath.workprec(2 * P + 64):
            exact = mpmath.mpf(num) / mpmath.mpf(2) ** (2 * P)
            assert abs(mpmath.mpf(tau[i]) + mpmath.mpf(low[i]) - exact) <= err[i], (eps[i], mu, zeta)
