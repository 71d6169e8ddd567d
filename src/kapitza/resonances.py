"""Curves of the nonlinear stability chart: strong resonances, twist zeros, Markeev's verdict along 1:4.

Inside zone ``n`` (``docs/theory.md`` section 5) the linear rotation ``w`` of the period map
runs monotonically through ``(0, pi)``: from 0 at the ``2T``-periodic edge to ``pi`` at the
``4T``-periodic one. So each zone holds exactly one curve ``w = 2 pi / q`` for ``q = 3``
(``tr M = -1``) and ``q = 4`` (``tr M = 0``), found here at each ``mu`` by bisection on the
certified rotation angle (no pixel grid). Along 1:4 Markeev's criterion compares the twist
with the resonant coefficient (:func:`kapitza.nonlinear_stability`); where the twist changes
sign inside a zone the zero is bracketed by a scan and refined by :func:`scipy.optimize.brentq`.
``docs/nonlinear.md`` section 6 shows the chart.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as _v
from ._normal_form import _DEFECT_DRAW, _normal_form, _w_of
from ._square import _floquet
from ._square import _edges_eps

__all__ = ["resonance_curve", "twist_zeros", "ZoneCurves", "NonlinearChart", "nonlinear_chart"]

PI = np.pi


def _w(eps, mu):
    _, _, theta, stable, n = _floquet(eps, mu)
    return _w_of(theta, n), stable


def _resonance_eps(mu, n, q):
    """eps on ``w = 2 pi / q`` in zone n (trusted 0 < mu < 1, arrays)."""
    lo, hi = _edges_eps(mu, n)
    target = 2.0 * PI / q
    # w rises from 0 at the 2T edge: the lower edge for even n, the upper for odd n
    rising = (n % 2) == 0
    a, b = lo.copy(), hi.copy()
    for _ in range(200):
        mid = 0.5 * (a + b)
        w, _ = _w(mid, mu)
        below = (w < target) if rising else (w > target)
        a = np.where(below, mid, a)
        b = np.where(below, b, mid)
        if np.all(b - a <= 2.0 * np.finfo(float).eps * b):
            break
    return 0.5 * (a + b)


def resonance_curve(mu, n, order):
    """The strong-resonance curve ``w = 2 pi / order`` inside zone ``n``, as ``eps(mu)``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int
        Zone index >= 0.
    order : int
        3 (``tr M = -1``) or 4 (``tr M = 0``); any integer >= 3 is accepted.

    Returns
    -------
    ndarray
        ``eps`` with ``tr M = 2 cos(2 pi / order)`` inside zone ``n`` (to a few ulps).

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Examples
    --------
    >>> from kapitza.resonances import resonance_curve
    >>> resonance_curve([0.3], 0, 4)
    array([0.6138...])
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    n = int(_v.nonnegative_int("n", n))
    order = _v.bounded_count("order", order, 1000, minimum=3)
    return _resonance_eps(mu, n, order)


def _twist_at(eps, mu, defect_max=None):
    kw = {} if defect_max is None else {"defect_max": defect_max}
    return _normal_form(np.atleast_1d(np.asarray(eps, float)), np.atleast_1d(np.asarray(mu, float)), **kw)[0].twist


def twist_zeros(mu, n, samples=400):
    """Where the twist vanishes inside zone ``n`` at one ``mu``.

    Parameters
    ----------
    mu : float
        ``0 < mu < 1``.
    n : int
        Zone index.
    samples : int, optional
        Points of the bracketing scan across the zone (spaced more densely near the edges).

    Returns
    -------
    ndarray
        The ``eps`` of each sign change of ``tau`` found (empty if none).

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Examples
    --------
    >>> from kapitza.resonances import twist_zeros
    >>> twist_zeros(0.3, 0)
    array([], dtype=float64)
    """
    from scipy.optimize import brentq

    mu = _v.one("mu", _v.in_range("mu", mu, 0.0, 1.0))
    n = int(_v.nonnegative_int("n", n))
    samples = _v.bounded_count("samples", samples, _v.MAX_POINTS, minimum=8)
    lo, hi = (float(v) for v in _edges_eps(np.array(mu), n))
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, PI, samples + 2)[1:-1])
    eps = lo + s * (hi - lo)
    _, stable = _w(eps, np.full_like(eps, mu))
    eps = eps[stable]
    if eps.size < 2:
        return np.empty(0)
    # the scan only brackets sign changes: the looser rounding bound will do; brentq refines exactly
    tau = _twist_at(eps, np.full_like(eps, mu), _DEFECT_DRAW)
    roots = []
    for i in np.flatnonzero(np.sign(tau[:-1]) * np.sign(tau[1:]) < 0):
        roots.append(brentq(lambda e: float(_twist_at(e, mu)[0]), eps[i], eps[i + 1], xtol=1e-15, rtol=4e-16))
    return np.asarray(roots)


