"""The motion commands through the real entry point ``kapitza.cli.main`` (and once as a process)."""
import csv
import json
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import kapitza as K
from cli_util import assert_one_line_error, run
from kapitza.motion import nonlinear_motion


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    return rows[0], rows[1:]


def test_simulate_writes_data_and_figures(tmp_path, capsys):
    stem = tmp_path / "run"
    code, out, err = run(["simulate", "--T", "0.15", "--A", "100", "--theta0", "0.1", "--periods", "4",
                          "--points-per-period", "50", "--orbits", "3", "--strobe-periods", "20", "--out", str(stem)], capsys)
    assert code == 0, err
    assert "stable (zone 0)" in out
    header, rows = read_csv(tmp_path / "run.csv")
    assert header == ["t", "theta", "dtheta", "pivot_y", "theta_linear", "dtheta_linear"]
    data = np.array(rows, dtype=float)
    assert data.shape == (201, 6)
    th, om = nonlinear_motion(data[:, 0], 0.1, 0.0, 0.15, 100.0)
    np.testing.assert_allclose(data[:, 1], th, rtol=0, atol=1e-15)  # written with repr: no digits lost
    lin = np.asarray(K.linear_motion(data[:, 0], 0.1, 0.0, 0.15, 100.0)[0])
    np.testing.assert_allclose(data[:, 4], lin, rtol=0, atol=1e-15)
    header, rows = read_csv(tmp_path / "run-strobe.csv")
    assert header == ["orbit", "k", "theta", "dtheta"] and len(rows) == 3 * 21
    summary = json.loads((tmp_path / "run.json").read_text())
    assert summary["parameters"]["zone"] == 0 and summary["motion"]["method"] == "exact"
    assert summary["motion"]["final"]["theta"] == pytest.approx(th[-1], abs=1e-15)
    for name in ("run-series", "run-phase", "run-strobe"):
        with Image.open(tmp_path / f"{name}.png") as im:
            assert im.size[0] > 500
        assert (tmp_path / f"{name}.svg").read_text().lstrip().startswith("<?xml")


def test_simulate_json_arnold_parameters_and_damping(capsys):
    code, out, err = run(["simulate", "--eps", "0.5", "--mu", "0.3", "--theta0", "0.2", "--damping", "0.5",
                          "--periods", "2", "--points-per-period", "20", "--json"], capsys)
    assert code == 0, err
    d = json.loads(out)
    T, A = K.to_physical(0.5, 0.3)
    assert d["parameters"]["T"] == pytest.approx(float(T)) and d["parameters"]["A"] == pytest.approx(float(A))
    assert d["motion"]["method"] == "dop853" and d["motion"]["c"] == 0.5
    assert d["linear"]["model"] == "linear"


def test_simulate_unstable_linear_overflow_is_reported_not_fatal(capsys):
    code, out, err = run(["simulate", "--T", "2", "--A", "100", "--periods", "200", "--points-per-period", "8",
                          "--json"], capsys)
    assert code == 0, err
    d = json.loads(out)
    assert "range of a double" in d["linear"]


