"""Figures of the nonlinear stability of the upright: the chart and the rotation number's growth.

Drawing only; the numbers come from :mod:`kapitza.resonances` (curves), :mod:`kapitza.normal_form`
(twist) and :mod:`kapitza.motion.rotation` (long exact runs). ``docs/nonlinear.md`` sections 6-7.
"""
from __future__ import annotations

import numpy as np

from .._normal_form import _DEFECT_DRAW, _normal_form
from ..resonances import nonlinear_chart
from . import _style

__all__ = ["plot_nonlinear_zone", "plot_nonlinear_overview", "nonlinear_chart_figure", "plot_rotation_growth",
           "rotation_growth_figure"]

RES3 = dict(color="#6a3d9a", linestyle="--", linewidth=1.3)
RES4_STABLE = dict(color="#1b7837", linestyle="-", linewidth=1.8)
RES4_UNSTABLE = dict(color="#d73027", linestyle="-", linewidth=2.4)
TWIST0 = dict(color="black", marker="o", linestyle="none", markersize=3)


def _twist_grid(z, across=41):
    """log10 |tau| on (mu, position across the zone) for zone curves ``z``."""
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, across))[1:-1]
    eps = z.eps_lo[:, None] + s[None, :] * (z.eps_hi - z.eps_lo)[:, None]
    mu = np.broadcast_to(z.mu[:, None], eps.shape)
    nf, stable = _normal_form(eps, mu, _DEFECT_DRAW)
    tau = np.where(stable, nf.twist, np.nan)
    return s, np.log10(np.abs(tau))


def plot_nonlinear_zone(z, ax=None, shade=True, across=41, legend=True):
    """One zone across its width: ``(eps - eps_lo)/(eps_hi - eps_lo)`` against ``mu``.

    Parameters
    ----------
    z : kapitza.resonances.ZoneCurves
    ax : matplotlib Axes, optional
    shade : bool
        Shade the zone by ``log10 |tau|`` (every point is Lyapunov stable by Moser's theorem
        unless it lies on a drawn curve that says otherwise).
    across : int
        Grid points across the zone for the shading.

    Returns
    -------
    Drawn
        ``"twist"`` (the mesh), ``"1:3"``, ``"1:4 stable"``, ``"1:4 unstable"``, ``"twist = 0"``;
        ``.data`` is ``z``.
    """
    import matplotlib.pyplot as plt

    ax = ax or plt.figure().add_subplot()
    drawn = _style.Drawn(ax, data=z)
    width = z.eps_hi - z.eps_lo
    pos = lambda e: (e - z.eps_lo) / width  # noqa: E731
    if shade and z.mu.size > 1:
        s, logt = _twist_grid(z, across)
        drawn["twist"] = ax.pcolormesh(s, z.mu, logt, shading="nearest", cmap="Blues", alpha=0.8, rasterized=True)
    drawn["1:3"] = ax.plot(pos(z.eps_1to3), z.mu, label="1:3  (tr M = -1)", **RES3)
    ok = z.markeev_stable
    drawn["1:4 stable"] = ax.plot(np.where(ok, pos(z.eps_1to4), np.nan), z.mu,
                                  label="1:4  (tr M = 0): Markeev stable", **RES4_STABLE)
    if not ok.all():
        drawn["1:4 unstable"] = ax.plot(np.where(~ok, pos(z.eps_1to4), np.nan), z.mu,
                                        label="1:4: Markeev unstable", **RES4_UNSTABLE)
    if z.twist_zeros:
        zm, ze = np.array(z.twist_zeros).T
        lo_z, hi_z = (np.interp(zm, z.mu, v) for v in (z.eps_lo, z.eps_hi))
        drawn["twist = 0"] = ax.plot((ze - lo_z) / (hi_z - lo_z), zm, label="twist = 0 (undecided)", **TWIST0)
    sign = {1: r"$\tau > 0$", -1: r"$\tau < 0$"}.get(z.twist_sign, r"$\tau$ changes sign")
    ax.set_title(f"zone {z.n}: {sign} throughout", fontsize=9)
    ax.set_xlim(0, 1)
    ax.set_ylim(z.mu.min(), z.mu.max())
    lo_kind, hi_kind = ("2T", "4T") if z.n % 2 == 0 else ("4T", "2T")
    ax.set_xlabel(rf"$(\varepsilon-\varepsilon_\mathrm{{lo}})/(\varepsilon_\mathrm{{hi}}-\varepsilon_\mathrm{{lo}})$"
                  f"   ({lo_kind} edge at 0, {hi_kind} edge at 1)", fontsize=8)
    ax.set_ylabel(r"$\mu$", fontsize=8)
    ax.tick_params(labelsize=8)
    if legend:
        _style.place_legend(ax, inside=True, fontsize=7, loc="lower right")
    return drawn


