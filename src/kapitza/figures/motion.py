"""Pictures of the motion: time series, phase portrait, stroboscopic map, basin.

Each ``plot_*`` function takes ``ax=None`` and returns what it drew; the
``*_figure`` functions lay out a captioned figure for the command line.
Angles are in radians, measured from the upright and counted counter-clockwise.
"""
from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.colors import BoundaryNorm, ListedColormap

from .. import _validate as _v
from ..analysis import analyze
from ._style import Drawn, caption, new_figure, place_legend

__all__ = [
    "wrap_angle",
    "plot_time_series",
    "plot_pivot",
    "plot_phase_portrait",
    "plot_strobe",
    "plot_basin",
    "time_series_figure",
    "phase_portrait_figure",
    "strobe_figure",
    "strobe_window",
    "island_members",
    "basin_figure",
    "parameter_label",
]

NONLINEAR_STYLE: dict[str, Any] = dict(color="#1f4e9c", linewidth=1.2)
LINEAR_STYLE: dict[str, Any] = dict(color="#c0392b", linewidth=1.0, linestyle="--")
PIVOT_STYLE: dict[str, Any] = dict(color="0.3", linewidth=1.0)
WINDOW_STYLE: dict[str, Any] = dict(color="0.55", linewidth=0.8, linestyle=":")
STROBE_MARK = dict(marker="o", markersize=3.5, linestyle="none", color="#e67e22", markeredgecolor="k",
                   markeredgewidth=0.4)


def padded_limits(lo, hi):
    """``(lo, hi)`` widened by 8 % of their span (0.1 where they meet), and by at least a millionth of
    the larger: limits whose ticks stay apart, and short, for an angle of any size."""
    pad = 0.08 * (hi - lo) or 0.1
    pad = max(pad, 1e-6 * max(abs(lo), abs(hi)))
    return lo - pad, hi + pad


def _ax(ax):
    if ax is None:
        fig = new_figure()
        ax = fig.add_subplot()
    return ax


def wrap_angle(theta):
    """``theta`` wrapped into ``(-pi, pi]``."""
    return np.pi - np.mod(np.pi - np.asarray(theta, float), 2.0 * np.pi)


def _broken(theta, other, jump=np.pi):
    """Insert NaN into both where the wrapped angle ``theta`` jumps by more than ``jump``, so
    that a curve is not joined across the seam at +-pi."""
    theta = np.asarray(theta, float)
    other = np.asarray(other, float)
    cut = np.flatnonzero(np.abs(np.diff(theta)) > jump) + 1
    return np.insert(theta, cut, np.nan), np.insert(other, cut, np.nan)


def parameter_label(T, A, l, g, drive=None, damping=0.0):
    """One-line parameter description with the stability verdict of the upright."""
    rep = analyze(T=T, A=A, l=l, g=g, drive=drive, damping=damping)
    return (f"T = {T:g} s, A = {A:g} m/s², l = {l:g} m, g = {g:g} m/s² "
            f"(ε = {rep.eps:.4g}, μ = {rep.mu:.4g}): upright {rep.verdict}")


def _model_label(traj):
    label = "nonlinear" if traj.model == "nonlinear" else "linear (2.3)"
    if traj.c > 0:
        label += f", c = {traj.c:g}/s"
    return label


# ------------------------------------------------------------------ plot functions
def _record(name, value, kind):
    """``value`` if it is the :mod:`kapitza.motion` record ``kind`` a picture draws, else the message."""
    from .. import motion

    if not isinstance(value, getattr(motion, kind)):
        raise _v.KapitzaValueError(f"{name} must be a kapitza.motion.{kind}; got {type(value).__name__}")
    return value


def _legend_choice(legend):
    if legend not in (None, "inside", "outside"):
        raise _v.KapitzaValueError(f"legend must be 'inside', 'outside' or None; got {legend!r}")
    return legend


