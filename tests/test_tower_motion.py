"""The tower's full motion: energy, the linear limit, one link as the single pendulum, safe tilt, animation."""
import math

import numpy as np
import pytest

import kapitza
from kapitza import Chain
from kapitza.motion.chain import chain_motion, tower_safe_tilt
from cli_util import run

G = 9.81


@pytest.mark.parametrize("links", ["rod", "point"])
@pytest.mark.parametrize("n", [2, 3])
def test_energy_is_conserved_without_drive_or_friction(links, n):
    ch = Chain([0.3, 0.2, 0.25][:n], [1.0, 0.6, 0.4][:n], links=links)
    # large swings through the hanging position and back: a real test of the coupling terms
    m = chain_motion(ch, [2.0, -1.0, 2.5][:n], [0.0, 3.0, -2.0][:n], T=0.05, A=0.0, periods=100, tol=math.pi,
                     stop=False)
    E = m.energy
    assert np.ptp(E) < 1e-8 * np.max(np.abs(E))
    assert np.max(np.abs(m.theta)) > 1.0


def test_energy_within_each_drive_segment():
    """With a piecewise-constant drive the acceleration is constant on each half period, and so is
    E = T_kin + (g + a) sum K_i cos(theta_i) there."""
    ch = Chain([0.2, 0.2])
    r = ch.analyze(frequency=60, stroke=0.02)
    m = chain_motion(ch, 0.3, 0.0, T=r.T, A=r.A, periods=10, points_per_period=40)
    seg = np.concatenate([[0], np.cumsum(np.diff(m.acceleration) != 0)])  # runs of one acceleration
    assert seg[-1] >= 18
    for k in np.unique(seg):
        e = m.energy[seg == k]
        assert np.ptp(e) < 1e-8 * np.max(np.abs(e)), k


def test_friction_only_takes_energy_away():
    ch = Chain([0.3, 0.2], joint_damping=0.05)
    m = chain_motion(ch, [1.0, -0.5], 0.0, T=0.05, A=0.0, periods=40, tol=math.pi, stop=False, points_per_period=20)
    assert np.all(np.diff(m.energy) <= 1e-10 * np.abs(m.energy[0]))
    assert m.energy[-1] < m.energy[0] - 0.1 * abs(m.energy[0] - m.energy.min())


@pytest.mark.parametrize("drive", [None, "sine"])
@pytest.mark.parametrize("c", [0.0, 0.004])
def test_small_motions_follow_the_monodromy(drive, c):
    ch = Chain([0.2, 0.15, 0.1], [1.0, 0.5, 0.3], links="point", joint_damping=c)
    r = ch.analyze(frequency=80, stroke=0.01, drive=drive)
    x0 = 1e-7 * np.array([1.0, -2.0, 0.5, 3.0 / r.T, 0.0, 1.0 / r.T])
    m = chain_motion(ch, x0[:3], x0[3:], T=r.T, A=r.A, drive=drive, periods=1, points_per_period=4, rtol=1e-12,
                     atol=1e-20)
    fl = kapitza.chain_floquet(ch, T=r.T, A=r.A, drive=drive)
    want = fl.monodromy @ x0 * math.exp(fl.log_scale)
    got = np.concatenate([m.theta[:, -1], m.dtheta[:, -1]])
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-6 * np.abs(want).max())


def test_one_link_is_the_single_pendulum_motion():
    L = 0.3
    ch = Chain([L])
    T, A = 0.01, 800.0
    m = chain_motion(ch, 0.4, 0.5, T=T, A=A, periods=20, points_per_period=10, rtol=1e-12, atol=1e-14, tol=math.pi,
                     stop=False)
    s = kapitza.simulate(0.4, 0.5, T=T, A=A, l=2 * L / 3, periods=20, points_per_period=10)
    np.testing.assert_allclose(m.theta[0], s.theta, atol=1e-8)


def test_safe_tilt_inside_and_outside_the_band():
    ch = Chain([0.2, 0.2])
    r = ch.analyze(frequency=60, stroke=0.02)
    tilt = tower_safe_tilt(ch, T=r.T, A=r.A, periods=20, accuracy=0.01)
    assert 0.05 < tilt.together < math.pi / 2 and 0.05 < tilt.mode < math.pi / 2
    # the value survives, a tilt clearly beyond it does not
    assert not chain_motion(ch, tilt.together, T=r.T, A=r.A, periods=20).toppled
    assert chain_motion(ch, tilt.together + 0.02, T=r.T, A=r.A, periods=20).toppled
    out = ch.analyze(frequency=20, stroke=0.02)
    assert not out.stable
    zero = tower_safe_tilt(ch, T=out.T, A=out.A, periods=20, accuracy=0.01)
    assert zero.together < 0.01 and zero.mode < 0.01
    assert "safe tilt" in str(tilt)


def test_animation_is_written(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from PIL import Image

    from kapitza.figures.tower import animate_tower

    ch = Chain([0.2, 0.2])
    a, b = ch.analyze(frequency=60, stroke=0.02), ch.analyze(frequency=20, stroke=0.02)
    ma = chain_motion(ch, 0.15, T=a.T, A=a.A, periods=12, points_per_period=20)
    mb = chain_motion(ch, 0.15, T=b.T, A=b.A, periods=12, points_per_period=20)
    assert not ma.toppled and mb.toppled
    p = animate_tower([ma, mb], tmp_path / "t.gif", titles=["stands", "falls"], fps=10, slowdown=1.0, duration=0.5)
    with Image.open(p) as im:
        assert im.n_frames == 6


def test_cli_motion_files(tmp_path, capsys):
    code, out, err = run(["tower", "--chain", "0.2,0.2", "--frequency", "60", "--stroke", "0.02", "--no-chart",
                          "--duration", "0.3", "--simulate", str(tmp_path / "m"), "--animate", str(tmp_path / "m.gif")],
                         capsys)
    assert code == 0, err
    assert "stands" in out
    lines = [x for x in (tmp_path / "m.csv").read_text().splitlines() if not x.startswith("#")]
    assert lines[0] == "t,pivot,theta1,theta2,dtheta1,dtheta2" and len(lines) > 20
    assert (tmp_path / "m.gif").stat().st_size > 0
    code, _, err = run(["tower", "--animate", str(tmp_path / "x.gif"), "--no-chart"], capsys)
    assert code == 2 and "point" in err
