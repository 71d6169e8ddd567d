"""kapitza stability for a real rig: drives, damping, frequency and stroke, a rod, --check."""
import json

import numpy as np
import pytest

import kapitza as K
from cli_util import assert_one_line_error, run


def test_rig_units_reach_the_same_report_as_T_and_A(capsys):
    # a square wave at 3.3333 Hz with stroke A T^2 / 4
    T, A = 0.15, 100.0
    code, out, _ = run(["stability", "--frequency", repr(1 / (2 * T)), "--stroke", repr(A * T * T / 4), "--json"], capsys)
    assert code == 0
    rep = json.loads(out)
    assert rep["T"] == pytest.approx(T, rel=1e-14) and rep["A"] == pytest.approx(A, rel=1e-14)
    assert rep["verdict"] == "stable (zone 0)"


def test_uniform_rod_uses_two_thirds_of_its_length(capsys):
    """The newcomer's rod: the verdict at T = 0.19, A = 100 differs between l = 1 and a 1 m rod."""
    code, out, _ = run(["stability", "--T", "0.19", "--A", "100", "--rod", "1", "--json"], capsys)
    rod = json.loads(out)
    assert rod["l"] == pytest.approx(2 / 3)
    assert rod["stable"] == bool(K.is_stable(*K.to_arnold(0.19, 100, 2 / 3)))
    assert rod["stable"] != bool(K.is_stable(*K.to_arnold(0.19, 100, 1.0)))


def test_drive_damping_and_check_exit_status(capsys):
    code, out, _ = run(["stability", "--duty", "0.3", "--T", "0.15", "--A", "100", "--damping", "0.3", "--check"], capsys)
    assert code == 1 and "rectangular wave, duty 0.3" in out and "c = 0.3 1/s" in out
    code, out, _ = run(["stability", "--T", "0.15", "--A", "100", "--check"], capsys)
    assert code == 0 and "stable (zone 0)" in out
    code, out, _ = run(["stability", "--eps", "0.53", "--mu", "0.3", "--zeta", "0.1", "--json"], capsys)
    rep = json.loads(out)
    assert rep["zeta"] == 0.1 and rep["growth"] < 0
    assert rep["determinant"] == pytest.approx(np.exp(-4 * np.sqrt(8) * 0.1 * 0.3 * 0.53))


@pytest.mark.parametrize("argv, needle", [
    (["--T", "0.1", "--A", "100", "--drive", "sawtooth"], "drive"),
    (["--T", "0.1", "--A", "100", "--duty", "1.5"], "duty"),
    (["--T", "0.1", "--A", "100", "--drive", "sine", "--duty", "0.3"], "--duty"),
    (["--T", "0.1", "--A", "100", "--damping", "-1"], "damping"),
    (["--T", "0.1", "--A", "100", "--zeta", "0.1", "--damping", "0.2"], "not both"),
    (["--T", "0.1", "--A", "100", "--frequency", "3"], "--T or --frequency"),
    (["--frequency", "3", "--rpm", "180", "--stroke", "0.1"], "--rpm"),
    (["--eps", "0.5", "--mu", "0.3", "--damping", "1"], "--zeta"),
    (["--frequency", "3"], "exactly one"),
    (["--frequency", "3", "--stroke", "0.1", "--amplitude", "0.05"], "exactly one"),
    (["--stroke", "0.1", "--A", "100"], "--frequency"),
    (["--T", "0.1", "--frequency", "3", "--stroke", "0.1"], "--T or --frequency"),
    (["--T", "0.1", "--A", "100", "--rod", "1", "--l", "1"], "--rod"),
    (["--T", "0.1", "--A", "100", "--rod", "-1"], "length"),
])
def test_bad_rig_input_is_one_line(argv, needle, capsys):
    code, _, err = run(["stability", *argv], capsys)
    assert_one_line_error(code, err, needle)


def test_zones_and_chart_take_a_drive(tmp_path, capsys):
    import csv

    out = tmp_path / "z.csv"
    code, _, err = run(["zones", "--drive", "sine", "--zeta", "0.1", "--zones", "2", "--points", "5",
                        "--out", str(out)], capsys)
    assert code == 0, err
    rows = list(csv.DictReader(line for line in open(out) if not line.startswith("#")))
    mu = np.array([float(r["mu"]) for r in rows if r["n"] == "1"])
    lo = np.array([float(r["eps_lo"]) for r in rows if r["n"] == "1"])
    ref, _ = K.zone_edges(mu, 1, drive="sine", zeta=0.1)
    np.testing.assert_allclose(lo, ref, rtol=1e-15)
    code, _, err = run(["chart", "--duty", "0.3", "--points", "100", "--out", str(tmp_path / "c")], capsys)
    assert code == 0, err
    assert (tmp_path / "c.png").stat().st_size > 0
    code, _, err = run(["chart", "--drive", "sine", "--plane", "physical", "--points", "60", "--out",
                        str(tmp_path / "p")], capsys)
    assert code == 0, err
    rows = list(csv.DictReader(line for line in open(tmp_path / "p.csv") if not line.startswith("#")))
    A = np.array([float(r["A"]) for r in rows if r["n"] == "0"])
    T_lo = np.array([float(r["T_lo"]) for r in rows if r["n"] == "0"])
    ok = np.isfinite(T_lo)
    assert ok.sum() > 50
    np.testing.assert_allclose(T_lo[ok], K.period_edges(A[ok], 0, drive="sine")[0], rtol=1e-9)


