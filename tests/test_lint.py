"""The code checks belong to the test command: ruff and mypy (configured in pyproject.toml) are clean on ``src/``."""
import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _run(module, *args):
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"{module} is not installed (it comes with the 'test' and 'lint' extras)")
    return subprocess.run([sys.executable, "-m", module, *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)


def test_ruff_clean():
    r = _run("ruff", "check", "src")
    assert r.returncode == 0, r.stdout + r.stderr


def test_mypy_clean():
    r = _run("mypy")  # the files and options: [tool.mypy] in pyproject.toml
    assert r.returncode == 0, r.stdout + r.stderr
