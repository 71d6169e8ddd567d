"""One point's searches narrowed on the compiled engine (``engines._compiled.narrow_rows``): the same
answers as the numpy search, and brackets that hold the engine's own change."""
import numpy as np
import pytest

import kapitza
from kapitza.drives import _api, from_samples
from kapitza.engines import magnus

pytest.importorskip("numba")
from kapitza.engines import _compiled  # noqa: E402


class _Smooth(kapitza.Drive):
    name = "smooth-rows-test"

    def _shape(self, tau):
        return np.sin(np.pi * tau) + 0.3 * np.sin(3.0 * np.pi * tau)


def _drives():
    t = np.arange(24) / 24.0
    return [kapitza.TriangleWave(), from_samples(t, np.sin(2 * np.pi * t) + 0.2 * np.cos(6 * np.pi * t)), _Smooth()]


@pytest.fixture(scope="module")
def compiled():
    assert magnus.load_compiled()


@pytest.mark.parametrize("damping", [0.0, 0.2])
@pytest.mark.parametrize("drive", _drives(), ids=lambda d: d.describe())
def test_the_reports_are_those_of_the_numpy_search(drive, damping, compiled, monkeypatch):
    rng = np.random.default_rng(17)
    pts = [(float(np.exp(rng.uniform(np.log(0.02), np.log(0.5)))), float(np.exp(rng.uniform(np.log(20.0), np.log(5e3)))))
           for _ in range(8)]
    calls = []
    narrow = _compiled.narrow_rows
    monkeypatch.setattr(_compiled, "narrow_rows", lambda *a: calls.append(1) or narrow(*a))
    fast = [str(kapitza.analyze(drive=drive, T=T, A=A, damping=damping)) for T, A in pts]
    assert len(calls) >= len(pts)   # (the compiled rows did run)
    monkeypatch.setattr(_api, "_narrowed_compiled", lambda *a: None)
    slow = [str(kapitza.analyze(drive=drive, T=T, A=A, damping=damping)) for T, A in pts]
    assert fast == slow


@pytest.mark.parametrize("seed", range(3))
def test_the_brackets_hold_the_engines_own_change(seed, compiled):
    drive = kapitza.TriangleWave()
    eng = drive._engine
    rng = np.random.default_rng(seed)
    mu = float(rng.uniform(0.1, 0.9))
    n = int(rng.integers(0, 3))
    lo_e, hi_e = kapitza.zone_edges(mu, n, drive=drive)
    grid = eng.grid(int(eng.steps_for(np.array([4.0 * float(hi_e)]), np.array([mu]))[0]))
    # the lower and the upper edge of zone n along eps, from brackets a binade wide
    lo = np.array([0.5 * float(lo_e), 0.5 * float(hi_e)])
    hi = np.array([2.0 * float(lo_e), 2.0 * float(hi_e)])
    spec = ([0, 0], [mu, mu], [0.0, 0.0], [0.0, 0.0], [n, n], [1, 0], [-1.0, 1.0], [0, 1])
    a, b, fa, fb = _compiled.narrow_rows(grid, *spec, lo, hi, 1 << 36, 1 << 16)
    assert np.all(b.view(np.int64) - a.view(np.int64) <= 1 << 36)
    out = _compiled.run(grid, np.concatenate([a, b]), np.full(4, mu), True, True)
    level = np.where(out[:, 3] >= 0, out[:, 3] + 0.5, np.rint(out[:, 2] / np.pi))
    # lower edge: level > n False at a, True at b; upper edge: level >= n + 1 the same
    assert level[0] <= n < level[2] and level[1] < n + 1 <= level[3]
    # the certified edges lie in the brackets, to the engine's accuracy
    for edge, x0, x1 in zip((lo_e, hi_e), a, b):
        assert x0 * (1.0 - 1e-9) <= float(edge) <= x1 * (1.0 + 1e-9)
    assert np.all(np.isfinite(fa)) and np.all(np.isfinite(fb)) and np.all(fa <= 0) and np.all(fb >= 0)
