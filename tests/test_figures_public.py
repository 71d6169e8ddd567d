"""Figure 7's magnified zones, zooming the chart, and the public plotting API (data, not pixels)."""
import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from kapitza import zone_edges  # noqa: E402
from kapitza.figures import chart  # noqa: E402
from kapitza.paper import data as D  # noqa: E402


@pytest.fixture(scope="module")
def fig7():
    return D.figure7_data()


@pytest.mark.parametrize("n", [1, 2, 3])
def test_figure7_magnifies_zones_1_to_3_with_two_distinct_edges(fig7, n):
    panel = f"zoom {n}"
    assert panel in fig7.axes
    lo = fig7.series_named(f"zone {n} lower [{panel}]")
    hi = fig7.series_named(f"zone {n} upper [{panel}]")
    # Drawn units: the wider edge spans 1..10 units, so the panel (+-1.15 x widest) shows it.
    span = float(np.max(hi.x))
    assert 1.0 <= span < 10.0
    # The two edges are distinct curves: apart by more than 10 % of the panel for mu < 0.3.
    low_mu = lo.y < 0.3
    assert np.all(hi.x[low_mu] - lo.x[low_mu] > 0.1 * span)
    assert lo.meta["period"] != hi.meta["period"]
    # The offsets map back to the exact edges (kapitza.zone_edges) at every sample.
    e_lo, e_hi = zone_edges(lo.y, n)
    np.testing.assert_allclose(lo.meta["eps"], e_lo, rtol=1e-14)
    np.testing.assert_allclose(hi.meta["eps"], e_hi, rtol=1e-14)
    scale = 10.0 ** lo.meta["exponent"]
    np.testing.assert_allclose(hi.x - lo.x, (e_hi - e_lo) / scale, rtol=1e-9, atol=1e-9)


def test_figure7_main_panel_edges_merge_but_zooms_do_not(fig7):
    # On the main panel zone 1 is narrower than 0.5 % of the window: why it needs a zoom.
    lo = fig7.series_named("zone 1 lower")
    hi = fig7.series_named("zone 1 upper")
    assert np.max(hi.x - lo.x) < 0.005 * 4.0


def test_chart_zoom_window_recomputes_edges_densely():
    # The --help zoom example: zone 1 fills the window with both edges inside it.
    c = chart.zone_curves((1.65, 1.8), (0.0, 0.35), 400)
    i = list(c.n).index(1)
    inside = (c.eps_lo[i] >= 1.65) & (c.eps_hi[i] <= 1.8)
    assert np.count_nonzero(inside) > 300
    assert np.all(c.eps_hi[i][inside] - c.eps_lo[i][inside] > 1e-3)
    # A narrow eps window crossed by a steep edge still gets many exact samples of it.
    c = chart.zone_curves((2.3, 2.301), (0.0, 1.0), 400)
    i = list(c.n).index(1)
    crossing = (c.eps_lo[i] >= 2.3) & (c.eps_lo[i] <= 2.301)
    assert np.count_nonzero(crossing) >= 100
    e_lo, _ = zone_edges(c.mu[crossing], 1)
    np.testing.assert_allclose(c.eps_lo[i][crossing], e_lo, rtol=1e-14)


def test_magnified_zones_picks_thin_visible_zones():
    assert chart.magnified_zones((0.0, 4.0), (0.0, 1.0)) == [1, 2, 3]
    assert chart.magnified_zones((1.65, 1.8), (0.0, 0.35)) == []


# ------------------------------------------------------------------ Figures 3, 4 and 8
@pytest.fixture(scope="module")
def dyn():
    return {n: D.ALL_FIGURES[n]() for n in (2, 3, 4, 5)}


def _arc(d):
    return next(s for s in d.series if s.role == "hyperbolic arc" and s.meta.get("period", 1) == 1)


