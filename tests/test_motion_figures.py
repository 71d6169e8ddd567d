"""Pictures of the motion and the animation: files written, frames counted, fallbacks said."""
import io

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from kapitza import KapitzaValueError  # noqa: E402
from kapitza.figures import animation as anim_mod  # noqa: E402
from kapitza.figures._style import save  # noqa: E402
from kapitza.figures.animation import ProgressBar, animate, frame_times  # noqa: E402
from kapitza.figures.motion import (  # noqa: E402
    basin_figure,
    phase_portrait_figure,
    plot_basin,
    plot_phase_portrait,
    plot_strobe,
    plot_time_series,
    strobe_figure,
    time_series_figure,
    wrap_angle,
)
from kapitza.motion import basin, simulate, stroboscopic_map  # noqa: E402

P = dict(T=0.15, A=100.0, l=1.0, g=9.81)


@pytest.fixture(scope="module")
def traj():
    return simulate(0.1, 0.0, **P, periods=3, points_per_period=60)


def test_plot_functions_draw_what_they_return(traj):
    lin = simulate(0.1, 0.0, **P, periods=3, points_per_period=60, model="linear")
    fig, axes = plt.subplots(2, 2)
    out = plot_time_series(traj, axes[0, 0], linear=lin, tol=0.5)
    np.testing.assert_array_equal(out["theta"].get_ydata(), traj.theta)
    assert out["linear"].get_linestyle() == "--"
    pp = plot_phase_portrait(traj, axes[0, 1])
    assert len(pp["strobe"].get_xdata()) == 4  # t = 0, 2T, 4T, 6T
    orb = stroboscopic_map(np.linspace(0.05, 0.3, 4), 0.0, **P, periods=20, every=1)
    st = plot_strobe(orb, axes[1, 0])
    assert len(st["points"]) == 4 and len(st["points"][0].get_xdata()) == 21
    b = basin(**P, periods=5, n_theta=11, n_dtheta=11)
    bs = plot_basin(b, axes[1, 1])
    assert bs["image"].get_array().shape == (11, 11)
    plt.close(fig)


def test_unstable_linear_curve_is_cut_where_it_leaves_the_axes():
    p = dict(P, T=0.3)
    tr = simulate(0.1, 0.0, **p, periods=10)
    lin = simulate(0.1, 0.0, **p, periods=10, model="linear")
    fig, ax = plt.subplots()
    out = plot_time_series(tr, ax, linear=lin)
    lo, hi = ax.get_ylim()
    y = out["linear"].get_ydata()
    assert np.all((y[:-1] >= lo) & (y[:-1] <= hi))  # only the last point may lie off the axes
    assert len(y) < lin.t.size and "grows without bound" in out["linear"].get_label()
    plt.close(fig)


def test_wrap_angle():
    np.testing.assert_allclose(wrap_angle([0.0, np.pi, 3 * np.pi / 2, -np.pi / 2, 7.0]),
                               [0.0, np.pi, -np.pi / 2, -np.pi / 2, 7.0 - 2 * np.pi])


def test_figures_are_written_and_captioned(tmp_path, traj):
    orb = stroboscopic_map(np.linspace(0.05, 0.3, 3), 0.0, **P, periods=10, every=1)
    b = basin(**P, periods=5, n_theta=9, n_dtheta=9)
    for name, fig in (("series", time_series_figure(traj)), ("phase", phase_portrait_figure(traj)),
                      ("strobe", strobe_figure(orb)), ("basin", basin_figure([b, b]))):
        assert "stable (zone 0)" in fig.kapitza_caption.replace("\n", " ")
        paths = save(fig, tmp_path / name)
        plt.close(fig)
        png, svg = paths
        with Image.open(png) as im:
            assert im.size[0] > 500 and im.size[1] > 400
        assert svg.read_text().lstrip().startswith("<?xml")


def test_animation_has_the_promised_frames(tmp_path, traj):
    res = animate(traj, tmp_path / "up.gif", fps=10, slowdown=1.0, dpi=40)
    assert res.format == "gif" and res.message == ""
    assert res.frames == frame_times(traj.t[-1], 10, 1.0).size == 10  # 0.9 s at 10 fps: 0, 0.1, ..., 0.9
    with Image.open(res.path) as im:
        assert im.n_frames == res.frames
        im.seek(0)
        first = np.asarray(im.convert("RGB"))
        im.seek(res.frames - 1)
        last = np.asarray(im.convert("RGB"))
    assert np.any(first != last)


def test_mp4_without_ffmpeg_falls_back_to_gif_and_says_so(tmp_path, traj, monkeypatch):
    monkeypatch.setattr(anim_mod, "ffmpeg_available", lambda: False)
    res = animate(traj, tmp_path / "clip.mp4", fps=5, slowdown=1.0, dpi=30)
    assert res.format == "gif" and res.path.suffix == ".gif" and res.path.exists()
    assert "ffmpeg" in res.message and "GIF" in res.message
    assert not (tmp_path / "clip.mp4").exists()


