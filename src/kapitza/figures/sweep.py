"""The map of a sweep over the chart, with the exact linear zone edges drawn on top."""
from __future__ import annotations

import numpy as np

from ..curves import edge_kinds
from ..parameters import G_EARTH
from ..zones import period_edges
from ._style import EDGE_2T, EDGE_4T, Drawn, caption, new_figure, place_legend

__all__ = ["plot_sweep_map", "sweep_figure"]

_AXES = {"arnold": (r"$\varepsilon = T\sqrt{A/(8l)}$", r"$\mu = \sqrt{g/A}$"),
         "physical": ("half-period $T$ [s]", "acceleration amplitude $A$ [m/s$^2$]")}


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
        Grid columns (``eps`` or ``T`` [s]) and rows (``mu`` or ``A`` [m/s^2]).
    values : array_like, shape ``(y.size, x.size)``
    plane : {'arnold', 'physical'}
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


def sweep_figure(x, y, values, *, plane="arnold", label, what, periods, tol, l=1.0, g=G_EARTH, drive=None,
                 title=None, damping=0.0, exact=True):
    """A captioned figure of one sweep variable (see :func:`plot_sweep_map`); ``exact``: whether the
    sweep followed the motion exactly or by DOP853 (the caption says which)."""
    fig = new_figure(7.0, 5.0, caption_lines=3)
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
                 "upright is linearly stable; the colour shows how far it can be knocked and still stand.")
    return fig
