"""One-call answers: the full stability picture of a parameter set.

This is what the ``kapitza stability`` command prints: verdict, zone, Floquet
multipliers, growth, rotation number and margins, for Arnold's ``(eps, mu)`` or
for the physical ``(T, A)`` of a rod ``l`` under gravity ``g``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, asdict

import numpy as np

from . import _point
from . import _validate as _v
from ._display import Summary, multipliers
from .parameters import G_EARTH, to_arnold
from .normal_form import _sentence_of, nonlinear_stability
from .propagation import _floquet, _multipliers
from .zones import amplitude_edges, period_edges, stability_margin

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
        Edges of ``nearest_zone`` in ``eps`` (NaN where ``A <= g``).
    margin : float
        Signed relative distance along ``eps`` (equivalently ``T`` at fixed
        ``A``) to the nearest edge of ``nearest_zone``: > 0 inside, < 0 outside.
    trace_margin : float
        ``1 - |tr M| / 2``: > 0 inside a zone.
    T, A, l, g : float or None
        Physical parameters, when given.
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
        from .advice import directions

        return directions(self, self.given)

    @property
    def frequency(self) -> float | None:
        """Drive frequency ``1/(2T)`` [Hz], when given physically."""
        return None if self.T is None else 0.5 / self.T

    def lines(self) -> list[tuple[str, str]]:
        """``(label, text)`` rows: what ``kapitza stability`` prints, and the HTML table shows."""
        rows = []
        if self.T is not None:
            rows.append(("parameters", f"T = {_fmt(self.T)} s (frequency {_fmt(self.frequency, 6)} Hz), "
                                       f"A = {_fmt(self.A)} m/s^2 ({_fmt(self.A / self.g, 4)} g), l = {_fmt(self.l)} m, "
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
            rows.append(("safe tilt", _safe_text(self.safe_tilt, self.safe_tilt_periods, self.stable)))
        lam = multipliers(self.multipliers)
        crit = "|tr M| < 2" if self.zeta == 0 else "|tr M| < 1 + det M"
        rows.append(("trace tr M", f"{_fmt(self.trace)}   (stable iff {crit})"))
        rows.append(("multipliers", lam))
        rows.append(("growth", f"{_fmt(self.growth)} per period 2T (log of the largest |multiplier|"
                               + ("; < 0: motions decay)" if self.zeta > 0 else ")")))
        rows.append(("rotation number", f"{_fmt(self.rotation_number)} turns per period"))
        if self.nonlinear is not None:
            rows.append(("nonlinear", self.nonlinear))
        if self.nearest_zone >= 0:
            where = "in" if self.stable else "nearest"
            rows.append((f"zone ({where})", f"n = {self.nearest_zone}: {_fmt(self.eps_lo)} < eps < {_fmt(self.eps_hi)}"))
            if self.T_lo is not None:
                rows.append(("", f"{_fmt(self.T_lo)} < T < {_fmt(self.T_hi)} s at this A"))
                rows.append(("", f"{_fmt(self.A_lo)} < A < {_fmt(self.A_hi)} m/s^2 at this T"))
            if self.frequency_lo is not None:
                f = self.frequency
                if np.isfinite(self.frequency_hi):
                    rows.append(("", f"{_fmt(self.frequency_lo, 6)} < frequency < {_fmt(self.frequency_hi, 6)} Hz at "
                                     f"this stroke ({_pct(self.frequency_lo, f)} / {_pct(self.frequency_hi, f)})"))
                else:
                    rows.append(("", f"frequency > {_fmt(self.frequency_lo, 6)} Hz at this stroke "
                                     f"({_pct(self.frequency_lo, f)}; no upper limit)"))
            if self.stroke_lo is not None:
                st, k, word = self.stroke, 1.0, "stroke"
                if self.given == "amplitude":
                    k, word = 0.5, "amplitude"
                rows.append(("", f"{_fmt(1e3 * k * self.stroke_lo, 6)} < {word} < {_fmt(1e3 * k * self.stroke_hi, 6)} mm "
                                 f"at this frequency ({_pct(self.stroke_lo, st)} / {_pct(self.stroke_hi, st)})"))
            for i, d in enumerate(self.directions):
                rows.append(("" if i else "to hold it" if not self.stable else "room", d["text"]))
        return rows

    def headline(self) -> str:
        where = f"T = {_fmt(self.T, 6)} s, A = {_fmt(self.A, 6)} m/s^2, " if self.T is not None else ""
        return f"{where}eps = {_fmt(self.eps, 6)}, mu = {_fmt(self.mu, 6)}: {self.verdict}"

    def as_dict(self) -> dict:
        """JSON-ready dictionary (complex multipliers as ``[re, im]`` pairs)."""
        d = asdict(self)
        d["directions"] = self.directions
        d["multipliers"] = [[float(z.real), float(z.imag)] for z in self.multipliers]
        return {k: (None if isinstance(v, float) and not np.isfinite(v) and k not in ("trace", "margin") else v)
                for k, v in d.items()}


def _safe_text(theta, periods, stable):
    """The safe tilt in words."""
    over = f" over {periods} periods" if periods else ""
    if not stable or not theta > 0:
        return "none: the upright is not stable, any tilt grows"
    return (f"stands for starting tilts from rest below {theta:.3g} rad ({math.degrees(theta):.3g} deg){over}; "
            "a larger start falls")


def _unstable_verdict(tau, nearest, eps, eps_lo):
    """The way of being unstable, in words a user recognises."""
    if nearest == 0 and eps <= eps_lo:
        return ("unstable: the drive is too weak to hold it up (it falls; below zone 0, "
                "one multiplier real and > 1)")
    if tau > 0:
        return "unstable: parametric resonance, 2T-type (multipliers real, positive)"
    return "unstable: parametric resonance, 4T-type, period doubling (multipliers real, negative)"


def _pct(edge, value):
    """The change from ``value`` to ``edge`` in percent, with its sign."""
    x = 100.0 * (edge / value - 1.0)
    return f"{x:+,.0f} %" if abs(x) >= 100 else f"{x:+.3g} %"


def _rig_margins(eps, mu, zone, drive, zeta, T, A, stroke):
    """Frequency interval of ``zone`` at this stroke and stroke interval at this frequency.

    At a fixed stroke ``A`` grows like ``f^2`` and ``T = 1/(2f)``, so ``eps`` is fixed and
    ``mu`` falls like ``1/f``; the zone is an interval of ``mu`` there (its edges ``eps_lo(mu)``,
    ``eps_hi(mu)`` both grow with ``mu``), found by bisection on the zone index read from the
    rotation angle. At a fixed frequency the stroke is proportional to ``A``.
    """
    if drive is None:
        return _square_rig_margins(eps, mu, zone, T, stroke)
    from .drives import as_drive
    from .drives._piecewise import _bisect_bits

    d = as_drive(drive)
    e = np.array([eps])
    z = np.array([zeta])

    def level(m):
        tau, growth, theta, st, zn, _ = d._floquet(np.broadcast_to(e, m.shape), m, np.broadcast_to(z, m.shape))
        return np.where(st, zn + 0.5, np.rint(theta / np.pi))

    # The angle falls as mu grows: [mu_lo, mu_hi] is where it lies in zone `zone`. Below
    # mu = 1e-6 (A > 1e12 g) nothing is searched: a zone reaching there has no upper frequency.
    lo, hi = np.full(1, 1e-6), np.full(1, 4.0)
    f = 0.5 / T
    out = dict(stroke=float(stroke))
    above = level(lo)[0] < zone + 1   # still in the zone (or below it) at the smallest mu
    mu_lo = lo if above else _bisect_bits(lambda m: level(m) < zone + 1, lo, hi)[0]
    if level(hi)[0] <= zone:
        mu_hi = _bisect_bits(lambda m: level(m) <= zone, lo, hi)[1]
    else:
        mu_hi = hi
    if mu_lo[0] < mu_hi[0]:
        out.update(frequency_lo=float(f * mu / mu_hi[0]),
                   frequency_hi=float("inf") if above else float(f * mu / mu_lo[0]))
    return out


_MU_MIN = 1e-6  # A = 1e12 g: a zone still open there has no upper frequency
_EPS_SERIES = 1e-5  # below this zone 0's lower edge is eps = sqrt(3/2) mu to rounding
_SQRT_3_2 = math.sqrt(1.5)


def _square_rig_margins(eps, mu, zone, T, stroke):
    """:func:`_rig_margins` for the undamped square wave, from the closed forms.

    At fixed ``eps`` both ``w - alpha`` and ``w - beta`` (``w = u - n pi``, ``docs/theory.md``
    section 5) decrease as ``mu`` grows (``u`` falls, ``alpha`` and ``beta`` rise), so zone ``n``
    is ``mu_b < mu < mu_a`` with ``w - alpha = 0`` at ``mu_a`` and ``w - beta = 0`` at ``mu_b``;
    both are found by regula falsi (:func:`kapitza._exact.illinois`) to an ulp or two of the
    gaps' rounding. Zone 0's lower gap is taken from :func:`kapitza._exact.lower_gap`, free of
    the cancellation of ``u`` against ``alpha`` as ``u -> 0``; that edge reaches every ``eps``
    (``eps_lo = sqrt(3/2) mu (1 + 4 mu^4 / 7 + ...)`` as ``mu -> 0``), so its search starts
    below ``eps / 2``, and below ``eps = 1e-5`` the series' first term is its value to rounding.
    """
    from . import _exact as X
    from .parameters import SQRT8

    n = float(zone)

    def gap(m, upper):
        p = np.sqrt(1.0 + m * m)
        q = np.sqrt((1.0 - m) * (1.0 + m))
        x, u = SQRT8 * eps * p, SQRT8 * eps * q
        with np.errstate(divide="ignore"):
            D = p / q
        w = u - n * np.pi
        return np.where(upper, w - X.beta_x(x, D), X.lower_gap(x, u, w, n, D, m))

    upper = np.array([False, True])
    lo = np.array([min(_MU_MIN, 0.5 * eps) if n == 0 else _MU_MIN, _MU_MIN])
    hi = np.full(2, 1.0 - 1e-12)
    f_lo = gap(lo, upper)
    out = dict(stroke=float(stroke))
    series = n == 0 and eps < _EPS_SERIES  # (then the gap at lo may underflow; its sign is known)
    if f_lo[0] <= 0.0 and not series:  # below the zone's lower edge at every mu: no frequency reaches it
        return out
    open_top = f_lo[1] < 0.0  # still in the zone at the smallest mu
    if series:
        roots = np.array([eps / _SQRT_3_2, X.illinois(lambda m: gap(m, upper[1:]), lo[1:], hi[1:], ulps=1.0)[0]])
    else:
        roots = X.illinois(lambda m: gap(m, upper), lo, hi, ulps=1.0)
    mu_a, mu_b = float(roots[0]), (0.0 if open_top else float(roots[1]))
    if mu_b < mu_a:
        f = 0.5 / T
        out.update(frequency_lo=float(f * mu / mu_a), frequency_hi=float("inf") if open_top else float(f * mu / mu_b))
    return out


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
    """
    rep = _analyze(eps, mu, T, A, l, g, drive, damping, zeta)
    if safe_tilt is not False and safe_tilt is not None:
        from .safety import with_safe_tilt

        rep = with_safe_tilt(rep, drive, None if safe_tilt is True else safe_tilt)
    return rep


