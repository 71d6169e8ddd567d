"""The engine of :mod:`kapitza.normal_form` on trusted input: each phase's cubic jet in closed form, the
period map composed from them, and its Birkhoff normal form by the cheapest accurate path (the
composed jets, the averaged quartic potential, or extended precision). The mathematics is in that
module's notes and in ``docs/nonlinear.md``; the resonance charts and the measured rotation number
share it."""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from math import factorial

import numpy as np

from . import _validate as _v
from ._square import _floquet
from .parameters import phase_angles_trusted as _phase_angles

PI = np.pi


# ---------------------------------------------------------------- one phase, in closed form
# Every cubic coefficient of a phase is k times an entire function of k. Near k = 0 the closed
# forms subtract nearly equal numbers ((c - sh)/k loses 1e-16/|k|), so there the same functions
# are summed from their power series, built once here from exact rationals.
_NSER = 16  # |k| <= 1: the first omitted term is below 1/(32)! ~ 4e-36
_K_SERIES = 1.0


def _ser_c():
    return [Fraction(1, factorial(2 * n)) for n in range(_NSER)]


def _ser_sh():
    return [Fraction(1, factorial(2 * n + 1)) for n in range(_NSER)]


def _ser_mul(a, b):
    return [sum(a[i] * b[n - i] for i in range(n + 1)) for n in range(_NSER)]


def _ser_tables():
    c, sh = _ser_c(), _ser_sh()
    shc = _ser_mul(sh, c)
    sh3 = _ser_mul(_ser_mul(sh, sh), sh)
    f1 = [c[n + 1] - sh[n + 1] for n in range(_NSER - 1)] + [Fraction(0)]          # (c - sh)/k
    f2 = [-shc[n + 1] for n in range(_NSER - 1)] + [Fraction(0)]                    # (1 - sh c)/k
    num3 = [3 * f1[n] - sh3[n] for n in range(_NSER)]                                 # 3 f1 - sh^3 = O(k)
    f3 = [num3[n + 1] for n in range(_NSER - 1)] + [Fraction(0)]                      # (3 f1 - sh^3)/k
    return {name: np.array([float(v) for v in s[::-1]]) for name, s in
            (("c", c), ("sh", sh), ("f1", f1), ("f2", f2), ("f3", f3))}


SERIES = _ser_tables()


_SER_LISTS = {name: coef.tolist() for name, coef in SERIES.items()}


def _polyval(name, k):
    """``np.polyval(SERIES[name], k)``. A few points are summed in Python floats (the same
    multiply then add, so the same bits) to spare the 32 array calls per series at one point."""
    if k.size > 8:
        return np.polyval(SERIES[name], k)
    coef = _SER_LISTS[name]
    vals = []
    for x in k.ravel().tolist():
        y = 0.0
        for c in coef:
            y = y * x + c
        vals.append(y)
    return np.array(vals, dtype=float).reshape(k.shape)


def _entire(k):
    """``c, sh, f1, f2, f3`` of ``k`` (any sign): ``c = cosh sqrt k``, ``sh = sinh(sqrt k)/sqrt k``,
    ``f1 = (c - sh)/k``, ``f2 = (1 - sh c)/k``, ``f3 = (3 f1 - sh^3)/k``."""
    k = np.asarray(k, float)
    small = np.abs(k) <= _K_SERIES
    ks = np.where(small, k, 0.0)
    out = {name: _polyval(name, ks) for name in SERIES}
    if not small.all():
        kb = np.where(small, 2.0 * _K_SERIES, k)
        r = np.sqrt(np.abs(kb))
        pos = kb > 0
        c = np.where(pos, np.cosh(r), np.cos(r))
        sh = np.where(pos, np.sinh(r), np.sin(r)) / r
        f1 = (c - sh) / kb
        f2 = (1.0 - sh * c) / kb
        f3 = (3.0 * f1 - sh**3) / kb
        for name, val in (("c", c), ("sh", sh), ("f1", f1), ("f2", f2), ("f3", f3)):
            out[name] = np.where(small, out[name], val)
    return out["c"], out["sh"], out["f1"], out["f2"], out["f3"]


def _phase_cubic(k):
    """Linear part ``L`` (..., 2, 2) and cubic part ``C`` (..., 2, 4) of the unit-time flow of
    ``theta_ss = k sin(theta)``; ``C[..., i, j]`` multiplies ``q^(3-j) p^j`` in component ``i``.

    Notes
    -----
    Variation of parameters on ``th3'' - k th3 = -k th1^3/6`` (``docs/nonlinear.md`` section 2)::

        th3(1)  = -k sh (3 + sh c)/48 q^3 - k (f1 + sh^3)/16 q^2 p + k sh f2/16 q p^2 + k f3/48 p^3
        th3'(1) = -k (3c + 5 sh + 3 k sh^3)/48 q^3 - k sh (1 + 3 sh c)/16 q^2 p
                  + k (f1 - 3 sh^3)/16 q p^2 + k sh f2/16 p^3
    """
    k = np.asarray(k, float)
    return _cubic_of(k, *_entire(k))


