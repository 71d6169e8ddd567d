"""Periodic solutions: Theorems 3.3 and 3.4, Corollary 4.1.

For fixed ``(l, g, A)`` with ``A > g`` the half-periods ``T`` at which (2.3) has a
2T-periodic solution are the roots of (3.10) ``u = alpha + 2k pi`` and (3.11)
``u = beta + (2k+1) pi``; a 4T-periodic (and not 2T-periodic) solution, of (3.12)
``u = alpha + (2k+1) pi`` and (3.13) ``u = beta + 2k pi`` (``u = w_e T``).
Corollary 4.1 numbers them ``T_1 < T~_1 < T~_2 < T_2 < T_3 < T~_3 < ...``:
``T_{n+1}`` is the 2T-periodic edge of zone ``n`` and ``T~_{n+1}`` its 4T-periodic edge.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _exact as X
from . import _validate as _v
from ._display import Summary, num
from .parameters import G_EARTH
from .propagation import linear_motion
from ._square import _edges_eps

__all__ = [
    "alpha",
    "beta",
    "boundary_periods",
    "BoundaryPeriod",
    "boundary_table",
    "PeriodicSolution",
    "periodic_solution",
]

#: Largest count of boundary periods and largest index (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_COUNT = 100_000


def _check_A(A, g):
    if np.any(A <= g):
        Ab, gb = np.broadcast_arrays(A, g)
        i = np.argwhere(Ab <= gb)[0]
        raise _v.KapitzaValueError(
            f"A must exceed g (A > g): with A <= g there is no elliptic phase and no periodic "
            f"solution (always unstable); got A={float(Ab[tuple(i)])!r}, g={float(gb[tuple(i)])!r}"
        )


def _time_scale(l, A):
    """``sqrt(8 l / A)`` (``T`` per unit ``eps``), formed where ``8 l / A`` leaves the doubles
    (``l = 1e308``) as ``sqrt(8) sqrt(l) / sqrt(A)``."""
    with np.errstate(over="ignore", under="ignore"):
        r = 8.0 * l / A
        return np.where(np.isfinite(r) & (r > 1e-300), np.sqrt(r), np.sqrt(8.0) * (np.sqrt(l) / np.sqrt(A)))


def _xD(T, A, l, g):
    """``(x, u, D)`` of validated physical parameters with ``A > g``."""
    T, A, l, g = (_v.positive(n, v) for n, v in zip("TAlg", (T, A, l, g)))
    _v.finite_rate(A, l, g)
    _check_A(A, g)
    w_h = np.sqrt((A + g) / l)
    w_e = np.sqrt((A - g) / l)
    with np.errstate(over="ignore"):  # w_h T = inf (T = 1e308): tanh and coth take their limit 1
        return w_h * T, w_e * T, w_h / w_e


@_v.shapes_named
def alpha(T, A, l=1.0, g=G_EARTH):
    """The angle ``alpha`` of Theorem 3.3: ``alpha(T) = 2 atan(D tanh(w_h T / 2))``.

    In the paper's form ``alpha(T) = 2 atan(D (e^{w_h T} - 1) / (e^{w_h T} + 1))``.

    Parameters
    ----------
    T, A, l, g : array_like, broadcast together
        Each finite and > 0, with ``A > g``.

    Returns
    -------
    ndarray
        Increasing and concave in ``T``, ``0 < alpha < 2 atan D``.

    Raises
    ------
    ValueError
        If a parameter is not finite and positive, or ``A <= g`` (naming it, its value and the range).

    See Also
    --------
    beta : the other angle; zone ``n`` is ``alpha + n pi < w_e T < beta + n pi``.

    Notes
    -----
    Left-hand side of (3.10) and (3.12); section 4 of the paper.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.alpha(0.15, 100.0)
    np.float64(1.2532...)
    """
    x, _, D = _xD(T, A, l, g)
    return X.alpha_x(x, D)


@_v.shapes_named
def beta(T, A, l=1.0, g=G_EARTH):
    """The angle ``beta`` of Theorem 3.3: ``beta(T) = 2 atan(D coth(w_h T / 2))``.

    In the paper's form ``beta(T) = 2 atan(D (e^{w_h T} + 1) / (e^{w_h T} - 1))``.

    Parameters
    ----------
    T, A, l, g : array_like, broadcast together
        Each finite and > 0, with ``A > g``.

    Returns
    -------
    ndarray
        Decreasing and convex in ``T``, ``2 atan D < beta < pi``.

    Raises
    ------
    ValueError
        If a parameter is not finite and positive, or ``A <= g`` (naming it, its value and the range).

    See Also
    --------
    alpha : the other angle.

    Notes
    -----
    Left-hand side of (3.11) and (3.13); section 4 of the paper.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.beta(0.15, 100.0)
    np.float64(2.0687...)
    """
    x, _, D = _xD(T, A, l, g)
    return X.beta_x(x, D)


@_v.shapes_named
def boundary_periods(A, count, l=1.0, g=G_EARTH):
    """The first ``count`` boundary half-periods ``T_n`` and ``T~_n`` of Corollary 4.1.

    Parameters
    ----------
    A : array_like
        Acceleration amplitude, ``A > g``.
    count : int
        How many of each, ``>= 1``.
    l, g : float or array_like
        Rod length and gravity, > 0; broadcast with ``A``.

    Returns
    -------
    T, T_tilde : ndarray, shape ``A.shape + (count,)``
        ``T[..., j] = T_{j+1}`` (a 2T-periodic solution exists) and
        ``T_tilde[..., j] = T~_{j+1}`` (a 4T-periodic one), so that
        ``T_1 < T~_1 < T~_2 < T_2 < T_3 < T~_3 < ...``.

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``T_{n+1}`` and ``T~_{n+1}`` are the edges of zone ``n`` (``docs/theory.md``
    section 5): for even ``n`` the lower edge solves (3.10) and the upper (3.13),
    for odd ``n`` the lower solves (3.12) and the upper (3.11), with ``k = n // 2``.

    Examples
    --------
    >>> import kapitza
    >>> T, T_tilde = kapitza.boundary_periods(A=100.0, count=2)
    >>> T
    array([0.1091..., 0.5075...])
    >>> T_tilde
    array([0.2008..., 0.5055...])
    """
    A = _v.positive("A", A)
    l = _v.positive("l", l)
    g = _v.positive("g", g)
    _v.finite_rate(A, l, g)
    count = _v.bounded_count("count", count, MAX_COUNT, minimum=1)
    _check_A(A, g)
    A, l, g = np.broadcast_arrays(A, l, g)
    n = np.arange(count)
    mu = np.sqrt(g / A)[..., None]
    lo, hi = _edges_eps(mu, n, np.sqrt((A - g) / A)[..., None])  # A - g is exact as A -> g
    scale = _time_scale(l, A)[..., None]
    lo, hi = lo * scale, hi * scale
    even = n % 2 == 0
    return np.where(even, lo, hi), np.where(even, hi, lo)


@dataclass(frozen=True, repr=False)
class BoundaryPeriod(Summary):
    """One boundary half-period of Corollary 4.1, labelled by what produced it.

    Attributes
    ----------
    name : str
        ``"T_j"`` (2T-periodic) or ``"T~_j"`` (4T-periodic).
    index : int
        ``j`` in the name (``j = n + 1``).
    tilde : bool
        True for ``T~_j``.
    T : float
        The half-period [s].
    period : str
        ``"2T"`` or ``"4T"``: the period of the solution that exists there.
    equation : str
        ``"3.10"``, ``"3.11"``, ``"3.12"`` or ``"3.13"``.
    k : int
        The integer ``k >= 0`` of that equation.
    zone : int
        The stability zone ``n`` this period bounds.
    edge : str
        ``"lower"`` or ``"upper"`` edge of the zone.
    eps, mu : float
        Arnold's parameters of the point.

    Examples
    --------
    >>> import kapitza
    >>> b = kapitza.boundary_table(100.0, 1)[1]
    >>> b
    <BoundaryPeriod: T~_1 = 0.2008... s, 4T-periodic (eq. 3.13, k = 0), upper edge of zone 0>
    >>> b.name, b.period, b.equation, b.zone, b.edge
    ('T~_1', '4T', '3.13', 0, 'upper')
    """

    name: str
    index: int
    tilde: bool
    T: float
    period: str
    equation: str
    k: int
    zone: int
    edge: str
    eps: float
    mu: float

    def as_dict(self) -> dict:
        return dict(self.__dict__)

    def headline(self) -> str:
        return (f"{self.name} = {num(self.T, 10)} s, {self.period}-periodic (eq. {self.equation}, k = {self.k}), "
                f"{self.edge} edge of zone {self.zone}")

    def lines(self) -> list[tuple[str, str]]:
        return [("boundary", f"{self.name} = {num(self.T, 12)} s"),
                ("solution", f"{self.period}-periodic, equation ({self.equation}) with k = {self.k}"),
                ("edge", f"{self.edge} edge of zone {self.zone}"),
                ("Arnold", f"eps = {num(self.eps, 12)}, mu = {num(self.mu, 12)}")]


def _label(n: int, upper: bool):
    """(tilde, equation, k) for the lower/upper edge of zone n."""
    k = n // 2
    if n % 2 == 0:
        return (True, "3.13", k) if upper else (False, "3.10", k)
    return (False, "3.11", k) if upper else (True, "3.12", k)


@_v.shapes_named
def boundary_table(A, count, l=1.0, g=G_EARTH):
    """The boundary half-periods of Corollary 4.1 in increasing order, each labelled.

    ``T_1``, ..., ``T_count`` (2T-periodic motions) and ``T~_1``, ..., ``T~_count`` (4T-periodic),
    with the equation and ``k`` that produced each and the zone edge it is.

    Parameters
    ----------
    A : float
        Acceleration amplitude, ``A > g``.
    count : int
        Number of zones (each gives one ``T_j`` and one ``T~_j``), ``>= 1``.
    l, g : float
        Rod length and gravity, > 0.

    Returns
    -------
    list of BoundaryPeriod
        ``2 * count`` entries in the order of Corollary 4.1.

    Raises
    ------
    ValueError
        If ``A <= g``, a parameter is not finite and positive, or ``count`` is out of range.

    Examples
    --------
    >>> import kapitza
    >>> [(row.name, round(float(row.T), 6)) for row in kapitza.boundary_table(100.0, 2)]
    [('T_1', 0.1091), ('T~_1', 0.200866), ('T~_2', 0.505503), ('T_2', 0.507578)]
    """
    A = _v.one("A", _v.positive("A", A))
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    _v.finite_rate(A, l, g)
    count = _v.bounded_count("count", count, MAX_COUNT, minimum=1)
    _check_A(A, g)
    mu = np.sqrt(g / A)
    n = np.arange(count)
    lo, hi = _edges_eps(mu, n, np.sqrt((A - g) / A))  # A - g is exact as A -> g
    scale = np.sqrt(8.0 * l / A)
    rows = []
    for zn in range(count):
        for upper, e in ((False, lo[zn]), (True, hi[zn])):
            tilde, eq, k = _label(zn, upper)
            rows.append(
                BoundaryPeriod(
                    name=("T~_" if tilde else "T_") + str(zn + 1),
                    index=zn + 1,
                    tilde=tilde,
                    T=float(e * scale),
                    period="4T" if tilde else "2T",
                    equation=eq,
                    k=k,
                    zone=zn,
                    edge="upper" if upper else "lower",
                    eps=float(e),
                    mu=float(mu),
                )
            )
    return rows


@dataclass(frozen=True, repr=False)
class PeriodicSolution(Summary):
    """A 2T- or 4T-periodic solution of (2.3) at a boundary half-period.

    Attributes
    ----------
    boundary : BoundaryPeriod
        Where it lives.
    A, l, g : float
    phi0 : float
        Initial polar angle in the hyperbolic phase variables
        ``(x_h, y_h) = (theta, theta'/w_h)``: (3.19) for (3.10)/(3.12),
        (3.22) for (3.11)/(3.13).
    theta0, dtheta0 : float
        The initial state ``(cos phi0, w_h sin phi0)`` (unit radius).
    period : float
        ``2T`` or ``4T`` [s].
    sign : int
        +1 if ``theta(t + 2T) = theta(t)``, -1 if ``theta(t + 2T) = -theta(t)``.

    Examples
    --------
    >>> import kapitza
    >>> sol = kapitza.periodic_solution(A=100.0, index=1, tilde=True)
    >>> sol.period, sol.sign
    (0.8034..., -1)
    >>> theta, dtheta = sol.motion([0.0, sol.period / 2, sol.period])
    >>> theta
    array([ 0.6163..., -0.6163...,  0.6163...])
    """

    boundary: BoundaryPeriod
    A: float
    l: float
    g: float
    phi0: float
    theta0: float
    dtheta0: float
    period: float
    sign: int

    @property
    def T(self) -> float:
        return self.boundary.T

    def headline(self) -> str:
        return (f"{self.boundary.headline()}; A = {num(self.A)} m/s^2, from theta0 = {num(self.theta0, 8)} rad, "
                f"dtheta0 = {num(self.dtheta0, 8)} rad/s")

    def lines(self) -> list[tuple[str, str]]:
        back = "theta(t + 2T) = theta(t)" if self.sign > 0 else "theta(t + 2T) = -theta(t)"
        return self.boundary.lines() + [
            ("parameters", f"A = {num(self.A)} m/s^2, l = {num(self.l)} m, g = {num(self.g)} m/s^2"),
            ("start", f"phi0 = {num(self.phi0, 10)}: theta0 = {num(self.theta0, 10)} rad, "
                      f"dtheta0 = {num(self.dtheta0, 10)} rad/s"),
            ("period", f"{num(self.period, 10)} s ({back})")]

    def motion(self, t):
        """``(theta, theta')`` at the times ``t >= 0``; see :func:`kapitza.linear_motion`."""
        return linear_motion(t, self.theta0, self.dtheta0, self.T, self.A, self.l, self.g)


@_v.shapes_named
def periodic_solution(A, index, tilde=False, l=1.0, g=G_EARTH):
    """The periodic solution at ``T_index`` (2T-periodic) or ``T~_index`` (4T-periodic).

    Parameters
    ----------
    A : float
        Acceleration amplitude, ``A > g``.
    index : int
        ``j >= 1`` of ``T_j`` / ``T~_j``.
    tilde : bool, optional
        False for ``T_j``, True for ``T~_j``.
    l, g : float
        Rod length and gravity, > 0.

    Returns
    -------
    PeriodicSolution

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    Proofs of Theorems 3.3 and 3.4 (sufficiency): the solution starting at the
    angle ``phi0 = atan((1 - e^{w_h T}) / (1 + e^{w_h T}))`` (3.19) or
    ``phi0 = -atan((e^{w_h T} + 1) / (e^{w_h T} - 1))`` (3.22) is periodic.

    Examples
    --------
    >>> import kapitza
    >>> sol = kapitza.periodic_solution(A=100.0, index=1)
    >>> sol.boundary
    <BoundaryPeriod: T_1 = 0.1091... s, 2T-periodic (eq. 3.10, k = 0), lower edge of zone 0>
    >>> sol.period
    0.2182...
    """
    index = _v.bounded_count("index", index, MAX_COUNT, minimum=1)
    tilde = _v.flag("tilde", tilde)
    table = boundary_table(A, index, l, g)
    entry = next(b for b in table if b.index == index and b.tilde == bool(tilde))
    A, l, g = (_v.one(n, _v.positive(n, v)) for n, v in zip("Alg", (A, l, g)))
    with np.errstate(over="ignore", invalid="ignore"):
        x = np.sqrt((A + g) / l) * entry.T
    x = x if np.isfinite(x) else np.sqrt(A + g) / np.sqrt(l) * entry.T
    t = np.tanh(0.5 * x)
    if entry.equation in ("3.10", "3.12"):
        phi0 = -np.arctan(t)  # (3.19): atan((1 - e^x)/(1 + e^x)) = -atan(tanh(x/2))
    else:
        phi0 = -np.arctan2(1.0, t)  # (3.22): -atan((e^x + 1)/(e^x - 1)) = -atan(coth(x/2))
    with np.errstate(over="ignore"):  # (A + g)/l may overflow where w_h does not
        w_h = np.sqrt((A + g) / l)
    w_h = w_h if np.isfinite(w_h) else np.sqrt(A + g) / np.sqrt(l)
    return PeriodicSolution(
        boundary=entry,
        A=A,
        l=l,
        g=g,
        phi0=float(phi0),
        theta0=float(np.cos(phi0)),
        dtheta0=float(w_h * np.sin(phi0)),
        period=(4.0 if entry.tilde else 2.0) * entry.T,
        sign=-1 if entry.tilde else 1,
    )
