"""Drawing of the paper's Figures 1-8 (matplotlib is imported here only).

``figureN(ax=None, data=None)`` draws Figure N from :mod:`kapitza.paper.data` and
returns the :class:`~kapitza.paper.data.FigureData` it drew. ``ax`` is one Axes
(Figures 2-5, 7) or a sequence of Axes (Figure 1: two; Figure 6: one main and one
per magnified zone; Figure 8: two); if None, a new figure is made.
:func:`make_figure` builds the complete figure with its caption, :func:`write_figure`
saves it as PNG and SVG with its data as JSON and CSV.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FuncFormatter, MultipleLocator

from .. import _io
from ..figures._style import EDGE_2T, EDGE_4T, ZONE_FILL, caption, new_figure, save
from . import data as D

__all__ = [
    "figure1",
    "figure2",
    "figure3",
    "figure4",
    "figure5",
    "figure6",
    "figure7",
    "figure8",
    "DRAW",
    "make_figure",
    "write_figure",
]

PI = np.pi

#: Colours of the four steps of the dynamics (section 2).
STEP_STYLE = {
    "hyperbolic arc": dict(color="#1f4e9c", linewidth=1.8),
    "stretch": dict(color="#2e8b3a", linewidth=1.8),
    "elliptic arc": dict(color="#c0392b", linewidth=1.8),
    "contraction": dict(color="#7d3c98", linewidth=1.8),
}
ALPHA_COLOR = "#1f4e9c"
BETA_COLOR = "#c0392b"
ASYMPTOTE = dict(color="0.55", linestyle=":", linewidth=1.0)


def _axes(ax, count, width, height, caption_lines=3):
    """``count`` Axes: the given ones, or those of a new figure."""
    if ax is not None:
        axes = list(np.atleast_1d(ax)) if count > 1 else [ax]
        if len(axes) != count:
            raise ValueError(f"this figure needs {count} Axes; got {len(axes)}")
        return axes
    fig = new_figure(width, height)
    return list(np.atleast_1d(fig.subplots(1, count)))


def _arrow(ax, x, y, dx, dy, size, **style):
    """A small arrow head at ``(x, y)`` pointing along ``(dx, dy)``."""
    n = np.hypot(dx, dy)
    if n == 0:
        return
    ux, uy = dx / n * size, dy / n * size
    ax.annotate("", xy=(x + ux, y + uy), xytext=(x - ux, y - uy),
                arrowprops=dict(arrowstyle="-|>", mutation_scale=12, shrinkA=0, shrinkB=0,
                                lw=style.get("linewidth", 1.2),
                                color=style.get("color", "k")))


def _pi_axis(axis, step=1.0):
    """Ticks at multiples of ``step * pi`` labelled in units of pi."""

    def fmt(v, _):
        k = v / PI
        if abs(k) < 1e-9:
            return "0"
        if abs(k - round(k)) < 1e-9:
            k = int(round(k))
            return r"$\pi$" if k == 1 else rf"${k}\pi$"
        return rf"${k:g}\pi$"

    axis.set_major_locator(MultipleLocator(step * PI))
    axis.set_major_formatter(FuncFormatter(fmt))


def _polyline_samples(xs, ys, per_segment=40):
    """Points along a polyline, dense enough to stand for it as an obstacle."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    if xs.size < 2:
        return np.column_stack([xs, ys])
    t = np.linspace(0.0, 1.0, per_segment)[:-1]
    x = (xs[:-1, None] + np.outer(np.diff(xs), t)).ravel()
    y = (ys[:-1, None] + np.outer(np.diff(ys), t)).ravel()
    return np.column_stack([np.append(x, xs[-1]), np.append(y, ys[-1])])


