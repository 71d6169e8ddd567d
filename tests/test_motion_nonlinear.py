"""Motion of the full and the linear equation: the exact path against the engine's linear
solution, against DOP853, energy per phase, damping, the pivot, the stroboscopic map."""
import subprocess
import sys

import numpy as np
import pytest

import kapitza as K
from kapitza import KapitzaValueError
from kapitza.motion import (
    nonlinear_motion,
    phase_energy,
    pivot_acceleration,
    pivot_displacement,
    pivot_stroke,
    pivot_velocity,
    simulate,
    stroboscopic_map,
)

STABLE = dict(T=0.15, A=100.0, l=1.0, g=9.81)      # zone 0
UNSTABLE = dict(T=0.3, A=100.0, l=1.0, g=9.81)     # between T~_1 and T~_2


# ------------------------------------------------------------------ linear model
@pytest.mark.parametrize("p", [STABLE, UNSTABLE, dict(T=0.4, A=5.0, l=0.7, g=9.81)])
def test_linear_simulation_is_the_engines_exact_solution(p):
    tr = simulate(0.03, -0.2, **p, periods=6, model="linear")
    th, om = K.linear_motion(tr.t, 0.03, -0.2, **p)
    np.testing.assert_array_equal(tr.theta, th)
    np.testing.assert_array_equal(tr.dtheta, om)
    assert tr.method == "exact"


def test_linear_dop853_path_matches_the_exact_linear_solution():
    tr = simulate(0.03, -0.2, **STABLE, periods=5, model="linear", method="dop853", rtol=1e-12, atol=1e-14)
    th, om = K.linear_motion(tr.t, 0.03, -0.2, **STABLE)
    assert np.max(np.abs(tr.theta - th)) < 1e-10
    assert np.max(np.abs(tr.dtheta - om)) < 1e-9


@pytest.mark.parametrize("p,periods,a0", [(STABLE, 8, 1e-3), (UNSTABLE, 2, 1e-5)])
def test_small_amplitude_nonlinear_motion_follows_the_linear_one(p, periods, a0):
    """The difference is the cubic term: O(a^3) for amplitude a, so it drops 8-fold when a halves."""
    t = np.linspace(0, 2 * p["T"] * periods, 400)
    diffs = []
    for a in (a0, a0 / 2):
        lin = np.asarray(K.linear_motion(t, a, 0.5 * a, **p)[0])
        non = nonlinear_motion(t, a, 0.5 * a, **p)[0]
        scale = np.max(np.abs(lin))
        diffs.append(np.max(np.abs(non - lin)))
        assert diffs[-1] < 1e-3 * scale  # relative deviation ~ a^2 * growth
    assert diffs[0] / diffs[1] == pytest.approx(8.0, rel=0.02)


def test_tiny_amplitude_nonlinear_equals_linear_to_rounding():
    t = np.linspace(0, 2 * STABLE["T"] * 10, 201)
    lin = np.asarray(K.linear_motion(t, 1e-9, 2e-9, **STABLE)[0])
    non = nonlinear_motion(t, 1e-9, 2e-9, **STABLE)[0]
    assert np.max(np.abs(non - lin)) < 1e-12 * np.max(np.abs(lin))


# ------------------------------------------------------------------ exact vs DOP853
@pytest.mark.parametrize("p", [STABLE, UNSTABLE, dict(T=0.5, A=9.81, l=1.0, g=9.81), dict(T=0.5, A=4.0, l=1.0, g=9.81)])
def test_exact_motion_matches_dop853_over_a_period(p):
    """Includes A = g (free flight in the second phase) and A < g (both phases hyperbolic)."""
    rng = np.random.default_rng(5)
    th0 = rng.uniform(-3, 3, 12)
    om0 = rng.uniform(-8, 8, 12)
    t = np.linspace(0, 2 * p["T"], 9)
    a = nonlinear_motion(t[:, None], th0, om0, **p)
    b = nonlinear_motion(t[:, None], th0, om0, **p, method="dop853", rtol=1e-12, atol=1e-13)
    assert np.max(np.abs(a[0] - b[0])) < 1e-10
    assert np.max(np.abs(a[1] - b[1])) < 1e-9


def test_exact_motion_arbitrary_times_shapes_and_order():
    t = np.array([[1.3, 0.0], [0.15, 0.449999]])  # unsorted, on and near switches
    th, om = nonlinear_motion(t, 0.2, 0.0, **STABLE)
    assert th.shape == (2, 2)
    for i in range(2):
        for j in range(2):
            s, w = nonlinear_motion(t[i, j], 0.2, 0.0, **STABLE)
            assert th[i, j] == s and om[i, j] == w
    assert th[0, 1] == 0.2 and om[0, 1] == 0.0


