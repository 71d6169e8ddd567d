"""The long double tier of drives given as linear pieces (the triangle, a measured drive), against mpmath.

Between the generic engine and mpmath the Taylor steps of ``kapitza._certify.pieces_mp`` are taken
in long double, with a bound on their rounding (``kapitza._certify.pieces_ld``). A verdict the tier
calls decided must be the exact one, and its trace must lie within its stated bound. The oracle is
the library's fixed-point product at the doubles themselves (``pieces_mp``, which
``test_pieces_certified.py`` checks against an independent one), so these tests check the tier's
bound, not the product.
"""
import numpy as np
import pytest

import kapitza as K
from kapitza import _certify as C
from kapitza.drives import from_samples

pytestmark = pytest.mark.skipif(not C.HAS_LONG_DOUBLE, reason="numpy's long double is the double here")


@pytest.fixture(autouse=True)
def _long_double_alone(monkeypatch):
    """The long double tier itself, also where the compiled double-double tier in front of it is
    loaded (``test_taylor_dd.py`` checks that one)."""
    from kapitza.engines import magnus

    monkeypatch.setattr(magnus, "compiled_pieces_tier", lambda: None)


def _measured():
    t = np.linspace(0.0, 1.0, 24, endpoint=False)
    return from_samples(t, np.sin(2 * np.pi * t) + 0.4 * np.cos(6 * np.pi * t + 0.3), kind="linear")


DRIVES = [K.TriangleWave(), _measured()]


def _beside(edges, k=8):
    e = np.asarray([x for x in np.ravel(edges) if np.isfinite(x) and x > 0])
    return (e.view(np.int64)[:, None] + np.arange(-k, k + 1)[None, :]).view(np.float64).ravel()


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.describe())
@pytest.mark.parametrize("zeta", [0.0, 0.1, 1.0])
def test_what_the_long_double_decides_is_the_exact_verdict(drive, zeta):
    pieces = drive._certified_pieces()
    rng = np.random.default_rng(7)
    eps, mu = [], []
    for m in (0.3, 0.75):
        lo, hi = K.zone_edges(m, np.arange(3), drive=drive, zeta=zeta)
        near = _beside(np.concatenate([np.ravel(lo), np.ravel(hi)]))
        eps.append(near)
        mu.append(np.full(near.size, m))
    far = 10.0 ** rng.uniform(-1.0, 1.0, 40)   # and points anywhere (their traces' bound)
    eps.append(far)
    mu.append(rng.uniform(0.02, 0.98, far.size))
    eps, mu = np.concatenate(eps), np.concatenate(mu)
    z = None if zeta == 0.0 else np.full(eps.size, zeta)
    dec, stable, tau, _, growth, tau_err = C.pieces_ld(eps, mu, z, pieces)
    ref = C.pieces_mp(eps, mu, z, pieces)
    r_tau = np.array([r[0] for r in ref])
    r_stable = np.array([r[2] for r in ref])
    r_growth = np.array([r[3] for r in ref])
    assert np.array_equal(stable[dec], r_stable[dec])
    assert np.all(np.abs(tau - r_tau) <= tau_err + 2.3e-16 * np.abs(r_tau))
    # the growth acosh|tau| (less kappa) is as good as tau makes it: tau's error over sqrt(tau^2 - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        g_err = np.where(np.abs(tau) > 1.0, tau_err / np.sqrt(np.abs(tau * tau - 1.0)), 0.0)
    assert np.all(np.abs(growth - r_growth)[dec] <= 1.01 * g_err[dec] + 1e-14 * np.abs(r_growth[dec]) + 1e-300)
    # it decides all but the doubles next to the threshold
    assert dec.mean() > 0.75


def test_past_its_step_limit_the_tier_declines():
    pieces = K.TriangleWave()._certified_pieces()
    dec, *_ = C.pieces_ld(np.array([5e3]), np.array([0.5]), None, pieces)
    assert not dec[0]