def _place_labels(ax, items, obstacles, fontsize=10, gap=7.0):
    """Annotate ``items`` ``(x, y, text)`` where their labels keep clear of ``obstacles``.

    Eight directions around each point are tried; the one whose label box lies
    farthest from the obstacles (curves, points, labels already placed) and inside
    the axes wins, with a slight preference for pointing away from the origin.
    Returns the offsets chosen, in points.
    """
    fig = ax.figure
    px = fig.dpi / 72.0
    trans = ax.transData
    obs = trans.transform(np.asarray(obstacles, float)) if len(obstacles) else np.zeros((0, 2))
    box = ax.get_window_extent()
    placed = []  # (cx, cy, half_w, half_h) in pixels
    offsets = []
    origin = trans.transform((0.0, 0.0))
    for x, y, text in items:
        p = trans.transform((x, y))
        hw = 0.36 * fontsize * px * max(len(text), 1)
        hh = 0.62 * fontsize * px
        radial = np.arctan2(p[1] - origin[1], p[0] - origin[0])
        best, best_score = None, -np.inf
        for ang in np.arange(0.0, 2.0 * np.pi, np.pi / 4.0):
            ca, sa = np.cos(ang), np.sin(ang)
            c = p + np.array([ca * (gap * px + hw), sa * (gap * px + hh)])
            dx = np.maximum(np.abs(obs[:, 0] - c[0]) - hw, 0.0)
            dy = np.maximum(np.abs(obs[:, 1] - c[1]) - hh, 0.0)
            score = float(np.min(np.hypot(dx, dy))) if obs.size else 1e9
            for qx, qy, qw, qh in placed:
                ddx = max(abs(qx - c[0]) - hw - qw, 0.0)
                ddy = max(abs(qy - c[1]) - hh - qh, 0.0)
                score = min(score, np.hypot(ddx, ddy))
            score = min(score, 18.0 * px)  # beyond this clearance, only direction matters
            inside = (box.x0 <= c[0] - hw) and (c[0] + hw <= box.x1) and (box.y0 <= c[1] - hh) and (c[1] + hh <= box.y1)
            score += (0.0 if inside else -100.0) + 2.0 * px * np.cos(ang - radial)
            if score > best_score:
                best, best_score = c, score
        placed.append((best[0], best[1], hw, hh))
        off = (best - p) / px
        offsets.append(tuple(off))
        ax.annotate(text, (x, y), xytext=off, textcoords="offset points", ha="center", va="center",
                    fontsize=fontsize, fontweight="bold", zorder=6)
    return offsets


# ------------------------------------------------------------------ Figure 1
def figure1(ax=None, data=None):
    """Figure 1: hyperbolic (2.6)-(2.7) and elliptic (2.12)-(2.13) rotation. ``ax``: two Axes."""
    data = data or D.figure1_data()
    axh, axe = _axes(ax, 2, 7.6, 4.6, 4)
    ext = data.parameters["extent"]
    size = 0.07 * ext
    first = True
    for s in data.series_with(role="hyperbola"):
        axh.plot(s.x, s.y, color=ALPHA_COLOR, linewidth=1.2,
                 label=r"hyperbolae $x_h^2 - y_h^2 = $ const" if first else None)
        first = False
    for s, ls in zip(data.series_with(role="asymptote"), (":", "--")):
        axh.plot(s.x, s.y, **{**ASYMPTOTE, "linestyle": ls}, label=s.label)
    first = True
    for s in data.series_with(role="circle"):
        axe.plot(s.x, s.y, color=BETA_COLOR, linewidth=1.2,
                 label=r"circles $x_e^2 + y_e^2 = $ const" if first else None)
        first = False
    for p in data.points:
        target = axh if p.panel == "hyperbolic" else axe
        color = ALPHA_COLOR if p.panel == "hyperbolic" else BETA_COLOR
        _arrow(target, p.x, p.y, p.meta["dx"], p.meta["dy"], size, color=color)
    axh.plot([], [], marker=r"$\rightarrow$", linestyle="none", color="k", markersize=10, label="direction of motion")
    for a, (xl, yl), title in ((axh, (r"$x_h = \theta$", r"$y_h = \dot\theta/\omega_h$"), "hyperbolic phase (2.6)"),
                               (axe, (r"$x_e = \theta$", r"$y_e = \dot\theta/\omega_e$"), "elliptic phase (2.12)")):
        a.set_xlim(-ext, ext)
        a.set_ylim(-ext, ext)
        a.set_aspect("equal")
        a.axhline(0, color="0.8", linewidth=0.6, zorder=0)
        a.axvline(0, color="0.8", linewidth=0.6, zorder=0)
        a.set_xlabel(xl)
        a.set_ylabel(yl)
        a.set_title(title, fontsize=10)
        a.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), fontsize=8, frameon=False, ncol=2)
    return data


