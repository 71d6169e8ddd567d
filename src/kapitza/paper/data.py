"""The numbers behind the paper's Figures 1-8, computed by the library.

Everything here is numpy/scipy: :func:`figure7_data` takes its curves from
:func:`kapitza.curves.zone_curves` (so that the data file holds exactly what
:func:`~kapitza.figures.chart.plot_zones` draws), except its magnified tongues, which come from
:mod:`kapitza.figures.chart`, a module that imports matplotlib.

Each ``figureN_data`` returns a :class:`FigureData`: named curves
(:class:`Series`) and labelled points (:class:`Point`) on one or more panels,
the parameters used and a caption. :mod:`kapitza.paper.figures` draws them;
:meth:`FigureData.as_dict` and :meth:`FigureData.csv_rows` are what is written
beside each figure, so a reader can re-plot it in another tool.

Default parameters (rod ``l = 1`` m, ``g = 9.81`` m/s^2) and why:

- Figures 2-5: ``A = 30`` m/s^2 (``mu = 0.572``, ``D = 1.40``), so the stretch at
  ``t = T`` is clearly visible while the hyperbolic arc of Figure 2 is not yet
  squeezed onto the asymptotes.
- Figure 6: ``A = 100`` m/s^2, the reference case of ``docs/theory.md`` section 5,
  whose ``T_n``, ``T~_n`` are quoted there.
- Figures 7 and 8: the whole ``eps``-``mu`` plane, ``0 < mu < 1``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _validate as _v
from ..parameters import G_EARTH, SQRT8
from ..periodic import alpha as alpha_T
from ..periodic import beta as beta_T
from ..periodic import boundary_table, periodic_solution
from ..phase_plane import notable_points, phi_h
from ..zones import G_m_curve, zone_edges
from . import approximations as ap

__all__ = [
    "Series",
    "Point",
    "FigureData",
    "figure1_data",
    "figure2_data",
    "figure3_data",
    "figure4_data",
    "figure5_data",
    "figure6_data",
    "figure7_data",
    "figure8_data",
    "ALL_FIGURES",
    "DYNAMICS_A",
    "DYNAMICS_A_OUTER",
    "FIGURE6_A",
]

PI = np.pi
QPI = 0.25 * PI

#: Amplitude used for Figures 2 and 5 [m/s^2].
DYNAMICS_A = 30.0
#: Amplitude used for Figures 3 and 4 [m/s^2]. At ``T_2`` and ``T~_2`` one has
#: ``w_e T > pi + 2 atan D > 3 pi / 2`` ((3.11), (3.12) with ``k = 0``), so
#: ``w_h T > 3 pi D / 2 > 4.71`` for every ``A``; the smaller ``D``, the smaller
#: ``w_h T`` and the farther the hyperbolic arc keeps from its asymptotes, but the
#: smaller the stretch ``y -> D y``. At ``A = 50`` both show (``w_h T = 6.0``,
#: ``D = 1.22``), and the figure magnifies the arc's turn near the origin.
DYNAMICS_A_OUTER = 50.0
#: Amplitude used for Figure 6 [m/s^2].
FIGURE6_A = 100.0


# ------------------------------------------------------------------ containers
@dataclass(frozen=True)
class Series:
    """One drawn curve.

    Attributes
    ----------
    name : str
        Machine name, unique within its figure (e.g. ``"alpha+1pi"``).
    label : str
        Legend text (matplotlib mathtext allowed).
    x, y : ndarray
        The curve.
    panel : str
        Which panel it belongs to (see :attr:`FigureData.axes`).
    role : str
        What it is (``"hyperbolic arc"``, ``"edge"``, ``"approximation"``...), used
        by the drawing code for its style.
    meta : dict
        Anything else that identifies the curve (zone ``n``, period index...).
    """

    name: str
    label: str
    x: np.ndarray
    y: np.ndarray
    panel: str = "main"
    role: str = ""
    meta: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Point:
    """One marked and labelled point.

    Attributes
    ----------
    label : str
        The label written beside it (e.g. ``"T~_2"`` or ``"3"``).
    x, y : float
        Its coordinates on its panel.
    panel : str
    meta : dict
        The quantities that define it (``T``, equation, ``k``, ``r``, ``phi``...).
    """

    label: str
    x: float
    y: float
    panel: str = "main"
    meta: dict = field(default_factory=dict)


@dataclass(frozen=True)
class FigureData:
    """Everything one figure shows.

    Attributes
    ----------
    number : int
        The paper's figure number.
    title : str
    caption : str
    parameters : dict
        The parameters used (``A``, ``l``, ``g``, ``T``... as applicable).
    axes : dict
        ``panel -> (x quantity, y quantity)``, in the project's vocabulary.
    series : tuple of Series
    points : tuple of Point
    """

    number: int
    title: str
    caption: str
    parameters: dict
    axes: dict
    series: tuple
    points: tuple = ()

    def series_named(self, name: str) -> Series:
        """The series called ``name`` (KeyError if absent)."""
        for s in self.series:
            if s.name == name:
                return s
        raise KeyError(name)

    def series_with(self, role=None, panel=None):
        """Series filtered by role and/or panel."""
        return [s for s in self.series if (role is None or s.role == role) and (panel is None or s.panel == panel)]

    def points_on(self, panel="main"):
        return [p for p in self.points if p.panel == panel]

    def point_labelled(self, label: str, panel="main") -> Point:
        for p in self.points:
            if p.label == label and p.panel == panel:
                return p
        raise KeyError(label)

    def as_dict(self) -> dict:
        """JSON-ready description (arrays as lists)."""
        return dict(
            figure=self.number,
            title=self.title,
            caption=self.caption,
            parameters=self.parameters,
            axes={k: dict(x=v[0], y=v[1]) for k, v in self.axes.items()},
            series=[dict(name=s.name, label=s.label, panel=s.panel, role=s.role, meta=s.meta,
                         x=np.asarray(s.x), y=np.asarray(s.y)) for s in self.series],
            points=[dict(label=p.label, panel=p.panel, x=p.x, y=p.y, meta=p.meta) for p in self.points],
        )

    def csv_header(self):
        return ["kind", "panel", "name", "index", "x", "y"]

    def csv_comments(self):
        lines = [f"Figure {self.number}: {self.title}"]
        lines += [f"panel {k!r}: x = {v[0]}, y = {v[1]}" for k, v in self.axes.items()]
        lines.append("kind 'curve': one row per sample of the named curve; kind 'point': a marked point, "
                     "name = its label")
        return lines

    def csv_rows(self):
        """Long-format rows ``(kind, panel, name, index, x, y)``."""
        for s in self.series:
            for i, (x, y) in enumerate(zip(np.asarray(s.x, float), np.asarray(s.y, float))):
                yield "curve", s.panel, s.name, i, float(x), float(y)
        for i, p in enumerate(self.points):
            yield "point", p.panel, p.label, i, float(p.x), float(p.y)


def _physical(A, l, g):
    A = _v.one("A", _v.positive("A", A))
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    if A <= g:
        raise _v.KapitzaValueError(f"A must exceed g (A > g) for the elliptic phase to exist; got A={A!r}, g={g!r}")
    return A, l, g


# ------------------------------------------------------------------ Figure 1
def figure1_data(levels=(0.3, 0.6, 0.9, 1.2), extent=1.6, samples=241) -> FigureData:
    """Hyperbolic and elliptic rotation (Figure 1).

    Parameters
    ----------
    levels : sequence of float
        Distances of the hyperbolae's vertices from the origin (and radii of the
        circles), each > 0.
    extent : float
        Half-width of the square window, > 0.
    samples : int
        Points per curve.

    Returns
    -------
    FigureData
        Panel ``"hyperbolic"``: branches of ``x_h^2 - y_h^2 = +-c^2`` traced with the
        angle ``phi_h(t)`` of (2.11) and the radius of (3.5), roles ``"hyperbola"`` and
        ``"asymptote"``; points labelled ``"arrow"`` carry the flow direction
        ``(dx, dy) = (y_h, x_h)`` of (2.6) in ``meta``. Panel ``"elliptic"``: circles
        ``x_e^2 + y_e^2 = c^2`` traced with ``phi_e = phi_0 - t`` (2.13), arrows with
        ``(dx, dy) = (y_e, -x_e)`` (2.12). Time is in units of ``1/w_h`` and ``1/w_e``.

    Notes
    -----
    Equations (2.6)-(2.7), (2.11) and (2.12)-(2.13) of the paper.
    """
    levels = _v.positive("levels", levels).ravel()
    extent = _v.one("extent", _v.positive("extent", extent))
    samples = _v.bounded_count("samples", samples, _v.MAX_POINTS, minimum=3)
    series, points = [], []
    R = extent * np.sqrt(2.0)
    for c in levels:
        # A branch starts at its vertex; x^2 - y^2 = +-c^2 reaches radius R at |t| = acosh(R^2/c^2)/2.
        t_max = 0.5 * np.arccosh(max(R * R / (c * c), 1.0))
        t = np.linspace(-t_max, t_max, samples)
        for vertex in (0.0, 0.5 * PI, PI, -0.5 * PI):
            phi = phi_h(t, vertex, 1.0)
            r = c / np.sqrt(np.abs(np.cos(2.0 * phi)))
            x, y = r * np.cos(phi), r * np.sin(phi)
            sign = "+" if vertex in (0.0, PI) else "-"
            series.append(Series(f"hyperbola c={c:g} vertex={vertex:.4f}", "", x, y, panel="hyperbolic",
                                 role="hyperbola", meta=dict(c=float(c), vertex_angle=float(vertex),
                                                             H=float(c * c) if sign == "+" else float(-c * c))))
            xv, yv = c * np.cos(vertex), c * np.sin(vertex)
            points.append(Point("arrow", float(xv), float(yv), panel="hyperbolic",
                                meta=dict(dx=float(yv), dy=float(xv))))
        theta = np.linspace(0.0, -2.0 * PI, samples)  # clockwise from phi_0 = 0 (2.13)
        series.append(Series(f"circle c={c:g}", "", c * np.cos(theta), c * np.sin(theta), panel="elliptic",
                             role="circle", meta=dict(c=float(c), H=float(c * c))))
        for ang in (0.5 * PI, -0.5 * PI):
            xv, yv = c * np.cos(ang), c * np.sin(ang)
            points.append(Point("arrow", float(xv), float(yv), panel="elliptic",
                                meta=dict(dx=float(yv), dy=float(-xv))))
    s = np.array([-extent, extent])
    series.append(Series("asymptote y=x", r"$y_h = x_h$ (unstable)", s, s, panel="hyperbolic", role="asymptote"))
    series.append(Series("asymptote y=-x", r"$y_h = -x_h$ (stable)", s, -s, panel="hyperbolic", role="asymptote"))
    return FigureData(
        number=1,
        title="Hyperbolic and elliptic rotation",
        caption=(r"Left: the hyperbolic phase (2.6) in $x_h = \theta$, $y_h = \dot\theta/\omega_h$: the phase point "
                 r"moves along the hyperbolae $x_h^2 - y_h^2 = $ const ($H_h$ is a first integral), away from the "
                 r"origin along $y_h = x_h$ and towards it along $y_h = -x_h$. Right: the elliptic phase (2.12) in "
                 r"$x_e = \theta$, $y_e = \dot\theta/\omega_e$: uniform clockwise rotation on circles (2.13). "
                 r"Arrows show the direction of motion."),
        parameters=dict(levels=[float(c) for c in levels], extent=extent),
        axes=dict(hyperbolic=("x_h = theta", "y_h = theta'/w_h"), elliptic=("x_e = theta", "y_e = theta'/w_e")),
        series=tuple(series),
        points=tuple(points),
    )


# ------------------------------------------------------------------ Figures 2-5
def _polar(r, phi):
    return r * np.cos(phi), r * np.sin(phi)


def _one_period(phi0, r0, T, A, l, g, samples, period):
    """Series and points of one period's four steps starting at ``(r0, phi0)`` (3.1)."""
    w_h = np.sqrt((A + g) / l)
    w_e = np.sqrt((A - g) / l)
    D = w_h / w_e
    npnt = notable_points(phi0, T, A, r0=r0, l=l, g=g)
    r, phi = npnt.r, npnt.phi
    tag = f" (period {period})"
    t = np.linspace(0.0, T, samples)
    ph = phi_h(t, phi0, w_h)
    rh = r0 * np.sqrt(np.abs(np.cos(2.0 * phi0)) / np.abs(np.cos(2.0 * ph)))  # (3.5)
    xh, yh = _polar(rh, ph)
    x1, y1 = _polar(r[1], phi[1])
    x2, y2 = _polar(r[2], phi[2])
    pe = np.linspace(phi[2], phi[3], samples)  # clockwise by w_e T (2.13)
    xe, ye = _polar(r[2], pe)
    x3, y3 = _polar(r[3], phi[3])
    x4, y4 = _polar(r[4], phi[4])
    meta = dict(period=period)
    series = [
        Series(f"hyperbolic arc{tag}", "hyperbolic arc, $0 \\leq t < T$", xh, yh, role="hyperbolic arc", meta=meta),
        Series(f"stretch{tag}", f"stretch $y \\mapsto Dy$ at $t = T$ ($D = {D:.3g}$)", np.array([x1, x2]),
               np.array([y1, y2]), role="stretch", meta=meta),
        Series(f"elliptic arc{tag}", "elliptic arc, $T \\leq t < 2T$", xe, ye, role="elliptic arc", meta=meta),
        Series(f"contraction{tag}", "contraction $y \\mapsto y/D$ at $t = 2T$", np.array([x3, x4]),
               np.array([y3, y4]), role="contraction", meta=meta),
    ]
    variables = ("hyperbolic", "hyperbolic", "elliptic", "elliptic", "hyperbolic")
    points = [
        Point(str(i), float(xx), float(yy),
              meta=dict(i=i, r=float(r[i]), phi=float(phi[i]), variables=variables[i], period=period))
        for i, (xx, yy) in enumerate(zip(*_polar(r, phi)))
    ]
    return series, points, npnt


