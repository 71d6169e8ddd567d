"""
The paper's Figure 7: the stability zones
=========================================

The upright pendulum is stable exactly in the shaded zones of Arnold's plane
(``eps = T sqrt(A/(8 l))``, ``mu = sqrt(g/A)``), bounded by the curves on which a ``2T``-periodic
(solid) or a ``4T``-periodic (dashed) motion exists (Csizmadia & Hatvani, Theorems 3.3-3.4).
The edges are computed exactly for this window, not interpolated on a grid.
"""
import matplotlib.pyplot as plt

from kapitza.figures import plot_zones

fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
drawn = plot_zones(ax, eps_range=(0, 4), mu_range=(0, 1), legend="outside")
ax.set_title("Stability zones of the inverted pendulum on a square-wave pivot")
plt.show()