# ------------------------------------------------------------------ Figures 2-5
def _draw_period(ax, series, r):
    """The four steps of one period, each with an arrow head in its middle."""
    for s in series:
        style = STEP_STYLE[s.role]
        ax.plot(s.x, s.y, label=s.label, **style)
        if len(s.x) > 2:
            k = len(s.x) // 2
            dx, dy = s.x[k + 1] - s.x[k - 1], s.y[k + 1] - s.y[k - 1]
            xm, ym = s.x[k], s.y[k]
        else:
            dx, dy = s.x[1] - s.x[0], s.y[1] - s.y[0]
            xm, ym = 0.5 * (s.x[0] + s.x[1]), 0.5 * (s.y[0] + s.y[1])
        _arrow(ax, xm, ym, dx, dy, 0.03 * r, color=style["color"], linewidth=1.0)


def _asymptotes(ax, lim, label=True):
    s = np.array([-lim, lim])
    ax.plot(s, s, **ASYMPTOTE)
    ax.plot(s, -s, **ASYMPTOTE, label=r"asymptotes $y = \pm x$" if label else None)
    ax.axhline(0, color="0.85", linewidth=0.6, zorder=0)
    ax.axvline(0, color="0.85", linewidth=0.6, zorder=0)
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")


def _label_points(ax, points, series, r):
    """Label every notable point; points that coincide share one label ("0 = 4")."""
    groups = []
    for p in points:
        for grp in groups:
            if np.hypot(grp[0].x - p.x, grp[0].y - p.y) < 1e-6 * r:
                grp.append(p)
                break
        else:
            groups.append([p])
    obstacles = np.vstack([_polyline_samples(s.x, s.y) for s in series]
                          + [np.array([[g[0].x, g[0].y] for g in groups])])
    for grp in groups:
        ax.plot([grp[0].x], [grp[0].y], "o", color="k", markersize=4.5, zorder=5)
    _place_labels(ax, [(g[0].x, g[0].y, " = ".join(q.label for q in g)) for g in groups], obstacles)


def _dynamics_axes(ax, periods, zoom):
    """The Axes of Figures 2-5: one panel per period, and a small one for the magnified turn."""
    count = periods + (zoom is not None)
    if ax is not None:
        axes = list(np.atleast_1d(ax))
        if len(axes) != count:
            raise ValueError(f"this figure needs {count} Axes; got {len(axes)}")
        return axes[:periods], (axes[periods] if zoom is not None else None)
    fig = new_figure(11.0 if periods == 2 else 8.6, 4.7 if periods == 2 else 6.0)
    widths = (1.0,) * periods + ((0.55,) if zoom is not None else ())
    gs = fig.add_gridspec(1, count, width_ratios=widths)
    mains = [fig.add_subplot(gs[0, i]) for i in range(periods)]
    if zoom is None:
        return mains, None
    # The small panel sits under the legend, in the right-hand column.
    sub = gs[0, periods].subgridspec(2, 1, height_ratios=(1.0, 1.0))
    return mains, fig.add_subplot(sub[1, 0])


