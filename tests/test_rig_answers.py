"""Answers for a rig: the safe tilt, the margin as directions, rig units on every command, the
frequency-stroke plane. The engineer's case: a sine shaker at 50 Hz with 3 mm amplitude under a
uniform 25 cm rod falls; Kapitza's threshold is 95.94 Hz, the amplitude that holds it 5.76 mm."""
import json

import numpy as np
import pytest

import kapitza as K
from cli_util import assert_one_line_error, run
from kapitza.advice import directions
from kapitza.rig_plane import rig_zone_curves
from kapitza.safety import safe_tilt

ROD = 0.25
L = 2 * ROD / 3


def _engineer(**kw):
    d = K.SineWave()
    T, A = d.from_rig(50.0, amplitude=0.003)
    return K.analyze(T=float(T), A=float(A), l=L, drive=d, **kw)


# ------------------------------------------------------------------ directions
def test_engineers_case_directions():
    from dataclasses import replace

    rep = replace(_engineer(), given="amplitude")
    assert not rep.stable
    f, a = rep.directions
    assert f["knob"] == "frequency" and f["action"] == "raise" and f["hi"] is None
    assert f["lo"] == pytest.approx(95.94, abs=0.01)
    assert f["text"].startswith("raise the frequency to at least 95.9 Hz (+91.9 %)")
    assert a["knob"] == "amplitude" and a["action"] == "increase" and a["unit"] == "mm"
    assert a["lo"] == pytest.approx(5.76, abs=0.005) and a["value"] == pytest.approx(3.0)
    # at the threshold's amplitude the rod is (just) held: the direction is right
    d = K.SineWave()
    T, A = d.from_rig(50.0, amplitude=1.001 * a["lo"] / 1e3)
    assert K.analyze(T=float(T), A=float(A), l=L, drive=d).stable
    T, A = d.from_rig(1.001 * f["lo"], amplitude=0.003)
    assert K.analyze(T=float(T), A=float(A), l=L, drive=d).stable
    T, A = d.from_rig(0.999 * f["lo"], amplitude=0.003)
    assert not K.analyze(T=float(T), A=float(A), l=L, drive=d).stable
    stroke = directions(rep, "stroke")[1]
    assert stroke["knob"] == "stroke" and stroke["lo"] == pytest.approx(2 * a["lo"])
    assert stroke["text"].startswith("increase the stroke to 11.5-152 mm")


def test_directions_inside_a_zone_and_on_arnolds_plane():
    rep = K.analyze(T=0.15, A=100.0)
    kinds = [d["knob"] for d in rep.directions]
    assert kinds == ["frequency", "stroke"] and all(d["action"] == "keep" for d in rep.directions)
    s = rep.directions[1]
    assert s["lo"] < s["value"] < s["hi"]
    rep = K.analyze(eps=1.0, mu=0.3)                  # between zones 0 and 1
    (d,) = rep.directions
    assert d["knob"] == "eps" and d["action"] in ("raise", "lower")
    lo, hi = d["lo"], d["hi"]
    assert K.is_stable(0.5 * (lo + hi), 0.3)
    assert "%" in d["text"] and "keeping mu" in d["text"]
    assert "directions" in rep.as_dict()


# ------------------------------------------------------------------ safe tilt
def test_safe_tilt_is_the_sweeps_quantity():
    from kapitza.sweeps.kernel import block_quantities

    eps, mu = np.array([0.5, 0.6]), np.array([0.3])
    ours = safe_tilt(eps[None, :], mu[:, None], tol=0.5, periods=60, floor=1e-4)
    sweep = block_quantities(eps, mu, plane="arnold", l=1.0, g=K.G_EARTH if hasattr(K, "G_EARTH") else 9.81,
                             drive="square", periods=60, tol=0.5, quantities=("tilt",), directions=1,
                             basin_resolution=2, accuracy=0.01, floor=1e-4)["max_safe_tilt"]
    assert ours.shape == (1, 2)
    np.testing.assert_allclose(ours, sweep, rtol=0.03)