@dataclass(frozen=True)
class ZoneCurves:
    """The curves of one zone on the ``mu`` where the zone is resolved in double precision.

    Attributes
    ----------
    n : int
    mu : ndarray
        Samples where the zone is wide enough that ``eps`` in a double resolves both resonance
        curves (``|w - 2 pi/q| < 1e-6`` at the curve found); far out the zones are thinner than
        a double's spacing of ``eps`` and are left out.
    eps_lo, eps_hi : ndarray
        Linear zone edges.
    eps_1to3, eps_1to4 : ndarray
        ``tr M = -1`` and ``tr M = 0``.
    twist_1to4, resonant_1to4 : ndarray
        ``tau`` and ``|c4|`` along 1:4: Markeev stable where ``|tau| > |c4|``.
    twist_zeros : list of (mu, eps)
        Sign changes of the twist found by the scan (undecided at third order).
    twist_sign : int
        The sign of ``tau`` over the zone when it has one (0 otherwise).

    Examples
    --------
    >>> from kapitza.resonances import nonlinear_chart
    >>> zone = nonlinear_chart([0.2, 0.3], zones=(0,), scan=0).zones[0]
    >>> zone.n, zone.mu
    (0, array([0.2, 0.3]))
    >>> zone.eps_lo, zone.eps_1to4, zone.eps_1to3, zone.eps_hi
    (array([0.2451..., 0.3691...]), array([0.5802..., 0.6138...]),
     array([0.6367..., 0.6652...]), array([0.6811..., 0.7059...]))
    """

    n: int
    mu: np.ndarray
    eps_lo: np.ndarray
    eps_hi: np.ndarray
    eps_1to3: np.ndarray
    eps_1to4: np.ndarray
    twist_1to4: np.ndarray
    resonant_1to4: np.ndarray
    twist_zeros: list
    twist_sign: int

    @property
    def markeev_stable(self) -> np.ndarray:
        return np.abs(self.twist_1to4) > self.resonant_1to4

    def rows(self):
        """CSV rows ``zone, mu, eps_lo, eps_hi, eps_1to3, eps_1to4, tau_1to4, c4_1to4, markeev``."""
        for i, m in enumerate(self.mu):
            yield [self.n, float(m), float(self.eps_lo[i]), float(self.eps_hi[i]), float(self.eps_1to3[i]),
                   float(self.eps_1to4[i]), float(self.twist_1to4[i]), float(self.resonant_1to4[i]),
                   "stable" if self.markeev_stable[i] else "unstable"]

    def as_dict(self) -> dict:
        d = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.__dict__.items()}
        d["twist_zeros"] = [list(map(float, p)) for p in self.twist_zeros]
        d["markeev_stable"] = self.markeev_stable.tolist()
        return d


CSV_HEADER = ["zone", "mu", "eps_lo", "eps_hi", "eps_1to3", "eps_1to4", "tau_1to4", "c4_1to4", "markeev_1to4"]


@dataclass(frozen=True)
class NonlinearChart:
    """The curves of the nonlinear chart, zone by zone (``docs/nonlinear.md`` section 6).

    Attributes
    ----------
    zones : tuple of ZoneCurves
    scan : int
        Points per zone and ``mu`` of the scan for twist zeros.

    Examples
    --------
    >>> from kapitza.resonances import nonlinear_chart
    >>> chart = nonlinear_chart([0.2, 0.3], zones=(0, 1), scan=0)
    >>> [zone.n for zone in chart.zones], chart.scan
    ([0, 1], 0)
    """

    zones: tuple
    scan: int

    def rows(self):
        for z in self.zones:
            yield from z.rows()

    def as_dict(self) -> dict:
        return {"zones": [z.as_dict() for z in self.zones], "twist_scan_points_per_zone_and_mu": self.scan}


def _zone_curves(mu, n, scan):
    res3 = _resonance_eps(mu, n, 3)
    res4 = _resonance_eps(mu, n, 4)
    w3, s3 = _w(res3, mu)
    w4, s4 = _w(res4, mu)
    ok = s3 & s4 & (np.abs(w3 - 2 * PI / 3) < 1e-6) & (np.abs(w4 - PI / 2) < 1e-6)
    mu, res3, res4 = mu[ok], res3[ok], res4[ok]
    lo, hi = _edges_eps(mu, n)
    nf, _ = _normal_form(res4, mu)
    zeros = [(float(m), float(e)) for m in (mu if scan else []) for e in twist_zeros(m, n, samples=scan)]
    signs = set(np.sign(nf.twist).tolist())
    sign = int(signs.pop()) if len(signs) == 1 and not zeros else 0
    return ZoneCurves(n=n, mu=mu, eps_lo=lo, eps_hi=hi, eps_1to3=res3, eps_1to4=res4, twist_1to4=nf.twist,
                      resonant_1to4=nf.resonant_4, twist_zeros=zeros, twist_sign=sign)


def nonlinear_chart(mu, zones=(0, 1, 2), *, scan=60):
    """Every curve of the nonlinear stability chart at these ``mu``.

    Parameters
    ----------
    mu : array_like
        1-d samples in ``(0, 1)``.
    zones : sequence of int
        Zone indices.
    scan : int, optional
        Points per zone and ``mu`` of the scan that brackets twist zeros (0: no scan).

    Returns
    -------
    NonlinearChart

    Raises
    ------
    ValueError
        If a ``mu`` is not in ``(0, 1)``, a zone index is not an integer ``>= 0``, or ``scan`` is
        out of range.

    Examples
    --------
    >>> from kapitza.resonances import nonlinear_chart
    >>> zone = nonlinear_chart([0.3], zones=(0,), scan=0).zones[0]
    >>> zone.twist_sign, zone.twist_zeros
    (-1, [])
    """
    mu = np.atleast_1d(_v.in_range("mu", mu, 0.0, 1.0)).ravel()
    zones = tuple(int(_v.nonnegative_int("zones", z)) for z in zones)
    scan = _v.bounded_count("scan", scan, _v.MAX_POINTS)
    return NonlinearChart(zones=tuple(_zone_curves(mu, n, scan) for n in zones), scan=scan)
