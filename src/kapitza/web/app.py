"""The explorer's ASGI application: a JSON API over the library and the page that draws it.

Each route parses its query, makes one call into the library and returns JSON (or a file).
Bad input is the library's own :class:`kapitza.KapitzaValueError`, answered with status 422
and ``{"detail": message}``; the sizes a request may ask for (samples, periods, the span of
a view) are bounded here, with the same kind of message, so no request computes for minutes.
"""
from __future__ import annotations

import contextlib
import functools
import json
import threading
from pathlib import Path
from typing import Literal

import numpy as np
import orjson
from fastapi import FastAPI, Query, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles

from .. import __version__, _io
from .. import _validate as _v
from ..analysis import analyze
from ..drives import parse_drive
from ..drives._api import damping_of
from ..parameters import G_EARTH, to_physical

__all__ = ["create_app", "LIMITS"]

STATIC = Path(__file__).with_name("static")

#: What one request may ask for.
LIMITS = dict(
    samples=4000,          # mu (or A) samples per edge of a chart
    eps_max=60.0,          # the largest eps a view of Arnold's plane may reach
    general_eps_max=12.0,  # ... with another drive or damping (each edge a Floquet eigenproblem)
    periods=200.0,         # drive periods 2T of a motion
    points_per_period=200,
    motion_samples=20000,  # periods * points_per_period
    theta0=3.15,           # |theta0| <= about pi: a tilt from the upright
    zeta=10.0,             # damping ratio (10: far beyond critical damping)
    drive_text=200,        # characters of a drive's text form
    url=4096,              # characters of a request's path and query
    safe_tilt_integrated_periods=60,  # periods of a safe tilt followed by DOP853 (sine drive or damping)
)

Plane = Literal["arnold", "physical", "rig"]


# ------------------------------------------------------------------ JSON
def _json_bytes(obj) -> bytes:
    """JSON of ``obj``, numpy arrays included (orjson: exact shortest round-trip floats; NaN as null)."""
    try:
        return orjson.dumps(obj, default=_default, option=orjson.OPT_SERIALIZE_NUMPY)
    except TypeError:  # an integer beyond 64 bits (the turns of a run-away linear motion)
        return json.dumps(_io.to_jsonable(obj), default=_default, separators=(",", ":")).encode()


def _default(o):
    if isinstance(o, np.ndarray):  # not C-contiguous or not float64/int
        return np.ascontiguousarray(o, dtype=float)
    if isinstance(o, (np.floating, np.integer, np.bool_)):
        return o.item()
    if isinstance(o, complex):
        return [o.real, o.imag]
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def _beyond(a):
    """``+-inf`` (an edge beyond the view) as ``+-1e308``: JSON has no infinity."""
    return np.clip(a, -1e308, 1e308)


class _JSON(JSONResponse):
    def render(self, content) -> bytes:
        return _json_bytes(content)


# ------------------------------------------------------------------ parsing
def _drive(drive: str):
    if len(drive) > LIMITS["drive_text"]:
        raise _v.KapitzaValueError(f"drive must be at most {LIMITS['drive_text']} characters; got {len(drive)}")
    return parse_drive(drive)


def _bounded(name, value, hi, lo=None):
    """``value`` within ``[lo, hi]`` (a size limit of the explorer), named in the message."""
    lo = -np.inf if lo is None else lo
    if not (lo <= value <= hi):
        where = f"{lo:g} <= {name} <= {hi:g}" if np.isfinite(lo) else f"{name} <= {hi:g}"
        raise _v.KapitzaValueError(f"{name} must satisfy {where} in the explorer; got {value!r}")
    return value


def _zeta(zeta):
    """The damping ratio, >= 0 (the library's check) and at most ``LIMITS['zeta']``."""
    return _bounded("zeta", _v.one("zeta", _v.nonnegative("zeta", zeta)), LIMITS["zeta"])


def _damping(zeta, l, g):
    """Viscous damping ``c = 2 zeta sqrt(g/l)`` [1/s] of the explorer's damping ratio (bounded)."""
    return damping_of(_zeta(zeta), _v.one("l", _v.positive("l", l)), _v.one("g", _v.positive("g", g)))


