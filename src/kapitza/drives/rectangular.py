"""A rectangular wave of any duty cycle, with zero mean acceleration."""
from __future__ import annotations

from .. import _validate as _v
from ._piecewise import PiecewiseConstant

# the closed interval of duty cycles (RectangularWave.parameters says so): a pulse narrower than a
# millionth of the period has a negative level beyond the step drives' 1e6 A, and at a duty near
# 1e-300 the drive's stroke underflows to zero
_DUTY = (1e-6, 1.0 - 1e-6)


class RectangularWave(PiecewiseConstant):
    """Acceleration ``+A`` for the fraction ``duty`` of the period ``2T``, then ``-A duty/(1 - duty)``.

    The second level makes the mean acceleration zero, so the pivot's velocity and displacement
    are periodic; ``duty = 0.5`` is the paper's square wave (:class:`~kapitza.SquareWave`).

    Parameters
    ----------
    duty : float
        ``1e-6 <= duty <= 1 - 1e-6``: the fraction of the period at ``+A``.

    Raises
    ------
    ValueError
        If ``duty`` is not in ``(0, 1)``.

    Examples
    --------
    >>> import numpy as np
    >>> import kapitza
    >>> drive = kapitza.RectangularWave(0.3)
    >>> drive.text(), drive.describe()
    ('rectangular:0.3', 'rectangular wave, duty 0.3 (+A for 0.3 of the period)')
    >>> drive.acceleration(np.array([0.0, 0.05, 0.1, 0.15]), T=0.1, A=100.0)
    array([100.        , 100.        , -42.8571..., -42.8571...])
    >>> kapitza.zone_edges(0.3, 0, drive=drive)
    (np.float64(0.6529...), np.float64(1.0310...))
    >>> half = kapitza.zone_edges(0.3, 0, drive=kapitza.RectangularWave(0.5))
    >>> np.allclose(half, kapitza.zone_edges(0.3, 0), rtol=1e-14)  # duty 0.5: the square wave
    True
    """

    name = "rectangular"
    text_form = "rectangular:DUTY"
    title = "rectangular, duty cycle"
    #: the duty cycle, as the constructor checks it: ``1e-6 <= duty <= 1 - 1e-6``
    parameters = ({"name": "duty", "min": _DUTY[0], "max": _DUTY[1], "default": 0.3, "examples": (0.3, 0.7),
                   "description": "the fraction of the period at +A"},)

    @classmethod
    def from_text(cls, parameters, text=None):
        if not parameters:
            raise _v.KapitzaValueError(
                f"drive 'rectangular' needs its duty cycle, e.g. 'rectangular:0.3'; got {text!r}")
        return cls(_v.number_text("duty", parameters))

    def __init__(self, duty):
        d = _v.one("duty", _v.in_range("duty", duty, *_DUTY, lo_open=False, hi_open=False))
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
