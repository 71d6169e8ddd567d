"""Grids as labelled arrays: the exact verdicts over a window as an ``xarray.DataArray``.

xarray is imported only when asked for (the ``sweep`` extra installs it), so ``import kapitza``
stays light.
"""
from __future__ import annotations

import numpy as np

__all__ = ["stability_grid_da"]


def stability_grid_da(eps, mu, drive=None, zeta=0.0, *, l=None, g=None):
    """:func:`kapitza.stability_grid` as an ``xarray.DataArray`` with coordinates, units and attributes.

    Parameters
    ----------
    eps, mu : 1-D array_like
        The grid's axes (as :func:`kapitza.stability_grid`).
    drive : Drive or str, optional
        The pivot's motion; the paper's square wave by default.
    zeta : float, optional
        Damping ratio ``c / (2 sqrt(g/l))``.
    l, g : float, optional
        A rod's equivalent length [m] and gravity [m/s^2]: then the physical coordinates
        ``A(mu)`` [m/s^2] and ``T(eps, mu)`` [s] are added.

    Returns
    -------
    xarray.DataArray
        Boolean, dims ``("mu", "eps")``, named ``"stable"``; ``attrs`` say the drive, the damping ratio
        and what the values mean.

    Raises
    ------
    ValueError
        As :func:`kapitza.stability_grid` (a :class:`kapitza.KapitzaValueError` naming the argument,
        its value and the allowed range), and for ``l`` or ``g`` not finite and > 0.
    ImportError
        Without xarray (the ``sweep`` extra).

    Examples
    --------
    >>> import numpy as np, kapitza
    >>> da = kapitza.grids.stability_grid_da(np.linspace(0.1, 4, 400), np.linspace(0.01, 0.99, 300), l=0.5)
    >>> da.sel(mu=0.3, eps=0.5, method="nearest").item()
    True
    >>> da.coords["A"].attrs["units"]
    'm/s^2'
    """
    try:
        import xarray as xr
    except ImportError as exc:  # pragma: no cover - the sweep extra installs it
        raise ImportError("stability_grid_da needs xarray (pip install 'kapitza[sweep]')") from exc
    from . import _validate as _v
    from .drives import as_drive, parse_drive
    from .zones import stability_grid

    d = parse_drive(drive) if isinstance(drive, str) else as_drive(drive)
    grid = stability_grid(eps, mu, drive=d, zeta=zeta)
    e = np.asarray(eps, float).ravel()
    m = np.asarray(mu, float).ravel()
    coords = {"eps": ("eps", e, {"long_name": "Arnold's eps = T sqrt(A / (8 l))", "units": "1"}),
              "mu": ("mu", m, {"long_name": "Arnold's mu = sqrt(g / A)", "units": "1"})}
    attrs = {"long_name": "the upright is (linearly) stable", "units": "1", "drive": d.describe(),
             "zeta": float(zeta), "source": "kapitza.stability_grid (exact zone edges)"}
    if l is not None or g is not None:
        from .parameters import G_EARTH, to_physical

        l = _v.one("l", _v.positive("l", 1.0 if l is None else l))
        g = _v.one("g", _v.positive("g", G_EARTH if g is None else g))
        T, A = to_physical(e[None, :], m[:, None], l, g)
        coords["A"] = ("mu", np.asarray(A)[:, 0], {"long_name": "pivot acceleration amplitude", "units": "m/s^2"})
        coords["T"] = (("mu", "eps"), np.asarray(T), {"long_name": "half-period of the drive", "units": "s"})
        attrs.update(l=l, g=g)
    return xr.DataArray(grid, dims=("mu", "eps"), coords=coords, name="stable", attrs=attrs)