def _physical_point(T, A, eps, mu, l, g):
    """``(T, A)`` from either pair; the other must be absent."""
    if (T is None) != (A is None) or (eps is None) != (mu is None) or (T is None) == (eps is None):
        raise _v.KapitzaValueError("give either T and A, or eps and mu (with l and g), not both or neither")
    if T is None:
        eps = _v.one("eps", _v.positive("eps", eps))
        mu = _v.one("mu", _v.positive("mu", mu))
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        T, A = (float(v) for v in to_physical(eps, mu, l, g))
    return T, A


class _BoundedRequests:
    """Refuse a path and query longer than ``LIMITS['url']`` (414) and any request body (413)."""

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send):
        if scope["type"] == "http":
            size = len(scope.get("raw_path") or b"") + len(scope.get("query_string") or b"")
            body = dict(scope.get("headers") or ()).get(b"content-length", b"0")
            status, detail = None, None
            if size > LIMITS["url"]:
                status, detail = 414, f"request path and query must be at most {LIMITS['url']} characters"
            elif body.strip() not in (b"", b"0"):
                status, detail = 413, "the explorer takes no request bodies"
            if status:
                return await _JSON(status_code=status, content={"detail": detail})(scope, receive, send)
        return await self.app(scope, receive, send)


# ------------------------------------------------------------------ the app
def create_app() -> FastAPI:
    """The explorer: the page at ``/``, the JSON API under ``/api``, its schema at ``/openapi.json``."""
    @contextlib.asynccontextmanager
    async def lifespan(app):
        # The routes compute with numpy: more threads than CPUs only take turns at the GIL, and
        # ten requests at once then all finish late. One thread per CPU keeps them in a queue.
        import anyio.to_thread

        anyio.to_thread.current_default_thread_limiter().total_tokens = max(2, _v.cpus())
        yield

    app = FastAPI(title="kapitza explorer", version=__version__, lifespan=lifespan, docs_url=None, redoc_url=None,
                  description="Exact stability zones and motions of the inverted pendulum on a vibrating pivot. "
                              "Parameters use the library's names: eps, mu (Arnold), T [s], A [m/s^2], l [m], "
                              "g [m/s^2], drive ('square', 'sine', 'rectangular:DUTY'), zeta (damping ratio).")

    @app.exception_handler(_v.KapitzaValueError)
    async def _value_error(request: Request, exc: _v.KapitzaValueError):
        return _JSON(status_code=422, content={"detail": str(exc).splitlines()[0]})

    @app.exception_handler(OverflowError)
    async def _overflow(request: Request, exc: OverflowError):
        return _JSON(status_code=422, content={"detail": f"the result exceeds a double: {exc}"})

    @app.exception_handler(RequestValidationError)
    async def _bad_query(request: Request, exc: RequestValidationError):
        parts = []
        for e in exc.errors():
            name = ".".join(str(x) for x in e.get("loc", ())[1:]) or "request"
            got = e.get("input")
            parts.append(f"{name}: {e.get('msg', 'invalid')}" + (f"; got {got!r}" if got is not None else ""))
        return _JSON(status_code=422, content={"detail": "; ".join(parts)})

    app.add_middleware(_BoundedRequests)

    @app.get("/", include_in_schema=False)
    def index():
        return FileResponse(STATIC / "index.html", media_type="text/html")

    app.mount("/static", StaticFiles(directory=STATIC), name="static")
    _docs_page(app)

    # -------------------------------------------------------------- chart
    @app.get("/api/chart", response_class=_JSON, summary="exact edges of every zone in a view")
    def chart(plane: Plane = "arnold",
              eps_min: float = 0.0, eps_max: float = 4.0, mu_min: float = 0.0, mu_max: float = 1.0,
              T_min: float = 0.0, T_max: float | None = None, A_min: float | None = None, A_max: float | None = None,
              l: float = 1.0, g: float = G_EARTH, drive: str = "square", zeta: float = 0.0,
              samples: int = Query(1000, description="samples per edge (at most 4000)"),
              f_min: float | None = Query(None, description="rig plane: lowest frequency [Hz]"),
              f_max: float | None = None,
              stroke_min: float | None = Query(None, description="rig plane: smallest stroke [m]"),
              stroke_max: float | None = None):
        """Edges ``lo``, ``hi`` of each zone ``n`` meeting the view, sampled at ``y`` (``mu`` on the
        arnold plane, ``A`` on the physical one); ``x`` is ``eps`` or ``T``. NaN (null) where a zone
        does not exist at a sample; 1e308 for an edge beyond the view. ``lower_edge``/``upper_edge``
        say which periodic motion lives on each edge (2T or 4T). ``mu_max``: at and above it
        (``A <= g / mu_max^2``) the upright always falls; the view may reach up to the larger of it
        and 1. On the ``rig`` plane ``x`` is the drive frequency [Hz] and ``y`` the stroke [m], both for log
        axes (``f_min`` .. ``stroke_max``); ``stroke_coefficient`` is ``k`` in stroke = k A T^2."""
        if plane == "rig":
            return Response(_rig_chart_json(f_min, f_max, stroke_min, stroke_max, l, g, drive, zeta, samples),
                            media_type="application/json")
        return Response(_chart_json(plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g,
                                    drive, zeta, samples), media_type="application/json")

    # -------------------------------------------------------------- point
    @app.get("/api/point", response_class=_JSON, summary="the stability report at one parameter set")
    def point(eps: float | None = None, mu: float | None = None, T: float | None = None, A: float | None = None,
              l: float = 1.0, g: float = G_EARTH, drive: str = "square", zeta: float = 0.0,
              frequency: float | None = Query(None, description="drive frequency [Hz], with stroke or amplitude"),
              stroke: float | None = Query(None, description="peak-to-peak travel of the pivot [m]"),
              amplitude: float | None = Query(None, description="displacement amplitude, half the stroke [m]"),
              rod: float | None = Query(None, description="a uniform rod of this length [m] (l = 2/3 of it)"),
              damping: float | None = Query(None, description="viscous damping c [1/s], instead of zeta"),
              safe_tilt: bool = Query(False, description="also the safe tilt (follows the real pendulum: slower)"),
              periods: int = Query(50, description="periods of the safe tilt (at most 200)")):
        """What ``kapitza stability --json`` prints (the same keys and numbers), with ``lines``: the
        table's rows and ``directions``: which knob to turn which way. Given ``T`` and ``A`` (or a rig's
        ``frequency`` with ``stroke`` or ``amplitude``, and ``rod`` for ``l``) the damping ratio ``zeta``
        becomes ``c = 2 zeta sqrt(g/l)``, or give ``damping`` (c) itself. ``safe_tilt=true`` adds the
        safe tilt [rad] (``kapitza.safe_tilt``), which is slower than the verdict: the page asks for
        it in a second request."""
        rep, d = _report(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
        if safe_tilt:
            from ..motion.basins import exact_path
            from ..safety import with_safe_tilt

            rep = with_safe_tilt(rep, d, _safe_periods(periods, exact_path(d, rep.zeta)))
        return _JSON(_io.to_jsonable({**rep.as_dict(), "lines": rep.lines()}))

    @app.get("/api/verdict", response_class=_JSON, summary="the verdict alone, at once (no margins)")
    async def verdict(eps: float | None = None, mu: float | None = None, T: float | None = None, A: float | None = None,
                l: float = 1.0, g: float = G_EARTH, drive: str = "square", zeta: float = 0.0,
                frequency: float | None = None, stroke: float | None = None, amplitude: float | None = None,
                rod: float | None = None, damping: float | None = None):
        """Stable or not and in which zone, from the Floquet multipliers alone (``kapitza.floquet``): the
        answer the page shows the moment a point is chosen, before the full report (margins and
        ranges, ``/api/point``) and the safe tilt (``/api/safe_tilt``). ``kind``: ``stable``,
        ``2T`` (multipliers real and positive), ``4T`` (period doubling) or ``weak`` (the pivot never
        accelerates down faster than g). A few milliseconds: answered on the event loop itself, never
        queued behind the slower routes' worker threads."""
        from ..propagation import floquet

        P = _point_of(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
        f = floquet(P["eps"], P["mu"], drive=None if P["drive"].name == "square" else P["drive"], zeta=P["zeta"])
        stable = bool(f.stable)
        if stable:
            kind, text = "stable", f"stable (zone {int(f.zone)})" + (", motions decay" if P["zeta"] > 0 else "")
        elif P["mu"] >= P["drive"].mu_max:
            kind, text = "weak", "always unstable: the pivot never accelerates down faster than g"
        elif float(f.trace) < 0:
            kind, text = "4T", "unstable: parametric resonance, 4T-type, period doubling"
        else:
            kind, text = "2T", "unstable: it falls (multipliers real, positive)"
        return _JSON(dict(eps=P["eps"], mu=P["mu"], T=P["T"], A=P["A"], zeta=P["zeta"], stable=stable,
                          zone=int(f.zone) if stable else -1, kind=kind, verdict=text, growth=float(f.growth),
                          trace=float(f.trace), given=P["given"]))

    @app.get("/api/safe_tilt", response_class=_JSON, summary="the largest starting tilt the real pendulum survives")
    def safe_tilt_route(eps: float | None = None, mu: float | None = None, T: float | None = None,
                        A: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                        zeta: float = 0.0, frequency: float | None = None, stroke: float | None = None,
                        amplitude: float | None = None, rod: float | None = None, damping: float | None = None,
                        periods: int = 50):
        """``safe_tilt`` [rad]: the largest starting tilt from rest whose motion stays above the horizontal
        for ``periods`` periods 2T (``kapitza.safe_tilt``; 0 where the upright is not stable), with the
        verdict it goes with and ``text``, the report's sentence."""
        from ..analysis import _safe_text
        from ..safety import safe_tilt
        from ..zones import is_stable

        from ..motion.basins import exact_path

        P = _point_of(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
        n = _safe_periods(periods, exact_path(P["drive"], P["zeta"]))
        d = None if P["drive"].name == "square" else P["drive"]
        stable = bool(is_stable(P["eps"], P["mu"], drive=d, zeta=P["zeta"]))
        theta = float(safe_tilt(P["eps"], P["mu"], drive=P["drive"], zeta=P["zeta"], periods=n)) if stable else 0.0
        return _JSON(dict(safe_tilt=theta, periods=n, stable=stable, eps=P["eps"], mu=P["mu"],
                          text=_safe_text(theta, n, stable)))

    # -------------------------------------------------------------- motion
    @app.get("/api/motion", response_class=_JSON, summary="linear and nonlinear motion, sampled for animation")
    def motion(T: float | None = None, A: float | None = None, eps: float | None = None, mu: float | None = None,
               l: float = 1.0, g: float = G_EARTH, drive: str = "square", zeta: float = 0.0,
               theta0: float = 0.1, dtheta0: float = 0.0, periods: float = 20.0, points_per_period: int = 60):
        """The motion from ``(theta0, dtheta0)`` at ``t = 0``, nonlinear and linear (the library's
        :func:`kapitza.simulate`), the pivot's height, and the stroboscopic points at ``t = 2kT``."""
        pair, _ = _motion(T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods, points_per_period)
        return _JSON(pair.as_dict())

    # -------------------------------------------------------------- exports
    @app.get("/api/export/chart.{fmt}", summary="the chart as kapitza chart writes it: PNG, SVG or its CSV",
             response_class=Response)
    def export_chart(fmt: Literal["png", "svg", "csv"], plane: Plane = "arnold",
                     eps_min: float = 0.0, eps_max: float = 4.0, mu_min: float = 0.0, mu_max: float = 1.0,
                     T_min: float = 0.0, T_max: float | None = None, A_min: float | None = None,
                     A_max: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                     zeta: float = 0.0, samples: int = 1000, T: float | None = None, A: float | None = None,
                     f_min: float | None = None, f_max: float | None = None, stroke_min: float | None = None,
                     stroke_max: float | None = None):
        """The figure of ``kapitza chart`` for this view (PNG or SVG) or the curves drawn (CSV),
        with the point ``(T, A)`` marked when given."""
        from ..figures._style import figure_bytes
        from ..figures.chart import chart_figure

        _bounded("samples", samples, LIMITS["samples"], 2)
        d = _drive(drive)
        zeta = _zeta(zeta)
        general, _ = _v.general_drive(d, zeta)
        _bounded("eps_max", eps_max, LIMITS["eps_max" if general is None else "general_eps_max"])
        mark = None
        if T is not None or A is not None:
            rep = analyze(T=T, A=A, l=l, g=g, drive=d, damping=_damping(zeta, l, g))
            mark = (rep, f"T = {T:g} s, A = {A:g} m/s$^2$")
        with _FIGURES:
            import matplotlib.pyplot as plt

            fig, curves, header = chart_figure(plane, (eps_min, eps_max), (mu_min, mu_max), (T_min, T_max),
                                               (A_min, A_max), l=l, g=g, drive=d, zeta=zeta,
                                               points=min(samples, 600) if plane == "rig" else samples, mark=mark,
                                               frequency_range=(f_min, f_max), stroke_range=(stroke_min, stroke_max))
            try:
                if fmt == "csv":
                    body = _io.csv_text(header, curves.rows(), comments=["exact zone edges drawn in kapitza-chart.png"])
                    return _file(body.encode(), "kapitza-chart.csv")
                return _file(figure_bytes(fig, fmt), f"kapitza-chart.{fmt}")
            finally:
                plt.close(fig)

    @app.get("/api/export/motion.{fmt}", summary="the motion as kapitza simulate writes it", response_class=Response)
    def export_motion(fmt: Literal["png", "svg", "csv", "json"], T: float | None = None, A: float | None = None,
                      eps: float | None = None, mu: float | None = None, l: float = 1.0, g: float = G_EARTH,
                      drive: str = "square", zeta: float = 0.0, theta0: float = 0.1, dtheta0: float = 0.0,
                      periods: float = 20.0, points_per_period: int = 60):
        """``kapitza simulate --out``'s files: the motion as CSV, its summary as JSON, the time
        series (nonlinear with the linear one) as PNG or SVG."""

        pair, d = _motion(T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods, points_per_period)
        if fmt == "csv":
            header, cols, comments = pair.table()
            return _file(_io.csv_text(header, zip(*cols), comments).encode(), "kapitza-motion.csv")
        if fmt == "json":
            tr = pair.motion
            rep = analyze(T=tr.T, A=tr.A, l=tr.l, g=tr.g, drive=d, damping=tr.c)
            return _file((json.dumps(_io.to_jsonable(pair.summary(rep)), indent=2) + "\n").encode(),
                         "kapitza-motion.json")
        from ..figures._style import figure_bytes
        from ..figures.motion import time_series_figure

        with _FIGURES:
            import matplotlib.pyplot as plt

            fig = time_series_figure(pair.motion, linear=pair.linear)
            try:
                return _file(figure_bytes(fig, fmt), f"kapitza-motion.{fmt}")
            finally:
                plt.close(fig)

    return app


_MEDIA = {"png": "image/png", "svg": "image/svg+xml", "csv": "text/csv", "json": "application/json"}
_FIGURES = threading.Lock()  # pyplot keeps global state: one figure at a time


def _file(body: bytes, name: str) -> Response:
    return Response(body, media_type=_MEDIA[name.rsplit(".", 1)[1]],
                    headers={"Content-Disposition": f'attachment; filename="{name}"'})


@functools.lru_cache(maxsize=128)
def _chart_json(plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples):
    """The JSON of ``/api/chart``; the last 128 views are kept (each at most a few 100 KiB), so a
    view many users open (the whole chart) is computed once."""
    from ..curves import edge_kinds, physical_window, physical_zone_curves, window_curves

    _bounded("samples", samples, LIMITS["samples"], 2)
    d = _drive(drive)
    zeta = _zeta(zeta)
    general, _ = _v.general_drive(d, zeta)
    cap = LIMITS["eps_max" if general is None else "general_eps_max"]
    if plane == "arnold":
        _bounded("eps_max", eps_max, cap)
        c = window_curves((eps_min, eps_max), (mu_min, mu_max), d, zeta, samples)
        y, lo, hi = c.mu, c.eps_lo, c.eps_hi
        view = dict(eps_min=eps_min, eps_max=eps_max, mu_min=mu_min, mu_max=mu_max)
    else:
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        (T_min, T_max), (A_min, A_max) = physical_window((T_min, T_max), (A_min, A_max), l, g, d)
        if np.isfinite(T_max) and np.isfinite(A_max) and A_max > 0:
            _bounded("T_max * sqrt(A_max / (8 l)) (the largest eps in view)",
                     float(T_max * np.sqrt(A_max / (8.0 * l))), cap)
        c = physical_zone_curves((T_min, T_max), (A_min, A_max), l, g, samples, d, zeta)
        y, lo, hi = c.A, c.T_lo, c.T_hi
        view = dict(T_min=T_min, T_max=T_max, A_min=A_min, A_max=A_max)
    zones = [dict(n=int(n), lower_edge=edge_kinds(n)[0], upper_edge=edge_kinds(n)[1], lo=_beyond(lo[i]),
                  hi=_beyond(hi[i]))
             for i, n in enumerate(c.n)]
    from ..rig_plane import stroke_coefficient

    return _json_bytes(dict(plane=plane, x="eps" if plane == "arnold" else "T", y="mu" if plane == "arnold" else "A",
                            view=view, l=l, g=g, drive=d.describe(), mu_max=d.mu_max, zeta=zeta, samples=int(np.size(y)), y_values=y,
                            zones=zones, stroke_coefficient=stroke_coefficient(d)))


def _report(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping):
    """The stability report of a point given as (eps, mu), (T, A) or a rig (frequency with stroke or
    amplitude), with ``rod`` for ``l`` and ``damping`` (c) for ``zeta``; and its drive."""
    from dataclasses import replace

    d = _drive(drive)
    pendulum = None
    if rod is not None:
        from ..system import Pendulum

        p = Pendulum.uniform_rod(rod, g=_v.one("g", _v.positive("g", g)))
        l, pendulum = p.l, p.describe()
    given = None
    if frequency is not None or stroke is not None or amplitude is not None:
        if T is not None or eps is not None or mu is not None:
            raise _v.KapitzaValueError("give a rig's frequency with stroke or amplitude (or A), without T, eps or mu")
        if frequency is None:
            raise _v.KapitzaValueError("stroke and amplitude go with frequency")
        T, A = (float(v) for v in d.from_rig(frequency, stroke=stroke, amplitude=amplitude, acceleration=A))
        given = "stroke" if stroke is not None else "amplitude" if amplitude is not None else "A"
    if damping is not None and zeta:
        raise _v.KapitzaValueError("give the damping as zeta or as damping (c), not both")
    if T is not None or A is not None:
        if eps is not None or mu is not None:
            raise _v.KapitzaValueError("give either T and A, or eps and mu, not both")
        c = _damping(zeta, l, g) if damping is None else _v.one("damping", _v.nonnegative("damping", damping))
        if damping is not None:  # the explorer's bound on the damping ratio
            from ..drives._api import zeta_of

            _zeta(float(zeta_of(c, _v.one("l", _v.positive("l", l)), _v.one("g", _v.positive("g", g)))))
        rep = analyze(T=T, A=A, l=l, g=g, drive=d, damping=c)
    else:
        if damping is not None:
            raise _v.KapitzaValueError("with eps and mu give the damping as zeta, not damping")
        rep = analyze(eps=eps, mu=mu, drive=d, zeta=_zeta(zeta))
    if given or pendulum:
        rep = replace(rep, given=given, pendulum=pendulum or rep.pendulum)
    return rep, d


def _safe_periods(periods, exact):
    """The periods of a safe tilt, bounded (far fewer where DOP853 follows the motion)."""
    if exact:
        return int(_bounded("periods", periods, LIMITS["periods"], 1))
    hi = LIMITS["safe_tilt_integrated_periods"]
    if not 1 <= periods <= hi:
        raise _v.KapitzaValueError(f"periods must satisfy 1 <= periods <= {hi} in the explorer for the sine drive or "
                                   f"damping (followed by DOP853); got {periods!r}")
    return int(periods)


def _point_of(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping):
    """A point as ``eps, mu, zeta`` (and ``T, A`` when physical) with its drive, validated as ``_report``."""
    from ..drives._api import zeta_of

    d = _drive(drive)
    if rod is not None:
        from ..system import Pendulum

        l = Pendulum.uniform_rod(rod).l
    given = None
    if frequency is not None or stroke is not None or amplitude is not None:
        if T is not None or eps is not None or mu is not None:
            raise _v.KapitzaValueError("give a rig's frequency with stroke or amplitude (or A), without T, eps or mu")
        if frequency is None:
            raise _v.KapitzaValueError("stroke and amplitude go with frequency")
        T, A = (float(v) for v in d.from_rig(frequency, stroke=stroke, amplitude=amplitude, acceleration=A))
        given = "stroke" if stroke is not None else "amplitude" if amplitude is not None else "A"
    if damping is not None and zeta:
        raise _v.KapitzaValueError("give the damping as zeta or as damping (c), not both")
    if T is not None or A is not None:
        if eps is not None or mu is not None:
            raise _v.KapitzaValueError("give either T and A, or eps and mu, not both")
        T = _v.one("T", _v.positive("T", T))
        A = _v.one("A", _v.positive("A", A))
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        from ..parameters import to_arnold

        eps, mu = (float(v) for v in to_arnold(T, A, l, g))
        z = _zeta(float(zeta_of(_v.one("damping", _v.nonnegative("damping", damping)), l, g))) if damping is not None \
            else _zeta(zeta)
    else:
        if damping is not None:
            raise _v.KapitzaValueError("with eps and mu give the damping as zeta, not damping")
        eps = _v.one("eps", _v.positive("eps", eps))
        mu = _v.one("mu", _v.positive("mu", mu))
        z = _zeta(zeta)
    return dict(eps=eps, mu=mu, T=T, A=A, zeta=z, drive=d, given=given)


def _docs_page(app):
    """``/docs``: Swagger UI from files served here (those of the ``fastapi-offline`` package, a Swagger
    UI that reads OpenAPI 3.1), so the API page works without a network; without the package a plain
    list of the routes from the schema."""
    from fastapi.responses import HTMLResponse

    try:
        import fastapi_offline

        assets = Path(fastapi_offline.__file__).with_name("static")
        if not (assets / "swagger-ui-bundle.js").is_file():  # pragma: no cover
            assets = None
    except ImportError:  # pragma: no cover - the web extra installs it
        assets = None
    if assets is not None:
        app.mount("/docs-assets", StaticFiles(directory=assets), name="docs-assets")

    @app.get("/docs", include_in_schema=False)
    def docs():
        if assets is not None:
            from fastapi.openapi.docs import get_swagger_ui_html

            return get_swagger_ui_html(openapi_url="/openapi.json", title="kapitza explorer: API",
                                       swagger_js_url="/docs-assets/swagger-ui-bundle.js",
                                       swagger_css_url="/docs-assets/swagger-ui.css",
                                       swagger_favicon_url="/docs-assets/favicon.png",
                                       swagger_ui_parameters={"validatorUrl": None})
        import html

        rows = "".join(f"<li><code>GET {html.escape(path)}</code>: {html.escape(ops.get('get', {}).get('summary', ''))}</li>"
                       for path, ops in app.openapi()["paths"].items())
        return HTMLResponse(f"<!doctype html><title>kapitza explorer: API</title><h1>kapitza explorer: API</h1>"
                            f"<p>The schema: <a href='/openapi.json'>/openapi.json</a></p><ul>{rows}</ul>")


@functools.lru_cache(maxsize=64)
def _rig_chart_json(f_min, f_max, stroke_min, stroke_max, l, g, drive, zeta, samples):
    """The JSON of ``/api/chart?plane=rig``: zone ``n`` is ``lo < frequency < hi`` at each stroke ``y``."""
    from ..curves import edge_kinds
    from ..rig_plane import rig_zone_curves, stroke_coefficient

    _bounded("samples", samples, LIMITS["samples"], 2)
    d = _drive(drive)
    zeta = _zeta(zeta)
    general, _ = _v.general_drive(d, zeta)
    c = rig_zone_curves((f_min, f_max), (stroke_min, stroke_max), l, g, d, zeta,
                        points=min(samples, 400 if general is None else 160))
    zones = [dict(n=int(n), lower_edge=edge_kinds(n)[0], upper_edge=edge_kinds(n)[1], lo=_beyond(c.f_lo[i]),
                  hi=_beyond(c.f_hi[i])) for i, n in enumerate(c.n)]
    (f0, f1), (s0, s1) = c.frequency_range, c.stroke_range
    return _json_bytes(dict(plane="rig", x="frequency", y="stroke", view=dict(f_min=f0, f_max=f1, stroke_min=s0,
                                                                              stroke_max=s1),
                            l=c.l, g=c.g, drive=d.describe(), mu_max=d.mu_max, zeta=zeta,
                            stroke_coefficient=stroke_coefficient(d), samples=int(c.stroke.size),
                            y_values=c.stroke, zones=zones))


def _motion(T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods, points_per_period):
    """The bounded motion pair and its drive."""
    from ..motion import motion_pair

    T, A = _physical_point(T, A, eps, mu, l, g)
    _bounded("periods", periods, LIMITS["periods"])
    _bounded("points_per_period", points_per_period, LIMITS["points_per_period"])
    _bounded("|theta0|", abs(theta0), LIMITS["theta0"])
    _bounded("periods * points_per_period", periods * points_per_period, LIMITS["motion_samples"])
    d = _drive(drive)
    c = _damping(zeta, l, g)
    pair = motion_pair(theta0, dtheta0, T, A, l, g, periods=periods, points_per_period=points_per_period, c=c, drive=d)
    return pair, d