def test_safe_tilt_against_the_exact_motion():
    """Just below the safe tilt the exact nonlinear motion stays above the horizontal for the
    periods asked; a little above it, it does not (zone 0, where the safe starts are one segment)."""
    th = float(safe_tilt(0.5, 0.3, periods=30))
    assert 0.05 < th < np.pi / 2
    T, A = (float(v) for v in K.to_physical(0.5, 0.3))
    below = K.simulate(0.995 * th, 0.0, T, A, periods=30, points_per_period=400).summary()
    above = K.simulate(1.03 * th, 0.0, T, A, periods=30, points_per_period=400).summary()
    assert below["stays_up"] and not above["stays_up"]


def test_safe_tilt_zone_2_is_tiny_and_unstable_is_zero():
    th = safe_tilt(2.9442806, 0.3, periods=20)
    assert isinstance(th, np.floating) and 0 < th < 1e-3
    assert safe_tilt(3.5, 0.3) == 0.0                  # linearly unstable
    arr = safe_tilt(T=0.15, A=[100.0, 20.0])
    assert arr.shape == (2,) and arr[0] > 0.1 and arr[1] == 0.0


@pytest.mark.parametrize("kw, needle", [
    (dict(eps=0.5, mu=0.3, periods=0), "periods"),
    (dict(eps=0.5, mu=0.3, tol=4.0), "tol"),
    (dict(eps=-0.5, mu=0.3), "eps"),
    (dict(eps=0.5, mu=0.3, damping=1.0), "zeta"),
    (dict(T=0.15, A=100.0, zeta=0.1), "damping"),
])
def test_safe_tilt_refuses_bad_input(kw, needle):
    with pytest.raises(K.KapitzaValueError, match=needle):
        safe_tilt(**kw)


def test_report_with_safe_tilt():
    rep = K.analyze(eps=0.5, mu=0.3, safe_tilt=20)
    assert rep.safe_tilt == pytest.approx(float(safe_tilt(0.5, 0.3, periods=20))) and rep.safe_tilt_periods == 20
    row = dict(rep.lines())["safe tilt"]
    assert row.startswith("stands for starting tilts from rest below") and "20 periods" in row
    assert K.analyze(eps=0.5, mu=0.3).safe_tilt is None   # not computed unless asked


# ------------------------------------------------------------------ the command line
def test_stability_answers_the_engineer(capsys):
    code, out, err = run(["stability", "--drive", "sine", "--frequency", "50", "--amplitude", "0.003", "--rod", "0.25",
                          "--json"], capsys)
    assert code == 0 and err == ""
    rep = json.loads(out)
    assert rep["stable"] is False and rep["safe_tilt"] == 0.0 and rep["given"] == "amplitude"
    assert [d["knob"] for d in rep["directions"]] == ["frequency", "amplitude"]
    assert rep["directions"][0]["lo"] == pytest.approx(95.94, abs=0.01)
    code, out, _ = run(["stability", "--drive", "sine", "--frequency", "50", "--stroke", "0.006", "--rod", "0.25"],
                       capsys)
    assert "raise the frequency to at least 95.9 Hz" in out and "increase the stroke to 11.5-152 mm" in out
    assert "(30.18 g)" in out and "margin" not in out
    code, out, _ = run(["stability", "--drive", "sine", "--frequency", "50", "--amplitude", "0.003", "--rod", "0.25"],
                       capsys)
    assert "frequency > 95.9408 Hz at this amplitude" in out and "stroke" not in out   # the quantity given


def test_stability_shows_the_safe_tilt(capsys):
    code, out, _ = run(["stability", "--eps", "1.78", "--mu", "0.3", "--safe-periods", "20"], capsys)
    assert code == 0 and "stable (zone 1)" in out
    line = next(l for l in out.splitlines() if l.startswith("safe tilt"))
    assert "rad" in line and "20 periods" in line
    code, out, _ = run(["stability", "--eps", "1.78", "--mu", "0.3", "--no-safe-tilt", "--json"], capsys)
    assert json.loads(out)["safe_tilt"] is None


def test_an_implausible_amplitude_is_computed_and_flagged(capsys):
    code, out, err = run(["stability", "--frequency", "50", "--amplitude", "3", "--rod", "0.25", "--json"], capsys)
    assert code == 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "24,465 g" in lines[0] and "--amplitude 0.003" in lines[0]
    assert "24,465 g" in json.loads(out)["warning"]


