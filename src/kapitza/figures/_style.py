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


#: Caption font size [pt] and the height one caption line takes [inch].
CAPTION_SIZE = 9
_LINE_IN = 1.3 * CAPTION_SIZE / 72.0
#: Height of one caption row [inch]: a line of text with room for a fraction in a formula.
_ROW_IN = 1.6 * CAPTION_SIZE / 72.0


def new_figure(width=7.0, height=5.0, caption_lines=0):
    """A figure ``width`` x ``height`` inches (constrained layout); :func:`caption` adds
    the height its caption needs, so no blank band is left under it."""
    return plt.figure(figsize=(width, height + _LINE_IN * caption_lines), layout="constrained")


def _visible_length(word: str) -> float:
    """Rough printed width of ``word`` in characters: mathtext commands and braces
    take no room, a ``\\command`` one character."""
    import re

    if "$" not in word:
        return len(word)
    s = re.sub(r"\\(mathrm|mathit|,|;|!|left|right)", "", word)
    s = re.sub(r"\\[A-Za-z]+", "x", s)
    return len(s.replace("{", "").replace("}", "").replace("$", "").replace("^", "").replace("_", "")) * 0.9


def wrap_caption(text: str, width_chars: float) -> list:
    """Split ``text`` into balanced lines of at most about ``width_chars`` characters.

    Spaces inside ``$...$`` never break a line (matplotlib's mathtext needs each formula
    whole on one line), and the lines are evened out so that the last is not an orphan.
    """
    words, cur, in_math = [], "", False
    for tok in text.split(" "):
        cur = tok if not cur else cur + " " + tok
        in_math ^= tok.count("$") % 2 == 1
        if not in_math:
            words.append(cur)
            cur = ""
    if cur:
        words.append(cur)
    lens = [_visible_length(w) for w in words]

    def greedy(limit):
        lines, line, n = [], [], 0.0
        for w, ln in zip(words, lens):
            if line and n + 1 + ln > limit:
                lines.append(line)
                line, n = [], 0.0
            n = n + ln + (1 if line else 0)
            line.append(w)
        if line:
            lines.append(line)
        return lines

    lines = greedy(width_chars)
    # Shrink the limit while the line count stays the same: balanced lines, no orphan.
    count, limit = len(lines), width_chars
    while limit > 10:
        trial = greedy(limit - 2)
        if len(trial) > count:
            break
        lines, limit = trial, limit - 2
    return [" ".join(line) for line in lines]


def _segments(line: str):
    """``line`` cut into plain text and ``$...$`` formulas, in order."""
    parts = line.split("$")
    return [(p if i % 2 == 0 else f"${p}$") for i, p in enumerate(parts) if p]


def caption(fig, text: str):
    """Put ``text`` under the axes as a caption, wrapped to the figure's width (mathtext kept
    whole, lines balanced), and make the figure taller by exactly what the caption needs.

    Each line is set as a row of plain-text and formula pieces on one baseline, so that only
    the formulas go through matplotlib's mathtext parser (a whole line of mixed text costs
    it ten times more). The space is reserved in the layout by a blank figure label of as
    many lines. The text is kept as ``fig.kapitza_caption``. Returns the caption's artist.
    """
    from matplotlib.offsetbox import AnchoredOffsetbox, HPacker, TextArea, VPacker

    lines = wrap_caption(text, fig.get_figwidth() * 72.0 / (0.52 * CAPTION_SIZE))
    props = dict(fontsize=CAPTION_SIZE)
    rows = [HPacker(children=[TextArea(seg, textprops=props) for seg in _segments(line)], align="baseline", pad=0,
                    sep=0) for line in lines]
    box = VPacker(children=rows, align="center", pad=0, sep=0.3 * CAPTION_SIZE)
    # Its height as set (rows with fractions are taller), so the figure grows by just that.
    try:
        height = box.get_bbox(fig.canvas.get_renderer()).height / fig.dpi
    except Exception:  # a canvas without a renderer: a generous estimate
        height = _ROW_IN * len(lines)
    height = 1.02 * height + 6.0 / 72.0
    fig.set_figheight(fig.get_figheight() + height + 0.1)
    # The room, in the layout: an invisible label of as many rows, spaced to the same height
    # (matplotlib sets a label of n lines n line spacings high).
    spacing = height / (len(lines) * 1.2 * CAPTION_SIZE / 72.0)
    fig.supxlabel("\n".join("Ág" for _ in lines), fontsize=CAPTION_SIZE, x=0.5, alpha=0.0, linespacing=spacing)
    art = AnchoredOffsetbox(loc="lower center", child=box, frameon=False, pad=0.0, borderpad=0.0,
                            bbox_to_anchor=(0.5, 0.0), bbox_transform=fig.transFigure)
    art.set_figure(fig)
    fig.add_artist(art)
    fig.kapitza_caption = text
    return art


def save(fig, stem, formats=("png", "svg"), dpi=150):
    """Write ``stem.<fmt>`` for each format atomically; return the paths.

    The layout is computed once, for the first format, and then kept for the others
    (the constrained layout measures every text, which costs as much as drawing it).
    """
    stem = Path(stem)
    paths = []
    for k, fmt in enumerate(formats):
        p = stem.with_suffix("." + fmt)
        with atomic_path(p) as tmp:
            fig.savefig(tmp, format=fmt, dpi=dpi)
        paths.append(p)
        if k == 0 and len(formats) > 1 and fig.get_layout_engine() is not None:
            # No engine at all, not the "none" placeholder: with any engine set, savefig draws
            # the whole figure once more before drawing it for real.
            with plt.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
                fig.set_layout_engine(None)
    return paths


def figure_bytes(fig, fmt="png", dpi=150) -> bytes:
    """The figure as the bytes :func:`save` would write in format ``fmt``."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=dpi)
    return buf.getvalue()


class Drawn(dict):
    """What a ``plot_*`` function drew.

    A dict ``name -> artist`` (or list of artists) with two attributes:

    Attributes
    ----------
    ax : matplotlib Axes
        The Axes drawn on (the one passed as ``ax=``, or the new one).
    data : object or None
        The numbers behind the drawing (e.g. :class:`kapitza.figures.chart.ZoneCurves`),
        when the function computed them.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from kapitza.figures import plot_zones
    >>> fig, ax = plt.subplots()
    >>> drawn = plot_zones(ax, eps_range=(0, 2))
    >>> drawn.ax is ax, sorted(drawn), type(drawn.data).__name__
    (True, ['G', 'edges', 'fill', 'legend'], 'ZoneCurves')
    >>> plt.close("all")
    """

    def __init__(self, ax, artists=None, data=None):
        super().__init__(artists or {})
        self.ax = ax
        self.data = data

    def __repr__(self):
        return f"Drawn(ax={self.ax!r}, artists={sorted(self)!r}, data={type(self.data).__name__})"


def place_legend(ax, inside=False, **kw):
    """A legend for ``ax``: inside the axes (``inside=True``, best corner, framed)
    or just outside its right edge (the captioned figures' default). None when nothing drawn
    has a label (a window in which no zone lies)."""
    if not ax.get_legend_handles_labels()[0]:
        return None
    if inside:
        return ax.legend(loc=kw.pop("loc", "best"), fontsize=kw.pop("fontsize", 8), framealpha=0.9, **kw)
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=kw.pop("fontsize", 8), frameon=False,
                     borderaxespad=0.0, **kw)
