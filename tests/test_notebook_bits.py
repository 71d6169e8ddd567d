"""What a notebook user reaches for: drives in the plot functions, labelled axes on their own Axes,
islands in a strobe plot by default, element-wise arrays, labelled grids."""
import numpy as np
import pytest

import kapitza as K

pytest.importorskip("matplotlib")


def test_plot_zones_takes_a_drive_and_damping():
    import matplotlib.pyplot as plt

    from kapitza.figures.chart import plot_zones

    fig, ax = plt.subplots()
    out = plot_zones(ax, (0.0, 2.0), (0.05, 0.9), points=60, drive="sine", zeta=0.05, legend=None)
    assert out.ax is ax and ax.get_xlabel() and ax.get_ylabel()
    assert len(ax.lines) + len(ax.collections) > 0
    plt.close(fig)


def test_time_series_labels_time_on_a_users_axes():
    import matplotlib.pyplot as plt

    from kapitza.figures.motion import plot_time_series, time_series_figure

    traj = K.simulate(0.1, 0.0, 0.15, 100.0, periods=3)
    fig, ax = plt.subplots()
    plot_time_series(traj, ax)
    assert "t" in ax.get_xlabel() and "θ" in ax.get_ylabel()
    plt.close(fig)
    fig = time_series_figure(traj)   # the figure's time axis is its lower (pivot) panel's
    assert fig.axes[0].get_xlabel() == "" and "t" in fig.axes[1].get_xlabel()
    plt.close(fig)


def test_strobe_keeps_every_period_by_default():
    orbits = K.stroboscopic_map(np.array([0.1, 0.3]), 0.0, 0.15, 100.0, periods=40)
    assert list(orbits.n) == list(range(41))
    assert orbits.theta.shape[0] == 41


def test_nonlinear_stability_element_wise_on_arrays():
    eps = np.array([0.5, 1.0, 1.78, 3.5])
    v = K.nonlinear_stability(eps, 0.3)
    assert list(v.kind) == ["moser", "linearly unstable", "moser", "linearly unstable"]
    assert list(v.stable) == [True, False, True, False] and list(v.unstable) == [False, True, False, True]
    one = K.nonlinear_stability(0.5, 0.3)
    assert v.twist[0] == one.twist and np.isnan(v.twist[1])
    with pytest.raises(ValueError, match="stability zone"):
        K.nonlinear_stability(1.0, 0.3)   # a single point still says why it has no answer


def test_rig_broadcasts_arrays():
    rig = K.Rig(K.Pendulum.uniform_rod(0.25), "sine")
    T, A = rig.physical(frequency=[50.0, 100.0], amplitude=0.003)
    assert T.shape == A.shape == (2,)
    reps = rig.analyze(frequency=np.array([50.0, 100.0]), amplitude=0.003)
    assert reps.shape == (2,) and [r.stable for r in reps] == [False, True]
    T, A = rig.physical(T=0.1, A=100.0)
    assert isinstance(T, np.floating)


def test_stability_grid_as_a_dataarray():
    pytest.importorskip("xarray")
    from kapitza.grids import stability_grid_da

    eps, mu = np.linspace(0.1, 4.0, 50), np.linspace(0.02, 0.98, 40)
    da = stability_grid_da(eps, mu, l=0.5)
    assert da.dims == ("mu", "eps") and da.name == "stable"
    np.testing.assert_array_equal(da.values, K.stability_grid(eps, mu))
    assert da.coords["A"].attrs["units"] == "m/s^2" and da.coords["T"].shape == (40, 50)
    assert da.sel(mu=0.3, eps=0.5, method="nearest").item() is True
    assert "square" in da.attrs["drive"]


def test_the_labelled_grid_is_reachable_from_import_kapitza():
    pytest.importorskip("xarray")
    import sys

    da = K.grids.stability_grid_da(np.array([0.5, 1.2]), np.array([0.3]), drive="sine")
    assert "kapitza.grids" in sys.modules and da.shape == (1, 2) and "sine" in da.attrs["drive"]
