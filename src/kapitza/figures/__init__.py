"""Figures (matplotlib): the plotting API of kapitza.

``import kapitza`` stays free of matplotlib; this package imports it, and only the
submodule a name lives in is imported when the name is first used.

Every ``plot_*`` function draws on ``ax=`` (a new figure when None) and returns a
:class:`Drawn`: a dict of the artists it made by name, with ``.ax`` (the Axes drawn on)
and ``.data`` (the numbers behind the drawing). Those with a legend take
``legend="inside"`` (inside the axes, best corner), ``"outside"`` (beside them) or None.
The ``*_figure`` functions lay out a complete captioned figure and return it.

=============================  ==================================================
Stability charts (:mod:`.chart`)
----------------------------------------------------------------------------------
:func:`plot_zones`             the exact zones in Arnold's ``eps``-``mu`` plane
:func:`plot_zones_physical`    the zones in the ``T``-``A`` plane
:func:`plot_tongue`            one thin zone magnified, both edges apart
:func:`zone_curves`            the edges that :func:`plot_zones` draws (no drawing)
:func:`tongue_curves`          the edges that :func:`plot_tongue` draws
:func:`magnified_zones`        which zones of a window are too thin to see
:func:`zone_chart_axes`        a chart's Axes with one panel per magnified zone
Drives (:mod:`.drives`)
----------------------------------------------------------------------------------
:func:`plot_drive_comparison`  several drives' zones on one chart
:func:`drive_curves`           the edges it draws
:func:`drive_comparison_figure` the captioned two-panel comparison
Motion (:mod:`.motion`)
----------------------------------------------------------------------------------
:func:`plot_time_series`       ``theta(t)``, with the linear motion beside it
:func:`plot_pivot`             the pivot's height
:func:`plot_phase_portrait`    ``(theta, theta')`` with the states at ``t = 2kT``
:func:`plot_strobe`            an ensemble's stroboscopic map
:func:`plot_basin`             which starts stay within a window of the upright
:func:`time_series_figure`, :func:`phase_portrait_figure`, :func:`strobe_figure`,
:func:`basin_figure`           the captioned figures of ``kapitza simulate``/``basin``
:func:`animate`                the animation of ``kapitza animate`` (:mod:`.animation`)
=============================  ==================================================

Example
-------
>>> import matplotlib.pyplot as plt
>>> from kapitza.figures import plot_zones
>>> fig, ax = plt.subplots()
>>> drawn = plot_zones(ax, eps_range=(0, 3), legend="inside")
>>> drawn.ax is ax, sorted(drawn)
(True, ['G', 'edges', 'fill', 'legend'])

See ``docs/figures.md``.
>>> plt.close("all")
"""
from __future__ import annotations

import importlib

#: Public name -> submodule that defines it.
_WHERE = {
    "Drawn": "_style",
    "plot_zones": "chart",
    "plot_zones_physical": "chart",
    "plot_tongue": "chart",
    "zone_curves": "chart",
    "tongue_curves": "chart",
    "magnified_zones": "chart",
    "zone_chart_axes": "chart",
    "plot_drive_comparison": "drives",
    "drive_curves": "drives",
    "drive_comparison_figure": "drives",
    "plot_time_series": "motion",
    "plot_pivot": "motion",
    "plot_phase_portrait": "motion",
    "plot_strobe": "motion",
    "plot_basin": "motion",
    "time_series_figure": "motion",
    "phase_portrait_figure": "motion",
    "strobe_figure": "motion",
    "basin_figure": "motion",
    "animate": "animation",
}

__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