def _analyze(eps, mu, T, A, l, g, drive, damping, zeta, pointwise=True):
    """:func:`analyze`; ``pointwise=False`` keeps every part on the array kernels (the path the
    scalar twins are tested and timed against)."""
    if pointwise and drive is None and zeta is None and _plain_zero(damping):
        rep = _plain_square(eps, mu, T, A, l, g)
        if rep is not None:
            return rep
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
    arnold = _v.parameter_set(eps, mu, T, A) == "arnold"
    physical = not arnold
    if arnold:
        if np.any(np.asarray(damping) != 0):
            raise _v.KapitzaValueError("with eps and mu give the damping as zeta = c / (2 sqrt(g/l)), not damping")
        eps = _v.one("eps", _v.positive("eps", eps))
        mu = _v.one("mu", _v.positive("mu", mu))
    else:
        if zeta is not None:
            raise _v.KapitzaValueError("with T and A give the damping as damping = c [1/s], not zeta")
        T = _v.one("T", _v.positive("T", T))
        A = _v.one("A", _v.positive("A", A))
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        eps, mu = (float(v) for v in to_arnold(T, A, l, g))
    if physical:
        c = _v.one("damping", _v.nonnegative("damping", damping))
        zeta_v = 0.5 * c * (np.sqrt(l) / np.sqrt(g)) if c > 0 else 0.0  # l / g may overflow
    else:
        c = None
        zeta_v = _v.one("zeta", _v.nonnegative("zeta", 0.0 if zeta is None else zeta))
    general, _ = _v.general_drive(drive, zeta_v)
    if general is not None:
        return _general_report(eps, mu, general, zeta_v, physical, T, A, l, g, c)
    return _square_report(eps, mu, physical, T, A, l, g, pointwise)


