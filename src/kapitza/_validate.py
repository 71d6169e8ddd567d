"""Validation of user input, done once at the public boundary.

Every public function converts its arguments here; private kernels trust what
they receive. Messages name the parameter, the offending value and the allowed
range, e.g. ``eps must be finite and > 0; got -1.0``.
"""
from __future__ import annotations

import sys

import numpy as np

__all__ = ["positive", "finite", "nonnegative_int", "in_range", "arnold", "parameter_set", "physical_parameters",
           "linearly_stable", "KapitzaValueError", "bounded_count", "bounded_ints", "bounded_work", "allow_large",
           "ALLOW_LARGE_ENV", "one", "broadcast", "workers", "scalars"]

#: Samples along a curve or a scan one call may ask for (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_POINTS = 200_000
#: Set this environment variable to 1 to lift the bounds on work (counts, periods, frames, ...).
ALLOW_LARGE_ENV = "KAPITZA_ALLOW_LARGE"


class KapitzaValueError(ValueError):
    """A parameter is outside its allowed range (a :class:`ValueError`).

    Examples
    --------
    >>> import kapitza
    >>> try:
    ...     kapitza.is_stable(0.5, 0.0)
    ... except ValueError as err:
    ...     print(type(err).__name__, "|", err)
    KapitzaValueError | mu must be finite and > 0 (0 < mu < inf); got 0.0
    """


class ReachError(KapitzaValueError):
    """``eps`` beyond the range a drive's Floquet data are computed over at ``mu`` (a
    :class:`KapitzaValueError`): ``eps`` the value asked (a user's, or a search's past the user's
    point), ``eps_max`` the drive's reach at ``mu``, ``why`` what bounds it."""

    def __init__(self, eps: float, mu: float, eps_max: float, why: str):
        self.eps, self.mu, self.eps_max, self.why = eps, mu, eps_max, why
        super().__init__(f"eps must satisfy eps <= {self.limit}; got {eps!r}")

    @property
    def limit(self) -> str:
        return f"{self.eps_max:.6g} at mu = {self.mu:.6g} for this drive's {self.why}"

    def about(self, point: str) -> KapitzaValueError:
        """The error to give where a search from ``point`` (what the user gave) went past the reach."""
        return KapitzaValueError(f"{point} put an edge beyond this drive's reach, eps <= {self.limit} "
                                 f"(its search reached eps = {self.eps:.6g})")


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
    ma = sys.modules.get("numpy.ma")  # (a masked array exists only once numpy.ma is loaded: 15 ms otherwise)
    if ma is not None and isinstance(value, ma.MaskedArray) and ma.is_masked(value):
        raise KapitzaValueError(f"{what}; got a masked array with masked entries")
    raw = _asarray(name, value, what)
    _no_time(name, value, raw, what)
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


def _no_time(name: str, value, raw: np.ndarray, what: str) -> None:
    """Refuse dates and durations (numpy's ``datetime64``/``timedelta64``, Python's ``datetime``
    types): numpy would read them as counts of their unit, a number the user never wrote."""
    import datetime as _dt

    kinds = {"M": "a date (datetime64)", "m": "a duration (timedelta64)"}
    if raw.dtype.kind in kinds:
        raise KapitzaValueError(f"{what}; got {kinds[raw.dtype.kind]} {_short(value)}")
    if raw.dtype.kind == "O" and any(isinstance(v, (np.datetime64, np.timedelta64, _dt.date, _dt.time,
                                                    _dt.timedelta)) for v in raw.ravel().tolist()[:10000]):
        raise KapitzaValueError(f"{what}; got a date or duration {_short(value)}")


def _asarray(name: str, value, what: str) -> np.ndarray:
    """``np.asarray(value)``; a ragged nesting of lists is refused by name."""
    try:
        return np.asarray(value)
    except (ValueError, TypeError):
        raise KapitzaValueError(f"{what}; got a ragged sequence {_short(value)} (rows of different lengths)") \
            from None


