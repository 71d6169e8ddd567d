"""Shared figure conventions: colours, edge styles, captions, atomic saving."""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt

from .._io import atomic_path

#: Style of the 2T-periodic edges (T_n) and 4T-periodic edges (T~_n).
EDGE_2T = dict(color="#1f4e9c", linestyle="-", linewidth=1.4)
EDGE_4T = dict(color="#c0392b", linestyle="--", linewidth=1.4)
ZONE_FILL = "#9ecae1"
G_STYLE = dict(color="0.35", linestyle=":", linewidth=1.0)


def new_figure(width=7.0, height=5.0, caption_lines=2):
    """A figure with room at the bottom for a caption of ``caption_lines`` lines."""
    fig = plt.figure(figsize=(width, height + 0.18 * caption_lines), layout="constrained")
    return fig


def caption(fig, text: str):
    """Put ``text`` under the axes as a caption (wrapped to the figure width)."""
    import textwrap

    width_chars = int(fig.get_figwidth() * 13)
    fig.supxlabel("\n".join(textwrap.wrap(text, width_chars)), fontsize=9, ha="center", x=0.5)


def save(fig, stem, formats=("png", "svg"), dpi=150):
    """Write ``stem.<fmt>`` for each format atomically; return the paths."""
    stem = Path(stem)
    paths = []
    for fmt in formats:
        p = stem.with_suffix("." + fmt)
        with atomic_path(p) as tmp:
            fig.savefig(tmp, format=fmt, dpi=dpi)
        paths.append(p)
    return paths
