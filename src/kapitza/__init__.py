"""kapitza: the inverted pendulum on a pivot driven by a square-wave acceleration.

Exact stability zones, periodic motions (Csizmadia & Hatvani, Theorems 3.3-3.4,
Corollary 4.1), Floquet data and exact linear motion, vectorised over numpy
arrays; other drives (duty cycles, steps, the sine) and damping in :mod:`kapitza.drives`
(``docs/drives.md``); nonlinear motion, stroboscopic maps and basins in :mod:`kapitza.motion`.
See ``docs/theory.md`` for the mathematics and conventions.

Arnold's parameters ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` are used
throughout; :func:`to_arnold` and :func:`to_physical` convert.
"""
from . import _interrupt  # noqa: F401  (first: Ctrl-C while the command starts up is one line, not a traceback)
from . import analysis, drives, limits, mathieu, motion, parameters, periodic, phase_plane, propagation, system, zones
from ._validate import KapitzaValueError
from .drives import RectangularWave, SineWave, SquareWave, StepDrive, parse_drive
from .limits import averaging_threshold, threshold_table
from .system import Pendulum, Rig
from .analysis import *  # noqa: F401,F403
from .parameters import *  # noqa: F401,F403
from .periodic import *  # noqa: F401,F403
from .propagation import *  # noqa: F401,F403
from .zones import *  # noqa: F401,F403
from .safety import safe_tilt
from .motion import basin, nonlinear_motion, phase_flow, simulate, stroboscopic_map, survival
from . import normal_form
from .normal_form import (BirkhoffNormalForm, NonlinearVerdict, TaylorMap, averaged_twist, birkhoff_normal_form,
                          nonlinear_stability, period_map_taylor, twist_coefficient)

__version__ = "0.1.0"

# Each module's __all__ is its public surface; the package re-exports them.
__all__ = [
    "KapitzaValueError",
    *parameters.__all__,
    *zones.__all__,
    *propagation.__all__,
    *periodic.__all__,
    *analysis.__all__,
    # drives and the rig
    "SquareWave",
    "RectangularWave",
    "StepDrive",
    "SineWave",
    "parse_drive",
    "Pendulum",
    "Rig",
    "averaging_threshold",
    "threshold_table",
    "drives",
    "mathieu",
    "phase_plane",
    "motion",
    "simulate",
    "nonlinear_motion",
    "phase_flow",
    "stroboscopic_map",
    "survival",
    "basin",
    "safe_tilt",
    # nonlinear (Lyapunov) stability of the upright: docs/nonlinear.md
    "normal_form",
    "twist_coefficient",
    "nonlinear_stability",
    "NonlinearVerdict",
    "birkhoff_normal_form",
    "BirkhoffNormalForm",
    "period_map_taylor",
    "TaylorMap",
    "averaged_twist",
]
