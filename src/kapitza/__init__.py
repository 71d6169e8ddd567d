"""kapitza: the inverted pendulum on a pivot driven by a square-wave acceleration.

Exact stability zones, periodic motions (Csizmadia & Hatvani, Theorems 3.3-3.4,
Corollary 4.1), Floquet data and exact linear motion, vectorised over numpy
arrays. See ``docs/theory.md`` for the mathematics and conventions.

Arnold's parameters ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` are used
throughout; :func:`to_arnold` and :func:`to_physical` convert.
"""
from ._validate import KapitzaValueError
from .parameters import G_EARTH, frequencies, phase_angles, to_arnold, to_physical
from .zones import (
    G_m_curve,
    StabilityMargin,
    amplitude_edges,
    is_stable,
    period_edges,
    stability_grid,
    stability_margin,
    zone_edges,
    zone_index,
    zone_width,
)
from .propagation import (
    Floquet,
    floquet,
    floquet_multipliers,
    growth_rate,
    linear_motion,
    monodromy,
    rotation_number,
)
from .periodic import (
    BoundaryPeriod,
    PeriodicSolution,
    alpha,
    beta,
    boundary_periods,
    boundary_table,
    periodic_solution,
)
from .analysis import StabilityReport, analyze
from . import phase_plane

__version__ = "0.1.0"

__all__ = [
    "KapitzaValueError",
    "G_EARTH",
    "to_arnold",
    "to_physical",
    "frequencies",
    "phase_angles",
    "is_stable",
    "zone_index",
    "zone_edges",
    "zone_width",
    "G_m_curve",
    "StabilityMargin",
    "stability_margin",
    "stability_grid",
    "period_edges",
    "amplitude_edges",
    "Floquet",
    "floquet",
    "floquet_multipliers",
    "growth_rate",
    "rotation_number",
    "monodromy",
    "linear_motion",
    "alpha",
    "beta",
    "boundary_periods",
    "BoundaryPeriod",
    "boundary_table",
    "PeriodicSolution",
    "periodic_solution",
    "StabilityReport",
    "analyze",
    "phase_plane",
]
