"""Animation of the pendulum on its vibrating pivot (GIF, or MP4 when ffmpeg is present).

The state at every frame is evaluated exactly at the frame's time (for the undamped
pendulum: the closed-form phase maps), never interpolated between samples. The
pivot moves on its zero-mean parabolic path (:func:`kapitza.motion.pivot_displacement`);
``theta`` is counted counter-clockwise from the upright, so ``theta > 0`` leans the
rod to the left, as in the paper's figure of the pendulum.
"""
from __future__ import annotations

import shutil
import sys
import textwrap
import time
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import matplotlib.pyplot as plt
from matplotlib import animation as mpl_animation

from .. import _validate as _v
from .._io import atomic_path
from .motion import LINEAR_STYLE, NONLINEAR_STYLE, WINDOW_STYLE, padded_limits, parameter_label

__all__ = ["ProgressBar", "AnimationResult", "animate", "ffmpeg_available", "frame_times", "MAX_FRAMES"]

#: Refuse renders longer than this many frames (``KAPITZA_ALLOW_LARGE=1`` lifts it).
MAX_FRAMES = 20000
#: Largest resolution (the figure is 9 x 4.6 inches: 600 dpi is 5400 x 2760 pixels).
MAX_DPI = 600
#: A GIF's frames are held in memory (RGBA) until the file is written: at most this many bytes.
MAX_GIF_BYTES = 2 * 1024**3
FIGSIZE = (9.0, 4.6)


class ProgressBar:
    """A one-line progress bar on standard error: ``label [#####.....]  45%  90/200``.

    Call it as ``bar(done, total)`` (``done`` counts from 1) or pass it as
    matplotlib's ``progress_callback`` through :meth:`frame_callback`.
    """

    def __init__(self, label="", stream=None, width=30, enabled=True):
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.enabled = enabled
        self._last = -1
        self._start = time.monotonic()
        self._shown = -1.0

    def __call__(self, done, total):
        if not self.enabled or total <= 0:
            return
        pct = int(100 * done / total)
        now = time.monotonic()
        # Redraw on each new percent but at most ~5 times a second, and always at the end.
        if done != total and (pct == self._last or now - self._shown < 0.2):
            return
        self._last = pct
        self._shown = now
        fill = int(self.width * done / total)
        elapsed = now - self._start
        eta = elapsed / done * (total - done) if done else 0.0
        tail = f" ~{eta:.0f} s left" if done < total else f" {elapsed:.1f} s"
        self.stream.write(f"\r{self.label} [{'#' * fill}{'.' * (self.width - fill)}] "
                          f"{pct:3d}%  {done}/{total}{tail}   ")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()

    def frame_callback(self, current, total):
        """matplotlib's ``progress_callback(current_frame, total_frames)`` (0-based)."""
        self(current + 1, total)


@dataclass(frozen=True)
class AnimationResult:
    """What was written.

    Attributes
    ----------
    path : Path
        The file (``.gif`` or ``.mp4``).
    frames : int
        Frames in the file.
    fps : float
        Frames per second of playback.
    slowdown : float
        Seconds of playback per second of motion.
    format : str
        ``'gif'`` or ``'mp4'``.
    message : str
        Empty, or why the format differs from the one asked for.
    """

    path: Path
    frames: int
    fps: float
    slowdown: float
    format: str
    message: str = ""


#: Render as matplotlib and Pillow would by themselves (a palette per GIF frame, every glyph
#: rasterised anew): the baseline of ``benchmarks/bench_renders.py``.
_LEGACY = False


