"""The engine benchmark still runs (CI runs it once at a tiny size so that it cannot rot)."""
import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parent.parent / "benchmarks" / "bench_engine.py"


def test_bench_engine_tiny_runs():
    proc = subprocess.run([sys.executable, str(BENCH), "--tiny"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    for needle in ("stability_grid:", "default call", "out= buffer reused", "baseline: numpy trace formula",
                   "numerical Floquet", "zone_edges:", "disagrees with the exact grid: 0 of"):
        assert needle in out, needle
    assert "Traceback" not in proc.stderr
