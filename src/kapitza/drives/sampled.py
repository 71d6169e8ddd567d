"""A measured drive: one period of sampled pivot acceleration (an accelerometer trace).

:func:`from_samples` turns samples ``(t_i, a_i)`` into a drive. Between samples the acceleration
is linear (``kind="linear"``, the default) or held (``kind="constant"``: ``a_i`` from ``t_i`` to
``t_{i+1}``); the last sample joins the first one period later. The mean of that periodic
function over the period is removed (it is reported as :attr:`SampledDrive.mean`: a pivot with a
mean acceleration drifts away) and the rest is scaled so that ``A`` is its peak:

    a(t) - mean = A s(t/T),     A = max |a - mean|,     T = period / 2,

so ``max|s| = 1`` (``docs/drives.md``, "A measured drive"). :attr:`SampledDrive.A` and
:attr:`SampledDrive.T` are these two numbers, in the units of the samples.

The stability data come from the generic engine (:mod:`kapitza.engines`) on a grid aligned with
the sample times: each step sees a linear (or constant) acceleration, where the sixth-order
Magnus step is accurate to rounding (exact for constant), so the drive's edges are those of the
interpolated signal to about 1e-12; the interpolation itself differs from the true signal by
``O(h^2)`` (linear) or ``O(h)`` (constant), ``h`` the sample step.
"""
from __future__ import annotations

import functools
import hashlib

import numpy as np

from .. import _validate as _v
from ._base import Drive

__all__ = ["SampledDrive", "from_samples"]

#: relative spread of the time steps still taken as uniform sampling
UNIFORM_RTOL = 1e-6


def _flat(values):
    """Whether a list or tuple holds no sequences (one value per sample)."""
    return not any(isinstance(v, (list, tuple, np.ndarray)) for v in values)


def _column(name, values, rows):
    """A 1-d float array of ``values``; a non-numeric or non-finite entry is refused by its row."""
    if isinstance(values, (str, bytes)):
        raise _v.KapitzaValueError(f"{name} must be a sequence of numbers; got the text {values!r}")
    if isinstance(values, np.ma.MaskedArray) and np.ma.is_masked(values):
        raise _v.KapitzaValueError(f"{name} must be numbers; got a masked array with masked entries")
    nested = isinstance(values, (list, tuple)) and not _flat(values)
    if nested or (not isinstance(values, (list, tuple)) and np.ndim(values) > 1):
        raise _v.KapitzaValueError(f"{name} must be one-dimensional (one value per sample); got {values!r:.60}")
    try:
        raw = np.asarray(values, dtype=object).ravel() if not isinstance(values, np.ndarray) else values.ravel()
    except Exception:  # noqa: BLE001 - anything numpy cannot hold is refused the same way
        raise _v.KapitzaValueError(f"{name} must be a sequence of numbers; got {values!r:.60}") from None
    out = np.empty(raw.size)
    for i, v in enumerate(raw.tolist()):
        if isinstance(v, (str, bytes, bool, complex, np.bool_)) or v is None:
            raise _v.KapitzaValueError(f"{name} must be numbers; {rows(i)} holds {v!r}")
        try:
            out[i] = float(v)
        except (TypeError, ValueError, OverflowError):
            raise _v.KapitzaValueError(f"{name} must be finite numbers; {rows(i)} holds {v!r:.60}") from None
        if not np.isfinite(out[i]):
            raise _v.KapitzaValueError(f"{name} must be finite; {rows(i)} holds {float(out[i])!r}")
    return out


