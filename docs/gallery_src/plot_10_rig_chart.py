"""
A real rig: frequency against stroke
====================================

How a shaker is set: its frequency and its stroke (the pivot's peak-to-peak travel). A uniform
rod 30 cm long (equivalent length ``l = 2 L / 3 = 0.2`` m, a little friction) on a pivot driven
with the paper's square-wave acceleration at 40 Hz and a 20 mm stroke stands (the star). At that
stroke it keeps standing down to about 30 Hz, below which it falls; at 40 Hz the stroke may grow
almost nine times (to 176 mm) before the rod starts to double its period (zone 0's upper edge, dashed).
Both axes are logarithmic; the zones are the exact edges of Arnold's plane, mapped point by
point. ``kapitza chart --plane rig --rod 0.3 --frequency 40 --stroke 0.02`` draws this figure;
``drive=kapitza.SineWave()`` gives a sinusoidal shaker's.
"""
import matplotlib.pyplot as plt

import kapitza
from kapitza.figures.chart import rig_chart_figure

rig = kapitza.Rig(kapitza.Pendulum.uniform_rod(0.3, damping=0.2))
report = rig.analyze(frequency=40.0, stroke=0.02)
print(report.verdict)
print(f"at 20 mm it stands above {report.frequency_lo:.1f} Hz; "
      f"at 40 Hz for {1e3 * report.stroke_lo:.1f} mm < stroke < {1e3 * report.stroke_hi:.0f} mm")

fig, curves, _ = rig_chart_figure(l=rig.pendulum.l, drive=rig.drive, zeta=rig.pendulum.zeta,
                                  mark=(report, "40 Hz, 20 mm"), rod=0.3,
                                  title="A 30 cm rod on a square-wave shaker")
plt.show()
