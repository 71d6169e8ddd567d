"""kapitza: the inverted pendulum on a pivot driven by a square-wave acceleration.

Exact stability zones, periodic motions (Csizmadia & Hatvani, Theorems 3.3-3.4,
Corollary 4.1), Floquet data and exact linear motion, vectorised over numpy
arrays; nonlinear motion, stroboscopic maps and basins in :mod:`kapitza.motion`.
See ``docs/theory.md`` for the mathematics and conventions.

Arnold's parameters ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` are used
throughout; :func:`to_arnold` and :func:`to_physical` convert.
"""
from . import analysis, motion, parameters, periodic, phase_plane, propagation, zones
from ._validate import KapitzaValueError
from .analysis import *  # noqa: F401,F403
from .parameters import *  # noqa: F401,F403
from .periodic import *  # noqa: F401,F403
from .propagation import *  # noqa: F401,F403
from .zones import *  # noqa: F401,F403
from .motion import basin, nonlinear_motion, phase_flow, simulate, stroboscopic_map, survival

__version__ = "0.1.0"

# Each module's __all__ is its public surface; the package re-exports them.
__all__ = [
    "KapitzaValueError",
    *parameters.__all__,
    *zones.__all__,
    *propagation.__all__,
    *periodic.__all__,
    *analysis.__all__,
    "phase_plane",
    "motion",
    "simulate",
    "nonlinear_motion",
    "phase_flow",
    "stroboscopic_map",
    "survival",
    "basin",
]
