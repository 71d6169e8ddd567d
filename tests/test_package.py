"""The package is ready to publish.

* The metadata: one version (``pyproject.toml``, read back through ``importlib.metadata``), the files a
  published package carries (LICENSE, CITATION.cff, CHANGELOG.md, ``py.typed``), the citation of the
  paper.
* ``python -m build`` makes a wheel and an sdist that ``twine check`` passes; the wheel installs into a
  fresh virtual environment and its ``kapitza paper`` runs (slow: it installs numpy, scipy, mpmath and
  matplotlib into the new environment).
"""
from __future__ import annotations

import os
import subprocess
import sys
import tarfile
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
VERSION = PYPROJECT["project"]["version"]


def test_one_version():
    from kapitza import _version

    import kapitza

    assert _version.__version__ == VERSION
    assert kapitza.__version__ == VERSION


def test_citation_cff_cites_kapitza_and_the_paper():
    yaml = pytest.importorskip("yaml")
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["type"] == "software"
    assert cff["version"] == VERSION and cff["license"] == "MIT"
    paper = cff["references"][0]
    assert paper["title"] == "On the existence of periodic motions of the excited inverted pendulum by elementary methods"
    assert [a["family-names"] for a in paper["authors"]] == ["Csizmadia", "Hatvani"]
    assert paper["year"] == 2017
    citing = (ROOT / "docs" / "citing.md").read_text()
    assert f"version = {{{VERSION}}}" in citing  # the BibTeX entry follows the version


def test_license_and_typing_marker():
    assert "MIT License" in (ROOT / "LICENSE").read_text()
    assert PYPROJECT["project"]["license"] == {"text": "MIT"}
    assert "License :: OSI Approved :: MIT License" in PYPROJECT["project"]["classifiers"]
    assert (ROOT / "src" / "kapitza" / "py.typed").exists()
    assert "py.typed" in PYPROJECT["tool"]["setuptools"]["package-data"]["kapitza"]
    assert f"## [{VERSION}]" in (ROOT / "CHANGELOG.md").read_text()


def test_paper_cited_in_full_in_readme_and_theory():
    full = "On the existence of periodic motions of the excited inverted pendulum"
    for path in (ROOT / "README.md", ROOT / "docs" / "theory.md"):
        text = " ".join(path.read_text().split())
        assert full in text and "Csizmadia" in text and "Hatvani" in text and "September 15, 2017" in text, path
    assert "../seed/" not in (ROOT / "docs" / "theory.md").read_text()


def _run(args, **kw):
    run = subprocess.run(args, capture_output=True, text=True, timeout=1800, **kw)
    assert run.returncode == 0, (args, run.stdout[-3000:], run.stderr[-3000:])
    return run


@pytest.mark.slow
def test_wheel_and_sdist_build_check_install_and_run(tmp_path):
    pytest.importorskip("build")
    pytest.importorskip("twine")
    dist = tmp_path / "dist"
    _run([sys.executable, "-m", "build", "--sdist", "--wheel", "--outdir", str(dist), str(ROOT)])
    wheel, = dist.glob(f"kapitza-{VERSION}-*.whl")
    sdist, = dist.glob(f"kapitza-{VERSION}.tar.gz")
    _run([sys.executable, "-m", "twine", "check", "--strict", str(wheel), str(sdist)])

    names = zipfile.ZipFile(wheel).namelist()
    assert "kapitza/py.typed" in names
    assert "kapitza/_version.py" in names
    assert any(n.startswith("kapitza/web/static/") for n in names)
    assert any(n.endswith(".dist-info/licenses/LICENSE") or n.endswith(".dist-info/LICENSE") for n in names)
    with tarfile.open(sdist) as tar:
        members = tar.getnames()
    assert any(m.endswith("/LICENSE") for m in members) and any(m.endswith("/pyproject.toml") for m in members)

    # a fresh environment that sees nothing of this checkout (no PYTHONPATH to its src/)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], env=env)
    bindir = venv / ("Scripts" if os.name == "nt" else "bin")
    _run([str(bindir / "python"), "-m", "pip", "install", "-q", f"{wheel}[plot]"], env=env, cwd=tmp_path)
    version = _run([str(bindir / "kapitza"), "--version"], env=env)
    assert version.stdout.strip() == f"kapitza {VERSION}"
    where = _run([str(bindir / "python"), "-c", "import kapitza; print(kapitza.__file__)"], env=env, cwd=tmp_path)
    assert str(venv) in where.stdout  # the installed copy, not the checkout
    out = tmp_path / "paper"
    _run([str(bindir / "kapitza"), "paper", "--quick", "--out", str(out)], env=env, cwd=tmp_path)
    assert (out / "report.html").exists()