_DYNAMICS = {
    2: dict(index=1, tilde=False, lemma="3.1", case="a"),
    3: dict(index=2, tilde=False, lemma="3.1", case="b"),
    4: dict(index=2, tilde=True, lemma="3.2", case="a"),
    5: dict(index=1, tilde=True, lemma="3.2", case="b"),
}


def _dynamics_data(number, A, l, g, samples):
    A, l, g = _physical(A, l, g)
    samples = _v.bounded_count("samples", samples, _v.MAX_POINTS, minimum=3)
    spec = _DYNAMICS[number]
    sol = periodic_solution(A, spec["index"], spec["tilde"], l, g)
    b = sol.boundary
    T = b.T
    w_h = np.sqrt((A + g) / l)
    w_e = np.sqrt((A - g) / l)
    D = w_h / w_e
    series, points, npnt = _one_period(sol.phi0, 1.0, T, A, l, g, samples, 1)
    if b.tilde:
        # Over 4T: the second period starts at point 4 (= point 0 turned by pi, Lemma 3.2).
        s2, p2, _ = _one_period(float(npnt.phi[4]), float(npnt.r[4]), T, A, l, g, samples, 2)
        series += s2
        for p in p2[1:]:
            i = int(p.label) + 4
            points.append(Point(str(i), p.x, p.y, meta={**p.meta, "i": i}))
    k = b.k
    phi = npnt.phi
    if spec["case"] == "a":
        rel = r"$\varphi_1 = -\varphi_0$, " + (r"$\varphi_3 = -\varphi_2 - 2k\pi$" if not b.tilde
                                                else r"$\varphi_3 = -\varphi_2 - \pi - 2k\pi$")
    else:
        rel = r"$\varphi_1 = -\varphi_0 - \pi$, " + (r"$\varphi_3 = -\varphi_2 - \pi - 2(k+1)\pi$" if not b.tilde
                                                       else r"$\varphi_3 = -\varphi_2 - 2\pi - 2k\pi$")
    cond = {("3.1", "a"): "3.2", ("3.1", "b"): "3.3", ("3.2", "a"): "3.8", ("3.2", "b"): "3.9"}[
        (spec["lemma"], spec["case"])]
    ret = ("point 4 returns to point 0" if not b.tilde
           else r"point 4 is point 0 turned by $\pi$ (right panel: the second period, $2T \leq t < 4T$) "
                "and point 8 returns to point 0")
    kind = "2T" if not b.tilde else "4T"
    interval = r"$-\pi/4 < \varphi_0 < 0$" if spec["case"] == "a" else r"$-\pi/2 < \varphi_0 < -\pi/4$"
    title = (f"Steps of the dynamics over one period, Lemma 3.1({spec['case']})" if not b.tilde
             else f"4T-periodic solution, Lemma 3.2({spec['case']})")
    # The hyperbolic arc turns at its vertex, nearest the origin: on the x-axis in case (a)
    # (x^2 - y^2 > 0), on the y-axis in case (b). Where it comes close to the origin, the
    # figure magnifies the turn.
    xh, yh = series[0].x, series[0].y
    vertex = float(np.min(np.hypot(xh, yh)))
    r_max = float(np.max(npnt.r))
    zoom = 3.0 * vertex if vertex < 0.2 * r_max else None
    axis = "x-axis" if spec["case"] == "a" else "y-axis"
    names = {"T_1": r"$T_1$", "T_2": r"$T_2$", "T~_1": r"$\tilde T_1$", "T~_2": r"$\tilde T_2$"}
    bname = names.get(b.name, b.name)
    caption = (f"{kind}-periodic solution at $T$ = {bname} = {T:.6g} s (eq. {b.equation}, $k = {k}$), "
               rf"$A = {A:g}$ m/s$^2$, $l = {l:g}$ m, $g = {g:g}$ m/s$^2$ ($D = {D:.4g}$, $\omega_h T = "
               rf"{w_h * T:.4g}$, "
               rf"$\omega_e T = {w_e * T:.4g}$). Start $\varphi_0 = {sol.phi0:.5f}$ from "
               f"({'3.19' if b.equation in ('3.10', '3.12') else '3.22'}), {interval}. "
               rf"Points 0-4 of (3.1): hyperbolic arc 0-1, stretch 1-2, clockwise elliptic arc 2-3 by $\omega_e T$, "
               f"contraction 3-4; conditions ({cond}): {rel}; {ret}. Points 0, 1, 4 in $(x_h, y_h)$, 2, 3 in "
               f"$(x_e, y_e)$. Case ({spec['case']}): the hyperbolic arc turns on the {axis}")
    if zoom is not None:
        caption += (rf", at {vertex:.3g} from the origin, since $\omega_h T$ is large "
                    + (r"($\omega_h T > 3\pi D/2$ at every $A$ here)" if b.index == 2 else "")
                    + "; the small panel magnifies the turn.")
    else:
        caption += "."
    return FigureData(
        number=number,
        title=title,
        caption=caption,
        parameters=dict(A=A, l=l, g=g, T=T, boundary=b.name, equation=b.equation, k=k, zone=b.zone,
                        lemma=spec["lemma"], case=spec["case"], condition=cond, phi0=sol.phi0, D=float(D),
                        w_h=float(w_h), w_e=float(w_e), periods=2 if b.tilde else 1,
                        notable_phi=[float(v) for v in phi],
                        notable_r=[float(v) for v in npnt.r], vertex=vertex, zoom=zoom),
        axes=dict(main=("x = theta", "y = theta'/w (w = w_h for points 0, 1, 4; w_e for 2, 3)")),
        series=tuple(series),
        points=tuple(points),
    )


