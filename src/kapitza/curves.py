"""Zone edges as data: exact curves of every zone that meets a window of a chart.

What a chart draws, without drawing it: the edges ``eps_lo(mu)``, ``eps_hi(mu)`` of each
zone visible in a window of Arnold's plane (:func:`zone_curves`), the same in the physical
``T``-``A`` plane of a rod (:func:`physical_zone_curves`) and for any drive with damping
(:func:`drive_curves`). Every sample is an exact edge (``docs/theory.md`` section 5); where an
edge crosses a narrow window the samples are refined there, so a tongue far thinner than a
pixel grid is still drawn as a curve. Used by the figures, the paper's data and the explorer.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as _v
from .drives import _api, as_drive
from .limits import averaging_threshold
from .parameters import G_EARTH, SQRT8
from ._square import _edges_eps

__all__ = ["edge_kinds", "mu_top", "window_range", "physical_window", "ZoneCurves", "zone_curves", "window_curves",
           "PhysicalZoneCurves", "physical_zone_curves", "DriveCurves", "drive_curves"]


def edge_kinds(n) -> tuple[str, str]:
    """``(lower, upper)``: which periodic motion lives on each edge of zone ``n``, ``"2T"`` or ``"4T"``.

    The lower edge of zone ``n`` is 2T-periodic (``T_n``) for even ``n`` and 4T-periodic
    (``T~_n``) for odd ``n``; the upper edge the other way round (Corollary 4.1).

    Parameters
    ----------
    n : int
        Zone index ``>= 0``.

    Returns
    -------
    lower, upper : str
        ``"2T"`` or ``"4T"``.

    Raises
    ------
    KapitzaValueError
        If ``n`` is not a whole number ``>= 0``.

    Examples
    --------
    >>> from kapitza.curves import edge_kinds
    >>> edge_kinds(0), edge_kinds(1)
    (('2T', '4T'), ('4T', '2T'))
    """
    n = _v.bounded_count("n", n, 2**61)
    return ("2T", "4T") if n % 2 == 0 else ("4T", "2T")


@dataclass(frozen=True)
class ZoneCurves:
    """Edge curves of the zones visible in a window: for zone ``n[i]``,
    ``eps_lo[i]``, ``eps_hi[i]`` sampled at ``mu`` (arrays ``(zones, points)``).

    Attributes
    ----------
    n : ndarray of int, shape (zones,)
        The zones' indices.
    mu : ndarray, shape (points,)
        The samples of Arnold's ``mu``.
    eps_lo, eps_hi : ndarray, shape (zones, points)
        Each zone's lower and upper edge in ``eps`` at each ``mu``.

    Examples
    --------
    >>> from kapitza.curves import zone_curves
    >>> zc = zone_curves((0.0, 2.0), (0.0, 1.0), points=50)
    >>> zc.n, zc.mu.shape, zc.eps_lo.shape
    (array([0, 1]), (50,), (2, 50))
    >>> next(zc.rows())
    (0, np.float64(1e-09), np.float64(1.2247...e-09), np.float64(0.6629...))
    """

    n: np.ndarray
    mu: np.ndarray
    eps_lo: np.ndarray
    eps_hi: np.ndarray

    def rows(self):
        """``(n, mu, eps_lo, eps_hi)`` rows for CSV export."""
        for i, n in enumerate(self.n):
            for j, m in enumerate(self.mu):
                yield int(n), m, self.eps_lo[i, j], self.eps_hi[i, j]


def zone_curves(eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), points=1200, max_zones=400, max_samples=None):
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
    max_samples : int, optional
        The most ``mu`` samples the result may hold, the refinement where edges cross a narrow
        window included (default ``4 * points``; at least ``points``).

    Returns
    -------
    ZoneCurves

    Raises
    ------
    ValueError
        If a range is outside the bounds above or empty, ``points`` is below 2, or the window needs
        more than ``max_zones`` zones.

    Examples
    --------
    >>> import numpy as np
    >>> from kapitza.curves import zone_curves
    >>> zc = zone_curves((0.0, 2.0), (0.0, 1.0), points=50)
    >>> zc.n
    array([0, 1])
    >>> i = int(np.argmin(abs(zc.mu - 0.3)))
    >>> float(zc.mu[i]), zc.eps_lo[0, i], zc.eps_hi[0, i]
    (0.2976..., np.float64(0.3661...), np.float64(0.7051...))
    """
    e0, e1 = window_range(eps_range, mu_range)
    m0, m1 = (float(v) for v in mu_range)
    points = _v.bounded_count("points", points, _v.MAX_POINTS, minimum=2)
    budget = 4 * points if max_samples is None else max(points, int(max_samples))
    tiny = 1e-9
    # Cluster samples towards the ends where the edges bend fastest (mu -> 0, mu -> 1).
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, points))
    mu = np.unique(np.clip(m0 + (m1 - m0) * s, tiny, 1.0 - tiny))
    q = np.sqrt((1.0 - mu) * (1.0 + mu))
    # zone n needs eps >= n pi / (SQRT8 q) at least (SQRT8 q / pi < 1: no overflow at the largest eps);
    # the highest zone that can reach e1 and the lowest that can reach e0:
    z_hi = float(np.floor(SQRT8 * q.max() / np.pi * e1))
    z_lo = max(0.0, float(np.floor(SQRT8 * q.min() / np.pi * e0)) - 1.0)
    if z_hi - z_lo + 1.0 > max_zones:
        count = z_hi - z_lo + 1.0
        shown = f"{int(count):,}" if count < 1e15 else f"about {count:.3g}"
        raise _v.KapitzaValueError(
            f"the window holds {shown} zones (more than {max_zones}); narrow eps range or mu range")
    n_hi, n_lo = int(z_hi), int(z_lo)
    n = np.arange(n_lo, n_hi + 1)
    lo, hi = _edges_blocked(mu, n)
    # Edges are continuous in mu: a zone meets the window if its eps range overlaps the window's,
    # even when it crosses the window between two samples (the resampling below then finds it).
    visible = (hi.max(axis=1) >= e0) & (lo.min(axis=1) <= e1)
    n, lo, hi = n[visible], lo[visible], hi[visible]
    # In a narrow eps window an edge may cross the window within a few mu samples; resample
    # each zone's crossing densely (still exact at every sample) so the zoom shows a curve.
    # The new samples of a pass are shared by every zone (one mu axis), so they come out of one
    # budget: at most `points` a pass in all, and `budget` in the end. (Giving each of k zones
    # `points` of its own made k^2 * points edges: 54 zones at eps ~ 60 ran out of memory.)
    for _ in range(3):  # each pass zooms on the crossings
        spans = []
        for i in range(n.size):
            inside = ((lo[i] >= e0) & (lo[i] <= e1)) | ((hi[i] >= e0) & (hi[i] <= e1)) | ((lo[i] < e0) & (hi[i] > e1))
            idx = np.flatnonzero(inside)
            if not idx.size:  # crossed between two samples: the bracketing pair
                k = np.flatnonzero(np.diff(np.sign(lo[i] - e0)) != 0)
                idx = k if k.size else np.flatnonzero(np.diff(np.sign(hi[i] - e1)) != 0)
            if idx.size and idx.size < points // 4:
                spans.append((mu[max(idx[0] - 1, 0)], mu[min(idx[-1] + 1, mu.size - 1)]))
        each = min(points, (budget - mu.size) // max(len(spans), 1))
        if not spans or each < 4:
            break
        new = np.setdiff1d(np.concatenate([np.linspace(a, b, each) for a, b in set(spans)]), mu)
        if not new.size:
            break
        new_lo, new_hi = _edges_blocked(new, n)
        order = np.argsort(np.concatenate([mu, new]), kind="stable")
        mu = np.concatenate([mu, new])[order]
        lo = np.concatenate([lo, new_lo], axis=1)[:, order]
        hi = np.concatenate([hi, new_hi], axis=1)[:, order]
    return ZoneCurves(n=n, mu=mu, eps_lo=lo, eps_hi=hi)


def _edges_blocked(mu, n, block=1 << 16):
    """:func:`kapitza.zones._edges_eps` of every zone ``n`` at every ``mu``, a block of columns at a
    time (the kernel's temporaries are some hundred bytes an edge: bounded by the block)."""
    lo = np.empty((n.size, mu.size))
    hi = np.empty((n.size, mu.size))
    step = max(1, block // max(n.size, 1))
    for j in range(0, mu.size, step):
        lo[:, j:j + step], hi[:, j:j + step] = _edges_eps(mu[None, j:j + step], n[:, None])
    return lo, hi


def window_curves(eps_range=(0.0, 4.0), mu_range=(0.0, 1.0), drive=None, zeta=0.0, points=1200, max_zones=400,
                  max_samples=None, check=None):
    """The edges of every zone of any drive, with damping, that meets a window of Arnold's plane.

    Parameters
    ----------
    eps_range, mu_range : (float, float)
        The window; ``0 <= eps_min < eps_max``, ``0 <= mu_min < mu_max <=`` :func:`mu_top` (1, or the
        drive's ``mu_max`` where larger: a rectangular wave of duty above one half).
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    zeta : float
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0.
    points : int
        ``mu`` samples (>= 2).
    max_zones : int
        Refuse windows that would need more zones than this (square wave).
    max_samples : int, optional
        The most ``mu`` samples after the refinement of :func:`zone_curves` (default ``4 * points``).
    check : callable, optional
        Called with no argument before each block of samples of another drive or damping (each
        edge an eigenproblem): a caller bounding the work (a deadline, a client gone) raises from it.

    Returns
    -------
    ZoneCurves
        NaN where a zone does not exist at a sample (other drives, damping); an upper edge of
        a damped zone beyond the window may be ``inf``.

    Raises
    ------
    ValueError
        If a range is outside the bounds above or empty, ``points`` is below 2, ``zeta`` is negative,
        or the window needs more than ``max_zones`` zones.

    Notes
    -----
    The undamped square wave takes :func:`zone_curves` (closed forms, refined where an edge
    crosses a narrow window); any other drive or damping takes :func:`drive_curves` at
    ``points`` values of ``mu`` spread over the window, each edge exact (``docs/drives.md``).

    Examples
    --------
    >>> from kapitza.curves import window_curves
    >>> wc = window_curves((0.0, 2.0), (0.05, 0.9), drive="sine", points=20)
    >>> wc.n, wc.eps_lo.shape
    (array([0]), (1, 20))
    >>> wc.mu[0], wc.eps_lo[0, 0], wc.eps_hi[0, 0]
    (np.float64(0.05), np.float64(0.0785...), np.float64(0.7499...))
    """
    zeta = _v.one("zeta", _v.damping_ratio(zeta))
    general = as_drive(drive)
    if general.closed_form(zeta):
        return zone_curves(eps_range, mu_range, points, max_zones, max_samples)
    top = mu_top(general)
    e0, e1 = window_range(eps_range, mu_range, top)
    points = _v.bounded_count("points", points, _v.MAX_POINTS, minimum=2)
    m0, m1 = (float(v) for v in mu_range)
    # from mu = 1e-3 as kapitza chart draws other drives (the window method and the edge-by-edge
    # solution of a damped zone 0 disagree at mu ~ 1e-9)
    mu = np.linspace(max(m0, 1e-3), min(m1, top * (1.0 - 1e-9)), points)
    if check is None:
        c = drive_curves(general, mu, e1, zeta, eps_min=e0)
        return ZoneCurves(n=c.zones, mu=mu, eps_lo=c.lo, eps_hi=c.hi)
    # block by block (each mu sample is independent of the others): the same curves
    parts = []
    for j in range(0, mu.size, _BLOCK):
        check()
        parts.append(drive_curves(general, mu[j:j + _BLOCK], e1, zeta, eps_min=e0))
    zones = np.unique(np.concatenate([c.zones for c in parts]))
    lo = np.full((zones.size, mu.size), np.nan)
    hi = np.full((zones.size, mu.size), np.nan)
    for j, c in zip(range(0, mu.size, _BLOCK), parts):
        k = np.searchsorted(zones, c.zones)
        lo[k, j:j + c.mu.size], hi[k, j:j + c.mu.size] = c.lo, c.hi
    return ZoneCurves(n=zones, mu=mu, eps_lo=lo, eps_hi=hi)


#: mu samples of another drive computed between two calls of window_curves' ``check``.
_BLOCK = 8


def mu_top(drive=None) -> float:
    """The largest ``mu`` a chart of ``drive`` may show: 1 (``A = g``), or the drive's
    :attr:`~kapitza.drives.Drive.mu_max` where that is larger (a rectangular wave of duty above one
    half holds the rod up with ``A < g``).

    Parameters
    ----------
    drive : Drive or str, optional
        The paper's square wave by default.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``drive`` names no drive.

    Examples
    --------
    >>> from kapitza.curves import mu_top
    >>> mu_top(), mu_top("rectangular:0.7")
    (1.0, 1.5275...)
    """
    return max(1.0, as_drive(drive).mu_max)


def physical_window(T_range=None, A_range=None, l=1.0, g=G_EARTH, drive=None):
    """``((T_min, T_max), (A_min, A_max))``: a window of the ``T``-``A`` plane with its defaults
    filled in (either range, or either end of one, may be None): ``T`` from 0 to ``2.5 sqrt(l/g)``,
    ``A`` from ``g / mu_top^2`` (:func:`mu_top`: ``g`` for the square and sine waves) to ``50 g``.
    Not checked: :func:`physical_zone_curves` checks it.

    Parameters
    ----------
    T_range, A_range : (float or None, float or None) or None
        The window's half-periods [s] and acceleration scales [m/s^2], ends that are None filled in.
    l, g : float
        Rod length [m] and gravity [m/s^2].
    drive : Drive or str, optional
        The paper's square wave by default.

    Returns
    -------
    ((float, float), (float, float))

    Raises
    ------
    KapitzaValueError
        If ``l`` or ``g`` is not a positive number or ``drive`` is not a drive kapitza knows (the
        window itself is not checked here).

    Examples
    --------
    >>> from kapitza.curves import physical_window
    >>> physical_window(None, (None, 200.0), l=1.0, g=9.81)
    ((0.0, 0.7981...), (9.81, 200.0))
    """
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    T0, T1 = (None, None) if T_range is None else T_range
    A0, A1 = (None, None) if A_range is None else A_range
    return ((0.0 if T0 is None else float(T0), 2.5 * float(np.sqrt(l / g)) if T1 is None else float(T1)),
            (g / mu_top(drive) ** 2 if A0 is None else float(A0), 50.0 * g if A1 is None else float(A1)))


def mu_top_note(top: float) -> str:
    """What an error message adds when a window's ``mu`` bound is a drive's ``mu_max`` (not 1)."""
    return "" if top == 1.0 else " (the drive's mu_max: beyond it the upright always falls)"


def window_range(eps_range, mu_range, mu_top=1.0):
    """``(eps_min, eps_max)`` of a window of Arnold's plane, checked: ``0 <= eps_min < eps_max < inf``,
    ``0 <= mu_min < mu_max <= mu_top`` (:class:`kapitza.KapitzaValueError` otherwise); ``mu_top``:
    :func:`mu_top` of the drive.

    Parameters
    ----------
    eps_range, mu_range : (float, float)
        The window.
    mu_top : float
        The largest ``mu`` allowed.

    Returns
    -------
    (float, float)

    Raises
    ------
    ValueError
        If the window is not as above.

    Examples
    --------
    >>> from kapitza.curves import window_range
    >>> window_range((0, 2), (0.1, 0.9), 1.0)
    (0.0, 2.0)
    >>> window_range((2, 1), (0.1, 0.9), 1.0)
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: eps range must satisfy 0 <= eps_min < eps_max < inf; got (2, 1)
    """
    e0, e1 = (float(v) for v in eps_range)
    m0, m1 = (float(v) for v in mu_range)
    if not (np.isfinite(e0) and np.isfinite(e1) and 0.0 <= e0 < e1):
        raise _v.KapitzaValueError(f"eps range must satisfy 0 <= eps_min < eps_max < inf; got ({e0:g}, {e1:g})")
    if not (0.0 <= m0 < m1 <= mu_top):
        raise _v.KapitzaValueError(f"mu range must satisfy 0 <= mu_min < mu_max <= {mu_top:.6g}{mu_top_note(mu_top)}; "
                                   f"got ({m0:g}, {m1:g})")
    return e0, e1


@dataclass(frozen=True)
class PhysicalZoneCurves:
    """Zone edges in the physical plane: for zone ``n[i]``, the half-periods
    ``T_lo[i]``, ``T_hi[i]`` at the amplitudes ``A`` (arrays ``(zones, points)``).

    Attributes
    ----------
    n : ndarray of int, shape (zones,)
        The zones' indices.
    A : ndarray, shape (points,)
        The samples of the acceleration scale [m/s^2].
    T_lo, T_hi : ndarray, shape (zones, points)
        Each zone's lower and upper edge in the half-period ``T`` [s] at each ``A``.
    l, g : float
        The rod length [m] and gravity [m/s^2] of the plane.

    Examples
    --------
    >>> from kapitza.curves import physical_zone_curves
    >>> pc = physical_zone_curves(A_range=(20.0, 200.0), l=1.0, points=20)
    >>> pc.n, pc.T_lo.shape
    (array([0, 1, 2]), (3, 20))
    >>> next(pc.rows())
    (0, np.float64(200.0), np.float64(0.0543...), np.float64(0.1370...))
    """

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

def physical_zone_curves(T_range=None, A_range=None, l=1.0, g=G_EARTH, points=1200, drive=None, zeta=0.0,
                         max_samples=None, check=None):
    """The edges of every zone visible in a window of the physical ``T``-``A`` plane.

    Parameters
    ----------
    T_range : (float, float), optional
        Half-periods [s]; default ``(0, 2.5 sqrt(l/g))``.
    A_range : (float, float), optional
        Acceleration amplitudes [m/s^2], ``g / mu_top^2 <= A_min < A_max`` (:func:`mu_top`: ``g`` for
        the square and sine waves, below which the upright always falls); default ``(g / mu_top^2, 50 g)``.
    l, g : float
        Rod length [m] and gravity [m/s^2].
    points : int
        ``A`` samples per edge (>= 2; more where the edges cross a narrow window).
    drive, zeta :
        As in :func:`window_curves` (``zeta = c / (2 sqrt(g/l))`` is the same over the plane).
    max_samples : int, optional
        The most ``A`` samples after refinement (default ``4 * points``).
    check : callable, optional
        As in :func:`window_curves`.

    Returns
    -------
    PhysicalZoneCurves

    Raises
    ------
    ValueError
        If a range is empty or outside its bounds, ``l`` or ``g`` is not > 0, ``points`` is below 2,
        or ``zeta`` is negative.

    Notes
    -----
    The edges of :func:`zone_curves`, mapped by ``A = g / mu^2`` and ``T = eps sqrt(8 l / A)``:
    at each ``A`` zone ``n`` is ``T_lo < T < T_hi`` (:func:`kapitza.period_edges`).

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.curves import physical_zone_curves
    >>> pc = physical_zone_curves(A_range=(100.0, 200.0), l=1.0, points=2)
    >>> pc.A[0], pc.T_lo[0, 0], pc.T_hi[0, 0]
    (np.float64(200.0), np.float64(0.0543...), np.float64(0.1370...))
    >>> kapitza.period_edges(200.0, 0, l=1.0)
    (np.float64(0.0543...), np.float64(0.1370...))
    """
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    top = mu_top(drive)
    A_low = g / top**2  # below it the upright always falls
    (T0, T1), (A0, A1) = physical_window(T_range, A_range, l, g, drive)
    if not (np.isfinite(T1) and 0.0 <= T0 < T1):
        raise _v.KapitzaValueError(f"T range must satisfy 0 <= T_min < T_max < inf; got ({T0:g}, {T1:g})")
    if not (np.isfinite(A1) and A_low <= A0 < A1):
        low = "g" if top == 1.0 else "g / mu_max^2"
        raise _v.KapitzaValueError(f"A range must satisfy {low} <= A_min < A_max < inf ({low} = {A_low:g}); "
                                   f"got ({A0:g}, {A1:g})")
    # eps = T sqrt(A / (8 l)) is largest at (T1, A1); cover the window in (eps, mu).
    mu_range = (np.sqrt(g / A1), min(np.sqrt(g / A0), top))
    curves = window_curves((T0 * np.sqrt(A0 / (8.0 * l)), T1 * np.sqrt(A1 / (8.0 * l))), mu_range, drive, zeta,
                           points, max_samples=max_samples, check=check)
    A = g / curves.mu**2
    scale = np.sqrt(8.0 * l / A)
    return PhysicalZoneCurves(n=curves.n, A=A, T_lo=curves.eps_lo * scale, T_hi=curves.eps_hi * scale, l=l, g=g)


@dataclass(frozen=True)
class DriveCurves:
    """Zone edges of one drive at the ``mu`` samples: ``lo[k]``, ``hi[k]`` for ``zones[k]``.

    Attributes
    ----------
    drive : str
        The drive's label.
    zeta : float
        The damping ratio.
    mu : ndarray, shape (points,)
        The samples of Arnold's ``mu``.
    zones : ndarray of int, shape (zones,)
        The zones' indices.
    lo, hi : ndarray, shape (zones, points)
        Each zone's lower and upper edge in ``eps`` (NaN where the zone misses that ``mu``).
    averaging : ndarray, shape (points,)
        The averaging criterion's ``eps`` at each ``mu`` (:func:`kapitza.averaging_threshold`).

    Examples
    --------
    >>> from kapitza.curves import drive_curves
    >>> dc = drive_curves("sine", [0.1, 0.3, 0.5], 2.0)
    >>> dc.zones, dc.lo.shape
    (array([0]), (1, 3))
    >>> next(dc.rows())
    ('sine wave', 0.0, 0, 0.1, 0.1570..., 0.7547...)
    """

    drive: str
    zeta: float
    mu: np.ndarray
    zones: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    averaging: np.ndarray

    def rows(self):
        """``(drive, zeta, zone, mu, eps_lo, eps_hi)`` rows for CSV."""
        for k, n in enumerate(self.zones):
            for m, a, b in zip(self.mu, self.lo[k], self.hi[k]):
                if np.isfinite(a) and np.isfinite(b):
                    yield self.drive, self.zeta, int(n), float(m), float(a), float(b)


def drive_curves(drive, mu, eps_max, zeta=0.0, eps_min=0.0):
    """Edges of every zone of ``drive`` that meets ``eps_min < eps < eps_max``, at the values ``mu``.

    Parameters
    ----------
    drive : Drive or str
        The pivot's motion (:mod:`kapitza.drives`).
    mu : array_like, shape ``(points,)``
        Where the edges are computed (each exactly: no interpolation).
    eps_max, eps_min : float
        The window of ``eps``.
    zeta : float
        Damping ratio ``c / (2 sqrt(g/l))``.

    Returns
    -------
    DriveCurves
        NaN where a zone does not exist at a ``mu``; an upper edge beyond the window of a
        damped zone may be ``inf`` (``docs/drives.md``).

    Raises
    ------
    ValueError
        If ``drive`` names no drive, ``mu`` is not in ``(0, mu_top)`` (:func:`mu_top`), the
        window is not ``0 <= eps_min < eps_max < inf`` or ``zeta`` is negative.

    Examples
    --------
    >>> from kapitza.curves import drive_curves
    >>> dc = drive_curves("sine", [0.1, 0.3, 0.5], 2.0)
    >>> dc.lo
    array([[0.1570..., 0.4746..., 0.8316...]])
    >>> dc.hi
    array([[0.7547..., 0.8114..., 0.9687...]])
    >>> dc.averaging
    array([0.1570..., 0.4712..., 0.7853...])
    """
    d = as_drive(drive)
    zeta = _v.one("zeta", _v.damping_ratio(zeta))
    top = mu_top(d)
    mu = np.atleast_1d(_v.in_range("mu", mu, 0.0, top, hi_open=True)).astype(float)
    if mu.ndim != 1:
        raise _v.KapitzaValueError(f"mu must be one row of values; got shape {mu.shape}")
    eps_min, eps_max = window_range((eps_min, eps_max), (0.0, top), top)
    rows, zone, lo_f, hi_f = _api.window_edges(d, mu, float(eps_min), float(eps_max), np.full(mu.size, float(zeta)))
    ok = np.isfinite(lo_f) & (lo_f < eps_max) & ~(hi_f < eps_min)
    zones = np.unique(zone[ok])
    lo = np.full((zones.size, mu.size), np.nan)
    hi = np.full((zones.size, mu.size), np.nan)
    k = np.searchsorted(zones, zone[ok])
    lo[k, rows[ok]] = lo_f[ok]
    hi[k, rows[ok]] = hi_f[ok]
    return DriveCurves(drive=d.label, zeta=float(zeta), mu=mu, zones=zones, lo=lo, hi=hi,
                       averaging=averaging_threshold(mu, d))
