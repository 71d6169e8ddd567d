"""Drives: the pivot motions kapitza knows, one file each behind one protocol.

Every drive is ``a(t) = A s(t/T)`` over the period ``2T`` with ``s`` of zero mean, so that
Arnold's ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` mean the same for all of them and
their charts share axes (``docs/drives.md``):

- :class:`SquareWave` — the paper's (2.2), with its closed forms;
- :class:`RectangularWave` — any duty cycle;
- :class:`StepDrive` — any piecewise-constant acceleration;
- :class:`SineWave` — Kapitza's original (the Mathieu equation).

:data:`DRIVES` maps the names used on the command line to the classes; :func:`as_drive`
turns ``None``, a name or a drive into a drive.
"""
from __future__ import annotations

from .. import _validate as _v
from ._base import Drive
from .rectangular import RectangularWave
from .sampled import SampledDrive, from_samples
from .sine import SineWave
from .square import SquareWave
from .steps import StepDrive
from .triangle import TriangleWave

__all__ = ["Drive", "SquareWave", "RectangularWave", "StepDrive", "SineWave", "TriangleWave", "from_samples", "DRIVES", "as_drive", "parse_drive"]

#: Drive classes by the name the command line and the reports use.
DRIVES = {
    "square": SquareWave,
    "rectangular": RectangularWave,
    "steps": StepDrive,
    "sine": SineWave,
    "triangle": TriangleWave,
    "samples": SampledDrive,
}

_SQUARE = SquareWave()


def as_drive(drive) -> Drive:
    """The drive object for ``drive``: ``None`` (the square wave), a name without parameters
    (``"square"``, ``"sine"``), or a :class:`Drive` instance."""
    if drive is None:
        return _SQUARE
    if isinstance(drive, Drive):
        return drive
    if isinstance(drive, str) and drive in ("square", "sine"):
        return DRIVES[drive]()
    if isinstance(drive, type) and issubclass(drive, Drive):
        raise _v.KapitzaValueError(f"drive must be a drive instance, e.g. {drive.__name__}(...); got the class")
    raise _v.KapitzaValueError(
        "drive must be a kapitza drive (SquareWave(), RectangularWave(duty), StepDrive(levels, fractions), "
        f"SineWave()) or one of 'square', 'sine'; got {drive!r}")


def parse_drive(text: str) -> Drive:
    """A drive from its short text form, as the command line and the web take it.

    ``square``; ``sine``; ``rectangular:DUTY`` (e.g. ``rectangular:0.3``); ``steps:LEVELS:FRACTIONS``
    with comma-separated numbers (e.g. ``steps:2,-1,1,-1:0.2,0.3,0.2,0.3``).
    """
    if not isinstance(text, str) or not text.strip():
        raise _v.KapitzaValueError(f"drive must be a non-empty text such as 'square'; got {text!r}")
    name, _, rest = text.strip().partition(":")
    name = name.strip().lower()
    forms = "'square', 'sine', 'rectangular:DUTY' or 'steps:LEVELS:FRACTIONS'"
    if name in ("square", "sine"):
        if rest:
            raise _v.KapitzaValueError(f"drive '{name}' takes no parameters; got {text!r}")
        return DRIVES[name]()
    if name == "rectangular":
        if not rest:
            raise _v.KapitzaValueError(f"drive 'rectangular' needs its duty cycle, e.g. 'rectangular:0.3'; got {text!r}")
        return RectangularWave(_number("duty", rest))
    if name == "steps":
        levels, sep, fractions = rest.partition(":")
        if not sep:
            raise _v.KapitzaValueError(
                f"drive 'steps' needs levels and fractions, e.g. 'steps:2,-1,1,-1:0.2,0.3,0.2,0.3'; got {text!r}")
        return StepDrive([_number("levels", x) for x in levels.split(",")],
                         [_number("fractions", x) for x in fractions.split(",")])
    raise _v.KapitzaValueError(f"drive must be one of {forms}; got {text!r}")


def _number(name, text):
    try:
        return float(text)
    except ValueError:
        raise _v.KapitzaValueError(f"{name} must be a number; got {text.strip()!r}") from None