def nonnegative_int(name: str, value, *, minimum: int = 0) -> np.ndarray:
    """Return ``value`` as an int array of integers >= ``minimum``."""
    arr = _asarray(name, value, f"{name} must be an integer >= {minimum} or an array of them")
    if arr.size == 0:
        raise KapitzaValueError(f"{name} must not be empty")
    _no_time(name, value, arr, f"{name} must be an integer >= {minimum}")
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
        big = np.abs(f) >= 2.0**62
        if big.any():  # would wrap on the conversion to int64
            raise KapitzaValueError(f"{name} must be an integer >= {minimum} and below 2**62; got {_first_bad(f, big)}")
        arr = f.astype(np.int64)
    elif arr.dtype.kind == "u" and np.any(arr >= 2**62):
        raise KapitzaValueError(f"{name} must be an integer >= {minimum} and below 2**62; got "
                                f"{_first_bad(arr, arr >= 2**62)}")
    arr = arr.astype(np.int64)
    bad = arr < minimum
    if bad.any():
        raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_first_bad(arr, bad)}")
    return arr


#: Largest eps: the phases ``2 sqrt(2) eps sqrt(1 +- mu^2)`` stay doubles.
EPS_MAX = 1e307


def arnold(eps, mu, *, together=True):
    """Arnold's ``(eps, mu)`` as float arrays, each finite and > 0 (``mu >= 1`` allowed); with
    ``together`` their shapes must broadcast (a mismatch names both)."""
    eps, mu = positive("eps", eps), positive("mu", mu)
    eps_in_range(eps)
    if together:
        shape_check(eps=eps, mu=mu)
    return eps, mu


def eps_in_range(eps, source=""):
    """Refuse ``eps`` beyond :data:`EPS_MAX` by name (``source``: where it came from, for the message)."""
    if np.any(eps > EPS_MAX):
        raise KapitzaValueError(f"eps must be <= {EPS_MAX:g} (the phase 2 sqrt(2) eps must be a double); got "
                                f"{_first_bad(eps, eps > EPS_MAX)}{source}")


def shape_check(**arrays) -> tuple:
    """The broadcast shape of the named arrays; a mismatch names the parameters and their shapes."""
    try:
        return np.broadcast_shapes(*(np.shape(v) for v in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} of shape {np.shape(v)}" for k, v in arrays.items())
        raise KapitzaValueError(f"{', '.join(arrays)} must have shapes that broadcast together; got {shapes}") \
            from None


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


#: Largest damping ratio: beyond it the damped Floquet data lose more than 1e-7 relative.
ZETA_MAX = 1e4


def damping_ratio(zeta, name="zeta") -> np.ndarray:
    """Damping ratio(s) ``zeta = c / (2 sqrt(g/l))`` as a float array, each ``0 <= zeta <= ZETA_MAX``."""
    if type(zeta) is float and zeta == 0.0:  # the default, on every call: no conversion to check
        return np.zeros(())
    z = nonnegative(name, zeta)
    if np.any(z > ZETA_MAX):
        raise KapitzaValueError(
            f"{name} must be a damping ratio <= {ZETA_MAX:g} (so heavily overdamped, the monodromy's growth, "
            f"about 1/zeta, loses its digits to rounding); got {_first_bad(z, z > ZETA_MAX)}")
    return z


def damping(damping, zeta, l, g):
    """``(c, zeta)``: the damping of a physical question, given as ``damping`` (``c`` >= 0, in 1/s)
    or as ``zeta`` (the ratio ``c / (2 sqrt(g/l))``), not both; ``l``, ``g`` validated arrays.

    One meaning everywhere: ``theta'' + c theta' = (g + a(t))/l theta``, and ``zeta`` the damping
    ratio of the hanging pendulum (``docs/drives.md`` section 3), bounded by :data:`ZETA_MAX`.
    """
    if zeta is not None:
        if damping is not None and np.any(nonnegative("damping", damping) != 0):
            raise KapitzaValueError("give the damping as damping = c [1/s] or as zeta = c / (2 sqrt(g/l)), not both")
        z = damping_ratio(zeta)
        if not np.any(z > 0):
            return np.zeros(z.shape), z
        return 2.0 * z * (np.sqrt(g) / np.sqrt(l)), z
    if damping is None or (type(damping) is float and damping == 0.0):
        return np.zeros(()), np.zeros(())
    c = nonnegative("damping", damping)
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        ratio = np.where(c > 0, 0.5 * c * (np.sqrt(l) / np.sqrt(g)), 0.0)  # l / g may overflow
    if np.any(ratio > ZETA_MAX):
        bad = np.broadcast_to(c, np.shape(ratio))
        raise KapitzaValueError(
            f"damping must give a damping ratio c / (2 sqrt(g/l)) <= {ZETA_MAX:g} (so heavily overdamped, the "
            f"monodromy's growth, about 1/zeta, loses its digits to rounding); got {_first_bad(bad, ratio > ZETA_MAX)}")
    return c, ratio


def number_text(name: str, text: str) -> float:
    """A number written in a text form (a drive's parameters), named in the message where it is none."""
    try:
        return float(text)
    except ValueError:
        raise KapitzaValueError(f"{name} must be a number; got {text.strip()!r}") from None


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


# ------------------------------------------------------------------ bounded work
def allow_large() -> bool:
    """Whether the bounds on work are lifted (environment variable ``KAPITZA_ALLOW_LARGE=1``)."""
    import os

    return os.environ.get(ALLOW_LARGE_ENV, "").strip().lower() in ("1", "true", "yes", "on")


def _over_limit(name: str, value, limit, what: str) -> KapitzaValueError:
    return KapitzaValueError(
        f"{name} must be <= {limit:,} ({what}); got {_short(value)}. To go past it on purpose, set the "
        f"environment variable {ALLOW_LARGE_ENV}=1")


def bounded_count(name: str, value, limit: int, *, minimum: int = 0, what: str = "a bound that keeps the work "
                  "within minutes and the memory within the machine") -> int:
    """A single integer ``minimum <= value <= limit``, as a Python ``int``.

    The upper bound keeps the work of one call within minutes and its memory within
    the machine; ``KAPITZA_ALLOW_LARGE=1`` lifts it (the lower bound stays).
    Integers beyond int64 are refused with the value shortened, never wrapped.
    """
    if isinstance(value, (np.datetime64, np.timedelta64)):  # np.timedelta64 is an np.integer
        _no_time(name, value, np.asarray(value), f"{name} must be an integer >= {minimum}")
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)) and abs(int(value)) >= 2**62:
        if int(value) < minimum:
            raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_short(int(value))}")
        if not allow_large():
            raise _over_limit(name, int(value), limit, what)
        raise KapitzaValueError(f"{name} must be an integer below 2**62; got {_short(int(value))}")
    if isinstance(value, (float, np.floating)) and np.isfinite(value) and abs(float(value)) >= 2.0**62:
        if float(value) < minimum:
            raise KapitzaValueError(f"{name} must be an integer >= {minimum}; got {_short(value)}")
        if not allow_large():
            raise _over_limit(name, value, limit, what)
        raise KapitzaValueError(f"{name} must be an integer below 2**62; got {_short(value)}")
    arr = nonnegative_int(name, value, minimum=minimum)
    if arr.size != 1:
        raise KapitzaValueError(f"{name} must be a single integer; got an array of shape {arr.shape}")
    n = int(arr.flat[0])
    if n > limit and not allow_large():
        raise _over_limit(name, n, limit, what)
    return n