@pytest.mark.parametrize("p", [STABLE, UNSTABLE, dict(T=0.5, A=9.81, l=1.0, g=9.81), dict(T=0.5, A=4.0, l=1.0, g=9.81)])
def test_one_motion_is_the_same_doubles_as_one_of_many(p):
    """One start takes its steps on one state (a float path), several starts together on arrays:
    the same motion to the last bit, over many periods, falling and turning included."""
    th0 = np.array([0.1, 2.5, -1.0, 3.0])
    om0 = np.array([0.0, 1.0, 12.0, -0.5])
    t = np.linspace(0.0, 30 * 2 * p["T"], 601)
    many = nonlinear_motion(t[:, None], th0, om0, **p)
    for i in range(th0.size):
        one = nonlinear_motion(t, th0[i], om0[i], **p)
        assert np.array_equal(one[0], many[0][:, i]) and np.array_equal(one[1], many[1][:, i])


def test_motion_is_continuous_across_the_switches():
    T = STABLE["T"]
    for k in range(1, 6):
        t = k * T + np.array([-1e-9, 0.0, 1e-9])
        th, om = nonlinear_motion(t, 0.3, 1.0, **STABLE)
        assert np.ptp(th) < 1e-7 and np.ptp(om) < 1e-6


# ------------------------------------------------------------------ energy
def test_energy_is_conserved_within_each_undamped_phase():
    T = STABLE["T"]
    for p in range(6):
        t = (p + np.linspace(1e-6, 1 - 1e-6, 50)) * T
        th, om = nonlinear_motion(t, 1.0, 3.0, **STABLE)
        E = phase_energy(t, th, om, **STABLE)
        assert np.ptp(E) < 1e-12 * np.max(np.abs(E))


def test_energy_decreases_within_each_damped_phase():
    T = STABLE["T"]
    c = 0.8
    tr = simulate(1.0, 3.0, **STABLE, periods=3, points_per_period=400, damping=c, rtol=1e-11, atol=1e-13)
    assert tr.method == "dop853"
    E = tr.energy
    j = np.floor(tr.t / T)
    inner = np.abs(tr.t / T - np.rint(tr.t / T)) > 1e-9  # samples on a switch belong to both sides
    for p in range(6):
        sel = (j == p) & inner
        dE = np.diff(E[sel])
        assert np.all(dE < 0)
        # and at the rate -c theta'^2 (trapezoid rule over the samples)
        rate = -c * tr.dtheta[sel] ** 2
        integral = np.sum(0.5 * (rate[1:] + rate[:-1]) * np.diff(tr.t[sel]))
        assert np.sum(dE) == pytest.approx(integral, rel=1e-4)


def test_undamped_dop853_energy_is_conserved_too():
    tr = simulate(1.0, 3.0, **STABLE, periods=1, method="dop853", rtol=1e-12, atol=1e-13)
    E = tr.energy
    first = tr.t < STABLE["T"]
    assert np.ptp(E[first]) < 1e-9 * np.max(np.abs(E))


# ------------------------------------------------------------------ pivot
def test_pivot_is_periodic_zero_mean_and_integrates_the_square_wave():
    T, A = 0.15, 100.0
    t = np.linspace(0, 2 * T, 200001)
    y = pivot_displacement(t, T, A)
    v = pivot_velocity(t, T, A)
    a = pivot_acceleration(t, T, A)
    assert abs(np.trapezoid(y, t) / (2 * T)) < 1e-9
    assert abs(np.trapezoid(v, t) / (2 * T)) < 1e-9
    assert y[0] == pytest.approx(y[-1], abs=1e-15) and v[0] == pytest.approx(v[-1], abs=1e-12)
    dt = t[1] - t[0]
    assert np.max(np.abs(np.gradient(y, dt)[1:-1] - v[1:-1])) < 1e-4 * A * T
    inner = (np.abs(t - T) > 2 * dt) & (t > 2 * dt) & (t < 2 * T - 2 * dt)
    assert np.max(np.abs(np.gradient(v, dt)[inner] - a[inner])) < 1e-6 * A
    assert np.ptp(y) == pytest.approx(pivot_stroke(T, A), rel=1e-9)
    assert pivot_acceleration(0.0, T, A) == A and pivot_acceleration(T, T, A) == -A
    assert y.min() == pytest.approx(-A * T * T / 8, rel=1e-9)  # at the middle of the hyperbolic phase
    assert t[np.argmin(y)] == pytest.approx(T / 2, abs=2 * dt)


def test_trajectory_pivot_and_strobe():
    tr = simulate(0.1, 0.0, **STABLE, periods=4)
    np.testing.assert_allclose(tr.pivot, pivot_displacement(tr.t, STABLE["T"], STABLE["A"]))
    tk, th, om = tr.strobe()
    assert tk.size == 5
    orb = stroboscopic_map(0.1, 0.0, **STABLE, periods=4, every=1)
    np.testing.assert_allclose(th, orb.theta, rtol=0, atol=1e-14)
    assert tr.periods == pytest.approx(4.0)


