"""The sweep's Zarr store: pre-created arrays, one region write per finished chunk, checksummed.

Layout (an xarray Dataset in Zarr form): every variable of :data:`kapitza.sweeps.kernel.VARIABLES`
that was asked for, on the dimensions ``(mu, eps)``, ``(A, T)`` or ``(stroke, frequency)`` with
their coordinates and units (``frequency`` in Hz, ``stroke`` in m), chunked exactly as the work is;
``chunk_checksum`` and ``chunk_done`` on ``(chunk_y, chunk_x)``. A finished chunk's values are
written into their region, then the CRC-32 of exactly those values (:func:`chunk_checksum`), then
its done flag. A point not yet computed holds a fill value no result can take (NaN for the real
variables, -2 for ``zone``, -1 for ``stable``; the ``_FillValue`` attribute of each).

Integrity. The store is built under a temporary name beside its path and renamed into place
when complete, so an interrupt at any moment leaves nothing at the path or a store that resumes.
Resuming never trusts a done flag alone: each flagged chunk is read back and its checksum
compared (:func:`verified_chunks`), and a chunk whose data is missing (a lost chunk file reads as
the fill value), truncated (unreadable) or different is recomputed and named. The attributes
hold the settings (``sweep_spec``, JSON), the kapitza version and the accuracy of each quantity.
"""
from __future__ import annotations

import os
import shutil
import uuid
import warnings
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from .. import _validate as _v
from .._io import atomic_path
from ..drives._api import zeta_of
from ..motion.basins import INTEGRATED_ATOL, INTEGRATED_RTOL, MIN_SAMPLES, SAMPLE_SPACING
from .kernel import VARIABLES
from .spec import PLANES, SweepSpec

__all__ = ["create_store", "open_store", "write_chunk", "done_chunks", "verified_chunks", "chunk_checksum",
           "open_sweep", "to_netcdf", "StoreCheck"]

#: Integer variables, their dtype and their fill: a value no result takes (``stable`` is 0 or 1,
#: ``zone`` is ``n >= 0`` or -1 where unstable).
_INT = {"stable": ("int8", -1), "zone": ("int16", -2)}
#: ``coordinate -> long name``.
_COORDS = {"eps": "Arnold's eps = T sqrt(A / (8 l))", "mu": "Arnold's mu = sqrt(g / A)",
           "T": "half-period of the drive", "A": "acceleration amplitude of the pivot",
           "frequency": "drive frequency f = 1 / (2 T)",
           "stroke": "stroke: peak-to-peak travel of the pivot, k A T^2"}
#: The store layout's version: 2 added ``chunk_checksum`` and fills that are not data.
LAYOUT = 2


def _attrs(spec: SweepSpec) -> dict:
    from .. import __version__
    from ..drives import parse_drive
    from ..rig_plane import stroke_coefficient

    acc = f"{100 * spec.accuracy:g} %"
    return {
        "title": "kapitza sweep: nonlinear stability of the inverted pendulum over the parameter plane",
        "kapitza_version": __version__,
        "sweep_spec": spec.to_json(),
        "quantities": ",".join(spec.quantities),
        "plane": spec.plane,
        "drive": parse_drive(spec.drive).describe(),
        "damping": ("none (undamped)" if spec.c == 0 else
                    f"viscous, c = {spec.c!r} 1/s (damping ratio zeta = c / (2 sqrt(g/l)) = "
                    f"{zeta_of(spec.c, spec.l, spec.g):.6g})"),
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
        **({"stroke_coefficient": stroke_coefficient(spec.drive),
            "rig_plane": f"a point (frequency f [Hz], stroke s [m]) is T = 1 / (2 f), A = s / (k T^2) with the "
                         f"drive's stroke coefficient k = {stroke_coefficient(spec.drive):.6g}"}
           if spec.plane == "rig" else {}),
        "radius_directions": spec.directions,
        "radius_scale": "start (theta0, dtheta0) = r (cos phi, (2/T) sin phi)",
        "basin_window": "|theta0| <= tol, |dtheta0| <= 2 tol / T",
    }


def _dtype(name):
    return _INT[name][0] if name in _INT else "float64"


def chunk_checksum(spec: SweepSpec, values: dict) -> int:
    """CRC-32 of one chunk's values, every variable of ``spec`` in order, as stored (dtype, C order),
    as a signed 32-bit integer (NetCDF 3 has no unsigned or 64-bit integers)."""
    crc = 0
    for name in spec.variables:
        crc = zlib.crc32(np.ascontiguousarray(values[name], dtype=_dtype(name)).tobytes(), crc)
    return crc - (1 << 32) if crc >= 1 << 31 else crc


