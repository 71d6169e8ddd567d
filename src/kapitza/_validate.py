"""Validation of user input, done once at the public boundary.

Every public function converts its arguments here; private kernels trust what
they receive. Messages name the parameter, the offending value and the allowed
range, e.g. ``eps must be finite and > 0; got -1.0``.
"""
from __future__ import annotations

import numpy as np

__all__ = ["positive", "finite", "nonnegative_int", "in_range", "arnold", "parameter_set", "physical_parameters",
           "linearly_stable", "KapitzaValueError"]


class KapitzaValueError(ValueError):
    """A parameter is outside its allowed range (a :class:`ValueError`)."""


def _first_bad(arr: np.ndarray, bad: np.ndarray) -> str:
    value = arr[bad].flat[0]
    value = value.item() if hasattr(value, "item") else value
    where = "" if arr.ndim == 0 else f" (at index {tuple(int(i) for i in np.argwhere(bad)[0])})"
    return f"{value!r}{where}"


def _short(value) -> str:
    """``repr(value)``, cut to a readable length."""
    text = repr(value)
    return text if len(text) <= 80 else text[:60] + f"... ({len(text)} characters)"


def _as_float(name: str, value) -> np.ndarray:
    what = f"{name} must be a real number or array of real numbers"
    # Nothing is converted silently: text, truth values, complex numbers and masked entries
    # are refused rather than read as numbers (or cut to their real part).
    if isinstance(value, (str, bytes)):
        raise KapitzaValueError(f"{what}; got the text {value!r}")
    if isinstance(value, np.ma.MaskedArray) and np.ma.is_masked(value):
        raise KapitzaValueError(f"{what}; got a masked array with masked entries")
    raw = np.asarray(value)
    if raw.dtype.kind == "b":
        raise KapitzaValueError(f"{what}; got a truth value {_short(value)}")
    if raw.dtype.kind == "c":
        raise KapitzaValueError(f"{what}; got a complex value {_short(value)}")
    if raw.dtype.kind in "USO" and any(isinstance(v, (str, bytes, bool, complex, np.bool_, np.complexfloating))
                                       for v in raw.ravel().tolist()[:10000]):
        raise KapitzaValueError(f"{what}; got {_short(value)}")
    try:
        arr = np.asarray(raw, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise KapitzaValueError(f"{what}; got {_short(value)}") from None
    if arr.size == 0:
        raise KapitzaValueError(f"{name} must not be empty")
    return arr


def finite(name: str, value) -> np.ndarray:
    """Return ``value`` as a float array, rejecting NaN and infinities."""
    arr = _as_float(name, value)
    bad = ~np.isfinite(arr)
    if bad.any():
        raise KapitzaValueError(f"{name} must be finite; got {_first_bad(arr, bad)}")
    return arr


def positive(name: str, value) -> np.ndarray:
    """Return ``value`` as a float array; every element must satisfy 0 < value < inf."""
    arr = _as_float(name, value)
    if arr.min() > 0 and arr.max() < np.inf:  # NaN fails both: two passes, no temporaries
        return arr
    bad = ~(np.isfinite(arr) & (arr > 0))
    if bad.any():
        raise KapitzaValueError(f"{name} must be finite and > 0 (0 < {name} < inf); got {_first_bad(arr, bad)}")
    return arr


def in_range(name: str, value, lo: float, hi: float, *, lo_open=True, hi_open=True) -> np.ndarray:
    """Return ``value`` as a float array inside the interval (lo, hi) (ends open or closed)."""
    arr = _as_float(name, value)
    ok = np.isfinite(arr)
    ok &= (arr > lo) if lo_open else (arr >= lo)
    ok &= (arr < hi) if hi_open else (arr <= hi)
    if not ok.all():
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise KapitzaValueError(f"{name} must lie in {left}{lo:g}, {hi:g}{right}; got {_first_bad(arr, ~ok)}")
    return arr


def nonnegative_int(name: str, value, *, minimum: int = 0) -> np.ndarray:
    """Return ``value`` as an int array of integers >= ``minimum``."""
    arr = np.asarray(value)
    if arr.size == 0:
        raise KapitzaValueError(f"{name} must not be empty")
    if isinstance(value, (str, bytes)) or arr.dtype.kind in "bcUS":
        raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_short(value)}")
    if arr.dtype.kind not in "iu":
        try:
            f = np.asarray(arr, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_short(value)}") from None
        bad = ~(np.isfinite(f) & (f == np.round(f)))
        if bad.any():
            raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_first_bad(f, bad)}")
        arr = f.astype(np.int64)
    arr = arr.astype(np.int64)
    bad = arr < minimum
    if bad.any():
        raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_first_bad(arr, bad)}")
    return arr


