"""Stability charts: the exact zones on Arnold's ``eps``-``mu`` plane (Figure 7 of the paper)
and in the physical ``T``-``A`` plane of a given rod."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from ..parameters import SQRT8
from ..curves import (PhysicalZoneCurves, ZoneCurves, mu_top, physical_window, physical_zone_curves, window_range,
                      zone_curves)
from .._square import _edges_eps
from ._style import EDGE_2T, EDGE_4T, G_STYLE, ZONE_FILL, Drawn, place_legend, real_log_ticks

__all__ = [
    "ZoneCurves",
    "zone_curves",
    "plot_zones",
    "magnified_zones",
    "magnified_zones_physical",
    "zone_chart_axes",
    "TongueCurves",
    "tongue_curves",
    "plot_tongue",
    "PhysicalZoneCurves",
    "plot_zones_physical",
    "chart_figure",
    "plot_zones_rig",
    "rig_chart_figure",
]


def _draw_tongues(ax, n, y, x_lo, x_hi, x_range, label_zones=True):
    """Fill each tongue and draw its two edges, 2T- and 4T-periodic styled apart."""
    fills, edges = [], []
    for i, k in enumerate(n):
        lo, hi = x_lo[i], x_hi[i]
        fills.append(ax.fill_betweenx(y, lo, hi, color=ZONE_FILL, linewidth=0, label="stable zone" if i == 0 else None))
        lower_2t = k % 2 == 0
        edges += ax.plot(lo, y, **(EDGE_2T if lower_2t else EDGE_4T))
        edges += ax.plot(hi, y, **(EDGE_4T if lower_2t else EDGE_2T))
        if label_zones:
            # Label each tongue just right of its upper edge, near the bottom of the window.
            inside = (hi > x_range[0]) & (hi < x_range[0] + 0.93 * (x_range[1] - x_range[0]))  # room for the label
            if inside.any():
                j = int(np.flatnonzero(inside)[min(np.count_nonzero(inside) - 1, len(y) // 8)])
                ax.annotate(f"n={k}", (hi[j], y[j]), xytext=(3, 0), textcoords="offset points",
                            fontsize=8, va="center", ha="left", color="0.15",
                            bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7))
    ax.plot([], [], label=r"2T-periodic edge ($T_n$)", **EDGE_2T)
    ax.plot([], [], label=r"4T-periodic edge ($\tilde T_n$)", **EDGE_4T)
    return {"fill": fills, "edges": edges}


def plot_zones(ax=None, eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), show_G=True, points=1200, label_zones=True,
               legend="outside", drive=None, zeta=0.0):
    """Draw the exact stability zones in the ``eps``-``mu`` plane.

    Parameters
    ----------
    ax : matplotlib Axes, optional
        Where to draw; a new figure is made if None.
    eps_range, mu_range : (float, float)
        The window. The edges are recomputed exactly for it, so zooming on a thin
        tongue shows both of its edges.
    show_G : bool
        Also draw the curves ``G_m`` along which the tongues lie.
    points : int
        ``mu`` samples per edge.
    label_zones : bool
        Write the zone index beside each tongue.
    legend : {"outside", "inside", None}
        Legend just right of the axes, inside them, or none.
    drive : Drive or str, optional
        The pivot's motion (``"sine"``, ``"rectangular:0.3"``, a :class:`kapitza.drives.Drive`);
        the paper's square wave by default.
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))`` (0: undamped). With another drive or damping the edges
        are root solves (:func:`kapitza.figures.drives.drive_curves`; ``show_G`` does not apply).

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"edges"`` (lists), ``"G"``; ``.data`` the :class:`ZoneCurves` (another
        drive or damping: the drive's curves).

    Raises
    ------
    ValueError
        If the window is empty or outside the plane, or another argument is out of range
        (:func:`kapitza.curves.window_curves`).

    Notes
    -----
    2T-periodic edges (``T_n``; lower edge of even zones, upper edge of odd ones)
    and 4T-periodic edges (``T~_n``) are styled apart. Each edge is drawn as a
    line, so a tongue thinner than a pixel still shows; :func:`plot_tongue`
    magnifies one.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from kapitza.figures import plot_zones
    >>> fig, ax = plt.subplots()
    >>> drawn = plot_zones(ax, eps_range=(0, 2))
    >>> sorted(drawn)
    ['G', 'edges', 'fill', 'legend']
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    from ..drives import as_drive

    general = as_drive(drive)
    general = None if general.closed_form(_v.damping_ratio(zeta)) else general
    if general is not None:
        from .drives import drive_curves, plot_drive_comparison

        top = mu_top(general)
        window_range(eps_range, mu_range, top)
        mu_s = np.linspace(max(mu_range[0], 1e-3), min(mu_range[1], 0.999 * top), min(points, 4000))
        dc = drive_curves(general, mu_s, eps_range[1], float(zeta))
        out = plot_drive_comparison([dc], ax, eps_range=eps_range, mu_range=mu_range)
        ax.set_xlabel(r"$\varepsilon = T\sqrt{A}/\sqrt{8l}$")
        ax.set_ylabel(r"$\mu = \sqrt{g/A}$")
        if not legend and out.get("legend") is not None:
            out["legend"].remove()
        return out
    curves = zone_curves(eps_range, mu_range, points)
    out = Drawn(ax, _draw_tongues(ax, curves.n, curves.mu, curves.eps_lo, curves.eps_hi, eps_range, label_zones),
                data=curves)
    out["G"] = []
    if show_G:
        mu = curves.mu
        q = np.sqrt((1.0 - mu) * (1.0 + mu))
        m_max = int(np.floor((2.0 * SQRT8 * q.max() * eps_range[1] / np.pi - 1.0) / 2.0))
        for m in range(0, max(m_max, -1) + 1):
            out["G"] += ax.plot((2 * m + 1) * np.pi / (2.0 * SQRT8 * q), mu, **G_STYLE,
                                label=r"$G_m$" if m == 0 else None)
    ax.set_xlim(*eps_range)
    ax.set_ylim(*mu_range)
    ax.set_xlabel(r"$\varepsilon = T\sqrt{A}/\sqrt{8l}$")
    ax.set_ylabel(r"$\mu = \sqrt{g/A}$")
    if legend:
        out["legend"] = place_legend(ax, inside=(legend == "inside"))
    return out


def magnified_zones(eps_range, mu_range, candidates=(1, 2, 3), fraction=0.02):
    """Zones among ``candidates`` that meet the window but are narrower than ``fraction``
    of its width everywhere in it: those a chart should magnify.

    Parameters
    ----------
    eps_range, mu_range : (float, float)
        The window.
    candidates : sequence of int
        Zones to consider.
    fraction : float
        Of the window's ``eps`` width.

    Returns
    -------
    list of int

    Raises
    ------
    ValueError
        If the window is not as in :func:`kapitza.curves.window_range`.

    Examples
    --------
    >>> from kapitza.figures import magnified_zones
    >>> magnified_zones((0, 4), (0, 1))
    [1, 2, 3]
    >>> magnified_zones((1.7, 1.9), (0.2, 0.4))
    []
    """
    curves = zone_curves(eps_range, mu_range, 200)
    width = float(eps_range[1] - eps_range[0])
    keep = []
    for i, n in enumerate(curves.n):
        seen = (curves.eps_hi[i] >= eps_range[0]) & (curves.eps_lo[i] <= eps_range[1])
        if (int(n) in candidates and seen.any()
                and np.max((curves.eps_hi[i] - curves.eps_lo[i])[seen]) < fraction * width):
            keep.append(int(n))
    return keep


def magnified_zones_physical(T_range, A_range, l=1.0, g=9.81, candidates=(1, 2, 3), fraction=0.02):
    """As :func:`magnified_zones`, for the physical ``T``-``A`` window of a rod ``l`` under ``g``:
    the zones narrower in ``T`` than ``fraction`` of the window wherever they meet it."""
    curves = physical_zone_curves(T_range, A_range, l, g, 200)
    T_lo, T_hi = curves.T_lo, curves.T_hi
    width = float(T_range[1] - T_range[0])
    keep = []
    for i, n in enumerate(curves.n):
        seen = (T_hi[i] >= T_range[0]) & (T_lo[i] <= T_range[1])
        if int(n) in candidates and seen.any() and np.max((T_hi[i] - T_lo[i])[seen]) < fraction * width:
            keep.append(int(n))
    return keep


def zone_chart_axes(fig, count):
    """The main Axes of a zone chart and ``count`` panels below it for magnified tongues.

    Parameters
    ----------
    fig : matplotlib Figure
    count : int
        Panels for magnified zones (0: the main Axes alone).

    Returns
    -------
    main, list of panels : matplotlib Axes

    Raises
    ------
    KapitzaValueError
        If ``count`` is not a whole number from 0 to 12.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from kapitza.figures import zone_chart_axes
    >>> main, panels = zone_chart_axes(plt.figure(), 2)
    >>> len(panels)
    2
    >>> plt.close("all")
    """
    count = _v.bounded_count("count", count, 12, what="panels in one row under the chart")
    if count == 0:
        return fig.add_subplot(), []
    gs = fig.add_gridspec(2, count, height_ratios=(2.4, 1.0))
    return fig.add_subplot(gs[0, :]), [fig.add_subplot(gs[1, i]) for i in range(count)]


@dataclass(frozen=True)
class TongueCurves:
    """One tongue magnified: zone ``n`` at the samples ``mu``, its edges as offsets from
    the tongue's midpoint ``eps_mid(mu)`` in units of ``scale = 10**exponent``.

    Attributes
    ----------
    n : int
    mu, eps_mid, eps_lo, eps_hi : ndarray
        The exact edges and their midpoint.
    lo, hi : ndarray
        ``(eps_lo - eps_mid) / scale`` and ``(eps_hi - eps_mid) / scale``: what is drawn.
    exponent : int
    scale : float
    """

    n: int
    mu: np.ndarray
    eps_mid: np.ndarray
    eps_lo: np.ndarray
    eps_hi: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    exponent: int
    scale: float


def tongue_curves(n, mu_range=(0.0, 1.0), points=400, *, drive=None, zeta=0.0):
    """The edges of zone ``n`` relative to its own midpoint, scaled so the tongue fills a panel.

    Parameters
    ----------
    n : int
        Zone index, ``>= 0``.
    mu_range : (float, float)
        ``0 <= mu_min < mu_max <= 1`` (for another drive, up to its :func:`kapitza.curves.mu_top`).
    points : int
        Samples of ``mu`` (>= 2).
    drive : Drive or str, optional
        The pivot's motion (``"sine"``, ``"rectangular:0.3"``, ...); the paper's square wave by default.
    zeta : float, optional
        Damping ratio (0: undamped). With another drive or damping the edges are
        :func:`kapitza.zone_edges`' root solves (NaN where the drive has no such zone).

    Returns
    -------
    TongueCurves

    Raises
    ------
    ValueError
        If ``n`` is not an integer ``>= 0``, the range is not as above, or ``points`` is below 2.

    Notes
    -----
    The zones ``n >= 1`` are exponentially narrow (``docs/theory.md``; widths in ``eps`` of
    0.013, 5e-4, 2e-5 for ``n = 1, 2, 3`` at small ``mu``): on the whole plane the two edges
    of each merge into one line. Measured from the midpoint in a power of ten that suits the zone,
    as Figure 6 magnifies its zones, both edges are distinct curves. The edges are exact at
    every sample (:func:`kapitza.zone_edges`).

    Examples
    --------
    >>> from kapitza.figures import tongue_curves
    >>> tc = tongue_curves(1, points=50)
    >>> type(tc).__name__, tc.mu.shape
    ('TongueCurves', (50,))
    """
    n = int(_v.nonnegative_int("n", n))
    points = _v.bounded_count("points", points, _v.MAX_POINTS, minimum=2)
    m0, m1 = (float(v) for v in mu_range)
    if not (0.0 <= m0 < m1 <= 1.0):
        raise _v.KapitzaValueError(f"mu range must satisfy 0 <= mu_min < mu_max <= 1; got ({m0:g}, {m1:g})")
    from ..drives import as_drive

    general = as_drive(drive)
    zeta = _v.damping_ratio(zeta)
    tiny = 1e-9
    if general.closed_form(zeta):
        mu = np.clip(np.linspace(m0, m1, points), tiny, 1.0 - tiny)
        lo, hi = _edges_eps(mu, n)
    else:
        from ..zones import zone_edges

        top = min(1.0, mu_top(general))
        mu = np.clip(np.linspace(m0, m1, points), 1e-3, (1.0 - 1e-6) * top)
        lo, hi = (np.asarray(v, dtype=float) for v in zone_edges(mu, n, drive=general, zeta=zeta))
    mid = 0.5 * (lo + hi)
    half = 0.5 * (hi - lo)
    top = float(np.nanmax(half)) if np.any(np.isfinite(half)) else 0.0
    exponent = int(np.floor(np.log10(top))) if top > 0 else 0
    scale = 10.0**exponent
    return TongueCurves(n=n, mu=mu, eps_mid=mid, eps_lo=lo, eps_hi=hi, lo=-half / scale, hi=half / scale,
                        exponent=exponent, scale=scale)


def plot_tongue(n, ax=None, mu_range=(0.0, 1.0), points=400, title=True, physical=None, *, drive=None, zeta=0.0):
    """Draw zone ``n`` magnified (see :func:`tongue_curves`): both edges, the stable tongue between.

    Parameters
    ----------
    n : int
        Zone index.
    ax : matplotlib Axes, optional
        Where to draw; a new figure is made if None.
    mu_range : (float, float)
    points : int
    title : bool
        Title the panel with the zone and where it lies.
    physical : (l, g), optional
        Draw in the physical plane of a rod ``l`` under ``g`` instead: ``T - T_mid(A)`` [s],
        in the power of ten shown, against ``A = g / mu^2`` (log axis).
    drive, zeta : optional
        The drive and the damping ratio, as in :func:`tongue_curves` (the square wave, undamped, by default).

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"lower"``, ``"upper"``; ``.data`` the :class:`TongueCurves`.

    Raises
    ------
    ValueError
        As in :func:`tongue_curves`.

    Examples
    --------
    >>> from kapitza.figures import plot_tongue
    >>> drawn = plot_tongue(2)
    >>> sorted(drawn)
    ['fill', 'lower', 'upper']
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    t = tongue_curves(n, mu_range, points, drive=drive, zeta=zeta)
    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    lower_2t = t.n % 2 == 0
    out = Drawn(ax, data=t)
    x_lo, x_hi, y, exponent = t.lo, t.hi, t.mu, t.exponent
    if physical is not None:
        l, g = (_v.one(k, _v.positive(k, v)) for k, v in zip(("l", "g"), physical))
        y = g / t.mu**2
        s = np.sqrt(8.0 * l / y)
        half = 0.5 * (t.eps_hi - t.eps_lo) * s
        exponent = int(np.floor(np.log10(float(np.max(half))))) if np.max(half) > 0 else 0
        x_lo, x_hi = -half / 10.0**exponent, half / 10.0**exponent
    out["fill"] = ax.fill_betweenx(y, x_lo, x_hi, color=ZONE_FILL, linewidth=0)
    out["lower"] = ax.plot(x_lo, y, **(EDGE_2T if lower_2t else EDGE_4T))[0]
    out["upper"] = ax.plot(x_hi, y, **(EDGE_4T if lower_2t else EDGE_2T))[0]
    w = 1.15 * max(float(np.nanmax(x_hi)) if np.any(np.isfinite(x_hi)) else 1.0, 1e-300)
    ax.set_xlim(-w, w)
    ax.axvline(0.0, color="0.8", linewidth=0.6, zorder=0)
    ax.tick_params(labelsize=7)
    if physical is not None:
        ax.set_yscale("log")
        ax.set_ylim(float(np.min(y)), float(np.max(y)))
        ax.set_xlabel(rf"$(T - T_\mathrm{{mid}})\,/\,10^{{{exponent}}}$ s", fontsize=8)
        ax.set_ylabel(r"$A$ [m/s$^2$]", fontsize=8)
        if title:
            k = int(np.argmax(y))  # the top of the window
            ax.set_title(rf"zone {t.n}: $T_\mathrm{{mid}}$ = {float(t.eps_mid[k] * s[k]):.3f} s at $A$ = {y[k]:.3g}",
                         fontsize=8)
        return out
    ax.set_ylim(*mu_range)
    ax.set_xlabel(rf"$(\varepsilon - \varepsilon_\mathrm{{mid}})\,/\,10^{{{exponent}}}$", fontsize=8)
    ax.set_ylabel(r"$\mu$", fontsize=8)
    if title:
        ax.set_title(rf"zone {t.n} ($\varepsilon_\mathrm{{mid}}$ = {t.eps_mid[0]:.3f} at $\mu$ = "
                     rf"{float(mu_range[0]):g})",
                     fontsize=8)
    return out


def plot_zones_physical(ax=None, T_range=None, A_range=None, l=1.0, g=9.81, points=1200, label_zones=True,
                        legend="outside", drive=None, zeta=0.0):
    """Draw the exact stability zones in the physical ``T``-``A`` plane of a rod ``l`` under ``g``.

    Parameters
    ----------
    ax : matplotlib Axes, optional
        Where to draw; a new figure is made if None.
    T_range : (float, float), optional
        Half-periods [s]; default ``(0, 2.5 sqrt(l/g))``.
    A_range : (float, float), optional
        Acceleration amplitudes [m/s^2], ``A > g``; default ``(g, 50 g)``, drawn on a log axis.
    l, g : float
        Rod length [m] and gravity [m/s^2].
    points : int
        ``A`` samples per edge.
    label_zones : bool
        Write the zone index beside each tongue.
    legend : {"outside", "inside", None}
        Legend just right of the axes, inside them, or none.
    drive, zeta : optional
        The pivot's motion and the damping ratio ``c / (2 sqrt(g/l))``
        (:func:`kapitza.curves.physical_zone_curves`); the paper's undamped square wave by default.

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"edges"``; ``.data`` the :class:`PhysicalZoneCurves`.

    Raises
    ------
    ValueError
        As in :func:`kapitza.curves.physical_zone_curves`.

    Notes
    -----
    The same edges as :func:`plot_zones`, mapped by ``A = g / mu^2`` and
    ``T = eps sqrt(8 l / A)``: at each ``A`` zone ``n`` is ``T_lo < T < T_hi``
    (:func:`kapitza.period_edges`).

    Examples
    --------
    >>> from kapitza.figures import plot_zones_physical
    >>> drawn = plot_zones_physical(l=1.0, points=200)
    >>> drawn.ax.get_xlabel(), drawn.data.n
    ('half-period of the drive $T$ [s]', array([0, 1, 2, 3, 4, 5]))
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    res = physical_zone_curves(T_range, A_range, l, g, points, drive, zeta)
    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    (T0, T1), (A0, A1) = physical_window(T_range, A_range, res.l, res.g, drive)
    out = Drawn(ax, _draw_tongues(ax, res.n, res.A, res.T_lo, res.T_hi, (T0, T1), label_zones), data=res)
    ax.set_yscale("log")
    ax.set_xlim(T0, T1)
    ax.set_ylim(A0, A1)
    ax.set_xlabel(r"half-period of the drive $T$ [s]")
    ax.set_ylabel(r"pivot acceleration amplitude $A$ [m/s$^2$]")
    if legend:
        out["legend"] = place_legend(ax, inside=(legend == "inside"))
    return out


def chart_figure(plane="arnold", eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), T_range=(0.0, None), A_range=(None, None),
                 *, l=1.0, g=9.81, drive=None, zeta=0.0, points=1200, mark=None, show_G=True, magnify=True,
                 title=None, frequency_range=None, stroke_range=None):
    """The whole chart ``kapitza chart`` writes and the explorer exports: zones, edges, caption.

    Parameters
    ----------
    plane : {"arnold", "physical"}
        Arnold's ``eps``-``mu`` plane, or ``T``-``A`` for the rod ``l`` under ``g``.
    eps_range, mu_range : (float, float)
        The window of the arnold plane.
    T_range, A_range : (float or None, float or None)
        The window of the physical plane; None: ``T`` up to ``2.5 sqrt(l/g)``, ``A`` from ``g``
        (``g / mu_max^2`` for a drive that holds the rod up below ``g``, see :func:`kapitza.curves.mu_top`)
        to ``50 g``.
    drive, zeta :
        The pivot's motion and the damping ratio (:func:`kapitza.curves.window_curves`).
    points : int
        Samples per edge.
    mark : (StabilityReport, str) or None
        A point to mark with a star, and its label.
    show_G : bool
        Draw the curves ``G_m`` (square wave, arnold plane).
    magnify : bool
        Add panels magnifying the zones 1-3 when they are too thin to see (square wave, arnold plane).
    title : str, optional

    Returns
    -------
    (Figure, curves, header)
        The figure, the curves drawn (``.rows()`` for CSV) and the CSV header.
    """
    from ._style import caption, new_figure

    if plane == "rig":
        return rig_chart_figure(frequency_range, stroke_range, l=l, g=g, drive=drive, zeta=zeta,
                                points=min(points, 2000), mark=mark, title=title)
    from ..drives import as_drive

    general = as_drive(drive)
    general = None if general.closed_form(_v.damping_ratio(zeta)) else general
    zeta = float(zeta)
    if plane not in ("arnold", "physical"):
        raise _v.KapitzaValueError(f"plane must be 'arnold', 'physical' or 'rig'; got {plane!r}")
    top = mu_top(general)
    if plane == "arnold":
        window_range(eps_range, mu_range, top)
    physical = None
    if plane == "physical":
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        T_range, A_range = physical_window(T_range, A_range, l, g, general)
    if general is not None or not magnify:
        magnify = []
    elif plane == "arnold":
        magnify = magnified_zones(eps_range, mu_range)
    elif 0.0 <= T_range[0] < T_range[1] and g <= A_range[0] < A_range[1]:
        magnify = magnified_zones_physical(T_range, A_range, l, g)
        physical = (l, g)
        mu_range = (float(np.sqrt(g / A_range[1])), float(min(np.sqrt(g / A_range[0]), 1.0)))
    else:
        magnify = []
    fig = new_figure(8.6, 7.4 if magnify else 5.2)
    ax, zooms = zone_chart_axes(fig, len(magnify))
    for zax, n in zip(zooms, magnify):
        plot_tongue(n, zax, mu_range, points=min(points, 600), physical=physical)
    if general is not None and plane == "physical":
        curves = plot_zones_physical(ax, T_range, A_range, l=l, g=g, points=points, drive=general, zeta=zeta).data
        header = ["n", "A", "T_lo", "T_hi"]
    elif general is not None:
        from .drives import drive_curves, plot_drive_comparison

        mu_s = np.linspace(max(mu_range[0], 1e-3), min(mu_range[1], 0.999 * top), min(points, 4000))
        curves = drive_curves(general, mu_s, eps_range[1], zeta)
        plot_drive_comparison([curves], ax, eps_range=eps_range, mu_range=mu_range)
        header = ["drive", "zeta", "n", "mu", "eps_lo", "eps_hi"]
    elif plane == "arnold":
        curves = plot_zones(ax, eps_range, mu_range, show_G=show_G, points=points).data
        header = ["n", "mu", "eps_lo", "eps_hi"]
        what = r"$\alpha + n\pi < \omega_e T < \beta + n\pi$ (zone $n$)"
        extra = r"; dotted: the curves $G_m$." if show_G else "."
        if magnify:
            extra += (" Lower panels: zone" + ("s " if len(magnify) > 1 else " ") + ", ".join(str(n) for n in magnify)
                      + r", too thin to see above, "
                      r"magnified ($\varepsilon$ from each tongue's midpoint, in the power of ten shown).")
    else:
        curves = plot_zones_physical(ax, T_range, A_range, l=l, g=g, points=points).data
        header = ["n", "A", "T_lo", "T_hi"]
        what = rf"for a rod $l$ = {l:g} m under $g$ = {g:g} m/s$^2$ (zone $n$)"
        extra = r"; below $A = g$ the upright is always unstable."
        if magnify:
            extra += (" Lower panels: zone" + ("s " if len(magnify) > 1 else " ") + ", ".join(str(n) for n in magnify)
                      + r", too thin to see above, magnified ($T$ from each tongue's midpoint at each $A$, in the "
                        r"power of ten shown).")
    if mark is not None:
        rep, label = mark
        if plane == "arnold":
            x, y = rep.eps, rep.mu
        elif rep.T is not None:
            x, y = rep.T, rep.A
        else:
            raise _v.KapitzaValueError("on the physical plane mark a point by its T and A")
        ax.plot([x], [y], marker="*", markersize=13, color="gold", markeredgecolor="k", linestyle="none",
                label=f"{label}: {rep.verdict.split(':')[0].split(' (')[0]}")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    if general is not None:
        damped = f", damping ratio {zeta:g}" if zeta > 0 else ""
        ax.set_title(title or f"Exact stability zones: {general.label}{damped}")
        m = general.mu_max
        falls = (rf" Below $A = {g / m**2:.4g}$ m/s$^2$" if plane == "physical" else rf" Beyond $\mu = {m:.4g}$") + (
            r" the upright always falls: the pivot never accelerates down faster than $g$.")
        caption(fig, f"Shaded: the upright position is stable ({general.describe()}{damped})" + (
            rf" for a rod $l$ = {l:g} m under $g$ = {g:g} m/s$^2$. Solid: edges with a 2T-periodic motion; "
            r"dashed: with a 4T-periodic one." if plane == "physical" else
            r"; lines: the exact zone edges; dashed: the averaging criterion $\langle v^2\rangle = g\,l$.") + falls)
    else:
        ax.set_title(title or "Exact stability zones of the inverted pendulum on a square-wave pivot")
        caption(fig, rf"Shaded: the upright position is stable, {what}. "
                     r"Solid: 2T-periodic edges $T_n$ (eqs. 3.10, 3.11); dashed: 4T-periodic edges $\tilde T_n$ "
                     r"(3.12, 3.13)"
                     + extra)
    return fig, curves, header


