"""The tower's band on the rig plane, Acheson's high-frequency criterion as its limit, the chart and ``kapitza tower``."""
import json
import math

import numpy as np
import pytest

import kapitza
from kapitza import Chain
from kapitza.chain import tower_curves
from cli_util import assert_one_line_error, run

G = 9.81
#: Mathieu's q on the edge b_1(q) = 0 (the first 4T-type edge at a = 0): the high-frequency
#: limit of the period-doubling stroke of a pendulum on a sinusoidal pivot, a < (q/2) l
Q_B1 = 0.9080463337


@pytest.mark.parametrize("links", ["rod", "point"])
def test_acheson_high_frequency_limit(links):
    """Acheson (1993): with a sinusoidal pivot of amplitude a and angular frequency W, in the limit
    of high frequency and small amplitude the tower stands iff every mode does, i.e.

        a W > sqrt(2 g l_1)  (the longest mode: Kapitza's criterion)  and  a < (q/2) l_N  (the shortest),

    with ``l_k`` the modal lengths (``g / l_k`` the hanging natural frequencies squared) and
    ``q = 0.90805`` Mathieu's first period-doubling edge. The exact band approaches both."""
    ch = Chain([0.2, 0.15, 0.1, 0.08], [1.0, 0.8, 0.5, 0.3], links=links)
    l1, lN = ch.modal_lengths[0], ch.modal_lengths[-1]
    errs = []
    for f in (500.0, 4000.0):
        W = 2 * math.pi * f
        a_lo, a_hi = math.sqrt(2 * G * l1) / W, 0.5 * Q_B1 * lN
        r = ch.analyze(frequency=f, amplitude=math.sqrt(a_lo * a_hi), drive="sine")
        assert r.stable
        errs.append((r.stroke_lo / 2 / a_lo - 1, r.stroke_hi / 2 / a_hi - 1))
    (lo1, hi1), (lo2, hi2) = errs
    assert abs(lo2) < 1e-4 and abs(hi2) < 1e-4
    # and the errors shrink as the frequency grows (corrections of order g / (a W^2) and a / l)
    assert abs(lo2) < abs(lo1) and abs(hi2) < abs(hi1)


def test_square_wave_high_frequency_limit():
    """The same limit for the paper's square wave: its averaging threshold <v^2> = g l_1 (kapitza.averaging_threshold)
    for the longest mode, and the limit of zone 0's upper edge for the shortest."""
    ch = Chain([0.2, 0.2, 0.2])
    l1, lN = ch.modal_lengths[0], ch.modal_lengths[-1]
    mu = 1e-3
    A = G / mu**2
    eps_K = float(kapitza.averaging_threshold(mu))
    hi = float(kapitza.zone_edges(mu, 0)[1])
    T_lo, T_hi = eps_K * math.sqrt(8 * l1 / A), hi * math.sqrt(8 * lN / A)
    r = ch.analyze(T=math.sqrt(T_lo * T_hi), A=A)
    assert r.stable
    assert r.T_lo == pytest.approx(T_lo, rel=1e-6)
    assert r.T_hi == pytest.approx(T_hi, rel=1e-14)


def test_curves_are_the_modes_as_single_pendulums():
    ch = Chain([0.3, 0.1], links="point")
    c = tower_curves(ch, grid=40, points=50)
    for k, l in enumerate(ch.modal_lengths):
        lo, hi = kapitza.zone_edges(c.mu, 0)
        A = G / c.mu**2
        np.testing.assert_allclose(c.frequency_lo[k], 0.5 / (lo * np.sqrt(8 * l / A)), rtol=1e-13)
        np.testing.assert_allclose(c.stroke_hi[k], 8 * 0.25 * l * hi**2, rtol=1e-13)
    # the band on the grid is the tower's verdict
    rng = np.random.default_rng(3)
    for _ in range(6):
        i, j = rng.integers(0, 40, 2)
        f, s = c.frequency[j], c.stroke[i]
        assert bool(c.stable[i, j]) == ch.analyze(frequency=f, stroke=s).stable
    assert c.stable.any() and not c.stable.all()
    rows = list(c.rows())
    assert {r[0] for r in rows} == {1, 2} and all(np.isfinite(r[4]) for r in rows)
    d = c.as_dict()
    json.dumps(d)
    assert len(d["modes"]) == 2


def test_friction_band_on_a_coarse_grid():
    ch = Chain([0.2, 0.2], joint_damping=0.003)
    c = tower_curves(ch, grid=12, points=20)
    assert c.stable.shape == (12, 12) and c.stable.any()
    i, j = np.argwhere(c.stable)[0]
    assert kapitza.chain_floquet(ch, T=0.5 / c.frequency[j], A=c.stroke[i] / (0.25 * (0.5 / c.frequency[j]) ** 2)).stable


