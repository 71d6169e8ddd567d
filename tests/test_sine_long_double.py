"""The long double tier of the sine drive's exact trace, against the fixed-point one.

Before the exact trace of ``kapitza.drives._mathieu._exact_half_period`` (Taylor steps in integer
arithmetic, precision doubled until the verdict is resolved), the same steps are taken in long double
with a bound on their rounding (``sine_ld``). A verdict it calls decided must be the exact one, and
its trace must lie within its bound.
"""
import numpy as np
import pytest

import kapitza as K
from kapitza import _certify as C
from kapitza.drives import _mathieu as M

pytestmark = pytest.mark.skipif(not C.HAS_LONG_DOUBLE, reason="numpy's long double is the double here")


@pytest.mark.parametrize("mu", [0.3, 0.6, 0.85])
def test_undamped_verdicts_beside_the_edges(mu):
    eps = []
    for n in (0, 1, 2):
        for edge in K.zone_edges(mu, n, drive="sine"):
            eps.append((np.array([float(edge)]).view(np.int64) + np.arange(-6, 7)).view(np.float64))
    eps = np.concatenate(eps)
    dec, stable, tau, _, _, err = M.sine_ld(eps, np.full(eps.size, mu))
    ref = [M._exact_tau(e, mu) for e in eps]
    r_tau = np.array([r[0] for r in ref])
    assert np.array_equal(stable[dec], np.array([r[2] for r in ref])[dec])
    assert np.all(np.abs(tau - r_tau)[dec] <= err[dec] + 2.3e-16 * np.abs(r_tau[dec]))
    assert dec.mean() > 0.6


@pytest.mark.parametrize("zeta", [0.05, 1.0])
def test_damped_verdicts(zeta):
    rng = np.random.default_rng(11)
    eps, mu = 10.0 ** rng.uniform(-1.0, 0.5, 30), rng.uniform(0.05, 0.95, 30)
    for m in (0.3, 0.5):   # (edges at eps of a few: the fixed-point reference takes seconds a point at 100)
        lo, hi = K.zone_edges(m, 1, drive="sine", zeta=zeta)
        near = (np.array([float(lo), float(hi)]).view(np.int64)[:, None] + np.arange(-4, 5)).view(np.float64).ravel()
        eps, mu = np.concatenate([eps, near]), np.concatenate([mu, np.full(near.size, m)])
    z = np.full(eps.size, zeta)
    dec, stable, *_ = M.sine_ld(eps, mu, z)
    M._DAMPED_EXACT.clear()
    with pytest.MonkeyPatch.context() as mp:   # the fixed-point trace alone
        mp.setattr(M, "_ld_pays", lambda eps, mu: False)
        ref = M.sine_damped_exact(eps, mu, z)
    M._DAMPED_EXACT.clear()
    assert np.array_equal(stable[dec], np.array([r[0] for r in ref])[dec])
    assert dec.mean() > 0.6


def test_far_damped_zone_without_the_fixed_point_trace(monkeypatch):
    # zone 1 at mu 0.7, zeta 1 lies at eps ~ 117.6 (q ~ 22,000), where the phi-system's zones are
    # thinner than an ulp and the double trace has no digits left: the phi-verdict's exact trace in
    # fixed point took 40 s a point there. The long double decides the phi-verdict, and the damped
    # verdict |tau_phi| < cosh(kappa) by its own bound; the answers are those the fixed-point trace
    # gave (three doubles, 123 s)
    def refuse(*args, **kwargs):
        raise AssertionError("the fixed-point trace was asked")

    monkeypatch.setattr(M, "_exact_tau", refuse)
    monkeypatch.setattr(M, "_exact_half_period", refuse)
    eps = np.array([117.64562450252139, 117.6456245025214, 117.64562450252141])
    assert not K.is_stable(eps, 0.7, drive="sine", zeta=1.0).any()
    lo, hi = K.zone_edges(0.7, 1, drive="sine", zeta=1.0)
    assert (float(lo), float(hi)) == (117.64562450252139, 117.64562450252141)
