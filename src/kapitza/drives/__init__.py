"""Drives: the pivot motions kapitza knows, one file each behind one contract.

Every drive is ``a(t) = A s(t/T)`` over the period ``2T`` with ``s`` of zero mean, so that
Arnold's ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` mean the same for all of them and
their charts share axes (``docs/drives.md``):

- :class:`SquareWave` -- the paper's (2.2), with its closed forms;
- :class:`RectangularWave` -- any duty cycle;
- :class:`StepDrive` -- any piecewise-constant acceleration;
- :class:`SineWave` -- Kapitza's original (the Mathieu equation);
- :class:`TriangleWave` -- acceleration linear between ``+A`` and ``-A``;
- :func:`from_samples` -- a measured drive, from one period of sampled acceleration.

Drives are found by name in one registry (:data:`DRIVES`), which a user's own
:class:`Drive` subclass joins with :func:`register`; the command line, the web API and the
sweep specification read their choices from it. :func:`as_drive` turns ``None``, a drive, a
registered name or a drive's text form (``"rectangular:0.3"``) into a drive; every function of
kapitza that takes ``drive=`` accepts all of these.
"""
from __future__ import annotations

from .. import _validate as _v
from ._base import Drive
from .rectangular import RectangularWave
from .sampled import SampledDrive, from_samples  # noqa: F401  (SampledDrive re-exported: kapitza.drives.SampledDrive)
from .sine import SineWave
from .square import SquareWave
from .steps import StepDrive
from .triangle import TriangleWave

__all__ = ["Drive", "SquareWave", "RectangularWave", "StepDrive", "SineWave", "TriangleWave", "from_samples",
           "DRIVES", "register", "as_drive", "parse_drive", "text_forms"]

#: Drive classes by the name the command line, the web API and the reports use (:func:`register` adds one).
DRIVES: dict[str, type[Drive]] = {}


def register(cls=None, *, name=None):
    """Add a :class:`Drive` subclass to the registry under ``name`` (its :attr:`Drive.name` by
    default), so that :func:`parse_drive`, :func:`as_drive`, the command line and the web API find
    it. Usable as a decorator (``@register``). Returns the class.

    Its text form is ``NAME`` or ``NAME:PARAMETERS``, read by the class's
    :meth:`Drive.from_text`; a name already taken by another class is refused.

    Parameters
    ----------
    cls : type, optional
        A subclass of :class:`Drive`; omitted when used as ``@register(name=...)``.
    name : str, optional
        A lower-case word without ``:``.

    Returns
    -------
    type
        ``cls`` (or, without it, a decorator that registers its class).

    Raises
    ------
    ValueError
        If ``cls`` is not a :class:`Drive` subclass, or the name is not a lower-case word or is
        taken by another class.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> from kapitza.drives import register, parse_drive
    >>> @register
    ... class Sawtooth(kapitza.Drive):
    ...     name = "my-sawtooth"
    ...     _breakpoints = (1.0,)
    ...     def _shape(self, tau):
    ...         return np.where(tau < 1.0, tau, tau - 2.0)
    >>> parse_drive("my-sawtooth")
    Sawtooth()
    >>> kapitza.zone_edges(0.3, 0, drive="my-sawtooth")
    (np.float64(0.7206...), np.float64(1.0404...))
    >>> register(kapitza.SineWave, name="my-sawtooth")
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: the drive name 'my-sawtooth' is taken by Sawtooth
    >>> from kapitza.drives import DRIVES
    >>> del DRIVES["my-sawtooth"]  # the registry as it was
    """
    def add(c):
        if not (isinstance(c, type) and issubclass(c, Drive)):
            raise _v.KapitzaValueError(f"register takes a subclass of kapitza.drives.Drive; got {c!r}")
        key = (name if name is not None else c.name)
        if not isinstance(key, str) or not key.strip() or ":" in key or key != key.strip().lower():
            raise _v.KapitzaValueError(f"a drive's name must be a lower-case word without ':'; got {key!r}")
        if DRIVES.get(key, c) is not c:
            raise _v.KapitzaValueError(f"the drive name {key!r} is taken by {DRIVES[key].__name__}")
        DRIVES[key] = c
        return c

    return add if cls is None else add(cls)


