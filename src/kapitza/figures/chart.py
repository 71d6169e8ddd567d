"""Stability charts: the exact zones on Arnold's ``eps``-``mu`` plane (Figure 7 of the paper)
and in the physical ``T``-``A`` plane of a given rod."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from ..parameters import SQRT8
from ..zones import _edges_eps
from ._style import EDGE_2T, EDGE_4T, G_STYLE, ZONE_FILL, Drawn, place_legend

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
]


@dataclass(frozen=True)
class ZoneCurves:
    """Edge curves of the zones visible in a window: for zone ``n[i]``,
    ``eps_lo[i]``, ``eps_hi[i]`` sampled at ``mu`` (arrays ``(zones, points)``)."""

    n: np.ndarray
    mu: np.ndarray
    eps_lo: np.ndarray
    eps_hi: np.ndarray

    def rows(self):
        """``(n, mu, eps_lo, eps_hi)`` rows for CSV export."""
        for i, n in enumerate(self.n):
            for j, m in enumerate(self.mu):
                yield int(n), m, self.eps_lo[i, j], self.eps_hi[i, j]


def zone_curves(eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), points=1200, max_zones=400):
    """Sample the edges of every zone that meets the window.

    Parameters
    ----------
    eps_range, mu_range : (float, float)
        The window; ``0 <= eps_min < eps_max``, ``0 <= mu_min < mu_max <= 1``.
    points : int
        Samples of ``mu`` across the window (>= 2). The edges are exact at
        every sample; nothing is interpolated on a pixel grid.
    max_zones : int
        Refuse windows that would need more zones than this.

    Returns
    -------
    ZoneCurves
    """
    e0, e1 = (float(v) for v in eps_range)
    m0, m1 = (float(v) for v in mu_range)
    if not (np.isfinite(e0) and np.isfinite(e1) and 0.0 <= e0 < e1):
        raise _v.KapitzaValueError(f"eps range must satisfy 0 <= eps_min < eps_max < inf; got ({e0:g}, {e1:g})")
    if not (0.0 <= m0 < m1 <= 1.0):
        raise _v.KapitzaValueError(f"mu range must satisfy 0 <= mu_min < mu_max <= 1; got ({m0:g}, {m1:g})")
    points = int(_v.nonnegative_int("points", points, minimum=2))
    tiny = 1e-9
    # Cluster samples towards the ends where the edges bend fastest (mu -> 0, mu -> 1).
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, points))
    mu = np.clip(m0 + (m1 - m0) * s, tiny, 1.0 - tiny)
    q = np.sqrt((1.0 - mu) * (1.0 + mu))
    n_hi = int(np.floor(SQRT8 * q.max() * e1 / np.pi))
    # Zone n needs eps >= n pi / (SQRT8 q) at least; the lowest zone that can reach e0:
    n_lo = max(0, int(np.floor(SQRT8 * q.min() * e0 / np.pi)) - 1)
    if n_hi - n_lo + 1 > max_zones:
        raise _v.KapitzaValueError(
            f"the window holds {n_hi - n_lo + 1} zones (more than {max_zones}); narrow eps range or mu range"
        )
    n = np.arange(n_lo, n_hi + 1)
    lo, hi = _edges_eps(mu[None, :], n[:, None])
    # Edges are continuous in mu: a zone meets the window if its eps range overlaps the window's,
    # even when it crosses the window between two samples (the resampling below then finds it).
    visible = (hi.max(axis=1) >= e0) & (lo.min(axis=1) <= e1)
    n, lo, hi = n[visible], lo[visible], hi[visible]
    # In a narrow eps window an edge may cross the window within a few mu samples; resample
    # each zone's crossing densely (still exact at every sample) so the zoom shows a curve.
    for _ in range(3):  # each pass zooms on the crossings by a factor ~ points / 4
        extra = []
        for i in range(n.size):
            inside = ((lo[i] >= e0) & (lo[i] <= e1)) | ((hi[i] >= e0) & (hi[i] <= e1)) | ((lo[i] < e0) & (hi[i] > e1))
            idx = np.flatnonzero(inside)
            if not idx.size:  # crossed between two samples: the bracketing pair
                k = np.flatnonzero(np.diff(np.sign(lo[i] - e0)) != 0)
                idx = k if k.size else np.flatnonzero(np.diff(np.sign(hi[i] - e1)) != 0)
            if idx.size and idx.size < points // 4:
                extra.append(np.linspace(mu[max(idx[0] - 1, 0)], mu[min(idx[-1] + 1, mu.size - 1)], points))
        if not extra:
            break
        mu = np.unique(np.concatenate([mu, *extra]))
        lo, hi = _edges_eps(mu[None, :], n[:, None])
    return ZoneCurves(n=n, mu=mu, eps_lo=lo, eps_hi=hi)


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
               legend="outside"):
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

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"edges"`` (lists), ``"G"``; ``.data`` the :class:`ZoneCurves`.

    Notes
    -----
    2T-periodic edges (``T_n``; lower edge of even zones, upper edge of odd ones)
    and 4T-periodic edges (``T~_n``) are styled apart. Each edge is drawn as a
    line, so a tongue thinner than a pixel still shows; :func:`plot_tongue`
    magnifies one.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(layout="constrained")
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
    of its width everywhere in it: those a chart should magnify."""
    curves = zone_curves(eps_range, mu_range, 200)
    width = float(eps_range[1] - eps_range[0])
    keep = []
    for i, n in enumerate(curves.n):
        seen = (curves.eps_hi[i] >= eps_range[0]) & (curves.eps_lo[i] <= eps_range[1])
        if int(n) in candidates and seen.any() and np.max((curves.eps_hi[i] - curves.eps_lo[i])[seen]) < fraction * width:
            keep.append(int(n))
    return keep