def arnold(eps, mu):
    """Arnold's ``(eps, mu)`` as float arrays, each finite and > 0 (``mu >= 1`` allowed)."""
    return positive("eps", eps), positive("mu", mu)


def parameter_set(eps, mu, T, A) -> str:
    """Which parameter set was given: ``"arnold"`` for ``(eps, mu)`` or ``"physical"`` for ``(T, A)``.

    Exactly one of the two pairs, whole, must be given (the others ``None``); otherwise the
    message says what to give.
    """
    arnold = eps is not None or mu is not None
    physical = T is not None or A is not None
    if arnold == physical:
        raise KapitzaValueError("give either eps and mu, or T and A (with l and g), not both or neither")
    if arnold and (eps is None or mu is None):
        raise KapitzaValueError("eps and mu must be given together")
    if physical and (T is None or A is None):
        raise KapitzaValueError("T and A must be given together")
    return "arnold" if arnold else "physical"


def physical_parameters(T, A, l, g, eps=None, mu=None):
    """``(T, A, l, g)`` as float arrays, each finite and > 0, from ``(T, A)`` or from Arnold's
    ``(eps, mu)`` with ``l`` and ``g``: ``A = g / mu^2``, ``T = eps sqrt(8 l / A)``
    (``docs/theory.md`` section 2; :func:`kapitza.to_physical`)."""
    l = positive("l", l)
    g = positive("g", g)
    if parameter_set(eps, mu, T, A) == "arnold":
        eps, mu = arnold(eps, mu)
        A = g / mu**2
        return eps * np.sqrt(8.0 * l / A), A, l, g
    return positive("T", T), positive("A", A), l, g


def nonnegative(name: str, value) -> np.ndarray:
    """Return ``value`` as a float array; every element must satisfy 0 <= value < inf."""
    arr = _as_float(name, value)
    bad = ~(np.isfinite(arr) & (arr >= 0))
    if bad.any():
        raise KapitzaValueError(f"{name} must be finite and >= 0 (0 <= {name} < inf); got {_first_bad(arr, bad)}")
    return arr


def general_drive(drive, zeta, name="zeta"):
    """``(drive, zeta)`` for the general path, or ``(None, None)`` for the paper's undamped square wave.

    ``drive``: ``None``, a name or a :class:`kapitza.drives.Drive`; ``zeta``: damping ratio(s) >= 0
    (the argument is called ``name`` in messages: ``zeta``, or ``damping`` for ``c``).
    """
    from .drives import as_drive

    d = as_drive(drive)
    z = nonnegative(name, zeta)
    if d.name == "square" and not np.any(z > 0):
        return None, None
    return d, z


def bounded_int(name: str, value, lo: int, hi: int) -> int:
    """Return ``value`` as one int with ``lo <= value <= hi``."""
    arr = nonnegative_int(name, value, minimum=lo)
    if arr.size != 1:
        raise KapitzaValueError(f"{name} must be a single integer; got shape {arr.shape}")
    v = int(arr.flat[0])
    if v > hi:
        raise KapitzaValueError(f"{name} must be an integer in [{lo}, {hi}]; got {v}")
    return v


def choices(name: str, values, allowed) -> tuple:
    """Return ``values`` (one name or several) as a tuple of members of ``allowed``, without repeats."""
    vals = (values,) if isinstance(values, str) else tuple(values)
    if not vals:
        raise KapitzaValueError(f"{name} must name at least one of {', '.join(map(repr, allowed))}")
    for v in vals:
        if v not in allowed:
            raise KapitzaValueError(f"{name} must be among {', '.join(map(repr, allowed))}; got {v!r}")
    return tuple(dict.fromkeys(vals))


def linearly_stable(eps, mu, stable):
    """Refuse points where the upright of the linearised equation (2.3) is not stable.

    ``eps, mu``: validated arrays of one shape; ``stable``: the exact verdict there (square wave,
    undamped). The message names the parameter, its value and where the allowed values lie.
    """
    bad = ~np.asarray(stable, dtype=bool)
    if not bad.any():
        return
    where = "" if bad.ndim == 0 else f" (at index {tuple(int(i) for i in np.argwhere(bad)[0])})"
    e, m = float(eps[bad].flat[0]), float(mu[bad].flat[0])
    if m >= 1.0:
        raise KapitzaValueError(f"mu must lie in (0, 1) (A > g) for a stable upright; got {m!r}{where}")
    raise KapitzaValueError(
        f"eps must lie inside a stability zone (alpha + n pi < w_e T < beta + n pi) at mu = {m!r}; "
        f"got eps = {e!r}{where}, where the linearised upright is unstable")
