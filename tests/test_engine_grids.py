"""The generic engine's grids: formed a block of steps at a time, kept within a byte budget."""
import numpy as np
import pytest

import kapitza
from kapitza.drives import from_samples
from kapitza.engines import magnus

FIELDS = ("h", "x", "s2", "p1", "p2", "p2m", "q1", "q2", "r1", "r2", "r2m", "r3", "r3m")


def _drives():
    t = np.arange(37) / 37.0
    return [kapitza.TriangleWave(), kapitza.SineWave(), kapitza.RectangularWave(0.3),
            from_samples(t, np.sin(2 * np.pi * t) + 0.3 * np.cos(6 * np.pi * t))]


@pytest.mark.parametrize("drive", _drives(), ids=lambda d: d.describe())
@pytest.mark.parametrize("block", [1, 7, 64])
def test_a_grid_formed_in_blocks_is_the_grid_formed_at_once(drive, block, monkeypatch):
    eng = drive._engine
    n = 256
    whole = magnus.Grid(eng.shape, eng.breaks, n)
    monkeypatch.setattr(magnus, "_GRID_BLOCK", block)
    parts = magnus.Grid(eng.shape, eng.breaks, n)
    assert parts.m == whole.m
    for name in FIELDS:
        assert np.array_equal(getattr(parts, name), getattr(whole, name)), name
    assert np.array_equal(parts.s_nodes, whole.s_nodes)


def test_the_grids_kept_stay_within_their_budget_and_give_the_same_answers(monkeypatch):
    drive = kapitza.TriangleWave()
    eng = drive._engine
    eps = np.array([0.4, 3.0, 40.0, 300.0])
    mu = np.full(eps.size, 0.3)
    before = eng.floquet(eps, mu)
    monkeypatch.setattr(type(eng), "GRID_BYTES", 128 * 4096)   # room for 4096 steps
    eng._grids.clear()
    seen = []
    for e in eps:
        eng.floquet(np.array([e]), np.array([0.3]))
        seen.append(sorted(eng._grids))
        assert sum(eng._grids) <= 4096 or len(eng._grids) == 1
    after = eng.floquet(eps, mu)
    for a, b in zip(before, after):
        np.testing.assert_array_equal(a, b)
    # (the largest grid, past the budget on its own, was kept alone)
    assert len(seen[-1]) == 1
