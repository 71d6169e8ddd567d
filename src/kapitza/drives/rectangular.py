"""A rectangular wave of any duty cycle, with zero mean acceleration."""
from __future__ import annotations

from .. import _validate as _v
from ._piecewise import PiecewiseConstant


class RectangularWave(PiecewiseConstant):
    """Acceleration ``+A`` for the fraction ``duty`` of the period ``2T``, then ``-A duty/(1 - duty)``.

    The second level makes the mean acceleration zero, so the pivot's velocity and displacement
    are periodic; ``duty = 0.5`` is the paper's square wave (:class:`~kapitza.SquareWave`).

    Parameters
    ----------
    duty : float
        ``0 < duty < 1``.
    """

    name = "rectangular"
    text_form = "rectangular:DUTY"

    @classmethod
    def from_text(cls, parameters, text=None):
        if not parameters:
            raise _v.KapitzaValueError(
                f"drive 'rectangular' needs its duty cycle, e.g. 'rectangular:0.3'; got {text!r}")
        return cls(_v.number_text("duty", parameters))

    def __init__(self, duty):
        d = _v.one("duty", _v.in_range("duty", duty, 0.0, 1.0))
        self.duty = d
        super().__init__((1.0, -d / (1.0 - d)), (d, 1.0 - d))

    def text(self) -> str:
        return f"rectangular:{self.duty!r}"

    def as_dict(self) -> dict:
        return {"drive": self.name, "duty": self.duty}

    @property
    def label(self) -> str:
        return f"rectangular, duty {100 * self.duty:.3g} %"

    def describe(self) -> str:
        return f"rectangular wave, duty {self.duty:.4g} (+A for {self.duty:.4g} of the period)"