def plot_nonlinear_overview(chart, ax=None):
    """The zones on Arnold's plane (``eps`` across, ``mu`` up) with the 1:3 and 1:4 curves.

    Returns
    -------
    Drawn
        ``"zone n"`` fills and the curves; ``.data`` is the chart.
    """
    import matplotlib.pyplot as plt

    ax = ax or plt.figure().add_subplot()
    drawn = _style.Drawn(ax, data=chart)
    for z in chart.zones:
        drawn[f"zone {z.n}"] = ax.fill_betweenx(z.mu, z.eps_lo, z.eps_hi, color=_style.ZONE_FILL, linewidth=0.6,
                                                edgecolor="#1f4e9c",
                                                label="linear zone: Lyapunov stable (Moser)" if z.n == 0 else None)
        drawn[f"1:3 zone {z.n}"] = ax.plot(z.eps_1to3, z.mu, label="1:3" if z.n == 0 else None, **RES3)
        drawn[f"1:4 zone {z.n}"] = ax.plot(z.eps_1to4, z.mu, label="1:4 (Markeev stable)" if z.n == 0 else None,
                                           **RES4_STABLE)
        ax.annotate(f"{z.n}", (z.eps_hi[0], z.mu[0]), xytext=(4, 2), textcoords="offset points", fontsize=8)
    ax.set_xlabel(r"$\varepsilon = T\sqrt{A}/\sqrt{8l}$")
    ax.set_ylabel(r"$\mu = \sqrt{g/A}$")
    ax.set_ylim(0, 1)
    ax.set_xlim(0, max(float(np.max(z.eps_hi)) for z in chart.zones) * 1.05)
    _style.place_legend(ax, inside=True, loc="upper left")
    return drawn


def nonlinear_chart_figure(chart=None, mu=None, zones=(0, 1, 2), scan=40, across=41):
    """The nonlinear stability chart: overview plus one panel per zone across its width.

    Parameters
    ----------
    chart : NonlinearChart, optional
        Computed from ``mu`` and ``zones`` when not given.
    mu : array_like, optional
        ``mu`` samples (default 80 in (0.01, 0.95)).

    Returns
    -------
    matplotlib Figure
    """
    if chart is None:
        chart = nonlinear_chart(np.linspace(0.01, 0.95, 80) if mu is None else mu, zones, scan=scan)
    k = len(chart.zones)
    fig = _style.new_figure(width=3.2 * (k + 1), height=4.2, caption_lines=3)
    axes = fig.subplots(1, k + 1)
    plot_nonlinear_overview(chart, axes[0])
    axes[0].set_title("zones on Arnold's plane", fontsize=9)
    for ax, z in zip(axes[1:], chart.zones):
        d = plot_nonlinear_zone(z, ax, across=across, legend=(z is chart.zones[0]))
        if "twist" in d:
            cb = fig.colorbar(d["twist"], ax=ax, location="bottom", shrink=0.9, pad=0.02, aspect=30)
            cb.set_label(r"$\log_{10}|\tau|$ [turns per period per rad$^2$]", fontsize=7)
            cb.ax.tick_params(labelsize=7)
    found = sum(len(z.twist_zeros) for z in chart.zones)
    unstable = sum(int((~z.markeev_stable).sum()) for z in chart.zones)
    _style.caption(fig, (
        "Nonlinear stability of the upright (square wave, undamped). Every point inside a linear zone is "
        "Lyapunov stable by Moser's twist theorem where the twist $\\tau \\neq 0$; the odd period map has no "
        "resonant term at 1:3 (dashed) below degree 5, so there the twist decides too. On 1:4 (solid) "
        "Markeev's criterion compares $|\\tau|$ with the resonant $|c_4|$: "
        + ("stable on every point drawn" if unstable == 0 else f"unstable on {unstable} of the points drawn")
        + " ($|\\tau|/|c_4|$ between "
          f"{min(float(np.min(np.abs(z.twist_1to4) / z.resonant_1to4)) for z in chart.zones):.2f}"
        f" and {max(float(np.max(np.abs(z.twist_1to4) / z.resonant_1to4)) for z in chart.zones):.2f}). "
        + (f"Twist zeros (undecided at third order): {found} found" if found else
           f"No twist zero found ({chart.scan} scan points per zone and $\\mu$)")
        + ". Zone panels: position across the zone; shading $\\log_{10}|\\tau|$, $\\tau$ grows without bound at the "
          "edges."))
    return fig


