"""
Damping widens the zones
========================

Viscous friction ``theta'' + c theta' = ...`` with damping ratio ``zeta = c / (2 sqrt(g/l))``:
the square wave's zones without damping (filled) and with ``zeta = 0.3`` (outlined, dash-dotted).
Damping moves the upper edges right more than the lower ones, so every zone widens, most where
``mu`` is large (weak shaking): at ``mu = 0.6`` zone 0 is a quarter wider and the thin zone 1
(magnified on the right) four times wider.
"""
import matplotlib.pyplot as plt
import numpy as np

from kapitza import SquareWave
from kapitza.figures import drive_curves, plot_drive_comparison

mu = np.linspace(0.005, 0.99, 160)
curves = [drive_curves(SquareWave(), mu, eps_max=2.5), drive_curves(SquareWave(), mu, eps_max=2.5, zeta=0.3)]
fig, (whole, zoom) = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
plot_drive_comparison(curves, whole, eps_range=(0, 2.5), averaging=False)
whole.set_title("the whole chart")
plot_drive_comparison(curves, zoom, eps_range=(1.7, 2.4), mu_range=(0.2, 0.62), averaging=False, legend=None)
zoom.set_title("zone 1, magnified")
plt.show()