def _cubic_of(k, c, sh, f1, f2, f3):
    """The jet of :func:`_phase_cubic` from ``k`` and its entire functions (float or mpf arrays)."""
    sh3 = sh**3
    L = np.stack([np.stack([c, sh], -1), np.stack([k * sh, c], -1)], -2)
    row_q = np.stack([-k * sh * (3 + sh * c) / 48, -k * (f1 + sh3) / 16, k * sh * f2 / 16, k * f3 / 48], -1)
    row_p = np.stack([-k * (3 * c + 5 * sh + 3 * k * sh3) / 48, -k * sh * (1 + 3 * sh * c) / 16,
                      k * (f1 - 3 * sh3) / 16, k * sh * f2 / 16], -1)
    return L, np.stack([row_q, row_p], -2)


def _entire_mp(k):
    """:func:`_entire` of one ``mpf`` ``k`` by the closed forms (at the working precision)."""
    import mpmath as mp

    r = mp.sqrt(abs(k))
    if k > 0:
        c, sh = mp.cosh(r), mp.sinh(r) / r
    else:
        c, sh = mp.cos(r), mp.sin(r) / r
    f1 = (c - sh) / k
    f2 = (1 - sh * c) / k
    return c, sh, f1, f2, (3 * f1 - sh**3) / k


# ---------------------------------------------------------------- cubic forms in two variables
def _mul(a, b):
    """Product of homogeneous forms in two variables, coefficients by power of the second one."""
    m, n = a.shape[-1], b.shape[-1]
    shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1]) + (m + n - 1,)
    out = np.zeros(shape, dtype=np.result_type(a, b))
    for i in range(m):
        out[..., i:i + n] += a[..., i:i + 1] * b
    return out


def _substitute(C, L):
    """The cubic ``v -> C(L v)``: ``C`` (..., r, 4) over ``q^(3-j) p^j``, ``L`` (..., 2, 2)."""
    lq, lp = L[..., 0, :], L[..., 1, :]
    qq = _mul(lq, lq)
    pp = _mul(lp, lp)
    mono = np.stack([_mul(qq, lq), _mul(qq, lp), _mul(lq, pp), _mul(pp, lp)], -2)  # (..., 4, 4)
    return np.einsum("...rj,...jm->...rm", C, mono)


def _compose(L1, C1, L2, C2):
    """Cubic jet of ``Phi2 o Phi1`` from the jets of the two maps."""
    return L2 @ L1, np.einsum("...ij,...jm->...im", L2, C1) + _substitute(C2, L1)


# ---------------------------------------------------------------- the period map
def _taylor(eps, mu):
    x, u, _ = _phase_angles(eps, mu)
    L1, C1 = _phase_cubic(x * x)
    L2, C2 = _phase_cubic(-u * u)
    return _compose(L1, C1, L2, C2)


# ---------------------------------------------------------------- the normal form
@dataclass(frozen=True)
class BirkhoffNormalForm:
    """The cubic map in the complex coordinate of the linear map's rotation (arrays).

    ``v = z e + conj(z e)``, ``e = (m12, lambda - m11)``; then
    ``z' = lambda z + c30 z^3 + c21 z^2 zbar + c12 z zbar^2 + c03 zbar^3 + O(|z|^5)``.

    Attributes
    ----------
    w : ndarray
        ``arccos(tr M / 2)`` in ``(0, pi)``: the linear rotation per period.
    rotation_number : ndarray
        ``w / (2 pi)``.
    coefficients : ndarray of complex, shape ``(..., 4)``
        ``c30, c21, c12, c03``.
    beta : ndarray
        ``Im(c21 / lambda)``: the twist in this coordinate.
    twist : ndarray
        ``tau = beta / (8 pi m12^2)``: the twist per ``r^2``, ``r = max |theta|``.
    resonant_4 : ndarray
        ``|c03| / (8 pi m12^2)``: the 1:4 resonant coefficient in the units of ``twist``.
    area_defect : ndarray
        ``|Re(c21 / lambda)| / |c21|``: zero for an area-preserving map; its size measures
        the rounding of the closed forms.
    m12 : ndarray
        ``M[0, 1]`` in the scaled variables (``r = 2 |z| |m12|``).

    Examples
    --------
    >>> import kapitza
    >>> bnf = kapitza.birkhoff_normal_form([0.5, 0.6], 0.3)
    >>> bnf.rotation_number
    array([0.1289..., 0.2320...])
    >>> bnf.twist
    array([-0.0677..., -0.1148...])
    >>> bnf.coefficients.shape, bool((bnf.area_defect < 1e-12).all())
    ((2, 4), True)
    """

    w: np.ndarray
    rotation_number: np.ndarray
    coefficients: np.ndarray
    beta: np.ndarray
    twist: np.ndarray
    resonant_4: np.ndarray
    area_defect: np.ndarray
    m12: np.ndarray

    def __post_init__(self):
        _v.scalar_fields(self)  # scalar in, numpy scalars out


