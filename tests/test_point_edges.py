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


@pytest.mark.parametrize("drive", [K.SineWave(), K.TriangleWave()], ids=lambda d: d.describe())
@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_the_rigs_edges_of_a_drive_without_steps_are_the_one_at_a_time_answers(drive, zeta):
    """The rig's four edges searched together (every drive) against ``amplitude_edges`` (its own
    bisection along A) and the verdict either side of each frequency edge."""
    l, g = 1.0, 9.80665
    for mu, n, where in [(0.3, 0, 0.5), (0.5, 1, 0.3), (0.2, 0, 0.9)]:
        lo, hi = (float(v) for v in K.zone_edges(mu, n, drive=drive, zeta=zeta))
        A = g / mu**2
        T = (lo + where * (hi - lo)) * np.sqrt(8.0 * l / A)
        rep = K.analyze(T=T, A=A, l=l, g=g, drive=drive, zeta=zeta)
        assert rep.stable and rep.zone == n
        assert (rep.A_lo, rep.A_hi) == tuple(float(v) for v in K.amplitude_edges(T, n, l, g, drive=drive, zeta=zeta))
        # at this stroke, the frequency f: T = 1 / (2 f), A = stroke / (k T^2)
        k = rep.stroke / (A * T * T)
        for f, inside in [(rep.frequency_lo, 1.0 + 1e-9), (rep.frequency_lo, 1.0 - 1e-9),
                          (rep.frequency_hi, 1.0 - 1e-9), (rep.frequency_hi, 1.0 + 1e-9)]:
            if not np.isfinite(f):
                continue
            Tf = 0.5 / (f * inside)
            stable = K.analyze(T=Tf, A=rep.stroke / (k * Tf * Tf), l=l, g=g, drive=drive, zeta=zeta).zone == n
            assert stable == ((f == rep.frequency_lo) == (inside > 1.0))