def test_animation_validates(tmp_path, traj):
    with pytest.raises(KapitzaValueError, match="format"):
        animate(traj, tmp_path / "x.avi")
    with pytest.raises(KapitzaValueError, match="fps"):
        animate(traj, tmp_path / "x.gif", fps=0)
    with pytest.raises(KapitzaValueError, match="frames"):
        animate(traj, tmp_path / "x.gif", slowdown=1e4)


def test_progress_bar_reaches_the_end():
    buf = io.StringIO()
    bar = ProgressBar("render", stream=buf, width=10)
    for i in range(50):
        bar.frame_callback(i, 50)
    text = buf.getvalue()
    assert text.endswith("\n")
    assert "[##########] 100%  50/50" in text.split("\r")[-1]
    quiet = io.StringIO()
    ProgressBar(stream=quiet, enabled=False)(5, 10)
    assert quiet.getvalue() == ""


def test_wrapped_phase_portrait_is_not_joined_across_the_seam():
    tr = simulate(0.1, 0.0, T=0.3, A=100.0, periods=20)  # falls and turns over
    fig, ax = plt.subplots()
    line = plot_phase_portrait(tr, ax)["curve"]
    x = np.asarray(line.get_xdata(), float)
    assert np.isnan(x).sum() >= 10  # one break per turn
    ok = ~np.isnan(x[1:]) & ~np.isnan(x[:-1])
    assert np.max(np.abs(np.diff(x)[ok])) < 1.0  # no segment crosses the plot
    plt.close(fig)


# ------------------------------------------------------------------ the user's orbit, the clock, the GIF kept
def test_strobe_window_frames_the_users_orbit_and_the_island():
    from kapitza.figures.motion import island_members, strobe_window

    orbits = stroboscopic_map(np.linspace(0.05, 0.6, 12), 0.0, **P, periods=120, every=1)
    own = stroboscopic_map(0.1, 0.0, **P, periods=120, every=1)
    keep = island_members(orbits)
    assert 0 < keep.sum() < keep.size  # an island and a sea, at these parameters
    (x0, x1), (y0, y1) = strobe_window(orbits, (own.theta, own.dtheta))
    for th, om in ((own.theta, own.dtheta), (orbits.theta[:, keep], orbits.dtheta[:, keep])):
        assert x0 < np.min(th) and np.max(th) < x1 and y0 < np.min(om) and np.max(om) < y1
    # The window is the island's, not the whole sea's: the subject fills it.
    assert x1 - x0 < 0.5 * 2 * np.pi
    own_span = np.ptp(own.theta) * np.ptp(own.dtheta)
    assert own_span > 0.05 * (x1 - x0) * (y1 - y0)
    fig = strobe_figure(orbits, highlight=(own.theta, own.dtheta))
    try:
        ax = fig.axes[0]
        assert ax.get_xlim() == pytest.approx((x0, x1)) and ax.get_ylim() == pytest.approx((y0, y1))
        text = fig.kapitza_caption
        assert f"{int(keep.sum())} of {keep.size}" in text and "120 periods" in text
    finally:
        plt.close(fig)


def test_strobe_figure_without_island_says_so_and_shows_the_wrapped_map():
    from kapitza.figures.motion import strobe_window

    q = dict(P, T=0.3)
    orbits = stroboscopic_map(np.linspace(0.05, 0.6, 6), 0.0, **q, periods=60, every=1)
    own = stroboscopic_map(0.05, 0.0, **q, periods=60, every=1)
    assert strobe_window(orbits, (own.theta, own.dtheta)) is None
    fig = strobe_figure(orbits, highlight=(own.theta, own.dtheta))
    try:
        assert fig.axes[0].get_xlim() == pytest.approx((-np.pi, np.pi))
        text = fig.kapitza_caption
        assert "no island" in text and "closed curves" not in text
    finally:
        plt.close(fig)


@pytest.mark.parametrize("l, stroke", [(1.0, 0.1), (1.0, 2.25), (0.2, 0.01)])
def test_animation_clock_sits_above_the_bobs_reach(l, stroke):
    xlim, ylim, y_clock = anim_mod._scene_limits(l, stroke)
    reach = 0.5 * stroke + l  # highest the bob can be: pivot at the top of its travel, rod upright
    assert y_clock - 0.03 * l - reach > 0.3 * l  # room for three lines of text and the bob's marker
    assert ylim[1] >= y_clock


def test_mp4_without_ffmpeg_leaves_an_existing_gif_untouched(tmp_path, traj, monkeypatch):
    monkeypatch.setattr(anim_mod, "ffmpeg_available", lambda: False)
    old = tmp_path / "clip.gif"
    old.write_bytes(b"the user's own GIF")
    res = animate(traj, tmp_path / "clip.mp4", fps=5, slowdown=1.0, dpi=30)
    assert old.read_bytes() == b"the user's own GIF"
    assert res.path == tmp_path / "clip-2.gif" and res.path.exists()
    assert str(res.path) in res.message