def figure2_data(A=DYNAMICS_A, l=1.0, g=G_EARTH, samples=400) -> FigureData:
    """Steps of the dynamics, Lemma 3.1(a): the 2T-periodic solution at ``T_1`` (Figure 2).

    Parameters
    ----------
    A, l, g : float
        Amplitude (``A > g``), rod length and gravity.
    samples : int
        Points per arc.

    Returns
    -------
    FigureData
        Series with roles ``"hyperbolic arc"``, ``"stretch"``, ``"elliptic arc"``,
        ``"contraction"``; points ``"0"``-``"4"`` with ``r``, ``phi`` of (3.1) in ``meta``.

    Notes
    -----
    ``T_1`` solves (3.10) with ``k = 0``; the start is (3.19), ``-pi/4 < phi_0 < 0``,
    and (3.2) holds: ``phi_1 = -phi_0``, ``phi_3 = -phi_2``.
    """
    return _dynamics_data(2, A, l, g, samples)


def figure3_data(A=DYNAMICS_A_OUTER, l=1.0, g=G_EARTH, samples=400) -> FigureData:
    """Steps of the dynamics, Lemma 3.1(b): the 2T-periodic solution at ``T_2`` (Figure 3).

    Parameters and returns as :func:`figure2_data`.

    Notes
    -----
    ``T_2`` solves (3.11) with ``k = 0``; the start is (3.22), ``-pi/2 < phi_0 < -pi/4``,
    and (3.3) holds: ``phi_1 = -phi_0 - pi``, ``phi_3 = -phi_2 - 3 pi``.
    """
    return _dynamics_data(3, A, l, g, samples)