def _plain(v):
    """``v`` as a float if it is a Python number with ``0 < v < inf``, else None."""
    if type(v) is float:
        return v if 0.0 < v < math.inf else None
    if type(v) is int and 0 < v < 2**53:
        return float(v)
    return None


def _plain_zero(v):
    return (type(v) is float or type(v) is int) and v == 0


def _plain_square(eps, mu, T, A, l, g):
    """The square wave's report when every argument is a plain Python number that the validation
    would pass as it is (the common call), or None: then the full validation runs. Saves the
    dozen array conversions of the validation, a good part of a one-point answer."""
    if T is None and A is None:
        e, m = _plain(eps), _plain(mu)
        if e is None or m is None or type(l) not in (float, int) or type(g) not in (float, int):
            return None
        return _square_report(e, m, False, None, None, l, g)
    if eps is not None or mu is not None:
        return None
    T, A, l, g = _plain(T), _plain(A), _plain(l), _plain(g)
    if T is None or A is None or l is None or g is None or not math.isfinite(l / g):
        return None
    e, m = T * math.sqrt(A / (8.0 * l)), math.sqrt(g / A)  # kapitza.to_arnold, where it needs no split
    if not (0.0 < e < math.inf and 0.0 < m < math.inf):
        return None
    return _square_report(e, m, True, T, A, l, g)