@pytest.mark.parametrize("argv,needles", [
    (["simulate", "--T", "-1", "--A", "100"], ["T must be finite and > 0"]),
    (["simulate", "--eps", "0.5"], ["--eps and --mu must be given together"]),
    (["simulate", "--T", "0.1", "--A", "100", "--damping", "1", "--method", "exact"], ["method='exact'"]),
    (["simulate", "--T", "0.1", "--A", "100", "--periods", "0"], ["periods must lie in [0.001, inf)"]),
    (["simulate", "--T", "0.1", "--A", "100", "--orbits", "0"], ["--orbits must be an integer >= 1"]),
    (["simulate", "--T", "0.1", "--A", "nan"], ["must be finite"]),
    (["basin", "--T", "0.15", "--A", "100", "--tol", "4"], ["tol must lie in"]),
    (["basin", "--T", "0.15", "--A", "100", "--resolution", "1"], ["--resolution must be an integer >= 2"]),
    (["animate", "--T", "0.15", "--A", "100", "--fps", "0"], ["fps must lie in"]),
    (["animate", "--T", "0.15", "--A", "100", "--out", "x.avi"], ["format must be 'gif' or 'mp4'"]),
    # a damping ratio out of range is refused as the ratio given, not as the c it would become
    (["animate", "--T", "0.15", "--A", "100", "--zeta", "1e9"], ["zeta must be a damping ratio <= 10000", "got 1000000000.0"]),
    (["simulate", "--T", "0.15", "--A", "100", "--damping", "-1"], ["damping must be finite and >= 0"]),
])
def test_bad_input_is_one_line_and_status_2(argv, needles, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(argv, capsys)
    assert_one_line_error(code, err, *needles)


def test_animate_writes_a_gif_with_the_promised_frames(tmp_path, capsys):
    out_file = tmp_path / "up.gif"
    code, out, err = run(["animate", "--T", "0.15", "--A", "100", "--periods", "1", "--fps", "10", "--slowdown", "2",
                          "--dpi", "40", "--out", str(out_file), "--json"], capsys)
    assert code == 0, err
    d = json.loads(out)
    assert d["frames"] == 7  # 0.3 s of motion, 2 s of video per s, 10 fps: frames at 0, 0.05, ..., 0.3 s
    with Image.open(out_file) as im:
        assert im.n_frames == d["frames"]
    assert "100%" in err  # the progress bar went to standard error


def test_animate_mp4_falls_back_with_a_message(tmp_path, capsys, monkeypatch):
    from kapitza.figures import animation

    monkeypatch.setattr(animation, "ffmpeg_available", lambda: False)  # whether or not this machine has it
    code, out, err = run(["animate", "--T", "0.15", "--A", "100", "--periods", "0.5", "--fps", "5", "--dpi", "30",
                          "--out", str(tmp_path / "clip.mp4"), "--quiet"], capsys)
    assert code == 0, err
    assert "ffmpeg was not found" in err and "GIF" in err
    assert (tmp_path / "clip.gif").exists() and "clip.gif" in out


@pytest.mark.parametrize("T,stays", [(0.15, True), (0.3, False)])
def test_basin_command_demonstrates_zone_survival(T, stays, tmp_path, capsys):
    stem = tmp_path / "basin"
    code, out, err = run(["basin", "--T", str(T), "--A", "100", "--periods", "30", "--resolution", "21", "--quiet",
                          "--out", str(stem), "--json"], capsys)
    assert code == 0, err
    d = json.loads(out)
    assert d["small_tilt"]["stays_up"] == {"linear": stays, "nonlinear": stays}
    assert [b["model"] for b in d["basins"]] == ["linear", "nonlinear"]
    header, rows = read_csv(tmp_path / "basin.csv")
    assert header == ["model", "theta0", "dtheta0", "survived", "periods_survived"] and len(rows) == 2 * 21 * 21
    frac = np.mean([int(r[3]) for r in rows if r[0] == "nonlinear"])
    assert frac == pytest.approx(d["basins"][1]["fraction"])
    assert (frac > 0.02) == stays
    assert json.loads((tmp_path / "basin.json").read_text())["tol"] == 0.5
    with Image.open(tmp_path / "basin.png") as im:
        assert im.size[0] > 800


def test_commands_are_listed_in_help(capsys):
    code, out, _ = run(["--help"], capsys)
    assert code == 0
    for name in ("simulate", "animate", "basin"):
        assert name in out


def test_simulate_as_a_process():
    proc = subprocess.run([sys.executable, "-m", "kapitza.cli", "simulate", "--T", "0.3", "--A", "100",
                           "--theta0", "0.05", "--periods", "3", "--json"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert d["parameters"]["stable"] is False
    assert d["motion"]["samples"] == 601
    bad = subprocess.run([sys.executable, "-m", "kapitza.cli", "simulate", "--T", "0", "--A", "100"],
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1


def test_simulate_linear_blow_up_gives_growth_per_period_not_turns(capsys):
    code, out, err = run(["simulate", "--T", "0.3", "--A", "100", "--theta0", "0.05", "--periods", "30"], capsys)
    assert code == 0, err
    assert "grows without bound: 3.07 e-folds per period 2T" in out
    assert not any(len(tok) > 12 and tok.isdigit() for tok in out.split())  # no 2.7e37 "turns"
    code, out, err = run(["simulate", "--T", "0.3", "--A", "100", "--theta0", "0.05", "--periods", "30", "--json"],
                         capsys)
    d = json.loads(out)
    assert d["linear"]["turns"] is None and d["linear"]["growth_per_period"] == pytest.approx(3.06997, rel=1e-4)
    assert isinstance(d["motion"]["turns"], int)  # the nonlinear pendulum does turn over


def test_help_names_every_drive_and_the_rig_options(capsys):
    from kapitza.drives import text_forms

    code, out, _ = run(["--help"], capsys)
    assert code == 0
    flat = " ".join(out.split())
    for form in text_forms():
        assert form in flat
    for option in ("--drive-file", "--damping", "--frequency", "--rpm", "--stroke", "--amplitude", "--rod"):
        assert option in flat


def test_package_docstring_names_every_drive():
    import kapitza
    from kapitza.drives import text_forms

    for form in text_forms():
        assert form in kapitza.__doc__
