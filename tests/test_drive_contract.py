"""The public drive contract: a user's drive that gives only its shape gets every question."""
import numpy as np
import pytest

import kapitza
from kapitza import Drive

from drive_ivp import edge, half_trace

C = 1.0 / 1.25  # max of |sin(pi t) + 0.5 sin(2 pi t)| is about 1.25: any scale will do


def shape(tau):
    tau = np.asarray(tau, float)
    return C * (np.sin(np.pi * tau) + 0.5 * np.sin(2 * np.pi * tau))


class TwoTone(Drive):
    """Only what the contract asks for: the shape and a name."""

    name = "two-tone"

    def _shape(self, tau):
        return shape(tau)


D = TwoTone()


@pytest.mark.parametrize("eps, mu", [(0.4, 0.2), (1.1, 0.4), (2.5, 0.3), (4.0, 0.7)])
def test_floquet_against_dop853(eps, mu):
    ref = half_trace(shape, eps, mu)
    f = kapitza.floquet(eps, mu, drive=D)
    assert abs(0.5 * f.trace - ref) <= 1e-9 * max(1.0, abs(ref))
    assert bool(kapitza.is_stable(eps, mu, drive=D)) == (abs(ref) < 1)


@pytest.mark.parametrize("mu, n", [(0.3, 0), (0.3, 1), (0.6, 2)])
def test_edges_and_zone_index(mu, n):
    lo, hi = map(float, kapitza.zone_edges(mu, n, drive=D))
    s = (-1.0) ** n
    assert lo == pytest.approx(edge(shape, mu, lo * (1 - 1e-6), lo * (1 + 1e-6), s), rel=1e-10)
    assert hi == pytest.approx(edge(shape, mu, hi * (1 - 1e-6), hi * (1 + 1e-6), -s), rel=1e-10)
    mid = 0.5 * (lo + hi)
    assert int(kapitza.zone_index(mid, mu, drive=D)) == n
    f = kapitza.floquet(mid, mu, drive=D)
    # the rotation number lies in (n/2, (n+1)/2) turns on zone n
    assert n / 2 < float(f.rotation_number) < (n + 1) / 2


def test_defaults_of_the_kinematics():
    tau = np.linspace(0, 2, 100001)
    V = D._velocity_shape(tau)
    Z = D._displacement_shape(tau)
    Vx = -C * (np.cos(np.pi * tau) / np.pi + 0.5 * np.cos(2 * np.pi * tau) / (2 * np.pi))
    Zx = -C * (np.sin(np.pi * tau) / np.pi**2 + 0.5 * np.sin(2 * np.pi * tau) / (2 * np.pi) ** 2)
    assert np.max(np.abs(V - Vx)) < 1e-14
    assert np.max(np.abs(Z - Zx)) < 1e-14
    assert D._mean_square_velocity == pytest.approx(C * C * (1 / np.pi**2 + 0.25 / (2 * np.pi) ** 2) / 2, rel=1e-13)
    assert D._stroke_coefficient == pytest.approx(Zx.max() - Zx.min(), rel=1e-9)
    assert D.mu_max == pytest.approx(np.sqrt(-shape(tau).min()), rel=1e-9)


def test_analyze_and_rig():
    r = kapitza.analyze(T=0.15, A=120, drive=D)
    eps, mu = kapitza.to_arnold(0.15, 120)
    assert r.stable == bool(kapitza.is_stable(eps, mu, drive=D))
    rig = kapitza.Rig(kapitza.Pendulum(), D)
    assert rig.analyze(T=0.15, A=120).stable == r.stable
    # damped: the verdict and the report agree
    rd = kapitza.analyze(T=0.15, A=120, drive=D, damping=0.2)
    assert rd.stable == bool(kapitza.is_stable(eps, mu, drive=D, zeta=0.1 * np.sqrt(1 / 9.81)))


def test_scalars_for_scalar_input():
    assert isinstance(kapitza.is_stable(0.5, 0.3, drive=D), np.bool_)
    assert isinstance(kapitza.zone_index(0.5, 0.3, drive=D), np.integer)
    out = kapitza.is_stable(np.array([0.5, 0.9]), 0.3, drive=D)
    assert out.shape == (2,)
    measured = kapitza.drives.from_samples([0, 1, 2, 3], [1, -1, 0.5, -0.5])
    for d in (D, kapitza.TriangleWave(), measured):
        for f in (d.acceleration, d.velocity, d.displacement):
            assert isinstance(f(0.1, 0.15, 100.0), np.float64)
            assert f(np.array([0.1, 0.2]), 0.15, 100.0).shape == (2,)
        assert isinstance(d.stroke(0.15, 100.0), np.float64)


def test_a_shape_without_zero_mean_is_refused():
    class Biased(Drive):
        name = "biased"

        def _shape(self, tau):
            return np.sin(np.pi * tau) + 0.1

    with pytest.raises(ValueError, match="zero mean"):
        Biased()._velocity_shape(np.array([0.1]))


def test_a_drive_without_shape_says_so():
    class Empty(Drive):
        name = "empty"

    with pytest.raises(NotImplementedError, match="_shape"):
        kapitza.is_stable(0.5, 0.3, drive=Empty())


