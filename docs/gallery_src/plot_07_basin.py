"""
Basin: which starts stay up
===========================

Over a grid of starting tilts and tilt rates, how many periods the pendulum stays within 0.5 rad of
the upright (zone 0, ``T = 0.15 s``, ``A = 100 m/s^2``, a 1 m rod).
"""
import matplotlib.pyplot as plt

import kapitza
from kapitza.figures import plot_basin

b = kapitza.basin(0.15, 100.0, periods=30, tol=0.5, n_theta=61, n_dtheta=61)
fig, ax = plt.subplots(figsize=(7, 5), layout="constrained")
plot_basin(b, ax)
plt.show()
