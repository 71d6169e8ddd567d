"""
A sweep: the largest safe tilt over the chart
=============================================

For every point of a small grid of Arnold's plane, the largest starting tilt from rest from which
the real pendulum stays within 0.5 rad of the upright for 60 periods, with the exact zone edges on
top. ``kapitza sweep`` computes such maps at any size on a Dask cluster and resumes an interrupted
run; here a 32 x 20 grid is computed in this process (``serial=True``) into a Zarr store.
"""
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from kapitza.figures.sweep import plot_sweep_map
from kapitza.sweeps import SweepSpec, open_sweep, sweep

spec = SweepSpec.window((0.05, 1.6), (0.02, 0.9), (32, 20), periods=60, quantities=("tilt",))
with tempfile.TemporaryDirectory() as tmp:
    sweep(spec, Path(tmp) / "small.zarr", serial=True, progress=False)
    ds = open_sweep(Path(tmp) / "small.zarr").load()

fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
plot_sweep_map(ds.eps.values, ds.mu.values, ds.max_safe_tilt.values, ax=ax, label="largest safe tilt (rad)")
ax.set_title("Largest safe starting tilt, 60 periods, within 0.5 rad")
plt.show()
