"""Damping and general drives against independent numerics: solve_ivp monodromy of the damped
equation, an mpmath product, and the damped edge conditions."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import kapitza.drives as kd
from kapitza.drives import _api
from kapitza._certify import tau_mp as _tau_mp
from kapitza.drives._piecewise import floquet_product

RTOL = 1e-12
DRIVES = [kd.SquareWave(), kd.RectangularWave(0.3), kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])]


def ivp_monodromy(drive, eps, mu, zeta):
    """Monodromy of theta'' + C theta' = 8 eps^2 (mu^2 + s(tau)) theta over tau in [0, 2],
    C = c T = 2 sqrt(8) zeta mu eps, integrated segment by segment (DOP853)."""
    C = 2.0 * np.sqrt(8.0) * zeta * mu * eps
    cols = []
    for y0 in ((1.0, 0.0), (0.0, 1.0)):
        y = np.array(y0)
        t = 0.0
        for s, h in zip(drive.levels, drive._durations):
            k = 8.0 * eps * eps * (mu * mu + s)
            sol = solve_ivp(lambda _, v: [v[1], k * v[0] - C * v[1]], (t, t + h), y,
                            method="DOP853", rtol=RTOL, atol=1e-14)
            y = sol.y[:, -1]
            t += h
        cols.append(y)
    return np.array(cols).T


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.name)
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.4])
def test_trace_and_determinant_against_solve_ivp(drive, zeta):
    rng = np.random.default_rng(3)
    for eps, mu in zip(rng.uniform(0.1, 2.5, 6), rng.uniform(0.05, 0.9, 6)):
        M = ivp_monodromy(drive, eps, mu, zeta)
        tr, det, mult, growth, _, stable, _ = _api.floquet(np.array(eps), np.array(mu), drive, np.array(zeta))
        kappa = 2.0 * np.sqrt(8.0) * zeta * mu * eps
        assert float(det) == pytest.approx(np.exp(-2 * kappa), rel=1e-15)
        assert np.linalg.det(M) == pytest.approx(np.exp(-2 * kappa), rel=1e-9)
        scale = np.abs(M).sum()
        # error in units of the tolerance, relative to the size of the entries
        assert abs(np.trace(M) - float(tr)) / (RTOL * scale) < 50
        lam = np.sort(np.abs(np.linalg.eigvals(M)))[::-1]
        assert np.log(lam[0]) == pytest.approx(float(growth), abs=1e-8 * max(1, scale))
        assert bool(stable) == bool(lam[0] < 1 - 1e-9 or (zeta == 0 and abs(np.trace(M)) < 2))


@pytest.mark.parametrize("drive", DRIVES[1:], ids=lambda d: d.name)
def test_product_against_mpmath_far_out(drive):
    """log|tr M / 2| and its sign agree with a 40+-digit product where cosh overflows doubles."""
    eps = np.array([50.0, 200.0, 800.0, 1000.0])
    mu = np.array([0.3, 0.6, 0.2, 0.9])
    f = floquet_product(eps, mu, drive.levels, drive._durations)
    ref = _tau_mp(eps, mu, drive.levels, drive._durations)
    for i, (t, lt, *_) in enumerate(ref):
        assert np.sign(f.tau[i]) == np.sign(t)
        assert f.log_tau[i] == pytest.approx(lt, rel=1e-12)
        assert np.isfinite(f.growth[i]) and f.growth[i] > 0


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.name)
@pytest.mark.parametrize("zeta", [0.05, 0.3])
def test_damped_edges_bound_the_damped_zones(drive, zeta):
    """At the damped edges a multiplier has modulus 1; just inside stable, just outside not
    (unless damping has joined two zones: their common edge is then reported at the point
    where |tr M_phi| / 2 cosh(kappa) is largest, and both sides are stable)."""
    mu = np.array([0.2, 0.45, 0.7])
    z = np.full(3, zeta)
    E = [_api.edges(mu, n, drive, z) for n in range(4)]
    for n in range(3):
        lo, hi = E[n]
        joined_lo = (lo == E[n - 1][1]) if n > 0 else np.zeros(3, bool)
        joined_hi = hi == E[n + 1][0]
        for e, sign, joined in ((lo, 1.0, joined_lo), (hi, -1.0, joined_hi)):
            ok = np.isfinite(e) & (e > 0) & ~joined
            inside = e * (1 + sign * 1e-9)
            outside = e * (1 - sign * 1e-9)
            s_in, zone_in = _api.verdict(inside[ok], mu[ok], drive, z[ok])
            s_out, _ = _api.verdict(outside[ok], mu[ok], drive, z[ok])
            assert s_in.all() and not s_out.any()
            assert np.all(zone_in == n)
            # independent: the multiplier of largest modulus is 1 at the edge (solve_ivp)
            for ei, mi in zip(e[ok], mu[ok]):
                M = ivp_monodromy(drive, ei, mi, zeta)
                lam = np.abs(np.linalg.eigvals(M))
                assert abs(lam.max() - 1.0) < 50 * RTOL * np.abs(M).sum() ** 2
            for ei, mi in zip(e[joined], mu[joined]):
                assert _api.verdict(np.array([ei * (1 - 1e-6), ei * (1 + 1e-6)]), np.full(2, mi), drive,
                                    np.full(2, zeta))[0].all()


def test_damped_square_wave_edge_condition():
    """The damped analogue of Theorems 3.3-3.4: sin(u_c - gamma_c) = -+cosh(kappa) sin(delta_c)
    at the edges, with (x_c, u_c) the phase angles at mu_c = mu sqrt(1 + zeta^2)."""
    from kapitza import _exact as X
    from kapitza.parameters import _phase_angles

    sq = kd.SquareWave()
    mu = np.linspace(0.1, 0.8, 15)
    zeta = 0.2
    mu_c = mu * np.sqrt(1 + zeta**2)
    for n in range(3):
        lo, hi = _api.edges(mu, n, sq, np.full(mu.size, zeta))
        for e, sgn in ((lo, 1.0), (hi, -1.0)):
            x, u, D = _phase_angles(e, mu_c)
            s4 = X.s4_of(mu_c)
            gamma = X.gamma_x(x, mu_c, s4)
            delta = X.delta_x(x, s4)
            kappa = 2 * np.sqrt(8) * zeta * mu * e
            lhs = np.sin(u - n * np.pi - gamma)
            rhs = -sgn * np.cosh(kappa) * np.sin(delta)
            np.testing.assert_allclose(lhs, rhs, atol=1e-11)


def test_damping_does_not_only_shrink_the_stable_set():
    """Damping raises the lower (Kapitza) edge of zone 0 (dissipation cannot stabilise a
    potential maximum) but can also move the resonance edge outwards: some points gain
    stability, others lose it."""
    sq = kd.SquareWave()
    mu = np.linspace(0.05, 0.9, 40)
    lo0, hi0 = _api.edges(mu, 0, sq, np.zeros(40))
    lo1, hi1 = _api.edges(mu, 0, sq, np.full(40, 0.3))
    assert np.all(lo1 >= lo0)
    moved = (lo1 > lo0 * (1 + 1e-9)) & (lo1 < hi0)
    assert moved.sum() > 20
    lost = 0.5 * (lo0 + lo1)[moved]
    assert not _api.verdict(lost, mu[moved], sq, np.full(moved.sum(), 0.3))[0].any()
    assert _api.verdict(lost, mu[moved], sq, np.zeros(moved.sum()))[0].all()
    up = (hi1 > hi0) & (lo1 < hi0)
    assert up.any()
    gained = 0.5 * (hi0 + hi1)[up]
    assert _api.verdict(gained, mu[up], sq, np.full(up.sum(), 0.3))[0].all()
    assert not _api.verdict(gained, mu[up], sq, np.zeros(up.sum()))[0].any()


@pytest.mark.parametrize("drive", DRIVES[1:], ids=lambda d: d.name)
def test_grid_is_pixel_exact(drive):
    eps = np.linspace(0.01, 4.0, 400)
    mu = np.linspace(0.02, 0.98, 60)
    out = np.zeros((mu.size, eps.size), bool)
    _api.grid(eps, mu, drive, np.zeros(1), out)
    E, MU = np.meshgrid(eps, mu)
    ref, _ = _api.verdict(E, MU, drive, np.zeros(E.shape))
    assert np.array_equal(out, ref), np.argwhere(out != ref)[:5]


def test_damped_grid_is_pixel_exact():
    sq = kd.SquareWave()
    eps = np.linspace(0.01, 3.0, 300)
    mu = np.linspace(0.02, 0.95, 40)
    out = np.zeros((mu.size, eps.size), bool)
    _api.grid(eps, mu, sq, np.full(mu.size, 0.2), out)
    E, MU = np.meshgrid(eps, mu)
    ref, _ = _api.verdict(E, MU, sq, np.full(E.shape, 0.2))
    assert np.array_equal(out, ref), np.argwhere(out != ref)[:5]


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.name)
def test_damped_edges_against_a_40_digit_product(drive):
    """At a damped edge |tr M_phi / 2| = cosh(kappa) (40+ digits, mpmath product at mu_c), and
    the points 1e-9 inside and outside are stable and unstable by the certified verdict."""
    from mpmath import mp

    zeta = 0.25
    mu = np.array([0.3, 0.55])
    E = [_api.edges(mu, n, drive, np.full(2, zeta)) for n in range(3)]
    for n in range(2):
        lo, hi = E[n]
        joined = np.concatenate([(lo == E[n - 1][1]) if n else np.zeros(2, bool), hi == E[n + 1][0]])
        for e, m in zip(np.concatenate([lo, hi])[~joined], np.concatenate([mu, mu])[~joined]):
            mu_c = m * np.sqrt(1 + zeta**2)
            (t, *_), = _tau_mp(np.array([e]), np.array([mu_c]), drive.levels, drive._durations)
            kappa = 2 * np.sqrt(8) * zeta * m * e
            with mp.workdps(40):
                target = float(mp.cosh(mp.mpf(kappa)))
            assert abs(abs(t) - target) < 1e-9 * max(1.0, target) * (1 + abs(t))