_real_log_ticks = real_log_ticks  # (the rig chart's and the rig sweep map's, kept in _style)


def plot_zones_rig(ax=None, frequency_range=None, stroke_range=None, l=1.0, g=9.81, drive=None, zeta=0.0, points=300,
                   around=None, label_zones=True, legend="outside"):
    """Draw the stability zones as a rig is set: drive frequency [Hz] across, stroke [mm] up, both log.

    Parameters
    ----------
    ax : matplotlib Axes, optional
    frequency_range, stroke_range : (float, float), optional
        Hz and metres (the axis shows millimetres); defaults sized to the rig
        (:func:`kapitza.rig_plane.rig_window`, around ``around = (frequency, stroke)`` when given).
    l, g, drive, zeta :
        Equivalent length [m], gravity, the pivot's motion and the damping ratio.
    points : int
        Stroke samples.

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"edges"``; ``.data`` the :class:`kapitza.rig_plane.RigZoneCurves`.

    Raises
    ------
    ValueError
        As in :func:`kapitza.rig_plane.rig_zone_curves`.

    Examples
    --------
    >>> from kapitza.figures.chart import plot_zones_rig
    >>> drawn = plot_zones_rig(l=0.2, around=(40.0, 0.02))
    >>> sorted(drawn), drawn.ax.get_xlim()
    (['edges', 'fill', 'legend'], (np.float64(10.0), np.float64(160.0)))
    >>> drawn.data.n
    array([0])
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    from ..rig_plane import rig_zone_curves

    res = rig_zone_curves(frequency_range, stroke_range, l, g, drive, zeta, points, around)
    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    (f0, f1), (s0, s1) = res.frequency_range, res.stroke_range
    far_lo, far_hi = f0 / 10.0, f1 * 10.0  # an edge beyond the window, drawn outside it
    lo = np.where(res.f_lo == -np.inf, far_lo, res.f_lo)
    hi = np.where(res.f_hi == np.inf, far_hi, res.f_hi)
    out = Drawn(ax, _draw_tongues(ax, res.n, 1e3 * res.stroke, lo, hi, (f0, f1), label_zones=False), data=res)
    for i, k in enumerate(res.n):
        if not label_zones:
            break
        ok = np.flatnonzero(np.isfinite(lo[i]) & np.isfinite(hi[i]) & (hi[i] > f0) & (lo[i] < f1))
        if ok.size:
            j = int(ok[ok.size // 3])
            x = float(np.sqrt(max(lo[i, j], f0) * min(hi[i, j], f1)))
            ax.annotate(f"n={k}", (x, 1e3 * res.stroke[j]), fontsize=9, ha="center", va="center", color="0.15",
                        bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.75))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(f0, f1)
    ax.set_ylim(1e3 * s0, 1e3 * s1)
    _real_log_ticks(ax.xaxis)
    _real_log_ticks(ax.yaxis)
    ax.set_xlabel("drive frequency [Hz]")
    ax.set_ylabel("stroke (peak-to-peak travel of the pivot) [mm]")
    ax.grid(True, which="major", color="0.88", linewidth=0.6)
    if legend:
        out["legend"] = place_legend(ax, inside=(legend == "inside"))
    return out


def rig_chart_figure(frequency_range=None, stroke_range=None, *, l=1.0, g=9.81, drive=None, zeta=0.0, points=300,
                     mark=None, title=None, rod=None):
    """The frequency-stroke chart of a rig (``kapitza chart --plane rig``): the zones on log axes with
    real tick labels, the window sized to the rig (around the marked point when there is one).

    ``mark``: ``(StabilityReport, label)`` with physical ``T`` and ``A``: starred, and the window centred
    on it. Returns ``(Figure, RigZoneCurves, CSV header)``.

    Parameters
    ----------
    frequency_range, stroke_range : (float, float), optional
        The window [Hz], [m] (:func:`kapitza.rig_plane.rig_window` by default).
    l, g, drive, zeta, points :
        As in :func:`plot_zones_rig`.
    mark : (StabilityReport, str), optional
        The rig's report (physical ``T`` and ``A``) and its label.
    title : str, optional
    rod : float, optional
        The rod's own length [m], for the caption.

    Returns
    -------
    (Figure, RigZoneCurves, list of str)

    Raises
    ------
    ValueError
        As in :func:`kapitza.rig_plane.rig_zone_curves`, or a ``mark`` without ``T`` and ``A``.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures.chart import rig_chart_figure
    >>> rig = kapitza.Rig(kapitza.Pendulum.uniform_rod(0.3))
    >>> report = rig.analyze(frequency=40.0, stroke=0.02)
    >>> fig, curves, header = rig_chart_figure(l=rig.pendulum.l, mark=(report, "the rig"), rod=0.3)
    >>> header, curves.frequency_range
    (['n', 'stroke', 'f_lo', 'f_hi'], (10.0, 160.0))
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    from ..drives import as_drive, parse_drive
    from ._style import caption, new_figure

    d = parse_drive(drive) if isinstance(drive, str) else as_drive(drive)
    around = None
    if mark is not None:
        rep = mark[0]
        if rep.T is None:
            raise _v.KapitzaValueError("on the rig plane mark a point by its frequency and stroke (or T and A)")
        around = (0.5 / rep.T, float(d.stroke(rep.T, rep.A)))
    fig = new_figure(8.6, 5.4)
    ax = fig.add_subplot()
    res = plot_zones_rig(ax, frequency_range, stroke_range, l, g, d, zeta, points, around, legend=None).data
    if mark is not None:
        f, s = around
        ax.plot([f], [1e3 * s], marker="*", markersize=14, color="gold", markeredgecolor="k", linestyle="none",
                label=f"{mark[1]}: {mark[0].verdict.split(':')[0].split(' (')[0]}")
    place_legend(ax)
    damped = f", damping ratio {float(zeta):g}" if zeta else ""
    body = f"uniform rod of {rod:g} m (l = {l:.4g} m)" if rod else f"equivalent length l = {l:.4g} m"
    ax.set_title(title or f"Where the upright stands: {d.describe()}{damped}", fontsize=10)
    caption(fig, f"Shaded: the upright position is stable ({body}, g = {g:g} m/s$^2$). At a fixed stroke the "
                 r"zone is a band of frequencies; both axes are logarithmic. Solid: edges with a 2T-periodic motion; "
                 "dashed: with a 4T-periodic one.")
    return fig, res, ["n", "stroke", "f_lo", "f_hi"]
