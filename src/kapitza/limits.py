"""The high-frequency (averaging) criterion of every drive, against the exact lower edge.

Averaging the fast motion of the pivot gives the effective potential of Kapitza's theory:
the upright is stable when ``<v_pivot^2> > g l``, ``v_pivot`` the pivot's velocity. With
``<v^2> = k A^2 T^2`` (``k`` the drive's mean square velocity shape, ``docs/drives.md``) this
is ``eps > eps_K = mu / sqrt(8 k)``: ``sqrt(3/2) mu`` for the square wave, ``pi mu / 2`` for
the sine. It is the ``mu -> 0`` limit of the exact lower edge of zone 0.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as _v
from .drives import as_drive

__all__ = ["averaging_threshold", "ThresholdRow", "threshold_table"]


@_v.shapes_named
def averaging_threshold(mu, drive=None):
    """``eps_K(mu)``: where ``<v_pivot^2> = g l`` for this drive (the averaging criterion).

    Parameters
    ----------
    mu : array_like
        ``mu > 0``.
    drive : Drive, optional
        The paper's square wave by default.

    Returns
    -------
    ndarray
        ``inf`` where ``eps_K`` exceeds the largest double (``mu`` beyond about 1.5e308 for the
        square wave).

    Raises
    ------
    ValueError
        If ``mu`` is not finite and > 0.

    Examples
    --------
    >>> import kapitza
    >>> kapitza.averaging_threshold(0.1)
    np.float64(0.1224...)
    >>> kapitza.zone_edges(0.1, 0)[0]
    np.float64(0.1224...)
    >>> kapitza.averaging_threshold(0.1, drive=kapitza.SineWave())
    np.float64(0.1570...)
    """
    return as_drive(drive).kapitza_eps(mu)


@dataclass(frozen=True)
class ThresholdRow:
    """One drive at one ``mu``: the averaging criterion against the exact lower edge of zone 0.

    Attributes
    ----------
    drive, description : str
        The drive's label and its one-line description.
    mu : float
        Arnold's ``mu``.
    eps_averaging : float
        The averaging criterion ``<v^2> = g l`` as an ``eps``.
    eps_exact : float
        The exact lower edge of zone 0 at this ``mu``.
    relative_error : float
        ``eps_averaging / eps_exact - 1``.
    rms_velocity_shape : float
        The drive's root-mean-square velocity in units of ``A T``.

    Examples
    --------
    >>> import kapitza
    >>> row = kapitza.threshold_table(0.1, [kapitza.SquareWave()])[0]
    >>> row.drive, row.mu
    ('square wave', 0.1)
    >>> row.eps_averaging, row.eps_exact, row.relative_error
    (0.1224..., 0.1224..., -5.7144...e-05)
    """

    drive: str
    description: str
    mu: float
    eps_averaging: float
    eps_exact: float
    relative_error: float
    rms_velocity_shape: float

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@_v.shapes_named
def threshold_table(mu, drives, zeta=0.0):
    """The averaging threshold of each drive against its exact zone-0 lower edge.

    Parameters
    ----------
    mu : array_like
        Values of ``mu`` in (0, 1).
    drives : sequence of Drive
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))`` (the exact edge uses it; the averaging criterion
        does not depend on it).

    Returns
    -------
    list of ThresholdRow
        ``relative_error = eps_averaging / eps_exact - 1``; both NaN where the damped drive has
        no zone 0 at this ``mu`` (damping can close it).

    Raises
    ------
    ValueError
        If a ``mu`` is not in ``(0, 1)``, ``zeta`` is negative, or a drive is not a drive.

    Examples
    --------
    >>> import kapitza
    >>> for row in kapitza.threshold_table([0.03, 0.3], [kapitza.SquareWave(), kapitza.SineWave()]):
    ...     print(f"{row.drive:12s} mu = {row.mu}: {row.relative_error:+.1e}")
    square wave  mu = 0.03: -4.6e-07
    square wave  mu = 0.3: -4.6e-03
    sine wave    mu = 0.03: -7.1e-07
    sine wave    mu = 0.3: -7.1e-03
    """
    mu = np.atleast_1d(_v.in_range("mu", mu, 0.0, 1.0)).ravel()
    if isinstance(drives, (str, bytes)) or not hasattr(drives, "__iter__"):
        raise _v.KapitzaValueError(f"drives must be a sequence of drives (names or Drive objects); got {drives!r}")
    zeta = _v.one("zeta", _v.in_range("zeta", zeta, 0.0, _v.ZETA_MAX, lo_open=False, hi_open=False))
    rows = []
    for drive in drives:
        d = as_drive(drive)
        eps_k = d.kapitza_eps(mu)
        lo, _ = d.edges(mu, np.zeros(mu.size, np.int64), np.full(mu.size, zeta))
        with np.errstate(divide="ignore", invalid="ignore"):  # eps_exact underflows to 0 for mu near 1e-300
            rel = eps_k / lo - 1.0
        for m, ek, el, re_ in zip(mu, eps_k, lo, rel):
            rows.append(ThresholdRow(drive=d.label, description=d.describe(), mu=float(m), eps_averaging=float(ek),
                                     eps_exact=float(el),
                                     relative_error=float(re_),
                                     rms_velocity_shape=float(np.sqrt(d._mean_square_velocity))))
    return rows