def bounded_ints(name: str, value, limit: int, *, minimum: int = 0) -> np.ndarray:
    """:func:`nonnegative_int` (any shape) with every element ``<= limit`` (as :func:`bounded_count`)."""
    arr = nonnegative_int(name, value, minimum=minimum)
    if np.any(arr > limit) and not allow_large():
        raise _over_limit(name, int(arr.max()), limit, "a bound that keeps the work within minutes and the memory "
                          "within the machine")
    return arr


def bounded_work(name: str, amount: float, limit: float, *, what: str) -> None:
    """Refuse a computed amount of work (``name``, e.g. ``"periods * points_per_period"``) beyond ``limit``
    unless ``KAPITZA_ALLOW_LARGE=1``."""
    if not (amount <= limit) and not allow_large():
        shown = f"{int(amount):,}" if float(amount).is_integer() and abs(amount) < 1e18 else f"{float(amount):.4g}"
        raise KapitzaValueError(
            f"{name} must be <= {limit:,.0f} ({what}); got {shown}. To go past it on purpose, set the "
            f"environment variable {ALLOW_LARGE_ENV}=1")


def workers(value, tasks: int) -> int:
    """Worker processes to start: ``value`` (an integer >= 1, at most 1024) capped at the machine's
    CPUs and at the number of ``tasks`` (40 asked for 2 chunks start 2)."""
    n = bounded_count("workers", value, 1024, minimum=1)
    return max(1, min(n, cpus(), int(tasks)))


def cpus() -> int:
    """The CPUs this process may run on."""
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on every platform
        return os.cpu_count() or 1