@pytest.mark.parametrize("n", [3, 4])
def test_hyperbolic_arc_visibly_off_its_asymptotes(dyn, n):
    d = dyn[n]
    s = _arc(d)
    # Distance of the arc from the nearer asymptote y = +-x, at its closest approach to the origin.
    k = int(np.argmin(np.hypot(s.x, s.y)))
    gap = min(abs(s.x[k] - s.y[k]), abs(s.x[k] + s.y[k])) / np.sqrt(2.0)
    r = max(np.max(np.hypot(q.x, q.y)) for q in d.series)
    assert gap > 0.02 * 1.22 * r  # a visible margin on the main panel
    zoom = d.parameters["zoom"]
    assert zoom is not None and gap > 0.15 * zoom  # and a large one on the magnified panel
    assert d.parameters["w_h"] * d.parameters["T"] < 6.5  # lower than at A = 30 (7.1)


def test_case_b_turns_on_the_y_axis_case_a_on_the_x_axis(dyn):
    for n, case in ((2, "a"), (3, "b"), (4, "a"), (5, "b")):
        s = _arc(dyn[n])
        k = int(np.argmin(np.hypot(s.x, s.y)))
        assert dyn[n].parameters["case"] == case
        if case == "a":
            assert s.x[k] > 0 and abs(s.y[k]) < 0.05 * s.x[k]
        else:
            assert s.y[k] < 0 and abs(s.x[k]) < 0.05 * abs(s.y[k])


@pytest.mark.parametrize("n", [4, 5])
def test_second_period_on_its_own_panel_and_legend_matches_strokes(dyn, n):
    from matplotlib.colors import to_hex

    from kapitza.paper import figures as F

    fig, d = F.make_figure(n, dyn[n])
    try:
        first, second = fig.axes[0], fig.axes[1]
        p2 = [s for s in d.series if s.meta.get("period") == 2]
        assert p2
        for s in p2:  # every second-period stroke is on the second panel only
            on = lambda a: any(np.array_equal(ln.get_xdata(), s.x) for ln in a.get_lines())  # noqa: E731
            assert on(second) and not on(first)
        legends = fig.legends or [a.get_legend() for a in fig.axes if a.get_legend()]
        assert len(legends) == 1
        drawn = {ln.get_label(): to_hex(ln.get_color()) for a in fig.axes for ln in a.get_lines()}
        for h, t in zip(legends[0].legend_handles, legends[0].get_texts()):
            assert to_hex(h.get_color()) == drawn[t.get_text()]
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def test_figure8_says_what_it_draws_instead_of_reference_6_and_hides_no_line():
    from kapitza.paper import figures as F
    from kapitza.paper.build import FIGURE8_NOTE

    d = D.figure8_data(points=200)
    assert "[6]" in d.caption and "not drawn" in d.caption
    assert "[6]" in FIGURE8_NOTE
    fig, _ = F.make_figure(8, d)
    try:
        right = fig.axes[1]
        kap = next(ln for ln in right.get_lines() if ln.get_label().startswith("Kapitza"))
        ref = next(ln for ln in right.get_lines() if "leading error" in ln.get_label())
        # The reference lies on Kapitza's error curve: it must be drawn so that both stay visible.
        assert ref.get_linestyle() == "None" and ref.get_marker() == "o" and ref.get_zorder() > kap.get_zorder()
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


# ------------------------------------------------------------------ the public plotting API
def _plot_calls():
    """Each public plot_* function with arguments small enough for a test."""
    from kapitza.figures.drives import drive_curves
    from kapitza.motion import basin, simulate, stroboscopic_map

    P = dict(T=0.15, A=100.0, l=1.0, g=9.81)
    traj = simulate(0.1, 0.0, **P, periods=2, points_per_period=40)
    lin = simulate(0.1, 0.0, **P, periods=2, points_per_period=40, model="linear")
    orb = stroboscopic_map(np.linspace(0.05, 0.3, 3), 0.0, **P, periods=20, every=1)
    bas = basin(**P, periods=3, tol=0.5, n_theta=8, n_dtheta=8, model="linear")
    curves = drive_curves("square", np.linspace(0.01, 0.9, 40), 2.0)
    return {
        "plot_zones": (lambda f, ax, **kw: f(ax, (0.0, 3.0), points=80, **kw), True),
        "plot_zones_physical": (lambda f, ax, **kw: f(ax, points=80, **kw), True),
        "plot_tongue": (lambda f, ax, **kw: f(1, ax, points=60), False),
        "plot_drive_comparison": (lambda f, ax, **kw: f([curves], ax, eps_range=(0.0, 2.0), **kw), True),
        "plot_time_series": (lambda f, ax, **kw: f(traj, ax, linear=lin, tol=0.3, **kw), True),
        "plot_pivot": (lambda f, ax, **kw: f(traj, ax), False),
        "plot_phase_portrait": (lambda f, ax, **kw: f(traj, ax, **kw), True),
        "plot_strobe": (lambda f, ax, **kw: f(orb, ax), False),
        "plot_basin": (lambda f, ax, **kw: f(bas, ax), False),
    }