def test_the_verdicts_of_a_report_are_those_of_mpmath_alone(monkeypatch):
    # the same report with the tier switched off (every exact verdict from mpmath): the same
    # verdicts, zones and edges; the recomputed trace (and what follows from it) is the long
    # double's within its bound, mpmath's correctly rounded
    drive = K.TriangleWave()
    for zeta in (0.0, 0.1):
        fast = K.analyze(T=0.15, A=100.0, drive=drive, zeta=zeta).as_dict()
        with monkeypatch.context() as m:
            m.setattr(C, "pieces_ld", lambda eps, *a: (np.zeros(np.size(eps), bool),) * 2
                      + (np.full(np.size(eps), np.nan),) * 4)
            slow = K.analyze(T=0.15, A=100.0, drive=drive, zeta=zeta).as_dict()
        near = ("trace", "multipliers", "growth", "trace_margin", "determinant")
        assert {k: v for k, v in fast.items() if k not in near} == {k: v for k, v in slow.items() if k not in near}
        for k in near:
            np.testing.assert_allclose(np.asarray(fast[k], float), np.asarray(slow[k], float), rtol=1e-14, err_msg=k)


@pytest.mark.parametrize("drive, zeta", [(K.TriangleWave(), 0.0), (K.TriangleWave(), 0.1), (K.RectangularWave(0.3), 0.0),
                                         (K.RectangularWave(0.3), 0.1)],
                         ids=lambda v: v.describe() if hasattr(v, "describe") else repr(v))
def test_a_reported_growth_beside_an_edge_is_the_exact_one(drive, zeta):
    # a search needs only the verdict there (the long double's growth, as good as its trace, stands);
    # a reported growth (floquet) is the exact one to 1e-12 even a few doubles from the edge
    mu = 0.4
    hi = float(K.zone_edges(mu, 0, drive=drive, zeta=zeta)[1])
    eps = (np.array([hi]).view(np.int64) + np.arange(0, 6)).view(np.float64)   # the unstable side
    got = np.asarray(K.floquet(eps, mu, drive=drive, zeta=zeta).growth)
    z = None if zeta == 0.0 else np.full(eps.size, zeta)
    if drive._steps() is not None and zeta == 0.0:
        levels, fractions = drive._steps()
        want = np.array([r[3] for r in C.tau_mp(eps, np.full(eps.size, mu), levels, tuple(2.0 * f for f in fractions))])
    elif drive._steps() is not None:
        levels, fractions = drive._steps()
        want = np.array([r[1] for r in C.damped_mp(eps, np.full(eps.size, mu), z, levels,
                                                   tuple(2.0 * f for f in fractions))])
    else:
        want = np.array([r[3] for r in C.pieces_mp(eps, np.full(eps.size, mu), z, drive._certified_pieces())])
    assert np.all(want > 0)
    assert np.allclose(got, want, rtol=1e-12, atol=0.0)


def test_a_report_settles_verdicts_at_mu_and_recomputes_traces_at_phi(monkeypatch):
    # damped, the phi-system's verdicts near the threshold are those at the rounded mu_c (as the
    # verdicts without the trace are); only a recomputed trace is taken at mu^2 (1 + zeta^2) exactly
    d = K.TriangleWave()
    zeta, mu_c = 0.1, 0.3
    edge = float(K.zone_edges(mu_c, 0, drive=d)[1])
    eps = np.array([edge, 5.0])          # one point on the threshold, one whose trace is rough
    calls = []
    real = C.pieces_exact

    def spy(e, m, z, *a, **k):
        calls.append((np.size(e), z is None))
        return real(e, m, z, *a, **k)

    monkeypatch.setattr(C, "pieces_exact", spy)
    mu = np.full(2, mu_c / np.sqrt(1.0 + zeta * zeta))
    d._floquet0(eps, np.full(2, mu_c), certify=True, trace=True, phi=(mu, np.full(2, zeta)))
    assert (1, True) in calls and (1, False) in calls