def test_friction_band_grid_is_as_asked_and_bounded():
    """With friction the grid asked for is the grid drawn (60 by default, at most 400), never a silent cap."""
    ch = Chain([0.2, 0.2], joint_damping=0.5)
    window = dict(frequency_range=(10, 1000), stroke_range=(1e-3, 0.1), points=20)
    assert tower_curves(ch, grid=80, **window).stable.shape == (80, 80)
    assert tower_curves(ch, grid=None, **window).stable.shape == (60, 60)
    assert tower_curves(Chain([0.2, 0.2]), **window).stable.shape == (200, 200)
    with pytest.raises(ValueError, match="grid"):
        tower_curves(ch, grid=401, **window)


def test_one_link_band_with_friction_is_the_damped_pendulums():
    """A one-link tower with joint friction c is the pendulum with damping c / I: its band is the
    damped one, which differs from the free band near its edges."""
    ch = Chain([0.2], joint_damping=0.2)
    window = dict(frequency_range=(5, 500), stroke_range=(1e-3, 0.3), points=20, grid=24)
    c = tower_curves(ch, **window)
    free = tower_curves(Chain([0.2]), **window)
    differ = np.argwhere(c.stable != free.stable)
    assert len(differ) >= 3
    rod = kapitza.Pendulum.uniform_rod(0.2)
    for i, j in differ:
        T = 0.5 / c.frequency[j]
        A = c.stroke[i] / (0.25 * T * T)
        assert kapitza.analyze(T=T, A=A, l=rod.l, damping=0.2 / ch.pivot_inertia).stable == c.stable[i, j]


def test_plot_returns_what_it_drew(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from kapitza.figures.tower import plot_tower_chart, tower_chart_figure, tower_family

    ch = Chain([0.2, 0.2, 0.2])
    d = plot_tower_chart(ch, mark=(200.0, 0.005))
    assert len(d["lower"]) == len(d["upper"]) == 3
    assert d.data.n_links == 3 and "mark" in d
    assert d.ax.get_xscale() == "log" and "frequency" in d.ax.get_xlabel()
    chains = tower_family(0.2, n_max=4)
    assert [c.n for c in chains] == [1, 2, 3, 4]
    fig, drawn = tower_chart_figure(chains)
    assert len(drawn) == 4 and "stable" in fig.kapitza_caption
    import matplotlib.pyplot as plt

    plt.close("all")


def test_every_modes_edges_are_labelled_inside_the_window():
    """Both edges of every mode carry their label ("k falls", "k doubles"), inside the panel, even
    where a long mode's upper edge runs near the top of the shared window."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from kapitza.figures.tower import tower_chart_figure, tower_family

    fig, drawn = tower_chart_figure(tower_family(0.2, n_max=4))
    for d in drawn:
        n = d.data.n_links
        texts = sorted(t.get_text() for t in d["labels"])
        assert texts == sorted([f"{k} falls" for k in range(1, n + 1)] + [f"{k} doubles" for k in range(1, n + 1)])
        (x0, x1), (y0, y1) = d.ax.get_xlim(), d.ax.get_ylim()
        for t in d["labels"]:
            x, y = t.xy
            assert x0 < x < x1 and y0 < y < y1, (n, t.get_text(), t.xy)
    plt.close("all")


def test_cli_tower_writes_chart_and_data(tmp_path, capsys):
    stem = tmp_path / "t"
    code, out, err = run(["tower", "--chain", "0.2,0.2", "--frequency", "200", "--stroke", "0.005", "--grid", "30",
                          "--points", "60", "--out", str(stem), "--json"], capsys)
    assert code == 0, err
    rep = json.loads(out)
    assert rep["report"]["stable"] is True and len(rep["report"]["modes"]) == 2
    for suffix in (".png", ".svg", ".csv", ".json"):
        assert (tmp_path / f"t{suffix}").stat().st_size > 0
    data = json.loads((tmp_path / "t.json").read_text())
    assert [c["modal_lengths"] for c in data["curves"]][-1] == pytest.approx(list(Chain([0.2, 0.2]).modal_lengths))
    head = (tmp_path / "t.csv").read_text().splitlines()
    assert any(line.startswith("links,mode,l,edge,mu,frequency,stroke") for line in head)


def test_cli_tower_point_only(capsys):
    code, out, _ = run(["tower", "--chain", "0.2,0.2", "--joint-damping", "0.002", "--T", "0.003", "--A", "3000",
                        "--no-chart"], capsys)
    assert code == 0
    assert "verdict" in out and "multipliers" in out


@pytest.mark.parametrize("argv, needle", [
    (["tower", "--chain", "0.2,-1", "--no-chart"], "lengths"),
    (["tower", "--chain", "0.2,x", "--no-chart"], "--chain"),
    (["tower", "--chain", "0.2", "--masses", "1,2", "--no-chart"], "masses"),
    (["tower", "--frequency", "10", "--no-chart"], "--frequency"),
    (["tower", "--T", "0.1", "--no-chart"], "--T"),
    (["tower", "--joint-damping", "-1", "--no-chart"], "joint_damping"),
    (["tower", "--grid", "99999"], "grid"),
])
def test_cli_tower_bad_input_is_one_line(argv, needle, capsys):
    code, _, err = run(argv, capsys)
    assert_one_line_error(code, err, needle)
