"""Exact propagation against independent numerics: solve_ivp (DOP853) and mp matrix powers.

Errors against solve_ivp are expressed in units of the requested tolerance, relative
to the size of the state at that time, ``r = sqrt(theta^2 + (theta'/w_h)^2)``.
"""
import math

import mpmath as mp
import numpy as np
import pytest

import ivp_ref
import kapitza as K
import oracle as O

RTOL = 1e-12
G = 9.81

# (T, A, l): stable in zones 0, 1, 2 and unstable (2T- and 4T-type), A < g, A = g
CASES = [
    (0.15, 100.0, 1.0),      # zone 0
    (0.5066, 100.0, 1.0),    # zone 1 (between T~_2 and T_2)
    (0.83736, 100.0, 1.0),   # zone 2 (between T_3 and T~_3)
    (0.05, 1000.0, 0.5),     # zone 0, stiffer
    (0.3, 100.0, 1.0),       # unstable, between zones 0 and 1
    (0.7, 100.0, 1.0),       # unstable, between zones 1 and 2
    (0.2, 5.0, 1.0),         # A < g: two hyperbolic phases
    (0.2, 9.81, 1.0),        # A = g: free flight in the second phase
]


def _state_norm(th, dth, A, l):
    wh = math.sqrt((A + G) / l)
    return np.hypot(th, dth / wh), wh


def _kappa(T, A, l):
    """||M|| in the scaled variables (theta, theta'/w_h): how much one period can amplify
    a perturbation (rounding in an integrator, or of the phase angles). Thin zones have
    large kappa, and the motion there is correspondingly ill-conditioned."""
    wh = math.sqrt((A + G) / l)
    M = K.monodromy(T, A, l)
    return float(np.linalg.norm(np.diag([1.0, 1.0 / wh]) @ M @ np.diag([1.0, wh]), 2))


@pytest.mark.parametrize("T,A,l", CASES)
def test_linear_motion_matches_solve_ivp_over_many_periods(T, A, l):
    eps, mu = K.to_arnold(T, A, l)
    stable = bool(K.is_stable(eps, mu))
    kappa = _kappa(T, A, l)
    periods = (40 if kappa < 50 else 10) if stable else 6
    rng = np.random.default_rng(int(1e4 * T) + int(A))
    # random times plus every switch k T (both phases meet there)
    t = np.concatenate([rng.uniform(0.0, 2 * T * periods, 150), T * np.arange(2 * periods)])
    th0, dth0 = 0.1, -0.3
    th_i, dth_i = ivp_ref.motion(t, th0, dth0, T, A, l, G, rtol=RTOL, atol=1e-16)
    th, dth = K.linear_motion(t, th0, dth0, T, A, l)
    r, wh = _state_norm(th_i, dth_i, A, l)
    err = np.maximum(np.abs(th - th_i), np.abs(dth - dth_i) / wh) / (RTOL * r)
    print(f"T={T} A={A}: max error {err.max():.3g} x rtol (median {np.median(err):.3g}), kappa {kappa:.3g}")
    # DOP853's global error: a few rtol per period, amplified by up to kappa
    assert err.max() < 2.0 * periods * max(kappa, 5.0)
    if stable:
        assert r.max() < 50 * kappa * r.min()  # bounded motion
    else:
        assert r[np.argmax(t)] > 2 * math.hypot(th0, dth0 / wh)


@pytest.mark.parametrize("T,A,l", CASES[:6] + [(0.01, 1e4, 2.0), (1.3, 30.0, 0.7)])
def test_monodromy_matches_solve_ivp(T, A, l):
    M = K.monodromy(T, A, l)
    Mi = ivp_ref.monodromy(T, A, l, G, rtol=RTOL, atol=1e-16)
    # columns carry different units: compare each column relative to its own size
    for j in range(2):
        err = np.max(np.abs(M[:, j] - Mi[:, j]) * [1.0, 1.0 / math.sqrt((A + G) / l)])
        scale = np.max(np.abs(Mi[:, j]) * [1.0, 1.0 / math.sqrt((A + G) / l)])
        assert err / (RTOL * scale) < 10.0, (T, A, l, j, err / (RTOL * scale))
    assert abs(np.linalg.det(M) - 1) < 1e-12 * np.abs(M).max() ** 2


@pytest.mark.parametrize("T,A,periods", [(0.15, 100.0, 10_000), (0.05, 1000.0, 10_000), (0.5066, 100.0, 2_000),
                                         (0.3, 100.0, 60), (0.7, 100.0, 25)])
def test_linear_motion_many_periods_matches_exact_matrix_powers(T, A, periods):
    # t up to 10^4 periods: the Chebyshev form of M^k against M^k in 70-digit arithmetic
    rng = np.random.default_rng(5)
    t = np.sort(np.concatenate([rng.uniform(0.0, 2 * T * periods, 40), [0.0, T, 2 * T * periods - 1e-9]]))
    th, dth = K.linear_motion(t, 0.2, 0.5, T, A)
    wh = math.sqrt(A + G)
    worst = 0.0
    for i in range(t.size):
        a, b = O.motion(t[i], 0.2, 0.5, T, A)
        with mp.workdps(50):
            r = mp.sqrt(a * a + (b / wh) ** 2)
            e = float(max(abs(th[i] - a), abs(dth[i] - b) / wh) / r)
        k = int(t[i] // (2 * T))
        worst = max(worst, e / (k + 1))
    kappa = _kappa(T, A, 1.0)
    x = math.sqrt(A + G) * T
    print(f"T={T} A={A}: worst error / (k + 1) = {worst:.2e} (kappa {kappa:.3g})")
    # per period: the rotation angle inherits the rounding of x, u amplified ~ kappa^2
    assert worst < 2e-16 * kappa**2 * (1 + x)


def test_linear_motion_starts_at_the_initial_state_and_is_continuous_at_switches():
    T, A = 0.15, 100.0
    th, dth = K.linear_motion(0.0, 0.3, -1.2, T, A)
    assert th == 0.3 and dth == -1.2
    k = np.arange(1, 30)
    before = K.linear_motion(k * T * (1 - 1e-13), 0.3, -1.2, T, A)
    after = K.linear_motion(k * T * (1 + 1e-13), 0.3, -1.2, T, A)
    at = K.linear_motion(k * T, 0.3, -1.2, T, A)
    for a, b, c in zip(before, after, at):
        np.testing.assert_allclose(a, c, rtol=1e-9, atol=1e-11)
        np.testing.assert_allclose(b, c, rtol=1e-9, atol=1e-11)


def test_linear_motion_broadcasts_like_scalar_calls():
    t = np.linspace(0.0, 3.0, 7)[:, None]
    T = np.array([0.15, 0.3, 0.5066])[None, :]
    th, dth = K.linear_motion(t, 0.1, 0.2, T, 100.0)
    assert th.shape == dth.shape == (7, 3)
    for i in range(7):
        for j in range(3):
            a, b = K.linear_motion(float(t[i, 0]), 0.1, 0.2, float(T[0, j]), 100.0)
            assert a == th[i, j] and b == dth[i, j]


def test_linear_motion_raises_overflow_beyond_a_double():
    with pytest.raises(OverflowError, match="range of a double"):
        K.linear_motion(1e4, 0.1, 0.0, 0.3, 100.0)