def _physical_window(T_range, A_range, l, g):
    """The ``(eps, mu)`` window covering the physical window ``T_range`` x ``A_range``."""
    (T0, T1), (A0, A1) = T_range, A_range
    return (T0 * np.sqrt(A0 / (8.0 * l)), T1 * np.sqrt(A1 / (8.0 * l))), (np.sqrt(g / A1), min(np.sqrt(g / A0), 1.0))


def magnified_zones_physical(T_range, A_range, l=1.0, g=9.81, candidates=(1, 2, 3), fraction=0.02):
    """As :func:`magnified_zones`, for the physical ``T``-``A`` window of a rod ``l`` under ``g``:
    the zones narrower in ``T`` than ``fraction`` of the window wherever they meet it."""
    eps_range, mu_range = _physical_window(T_range, A_range, l, g)
    curves = zone_curves(eps_range, mu_range, 200)
    scale = np.sqrt(8.0 * l * curves.mu**2 / g)  # T = eps sqrt(8 l / A), A = g / mu^2
    T_lo, T_hi = curves.eps_lo * scale, curves.eps_hi * scale
    width = float(T_range[1] - T_range[0])
    keep = []
    for i, n in enumerate(curves.n):
        seen = (T_hi[i] >= T_range[0]) & (T_lo[i] <= T_range[1])
        if int(n) in candidates and seen.any() and np.max((T_hi[i] - T_lo[i])[seen]) < fraction * width:
            keep.append(int(n))
    return keep


def zone_chart_axes(fig, count):
    """The main Axes of a zone chart and ``count`` panels below it for magnified tongues."""
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


def tongue_curves(n, mu_range=(0.0, 1.0), points=400):
    """The edges of zone ``n`` relative to its own midpoint, scaled so the tongue fills a panel.

    Parameters
    ----------
    n : int
        Zone index, ``>= 0``.
    mu_range : (float, float)
        ``0 <= mu_min < mu_max <= 1``.
    points : int
        Samples of ``mu`` (>= 2).

    Returns
    -------
    TongueCurves

    Notes
    -----
    The zones ``n >= 1`` are exponentially narrow (``docs/theory.md``; widths in ``eps`` of
    0.013, 5e-4, 2e-5 for ``n = 1, 2, 3`` at small ``mu``): on the whole plane the two edges
    of each merge into one line. Measured from the midpoint in a power of ten that suits the zone,
    as Figure 6 magnifies its zones, both edges are distinct curves. The edges are exact at
    every sample (:func:`kapitza.zone_edges`).
    """
    n = int(_v.nonnegative_int("n", n))
    points = int(_v.nonnegative_int("points", points, minimum=2))
    m0, m1 = (float(v) for v in mu_range)
    if not (0.0 <= m0 < m1 <= 1.0):
        raise _v.KapitzaValueError(f"mu range must satisfy 0 <= mu_min < mu_max <= 1; got ({m0:g}, {m1:g})")
    tiny = 1e-9
    mu = np.clip(np.linspace(m0, m1, points), tiny, 1.0 - tiny)
    lo, hi = _edges_eps(mu, n)
    mid = 0.5 * (lo + hi)
    half = 0.5 * (hi - lo)
    top = float(np.max(half))
    exponent = int(np.floor(np.log10(top))) if top > 0 else 0
    scale = 10.0**exponent
    return TongueCurves(n=n, mu=mu, eps_mid=mid, eps_lo=lo, eps_hi=hi, lo=-half / scale, hi=half / scale,
                        exponent=exponent, scale=scale)


