"""A report's edges searched together equal the same edges searched one question at a time.

``analyze`` asks ``Drive.point_edges``: for a point inside a zone, the margin's two edges in ``eps``
and the rig's four (along ``A`` and the frequency) are found in one search, the brackets narrowed
by the ladders' rungs and the certified levels shared. Here the same reports are made with that
joint search switched off (``point_margin``, then ``point_intervals``) and compared field by field,
for the step drives and the damped square wave.
"""
import numpy as np
import pytest

import kapitza as K
from kapitza.drives import Drive

DRIVES = [K.RectangularWave(0.3), K.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3]), K.SquareWave()]


def _reports(drive, points, zeta):
    return [K.analyze(T=T, A=A, drive=drive, zeta=zeta).as_dict() for T, A in points]


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.describe())
@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_the_joint_search_gives_the_reports_of_the_separate_ones(drive, zeta, monkeypatch):
    if isinstance(drive, K.SquareWave) and zeta == 0.0:
        pytest.skip("the square wave's undamped report comes from its closed forms")
    rng = np.random.default_rng(17)
    points = [(float(rng.uniform(0.05, 0.35)), float(10 ** rng.uniform(1.5, 3.0))) for _ in range(4)]
    # one point certainly inside zone 0 (the upright held), so the joint path is taken
    lo, hi = (float(v) for v in K.zone_edges(0.3, 0, drive=drive, zeta=zeta))
    A = 9.80665 / 0.3 ** 2
    points.append((0.5 * (lo + hi) * np.sqrt(8.0 / A), A))
    joint = _reports(drive, points, zeta)
    assert any(r["stable"] for r in joint)
    monkeypatch.setattr(Drive, "_joint_edges", lambda self, zeta: False)
    monkeypatch.setattr(type(drive), "_joint_edges", lambda self, zeta: False)
    separate = _reports(drive, points, zeta)
    assert joint == separate
