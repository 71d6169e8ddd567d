"""The documentation site builds offline with warnings as errors, and its examples run.

* ``test_site_builds_offline_*``: Sphinx builds ``docs/`` (a copy, so the checkout stays clean) with
  ``-W``; every public name has its API page; no page loads a script, stylesheet, font or picture from
  another host. The default suite builds the guides and the API reference
  (``KAPITZA_DOCS_QUICK=1``); the full build, running the gallery scripts and the notebooks, is marked
  slow.
* ``test_intersphinx_inventories_*``: the links into numpy, scipy, matplotlib, xarray, dask and
  Python are made offline from ``docs/_intersphinx/``, which lists every object of theirs the pages name.
* ``test_docstring_examples_run``: every ``Examples`` section of the package's docstrings is a doctest
  and passes.
* ``test_gallery_script_runs_and_draws``: each gallery script runs and draws its figure.
* ``test_tutorial_notebook_runs``: each tutorial notebook runs top to bottom in a fresh kernel
  (nbclient) and shows what it says it shows.
"""
from __future__ import annotations

import doctest
import importlib
import os
import pkgutil
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
TUTORIALS = ["teacher", "engineer", "researcher"]

#: (subpackage or module, the API page that lists its public names)
API_PAGES = {
    "kapitza": None,  # spread over core, drives, motion, nonlinear
    "kapitza.phase_plane": "core",
    "kapitza.curves": "core",
    "kapitza.grids": "core",
    "kapitza.drives": "drives",
    "kapitza.mathieu": "drives",
    "kapitza.limits": "drives",
    "kapitza.motion": "motion",
    "kapitza.normal_form": "nonlinear",
    "kapitza.resonances": "nonlinear",
    "kapitza.figures": "figures",
    "kapitza.sweeps": "sweeps",
    "kapitza.web": "web",
}


def _public_names():
    """(documented path, name) of every public function and class."""
    out = []
    for modname in API_PAGES:
        mod = importlib.import_module(modname)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if callable(obj) and not isinstance(obj, type(sys)):
                out.append((modname, name))
    return out


def _documented(modname, name, api_text):
    """Whether ``name`` of ``modname`` is in an autosummary of the API pages (under its module)."""
    for block in re.split(r"\.\. currentmodule:: ", api_text)[1:]:
        current = block.split()[0]
        names = re.findall(r"^   (\w+)$", block, flags=re.M)
        if name in names and (current == modname or (modname == "kapitza" and current == "kapitza")):
            return True
        if name in names and modname != "kapitza" and current == "kapitza":
            # a name of a subpackage re-exported at the top level is documented there
            import kapitza

            if getattr(kapitza, name, None) is getattr(importlib.import_module(modname), name):
                return True
    return False


def test_every_public_function_and_class_is_in_the_api_reference():
    api_text = "\n".join(p.read_text() for p in sorted((DOCS / "api").glob("*.rst")))
    missing = [f"{m}.{n}" for m, n in _public_names() if not _documented(m, n, api_text)]
    assert not missing, f"not in docs/api/*.rst: {missing}"


def _build(tmp_path, quick):
    src = tmp_path / "docs"
    shutil.copytree(DOCS, src, ignore=shutil.ignore_patterns("_build", "gallery", "generated", "jupyter_execute"))
    for name in ("CHANGELOG.md", "CITATION.cff"):
        shutil.copy(ROOT / name, tmp_path / name)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    # sphinx-gallery picks its own backend; a backend forced here would keep the notebooks' figures out
    for name in ("KAPITZA_DOCS_ONLINE", "MPLBACKEND"):
        env.pop(name, None)
    env["KAPITZA_DOCS_QUICK"] = "1" if quick else "0"
    out = tmp_path / "html"
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(src), str(out)],
                         capture_output=True, text=True, env=env, timeout=3600)
    # Sphinx's own warnings and errors (the notebook kernel's start-up notices are not the site's)
    warnings = [line for line in run.stderr.splitlines() if re.search(r"\b(WARNING|ERROR|CRITICAL): ", line)]
    assert run.returncode == 0 and not warnings, run.stderr[-5000:]
    return out


