"""The engine commands through the real entry point ``kapitza.cli.main`` (and once as a process)."""
import csv
import json
import math
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import kapitza as K
from cli_util import assert_one_line_error, run


def read_csv(path):
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if not line.startswith("#"))]
    return rows[0], rows[1:]


# ---------------------------------------------------------------- stability
def test_stability_table_for_the_readme_example(capsys):
    code, out, err = run(["stability", "--T", "0.15", "--A", "100"], capsys)
    assert code == 0 and err == ""
    assert "stable (zone 0)" in out
    assert "0.109100185651" in out and "0.200866326585" in out  # T_1 < T < T~_1 at this A


def test_stability_says_beforehand_when_its_report_takes_long(capsys, monkeypatch):
    from kapitza.cli import engine

    # the triangle at T = 0.15 s, A = 1e10 m/s^2 (eps 5,300) integrates 2^20 steps a period: 20-30 s
    note = engine.long_report_note(dict(T=0.15, A=1e10, l=1.0, g=9.81, drive=K.TriangleWave()))
    assert note.startswith("eps = 5303.3 with the triangle wave") and "1,048,576 steps" in note
    # exact products and ordinary points say nothing; a point beyond reach is left to the report's own error
    assert engine.long_report_note(dict(eps=3e4, mu=0.1)) is None
    assert engine.long_report_note(dict(eps=3e4, mu=0.1, drive=K.RectangularWave(0.3))) is None
    assert engine.long_report_note(dict(T=0.15, A=100.0, l=1.0, g=9.81, drive=K.TriangleWave())) is None
    assert engine.long_report_note(dict(eps=3e9, mu=0.1, drive=K.TriangleWave())) is None
    assert engine.long_report_note(dict(T=0.15, A=1e10, l=1.0, g=0.0, drive=K.TriangleWave())) is None
    # the sine's physical report from eps 30 (its rig edges by exact traces: 8 s there, a minute at 60);
    # at an Arnold point (no rig edges) or below 30, or beyond its reach, nothing
    A = 9.81 / 0.5**2
    note = engine.long_report_note(dict(T=40.0 * np.sqrt(8.0 / A), A=A, l=1.0, g=9.81, drive=K.SineWave()))
    assert note.startswith("eps = 40 with the sine wave") and "exact traces" in note
    assert engine.long_report_note(dict(T=20.0 * np.sqrt(8.0 / A), A=A, l=1.0, g=9.81, drive=K.SineWave())) is None
    assert engine.long_report_note(dict(eps=40.0, mu=0.5, drive=K.SineWave())) is None
    assert engine.long_report_note(dict(T=5e3 * np.sqrt(8.0 / A), A=A, l=1.0, g=9.81, drive=K.SineWave())) is None
    # the command prints it to standard error before the report (here at an ordinary point, the bar lowered)
    monkeypatch.setattr(engine, "LONG_REPORT_STEPS", 1)
    code, out, err = run(["stability", "--drive", "triangle", "--T", "0.15", "--A", "100"], capsys)
    assert code == 0 and err.startswith("kapitza: note: eps = 0.53033 with the triangle wave") and "zone" in out


def test_stability_json_matches_the_library(capsys):
    code, out, _ = run(["stability", "--eps", "0.5", "--mu", "0.3", "--json"], capsys)
    assert code == 0
    d = json.loads(out)
    rep = K.analyze(eps=0.5, mu=0.3)
    assert d["stable"] == rep.stable and d["zone"] == rep.zone and d["verdict"] == rep.verdict
    assert d["growth"] == rep.growth and d["trace"] == rep.trace and d["margin"] == rep.margin
    assert d["eps_lo"] == rep.eps_lo and d["eps_hi"] == rep.eps_hi
    assert [complex(*z) for z in d["multipliers"]] == list(rep.multipliers)


def test_stability_json_physical_and_unstable(capsys):
    code, out, _ = run(["stability", "--T", "0.3", "--A", "100", "--l", "1", "--g", "9.81", "--json"], capsys)
    assert code == 0
    d = json.loads(out)
    assert d["stable"] is False and d["zone"] == -1 and d["verdict"].startswith("unstable: parametric resonance, 4T-type")
    assert d["T"] == 0.3 and d["A"] == 100.0 and d["margin"] < 0
    assert d["T_lo"] < d["T_hi"] and not (d["T_lo"] < 0.3 < d["T_hi"])


