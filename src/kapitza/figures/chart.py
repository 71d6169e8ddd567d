"""Stability charts: the exact zones on Arnold's ``eps``-``mu`` plane (Figure 7 of the paper)
and in the physical ``T``-``A`` plane of a given rod."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from ..parameters import SQRT8
from ..zones import _edges_eps
from ._style import EDGE_2T, EDGE_4T, G_STYLE, ZONE_FILL

__all__ = ["ZoneCurves", "zone_curves", "plot_zones", "PhysicalZoneCurves", "plot_zones_physical"]


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
    visible = ((hi >= e0) & (lo <= e1)).any(axis=1)
    return ZoneCurves(n=n[visible], mu=mu, eps_lo=lo[visible], eps_hi=hi[visible])


def _draw_tongues(ax, n, y, x_lo, x_hi, x_range, label_zones=True):
    """Fill each tongue and draw its two edges, 2T- and 4T-periodic styled apart."""
    for i, k in enumerate(n):
        lo, hi = x_lo[i], x_hi[i]
        ax.fill_betweenx(y, lo, hi, color=ZONE_FILL, linewidth=0, label="stable zone" if i == 0 else None)
        lower_2t = k % 2 == 0
        ax.plot(lo, y, **(EDGE_2T if lower_2t else EDGE_4T))
        ax.plot(hi, y, **(EDGE_4T if lower_2t else EDGE_2T))
        if label_zones:
            # Label each tongue just right of its upper edge, near the bottom of the window.
            inside = (hi > x_range[0]) & (hi < x_range[1])
            if inside.any():
                j = int(np.flatnonzero(inside)[min(np.count_nonzero(inside) - 1, len(y) // 8)])
                ax.annotate(f"n={k}", (hi[j], y[j]), xytext=(3, 0), textcoords="offset points",
                            fontsize=8, va="center", ha="left", color="0.15",
                            bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7))
    ax.plot([], [], label=r"2T-periodic edge ($T_n$)", **EDGE_2T)
    ax.plot([], [], label=r"4T-periodic edge ($\tilde T_n$)", **EDGE_4T)


def plot_zones(ax=None, eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), show_G=True, points=1200, label_zones=True):
    """Draw the exact stability zones in the ``eps``-``mu`` plane.

    Parameters
    ----------
    ax : matplotlib Axes, optional
        Where to draw; a new figure is made if None.
    eps_range, mu_range : (float, float)
        The window.
    show_G : bool
        Also draw the curves ``G_m`` along which the tongues lie.
    points : int
        ``mu`` samples per edge.
    label_zones : bool
        Write the zone index beside each tongue.

    Returns
    -------
    ZoneCurves
        What was drawn.

    Notes
    -----
    2T-periodic edges (``T_n``; lower edge of even zones, upper edge of odd ones)
    and 4T-periodic edges (``T~_n``) are styled apart. Each edge is drawn as a
    line, so a tongue thinner than a pixel still shows.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(layout="constrained")
    curves = zone_curves(eps_range, mu_range, points)
    _draw_tongues(ax, curves.n, curves.mu, curves.eps_lo, curves.eps_hi, eps_range, label_zones)
    if show_G:
        mu = curves.mu
        q = np.sqrt((1.0 - mu) * (1.0 + mu))
        m_max = int(np.floor((2.0 * SQRT8 * q.max() * eps_range[1] / np.pi - 1.0) / 2.0))
        for m in range(0, max(m_max, -1) + 1):
            ax.plot((2 * m + 1) * np.pi / (2.0 * SQRT8 * q), mu, **G_STYLE, label=r"$G_m$" if m == 0 else None)
    ax.set_xlim(*eps_range)
    ax.set_ylim(*mu_range)
    ax.set_xlabel(r"$\varepsilon = T\sqrt{A}/\sqrt{8l}$")
    ax.set_ylabel(r"$\mu = \sqrt{g/A}$")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    return curves


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


def plot_zones_physical(ax=None, T_range=None, A_range=None, l=1.0, g=9.81, points=1200, label_zones=True):
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

    Returns
    -------
    PhysicalZoneCurves

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
    mu_range = (np.sqrt(g / A1), min(np.sqrt(g / A0), 1.0))
    curves = zone_curves((T0 * np.sqrt(A0 / (8.0 * l)), T1 * np.sqrt(A1 / (8.0 * l))), mu_range, points)
    A = g / curves.mu**2
    scale = np.sqrt(8.0 * l / A)
    res = PhysicalZoneCurves(n=curves.n, A=A, T_lo=curves.eps_lo * scale, T_hi=curves.eps_hi * scale, l=l, g=g)
    _draw_tongues(ax, res.n, A, res.T_lo, res.T_hi, (T0, T1), label_zones)
    ax.set_yscale("log")
    ax.set_xlim(T0, T1)
    ax.set_ylim(A0, A1)
    ax.set_xlabel(r"half-period of the drive $T$ [s]")
    ax.set_ylabel(r"pivot acceleration amplitude $A$ [m/s$^2$]")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    return res