def test_figures_exports_its_functions():
    import kapitza.figures as KF

    for name in KF.__all__:
        assert callable(getattr(KF, name)), name
    plots = {n for n in KF.__all__ if n.startswith("plot_")}
    assert plots == set(_plot_calls())


def test_every_plot_function_takes_ax_and_returns_drawn_with_legend_inside():
    import matplotlib.pyplot as plt

    import kapitza.figures as KF

    for name, (call, has_legend) in _plot_calls().items():
        fig, ax = plt.subplots(figsize=(5, 4))
        try:
            kw = {"legend": "inside"} if has_legend else {}
            drawn = call(getattr(KF, name), ax, **kw)
            assert isinstance(drawn, KF.Drawn), name
            assert drawn.ax is ax and drawn.data is not None, name
            assert drawn and all(v is not None for v in drawn.values()), name
            if has_legend:
                leg = drawn["legend"]
                assert leg is ax.get_legend(), name
                fig.canvas.draw()
                lb, ab = leg.get_window_extent(), ax.get_window_extent()
                assert ab.x0 <= lb.x0 and lb.x1 <= ab.x1 and ab.y0 <= lb.y0 and lb.y1 <= ab.y1, name
        finally:
            plt.close(fig)


def test_import_kapitza_figures_does_not_load_every_submodule():
    import subprocess
    import sys

    code = ("import sys, kapitza.figures as F; assert 'kapitza.figures.animation' not in sys.modules; "
            "F.plot_zones; assert 'kapitza.figures.chart' in sys.modules; "
            "assert 'kapitza.figures.animation' not in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)


# ------------------------------------------------------------------ captions
def test_captions_typeset_their_maths():
    import re

    for n, make in D.ALL_FIGURES.items():
        text = make().caption
        assert text.count("$") % 2 == 0, n
        outside = " ".join(text.split("$")[::2])
        for raw in (r"\bw_h", r"\bw_e", r"\btheta", r"\beps\b", r"\bmu\b", r"\^", r"\bpi\b", r"\bphi_", r"\bsqrt",
                    "->", "T~"):
            assert not re.search(raw, outside), (n, raw)
        assert not re.search(r"[A-Za-z]_[A-Za-z0-9{]", outside), n


@pytest.mark.parametrize("n", [1, 8])
def test_caption_clear_of_the_axes_with_no_blank_band_and_no_orphan(n):
    import matplotlib.pyplot as plt

    from kapitza.figures._style import wrap_caption
    from kapitza.paper import figures as F

    fig, d = F.make_figure(n)
    try:
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        cap = next(a for a in fig.artists if hasattr(a, "get_child")).get_window_extent(r)
        lowest = min([ax.get_tightbbox(r).y0 for ax in fig.axes] + [lg.get_window_extent(r).y0 for lg in fig.legends])
        gap = (lowest - cap.y1) / fig.dpi
        assert 0.0 < gap < 0.35  # clear of the axes, and no blank band between
        assert cap.y0 / fig.dpi < 0.15  # and none below it
        assert fig.kapitza_caption.startswith(f"Figure {n}. ")
    finally:
        plt.close(fig)
    lines = wrap_caption(f"Figure {n}. {d.caption}", 100)
    assert len(lines[-1]) > 0.5 * max(len(ln) for ln in lines)  # balanced: no orphan last line


def test_report_title_has_no_literal_asterisks():
    from kapitza.paper.report import Para, to_html

    html = to_html([Para("L. C. and L. H., *On the existence of periodic motions* (2017). **All checks passed.**")],
                   None, "t")
    assert "*" not in html and "<em>On the existence of periodic motions</em>" in html


def test_physical_chart_magnifies_its_thin_zones():
    import matplotlib.pyplot as plt

    l, g = 1.0, 9.81
    T_win, A_win = (0.0, 2.5 * np.sqrt(l / g)), (g, 50 * g)
    assert chart.magnified_zones_physical(T_win, A_win, l, g) == [1, 2, 3]
    assert chart.magnified_zones_physical((0.0, 0.2), (50.0, 400.0), l, g) == []  # zone 0 only: nothing thin
    fig, ax = plt.subplots()
    try:
        mu_win = (np.sqrt(g / A_win[1]), 1.0)
        d = chart.plot_tongue(2, ax, mu_win, points=200, physical=(l, g))
        x_lo, A = d["lower"].get_data()
        x_hi, _ = d["upper"].get_data()
        np.testing.assert_allclose(A, g / d.data.mu**2)
        span = np.max(x_hi)
        assert 1.0 <= span < 10.0 and ax.get_yscale() == "log"
        mid = (A > 30.0) & (A < 300.0)
        assert np.all(x_hi[mid] - x_lo[mid] > 0.1 * span)  # two distinct edges where the zone is open
        exp = int(ax.get_xlabel().split("10^{")[1].split("}")[0])
        width_T = (d.data.eps_hi - d.data.eps_lo) * np.sqrt(8 * l / A)
        np.testing.assert_allclose((x_hi - x_lo) * 10.0**exp, width_T, rtol=1e-9, atol=1e-300)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("drive, zeta", [("sine", 0.0), ("rectangular:0.3", 0.0), (None, 0.05)])
def test_a_tongue_of_another_drive_or_damped_is_that_drives_zone(drive, zeta):
    import matplotlib.pyplot as plt
    from kapitza.figures import plot_tongue, tongue_curves

    t = tongue_curves(1, (0.05, 0.6), 12, drive=drive, zeta=zeta)
    lo, hi = zone_edges(t.mu, 1, drive=drive, zeta=zeta)
    np.testing.assert_allclose(t.eps_lo, lo, rtol=1e-12)
    np.testing.assert_allclose(t.eps_hi, hi, rtol=1e-12)
    square_lo, _ = zone_edges(t.mu, 1)
    assert np.all(np.abs(t.eps_lo - square_lo) > 1e-6)          # not the square wave's tongue
    assert np.nanmax(t.hi) < 10.0 and np.nanmax(t.hi) >= 1.0    # scaled to fill the panel
    fig, ax = plt.subplots()
    drawn = plot_tongue(1, ax, (0.05, 0.6), points=12, drive=drive, zeta=zeta)
    assert drawn.data.eps_lo[3] == t.eps_lo[3]
    assert ax.get_xlabel() and ax.get_ylabel()
    plt.close(fig)


def test_drive_comparison_legend_says_what_the_dashed_lines_are():
    import matplotlib.pyplot as plt
    from kapitza.figures import drive_curves, plot_drive_comparison

    mu = np.linspace(0.05, 0.9, 12)
    fig, ax = plt.subplots()
    out = plot_drive_comparison([drive_curves("sine", mu, eps_max=2.0)], ax, eps_range=(0, 2))
    texts = [t.get_text() for t in out["legend"].get_texts()]
    assert any("averaging" in t for t in texts) and any("sine" in t for t in texts)
    fig2, ax2 = plt.subplots()
    out = plot_drive_comparison([drive_curves("sine", mu, eps_max=2.0)], ax2, eps_range=(0, 2), averaging=False)
    assert not any("averaging" in t.get_text() for t in out["legend"].get_texts())
    plt.close("all")