def _w_of(theta, n):
    """``w`` in ``(0, pi)`` of the certified rotation angle ``theta`` in ``(n pi, (n+1) pi)``."""
    even = np.mod(n, 2) == 0
    return np.where(even, theta - n * PI, (n + 1) * PI - theta)


def _normal_coordinate(M, lam):
    """``(e1, e2, f)``: the eigenvector ``e = (m12, lambda - m11)`` of ``M`` and the row ``f``
    (..., 2) with ``z = f . v`` for ``v = z e + conj(z e)`` (float or mpf arrays)."""
    e1 = M[..., 0, 1] + 0j
    e2 = lam - M[..., 0, 0]
    # f . e = 1, f . ebar = 0
    det = np.asarray(e1 * np.conj(e2) - np.conj(e1) * e2)          # = -2 i m12 sin w
    return e1, e2, np.stack([np.conj(e2), -np.conj(e1)], -1) / det[..., None]


def _coefficients(M, C, lam):
    """``(c30, c21, c12, c03)`` of the cubic ``C`` in the coordinate ``z`` of ``v = z e + conj(z e)``,
    ``e = (m12, lambda - m11)`` (float or mpf arrays)."""
    e1, e2, f = _normal_coordinate(M, lam)
    Lz = np.stack([np.stack([e1, np.conj(e1)], -1), np.stack([e2, np.conj(e2)], -1)], -2)
    D = _substitute(C + 0j, Lz)                          # (..., 2, 4) over z^3, z^2 zbar, z zbar^2, zbar^3
    return np.einsum("...i,...ij->...j", f, D)


#: Above this rounding estimate (the area defect; the twist's relative error is found to be at
#: most about twice it), the normal form is recomputed in extended precision: the cubic terms of
#: the ``+A`` phase grow like ``e^{3x}`` while the map's own coefficients inside the thin zones
#: stay far smaller. Below it the twist is good to about 2e-9 relative.
_DEFECT_MP = 1e-9
#: Below this eps the normal form is computed in extended precision (see :func:`_normal_form`).
_EPS_TINY = 1e-3
#: The looser bound of pictures and of scans that only bracket sign changes.
_DEFECT_DRAW = 1e-4


def _normal_form_mp(eps, mu):
    """``(w, coefficients, m12)`` of one point in extended precision (same closed forms)."""
    import mpmath as mp

    e, m = mp.mpf(float(eps)), mp.mpf(float(mu))
    x = 2 * mp.sqrt(2) * e * mp.sqrt(1 + m * m)
    # the map is I + O(eps^2) and tr M / 2 = 1 - O(eps^4): 4 |log10 eps| digits cancel at small eps
    with mp.workdps(40 + int(2.5 * float(x)) + 4 * max(0, int(-mp.log10(e)))):
        e, m = mp.mpf(float(eps)), mp.mpf(float(mu))
        x = 2 * mp.sqrt(2) * e * mp.sqrt(1 + m * m)
        u = 2 * mp.sqrt(2) * e * mp.sqrt((1 - m) * (1 + m))
        k1, k2 = x * x, -u * u
        L1, C1 = _cubic_of(k1, *_entire_mp(k1))
        L2, C2 = _cubic_of(k2, *_entire_mp(k2))
        M, C = _compose(L1, C1, L2, C2)
        w = mp.acos((M[0, 0] + M[1, 1]) / 2)
        coef = _coefficients(M, C, mp.expj(w))
        return float(w), np.array([complex(c) for c in coef]), float(M[0, 1])


#: Gauss-Legendre rule on [0, 1] for the averages of the quartic potential over each phase; exact
#: to rounding for the integrands ``e^{+-4 x s}`` with ``x <= _X_AVERAGED``.
_GL_X, _GL_W2 = np.polynomial.legendre.leggauss(128)
_GL_S, _GL_W = (_GL_X + 1.0) / 2.0, _GL_W2 / 2.0
#: Up to this ``x = w_h T`` the averaged form keeps a relative error of about 1e-15 e^x <= 1e-9.
_X_AVERAGED = 13.0