def _motion_options(traj, linear=None, tol=None):
    """The checked ``(traj, linear, tol)`` of a time-series picture."""
    _record("traj", traj, "Trajectory")
    if linear is not None:
        _record("linear", linear, "Trajectory")
    return traj, linear, None if tol is None else _v.one("tol", _v.positive("tol", tol))


def plot_time_series(traj, ax=None, *, linear=None, tol=None, legend=None):
    """``theta(t)`` of a :class:`kapitza.motion.Trajectory` (and a linear one beside it).

    Parameters
    ----------
    traj : Trajectory
    ax : matplotlib Axes, optional
    linear : Trajectory, optional
        Drawn dashed for comparison.
    tol : float, optional
        Draw the window ``|theta| <= tol`` [rad].
    legend : {None, "inside", "outside"}
        Add a legend inside the axes (best corner) or beside them; None: none.

    Returns
    -------
    Drawn
        The artists by name, with ``.ax`` and ``.data``.

    Raises
    ------
    KapitzaValueError
        If ``traj`` (or ``linear``) is not a :class:`~kapitza.motion.Trajectory`, ``tol`` is not a
        positive number or ``legend`` not one of its choices; nothing is drawn then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import plot_time_series
    >>> traj = kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=10)
    >>> drawn = plot_time_series(traj)
    >>> drawn.data is traj
    True
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    traj, linear, tol = _motion_options(traj, linear, tol)
    _legend_choice(legend)
    ax = _ax(ax)
    out = Drawn(ax, {"theta": ax.plot(traj.t, traj.theta, label=_model_label(traj), **NONLINEAR_STYLE)[0]}, data=traj)
    lo, hi = float(np.min(traj.theta)), float(np.max(traj.theta))
    if tol is not None:
        lo, hi = min(lo, -tol), max(hi, tol)
    lo, hi = padded_limits(lo, hi)
    if linear is not None:
        label = _model_label(linear)
        off = np.flatnonzero((linear.theta < lo) | (linear.theta > hi))
        end = linear.t.size
        if off.size:
            # An unstable linear motion grows without bound; keep the axes on the motion
            # drawn in full, stop the linear curve where it leaves and say when.
            label += f", grows without bound: off the plot from t = {linear.t[off[0]]:.3g} s"
            end = off[0] + 1
        out["linear"] = ax.plot(linear.t[:end], linear.theta[:end], label=label, **LINEAR_STYLE)[0]
    ax.set_ylim(lo, hi)
    if tol is not None:
        out["window"] = [ax.axhline(s * tol, **WINDOW_STYLE) for s in (-1, 1)]
        out["window"][0].set_label(f"window |θ| ≤ {tol:g} rad")
    ax.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
    ax.set_xlim(traj.t[0], traj.t[-1])
    ax.set_ylabel("θ  (rad from upright)")
    ax.set_xlabel("t  (s)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    return _legend(out, legend)


def _legend(out, legend):
    """Add the legend asked for (``"inside"``, ``"outside"`` or None) to a :class:`Drawn`."""
    if _legend_choice(legend):
        out["legend"] = place_legend(out.ax, inside=(legend == "inside"))
    return out


def plot_pivot(traj, ax=None):
    """Pivot height ``y(t)`` [mm] above its mean position.

    Parameters
    ----------
    traj : Trajectory
        From :func:`kapitza.simulate`.
    ax : matplotlib Axes, optional

    Returns
    -------
    Drawn
        ``{"pivot": line}``, with ``.ax`` and ``.data`` (the trajectory).

    Raises
    ------
    KapitzaValueError
        If ``traj`` is not a :class:`~kapitza.motion.Trajectory`; nothing is drawn then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import plot_pivot
    >>> drawn = plot_pivot(kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=2))
    >>> sorted(drawn), drawn.ax.get_ylabel()
    (['pivot'], 'pivot y  (mm)')
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    _record("traj", traj, "Trajectory")
    ax = _ax(ax)
    line = ax.plot(traj.t, 1e3 * traj.pivot, **PIVOT_STYLE)[0]
    ax.set_ylabel("pivot y  (mm)")
    ax.set_xlabel("t  (s)")
    ax.set_xlim(traj.t[0], traj.t[-1])
    ax.grid(True, linewidth=0.3, alpha=0.5)
    return Drawn(ax, {"pivot": line}, data=traj)