def test_stability_json_for_A_below_g_has_no_nan(capsys):
    code, out, _ = run(["stability", "--eps", "0.5", "--mu", "1.5", "--json"], capsys)
    assert code == 0
    assert "NaN" not in out
    d = json.loads(out)
    assert d["verdict"] == "always unstable: no elliptic phase (A <= g)"
    assert d["eps_lo"] is None and math.isfinite(d["growth"])


def test_stability_far_out_prints_an_infinite_trace_as_text(capsys):
    code, out, _ = run(["stability", "--eps", "800", "--mu", "0.5", "--json"], capsys)
    assert code == 0
    d = json.loads(out)
    assert d["trace"] in ("inf", "-inf") and d["growth"] > 700


@pytest.mark.parametrize("argv,needles", [
    (["stability", "--T", "-1", "--A", "100"], ["T", "-1.0"]),
    (["stability", "--T", "0.15", "--A", "0"], ["A", "0.0"]),
    (["stability", "--eps", "0.5", "--mu", "-0.3"], ["mu", "-0.3"]),
    (["stability", "--T", "0.15", "--A", "100", "--l", "0"], ["l", "0.0"]),
    (["stability", "--T", "0.15"], ["--T and --A"]),
    (["stability", "--T", "0.15", "--A", "100", "--eps", "0.5", "--mu", "0.3"], ["not both"]),
    (["stability"], ["give the parameters"]),
    (["stability", "--T", "nan", "--A", "100"], ["must be finite", "nan"]),
    (["stability", "--T", "abc", "--A", "100"], ["not a number", "abc"]),
    (["stability", "--bogus"], ["unrecognized arguments"]),
    (["periods", "--A", "5"], ["A must exceed g"]),
    (["periods", "--A", "100", "--count", "0"], ["--count"]),
    (["zones", "--zones", "0"], ["--zones"]),
    (["zones", "--mu-min", "0"], ["mu-min"]),
    (["zones", "--out", "x.txt"], [".csv or .json"]),
    (["chart", "--eps-min", "3", "--eps-max", "2"], ["eps-min"]),
    (["chart", "--mark-T", "0.1"], ["--mark-T and --mark-A"]),
    (["nonsense"], ["invalid choice"]),
])
def test_bad_input_exits_2_with_a_one_line_message(argv, needles, capsys):
    code, out, err = run(argv, capsys)
    assert_one_line_error(code, err, *needles)


def test_version_and_help(capsys):
    code, out, _ = run(["--version"], capsys)
    assert code == 0 and out.strip() == f"kapitza {K.__version__}"
    code, out, _ = run([], capsys)
    assert code == 2 and "stability" in out and "periods" in out


