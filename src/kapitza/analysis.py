"""One-call answers: the full stability picture of a parameter set.

This is what the ``kapitza stability`` command prints: verdict, zone, Floquet
multipliers, growth, rotation number and margins, for Arnold's ``(eps, mu)`` or
for the physical ``(T, A)`` of a rod ``l`` under gravity ``g``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, asdict

import numpy as np

from . import _validate as _v
from ._display import Summary, digits_apart, multipliers
from .advice import directions, percent_change
from .drives import as_drive
from .parameters import G_EARTH, to_arnold
from .safety import safe_tilt_sentence

__all__ = ["StabilityReport", "analyze"]


@dataclass(frozen=True, repr=False)
class StabilityReport(Summary):
    """Everything about the upright position at one parameter set (scalars).

    ``print(report)`` gives the table ``kapitza stability`` prints (an HTML table in Jupyter);
    ``repr`` one line; :meth:`as_dict` the JSON.

    Attributes
    ----------
    eps, mu : float
        Arnold's parameters.
    stable : bool
    verdict : str
        A sentence: ``"stable (zone 0)"``; ``"unstable: the drive is too weak to hold it up ..."``
        below zone 0; ``"unstable: parametric resonance, 2T-type ..."`` (or ``4T-type``) between
        zones; or ``"always unstable: no elliptic phase (A <= g)"``.
    zone : int
        Zone containing the point, -1 where unstable.
    nearest_zone : int
        The zone the margins refer to (the containing one, or the nearest).
    trace : float
        ``tr M`` (may be ``+-inf``).
    multipliers : tuple of complex
        Largest modulus first.
    growth : float
        ``log max|lambda|`` per period ``2T``.
    rotation_number : float
        Turns per period (see :class:`kapitza.Floquet`).
    eps_lo, eps_hi : float
        Edges of ``nearest_zone`` in ``eps`` (NaN where ``A <= g``): those of :func:`kapitza.zone_edges`,
        except for the undamped square wave, whose report takes its closed forms' roots (within
        4 ulp of them, either side).
    margin : float
        Signed relative distance along ``eps`` (equivalently ``T`` at fixed
        ``A``) to the nearest edge of ``nearest_zone``: > 0 inside, < 0 outside.
    trace_margin : float
        ``1 - |tr M| / 2``: > 0 inside a zone.
    T, A, l, g : float or None
        Physical parameters, when given.
    A_g : float or None
        ``A / g``, the acceleration amplitude in units of gravity (a property; in :meth:`as_dict`,
        the JSON of ``kapitza stability --json`` and ``/api/point``), when given physically.
    drive : str
        The pivot's motion (:meth:`kapitza.drives.Drive.describe`).
    pendulum : str or None
        What swings and which length the formulas use, when known (:class:`kapitza.Pendulum`).
    damping : float or None
        Viscous damping ``c`` [1/s], when given physically.
    zeta : float
        Damping ratio ``c / (2 sqrt(g/l))`` (0 undamped).
    determinant : float
        ``det M = exp(-2 c T)``.
    T_lo, T_hi : float or None
        ``nearest_zone`` as an interval of half-periods at this ``A``.
    stroke : float or None
        Peak-to-peak travel of the pivot [m].
    frequency_lo, frequency_hi : float or None
        ``nearest_zone`` as an interval of drive frequencies [Hz] at this stroke (how a shaker
        is turned: its stroke fixed, its frequency changed; ``eps`` stays fixed, ``mu`` varies).
    stroke_lo, stroke_hi : float or None
        ``nearest_zone`` as an interval of strokes [m] at this frequency (``A`` scales with it).
    A_lo, A_hi : float or None
        ``nearest_zone`` as an interval of amplitudes at this ``T``.
    safe_tilt : float or None
        Where computed (``analyze(..., safe_tilt=True)``): the largest starting tilt from rest [rad]
        that the real (nonlinear) pendulum survives above the horizontal for ``safe_tilt_periods``
        periods (:func:`kapitza.safe_tilt`); 0 where linearly unstable.
    safe_tilt_periods : int or None
    given : str or None
        The amplitude a rig was described by (``"amplitude"``, ``"stroke"`` or ``"A"``): the
        intervals and :attr:`directions` answer in it.
    nonlinear : str or None
        The verdict on the full equation's upright where it is linearly stable (undamped
        square wave only): Lyapunov stable by Moser's twist theorem or Markeev's criterion,
        or undecided at third order, with the twist (:func:`kapitza.nonlinear_stability`,
        ``docs/nonlinear.md``).

    Examples
    --------
    >>> import kapitza
    >>> r = kapitza.analyze(T=0.15, A=100.0, l=1.0)
    >>> r
    <StabilityReport: T = 0.15 s, A = 100 m/s^2, eps = 0.5303..., mu = 0.3132...: stable (zone 0)>
    >>> r.stable, r.zone, r.verdict
    (True, 0, 'stable (zone 0)')
    >>> r.T_lo, r.T_hi
    (0.1091..., 0.2008...)
    >>> r.as_dict()["margin"]
    0.2726...
    """

    eps: float
    mu: float
    stable: bool
    verdict: str
    zone: int
    nearest_zone: int
    trace: float
    multipliers: tuple
    growth: float
    rotation_number: float
    eps_lo: float
    eps_hi: float
    margin: float
    trace_margin: float
    T: float | None = None
    A: float | None = None
    l: float | None = None
    g: float | None = None
    T_lo: float | None = None
    T_hi: float | None = None
    A_lo: float | None = None
    A_hi: float | None = None
    stroke: float | None = None
    frequency_lo: float | None = None
    frequency_hi: float | None = None
    stroke_lo: float | None = None
    stroke_hi: float | None = None
    drive: str = "square wave (+A for T, -A for T)"
    pendulum: str | None = None
    damping: float | None = None
    zeta: float = 0.0
    determinant: float = 1.0
    nonlinear: str | None = None
    safe_tilt: float | None = None
    safe_tilt_periods: int | None = None
    given: str | None = None

    @property
    def directions(self) -> list:
        """Which knob to turn which way to reach (or how far one may leave) the nearest zone
        (:func:`kapitza.advice.directions`): records with a ``text`` sentence each."""
        return directions(self, self.given)

    @property
    def A_g(self) -> float | None:
        """The acceleration amplitude in units of gravity, ``A / g``, when given physically."""
        return None if self.A is None or self.g is None else self.A / self.g

    @property
    def frequency(self) -> float | None:
        """Drive frequency ``1/(2T)`` [Hz], when given physically."""
        return None if self.T is None else 0.5 / self.T

    def lines(self) -> list[tuple[str, str]]:
        """``(label, text)`` rows: what ``kapitza stability`` prints, and the HTML table shows."""
        rows = []
        if self.T is not None:
            rows.append(("parameters", f"T = {_fmt(self.T)} s (frequency {_fmt(self.frequency, 6)} Hz), "
                                       f"A = {_fmt(self.A)} m/s^2 ({_fmt(self.A_g, 4)} g), "
                                       f"l = {_fmt(self.l)} m, "
                                       f"g = {_fmt(self.g)} m/s^2"))
        if self.pendulum:
            rows.append(("pendulum", self.pendulum))
        rows.append(("drive", self.drive))
        if self.zeta > 0:
            c = f"c = {_fmt(self.damping, 6)} 1/s, " if self.damping is not None else ""
            rows.append(("damping", f"{c}ratio zeta = {_fmt(self.zeta, 6)}; det M = {_fmt(self.determinant)}"))
        rows.append(("Arnold", f"eps = {_fmt(self.eps)}, mu = {_fmt(self.mu)}"))
        rows.append(("verdict", self.verdict))
        if self.safe_tilt is not None:
            rows.append(("safe tilt", safe_tilt_sentence(self.safe_tilt, self.safe_tilt_periods, self.stable)))
        lam = multipliers(self.multipliers)
        crit = "|tr M| < 2" if self.zeta == 0 else "|tr M| < 1 + det M"
        note = ""
        if self.zeta == 0 and abs(self.trace) == 2.0:
            # (a trace within half an ulp of the threshold: the double cannot show which side it is on)
            note = f"; |tr M| rounds to 2, and is {'below' if self.stable else 'at or above'} it in extended precision"
        rows.append(("trace tr M", f"{_fmt(self.trace)}   (stable iff {crit}{note})"))
        rows.append(("multipliers", lam))
        rows.append(("growth", f"{_fmt(self.growth)} per period 2T (log of the largest |multiplier|"
                               + ("; < 0: motions decay)" if self.zeta > 0 else ")")))
        rows.append(("rotation number", f"{_fmt(self.rotation_number)} turns per period"))
        if self.nonlinear is not None:
            rows.append(("nonlinear", self.nonlinear))
        if self.nearest_zone >= 0:
            where = "in" if self.stable else "nearest"
            rows.append((f"zone ({where})", f"n = {self.nearest_zone}: {_between(self.eps_lo, 'eps', self.eps_hi)}"))
            if self.T_lo is not None:
                rows.append(("", f"{_between(self.T_lo, 'T', self.T_hi)} s at this A"))
                rows.append(("", f"{_between(self.A_lo, 'A', self.A_hi)} m/s^2 at this T"))
            if self.frequency_lo is not None:
                f = self.frequency
                kept = "amplitude" if self.given == "amplitude" else "stroke"
                if self.frequency_hi is not None and np.isfinite(self.frequency_hi):
                    rows.append(("", f"{_between(self.frequency_lo, 'frequency', self.frequency_hi, 6)} Hz at "
                                     f"this {kept} ({percent_change(self.frequency_lo, f)} / "
                                     f"{percent_change(self.frequency_hi, f)})"))
                else:
                    rows.append(("", f"frequency > {_fmt(self.frequency_lo, 6)} Hz at this {kept} "
                                     f"({percent_change(self.frequency_lo, f)}; no upper limit)"))
            if self.stroke_lo is not None and self.stroke_hi is not None:
                st, k, word = self.stroke, 1.0, "stroke"
                if self.given == "amplitude":
                    k, word = 0.5, "amplitude"
                rows.append(("",
                             f"{_between(1e3 * k * self.stroke_lo, word, 1e3 * k * self.stroke_hi, 6)} mm "
                                 f"at this frequency ({percent_change(self.stroke_lo, st)} / "
                                 f"{percent_change(self.stroke_hi, st)})"))
            ways = self.directions
            if not self.stable:
                # (a knob whose range holds no double, its ends adjacent in SI units and so within two
                # spacings in the record's, would be named one value twice: left out; the zone may have
                # no eps inside at this mu and still a wide range of A or of the stroke, which reaches it
                # where mu is lower)
                ways = [d for d in ways if d["hi"] is None or d["hi"] - d["lo"] > 2.0 * np.spacing(d["hi"])]
                if not ways:
                    inside = "eps" if np.nextafter(self.eps_lo, np.inf) >= self.eps_hi else "setting of the knobs"
                    rows.append(("to hold it", f"nothing: zone {self.nearest_zone} is thinner than the spacing of "
                                               f"the doubles about it (no {inside} inside it)"))
                    return rows
            for i, d in enumerate(ways):
                rows.append(("" if i else "to hold it" if not self.stable else "room", d["text"]))
        return rows

    def headline(self) -> str:
        where = f"T = {_fmt(self.T, 6)} s, A = {_fmt(self.A, 6)} m/s^2, " if self.T is not None else ""
        return f"{where}eps = {_fmt(self.eps, 6)}, mu = {_fmt(self.mu, 6)}: {self.verdict}"

    def as_dict(self) -> dict:
        """JSON-ready dictionary (complex multipliers as ``[re, im]`` pairs; ``A_g`` the amplitude in g)."""
        d = asdict(self)
        d["directions"] = self.directions
        d["A_g"] = self.A_g
        d["multipliers"] = [[float(z.real), float(z.imag)] for z in self.multipliers]
        return {k: (None if isinstance(v, float) and not np.isfinite(v) and k not in ("trace", "margin") else v)
                for k, v in d.items()}


def _unstable_verdict(tau, nearest, eps, eps_lo):
    """The way of being unstable, in words a user recognises."""
    if nearest == 0 and eps <= eps_lo:
        return ("unstable: the drive is too weak to hold it up (it falls; below zone 0, "
                "one multiplier real and > 1)")
    if tau > 0:
        return "unstable: parametric resonance, 2T-type (multipliers real, positive)"
    return "unstable: parametric resonance, 4T-type, period doubling (multipliers real, negative)"


def _between(lo, name, hi, digits=12):
    """``lo < name < hi`` with at least ``digits`` significant digits, more where they tell the ends
    apart (a zone a few doubles wide is not written as one number twice)."""
    d = digits_apart(lo, hi, least=digits)
    return f"{_fmt(lo, d)} < {name} < {_fmt(hi, d)}"


def _fmt(v, digits=12):
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def analyze(*, eps=None, mu=None, T=None, A=None, l=1.0, g=G_EARTH, drive=None, damping=0.0,
            zeta=None, safe_tilt=False) -> StabilityReport:
    """Stability report for one parameter set, given as ``(eps, mu)`` or ``(T, A, l, g)``.

    Parameters
    ----------
    eps, mu : float, optional
        Arnold's parameters (> 0; ``mu >= 1`` means ``A <= g``).
    T, A : float, optional
        Drive half-period [s] and acceleration amplitude [m/s^2], > 0.
    l, g : float, optional
        Rod length [m] and gravity [m/s^2] (used with ``T, A``), > 0.
    drive : Drive or str, optional
        The pivot's motion (:mod:`kapitza.drives`); the paper's square wave by default.
    damping : float, optional
        Viscous damping ``c`` >= 0 [1/s] in ``theta'' + c theta' = ...`` (with ``T, A``).
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))`` >= 0 (with ``eps, mu``).
    safe_tilt : bool or int, optional
        Also find the safe tilt (:func:`kapitza.safe_tilt`) over its default periods, or over this
        many periods (an int); it follows the real pendulum, so it takes up to a second or so.

    Returns
    -------
    StabilityReport

    Raises
    ------
    ValueError
        If neither or both parameter sets are given, or a value is out of range.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.analyze(eps=0.5, mu=0.3)
    <StabilityReport: eps = 0.5, mu = 0.3: stable (zone 0)>
    >>> kapitza.analyze(eps=1.2, mu=0.3).verdict
    'unstable: parametric resonance, 4T-type, period doubling (multipliers real, negative)'
    >>> r = kapitza.analyze(T=0.15, A=100.0, l=1.0, damping=0.5)
    >>> r.stable, r.zeta, r.determinant
    (True, 0.0798..., 0.8607...)
    >>> kapitza.analyze(eps=0.5)
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: eps and mu must be given together
    """
    rep = _analyze(eps, mu, T, A, l, g, drive, damping, zeta)
    if safe_tilt is not False and safe_tilt is not None:
        from .safety import with_safe_tilt

        rep = with_safe_tilt(rep, drive, None if safe_tilt is True else safe_tilt)
    return rep


def _analyze(eps, mu, T, A, l, g, drive, damping, zeta, pointwise=True):
    """:func:`analyze`; ``pointwise=False`` keeps every part on the array kernels (the path the
    scalar twins of the square wave are tested and timed against)."""
    d = as_drive(drive)
    point = _plain_point(eps, mu, T, A, l, g, damping, zeta)
    if point is None:
        point = _validated_point(eps, mu, T, A, l, g, damping, zeta)
    e, physical, T, A, l = point[0], point[3], point[4], point[5], point[6]
    _v.eps_in_range(np.float64(e), f" (of T = {T!r}, A = {A!r}, l = {l!r})" if physical else "")
    if physical and not d.point_stroke(T, A) > 0.0:
        # (the report's rig intervals are read against the stroke)
        raise _v.KapitzaValueError(
            f"T and A must give a stroke {d.point_stroke(1.0, 1.0):.6g} A T^2 within the range of positive "
            f"doubles; got T = {T!r}, A = {A!r}, whose stroke rounds to 0 m")
    try:
        return _report(d, *point, pointwise)
    except _v.ReachError as err:
        if err.eps == e:
            raise
        raise err.about(f"eps = {e!r} and mu = {point[1]!r}") from None


def _validated_point(eps, mu, T, A, l, g, damping, zeta):
    """``(eps, mu, zeta, physical, T, A, l, g, c)`` of one parameter set, validated, as floats."""
    for name, v in (("eps", eps), ("mu", mu), ("T", T), ("A", A), ("l", l), ("g", g), ("damping", damping),
                    ("zeta", zeta)):
        try:
            shape = np.shape(v)
        except ValueError:  # a ragged nesting of lists
            shape = "ragged"
        if v is not None and shape != ():
            raise _v.KapitzaValueError(
                f"analyze takes single values; got {name} of shape {shape} (for arrays use "
                "kapitza.floquet, is_stable, zone_index or stability_margin)")
    if _v.parameter_set(eps, mu, T, A) == "arnold":
        if damping is not None and np.any(np.asarray(damping) != 0):
            raise _v.KapitzaValueError("with eps and mu give the damping as zeta = c / (2 sqrt(g/l)), not damping")
        eps = _v.one("eps", _v.positive("eps", eps))
        mu = _v.one("mu", _v.positive("mu", mu))
        z = _v.one("zeta", _v.damping_ratio(0.0 if zeta is None else zeta))
        return eps, mu, z, False, None, None, l, g, None
    T = _v.one("T", _v.positive("T", T))
    A = _v.one("A", _v.positive("A", A))
    l = _v.one("l", _v.positive("l", l))
    g = _v.one("g", _v.positive("g", g))
    eps, mu = (float(v) for v in to_arnold(T, A, l, g))
    c, z = _v.damping(damping, zeta, np.asarray(l), np.asarray(g))
    return eps, mu, _v.one("zeta", z), True, T, A, l, g, _v.one("damping", c)


def _plain(v):
    """``v`` as a float if it is a Python number with ``0 < v < inf``, else None."""
    if type(v) is float:
        return v if 0.0 < v < math.inf else None
    if type(v) is int and 0 < v < 2**53:
        return float(v)
    return None


def _plain_zero(v):
    return (type(v) is float or type(v) is int) and v == 0


def _plain_ratio(v):
    """``v`` as a float if it is a Python number with ``0 <= v < inf``, else None."""
    if _plain_zero(v):
        return 0.0
    return _plain(v)


def _plain_point(eps, mu, T, A, l, g, damping, zeta):
    """:func:`_validated_point` when every argument is a plain Python number that the validation
    would pass as it is (the common call), or None: then the full validation runs. Saves the dozen
    array conversions of the validation, a good part of a one-point answer."""
    if T is None and A is None:
        e, m = _plain(eps), _plain(mu)
        z = 0.0 if zeta is None else _plain_ratio(zeta)
        if (e is None or m is None or z is None or z > _v.ZETA_MAX or not (damping is None or _plain_zero(damping))
                or type(l) not in (float, int) or type(g) not in (float, int)):
            return None
        return e, m, z, False, None, None, l, g, None
    if eps is not None or mu is not None or zeta is not None:
        return None
    T, A, l, g = _plain(T), _plain(A), _plain(l), _plain(g)
    c = 0.0 if damping is None else _plain_ratio(damping)
    if T is None or A is None or l is None or g is None or c is None or not math.isfinite(l / g):
        return None
    e, m = T * math.sqrt(A / (8.0 * l)), math.sqrt(g / A)  # kapitza.to_arnold, where it needs no split
    if not (0.0 < e < math.inf and 0.0 < m < math.inf):
        return None
    z = 0.5 * c * (math.sqrt(l) / math.sqrt(g)) if c > 0 else 0.0  # as _validate.damping
    if not z <= _v.ZETA_MAX:
        return None
    return e, m, z, True, T, A, l, g, c


def _report(drive, eps, mu, zeta, physical, T, A, l, g, c, pointwise=True):
    """The report of one validated point (floats): every part asked of the drive."""
    trace, det, mult, growth, rho, stable, zone, theta, exact_theta = drive.point_floquet(eps, mu, zeta, pointwise)
    (_, nz, eps_lo, eps_hi, margin), intervals = drive.point_edges(
        eps, mu, zeta, (T, A, l, g, c) if physical else None, pointwise,
        level0=zone + 0.5 if stable else float(np.rint(theta / np.pi)))
    if stable:
        verdict = f"stable (zone {zone})" + (", motions decay" if zeta > 0 else "")
    else:
        verdict = drive.point_sentence(mu, zeta, nz, eps_lo) or _unstable_verdict(trace, nz, eps, eps_lo)
    phys = {}
    if physical:
        phys = dict(T=T, A=A, l=l, g=g)
        if intervals is not None:
            phys.update(intervals)
        else:
            phys["stroke"] = drive.point_stroke(T, A)
    nonlinear = drive.point_nonlinear(eps, mu, zeta, theta, zone, exact_theta, pointwise) if stable else None
    return StabilityReport(
        eps=float(eps), mu=float(mu), stable=stable, verdict=verdict,
        zone=zone if stable else -1, nearest_zone=nz, trace=trace, multipliers=mult, growth=growth,
        rotation_number=rho, eps_lo=eps_lo, eps_hi=eps_hi, margin=margin,
        trace_margin=1.0 - abs(trace) / (1.0 + det), drive=drive.describe(), damping=c, zeta=float(zeta),
        determinant=float(det), nonlinear=nonlinear, **phys)