def test_zeta_with_physical_parameters_is_the_damping_it_means(capsys):
    c = float(2 * 0.1 * np.sqrt(9.81 / 1.0))
    _, a, _ = run(["stability", "--T", "0.15", "--A", "100", "--zeta", "0.1", "--no-safe-tilt", "--json"], capsys)
    _, b, _ = run(["stability", "--T", "0.15", "--A", "100", "--damping", repr(c), "--no-safe-tilt", "--json"], capsys)
    a, b = json.loads(a), json.loads(b)
    assert a["zeta"] == pytest.approx(0.1) and a["damping"] == pytest.approx(c)
    assert a["trace"] == pytest.approx(b["trace"], rel=1e-12)


def test_every_one_point_command_takes_the_rig(capsys, tmp_path):
    T, A = 0.15, 100.0
    rig = ["--frequency", repr(1 / (2 * T)), "--stroke", repr(A * T * T / 4)]
    code, out, _ = run(["simulate", *rig, "--periods", "2", "--json"], capsys)
    assert code == 0 and json.loads(out)["parameters"]["T"] == pytest.approx(T)
    code, out, _ = run(["simulate", *rig, "--periods", "2", "--rod", "1.5"], capsys)
    assert code == 0 and "3.33333 Hz, stroke 562.5 mm" in out and "l = 1 m" in out
    code, out, _ = run(["simulate", "--eps", "0.5", "--mu", "0.3", "--zeta", "0.1", "--periods", "2", "--json"], capsys)
    assert code == 0
    code, out, _ = run(["nonlinear", *rig, "--json"], capsys)
    assert code == 0 and json.loads(out)["eps"] == pytest.approx(float(K.to_arnold(T, A)[0]))
    code, out, _ = run(["basin", *rig, "--resolution", "5", "--periods", "3", "--model", "nonlinear", "--quiet",
                        "--out", str(tmp_path / "b"), "--json"], capsys)
    assert code == 0 and json.loads(out)["parameters"]["T"] == pytest.approx(T)
    code, out, _ = run(["chart", "--plane", "rig", "--rod", "0.25", "--frequency", "50", "--amplitude", "0.003",
                        "--points", "60", "--out", str(tmp_path / "rig")], capsys)
    assert code == 0 and (tmp_path / "rig.png").exists() and (tmp_path / "rig.csv").exists()
    assert (tmp_path / "rig.csv").read_text().splitlines()[1] == "n,stroke,f_lo,f_hi"


@pytest.mark.parametrize("argv, needle", [
    (["simulate", "--frequency", "3", "--stroke", "0.1", "--amplitude", "0.05"], "exactly one"),
    (["basin", "--stroke", "0.1"], "--frequency"),
    (["nonlinear", "--frequency", "3", "--stroke", "0.1", "--rod", "1", "--l", "1"], "--rod"),
    (["chart", "--plane", "rig", "--frequency", "50"], "--stroke"),
    (["chart", "--plane", "rig", "--frequency-min", "10", "--frequency-max", "5"], "frequency"),
])
def test_bad_rig_input_on_other_commands(argv, needle, capsys):
    code, _, err = run(argv, capsys)
    assert_one_line_error(code, err, needle)


# ------------------------------------------------------------------ the frequency-stroke plane
@pytest.mark.parametrize("drive", ["square", "sine"])
def test_rig_plane_edges_are_the_reports_frequencies(drive):
    d = K.parse_drive(drive)
    c = rig_zone_curves((10.0, 400.0), (0.001, 0.1), L, 9.81, d, points=40)
    assert list(c.n[:1]) == [0]
    for j in (5, 20, 35):
        s = c.stroke[j]
        T, A = d.from_rig(50.0, stroke=s)
        rep = K.analyze(T=float(T), A=float(A), l=L, drive=None if drive == "square" else d)
        if rep.nearest_zone == 0 and rep.frequency_lo is not None:
            assert c.f_lo[0, j] == pytest.approx(rep.frequency_lo, rel=2e-3)


