"""Every public function, class and drive of the API reference documents itself in full.

* ``test_every_public_name_has_its_sections``: walks the names the API pages list (``docs/api/*.rst``)
  and the ``__all__`` of :mod:`kapitza` and its public subpackages, and parses each docstring with
  numpydoc: a function has Parameters (when it takes any), Returns, Raises and an Examples section
  written as a doctest (``tests/test_docs.py`` runs them); a class has Examples, Parameters for what
  its constructor takes (a result record, built by the library and not by its reader, lists its
  Attributes instead) and Raises when its constructor checks anything.
* ``test_bad_input_is_refused_with_the_librarys_message``: the functions whose Raises sections were
  the last written refuse bad input with :class:`kapitza.KapitzaValueError`, never a bare
  ``TypeError``, a warning or a wrong answer.
"""
from __future__ import annotations

import importlib
import inspect
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

numpydoc = pytest.importorskip("numpydoc.docscrape")
pytest.importorskip("matplotlib")
pytest.importorskip("xarray")
pytest.importorskip("fastapi")

import kapitza  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
MODULES = ["kapitza", "kapitza.drives", "kapitza.motion", "kapitza.figures", "kapitza.sweeps", "kapitza.web",
           "kapitza.widgets", "kapitza.mathieu", "kapitza.limits", "kapitza.normal_form", "kapitza.resonances",
           "kapitza.phase_plane", "kapitza.curves", "kapitza.rig_plane", "kapitza.chain", "kapitza.motion.chain"]

#: Nothing to raise: no argument at all, or the exception itself.
NO_RAISES = {"kapitza.drives.text_forms", "kapitza.KapitzaValueError"}


def _public():
    """``{id: (documented name, object)}`` of every public function and class."""
    out = {}
    api = "\n".join(p.read_text() for p in sorted((ROOT / "docs" / "api").glob("*.rst")) if p.name != "index.rst")
    for block in re.split(r"\.\. currentmodule:: ", api)[1:]:
        module = importlib.import_module(block.split()[0])
        for name in re.findall(r"^   (\w+)$", block, flags=re.M):
            obj = getattr(module, name)
            out.setdefault(id(obj), (f"{module.__name__}.{name}", obj))
    for modname in MODULES:
        try:
            module = importlib.import_module(modname)
        except ImportError:  # an extra that is not installed
            continue
        for name in module.__all__:
            obj = getattr(module, name)
            if callable(obj) and not inspect.ismodule(obj):
                out.setdefault(id(obj), (f"{modname}.{name}", obj))
    return list(out.values())


def _takes_arguments(obj):
    try:
        return bool(inspect.signature(obj).parameters)
    except (TypeError, ValueError):
        return False


def _missing(full, obj):
    doc = inspect.getdoc(obj) or ""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numpydoc's notes on sections it does not know
        if inspect.isclass(obj):
            d = numpydoc.ClassDoc(obj, doc=doc, config={"show_class_members": False})
        else:
            d = numpydoc.FunctionDoc(obj, doc=doc)
    missing = []
    examples = "\n".join(d["Examples"])
    if ">>>" not in examples:
        missing.append("Examples (a doctest)")
    if inspect.isclass(obj):
        record = not d["Parameters"] and bool(d["Attributes"])
        if _takes_arguments(obj) and not record:
            missing += [s for s in ("Parameters", "Raises") if not d[s]]
        if not _takes_arguments(obj) and not (d["Parameters"] or d["Attributes"] or d["Examples"]):
            missing.append("Parameters or Attributes")
    else:
        if _takes_arguments(obj) and not d["Parameters"]:
            missing.append("Parameters")
        if not (d["Returns"] or d["Yields"]):
            missing.append("Returns")
        if not d["Raises"] and full not in NO_RAISES:
            missing.append("Raises")
    return missing


def test_every_public_name_has_its_sections():
    names = _public()
    assert len(names) >= 150
    incomplete = {full: m for full, obj in names if (m := _missing(full, obj))}
    assert not incomplete, incomplete


@pytest.mark.parametrize("call, message", [
    (lambda: kapitza.curves.edge_kinds(-1), "n must be an integer >= 0"),
    (lambda: kapitza.curves.physical_window(l=-1.0), "l must be finite and > 0"),
    (lambda: kapitza.figures.zone_chart_axes(None, -1), "count must be an integer >= 0"),
    (lambda: kapitza.figures.plot_time_series("x"), "traj must be a kapitza.motion.Trajectory; got str"),
    (lambda: kapitza.figures.basin_figure([]), "basins must hold at least one"),
    (lambda: kapitza.figures.drive_comparison_figure([]), "curves must be one or more"),
    (lambda: kapitza.figures.drive_comparison_figure(
        [kapitza.curves.drive_curves("square", np.linspace(0.1, 0.9, 5), 2.0)], eps_max=float("nan")),
     "eps_max must be finite and > 0"),
    (lambda: kapitza.figures.plot_drive_comparison([], legend="left"), "legend must be 'inside', 'outside' or None"),
    (lambda: kapitza.sweeps.done_chunks(None), "grp must be a sweep store"),
    (lambda: kapitza.sweeps.to_netcdf(None, "never-written.nc"), "ds must be an xarray.Dataset"),
    (lambda: kapitza.web.create_app(hosts="example.org"), "hosts must be a sequence of host names"),
    (lambda: kapitza.web.serve(None), "sock must be a bound socket.socket"),
])
def test_bad_input_is_refused_with_the_librarys_message(call, message, tmp_path, monkeypatch):
    import kapitza.figures
    import kapitza.sweeps
    import kapitza.web

    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(kapitza.KapitzaValueError, match=re.escape(message)):
            call()
    assert not (tmp_path / "never-written.nc").exists()


def test_a_sweep_chunk_outside_the_grid_is_named():
    from kapitza.sweeps import SweepSpec, compute_chunk

    spec = SweepSpec.window((0.3, 0.9), (0.2, 0.4), (4, 3), quantities=("linear",), chunk=2)
    with pytest.raises(kapitza.KapitzaValueError, match=re.escape("iy must satisfy 0 <= iy < 2")):
        compute_chunk(spec, 2, 0)