#: An attribute that loads something: a script, a stylesheet, a font, a picture, a frame.
_LOADS = re.compile(r"<(?:script|link|img|iframe|source|video|audio)\b[^>]*?\b(?:src|href)\s*=\s*[\"']?(https?:)?//",
                    re.I)


def _check_offline(out):
    for page in out.rglob("*.html"):
        text = page.read_text(errors="replace")
        hits = [m.group(0) for m in _LOADS.finditer(text)]
        assert not hits, (page.relative_to(out), hits[:3])
    for sheet in out.rglob("*.css"):
        assert not re.search(r"url\(\s*[\"']?(https?:)?//", sheet.read_text(errors="replace")), sheet.relative_to(out)
        assert "@import url(http" not in sheet.read_text(errors="replace")


def _check_api_pages(out):
    for modname, name in _public_names():
        candidates = [out / "api" / "generated" / f"{modname}.{name}.html", out / "api" / "generated" / f"kapitza.{name}.html"]
        assert any(c.exists() for c in candidates), (modname, name)


#: A cross-reference role naming an object of another project (whose documentation intersphinx links).
_EXTERNAL_ROLE = re.compile(r":(?:class|func|meth|attr|exc|mod|obj|data):`[~!]?("
                            r"(?:numpy|scipy|matplotlib|xarray|dask|pathlib)(?:\.\w+)+"
                            r"|(?!Kapitza)[A-Z]\w*(?:Error|Exception|Warning))`")


def _inventories():
    """``{(role, name)}`` of the inventories the offline build links other projects with."""
    out = set()
    for path in (DOCS / "_intersphinx").glob("*.txt"):
        lines = path.read_text().splitlines()
        assert lines[0] == "# Sphinx inventory version 1", path.name
        for line in lines[3:]:
            name, role, _ = line.split(None, 2)
            out.add((role, name))
    return out


def test_intersphinx_inventories_name_every_object_of_another_project_the_pages_name():
    """Offline, a reference to numpy, scipy, matplotlib, xarray, dask or Python is linked only if the
    shipped inventory lists it: every such reference in the docstrings and pages is listed."""
    listed = {name for _, name in _inventories()}
    texts = [*(ROOT / "src" / "kapitza").rglob("*.py"), *DOCS.rglob("*.md"), *DOCS.rglob("*.rst"),
             *DOCS.rglob("*.ipynb"), *(DOCS / "gallery_src").glob("*.py")]
    named = {m.group(1): path for path in texts if "_build" not in path.parts
             for m in _EXTERNAL_ROLE.finditer(path.read_text(errors="replace"))}
    assert len(named) >= 8
    missing = {name: str(path.relative_to(ROOT)) for name, path in named.items() if name not in listed}
    assert not missing, f"add to docs/_intersphinx/*.txt (role and page in its project's documentation): {missing}"


def test_site_builds_offline_with_warnings_as_errors(tmp_path):
    out = _build(tmp_path, quick=True)
    api = (out / "api" / "index.html").read_text()
    for url in ("https://docs.python.org/3/library/exceptions.html#ValueError",
                "https://numpy.org/doc/stable/reference/generated/numpy.ndarray.html#numpy.ndarray",
                "https://matplotlib.org/stable/api/axes_api.html#matplotlib.axes.Axes",
                "https://docs.xarray.dev/en/stable/generated/xarray.Dataset.html#xarray.Dataset",
                "https://docs.dask.org/en/stable/generated/dask.array.Array.html#dask.array.Array"):
        assert f'href="{url}"' in api, url  # intersphinx links, made offline
    scipy = 'href="https://docs.scipy.org/doc/scipy/reference/generated/scipy.linalg.expm.html#scipy.linalg.expm"'
    assert scipy in (out / "api" / "generated" / "kapitza.chain_floquet.html").read_text()
    index = (out / "index.html").read_text()
    assert "explorer.png" in index and "drives-compare.png" in index
    for page in ("getting-started", "theory", "user-guide", "citing", "changelog", "drives", "motion", "nonlinear",
                 "sweeps", "figures", "paper", "api/index", "api/core", "gallery/index", "tutorials/index"):
        assert (out / f"{page}.html").exists(), page
    assert "Csizmadia" in (out / "citing.html").read_text()
    _check_api_pages(out)
    _check_offline(out)