def _tmp_prefix(path: Path, what="creating") -> str:
    return f".{path.name}.{what}-"


def remove_leftovers(path: Path):
    """Remove what an interrupted creation (or rebuild) of the store ``path`` left beside it: the
    temporary folders whose process is gone."""
    prefixes = (_tmp_prefix(path), _tmp_prefix(path, "replaced"))
    try:
        names = [p for p in path.parent.iterdir() if p.name.startswith(prefixes)]
    except OSError:
        return
    for p in names:
        try:
            rest = next(p.name[len(x):] for x in prefixes if p.name.startswith(x))
            pid = int(rest.split("-")[0])
            os.kill(pid, 0)
        except ProcessLookupError:  # its creator is gone: a leftover
            shutil.rmtree(p, ignore_errors=True)
        except (ValueError, OSError):
            continue


def create_store(path, spec: SweepSpec):
    """Create the store with every array pre-allocated (nothing computed yet), atomically: it is
    built under a temporary name beside ``path`` and renamed into place once complete."""
    import dask.array as da
    import xarray as xr
    import zarr

    path = Path(path)
    remove_leftovers(path)
    tmp = path.parent / f"{_tmp_prefix(path)}{os.getpid()}-{uuid.uuid4().hex[:8]}"
    (yn, yu), (xn, xu) = PLANES[spec.plane][1], PLANES[spec.plane][0]
    c = spec.chunk
    enc: dict[str, dict[str, Any]]
    data, enc = {}, {}
    for name in spec.variables:
        long, units = VARIABLES[name]
        dt = _dtype(name)
        fill = _INT[name][1] if name in _INT else np.nan
        data[name] = (spec.dims, da.full(spec.shape, fill, dtype=dt, chunks=(c, c)),
                      {"long_name": long, "units": units})
        enc[name] = {"chunks": (c, c), "_FillValue": fill}
    flags = {"chunk_checksum": ("int32", "CRC-32 of the chunk's values as written (every variable in order)"),
             "chunk_done": ("int8", "1 once every value of this chunk and its checksum are written")}
    for name, (dt, long) in flags.items():
        data[name] = (("chunk_y", "chunk_x"), da.zeros(spec.chunk_shape, dtype=dt, chunks=spec.chunk_shape),
                      {"long_name": long, "units": "1"})
        enc[name] = {"_FillValue": None}
    coords = {yn: (yn, np.asarray(spec.y), {"units": yu, "long_name": _COORDS[yn]}),
              xn: (xn, np.asarray(spec.x), {"units": xu, "long_name": _COORDS[xn]})}
    ds = xr.Dataset(data, coords=coords, attrs={**_attrs(spec), "store_layout": LAYOUT})
    try:
        ds.to_zarr(str(tmp), mode="w-", compute=False, encoding=enc, consolidated=False, zarr_format=2)
        grp = zarr.open_group(str(tmp), mode="r+", use_consolidated=False)
        for name, (dt, _) in flags.items():
            grp[name][...] = np.zeros(spec.chunk_shape, dtype=dt)  # type: ignore[index]
        zarr.consolidate_metadata(str(tmp))
        try:
            os.rename(tmp, path)  # atomic: the store appears complete or not at all
        except OSError:
            if path.exists():
                raise _v.KapitzaValueError(f"store must be a new path, or resumed (resume=True, --resume); got "
                                           f"{str(path)!r}, which exists") from None
            raise
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return open_store(path)


def open_store(path):
    """The store's Zarr group, open for writing (consolidated metadata when it is there).

    Parameters
    ----------
    path : path
        The sweep's Zarr store.

    Returns
    -------
    zarr.Group

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If ``path`` is not a Zarr group.

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> from kapitza.sweeps import SweepSpec, done_chunks, open_store, sweep
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",), chunk=2)
    >>> folder = tempfile.mkdtemp()
    >>> run = sweep(spec, os.path.join(folder, "map.zarr"), serial=True, progress=False)
    >>> done_chunks(open_store(run.store))
    array([[ True,  True],
           [ True,  True]])
    >>> shutil.rmtree(folder)
    """
    import zarr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if not Path(path).exists():
            raise FileNotFoundError(f"no sweep store at {str(path)!r}")
        try:
            return zarr.open_group(str(path), mode="r+", use_consolidated=(Path(path) / ".zmetadata").exists())
        except Exception as exc:  # zarr's own "no group here" (its class moved between versions)
            raise _v.KapitzaValueError(f"store must be a kapitza sweep store (a Zarr group); {str(path)!r} is not "
                                       f"one ({type(exc).__name__})") from None


