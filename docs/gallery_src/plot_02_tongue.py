"""
A thin tongue, magnified
========================

Zones 1, 2, ... are tongues far thinner than a pixel of the whole chart. ``plot_tongue`` frames
zone ``n`` about its midpoint so both of its edges are seen apart, here zone 2.
"""
import matplotlib.pyplot as plt

from kapitza.figures import plot_tongue

fig, ax = plt.subplots(figsize=(7, 5), layout="constrained")
drawn = plot_tongue(2, ax, mu_range=(0.0, 0.6))
plt.show()
