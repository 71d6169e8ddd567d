"""Motion of the pendulum on its vibrating pivot: linear and fully nonlinear.

* :func:`nonlinear_motion`, :func:`simulate` -- ``theta(t)`` of the full equation,
  exact in Jacobi elliptic functions (undamped) or by DOP853 (damped, cross-check);
  the linear model comes from :func:`kapitza.linear_motion`.
* :func:`phase_flow` -- the exact flow of one phase, ``theta'' = s sin(theta)``.
* :func:`stroboscopic_map` -- ensembles mapped over whole periods ``2T``.
* :func:`basin`, :func:`survival` -- which initial states stay near the upright.
* :func:`measured_rotation_number` -- rotation numbers of small invariant curves, measured.
* :func:`pivot_displacement` and friends -- where the pivot is.

Drawing lives in :mod:`kapitza.figures.motion` and :mod:`kapitza.figures.animation`.
"""
from .pivot import pivot_acceleration, pivot_displacement, pivot_stroke, pivot_velocity
from .nonlinear import METHODS, MODELS, Trajectory, nonlinear_motion, phase_energy, phase_flow, simulate
from .strobe import StrobeOrbits, stroboscopic_map
from .basins import Basin, basin, survival
from .rotation import RotationRun, measured_rotation_number
from .pair import MotionPair, motion_pair

__all__ = [
    "pivot_acceleration",
    "pivot_velocity",
    "pivot_displacement",
    "pivot_stroke",
    "phase_flow",
    "nonlinear_motion",
    "phase_energy",
    "Trajectory",
    "simulate",
    "MODELS",
    "METHODS",
    "StrobeOrbits",
    "stroboscopic_map",
    "survival",
    "Basin",
    "basin",
    "RotationRun",
    "measured_rotation_number",
    "MotionPair",
    "motion_pair",
]
