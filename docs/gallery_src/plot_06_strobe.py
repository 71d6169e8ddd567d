"""
Stroboscopic map: the island about the upright
==============================================

Many starts from rest, each looked at once per drive period ``2T`` (zone 0, ``T = 0.15 s``,
``A = 100 m/s^2``, a 1 m rod). Near the upright the states lie on closed curves: an island of
motions that stay up. Started further out, the states scatter and the pendulum falls.
``strobe_figure`` frames the island and counts the starts that stay up.
"""
import matplotlib.pyplot as plt
import numpy as np

import kapitza
from kapitza.figures import strobe_figure

theta0 = np.linspace(-0.6, 0.6, 25)
orbits = kapitza.stroboscopic_map(theta0, 0.0, 0.15, 100.0, periods=200, every=1)
fig = strobe_figure(orbits)
plt.show()