@pytest.mark.slow
def test_site_builds_offline_with_gallery_and_notebooks_executed(tmp_path):
    out = _build(tmp_path, quick=False)
    gallery = sorted((DOCS / "gallery_src").glob("plot_*.py"))
    assert len(gallery) >= 9
    for script in gallery:
        page = (out / "gallery" / f"{script.stem}.html").read_text()
        assert re.search(r'<img [^>]*src="[^"]*sphx_glr_' + script.stem, page), script.name  # its figure is drawn
        assert f"{script.stem}.ipynb" in page and f"{script.stem}.py" in page  # both downloads offered
    for name in TUTORIALS:
        page = (out / "tutorials" / f"{name}.html").read_text()
        assert "<img" in page and "cell_output" in page, name
        assert "Traceback" not in page, name
    _check_api_pages(out)
    _check_offline(out)


def _modules():
    import kapitza

    for info in pkgutil.walk_packages(kapitza.__path__, "kapitza."):
        if ".cli" in info.name or info.name.endswith("__main__"):
            continue
        try:
            yield importlib.import_module(info.name)
        except ImportError:  # an optional extra that is not installed
            continue


def test_docstring_examples_run():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    seen, tests = set(), []
    for mod in [importlib.import_module("kapitza"), *_modules()]:
        for test in finder.find(mod, mod.__name__):
            if test.examples and test.name not in seen:
                seen.add(test.name)
                tests.append(test)
    assert len(tests) >= 4
    failures = []
    for test in tests:
        out = []
        result = runner.run(test, out=out.append)
        if result.failed:
            failures.append("".join(out))
    import matplotlib.pyplot as plt

    plt.close("all")
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("script", sorted(p.name for p in (DOCS / "gallery_src").glob("plot_*.py")))
def test_gallery_script_runs_and_draws(script, tmp_path, monkeypatch):
    """Each gallery script runs as a reader would run it and draws its figure (the full site build,
    which runs them too, is marked slow; this keeps a broken gallery example out of the default suite)."""
    import runpy
    import warnings

    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    plt.close("all")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*non-interactive.*")  # plt.show() on Agg
        runpy.run_path(str(DOCS / "gallery_src" / script), run_name="__main__")
    try:
        assert plt.get_fignums(), f"{script} drew no figure"
        assert all(plt.figure(n).axes for n in plt.get_fignums()), f"{script} left an empty figure"
    finally:
        plt.close("all")
    assert not list(tmp_path.iterdir()), f"{script} left files in the working directory"


#: Something each notebook must show once run (a result, not only the absence of an error).
NOTEBOOK_SHOWS = {
    "teacher": ["stays up? False True", "stable (zone 0)",
                # what section 4 explains: faster at the same A is too weak, slower is period doubling
                "T = 0.05 s: unstable: the drive is too weak", "T = 0.25 s: unstable: parametric resonance"],
    "engineer": ["stable: False", "raise the frequency to at least 95.9 Hz",
                 "increase the amplitude to 5.76-75.8 mm"],   # in the quantity the rig was given
    "researcher": ["worst relative difference"],
}


@pytest.mark.parametrize("name", TUTORIALS)
def test_tutorial_notebook_runs(name, tmp_path, monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    book = nbformat.read(DOCS / "tutorials" / f"{name}.ipynb", as_version=4)
    assert not any(c.get("outputs") for c in book.cells if c.cell_type == "code")  # stored without outputs
    nbclient.NotebookClient(book, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    text = "\n".join(o.get("text", "") for c in book.cells if c.cell_type == "code" for o in c.outputs)
    images = sum("image/png" in o.get("data", {}) for c in book.cells if c.cell_type == "code" for o in c.outputs)
    for want in NOTEBOOK_SHOWS[name]:
        assert want in text, (name, want)
    assert images >= 1
