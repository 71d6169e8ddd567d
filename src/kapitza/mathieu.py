"""Mathieu's equation ``y'' + (a - 2 q cos 2z) y = 0``: characteristic values and the sine drive's zones.

The characteristic values ``a_n(q)`` (even solutions) and ``b_n(q)`` (odd) are eigenvalues of
four symmetric tridiagonal matrices (DLMF 28.4), bisected with the Sturm count of the infinite
matrix: no truncation is chosen and no eigensolver runs. ``scipy.special.mathieu_a/b`` are not
used: they are known to return wrong values and to jump branches (scipy issues 4479, 14526).
The sine drive (acceleration ``A sin(pi t/T)``) is Mathieu's equation with ``q = 16 eps^2/pi^2``
and ``a = -2 mu^2 q``; its zone ``n`` is ``a_n(q) < a < b_{n+1}(q)`` (``docs/mathieu.md``).
The engine behind these functions, and behind :class:`kapitza.SineWave`, is
``kapitza.drives._mathieu``.
"""
from __future__ import annotations

from . import _validate as _v
from .drives._mathieu import characteristic, sine_edges

__all__ = ["characteristic_a", "characteristic_b", "sine_zone_edges"]


@_v.shapes_named
def characteristic_a(n, q):
    """Mathieu characteristic value ``a_n(q)`` (even solutions), ``n >= 0``.

    Parameters
    ----------
    n : int or array_like of int
        Order, ``n >= 0``.
    q : array_like
        Finite; broadcasts with ``n``; ``|q|`` up to about 1e6.

    Returns
    -------
    ndarray
        ``a_n(q)`` to a few ulp of ``|a_n| + q`` (1e-17 absolute near 0).

    Raises
    ------
    ValueError
        If ``n`` is not an integer ``>= 0``, or ``q`` is not finite or beyond the bound.

    Notes
    -----
    DLMF 28.2, 28.4: eigenvalues of the symmetric tridiagonal matrices in the module notes, by
    Sturm bisection; ``docs/mathieu.md``.

    Examples
    --------
    >>> from kapitza.mathieu import characteristic_a
    >>> characteristic_a([0, 1, 2], 0.0)
    array([0., 1., 4.])
    >>> characteristic_a(0, 1.0)
    np.float64(-0.4551...)
    """
    n = _v.nonnegative_int("n", n)
    q = _v.finite("q", q)
    return _v.scalars(characteristic("a", n, q))


@_v.shapes_named
def characteristic_b(n, q):
    """Mathieu characteristic value ``b_n(q)`` (odd solutions), ``n >= 1``.

    Parameters
    ----------
    n : int or array_like of int
        Order, ``n >= 1``.
    q : array_like
        Finite; broadcasts with ``n``.

    Returns
    -------
    ndarray

    Raises
    ------
    ValueError
        If ``n`` is not an integer ``>= 1``, or ``q`` is not finite or beyond the bound.

    Examples
    --------
    >>> from kapitza.mathieu import characteristic_b
    >>> characteristic_b([1, 2], 0.0)
    array([1., 4.])
    >>> characteristic_b(1, 1.0)
    np.float64(-0.1102...)
    """
    n = _v.nonnegative_int("n", n, minimum=1)
    q = _v.finite("q", q)
    return _v.scalars(characteristic("b", n, q))


@_v.shapes_named
def sine_zone_edges(mu, n):
    """Edges ``eps_lo < eps_hi`` of zone ``n`` of the sine drive (acceleration ``A sin(pi t/T)``).

    Parameters
    ----------
    mu : array_like
        ``0 < mu < 1``.
    n : int or array_like of int
        Zone index ``>= 0``; broadcasts with ``mu``.

    Returns
    -------
    eps_lo, eps_hi : ndarray
        Zone ``n`` is ``a_n(q) < -2 mu^2 q < b_{n+1}(q)``, ``q = 16 eps^2 / pi^2``; the lower
        edge carries a 2T-periodic motion for even ``n`` (4T for odd), the upper the other.
        Each is the double on the unstable side of its crossing (``eps_lo`` the last double
        below it, ``eps_hi`` the first above), so zone ``n`` is ``eps_lo < eps < eps_hi``. A zone
        thinner than the spacing of doubles (large ``q``) has no double inside: then
        ``eps_lo == eps_hi`` or they are neighbours.

    Raises
    ------
    ValueError
        If ``mu`` is not in ``(0, 1)`` or ``n`` is not an integer ``>= 0``.

    Notes
    -----
    Each crossing of the ray with its characteristic value is bisected on doubles with the
    Sturm count of DLMF's tridiagonal matrix (module notes; ``docs/mathieu.md``), to within
    ``4e-15 + 4u / (1 - mu^2)`` relative (``u`` the unit roundoff: the root's own conditioning
    as ``mu -> 1``). Damped zones: :func:`kapitza.zone_edges` with ``drive=SineWave()`` and ``zeta``.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.mathieu import sine_zone_edges
    >>> sine_zone_edges(0.3, [0, 1])
    (array([0.4746..., 2.3934...]), array([0.8114..., 2.3972...]))
    >>> kapitza.zone_edges(0.3, 0, drive="sine")
    (np.float64(0.4746...), np.float64(0.8114...))
    """
    mu = _v.in_range("mu", mu, 0.0, 1.0)
    n = _v.nonnegative_int("n", n)
    return _v.scalars(*sine_edges(mu, n))
