"""The nonlinear verdict: Moser off 1:4, Markeev on 1:4, the resonance curves, long runs.

Markeev's criterion is first checked on a map whose normal form is known by hand (rotations by
pi/4 between two cubic kicks, linear part a rotation by pi/2): there both outcomes occur, and
runs show escape exactly where the criterion says "unstable". On the pendulum every 1:4 point
of zones 0-4 has |tau| / |c4| between 2.8 and 3 (docs/nonlinear.md section 6): stable.
"""
import numpy as np
import pytest

import kapitza as K
from kapitza import normal_form as NF
from kapitza import _normal_form as NFE
from kapitza.motion import stroboscopic_map
from kapitza.resonances import nonlinear_chart, resonance_curve, twist_zeros

C4, S4 = np.cos(np.pi / 4), np.sin(np.pi / 4)
ROT = np.array([[C4, S4], [-S4, C4]])


def kicked_jet(a, b):
    """Jet of R(pi/4) K_b R(pi/4) K_a, K_a(q, p) = (q, p + a q^3)."""
    zero = np.zeros((2, 4))
    Ka = (np.eye(2), np.array([[0, 0, 0, 0], [a, 0, 0, 0.0]]))
    Kb = (np.eye(2), np.array([[0, 0, 0, 0], [b, 0, 0, 0.0]]))
    L, C = NFE._compose(*Ka, ROT, zero)
    L, C = NFE._compose(L, C, *Kb)
    return NFE._compose(L, C, ROT, zero)


def kicked_map(q, p, a, b):
    p = p + a * q**3
    q, p = C4 * q + S4 * p, -S4 * q + C4 * p
    p = p + b * q**3
    return C4 * q + S4 * p, -S4 * q + C4 * p


def kicked_verdict(a, b):
    L, C = kicked_jet(a, b)
    w = np.arccos(np.trace(L) / 2)
    lam = np.exp(1j * w)
    coef = NFE._coefficients(L, C, lam)
    beta = (coef[1] / lam).imag
    return NF.KINDS[int(NF._verdict_kinds(np.array(w), np.array(beta), coef, 1e-12))], beta, coef


@pytest.mark.parametrize("a, b, kind", [(1.0, -0.9, "markeev unstable"), (1.0, -0.6, "markeev unstable"),
                                        (1.0, -0.3, "markeev stable"), (1.0, 0.5, "markeev stable"),
                                        (1.0, -1.0, "undecided")])
def test_markeev_criterion_on_a_map_known_by_hand(a, b, kind):
    got, beta, coef = kicked_verdict(a, b)
    assert got == kind
    # by hand: |beta| = 3 |a + b| / 4 (in this coordinate), |c03| = |a - b| / 4 ... times a common factor
    np.testing.assert_allclose(abs(beta) / abs(coef[3]), 3 * abs(a + b) / abs(a - b), atol=1e-12)
    if kind == "undecided":
        return
    ang = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    q, p = 0.05 * np.cos(ang), 0.05 * np.sin(ang)
    top = 0.0
    for _ in range(20000):
        q, p = kicked_map(q, p, a, b)
        top = np.max(np.hypot(q, p))
        if top > 1.0:
            break
    if kind == "markeev unstable":
        assert top > 1.0  # some start escapes along the rays where the resonance beats the twist
    else:
        assert top < 0.1


# ---------------------------------------------------------------- the pendulum
def test_verdicts_off_and_on_the_strong_resonances():
    mu = np.array([0.1, 0.3, 0.5])
    for n in range(3):
        e3 = resonance_curve(mu, n, 3)
        e4 = resonance_curve(mu, n, 4)
        v3 = K.nonlinear_stability(e3, mu)
        v4 = K.nonlinear_stability(e4, mu)
        np.testing.assert_allclose(v3.trace, -1.0, atol=1e-9)
        np.testing.assert_allclose(v4.trace, 0.0, atol=1e-9)
        assert list(v3.kind) == ["moser 1:3"] * 3 and v3.stable.all()
        assert list(v4.kind) == ["markeev stable"] * 3 and v4.stable.all() and not v4.unstable.any()
        ratio = np.abs(v4.twist) / v4.resonant_4
        assert np.all((ratio > 2.7) & (ratio < 3.0 + 1e-9))
        off = K.nonlinear_stability(0.5 * (e3 + e4), mu)
        assert list(off.kind) == ["moser"] * 3


def test_verdict_prints_its_numbers():
    v = K.nonlinear_stability(0.5, 0.3)
    text = str(v)
    assert text.startswith("Lyapunov stable (Moser's twist theorem")
    assert f"{float(v.twist):.10g}" in text and "rho_0 = 0.1289526744" in text
    e4 = float(resonance_curve(0.3, 0, 4))
    assert "Markeev: |tau| > |c4|" in str(K.nonlinear_stability(e4, 0.3))


def test_chart_curves_are_ordered_inside_their_zones():
    ch = nonlinear_chart(np.linspace(0.05, 0.6, 6), zones=(0, 1), scan=12)
    for z in ch.zones:
        assert z.mu.size == 6
        rising = z.n % 2 == 0  # w grows from the 2T edge: lower for even zones
        first, second = (z.eps_1to4, z.eps_1to3) if rising else (z.eps_1to3, z.eps_1to4)
        assert np.all((z.eps_lo < first) & (first < second) & (second < z.eps_hi))
        assert z.twist_zeros == [] and z.twist_sign == (-1) ** (z.n + 1)
        assert z.markeev_stable.all()
        assert len(list(z.rows())) == 6


def test_twist_zeros_finds_none_in_zone_0():
    assert twist_zeros(0.3, 0, samples=50).size == 0


def _bounded_runs(eps, mu, periods, r=0.01):
    T, A = (float(v) for v in K.to_physical(eps, mu))
    ang = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    orbit = stroboscopic_map(r * np.cos(ang), r * np.sin(ang) / T, T, A, periods=periods, every=1000)
    return np.max(np.abs(orbit.theta))


def test_runs_near_the_upright_on_1to4_stay_bounded():
    e4 = float(resonance_curve(0.3, 0, 4))
    assert _bounded_runs(e4, 0.3, 3000) < 0.05


@pytest.mark.slow
@pytest.mark.parametrize("n, order", [(0, 4), (1, 4), (0, 3), (1, 3), (0, 5)])
def test_runs_near_the_upright_stay_bounded_for_1e5_periods(n, order):
    e = float(resonance_curve(0.2, n, order))
    tau = abs(float(K.twist_coefficient(e, 0.2)))
    r = min(0.01, 0.002 / np.sqrt(tau))
    assert _bounded_runs(e, 0.2, 100000, r) < 10 * r * max(1.0, abs(float(K.period_map_taylor(e, 0.2).linear[0, 1])))
