"""The sweep's Zarr store: pre-created arrays, one region write per finished chunk, done flags.

Layout (an xarray Dataset in Zarr form): every variable of :data:`kapitza.sweeps.kernel.VARIABLES`
that was asked for, on the dimensions ``(mu, eps)`` or ``(A, T)`` with their coordinates and
units, chunked exactly as the work is; ``chunk_done`` on ``(chunk_y, chunk_x)``, set to 1 only
after a chunk's values are all written. An interrupted sweep therefore leaves finished chunks
marked and everything else recomputable; the attributes hold the settings (``sweep_spec``, JSON),
the kapitza version and the accuracy of each quantity.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import _validate as _v
from .._io import atomic_path
from ..drives._api import zeta_of
from ..motion.basins import INTEGRATED_ATOL, INTEGRATED_RTOL, MIN_SAMPLES, SAMPLE_SPACING
from .kernel import VARIABLES
from .spec import PLANES, SweepSpec

__all__ = ["create_store", "open_store", "write_chunk", "done_chunks", "open_sweep", "to_netcdf"]

_INT = {"stable": "int8", "zone": "int16"}


def _attrs(spec: SweepSpec) -> dict:
    from .. import __version__
    from ..drives import parse_drive

    acc = f"{100 * spec.accuracy:g} %"
    return {
        "title": "kapitza sweep: nonlinear stability of the inverted pendulum over the parameter plane",
        "kapitza_version": __version__,
        "sweep_spec": spec.to_json(),
        "quantities": ",".join(spec.quantities),
        "plane": spec.plane,
        "drive": parse_drive(spec.drive).describe(),
        "damping": ("none (undamped)" if spec.c == 0 else
                    f"viscous, c = {spec.c!r} 1/s (damping ratio zeta = c / (2 sqrt(g/l)) = {zeta_of(spec.c, spec.l, spec.g):.6g})"),
        "damping_c_per_s": spec.c,
        "path": ("exact: step flows in Jacobi elliptic functions (undamped piecewise-constant drive)" if spec.exact else
                 f"integrated: DOP853, rtol {INTEGRATED_RTOL:g} and atol {INTEGRATED_ATOL:g} per component, restarted "
                 f"at every jump of the drive (the sine drive or damping has no exact flow)"),
        "periods": spec.periods,
        "tol_rad": spec.tol,
        "l_m": spec.l,
        "g_m_per_s2": spec.g,
        "survival_test": ("|theta(t)| <= tol on all of [0, 2NT], checked on the continuous motion "
                          "(kapitza.motion.survival)" if spec.exact else
                          f"|theta(t)| <= tol on [0, 2NT], checked at instants evenly spaced over each period (at "
                          f"least {MIN_SAMPLES}, (w_h + c) dt <= {SAMPLE_SPACING:g}) and between them on the cubic "
                          f"Hermite interpolant through (theta, theta'), error about (w dt)^4/384 < 5e-6 of the "
                          f"swing: sampled, not exact (kapitza.motion.survival)"),
        "accuracy": (f"max_safe_tilt, max_safe_radius: bisection; the value v stays and a start less than "
                     f"{acc} above it does not, so v is the edge of the safe starts from the upright to {acc} "
                     f"where they form one segment (near zone edges they can be ragged at that scale); 0 means "
                     f"below floor {spec.floor:g} rad; capped at tol. basin_area: exact fraction of a "
                     f"{spec.basin_resolution} x {spec.basin_resolution} start grid. Linear quantities: exact"
                     + (" (with the damping)." if spec.c else ".")
                     + ("" if spec.exact else " 'Stays' is the sampled test of survival_test (DOP853), not the "
                        "exact one.")),
        "radius_directions": spec.directions,
        "radius_scale": "start (theta0, dtheta0) = r (cos phi, (2/T) sin phi)",
        "basin_window": "|theta0| <= tol, |dtheta0| <= 2 tol / T",
    }


def create_store(path, spec: SweepSpec):
    """Create the store with every array pre-allocated (nothing computed yet)."""
    import dask.array as da
    import xarray as xr

    (yn, yu), (xn, xu) = PLANES[spec.plane][1], PLANES[spec.plane][0]
    c = spec.chunk
    data, enc = {}, {}
    for name in spec.variables:
        long, units = VARIABLES[name]
        dt = _INT.get(name, "float64")
        fill = 0 if name in _INT else np.nan
        data[name] = (spec.dims, da.full(spec.shape, fill, dtype=dt, chunks=(c, c)), {"long_name": long, "units": units})
        enc[name] = {"chunks": (c, c), "_FillValue": None if name in _INT else np.nan}
    data["chunk_done"] = (("chunk_y", "chunk_x"), da.zeros(spec.chunk_shape, dtype="int8", chunks=spec.chunk_shape),
                          {"long_name": "1 once every value of this chunk is written", "units": "1"})
    enc["chunk_done"] = {"_FillValue": None}
    coords = {yn: (yn, np.asarray(spec.y), {"units": yu}), xn: (xn, np.asarray(spec.x), {"units": xu})}
    ds = xr.Dataset(data, coords=coords, attrs=_attrs(spec))
    ds.to_zarr(str(path), mode="w-", compute=False, encoding=enc, consolidated=True, zarr_format=2)
    grp = open_store(path)
    grp["chunk_done"][...] = np.zeros(spec.chunk_shape, dtype="int8")
    return grp


def open_store(path):
    """The store's Zarr group, open for writing."""
    import zarr

    return zarr.open_group(str(path), mode="r+")


def stored_spec(path) -> SweepSpec:
    """The settings a store was created with."""
    try:
        text = open_store(path).attrs.get("sweep_spec")
    except Exception:  # not a Zarr group at all
        text = None
    if text is None:
        raise _v.KapitzaValueError(f"store must be a kapitza sweep store; got {str(path)!r} (no sweep_spec attribute)")
    return SweepSpec.from_json(text)


def write_chunk(grp, spec: SweepSpec, iy, ix, values: dict):
    """Write one finished chunk into its region, then set its done flag."""
    ys, xs = spec.chunk_slices(iy, ix)
    for name in spec.variables:
        grp[name][ys, xs] = values[name]
    grp["chunk_done"][iy, ix] = 1


def done_chunks(grp) -> np.ndarray:
    """Boolean ``(chunk_y, chunk_x)`` array of the finished chunks."""
    return np.asarray(grp["chunk_done"][...]) == 1


def open_sweep(path):
    """The sweep as an :class:`xarray.Dataset` (lazy, backed by the Zarr store)."""
    import xarray as xr

    if not Path(path).exists():
        raise _v.KapitzaValueError(f"store must be an existing sweep store; got {str(path)!r} (no such path)")
    return xr.open_zarr(str(path))


def to_netcdf(ds, path):
    """Write the Dataset as NetCDF (classic 64-bit format via scipy, no extra library), atomically."""
    with atomic_path(path, suffix=".nc") as tmp:
        ds.load().to_netcdf(tmp, engine="scipy")
    return Path(path)