def _square_report(eps, mu, physical, T, A, l, g, pointwise=True):
    """:func:`analyze` for the paper's undamped square wave (validated floats).

    With ``pointwise`` each part is first asked of its scalar twin in :mod:`kapitza._point`
    (Python floats: numpy's overhead per call on one-element arrays was most of the time); the
    array kernels answer wherever a twin declines -- within the rounding bound of an edge, where
    the verdict is decided in extended precision, or near a threshold of the nonlinear verdict --
    and everywhere with ``pointwise=False``, the path the twins are tested against.
    """
    fl = _point.floquet(eps, mu) if pointwise else None
    if fl is None:
        tau, growth, theta, stable, zone = (np.asarray(a)[()] for a in _floquet(eps, mu))
        mult = tuple(complex(z) for z in _multipliers(tau, growth, theta, stable))
        tau, growth, theta, stable, zone = float(tau), float(growth), float(theta), bool(stable), int(zone)
    else:
        tau, growth, theta, stable, zone = fl
        mult = _point.multipliers(tau, growth, theta, stable)
    mg = _point.stability_margin(eps, mu) if pointwise else None
    if mg is None:
        m = stability_margin(eps, mu)
        mg = (bool(m.stable), int(m.zone), float(m.eps_lo), float(m.eps_hi), float(m.margin))
    _, nz, eps_lo, eps_hi, margin = mg
    if mu >= 1.0:
        verdict = "always unstable: no elliptic phase (A <= g)"
    elif stable:
        verdict = f"stable (zone {zone})"
    else:
        verdict = _unstable_verdict(tau, nz, eps, eps_lo)
    phys = {}
    if physical:
        phys = dict(T=T, A=A, l=l, g=g)
        stroke = 0.25 * A * T * T
        phys["stroke"] = stroke
        if nz >= 0:
            rig = _point.rig_intervals(eps, mu, nz, T, A, l, g) if pointwise else None
            if rig is None:
                Tlo, Thi = period_edges(A, nz, l, g)
                Alo, Ahi = amplitude_edges(T, nz, l, g)
                rig = dict(T_lo=float(Tlo), T_hi=float(Thi), A_lo=float(Alo), A_hi=float(Ahi),
                           stroke_lo=float(stroke * Alo / A), stroke_hi=float(stroke * Ahi / A))
                rig.update(_rig_margins(eps, mu, nz, None, 0.0, T, A, stroke))
            phys.update(rig)
    nonlinear = None
    if stable:
        nonlinear = _point.nonlinear(eps, mu, theta, zone, exact_theta=fl is None) if pointwise else None
        if nonlinear is None:
            nonlinear = _sentence_of(eps, mu) if pointwise else str(nonlinear_stability(eps, mu))
    return StabilityReport(
        eps=float(eps),
        mu=float(mu),
        stable=stable,
        verdict=verdict,
        zone=zone,
        nearest_zone=nz,
        trace=2.0 * tau,
        multipliers=mult,
        growth=growth,
        rotation_number=theta / (2.0 * np.pi),
        eps_lo=eps_lo,
        eps_hi=eps_hi,
        margin=margin,
        trace_margin=1.0 - abs(tau),
        nonlinear=nonlinear,
        **phys,
    )