def _dynamics(ax, data):
    par = data.parameters
    periods = par["periods"]
    zoom = par.get("zoom")
    mains, zax = _dynamics_axes(ax, periods, zoom)
    r = max(np.max(np.hypot(s.x, s.y)) for s in data.series)
    lim = 1.22 * r
    xl, yl = r"$x = \theta$", r"$y = \dot\theta/\omega_h$ (points 0, 1, 4), $\dot\theta/\omega_e$ (points 2, 3)"
    for i, a in enumerate(mains, start=1):
        mine = [s for s in data.series if s.meta.get("period", 1) == i]
        if i == 2:
            # The first period stays in view, faint, so the turn by pi is plain.
            for s in data.series:
                if s.meta.get("period", 1) == 1:
                    a.plot(s.x, s.y, color="0.75", linewidth=1.0, zorder=1,
                           label="first period ($0 \\leq t < 2T$)" if s.role == "hyperbolic arc" else None)
        _draw_period(a, mine, r)
        _asymptotes(a, lim)
        lo, hi = (0, 4) if i == 1 else (4, 8)
        pts = [p for p in data.points if lo <= p.meta["i"] <= hi]
        if i == 1 and periods == 2:
            pts = [p for p in pts if p.label != "8"]
        _label_points(a, pts, mine, r)
        a.set_xlabel(xl)
        a.set_ylabel(yl if i == 1 else "")
        if periods == 2:
            a.set_title("first period, $0 \\leq t < 2T$" if i == 1 else "second period, $2T \\leq t < 4T$",
                        fontsize=9)
    name = _tex_name(par["boundary"]).strip("$")
    head = (f"{data.title}\n$T = {name} = {par['T']:.5g}$ s, $A = {par['A']:g}$ m/s$^2$ (eq. {par['equation']}, "
            f"$k = {par['k']}$)")
    fig = mains[0].figure
    if periods == 2:
        fig.suptitle(head, fontsize=10)
    else:
        mains[0].set_title(head, fontsize=10)
    # One legend: the strokes exactly as drawn (the first period's, or the second panel's with its ghost).
    handles, labels = mains[-1].get_legend_handles_labels()
    if zax is not None:
        h = zoom
        hyper = [s for s in data.series if s.role == "hyperbolic arc"]
        for s in hyper:
            if s.meta.get("period", 1) == 1:
                zax.plot(s.x, s.y, **STEP_STYLE["hyperbolic arc"])
        _asymptotes(zax, h, label=False)
        zax.set_title(f"the turn of arc 0-1,\nmagnified {lim / h:.0f}$\\times$", fontsize=8)
        zax.tick_params(labelsize=7)
        zax.set_xlabel(r"$x$", fontsize=8)
        zax.set_ylabel(r"$y$", fontsize=8)
        mains[0].add_patch(plt.Rectangle((-h, -h), 2 * h, 2 * h, fill=False, edgecolor="0.3", linewidth=0.8,
                                         zorder=7))
        fig.legend(handles, labels, loc="upper right", bbox_to_anchor=(1.0, 0.93), fontsize=8, frameon=False)
    else:
        mains[-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False, borderaxespad=0.0)
    return data


def figure2(ax=None, data=None):
    """Figure 2: steps of the dynamics, Lemma 3.1(a) (2T-periodic solution at ``T_1``)."""
    return _dynamics(ax, data or D.figure2_data())


def figure3(ax=None, data=None):
    """Figure 3: steps of the dynamics, Lemma 3.1(b) (2T-periodic solution at ``T_2``)."""
    return _dynamics(ax, data or D.figure3_data())


def figure4(ax=None, data=None):
    """Figure 4: 4T-periodic solution, Lemma 3.2(a) (at ``T~_2``)."""
    return _dynamics(ax, data or D.figure4_data())


def figure5(ax=None, data=None):
    """Figure 5: 4T-periodic solution, Lemma 3.2(b) (at ``T~_1``)."""
    return _dynamics(ax, data or D.figure5_data())


# ------------------------------------------------------------------ Figure 6
def _tex_name(label):
    """``"T~_2"`` -> ``"$\\tilde T_{2}$"``, ``"T_3"`` -> ``"$T_{3}$"``."""
    tilde, _, index = label.partition("_")
    return rf"$\tilde T_{{{index}}}$" if tilde == "T~" else rf"$T_{{{index}}}$"


