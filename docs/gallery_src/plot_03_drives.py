"""
Square wave, sine and a 30 % duty cycle
=======================================

Three drives with the same meaning of ``T`` (half the drive period) and ``A`` (the acceleration
scale), so their zones share Arnold's axes. Dashed: each drive's high-frequency (averaging)
criterion ``<v_pivot^2> > g l``.
"""
import matplotlib.pyplot as plt
import numpy as np

from kapitza import RectangularWave, SineWave, SquareWave
from kapitza.figures import drive_curves, plot_drive_comparison

mu = np.linspace(0.01, 0.99, 120)
curves = [drive_curves(d, mu, eps_max=2.5) for d in (SquareWave(), SineWave(), RectangularWave(0.3))]
fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
drawn = plot_drive_comparison(curves, ax, eps_range=(0, 2.5))
plt.show()
