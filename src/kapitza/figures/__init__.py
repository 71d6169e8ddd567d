"""Figures (matplotlib). Imported only on demand: ``import kapitza`` stays free of matplotlib."""
