"""The sine drive's compiled kernels (:mod:`kapitza.engines._sine`) against their numpy forms: Hill's
continuant and the half period's Taylor steps, the same arithmetic in the same order."""
import numpy as np
import pytest

from kapitza.drives import _mathieu as M
from kapitza.engines import magnus

pytest.importorskip("numba")
from kapitza.engines import _sine  # noqa: E402


def both(f, monkeypatch):
    """``f()`` with the numpy kernels, then with the compiled ones (which must have run: each kernel
    called is counted)."""
    with monkeypatch.context() as m:
        m.setattr(magnus, "compiled_sine", lambda: None)
        ref = f()
    calls = []
    with monkeypatch.context() as m:
        m.setattr(magnus, "compiled_sine", lambda: _sine)
        for name in ("continuant", "half_period_steps", "count"):
            kernel = getattr(_sine, name)
            m.setattr(_sine, name, lambda *a, _k=kernel: calls.append(1) or _k(*a))
        got = f()
    assert calls, "the compiled kernels did not run"
    return ref, got


def same(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    # equal where numpy's vector log, cos and sin equal the C library's; within a few ulp anywhere
    np.testing.assert_allclose(b, a, rtol=1e-14, atol=0, equal_nan=True)


@pytest.mark.parametrize("seed", range(4))
def test_the_compiled_continuant_is_hills(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    q = 10.0 ** rng.uniform(-8, 6, 12)
    a = -2.0 * rng.uniform(0.01, 2.0, q.size) ** 2 * q
    ref, got = both(lambda: M._hill_half_trace(a, q), monkeypatch)
    for x, y in zip(ref, got):
        same(x, y)
    ref, got = both(lambda: M._hill_half_trace(a, q, minus_one=True), monkeypatch)
    same(ref, got)


def test_the_compiled_continuant_keeps_the_products_shape_and_its_nans(monkeypatch):
    p = np.random.default_rng(5).uniform(-0.3, 0.3, (2, 3, 37))
    p[1, 2, 5] = np.nan
    p[0, 1, 9] = 1e300
    with np.errstate(invalid="ignore", over="ignore"):
        ref, got = both(lambda: M._continuant(p), monkeypatch)
    assert got[0].shape == got[1].shape == (2, 3)
    assert np.isnan(got[0][1, 2]) and np.isfinite(got[0][0, 0])
    for x, y in zip(ref, got):
        same(x, y)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("bound", ["quick", None])
def test_the_compiled_half_period_is_the_numpy_one(seed, bound, monkeypatch):
    rng = np.random.default_rng(seed)
    eps = np.concatenate([rng.uniform(1e-3, 2.0, 20), rng.uniform(2.0, 80.0, 6)])
    mu = rng.uniform(0.0, 1.5, eps.size)
    ref, got = both(lambda: M._half_period(eps, mu, bound=bound), monkeypatch)
    for x, y in zip(ref, got):
        same(x, y)


def test_the_traces_and_verdicts_of_the_sine_drive_agree(monkeypatch):
    rng = np.random.default_rng(9)
    eps, mu = rng.uniform(0.01, 6.0, 64), rng.uniform(0.0, 1.0, 64)
    ref, got = both(lambda: M._sine_traces(eps, mu, bound="quick"), monkeypatch)
    for x, y in zip(ref, got):
        same(x, y)
    import kapitza

    ref, got = both(lambda: kapitza.is_stable(eps, mu, drive="sine", zeta=0.05), monkeypatch)
    assert np.array_equal(ref, got)


@pytest.mark.parametrize("seed", range(3))
def test_the_compiled_sturm_counts_are_the_numpy_ones(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    n = 400
    fam = rng.integers(0, 4, n)
    q = np.concatenate([10.0 ** rng.uniform(-6, 6, n - 8), np.zeros(4), np.full(4, 1e8)])
    # values about the characteristic values: around r^2, and some exactly on a diagonal entry
    r = rng.integers(0, 60, n).astype(float)
    x = r * r + rng.normal(0.0, 1.0, n) * np.sqrt(q + 1.0)
    x[:10] = (2.0 * r[:10]) ** 2
    ref, got = both(lambda: M._count(fam, q, x), monkeypatch)
    assert got.dtype == ref.dtype and np.array_equal(ref, got)