# ------------------------------------------------------------------ stroboscopic map
def test_stroboscopic_map_agrees_with_the_motion_and_the_monodromy():
    rng = np.random.default_rng(2)
    th0 = rng.uniform(-0.5, 0.5, 300)
    om0 = rng.uniform(-3, 3, 300)
    orb = stroboscopic_map(th0, om0, **STABLE, periods=7, every=3)
    assert list(orb.n) == [0, 3, 6, 7]
    th, om = nonlinear_motion(2 * STABLE["T"] * 7, th0, om0, **STABLE)
    assert np.max(np.abs(orb.final[0] - th)) < 1e-12
    # linear model: M^k
    lin = stroboscopic_map(th0, om0, **STABLE, periods=4, model="linear")
    M = K.monodromy(**STABLE)
    ref = np.linalg.matrix_power(M, 4) @ np.vstack([th0, om0])
    np.testing.assert_allclose(lin.theta[-1], ref[0], rtol=1e-11, atol=1e-13)


def test_stroboscopic_map_chunks_and_workers_give_identical_results():
    rng = np.random.default_rng(4)
    th0 = rng.uniform(-1, 1, (40, 50))
    om0 = rng.uniform(-5, 5, (40, 50))
    a = stroboscopic_map(th0, om0, **STABLE, periods=5)
    b = stroboscopic_map(th0, om0, **STABLE, periods=5, chunk=333, workers=2)
    assert a.theta.shape == (6, 40, 50)  # every period is kept by default
    np.testing.assert_array_equal(a.theta, b.theta)
    np.testing.assert_array_equal(a.dtheta, b.dtheta)


def test_stroboscopic_map_damped_uses_dop853():
    orb = stroboscopic_map([0.1, 0.2], 0.0, **STABLE, periods=3, damping=0.5)
    ref = simulate(0.2, 0.0, **STABLE, t=2 * STABLE["T"] * np.arange(4), damping=0.5)
    np.testing.assert_allclose(orb.theta[-1, 1], ref.theta[-1], rtol=1e-8)


def test_linear_map_overflow_is_reported_not_nan():
    with pytest.raises(OverflowError, match="range of a double"):
        stroboscopic_map(0.1, 0.0, T=2.0, A=100.0, periods=200, model="linear")


def test_damping_is_given_as_c_or_as_zeta_with_one_meaning():
    l, g = 0.5, 9.81
    z = 0.05
    a = simulate(0.2, 0.0, 0.15, 100.0, l, g, periods=3, zeta=z)
    b = simulate(0.2, 0.0, 0.15, 100.0, l, g, periods=3, damping=2.0 * z * np.sqrt(g) / np.sqrt(l))
    assert a.c == b.c and a.method == "dop853"
    np.testing.assert_array_equal(a.theta, b.theta)
    th, _ = nonlinear_motion(a.t, 0.2, 0.0, 0.15, 100.0, l, g, zeta=z)
    np.testing.assert_allclose(th, a.theta, atol=1e-9)


# ------------------------------------------------------------------ validation and imports
@pytest.mark.parametrize("kwargs,needle", [
    (dict(T=-1.0, A=100.0), "T must be finite and > 0"),
    (dict(T=0.1, A=0.0), "A must be finite and > 0"),
    (dict(T=0.1, A=100.0, damping=-1.0), "damping must be finite and >= 0"),
    (dict(T=0.1, A=100.0, zeta=0.05, method="exact"), "method='exact' solves the undamped"),
    (dict(T=0.1, A=100.0, method="rk4"), "method must be one of"),
    (dict(T=0.1, A=100.0, method="dop853", rtol=1e-16), "rtol must lie in"),
])
def test_nonlinear_motion_validates(kwargs, needle):
    with pytest.raises(KapitzaValueError, match=needle):
        nonlinear_motion(0.1, 0.1, 0.0, **kwargs)


def test_simulate_and_map_validate():
    with pytest.raises(KapitzaValueError, match="model must be one of"):
        simulate(0.1, 0.0, **STABLE, model="averaged")
    with pytest.raises(KapitzaValueError, match="t must be >= 0"):
        nonlinear_motion(-1.0, 0.1, 0.0, **STABLE)
    with pytest.raises(KapitzaValueError, match="periods must be an integer >= 0"):
        stroboscopic_map(0.1, 0.0, **STABLE, periods=-2)
    with pytest.raises(KapitzaValueError, match="theta0 must be finite"):
        stroboscopic_map(np.nan, 0.0, **STABLE)
    with pytest.raises(KapitzaValueError, match="single parameter set"):
        nonlinear_motion(0.1, 0.1, 0.0, T=[0.1, 0.2], A=100.0, method="dop853")


def test_import_kapitza_motion_stays_free_of_matplotlib():
    code = "import sys, kapitza, kapitza.motion; assert 'matplotlib' not in sys.modules, 'matplotlib imported'"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
