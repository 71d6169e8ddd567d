"""What a sweep computes: the parameter grid, the quantities and their settings."""
from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from ..drives import as_drive, parse_drive
from ..parameters import G_EARTH
from ..motion.basins import INTEGRATED_STEP_COST, MAX_INTEGRATED_STATE_PERIODS, exact_path, integrated_work
from .kernel import QUANTITIES

__all__ = ["SweepSpec", "PLANES", "MAX_POINTS", "MAX_INTEGRATED_SWEEP"]

#: ``plane -> ((x name, x units), (y name, y units))``: columns and rows of the map.
PLANES = {"arnold": (("eps", "1"), ("mu", "1")), "physical": (("T", "s"), ("A", "m/s^2")),
          "rig": (("frequency", "Hz"), ("stroke", "m"))}
#: Planes whose window is spaced geometrically (drawn on log axes).
GEOMETRIC = ("rig",)
#: Largest grid a sweep accepts (points), and largest side.
MAX_POINTS = 4096 * 4096
MAX_SIDE = 8192
#: Largest estimated work of a sweep on the integrated path (state-periods, :meth:`SweepSpec.integrated_work`):
#: about an hour on one core (``KAPITZA_ALLOW_LARGE=1`` lifts it, e.g. for a cluster).
MAX_INTEGRATED_SWEEP = 60 * MAX_INTEGRATED_STATE_PERIODS
#: How much more of that work the compiled integrator (numba, the ``fast`` extra) does in the same hour:
#: about 0.4 us of CPU per estimated state-period on a chart where every point stands (the dearest
#: case; measured 2026-11-27, damped square wave, 300 periods), against about 20 us for DOP853 in numpy.
COMPILED_INTEGRATED_SPEEDUP = 40


