"""The tower from the other commands: ``kapitza chart --chain`` (the band on the rig plane, its
files and data) and ``kapitza simulate/animate --chain`` (the full motion), through the real CLI."""
import csv
import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import kapitza
from kapitza import Chain
from kapitza.chain import tower_curves
from cli_util import assert_one_line_error, run


def _csv(path):
    """The header and rows of a CSV file written by kapitza (``#`` lines are comments)."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    return rows[0], rows[1:]


def _check_png(path):
    from PIL import Image

    with Image.open(path) as im:
        im.verify()
    with Image.open(path) as im:
        assert im.format == "PNG" and im.size[0] > 300 and im.size[1] > 200


# ====================================================================== kapitza chart --chain
def test_chart_chain_writes_every_format_and_its_data_agree_with_tower_curves(tmp_path, capsys):
    stem = tmp_path / "tower"
    code, out, err = run(["chart", "--chain", "0.2,0.2,0.2", "--plane", "rig", "--points", "40", "--grid", "24",
                          "--pdf", "--title", "Three rods", "--out", str(stem)], capsys)
    assert code == 0, err
    assert "wrote" in out and "tower.json" in out
    _check_png(tmp_path / "tower.png")
    assert ET.parse(tmp_path / "tower.svg").getroot().tag.endswith("svg")
    assert (tmp_path / "tower.pdf").read_bytes()[:5] == b"%PDF-"
    data = json.loads((tmp_path / "tower.json").read_text())
    assert data["chain"]["lengths"] == [0.2, 0.2, 0.2] and data["g"] == 9.81 and "report" not in data
    # the towers of 1, 2 and 3 links, each recomputed independently of the command on the same window
    assert [len(c["modal_lengths"]) for c in data["curves"]] == [1, 2, 3]
    fr, sr = tuple(data["curves"][0]["frequency_range"]), tuple(data["curves"][0]["stroke_range"])
    header, rows = _csv(tmp_path / "tower.csv")
    assert header == ["links", "mode", "l", "edge", "mu", "frequency", "stroke"]
    for n, got in zip((1, 2, 3), data["curves"]):
        ref = tower_curves(Chain([0.2] * n), frequency_range=fr, stroke_range=sr, points=40, grid=24)
        assert got["modal_lengths"] == pytest.approx(list(ref.modal_lengths), rel=1e-14)
        assert np.array(got["band"]["stable"], dtype=bool).tolist() == ref.stable.tolist()
        assert got["band"]["stable"] and 0 < np.mean(got["band"]["stable"]) < 1  # the band is there, not everything
        for k in range(n):
            lo = np.array([np.nan if v is None else v for v in got["modes"][k]["lower"]["frequency"]])
            np.testing.assert_allclose(lo, ref.frequency_lo[k], rtol=1e-13)
        mine = [r for r in rows if int(r[0]) == n]
        want = list(ref.rows())
        assert len(mine) == len(want)
        for r, w in zip(mine, want):
            assert (int(r[1]), r[3]) == (w[0], w[2])
            np.testing.assert_allclose([float(x) for x in (r[2], r[4], r[5], r[6])], [w[1], w[3], w[4], w[5]],
                                       rtol=1e-15)


def test_chart_chain_marks_a_point_with_the_towers_verdict(tmp_path, capsys):
    stem = tmp_path / "double"
    code, out, err = run(["chart", "--chain", "0.2,0.2", "--links", "point", "--masses", "1,0.5", "--only",
                          "--frequency", "60", "--stroke", "0.02", "--points", "30", "--grid", "16",
                          "--out", str(stem)], capsys)
    assert code == 0, err
    ch = Chain([0.2, 0.2], [1, 0.5], links="point")
    rep = ch.analyze(frequency=60, stroke=0.02)
    assert rep.verdict in out
    data = json.loads((tmp_path / "double.json").read_text())
    assert data["report"]["stable"] is rep.stable and len(data["curves"]) == 1
    assert data["chain"]["links"] == "point" and data["chain"]["masses"] == [1.0, 0.5]
    # the window holds the point
    fr, sr = data["curves"][0]["frequency_range"], data["curves"][0]["stroke_range"]
    assert fr[0] < 60 < fr[1] and sr[0] < 0.02 < sr[1]
    _check_png(tmp_path / "double.png")


def test_chart_chain_window_and_amplitude_axis(tmp_path, capsys):
    code, _, err = run(["chart", "--chain", "0.3,0.2", "--frequency-min", "10", "--frequency-max", "500",
                        "--stroke-min", "0.001", "--stroke-max", "0.1", "--amplitude-axis", "--drive", "sine",
                        "--points", "30", "--grid", "12", "--only", "--out", str(tmp_path / "w")], capsys)
    assert code == 0, err
    data = json.loads((tmp_path / "w.json").read_text())
    assert data["curves"][0]["frequency_range"] == [10.0, 500.0] and data["curves"][0]["stroke_range"] == [0.001, 0.1]
    assert "sine" in data["drive"]["description"]


def test_chart_without_chain_is_the_single_pendulums(tmp_path, capsys):
    code, _, err = run(["chart", "--points", "50", "--no-magnify", "--out", str(tmp_path / "c")], capsys)
    assert code == 0, err
    assert not (tmp_path / "c.json").exists()
    header, _ = _csv(tmp_path / "c.csv")
    assert "links" not in header


@pytest.mark.parametrize("argv, needles", [
    (["--chain", "0.2,0.2", "--plane", "arnold"], ["--plane rig", "arnold"]),
    (["--chain", "0.2,0.2", "--plane", "physical"], ["--plane rig", "physical"]),
    (["--masses", "1,2"], ["--masses", "--chain"]),
    (["--links", "point"], ["--links", "--chain"]),
    (["--joint-damping", "0.1"], ["--joint-damping", "--chain"]),
    (["--only"], ["--only", "--chain"]),
    (["--grid", "20"], ["--grid", "--chain"]),
    (["--chain", "0.2,x"], ["--chain", "0.2,x"]),
    (["--chain", ","], ["--chain"]),
    (["--chain", "0.2,-1"], ["lengths"]),
    (["--chain", "0.2", "--masses", "1,2"], ["masses"]),
    (["--chain", "0.2", "--links", "chain"], ["--links"]),
    (["--chain", "0.2", "--joint-damping", "-1"], ["joint_damping"]),
    (["--chain", "0.2", "--joint-damping", "inf"], ["--joint-damping"]),
    (["--chain", "0.2", "--rod", "0.3"], ["--rod", "--chain"]),
    (["--chain", "0.2", "--l", "0.5"], ["--l", "--chain"]),
    (["--chain", "0.2", "--zeta", "0.1"], ["--zeta", "--joint-damping"]),
    (["--chain", "0.2", "--damping", "0.1"], ["--damping", "--joint-damping"]),
    (["--chain", "0.2", "--mark-eps", "0.5", "--mark-mu", "0.3"], ["--mark-eps"]),
    (["--chain", "0.2", "--frequency", "50"], ["--frequency", "--stroke"]),
    (["--chain", "0.2", "--frequency", "-5", "--stroke", "0.01"], ["frequency"]),
    (["--chain", "0.2", "--mark-T", "0.01"], ["--mark-T", "--mark-A"]),
    (["--chain", "0.2", "--frequency", "50", "--rpm", "3000", "--stroke", "0.01"], ["--rpm"]),
    (["--chain", "0.2", "--frequency-min", "100", "--frequency-max", "10"], ["--frequency-min"]),
    (["--chain", "0.2", "--stroke-min", "0"], ["--stroke-min"]),
    (["--chain", "0.2", "--grid", "1"], ["--grid"]),
    (["--chain", "0.2", "--grid", "99999"], ["--grid"]),
    (["--chain", "0.2", "--points", "1"], ["--points"]),
    (["--chain", "0.2", "--g", "0"], ["g"]),
])
def test_chart_chain_bad_input_is_one_line(argv, needles, tmp_path, capsys):
    code, _, err = run(["chart", *argv, "--out", str(tmp_path / "x")], capsys)
    assert_one_line_error(code, err, *needles)
    assert not list(tmp_path.iterdir())


# ====================================================================== kapitza simulate --chain
def test_simulate_chain_is_chain_motion_and_writes_its_files(tmp_path, capsys):
    stem = tmp_path / "run"
    code, out, err = run(["simulate", "--chain", "0.2,0.2", "--frequency", "60", "--stroke", "0.02", "--theta0", "0.15",
                          "--periods", "15", "--points-per-period", "20", "--out", str(stem)], capsys)
    assert code == 0, err
    ch = Chain([0.2, 0.2])
    rep = ch.analyze(frequency=60, stroke=0.02)
    ref = kapitza.chain_motion(ch, 0.15, T=rep.T, A=rep.A, periods=15, points_per_period=20)
    assert rep.stable and not ref.toppled
    assert rep.verdict in out and "stands" in out
    header, rows = _csv(tmp_path / "run.csv")
    assert header == ["t", "pivot", "theta1", "theta2", "dtheta1", "dtheta2"]
    got = np.array(rows, dtype=float).T
    np.testing.assert_array_equal(got[0], ref.t)
    np.testing.assert_array_equal(got[2:4], ref.theta)
    np.testing.assert_array_equal(got[4:6], ref.dtheta)
    np.testing.assert_array_equal(got[1], ref.pivot)
    summary = json.loads((tmp_path / "run.json").read_text())
    assert summary["report"]["stable"] is True and summary["motion"]["toppled"] is False
    assert summary["parameters"]["given"] == "stroke" and summary["parameters"]["frequency"] == pytest.approx(60)
    assert summary["motion"]["largest_tilt"] == pytest.approx(float(np.max(np.abs(ref.theta))), rel=1e-15)
    _check_png(tmp_path / "run-series.png")
    assert ET.parse(tmp_path / "run-series.svg").getroot().tag.endswith("svg")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run-series.png", "run-series.svg", "run.csv", "run.json"]


def test_simulate_chain_starts_link_by_link(capsys):
    """--theta0 and --dtheta0 as one value per link: the motion is chain_motion's from those angles and
    rates, and the summary names them."""
    code, out, err = run(["simulate", "--chain", "0.2,0.15,0.1", "--frequency", "150", "--stroke", "0.008",
                          "--theta0", "0.1,-0.05,0.2", "--dtheta0", "0,0.5,-1", "--periods", "30",
                          "--points-per-period", "10", "--json"], capsys)
    assert code == 0, err
    s = json.loads(out)
    assert s["start"]["theta0"] == [0.1, -0.05, 0.2] and s["start"]["dtheta0"] == [0.0, 0.5, -1.0]
    ch = Chain([0.2, 0.15, 0.1])
    rep = ch.analyze(frequency=150, stroke=0.008)
    ref = kapitza.chain_motion(ch, [0.1, -0.05, 0.2], [0.0, 0.5, -1.0], T=rep.T, A=rep.A, periods=30,
                               points_per_period=10)
    assert s["motion"]["largest_tilt"] == pytest.approx(float(np.max(np.abs(ref.theta))), rel=1e-15)
    assert s["motion"]["final"]["theta"] == pytest.approx(list(ref.theta[:, -1]), rel=1e-15)
    code, out, err = run(["simulate", "--chain", "0.2,0.15,0.1", "--frequency", "150", "--stroke", "0.008",
                          "--theta0", "0.1,-0.05,0.2", "--periods", "30"], capsys)
    assert code == 0, err
    assert "theta0 = (0.1, -0.05, 0.2) rad (link by link)" in out


def test_simulate_chain_topples_below_the_band_along_the_mode(capsys):
    code, out, err = run(["simulate", "--chain", "0.2,0.2", "--T", "0.025", "--A", "128", "--along-mode", "--theta0",
                          "0.2", "--periods", "12", "--json"], capsys)
    assert code == 0, err
    s = json.loads(out)
    ch = Chain([0.2, 0.2])
    shape = ch.mode_shapes[:, 0] / np.max(np.abs(ch.mode_shapes[:, 0]))
    assert s["start"]["theta0"] == pytest.approx(list(0.2 * shape), rel=1e-15) and s["start"]["along_mode"]
    assert s["report"]["stable"] is False and s["motion"]["toppled"] is True
    ref = kapitza.chain_motion(ch, 0.2 * shape, T=0.025, A=128, periods=12,
                               points_per_period=max(8, min(200, int(2000 / 12) + 1)))
    assert s["motion"]["t_topple"] == pytest.approx(ref.t_topple, rel=1e-12)


def test_simulate_chain_default_duration_and_drives(capsys):
    # no --periods: about 3 s of motion, whatever the frequency; a sine drive and a drive file's shape alike
    code, out, err = run(["simulate", "--chain", "0.2", "--drive", "sine", "--frequency", "40", "--amplitude", "0.01",
                          "--json"], capsys)
    assert code == 0, err
    s = json.loads(out)
    assert s["motion"]["duration"] == pytest.approx(3.0, rel=1e-9)
    assert "sine" in s["drive"]["description"] and s["parameters"]["given"] == "amplitude"
    # one link is the single pendulum: its verdict is kapitza.analyze's for the rod
    rod = kapitza.Pendulum.uniform_rod(0.2)
    assert s["report"]["stable"] == bool(kapitza.analyze(T=s["parameters"]["T"], A=s["parameters"]["A"], l=rod.l,
                                                         drive="sine").stable)


@pytest.mark.parametrize("argv, needles", [
    (["--chain", "0.2", "--eps", "0.5", "--mu", "0.3"], ["--eps", "--frequency"]),
    (["--chain", "0.2"], ["--chain", "--frequency"]),
    (["--chain", "0.2", "--frequency", "50"], ["--stroke"]),
    (["--chain", "0.2", "--T", "0.01"], ["--T", "--A"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--model", "linear"], ["--chain", "nonlinear"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--method", "exact"], ["--method exact"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--rod", "0.3"], ["--rod"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--l", "0.3"], ["--l"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--damping", "0.3"], ["--damping", "--joint-damping"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--zeta", "0.1"], ["--zeta", "--joint-damping"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--orbits", "3"], ["--orbits"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--periods", "0"], ["--periods"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--periods", "1e9"], ["periods"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--tol", "4"], ["tol"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--rtol", "1"], ["rtol"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--points-per-period", "1"], ["points_per_period"]),
    (["--chain", "0.2,0", "--T", "0.01", "--A", "1000"], ["lengths"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--masses", "1,2"], ["masses"]),
    (["--chain", "0.2", "--T", "0.01", "--A", "1000", "--joint-damping", "-0.1"], ["joint_damping"]),
    (["--chain", "0.2", "--T", "10", "--A", "1e9"], ["T, A and g"]),
    (["--along-mode", "--T", "0.1", "--A", "100"], ["--along-mode", "--chain"]),
    (["--masses", "1", "--T", "0.1", "--A", "100"], ["--masses", "--chain"]),
    (["--chain", "0.2,0.2", "--T", "0.01", "--A", "1000", "--theta0", "0.1,0.2,0.3"], ["--theta0", "one per link", "2"]),
    (["--chain", "0.2,0.2", "--T", "0.01", "--A", "1000", "--dtheta0", "1,2,3"], ["--dtheta0", "one per link"]),
    (["--chain", "0.2,0.2", "--T", "0.01", "--A", "1000", "--theta0", "0.1,x"], ["--theta0", "not a number"]),
    (["--chain", "0.2,0.2", "--T", "0.01", "--A", "1000", "--theta0", "0.1,0.2", "--along-mode"],
     ["--along-mode", "--theta0"]),
    (["--T", "0.1", "--A", "100", "--theta0", "0.1,0.2"], ["--theta0", "--chain"]),
])
@pytest.mark.parametrize("command", ["simulate", "animate"])
def test_motion_chain_bad_input_is_one_line(command, argv, needles, tmp_path, capsys):
    if command == "animate" and "--orbits" in argv:
        argv = [a if a != "--orbits" else "--compare-linear" for a in argv if a != "3"]
        needles = ["--compare-linear"]
    if command == "animate" and "--points-per-period" in argv:
        return  # simulate's option
    out = str(tmp_path / ("x.gif" if command == "animate" else "x"))
    code, _, err = run([command, *argv, "--out", out], capsys)
    assert_one_line_error(code, err, *needles)
    assert not list(tmp_path.iterdir())


# ====================================================================== kapitza animate --chain
def test_animate_chain_writes_the_tower_standing_and_fallen(tmp_path, capsys):
    from PIL import Image

    path = tmp_path / "fall.gif"
    code, out, err = run(["animate", "--chain", "0.2,0.2", "--frequency", "20", "--stroke", "0.02", "--periods", "12",
                          "--fps", "10", "--quiet", "--json", "--out", str(path)], capsys)
    assert code == 0, err
    s = json.loads(out)
    assert s["motion"]["toppled"] is True and s["file"] == str(path) and s["format"] == "gif"
    # the fall is followed by a second of the tower lying where it fell
    assert s["frames"] == int((s["motion"]["duration"] + 1.0) * 10) + 1
    with Image.open(path) as im:
        assert im.format == "GIF" and im.n_frames >= 2
        im.seek(im.n_frames - 1)
        im.convert("RGB").save(tmp_path / "last.png")
    _check_png(tmp_path / "last.png")


def test_animate_chain_mp4_without_ffmpeg_is_the_gif_beside_it(tmp_path, capsys, monkeypatch):
    from kapitza.figures import animation

    monkeypatch.setattr(animation, "ffmpeg_available", lambda: False)  # whether or not this machine has it
    code, out, err = run(["animate", "--chain", "0.2", "--T", "0.01", "--A", "1000", "--periods", "5", "--quiet",
                          "--out", str(tmp_path / "one.mp4")], capsys)
    assert code == 0, err
    assert (tmp_path / "one.gif").stat().st_size > 0 and not (tmp_path / "one.mp4").exists()
    assert "ffmpeg" in err and len(err.strip().splitlines()) == 1
    assert "wrote" in out and "one.gif" in out


def test_animate_chain_mp4_is_a_video_of_every_frame(tmp_path, capsys):
    """With ffmpeg present, ``--out x.mp4`` is an H.264 MP4 holding every frame of the fall and the
    second after it (read back by ffprobe), at an odd pixel size too."""
    import shutil
    import subprocess

    from kapitza.figures.animation import ffmpeg_available

    if not ffmpeg_available() or shutil.which("ffprobe") is None:
        pytest.skip("ffmpeg (with ffprobe) is not installed")
    path = tmp_path / "fall.mp4"
    code, out, err = run(["animate", "--chain", "0.2,0.2", "--frequency", "20", "--stroke", "0.02", "--periods", "12",
                          "--fps", "10", "--dpi", "81", "--quiet", "--json", "--out", str(path)], capsys)
    assert code == 0, err
    s = json.loads(out)
    assert s["format"] == "mp4" and s["file"] == str(path) and s["motion"]["toppled"] is True
    assert not list(tmp_path.glob("*.gif"))
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                            "stream=codec_name,nb_read_frames,width,height", "-of", "json", str(path)],
                           capture_output=True, text=True, check=True)
    stream = json.loads(probe.stdout)["streams"][0]
    assert stream["codec_name"] == "h264"
    assert int(stream["nb_read_frames"]) == s["frames"] == int((s["motion"]["duration"] + 1.0) * 10) + 1
    assert stream["width"] > 100 and stream["height"] > 100


def test_animate_chain_out_must_be_an_animation(tmp_path, capsys):
    code, _, err = run(["animate", "--chain", "0.2", "--T", "0.01", "--A", "1000", "--out", str(tmp_path / "x.png")],
                       capsys)
    assert_one_line_error(code, err, "--out", ".gif")


# ====================================================================== help
@pytest.mark.parametrize("command", ["chart", "simulate", "animate"])
def test_help_names_the_tower(command, capsys):
    code, out, _ = run([command, "--help"], capsys)
    assert code == 0
    assert "--chain L1,L2,..." in out and "--joint-damping" in out and "--masses" in out
    assert f"kapitza {command} --chain" in out  # an example
    assert max(len(line) for line in out.splitlines()) <= 130
