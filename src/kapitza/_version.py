"""The package version, read from the installed distribution's metadata.

``pyproject.toml`` is the one place the version is written; this module reads it back from the
metadata that ``pip install`` (editable or not) records, so the two cannot disagree.
"""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("kapitza")
except PackageNotFoundError:  # run from a source tree that was never installed
    __version__ = "0+unknown"

__all__ = ["__version__"]
