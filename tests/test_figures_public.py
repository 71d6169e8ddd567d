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
