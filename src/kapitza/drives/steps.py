"""Any piecewise-constant drive: levels and the fractions of the period they last."""
from __future__ import annotations

from ._piecewise import PiecewiseConstant


class StepDrive(PiecewiseConstant):
    """Acceleration ``levels[i] * A`` for the fraction ``fractions[i]`` of the period ``2T``.

    Parameters
    ----------
    levels : sequence of float
        Finite; ``sum(levels * fractions) = 0`` (zero mean, so that the pivot's velocity and
        displacement are periodic), not all 0. 2 to 64 steps.
    fractions : sequence of float
        Each > 0, summing to 1; the same length as ``levels``.

    Notes
    -----
    The monodromy is the product of the exact segment matrices (``docs/drives.md``);
    ``StepDrive([1, -1], [0.5, 0.5])`` is the paper's square wave.
    """

    name = "steps"
