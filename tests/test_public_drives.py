"""Every public function takes a drive and damping; the defaults are today's answers."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import kapitza as K
import kapitza.drives as kd
from kapitza._validate import KapitzaValueError

HALF = kd.RectangularWave(0.5)
RNG = np.random.default_rng(11)
EPS = RNG.uniform(0.02, 4.0, 4000)
MU = RNG.uniform(0.02, 0.98, 4000)


def test_fifty_percent_duty_is_the_square_wave_everywhere():
    np.testing.assert_array_equal(K.is_stable(EPS, MU, drive=HALF), K.is_stable(EPS, MU))
    np.testing.assert_array_equal(K.zone_index(EPS, MU, drive=HALF), K.zone_index(EPS, MU))
    np.testing.assert_allclose(K.growth_rate(EPS, MU, drive=HALF), K.growth_rate(EPS, MU), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(K.rotation_number(EPS, MU, drive=HALF), K.rotation_number(EPS, MU), atol=1e-9)
    lo, hi = K.zone_edges(np.linspace(0.1, 0.95, 50), 2, drive=HALF)
    lo0, hi0 = K.zone_edges(np.linspace(0.1, 0.95, 50), 2)
    np.testing.assert_allclose(lo, lo0, rtol=1e-13)
    np.testing.assert_allclose(hi, hi0, rtol=1e-13)
    g = K.stability_grid(np.linspace(0.01, 4, 300), np.linspace(0.02, 0.98, 80), drive=HALF)
    np.testing.assert_array_equal(g, K.stability_grid(np.linspace(0.01, 4, 300), np.linspace(0.02, 0.98, 80)))


def test_zero_damping_returns_todays_values_exactly():
    a, b = K.floquet(EPS, MU), K.floquet(EPS, MU, zeta=0.0)
    for name in ("trace", "growth", "rotation_number", "stable", "zone"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    r0, r1 = K.analyze(T=0.15, A=100.0), K.analyze(T=0.15, A=100.0, damping=0.0)
    assert r0 == r1


@pytest.mark.parametrize("drive", [None, kd.RectangularWave(0.3), kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])],
                         ids=["square", "rect30", "steps4"])
def test_damped_monodromy_determinant_and_motion_against_solve_ivp(drive):
    T, A, l, g, c = 0.15, 100.0, 0.8, 9.81, 0.9
    d = kd.as_drive(drive)
    M = K.monodromy(T, A, l, g, drive=drive, damping=c)
    assert np.linalg.det(M) == pytest.approx(np.exp(-2 * c * T), rel=1e-12)
    t = np.array([0.0, 0.07, 0.3, 1.234, 2.5])
    th, dth = K.linear_motion(t, 0.05, -0.2, T, A, l, g, drive=drive, damping=c)

    def rhs(tt, y):
        return [y[1], (g + A * d._shape(np.mod(tt / T, 2.0))) / l * y[0] - c * y[1]]

    # restart at every switch so that the integrator never steps across a jump of a(t)
    switches = np.cumsum([0.0] + [2 * f * T for f in d.fractions] * 10)
    y, ref = np.array([0.05, -0.2]), []
    for tk in t:
        ts = 0.0 if not ref else t[len(ref) - 1]
        for a0, b0 in zip(switches[:-1], switches[1:]):
            lo_, hi_ = max(a0, ts), min(b0, tk)
            if hi_ > lo_:
                y = solve_ivp(rhs, (lo_, hi_), y, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
        ref.append(y.copy())
    ref = np.array(ref)
    np.testing.assert_allclose(th, ref[:, 0], atol=1e-9)
    np.testing.assert_allclose(dth, ref[:, 1], atol=1e-8)
    # the multipliers of the report are the eigenvalues of the monodromy
    rep = K.analyze(T=T, A=A, l=l, g=g, drive=drive, damping=c)
    np.testing.assert_allclose(sorted(np.abs(rep.multipliers)), sorted(np.abs(np.linalg.eigvals(M))), rtol=1e-9)
    assert rep.stable == bool(np.abs(np.linalg.eigvals(M)).max() < 1)
    assert rep.determinant == pytest.approx(np.exp(-2 * c * T), rel=1e-14)


def test_period_and_amplitude_edges_of_a_damped_drive_are_zone_edges():
    d = kd.RectangularWave(0.3)
    A, T, l, g, c = 150.0, 0.2, 1.0, 9.81, 0.4
    Tlo, Thi = K.period_edges(A, 0, l, g, drive=d, damping=c)
    for Te, inside in ((Tlo, Tlo * (1 + 1e-9)), (Thi, Thi * (1 - 1e-9))):
        assert K.analyze(T=inside, A=A, l=l, g=g, drive=d, damping=c).stable
        assert not K.analyze(T=Te * (1 - 1e-9) if Te is Tlo else Te * (1 + 1e-9), A=A, l=l, g=g, drive=d,
                             damping=c).stable
    Alo, Ahi = K.amplitude_edges(T, 0, l, g, drive=d, damping=c)
    assert K.analyze(T=T, A=Alo * (1 + 1e-9), l=l, g=g, drive=d, damping=c).stable
    assert not K.analyze(T=T, A=Alo * (1 - 1e-9), l=l, g=g, drive=d, damping=c).stable
    assert K.analyze(T=T, A=Ahi * (1 - 1e-9), l=l, g=g, drive=d, damping=c).stable
    assert not K.analyze(T=T, A=Ahi * (1 + 1e-9), l=l, g=g, drive=d, damping=c).stable


@pytest.mark.parametrize("call, match", [
    (lambda: K.is_stable(0.5, 0.3, zeta=-0.1), "zeta"),
    (lambda: K.is_stable(0.5, 0.3, zeta=float("nan")), "zeta"),
    (lambda: K.is_stable(0.5, 0.3, drive="sawtooth"), "drive"),
    (lambda: K.analyze(T=0.1, A=100, damping=-1), "damping"),
    (lambda: K.analyze(eps=0.5, mu=0.3, damping=1.0), "zeta"),
    (lambda: K.analyze(T=0.1, A=100, zeta=0.1, damping=0.2), "damping"),
    (lambda: K.period_edges(100.0, 0, zeta=0.1, damping=0.2), "not both"),
    (lambda: K.amplitude_edges(0.15, 0, zeta=-0.1), "zeta"),
    (lambda: K.monodromy(0.1, 100, damping=-0.5), "damping"),
    (lambda: K.stability_grid([0.5, 1.0], [0.3], zeta=[0.1, 0.2]), "zeta"),
])
def test_bad_drive_or_damping_names_the_parameter(call, match):
    with pytest.raises(KapitzaValueError, match=match):
        call()


@pytest.mark.parametrize("drive", [K.SquareWave(), K.RectangularWave(0.3)], ids=lambda d: d.name)
def test_damping_and_zeta_mean_the_same_in_every_physical_function(drive):
    """``damping=c`` and ``zeta=c / (2 sqrt(g/l))`` are one damping, in every function that takes it."""
    l, g, c = 0.8, 9.81, 0.3
    zeta = c / (2.0 * np.sqrt(g / l))
    for fn, args in ((K.period_edges, (100.0, 0, l, g)), (K.amplitude_edges, (0.15, 0, l, g))):
        a = fn(*args, drive=drive, damping=c)
        b = fn(*args, drive=drive, zeta=zeta)
        assert np.allclose(a, b, rtol=1e-12, atol=0), fn.__name__
    ra = K.analyze(T=0.15, A=100.0, l=l, g=g, drive=drive, damping=c)
    rb = K.analyze(T=0.15, A=100.0, l=l, g=g, drive=drive, zeta=zeta)
    assert ra.zeta == pytest.approx(rb.zeta, rel=1e-14) and ra.damping == pytest.approx(rb.damping, rel=1e-14)
    assert ra.stable == rb.stable and ra.growth == pytest.approx(rb.growth, rel=1e-12)
    # on Arnold's plane the same ratio gives the same verdict as the physical damping
    e, m = K.to_arnold(0.15, 100.0, l, g)
    assert K.growth_rate(e, m, drive, zeta=zeta) == pytest.approx(ra.growth, rel=1e-12)
    assert np.allclose(K.monodromy(0.15, 100.0, l, g, drive, damping=c),
                       K.monodromy(0.15, 100.0, l, g, drive, zeta=zeta), rtol=1e-12, atol=0)
