"""The tower's charts on the rig plane (drive frequency against stroke, log axes): the stable
band of a chain of linked pendulums with each mode's zone-0 edges, for one tower or for towers
of 1 to N equal links side by side (``docs/tower.md``)."""
from __future__ import annotations

import numpy as np

from ..chain import Chain, tower_curves
from ._style import ZONE_FILL, Drawn, caption, new_figure

__all__ = ["plot_tower_chart", "tower_chart_figure", "tower_family", "plot_tower_motion", "tower_motion_figure",
           "animate_tower"]

#: one colour per mode, longest (mode 1) first
MODE_COLOURS = ("#1f4e9c", "#2e8b57", "#d48a00", "#8e44ad", "#c0392b", "#555555")


def _colour(k):
    return MODE_COLOURS[k % len(MODE_COLOURS)]


def _plain_log_axis(axis, lo, hi):
    """Real numbers on a log axis (0.5, 1, 2, 5, 10, 20, ... over a short range; 1, 10, 100 over a
    long one), not powers of ten."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    subs = (1.0, 2.0, 5.0) if hi / lo < 10**2.6 else (1.0,)
    axis.set_major_locator(LogLocator(base=10.0, subs=subs))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def tower_family(lengths, masses=None, links="rod", joint_damping=0.0, n_max=4):
    """Towers of 1 to ``n_max`` links: the first ``n`` links of ``lengths`` (a single length is
    repeated), e.g. ``tower_family(0.2)``: one, two, three and four 0.2 m rods.

    Parameters
    ----------
    lengths : float or sequence of float
        Link lengths [m] from the pivot up.
    masses, links, joint_damping :
        As in :class:`kapitza.Chain`.
    n_max : int
        The most links.

    Returns
    -------
    list of Chain

    Raises
    ------
    ValueError
        As in :class:`kapitza.Chain`.

    Examples
    --------
    >>> from kapitza.figures.tower import tower_family
    >>> [tower.n for tower in tower_family(0.2)]
    [1, 2, 3, 4]
    >>> tower_family([0.3, 0.2])
    [Chain([0.3], masses=[1.0], links='rod'), Chain([0.3, 0.2], masses=[1.0, 1.0], links='rod')]
    """
    L = list(np.atleast_1d(np.asarray(lengths, dtype=float)))
    if len(L) == 1:
        L = L * n_max
    m = None if masses is None else list(np.atleast_1d(np.asarray(masses, dtype=float)))
    if m is not None and len(m) == 1:
        m = m * len(L)
    return [Chain(L[:n], None if m is None else m[:n], links=links, joint_damping=joint_damping)
            for n in range(1, min(n_max, len(L)) + 1)]


def plot_tower_chart(chain=None, drive=None, g=9.81, ax=None, frequency_range=None, stroke_range=None,
                     amplitude=False, mark=None, curves=None, legend=True, title=True, label_edges=True):
    """Draw a tower's stable band on the rig plane, each mode's zone-0 edges labelled.

    Parameters
    ----------
    chain : Chain
        The tower (ignored when ``curves`` is given).
    drive, g, frequency_range, stroke_range :
        As in :func:`kapitza.chain.tower_curves`.
    ax : matplotlib Axes, optional
    amplitude : bool
        The vertical axis in displacement amplitude (half the stroke) instead of the stroke.
    mark : (frequency, stroke), optional
        A point to mark [Hz], [m].
    curves : TowerCurves, optional
        Precomputed curves.

    Returns
    -------
    Drawn
        ``"band"``, ``"lower"`` and ``"upper"`` (lists, one line per mode), ``"labels"``,
        ``"mark"``; ``.data`` is the :class:`~kapitza.chain.TowerCurves`.

    Raises
    ------
    ValueError
        As in :func:`kapitza.tower_curves`.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.figures.tower import plot_tower_chart
    >>> drawn = plot_tower_chart(kapitza.Chain([0.2, 0.2, 0.2]), mark=(200.0, 0.005))
    >>> sorted(drawn), len(drawn["lower"])
    (['band', 'labels', 'legend', 'lower', 'mark', 'upper'], 3)
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    if curves is None:
        curves = tower_curves(chain, drive=drive, g=g, frequency_range=frequency_range, stroke_range=stroke_range)
    if ax is None:
        ax = plt.figure(figsize=(6.0, 4.5), layout="constrained").add_subplot()
    y = 0.5 if amplitude else 1.0
    mm = 1e3 * y
    art = {}
    f, s = curves.frequency, curves.stroke
    art["band"] = ax.contourf(f, mm * s, curves.stable.astype(float), levels=[0.5, 1.5], colors=[ZONE_FILL], alpha=0.85)
    lower, upper, labels = [], [], []
    fr, sr = curves.frequency_range, curves.stroke_range
    for k, l in enumerate(curves.modal_lengths):
        c = _colour(k)
        name = f"mode {k + 1}: l = {1e3 * l:.4g} mm"
        (ln,) = ax.plot(curves.frequency_lo[k], mm * curves.stroke_lo[k], color=c, lw=1.5, label=name)
        (un,) = ax.plot(curves.frequency_hi[k], mm * curves.stroke_hi[k], color=c, lw=1.5, ls="--")
        lower.append(ln)
        upper.append(un)
        if label_edges:
            labels += _edge_labels(ax, curves, k, c, mm, fr, sr)
    art["lower"], art["upper"], art["labels"] = lower, upper, labels
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(*fr)
    ax.set_ylim(mm * sr[0], mm * sr[1])
    _plain_log_axis(ax.xaxis, *fr)
    _plain_log_axis(ax.yaxis, mm * sr[0], mm * sr[1])
    ax.set_xlabel("drive frequency 1/(2T) [Hz]")
    ax.set_ylabel("displacement amplitude [mm]" if amplitude else "stroke (peak to peak) [mm]")
    ax.grid(True, which="major", color="0.85", lw=0.6)
    if mark is not None:
        (art["mark"],) = ax.plot([mark[0]], [mm * mark[1]], marker="*", ms=12, color="k", ls="none", label="the point")
    if title:
        n = curves.n_links
        ax.set_title(f"{n} link{'s' if n > 1 else ''}", fontsize=10)
    if legend:
        art["legend"] = ax.legend(loc="lower left", fontsize=7, framealpha=0.9)
    return Drawn(ax, art, curves)


