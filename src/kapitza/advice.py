"""The margin as a direction: which knob to turn which way, and by how much.

A stability report knows the zone it refers to as intervals of each knob with the others held:
the frequency at a fixed stroke, the stroke (or amplitude) at a fixed frequency, ``T`` at a fixed
``A``, ``A`` at a fixed ``T``, ``eps`` at a fixed ``mu``. :func:`directions` turns each into one
record and one sentence a user can act on::

    raise the frequency to at least 95.9 Hz (+92 %), keeping the amplitude
    increase the amplitude to 5.76-75.9 mm (+92 % to +2,430 %), keeping the frequency

inside a zone the same records say how far each knob may go before stability is lost.
"""
from __future__ import annotations

import math

from ._display import digits_apart

__all__ = ["directions", "KNOBS"]

#: ``knob -> (unit, scale from SI to that unit, what is held)``.
KNOBS = {
    "frequency": ("Hz", 1.0, None),
    "stroke": ("mm", 1e3, "frequency"),
    "amplitude": ("mm", 1e3, "frequency"),
    "T": ("s", 1.0, "A"),
    "A": ("m/s^2", 1.0, "T"),
    "eps": ("", 1.0, "mu"),
}


def percent_change(edge, value):
    """The change from ``value`` to ``edge`` in percent, with its sign, as a report shows it ("no
    limit" for an infinite ``edge``; past a million per cent in scientific notation)."""
    if not math.isfinite(edge):
        return "no limit"
    x = 100.0 * (edge / value - 1.0)
    if abs(x) >= 1e6:   # (beside a tiny value: not a row of thousands' groups)
        return f"{x:+.3g} %"
    return f"{x:+,.0f} %" if abs(x) >= 100 else f"{x:+.3g} %"


def _plain(x, digits):
    """``x`` to ``digits`` significant digits, written out (``1,130``, ``0.0192``) between 1e-3 and 1e9;
    in powers of ten beyond (a user reads ``1.13e+03 mm`` badly)."""
    if x == 0 or not math.isfinite(x) or not 1e-3 <= abs(x) < 1e9:
        return f"{x:.{digits}g}"
    r = float(f"{x:.{digits}g}")
    text = f"{r:,.{max(0, digits - 1 - math.floor(math.log10(abs(r))))}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text   # as %g: no trailing zeros


def _record(knob, value, lo, hi, stable, held, zone, words=("raise", "lower")):
    """One direction: the interval ``(lo, hi)`` of ``knob`` (SI) that is zone ``zone`` with ``held`` fixed."""
    unit, scale, _ = KNOBS[knob]
    name = {"T": "the half-period T", "A": "the acceleration A", "eps": "eps"}.get(knob, f"the {knob}")
    u = f" {unit}" if unit else ""
    v, a, b = value * scale, lo * scale, hi * scale
    dg = digits_apart(v, a, b)

    def _num(x):
        return _plain(x, dg)

    rng = f"{_num(a)}-{_num(b)}{u}" if math.isfinite(b) else f"at least {_num(a)}{u}"
    keep = (f", keeping {held}" if held in ("mu", "T", "A") else f", keeping the {held}") if held else ""
    if stable:
        action = "keep"
        if math.isfinite(b):
            text = (f"{name} may range over {_num(a)}-{_num(b)}{u} ({percent_change(lo, value)} / "
                    f"{percent_change(hi, value)}){keep}; outside it the upright falls")
        else:
            text = f"{name} may fall to {_num(a)}{u} ({percent_change(lo, value)}; no upper limit){keep}"
    elif value < lo:
        action = words[0]
        change = (percent_change(lo, value) if not math.isfinite(b)
                  else f"{percent_change(lo, value)} to {percent_change(hi, value)}")
        text = f"{action} {name} to {rng} ({change}){keep}"
    else:
        action = words[1]
        change = (f"{percent_change(hi, value)} to {percent_change(lo, value)}" if math.isfinite(hi)
                  else percent_change(lo, value))
        text = f"{action} {name} to {rng} ({change}){keep}"
    return dict(knob=knob, unit=unit, value=v, lo=a, hi=b if math.isfinite(b) else None, holding=held,
                action=action, zone=zone, change_lo=100.0 * (lo / value - 1.0),
                change_hi=100.0 * (hi / value - 1.0) if math.isfinite(hi) else None, text=text)


def directions(report, given=None) -> list[dict]:
    """How to reach (or how far one may leave) ``report.nearest_zone``, one record per knob.

    Parameters
    ----------
    report : StabilityReport
    given : str, optional
        The amplitude the user gave: ``"amplitude"`` (half the stroke), ``"stroke"`` or ``"A"``;
        the answers come in that quantity (by default: ``stroke`` when the report has rig
        intervals, else ``A``).

    Returns
    -------
    list of dict
        ``knob``, ``unit``, ``value`` (now), ``lo``, ``hi`` (the zone's interval in that unit,
        ``hi`` None when unbounded), ``holding`` (the knob kept fixed), ``action`` (``raise``,
        ``lower``, ``increase``, ``decrease``, or ``keep`` inside the zone), ``change_lo``,
        ``change_hi`` (percent), ``text`` (the sentence). Empty where no zone is near.
    """
    r = report
    if r.nearest_zone < 0:
        return []
    out = []
    n, st = r.nearest_zone, bool(r.stable)
    if r.T is not None:
        f = 0.5 / r.T
        if r.frequency_lo is not None and r.frequency_hi is not None:
            held = "amplitude" if given == "amplitude" else "stroke" if given in ("stroke", None) else "stroke"
            out.append(_record("frequency", f, r.frequency_lo, r.frequency_hi, st, held, n))
        if given in ("amplitude", "stroke") or (given is None and r.stroke_lo is not None):
            if r.stroke_lo is not None and r.stroke is not None:
                k = 0.5 if given == "amplitude" else 1.0
                out.append(_record("amplitude" if given == "amplitude" else "stroke", k * r.stroke, k * r.stroke_lo,
                                   k * r.stroke_hi, st, "frequency", n, ("increase", "decrease")))
        else:
            if r.A_lo is not None:
                out.append(_record("A", r.A, r.A_lo, r.A_hi, st, "T", n, ("increase", "decrease")))
            if r.T_lo is not None:
                out.append(_record("T", r.T, r.T_lo, r.T_hi, st, "A", n, ("lengthen", "shorten")))
    elif math.isfinite(r.eps_lo) and math.isfinite(r.eps_hi):
        out.append(_record("eps", r.eps, r.eps_lo, r.eps_hi, st, "mu", n))
    return out