def _incomplete(path, why):
    return _v.KapitzaValueError(
        f"store must be a complete kapitza sweep store; {str(path)!r} {why}: delete it (nothing in it can be "
        f"trusted) or give another path")


def stored_spec(path) -> SweepSpec:
    """The settings a store was created with."""
    path = Path(path)
    if not path.is_dir():
        raise _incomplete(path, "is not a folder")
    if not (path / ".zgroup").exists() and not (path / ".zmetadata").exists():
        raise _incomplete(path, "has no Zarr metadata (.zgroup, .zattrs: copied without its dot files, or its "
                                "creation was interrupted by an older kapitza)")
    try:
        text = open_store(path).attrs.get("sweep_spec")
    except Exception:  # not a readable Zarr group
        text = None
    if text is None:
        raise _incomplete(path, "has no readable sweep_spec attribute")
    try:
        return SweepSpec.from_json(text)
    except (ValueError, TypeError) as exc:
        raise _incomplete(path, f"has unreadable settings ({str(exc).splitlines()[0]})") from None


def write_chunk(grp, spec: SweepSpec, iy, ix, values: dict):
    """Write one finished chunk into its region, then its checksum, then its done flag."""
    ys, xs = spec.chunk_slices(iy, ix)
    for name in spec.variables:
        grp[name][ys, xs] = np.asarray(values[name], dtype=_dtype(name))
    grp["chunk_checksum"][iy, ix] = chunk_checksum(spec, values)
    grp["chunk_done"][iy, ix] = 1


def done_chunks(grp) -> np.ndarray:
    """Boolean ``(chunk_y, chunk_x)`` array of the chunks flagged finished (flags only: resuming
    checks each one's data, :func:`verified_chunks`).

    Parameters
    ----------
    grp : zarr.Group
        The store (:func:`open_store`).

    Returns
    -------
    ndarray of bool

    Raises
    ------
    KapitzaValueError
        If ``grp`` is not a sweep store (no chunk flags).

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> from kapitza.sweeps import SweepSpec, done_chunks, open_store, sweep
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",), chunk=2)
    >>> folder = tempfile.mkdtemp()
    >>> run = sweep(spec, os.path.join(folder, "map.zarr"), serial=True, progress=False)
    >>> done_chunks(open_store(run.store)).shape
    (2, 2)
    >>> shutil.rmtree(folder)
    """
    try:
        flags = grp["chunk_done"]
    except (TypeError, KeyError, AttributeError):
        raise _v.KapitzaValueError(f"grp must be a sweep store opened by open_store; got {type(grp).__name__}") \
            from None
    return np.asarray(flags[...]) == 1


class StoreCheck:
    """What :func:`verified_chunks` found: ``done`` (bool per chunk: flagged and its data checked),
    ``damaged`` (chunks flagged finished whose data is missing, unreadable or not what was written),
    ``notes`` (store-wide repairs, one phrase each)."""

    def __init__(self, done, damaged, notes):
        self.done, self.damaged, self.notes = done, damaged, notes


def _read(arr, sel=Ellipsis):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return np.asarray(arr[sel])


def _rewrite(grp, name, value):
    """Overwrite a whole small array, first removing a damaged chunk file that would be read back."""
    try:
        grp[name][...] = value
    except Exception:
        for f in (Path(grp.store.root) / name).iterdir():
            if not f.name.startswith("."):
                f.unlink()
        grp[name][...] = value


