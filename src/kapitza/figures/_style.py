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
    box = VPacker(children=rows, align="center", pad=0, sep=0.3 * CAPTION_SIZE)  # type: ignore[arg-type]
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


#: Save the earlier way: the layout run inside the first ``savefig``, each format's ticks and
#: titles worked out anew on every pass, PNG at zlib's default level. Kept only so that
#: ``benchmarks/bench_renders.py`` can time the difference; the files are the same either way.
_LEGACY = False

#: zlib level of the PNG files: the same pixels as the default level 6 in about half the time,
#: for a file a few per cent larger.
PNG_COMPRESS_LEVEL = 2


def _freeze_ticks(fig):
    """Fix every axis's tick positions and labels at what the layout just drew.

    Each draw (and each tight bbox the draw asks for: spines, labels, titles) runs the axis's
    locator and formatter again; with the layout done, they cannot change any more, so a fixed
    list gives the same ticks for the formats still to write. An axis whose formatter shows an
    offset (``1e3`` above the axis) keeps its own.
    """
    from matplotlib.ticker import FixedFormatter, FixedLocator, NullLocator

    for ax in fig.get_axes():
        for axis in ax._axis_map.values():
            for which in (axis.major, axis.minor):
                if isinstance(which.locator, (NullLocator, FixedLocator)):
                    continue
                locs = axis.get_majorticklocs() if which is axis.major else axis.get_minorticklocs()
                labels = which.formatter.format_ticks(locs)
                if which.formatter.get_offset():
                    continue
                fixed_loc, fixed_fmt = FixedLocator(locs), FixedFormatter(labels)
                if which is axis.major:
                    axis.set_major_locator(fixed_loc)
                    axis.set_major_formatter(fixed_fmt)
                else:
                    axis.set_minor_locator(fixed_loc)
                    axis.set_minor_formatter(fixed_fmt)
        # Above an axes with no ticks or label on top, the title sits at y = 1: say so, or
        # every draw measures the axes' ticks to find that out.
        titles = (ax.title, ax._left_title, ax._right_title)
        if all(t.get_position()[1] == 1.0 for t in titles):
            ax._autotitlepos = False


def _layout_once(fig, dpi):
    """Run ``fig``'s layout engine once at ``dpi`` and remove it (then freeze the ticks).

    The layout is computed by the same Agg renderer (same resolution, same text measurements) that
    ``savefig(dpi=dpi)`` of a PNG would use, so that PNG is the same picture. Returns False (and does
    nothing) for a figure whose canvas is not Agg's."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(fig.canvas, FigureCanvasAgg):
        return False
    engine = fig.get_layout_engine()
    if engine is not None:
        own = fig.dpi
        fig.dpi = dpi
        try:
            engine.execute(fig)
        finally:
            fig.dpi = own
        # No engine at all, not the "none" placeholder: with any engine set, savefig draws
        # the whole figure once more before drawing it for real.
        with plt.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)
    _freeze_ticks(fig)
    return True


def _savefig(fig, path, fmt, dpi):
    kw = {"pil_kwargs": {"compress_level": PNG_COMPRESS_LEVEL}} if fmt == "png" and not _LEGACY else {}
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, dpi=dpi, **kw)


def save(fig, stem, formats=("png", "svg"), dpi=150):
    """Write ``stem.<fmt>`` for each format atomically; return the paths.

    The layout is computed once, by the renderer of the first format (a PNG), and then kept for
    the others (the constrained layout measures every text, which costs as much as drawing it),
    with the ticks and titles it settled.
    """
    stem = Path(stem)
    formats = list(formats)
    paths = [stem.with_suffix("." + fmt) for fmt in formats]
    if not _LEGACY and len(formats) > 1 and formats[0] == "png" and _layout_once(fig, dpi):
        for p, fmt in zip(paths, formats):
            _savefig(fig, p, fmt, dpi)
        return paths
    for k, (p, fmt) in enumerate(zip(paths, formats)):
        _savefig(fig, p, fmt, dpi)
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


def real_log_ticks(axis):
    """Log axis ticks labelled as plain numbers (0.5, 2, 20, 200), not powers of ten."""
    from matplotlib.ticker import FuncFormatter, LogLocator

    def label(v, _pos):
        return f"{v:.6g}" if v > 0 else ""

    axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(label))
    axis.set_minor_locator(LogLocator(base=10.0, subs=tuple(range(1, 10))))
    axis.set_minor_formatter(FuncFormatter(lambda v, p: ""))
