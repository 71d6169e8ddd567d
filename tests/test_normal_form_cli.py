"""``kapitza nonlinear`` through its real entry point, the figures, and the stability report's line."""
import csv
import json

import numpy as np
import pytest

import kapitza as K
from cli_util import assert_one_line_error, run


def test_point_prints_the_verdict_with_its_numbers(capsys):
    code, out, err = run(["nonlinear", "--eps", "0.5", "--mu", "0.3"], capsys)
    assert code == 0, err
    assert "Lyapunov stable (Moser's twist theorem" in out
    assert f"tau = {float(K.twist_coefficient(0.5, 0.3)):.12g}" in out


def test_point_json_and_physical_parameters(capsys):
    code, out, _ = run(["nonlinear", "--T", "0.15", "--A", "100", "--json"], capsys)
    assert code == 0
    rec = json.loads(out)
    eps, mu = K.to_arnold(0.15, 100.0)
    assert rec["kind"] == "moser" and rec["stable"] is True
    assert rec["twist"] == pytest.approx(float(K.twist_coefficient(eps, mu)), rel=1e-14)


@pytest.mark.parametrize("argv, needle", [
    (["nonlinear", "--eps", "-0.5", "--mu", "0.3"], "eps"),
    (["nonlinear", "--eps", "0.5", "--mu", "nan"], "mu"),
    (["nonlinear"], "give a point"),
    (["nonlinear", "--chart", "--zones", "9"], "--zones must lie in [1, 6]"),
])
def test_bad_input_is_one_line_and_status_2(capsys, argv, needle):
    code, _, err = run(argv, capsys)
    assert_one_line_error(code, err, needle)


@pytest.mark.parametrize("eps, mu", [(0.9, 0.3), (0.05, 0.3), (0.5, 1.2)])
def test_linearly_unstable_points_are_unstable_by_the_first_approximation(capsys, eps, mu):
    code, out, err = run(["nonlinear", "--eps", str(eps), "--mu", str(mu), "--json"], capsys)
    assert code == 0, err
    rec = json.loads(out)
    f = K.floquet(eps, mu)
    assert not K.is_stable(eps, mu) and float(f.growth) > 0
    assert rec["unstable"] is True and rec["stable"] is False and rec["kind"] == "linearly unstable"
    assert rec["growth"] == pytest.approx(float(f.growth), rel=1e-14)
    assert "first approximation" in rec["verdict"]


def test_chart_writes_figure_and_curves(capsys, tmp_path):
    stem = tmp_path / "nl"
    code, out, err = run(["nonlinear", "--chart", "--zones", "2", "--points", "5", "--scan", "8", "--out", str(stem)],
                         capsys)
    assert code == 0, err
    for suffix in (".png", ".svg", ".csv", ".json"):
        assert (tmp_path / ("nl" + suffix)).stat().st_size > 0
    rows = [r for r in csv.reader(open(tmp_path / "nl.csv")) if r and not r[0].startswith("#")]
    assert rows[0][:3] == ["zone", "mu", "eps_lo"]
    # zone 0 at every mu; zone 1 only where a double eps resolves it (not at mu = 0.95)
    assert [r[0] for r in rows[1:]].count("0") == 5 and [r[0] for r in rows[1:]].count("1") == 4
    data = json.load(open(tmp_path / "nl.json"))
    z = data["zones"][1]
    np.testing.assert_allclose(K.floquet(z["eps_1to4"], z["mu"]).trace, 0.0, atol=1e-9)
    assert all(z["markeev_stable"])


def test_rotation_figure_and_data(capsys, tmp_path):
    code, out, err = run(["nonlinear", "--eps", "0.5", "--mu", "0.3", "--rotation", "--periods", "64",
                          "--r-max", "0.2", "--out", str(tmp_path / "p")], capsys)
    assert code == 0, err
    rows = [r for r in csv.reader(open(tmp_path / "p-rotation.csv")) if r and not r[0].startswith("#")]
    r, meas, pred = (np.array([float(x[i]) for x in rows[1:]]) for i in range(3))
    assert r.size == 24 and (tmp_path / "p-rotation.png").exists()
    small = r < 0.05
    np.testing.assert_allclose(meas[small], pred[small], atol=2e-5)


def test_figure_functions_take_ax_and_return_what_they_drew():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from kapitza.figures.nonlinear import plot_nonlinear_overview, plot_nonlinear_zone, plot_rotation_growth
    from kapitza.motion import measured_rotation_number
    from kapitza.resonances import nonlinear_chart

    chart = nonlinear_chart([0.1, 0.3, 0.5], zones=(0, 1), scan=0)
    fig, ax = plt.subplots()
    d = plot_nonlinear_zone(chart.zones[1], ax=ax, across=9)
    assert d.ax is ax and {"twist", "1:3", "1:4 stable"} <= set(d) and d.data is chart.zones[1]
    d = plot_nonlinear_overview(chart)
    assert "zone 0" in d and d.data is chart
    run_ = measured_rotation_number(0.5, 0.3, [0.01, 0.1], periods=32)
    d = plot_rotation_growth(run_)
    assert {"measured", "normal form", "linear"} <= set(d)
    plt.close("all")


def test_stability_report_says_the_nonlinear_verdict():
    rep = K.analyze(eps=0.5, mu=0.3)
    assert rep.nonlinear.startswith("Lyapunov stable (Moser")
    assert "nonlinear" in str(rep) and rep.as_dict()["nonlinear"] == rep.nonlinear
    assert K.analyze(eps=0.9, mu=0.3).nonlinear is None
    assert K.analyze(eps=0.5, mu=0.3, zeta=0.1).nonlinear is None   # damped: not this verdict
