"""The map of a sweep over the chart, with the exact linear zone edges drawn on top."""
from __future__ import annotations

import numpy as np

from ..curves import edge_kinds
from ..parameters import G_EARTH
from ..zones import period_edges
from ._style import EDGE_2T, EDGE_4T, Drawn, caption, new_figure, place_legend, real_log_ticks

__all__ = ["plot_sweep_map", "sweep_figure"]

_AXES = {"arnold": (r"$\varepsilon = T\sqrt{A/(8l)}$", r"$\mu = \sqrt{g/A}$"),
         "physical": ("half-period $T$ [s]", "acceleration amplitude $A$ [m/s$^2$]"),
         "rig": ("drive frequency [Hz]", "stroke (peak-to-peak travel of the pivot) [mm]")}


def _log_cell_edges(v):
    """Cell boundaries of grid values ``v`` on a log axis: geometric midpoints, the end cells as wide
    as their neighbours (a single value, or a window of one value repeated, a factor 1.25 either way)."""
    v = np.log(np.asarray(v, float))
    if v[0] == v[-1]:
        return np.exp(np.linspace(v[0] - np.log(1.25), v[0] + np.log(1.25), v.size + 1))
    half = np.full(1, np.log(1.25)) if v.size == 1 else np.diff(v) / 2.0
    return np.exp(np.concatenate([[v[0] - half[0]], v[:-1] + half, [v[-1] + half[-1]]]))


def _rig_edges(f_range, s_range, l, g, drive, c, points=300):
    """``[(n, stroke [m], f_lo, f_hi)]`` of the zones in the window of the rig plane (damping ``c``
    [1/s]; :func:`kapitza.rig_plane.rig_zone_curves`). An edge beyond the window at a stroke is put
    a decade outside it, as the rig chart draws it, so that a nearly level edge runs off the side."""
    from ..drives._api import zeta_of
    from ..rig_plane import rig_zone_curves

    rc = rig_zone_curves(f_range, s_range, l, g, drive, float(zeta_of(c, l, g)), points)
    lo = np.where(rc.f_lo == -np.inf, f_range[0] / 10.0, rc.f_lo)
    hi = np.where(rc.f_hi == np.inf, f_range[1] * 10.0, rc.f_hi)
    return [(int(n), rc.stroke, lo[i], hi[i]) for i, n in enumerate(rc.n)]


def _edges(plane, y_range, x_max, l, g, drive, points=400, max_zones=60, c=0.0):
    """``[(n, y, x_lo, x_hi)]`` of the zones that reach into ``x <= x_max`` (damping ``c`` [1/s])."""
    from ..curves import mu_top
    from ..drives import as_drive

    out = []
    d = as_drive(drive)
    top = mu_top(drive)  # beyond it no zone: the upright always falls
    if plane == "arnold":
        y = np.linspace(max(y_range[0], 1e-3), min(y_range[1], 0.999 * top), points)
    else:
        y = np.linspace(max(y_range[0], 1.0001 * g / top**2), y_range[1], points)
    if y.size == 0 or y[0] >= y[-1]:
        return out
    for n in range(max_zones):
        lo, hi = (d.edges(y, np.int64(n), np.asarray(0.5 * c * np.sqrt(l / g)), certify=False) if plane == "arnold"
                  else period_edges(y, n, l, g, drive=drive, damping=c))
        if not np.any(np.isfinite(lo)) or np.nanmin(lo) > x_max:
            break
        out.append((n, y, lo, hi))
    return out


def plot_sweep_map(x, y, values, *, plane="arnold", ax=None, l=1.0, g=G_EARTH, drive=None, label=None,
                   cmap="viridis", colorbar=True, edges=True, damping=0.0):
    """Draw a sweep's map ``values[y, x]`` with the exact zone edges on top.

    Parameters
    ----------
    x, y : array_like
        Grid columns (``eps``, ``T`` [s] or drive frequency [Hz]) and rows (``mu``, ``A`` [m/s^2] or
        stroke [m]).
    values : array_like, shape ``(y.size, x.size)``
    plane : {'arnold', 'physical', 'rig'}
        The rig plane is drawn as ``kapitza chart --plane rig`` draws it: both axes logarithmic with
        plain-number ticks, the stroke in millimetres, the edges from :func:`kapitza.rig_plane.rig_zone_curves`.
    ax : matplotlib Axes, optional
    l, g, drive, damping :
        The pendulum, drive and viscous damping ``c`` [1/s] of the sweep (for the edges,
        :func:`kapitza.zone_edges` / :func:`kapitza.period_edges`).
    label : str, optional
        Colour-bar label.
    edges : bool
        Draw the zone edges (2T-periodic solid, 4T-periodic dashed, ``docs/theory.md`` section 5).

    Returns
    -------
    Drawn
        ``mesh``, ``colorbar``, ``edges`` (list of lines).
    """
    import matplotlib.pyplot as plt

    if ax is None:
        ax = plt.figure().add_subplot()
    x, y, v = np.asarray(x, float), np.asarray(y, float), np.asarray(values, float)
    if plane == "rig":
        return _plot_rig_map(ax, x, y, v, l, g, drive, label, cmap, colorbar, edges, damping)
    mesh = ax.pcolormesh(x, y, v, shading="nearest", cmap=cmap, rasterized=True)
    drawn = Drawn(ax, {"mesh": mesh, "edges": []})
    if colorbar:
        drawn["colorbar"] = ax.figure.colorbar(mesh, ax=ax, label=label)
    if edges:
        for n, yy, lo, hi in _edges(plane, (y.min(), y.max()), x.max(), l, g, drive, c=float(damping)):
            lo_style, hi_style = (EDGE_2T, EDGE_4T) if edge_kinds(n)[0] == "2T" else (EDGE_4T, EDGE_2T)
            a = ax.plot(lo, yy, **lo_style, label="2T-periodic edge" if n == 0 else None)
            b = ax.plot(hi, yy, **hi_style, label="4T-periodic edge" if n == 0 else None)
            drawn["edges"] += a + b
    dx = 0.5 * (x[1] - x[0]) if x.size > 1 else 0.5 * x[0]
    dy = 0.5 * (y[1] - y[0]) if y.size > 1 else 0.5 * y[0]
    ax.set_xlim(x.min() - dx, x.max() + dx)
    ax.set_ylim(y.min() - dy, y.max() + dy)
    ax.set_xlabel(_AXES[plane][0])
    ax.set_ylabel(_AXES[plane][1])
    return drawn