def _mark(ax, p, offset, at=None):
    two = p.meta["period"] == "2T"
    x, y = at if at is not None else (p.x, p.y)
    ax.plot([x], [y], "o" if two else "s", markersize=6, zorder=5,
            color=ALPHA_COLOR if two else BETA_COLOR, markeredgecolor="k", markeredgewidth=0.6)
    ax.annotate(_tex_name(p.label), (x, y), xytext=offset, textcoords="offset points", fontsize=10,
                ha="center", va="center", zorder=6,
                bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85),
                arrowprops=dict(arrowstyle="-", color="0.4", lw=0.6, shrinkA=0, shrinkB=3))


def figure6(ax=None, data=None):
    """Figure 6: the graphical solution of (3.10)-(3.13). ``ax``: the main Axes, then one per zoom panel."""
    data = data or D.figure6_data()
    zoom_panels = [p for p in data.axes if p.startswith("zoom")]
    if ax is None:
        fig = new_figure(9.0, 7.4)
        gs = fig.add_gridspec(2, max(len(zoom_panels), 1), height_ratios=(2.3, 1.0))
        axes = [fig.add_subplot(gs[0, :])] + [fig.add_subplot(gs[1, i]) for i in range(len(zoom_panels))]
    else:
        axes = list(np.atleast_1d(ax))
        if len(axes) != 1 + len(zoom_panels):
            raise ValueError(f"Figure 6 needs {1 + len(zoom_panels)} Axes; got {len(axes)}")
    main, zooms = axes[0], axes[1:]
    first = {"alpha": True, "beta": True}
    for s in data.series_with(panel="main"):
        if s.role == "line":
            main.plot(s.x, s.y, color="k", linewidth=1.3, label=r"$y = \omega_e T$")
            continue
        color = ALPHA_COLOR if s.role == "alpha" else BETA_COLOR
        label = None
        if first[s.role]:
            label = r"$\alpha(T) + n\pi$" if s.role == "alpha" else r"$\beta(T) + n\pi$"
            first[s.role] = False
        main.plot(s.x, s.y, color=color, linewidth=1.3, linestyle="-" if s.role == "alpha" else "--", label=label)
    for p in data.points_on("main"):
        lower = p.meta["edge"] == "lower"
        off = (-22, 14) if lower else (20, -14)
        if p.meta["zone"] == 0:
            off = (-20, 12) if lower else (16, -16)
        _mark(main, p, off)
    main.plot([], [], "o", color=ALPHA_COLOR, markeredgecolor="k", label=r"$T_j$: 2T-periodic solution")
    main.plot([], [], "s", color=BETA_COLOR, markeredgecolor="k", label=r"$\tilde T_j$: 4T-periodic solution")
    u_max = max(np.max(s.x) for s in data.series_with(panel="main"))
    main.set_xlim(0, u_max)
    main.set_ylim(0, u_max)
    _pi_axis(main.xaxis)
    _pi_axis(main.yaxis)
    main.grid(True, color="0.92", linewidth=0.6)
    main.set_xlabel(r"$\omega_e T$ [rad]")
    main.set_ylabel(r"angle [rad]")
    par = data.parameters
    main.set_title(f"Conditions (3.10)-(3.13): $A = {par['A']:g}$ m/s$^2$, $l = {par['l']:g}$ m, "
                   f"$g = {par['g']:g}$ m/s$^2$", fontsize=10)
    main.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False, borderaxespad=0.0)
    for zax, panel in zip(zooms, zoom_panels):
        # Plotted relative to the window centre, in a power of ten that suits the window, so the
        # ticks stay readable however narrow the zone.
        xs = data.series_with(panel=panel)[0].x
        c = 0.5 * (xs[0] + xs[-1])
        half = 0.5 * (xs[-1] - xs[0])
        exp = int(np.floor(np.log10(half)))
        scale = 10.0 ** exp
        for s in data.series_with(panel=panel):
            X, Y = (s.x - c) / scale, (s.y - c) / scale
            if s.role == "line":
                zax.plot(X, Y, color="k", linewidth=1.2)
            else:
                zax.plot(X, Y, color=ALPHA_COLOR if s.role == "alpha" else BETA_COLOR, linewidth=1.2,
                         linestyle="-" if s.role == "alpha" else "--")
        for p in data.points_on(panel):
            _mark(zax, p, (-14, 12) if p.meta["edge"] == "lower" else (14, -12),
                  at=((p.x - c) / scale, (p.y - c) / scale))
        zax.set_xlim(-half / scale, half / scale)
        zax.set_ylim(-half / scale, half / scale)
        zax.tick_params(labelsize=7)
        zone = panel.split()[1]
        zax.set_title(f"zone {zone}, centre $c$ = {c:.6g} rad", fontsize=8)
        zax.set_xlabel(rf"$(\omega_e T - c)\,/\,10^{{{exp}}}$", fontsize=8)
        zax.set_ylabel(rf"$(\mathrm{{angle}} - c)\,/\,10^{{{exp}}}$", fontsize=8)
    return data


