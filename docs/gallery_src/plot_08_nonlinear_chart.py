"""
The nonlinear chart: is the real pendulum stable?
=================================================

Inside the zones the linearised upright is stable; the real pendulum is Lyapunov stable wherever
the twist of its period map is non-zero (Moser's theorem), except on the 1:4 resonance where
Markeev's criterion decides. The chart draws the 1:3 and 1:4 resonance curves in zones 0 and 1,
shades the size of the twist across each zone, and would draw the zeros of the twist (it finds none
here: the caption says so).
"""
import matplotlib.pyplot as plt

from kapitza.figures.nonlinear import nonlinear_chart_figure

fig = nonlinear_chart_figure(zones=(0, 1), scan=20, across=21)
plt.show()
