"""What a sweep computes: the parameter grid, the quantities and their settings."""
from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from ..drives import as_drive, parse_drive
from ..parameters import G_EARTH
from .kernel import QUANTITIES

__all__ = ["SweepSpec", "PLANES", "MAX_POINTS"]

#: ``plane -> ((x name, x units), (y name, y units))``: columns and rows of the map.
PLANES = {"arnold": (("eps", "1"), ("mu", "1")), "physical": (("T", "s"), ("A", "m/s^2"))}
#: Largest grid a sweep accepts (points), and largest side.
MAX_POINTS = 4096 * 4096
MAX_SIDE = 8192


@dataclass(frozen=True)
class SweepSpec:
    """A sweep over a rectangular grid of parameters.

    Attributes
    ----------
    plane : {'arnold', 'physical'}
        Columns ``x`` and rows ``y`` are ``(eps, mu)`` or ``(T [s], A [m/s^2])``.
    x, y : tuple of float
        Grid values, each > 0 (``mu`` may be >= 1: ``A <= g``, unstable).
    l, g : float
        Rod length [m] and gravity [m/s^2]; on Arnold's plane the quantities do not depend on them
        (angles and ``dtheta T`` are scale-free).
    drive : str
        A piecewise-constant drive in its text form (``square``, ``rectangular:D``, ``steps:...``).
    periods : int
        ``N``, periods ``2T`` each start must stay within ``tol``.
    tol : float
        Window half-width [rad], ``0 < tol < pi``.
    quantities : tuple of str
        Among ``tilt``, ``radius``, ``basin``, ``linear`` (:data:`kapitza.sweeps.kernel.QUANTITIES`).
    directions : int
        Directions of the phase plane for ``radius``.
    basin_resolution : int
        Start grid ``n x n`` for ``basin``.
    accuracy : float
        Relative width of the final bisection bracket (0.01: 1 %).
    floor : float
        Smallest radius tried [rad]; a radius below it is reported as 0.
    chunk : int
        Points per side of a chunk (the unit of work, of storage and of resumption).
    """

    plane: str
    x: tuple
    y: tuple
    l: float = 1.0
    g: float = G_EARTH
    drive: str = "square"
    periods: int = 200
    tol: float = 0.5
    quantities: tuple = ("tilt", "linear")
    directions: int = 8
    basin_resolution: int = 21
    accuracy: float = 0.01
    floor: float = 1e-4
    chunk: int = 32

    def __post_init__(self):
        s = object.__setattr__
        if self.plane not in PLANES:
            raise _v.KapitzaValueError(f"plane must be one of 'arnold', 'physical'; got {self.plane!r}")
        names = PLANES[self.plane]
        for attr, (name, _) in zip(("x", "y"), names):
            arr = np.atleast_1d(_v.positive(name, getattr(self, attr))).astype(float)
            if arr.ndim != 1 or not 1 <= arr.size <= MAX_SIDE:
                raise _v.KapitzaValueError(f"{name} must be 1 to {MAX_SIDE} grid values; got {arr.size}")
            s(self, attr, tuple(float(v) for v in arr))
        if len(self.x) * len(self.y) > MAX_POINTS:
            raise _v.KapitzaValueError(f"the grid must have at most {MAX_POINTS} points; got {len(self.x) * len(self.y)}")
        s(self, "l", _v.one("l", _v.positive("l", self.l)))
        s(self, "g", _v.one("g", _v.positive("g", self.g)))
        d = parse_drive(self.drive) if isinstance(self.drive, str) else as_drive(self.drive)
        if not hasattr(d, "levels"):
            raise _v.KapitzaValueError(f"drive must be piecewise constant for a sweep (square, rectangular, steps); "
                                       f"got {d.describe()}")
        s(self, "drive", _drive_text(d))
        s(self, "periods", _v.bounded_count("periods", self.periods, 1_000_000, minimum=1))
        s(self, "tol", _v.one("tol", _v.in_range("tol", self.tol, 0.0, np.pi)))
        s(self, "quantities", _v.choices("quantities", self.quantities, tuple(QUANTITIES)))
        s(self, "directions", _v.bounded_count("directions", self.directions, 256, minimum=1))
        s(self, "basin_resolution", _v.bounded_count("basin_resolution", self.basin_resolution, 401, minimum=2))
        s(self, "accuracy", _v.one("accuracy", _v.in_range("accuracy", self.accuracy, 1e-6, 1.0, lo_open=False)))
        s(self, "floor", _v.one("floor", _v.in_range("floor", self.floor, 0.0, self.tol)))
        s(self, "chunk", _v.bounded_count("chunk", self.chunk, 1024, minimum=1))

    # ------------------------------------------------------------------ construction
    @classmethod
    def window(cls, x_range, y_range, resolution, plane="arnold", **kw) -> "SweepSpec":
        """A regular grid: ``resolution = (nx, ny)`` (or one int for both) points over each range."""
        nx, ny = (resolution, resolution) if np.ndim(resolution) == 0 else resolution
        names = PLANES.get(plane, (("x", ""), ("y", "")))
        nx = _v.bounded_count(f"resolution ({names[0][0]})", nx, MAX_SIDE, minimum=1)
        ny = _v.bounded_count(f"resolution ({names[1][0]})", ny, MAX_SIDE, minimum=1)
        for (name, _), r in zip(names, (x_range, y_range)):
            lo, hi = (float(v) for v in _v.positive(f"{name} range", r))
            if not lo <= hi:
                raise _v.KapitzaValueError(f"{name} range must be (low, high) with low <= high; got ({lo!r}, {hi!r})")
        return cls(plane=plane, x=tuple(np.linspace(*x_range, nx)), y=tuple(np.linspace(*y_range, ny)), **kw)

    # ------------------------------------------------------------------ layout
    @property
    def dims(self):
        """``(y name, x name)``: the dimensions of every map."""
        return PLANES[self.plane][1][0], PLANES[self.plane][0][0]

    @property
    def shape(self):
        return len(self.y), len(self.x)

    @property
    def chunk_shape(self):
        """Chunks along ``(y, x)``."""
        return tuple(-(-n // self.chunk) for n in self.shape)

    def chunk_slices(self, iy, ix):
        c = self.chunk
        return slice(iy * c, min((iy + 1) * c, self.shape[0])), slice(ix * c, min((ix + 1) * c, self.shape[1]))

    def all_chunks(self):
        ny, nx = self.chunk_shape
        return [(iy, ix) for iy in range(ny) for ix in range(nx)]

    @property
    def variables(self):
        """Variables written, in order."""
        return tuple(v for q in self.quantities for v in QUANTITIES[q])

    def as_dict(self) -> dict:
        """Everything that fixes the result (stored with it; resuming demands the same)."""
        return {k: getattr(self, k) for k in ("plane", "x", "y", "l", "g", "drive", "periods", "tol", "quantities",
                                              "directions", "basin_resolution", "accuracy", "floor", "chunk")}

    def to_json(self) -> str:
        return json.dumps({k: list(v) if isinstance(v, tuple) else v for k, v in self.as_dict().items()},
                          sort_keys=True)

    @classmethod
    def from_json(cls, text) -> "SweepSpec":
        return cls(**json.loads(text))


def _drive_text(d) -> str:
    """The text form :func:`kapitza.parse_drive` reads back."""
    if d.name == "square":
        return "square"
    if d.name == "rectangular":
        return f"rectangular:{d.duty!r}"
    return "steps:" + ",".join(repr(float(v)) for v in d.levels) + ":" + ",".join(repr(float(v)) for v in d.fractions)