# A measured drive (SampledDrive) is built from its samples (from_samples, --drive-file), not from a name.
for _cls in (SquareWave, RectangularWave, StepDrive, SineWave, TriangleWave):
    register(_cls)

_SQUARE = SquareWave()


def text_forms() -> list[str]:
    """The text forms of the registered drives (``square``, ``rectangular:DUTY``, ...), for help texts.

    Returns
    -------
    list of str

    Examples
    --------
    >>> from kapitza.drives import text_forms
    >>> text_forms()[:5]
    ['square', 'rectangular:DUTY', 'steps:LEVELS:FRACTIONS', 'sine', 'triangle']
    """
    return [c.text_form or key for key, c in DRIVES.items()]


def as_drive(drive) -> Drive:
    """The drive object for ``drive``: ``None`` (the square wave), a :class:`Drive` instance, or a
    text (a registered name, or a text form such as ``"rectangular:0.3"``: :func:`parse_drive`).

    Parameters
    ----------
    drive : None, Drive or str

    Returns
    -------
    Drive

    Raises
    ------
    ValueError
        If ``drive`` is none of these, a class rather than an instance, or a text naming no drive.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.drives import as_drive
    >>> as_drive(None), as_drive("rectangular:0.3"), as_drive(kapitza.SineWave())
    (SquareWave(), RectangularWave(duty=0.3), SineWave())
    >>> as_drive(kapitza.SineWave)
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: drive must be a drive instance, e.g. SineWave(...); got the class
    """
    if drive is None:
        return _SQUARE
    if isinstance(drive, Drive):
        return drive
    if isinstance(drive, str):
        return parse_drive(drive)
    if isinstance(drive, type) and issubclass(drive, Drive):
        raise _v.KapitzaValueError(f"drive must be a drive instance, e.g. {drive.__name__}(...); got the class")
    raise _v.KapitzaValueError(
        f"drive must be a kapitza drive (a Drive instance) or its text form ({', '.join(text_forms())}); "
        f"got {drive!r}")


def parse_drive(text: str) -> Drive:
    """A drive from its short text form, as the command line and the web take it.

    ``NAME`` or ``NAME:PARAMETERS`` for a registered name: ``square``; ``sine``;
    ``rectangular:DUTY`` (e.g. ``rectangular:0.3``); ``steps:LEVELS:FRACTIONS`` with
    comma-separated numbers (e.g. ``steps:2,-1,1,-1:0.2,0.3,0.2,0.3``).

    Parameters
    ----------
    text : str

    Returns
    -------
    Drive

    Raises
    ------
    ValueError
        If ``text`` is empty, names no registered drive, or its parameters are not the drive's.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.parse_drive("sine")
    SineWave()
    >>> kapitza.parse_drive("steps:2,-1,1,-1:0.2,0.3,0.2,0.3")
    StepDrive(levels=[2.0, -1.0, 1.0, -1.0], fractions=[0.2, 0.3, 0.2, 0.3])
    >>> kapitza.parse_drive("rectangular:1.5")
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: duty must lie in [1e-06, 0.999999]; got 1.5
    """
    if not isinstance(text, str) or not text.strip():
        raise _v.KapitzaValueError(f"drive must be a non-empty text such as 'square'; got {text!r}")
    name, sep, rest = text.strip().partition(":")
    name = name.strip().lower()
    cls = DRIVES.get(name)
    if cls is None:
        forms = ", ".join(repr(f) for f in text_forms())
        raise _v.KapitzaValueError(f"drive must be one of {forms}; got {text!r}")
    return cls.from_text(rest.strip() if sep else None, text)