# ------------------------------------------------------------------ Figure 7
def figure7(ax=None, data=None):
    """Figure 7: the exact stability zones (:func:`kapitza.figures.chart.plot_zones`) and the
    thin zones magnified (:func:`kapitza.figures.chart.plot_tongue`). ``ax``: the main Axes,
    then one per magnified zone."""
    from ..figures.chart import plot_zones, zone_chart_axes

    data = data or D.figure7_data()
    par = data.parameters
    magnify = list(par.get("magnify", ()))
    if ax is None:
        main, zooms = zone_chart_axes(new_figure(8.2, 7.6), len(magnify))
    else:
        axes = list(np.atleast_1d(ax))
        if len(axes) != 1 + len(magnify):
            raise ValueError(f"Figure 7 needs {1 + len(magnify)} Axes; got {len(axes)}")
        main, zooms = axes[0], axes[1:]
    plot_zones(main, tuple(par["eps_range"]), tuple(par["mu_range"]), show_G=True, points=par["points"])
    main.set_title("The exact stability zones of the upright position", fontsize=10)
    for zax, n in zip(zooms, magnify):
        panel = f"zoom {n}"
        lo = data.series_named(f"zone {n} lower [{panel}]")
        hi = data.series_named(f"zone {n} upper [{panel}]")
        lower_2t = n % 2 == 0
        zax.fill_betweenx(lo.y, lo.x, hi.x, color=ZONE_FILL, linewidth=0)
        zax.plot(lo.x, lo.y, **(EDGE_2T if lower_2t else EDGE_4T))
        zax.plot(hi.x, hi.y, **(EDGE_4T if lower_2t else EDGE_2T))
        w = 1.15 * float(np.max(hi.x))
        zax.set_xlim(-w, w)
        zax.set_ylim(*par["mu_range"])
        zax.axvline(0.0, color="0.8", linewidth=0.6, zorder=0)
        zax.tick_params(labelsize=7)
        e = lo.meta["exponent"]
        zax.set_xlabel(rf"$(\varepsilon - \varepsilon_\mathrm{{mid}})\,/\,10^{{{e}}}$", fontsize=8)
        zax.set_ylabel(r"$\mu$", fontsize=8)
        mid = 0.5 * (lo.meta["eps"][0] + hi.meta["eps"][0])
        zax.set_title(rf"zone {n} ($\varepsilon_\mathrm{{mid}}$ = {mid:.3f} at $\mu$ = 0)", fontsize=8)
    return data