def figure4_data(A=DYNAMICS_A_OUTER, l=1.0, g=G_EARTH, samples=400) -> FigureData:
    """4T-periodic solution, Lemma 3.2(a), at ``T~_2`` (Figure 4); two periods, points 0-8.

    Parameters and returns as :func:`figure2_data`.

    Notes
    -----
    ``T~_2`` solves (3.12) with ``k = 0``; the start is (3.19) and (3.8) holds:
    ``phi_1 = -phi_0``, ``phi_3 = -phi_2 - pi``, so ``phi_4 = phi_0 - pi``.
    """
    return _dynamics_data(4, A, l, g, samples)


def figure5_data(A=DYNAMICS_A, l=1.0, g=G_EARTH, samples=400) -> FigureData:
    """4T-periodic solution, Lemma 3.2(b), at ``T~_1`` (Figure 5); two periods, points 0-8.

    Parameters and returns as :func:`figure2_data`.

    Notes
    -----
    ``T~_1`` solves (3.13) with ``k = 0``; the start is (3.22) and (3.9) holds:
    ``phi_1 = -phi_0 - pi``, ``phi_3 = -phi_2 - 2 pi``, so ``phi_4 = phi_0 - pi``.
    """
    return _dynamics_data(5, A, l, g, samples)


# ------------------------------------------------------------------ Figure 6
def figure6_data(A=FIGURE6_A, l=1.0, g=G_EARTH, zones=4, samples=1500, zoom_samples=200) -> FigureData:
    """The graphical solution of (3.10)-(3.13) (Figure 6).

    Parameters
    ----------
    A, l, g : float
        Amplitude (``A > g``), rod length and gravity.
    zones : int
        Number of zones ``n = 0 .. zones-1`` shown; each gives one ``T_{n+1}`` and
        one ``T~_{n+1}``.
    samples, zoom_samples : int
        Points per curve on the main panel and on each zoom panel.

    Returns
    -------
    FigureData
        Panel ``"main"``: curves ``alpha(T) + n pi`` (name ``"alpha+{n}pi"``) and
        ``beta(T) + n pi`` (``"beta+{n}pi"``) against ``u = w_e T``, the line
        ``y = u`` (``"w_e T"``); points at the intersections labelled ``T_j`` /
        ``T~_j`` with ``meta``: ``T``, ``u``, ``equation``, ``k``, ``zone``, ``curve``
        (``"alpha"`` or ``"beta"``), ``shift`` (``n``), ``period`` (``"2T"``/``"4T"``).
        Panels ``"zoom n"`` (``n >= 1``): the same near the two intersections of zone
        ``n``, which lie too close together to be told apart on the main panel.

    Notes
    -----
    An intersection of ``y = w_e T`` with ``alpha + n pi`` is (3.10) (``n = 2k``) or
    (3.12) (``n = 2k + 1``); with ``beta + n pi`` it is (3.13) (``n = 2k``) or (3.11)
    (``n = 2k + 1``). Section 4: ``alpha`` is increasing and concave, ``beta``
    decreasing and convex, so each line meets each curve once.
    """
    A, l, g = _physical(A, l, g)
    zones = int(_v.nonnegative_int("zones", zones, minimum=1))
    samples = _v.bounded_count("samples", samples, _v.MAX_POINTS, minimum=3)
    zoom_samples = _v.bounded_count("zoom_samples", zoom_samples, _v.MAX_POINTS, minimum=3)
    w_h = np.sqrt((A + g) / l)
    w_e = np.sqrt((A - g) / l)
    u_max = zones * PI + 0.35 * PI
    u = np.linspace(u_max * 1e-4, u_max, samples)
    T = u / w_e
    al, be = alpha_T(T, A, l, g), beta_T(T, A, l, g)
    series = []
    for n in range(zones):
        series.append(Series(f"alpha+{n}pi", rf"$\alpha(T) + {n}\pi$" if n else r"$\alpha(T)$", u, al + n * PI,
                             role="alpha", meta=dict(shift=n)))
        series.append(Series(f"beta+{n}pi", rf"$\beta(T) + {n}\pi$" if n else r"$\beta(T)$", u, be + n * PI,
                             role="beta", meta=dict(shift=n)))
    series.append(Series("w_e T", r"$y = \omega_e T$", u, u, role="line"))
    table = boundary_table(A, zones, l, g)
    points = []
    for b in table:
        ub = float(w_e * b.T)
        meta = dict(name=b.name, T=b.T, u=ub, equation=b.equation, k=b.k, zone=b.zone, edge=b.edge,
                    curve="beta" if b.edge == "upper" else "alpha", shift=b.zone, period=b.period, eps=b.eps, mu=b.mu)
        points.append(Point(b.name, ub, ub, meta=meta))
    axes = dict(main=("w_e T [rad]", "angle [rad]"))
    for n in range(1, zones):
        lo = next(p for p in points if p.meta["zone"] == n and p.meta["edge"] == "lower")
        hi = next(p for p in points if p.meta["zone"] == n and p.meta["edge"] == "upper")
        c = 0.5 * (lo.x + hi.x)
        half = 1.6 * (hi.x - lo.x)
        uz = np.linspace(c - half, c + half, zoom_samples)
        Tz = uz / w_e
        panel = f"zoom {n}"
        axes[panel] = ("w_e T [rad]", "angle [rad]")
        series.append(Series(f"alpha+{n}pi [{panel}]", rf"$\alpha(T) + {n}\pi$", uz, alpha_T(Tz, A, l, g) + n * PI,
                             panel=panel, role="alpha", meta=dict(shift=n)))
        series.append(Series(f"beta+{n}pi [{panel}]", rf"$\beta(T) + {n}\pi$", uz, beta_T(Tz, A, l, g) + n * PI,
                             panel=panel, role="beta", meta=dict(shift=n)))
        series.append(Series(f"w_e T [{panel}]", r"$y = \omega_e T$", uz, uz, panel=panel, role="line"))
        points += [Point(p.label, p.x, p.y, panel=panel, meta=p.meta) for p in (lo, hi)]
    return FigureData(
        number=6,
        title="Conditions (3.10)-(3.13)",
        caption=(rf"$A = {A:g}$ m/s$^2$, $l = {l:g}$ m, $g = {g:g}$ m/s$^2$ ($D = {w_h / w_e:.4g}$). The line "
                 r"$y = \omega_e T$ meets $\alpha(T) + n\pi$ at the lower edge of zone $n$ and $\beta(T) + n\pi$ at "
                 r"its upper edge: $T_j$ (2T-periodic solution; (3.10) for $n = 2k$, (3.11) for $n = 2k+1$) and "
                 r"$\tilde T_j$ (4T-periodic; (3.12) for $n = 2k+1$, (3.13) for $n = 2k$), $j = n + 1$. Lower "
                 r"panels: magnified windows around the pairs of zones $n \geq 1$, whose widths shrink like "
                 r"$e^{-\omega_h T}$."),
        parameters=dict(A=A, l=l, g=g, zones=zones, w_h=float(w_h), w_e=float(w_e), D=float(w_h / w_e)),
        axes=axes,
        series=tuple(series),
        points=tuple(points),
    )