def verified_chunks(grp, spec: SweepSpec) -> StoreCheck:
    """Check every chunk flagged finished against its checksum, and repair what is store-wide.

    The coordinates are compared with ``spec`` and rewritten if lost or damaged; unreadable done
    flags or checksums are reset (every chunk is then recomputed). A flagged chunk whose values
    cannot be read (a truncated chunk file) or whose CRC-32 differs from the one stored (a lost
    chunk file reads as the fill value) is reported in ``damaged`` and its flag cleared.
    """
    notes = []
    if "chunk_checksum" not in grp or "chunk_done" not in grp:
        raise _v.KapitzaValueError(
            "store must carry per-chunk checksums to be resumed; "
            f"{str(grp.store.root)!r} was made by an older kapitza without them, so its finished chunks cannot be "
            "verified: run the sweep again into a new store")
    yn, xn = spec.dims
    for name, want in ((yn, np.asarray(spec.y)), (xn, np.asarray(spec.x))):
        try:
            ok = np.array_equal(_read(grp[name]), want)
        except Exception:
            ok = False
        if not ok:
            _rewrite(grp, name, want)
            notes.append(f"coordinate {name} rewritten")
    try:
        flags = _read(grp["chunk_done"]) == 1
        sums = _read(grp["chunk_checksum"])
    except Exception:
        flags = np.zeros(spec.chunk_shape, dtype=bool)
        sums = np.zeros(spec.chunk_shape, dtype=np.int32)
        notes.append("done flags or checksums unreadable: every chunk recomputed")
        _rewrite(grp, "chunk_checksum", sums)
        _rewrite(grp, "chunk_done", np.zeros(spec.chunk_shape, dtype="int8"))
    damaged = []
    for iy, ix in zip(*np.nonzero(flags)):
        ys, xs = spec.chunk_slices(iy, ix)
        try:
            values = {name: _read(grp[name], (ys, xs)) for name in spec.variables}
            good = chunk_checksum(spec, values) == int(sums[iy, ix])
        except Exception:  # a truncated or otherwise unreadable chunk file
            good = False
        if not good:
            flags[iy, ix] = False
            damaged.append((int(iy), int(ix)))
    if damaged:
        for iy, ix in damaged:
            grp["chunk_done"][iy, ix] = 0
            _drop_chunk_files(grp, spec, iy, ix)
    return StoreCheck(flags, damaged, notes)


def _drop_chunk_files(grp, spec, iy, ix):
    """Remove the chunk files of a damaged chunk so that its rewrite never reads them back."""
    root = Path(grp.store.root)
    for name in spec.variables:
        f = root / name / f"{iy}.{ix}"
        try:
            f.unlink()
        except FileNotFoundError:
            pass


def open_sweep(path):
    """The sweep as an :class:`xarray.Dataset` (lazy, backed by the Zarr store).

    Values are as stored (no masking): a point not computed holds its variable's ``_FillValue``
    (NaN, or -2 for ``zone``, -1 for ``stable``), so the integer variables keep their dtype.

    Parameters
    ----------
    path : path
        The sweep's Zarr store.

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    ValueError
        If ``path`` is not a sweep's store.

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> from kapitza.sweeps import SweepSpec, open_sweep, sweep
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",))
    >>> folder = tempfile.mkdtemp()
    >>> run = sweep(spec, os.path.join(folder, "map.zarr"), serial=True, progress=False)
    >>> ds = open_sweep(run.store)
    >>> ds.stable.dims, ds.stable.values
    (('mu', 'eps'), array([[1, 1, 0, 0],
           [0, 1, 1, 0],
           [0, 1, 1, 0]], dtype=int8))
    >>> round(float(ds.margin.sel(eps=0.5, mu=0.3, method="nearest")), 4)
    0.2617
    >>> shutil.rmtree(folder)
    """
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise _v.KapitzaValueError(f"store must be an existing sweep store; got {str(path)!r} (no such path)")
    stored_spec(path)  # a clear error for what is not a complete store
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xr.open_zarr(str(path), consolidated=(path / ".zmetadata").exists(), mask_and_scale=False)


def to_netcdf(ds, path):
    """Write the Dataset as NetCDF (classic 64-bit format via scipy, no extra library), atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep (:func:`open_sweep`).
    path : path
        The ``.nc`` file to write.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    KapitzaValueError
        If ``ds`` is not an :class:`xarray.Dataset`; nothing is written then.

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> import xarray as xr
    >>> from kapitza.sweeps import SweepSpec, open_sweep, sweep, to_netcdf
    >>> spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",))
    >>> folder = tempfile.mkdtemp()
    >>> run = sweep(spec, os.path.join(folder, "map.zarr"), serial=True, progress=False)
    >>> path = to_netcdf(open_sweep(run.store), os.path.join(folder, "map.nc"))
    >>> path.name
    'map.nc'
    >>> with xr.open_dataset(path) as nc:
    ...     print(nc.growth.dims, nc.attrs["plane"])
    ('mu', 'eps') arnold
    >>> shutil.rmtree(folder)
    """
    import xarray as xr

    if not isinstance(ds, xr.Dataset):
        raise _v.KapitzaValueError(f"ds must be an xarray.Dataset (open_sweep); got {type(ds).__name__}")
    with atomic_path(path, suffix=".nc") as tmp:
        ds.load().to_netcdf(tmp, engine="scipy")
    return Path(path)
