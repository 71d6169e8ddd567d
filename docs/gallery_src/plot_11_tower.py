"""
The tower: linked pendulums on one pivot
========================================

One, two and three uniform rods of 20 cm, hinged one on another, on a square-wave pivot. A tower
of ``N`` links moves in ``N`` modes, each a single pendulum of its own equivalent length ``l_k``;
the tower stands where every mode is stable (shaded). The longest mode sets the lower edge
(solid: below it, too slow, the tower leans over and falls), the shortest mode the upper one
(dashed: beyond it, too large a stroke, that mode doubles its period). Each link added lengthens
the longest mode and shortens the shortest, so the band narrows from both sides: at 200 Hz the
largest safe stroke falls from 117 mm (one rod) to 16 mm (three), and the lowest frequency
at a 5 mm stroke rises from 99 Hz to 174 Hz. The star, 200 Hz with a 5 mm stroke, holds all
three up. The thin strip above the two-link band is real: there mode 2 sits in its narrow zone 1.
``kapitza tower --chain 0.2,0.2,0.2 --frequency 200 --stroke 0.005`` draws this figure.
"""
import matplotlib.pyplot as plt

import kapitza
from kapitza.figures.tower import tower_chart_figure, tower_family

towers = tower_family(0.2, n_max=3)
for tower in towers:
    report = kapitza.analyze_chain(tower, frequency=200.0, stroke=0.005)
    lengths = ", ".join(f"{1e3 * l:.1f}" for l in tower.modal_lengths)
    print(f"{tower.n} link(s), modes l_k = {lengths} mm: stable {report.stable}; at 5 mm it stands above "
          f"{report.frequency_lo:.0f} Hz, at 200 Hz for strokes up to {1e3 * report.stroke_hi:.0f} mm")

fig, drawn = tower_chart_figure(towers, mark=(200.0, 0.005))
plt.show()
