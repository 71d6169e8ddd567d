"""The explorer's ASGI application: a JSON API over the library and the page that draws it.

Each route parses its query, makes one call into the library and returns JSON (or a file).
Bad input is the library's own :class:`kapitza.KapitzaValueError`, answered with status 422
and ``{"detail": message}``; the sizes a request may ask for (samples, periods, the span of
a view) are bounded here, with the same kind of message, so no request computes for minutes.

Work is done in worker threads (one per CPU). A request whose client has gone is not started,
and a chart of another drive or of damping (an eigenproblem per edge and sample) stops between
blocks of samples when its client goes or when it has used ``LIMITS["chart_cpu_seconds"]`` of
CPU time (then a 422 says so). Only requests whose ``Host`` names this machine's loopback, or
the name the server was started with, are answered (a web page cannot reach the explorer by
DNS rebinding). See ``docs/robustness.md``.
"""
from __future__ import annotations

import collections
import contextlib
import functools
import json
import os
import threading
import time
from pathlib import Path
from typing import Any, Literal

import numpy as np
import orjson
from fastapi import FastAPI, Query, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles

from .. import __version__, _io
from .server import HOSTS_ENV
from .. import _validate as _v
from ..analysis import analyze
from ..drives import DRIVES, parse_drive, text_forms
from ..drives._api import damping_of
from ..engines import load_compiled
from ..parameters import G_EARTH, to_physical

__all__ = ["create_app", "LIMITS", "drives_answer", "drive_answer", "chart_answer", "point_answer", "verdict_answer",
           "safe_tilt_answer",
           "motion_answer", "tower_chart_answer", "tower_point_answer", "tower_motion_answer", "error_detail",
           "json_bytes"]

STATIC = Path(__file__).with_name("static")

#: What one request may ask for.
LIMITS: dict[str, Any] = dict(
    samples=4000,          # mu (or A) samples per edge of a chart, refinement included
    general_samples=400,   # ... with another drive or damping (each an eigenproblem per edge)
    export_samples=1000,   # samples asked of a chart export (the figure refines up to 4 times as many)
    chart_cpu_seconds=60.0,  # CPU seconds one chart of another drive or damping may use
    cache_bytes=64 << 20,  # the JSON of recent views kept
    eps_max=60.0,          # the largest eps a view of Arnold's plane may reach
    general_eps_max=12.0,  # ... with another drive or damping (each edge a Floquet eigenproblem)
    general_point_eps=1000.0,  # the largest eps of a point's report or safe tilt with a drive whose periods are
                               # integrated (about eps steps each: the triangle, linear samples, a user's shape)
    own_point_eps=20.0,    # ... with a drive of its own Floquet data whose cost grows with eps (the sine: a
                           # report's certified steps form exact traces beside its thin zones, 3 s at eps 20)
    periods=200.0,         # drive periods 2T of a motion
    points_per_period=200,
    motion_samples=20000,  # periods * points_per_period
    theta0=3.15,           # |theta0| <= about pi: a tilt from the upright
    zeta=10.0,             # damping ratio (10: far beyond critical damping)
    drive_text=200,        # characters of a drive's text form
    url=4096,              # characters of a request's path and query
    safe_tilt_integrated_periods=60,  # periods of a safe tilt followed by DOP853 (sine drive or damping)
    chain_links=4,         # links of a tower
    chain_length=(0.01, 10.0),  # [m] each link's length
    chain_mass=(0.001, 1000.0),  # [kg] each link's mass
    tower_grid=200,        # grid points per axis of a tower's band (square and rectangular waves)
    tower_general_grid=80,  # ... with another drive (each grid point an eigenproblem per mode)
    tower_points=600,      # samples per mode edge of a tower's band
    tower_general_points=200,
    tower_frequency=(1e-3, 1e6),  # [Hz] the rig plane's frequency window
    tower_stroke=(1e-6, 100.0),   # [m] ... and its stroke window
    tower_periods=600.0,   # drive periods 2T of a tower's motion (DOP853 with N links)
    chain_friction_rate=1e3,  # [1/s] the fastest decay rate of joint friction (largest eigenvalue of M^-1 C):
                              # the motion's DOP853 steps grow with it
    tower_friction_grid=60,   # grid points per axis of a damped tower's band (each point a 2N monodromy)
    tower_friction_general_grid=24,  # ... with a smooth drive (each point an integrated period)
)

Plane = Literal["arnold", "physical", "rig"]

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1")


# ------------------------------------------------------------------ JSON
def _json_bytes(obj) -> bytes:
    """JSON of ``obj``, numpy arrays included (orjson: exact shortest round-trip floats; NaN as null)."""
    try:
        return orjson.dumps(obj, default=_default, option=orjson.OPT_SERIALIZE_NUMPY)
    except TypeError:  # an integer beyond 64 bits (the turns of a run-away linear motion)
        return json.dumps(_io.to_jsonable(obj), default=_default, separators=(",", ":")).encode()


def json_bytes(obj) -> bytes:
    """The JSON text the routes send for ``obj`` (numpy arrays included, NaN as null)."""
    return _json_bytes(obj)


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
    return _parsed_drive(drive)


@functools.lru_cache(maxsize=64)
def _parsed_drive(text: str):
    """The drive of ``text``, built once: drives are immutable (their derived tables cached on them),
    and building one costs a few tenths of a millisecond of every request naming it."""
    return parse_drive(text)


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


def allowed_hosts(extra=None) -> frozenset:
    """The host names the explorer answers to: the loopback names and those of ``HOSTS_ENV``."""
    names = os.environ.get(HOSTS_ENV, "") if extra is None else ",".join(extra)
    return frozenset(LOOPBACK_NAMES) | {h.strip().lower().strip("[]") for h in names.split(",") if h.strip()}


def host_name(header: bytes) -> str:
    """The name of a ``Host`` header without its port (``[::1]:8000`` -> ``::1``), lower case."""
    text = header.decode("latin-1").strip().lower()
    if text.startswith("["):  # an IPv6 literal
        return text[1:text.find("]")] if "]" in text else text
    return text.rsplit(":", 1)[0] if text.count(":") == 1 else text


class _BoundedRequests:
    """Refuse a ``Host`` the explorer does not serve (421), a path and query longer than
    ``LIMITS['url']`` (414) and any request body (413)."""

    def __init__(self, app, hosts=None):
        self.app = app
        self.hosts = allowed_hosts() if hosts is None else frozenset(hosts)

    async def __call__(self, scope, receive, send):
        if scope["type"] == "http":
            size = len(scope.get("raw_path") or b"") + len(scope.get("query_string") or b"")
            headers = dict(scope.get("headers") or ())
            body = headers.get(b"content-length", b"0")
            host = host_name(headers.get(b"host", b""))
            status, detail = None, None
            if host not in self.hosts:
                # DNS rebinding: a page of another site, its name pointed at this machine
                status, detail = 421, (f"this explorer answers to {', '.join(sorted(self.hosts))}, not to the "
                                       f"host {host[:100]!r} (start it with --host NAME to serve another name)")
            elif size > LIMITS["url"]:
                status, detail = 414, f"request path and query must be at most {LIMITS['url']} characters"
            elif body.strip() not in (b"", b"0") or b"transfer-encoding" in headers:
                status, detail = 413, "the explorer takes no request bodies"
            if status:
                return await _JSON(status_code=status, content={"detail": detail})(scope, receive, send)
        return await self.app(scope, receive, send)