def plot_tongue(n, ax=None, mu_range=(0.0, 1.0), points=400, title=True, physical=None):
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

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"lower"``, ``"upper"``; ``.data`` the :class:`TongueCurves`.
    """
    import matplotlib.pyplot as plt

    t = tongue_curves(n, mu_range, points)
    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    lower_2t = t.n % 2 == 0
    out = Drawn(ax, data=t)
    x_lo, x_hi, y, exponent = t.lo, t.hi, t.mu, t.exponent
    if physical is not None:
        l, g = (float(_v.positive(k, v)) for k, v in zip(("l", "g"), physical))
        y = g / t.mu**2
        s = np.sqrt(8.0 * l / y)
        half = 0.5 * (t.eps_hi - t.eps_lo) * s
        exponent = int(np.floor(np.log10(float(np.max(half))))) if np.max(half) > 0 else 0
        x_lo, x_hi = -half / 10.0**exponent, half / 10.0**exponent
    out["fill"] = ax.fill_betweenx(y, x_lo, x_hi, color=ZONE_FILL, linewidth=0)
    out["lower"] = ax.plot(x_lo, y, **(EDGE_2T if lower_2t else EDGE_4T))[0]
    out["upper"] = ax.plot(x_hi, y, **(EDGE_4T if lower_2t else EDGE_2T))[0]
    w = 1.15 * max(float(np.max(x_hi)), 1e-300)
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
        ax.set_title(rf"zone {t.n} ($\varepsilon_\mathrm{{mid}}$ = {t.eps_mid[0]:.3f} at $\mu$ = {float(mu_range[0]):g})",
                     fontsize=8)
    return out


@dataclass(frozen=True)
class PhysicalZoneCurves:
    """Zone edges in the physical plane: for zone ``n[i]``, the half-periods
    ``T_lo[i]``, ``T_hi[i]`` at the amplitudes ``A`` (arrays ``(zones, points)``)."""

    n: np.ndarray
    A: np.ndarray
    T_lo: np.ndarray
    T_hi: np.ndarray
    l: float
    g: float

    def rows(self):
        """``(n, A, T_lo, T_hi)`` rows for CSV export."""
        for i, n in enumerate(self.n):
            for j, a in enumerate(self.A):
                yield int(n), a, self.T_lo[i, j], self.T_hi[i, j]


def plot_zones_physical(ax=None, T_range=None, A_range=None, l=1.0, g=9.81, points=1200, label_zones=True,
                        legend="outside"):
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

    Returns
    -------
    Drawn
        Artists ``"fill"``, ``"edges"``; ``.data`` the :class:`PhysicalZoneCurves`.

    Notes
    -----
    The same edges as :func:`plot_zones`, mapped by ``A = g / mu^2`` and
    ``T = eps sqrt(8 l / A)``: at each ``A`` zone ``n`` is ``T_lo < T < T_hi``
    (:func:`kapitza.period_edges`).
    """
    import matplotlib.pyplot as plt

    l = float(_v.positive("l", l))
    g = float(_v.positive("g", g))
    T0, T1 = (0.0, 2.5 * np.sqrt(l / g)) if T_range is None else (float(T_range[0]), float(T_range[1]))
    A0, A1 = (g, 50.0 * g) if A_range is None else (float(A_range[0]), float(A_range[1]))
    if not (np.isfinite(T1) and 0.0 <= T0 < T1):
        raise _v.KapitzaValueError(f"T range must satisfy 0 <= T_min < T_max < inf; got ({T0:g}, {T1:g})")
    if not (np.isfinite(A1) and g <= A0 < A1):
        raise _v.KapitzaValueError(f"A range must satisfy g <= A_min < A_max < inf (g = {g:g}); got ({A0:g}, {A1:g})")
    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    # eps = T sqrt(A / (8 l)) is largest at (T1, A1); cover the window in (eps, mu).
    eps_range, mu_range = _physical_window((T0, T1), (A0, A1), l, g)
    curves = zone_curves(eps_range, mu_range, points)
    A = g / curves.mu**2
    scale = np.sqrt(8.0 * l / A)
    res = PhysicalZoneCurves(n=curves.n, A=A, T_lo=curves.eps_lo * scale, T_hi=curves.eps_hi * scale, l=l, g=g)
    out = Drawn(ax, _draw_tongues(ax, res.n, A, res.T_lo, res.T_hi, (T0, T1), label_zones), data=res)
    ax.set_yscale("log")
    ax.set_xlim(T0, T1)
    ax.set_ylim(A0, A1)
    ax.set_xlabel(r"half-period of the drive $T$ [s]")
    ax.set_ylabel(r"pivot acceleration amplitude $A$ [m/s$^2$]")
    if legend:
        out["legend"] = place_legend(ax, inside=(legend == "inside"))
    return out