def plot_rotation_growth(run, ax=None):
    """Measured rotation numbers of the exact map against ``w/(2 pi) + tau r^2``.

    Parameters
    ----------
    run : kapitza.motion.RotationRun
        From :func:`kapitza.motion.measured_rotation_number` at one ``(eps, mu)`` over ``r``.

    Returns
    -------
    Drawn
        ``"measured"``, ``"normal form"``, ``"linear"``; ``.data`` is ``run``.
    """
    import matplotlib.pyplot as plt

    ax = ax or plt.figure().add_subplot()
    drawn = _style.Drawn(ax, data=run)
    # each orbit at the largest |theta| it reached: the definition of r for its invariant curve
    r = np.ravel(run.max_theta)
    rho0 = float(np.ravel(run.w)[0]) / (2 * np.pi)
    tau = float(np.ravel(run.twist)[0])
    ok = np.ravel(run.bounded)
    drawn["measured"] = ax.plot(r[ok], np.ravel(run.rotation_number)[ok], "o", color="#1f4e9c", markersize=4,
                                label=f"exact nonlinear map, {run.periods} periods")
    rr = np.linspace(0, r.max() * 1.02, 200)
    drawn["normal form"] = ax.plot(rr, rho0 + tau * rr**2, "-", color="#d55e00",
                                   label=rf"$\rho_0 + \tau r^2$, $\tau$ = {tau:.5g}")
    drawn["linear"] = ax.axhline(rho0, color="0.5", linestyle=":", linewidth=1.0,
                                 label=rf"$\rho_0 = w/2\pi$ = {rho0:.6g}")
    if not ok.all():
        drawn["escaped"] = ax.plot(r[~ok], np.full((~ok).sum(), rho0), "x", color="#d73027",
                                   label="left |theta| < pi/2")
    ax.set_xlabel(r"amplitude $r = \max|\theta|$ of the invariant curve [rad]")
    ax.set_ylabel(r"rotation number $\rho$ [turns per period $2T$]")
    ax.set_xlim(0, rr[-1])
    _style.place_legend(ax, inside=True)
    return drawn


def rotation_growth_figure(run):
    """:func:`plot_rotation_growth` with its caption."""
    fig = _style.new_figure(width=7.0, height=4.3, caption_lines=4)
    ax = fig.add_subplot()
    plot_rotation_growth(run, ax)
    e, m = float(np.ravel(run.eps)[0]), float(np.ravel(run.mu)[0])
    ax.set_title(rf"$\varepsilon$ = {e:.6g}, $\mu$ = {m:.6g}", fontsize=9)
    _style.caption(fig, (
        "Rotation number of the stroboscopic map around the upright against the size of the invariant curve. "
        "Dots: orbits of the exact nonlinear map (Jacobi elliptic phase flows), each started on the linear "
        "map's invariant ellipse and placed at the largest $|\\theta|$ it reached; its rotation is the "
        "windowed average of the angle gained per period in the linear normal coordinate. Curve: the "
        "Birkhoff normal form's $\\rho_0 + \\tau r^2$ (kapitza.twist_coefficient). They agree as r goes to 0; "
        "what gap opens at larger r is the $O(r^4)$ term."))
    return fig