def _plot_rig_map(ax, f, s, v, l, g, drive, label, cmap, colorbar, edges, damping):
    """The rig plane as ``kapitza chart --plane rig`` draws it: frequency [Hz] across, stroke [mm] up,
    both logarithmic with plain-number ticks, the zone edges of :mod:`kapitza.rig_plane` on top."""
    fe, se = _log_cell_edges(f), _log_cell_edges(s)
    mesh = ax.pcolormesh(fe, 1e3 * se, v, shading="flat", cmap=cmap, rasterized=True)
    drawn = Drawn(ax, {"mesh": mesh, "edges": []})
    if colorbar:
        drawn["colorbar"] = ax.figure.colorbar(mesh, ax=ax, label=label)
    if edges:
        named = set()
        for n, stroke, lo, hi in _rig_edges((fe[0], fe[-1]), (se[0], se[-1]), l, g, drive, float(damping)):
            for f_edge, kind in zip((lo, hi), edge_kinds(n)):
                if not np.any((f_edge > fe[0]) & (f_edge < fe[-1])):  # beyond the window at every stroke
                    continue
                style, name = (EDGE_2T, "2T-periodic edge") if kind == "2T" else (EDGE_4T, "4T-periodic edge")
                drawn["edges"] += ax.plot(f_edge, 1e3 * stroke, **style, label=None if name in named else name)
                named.add(name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(fe[0], fe[-1])
    ax.set_ylim(1e3 * se[0], 1e3 * se[-1])
    real_log_ticks(ax.xaxis)
    real_log_ticks(ax.yaxis)
    ax.set_xlabel(_AXES["rig"][0])
    ax.set_ylabel(_AXES["rig"][1])
    return drawn


def sweep_figure(x, y, values, *, plane="arnold", label, what, periods, tol, l=1.0, g=G_EARTH, drive=None,
                 title=None, damping=0.0, exact=True):
    """A captioned figure of one sweep variable (see :func:`plot_sweep_map`); ``exact``: whether the
    sweep followed the motion exactly or by DOP853 (the caption says which)."""
    rig = ""
    if plane == "rig":
        from ..drives import as_drive
        from ..rig_plane import stroke_coefficient

        d = as_drive(drive)
        rig = (f" Rig plane ({d.describe()}, l = {l:.4g} m, g = {g:g} m/s$^2$): drive frequency $f = 1/(2T)$ and "
               f"stroke $s = k A T^2$ (peak-to-peak travel, $k$ = {stroke_coefficient(d):.4g}), both axes "
               "logarithmic; at a fixed stroke a zone is a band of frequencies.")
    fig = new_figure(7.0, 5.0, caption_lines=4 if rig else 3)
    ax = fig.add_subplot()
    drawn = plot_sweep_map(x, y, values, plane=plane, ax=ax, l=l, g=g, drive=drive, label=label, damping=damping)
    if drawn["edges"]:
        place_legend(ax, inside=True, loc="upper right")
    ax.set_title(title or f"{what}: {periods} periods, window $|\\theta| \\leq$ {tol:g} rad", fontsize=10)
    caption(fig, f"Colour: {what} of the full (nonlinear) pendulum: starts that keep $|\\theta| \\leq$ {tol:g} rad "
                 f"for {periods} drive periods $2T$"
                 + (f", damping $c$ = {damping:g} 1/s" if damping else "")
                 + (", checked on the continuous motion" if exact else
                    ", followed by DOP853 and checked at sampled instants") + ". Lines: the exact edges of the "
                 "linear stability zones (solid: a 2T-periodic solution, dashed: a 4T-periodic one). Inside a zone the "
                 "upright is linearly stable; the colour shows how far it can be knocked and still stand." + rig)
    return fig
