"""Nonlinear motion, stroboscopic maps, basins and the motion commands for other drives."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import kapitza as K
import kapitza.drives as kd
from kapitza.motion import basin, stroboscopic_map
from kapitza._validate import KapitzaValueError
from cli_util import assert_one_line_error, run

T, A = 0.15, 100.0


def test_two_equal_steps_move_exactly_like_the_square_wave():
    a = K.simulate(0.3, 0.5, T, A, periods=7)
    b = K.simulate(0.3, 0.5, T, A, periods=7, drive=kd.StepDrive([1, -1], [0.5, 0.5]))
    np.testing.assert_allclose(b.theta, a.theta, atol=1e-13)
    s0 = stroboscopic_map(np.linspace(-0.4, 0.4, 9), 0.1, T, A, periods=30)
    s1 = stroboscopic_map(np.linspace(-0.4, 0.4, 9), 0.1, T, A, periods=30, drive=kd.RectangularWave(0.5))
    np.testing.assert_allclose(s1.theta, s0.theta, atol=1e-11)


@pytest.mark.parametrize("drive", [kd.RectangularWave(0.3), kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])],
                         ids=["rect30", "steps4"])
def test_exact_step_flows_agree_with_dop853(drive):
    ex = K.simulate(0.4, -1.0, T, A, periods=4, drive=drive)
    iv = K.simulate(0.4, -1.0, T, A, periods=4, drive=drive, method="dop853", rtol=1e-12, atol=1e-13)
    assert ex.method == "exact" and iv.method == "dop853"
    np.testing.assert_allclose(ex.theta, iv.theta, atol=1e-8)
    # the pivot and the energy use the drive's own motion
    np.testing.assert_allclose(ex.pivot, drive.displacement(ex.t, T, A))


def test_nonlinear_motion_takes_the_drive_and_broadcasts_its_parameters():
    from kapitza.motion import nonlinear_motion, phase_energy, pivot_acceleration, pivot_displacement, pivot_stroke

    d = kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])
    t = np.linspace(0.0, 6 * T, 37)
    Ts = np.array([0.1, 0.15, 0.2])
    # one parameter set per column: each the same as its own simulation (the same exact step flows)
    th, om = nonlinear_motion(t[:, None], 0.3, -0.2, Ts[None, :], A, drive=d)
    for j, Tj in enumerate(Ts):
        tr = K.simulate(0.3, -0.2, Tj, A, t=t, drive=d)
        np.testing.assert_allclose(th[:, j], tr.theta, rtol=1e-12, atol=1e-13)
        # and against DOP853 on the same drive, an independent integration
        iv = nonlinear_motion(t, 0.3, -0.2, Tj, A, drive=d, method="dop853", rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(th[:, j], iv[0], atol=1e-8)
    # the square wave by name and by default are the same motion
    np.testing.assert_array_equal(nonlinear_motion(t, 0.3, 0.0, T, A)[0],
                                  nonlinear_motion(t, 0.3, 0.0, T, A, drive="square")[0])
    # the energy of the current step is conserved within each step of this drive
    tr = K.simulate(0.3, -0.2, T, A, periods=2, points_per_period=400, drive=d)
    E = phase_energy(tr.t, tr.theta, tr.dtheta, T, A, drive=d)
    first = tr.t < 0.4 * T * 0.999
    assert np.ptp(E[first]) < 1e-9 * abs(E[0])
    # the pivot functions are the drive's
    np.testing.assert_array_equal(pivot_acceleration(t, T, A, drive=d), d.acceleration(t, T, A))
    np.testing.assert_array_equal(pivot_displacement(t, T, A, drive=d), d.displacement(t, T, A))
    assert pivot_stroke(T, A, drive=d) == pytest.approx(float(d.stroke(T, A)), rel=1e-15)
    with pytest.raises(KapitzaValueError, match="piecewise-constant"):
        nonlinear_motion(t, 0.3, 0.0, T, A, drive="sine", method="exact")


def test_sine_motion_against_a_direct_integration():
    tr = K.simulate(0.2, 0.0, T, A, periods=3, drive="sine", rtol=1e-11)
    assert tr.method == "dop853"
    sol = solve_ivp(lambda t, y: [y[1], (9.81 + A * np.sin(np.pi * t / T)) * np.sin(y[0])], (0, tr.t[-1]),
                    [0.2, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=tr.t, max_step=T / 20)
    np.testing.assert_allclose(tr.theta, sol.y[0], atol=1e-7)
    with pytest.raises(KapitzaValueError, match="piecewise-constant"):
        K.simulate(0.2, 0.0, T, A, drive="sine", method="exact")


def test_damped_linear_motion_of_a_drive_decays_like_its_multipliers():
    d = kd.RectangularWave(0.4)
    tr = K.simulate(0.1, 0.0, T, A, periods=40, points_per_period=4, drive=d, damping=1.0, model="linear")
    rep = K.analyze(T=T, A=A, drive=d, damping=1.0)
    assert rep.stable and rep.growth < 0
    # the states at t = 2kT are the powers of the damped monodromy applied to the start
    M = K.monodromy(T, A, drive=d, damping=1.0)
    x = np.array([0.1, 0.0])
    for k in range(1, 41):
        x = M @ x
        assert tr.theta[4 * k] == pytest.approx(x[0], abs=1e-9)
    assert np.abs(np.linalg.eigvals(M)).max() == pytest.approx(np.exp(rep.growth), rel=1e-12)


def test_basins_of_step_drives_and_of_the_sine():
    b = basin(T, A, drive=kd.RectangularWave(0.4), n_theta=21, n_dtheta=21, periods=10)
    assert 0 < b.fraction < 1
    # the sine (DOP853): a start survives exactly when its sampled motion stays in the window
    s = basin(T, A, drive="sine", n_theta=9, n_dtheta=9, periods=6)
    assert 0 < s.fraction < 1
    for i in (0, 4, 8):
        for j in (2, 4, 6):
            tr = K.simulate(s.theta0[j], s.dtheta0[i], T, A, periods=6, points_per_period=64, drive="sine",
                            rtol=1e-10)
            inside = np.all(np.abs(tr.theta) <= s.tol)
            assert inside == (s.periods_survived[i, j] == 6)


def test_motion_commands_take_a_drive(tmp_path, capsys):
    code, out, err = run(["simulate", "--T", "0.15", "--A", "100", "--drive", "sine", "--periods", "2", "--json"], capsys)
    assert code == 0, err
    assert '"dop853"' in out
    code, out, err = run(["simulate", "--T", "0.15", "--A", "100", "--duty", "0.4", "--periods", "2"], capsys)
    assert code == 0 and "rectangular wave, duty 0.4" in out
    code, out, err = run(["basin", "--T", "0.15", "--A", "100", "--drive", "sine", "--quiet", "--resolution", "11",
                          "--periods", "5", "--out", str(tmp_path / "b")], capsys)
    assert code == 0, err
    assert (tmp_path / "b.png").stat().st_size > 0
    code, _, err = run(["simulate", "--T", "0.15", "--A", "100", "--drive", "square:2"], capsys)
    assert_one_line_error(code, err, "no parameters")
