"""The stroboscopic-map benchmark still runs (once, at a tiny size, so that it cannot rot)."""
import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parent.parent / "benchmarks" / "bench_strobe.py"


def test_bench_strobe_tiny_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--tiny"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    for needle in ("exact ensemble map:", "1 process", "workers", "baseline: solve_ivp DOP853 loop",
                   "agreement on the sample after   1 period", "ratio (baseline / exact)", "100,000 states x 1,000 periods"):
        assert needle in out, needle
    line = next(ln for ln in out.splitlines() if "after   1 period" in ln)
    assert float(line.split("=")[1].split()[0]) < 1e-8  # the two solutions agree over one period
    assert "Traceback" not in proc.stderr
