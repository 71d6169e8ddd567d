"""Sphinx configuration of the kapitza documentation.

Build (offline, warnings as errors), from the repository root::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

The site needs no network, and no page loads a script, a font or a stylesheet from another host.
Links into the documentation of Python, numpy, scipy, matplotlib, xarray and dask (intersphinx) are
made from the small inventories in ``_intersphinx/`` (version-1 text: name, role, page), which list
every object of those projects these pages name (``tests/test_docs.py`` checks that); with
``KAPITZA_DOCS_ONLINE=1`` the projects' full inventories are fetched from the web instead.
``KAPITZA_DOCS_QUICK=1`` skips running the gallery scripts and the tutorial notebooks (the API
reference and the guides only).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS.parent / "src"))

from kapitza._version import __version__  # noqa: E402

ONLINE = os.environ.get("KAPITZA_DOCS_ONLINE") == "1"
QUICK = os.environ.get("KAPITZA_DOCS_QUICK") == "1"

project = "kapitza"
author = "The kapitza authors"
copyright = "2026, The kapitza authors"
version = release = __version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_design",
    "myst_nb",
    "sphinx_gallery.gen_gallery",
]

exclude_patterns = ["_build", "_intersphinx", "gallery_src/README.rst", "sg_execution_times.rst",
                    "**.ipynb_checkpoints", "Thumbs.db", ".DS_Store",
                    "gallery/*.ipynb", "gallery/*.py", "gallery/*.codeobj.json", "gallery/*.zip"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"

# -- API reference ------------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"  # numpydoc's Parameters sections say the types in words
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

# -- Links to other projects (offline from _intersphinx/, their full inventories online) ----------
INTERSPHINX_SITES = {
    "python": "https://docs.python.org/3",
    "numpy": "https://numpy.org/doc/stable",
    "scipy": "https://docs.scipy.org/doc/scipy",
    "matplotlib": "https://matplotlib.org/stable",
    "xarray": "https://docs.xarray.dev/en/stable",
    "dask": "https://docs.dask.org/en/stable",
}
intersphinx_mapping = {name: (url, None if ONLINE else str(DOCS / "_intersphinx" / f"{name}.txt"))
                       for name, url in INTERSPHINX_SITES.items()}

# -- Markdown and notebooks ---------------------------------------------------------------------
myst_enable_extensions = ["colon_fence", "deflist", "substitution"]
myst_substitutions = {"version": release}
myst_heading_anchors = 3
nb_execution_mode = "off" if QUICK else "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# -- Gallery ------------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": "gallery_src",
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "plot_gallery": "False" if QUICK else "True",
    "download_all_examples": False,
    "remove_config_comments": True,
    "show_memory": False,
    "show_signature": False,
    "min_reported_time": 10**6,
    "matplotlib_animations": False,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    "write_computation_times": False,  # its page loads DataTables from a CDN
}

# -- HTML ---------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"kapitza {release}"
html_static_path = ["_static"]
html_css_files = ["kapitza.css"]
html_last_updated_fmt = None
html_show_sourcelink = False
html_copy_source = False
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "header_links_before_dropdown": 6,
    "footer_start": ["copyright"],
    "footer_end": [],
    "secondary_sidebar_items": ["page-toc"],
}
html_context = {"default_mode": "light"}
# Pages without sub-pages: no empty "Section Navigation" column.
html_sidebars = {page: [] for page in ("index", "getting-started", "theory", "citing", "changelog")}
