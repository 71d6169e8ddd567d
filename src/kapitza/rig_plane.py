"""The stability zones as a rig is set: drive frequency against stroke (both on log axes).

A shaker is turned by its frequency ``f`` and its stroke ``s`` (peak-to-peak travel of the
pivot). With the drive's stroke coefficient ``k`` (``s = k A T^2``: 1/4 for the square wave,
``2/pi^2`` for the sine) and ``T = 1/(2 f)``::

    eps = sqrt(s / (8 l k))           (fixed by the stroke alone)
    mu  = sqrt(g k / (4 s)) / f       (falls like 1/f at a fixed stroke)

so at a fixed stroke zone ``n`` is one interval of ``mu`` (both edges ``eps_lo(mu)``,
``eps_hi(mu)`` grow with ``mu``): ``eps_hi(mu_a) = eps`` and ``eps_lo(mu_b) = eps``, that is
the frequencies ``f_lo = K / mu_b < f < f_hi = K / mu_a`` with ``K = sqrt(g k / (4 s))``.
:func:`rig_zone_curves` finds them from the exact edges (:func:`kapitza.zone_edges`) sampled
densely in ``mu`` (geometrically) and inverted by interpolation, one pair per stroke sample.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as _v
from .parameters import G_EARTH
from .zones import zone_edges

__all__ = ["RigZoneCurves", "rig_zone_curves", "rig_window", "stroke_coefficient"]

#: Largest zone drawn.
MAX_ZONES = 40


def stroke_coefficient(drive=None) -> float:
    """``k`` in ``stroke = k A T^2`` for the drive (1/4 for the square wave).

    Parameters
    ----------
    drive : Drive or str, optional
        The paper's square wave by default.

    Returns
    -------
    float
        The pivot's peak-to-peak travel is ``k A T^2`` for the acceleration scale ``A`` and
        half-period ``T``.

    Raises
    ------
    ValueError
        If ``drive`` names no drive.

    Examples
    --------
    >>> from kapitza.rig_plane import stroke_coefficient
    >>> stroke_coefficient(), stroke_coefficient("sine")
    (0.25, 0.2026...)
    """
    from .drives import as_drive

    return float(as_drive(drive).stroke(1.0, 1.0))


def rig_window(frequency_range=None, stroke_range=None, l=1.0, g=G_EARTH, around=None):
    """``((f_min, f_max), (s_min, s_max))`` [Hz, m] with the defaults filled in.

    Around a rig's point ``around = (f, s)``: a factor 4 either way in frequency and 40 in stroke
    (the point in the middle of both log axes). Without one: from twice the hanging pendulum's
    own frequency ``sqrt(g/l) / (2 pi)`` to 200 times it, and strokes from ``l / 1000`` to ``l``.

    Parameters
    ----------
    frequency_range, stroke_range : (float, float), optional
        Given ends are kept.
    l, g : float
        Equivalent length [m] and gravity [m/s^2].
    around : (float, float), optional
        A rig's ``(frequency [Hz], stroke [m])``.

    Returns
    -------
    ((float, float), (float, float))
        Not checked: :func:`rig_zone_curves` checks the window (``l``, ``g`` and ``around`` are
        checked here).

    Raises
    ------
    KapitzaValueError
        If ``l`` or ``g`` is not finite and positive, or ``around`` is not a pair of finite
        positive numbers.

    Examples
    --------
    >>> from kapitza.rig_plane import rig_window
    >>> rig_window(l=0.2, around=(40.0, 0.02))
    ((10.0, 160.0), (0.0005, 0.8))
    >>> rig_window(l=0.2)
    ((2.2293..., 222.9305...), (0.0002, 0.2))
    """
    f0, f1 = (None, None) if frequency_range is None else frequency_range
    s0, s1 = (None, None) if stroke_range is None else stroke_range
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    if around is not None:
        try:
            fa, sa = (float(v) for v in around)
        except (TypeError, ValueError):
            raise _v.KapitzaValueError(f"around must be a rig's (frequency, stroke); got {around!r}") from None
        if not (0.0 < fa < np.inf and 0.0 < sa < np.inf):
            raise _v.KapitzaValueError(f"around must be a rig's (frequency, stroke) with 0 < frequency < inf and "
                                       f"0 < stroke < inf; got ({fa!r}, {sa!r})")
        df, ds = (fa / 4.0, fa * 4.0), (sa / 40.0, sa * 40.0)
    else:
        fn = float(np.sqrt(g / l) / (2.0 * np.pi))
        df, ds = (2.0 * fn, 200.0 * fn), (l / 1000.0, float(l))
    return ((df[0] if f0 is None else float(f0), df[1] if f1 is None else float(f1)),
            (ds[0] if s0 is None else float(s0), ds[1] if s1 is None else float(s1)))


@dataclass(frozen=True)
class RigZoneCurves:
    """Zone ``n[i]`` is ``f_lo[i, j] < f < f_hi[i, j]`` at the stroke ``stroke[j]`` [m]; NaN where the
    zone misses that stroke in the window, ``-inf``/``inf`` where an edge lies beyond it.

    Attributes
    ----------
    n : ndarray of int, shape (zones,)
        The zones' indices.
    stroke : ndarray, shape (points,)
        The samples of the stroke [m] (peak-to-peak pivot travel).
    f_lo, f_hi : ndarray, shape (zones, points)
        Each zone's lower and upper edge in the drive frequency [Hz] at each stroke.
    l, g : float
        The equivalent length [m] and gravity [m/s^2].
    frequency_range, stroke_range : (float, float)
        The window [Hz], [m] (:func:`rig_window`).

    Examples
    --------
    >>> from kapitza.rig_plane import rig_zone_curves
    >>> rc = rig_zone_curves(l=0.2, around=(40.0, 0.02), points=30)
    >>> rc.n, rc.f_lo.shape == (1, rc.stroke.size)
    (array([0]), True)
    >>> next(rc.rows())
    (0, np.float64(0.0005), np.float64(1213.0554...), np.float64(inf))
    """

    n: np.ndarray
    stroke: np.ndarray
    f_lo: np.ndarray
    f_hi: np.ndarray
    l: float
    g: float
    frequency_range: tuple
    stroke_range: tuple

    def rows(self):
        """``(n, stroke, f_lo, f_hi)`` rows for CSV export."""
        for i, n in enumerate(self.n):
            for j, s in enumerate(self.stroke):
                yield int(n), s, self.f_lo[i, j], self.f_hi[i, j]


def rig_zone_curves(frequency_range=None, stroke_range=None, l=1.0, g=G_EARTH, drive=None, zeta=0.0, points=300,
                    around=None, mu_samples=None) -> RigZoneCurves:
    """The edges of every zone in a window of the frequency-stroke plane of a rig.

    Parameters
    ----------
    frequency_range : (float, float), optional
        Drive frequencies [Hz] (defaults: :func:`rig_window`).
    stroke_range : (float, float), optional
        Strokes (peak-to-peak) [m].
    l, g : float
        Equivalent length [m] (a uniform rod of length L: ``2 L / 3``) and gravity [m/s^2].
    drive, zeta : optional
        The pivot's motion and the damping ratio ``c / (2 sqrt(g/l))`` (constant over the plane).
    points : int
        Stroke samples (geometric).
    around : (float, float), optional
        A rig's ``(frequency, stroke)`` that the default window is centred on.
    mu_samples : int, optional
        ``mu`` samples of each exact edge before inversion (default 2000 for the undamped square
        wave, whose edges are closed forms; 160 for another drive or damping, where each is a root
        solve: the inversion's interpolation error is then about 1e-4 relative).

    Returns
    -------
    RigZoneCurves

    Raises
    ------
    ValueError
        If a range is empty or not positive, ``l`` or ``g`` is not > 0, ``points`` is out of range,
        ``zeta`` is negative, or ``drive`` names no drive.

    Examples
    --------
    A 30 cm rod (``l = 0.2`` m) on a square-wave shaker: at a 20 mm stroke it stands from 30 Hz up.

    >>> import numpy as np
    >>> from kapitza.rig_plane import rig_zone_curves
    >>> rc = rig_zone_curves(l=0.2, around=(40.0, 0.02), points=30)
    >>> rc.n
    array([0])
    >>> j = int(np.argmin(abs(rc.stroke - 0.02)))
    >>> float(rc.stroke[j]), float(rc.f_lo[0, j]), float(rc.f_hi[0, j])
    (0.0198..., 30.5001..., inf)
    """
    from .drives import as_drive, parse_drive
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    zeta = _v.one("zeta", _v.nonnegative("zeta", zeta))
    points = _v.bounded_count("points", points, 20_000, minimum=2)
    d = parse_drive(drive) if isinstance(drive, str) else as_drive(drive)
    (f0, f1), (s0, s1) = rig_window(frequency_range, stroke_range, l, g, around)
    for name, a, b in (("frequency", f0, f1), ("stroke", s0, s1)):
        if not (np.isfinite(a) and np.isfinite(b) and 0.0 < a < b):
            raise _v.KapitzaValueError(f"{name} range must satisfy 0 < {name}_min < {name}_max < inf; got ({a:g}, "
                                       f"{b:g})")
    k = stroke_coefficient(d)
    stroke = np.geomspace(s0, s1, points)
    eps_all = np.sqrt(np.array([s0, s1]) / (8.0 * l * k))
    K_all = np.sqrt(g * k / (4.0 * np.array([s0, s1])))
    top = float(d.mu_max) if np.isfinite(d.mu_max) else 1.0
    m_lo = max(float(K_all.min() / f1), 1e-9)
    m_hi = min(float(K_all.max() / f0), 0.999999 * top)
    n_max = min(MAX_ZONES, int(np.ceil(float(eps_all.max()) * np.sqrt(8.0) / np.pi)) + 2)
    if mu_samples is None:
        mu_samples = 2000 if d.closed_form(zeta) else 160
    edges = None
    if m_lo < m_hi:
        mu = np.geomspace(m_lo, m_hi, _v.bounded_count("mu_samples", mu_samples, 100_000, minimum=2))
        lo_e = np.full((n_max, mu.size), np.inf)
        hi_e = np.full((n_max, mu.size), np.inf)
        for i in range(n_max):
            lo_e[i], hi_e[i] = _row_edges(mu, i, d, zeta, float(eps_all.max()))
        edges = (mu, lo_e, hi_e)

    def frequencies(st):
        f_lo = np.full((n_max, st.size), np.nan)
        f_hi = np.full((n_max, st.size), np.nan)
        if edges is None:
            return f_lo, f_hi
        mu, lo_e, hi_e = edges
        eps = np.sqrt(st / (8.0 * l * k))
        K = np.sqrt(g * k / (4.0 * st))
        for i in range(n_max):
            a_mu = _inverse(hi_e[i], mu, eps)   # mu where the upper edge reaches eps: the highest frequency
            b_mu = _inverse(lo_e[i], mu, eps)   # mu where the lower edge reaches eps: the lowest frequency
            with np.errstate(divide="ignore", invalid="ignore"):
                f_hi[i] = np.where(a_mu == -np.inf, np.inf, K / a_mu)
                f_lo[i] = np.where(b_mu == np.inf, -np.inf, K / b_mu)
            empty = np.isnan(a_mu) | np.isnan(b_mu) | (a_mu >= b_mu)
            f_lo[i, empty] = np.nan
            f_hi[i, empty] = np.nan
        return f_lo, f_hi

    f_lo, f_hi = frequencies(stroke)
    # An edge nearly level in this plane (the upper edge as mu -> 0) jumps between stroke samples:
    # sample those gaps finely, so that it is drawn where it is.
    with np.errstate(divide="ignore", invalid="ignore"):
        jump = np.zeros(points - 1, dtype=bool)
        for f in (f_lo, f_hi):
            a, b = f[:, :-1], f[:, 1:]
            fin = np.isfinite(a) & np.isfinite(b)
            jump |= np.any((fin & (np.abs(np.log(np.abs(b) / np.abs(a))) > 0.1))
                           | (np.isfinite(a) != np.isfinite(b)) | (np.isnan(a) != np.isnan(b)), axis=0)
    if jump.any():
        extra = [np.geomspace(stroke[j], stroke[j + 1], 26)[1:-1] for j in np.flatnonzero(jump)[:200]]
        stroke = np.unique(np.concatenate([stroke, *extra]))
        f_lo, f_hi = frequencies(stroke)
    keep = [i for i in range(n_max) if np.any(np.isfinite(f_lo[i]) & (f_lo[i] < f1) | (f_lo[i] == -np.inf))
            and np.any((f_hi[i] > f0) & ~np.isnan(f_hi[i]))]
    return RigZoneCurves(n=np.array(keep, dtype=int), stroke=stroke, f_lo=f_lo[keep], f_hi=f_hi[keep], l=l, g=g,
                         frequency_range=(f0, f1), stroke_range=(s0, s1))


def _row_edges(mu, n, drive, zeta, eps_top):
    """Zone ``n``'s edges at the increasing ``mu`` samples, ``inf`` at the samples a drive's edge
    solver refuses as too far out (the sine drive's edges beyond ``q = 1e8`` as ``mu -> 1``): those
    lie beyond the window as long as the last edge it gives is already above ``eps_top``. To a
    pixel: each edge as the drive's search leaves it (not moved to its certified double)."""

    try:
        lo, hi = zone_edges(mu, n, drive=drive, zeta=zeta, certify=False)
        return np.asarray(lo, float), np.asarray(hi, float)
    except _v.KapitzaValueError:
        if mu.size < 2:
            raise
    # the refusal grows with mu: the longest prefix the solver takes, by bisection
    good, bad = 0, mu.size
    while bad - good > 1:
        mid = (good + bad) // 2
        try:
            zone_edges(mu[mid], n, drive=drive, zeta=zeta, certify=False)
            good = mid
        except _v.KapitzaValueError:
            bad = mid
    lo = np.full(mu.size, np.inf)
    hi = np.full(mu.size, np.inf)
    lo[:bad], hi[:bad] = (np.asarray(a, float)
                          for a in zone_edges(mu[:bad], n, drive=drive, zeta=zeta, certify=False))
    if not lo[bad - 1] > eps_top:
        raise _v.KapitzaValueError(f"the drive's zone {n} edges stop at mu = {mu[bad - 1]:.6g} inside the window "
                                   f"(eps = {lo[bad - 1]:.4g} <= {eps_top:.4g}): narrow the frequency range")
    return lo, hi


def _inverse(edge, mu, eps):
    """``mu`` where the increasing ``edge(mu)`` equals each ``eps``: ``-inf`` below the samples' range
    (``eps`` under the edge's first sample), ``inf`` above it, NaN where the edge has no finite sample."""
    ok = np.isfinite(edge)
    if ok.sum() < 2:
        return np.full(eps.shape, np.nan)
    e, m = edge[ok], mu[ok]
    # keep a monotone run (the edges grow with mu; a damped edge may stop where zones join)
    e = np.maximum.accumulate(e)
    out = np.interp(eps, e, np.log(m))
    out = np.exp(out)
    out = np.where(eps < e[0], -np.inf, out)
    out = np.where(eps > e[-1], np.inf, out)
    return out