# ------------------------------------------------------------------ Figure 7
def figure7_data(eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), points=600, magnify=(1, 2, 3),
                 zoom_points=300) -> FigureData:
    """The exact stability zones on the ``eps``-``mu`` plane (Figure 7).

    Parameters
    ----------
    eps_range, mu_range : (float, float)
        The window.
    points : int
        ``mu`` samples per edge.
    magnify : sequence of int
        Zones drawn magnified in panels of their own (:func:`kapitza.figures.chart.tongue_curves`).
    zoom_points : int
        ``mu`` samples per edge on each magnified panel.

    Returns
    -------
    FigureData
        Series ``"zone n lower"`` / ``"zone n upper"`` (role ``"edge"``, ``meta``: ``zone``,
        ``edge``, ``period``) with ``x = eps``, ``y = mu``, and ``"G_m"`` (role ``"G"``).
        Panels ``"zoom n"``: the edges of zone ``n`` as ``x = (eps - eps_mid(mu)) / 10^e``
        (``meta``: ``zone``, ``edge``, ``period``, ``exponent`` e, and ``eps`` the exact edge).

    Notes
    -----
    The edges are the solution sets of (3.10)-(3.13) (:func:`kapitza.zone_edges`),
    the curves drawn by :func:`kapitza.figures.chart.plot_zones`; ``G_m``:
    ``2 sqrt 2 eps sqrt(1 - mu^2) = (2m + 1) pi/2`` (section 4).
    """
    from ..curves import zone_curves  # what plot_zones draws
    from ..figures.chart import tongue_curves  # what plot_tongue draws

    points = _v.bounded_count("points", points, _v.MAX_POINTS, minimum=2)
    curves = zone_curves(eps_range, mu_range, points)
    series = []
    for i, n in enumerate(curves.n):
        n = int(n)
        lower_kind, upper_kind = ("2T", "4T") if n % 2 == 0 else ("4T", "2T")
        series.append(Series(f"zone {n} lower", "", curves.eps_lo[i], curves.mu, role="edge",
                             meta=dict(zone=n, edge="lower", period=lower_kind)))
        series.append(Series(f"zone {n} upper", "", curves.eps_hi[i], curves.mu, role="edge",
                             meta=dict(zone=n, edge="upper", period=upper_kind)))
    mu = curves.mu
    q = np.sqrt((1.0 - mu) * (1.0 + mu))
    m_max = int(np.floor((2.0 * SQRT8 * q.max() * eps_range[1] / PI - 1.0) / 2.0))
    for m in range(0, max(m_max, -1) + 1):
        series.append(Series(f"G_{m}", rf"$G_{m}$", G_m_curve(mu, m), mu, role="G", meta=dict(m=m)))
    axes = dict(main=("eps = T sqrt(A)/sqrt(8 l)", "mu = sqrt(g/A)"))
    magnify = [int(n) for n in magnify]
    for n in magnify:
        t = tongue_curves(n, mu_range, zoom_points)
        panel = f"zoom {n}"
        axes[panel] = (f"(eps - eps_mid(mu)) / 1e{t.exponent}", "mu = sqrt(g/A)")
        lower_kind, upper_kind = ("2T", "4T") if n % 2 == 0 else ("4T", "2T")
        for edge, x, e, kind in (("lower", t.lo, t.eps_lo, lower_kind), ("upper", t.hi, t.eps_hi, upper_kind)):
            series.append(Series(f"zone {n} {edge} [{panel}]", "", x, t.mu, panel=panel, role="magnified edge",
                                 meta=dict(zone=n, edge=edge, period=kind, exponent=t.exponent, eps=e)))
    w = {n: float(np.subtract(*zone_edges(1e-9, n)[::-1])) for n in magnify}  # widest at mu -> 0
    widths = ", ".join(f"{n}: {w[n]:.2g}" for n in magnify)
    ratios = [w[a] / w[b] for a, b in zip(magnify, magnify[1:]) if w[b] > 0]
    shrink = (f", and each is about {np.mean(ratios):.0f} times narrower than the one before" if ratios else "")
    return FigureData(
        number=7,
        title="The exact stability zones",
        caption=r"Shaded: the upright position is stable, $\alpha + n\pi < \omega_e T < \beta + n\pi$ (zone $n$). "
                r"Solid blue: 2T-periodic edges $T_n$ (3.10, 3.11); dashed red: 4T-periodic edges $\tilde T_n$ "
                r"(3.12, 3.13); dotted: the curves $G_m$, $2\sqrt{2}\,\varepsilon\sqrt{1-\mu^2} = (2m+1)\pi/2$, "
                r"along which the tongues lie. Zones $n \geq 1$ are too thin to show as regions on the plane "
                f"(largest widths in $\\varepsilon$, zone {widths}); the lower panels magnify them: "
                r"$\varepsilon$ measured from each tongue's midpoint $\varepsilon_\mathrm{mid}(\mu)$, in the power "
                r"of ten shown. Every tongue narrows to nothing as $\mu \to 1$" f"{shrink}.",
        parameters=dict(eps_range=[float(v) for v in eps_range], mu_range=[float(v) for v in mu_range],
                        points=points, zones=[int(n) for n in curves.n], magnify=magnify, zoom_points=zoom_points),
        axes=axes,
        series=tuple(series),
    )