def test_zones_and_compare_take_a_rigs_damping(capsys):
    from kapitza.drives._api import zeta_of

    code, a, _ = run(["zones", "--zones", "1", "--points", "3", "--damping", "0.5", "--rod", "0.3", "--json"], capsys)
    z = float(zeta_of(0.5, 0.2, 9.81))
    code2, b, _ = run(["zones", "--zones", "1", "--points", "3", "--zeta", repr(z), "--json"], capsys)
    assert code == code2 == 0 and json.loads(a) == json.loads(b)
    code, _, err = run(["zones", "--rod", "0.3"], capsys)
    assert_one_line_error(code, err, "--damping")
    code, _, err = run(["compare", "--damping", "0.5", "--zeta", "0.1"], capsys)
    assert_one_line_error(code, err, "not both")


def test_a_rig_answers_in_the_quantity_it_was_given():
    rig = K.Rig(K.Pendulum.uniform_rod(0.25), "sine")
    rep = rig.analyze(frequency=50.0, amplitude=0.003)
    assert rep.given == "amplitude" and [d["knob"] for d in rep.directions] == ["frequency", "amplitude"]
    assert "increase the amplitude to 5.76-75.8 mm" in str(rep) and "stroke" not in str(rep)
    reps = rig.analyze(frequency=[50.0, 60.0], stroke=0.006)
    assert all(r.given == "stroke" and "increase the stroke to" in r.directions[1]["text"] for r in reps)
    assert rig.analyze(T=0.01, A=296.0).given is None


def test_directions_write_numbers_out():
    rep = K.analyze(T=0.2, A=150.0, drive="rectangular:0.3", zeta=0.05)
    stroke = next(d for d in rep.directions if d["knob"] == "stroke")
    assert "584-1,130 mm" in stroke["text"] and "e+" not in stroke["text"]
    assert stroke["hi"] == pytest.approx(1132.76, rel=1e-4)     # the JSON keeps the number itself
    far = K.analyze(T=0.01, A=296088.132033, l=0.25 * 2 / 3, drive="sine")
    assert all("e+" not in d["text"] for d in far.directions)   # 288,000 Hz, not 2.88e+05 Hz


def test_nonlinear_takes_the_rigs_damping_and_names_what_it_cannot_answer(capsys):
    rig = ["--frequency", "3.3333333333", "--stroke", "0.5625"]
    code, out, err = run(["nonlinear", *rig, "--rod", "1.5", "--damping", "0.5", "--json"], capsys)
    d = json.loads(out)
    rep = K.analyze(T=0.15, A=100.0, l=1.0, damping=0.5)
    assert code == 0 and d["kind"] == "asymptotically stable" and d["stable"] is True
    assert d["growth"] == pytest.approx(float(rep.growth), rel=1e-9) and d["growth"] < 0
    code, out, _ = run(["nonlinear", "--eps", "1.2", "--mu", "0.3", "--zeta", "0.05", "--json"], capsys)
    assert code == 0 and json.loads(out)["unstable"] is True
    code, out, _ = run(["nonlinear", "--eps", "0.5", "--mu", "0.3", "--drive", "square", "--json"], capsys)
    assert code == 0 and json.loads(out)["kind"] == "moser"       # the square wave, named, as before
    for argv, needle in ((["--eps", "0.5", "--mu", "0.3", "--drive", "sine"], "--drive sine"),
                         (["--eps", "0.5", "--mu", "0.3", "--duty", "0.3"], "--duty 0.3"),
                         (["--chart", "--zeta", "0.1"], "--zeta"),
                         (["--eps", "0.5", "--mu", "0.3", "--damping", "0.3"], "--zeta")):
        code, _, err = run(["nonlinear", *argv], capsys)
        assert_one_line_error(code, err, needle)


@pytest.mark.parametrize("command", [["simulate", "--periods", "2"], ["nonlinear"], ["chart", "--plane", "rig", "--points", "30"]])
def test_an_implausible_amplitude_is_flagged_by_every_command(command, capsys, tmp_path):
    code, _, err = run([*command, "--frequency", "50", "--amplitude", "3", "--rod", "0.25", "--out",
                        str(tmp_path / "x")] if command[0] == "chart" else
                       [*command, "--frequency", "50", "--amplitude", "3", "--rod", "0.25"], capsys)
    assert code == 0
    notes = [line for line in err.splitlines() if line.startswith("kapitza: note:")]
    assert len(notes) == 1 and "24,465 g" in notes[0] and "--amplitude 0.003" in notes[0]
