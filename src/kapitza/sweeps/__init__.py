"""Nonlinear stability maps over the parameter plane, chunked, on Dask, into a Zarr store.

``docs/sweeps.md``. For a grid of ``(eps, mu)`` or ``(T, A)`` a sweep computes per point the
largest safe starting tilt at rest, the largest safe radius over the directions of the phase
plane, the basin area and the median escape time of the upright for ``N`` periods
(:mod:`kapitza.sweeps.kernel`), beside the exact linear verdict, zone, growth and margin. Chunks
of the grid run on a Dask cluster (local by default) or serially, each written to the store as
it finishes, so an interrupted sweep resumes without losing or repeating finished work.

Needs the ``sweep`` extra (dask[distributed], zarr, xarray, tqdm); ``import kapitza`` does not
load this package.
"""
from .kernel import QUANTITIES, VARIABLES
from .spec import SweepSpec
from .run import SweepRun, compute_chunk, sweep
from .store import done_chunks, open_store, open_sweep, to_netcdf

__all__ = ["QUANTITIES", "VARIABLES", "SweepSpec", "SweepRun", "sweep", "compute_chunk", "open_sweep",
           "open_store", "done_chunks", "to_netcdf"]