def _edge_labels(ax, curves, k, colour, mm, fr, sr):
    """Short labels on a mode's two edges where they run inside the window: ``k falls`` on the
    lower edge, ``k doubles`` on the upper one. A label goes on the side of its line where the
    mode fails (under a solid edge, above a dashed one), or on the other side where the window
    leaves no room there (a long mode's upper edge near the top of the window)."""
    out = []
    for F, S, text, where in ((curves.frequency_lo[k], curves.stroke_lo[k], f"{k + 1} falls", 0.25),
                              (curves.frequency_hi[k], curves.stroke_hi[k], f"{k + 1} doubles", 0.75)):
        falls = text.endswith("falls")
        visible = np.isfinite(F) & np.isfinite(S) & (F > fr[0] * 1.5) & (F < fr[1] / 1.6)
        for below in ((True, False) if falls else (False, True)):
            # room for the text under the line (and over the axis) or over it (and under the top)
            room_lo, room_hi = (2.0, 1.1) if below else (1.1, 2.0)
            idx = np.flatnonzero(visible & (S > sr[0] * room_lo) & (S < sr[1] / room_hi))
            if idx.size:
                break
        else:
            continue
        if below == falls:
            # a point part-way along the visible piece, spread by mode so that labels do not pile up
            j = idx[int((where + 0.12 * k) % 1.0 * (idx.size - 1))]
        else:
            # on the other side: where the edge runs level (three quarters along in log frequency),
            # clear of the shorter modes' labels crowding the low frequencies
            logf = np.log(F[idx])
            j = idx[int(np.argmin(np.abs(logf - (logf.min() + where * (logf.max() - logf.min())))))]
        out.append(ax.annotate(text, (F[j], mm * S[j]), fontsize=7, color=colour, ha="right" if below else "left",
                               va="top" if below else "bottom", xytext=(-2, -2) if below else (2, 2),
                               textcoords="offset points"))
    return out