def _coefficients_averaged(x, u, M, lam, sin_w):
    """``(c30, c21, c12, c03)`` from the quartic potential averaged along the linear motion.

    The Hamiltonian of ``theta_ss = k sin(theta)`` is ``p^2/2 - k q^2/2 + k q^4/24 + ...``; by
    variation of constants the cubic part of the period map is generated by
    ``int_0^2 k (z xi + conj(z xi))^4 / 24 ds``, ``xi`` the Floquet solution through
    ``(m12, lambda - m11)``, and ``dz/ds = i/(2 m12 sin w) dH/dzbar`` in this coordinate, so
    ``c_{j,3-j} = lambda i/(2 m12 sin w) binom(4, j)(4 - j)/24 int k xi^j xibar^(4-j) ds``
    (``docs/nonlinear.md`` section 3). No ``e^{3x}``-sized terms cancel here: the integrands are
    of the size of the answer, which is why this form serves the thin zones.
    """
    m11, m12 = M[..., 0, 0], M[..., 0, 1]
    xi0 = m12 + 0j
    d0 = lam - m11
    xs, us = x[..., None] * _GL_S, u[..., None] * _GL_S
    xi1 = xi0[..., None] * np.cosh(xs) + d0[..., None] * (np.sinh(xs) / x[..., None])
    a1 = xi0 * np.cosh(x) + d0 * np.sinh(x) / x
    b1 = xi0 * x * np.sinh(x) + d0 * np.cosh(x)
    xi2 = a1[..., None] * np.cos(us) + b1[..., None] * (np.sin(us) / u[..., None])
    c1, c2 = np.conj(xi1), np.conj(xi2)
    factor = lam * 1j / (2.0 * m12 * sin_w)
    out = []
    for j, weight in ((3, 4 / 24), (2, 12 / 24), (1, 12 / 24), (0, 4 / 24)):
        I = (x * x) * np.sum(_GL_W * xi1**j * c1 ** (4 - j), -1) - (u * u) * np.sum(_GL_W * xi2**j * c2 ** (4 - j), -1)
        out.append(factor * weight * I)
    return np.stack(out, -1)


def _normal_form(eps, mu, defect_max=_DEFECT_MP):
    """The normal form by the cheapest path that is accurate: the composed closed-form jets, or
    where their rounding estimate is too large the averaged quartic potential (``x <= 13``),
    or beyond that the closed forms again in extended precision."""
    M, C = _taylor(eps, mu)
    _, _, theta, stable, n = _floquet(eps, mu)
    w = _w_of(theta, n)
    lam = np.exp(1j * w)
    m12 = M[..., 0, 1]
    # At tiny eps with a subnormal mu, m12 sin w underflows to 0 in doubles: those points are
    # redone in extended precision below (eps < _EPS_TINY), so the double pass may divide by 0.
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        coef = _coefficients(M, C, lam)
    r21 = coef[..., 1] / lam
    with np.errstate(invalid="ignore", divide="ignore"):
        defect = np.abs(r21.real) / np.where(np.abs(r21) > 0, np.abs(r21), 1.0)
    # At small eps the monodromy is I + O(eps^2) and its linear data cancel in double precision
    # (the twist was 4e-9 off at eps = 1e-4, of the wrong sign by 1e-12): extended precision there.
    tiny = stable & (eps < _EPS_TINY)
    redo = stable & ((defect > defect_max) | tiny)
    if np.any(redo):
        x, u, _ = _phase_angles(eps, mu)
        avg = redo & (x <= _X_AVERAGED) & ~tiny
        if np.any(avg):
            coef = np.array(coef)
            coef[avg] = _coefficients_averaged(x[avg], u[avg], M[avg], lam[avg], np.sin(w[avg]))
        w, coef, m12 = np.array(w, float), np.array(coef), np.array(m12, float)
        for i in np.ndindex(redo.shape):
            if redo[i] and not avg[i]:
                w[i], coef[i], m12[i] = _normal_form_mp(eps[i], mu[i])
        lam = np.exp(1j * w)
        r21 = coef[..., 1] / lam
        defect = np.where(redo, 0.0, defect)
    beta = r21.imag
    scale = 8.0 * PI * m12 * m12
    return BirkhoffNormalForm(w=w, rotation_number=w / (2.0 * PI), coefficients=coef, beta=beta,
                              twist=beta / scale, resonant_4=np.abs(coef[..., 3]) / scale,
                              area_defect=defect, m12=m12), stable


def _stable_arnold(eps, mu):
    """Validated ``(eps, mu)``, broadcast, every point linearly stable (square wave, undamped)."""
    eps, mu = _v.arnold(eps, mu)
    eps, mu = np.broadcast_arrays(eps, mu)
    _, _, _, stable, _ = _floquet(eps, mu)
    _v.linearly_stable(eps, mu, stable)
    return eps, mu