def finite_rate(A, l, g) -> None:
    """Refuse ``A``, ``l``, ``g`` whose ``(g + A)/l``, the hyperbolic phase's ``w_h^2``, is not a double."""
    A, l, g = np.asarray(A, float), np.asarray(l, float), np.asarray(g, float)
    with np.errstate(over="ignore"):
        s = np.asarray((g + A) / l)
    bad = ~np.isfinite(s)
    if bad.any():
        A_, l_ = np.broadcast_to(A, s.shape), np.broadcast_to(l, s.shape)
        raise KapitzaValueError(
            f"A, g and l must give a finite (g + A)/l, the hyperbolic phase's w_h^2; got l = "
            f"{float(l_[bad].flat[0])!r} with A = {float(A_[bad].flat[0])!r}")


def floor_below(floor, tol) -> float:
    """The smallest tilt a safe-tilt search tries, in ``(0, pi)`` and below the window ``tol`` (a
    validated float): the message names both, since a user may have given only ``tol``."""
    floor = one("floor", in_range("floor", floor, 0.0, np.pi))
    if not floor < tol:
        raise KapitzaValueError(f"tol must be > floor, the smallest start tried; got tol={tol!r}, floor={floor!r}")
    return floor


def flag(name: str, value) -> bool:
    """A yes/no option: ``True``/``False`` (numpy's too), nothing else."""
    if not isinstance(value, (bool, np.bool_)):
        raise KapitzaValueError(f"{name} must be True or False; got {_short(value)}")
    return bool(value)


# ------------------------------------------------------------------ results
def scalars(*values):
    """Each 0-d array among ``values`` as a numpy scalar (``np.float64``, ``np.int64``, ``np.bool_``):
    scalar input gives numpy scalars, array input arrays, in every public function. One value in,
    one value out; several in, a tuple out."""
    out = tuple(v[()] if isinstance(v, np.ndarray) and v.ndim == 0 else v for v in values)
    return out[0] if len(out) == 1 else out


def scalar_fields(record) -> None:
    """:func:`scalars` for each field of a frozen dataclass of results (call from ``__post_init__``);
    a Python ``float`` field becomes ``np.float64``."""
    import dataclasses

    for f in dataclasses.fields(record):
        v = getattr(record, f.name)
        if isinstance(v, np.ndarray) and v.ndim == 0:
            object.__setattr__(record, f.name, v[()])
        elif type(v) is float:
            object.__setattr__(record, f.name, np.float64(v))


# ------------------------------------------------------------------ shapes
def shapes_named(fn):
    """Decorator of a public function: numpy's broadcast error ("shape mismatch: objects cannot be
    broadcast ...") becomes a :class:`KapitzaValueError` naming the array arguments and their shapes."""
    import functools
    import inspect

    sig = inspect.signature(fn)

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except ValueError as exc:
            text = str(exc)
            if isinstance(exc, KapitzaValueError) or not ("broadcast" in text or "shape mismatch" in text):
                raise
            try:
                bound = sig.bind(*args, **kwargs)
            except TypeError:
                raise exc from None
            arrays = {k: v for k, v in bound.arguments.items()
                      if isinstance(v, (list, tuple, np.ndarray)) and not isinstance(v, str)}
            shapes = ", ".join(f"{k} of shape {np.shape(v)}" for k, v in arrays.items()) or "no arrays"
            raise KapitzaValueError(f"{', '.join(arrays) or 'the arguments'} must have shapes that broadcast "
                                    f"together; got {shapes}") from None

    return wrapper



def one(name: str, arr) -> float:
    """The single value of a validated float array ``arr`` as a Python ``float`` (``name`` in the message:
    a list given where one number is meant is refused by name, not by numpy's conversion text)."""
    arr = np.asarray(arr)
    if arr.size != 1:
        raise KapitzaValueError(f"{name} must be a single number here; got an array of shape {arr.shape}")
    return float(arr.reshape(()))


def broadcast(**arrays):
    """``np.broadcast_arrays`` of the named arrays; a mismatch names the parameters and their shapes."""
    shape_check(**arrays)
    return np.broadcast_arrays(*arrays.values())


def phase_resolved(t, T) -> None:
    """Refuse times with ``|t / T| >= 2**52``: beyond it the time within a half-period, which
    decides the phase of the drive, is lost (``t``, ``T``: validated arrays that broadcast)."""
    t, T = np.broadcast_arrays(t, T)
    with np.errstate(over="ignore"):
        bad = ~(np.abs(t / T) < 2.0**52)
    if bad.any():
        raise KapitzaValueError(
            f"t / T must be below 2**52 (beyond it the time within a half-period is lost); got t = "
            f"{float(t[bad].flat[0])!r} with T = {float(T[bad].flat[0])!r}")