def tower_chart_figure(chains, drive=None, g=9.81, frequency_range=None, stroke_range=None, amplitude=False,
                       mark=None, curves=None, title=None):
    """One panel per tower (e.g. :func:`tower_family`), sharing the window, with a caption.

    ``curves``: the towers' :class:`~kapitza.chain.TowerCurves`, when computed already;
    ``title``: a title over the panels.

    Parameters
    ----------
    chains : sequence of Chain
    drive, g, frequency_range, stroke_range, amplitude, mark :
        As in :func:`plot_tower_chart`; the window defaults to one holding every tower's band.
    curves : sequence of TowerCurves, optional
    title : str, optional

    Returns
    -------
    fig, list of Drawn

    Raises
    ------
    ValueError
        As in :func:`kapitza.tower_curves`.

    Examples
    --------
    >>> from kapitza.figures.tower import tower_chart_figure, tower_family
    >>> fig, drawn = tower_chart_figure(tower_family(0.2, n_max=3), mark=(200.0, 0.005))
    >>> len(drawn), [d.data.n_links for d in drawn]
    (3, [1, 2, 3])
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    from ..chain import default_window
    from ..drives import as_drive

    d = as_drive(drive)
    if frequency_range is None or stroke_range is None:
        wins = [default_window(c, d, g) for c in chains]
        fr = (min(w[0][0] for w in wins), max(w[0][1] for w in wins))
        sr = (min(w[1][0] for w in wins), max(w[1][1] for w in wins))
        frequency_range = frequency_range or fr
        stroke_range = stroke_range or sr
    n = len(chains)
    cols = min(n, 2) if n == 4 else n
    rows = (n + cols - 1) // cols
    fig = new_figure(width=4.2 * cols + 0.4, height=3.6 * rows)
    axes = fig.subplots(rows, cols, squeeze=False, sharex=True, sharey=True).ravel()
    drawn = []
    for i, (ax, ch) in enumerate(zip(axes, chains)):
        drawn.append(plot_tower_chart(ch, drive=d, g=g, ax=ax, frequency_range=frequency_range,
                                      stroke_range=stroke_range, amplitude=amplitude, mark=mark,
                                      curves=None if curves is None else curves[i]))
    for ax in axes[n:]:
        ax.set_visible(False)
    for ax in axes[:n]:
        if not ax.get_subplotspec().is_last_row():
            ax.set_xlabel("")
        if not ax.get_subplotspec().is_first_col():
            ax.set_ylabel("")
    if title:
        fig.suptitle(title, fontsize=11)
    c0 = chains[-1]
    kind = "uniform rods" if c0.links == "rod" else "point masses on massless rods"
    friction = (f" Joint friction c = {c0.joint_damping:.3g} N m s/rad couples the modes: the shading is the full "
                f"2N monodromy's verdict.") if c0.joint_damping > 0 and c0.n > 1 else ""
    more = " More links: a narrower band." if n > 1 else ""
    caption(fig, f"Shaded: the upright tower is stable ({d.describe()}, {kind}, g = {g:g} m/s$^2$). Each mode k of "
                 f"equivalent length $l_k$ is a single pendulum: solid, its lower edge of zone 0 (below it, too slow, "
                 f"the mode falls: the longest mode sets it); dashed, its upper edge (beyond it, too large a stroke, "
                 f"the mode doubles its period: the shortest mode sets it).{more}{friction}"
                 + (" Star: the point asked about." if mark is not None else ""))
    return fig, drawn


def plot_tower_motion(motion, ax=None, legend=True):
    """Draw each link's angle against time, the toppling window ``|theta| = tol`` and the moment
    the tower toppled.

    Parameters
    ----------
    motion : ChainMotion
        From :func:`kapitza.chain_motion`.
    ax : matplotlib Axes, optional

    Returns
    -------
    Drawn
        ``"links"`` (one line per link), ``"window"``, ``"topple"`` (when it toppled).
    """
    import matplotlib.pyplot as plt

    if ax is None:
        ax = plt.figure(figsize=(7.0, 3.6), layout="constrained").add_subplot()
    art = {"links": []}
    for j, th in enumerate(motion.theta):
        (ln,) = ax.plot(motion.t, th, color=_colour(j), lw=1.0, label=f"link {j + 1}")
        art["links"].append(ln)
    art["window"] = [ax.axhline(s * motion.tol, color="0.5", lw=0.8, ls=":") for s in (-1, 1)]
    if motion.toppled:
        art["topple"] = ax.axvline(motion.t_topple, color="#c0392b", lw=1.0, ls="--",
                                   label=f"toppled, t = {motion.t_topple:.3g} s")
    ax.axhline(0.0, color="0.75", lw=0.6)
    ax.set_xlim(0.0, 1.03 * max(float(motion.t[-1]), 1e-12))  # room for the moment it toppled, at the end
    top = max(1.1 * float(np.max(np.abs(motion.theta))) if motion.theta.size else 0.0, 0.05)
    ax.set_ylim(-min(top, 1.15 * motion.tol), min(top, 1.15 * motion.tol))
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(r"angle from the upright $\theta_j$ [rad]")
    ax.grid(True, color="0.9", lw=0.6)
    if legend:
        art["legend"] = ax.legend(loc="best", fontsize=7, ncol=min(motion.theta.shape[0] + 1, 5), framealpha=0.9)
    return Drawn(ax, art, motion)


def tower_motion_figure(motion, title=None):
    """The tower's motion over time (:func:`plot_tower_motion`) with a title and a caption.

    Returns
    -------
    fig, Drawn
    """
    fig = new_figure(width=7.0, height=3.8)
    ax = fig.add_subplot()
    drawn = plot_tower_motion(motion, ax=ax)
    n = motion.theta.shape[0]
    ax.set_title(title or f"{n}-link tower, T = {motion.T:.4g} s ({0.5 / motion.T:.4g} Hz), "
                          f"A = {motion.A:.4g} m/s$^2$", fontsize=10)
    end = (f"A link passed {motion.tol:.3g} rad at t = {motion.t_topple:.3g} s: the tower toppled." if motion.toppled
           else f"Every link stayed within {motion.tol:.3g} rad: the tower stands.")
    shown = ax.get_ylim()[1] >= motion.tol
    window = (f" Dotted: {chr(177)}{motion.tol:.3g} rad, beyond which a link has fallen." if shown else "")
    dt = float(np.median(np.diff(motion.t))) if motion.t.size > 1 else 0.0
    alias = (f" Sampled every {dt:.3g} s against a drive period of {2 * motion.T:.3g} s: the fast shaking is "
             "aliased, the slow swaying is not." if dt > 0.5 * motion.T else "")
    caption(fig, f"The full (nonlinear) motion of the tower on its shaken pivot ({motion.drive}): each link's angle "
                 f"from the upright (link 1 at the pivot). The small fast wiggles are the drive's shaking, the slow "
                 f"swaying the tower's own motion.{window} {end}{alias}")
    return fig, drawn


def _fresh(path):
    """``path``, or the first of ``stem-2.ext``, ``stem-3.ext``... that does not exist."""
    cand, k = path, 2
    while cand.exists():
        cand = path.with_name(f"{path.stem}-{k}{path.suffix}")
        k += 1
    return cand


def animate_tower(motions, path, *, titles=None, fps=20.0, slowdown=1.0, dpi=80, duration=None, progress=None):
    """Animate one or more tower motions side by side (:func:`kapitza.motion.chain.chain_motion`).

    Parameters
    ----------
    motions : ChainMotion or list of ChainMotion
    path : str or Path
        The ``.gif`` or ``.mp4`` written (atomically). MP4 needs ffmpeg: without it a GIF is
        written beside, under a fresh name if that GIF exists (the path returned says which).
    titles : list of str, optional
        One per panel.
    fps : float
        Frames per second of playback (1 .. 60).
    slowdown : float
        Playback seconds per second of motion (> 0; 1: real time, the drive's shaking aliased,
        the tower's slow motion as it is).
    dpi : int
    duration : float, optional
        Seconds of motion shown; the longest motion by default (a toppled tower stays fallen).
    progress : callable, optional
        Called as ``progress(done, total)`` after each frame (e.g. a
        :class:`kapitza.figures.animation.ProgressBar`).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ValueError
        If ``fps``, ``slowdown`` or ``duration`` is out of range.

    Examples
    --------
    >>> import os, shutil, tempfile
    >>> import kapitza
    >>> from kapitza.figures.tower import animate_tower
    >>> tower = kapitza.Chain([0.2, 0.2])
    >>> motion = kapitza.chain_motion(tower, 0.05, T=0.0025, A=3200.0, periods=4, points_per_period=8)
    >>> folder = tempfile.mkdtemp()
    >>> animate_tower(motion, os.path.join(folder, "tower.gif"), fps=10).name
    'tower.gif'
    >>> shutil.rmtree(folder)
    >>> import matplotlib.pyplot as plt
    >>> plt.close("all")
    """
    from pathlib import Path

    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter

    from .. import _validate as _v
    from .._io import atomic_path
    from .animation import ffmpeg_available

    if not isinstance(motions, (list, tuple)):
        motions = [motions]
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".") or "gif"
    if fmt not in ("gif", "mp4"):
        raise _v.KapitzaValueError(f"animation format must be .gif or .mp4; got {path.suffix or 'no suffix'!r}")
    fps = _v.one("fps", _v.in_range("fps", fps, 1.0, 60.0, lo_open=False, hi_open=False))
    slowdown = _v.one("slowdown", _v.positive("slowdown", slowdown))
    dpi = _v.bounded_count("dpi", dpi, 600, minimum=20)
    t_end = max(float(m.t[-1]) for m in motions) if duration is None else \
        _v.one("duration", _v.positive("duration", duration))
    n_frames = int(t_end * fps * slowdown) + 1
    _v.bounded_work("the frames, duration * fps * slowdown", n_frames, 2000, what="a GIF of a few minutes' render")
    if fmt == "mp4" and not ffmpeg_available():
        fmt, path = "gif", _fresh(path.with_suffix(".gif"))
    elif path.suffix.lower() != "." + fmt:
        path = path.with_suffix("." + fmt)
    times = np.arange(n_frames) / (fps * slowdown)
    k = len(motions)
    fig, axes = plt.subplots(1, k, figsize=(3.6 * k, 3.0), squeeze=False)
    axes = axes.ravel()
    artists = []
    for i, (ax, m) in enumerate(zip(axes, motions)):
        H = sum(m.lengths)
        amp = float(np.max(np.abs(m.pivot))) if m.pivot.size else 0.0
        ax.set_xlim(-1.1 * H, 1.1 * H)
        ax.set_ylim(-0.3 * H - amp, 1.15 * H + amp)
        ax.set_aspect("equal")
        ax.axhline(-amp, color="0.6", lw=0.8)
        ax.set_xticks([])
        ax.set_yticks([])
        if titles:
            ax.set_title(titles[i], fontsize=9)
        (line,) = ax.plot([], [], "-o", color=_colour(0), lw=3, ms=4, mfc="k", mec="k")
        (base,) = ax.plot([], [], "s", color="0.3", ms=9)
        clock = ax.text(0.03, 0.03, "", transform=ax.transAxes, fontsize=8)
        x, y = m.joints()
        artists.append((m, x, y, line, base, clock))
    fig.tight_layout()

    def frame(j):
        t = times[j]
        out = []
        for m, x, y, line, base, clock in artists:
            tt = min(t, float(m.t[-1]))  # a toppled tower lies where it fell
            xs = [np.interp(tt, m.t, xi) for xi in x]
            ys = [np.interp(tt, m.t, yi) for yi in y]
            line.set_data(xs, ys)
            base.set_data([xs[0]], [ys[0]])
            state = "fallen" if m.toppled and t >= m.t_topple else f"t = {t:5.2f} s"
            clock.set_text(state)
            out += [line, base, clock]
        return out

    anim = FuncAnimation(fig, frame, frames=n_frames, blit=False)
    writer = PillowWriter(fps=fps) if fmt == "gif" else FFMpegWriter(fps=fps)
    try:
        with atomic_path(path, suffix="." + fmt) as tmp:
            anim.save(tmp, writer=writer, dpi=dpi,
                      progress_callback=None if progress is None else (lambda i, n: progress(i + 1, n)))
    finally:  # an unwritable path must not leave the figure open
        plt.close(fig)
    return path
