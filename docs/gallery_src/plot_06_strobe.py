"""
Stroboscopic map: the island about the upright
==============================================

Many starts, each looked at once per drive period ``2T``: near the upright the states lie on closed
curves (the pendulum stays up); further out they scatter (it falls).
"""
import matplotlib.pyplot as plt
import numpy as np

import kapitza
from kapitza.figures import plot_strobe

theta0 = np.linspace(-0.9, 0.9, 25)
orbits = kapitza.stroboscopic_map(theta0, 0.0, 0.15, 100.0, periods=150, every=1)
fig, ax = plt.subplots(figsize=(7, 5), layout="constrained")
plot_strobe(orbits, ax)
plt.show()
