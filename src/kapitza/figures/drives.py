"""Several drives on one chart: their exact stability zones overlaid on Arnold's plane."""
from __future__ import annotations

import numpy as np

from ..curves import DriveCurves, drive_curves
from .. import _validate as _v
from . import _style
from ._style import Drawn

__all__ = ["DriveCurves", "drive_curves", "plot_drive_comparison", "drive_comparison_figure"]

#: One colour per drive, in order (colour-blind safe).
DRIVE_COLOURS = ["#1f4e9c", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9"]


def plot_drive_comparison(curves, ax=None, eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), averaging=True,
                          legend="inside"):
    """Overlay the stability zones of several drives (``DriveCurves``) on one eps-mu chart.

    Each drive has one colour: its zones filled lightly, their edges drawn as curves (so thin
    tongues stay visible), its averaging criterion ``<v^2> = g l`` dashed.

    Parameters
    ----------
    curves : sequence of DriveCurves
        From :func:`drive_curves`.
    ax : matplotlib Axes, optional
        Drawn on a new figure when None.
    eps_range, mu_range : (float, float)
        The window.
    averaging : bool
        Draw each drive's averaging criterion.
    legend : {"inside", "outside", None}
        Legend inside the axes (best corner), beside them, or none (``True`` means inside).

    Returns
    -------
    Drawn
        ``"fills"``, ``"edges"``, ``"averaging"`` (lists of artists) and ``"legend"``, with
        ``.ax`` and ``.data`` (the curves).

    Raises
    ------
    KapitzaValueError
        If ``legend`` is not one of its three choices (checked before anything is drawn).

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> from kapitza.figures import drive_curves, plot_drive_comparison
    >>> mu = np.linspace(0.01, 0.99, 40)
    >>> curves = [drive_curves(d, mu, eps_max=4.0) for d in (kapitza.SquareWave(), kapitza.SineWave())]
    >>> drawn = plot_drive_comparison(curves)
    >>> sorted(drawn)
    ['averaging', 'edges', 'fills', 'legend']
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    if legend is True:
        legend = "inside"
    if legend not in (None, False, "inside", "outside"):
        raise _v.KapitzaValueError(f"legend must be 'inside', 'outside' or None; got {legend!r}")
    if ax is None:
        _, ax = plt.subplots()
    out = Drawn(ax, {"fills": [], "edges": [], "averaging": []}, data=list(curves))
    drawn = set()
    names = list(dict.fromkeys(c.drive for c in curves))
    undamped = {c.drive for c in curves if c.zeta == 0}
    for c in curves:
        colour = DRIVE_COLOURS[names.index(c.drive) % len(DRIVE_COLOURS)]
        damped = c.zeta > 0
        label = c.drive + (f", damping ratio {c.zeta:g}" if damped else "")
        style = dict(color=colour, linewidth=1.1, linestyle=(0, (6, 2, 1, 2)) if damped else "-")
        for k in range(c.zones.size):
            ok = np.isfinite(c.lo[k]) & ~np.isnan(c.hi[k])
            hi = np.minimum(c.hi[k][ok], eps_range[1])  # an edge beyond the view: paint to its end
            if not damped or c.drive not in undamped:  # damped zones as outlines over the undamped fills
                out["fills"].append(ax.fill_betweenx(c.mu[ok], c.lo[k][ok], hi, color=colour, alpha=0.18,
                                                     linewidth=0))
            out["edges"] += ax.plot(c.lo[k][ok], c.mu[ok], label=label if k == 0 else None, **style)
            fin = np.isfinite(c.hi[k][ok])
            out["edges"] += ax.plot(np.where(fin, hi, np.nan), c.mu[ok], **style)
        if averaging and c.drive not in drawn:  # the criterion does not depend on the damping
            drawn.add(c.drive)
            out["averaging"] += ax.plot(c.averaging, c.mu, color=colour, linewidth=1.0, linestyle=(0, (4, 3)))
    if out["averaging"]:  # one legend row says what the dashed lines are (each in its drive's colour)
        out["averaging"] += ax.plot([], [], color="0.35", linewidth=1.0, linestyle=(0, (4, 3)),
                                    label=r"averaging criterion $\langle v^2\rangle = g\,l$ (dashed)")
    ax.set_xlim(*eps_range)
    ax.set_ylim(*mu_range)
    ax.set_xlabel(r"$\varepsilon = T\sqrt{A/(8l)}$")
    ax.set_ylabel(r"$\mu = \sqrt{g/A}$")
    if legend:
        out["legend"] = _style.place_legend(ax, inside=(legend == "inside"), fontsize=7)
    return out


def drive_comparison_figure(curves, eps_max=4.0, zoom=(1.2, 0.6), title=None):
    """Two panels: the whole chart and a zoom on zone 0 near Kapitza's limit; returns the figure.

    Parameters
    ----------
    curves : sequence of DriveCurves
        From :func:`drive_curves`, one per drive.
    eps_max : float
        The whole chart's ``eps`` range is ``(0, eps_max)``.
    zoom : (float, float)
        The zoomed panel's largest ``eps`` and ``mu``.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    KapitzaValueError
        If ``curves`` is empty or holds something other than :class:`~kapitza.curves.DriveCurves`,
        or ``eps_max`` or either end of ``zoom`` is not a positive number; no figure is made then.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> from kapitza.figures import drive_comparison_figure, drive_curves
    >>> mu = np.linspace(0.01, 0.99, 40)
    >>> curves = [drive_curves(d, mu, eps_max=4.0) for d in (kapitza.SquareWave(), kapitza.SineWave())]
    >>> fig = drive_comparison_figure(curves)
    >>> len(fig.axes)
    2
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    curves = list(curves)
    if not curves or not all(isinstance(c, DriveCurves) for c in curves):
        raise _v.KapitzaValueError("curves must be one or more kapitza.curves.DriveCurves (drive_curves); got "
                                   + (", ".join(sorted({type(c).__name__ for c in curves})) or "none"))
    eps_max = _v.one("eps_max", _v.positive("eps_max", eps_max))
    try:
        zoom_eps, zoom_mu = zoom
    except (TypeError, ValueError):
        raise _v.KapitzaValueError(f"zoom must be a pair (eps, mu); got {_v._short(zoom)}") from None
    zoom = (_v.one("zoom eps", _v.positive("zoom eps", zoom_eps)), _v.one("zoom mu", _v.positive("zoom mu", zoom_mu)))
    fig = _style.new_figure(width=11.0, height=5.0, caption_lines=3)
    ax1, ax2 = fig.subplots(1, 2)
    plot_drive_comparison(curves, ax1, eps_range=(0.0, eps_max), legend=None)
    plot_drive_comparison(curves, ax2, eps_range=(0.0, zoom[0]), mu_range=(0.0, zoom[1]), legend=None)
    handles, labels = ax1.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside upper center", ncols=min(len(labels), 4), fontsize=8, frameon=False)
    ax1.set_title("stability zones (filled) and their exact edges", fontsize=9)
    ax2.set_title("zone 0 near the averaging limit", fontsize=9)
    if title:
        fig.suptitle(title)
    damped = any(c.zeta > 0 for c in curves)
    # Which zones are thinner than about a line width (0.4 % of the window) somewhere in view.
    thin = sorted({c.drive for c in curves for k in range(c.zones.size) if int(c.zones[k]) >= 1
                   and np.any(np.isfinite(c.lo[k]) & (c.lo[k] < eps_max) & (c.hi[k] - c.lo[k] < 0.004 * eps_max))})
    _style.caption(fig, "The upright is stable inside the filled zones; each colour is one drive"
                        + (", dash-dotted with damping" if damped else "") + ". All drives share Arnold's axes: "
                        r"$T$ is half the drive period, $A$ its acceleration scale. Dashed: each drive's "
                        r"high-frequency (averaging) criterion $\langle v^2\rangle = g\,l$, which the exact lower "
                        r"edge of zone 0 approaches as $\mu \to 0$."
                        + (r" Some zones $n \geq 1$ are thinner than a line in parts of the left panel (drives: "
                           + "; ".join(thin) + "): there their two edges are drawn as one curve; a kapitza chart "
                           "window zoomed on one (--eps-min ... --mu-max) shows both." if thin else ""))
    return fig
