"""Nonlinear stability of the upright: the period map to third order and its Birkhoff normal form.

The linear zones (``docs/theory.md`` section 5) say when the upright is an *elliptic* fixed
point of the stroboscopic map of the full equation ``theta'' = (g + a(t))/l sin(theta)``;
whether it is *Lyapunov stable* is decided by the nonlinear terms. This module computes, in
closed form and vectorised over ``(eps, mu)``, everything ``docs/nonlinear.md`` derives:

1. **The cubic Taylor map of one period.** Time is measured in half-periods, ``s = t/T``; the
   state is ``v = (q, p) = (theta, dtheta/ds) = (theta, T theta')``. Each phase of the square wave
   (2.2) is then ``theta_ss = k sin(theta)`` for a unit time, with ``k = x^2`` (``x = w_h T``,
   the ``+A`` phase, first) and ``k = -u^2`` (``u = w_e T``, the ``-A`` phase), so only
   ``(eps, mu)`` remain (``docs/theory.md`` section 2). Expanding ``theta = th1 + th3 + ...``
   in the size of the start, ``th1'' = k th1`` and ``th3'' = k th3 - k th1^3 / 6`` with
   ``th3(0) = th3'(0) = 0``; variation of parameters gives ``th3(1)``, ``th3'(1)`` as cubic forms
   in ``(q, p)`` whose coefficients are polynomials in ``c = cosh sqrt(k)`` (``cos u``),
   ``sh = sinh(sqrt k)/sqrt k`` (``sin u / u``) and ``k`` (:func:`_phase_cubic`). The two phases
   compose as ``P(v) = L2 L1 v + L2 C1(v) + C2(L1 v) + O(|v|^5)``; the map is odd, so there
   are no even orders.
2. **The Birkhoff normal form.** With ``M = L2 L1``, ``cos w = tr M / 2``, ``w`` in ``(0, pi)``,
   ``lambda = e^{i w}``, its eigenvector ``e = (m12, lambda - m11)`` and ``v = z e + conj(z e)``,
   the map reads ``z' = lambda z + c30 z^3 + c21 z^2 zbar + c12 z zbar^2 + c03 zbar^3 + O(5)``.
   Only ``z^2 zbar`` (always) and ``zbar^3`` (at ``lambda^4 = 1``, ``tr M = 0``) are resonant at
   degree 3; the twist is ``beta = Im(c21 / lambda)`` (area preservation makes ``Re`` vanish).
3. **The twist coefficient** ``tau = beta / (8 pi m12^2)``: the invariant curve through
   ``max|theta| = r`` turns ``rho(r) = w/(2 pi) + tau r^2 + O(r^4)`` per period, in the direction
   the linear map turns (``r = 2 |z| |m12|`` on the invariant ellipse).
4. **The verdict**: Moser's twist theorem off 1:4 (1:3 included: oddness removes the ``zbar^2``
   term), Markeev's criterion on 1:4 (``|beta|`` against ``|c03|``), undecided where ``beta = 0``.

In the thin zones the composed jets round badly (the ``+A`` phase's cubic terms grow like
``e^{3x}``); there the same coefficients come from the quartic potential averaged along the
Floquet solution (:func:`_coefficients_averaged`, ``x <= 13``) and beyond that from the closed
forms in extended precision (:func:`_normal_form_mp`). The three paths are tested as twins.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as _v
from ._normal_form import PI, SERIES as SERIES, BirkhoffNormalForm, _normal_form, _stable_arnold, _taylor, _w_of
from ._square import _floquet

__all__ = [
    "TaylorMap",
    "period_map_taylor",
    "BirkhoffNormalForm",
    "birkhoff_normal_form",
    "twist_coefficient",
    "averaged_twist",
    "NonlinearVerdict",
    "nonlinear_stability",
]


# ---------------------------------------------------------------- the period map
@dataclass(frozen=True)
class TaylorMap:
    """Third-order Taylor expansion of the period map at the upright (arrays of the shape of ``(eps, mu)``).

    In the scaled variables ``v = (q, p) = (theta, T theta')`` at ``t = 0 mod 2T``::

        P(v) = M v + C(v) + O(|v|^5),   C_i(v) = sum_j cubic[..., i, j] q^(3-j) p^j.

    Attributes
    ----------
    linear : ndarray, shape ``(..., 2, 2)``
        The monodromy ``M = E H`` in the scaled variables.
    cubic : ndarray, shape ``(..., 2, 4)``
        Coefficients of ``q^3, q^2 p, q p^2, p^3`` in each component.

    Examples
    --------
    >>> import kapitza
    >>> P = kapitza.period_map_taylor(0.5, 0.3)
    >>> P.linear
    array([[ 2.7213...,  1.9742...],
           [-2.3572..., -1.3426...]])
    >>> P.cubic.shape
    (2, 4)
    """

    linear: np.ndarray
    cubic: np.ndarray

    def __post_init__(self):
        _v.scalar_fields(self)  # scalar in, numpy scalars out

    def __call__(self, q, p):
        """``M v + C(v)`` at ``v = (q, p)`` (arrays broadcast against the map's shape)."""
        q, p = np.asarray(q, float), np.asarray(p, float)
        mono = np.stack([q**3, q * q * p, q * p * p, p**3], -1)
        M, C = self.linear, self.cubic
        return (M[..., 0, 0] * q + M[..., 0, 1] * p + np.sum(C[..., 0, :] * mono, -1),
                M[..., 1, 0] * q + M[..., 1, 1] * p + np.sum(C[..., 1, :] * mono, -1))


@_v.shapes_named
def period_map_taylor(eps, mu):
    """The period map of the full equation to third order at the upright, in closed form.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        Arnold's parameters, ``eps > 0`` and ``0 < mu < 1`` (``A > g``).

    Returns
    -------
    TaylorMap

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``docs/nonlinear.md`` sections 1-2: the ``+A`` phase (``k = x^2``) then the ``-A`` phase
    (``k = -u^2``), each of unit length in ``s = t/T``; the linear part is ``docs/theory.md``
    section 3's ``M`` with ``theta'`` scaled by ``T``.

    Examples
    --------
    >>> import kapitza
    >>> P = kapitza.period_map_taylor(0.5, 0.3)
    >>> P.linear.shape
    (2, 2)
    """
    eps = _v.positive("eps", eps)
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    eps, mu = np.broadcast_arrays(eps, mu)
    # The cubic terms grow like exp(3 w_h T): beyond w_h T = 200 they leave a double.
    with np.errstate(over="ignore"):  # eps = 1e308: x = inf, refused below
        x = 2.0 * np.sqrt(2.0) * eps * np.sqrt(1.0 + mu * mu)
    if np.any(x > 200.0):
        bad = x > 200.0
        raise _v.KapitzaValueError(
            f"eps must keep w_h T = 2 sqrt(2) eps sqrt(1 + mu^2) <= 200 (the cubic terms grow like "
            f"exp(3 w_h T)); got eps = {float(eps[bad].flat[0])!r} with mu = {float(mu[bad].flat[0])!r}")
    M, C = _taylor(eps, mu)
    return TaylorMap(linear=M, cubic=C)


# ---------------------------------------------------------------- the normal form


@_v.shapes_named
def birkhoff_normal_form(eps, mu):
    """The Birkhoff normal form of the period map at the upright, to third order.

    Takes and validates ``eps, mu`` as :func:`twist_coefficient` does; returns a
    :class:`BirkhoffNormalForm` of their broadcast shape.

    Parameters
    ----------
    eps, mu : array_like
        Arnold's parameters, broadcast together; each point inside a stability zone of the
        square wave (``0 < mu < 1``).

    Returns
    -------
    BirkhoffNormalForm

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``docs/nonlinear.md`` section 3. The resonant coefficients are invariant under the
    near-identity changes that remove the others, so they are read off directly.

    Examples
    --------
    >>> import kapitza
    >>> bnf = kapitza.birkhoff_normal_form(0.5, 0.3)
    >>> (bnf.rotation_number, bnf.twist)
    (np.float64(0.1289...), np.float64(-0.0677...))
    """
    eps, mu = _stable_arnold(eps, mu)
    return _normal_form(eps, mu)[0]


@_v.shapes_named
def twist_coefficient(eps, mu):
    """The twist ``tau``: ``rho(r) = w/(2 pi) + tau r^2 + O(r^4)``.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        Arnold's parameters of linearly stable points (inside a zone, ``0 < mu < 1``).

    Returns
    -------
    tau : ndarray
        On the section ``t = 0 mod 2T`` (the start of the ``+A`` phase), in the variables
        ``(theta, theta')``, the invariant curve of the nonlinear period map whose largest
        ``|theta|`` is ``r`` turns ``rho(r) = w/(2 pi) + tau r^2 + O(r^4)`` times per period,
        ``cos w = tr M / 2``, ``w`` in ``(0, pi)``, both counted in the direction in which the
        linear map turns. ``tau < 0``: the rotation slows with amplitude.

    Raises
    ------
    ValueError
        Naming ``eps`` (and ``mu``) where a point is not linearly stable.

    Notes
    -----
    ``docs/nonlinear.md`` section 3: ``tau = Im(c21 / lambda) / (8 pi m12^2)``, closed forms
    throughout (no ODE solve).

    Examples
    --------
    >>> import kapitza
    >>> kapitza.twist_coefficient(0.5, 0.3)
    np.float64(-0.0677...)
    """
    eps, mu = _stable_arnold(eps, mu)
    return _normal_form(eps, mu)[0].twist


# ---------------------------------------------------------------- the Kapitza limit
@_v.shapes_named
def averaged_twist(eps, mu):
    """The twist predicted by Kapitza's averaged (effective) potential, valid as ``eps -> 0``.

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        ``eps > sqrt(3/2) mu`` (the averaged upright is stable), both > 0.

    Returns
    -------
    ndarray
        ``3 T c4 / (2 pi Omega)`` with, in units of ``T``, ``(Omega T)^2 = 16 eps^4/3 - 8 eps^2 mu^2``
        and ``c4 T^2 = eps^2 mu^2 / 3 - 8 eps^4 / 9`` (always < 0: a soft well).

    Raises
    ------
    ValueError
        If an argument is outside its allowed range: a :class:`kapitza.KapitzaValueError` naming
        the argument, its value and the range.

    Notes
    -----
    ``docs/nonlinear.md`` section 5. The effective potential is
    ``U = (g/l) cos(theta) + <v^2>/(2 l^2) sin^2(theta)``, ``<v^2> = A^2 T^2/12`` for the
    square wave; ``U = Omega^2 theta^2 / 2 + c4 theta^4 + ...`` and a Duffing oscillation of
    amplitude ``r`` has frequency ``Omega + 3 c4 r^2 / (2 Omega)``; a period ``2T`` turns it
    by ``2 T Omega(r)``.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.averaged_twist(0.5, 0.3)
    np.float64(-0.0585...)
    """
    eps = _v.positive("eps", eps)
    mu = _v.positive("mu", mu)
    eps, mu = _v.broadcast(eps=eps, mu=mu)
    # In units of eps^2: (Omega T)^2 = eps^4 (16/3 - 8 m), c4 T^2 = eps^4 (m/3 - 8/9), m = (mu/eps)^2,
    # so the twist is 3 eps^2 (m/3 - 8/9) / (2 pi sqrt(16/3 - 8 m)) with no eps^4 to overflow.
    with np.errstate(under="ignore", over="ignore"):
        m = (mu / eps) ** 2
    bad = ~(m < 2.0 / 3.0)
    if bad.any():
        raise _v.KapitzaValueError(
            f"eps must exceed the averaging threshold sqrt(3/2) mu; got eps = {float(eps[bad].flat[0])!r}")
    with np.errstate(over="ignore"):
        tau = 3.0 * (eps * eps) * (m / 3.0 - 8.0 / 9.0) / (2.0 * PI * np.sqrt(16.0 / 3.0 - 8.0 * m))
    big = ~np.isfinite(tau)
    if big.any():
        raise _v.KapitzaValueError(
            f"eps must be below about 1e154 (the twist, about -0.5 eps^2, must be a double); got eps = "
            f"{float(eps[big].flat[0])!r}")
    return _v.scalars(tau)


# ---------------------------------------------------------------- the verdict
#: Verdict kinds, in the order of the codes of :attr:`NonlinearVerdict.code`.
KINDS = ("moser", "moser 1:3", "markeev stable", "markeev unstable", "undecided")


def sentence(kind, rho, tr, tau, c4) -> str:
    """The verdict of one point in words, with its numbers (``kind`` one of :data:`KINDS`)."""
    nums = f"rho_0 = {rho:.10g}, tr M = {tr:.10g}, twist tau = {tau:.10g} per rad^2"
    if kind == "moser":
        return f"Lyapunov stable (Moser's twist theorem: twist != 0, not at 1:4); {nums}"
    if kind == "moser 1:3":
        return (f"Lyapunov stable (Moser's twist theorem at 1:3: the odd map has no zbar^2 term, "
                f"twist != 0); {nums}")
    if kind == "markeev stable":
        return f"Lyapunov stable at 1:4 (Markeev: |tau| > |c4| = {c4:.10g}); {nums}"
    if kind == "markeev unstable":
        return f"unstable at 1:4 (Markeev: |tau| < |c4| = {c4:.10g}); {nums}"
    if kind == "linearly unstable":
        return f"not linearly stable (outside the zones or on an edge): tr M = {tr:.10g}"
    return f"undecided at this order (twist tau = 0, or |tau| = |c4| at 1:4); {nums}, |c4| = {c4:.10g}"


@dataclass(frozen=True)
class NonlinearVerdict:
    """Nonlinear (Lyapunov) stability of the upright, with the numbers behind it (arrays).

    Attributes
    ----------
    eps, mu : ndarray
    stable : ndarray of bool
        Lyapunov stable by the theorem named in ``kind``.
    unstable : ndarray of bool
        Unstable by Markeev's criterion at 1:4, or linearly unstable (a multiplier outside the
        unit circle); neither flag: undecided at this order.
    kind : ndarray of str
        ``"moser"`` (twist != 0, ``w`` off 1:4), ``"moser 1:3"`` (on ``tr M = -1``: oddness
        removes the resonant ``zbar^2``, the twist decides), ``"markeev stable"`` /
        ``"markeev unstable"`` (on ``tr M = 0``: ``|tau|`` against ``|c4|``), ``"undecided"``
        (twist zero, or ``|tau| = |c4|`` at 1:4), or ``"linearly unstable"`` outside the zones
        (there the other numbers are NaN).
    rotation_number : ndarray
        ``w / (2 pi)`` in ``(0, 1/2)``.
    trace : ndarray
        ``tr M = 2 cos w``.
    twist : ndarray
        ``tau`` of :func:`twist_coefficient`.
    resonant_4 : ndarray
        ``|c4|``: the ``zbar^3`` coefficient in the units of ``tau`` (it decides only at 1:4).

    Examples
    --------
    >>> import kapitza
    >>> v = kapitza.nonlinear_stability([0.5, 1.0], 0.3)
    >>> v.kind
    array(['moser', 'linearly unstable'], dtype='<U17')
    >>> v.stable, v.unstable
    (array([ True, False]), array([False,  True]))
    >>> v.twist
    array([-0.0677...,         nan])
    """

    eps: np.ndarray
    mu: np.ndarray
    stable: np.ndarray
    unstable: np.ndarray
    kind: np.ndarray
    rotation_number: np.ndarray
    trace: np.ndarray
    twist: np.ndarray
    resonant_4: np.ndarray

    def __post_init__(self):
        _v.scalar_fields(self)  # scalar in, numpy scalars out

    def sentences(self) -> list[str]:
        """One sentence per point (flattened order): the verdict, the theorem and its numbers."""
        out = []
        for e, m, k, rho, tr, tau, c4 in zip(*(np.ravel(a) for a in (
                self.eps, self.mu, self.kind, self.rotation_number, self.trace, self.twist, self.resonant_4))):
            s = sentence(k, rho, tr, tau, c4)
            out.append(f"eps = {e:.10g}, mu = {m:.10g}: {s}" if np.size(self.eps) > 1 else s)
        return out

    def __str__(self) -> str:
        return "\n".join(self.sentences())


def _elementwise(eps, mu, st, tau, growth, tol):
    """:func:`nonlinear_stability` of arrays with some points outside the zones: the stable ones
    answered as usual, the others ``"linearly unstable"`` (``unstable`` where the growth is > 0)."""
    nan = np.full(eps.shape, np.nan)
    out = dict(stable=np.zeros(eps.shape, bool), unstable=growth > 0,
               kind=np.full(eps.shape, "linearly unstable", dtype=object), rotation_number=nan.copy(),
               trace=2.0 * tau, twist=nan.copy(), resonant_4=nan.copy())
    if st.any():
        sub = nonlinear_stability(eps[st], mu[st], tol=tol)
        for k in out:
            out[k][st] = getattr(sub, k)
    out["kind"] = out["kind"].astype(str)
    return NonlinearVerdict(eps=eps, mu=mu, **out)


def _on_curve(eps, mu, w, target, tol):
    """Whether ``w = target`` is crossed within ``tol * eps`` of ``eps`` (or met to 1e-14)."""
    h = np.maximum(tol, 4.0 * np.finfo(float).eps) * eps
    _, _, th_m, st_m, n_m = _floquet(eps - h, mu)
    _, _, th_p, st_p, n_p = _floquet(eps + h, mu)
    d_m = np.where(st_m, _w_of(th_m, n_m) - target, np.nan)
    d_p = np.where(st_p, _w_of(th_p, n_p) - target, np.nan)
    with np.errstate(invalid="ignore"):
        crossed = (d_m * d_p) <= 0.0
    return crossed | (np.abs(w - target) <= 1e-14)


def _verdict_kinds(w, beta, coef, tol, on4=None, on3=None):
    scale = np.sum(np.abs(coef), -1)
    c03 = np.abs(coef[..., 3])
    zero_twist = np.abs(beta) <= 1e-12 * scale
    on4 = np.abs(w - 0.5 * PI) <= tol if on4 is None else on4
    on3 = np.abs(w - 2.0 * PI / 3.0) <= tol if on3 is None else on3
    tie = on4 & (np.abs(np.abs(beta) - c03) <= 1e-12 * scale)
    code = np.where(on3, 1, 0)
    code = np.where(on4, np.where(np.abs(beta) > c03, 2, 3), code)
    code = np.where(zero_twist | tie, 4, code)
    return code


def sentence_of(eps, mu, tol=1e-15):
    """``str(nonlinear_stability(eps, mu))`` of one trusted, linearly stable point: the same
    kernels on the same numbers, without the validation, and with the two sides of the 1:4 and
    1:3 tests computed once for both (:func:`kapitza.analyze`, where the scalar twin declines)."""
    eps, mu = np.asarray(eps, float), np.asarray(mu, float)
    nf, _ = _normal_form(eps, mu)
    h = np.maximum(tol, 4.0 * np.finfo(float).eps) * eps
    sides = [_floquet(eps - h, mu), _floquet(eps + h, mu)]
    on = []
    for target in (0.5 * PI, 2.0 * PI / 3.0):  # as _on_curve
        d_m, d_p = (np.where(f[3], _w_of(f[2], f[4]) - target, np.nan) for f in sides)
        with np.errstate(invalid="ignore"):
            crossed = (d_m * d_p) <= 0.0
        on.append(crossed | (np.abs(nf.w - target) <= 1e-14))
    code = _verdict_kinds(nf.w, nf.beta, nf.coefficients, tol, on[0], on[1])
    return sentence(KINDS[int(code)], nf.rotation_number, 2.0 * np.cos(nf.w), nf.twist, nf.resonant_4)


@_v.shapes_named
def nonlinear_stability(eps, mu, *, tol=1e-15):
    """Lyapunov stability of the upright of the full equation (square wave, undamped).

    Parameters
    ----------
    eps, mu : array_like, broadcast together
        Arnold's parameters of linearly stable points.
    tol : float, optional
        A point is taken to lie on the 1:4 (1:3) curve where ``w = pi/2`` (``2 pi/3``) is crossed
        within a relative distance ``tol`` in ``eps`` (at least 4 ulps: the resolution of a
        double ``eps``, which in the thin zones moves ``w`` by far more than an ulp); the twist
        is taken to vanish where ``|beta|`` is below ``1e-12`` times the sum of the cubic
        coefficients' sizes (a rounding bound of the closed forms).

    Returns
    -------
    NonlinearVerdict

    Raises
    ------
    ValueError
        Where a single point is not linearly stable (``docs/theory.md`` section 5). Arrays are
        answered element-wise: a point outside the zones (or on an edge) gets the kind
        ``"linearly unstable"``, ``unstable`` where a multiplier lies outside the unit circle
        (Lyapunov's theorem on instability by the first approximation), and NaN numbers.

    Notes
    -----
    ``docs/nonlinear.md`` section 4. Off 1:4 the normal form is ``z -> lambda z e^{i beta |z|^2}
    + O(|z|^5)`` (the map is odd, so at 1:3 no ``zbar^2`` term stops the reduction), and
    Moser's twist theorem (Moser 1962) gives stability when ``beta != 0``. On 1:4 the term
    ``c03 zbar^3`` is resonant: stable if ``|beta| > |c03|``, unstable if ``|beta| < |c03|``
    (Markeev 1978; Bardin & Markeev 1995). Points exactly on a curve have measure zero; near
    1:4 the stable region around the upright shrinks with the distance to it.

    Examples
    --------
    >>> import kapitza
    >>> verdict = kapitza.nonlinear_stability(0.5, 0.3)
    >>> verdict.stable
    np.True_
    """
    tol = _v.one("tol", _v.in_range("tol", tol, 0.0, 1.0, lo_open=False))
    e, m = np.broadcast_arrays(*_v.arnold(eps, mu))
    if e.ndim > 0:
        tau, growth, _, st, _ = _floquet(e, m)
        st = np.asarray(st, bool)
        if not st.all():
            return _elementwise(e, m, st, np.asarray(tau, float), np.asarray(growth, float), tol)
    eps, mu = _stable_arnold(eps, mu)
    nf, _ = _normal_form(eps, mu)
    on4 = _on_curve(eps, mu, nf.w, 0.5 * PI, tol)
    on3 = _on_curve(eps, mu, nf.w, 2.0 * PI / 3.0, tol)
    code = _verdict_kinds(nf.w, nf.beta, nf.coefficients, tol, on4, on3)
    return NonlinearVerdict(eps=eps, mu=mu, stable=np.isin(code, (0, 1, 2)), unstable=code == 3,
                            kind=np.asarray(KINDS)[code], rotation_number=nf.rotation_number,
                            trace=2.0 * np.cos(nf.w), twist=nf.twist, resonant_4=nf.resonant_4)