# ------------------------------------------------------------------ Figure 8
def figure8(ax=None, data=None):
    """Figure 8: ``G_0``, the exact first zone and approximations. ``ax``: two Axes (plane, errors)."""
    data = data or D.figure8_data()
    axp, axe = _axes(ax, 2, 8.6, 5.6, 5)
    lo = data.series_named("exact lower")
    hi = data.series_named("exact upper")
    axp.fill_betweenx(lo.y, lo.x, hi.x, color=ZONE_FILL, linewidth=0, label="exact first zone (stable)")
    axp.plot(lo.x, lo.y, **{**EDGE_2T, "linewidth": 2.6}, label=lo.label)
    axp.plot(hi.x, hi.y, **{**EDGE_4T, "linewidth": 2.6}, label=hi.label)
    g0 = data.series_named("G_0")
    axp.plot(g0.x, g0.y, color="0.3", linestyle=(0, (5, 3)), linewidth=1.2, label=r"$G_0$")
    styles = {
        "Kapitza": dict(color="#e67e22", linewidth=1.0, linestyle="-"),
        "series4 lower": dict(color="#16a085", linewidth=1.0, linestyle="-."),
        "series4 upper": dict(color="#16a085", linewidth=1.0, linestyle="-."),
        "series mu lower": dict(color="#8e44ad", linewidth=1.0, linestyle=(0, (1, 1.5))),
    }
    for name, st in styles.items():
        s = data.series_named(name)
        axp.plot(s.x, s.y, label=s.label if name != "series4 upper" else None, **st)
    eps_max = data.parameters["eps_max"]
    axp.set_xlim(0, eps_max)
    axp.set_ylim(0, 1)
    axp.set_xlabel(r"$\varepsilon = T\sqrt{A}/\sqrt{8l}$")
    axp.set_ylabel(r"$\mu = \sqrt{g/A}$")
    axp.set_title("first zone and approximations", fontsize=10)
    axp.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=7.5, frameon=False, ncol=2)
    estyles = {
        "error Kapitza": styles["Kapitza"],
        "error series4 lower": styles["series4 lower"],
        "error series4 upper": {**styles["series4 upper"], "color": "#0b5345", "linestyle": "--"},
        "error series mu lower": styles["series mu lower"],
    }
    floor = 1e-15  # below this the difference is rounding, not approximation error
    for name, st in estyles.items():
        s = data.series_named(name)
        y = np.where(s.y > floor, s.y, np.nan)
        axe.loglog(s.x, y, label=s.label, **{**st, "linewidth": 1.4})
    ref = data.series_named("mu^4 reference")
    # Kapitza's error lies on its leading term: open circles at every 25th sample keep both in view.
    axe.loglog(ref.x[::25], ref.y[::25], color="k", linestyle="none", marker="o", markersize=4.5,
               markerfacecolor="none", markeredgewidth=0.8, label=ref.label, zorder=4)
    axe.set_xlabel(r"$\mu = \sqrt{g/A}$")
    axe.set_ylabel(r"$|\varepsilon_\mathrm{approx}/\varepsilon_\mathrm{exact} - 1|$")
    axe.set_title("relative error of each approximated edge", fontsize=10)
    axe.set_ylim(1e-15, 10)
    axe.grid(True, which="major", color="0.92", linewidth=0.6)
    axe.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=7.5, frameon=False, ncol=2)
    return data


#: Figure number -> drawing function.
DRAW = {1: figure1, 2: figure2, 3: figure3, 4: figure4, 5: figure5, 6: figure6, 7: figure7, 8: figure8}


def make_figure(number, data=None):
    """The complete Figure ``number`` with its caption: ``(fig, data)``."""
    if number not in DRAW:
        raise ValueError(f"the paper has Figures 1-8; got {number!r}")
    data = data or D.ALL_FIGURES[number]()
    DRAW[number](None, data)
    fig = plt.gcf()
    caption(fig, f"Figure {number}. {data.caption}")
    return fig, data


def write_figure(number, out_dir, data=None):
    """Write ``figureN.png``, ``figureN.svg``, ``figureN.json`` and ``figureN.csv`` into ``out_dir``.

    Returns
    -------
    data : FigureData
    paths : list of Path
    """
    out_dir = Path(out_dir)
    fig, data = make_figure(number, data)
    try:
        paths = save(fig, out_dir / f"figure{number}")
    finally:
        plt.close(fig)
    paths.append(_io.write_json(out_dir / f"figure{number}.json", data.as_dict()))
    paths.append(_io.write_csv(out_dir / f"figure{number}.csv", data.csv_header(), data.csv_rows(),
                               data.csv_comments()))
    return data, paths
