"""Stability zones on Arnold's ``eps``-``mu`` plane and in the physical ``(T, A)`` plane.

Zone ``n`` (``n = 0, 1, 2, ...``) is the set ``alpha + n pi < u < beta + n pi``
(``docs/theory.md`` section 5, from Theorems 3.3-3.4 and Corollary 4.1). At fixed
``mu`` it is one interval ``eps_lo(n) < eps < eps_hi(n)``; the lower edge is
2T-periodic for even ``n`` and 4T-periodic for odd ``n``, the upper edge the
other way round.

Every function here validates its input once and asks the drive (:mod:`kapitza.drives`):
the square wave answers from its closed forms (:mod:`kapitza._square`), any other drive, and
damping, from the generic engine (:mod:`kapitza.drives._api`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _exact as X
from . import _validate as _v
from ._display import Summary, num, shape_of, span, stable_share
from ._square import _edge_u, _edges_eps, _kappa, _verdict, _verdict_careful  # noqa: F401  (for callers of the kernels' old home)
from .drives import as_drive
from .parameters import G_EARTH, SQRT8

__all__ = [
    "is_stable",
    "zone_index",
    "zone_edges",
    "zone_width",
    "G_m_curve",
    "StabilityMargin",
    "stability_margin",
    "stability_grid",
    "period_edges",
    "amplitude_edges",
]

PI = np.pi
# ---------------------------------------------------------------- public API
@_v.shapes_named
def is_stable(eps, mu, drive=None, zeta=0.0):
    """Whether the upright position is (strongly) stable at Arnold's ``(eps, mu)``.

    Parameters
    ----------
    eps : array_like
        ``eps = T sqrt(A / (8 l))``, finite and > 0.
    mu : array_like
        ``mu = sqrt(g / A)``, finite and > 0; ``mu >= 1`` (``A <= g``) is always unstable
        for the square wave. ``eps`` and ``mu`` broadcast together.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    zeta : array_like, optional
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0 (``docs/drives.md`` section 3); broadcasts.

    Returns
    -------
    ndarray of bool
        True where ``alpha + n pi < u < beta + n pi`` for some ``n >= 0`` (square wave,
        undamped); in general where both Floquet multipliers lie strictly inside the unit
        circle, or on it and distinct (``|tr M_phi| < 2 cosh(c T)``).

    Raises
    ------
    ValueError
        If ``eps`` or ``mu`` is not finite and > 0, ``zeta`` is negative, or they do not broadcast.

    Notes
    -----
    Theorems 3.3-3.4 and Corollary 4.1; ``docs/theory.md`` section 5. Points exactly
    on an edge (a 2T- or 4T-periodic solution exists, ``|tr M| = 2``) are unstable.
    Other drives and damping: ``docs/drives.md``.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.is_stable(0.5, 0.3)
    np.True_
    >>> kapitza.is_stable([0.2, 0.5, 1.2], 0.3)
    array([False,  True, False])
    >>> kapitza.is_stable(0.5, 0.3, drive="sine")
    np.True_
    >>> kapitza.is_stable(0.5, -0.3)
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: mu must be finite and > 0 (0 < mu < inf); got -0.3
    """
    eps, mu = _v.arnold(eps, mu)
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    return _v.scalars(np.asarray(d.verdict(eps, mu, zeta, want_zone=False)[0]))


@_v.shapes_named
def zone_index(eps, mu, drive=None, zeta=0.0):
    """Index ``n`` of the stability zone containing ``(eps, mu)``, or -1 where unstable.

    Parameters
    ----------
    eps, mu, drive, zeta :
        As in :func:`is_stable`.

    Returns
    -------
    ndarray of int
        Zone ``n`` is where the rotation angle per period lies in ``(n pi, (n + 1) pi)``
        (``docs/drives.md`` section 2); for the square wave ``alpha + n pi < u < beta + n pi``.

    Raises
    ------
    ValueError
        As in :func:`is_stable`.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.zone_index([0.2, 0.5, 1.2, 1.4], 0.3)
    array([-1,  0, -1, -1])
    """
    eps, mu = _v.arnold(eps, mu)
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    return _v.scalars(np.asarray(d.verdict(eps, mu, zeta)[1]))


@_v.shapes_named
def zone_edges(mu, n, drive=None, zeta=0.0, *, certify=True):
    """Edges ``eps_lo < eps_hi`` of stability zone ``n`` at the given ``mu``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int or array_like of int
        Zone index, ``n >= 0``; broadcasts with ``mu``.
    drive, zeta : optional
        As in :func:`is_stable`. For other drives and with damping the edges are found by
        safeguarded root solves to about 1e-14 relative, zone 0's lower edge included as
        ``mu -> 0`` (Kapitza's regime, formed without cancellation; checked against a 50-digit
        reference for ``mu`` in [1e-3, 0.9] in ``tests/test_drive_edges_oracle.py``;
        ``docs/drives.md``); NaN where the
        drive has no such zone at this ``mu``; where damping has joined zones ``n`` and
        ``n + 1``, ``eps_hi`` of one is ``eps_lo`` of the other.
    certify : bool, optional
        Move each edge to the double the certified verdict puts it at (default; below). False
        gives the solver's doubles, as charts draw them: for the square wave the closed forms'
        roots, within 4 ulp of those doubles on either side, about 170 times faster (0.2 us an
        edge against about 40 us, ``benchmarks/README.md``); for other drives the search's
        doubles, as accurate as ``docs/drives.md`` says.

    Returns
    -------
    eps_lo, eps_hi : ndarray
        Zone ``n`` is ``eps_lo < eps < eps_hi``: each edge is the double the certified verdict
        puts it at, ``eps_lo`` the last unstable double below the zone and ``eps_hi`` the first
        unstable one above it, so :func:`is_stable` is False at both and True at the doubles next
        to them inside. A zone with no stable double, thinner than their spacing, is reported
        by the two adjacent doubles its exact trace changes sign between, each in its own gap
        (``docs/drives.md`` says where a drive of linear pieces keeps the solver's doubles, far
        out near ``mu = 1``; the sine's come from its Sturm counts, ``docs/mathieu.md``). For the
        square wave the closed forms' roots lie within 4 ulp of these doubles (against the
        50-digit reference on the sweeps of ``tests/test_zones_oracle.py``: 201 values of
        ``mu`` in [0.1, 0.2] for zone 0's lower edge, where the solver changes form, and ``mu``
        in [0.01, 0.99] for both edges of zones 0-2). The lower edge carries a 2T-periodic solution for even
        ``n`` (eq. 3.10) and a 4T-periodic one for odd ``n`` (eq. 3.12); the upper
        edge a 4T- (3.13) respectively 2T-periodic one (3.11).

    Raises
    ------
    ValueError
        If ``mu`` is not in ``(0, 1)``, ``n`` is negative or not an integer, or ``zeta`` is negative.

    Notes
    -----
    ``u = alpha + n pi`` and ``u = beta + n pi`` at fixed ``mu``, ``u = 2 sqrt 2 eps
    sqrt(1 - mu^2)``; ``docs/theory.md`` section 5. Where the zone is narrower than
    a double's resolution of ``eps`` the two edges round to the same number; use
    :func:`zone_width` for the width.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.zone_edges(0.3, 0)
    (np.float64(0.3691...), np.float64(0.7059...))
    >>> kapitza.zone_edges(0.3, [0, 1, 2])
    (array([0.3691..., 1.7760..., 2.9441...]), array([0.7059..., 1.7837..., 2.9444...]))
    >>> kapitza.zone_edges(0.3, 0, drive="sine")
    (np.float64(0.4746...), np.float64(0.8114...))
    """
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    n = _v.nonnegative_int("n", n)
    mu = _v.positive("mu", mu)
    try:
        lo, hi = d.edges(mu, n, zeta, _v.flag("certify", certify))
    except _v.ReachError as err:
        raise err.about(f"mu = {mu.item()!r} and n = {int(n)}" if mu.size == 1 and np.size(n) == 1
                        else "mu and n") from None
    return _v.scalars(np.asarray(lo), np.asarray(hi))


@_v.shapes_named
def zone_width(mu, n, log=False):
    """Width ``eps_hi - eps_lo`` of zone ``n``, free of cancellation.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int or array_like of int
        Zone index ``>= 0``; broadcasts with ``mu``.
    log : bool, optional
        Return the natural logarithm of the width, finite even where the width
        underflows a double (``x`` beyond about 700).

    Returns
    -------
    ndarray

    Raises
    ------
    ValueError
        If ``mu`` is not in ``(0, 1)`` or ``n`` is not an integer ``>= 0``.

    Notes
    -----
    With ``x = D u`` at the two edges (``u_lo = n pi + gamma(x_lo) - delta(x_lo)``,
    ``u_hi = n pi + gamma(x_hi) + delta(x_hi)``, ``docs/theory.md`` section 5)::

        u_hi - u_lo = delta(x_lo) + delta(x_hi) + [gamma(x_hi) - gamma(x_lo)],

    with ``delta = atan(sqrt(1 - mu^4) / sinh x)`` and the bracket written as one
    arctangent of ``mu^2 sinh(x_hi - x_lo) / (s4 cosh x_lo cosh x_hi)``. Where the
    zone is wide the edges are subtracted directly (no cancellation to fear); where
    it is narrow the relation above is solved by fixed-point iteration (it contracts
    by ``D gamma' ~ e^{-2x}``), so the edges are never subtracted.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.zone_width(0.3, [0, 1, 2])
    array([3.3678...e-01, 7.7025...e-03, 2.4735...e-04])
    >>> kapitza.zone_width(0.3, 400, log=True)
    np.float64(-1376.7438...)
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    n = _v.nonnegative_int("n", n)
    log = _v.flag("log", log)
    ulo, q = _edge_u(mu, n, upper=False)
    uhi, _ = _edge_u(mu, n, upper=True)
    mu_b = np.broadcast_to(mu, ulo.shape)
    D = np.sqrt(1.0 + mu_b * mu_b) / q
    s4 = X.s4_of(mu_b)
    xlo, xhi = D * ulo, D * uhi
    with np.errstate(over="ignore", under="ignore"):
        dsum = X.delta_x(xlo, s4) + X.delta_x(xhi, s4)
        c = mu_b * mu_b / (s4 * np.cosh(xlo) * np.cosh(xhi))
        du = dsum
        for _ in range(12):
            du = dsum + np.arctan2(c * np.sinh(D * du), 1.0 + (mu_b**4 / s4**2) * np.tanh(xlo) * np.tanh(xhi))
    wide = (uhi - ulo) > 0.05 * uhi
    du = np.where(wide, uhi - ulo, du)
    if not log:
        return du / (SQRT8 * q)

    # Far out delta underflows: log(delta) ~ log s4 - log sinh x, and the bracket is negligible.
    def log_delta(x):
        lz = np.log(s4) - X.log_sinh(x)
        with np.errstate(under="ignore"):
            return np.where(lz < -30.0, lz, np.log(np.arctan(np.exp(np.maximum(lz, -30.0)))))

    with np.errstate(divide="ignore"):
        log_du = np.where(du > 1e-280, np.log(du), np.logaddexp(log_delta(xlo), log_delta(xhi)))
    return log_du - np.log(SQRT8 * q)


@_v.shapes_named
def G_m_curve(mu, m):
    """The curve ``G_m``: ``2 sqrt 2 eps sqrt(1 - mu^2) = (2m + 1) pi / 2``, as ``eps(mu)``.

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    m : int or array_like of int
        ``m >= 0``; broadcasts with ``mu``.

    Returns
    -------
    ndarray
        ``eps`` on ``G_m``. Zone ``m`` lies along ``G_m`` (section 4 of the paper).

    Raises
    ------
    ValueError
        If ``mu`` is not in ``(0, 1)`` or ``m`` is not an integer ``>= 0``.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.G_m_curve(0.3, 0)
    np.float64(0.5821...)
    >>> lo, hi = kapitza.zone_edges(0.3, 0)
    >>> bool(lo < kapitza.G_m_curve(0.3, 0) < hi)
    True
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    m = _v.nonnegative_int("m", m)
    return (2 * m + 1) * PI / (2.0 * SQRT8 * np.sqrt((1.0 - mu) * (1.0 + mu)))


@dataclass(frozen=True, repr=False)
class StabilityMargin(Summary):
    """Distance of ``(eps, mu)`` to the nearest zone edge along ``eps`` (fixed ``mu``,
    i.e. fixed ``A``: only the drive period changes). Arrays of the broadcast shape.

    Attributes
    ----------
    stable : ndarray of bool
    zone : ndarray of int
        The zone containing the point, or the nearest zone where unstable.
    eps_lo, eps_hi : ndarray
        Edges of that zone; NaN where there is none to give (``mu >= 1``, or a phase
        ``u = w_e T`` beyond ``2^52``, whose rounding exceeds a whole zone).
    margin : ndarray
        Signed relative distance to the nearest edge of that zone,
        ``min(eps - eps_lo, eps_hi - eps) / eps``: positive inside a zone
        (the fraction by which ``T`` may change before stability is lost),
        negative outside (the fraction by which ``T`` must change to gain it).
        ``-inf`` where ``mu >= 1`` or ``u > 2^52``.

    Examples
    --------
    >>> import kapitza
    >>> m = kapitza.stability_margin(0.5, 0.3)
    >>> m.stable, m.zone
    (np.True_, np.int64(0))
    >>> m.margin
    np.float64(0.2617...)
    """

    stable: np.ndarray
    zone: np.ndarray
    eps_lo: np.ndarray
    eps_hi: np.ndarray
    margin: np.ndarray

    def headline(self) -> str:
        if np.ndim(self.stable) == 0:
            return (f"{'stable in' if self.stable else 'unstable, nearest'} zone {int(self.zone)}, "
                    f"{num(self.eps_lo, 10)} < eps < {num(self.eps_hi, 10)}, margin {100 * float(self.margin):.4g}%")
        return stable_share(self.stable)

    def lines(self) -> list[tuple[str, str]]:
        if np.ndim(self.stable) == 0:
            return [("verdict", "stable" if self.stable else "unstable"),
                    ("zone", f"{int(self.zone)} ({'containing' if self.stable else 'nearest'})"),
                    ("edges", f"{num(self.eps_lo, 12)} < eps < {num(self.eps_hi, 12)}"),
                    ("margin", f"{100 * float(self.margin):.6g}% of eps")]
        return [("points", shape_of(self.stable)), ("stable", f"{100 * float(np.mean(self.stable)):.4g}%"),
                ("margin", f"{span(100 * np.asarray(self.margin))} % of eps")]

    def __post_init__(self):
        _v.scalar_fields(self)



@_v.shapes_named
def stability_margin(eps, mu, drive=None, zeta=0.0):
    """Signed relative distance from ``(eps, mu)`` to the nearest zone edge along ``eps``.

    Parameters
    ----------
    eps, mu, drive, zeta :
        As in :func:`is_stable`.

    Returns
    -------
    StabilityMargin

    Raises
    ------
    ValueError
        As in :func:`is_stable`.

    Examples
    --------
    >>> import kapitza
    >>> m = kapitza.stability_margin([0.5, 1.2], 0.3)
    >>> m.zone
    array([0, 0])
    >>> m.margin
    array([ 0.2617..., -0.4117...])
    """
    eps, mu = _v.arnold(eps, mu)
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    try:
        stable, zone, lo, hi, margin = d.margin(eps, mu, zeta)
    except _v.ReachError as err:
        if np.any(eps == err.eps):
            raise
        raise err.about(f"eps = {eps.item()!r} and mu = {mu.item()!r}" if eps.size == mu.size == 1
                        else "eps and mu") from None
    return StabilityMargin(stable=stable, zone=zone, eps_lo=lo, eps_hi=hi, margin=margin)


@_v.shapes_named
def stability_grid(eps, mu, out=None, drive=None, zeta=0.0):
    """Exact stability verdicts over the grid ``eps`` x ``mu``.

    Parameters
    ----------
    eps : 1-D array_like
        Finite, > 0; any order.
    mu : 1-D array_like
        Finite, > 0; ``mu >= 1`` rows are all unstable.
    out : ndarray of bool, shape ``(len(mu), len(eps))``, optional
        C-contiguous array to write into (saves allocating a fresh image when
        grids are computed repeatedly).
    drive : Drive or str, optional
        As in :func:`is_stable`.
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0 (one value for the whole grid).

    Returns
    -------
    ndarray of bool, shape ``(len(mu), len(eps))``
        ``grid[i, j] == is_stable(eps[j], mu[i])`` except within about 1e-13
        relative of an edge.

        The same grid with coordinates (``eps``, ``mu``, and ``T``, ``A`` with ``l=``), units and
        the drive as attributes: :func:`kapitza.grids.stability_grid_da` (an ``xarray.DataArray``).

    Raises
    ------
    ValueError
        If ``eps`` or ``mu`` is not a 1-D array of finite values > 0, ``out`` has the wrong shape,
        dtype or layout, or ``zeta`` is negative.

    Notes
    -----
    No per-pixel trigonometry: for each ``mu`` the edges of the zones that meet
    the ``eps`` range are computed (:func:`zone_edges`), located in the sorted
    ``eps`` grid by binary search, and the stable runs are painted row by row.
    The cost is ``O(len(mu) * zones * log len(eps))`` plus writing the output.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> grid = kapitza.stability_grid(np.linspace(0.1, 1.5, 8), [0.1, 0.3, 0.5])
    >>> grid.shape
    (3, 8)
    >>> grid.astype(int)
    array([[0, 1, 1, 0, 0, 0, 0, 0],
           [0, 0, 1, 1, 0, 0, 0, 0],
           [0, 0, 0, 1, 0, 0, 0, 0]])
    """
    eps, mu = _v.arnold(eps, mu, together=False)  # the grid's two axes
    d, zeta = as_drive(drive), _v.damping_ratio(zeta)
    if zeta.ndim != 0:
        raise _v.KapitzaValueError(f"zeta must be a single number for a grid; got shape {zeta.shape}")
    if eps.ndim != 1 or mu.ndim != 1:
        raise _v.KapitzaValueError(
            f"eps and mu must be 1-D arrays; got shapes {eps.shape} and {mu.shape}"
        )
    W = eps.size
    order = None
    if W > 1 and not np.all(eps[1:] >= eps[:-1]):
        order = np.argsort(eps, kind="stable")
        eps = eps[order]
    shape = (mu.size, W)
    if out is None:
        out = np.zeros(shape, dtype=bool)
    else:
        if not (isinstance(out, np.ndarray) and out.shape == shape and out.dtype == bool
                and out.flags.c_contiguous and out.flags.writeable):
            raise _v.KapitzaValueError(
                f"out must be a writeable C-contiguous bool array of shape {shape}")
        out.fill(False)
    d.paint(eps, mu, float(zeta), out)
    if order is not None:
        out[:, order] = out.copy()
    return out


@_v.shapes_named
def period_edges(A, n, l=1.0, g=G_EARTH, drive=None, damping=None, zeta=None):
    """Half-periods ``T_lo < T_hi`` bounding stability zone ``n`` for fixed ``A > g``.

    Parameters
    ----------
    A : array_like
        Amplitude of the pivot acceleration, ``A > g``.
    n : int or array_like of int
        Zone index ``>= 0``.
    l, g : float or array_like
        Rod length and gravity, > 0. All broadcast together.
    drive : Drive or str, optional
        As in :func:`is_stable`.
    damping : array_like, optional
        Viscous damping ``c`` >= 0 [1/s] (``theta'' + c theta' = ...``); or
    zeta : array_like, optional
        its damping ratio ``c / (2 sqrt(g/l))`` (give one of the two).

    Returns
    -------
    T_lo, T_hi : ndarray
        For even ``n``: ``(T_{n+1}, T~_{n+1})``; for odd ``n``: ``(T~_{n+1}, T_{n+1})``
        (Corollary 4.1). NaN where another drive has no zone ``n`` at this ``A``.

    Raises
    ------
    ValueError
        If ``A <= g``, a length or gravity is not > 0, ``n`` is not an integer ``>= 0``, or both
        ``damping`` and ``zeta`` are given.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.period_edges(100.0, 0, l=1.0)
    (np.float64(0.1091...), np.float64(0.2008...))
    >>> kapitza.period_edges(100.0, 0, l=1.0, damping=0.5)
    (np.float64(0.1091...), np.float64(0.2010...))
    """
    A = _v.positive("A", A)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    n = _v.nonnegative_int("n", n)
    c, _ = _v.damping(damping, zeta, l, g)
    lo, hi = as_drive(drive).period_edges(A, n, l, g, c)
    return _v.scalars(np.asarray(lo), np.asarray(hi))


@_v.shapes_named
def amplitude_edges(T, n, l=1.0, g=G_EARTH, drive=None, damping=None, zeta=None):
    """Amplitudes ``A_lo < A_hi`` bounding stability zone ``n`` for fixed half-period ``T``.

    Parameters
    ----------
    T : array_like
        Half-period of the drive, > 0.
    n : int or array_like of int
        Zone index ``>= 0``.
    l, g : float or array_like
        Rod length and gravity, > 0. All broadcast together.
    drive, damping, zeta : optional
        As in :func:`period_edges`; other drives and damping are solved by bisection on the
        zone index along ``A`` (``docs/drives.md``).

    Returns
    -------
    A_lo, A_hi : ndarray
        Zone ``n`` at this ``T`` is ``A_lo < A < A_hi``.

    Raises
    ------
    ValueError
        If ``T``, ``l`` or ``g`` is not > 0, ``n`` is not an integer ``>= 0``, or both ``damping`` and
        ``zeta`` are given.

    Notes
    -----
    At fixed ``T`` the elliptic phase angle ``u = T sqrt((A - g)/l)`` increases with
    ``A`` and ``x^2 = u^2 + 2 g T^2 / l``; each edge equation ``u - n pi = alpha`` or
    ``beta`` changes sign once on ``n pi <= u <= (n+1) pi`` and is solved there by
    regula falsi (Illinois). Zone 0's lower edge, where ``u`` and ``alpha`` agree to
    ``O(u^3)`` as ``kappa = 2 g T^2 / l -> 0`` (``u ~ (6 kappa)^(1/4)``), is solved on the
    cancellation-free form of that gap (:func:`kapitza._exact.sin_half_a0`). Both edges are
    within 5 ulp of the 50-digit reference on the rigs of ``tests/test_rig_edges_oracle.py``
    (``kappa`` from 1e-299 to about 100, zones 0-2; no proof of a bound is claimed).

    Examples
    --------
    >>> import kapitza
    >>> kapitza.amplitude_edges(0.15, 0, l=1.0)
    (np.float64(73.0882...), np.float64(169.1717...))
    """
    T = _v.positive("T", T)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    n = _v.nonnegative_int("n", n)
    c, _ = _v.damping(damping, zeta, l, g)
    lo, hi = as_drive(drive).amplitude_edges(T, n, l, g, c)
    return _v.scalars(np.asarray(lo), np.asarray(hi))