# ------------------------------------------------------------------ the answers
# What the routes answer, as plain functions of the same parameters (no request): the notebook
# explorer (kapitza.widgets) calls them for the same JSON without a server.
def drives_answer() -> dict:
    """What ``/api/drives`` answers: the registered drives (:data:`kapitza.drives.DRIVES`, a user's
    own class included), in the registry's order, the first the default.

    Each has its ``name``, ``title`` (what a menu calls it), ``text_form`` and ``parameters`` (the
    class's description of the numbers of ``NAME:VALUE``, or None where no list of numbers describes
    them). ``page`` says whether the explorer's page offers it: a drive with at most one number whose
    ``default`` (``NAME`` or ``NAME:DEFAULT``) the registry reads back; ``default`` is that text and
    ``examples`` the texts (with their legends' labels) the page lists as overlays."""
    drives = []
    for key, cls in DRIVES.items():
        params = cls.parameters
        entry = dict(name=key, title=cls.title or key, text_form=cls.text_form or key,
                     parameters=None if params is None else [_io.to_jsonable(dict(p)) for p in params],
                     page=False, default=None, label=None, examples=[])
        if params is not None and len(params) <= 1:
            try:
                text = key + "".join(f":{p['default']!r}" for p in params)
                d = parse_drive(text)
            except (ValueError, TypeError, KeyError):  # a class whose parameters the form cannot give
                d = None
            if d is not None:
                values = [(f"{key}:{v!r}", v) for v in params[0].get("examples", ())] if params else []
                examples = []
                for t, _ in values or [(text, None)]:
                    try:
                        examples.append(dict(text=t, label=parse_drive(t).label))
                    except (ValueError, TypeError):
                        pass
                entry.update(page=True, default=text, label=d.label, examples=examples)
        drives.append(entry)
    return dict(drives=drives, default=next(iter(DRIVES)), text_forms=text_forms())


def drive_answer(drive="square", zeta=0.0) -> dict:
    """What ``/api/drive`` answers: what the page needs to know of one drive (its text form) at the
    damping ratio ``zeta``: ``label``, ``mu_max`` (at and above it the upright always falls), ``peak``
    (the largest ``|a| / A``), ``stroke_coefficient`` (``k`` in stroke = k A T^2), ``closed_form``
    (whether its edges are closed forms here: a chart may ask more samples) and ``exact_motion``
    (whether a motion is followed by exact step flows rather than DOP853: a safe tilt may take more
    periods)."""
    from ..motion.basins import exact_path
    from ..rig_plane import stroke_coefficient

    d = _drive(drive)
    z = _zeta(zeta)
    return dict(drive=drive, label=d.label, describe=d.describe(), mu_max=d.mu_max, peak=float(d.peak),
                stroke_coefficient=float(stroke_coefficient(d)), closed_form=bool(d.closed_form(z)),
                exact_motion=bool(exact_path(d, z)), zeta=z)


def chart_answer(plane="arnold", eps_min=0.0, eps_max=4.0, mu_min=0.0, mu_max=1.0, T_min=0.0, T_max=None, A_min=None,
                 A_max=None, l=1.0, g=G_EARTH, drive="square", zeta=0.0, samples=None, f_min=None, f_max=None,
                 stroke_min=None, stroke_max=None, check=None) -> bytes:
    """The JSON body of ``/api/chart`` (bytes)."""
    if plane == "rig":
        return _rig_chart_json(f_min, f_max, stroke_min, stroke_max, l, g, drive, zeta, samples)
    if plane not in ("arnold", "physical"):
        raise _v.KapitzaValueError(f"plane must be one of 'arnold', 'physical', 'rig'; got {plane!r}")
    return _chart_json(plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples,
                       check)