@dataclass(frozen=True)
class SweepSpec:
    """A sweep over a rectangular grid of parameters.

    Attributes
    ----------
    plane : {'arnold', 'physical', 'rig'}
        Columns ``x`` and rows ``y`` are ``(eps, mu)``, ``(T [s], A [m/s^2])`` or, as a rig is set,
        ``(frequency [Hz], stroke [m])``: the drive frequency ``f = 1 / (2T)`` and the stroke (peak-to-peak
        travel of the pivot) ``s = k A T^2`` with the drive's stroke coefficient ``k``
        (:func:`kapitza.rig_plane.stroke_coefficient`), so a point is ``T = 1 / (2f)``, ``A = s / (k T^2)``.
    x, y : tuple of float
        Grid values, each > 0 (``mu`` may be >= 1: ``A <= g``, unstable).
    l, g : float
        Rod length [m] and gravity [m/s^2]; on Arnold's plane the quantities do not depend on them
        (angles and ``dtheta T`` are scale-free).
    drive : str
        The drive in its text form (``square``, ``sine``, ``rectangular:D``, ``steps:...``).
    c : float
        Viscous damping [1/s], ``>= 0``, in ``theta'' = s sin(theta) - c theta'`` (as
        :func:`kapitza.motion.survival`); the damping ratio is ``zeta = c / (2 sqrt(g/l))``
        (on Arnold's plane give ``c = 2 zeta sqrt(g/l)`` for a scale-free map). An undamped
        piecewise-constant drive is followed exactly; the sine drive or ``c > 0`` by DOP853, far
        slower and bounded (:meth:`integrated_work`, ``docs/sweeps.md``).
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

    Raises
    ------
    ValueError
        If a value is out of range: a grid value not > 0, an unknown plane, drive or quantity, a
        count beyond its bound, or (the integrated path) more work than one sweep may take.

    Examples
    --------
    >>> from kapitza.sweeps import SweepSpec
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("tilt", "linear"), periods=10, chunk=2)
    >>> spec.x, spec.y
    ((0.3, 0.5, 0.7000..., 0.9), (0.2, 0.3000..., 0.4))
    >>> spec.dims, spec.shape, spec.chunk_shape
    (('mu', 'eps'), (3, 4), (2, 2))
    >>> spec.variables
    ('max_safe_tilt', 'stable', 'zone', 'growth', 'margin')
    >>> spec.exact, spec.integrated_work()
    (True, 0.0)
    >>> SweepSpec.window((0.3, 0.9), (0.2, 0.4), 4, quantities=("speed",))
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: quantities must be among 'tilt', 'radius', 'basin', 'linear'; got 'speed'
    """

    plane: str
    x: tuple
    y: tuple
    l: float = 1.0
    g: float = G_EARTH
    drive: str = "square"
    c: float = 0.0
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
            raise _v.KapitzaValueError(f"plane must be one of 'arnold', 'physical', 'rig'; got {self.plane!r}")
        names = PLANES[self.plane]
        for attr, (name, _) in zip(("x", "y"), names):
            arr = np.atleast_1d(_v.positive(name, getattr(self, attr))).astype(float)
            if arr.ndim != 1 or not 1 <= arr.size <= MAX_SIDE:
                raise _v.KapitzaValueError(f"{name} must be 1 to {MAX_SIDE} grid values; got {arr.size}")
            s(self, attr, tuple(float(v) for v in arr))
        if len(self.x) * len(self.y) > MAX_POINTS:
            raise _v.KapitzaValueError(f"the grid must have at most {MAX_POINTS} points; got "
                                       f"{len(self.x) * len(self.y)}")
        s(self, "l", _v.one("l", _v.positive("l", self.l)))
        s(self, "g", _v.one("g", _v.positive("g", self.g)))
        d = parse_drive(self.drive) if isinstance(self.drive, str) else as_drive(self.drive)
        s(self, "drive", d.text())
        s(self, "c", float(_v.one("c", _v.nonnegative("c", self.c))))
        s(self, "periods", _v.bounded_count("periods", self.periods, 1_000_000, minimum=1))
        s(self, "tol", _v.one("tol", _v.in_range("tol", self.tol, 0.0, np.pi)))
        s(self, "quantities", _v.choices("quantities", self.quantities, tuple(QUANTITIES)))
        s(self, "directions", _v.bounded_count("directions", self.directions, 256, minimum=1))
        s(self, "basin_resolution", _v.bounded_count("basin_resolution", self.basin_resolution, 401, minimum=2))
        s(self, "accuracy", _v.one("accuracy", _v.in_range("accuracy", self.accuracy, 1e-6, 1.0, lo_open=False)))
        s(self, "floor", _v.floor_below(self.floor, self.tol))
        s(self, "chunk", _v.bounded_count("chunk", self.chunk, 1024, minimum=1))
        if not self.exact:
            compiled = self.compiled_integrator
            _v.bounded_work("the sweep's estimated DOP853 work (sine drive or damping): points * periods * "
                            "(6 * searched directions + basin_resolution^2 / 2) * max(1, (w_h + c) 2T / 3)",
                            self.integrated_work(),
                            MAX_INTEGRATED_SWEEP * (COMPILED_INTEGRATED_SPEEDUP if compiled else 1),
                            what="state-periods integrated by DOP853, about an hour on one core"
                                 + ("" if compiled else " (the compiled integrator, pip install 'kapitza[fast]', "
                                                        f"does {COMPILED_INTEGRATED_SPEEDUP} times as much)")
                                 + "; the exact path (an undamped square, rectangular or steps drive) is far cheaper")

    # ------------------------------------------------------------------ construction
    @classmethod
    def window(cls, x_range, y_range, resolution, plane="arnold", **kw) -> "SweepSpec":
        """A regular grid: ``resolution = (nx, ny)`` (or one int for both) points over each range, evenly
        spaced (geometrically on the rig plane, whose map is drawn on log axes: ``f`` and ``s`` span decades).

        Examples
        --------
        >>> spec = SweepSpec.window((10.0, 40.0), (0.001, 0.004), 3, plane="rig", quantities=("linear",))
        >>> spec.dims, spec.x, spec.y
        (('stroke', 'frequency'), (10.0, 20.0..., 40.0), (0.001, 0.002..., 0.004))
        """
        nx, ny = (resolution, resolution) if np.ndim(resolution) == 0 else resolution
        names = PLANES.get(plane, (("x", ""), ("y", "")))
        nx = _v.bounded_count(f"resolution ({names[0][0]})", nx, MAX_SIDE, minimum=1)
        ny = _v.bounded_count(f"resolution ({names[1][0]})", ny, MAX_SIDE, minimum=1)
        ends = []
        for (name, _), r in zip(names, (x_range, y_range)):
            lo, hi = (float(v) for v in _v.positive(f"{name} range", r))
            if not lo <= hi:
                raise _v.KapitzaValueError(f"{name} range must be (low, high) with low <= high; got ({lo!r}, {hi!r})")
            ends.append((lo, hi))
        axes = []
        for (lo, hi), n in zip(ends, (nx, ny)):
            if plane in GEOMETRIC:
                v = np.geomspace(lo, hi, n)
                v[0], v[-1] = (lo, lo) if n == 1 else (lo, hi)  # the ends as given (geomspace rounds them)
            else:
                v = np.linspace(lo, hi, n)
            axes.append(tuple(float(a) for a in v))
        return cls(plane=plane, x=axes[0], y=axes[1], **kw)

    # ------------------------------------------------------------------ path and work
    @property
    def exact(self) -> bool:
        """Whether the motion is followed exactly (an undamped piecewise-constant drive); otherwise
        by DOP853 with the window checked at sampled instants (:func:`kapitza.motion.survival`)."""
        return exact_path(parse_drive(self.drive), self.c)

    @property
    def compiled_integrator(self) -> bool:
        """Whether the integrated path runs in the compiled kernel: numba is installed and the drive
        describes its shape to it (:meth:`kapitza.drives.Drive._shape_table`)."""
        from .kernel import compiled_available

        return (not self.exact) and compiled_available() and parse_drive(self.drive)._shape_table() is not None

    def integrated_work(self) -> float:
        """Estimated state-periods of the integrated path (0 on the exact path): per point about six
        candidate lives of ``periods`` per searched direction (the scan's survivor, the bisection's,
        the failures' short lives) and half the basin grid, each scaled by ``max(1, (w_h + c) 2T / 3)``
        (DOP853's steps grow with the period), plus the per-period overhead of each chunk."""
        if self.exact:
            return 0.0
        from .kernel import plane_to_physical

        X, Y = np.meshgrid(np.asarray(self.x), np.asarray(self.y))
        T, A = plane_to_physical(self.plane, X, Y, self.l, self.g, self.drive)
        searches = self.directions if "radius" in self.quantities else (1 if "tilt" in self.quantities else 0)
        states = 6.0 * searches + (self.basin_resolution ** 2 / 2.0 if "basin" in self.quantities else 0.0)
        d = parse_drive(self.drive)
        per_point = integrated_work(self.periods, states, T, A, self.l, self.g, self.c, d) - \
            integrated_work(self.periods, 0.0, T, A, self.l, self.g, self.c, d)
        overhead = len(self.all_chunks()) * 10.0 * self.periods * INTEGRATED_STEP_COST
        return float(per_point + overhead)

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
        return {k: getattr(self, k) for k in ("plane", "x", "y", "l", "g", "drive", "c", "periods", "tol", "quantities",
                                              "directions", "basin_resolution", "accuracy", "floor", "chunk")}

    def to_json(self) -> str:
        return json.dumps({k: list(v) if isinstance(v, tuple) else v for k, v in self.as_dict().items()},
                          sort_keys=True)

    @classmethod
    def from_json(cls, text) -> "SweepSpec":
        return cls(**json.loads(text))
