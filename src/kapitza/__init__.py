"""kapitza: the inverted pendulum on a vibrating pivot (square wave, duty cycles, steps, sine, triangle, measured).

Exact stability zones, periodic motions (Csizmadia & Hatvani, Theorems 3.3-3.4,
Corollary 4.1) for the paper's square-wave acceleration, Floquet data and exact linear motion, vectorised
over numpy arrays; the other drives (``drive="square"``, ``"rectangular:DUTY"``, ``"steps:LEVELS:FRACTIONS"``,
``"sine"``, ``"triangle"``, a measured one from samples) and damping in :mod:`kapitza.drives`
(``docs/drives.md``); nonlinear motion, stroboscopic maps and basins in :mod:`kapitza.motion`.
See ``docs/theory.md`` for the mathematics, ``docs/architecture.md`` for the layout.

Arnold's parameters ``eps = T sqrt(A/(8 l))`` and ``mu = sqrt(g/A)`` are used
throughout; :func:`to_arnold` and :func:`to_physical` convert.

The heavier layers -- :mod:`~kapitza.motion`, :mod:`~kapitza.normal_form`, :mod:`~kapitza.mathieu`,
:mod:`~kapitza.figures` -- are loaded on first use (``kapitza.simulate``, ``kapitza.figures``), so
``import kapitza`` costs about what numpy and scipy.special do.
"""
from . import _interrupt  # noqa: F401  (first: Ctrl-C while the command starts up is one line, not a traceback)

# ---- errors
from ._validate import KapitzaValueError

# ---- parameters: Arnold's eps, mu and the physical T, A, l, g
from .parameters import G_EARTH, frequencies, phase_angles, to_arnold, to_physical

# ---- drives and the rig
from .drives import (Drive, RectangularWave, SineWave, SquareWave, StepDrive, TriangleWave, from_samples, parse_drive,
                     register)
from .system import Pendulum
from .rig import Rig

# ---- the safe starting tilt of the real pendulum beside every verdict
from .safety import safe_tilt

# ---- the tower of linked pendulums on one pivot: docs/tower.md
from .chain import Chain, ChainReport, analyze_chain, chain_floquet, tower_curves

# ---- stability zones and their edges
from .zones import (G_m_curve, StabilityMargin, amplitude_edges, is_stable, period_edges, stability_grid,
                    stability_margin, zone_edges, zone_index, zone_width)

# ---- one period: Floquet data and the exact linear motion
from .propagation import Floquet, floquet, floquet_multipliers, growth_rate, linear_motion, monodromy, rotation_number

# ---- one point, every answer
from .analysis import StabilityReport, analyze

# ---- periodic solutions on the zones' edges
from .periodic import BoundaryPeriod, PeriodicSolution, alpha, beta, boundary_periods, boundary_table, periodic_solution

# ---- the high-frequency limit
from .limits import averaging_threshold, threshold_table

#: Loaded on first use: name -> (module, attribute or None for the module itself).
_LAZY = {
    # pyproject.toml's version, read from the installed metadata (importlib.metadata: tens of ms)
    "__version__": ("kapitza._version", "__version__"),
    "motion": ("kapitza.motion", None),
    "simulate": ("kapitza.motion", "simulate"),
    "nonlinear_motion": ("kapitza.motion", "nonlinear_motion"),
    "phase_flow": ("kapitza.motion", "phase_flow"),
    "stroboscopic_map": ("kapitza.motion", "stroboscopic_map"),
    "survival": ("kapitza.motion", "survival"),
    "basin": ("kapitza.motion", "basin"),
    # nonlinear (Lyapunov) stability of the upright: docs/nonlinear.md
    "normal_form": ("kapitza.normal_form", None),
    "twist_coefficient": ("kapitza.normal_form", "twist_coefficient"),
    "nonlinear_stability": ("kapitza.normal_form", "nonlinear_stability"),
    "NonlinearVerdict": ("kapitza.normal_form", "NonlinearVerdict"),
    "birkhoff_normal_form": ("kapitza.normal_form", "birkhoff_normal_form"),
    "BirkhoffNormalForm": ("kapitza.normal_form", "BirkhoffNormalForm"),
    "period_map_taylor": ("kapitza.normal_form", "period_map_taylor"),
    "TaylorMap": ("kapitza.normal_form", "TaylorMap"),
    "averaged_twist": ("kapitza.normal_form", "averaged_twist"),
    "mathieu": ("kapitza.mathieu", None),
    "phase_plane": ("kapitza.phase_plane", None),
    "analysis": ("kapitza.analysis", None),
    "limits": ("kapitza.limits", None),
    "system": ("kapitza.system", None),
    "figures": ("kapitza.figures", None),
    "grids": ("kapitza.grids", None),  # grids as xarray.DataArray (the sweep extra)
    "chain_motion": ("kapitza.motion.chain", "chain_motion"),
    "tower_safe_tilt": ("kapitza.motion.chain", "tower_safe_tilt"),
    "widgets": ("kapitza.widgets", None),  # the explorer in a notebook (the widgets extra)
}


def __getattr__(name):
    """The heavy layers of :data:`_LAZY`, imported on first use."""
    try:
        module, attr = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'kapitza' has no attribute {name!r}") from None
    import importlib

    value = importlib.import_module(module)
    if attr is not None:
        value = getattr(value, attr)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "KapitzaValueError",
    # parameters
    "G_EARTH", "to_arnold", "to_physical", "frequencies", "phase_angles",
    # drives and the rig
    "Drive", "SquareWave", "RectangularWave", "StepDrive", "SineWave", "TriangleWave", "from_samples", "parse_drive",
           "register",
    "Pendulum", "Rig",
    # the tower of linked pendulums: docs/tower.md
    "Chain", "ChainReport", "analyze_chain", "chain_floquet", "tower_curves", "chain_motion", "tower_safe_tilt",
    "drives",
    # zones
    "is_stable", "zone_index", "zone_edges", "zone_width", "G_m_curve", "StabilityMargin", "stability_margin",
    "stability_grid", "period_edges", "amplitude_edges",
    # one period
    "Floquet", "floquet", "floquet_multipliers", "growth_rate", "rotation_number", "monodromy", "linear_motion",
    # one point
    "StabilityReport", "analyze",
    # periodic solutions
    "alpha", "beta", "boundary_periods", "BoundaryPeriod", "boundary_table", "PeriodicSolution", "periodic_solution",
    # limits
    "averaging_threshold", "threshold_table",
    # loaded on first use
    "safe_tilt",
    "mathieu", "phase_plane", "motion", "simulate", "nonlinear_motion", "phase_flow", "stroboscopic_map", "survival",
    "basin", "normal_form", "twist_coefficient", "nonlinear_stability", "NonlinearVerdict", "birkhoff_normal_form",
    "BirkhoffNormalForm", "period_map_taylor", "TaylorMap", "averaged_twist",
]
