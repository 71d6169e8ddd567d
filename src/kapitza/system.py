"""What swings: a pendulum (:class:`Pendulum`); the rig that drives it is :class:`kapitza.rig.Rig`.

A rigid body swinging about a pivot obeys the same equation as a point mass on a massless
rod of the *equivalent length* ``l = I / (m d)`` (``I`` its moment of inertia about the
pivot, ``m`` its mass, ``d`` the distance from the pivot to its centre of mass): a uniform
rod of length ``L`` pivoted at one end has ``l = 2 L / 3``. Every formula of kapitza uses
that ``l``. Viscous friction at the pivot adds ``c theta'`` (``c`` in 1/s): its damping
ratio ``zeta = c / (2 sqrt(g/l))`` is what Arnold's plane sees (``docs/drives.md``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import _validate as _v
from .parameters import G_EARTH

__all__ = ["Pendulum"]


def _scalar(name, value, *, positive=True):
    if np.ndim(value) != 0:
        raise _v.KapitzaValueError(f"{name} must be a single number; got {value!r}")
    if positive:
        return _v.one(name, _v.positive(name, value))
    v = _v.one(name, _v.finite(name, value))
    if v < 0:
        raise _v.KapitzaValueError(f"{name} must be finite and >= 0 (0 <= {name} < inf); got {v!r}")
    return v


@dataclass(frozen=True)
class Pendulum:
    """What swings about the pivot.

    Parameters
    ----------
    l : float
        Equivalent length [m] (``I / (m d)``), > 0.
    g : float
        Gravity [m/s^2], > 0.
    damping : float
        Viscous damping ``c`` [1/s] in ``theta'' + c theta' = ...``, >= 0.
    model : str
        What the length describes, for reports (``"point mass"``, ``"uniform rod"``, ...).
    size : float or None
        The body's own length [m] where it differs from ``l`` (a rod's length).

    Use :meth:`point_mass`, :meth:`uniform_rod` or :meth:`compound` to describe the body as
    it is measured.

    Raises
    ------
    ValueError
        If ``l`` or ``g`` is not finite and > 0, or ``damping`` is negative.

    Examples
    --------
    >>> import kapitza
    >>> rod = kapitza.Pendulum.uniform_rod(0.3, damping=0.2)
    >>> rod.l, rod.zeta
    (0.1999..., np.float64(0.0142...))
    >>> rod.describe()
    'uniform rod of length 0.3 m (equivalent length l = 0.2 m), damping c = 0.2 1/s (ratio 0.0142...)'
    >>> kapitza.Pendulum.compound(inertia=0.012, mass=0.4, distance=0.15).l
    0.2
    """

    l: float = 1.0
    g: float = G_EARTH
    damping: float = 0.0
    model: str = "point mass"
    size: float | None = field(default=None)

    def __post_init__(self):
        object.__setattr__(self, "l", _scalar("l", self.l))
        object.__setattr__(self, "g", _scalar("g", self.g))
        object.__setattr__(self, "damping", _scalar("damping", self.damping, positive=False))

    @classmethod
    def point_mass(cls, length, g=G_EARTH, damping=0.0):
        """A bob on a massless rod of ``length`` [m]: ``l = length``."""
        return cls(l=_scalar("length", length), g=g, damping=damping, model="point mass")

    @classmethod
    def uniform_rod(cls, length, g=G_EARTH, damping=0.0):
        """A uniform rod of ``length`` [m] pivoted at one end: ``l = 2 length / 3``."""
        L = _scalar("length", length)
        return cls(l=2.0 * L / 3.0, g=g, damping=damping, model="uniform rod", size=L)

    @classmethod
    def compound(cls, inertia, mass, distance, g=G_EARTH, damping=0.0):
        """Any rigid body: moment of inertia about the pivot [kg m^2], mass [kg], and the
        distance from the pivot to the centre of mass [m]: ``l = inertia / (mass distance)``."""
        I = _scalar("inertia", inertia)
        m = _scalar("mass", mass)
        d = _scalar("distance", distance)
        if I < m * d * d * (1.0 - 1e-12):
            raise _v.KapitzaValueError(
                f"inertia must be at least mass * distance^2 = {m * d * d!r} (parallel-axis theorem); got {I!r}")
        return cls(l=I / (m * d), g=g, damping=damping, model="compound pendulum", size=d)

    @property
    def zeta(self) -> float:
        """Damping ratio ``c / (2 sqrt(g/l))`` of the hanging pendulum."""
        return 0.5 * self.damping * np.sqrt(self.l / self.g)

    def describe(self) -> str:
        """One line saying which length the formulas use."""
        if self.model == "uniform rod":
            text = f"uniform rod of length {self.size:.6g} m (equivalent length l = {self.l:.6g} m)"
        elif self.model == "compound pendulum":
            text = f"compound pendulum, equivalent length l = {self.l:.6g} m"
        else:
            text = f"point mass on a massless rod, l = {self.l:.6g} m"
        if self.damping > 0:
            text += f", damping c = {self.damping:.6g} 1/s (ratio {self.zeta:.4g})"
        return text

    def as_dict(self) -> dict:
        return {"l": self.l, "g": self.g, "damping": self.damping, "model": self.model, "size": self.size,
                "zeta": self.zeta}
