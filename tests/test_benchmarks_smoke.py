"""The benchmarks still run (CI runs each once at a tiny size so that none can rot)."""
import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parent.parent / "benchmarks"


def run_tiny(script):
    proc = subprocess.run([sys.executable, str(BENCH / script), "--tiny"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    return proc.stdout


def test_bench_engine_tiny_runs():
    out = run_tiny("bench_engine.py")
    for needle in ("stability_grid:", "default call", "out= buffer reused", "baseline: numpy trace formula",
                   "numerical Floquet", "zone_edges:", "disagrees with the exact grid: 0 of"):
        assert needle in out, needle


def test_bench_strobe_tiny_runs():
    out = run_tiny("bench_strobe.py")
    for needle in ("exact ensemble map:", "1 process", "workers", "baseline: solve_ivp DOP853 loop",
                   "agreement on the sample after   1 period", "ratio (baseline / exact)", "100,000 states x 1,000 periods"):
        assert needle in out, needle
    line = next(ln for ln in out.splitlines() if "after   1 period" in ln)
    assert float(line.split("=")[1].split()[0]) < 1e-8  # the two solutions agree over one period


def test_bench_drives_tiny_runs():
    out = run_tiny("bench_drives.py")
    for needle in ("four-step drive:", "square wave, damping ratio 0.2:", "baseline: numerical Floquet",
                   "ratio (baseline per point / chart per point)"):
        assert needle in out, needle
    assert "pointwise verdicts disagree with the chart: 0 of" in out
    assert "solve_ivp verdicts differing from the exact ones on the sample: 0 of" in out


def test_bench_basin_io_tiny_runs():
    out = run_tiny("bench_basin_io.py")
    for needle in ("baseline: row at a time", "columns=", "ratio baseline / columns", "--workers 1:", "--workers 2:"):
        assert needle in out, needle
    assert "files identical: True" in out


def test_bench_sweep_tiny_runs():
    out = run_tiny("bench_sweep.py")
    for needle in ("sweep kernel: max safe tilt to 1 %", "brute-force basin 121 x 121", "ratio (solve_ivp / sweep)",
                   "LocalCluster 2 workers", "overhead per chunk", "512 x 512 points x 1,000 periods", "1024 cores"):
        assert needle in out, needle
    line = next(ln for ln in out.splitlines() if "worst |relative difference|" in ln)
    assert float(line.split("=")[1].split("%")[0]) <= 1.0  # the bisected tilt is within its stated accuracy


def test_bench_paper_tiny_runs():
    out = run_tiny("bench_paper.py")
    for needle in ("baseline: one process, as before", "build: 2 processes",
                   "ratio (baseline / build): wall", "same files written: True", "every check passed: baseline True"):
        assert needle in out, needle


def test_bench_twist_tiny_runs():
    out = run_tiny("bench_twist.py")
    for needle in ("twist_coefficient:", "not from the composed jets", "baseline: solve_ivp DOP853",
                   "agreement on the sample", "ratio (baseline / closed forms)"):
        assert needle in out, needle


def test_bench_web_tiny_runs():
    out = run_tiny("bench_web.py")
    for needle in ("kapitza serve: first request answered", "chart, full view", "chart, zone 2 zoomed",
                   "point (stability report)", "motion (square wave, the page's request)",
                   "motion, start moved by 1e-12", "baseline: the library call in-process", "p50 / baseline"):
        assert needle in out, needle
    # both motion queries compare the steps on one state with the array function's, same doubles
    assert out.count("each step on one-element arrays") == 2 and out.count("same doubles: True") == 2
    # six queries at two levels of clients each, none answered with an error
    assert "never cached" in out and out.count("errors 0") == 12


def test_bench_sweep_integrated_tiny_runs():
    out = run_tiny("bench_sweep_integrated.py")
    for needle in ("exact path (square, undamped) -- baseline", "integrated path (square, zeta = 0.05)",
                   "integrated path (sine, undamped)", "ratio (this / exact)", "integrated vs exact"):
        assert needle in out, needle


def test_bench_one_engine_tiny_runs():
    out = run_tiny("bench_one_engine.py")
    for needle in ("analyze(T=0.15, A=100)", "RectangularWave(0.5)", "square, damping=1e-9", "x the square wave",
                   "is_stable of one point", "stability_grid 256 x 256"):
        assert needle in out, needle
    worst = float(out.split("largest relative difference of eps_hi from the square wave's:")[1].split()[0])
    assert worst < 1e-14  # the same physics gives the same zone


def test_bench_drives_generic_tiny_runs():
    out = run_tiny("bench_drives_generic.py")
    for needle in ("square wave (baseline)", "triangle wave", "measured drive, 50 samples", "ratio to the square wave",
                   "chart (eps in (0, 4], mu in (0, 1)) from exact edges"):
        assert needle in out, needle
    assert "pointwise verdicts disagreeing with the chart: 0 of 40" in out


def test_bench_sine_tiny_runs():
    out = run_tiny("bench_sine.py")
    for needle in ("kapitza stability_grid", "scipy mathieu_a/b chart", "ratio scipy / kapitza", "pixels that differ",
                   "kapitza zone_edges", "scipy brentq on mathieu_a/b"):
        assert needle in out, needle


def test_bench_sine_rig_tiny_runs():
    out = run_tiny("bench_sine_rig.py")
    for needle in ("whole command", "start-up alone", "damped sine rig", "x wall", "the start-up",
                   "first call in a fresh process", "bytecode cache:"):
        assert needle in out, needle


def test_bench_renders_tiny_runs():
    out = run_tiny("bench_renders.py")
    for needle in ("animate:", "baseline (glyphs rasterised", "ratio (baseline / kapitza)", "pixels differing"):
        assert needle in out, needle
