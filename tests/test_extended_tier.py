"""The long double tier of piecewise-constant verdicts, against mpmath.

Between the doubles and mpmath the segment product is taken in long double (x86's 64-bit
significand) with the same rounding bound; a verdict it calls decided must be the exact one. The
oracle here is the library's own mpmath product at the doubles themselves
(``kapitza._certify.tau_mp`` / ``damped_mp``, which ``test_damped_certified.py`` checks against an
independent matrix-exponential oracle), so these tests check the tier's bound, not the product.
"""
import numpy as np
import pytest

import kapitza as K
from kapitza import _certify
from kapitza.drives import _api
from kapitza.drives import _piecewise as P

pytestmark = pytest.mark.skipif(P.LONG_DOUBLE is None, reason="numpy's long double is the double here")

DRIVES = [K.SquareWave(), K.RectangularWave(0.3), K.RectangularWave(0.8),
          K.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])]


def _beside(edges, k=6):
    """The doubles within ``k`` ulp of each finite edge."""
    e = np.asarray([x for x in np.ravel(edges) if np.isfinite(x) and x > 0])
    return (e.view(np.int64)[:, None] + np.arange(-k, k + 1)[None, :]).view(np.float64).ravel()


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.describe())
@pytest.mark.parametrize("zeta", [0.0, 1e-9, 0.05, 1.0])
def test_what_the_long_double_decides_is_the_exact_verdict(drive, zeta):
    rng = np.random.default_rng(3)
    levels, fractions = drive._steps()
    durations = tuple(2.0 * f for f in fractions)
    mus = rng.uniform(0.05, 0.95, 3) * np.sqrt(drive._trough)
    decided = total = 0
    for mu in mus:
        lo, hi = K.zone_edges(mu, np.arange(3), drive=drive, zeta=zeta)
        eps = _beside([lo, hi])
        m, z = np.full(eps.shape, mu), np.full(eps.shape, zeta)
        dec, stable, tau, _, growth, tau_err = P.extended_verdicts(eps, m, z if zeta else None, levels, durations)
        if zeta:
            exact = _certify.damped_mp(eps[dec], m[dec], z[dec], levels, durations)
            assert stable[dec].tolist() == [r[0] for r in exact]
            # the growth acosh|tau| - kappa carries the trace's error (its stated bound) divided by
            # sqrt(tau^2 - 1): checked off the phi-zones
            g_exact = np.array([r[1] for r in exact])
            t, te = tau[dec], tau_err[dec]
            off = np.abs(t) > 1.0 + 1e-6
            slack = te[off] / np.sqrt(t[off] ** 2 - 1.0) + 1e-14 * (1.0 + np.abs(g_exact[off]))
            assert np.all(np.abs(growth[dec][off] - g_exact[off]) <= slack)
        else:
            exact = _certify.tau_mp(eps[dec], m[dec], levels, durations)
            assert stable[dec].tolist() == [r[2] for r in exact]
            # tr M / 2 within its stated bound (and the rounding to a double), however the segments cancel
            err = np.abs(tau[dec] - np.array([r[0] for r in exact]))
            assert np.all(err <= tau_err[dec] + 2.3e-16 * np.abs(tau[dec]))
        decided += int(dec.sum())
        total += eps.size
    # the tier is there to spare mpmath: beside these edges it decides most points (not all: where
    # the segments cancel strongly, thin zones' edges stay with mpmath)
    assert decided >= 0.75 * total


def test_an_undecidable_point_is_left_to_mpmath():
    # at eps = 1e-300 tr M / 2 = 1 to far below any long double's rounding: nothing may be decided
    dec, *_ = P.extended_verdicts(np.array([1e-300, 0.5]), np.array([0.3, 0.3]), None, (1.0, -1.0), (1.0, 1.0))
    assert dec.tolist() == [False, True]


@pytest.mark.parametrize("drive", DRIVES[1:], ids=lambda d: d.describe())
@pytest.mark.parametrize("zeta", [0.0, 1e-9, 0.3])
def test_searches_asking_the_certified_verdict_at_every_step_find_the_same_pair(drive, zeta, monkeypatch):
    # the one-point margin with certified steps (cheap here) against the fast steps with the final
    # pair certified (mpmath), on the same points
    rng = np.random.default_rng(11)
    pts = [(float(rng.uniform(0.2, 3.0)), float(rng.uniform(0.1, 0.9)) * np.sqrt(drive._trough)) for _ in range(6)]
    cheap = [_api.point_margin(drive, e, m, zeta) for e, m in pts]
    monkeypatch.setattr(type(drive), "_certified_cheap", lambda self, damped: False)
    slow = [_api.point_margin(drive, e, m, zeta) for e, m in pts]
    assert cheap == slow
