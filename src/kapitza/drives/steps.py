"""Any piecewise-constant drive: levels and the fractions of the period they last."""
from __future__ import annotations

from .. import _validate as _v
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
    text_form = "steps:LEVELS:FRACTIONS"

    def text(self) -> str:
        return ("steps:" + ",".join(repr(float(v)) for v in self.levels) + ":"
                + ",".join(repr(float(v)) for v in self.fractions))

    @classmethod
    def from_text(cls, parameters, text=None):
        levels, sep, fractions = (parameters or "").partition(":")
        if not sep:
            raise _v.KapitzaValueError(
                f"drive 'steps' needs levels and fractions, e.g. 'steps:2,-1,1,-1:0.2,0.3,0.2,0.3'; got {text!r}")
        return cls([_v.number_text("levels", x) for x in levels.split(",")],
                   [_v.number_text("fractions", x) for x in fractions.split(",")])
