"""The rig as an object: what swings (a :class:`~kapitza.Pendulum` or a tower, :class:`~kapitza.Chain`)
and how its pivot is driven (a drive); its questions asked in the rig's own units."""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from . import _validate as _v
from .chain import Chain
from .drives import Drive, as_drive
from .system import Pendulum

__all__ = ["Rig"]


@dataclass(frozen=True)
class Rig:
    """A pendulum and the drive of its pivot: the object the questions of a real rig are asked of.

    Parameters
    ----------
    pendulum : Pendulum or Chain
        What swings: one pendulum, or a tower of linked ones (:class:`kapitza.Chain`; its
        ``analyze`` also takes ``g``).
    drive : Drive or str, optional
        The paper's square wave by default.

    Raises
    ------
    ValueError
        If ``pendulum`` is not a :class:`kapitza.Pendulum` or :class:`kapitza.Chain`, or ``drive``
        names no drive; :meth:`analyze` and :meth:`physical` also when a value is out of range or
        the point is given twice or not at all.

    Examples
    --------
    A 30 cm rod on a shaker run at 40 Hz with a 20 mm stroke (square-wave acceleration):

    >>> import kapitza
    >>> rig = kapitza.Rig(kapitza.Pendulum.uniform_rod(0.3, damping=0.2))
    >>> rig.physical(frequency=40.0, stroke=0.02)
    (np.float64(0.0125), np.float64(511.99...))
    >>> report = rig.analyze(frequency=40.0, stroke=0.02)
    >>> report
    <StabilityReport: T = 0.0125 s, A = 512 m/s^2, eps = 0.223607, mu = 0.13842: stable (zone 0), motions decay>
    >>> round(report.frequency_lo, 2), report.frequency_hi
    (30.35, inf)
    >>> [r.stable for r in rig.analyze(frequency=[20.0, 40.0], stroke=0.02)]
    [False, True]
    """

    pendulum: Pendulum = field(default_factory=Pendulum)
    drive: Drive | str | None = None

    def __post_init__(self):
        if not isinstance(self.pendulum, (Pendulum, Chain)):
            raise _v.KapitzaValueError(f"pendulum must be a kapitza.Pendulum or kapitza.Chain; got {self.pendulum!r}")
        object.__setattr__(self, "drive", as_drive(self.drive))

    def arnold(self, T, A):
        """Arnold's ``(eps, mu)`` of the half-period ``T`` [s] and acceleration scale ``A`` [m/s^2]."""
        from .parameters import to_arnold

        return to_arnold(T, A, self.pendulum.l, self.pendulum.g)

    def physical(self, *, T=None, A=None, frequency=None, stroke=None, amplitude=None):
        """``(T, A)`` from either ``(T, A)`` or the frequency [Hz] with the stroke or the
        displacement amplitude [m] (or ``A``)."""
        if frequency is None:
            if T is None or A is None:
                raise _v.KapitzaValueError("give T and A, or the frequency with the stroke, amplitude or A")
            if stroke is not None or amplitude is not None:
                raise _v.KapitzaValueError("stroke and amplitude go with frequency, not with T and A")
            T_, A_ = np.broadcast_arrays(_v.positive("T", T), _v.positive("A", A))
            return T_[()], A_[()]
        if T is not None:
            raise _v.KapitzaValueError("give T or frequency, not both")
        T_, A_ = np.broadcast_arrays(*self.drive.from_rig(frequency, stroke=stroke, amplitude=amplitude,
                                                          acceleration=A))
        return T_[()], A_[()]

    def analyze(self, **kwargs):
        """The stability report of this rig at ``T, A`` or ``frequency`` with ``stroke``/``amplitude``/``A``;
        arrays (broadcast together) give an object array of reports of their shape."""
        from .analysis import analyze

        if not isinstance(self.pendulum, Pendulum):  # a Chain: the tower's report (docs/tower.md)
            return self.pendulum.analyze(drive=self.drive, **kwargs)
        T, A = self.physical(**kwargs)
        p = self.pendulum
        # the answers come in the quantity the point was given in (amplitude or stroke, as from the CLI)
        given = next((k for k in ("stroke", "amplitude") if kwargs.get(k) is not None), None)
        if given is None and kwargs.get("frequency") is not None:
            given = "A"

        def one(t, a):
            return replace(analyze(T=float(t), A=float(a), l=p.l, g=p.g, drive=self.drive, damping=p.damping),
                           pendulum=p.describe(), given=given)

        if np.ndim(T) == 0:
            return one(T, A)
        out = np.empty(np.shape(T), dtype=object)
        for i in np.ndindex(out.shape):
            out[i] = one(T[i], A[i])
        return out