def test_compiled_and_numpy_engines_are_twins():
    # one definition of the step, two products (a compiled loop and a numpy tree): they agree
    from kapitza.engines import load_compiled
    from kapitza.engines.magnus import Engine

    if not load_compiled():
        pytest.skip("numba is not installed (the fast extra)")
    rng = np.random.default_rng(3)
    eps = np.concatenate([rng.uniform(0.05, 8.0, 200), [1e-4, 40.0]])
    mu = np.concatenate([rng.uniform(0.0, 1.0, 200), [0.3, 0.2]])
    for drive in (D, kapitza.TriangleWave(),
                  kapitza.drives.from_samples(np.arange(50), np.sin(np.arange(50) * 0.3) ** 3, kind="constant")):
        eng = drive._engine
        try:
            Engine.compiled = True
            fast = eng.floquet(eps, mu, growth=True)
            fast_period = eng.period(eps, mu)
            Engine.compiled = False
            slow = eng.floquet(eps, mu, growth=True)
            slow_period = eng.period(eps, mu)
        finally:
            Engine.compiled = True
        tau_f, lt_f, th_f, z_f, g_f = fast
        tau_s, lt_s, th_s, z_s, g_s = slow
        assert np.allclose(lt_f, lt_s, rtol=1e-11, atol=1e-11)
        assert np.allclose(tau_f, tau_s, rtol=1e-10, atol=1e-12)
        # (near tau = 1 the growth sqrt(2 (tau - 1)) inherits the rounding of tau - 1: left out)
        far = np.abs(np.abs(tau_s) - 1.0) > 1e-6
        assert np.allclose(g_f[far], g_s[far], rtol=1e-9, atol=1e-12)
        # the zone index and the whole turns agree exactly away from the edges
        clear = np.abs(np.abs(tau_s) - 1.0) > 1e-8
        assert (z_f[clear] == z_s[clear]).all()
        assert np.allclose(th_f[clear], th_s[clear], rtol=1e-9, atol=1e-9)
        assert np.allclose(fast_period[2], slow_period[2], rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("text", ["square", "sine", "triangle", "rectangular:0.3", "rectangular:0.7",
                                  "steps:2,-1,1,-1:0.2,0.3,0.2,0.3", "steps:1.5,-0.5:0.25,0.75"])
def test_a_drives_text_reads_back_as_the_same_drive(text):
    d = kapitza.parse_drive(text)
    again = kapitza.parse_drive(d.text())
    assert again == d and again.describe() == d.describe()


def test_peak_is_the_largest_acceleration_of_the_shape():
    tau = np.linspace(0.0, 2.0, 200_001)
    assert D.peak == pytest.approx(np.max(np.abs(shape(tau))), rel=1e-9)
    assert kapitza.StepDrive([3.0, -1.0], [0.25, 0.75]).peak == 3.0
    assert kapitza.SineWave().peak == 1.0 and kapitza.SquareWave().peak == 1.0


def test_a_drive_without_text_form_says_so_where_one_is_needed():
    from kapitza.sweeps.spec import SweepSpec

    t = np.linspace(0.0, 1.0, 64, endpoint=False)
    measured = kapitza.from_samples(t, np.sin(2 * np.pi * t))
    with pytest.raises(ValueError, match="no text form"):
        SweepSpec(plane="arnold", x=[1.0, 2.0], y=[0.2, 0.3], drive=measured)
    # a drive with a text form is kept by it, the triangle wave too
    assert SweepSpec(plane="arnold", x=[1.0, 2.0], y=[0.2, 0.3], drive=kapitza.TriangleWave()).drive == "triangle"


def test_a_step_drive_beyond_its_limit_points_to_measured_drives():
    with pytest.raises(ValueError, match=r"at most 64 steps; got 65 .*from_samples"):
        kapitza.StepDrive(np.tile([1.0, -1.0], 33)[:65] - np.mean(np.tile([1.0, -1.0], 33)[:65]), np.full(65, 1 / 65))


def test_the_engine_loads_numba_only_after_its_budget_of_numpy_work(monkeypatch):
    # a command of one report runs the numpy tree; the compiled loop is loaded once the process has
    # asked Engine.COMPILED_FROM point-steps (each call counted as at least CALL_WORK)
    from kapitza.engines import magnus

    loads = []
    monkeypatch.setattr(magnus, "_COMPILED", None)
    monkeypatch.setattr(magnus, "_TREE_WORK", 0)
    monkeypatch.setattr(magnus.Engine, "COMPILED_FROM", 3 * magnus.Engine.CALL_WORK)
    monkeypatch.setattr(magnus, "load_compiled", lambda: loads.append(1))
    eng = kapitza.TriangleWave()._engine
    eps, mu = np.array([0.5]), np.array([0.3])
    for _ in range(2):   # two one-point calls: below the budget, the numpy tree, nothing loaded
        eng.floquet(eps, mu)
    assert loads == [] and magnus._TREE_WORK == 2 * magnus.Engine.CALL_WORK
    eng.floquet(eps, mu)
    assert loads == [1]