class SampledDrive(Drive):
    """A drive given by samples of its acceleration over one period (see :func:`from_samples`).

    Attributes
    ----------
    A : float
        Peak acceleration about the mean, ``max|a - mean|`` (units of the samples).
    T : float
        Half the period (units of the sample times).
    period : float
        The period ``2T``.
    mean : float
        The mean acceleration removed from the samples.
    kind : str
        ``"linear"`` or ``"constant"`` between samples.
    periods : int
        How many periods the samples covered (several are averaged phase by phase).
    """

    name = "samples"

    @property
    def own_scale(self):
        return self.T, self.A

    def __init__(self, phase, s, kind, A, T, mean, periods=1):
        self._phase = phase  # sample times in tau, in [0, 2)
        self._s = s
        self.kind = kind
        self.A = float(A)
        self.T = float(T)
        self.period = 2.0 * self.T
        self.mean = float(mean)
        self.periods = int(periods)
        n = s.size
        self._min_steps = max(64, n)
        if kind == "linear":
            self._xp = np.concatenate([phase, [2.0]])
            self._fp = np.concatenate([s, s[:1]])
            self._breakpoints = tuple(phase[1:])
        else:
            self._breakpoints = tuple(phase[1:])
        self._digest = hashlib.sha1(np.concatenate([phase, s]).tobytes() + kind.encode()).hexdigest()[:12]

    def _shape(self, tau):
        tau = np.asarray(tau, float)
        if self.kind == "linear":
            return np.interp(tau, self._xp, self._fp)
        i = np.clip(np.searchsorted(self._phase, tau, side="right") - 1, 0, self._s.size - 1)
        return self._s[i]

    def _linear_pieces(self):
        return self._pieces

    @functools.cached_property
    def _pieces(self):
        """The samples as linear pieces (built once: a report asks for them at every step)."""
        if self.kind == "linear":
            x, f = self._xp, self._fp
            return tuple(zip(x[:-1].tolist(), x[1:].tolist(), f[:-1].tolist(), f[1:].tolist()))
        ends = np.concatenate([self._phase[1:], [2.0]])
        return tuple(zip(self._phase.tolist(), ends.tolist(), self._s.tolist(), self._s.tolist()))

    @property
    def samples(self):
        """``(t, a)``: one period of the samples as used (the mean removed, times from 0)."""
        return self._phase * self.T, self._s * self.A

    def text(self) -> str:
        raise _v.KapitzaValueError("a measured drive (from_samples, --drive-file) has no text form to name it by "
                                   "(in a sweep's spec, a link)")

    def as_dict(self) -> dict:
        return {"drive": self.name, "kind": self.kind, "samples": int(self._s.size), "period": self.period,
                "A": self.A, "mean": self.mean, "digest": self._digest}

    def __repr__(self):
        return (f"SampledDrive({self._s.size} samples, kind={self.kind!r}, period={self.period:.6g}, "
                f"A={self.A:.6g}, mean={self.mean:.6g})")

    def __eq__(self, other):
        return type(self) is type(other) and self.kind == other.kind and np.array_equal(self._phase, other._phase) \
            and np.array_equal(self._s, other._s)

    def __hash__(self):
        return hash((type(self).__name__, self._digest))

    @property
    def label(self) -> str:
        return f"measured ({self._s.size} samples)"

    def describe(self) -> str:
        between = "linear" if self.kind == "linear" else "held"
        return (f"measured drive: {self._s.size} samples, {between} between them, period {self.period:.6g}, "
                f"peak {self.A:.6g} about the mean {self.mean:.6g} (removed)")


