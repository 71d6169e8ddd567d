"""The compiled survival kernel (numba) and the numpy loops are twins: the same phase flows, the same
window test, the same scan and bisection, so the same results (to rounding: a start that leaves the
window by less than the last bits of its trajectory may be judged differently)."""
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("numba")

import kapitza
from kapitza.motion._elliptic import _phase_step
from kapitza.motion.basins import survival_chunk
from kapitza.sweeps.kernel import block_quantities, period_step, ray_radii

G = kapitza.parameters.G_EARTH


def _jit():
    import kapitza.motion._survival_jit as J

    return J


def test_phase_flow_agrees_with_the_numpy_flow_to_rounding():
    """Every branch: libration (AGM and theta series), rotation, the separatrix region, both signs of s."""
    J = _jit()
    rng = np.random.default_rng(3)
    n = 4000
    th = rng.uniform(-3, 3, n) * 10.0 ** rng.uniform(-8, 0, n)
    om = rng.normal(0, 5, n) * 10.0 ** rng.uniform(-8, 0.5, n)
    s2 = rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-1, 3, n)
    t = 10.0 ** rng.uniform(-3, 0, n)
    want_th, want_om = _phase_step(th, om, s2, t)
    work = np.empty(18)
    got = np.array([J.phase_step(*args, work) for args in zip(th, om, s2, t)])
    w = np.sqrt(np.abs(s2))
    # errors relative to the size of the motion: the energy scale of the state before and after
    scale = np.abs(th) + np.abs(om) / w + np.abs(want_th) + np.abs(want_om) / w
    assert np.max(np.abs(got[:, 0] - want_th) / scale) < 1e-12
    assert np.max(np.abs(got[:, 1] - want_om) / (w * scale)) < 1e-12
    assert np.mean(got[:, 0] == want_th) > 0.5  # mostly the very same bits


def test_survival_counts_agree_with_the_numpy_loop():
    eps, mu = 0.55, 0.3
    T, A = (float(v) for v in kapitza.to_physical(eps, mu))
    period = period_step(np.array([T]), np.array([A]), 1.0, G, 0.0, kapitza.drives.parse_drive("square"), 0.5)
    th = np.linspace(-0.5, 0.5, 41)
    om = np.linspace(-1.0, 1.0, 41) / T
    th0, om0 = (a.ravel() for a in np.meshgrid(th, om))
    point = np.zeros(th0.size, dtype=np.int64)
    want = survival_chunk(th0, om0, period, 300, 0.5, idx=point)
    got = _jit().survival_compiled(th0, om0, point, *_jit().pack_plan(period.subs, 1), 300, 0.5)
    assert 0.03 < np.mean(want == 300) < 0.9  # both outcomes occur
    assert np.mean(got == want) >= 0.995


def test_ray_radii_agree_with_the_numpy_searches():
    eps, mu = np.meshgrid(np.linspace(0.1, 2.5, 9), np.linspace(0.05, 0.9, 7))
    T, A = (np.asarray(v, float).ravel() for v in kapitza.to_physical(eps, mu))
    period = period_step(T, A, 1.0, G, 0.0, kapitza.drives.parse_drive("rectangular:0.4"), 0.5)
    phis = np.pi * np.arange(4) / 4
    want = ray_radii(T, period, phis, 150, 0.5, 0.01, 1e-4, compiled=False)
    got = ray_radii(T, period, phis, 150, 0.5, 0.01, 1e-4, compiled=True)
    assert np.count_nonzero(want > 0.01) >= 20
    assert np.mean(got == want) >= 0.98


@pytest.mark.parametrize("drive", ["square", "steps:1,-0.5,-0.25:0.3,0.5,0.2"])
def test_maps_agree_with_the_numpy_path(drive):
    kw = dict(plane="arnold", l=1.0, g=G, drive=drive, periods=120, tol=0.5, quantities=("tilt", "radius", "basin"),
              directions=3, basin_resolution=5, accuracy=0.01, floor=1e-4)
    eps, mu = np.linspace(0.05, 3.0, 11), np.linspace(0.02, 0.98, 10)
    want = block_quantities(eps, mu, compiled=False, **kw)
    got = block_quantities(eps, mu, compiled=True, **kw)
    assert np.count_nonzero(want["max_safe_tilt"] > 0) >= 8
    for k in want:
        assert got[k].dtype == want[k].dtype
        assert np.mean(got[k] == want[k]) >= 0.97, k


def test_the_integrated_path_takes_its_own_compiled_twin():
    """The sine drive or damping has no exact flow: ``compiled`` picks the compiled DOP853 per state
    (tests/test_integrated_jit.py) or the numpy DOP853 loop; they agree to the search's accuracy."""
    kw = dict(plane="arnold", l=1.0, g=G, drive="sine", periods=5, tol=0.5, quantities=("tilt",), directions=1,
              basin_resolution=5, accuracy=0.01, floor=1e-4)
    a = block_quantities([0.4, 0.6], [0.2], compiled=False, **kw)["max_safe_tilt"]
    b = block_quantities([0.4, 0.6], [0.2], compiled=True, **kw)["max_safe_tilt"]
    assert np.allclose(a, b, rtol=0.01) and np.all(a > 0)


@pytest.mark.parametrize("module,drive", [("_survival_jit", "square"), ("_integrated_jit", "sine")],
                         ids=["exact-flows", "dop853"])
def test_a_second_process_loads_the_compiled_kernels_from_the_disk_cache(module, drive):
    """Both compiled kernels (exact step flows; DOP853 for the sine drive) are cached on disk: a second
    process loads them instead of compiling."""
    code = (f"from kapitza.sweeps.kernel import block_quantities; import kapitza.motion.{module} as J; "
            f"block_quantities([0.5], [0.3], plane='arnold', l=1.0, g=9.81, drive={drive!r}, periods=5, tol=0.5, "
            "quantities=('tilt', 'basin'), directions=1, basin_resolution=5, accuracy=0.01, floor=1e-4, "
            "compiled=True); "
            "print(sum(J.ray_radii_kernel.stats.cache_hits.values()), sum(J.ray_radii_kernel.stats.cache_misses.values()),"
            " sum(J.survival_kernel.stats.cache_hits.values()))")
    for _ in range(2):  # the first run may compile and write the cache; the second must load it
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=900)
        assert out.returncode == 0, out.stderr
    assert tuple(int(v) for v in out.stdout.split()) == (1, 0, 1)


def test_import_kapitza_does_not_load_numba():
    code = "import sys, kapitza, kapitza.sweeps; sys.exit(1 if 'numba' in sys.modules else 0)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True).returncode == 0


def test_bench_sweep_kernel_tiny_runs():
    from pathlib import Path

    bench = Path(__file__).resolve().parent.parent / "benchmarks" / "bench_sweep_kernel.py"
    proc = subprocess.run([sys.executable, str(bench), "--tiny"], capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr
    for needle in ("compiled kernel", "baseline numpy path", "ratio (numpy / compiled)", "identical values",
                   "extrapolated to 512 x 512", "sine drive:", "zeta = 0.05:"):
        assert needle in proc.stdout, needle


def test_the_commands_default_chunk_does_not_punish_small_or_large_maps():
    from kapitza.cli.sweep import default_chunk

    assert default_chunk(32, 24) == 8  # the default map: 4 x 3 chunks, both cores busy
    assert default_chunk(512, 512) == 64  # 64 chunks of 4,096 points
    assert default_chunk(3, 2) == 8 and default_chunk(8192, 8192) == 64
