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

    Raises
    ------
    ValueError
        If the levels or fractions are not as above.

    Notes
    -----
    The monodromy is the product of the exact segment matrices (``docs/drives.md``);
    ``StepDrive([1, -1], [0.5, 0.5])`` is the paper's square wave.

    Examples
    --------
    >>> import kapitza
    >>> drive = kapitza.StepDrive([1, -1, 1, -1], [0.2, 0.3, 0.3, 0.2])
    >>> drive.text()
    'steps:1.0,-1.0,1.0,-1.0:0.2,0.3,0.3,0.2'
    >>> kapitza.zone_edges(0.3, 0, drive=drive)
    (np.float64(0.6620...), np.float64(1.0186...))
    >>> kapitza.StepDrive([1, -1], [0.5, 0.5]).describe()
    '2-step drive (+1 A for 0.5, -1 A for 0.5 of the period)'
    >>> kapitza.StepDrive([1, 1], [0.5, 0.5])
    Traceback (most recent call last):
        ...
    kapitza._validate.KapitzaValueError: levels must have zero mean over the period (...); got mean 1.0
    """

    name = "steps"
    text_form = "steps:LEVELS:FRACTIONS"
    title = "steps: levels and fractions"
    parameters = None  # lists of numbers, not one number: no simple form offers it

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