def plot_phase_portrait(traj, ax=None, *, strobe=True, wrap=None, legend=None):
    """The curve ``(theta, theta')`` with the stroboscopic points ``t = 2kT`` marked.

    Parameters
    ----------
    traj : Trajectory
    ax : matplotlib Axes, optional
    strobe : bool
        Mark the states at ``t = 2kT``.
    wrap : bool, optional
        Wrap ``theta`` into ``(-pi, pi]``; by default only when the motion turns over.
    legend : {None, "inside", "outside"}
        Add a legend inside the axes (best corner) or beside them; None: none.

    Returns
    -------
    Drawn
        The artists by name, with ``.ax`` and ``.data``.

    Raises
    ------
    KapitzaValueError
        If ``traj`` is not a :class:`~kapitza.motion.Trajectory`, ``strobe`` or ``wrap`` not True or
        False, or ``legend`` not one of its choices; nothing is drawn then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import plot_phase_portrait
    >>> traj = kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=10)
    >>> drawn = plot_phase_portrait(traj)
    >>> drawn.ax.get_xlabel()
    'θ  (rad from upright)'
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    _record("traj", traj, "Trajectory")
    strobe = _v.flag("strobe", strobe)
    wrap = None if wrap is None else _v.flag("wrap", wrap)
    _legend_choice(legend)
    ax = _ax(ax)
    if wrap is None:
        wrap = bool(np.max(np.abs(traj.theta)) > np.pi)
    th = wrap_angle(traj.theta) if wrap else traj.theta
    x, y = _broken(th, traj.dtheta) if wrap else (th, traj.dtheta)
    out = Drawn(ax, {"curve": ax.plot(x, y, label=f"motion ({_model_label(traj)})",
                                      **{**NONLINEAR_STYLE, "linewidth": 0.7})[0]}, data=traj)
    if strobe:
        _, sth, som = traj.strobe()
        sth = wrap_angle(sth) if wrap else sth
        out["strobe"] = ax.plot(sth, som, label="t = 2kT (stroboscopic)", **STROBE_MARK)[0]
    out["start"] = ax.plot([th[0]], [traj.dtheta[0]], marker="*", markersize=11, color="gold",
                           markeredgecolor="k", linestyle="none", label="start", zorder=5)[0]
    ax.set_xlabel("θ  (rad from upright)" + (", wrapped to (−π, π]" if wrap else ""))
    ax.set_ylabel("θ'  (rad/s)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    return _legend(out, legend)


def plot_strobe(orbits, ax=None, *, wrap=True, max_members=200, colorbar=True):
    """Stroboscopic points ``(theta(2kT), theta'(2kT))`` of each member of an ensemble.

    Parameters
    ----------
    orbits : StrobeOrbits
        From :func:`kapitza.motion.stroboscopic_map` with ``every=1``, members along
        the last axis.
    ax : matplotlib Axes, optional
    wrap : bool
        Wrap ``theta`` into ``(-pi, pi]``.
    max_members : int
        Draw at most this many members.
    colorbar : bool
        Add a colour bar of the members' initial angle ``theta(0)``.

    Returns
    -------
    Drawn
        The artists by name, with ``.ax`` and ``.data``.

    Raises
    ------
    KapitzaValueError
        If ``orbits`` is not a :class:`~kapitza.motion.StrobeOrbits`, ``max_members`` is not a whole
        number from 1 to 100,000, or ``wrap`` or ``colorbar`` not True or False; nothing is drawn then.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> from kapitza.figures import plot_strobe
    >>> orbits = kapitza.stroboscopic_map(np.linspace(0.05, 0.4, 8), 0.0, T=0.15, A=100.0, periods=50)
    >>> drawn = plot_strobe(orbits)
    >>> sorted(drawn)
    ['colorbar', 'points']
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    _record("orbits", orbits, "StrobeOrbits")
    wrap, colorbar = _v.flag("wrap", wrap), _v.flag("colorbar", colorbar)
    max_members = _v.bounded_count("max_members", max_members, 100_000, minimum=1)
    ax = _ax(ax)
    th = orbits.theta.reshape(orbits.theta.shape[0], -1)[:, :max_members]
    om = orbits.dtheta.reshape(orbits.dtheta.shape[0], -1)[:, :max_members]
    if wrap:
        th = wrap_angle(th)
    m = th.shape[1]
    start = orbits.theta.reshape(orbits.theta.shape[0], -1)[0, :max_members]
    lo, hi = float(start.min()), float(start.max())
    norm = plt.Normalize(lo, hi if hi > lo else lo + 1.0)
    cmap = plt.get_cmap("viridis")
    # Later members are drawn first so the innermost (small-angle) curves stay on top.
    order = np.argsort(-np.abs(start))
    pts = [ax.plot(th[:, i], om[:, i], linestyle="none", marker=".", markersize=1.6,
                   color=cmap(norm(start[i])))[0] for i in order]
    out = Drawn(ax, {"points": pts}, data=orbits)
    if colorbar and m > 1:
        sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
        out["colorbar"] = ax.figure.colorbar(sm, ax=ax, fraction=0.05, pad=0.02)
        out["colorbar"].set_label("initial angle θ(0)  (rad)", fontsize=8)
    ax.set_xlabel("θ(2kT)  (rad from upright)" + (", wrapped" if wrap else ""))
    ax.set_ylabel("θ'(2kT)  (rad/s)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    return out


def plot_basin(basin, ax=None, *, colorbar=True):
    """Periods survived on the grid of initial states, with the basin's edge.

    Parameters
    ----------
    basin : Basin
    ax : matplotlib Axes, optional
    colorbar : bool

    Returns
    -------
    Drawn
        The artists by name, with ``.ax`` and ``.data``.

    Raises
    ------
    KapitzaValueError
        If ``basin`` is not a :class:`~kapitza.motion.Basin` or ``colorbar`` not True or False;
        nothing is drawn then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import plot_basin
    >>> drawn = plot_basin(kapitza.basin(T=0.15, A=100.0, periods=10, n_theta=11, n_dtheta=11))
    >>> sorted(drawn)
    ['colorbar', 'edge', 'image']
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    _record("basin", basin, "Basin")
    colorbar = _v.flag("colorbar", colorbar)
    ax = _ax(ax)
    N = basin.periods
    edges = np.unique(np.concatenate([[0, 1], np.geomspace(1, N, 6).round(), [N, N + 1]])).astype(float)
    cmap = ListedColormap(plt.get_cmap("magma")(np.linspace(0.08, 0.78, edges.size - 2)).tolist()
                          + [(0.62, 0.79, 0.88, 1.0)])
    norm = BoundaryNorm(edges, cmap.N)
    dx = basin.theta0[1] - basin.theta0[0]
    dy = basin.dtheta0[1] - basin.dtheta0[0]
    extent = (basin.theta0[0] - dx / 2, basin.theta0[-1] + dx / 2, basin.dtheta0[0] - dy / 2,
              basin.dtheta0[-1] + dy / 2)
    im = ax.imshow(basin.periods_survived, origin="lower", extent=extent, aspect="auto", cmap=cmap, norm=norm,
                   interpolation="nearest")
    out = Drawn(ax, {"image": im}, data=basin)
    if basin.survived.any() and not basin.survived.all():
        out["edge"] = ax.contour(basin.theta0, basin.dtheta0, basin.survived.astype(float), levels=[0.5],
                                 colors="k", linewidths=0.8)
    if colorbar:
        cb = ax.figure.colorbar(im, ax=ax, ticks=edges[:-1] + 0.5 * np.diff(edges), fraction=0.05, pad=0.02)
        labels = [f"{int(a)}" if b - a <= 1 else f"{int(a)}–{int(b) - 1}" for a, b in zip(edges[:-1], edges[1:])]
        labels[-1] = f"all {N}"
        cb.ax.set_yticklabels(labels, fontsize=7)
        cb.set_label("whole periods 2T within the window", fontsize=8)
        out["colorbar"] = cb
    ax.set_xlabel("θ(0)  (rad from upright)")
    ax.set_ylabel("θ'(0)  (rad/s)")
    ax.set_title(f"{basin.model}: {100 * basin.fraction:.3g}% of the grid stays up", fontsize=9)
    return out


# ------------------------------------------------------------------ captioned figures
def time_series_figure(traj, *, linear=None, tol=None, title=None):
    """Angle and pivot height against time, with a caption.

    Parameters
    ----------
    traj : Trajectory
        From :func:`kapitza.simulate`.
    linear : Trajectory, optional
        The linear motion on the same samples, drawn beside it.
    tol : float, optional
        A window ``|theta| < tol`` to shade.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    KapitzaValueError
        If ``traj`` (or ``linear``) is not a :class:`~kapitza.motion.Trajectory` or ``tol`` is not a
        positive number; no figure is made then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import time_series_figure
    >>> fig = time_series_figure(kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=10))
    >>> len(fig.axes)
    2
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    traj, linear, tol = _motion_options(traj, linear, tol)
    fig = new_figure(7.5, 5.0, caption_lines=3)
    gs = fig.add_gridspec(2, 1, height_ratios=[3, 1])
    ax = fig.add_subplot(gs[0])
    axp = fig.add_subplot(gs[1], sharex=ax)
    plot_time_series(traj, ax, linear=linear, tol=tol)
    plot_pivot(traj, axp)
    ax.tick_params(labelbottom=False)
    ax.set_xlabel("")  # the pivot panel below carries the time axis
    ax.legend(loc="upper left", fontsize=8, framealpha=0.9)
    drive = traj.drive
    ax.set_title(title or f"Pendulum on a vibrating pivot ({drive.label}): angle from the upright", fontsize=10)
    pivot_text = f"{drive.describe()}, stroke {1000 * float(drive.stroke(traj.T, traj.A)):.3g} mm."
    caption(fig, parameter_label(traj.T, traj.A, traj.l, traj.g, drive, traj.c)
            + f". Start θ = {traj.theta0:g} rad, θ' = "
            f"{traj.dtheta0:g} rad/s at t = 0 (a = +A). Lower panel: the pivot's height, " + pivot_text)
    return fig


def phase_portrait_figure(traj, *, title=None):
    """Phase portrait ``(theta, theta')`` with stroboscopic points, with a caption.

    Parameters
    ----------
    traj : Trajectory
        From :func:`kapitza.simulate`.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    KapitzaValueError
        If ``traj`` is not a :class:`~kapitza.motion.Trajectory`; no figure is made then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import phase_portrait_figure
    >>> fig = phase_portrait_figure(kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=10))
    >>> fig.axes[0].get_xlabel()
    'θ  (rad from upright)'
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    _record("traj", traj, "Trajectory")
    fig = new_figure(6.5, 5.2, caption_lines=3)
    ax = fig.add_subplot()
    plot_phase_portrait(traj, ax)
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, fontsize=8, frameon=False)
    fig.suptitle(title or "Phase portrait", fontsize=10)
    caption(fig, parameter_label(traj.T, traj.A, traj.l, traj.g, traj.drive, traj.c)
            + f". {traj.periods:g} periods 2T; dots: the "
            "state once per period (t = 2kT), i.e. the stroboscopic map. θ' jumps in slope, not in value, at the "
            "switches.")
    return fig


def island_members(orbits, bound=0.5 * np.pi):
    """Which members of an ensemble stay about the upright: ``|theta| < bound`` at every
    recorded ``t = 2kT`` (bool array over the members, flattened)."""
    th = orbits.theta.reshape(orbits.theta.shape[0], -1)
    return np.all(np.isfinite(th) & (np.abs(th) < bound), axis=0)


def strobe_window(orbits, own=None, pad=0.12):
    """Axes limits ``((x0, x1), (y0, y1))`` framing the island about the upright and the
    user's own orbit ``own = (theta_k, dtheta_k)``; None when neither stays near the upright
    (then the whole wrapped map is shown)."""
    keep = island_members(orbits)
    xs, ys = [], []
    if keep.any():
        xs.append(orbits.theta.reshape(orbits.theta.shape[0], -1)[:, keep].ravel())
        ys.append(orbits.dtheta.reshape(orbits.dtheta.shape[0], -1)[:, keep].ravel())
    if own is not None:
        th, om = (np.asarray(v, float) for v in own)
        if np.all(np.abs(th) < 0.5 * np.pi):
            xs.append(th)
            ys.append(om)
    if not xs:
        return None
    x, y = np.concatenate(xs), np.concatenate(ys)
    x, y = x[np.isfinite(x) & np.isfinite(y)], y[np.isfinite(x) & np.isfinite(y)]
    if x.size == 0:
        return None
    hx = max(np.max(np.abs(x)), 1e-3) * (1.0 + pad)
    hy = max(np.max(np.abs(y)), 1e-3) * (1.0 + pad)
    return (-hx, hx), (-hy, hy)


def strobe_figure(orbits, *, title=None, highlight=None):
    """Stroboscopic map about the upright, with the user's own orbit, and a caption.

    Parameters
    ----------
    orbits : StrobeOrbits
        The ensemble (``every=1``). Members that stay within ``pi/2`` of the upright form
        the island and are drawn in colour; the others (the chaotic sea, when there is
        one) are drawn faint.
    highlight : (theta_k, dtheta_k), optional
        The user's own orbit at ``t = 2kT``, drawn on top.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    KapitzaValueError
        If ``orbits`` is not a :class:`~kapitza.motion.StrobeOrbits` or ``highlight`` is not a pair
        of equally long sequences of finite numbers; no figure is made then.

    Notes
    -----
    The axes frame the island and the user's orbit (:func:`strobe_window`); only when
    neither stays near the upright is the whole wrapped map shown. The caption says
    what is drawn.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> from kapitza.figures import strobe_figure
    >>> orbits = kapitza.stroboscopic_map(np.linspace(0.05, 0.4, 8), 0.0, T=0.15, A=100.0, periods=50)
    >>> fig = strobe_figure(orbits)
    >>> fig.axes[0].get_xlabel()
    'θ(2kT)  (rad from upright)'
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    _record("orbits", orbits, "StrobeOrbits")
    if highlight is not None:
        try:
            hth, hom = (np.asarray(v, float).ravel() for v in highlight)
        except (TypeError, ValueError):
            raise _v.KapitzaValueError(f"highlight must be a pair (theta_k, dtheta_k) of sequences of numbers; "
                                       f"got {_v._short(highlight)}") from None
        if hth.size != hom.size:
            raise _v.KapitzaValueError(f"highlight must be a pair of equally long sequences; got {hth.size} angles "
                                       f"and {hom.size} rates")
        _v.finite("highlight", np.concatenate([hth, hom]))
    fig = new_figure(6.5, 5.2, caption_lines=3)
    ax = fig.add_subplot()
    keep = island_members(orbits)
    window = strobe_window(orbits, highlight)
    m = keep.size
    th = orbits.theta.reshape(orbits.theta.shape[0], -1)
    om = orbits.dtheta.reshape(orbits.dtheta.shape[0], -1)
    if (~keep).any():
        ax.plot(wrap_angle(th[:, ~keep]).ravel(), om[:, ~keep].ravel(), linestyle="none", marker=".",
                markersize=1.2, color="0.78", zorder=1, label="leave the upright (chaotic sea)")
    if keep.any():
        plot_strobe(dataclasses.replace(orbits, theta=th[:, keep], dtheta=om[:, keep]), ax, wrap=False)
    own_note = ""
    if highlight is not None:
        hth, hom = (np.asarray(v, float) for v in highlight)
        ax.plot(wrap_angle(hth), hom, **{**STROBE_MARK, "markersize": 3.0}, zorder=5, label="your orbit")
        stays = bool(np.all(np.abs(hth) < 0.5 * np.pi))
        own_note = (f" Orange: your start, {hth.size - 1} periods"
                    + (", staying about the upright." if stays else ", leaving the upright."))
    if window is not None:
        ax.set_xlim(*window[0])
        ax.set_ylim(*window[1])
        ax.set_xlabel("θ(2kT)  (rad from upright)")
    else:
        ax.set_xlim(-np.pi, np.pi)
        ax.set_xlabel("θ(2kT)  (rad from upright), wrapped to (−π, π]")
    ax.set_ylabel("θ'(2kT)  (rad/s)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9, markerscale=3)
    ax.set_title(title or "Stroboscopic map (one point per drive period 2T)", fontsize=10)
    n = int(orbits.n[-1])
    k = int(np.count_nonzero(keep))
    if k:
        what = (f" {k} of {m} starts at rest (colour: θ(0)) stay within π/2 of the upright for {n} periods: "
                "the closed curves are quasi-periodic motions on the island about the upright")
        what += (f"; the other {m - k} leave it (grey dots, outside the frame: the chaotic sea)." if k < m else ".")
    else:
        what = (f" None of the {m} starts at rest stays near the upright over {n} periods: there is no island "
                "here (grey: their states, θ wrapped to (−π, π]).")
    caption(fig, parameter_label(orbits.T, orbits.A, orbits.l, orbits.g) + "." + what + own_note)
    return fig


def basin_figure(basins, *, title=None):
    """Basins side by side (e.g. linear and nonlinear), with a caption.

    Parameters
    ----------
    basins : sequence of Basin
        From :func:`kapitza.basin`, one panel each.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    KapitzaValueError
        If ``basins`` is empty or holds something other than :class:`~kapitza.motion.Basin`; no figure
        is made then.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures import basin_figure
    >>> grids = [kapitza.basin(T=0.15, A=100.0, periods=10, n_theta=11, n_dtheta=11, model=m)
    ...          for m in ("linear", "nonlinear")]
    >>> fig = basin_figure(grids)
    >>> len(fig.axes)
    3
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    basins = [_record("basins[]", b, "Basin") for b in basins]
    if not basins:
        raise _v.KapitzaValueError("basins must hold at least one kapitza.motion.Basin; got none")
    fig = new_figure(5.2 * len(basins) + 0.8, 4.8, caption_lines=3)
    axes = fig.subplots(1, len(basins), squeeze=False)[0]
    for i, (ax, b) in enumerate(zip(axes, basins)):
        plot_basin(b, ax, colorbar=(i == len(basins) - 1))
        if i > 0:
            ax.set_ylabel("")
    b = basins[0]
    fig.suptitle(title or f"Which starts keep the pendulum within {b.tol:g} rad of the upright for "
                 f"{b.periods} periods?", fontsize=10)
    drive, c = b.drive, b.c
    checked = ("checked on the continuous motion, not only at t = 2kT"
               if drive._steps() is not None and not c
               else "a DOP853 solution checked at 64 or more instants per period and on the Hermite interpolant "
                    "between them")
    damped = f", damping c = {c:g} 1/s" if c else ""
    caption(fig, parameter_label(b.T, b.A, b.l, b.g, drive) + damped
            + f". Light blue: |θ(t)| ≤ window for the whole time "
            f"({checked}); darker: whole periods completed before leaving. Black line: the basin's edge.")
    return fig
