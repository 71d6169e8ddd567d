"""
The pendulum stands: motion and phase portrait
==============================================

A 1 m rod, ``A = 100 m/s^2``, half-period ``T = 0.15 s`` (zone 0), started 0.1 rad from the upright
at rest: the real (nonlinear) pendulum rocks slowly about the upright, with the fast shake of the
drive on top. The phase portrait marks the states at ``t = 2kT`` (the stroboscopic map).
"""
import matplotlib.pyplot as plt

import kapitza
from kapitza.figures import plot_phase_portrait, plot_time_series

traj = kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=40)
fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
plot_time_series(traj, a, legend="inside")
a.set_xlabel("t (s)")
plot_phase_portrait(traj, b, legend="inside")
plt.show()

# %%
# Outside every zone (``T = 0.3 s``) the same start falls over:
print(kapitza.simulate(0.1, 0.0, T=0.3, A=100.0, periods=10).summary()["stays_up"])
