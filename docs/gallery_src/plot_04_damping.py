"""
Damping widens the zones
========================

Viscous friction ``theta'' + c theta' = ...`` with damping ratio ``zeta = c / (2 sqrt(g/l))``:
the square wave's zones without damping (filled) and with ``zeta = 0.2`` (outlined, dash-dotted).
"""
import matplotlib.pyplot as plt
import numpy as np

from kapitza import SquareWave
from kapitza.figures import drive_curves, plot_drive_comparison

mu = np.linspace(0.01, 0.99, 100)
curves = [drive_curves(SquareWave(), mu, eps_max=2.5), drive_curves(SquareWave(), mu, eps_max=2.5, zeta=0.2)]
fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
drawn = plot_drive_comparison(curves, ax, eps_range=(0, 2.5), averaging=False)
plt.show()