def point_answer(eps=None, mu=None, T=None, A=None, l=1.0, g=G_EARTH, drive="square", zeta=0.0, frequency=None,
                 stroke=None, amplitude=None, rod=None, damping=None, safe_tilt=False, periods=50) -> dict:
    """What ``/api/point`` answers: the report as ``kapitza stability --json`` prints it, with ``lines``."""
    rep, d = _report(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
    if safe_tilt:
        from ..motion.basins import exact_path
        from ..safety import with_safe_tilt

        rep = with_safe_tilt(rep, d, _safe_periods(periods, exact_path(d, rep.zeta)))
    return _io.to_jsonable({**rep.as_dict(), "lines": rep.lines()})


def verdict_answer(eps=None, mu=None, T=None, A=None, l=1.0, g=G_EARTH, drive="square", zeta=0.0, frequency=None,
                   stroke=None, amplitude=None, rod=None, damping=None) -> dict:
    """What ``/api/verdict`` answers: stable or not, the zone and the kind of instability."""
    from ..propagation import floquet

    P = _point_of(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
    f = floquet(P["eps"], P["mu"], drive=P["drive"], zeta=P["zeta"])
    stable = bool(f.stable)
    if stable:
        kind, text = "stable", f"stable (zone {int(f.zone)})" + (", motions decay" if P["zeta"] > 0 else "")
    elif P["mu"] >= P["drive"].mu_max:
        kind, text = "weak", "always unstable: the pivot never accelerates down faster than g"
    elif float(f.trace) < 0:
        kind, text = "4T", "unstable: parametric resonance, 4T-type, period doubling"
    else:
        kind, text = "2T", "unstable: it falls (multipliers real, positive)"
    return dict(eps=P["eps"], mu=P["mu"], T=P["T"], A=P["A"], zeta=P["zeta"], stable=stable,
                zone=int(f.zone) if stable else -1, kind=kind, verdict=text, growth=float(f.growth),
                trace=float(f.trace), given=P["given"])


def safe_tilt_answer(eps=None, mu=None, T=None, A=None, l=1.0, g=G_EARTH, drive="square", zeta=0.0, frequency=None,
                     stroke=None, amplitude=None, rod=None, damping=None, periods=50) -> dict:
    """What ``/api/safe_tilt`` answers: the safe tilt with its verdict and sentence."""
    from ..motion.basins import exact_path
    from ..safety import safe_tilt, safe_tilt_sentence
    from ..zones import is_stable

    P = _point_of(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
    _point_reach(P)
    n = _safe_periods(periods, exact_path(P["drive"], P["zeta"]))
    d = P["drive"]
    stable = bool(is_stable(P["eps"], P["mu"], drive=d, zeta=P["zeta"]))
    theta = float(safe_tilt(P["eps"], P["mu"], drive=P["drive"], zeta=P["zeta"], periods=n)) if stable else 0.0
    return dict(safe_tilt=theta, periods=n, stable=stable, eps=P["eps"], mu=P["mu"],
                text=safe_tilt_sentence(theta, n, stable))


def motion_answer(T=None, A=None, eps=None, mu=None, l=1.0, g=G_EARTH, drive="square", zeta=0.0, theta0=0.1,
                  dtheta0=0.0, periods=20.0, points_per_period=60) -> dict:
    """What ``/api/motion`` answers: the motion pair, sampled for animation."""
    return _motion(T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods, points_per_period)[0].as_dict()


def error_detail(exc: BaseException) -> str | None:
    """The one-line ``detail`` of a 422 for a user's error (None: not a user's error)."""
    if isinstance(exc, _v.KapitzaValueError):
        return str(exc).splitlines()[0]
    if isinstance(exc, OverflowError):
        return f"the result exceeds a double: {exc}"
    return None


# ------------------------------------------------------------------ the app
def _iterable(value):
    try:
        return list(value)
    except TypeError:
        return [value]


#: Imported at the server's start (see ``lifespan`` in :func:`create_app`), not by each route's first
#: call: every module a route imports where it is first needed (``tests/test_web_api.py`` checks the list)
_ROUTE_MODULES = ("kapitza.motion", "kapitza.motion.basins", "kapitza.motion.pair", "kapitza.motion.chain",
                  "kapitza.safety", "kapitza.propagation", "kapitza.zones", "kapitza.curves", "kapitza.rig_plane",
                  "kapitza.system", "kapitza.chain", "kapitza.figures._style", "kapitza.figures.chart",
                  "kapitza.figures.motion")


def create_app(hosts=None) -> FastAPI:
    """The explorer: the page at ``/``, the JSON API under ``/api``, its schema at ``/openapi.json``.

    ``hosts``: the names it answers to (default :func:`allowed_hosts`: loopback and ``HOSTS_ENV``).

    Parameters
    ----------
    hosts : sequence of str, optional

    Returns
    -------
    fastapi.FastAPI

    Raises
    ------
    KapitzaValueError
        If ``hosts`` is a single string or holds something other than strings.

    Examples
    --------
    >>> from kapitza.web import create_app
    >>> app = create_app()
    >>> for path in sorted({route.path for route in app.routes if route.path.startswith("/api/")}):
    ...     print(path)
    /api/chart
    /api/drive
    /api/drives
    /api/export/chart.{fmt}
    /api/export/motion.{fmt}
    /api/motion
    /api/point
    /api/safe_tilt
    /api/tower/chart
    /api/tower/motion
    /api/tower/point
    /api/verdict
    """
    if hosts is not None:
        if isinstance(hosts, (str, bytes)) or not all(isinstance(h, str) for h in _iterable(hosts)):
            raise _v.KapitzaValueError(f"hosts must be a sequence of host names (str); got {_v._short(hosts)}")
        hosts = list(hosts)

    @contextlib.asynccontextmanager
    async def lifespan(app):
        # The routes compute with numpy: more threads than CPUs only take turns at the GIL, and
        # ten requests at once then all finish late. One thread per CPU keeps them in a queue.
        import importlib

        import anyio.to_thread

        anyio.to_thread.current_default_thread_limiter().total_tokens = max(2, _v.cpus())
        # The modules the routes import where they are first needed are imported here, once, before
        # any request: two first requests in two threads (a page's first load asks the motion and
        # the safe tilt at once) would otherwise import one package together, and the second can
        # find it half made (an ImportError, a route that never answers)
        for name in _ROUTE_MODULES:
            importlib.import_module(name)
        # a server answers many small questions: the generic engine's compiled loop, loaded once
        # here, serves them all (a command of one report runs without it)
        load_compiled()
        yield

    app = FastAPI(title="kapitza explorer", version=__version__, lifespan=lifespan, docs_url=None, redoc_url=None,
                  description="Exact stability zones and motions of the inverted pendulum on a vibrating pivot. "
                              "Parameters use the library's names: eps, mu (Arnold), T [s], A [m/s^2], l [m], "
                              f"g [m/s^2], drive ({', '.join(repr(f) for f in text_forms())}: /api/drives), "
                              "zeta (damping ratio).")

    @app.exception_handler(_v.KapitzaValueError)
    async def _value_error(request: Request, exc: _v.KapitzaValueError):
        return _JSON(status_code=422, content={"detail": error_detail(exc)})

    @app.exception_handler(_Cancelled)
    async def _gone(request: Request, exc: _Cancelled):
        return Response(status_code=499)  # the client closed the connection; nobody reads this

    @app.exception_handler(OverflowError)
    async def _overflow(request: Request, exc: OverflowError):
        return _JSON(status_code=422, content={"detail": error_detail(exc)})

    @app.exception_handler(RequestValidationError)
    async def _bad_query(request: Request, exc: RequestValidationError):
        parts = []
        for e in exc.errors():
            name = ".".join(str(x) for x in e.get("loc", ())[1:]) or "request"
            got = e.get("input")
            parts.append(f"{name}: {e.get('msg', 'invalid')}" + (f"; got {got!r}" if got is not None else ""))
        return _JSON(status_code=422, content={"detail": "; ".join(parts)})

    app.add_middleware(_BoundedRequests, hosts=hosts)
    app.openapi = functools.partial(_openapi, app)  # type: ignore[method-assign]

    @app.get("/", include_in_schema=False)
    def index():
        return FileResponse(STATIC / "index.html", media_type="text/html")

    app.mount("/static", StaticFiles(directory=STATIC), name="static")
    _docs_page(app)

    # -------------------------------------------------------------- drives
    @app.get("/api/drives", response_class=_JSON, summary="the drives the explorer knows (the registry)")
    def drives():
        """The registered drives (``kapitza.drives.DRIVES``, with any a user registered before the
        app was made): ``name``, ``title``, ``text_form``, ``parameters`` (each number's ``name``,
        ``min`` and ``max`` (open ends), ``default``, ``examples``), ``page`` (whether the page's lists
        offer it), ``default`` (its text at the default parameters) and ``examples`` (texts with
        their labels, the overlay list)."""
        return _JSON(drives_answer())

    @app.get("/api/drive", response_class=_JSON, summary="one drive's numbers the page uses")
    def drive_route(drive: str = "square", zeta: float = 0.0):
        """For a drive's text form at damping ratio ``zeta``: ``label``, ``mu_max``, ``peak``,
        ``stroke_coefficient`` (stroke = k A T^2), ``closed_form`` (edges from closed forms: the
        square wave undamped) and ``exact_motion`` (motions by exact step flows: an undamped
        piecewise-constant drive)."""
        return _JSON(drive_answer(drive, zeta))

    # -------------------------------------------------------------- chart
    @app.get("/api/chart", response_class=_JSON, summary="exact edges of every zone in a view")
    async def chart(request: Request, plane: Plane = "arnold",
                    eps_min: float = 0.0, eps_max: float = 4.0, mu_min: float = 0.0, mu_max: float = 1.0,
                    T_min: float = 0.0, T_max: float | None = None, A_min: float | None = None,
                    A_max: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                    zeta: float = 0.0,
                    samples: int | None = Query(None, description="samples per edge, refinement included (default "
                                                                  "1000, at most 4000; with another drive or damping "
                                                                  "default 300, at most 400)"),
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
            key: tuple = ("rig", f_min, f_max, stroke_min, stroke_max, l, g, drive, zeta, samples)
            body = _VIEWS.get(key)
            if body is None:
                body = await _worker(request, lambda *a: _rig_chart_json(*a[:-1]), *key[1:])
                _VIEWS.put(key, body)
            return Response(body, media_type="application/json")
        key = (plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples)
        body = _VIEWS.get(key)
        if body is None:
            body = await _worker(request, _chart_json, *key)
            _VIEWS.put(key, body)
        return Response(body, media_type="application/json")

    # -------------------------------------------------------------- point
    @app.get("/api/point", response_class=_JSON, summary="the stability report at one parameter set")
    async def point(request: Request, eps: float | None = None, mu: float | None = None, T: float | None = None,
                    A: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                    zeta: float = 0.0,
                    frequency: float | None = Query(None, description="drive frequency [Hz], with stroke or amplitude"),
                    stroke: float | None = Query(None, description="peak-to-peak travel of the pivot [m]"),
                    amplitude: float | None = Query(None, description="displacement amplitude, half the stroke [m]"),
                    rod: float | None = Query(None, description="a uniform rod of this length [m] (l = 2/3 of it)"),
                    damping: float | None = Query(None, description="viscous damping c [1/s], instead of zeta"),
                    safe_tilt: bool = Query(False,
                                            description="also the safe tilt (follows the real pendulum: slower)"),
                    periods: int = Query(50, description="periods of the safe tilt (at most 200)")):
        """What ``kapitza stability --json`` prints (the same keys and numbers), with ``lines``: the
        table's rows and ``directions``: which knob to turn which way. Given ``T`` and ``A`` (or a rig's
        ``frequency`` with ``stroke`` or ``amplitude``, and ``rod`` for ``l``) the damping ratio ``zeta``
        becomes ``c = 2 zeta sqrt(g/l)``, or give ``damping`` (c) itself. ``safe_tilt=true`` adds the
        safe tilt [rad] (``kapitza.safe_tilt``), which is slower than the verdict: the page asks for
        it in a second request."""
        return await _worker(request, _point, eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod,
                             damping, safe_tilt, periods)

    def _point(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping, safe_tilt, periods, check):
        return _JSON(point_answer(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping,
                                  safe_tilt, periods))

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
        return _JSON(verdict_answer(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping))

    @app.get("/api/safe_tilt", response_class=_JSON, summary="the largest starting tilt the real pendulum survives")
    def safe_tilt_route(eps: float | None = None, mu: float | None = None, T: float | None = None,
                        A: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                        zeta: float = 0.0, frequency: float | None = None, stroke: float | None = None,
                        amplitude: float | None = None, rod: float | None = None, damping: float | None = None,
                        periods: int = 50):
        """``safe_tilt`` [rad]: the largest starting tilt from rest whose motion stays above the horizontal
        for ``periods`` periods 2T (``kapitza.safe_tilt``; 0 where the upright is not stable), with the
        verdict it goes with and ``text``, the report's sentence."""
        return _JSON(safe_tilt_answer(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping,
                                      periods))

    # -------------------------------------------------------------- motion
    @app.get("/api/motion", response_class=_JSON, summary="linear and nonlinear motion, sampled for animation")
    async def motion(request: Request, T: float | None = None, A: float | None = None, eps: float | None = None,
                     mu: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                     zeta: float = 0.0, theta0: float = 0.1, dtheta0: float = 0.0, periods: float = 20.0,
                     points_per_period: int = 60):
        """The motion from ``(theta0, dtheta0)`` at ``t = 0``, nonlinear and linear (the library's
        :func:`kapitza.simulate`), the pivot's height, and the stroboscopic points at ``t = 2kT``."""
        # kept with the views: a class opening the same point (the first view's) is answered once
        key = ("motion", T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods, points_per_period)
        body = _VIEWS.get(key)
        if body is None:
            body = await _worker(request, lambda check: _JSON(motion_answer(*key[1:])).body)
            _VIEWS.put(key, body)
        return Response(body, media_type="application/json")

    # -------------------------------------------------------------- the tower
    chain_q = Query("0.2,0.2,0.2", description="link lengths [m] from the pivot up, comma-separated: 1 to 4 links, "
                                              "each 0.01 .. 10 m")
    masses_q = Query(None, description="link masses [kg], comma-separated, one per link (default: equal)")
    links_q = Query("rod", description="rod: uniform rods; point: point masses on massless rods")
    friction_q = Query(0.0, description="viscous friction c at every joint, the pivot included [N m s/rad] "
                                        "(0: none; its fastest decay rate at most 1000 1/s)")

    @app.get("/api/tower/chart", response_class=_JSON, summary="the tower's stable band on the rig plane")
    async def tower_chart(request: Request, chain: str = chain_q, masses: str | None = masses_q,
                          links: Literal["rod", "point"] = links_q, drive: str = "square", g: float = G_EARTH,
                          f_min: float | None = Query(None, description="lowest frequency [Hz] (default: the tower's "
                                                                        "whole band)"),
                          f_max: float | None = None,
                          stroke_min: float | None = Query(None, description="smallest stroke, peak to peak [m]"),
                          stroke_max: float | None = None,
                          grid: int | None = Query(None, description="grid points per axis of the band (default 120, "
                                                                     "at most 200; sine: 50, at most 80)"),
                          points: int | None = Query(None, description="samples per mode edge (default 300, at most "
                                                                       "600; sine: 120, at most 200)"),
                          joint_damping: float = friction_q):
        """The tower of linked pendulums (``kapitza.tower_curves``): each mode ``k`` (equivalent length
        ``l``) has a lower edge of zone 0 (below it in frequency the mode falls) and an upper one (beyond
        it the mode doubles its period), as ``frequency`` and ``stroke`` along the edge; ``band`` is the
        tower's verdict on a grid (``stable[i][j]`` at ``stroke[i]``, ``frequency[j]``; 1: every mode
        stable). Without a window, the tower's whole band. With ``joint_damping`` the modes couple: the
        band is the full ``2N`` monodromy's verdict on a coarser grid (default and at most 60; a smooth
        drive: 20, at most 24), the edges drawn the frictionless modes'."""
        return Response(await _worker(request, lambda *a: _tower_chart_json(*a[:-1]), chain, masses, links, drive, g,
                                      f_min, f_max, stroke_min, stroke_max, grid, points, joint_damping),
                        media_type="application/json")

    @app.get("/api/tower/point", response_class=_JSON, summary="the tower's verdict and report at one point")
    async def tower_point(request: Request, chain: str = chain_q, masses: str | None = masses_q,
                          links: Literal["rod", "point"] = links_q, drive: str = "square", g: float = G_EARTH,
                          T: float | None = None, A: float | None = None,
                          frequency: float | None = Query(None, description="drive frequency [Hz], with stroke or "
                                                                            "amplitude"),
                          stroke: float | None = Query(None, description="peak-to-peak travel of the pivot [m]"),
                          amplitude: float | None = Query(None, description="displacement amplitude [m]"),
                          joint_damping: float = friction_q):
        """What ``kapitza tower --json`` gives as ``report`` (``kapitza.analyze_chain``): ``stable``, the
        ``verdict`` (which mode fails first and how), the modal lengths, each mode's zone and margin,
        the band through the point; with ``lines``, the rows of its table."""
        return await _worker(request, lambda check: _JSON(tower_point_answer(chain, masses, links, drive, g, T, A,
                                                                             frequency, stroke, amplitude,
                                                                             joint_damping)))

    @app.get("/api/tower/motion", response_class=_JSON, summary="the tower's full motion, sampled for animation")
    async def tower_motion(request: Request, chain: str = chain_q, masses: str | None = masses_q,
                           links: Literal["rod", "point"] = links_q, drive: str = "square", g: float = G_EARTH,
                           T: float | None = None, A: float | None = None, frequency: float | None = None,
                           stroke: float | None = None, amplitude: float | None = None,
                           theta0: float = Query(0.1, description="starting tilt of every link, at rest [rad]"),
                           periods: float | None = Query(None, description="drive periods 2T (default: about 1.5 s, "
                                                                           "at most 600)"),
                           points_per_period: int | None = None, joint_damping: float = friction_q):
        """The nonlinear motion of the tower (``kapitza.chain_motion``) from every link tilted by
        ``theta0``: ``theta[k]`` the angle of link ``k+1`` from the upright [rad] at the times ``t``,
        ``pivot`` the pivot's height [m]; ``toppled`` and ``t_topple`` when a link passed pi/2."""
        return await _worker(request, lambda check: _JSON(tower_motion_answer(
            chain, masses, links, drive, g, T, A, frequency, stroke, amplitude, theta0, periods, points_per_period,
            joint_damping)))

    # -------------------------------------------------------------- exports
    @app.get("/api/export/chart.{fmt}", summary="the chart as kapitza chart writes it: PNG, SVG or its CSV",
             response_class=Response)
    async def export_chart(request: Request, fmt: Literal["png", "svg", "csv"], plane: Plane = "arnold",
                           eps_min: float = 0.0, eps_max: float = 4.0, mu_min: float = 0.0, mu_max: float = 1.0,
                           T_min: float = 0.0, T_max: float | None = None, A_min: float | None = None,
                           A_max: float | None = None, l: float = 1.0, g: float = G_EARTH, drive: str = "square",
                           zeta: float = 0.0, samples: int | None = None, T: float | None = None,
                           A: float | None = None,
                           f_min: float | None = None, f_max: float | None = None, stroke_min: float | None = None,
                           stroke_max: float | None = None):
        """The figure of ``kapitza chart`` for this view (PNG or SVG) or the curves drawn (CSV),
        with the point ``(T, A)`` marked when given."""
        return await _worker(request, _export_chart, fmt, plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max,
                             A_min, A_max, l, g, drive, zeta, samples, T, A, f_min, f_max, stroke_min, stroke_max)

    def _export_chart(fmt, plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g, drive, zeta,
                      samples, T, A, f_min, f_max, stroke_min, stroke_max, check):
        from ..figures._style import figure_bytes
        from ..figures.chart import chart_figure

        if plane == "rig":  # the rig plane's own bounds (its figure draws at most 600 samples per edge)
            d, zeta = _drive(drive), _zeta(zeta)
            samples = 300 if samples is None else samples
            _bounded("samples", samples, LIMITS["samples"], 2)
            general = d
        else:
            d, zeta, general, samples, (T_min, T_max), (A_min, A_max), l, g = _view(
                plane, eps_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples)
        if plane == "rig":
            pass
        elif general is None:  # the figure's refinement takes up to 4 x samples: at most LIMITS["samples"]
            _bounded("samples", samples, LIMITS["export_samples"], 2)
        else:
            # the figure computes its curves in one call: first make sure they fit the CPU budget
            _chart_json(plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g, drive, zeta,
                        samples, check)
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
    async def export_motion(request: Request, fmt: Literal["png", "svg", "csv", "json"], T: float | None = None,
                            A: float | None = None, eps: float | None = None, mu: float | None = None, l: float = 1.0,
                            g: float = G_EARTH, drive: str = "square", zeta: float = 0.0, theta0: float = 0.1,
                            dtheta0: float = 0.0, periods: float = 20.0, points_per_period: int = 60):
        """``kapitza simulate --out``'s files: the motion as CSV, its summary as JSON, the time
        series (nonlinear with the linear one) as PNG or SVG."""
        return await _worker(request, _export_motion, fmt, T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods,
                             points_per_period)

    def _export_motion(fmt, T, A, eps, mu, l, g, drive, zeta, theta0, dtheta0, periods, points_per_period, check):
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


class _Cancelled(Exception):
    """The client went away: the work stops and nobody is answered."""


class _ViewCache:
    """The JSON of the views most recently asked for, least recently used dropped first, bounded
    by its size in bytes (``LIMITS["cache_bytes"]``), not by a count: a view many users open
    (the whole chart) is computed once, and no mix of large views can grow the server."""

    def __init__(self):
        self._items = collections.OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()

    def get(self, key):
        with self._lock:
            body = self._items.get(key)
            if body is not None:
                self._items.move_to_end(key)
            return body

    def put(self, key, body: bytes):
        limit = LIMITS["cache_bytes"]
        if len(body) > limit // 8:  # one view may not push out most of the others
            return
        with self._lock:
            if key in self._items:
                return
            self._items[key] = body
            self._bytes += len(body)
            while self._bytes > limit:
                _, old = self._items.popitem(last=False)
                self._bytes -= len(old)

    @property
    def nbytes(self) -> int:
        return self._bytes


_VIEWS = _ViewCache()


async def _worker(request: Request, fn, *args):
    """``fn(*args, check)`` in a worker thread. ``check()`` raises :class:`_Cancelled` once the
    client has gone; a request whose client left while it waited for a thread is not started."""
    import anyio

    gone = threading.Event()

    def check():
        if gone.is_set():
            raise _Cancelled

    async def watch():
        while not await request.is_disconnected():
            await anyio.sleep(0.25)
        gone.set()

    def run():
        check()  # the client left while the request waited for a thread: nothing to do
        try:
            return fn(*args, check), None
        except Exception as exc:  # noqa: BLE001 - raised below, outside the task group
            return None, exc

    if await request.is_disconnected():
        raise _Cancelled
    async with anyio.create_task_group() as tasks:
        tasks.start_soon(watch)
        try:
            result, error = await anyio.to_thread.run_sync(run)
        finally:
            tasks.cancel_scope.cancel()
    if error is not None:
        raise error
    return result


class _Budget:
    """A check for :func:`kapitza.curves.window_curves`: the client still there, and the CPU time of
    this thread within ``LIMITS["chart_cpu_seconds"]`` (CPU, not wall time: a loaded machine does
    not shrink what a view may compute)."""

    def __init__(self, check):
        self.check = check
        self.start = time.thread_time()

    def __call__(self):
        if self.check is not None:
            self.check()
        used = time.thread_time() - self.start
        if used > LIMITS["chart_cpu_seconds"]:
            raise _v.KapitzaValueError(
                f"this view takes more than {LIMITS['chart_cpu_seconds']:g} s of computing (another drive or damping "
                f"solves an eigenproblem per edge and sample): ask fewer samples or a smaller eps range")


def _view(plane, eps_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples):
    """The bounds every view obeys, for the chart and its exports alike: samples, eps of the
    view (on the physical plane the largest ``eps = T_max sqrt(A_max / (8 l))``)."""
    from ..curves import physical_window

    d = _drive(drive)
    zeta = _zeta(zeta)
    general = None if d.closed_form(zeta) else d
    if samples is None:
        samples = 1000 if general is None else 300
    _bounded("samples", samples, LIMITS["samples" if general is None else "general_samples"], 2)
    cap = LIMITS["eps_max" if general is None else "general_eps_max"]
    if plane == "arnold":
        _bounded("eps_max", eps_max, cap)
    else:
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        (T_min, T_max), (A_min, A_max) = physical_window((T_min, T_max), (A_min, A_max), l, g, d)
        if np.isfinite(T_max) and np.isfinite(A_max) and A_max > 0:
            _bounded("T_max * sqrt(A_max / (8 l)) (the largest eps in view)",
                     float(T_max * np.sqrt(A_max / (8.0 * l))), cap)
    return d, zeta, general, samples, (T_min, T_max), (A_min, A_max), l, g


def _chart_json(plane, eps_min, eps_max, mu_min, mu_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples,
                check=None):
    """The JSON of ``/api/chart``. Every size is bounded after the narrow-window refinement: at
    most ``LIMITS["samples"]`` samples in all, for the at most ~55 zones of an ``eps <= 60`` view."""
    from ..curves import edge_kinds, physical_zone_curves, window_curves

    d, zeta, general, samples, (T_min, T_max), (A_min, A_max), l, g = _view(
        plane, eps_max, T_min, T_max, A_min, A_max, l, g, drive, zeta, samples)
    budget = _Budget(check)
    most = LIMITS["samples" if general is None else "general_samples"]
    if plane == "arnold":
        c = window_curves((eps_min, eps_max), (mu_min, mu_max), d, zeta, samples, max_samples=most, check=budget)
        y, lo, hi = c.mu, c.eps_lo, c.eps_hi
        view = dict(eps_min=eps_min, eps_max=eps_max, mu_min=mu_min, mu_max=mu_max)
    else:
        c = physical_zone_curves((T_min, T_max), (A_min, A_max), l, g, samples, d, zeta, max_samples=most,
                                 check=budget)
        y, lo, hi = c.A, c.T_lo, c.T_hi
        view = dict(T_min=T_min, T_max=T_max, A_min=A_min, A_max=A_max)
    if np.size(y) > most:  # the library keeps max_samples; a size cap is checked on what is sent
        raise _v.KapitzaValueError(f"the view needs {np.size(y)} samples after refinement (at most {most})")
    zones = [dict(n=int(n), lower_edge=edge_kinds(n)[0], upper_edge=edge_kinds(n)[1], lo=_beyond(lo[i]),
                  hi=_beyond(hi[i]))
             for i, n in enumerate(c.n)]
    from ..rig_plane import stroke_coefficient

    return _json_bytes(dict(plane=plane, x="eps" if plane == "arnold" else "T", y="mu" if plane == "arnold" else "A",
                            view=view, l=l, g=g, drive=d.describe(), mu_max=d.mu_max, zeta=zeta,
                            samples=int(np.size(y)), y_values=y,
                            zones=zones, stroke_coefficient=stroke_coefficient(d)))


def _report(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping):
    """The stability report of a point given as (eps, mu), (T, A) or a rig (frequency with stroke or
    amplitude), with ``rod`` for ``l`` and ``damping`` (c) for ``zeta``; and its drive."""
    from dataclasses import replace

    P = _point_of(eps, mu, T, A, l, g, drive, zeta, frequency, stroke, amplitude, rod, damping)
    _point_reach(P)
    if P["T"] is not None:
        rep = analyze(T=P["T"], A=P["A"], l=P["l"], g=P["g"], drive=P["drive"], damping=P["c"])
    else:
        rep = analyze(eps=P["eps"], mu=P["mu"], drive=P["drive"], zeta=P["zeta"])
    if P["given"] or P["pendulum"]:
        rep = replace(rep, given=P["given"], pendulum=P["pendulum"] or rep.pendulum)
    return rep, P["drive"]


def _point_reach(P):
    """A point within ``LIMITS['general_point_eps']`` where a verdict costs more the larger ``eps`` (its
    periods integrated in about ``eps`` steps, not exact segment products: a report's searches take
    seconds at eps 1,000 and minutes beyond 10,000), within ``LIMITS['own_point_eps']`` for a drive of
    its own Floquet data (the sine: 3 s at eps 20, a minute at 60, its exact traces growing with q)."""
    d = P["drive"]
    if d._far_cost:
        name = "eps" if P["T"] is None else "T sqrt(A / (8 l)) (the point's eps)"
        _bounded(name, P["eps"], LIMITS["general_point_eps" if d._from_shape else "own_point_eps"])


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
    """A point as ``eps, mu, zeta`` (and ``T, A, l, g`` and the damping ``c`` [1/s] when physical) with its
    drive, what the rig gave (``given``) and the rod's description (``pendulum``), validated."""
    from ..drives._api import zeta_of

    d = _drive(drive)
    pendulum = c = None
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
        if T is None or A is None:
            raise _v.KapitzaValueError(f"give T and A together (or eps and mu); got only {'T' if A is None else 'A'}")
        T = _v.one("T", _v.positive("T", T))
        A = _v.one("A", _v.positive("A", A))
        l = _v.one("l", _v.positive("l", l))
        g = _v.one("g", _v.positive("g", g))
        from ..parameters import to_arnold

        eps, mu = (float(v) for v in to_arnold(T, A, l, g))
        if damping is None:
            z = _zeta(zeta)
            c = _damping(z, l, g)
        else:
            c = _v.one("damping", _v.nonnegative("damping", damping))
            z = _zeta(float(zeta_of(c, l, g)))  # the explorer's bound on the damping ratio
    else:
        if damping is not None:
            raise _v.KapitzaValueError("with eps and mu give the damping as zeta, not damping")
        if eps is None and mu is None:
            raise _v.KapitzaValueError("give the point: eps and mu, T and A, or a rig's frequency with stroke or "
                                       "amplitude")
        if eps is None or mu is None:
            raise _v.KapitzaValueError("give eps and mu together (or T and A); got only "
                                       f"{'eps' if mu is None else 'mu'}")
        eps = _v.one("eps", _v.positive("eps", eps))
        mu = _v.one("mu", _v.positive("mu", mu))
        z = _zeta(zeta)
    return dict(eps=eps, mu=mu, T=T, A=A, l=l, g=g, c=c, zeta=z, drive=d, given=given, pendulum=pendulum)


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

        rows = "".join(f"<li><code>GET {html.escape(path)}</code>: "
                       f"{html.escape(ops.get('get', {}).get('summary', ''))}</li>"
                       for path, ops in app.openapi()["paths"].items())
        return HTMLResponse(f"<!doctype html><title>kapitza explorer: API</title><h1>kapitza explorer: API</h1>"
                            f"<p>The schema: <a href='/openapi.json'>/openapi.json</a></p><ul>{rows}</ul>")


@functools.lru_cache(maxsize=64)
def _rig_chart_json(f_min, f_max, stroke_min, stroke_max, l, g, drive, zeta, samples):
    """The JSON of ``/api/chart?plane=rig``: zone ``n`` is ``lo < frequency < hi`` at each stroke ``y``."""
    from ..curves import edge_kinds
    from ..rig_plane import rig_zone_curves, stroke_coefficient

    if samples is not None:
        _bounded("samples", samples, LIMITS["samples"], 2)
    d = _drive(drive)
    zeta = _zeta(zeta)
    general = None if d.closed_form(zeta) else d
    samples = (1000 if general is None else 300) if samples is None else samples
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


def _openapi(app):
    """The schema FastAPI generates, with the 422 body as sent: ``{"detail": "text"}`` (FastAPI
    describes its own list of validation errors, which the explorer does not send)."""
    from fastapi.openapi.utils import get_openapi

    if app.openapi_schema:
        return app.openapi_schema
    schema = get_openapi(title=app.title, version=app.version, description=app.description, routes=app.routes)
    components = schema.setdefault("components", {}).setdefault("schemas", {})
    components.pop("HTTPValidationError", None)
    components.pop("ValidationError", None)
    components["Error"] = {"title": "Error", "type": "object", "required": ["detail"],
                           "properties": {"detail": {"title": "Detail", "type": "string",
                                                     "description": "one line naming the parameter, its value "
                                                                    "and the allowed range"}}}
    error = {"content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
    for path in schema.get("paths", {}).values():
        for op in path.values():
            responses = op.setdefault("responses", {})
            responses["422"] = {"description": "bad input or a size beyond the explorer's limits", **error}
            responses["421"] = {"description": "a Host the explorer does not answer to", **error}
            responses["413"] = {"description": "a request with a body", **error}
            responses["414"] = {"description": "a path and query longer than the limit", **error}
    app.openapi_schema = schema
    return schema


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
    pair = motion_pair(theta0, dtheta0, T, A, l, g, periods=periods, points_per_period=points_per_period, damping=c,
                       drive=d)
    return pair, d


# ------------------------------------------------------------------ the tower (linked pendulums)
def _numbers(name, text):
    """Comma-separated numbers (``chain``, ``masses``), their count bounded by ``LIMITS['chain_links']``."""
    if not isinstance(text, str):
        text = ",".join(str(x) for x in np.atleast_1d(text))
    if len(text) > LIMITS["drive_text"]:
        raise _v.KapitzaValueError(f"{name} must be at most {LIMITS['drive_text']} characters; got {len(text)}")
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise _v.KapitzaValueError(f"{name} must be comma-separated numbers, one per link from the pivot up "
                                   f"(e.g. 0.2,0.2); got {text!r}") from None
    n = LIMITS["chain_links"]
    if not 1 <= len(vals) <= n:
        raise _v.KapitzaValueError(f"{name} must hold 1 to {n} links in the explorer (1 <= N <= {n}); "
                                   f"got {len(vals)}")
    return vals


def _chain(chain, masses=None, links="rod", joint_damping=0.0):
    """The :class:`kapitza.Chain` of the explorer's ``chain`` (lengths [m]), ``masses`` [kg],
    ``links`` and ``joint_damping`` [N m s/rad], each length and mass within the explorer's ranges
    and the friction's fastest decay rate at most ``LIMITS['chain_friction_rate']``."""
    import scipy.linalg

    from ..chain import Chain

    lengths = _numbers("chain", chain)
    for name, vals, (lo, hi), unit in (("chain", lengths, LIMITS["chain_length"], "m"),
                                       ("masses", None if masses is None or masses == "" else
                                        _numbers("masses", masses),
                                        LIMITS["chain_mass"], "kg")):
        if vals is None:
            continue
        for i, v in enumerate(vals):
            if not (np.isfinite(v) and lo <= v <= hi):
                raise _v.KapitzaValueError(f"{name} must lie within {lo:g} .. {hi:g} {unit} per link in the explorer "
                                           f"({lo:g} <= {name}[i] <= {hi:g}); got {name}[{i}] = {v:g}")
        if name == "masses":
            masses = vals
    if links not in ("rod", "point"):
        raise _v.KapitzaValueError(f"links must be one of 'rod', 'point'; got {links!r}")
    c = float(_v.one("joint_damping", _v.nonnegative("joint_damping", joint_damping)))
    out = Chain(lengths, None if masses in (None, "") else masses, links=links, joint_damping=c)
    if c > 0:
        rate = float(scipy.linalg.eigh(out.damping_matrix(), out.mass_matrix(), eigvals_only=True)[-1])
        top = LIMITS["chain_friction_rate"]
        if not rate <= top:
            raise _v.KapitzaValueError(
                f"joint_damping must be at most {c * top / rate:.3g} N m s/rad for this tower in the explorer (its "
                f"fastest friction decay rate, the largest eigenvalue of M^-1 C, <= {top:g} 1/s); got {c:g}, "
                f"a rate of {rate:.3g} 1/s")
    return out


def _tower_T_A(d, T, A, frequency, stroke, amplitude):
    """``(T, A)`` of a point given as ``T, A`` or as a rig's frequency with stroke or amplitude."""
    if frequency is not None or stroke is not None or amplitude is not None:
        if T is not None:
            raise _v.KapitzaValueError("give a rig's frequency with stroke or amplitude (or A), without T")
        if frequency is None:
            raise _v.KapitzaValueError("stroke and amplitude go with frequency")
        if stroke is not None and amplitude is not None:
            raise _v.KapitzaValueError("give stroke or amplitude, not both")
        T, A = (float(v) for v in d.from_rig(frequency, stroke=stroke, amplitude=amplitude, acceleration=A))
    if T is None or A is None:
        raise _v.KapitzaValueError("give the point: T and A, or a rig's frequency with stroke or amplitude")
    return float(_v.one("T", _v.positive("T", T))), float(_v.one("A", _v.positive("A", A)))


def _tower_window(chain, d, g, f_min, f_max, stroke_min, stroke_max):
    """The rig-plane window (the tower's default window where an end is not given), bounded."""
    from ..chain import default_window

    (F0, F1), (S0, S1) = default_window(chain, d, g)
    f0, f1 = (F0 if f_min is None else f_min), (F1 if f_max is None else f_max)
    s0, s1 = (S0 if stroke_min is None else stroke_min), (S1 if stroke_max is None else stroke_max)
    for name, v, (lo, hi) in (("f_min", f0, LIMITS["tower_frequency"]), ("f_max", f1, LIMITS["tower_frequency"]),
                              ("stroke_min", s0, LIMITS["tower_stroke"]), ("stroke_max", s1, LIMITS["tower_stroke"])):
        _bounded(name, v, hi, lo)
    if not f0 < f1:
        raise _v.KapitzaValueError(f"f_min must be below f_max; got f_min = {f0:g}, f_max = {f1:g}")
    if not s0 < s1:
        raise _v.KapitzaValueError(f"stroke_min must be below stroke_max; got stroke_min = {s0:g}, "
                                   f"stroke_max = {s1:g}")
    return (float(f0), float(f1)), (float(s0), float(s1))


def tower_chart_answer(chain="0.2,0.2,0.2", masses=None, links="rod", drive="square", g=G_EARTH, f_min=None,
                       f_max=None, stroke_min=None, stroke_max=None, grid=None, points=None,
                       joint_damping=0.0) -> bytes:
    """The JSON body of ``/api/tower/chart`` (bytes): the tower's band on the rig plane."""
    return _tower_chart_json(chain, masses, links, drive, g, f_min, f_max, stroke_min, stroke_max, grid, points,
                             joint_damping)


@functools.lru_cache(maxsize=32)
def _tower_chart_json(chain, masses, links, drive, g, f_min, f_max, stroke_min, stroke_max, grid, points,
                      joint_damping=0.0):
    from ..chain import tower_curves

    c = _chain(chain, masses, links, joint_damping)
    d = _drive(drive)
    g = float(_v.one("g", _v.in_range("g", g, 1e-3, 1e3, lo_open=False, hi_open=False)))
    closed = d.closed_form(0.0)
    coupled = c.joint_damping > 0 and c.n > 1  # the band is the 2N monodromy's verdict, point by point
    piecewise = getattr(d, "levels", None) is not None
    if coupled:
        top = LIMITS["tower_friction_grid" if piecewise else "tower_friction_general_grid"]
        grid = (top if piecewise else 20) if grid is None else grid
    else:
        top = LIMITS["tower_grid" if closed else "tower_general_grid"]
        grid = (120 if closed else 50) if grid is None else grid
    points = (300 if closed else 120) if points is None else points
    _bounded("grid", grid, top, 2)
    _bounded("points", points, LIMITS["tower_points" if closed else "tower_general_points"], 2)
    fr, sr = _tower_window(c, d, g, f_min, f_max, stroke_min, stroke_max)
    b = tower_curves(c, drive=d, g=g, frequency_range=fr, stroke_range=sr, points=int(points), grid=int(grid))
    from ..rig_plane import stroke_coefficient

    def curve(F, S):
        return dict(frequency=_beyond(F), stroke=_beyond(S))

    modes = [dict(mode=k + 1, l=l, lower=curve(b.frequency_lo[k], b.stroke_lo[k]),
                  upper=curve(b.frequency_hi[k], b.stroke_hi[k])) for k, l in enumerate(b.modal_lengths)]
    return _json_bytes(dict(plane="rig", x="frequency", y="stroke", chain=c.describe(), lengths=list(c.lengths),
                            masses=list(c.masses), links=c.links, n_links=c.n, modal_lengths=list(b.modal_lengths),
                            joint_damping=c.joint_damping,
                            band_method="2N monodromy" if coupled else "modes",
                            drive=d.describe(), mu_max=d.mu_max, g=g, stroke_coefficient=stroke_coefficient(d),
                            view=dict(f_min=fr[0], f_max=fr[1], stroke_min=sr[0], stroke_max=sr[1]), modes=modes,
                            band=dict(frequency=b.frequency, stroke=b.stroke,
                                      stable=b.stable.astype(np.uint8))))


def tower_point_answer(chain="0.2,0.2,0.2", masses=None, links="rod", drive="square", g=G_EARTH, T=None, A=None,
                       frequency=None, stroke=None, amplitude=None, joint_damping=0.0) -> dict:
    """What ``/api/tower/point`` answers: the tower's report (``kapitza tower --json``'s ``report``)
    with ``lines``, the rows of its table."""
    c = _chain(chain, masses, links, joint_damping)
    d = _drive(drive)
    g = float(_v.one("g", _v.positive("g", g)))
    T, A = _tower_T_A(d, T, A, frequency, stroke, amplitude)
    rep = c.analyze(T=T, A=A, g=g, drive=d)
    return _io.to_jsonable({**rep.as_dict(), "lines": rep.lines(), "n_links": c.n, "lengths": list(c.lengths),
                            "links": c.links})


def tower_motion_answer(chain="0.2,0.2,0.2", masses=None, links="rod", drive="square", g=G_EARTH, T=None, A=None,
                        frequency=None, stroke=None, amplitude=None, theta0=0.1, periods=None,
                        points_per_period=None, joint_damping=0.0) -> dict:
    """What ``/api/tower/motion`` answers: the tower's full (nonlinear) motion from every link tilted
    by ``theta0`` at rest, sampled for animation (``kapitza.chain_motion``)."""
    from ..motion.chain import chain_motion

    c = _chain(chain, masses, links, joint_damping)
    d = _drive(drive)
    g = float(_v.one("g", _v.positive("g", g)))
    T, A = _tower_T_A(d, T, A, frequency, stroke, amplitude)
    theta0 = float(_v.one("theta0", _v.finite("theta0", theta0)))
    _bounded("|theta0|", abs(theta0), LIMITS["theta0"])
    if periods is None:
        periods = max(10.0, min(LIMITS["tower_periods"], 1.5 / (2.0 * T)))
    if points_per_period is None:
        points_per_period = max(4, min(60, int(LIMITS["motion_samples"] / 4 / periods)))
    _bounded("periods", periods, LIMITS["tower_periods"], 1)
    _bounded("points_per_period", points_per_period, LIMITS["points_per_period"], 4)
    _bounded("periods * points_per_period", periods * points_per_period, LIMITS["motion_samples"])
    m = chain_motion(c, theta0, 0.0, T=T, A=A, g=g, drive=d, periods=float(periods),
                     points_per_period=int(points_per_period))
    rep = c.analyze(T=T, A=A, g=g, drive=d)
    return _io.to_jsonable(dict(t=m.t, pivot=m.pivot, theta=m.theta, dtheta=m.dtheta, lengths=list(c.lengths),
                                links=c.links, n_links=c.n, T=T, A=A, g=g, frequency=0.5 / T, theta0=theta0,
                                periods=float(periods), points_per_period=int(points_per_period),
                                toppled=bool(m.toppled), t_topple=m.t_topple, tol=m.tol, stable=bool(rep.stable),
                                verdict=rep.verdict, chain=c.describe(), drive=d.describe(),
                                joint_damping=c.joint_damping))