def _general_report(eps, mu, drive, zeta, physical, T, A, l, g, c):
    """:func:`analyze` for another drive or with damping (``docs/drives.md``)."""
    from .drives import _api

    e, m, z = np.asarray(eps, float), np.asarray(mu, float), np.asarray(zeta, float)
    trace, det, mult, growth, rho, stable, zone = (np.asarray(a)[()] for a in _api.floquet(e, m, drive, z))
    stable_m, nz, lo, hi, margin = (np.asarray(a)[()] for a in _api.margin(e, m, drive, z))
    stable = bool(stable)
    with np.errstate(over="ignore", divide="ignore"):  # tr M_phi / 2 = tr M / 2 * e^(cT), +-inf beyond doubles
        tau_phi = float(np.sign(trace) * np.exp(np.log(abs(float(trace)) / 2.0) + 2.0 * np.sqrt(8.0) * zeta * mu * eps))
    if stable:
        verdict = f"stable (zone {int(zone)})" + (", motions decay" if zeta > 0 else "")
    elif mu >= drive.mu_max:
        verdict = (f"always unstable: the pivot never accelerates down faster than g (mu >= {drive.mu_max:.6g}, "
                   f"the drive's mu_max)")
    elif np.all(np.isnan(lo)) and int(nz) < 0:
        verdict = "always unstable: the drive has no attracting phase at this mu"
    else:
        verdict = _unstable_verdict(tau_phi, int(nz), eps, float(lo))
    phys = {}
    if physical:
        phys = dict(T=T, A=A, l=l, g=g)
        if int(nz) >= 0:
            from .zones import amplitude_edges, period_edges

            Tlo, Thi = period_edges(A, int(nz), l, g, drive=drive, damping=c)
            Alo, Ahi = amplitude_edges(T, int(nz), l, g, drive=drive, damping=c)
            stroke = float(drive.stroke(T, A))
            phys.update(T_lo=float(Tlo), T_hi=float(Thi), A_lo=float(Alo), A_hi=float(Ahi),
                        stroke_lo=stroke * float(Alo) / A, stroke_hi=stroke * float(Ahi) / A)
            phys.update(_rig_margins(eps, mu, int(nz), drive, zeta, T, A, stroke))
        else:
            phys["stroke"] = float(drive.stroke(T, A))
    return StabilityReport(
        eps=float(eps), mu=float(mu), stable=stable, verdict=verdict,
        zone=int(zone) if stable else -1, nearest_zone=int(nz), trace=float(trace),
        multipliers=tuple(complex(x) for x in mult), growth=float(growth), rotation_number=float(rho),
        eps_lo=float(lo), eps_hi=float(hi), margin=float(margin),
        trace_margin=float(1.0 - abs(float(trace)) / (1.0 + float(det))),
        drive=drive.describe(), damping=c, zeta=float(zeta), determinant=float(det), **phys)