class _BlitPillowWriter(mpl_animation.PillowWriter):
    """:class:`matplotlib.animation.PillowWriter` that takes each frame from the canvas as
    drawn (static background plus the moving artists) instead of re-rendering the figure, and
    writes the GIF with one palette for all frames.

    Pillow would quantise every RGBA frame to its own adaptive palette (most of the time of a
    render). The frames share their background, so one palette, taken from a few frames spread
    over the clip, serves them all; each frame is then mapped to it (nearest colour, no
    dithering, as Pillow's own conversion does not dither either).
    """

    def grab_frame(self, **savefig_kwargs):
        from PIL import Image

        canvas = self.fig.canvas
        w, h = canvas.get_width_height(physical=True)
        frame = Image.frombuffer("RGBA", (w, h), bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
        self._frames.append(frame if _LEGACY else frame.convert("RGB"))

    def finish(self):
        if _LEGACY or len(self._frames) < 2:
            return super().finish()
        from PIL import Image

        frames = self._frames
        picks = sorted({0, len(frames) // 3, (2 * len(frames)) // 3, len(frames) - 1})
        w, h = frames[0].size
        sample = Image.new("RGB", (w, h * len(picks)))
        for i, j in enumerate(picks):
            sample.paste(frames[j], (0, i * h))
        palette = sample.quantize(colors=256, method=Image.Quantize.FASTOCTREE)
        self._frames = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
        super().finish()


class _GlyphCache:
    """Rasterised glyphs kept between frames while an animation is drawn.

    matplotlib's Agg renderer asks FreeType for every glyph of every string anew; the clock is
    redrawn each frame, so a clip rasterises the same dozen characters thousands of times. The
    bitmap of a glyph depends only on the font, size, glyph and the sub-pixel part of its
    position (the whole-pixel part only moves it), so each is kept under that key and drawn
    again where matplotlib would draw it: the same pixels, without FreeType. Used as a context
    manager around the frames; anything but plain upright antialiased text (mathtext boxes,
    rotation, slant) goes through matplotlib's own path.
    """

    def __init__(self, renderer):
        self.renderer = renderer
        self.cache = {}
        self.fonts = []  # keep the fonts alive: their ids are part of the keys
        self.mono = {}  # (font file, size, dpi) -> [checked strings, advance, {char: (font, glyph)}]

    def __enter__(self):
        r = self.renderer
        try:
            from matplotlib.backends.backend_agg import get_hinting_flag
            from matplotlib.ft2font import RenderMode

            self._flags, self._mode = get_hinting_flag, RenderMode.NORMAL
            self._orig = r._draw_text_glyphs_and_boxes
            r._renderer.draw_text_image  # noqa: B018 - the private API this relies on
        except (ImportError, AttributeError):
            self._orig = None
            return self
        self._orig_text = r.draw_text
        r._draw_text_glyphs_and_boxes = self._draw
        r.draw_text = self._draw_text
        return self

    def __exit__(self, *exc):
        if self._orig is not None:
            del self.renderer._draw_text_glyphs_and_boxes  # the class's methods again
            del self.renderer.draw_text
        return False

    def _draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
        """The layout of a string in a monospaced font is its characters at a fixed advance: laid
        out from the characters once seen, after the first strings of that font were checked
        against matplotlib's own layout (any difference, or another font: its own layout)."""
        r = self.renderer
        if ismath or angle or (mtext is not None and (mtext.get_fontfeatures() or mtext.get_language())):
            return self._orig_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)
        font = r._prepare_font(prop)
        key = (font.fname, prop.get_size_in_points(), r.dpi)
        entry = self.mono.get(key)
        if entry is None:
            pair = font._layout("00", flags=self._flags())
            adv = pair[1].x - pair[0].x if len(pair) == 2 else None
            entry = self.mono[key] = [0, adv, {}]
        checked, adv, chars = entry
        items = None
        if adv and checked >= 0 and "\n" not in s:
            glyphs = []
            for c in s:
                g = chars.get(c)
                if g is None:
                    one = font._layout(c, flags=self._flags())
                    g = chars[c] = (one[0].ft_object, one[0].glyph_index) if len(one) == 1 and one[0].x == 0 else False
                if not g:
                    break
                glyphs.append(g)
            else:
                items = [(f, gi, i * adv) for i, (f, gi) in enumerate(glyphs)]
        if items is not None and checked < 3:
            real = font._layout(s, flags=self._flags())
            same = len(real) == len(items) and all(
                it.ft_object is f and it.glyph_index == gi and it.x == gx and it.y == 0
                for it, (f, gi, gx) in zip(real, items))
            entry[0] = checked + 1 if same else -1
            if not same:
                items = None
        if items is None:
            return self._orig_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)
        size = prop.get_size_in_points()
        self._draw(gc, x, y, angle, [(f, size, gi, 0, 1, gx, 0.0) for f, gi, gx in items], [])

    def _draw(self, gc, x, y, angle, glyphs, boxes):
        glyphs = list(glyphs)
        if angle or boxes or not gc.get_antialiased() or any(g[3] != 0 or g[4] != 1 for g in glyphs):
            return self._orig(gc, x, y, angle, glyphs, boxes)
        r = self.renderer
        height = r.height
        flags = self._flags()
        for font, size, glyph_index, _, _, dx, dy in glyphs:
            # the position FreeType is given, in 1/64 pixel (as matplotlib computes it)
            px = round(0x40 * (x + dx))
            py = round(0x40 * (height - y + dy))
            key = (id(font), size, r.dpi, glyph_index, px & 63, py & 63, flags)
            hit = self.cache.get(key)
            if hit is None:
                font.set_size(size, r.dpi)
                font._set_transform(np.array([[0x10000, 0], [0, 0x10000]]), [px & 63, py & 63])
                bitmap = font._render_glyph(glyph_index, flags, self._mode)
                hit = self.cache[key] = (np.array(bitmap.buffer), bitmap.left, bitmap.top)
                self.fonts.append(font)
            buf, left, top = hit
            r._renderer.draw_text_image(buf, left + (px >> 6), int(height) - (top + (py >> 6)) + buf.shape[0], 0, gc)


def ffmpeg_available() -> bool:
    """Whether matplotlib can write MP4 here (an ``ffmpeg`` executable is found)."""
    return (bool(mpl_animation.writers.is_available("ffmpeg"))
            and shutil.which(plt.rcParams["animation.ffmpeg_path"]) is not None)


def default_slowdown(T, fps):
    """Playback seconds per second of motion so that one drive period ``2T`` spans >= 24 frames."""
    return max(1.0, 24.0 / (2.0 * T * fps))


def frame_times(duration, fps, slowdown):
    """Times of the frames [s of motion]: ``k / (fps * slowdown)`` up to ``duration``
    (at most :data:`MAX_FRAMES` of them, checked before anything is allocated)."""
    n = np.floor(duration * fps * slowdown + 1e-9) + 1.0
    _v.bounded_work("the frames, duration * fps * slowdown", n, MAX_FRAMES,
                    what=f"a render of minutes; shorten the motion or lower fps * slowdown (now {fps:g} * "
                         f"{slowdown:.3g})")
    return np.arange(int(n)) / (fps * slowdown)


#: Height of the band kept free above the pendulum for the clock, in rod lengths.
CLOCK_BAND = 0.5


def _scene_limits(l, stroke):
    """Limits of the scene: the bob's reach (``l`` about a pivot within ``+-stroke/2``), with a band
    above it, where the bob never goes, for the clock. Returns ``(xlim, ylim, y_clock)``."""
    half = 0.5 * stroke
    r = 1.12 * l
    top = r + half + CLOCK_BAND * l
    return (-r, r), (-r - half, top), top


def _fresh_path(path):
    """``path`` if it does not exist, else the first of ``stem-2.ext``, ``stem-3.ext``... that does not."""
    if not path.exists():
        return path
    k = 2
    while (cand := path.with_name(f"{path.stem}-{k}{path.suffix}")).exists():
        k += 1
    return cand


def animate(traj, path, *, fps=25.0, slowdown=None, dpi=100, progress=None, format=None, linear=None,
            tol=None, title=None) -> AnimationResult:
    """Render a :class:`kapitza.motion.Trajectory` as an animation.

    Parameters
    ----------
    traj : Trajectory
        The motion; its whole duration is rendered.
    path : str or Path
        Output file; ``.gif`` or ``.mp4`` (MP4 needs ffmpeg: without it a GIF is
        written beside, under a fresh name ``stem-2.gif``... if that GIF exists, and
        :attr:`AnimationResult.message` names it).
    fps : float, optional
        Playback frames per second (1 to 60).
    slowdown : float, optional
        Playback seconds per second of motion (>= 1 slows it down); by default one
        drive period spans at least 24 frames, so the vibration is not aliased.
    dpi : int, optional
        Resolution (the figure is 9 x 4.6 inches).
    progress : callable or bool, optional
        ``True``: a :class:`ProgressBar` on standard error; a callable is called
        as ``progress(done, total)``.
    format : {None, 'gif', 'mp4'}
        Overrides the suffix of ``path``.
    linear : Trajectory, optional
        A linear motion to draw in the time panel for comparison.
    tol : float, optional
        Draw the window ``|theta| <= tol`` in the time panel.
    title : str, optional

    Returns
    -------
    AnimationResult

    Raises
    ------
    KapitzaValueError
        If the format is not GIF or MP4, ``fps`` is outside 1 to 60, ``slowdown`` or ``tol`` is not
        positive, ``dpi`` is not a whole number from 20 to 600, or the frames would exceed 20,000
        (or a GIF's frames 2 GiB of memory); nothing is written then.

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> import kapitza
    >>> from kapitza.figures import animate
    >>> folder = tempfile.mkdtemp()
    >>> result = animate(kapitza.simulate(0.1, 0.0, T=0.15, A=100.0, periods=1), os.path.join(folder, "up.gif"),
    ...                  fps=10, dpi=40)
    >>> result.path.name, result.frames, result.format
    ('up.gif', 25, 'gif')
    >>> shutil.rmtree(folder)
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    path = Path(path)
    fmt = format or (path.suffix.lower().lstrip(".") or "gif")
    if fmt not in ("gif", "mp4"):
        raise _v.KapitzaValueError(f"animation format must be 'gif' or 'mp4'; got {fmt!r}")
    fps = _v.one("fps", _v.in_range("fps", fps, 1.0, 60.0, lo_open=False, hi_open=False))
    slowdown = default_slowdown(traj.T, fps) if slowdown is None else \
        _v.one("slowdown", _v.positive("slowdown", slowdown))
    dpi = _v.bounded_count("dpi", dpi, MAX_DPI, minimum=20)
    if tol is not None:   # (the window |theta| <= tol of the motion functions)
        tol = _v.one("tol", _v.in_range("tol", tol, 0.0, np.pi, hi_open=False))
    duration = float(traj.t[-1])
    times = frame_times(duration, fps, slowdown)
    message = ""
    if fmt == "mp4" and not ffmpeg_available():
        # Never replace a GIF the user already has: fall back to a fresh name, and say which.
        gif = _fresh_path(path.with_suffix(".gif"))
        message = (f"ffmpeg was not found, so MP4 cannot be written; wrote the GIF {gif} instead "
                   "(install ffmpeg for MP4)")
        fmt, path = "gif", gif
    else:
        path = path.with_suffix("." + fmt)
    if fmt == "gif":
        frame_bytes = 4.0 * round(FIGSIZE[0] * dpi) * round(FIGSIZE[1] * dpi)
        _v.bounded_work("the GIF's frames * bytes per frame", times.size * frame_bytes, MAX_GIF_BYTES,
                        what=f"a GIF's frames are held in memory until it is written: {times.size} frames of "
                             f"{frame_bytes / 2**20:.1f} MiB at dpi {dpi}; lower --dpi, fps * slowdown or the "
                             f"periods, or write MP4")

    th, _ = traj.at(times)
    drive = traj.drive
    yp = drive.displacement(times, traj.T, traj.A)
    acc = drive.acceleration(times, traj.T, traj.A)
    l = traj.l
    bx = -l * np.sin(th)
    by = yp + l * np.cos(th)

    fig = plt.figure(figsize=FIGSIZE, dpi=dpi, layout="constrained")
    gs = fig.add_gridspec(1, 2, width_ratios=[1.0, 1.35])
    ax = fig.add_subplot(gs[0])
    axt = fig.add_subplot(gs[1])
    stroke = float(drive.stroke(traj.T, traj.A))
    xlim, ylim, y_clock = _scene_limits(l, stroke)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal")
    ax.set_xlabel("x  (m)")
    ax.set_ylabel("height  (m, pivot's mean at 0)")
    ax.plot([0, 0], [-0.5 * stroke, 0.5 * stroke], color="0.6", linewidth=6, solid_capstyle="butt", alpha=0.5,
            label="pivot's travel")
    upright, = ax.plot([], [], color="0.55", linestyle=":", linewidth=1.0, label="upright")
    trail, = ax.plot([], [], color="#e67e22", linewidth=1.0, alpha=0.6, label="bob's recent path")
    rod, = ax.plot([], [], color="k", linewidth=2.2, solid_capstyle="round")
    bob, = ax.plot([], [], marker="o", markersize=13, color="#1f4e9c", markeredgecolor="k")
    pivot, = ax.plot([], [], marker="s", markersize=8, color="0.2")
    # The clock sits in the band above the bob's reach, so the bob never covers it.
    clock = ax.text(0.0, y_clock - 0.03 * l, "", ha="center", va="top", fontsize=7, family="monospace",
                    linespacing=1.1)
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, fontsize=6.5, frameon=False,
              handlelength=1.5, columnspacing=1.0)

    axt.plot([], [], label=f"θ(t), {traj.model}", **NONLINEAR_STYLE)
    line, = axt.plot([], [], **NONLINEAR_STYLE)
    if linear is not None:
        lin_t, lin_th = linear.t, linear.theta
        axt.plot([], [], label="θ(t), linear (2.3)", **LINEAR_STYLE)
        lline, = axt.plot([], [], **LINEAR_STYLE)
    else:
        lline = None
    now, = axt.plot([], [], marker="o", markersize=5, color="#1f4e9c")
    lo, hi = float(np.min(traj.theta)), float(np.max(traj.theta))
    if tol is not None:
        for s in (-1, 1):
            axt.axhline(s * tol, **WINDOW_STYLE)
        axt.plot([], [], label=f"window |θ| ≤ {tol:g} rad", **WINDOW_STYLE)
        lo, hi = min(lo, -tol), max(hi, tol)
    y0, y1 = padded_limits(lo, hi)
    pad = y1 - hi
    axt.set_xlim(0.0, duration)
    axt.set_ylim(y0, y1)
    if linear is not None:
        # An unstable linear motion is drawn until it leaves the axes (then one step beyond).
        off = np.flatnonzero(np.abs(lin_th) > max(abs(lo), abs(hi)) + pad)
        lin_end = off[0] + 1 if off.size else lin_t.size
    axt.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
    axt.set_xlabel("t  (s)")
    axt.set_ylabel("θ  (rad from upright)")
    axt.grid(True, linewidth=0.4, color="0.88")  # opaque: GIF palettes dither translucent lines
    axt.legend(loc="upper left", fontsize=7, framealpha=0.85)
    head = title or parameter_label(traj.T, traj.A, traj.l, traj.g, traj.drive, traj.c)
    fig.suptitle("\n".join(textwrap.wrap(head, 120)), fontsize=8.5)  # two lines rather than cut at the edges

    trail_n = max(2, int(round(2.0 * traj.T * fps * slowdown)))  # about one drive period
    dense_t = traj.t

    def draw(k):
        x, y, p = bx[k], by[k], yp[k]
        rod.set_data([0.0, x], [p, y])
        bob.set_data([x], [y])
        pivot.set_data([0.0], [p])
        upright.set_data([0.0, 0.0], [p, p + l])
        a = max(0, k - trail_n)
        trail.set_data(bx[a:k + 1], by[a:k + 1])
        j = int(np.searchsorted(dense_t, times[k], side="right"))
        line.set_data(np.append(dense_t[:j], times[k]), np.append(traj.theta[:j], th[k]))
        if lline is not None:
            jl = min(int(np.searchsorted(lin_t, times[k], side="right")), lin_end)
            lline.set_data(lin_t[:jl], lin_th[:jl])
        now.set_data([times[k]], [th[k]])
        phase = f"a = {acc[k] / traj.A:+.2f} A" + (" (repels)" if traj.g + acc[k] > 0 else " (attracts)")
        angle = f"{th[k]:+.3f}" if abs(th[k]) < 1e6 else f"{th[k]:+.4g}"   # (not a line of 300 digits)
        clock.set_text(f"t = {times[k]:.3f} s = {times[k] / (2 * traj.T):.2f} · 2T\n"
                       f"θ = {angle} rad\n{phase}")
        return dynamic

    dynamic = [rod, bob, pivot, upright, trail, line, now, clock] + ([lline] if lline is not None else [])
    for a in dynamic:
        a.set_animated(True)
    # Lay the figure out once (on the last frame, whose texts are widest), freeze it and keep
    # the static part as a bitmap: each frame then redraws only the moving artists, instead of
    # every tick label and the constrained layout.
    draw(times.size - 1)
    fig.canvas.draw()
    fig.set_layout_engine("none")
    fig.canvas.draw()
    background = fig.canvas.copy_from_bbox(fig.bbox)  # type: ignore[attr-defined]  # (the Agg canvas)

    if progress is True:
        progress = ProgressBar(f"rendering {path.name}")
    writer = _BlitPillowWriter(fps=fps) if fmt == "gif" else mpl_animation.FFMpegWriter(fps=fps)
    try:
        with atomic_path(path) as tmp:
            with writer.saving(fig, str(tmp), dpi), \
                    (nullcontext() if _LEGACY else _GlyphCache(fig.canvas.get_renderer())):  # type: ignore[attr-defined]
                for k in range(times.size):
                    fig.canvas.restore_region(background)  # type: ignore[attr-defined]
                    for a in draw(k):
                        a.axes.draw_artist(a)
                    writer.grab_frame()
                    if progress:
                        progress(k + 1, times.size)
    finally:
        plt.close(fig)
    return AnimationResult(path=path, frames=int(times.size), fps=fps, slowdown=slowdown, format=fmt, message=message)
