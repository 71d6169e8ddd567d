"""Reproduction of the paper: its eight figures and checks of its numbered results.

Csizmadia & Hatvani, *On the existence of periodic motions of the excited
inverted pendulum by elementary methods*. :func:`kapitza.paper.build.build_paper`
(the ``kapitza paper`` command) writes Figures 1-8 (PNG, SVG and the data behind
each), and a report (Markdown and self-contained HTML) that states Lemmas 3.1-3.2,
Theorems 3.3-3.4, Corollary 4.1 and the description of the stability zones in
section 4, each with its numerical verification.

Modules
-------
data
    The numbers behind each figure: ``figure1_data`` ... ``figure8_data``.
figures
    Drawing (matplotlib, imported only here): ``figure1(ax=None)`` ... ``figure8``.
checks
    Each numbered claim as a function returning a :class:`~kapitza.paper.checks.CheckResult`.
approximations
    Kapitza's averaging criterion and the small-``eps`` expansions compared in Figure 8.
report
    Markdown and HTML writers.
build
    Everything above, written into one folder.

Importing this package (or ``checks``, ``data``, ``report``, ``build``) does not import
matplotlib; drawing, and the curves of Figure 7, do.
"""
__all__ = ["approximations", "checks", "data", "report", "build"]