def test_python_dash_m_kapitza():
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-m", "kapitza", "stability", "--eps", "0.5", "--mu", "0.3", "--check"],
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "stable (zone 0)" in proc.stdout


def test_closed_pipe_is_quiet():
    import subprocess
    import sys

    proc = subprocess.run(f"{sys.executable} -m kapitza zones --zones 40 --points 400 --json | head -c 10",
                          shell=True, capture_output=True, text=True)
    assert proc.stderr == "" and len(proc.stdout) == 10


def test_rig_margins_along_frequency_and_stroke():
    """At a fixed stroke eps is fixed and mu ~ 1/f; the frequency interval's ends are zone edges."""
    rep = K.analyze(T=0.5064, A=100.0)        # zone 1, thin
    assert rep.zone == 1 and rep.frequency_lo < rep.frequency < rep.frequency_hi
    k = rep.stroke / (rep.A * rep.T**2)
    for f_edge, inside in ((rep.frequency_lo, 1.0 + 1e-7), (rep.frequency_hi, 1.0 - 1e-7)):
        for factor, stable in ((inside, True), (2.0 - inside, False)):
            f = f_edge * factor
            T = 0.5 / f
            A = rep.stroke / (k * T * T)
            assert K.analyze(T=T, A=A).stable == stable
    # the stroke interval at this frequency is the A interval scaled
    assert rep.stroke_lo / rep.stroke == pytest.approx(rep.A_lo / rep.A)
    weak = K.analyze(T=0.01, A=100.0)
    assert weak.verdict.startswith("unstable: the drive is too weak") and weak.frequency_lo > weak.frequency
    assert "no upper limit" in str(weak)


def test_periods_by_mu_and_zones_json_with_out(tmp_path, capsys):
    import json

    code, out, _ = run(["periods", "--mu", repr((9.81 / 100) ** 0.5), "--count", "1", "--json"], capsys)
    assert code == 0
    assert json.loads(out)["periods"][0]["T"] == pytest.approx(0.10910018565, rel=1e-9)
    code, _, err = run(["periods", "--mu", "1.5"], capsys)
    assert_one_line_error(code, err, "--mu")
    code, out, _ = run(["zones", "--zones", "2", "--points", "50", "--json", "--out", str(tmp_path / "z.json")], capsys)
    assert code == 0 and json.loads(out) == {"wrote": str(tmp_path / "z.json"), "zones": 2, "points": 50}


def test_analyze_says_it_takes_single_values():
    with pytest.raises(ValueError, match="single values; got T of shape"):
        K.analyze(T=[0.1, 0.2], A=100.0)


def test_square_wave_frequency_interval_matches_the_general_bisection():
    # The closed-form path (regula falsi in mu at fixed eps) against the drive-generic bisection on
    # the rotation angle, where both give an interval; where the zone cannot be reached by changing
    # the frequency at this stroke the closed forms give none (the bisection gave a degenerate one).
    import numpy as np

    import kapitza as K
    from kapitza import _square as S
    from kapitza.drives import SquareWave, _api

    rng = np.random.default_rng(5)
    compared = 0
    for _ in range(60):
        T, A = 10 ** rng.uniform(-2.5, 0.0), 10 ** rng.uniform(1.0, 3.0)
        eps, mu = (float(v) for v in K.to_arnold(T, A))
        nz = int(K.stability_margin(eps, mu).zone)
        if nz < 0:
            continue
        a = S.rig_margins(eps, mu, nz, T, 0.25 * A * T * T)
        # the drive-generic search of analyze (A and the frequency together, on the rotation angle)
        b = _api.rig_intervals(eps, mu, nz, SquareWave(), 0.0, T, A, 1.0, K.G_EARTH)
        if "frequency_lo" in a:
            compared += 1
            assert a["frequency_lo"] == pytest.approx(b["frequency_lo"], rel=1e-11)
            assert a["frequency_hi"] == pytest.approx(b["frequency_hi"], rel=1e-11)
        else:  # unreachable: the zone's lower edge is above this eps at every mu
            eps_lo, _ = K.zone_edges(np.geomspace(1e-6, 0.999, 400), nz)
            assert np.all(eps_lo >= eps)
    assert compared >= 30


def test_acceleration_in_g_is_one_field_in_text_json_and_report(capsys):
    """A in units of g: the text's "(40.77 g)", the JSON's A_g and the report's dictionary agree."""
    argv = ["stability", "--frequency", "50", "--stroke", "0.01", "--rod", "0.25", "--no-safe-tilt"]
    code, out, _ = run([*argv, "--json"], capsys)
    assert code == 0
    rep = json.loads(out)
    assert rep["A_g"] == pytest.approx(400.0 / 9.81, rel=1e-14) and rep["A_g"] == rep["A"] / rep["g"]
    code, text, _ = run(argv, capsys)
    assert f"({rep['A_g']:.4g} g)" in text
    assert K.analyze(T=0.01, A=400.0, l=0.2, g=9.8).as_dict()["A_g"] == pytest.approx(400 / 9.8)
    assert json.loads(run(["stability", "--eps", "0.5", "--mu", "0.3", "--json"], capsys)[1])["A_g"] is None
