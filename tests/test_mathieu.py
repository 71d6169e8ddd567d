"""Mathieu characteristic values and the sine drive against mpmath, DLMF and solve_ivp."""
import numpy as np
import pytest
from mpmath import mp
from scipy.integrate import solve_ivp

import kapitza as K
import kapitza.drives as kd
from kapitza import mathieu as M
from kapitza._validate import KapitzaValueError

SINE = kd.SineWave()


def mp_characteristic(kind, n, q, N=44, dps=40):
    """Eigenvalue of the truncated family matrix at 40 digits (truncation far beyond need)."""
    with mp.workdps(dps):
        q = mp.mpf(q)
        parity = n % 2
        if kind == "a" and parity == 0:
            d, s0, shift, k = [(2 * r) ** 2 for r in range(N)], mp.sqrt(2), 0, n // 2
        elif kind == "a":
            d, s0, shift, k = [(2 * r + 1) ** 2 for r in range(N)], 1, 1, (n - 1) // 2
        elif parity == 1:
            d, s0, shift, k = [(2 * r + 1) ** 2 for r in range(N)], 1, -1, (n - 1) // 2
        else:
            d, s0, shift, k = [(2 * r + 2) ** 2 for r in range(N)], 1, 0, (n - 2) // 2
        A = mp.zeros(N, N)
        for r in range(N):
            A[r, r] = d[r]
            if r + 1 < N:
                A[r, r + 1] = A[r + 1, r] = q * (s0 if r == 0 else 1)
        A[0, 0] += shift * q
        ev = sorted(mp.eigsy(A, eigvals_only=True))
        return ev[k]


@pytest.mark.parametrize("q", [0.5, 10.0, 100.0])
def test_characteristic_values_against_mpmath(q):
    for n in range(0, 7):
        ref = mp_characteristic("a", n, q)
        assert float(M.characteristic_a(n, q)) == pytest.approx(float(ref), rel=1e-13, abs=1e-13)
        if n >= 1:
            ref = mp_characteristic("b", n, q)
            assert float(M.characteristic_b(n, q)) == pytest.approx(float(ref), rel=1e-13, abs=1e-13)


def test_characteristic_values_known_and_symmetric():
    # DLMF table 28.8 / Abramowitz-Stegun 20.1 at q = 1
    np.testing.assert_allclose(M.characteristic_a([0, 1, 2], 1.0), [-0.455138604107, 1.859108072514, 4.371300982735],
                               rtol=1e-11)
    np.testing.assert_allclose(M.characteristic_b([1, 2], 1.0), [-0.110248816992, 3.917024772998], rtol=1e-11)
    n = np.arange(0, 8)
    np.testing.assert_array_equal(M.characteristic_a(n, 0.0), n**2)
    np.testing.assert_allclose(M.characteristic_a(n[1::2], -3.0), M.characteristic_b(n[1::2], 3.0), rtol=1e-14)
    np.testing.assert_allclose(M.characteristic_a(n[::2], -3.0), M.characteristic_a(n[::2], 3.0), rtol=1e-14)


@pytest.mark.parametrize("q", [1e3, 1e4])
def test_large_q_against_the_dlmf_asymptotic_series(q):
    """DLMF 28.8.1: a_n ~ b_{n+1} ~ -2q + 2 s sqrt(q) - (s^2 + 1)/8 - (s^3 + 3 s)/(2^7 sqrt q) - ..., s = 2n + 1."""
    for n in range(4):
        s = 2 * n + 1
        h = np.sqrt(q)
        series = -2 * q + 2 * s * h - (s**2 + 1) / 8 - (s**3 + 3 * s) / (2**7 * h) \
            - (5 * s**4 + 34 * s**2 + 9) / (2**12 * q)
        nxt = (33 * s**5 + 410 * s**3 + 405 * s) / (2**17 * h**3)  # size of the next term
        for val in (M.characteristic_a(n, q), M.characteristic_b(n + 1, q)):
            assert abs(float(val) - series) < 3 * nxt + 1e-12 * q


def sine_monodromy(eps, mu, zeta=0.0, rtol=1e-12):
    C = 2 * np.sqrt(8) * zeta * mu * eps
    cols = []
    for y0 in ((1.0, 0.0), (0.0, 1.0)):
        sol = solve_ivp(lambda t, y: [y[1], 8 * eps * eps * (mu * mu + np.sin(np.pi * t)) * y[0] - C * y[1]],
                        (0.0, 2.0), y0, method="DOP853", rtol=rtol, atol=1e-15)
        cols.append(sol.y[:, -1])
    return np.array(cols).T


def test_sine_edges_carry_periodic_motions():
    """At the edges tr M = +-2 (solve_ivp), with the paper's 2T/4T alternation."""
    mu = np.array([0.05, 0.3, 0.6, 0.85])
    for n in range(4):
        lo, hi = K.zone_edges(mu, n, drive=SINE)
        for e, m, sign in [(x, y, (-1) ** n) for x, y in zip(lo, mu)] + [(x, y, (-1) ** (n + 1)) for x, y in zip(hi, mu)]:
            Mo = sine_monodromy(e, m)
            if np.abs(Mo).sum() > 1e6:  # tr M = +-2 cancels 1e6-sized entries: beyond solve_ivp's reach
                continue
            assert np.trace(Mo) / 2 == pytest.approx(sign, abs=50 * 1e-12 * np.abs(Mo).sum())


def test_sine_verdicts_and_traces_against_solve_ivp():
    rng = np.random.default_rng(4)
    eps = rng.uniform(0.05, 3.5, 40)
    mu = rng.uniform(0.02, 0.95, 40)
    f = K.floquet(eps, mu, drive=SINE)
    for i in range(eps.size):
        Mo = sine_monodromy(eps[i], mu[i])
        assert bool(f.stable[i]) == bool(abs(np.trace(Mo)) < 2)
        assert abs(np.trace(Mo) - f.trace[i]) < 100 * 1e-12 * np.abs(Mo).sum()


def test_sine_kapitza_limit():
    mu = np.array([1e-3, 1e-2, 0.05])
    lo, _ = K.zone_edges(mu, 0, drive=SINE)
    rel = lo / (np.pi * mu / 2) - 1
    assert np.all(np.abs(rel) < 10 * mu**2)
    assert abs(rel[0]) < 1e-5


def test_sine_grid_is_pixel_exact_and_damped_edges_hold():
    eps = np.linspace(0.01, 4.0, 300)
    mu = np.linspace(0.02, 0.98, 50)
    g = K.stability_grid(eps, mu, drive=SINE)
    E, MU = np.meshgrid(eps, mu)
    np.testing.assert_array_equal(g, K.is_stable(E, MU, drive=SINE))
    zeta = 0.15
    mu1 = np.array([0.2, 0.5])
    for n in range(2):
        lo, hi = K.zone_edges(mu1, n, drive=SINE, zeta=zeta)
        for e, m in zip(np.concatenate([lo, hi]), np.concatenate([mu1, mu1])):
            Mo = sine_monodromy(e, m, zeta)
            lam = np.abs(np.linalg.eigvals(Mo))
            assert abs(lam.max() - 1.0) < 50 * 1e-12 * np.abs(Mo).sum() ** 2


def test_bad_input():
    with pytest.raises(KapitzaValueError, match="n"):
        M.characteristic_b(0, 1.0)
    with pytest.raises(KapitzaValueError, match="q"):
        M.characteristic_a(1, float("nan"))
    with pytest.raises(KapitzaValueError, match="mu"):
        M.sine_zone_edges(1.2, 0)