def from_samples(t, a, period=None, kind="linear", *, rows=None):
    """A drive from samples of the pivot's acceleration over one period (or several).

    Parameters
    ----------
    t : array_like
        Sample times, strictly increasing (any origin; seconds for a rig).
    a : array_like
        Pivot accelerations at ``t`` (m/s^2 for a rig), upward positive.
    period : float, optional
        The drive period. Default: the sample span plus one step, for uniform times only
        (non-uniform times need it). With ``period`` shorter than the samples' span the
        samples cover several periods: they must then be uniform with a whole number of steps
        per period, and the samples at the same phase are averaged.
    kind : {"linear", "constant"}
        The acceleration between samples: linear, or held at the earlier sample.
    rows : callable, optional
        ``rows(i)`` names sample ``i`` in messages (a file's row); "sample i" by default.

    Returns
    -------
    SampledDrive
        With ``drive.A`` (peak of ``a - mean``), ``drive.T`` (half the period), ``drive.mean``
        (removed). ``analyze(T=drive.T, A=drive.A, drive=drive)`` is the measured rig.

    Raises
    ------
    KapitzaValueError
        Non-numeric, non-finite or unsorted entries (named by their row), fewer than two
        samples, a span longer than the period that is not a whole number of uniform steps,
        a constant signal, or a mean larger than the signal's peak about it (an offset such as
        gravity left in the trace).

    Examples
    --------
    One period of a measured 40 Hz sine, 64 samples, with an offset of 5 m/s^2 (removed):

    >>> import numpy as np
    >>> import kapitza
    >>> t = np.arange(64) / 64 * 0.025
    >>> drive = kapitza.from_samples(t, 5.0 + 650.0 * np.sin(2 * np.pi * t / 0.025))
    >>> float(drive.T), float(drive.A), round(float(drive.mean), 6)
    (0.0125, 650.0, 5.0)
    >>> eps, mu = kapitza.to_arnold(drive.T, drive.A, l=0.2)
    >>> kapitza.is_stable(eps, mu, drive=drive), kapitza.is_stable(eps, mu, drive="sine")
    (np.True_, np.True_)
    >>> kapitza.from_samples([0.0, 0.01, 0.02], [1.0, 1.0, 1.0])
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: the acceleration samples are constant: there is no drive to analyse
    """
    rows = rows or (lambda i: f"sample {i}")
    if kind not in ("linear", "constant"):
        raise _v.KapitzaValueError(f"kind must be 'linear' or 'constant'; got {kind!r}")
    t = _column("t", t, rows)
    a = _column("a", a, rows)
    if t.size != a.size:
        raise _v.KapitzaValueError(f"t and a must have the same length; got {t.size} and {a.size}")
    if t.size < 2:
        raise _v.KapitzaValueError(f"a drive needs at least 2 samples of one period; got {t.size}")
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise _v.KapitzaValueError(
            f"t must be strictly increasing; {rows(i)} has t = {float(t[i])!r} after {float(t[i - 1])!r}")
    step = float(np.mean(dt))
    uniform = bool(np.all(np.abs(dt - step) <= UNIFORM_RTOL * step))
    span = float(t[-1] - t[0])
    if period is None:
        if not uniform:
            i = int(np.argmax(np.abs(dt - step))) + 1
            raise _v.KapitzaValueError(
                f"the sample times are not uniform ({rows(i)} is {dt[i - 1]:.6g} after the previous one, the mean "
                f"step is {step:.6g}): give the period")
        period = span + step
    period = _v.one("period", _v.positive("period", period))
    periods = 1
    if period <= span:
        # several periods: uniform samples, a whole number per period, averaged phase by phase
        per = period / step
        if not uniform or abs(per - round(per)) > 1e-6 * per:
            raise _v.KapitzaValueError(
                f"the samples span {span:.6g}, more than the period {period:.6g}: several periods are averaged only "
                f"for uniform times with a whole number of steps per period (here {per:.6g} steps per period)")
        per = int(round(per))
        k = np.arange(t.size)
        periods = int(np.ceil(t.size / per))
        acc = np.bincount(k % per, weights=a, minlength=per)
        cnt = np.bincount(k % per, minlength=per)
        a = acc / cnt
        t = t[0] + step * np.arange(per)
    phase = 2.0 * (t - t[0]) / period
    # the periodic interpolant's mean: trapezoids (linear) or rectangles (constant), the last
    # interval running to one period after the first sample
    h = np.diff(np.concatenate([phase, [2.0]]))
    if kind == "linear":
        mean = float(np.sum(h * 0.5 * (a + np.roll(a, -1))) / 2.0)
    else:
        mean = float(np.sum(h * a) / 2.0)
    ac = a - mean
    peak = float(np.max(np.abs(ac)))
    if not peak > 0.0 or peak <= 1e-12 * max(abs(mean), float(np.max(np.abs(a)))):
        raise _v.KapitzaValueError("the acceleration samples are constant: there is no drive to analyse")
    if abs(mean) > peak:
        raise _v.KapitzaValueError(
            f"the mean acceleration {mean:.6g} is larger than the signal's peak {peak:.6g} about it: remove the "
            "offset (gravity?) from the samples, or check the column")
    return SampledDrive(phase, ac / peak, kind, peak, 0.5 * period, mean, periods)
