"""The averaging (Kapitza) criterion of each drive is the mu -> 0 limit of its exact edge;
rigs described as measured; drives parsed from text."""
import numpy as np
import pytest

import kapitza.drives as kd
from kapitza._validate import KapitzaValueError
from kapitza.limits import averaging_threshold, threshold_table
from kapitza import Pendulum, Rig


def test_square_wave_error_is_four_sevenths_mu_to_the_fourth():
    rows = threshold_table([0.02, 0.04], [kd.SquareWave()])
    for r in rows:
        assert r.relative_error == pytest.approx(-(4 / 7) * r.mu**4, rel=2e-2)


@pytest.mark.parametrize("drive", [kd.RectangularWave(0.3), kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])],
                         ids=["rect30", "steps4"])
def test_asymmetric_drives_converge_like_mu_squared(drive):
    rows = threshold_table([0.05, 0.1, 0.2], [drive])
    err = np.array([r.relative_error for r in rows])
    mu = np.array([r.mu for r in rows])
    c = err / mu**2
    assert np.all(err < 0)
    # the coefficient of mu^2 settles: ratio between neighbouring mu close to 1
    assert c[0] / c[1] == pytest.approx(1.0, abs=0.05)


def test_averaging_threshold_matches_the_drive_shape():
    assert float(averaging_threshold(0.2)) == pytest.approx(np.sqrt(1.5) * 0.2)
    assert float(averaging_threshold(0.2, kd.SineWave())) == pytest.approx(np.pi * 0.1)
    with pytest.raises(KapitzaValueError, match="mu"):
        threshold_table([1.5], [kd.SquareWave()])


def test_uniform_rod_equivalent_length():
    rod = Pendulum.uniform_rod(0.3)
    assert rod.l == pytest.approx(0.2)
    assert "equivalent length l = 0.2 m" in rod.describe()
    c = Pendulum.compound(inertia=0.5 * 0.3**2 / 3, mass=0.5, distance=0.15)  # rod: I = m L^2 / 3
    assert c.l == pytest.approx(0.2)
    assert Pendulum(l=1.0, g=9.81, damping=2 * np.sqrt(9.81)).zeta == pytest.approx(1.0)
    with pytest.raises(KapitzaValueError, match="inertia"):
        Pendulum.compound(inertia=0.001, mass=1.0, distance=0.5)
    with pytest.raises(KapitzaValueError, match="damping"):
        Pendulum(damping=-1.0)
    with pytest.raises(KapitzaValueError, match="length"):
        Pendulum.uniform_rod(0.0)


def test_rig_takes_frequency_and_stroke():
    rig = Rig(Pendulum.uniform_rod(0.2), kd.SineWave())
    T, A = rig.physical(frequency=40.0, amplitude=0.01)
    assert T == pytest.approx(1 / 80)
    assert A == pytest.approx(0.01 * (80 * np.pi) ** 2)
    with pytest.raises(KapitzaValueError):
        rig.physical(T=0.1)
    with pytest.raises(KapitzaValueError):
        rig.physical(T=0.1, frequency=3.0, stroke=0.01)


@pytest.mark.parametrize("text, expected", [
    ("square", kd.SquareWave()),
    ("sine", kd.SineWave()),
    ("rectangular:0.3", kd.RectangularWave(0.3)),
    (" Steps:2,-1,1,-1:0.2,0.3,0.2,0.3 ", kd.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])),
])
def test_parse_drive(text, expected):
    assert kd.parse_drive(text) == expected


@pytest.mark.parametrize("text, match", [
    ("", "drive"), ("sawtooth", "drive must be one of"), ("square:3", "no parameters"),
    ("rectangular", "duty"), ("rectangular:x", "duty must be a number"), ("rectangular:1.5", "duty"),
    ("steps:1,-1", "levels and fractions"), ("steps:1,1:0.5,0.5", "zero mean"),
])
def test_parse_drive_errors(text, match):
    with pytest.raises(KapitzaValueError, match=match):
        kd.parse_drive(text)


def test_compare_command_writes_chart_edges_and_thresholds(tmp_path, capsys):
    import csv
    from cli_util import run

    out = tmp_path / "cmp"
    code, text, err = run(["compare", "--drive", "square", "--drive", "rectangular:0.3", "--zeta", "0.2",
                           "--points", "60", "--mu", "0.05,0.1", "--out", str(out)], capsys)
    assert code == 0, err
    for suffix in (".png", ".svg", ".csv"):
        assert (tmp_path / ("cmp" + suffix)).stat().st_size > 0
    rows = list(csv.DictReader(line for line in open(tmp_path / "cmp.csv") if not line.startswith("#")))
    kinds = {(r["drive"], float(r["zeta"])) for r in rows}
    assert kinds == {("square wave", 0.0), ("square wave", 0.2), ("rectangular, duty 30 %", 0.0),
                     ("rectangular, duty 30 %", 0.2)}
    # the square wave's undamped edges in the file are kapitza.zone_edges'
    from kapitza import zone_edges

    sq = [r for r in rows if r["drive"] == "square wave" and float(r["zeta"]) == 0.0 and r["zone"] == "0"]
    lo, hi = zone_edges(np.array([float(r["mu"]) for r in sq]), 0)
    np.testing.assert_allclose([float(r["eps_lo"]) for r in sq], lo, rtol=1e-14)
    thr = list(csv.DictReader(open(tmp_path / "cmp-thresholds.csv")))
    assert len(thr) == 4 and "square wave" in text


@pytest.mark.parametrize("argv, needle", [
    (["compare", "--drive", "rectangular:2"], "duty"),
    (["compare", "--zeta", "-1"], "--zeta"),
    (["compare", "--points", "1"], "--points"),
    (["compare", "--mu", "0.1,x"], "--mu"),
    (["compare", "--mu", "1.5"], "mu"),
])
def test_compare_bad_input_is_one_line(argv, needle, capsys):
    from cli_util import assert_one_line_error, run

    code, _, err = run(argv + ["--out", "/nonexistent-dir/x"], capsys)
    assert_one_line_error(code, err, needle)