# ------------------------------------------------------------------ Figure 8
def figure8_data(eps_max=1.6, points=500, error_mu=(0.02, 0.98)) -> FigureData:
    """``G_0``, the exact first zone and its classical approximations (Figure 8).

    Parameters
    ----------
    eps_max : float
        Right end of the ``eps`` window of the plane panel.
    points : int
        ``mu`` samples per curve.
    error_mu : (float, float)
        ``mu`` range of the error panel (log-spaced).

    Returns
    -------
    FigureData
        Panel ``"plane"`` (``x = eps``, ``y = mu``): ``"exact lower"``, ``"exact upper"``
        (role ``"exact"``), ``"G_0"`` (role ``"G"``), ``"Kapitza"``, ``"series4 lower"``,
        ``"series4 upper"``, ``"series mu lower"`` (role ``"approximation"``).
        Panel ``"error"`` (``x = mu``, ``y = |eps_approx / eps_exact - 1|``): one series
        per approximated edge, same names with the prefix ``"error "``.

    Notes
    -----
    See :mod:`kapitza.paper.approximations` for the derivations. Kapitza's criterion
    and the series in ``mu`` tend to the exact lower edge (3.10, ``k = 0``) as
    ``mu -> 0``, with relative errors ``(4/7) mu^4`` and ``(8424/13475) mu^8``.
    """
    eps_max = _v.one("eps_max", _v.positive("eps_max", eps_max))
    points = _v.bounded_count("points", points, _v.MAX_POINTS, minimum=3)
    m0, m1 = (float(v) for v in error_mu)
    if not (0.0 < m0 < m1 < 1.0):
        raise _v.KapitzaValueError(f"error_mu must satisfy 0 < mu_min < mu_max < 1; got ({m0:g}, {m1:g})")
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, PI, points))
    mu = np.clip(s, 1e-6, 1.0 - 1e-6)
    lo, hi = zone_edges(mu, 0, certify=False)   # (curves drawn: the closed forms' roots)
    kap = ap.kapitza_edge(mu)
    s4lo, s4hi = ap.series4_edges(mu)
    ser = ap.lower_edge_series(mu, 2)
    g0 = G_m_curve(mu, 0)
    inside = lambda e: np.where(e <= 1.05 * eps_max, e, np.nan)  # noqa: E731 - clip what leaves the window
    series = [
        Series("exact lower", r"exact lower edge (3.10), $T_1$", lo, mu, panel="plane", role="exact",
               meta=dict(edge="lower", period="2T")),
        Series("exact upper", r"exact upper edge (3.13), $\tilde T_1$", hi, mu, panel="plane", role="exact",
               meta=dict(edge="upper", period="4T")),
        Series("G_0", r"$G_0$", g0, mu, panel="plane", role="G"),
        Series("Kapitza", r"Kapitza: $\varepsilon = \sqrt{3/2}\,\mu$", inside(kap), mu, panel="plane",
               role="approximation", meta=dict(edge="lower")),
        Series("series4 lower", r"$\mathrm{tr}\,M$ to $O(\varepsilon^4)$ (both edges)", inside(s4lo), mu, panel="plane",
               role="approximation", meta=dict(edge="lower")),
        Series("series4 upper", r"$\mathrm{tr}\,M$ to $O(\varepsilon^4)$, upper", inside(s4hi), mu, panel="plane",
               role="approximation", meta=dict(edge="upper")),
        Series("series mu lower", r"$\varepsilon^2 = \frac{3}{2}\mu^2(1 + \frac{8}{7}\mu^4)$", inside(ser), mu,
               panel="plane", role="approximation", meta=dict(edge="lower")),
    ]
    me = np.geomspace(m0, m1, points)
    elo, ehi = zone_edges(me, 0, certify=False)
    a_lo, a_hi = ap.series4_edges(me)
    errs = [
        ("error Kapitza", "Kapitza (lower)", ap.kapitza_edge(me) / elo - 1.0, "lower"),
        ("error series4 lower", r"$O(\varepsilon^4)$ trace, lower", a_lo / elo - 1.0, "lower"),
        ("error series4 upper", r"$O(\varepsilon^4)$ trace, upper", a_hi / ehi - 1.0, "upper"),
        ("error series mu lower", r"series in $\mu$, lower", ap.lower_edge_series(me, 2) / elo - 1.0, "lower"),
    ]
    for name, label, err, edge in errs:
        series.append(Series(name, label, me, np.abs(err), panel="error", role="error",
                             meta=dict(edge=edge, signed=err)))
    series.append(Series("mu^4 reference", r"$\frac{4}{7}\mu^4$ (Kapitza's leading error)", me, 4.0 / 7.0 * me**4,
                         panel="error",
                         role="reference"))
    return FigureData(
        number=8,
        title="Curve G_0, the exact first zone and its approximations",
        caption=(r"Left: the exact first stability zone (thick edges, shaded), the curve $G_0$ (dashed) and "
                 r"approximations (thin). The paper's Figure 8 draws, as its thin curve, the first approximating zone "
                 r"of its reference [6] (Csizmadia and Hatvani, Meccanica 49, 2014); this paper does not give that "
                 r"zone's formula, so it is not drawn here. Drawn instead, each derived in kapitza and checked: "
                 r"Kapitza's averaging criterion $\langle v^2\rangle > g\,l$, i.e. $A^2T^2/12 > g\,l$, i.e. "
                 r"$\varepsilon > \sqrt{3/2}\,\mu$; both edges of the $O(\varepsilon^4)$ truncation of "
                 r"$\mathrm{tr}\,M$ ($\mu < 1/\sqrt{2}$); and the series "
                 r"$\varepsilon^2 = \frac{3}{2}\mu^2(1 + \frac{8}{7}\mu^4)$ of the lower edge. Right: relative "
                 r"error of each approximated edge; Kapitza's is $\frac{4}{7}\mu^4$ to leading order (circles), "
                 r"so it tends to the exact edge as $\mu \to 0$."),
        parameters=dict(eps_max=eps_max, points=points, error_mu=[m0, m1]),
        axes=dict(plane=("eps = T sqrt(A)/sqrt(8 l)", "mu = sqrt(g/A)"),
                  error=("mu = sqrt(g/A)", "|eps_approx/eps_exact - 1|")),
        series=tuple(series),
    )


#: Figure number -> data function (default parameters).
ALL_FIGURES = {
    1: figure1_data,
    2: figure2_data,
    3: figure3_data,
    4: figure4_data,
    5: figure5_data,
    6: figure6_data,
    7: figure7_data,
    8: figure8_data,
}
