"""How results print: a short ``repr``, a table for ``print`` and an HTML table in Jupyter.

A result class lists its rows once, in ``lines()`` (``(label, text)`` pairs), and a one-line
``headline()``; this mixin turns them into ``__str__`` (the table the command line prints),
``__repr__`` (``<Name: headline>``, never whole arrays) and ``_repr_html_``. Dataclasses using it
are declared with ``repr=False`` so that the generated field-by-field ``repr`` does not win.
"""
from __future__ import annotations

import html

import numpy as np


class Summary:
    """Mixin for result objects: ``lines()`` and ``headline()`` give ``str``, ``repr`` and HTML."""

    def lines(self) -> list[tuple[str, str]]:  # pragma: no cover - every user overrides it
        raise NotImplementedError

    def headline(self) -> str:  # pragma: no cover - every user overrides it
        raise NotImplementedError

    def __str__(self) -> str:
        return "\n".join(f"{k:<16} {v}" for k, v in self.lines())

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self.headline()}>"

    def _repr_html_(self) -> str:
        body = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th><td style='text-align:left'>"
                       f"{html.escape(v)}</td></tr>" for k, v in self.lines())
        return f"<table><caption style='text-align:left'>{html.escape(type(self).__name__)}</caption>{body}</table>"


def num(v, digits=6) -> str:
    """A number for a summary line (``g`` format; ``-`` for None)."""
    if v is None:
        return "-"
    return f"{float(v):.{digits}g}"


def digits_apart(*values, least=3) -> int:
    """Significant digits that tell ``values`` apart (``least`` at least, 17 at most: the ends of a
    range a few doubles wide are not written as one number twice; None and non-finite values aside)."""
    vals = [float(v) for v in values if v is not None and np.isfinite(v)]
    for d in range(least, 18):
        if len({f"{v:.{d}g}" for v in vals}) == len(set(vals)):
            return d
    return 17


def span(values, digits=6) -> str:
    """``min .. max`` of an array (one number if they agree; NaN ignored)."""
    a = np.asarray(values, dtype=float)
    fin = a[np.isfinite(a)] if a.size else a
    if fin.size == 0:
        return "-" if a.size == 0 else num(a.flat[0], digits)
    lo, hi = float(fin.min()), float(fin.max())
    return num(lo, digits) if lo == hi else f"{num(lo, digits)} .. {num(hi, digits)}"


def shape_of(a) -> str:
    """``"one point"`` or ``"shape (m, n): k points"``."""
    a = np.asarray(a)
    return "one point" if a.ndim == 0 else f"shape {a.shape}: {a.size:,} points"


def stable_share(stable) -> str:
    """``"shape (m, n): k points, p% stable"`` for an array of verdicts."""
    return f"{shape_of(stable)}, {100 * float(np.mean(stable)):.4g}% stable"


def multipliers(values) -> str:
    """Floquet multipliers as ``a+bi, a-bi`` (real ones without an imaginary part), 10 digits."""
    return ", ".join(f"{z.real:.10g}{z.imag:+.10g}i" if z.imag else f"{z.real:.10g}"
                     for z in np.ravel(np.asarray(values, dtype=complex)))