# ---------------------------------------------------------------- periods
def test_periods_json_and_csv(tmp_path, capsys):
    path = tmp_path / "sub" / "periods.csv"
    code, out, err = run(["periods", "--A", "100", "--count", "3", "--json", "--csv", str(path)], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    names = [p["name"] for p in d["periods"]]
    assert names == ["T_1", "T~_1", "T~_2", "T_2", "T_3", "T~_3"]
    T, Tt = K.boundary_periods(100.0, 3)
    got = {p["name"]: p["T"] for p in d["periods"]}
    for j in range(3):
        assert got[f"T_{j + 1}"] == T[j] and got[f"T~_{j + 1}"] == Tt[j]
    assert abs(got["T_1"] - 0.10910018565) < 5e-12 and abs(got["T~_2"] - 0.50550270119) < 5e-12
    header, rows = read_csv(path)
    assert header == ["name", "T", "period", "equation", "k", "zone", "edge", "eps", "mu"]
    assert [r[0] for r in rows] == names
    assert [float(r[1]) for r in rows] == [p["T"] for p in d["periods"]]  # repr round-trips
    assert [r[3] for r in rows] == ["3.10", "3.13", "3.12", "3.11", "3.10", "3.13"]


def test_periods_table(capsys):
    code, out, _ = run(["periods", "--A", "100", "--count", "2"], capsys)
    assert code == 0
    assert "T~_2" in out and "0.505502701185607" in out and "3.12" in out


# ---------------------------------------------------------------- zones
def test_zones_csv_and_json_files(tmp_path, capsys):
    csv_path, json_path = tmp_path / "z.csv", tmp_path / "z.json"
    code, out, _ = run(["zones", "--zones", "3", "--points", "5", "--out", str(csv_path)], capsys)
    assert code == 0 and "wrote" in out
    header, rows = read_csv(csv_path)
    assert header == ["n", "mu", "eps_lo", "eps_hi", "lower_edge", "upper_edge"]
    assert len(rows) == 15
    for r in rows:
        n, mu, lo, hi = int(r[0]), float(r[1]), float(r[2]), float(r[3])
        elo, ehi = K.zone_edges(mu, n)
        assert (lo, hi) == (elo, ehi)
        assert (r[4], r[5]) == (("2T", "4T") if n % 2 == 0 else ("4T", "2T"))
    code, _, _ = run(["zones", "--zones", "2", "--points", "4", "--mu-min", "0.1", "--mu-max", "0.9",
                      "--out", str(json_path)], capsys)
    assert code == 0
    d = json.loads(json_path.read_text())
    z1 = d["zones"][1]
    assert z1["n"] == 1 and z1["lower_edge"] == "4T"
    lo, hi = K.zone_edges(np.array(z1["mu"]), 1)
    assert z1["mu"][0] == 0.1 and z1["mu"][-1] == 0.9
    assert z1["eps_lo"] == lo.tolist() and z1["eps_hi"] == hi.tolist()


def test_zones_json_to_stdout(capsys):
    code, out, _ = run(["zones", "--zones", "1", "--points", "3", "--json"], capsys)
    assert code == 0
    d = json.loads(out)
    assert len(d["zones"]) == 1 and len(d["zones"][0]["mu"]) == 3


# ---------------------------------------------------------------- chart
def test_chart_writes_png_svg_csv(tmp_path, capsys):
    from PIL import Image

    stem = tmp_path / "figs" / "chart"
    code, out, err = run(["chart", "--out", str(stem), "--points", "60", "--mark-T", "0.15", "--mark-A", "100"], capsys)
    assert code == 0, err
    png, svg, data = stem.with_suffix(".png"), stem.with_suffix(".svg"), stem.with_suffix(".csv")
    with Image.open(png) as im:
        im.verify()
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size[0] > 500 and im.size[1] > 300
        # not blank: the zones are filled
        colours = np.unique(np.asarray(im.convert("RGB")).reshape(-1, 3), axis=0)
        assert len(colours) > 10
    root = ET.parse(svg).getroot()
    assert root.tag.endswith("svg")
    header, rows = read_csv(data)
    assert header == ["n", "mu", "eps_lo", "eps_hi"]
    n = {int(r[0]) for r in rows}
    assert {0, 1, 2, 3} <= n
    for r in rows[::17]:
        mu = float(r[1])
        lo, hi = K.zone_edges(mu, int(r[0]))
        # the curves drawn are the closed forms' roots, within 4 ulp of the certified edges
        assert abs(float(r[2]) - lo) <= 4 * np.spacing(lo) and abs(float(r[3]) - hi) <= 4 * np.spacing(hi)
    assert not list(tmp_path.glob("figs/.*"))  # no temporary files left behind


def test_chart_pdf_and_window(tmp_path, capsys):
    stem = tmp_path / "zoom"
    code, _, err = run(["chart", "--out", str(stem) + ".png", "--eps-min", "2.7", "--eps-max", "2.9", "--mu-min", "0",
                        "--mu-max", "0.3", "--points", "40", "--pdf", "--no-G"], capsys)
    assert code == 0, err
    assert stem.with_suffix(".pdf").read_bytes()[:5] == b"%PDF-"
    assert stem.with_suffix(".png").stat().st_size > 0


def test_chart_physical_plane_of_another_drive_is_its_period_edges(tmp_path, capsys):
    """The T-A chart of a damped rectangular wave draws that drive's edges (kapitza.period_edges),
    with the marked point's verdict for that drive."""
    from kapitza.drives import parse_drive
    from kapitza.drives._api import damping_of

    stem = tmp_path / "rect"
    code, _, err = run(["chart", "--plane", "physical", "--duty", "0.3", "--zeta", "0.05", "--points", "30",
                        "--A-min", "20", "--A-max", "300", "--T-max", "0.5", "--mark-T", "0.1", "--mark-A", "150",
                        "--out", str(stem)], capsys)
    assert code == 0, err
    header, rows = read_csv(stem.with_suffix(".csv"))
    assert header == ["n", "A", "T_lo", "T_hi"]
    drive, c = parse_drive("rectangular:0.3"), damping_of(0.05, 1.0, 9.81)
    for r in rows[::7]:
        n, A, lo, hi = int(r[0]), float(r[1]), float(r[2]), float(r[3])
        want = K.period_edges(A, n, drive=drive, damping=c)
        for got, ref in zip((lo, hi), want):
            if np.isfinite(ref) and got < 1e300:
                assert got == pytest.approx(float(ref), rel=1e-9)
    assert {int(r[0]) for r in rows} >= {0, 1}
    code, _, err = run(["chart", "--plane", "physical", "--drive", "sine", "--T-max", "1e6", "--A-max", "1e6",
                        "--out", str(tmp_path / "far")], capsys)
    assert code == 2 and "largest eps" in err


# ---------------------------------------------------------------- as a process
def test_module_entry_point_in_a_subprocess():
    proc = subprocess.run([sys.executable, "-m", "kapitza.cli", "stability", "--T", "0.15", "--A", "100"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "stable (zone 0)" in proc.stdout
    bad = subprocess.run([sys.executable, "-m", "kapitza.cli", "stability", "--T", "0", "--A", "100"],
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and len(bad.stderr.strip().splitlines()) == 1


def test_import_kapitza_does_not_import_matplotlib():
    code = ("import sys, kapitza; "
            "print(sorted(m for m in ('matplotlib', 'PIL', 'mpmath', 'hypothesis') if m in sys.modules))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


@pytest.mark.parametrize("argv", [
    ["chart", "--out", "/dev/null/sub/chart"],
    ["zones", "--out", "/dev/null/sub/z.csv"],
    ["periods", "--A", "100", "--csv", "/dev/null/sub/p.csv"],
])
def test_unwritable_output_is_a_one_line_error(argv, capsys):
    code, out, err = run(argv, capsys)
    assert_one_line_error(code, err, "cannot write")


def test_chart_of_a_drive_that_holds_the_rod_up_below_g(tmp_path, capsys):
    """Duty 0.8: the default window reaches the drive's mu_max = 2 (A = g/4), and zone 0 is drawn
    above mu = 1 with the library's edges; beyond mu_max a window is refused, for the square wave
    beyond 1 as before. On the T-A plane the default window starts at A = g / mu_max^2."""
    drive = K.RectangularWave(0.8)
    stem = tmp_path / "r08"
    code, _, err = run(["chart", "--duty", "0.8", "--points", "80", "--out", str(stem)], capsys)
    assert code == 0, err
    header, rows = read_csv(stem.with_suffix(".csv"))
    assert header == ["drive", "zeta", "n", "mu", "eps_lo", "eps_hi"]
    above = [r for r in rows if int(r[2]) == 0 and 1.0 < float(r[3]) and np.isfinite(float(r[4]))]
    assert len(above) > 20 and max(float(r[3]) for r in above) > 1.8
    for r in above[::5]:
        lo, hi = K.zone_edges(float(r[3]), 0, drive=drive)
        assert float(r[4]) == pytest.approx(float(lo), rel=1e-9) and float(r[5]) == pytest.approx(float(hi), rel=1e-9)
    code, _, err = run(["chart", "--duty", "0.8", "--mu-max", "2.5", "--out", str(stem)], capsys)
    assert_one_line_error(code, err, "mu-max <= 2", "2.5", "always falls")
    code, _, err = run(["chart", "--mu-max", "1.2", "--out", str(stem)], capsys)
    assert_one_line_error(code, err, "mu-max <= 1;", "1.2")
    code, _, err = run(["chart", "--duty", "0.8", "--plane", "physical", "--points", "40", "--out", str(stem)], capsys)
    assert code == 0, err
    A = [float(r[1]) for r in read_csv(stem.with_suffix(".csv"))[1]]
    assert min(A) == pytest.approx(9.81 / 4.0, rel=1e-8)  # sampled to mu_max (1 - 1e-9)
    code, _, err = run(["chart", "--duty", "0.8", "--plane", "physical", "--A-min", "2", "--out", str(stem)], capsys)
    assert_one_line_error(code, err, "A_min", "2.4525", "got (2,")
