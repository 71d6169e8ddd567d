"""The notebook explorer: the page's JavaScript (``web/static/explorer.js``) in a cell, its
requests answered in the kernel by the functions the web API's routes call."""
from __future__ import annotations

import concurrent.futures
import inspect
import json
import logging
import re
import threading
from pathlib import Path
from typing import Callable
from urllib.parse import parse_qsl, urlsplit

import anywidget
import traitlets

from .. import _validate as _v
from ..drives import parse_drive
from ..parameters import G_EARTH, to_arnold, to_physical
from ..web import app as _app

__all__ = ["Explorer", "answer"]

_STATIC = _app.STATIC
_LOG = logging.getLogger(__name__)

#: The routes of ``/api`` the explorer asks, and the functions that answer them.
ROUTES: dict[str, Callable] = {
    "chart": _app.chart_answer,
    "verdict": _app.verdict_answer,
    "point": _app.point_answer,
    "safe_tilt": _app.safe_tilt_answer,
    "motion": _app.motion_answer,
    "drives": _app.drives_answer,
    "drive": _app.drive_answer,
    "tower/chart": _app.tower_chart_answer,
    "tower/point": _app.tower_point_answer,
    "tower/motion": _app.tower_motion_answer,
}
# parameters without a default that are integers, and those that are texts (the rest without one are floats)
_INTS = {"samples", "grid", "points", "points_per_period"}
_TEXTS = {"masses"}


class _Dropped(Exception):
    """The explorer no longer wants this answer (a newer choice replaced it)."""


def _parse(route: str, query) -> dict:
    """The keyword arguments of ``ROUTES[route]`` from a query's strings, typed as the route types
    them (by each parameter's default); unknown names are ignored, as the web API ignores them."""
    params = inspect.signature(ROUTES[route]).parameters
    kwargs: dict[str, object] = {}
    for name, text in query:
        if name not in params or name == "check":
            continue
        default = params[name].default
        if isinstance(default, bool):
            if text.lower() not in ("true", "false", "1", "0"):
                raise _v.KapitzaValueError(f"{name} must be true or false; got {text!r}")
            kwargs[name] = text.lower() in ("true", "1")
        elif isinstance(default, str) or name in _TEXTS:
            kwargs[name] = text
        elif isinstance(default, int) or name in _INTS:
            try:
                kwargs[name] = int(text)
            except ValueError:
                raise _v.KapitzaValueError(f"{name} must be an integer; got {text!r}") from None
        else:
            try:
                kwargs[name] = float(text)
            except ValueError:
                raise _v.KapitzaValueError(f"{name} must be a number; got {text!r}") from None
    return kwargs


def answer(url: str, check=None) -> dict:
    """The explorer's answer to ``url`` (``"/api/ROUTE?query"``), as the web API gives it.

    Parameters
    ----------
    url : str
        A route of the web API with its query, e.g. ``"/api/verdict?eps=0.5&mu=0.3"``.
    check : callable, optional
        Called between blocks of a long chart; it raises to stop one nobody waits for.

    Returns
    -------
    dict
        ``{"ok": True, "json": text}`` with the JSON text the route sends, or
        ``{"ok": False, "detail": message}`` with the one-line message of its 422 (an unknown
        route or a bad query is answered so, not raised).

    Raises
    ------
    Exception
        What ``check()`` raises, passed on unchanged (the chart is abandoned).

    Examples
    --------
    >>> from kapitza.widgets import answer
    >>> answer("/api/verdict?eps=0.5&mu=0.3")["ok"]
    True
    >>> answer("/api/verdict?eps=-1&mu=0.3")["detail"]
    'eps must be finite and > 0 (0 < eps < inf); got -1.0'
    """
    parts = urlsplit(url)
    route = parts.path[len("/api/"):]
    try:
        if not parts.path.startswith("/api/") or route not in ROUTES:
            raise _v.KapitzaValueError(f"the explorer answers {', '.join('/api/' + r for r in ROUTES)}; "
                                       f"not {parts.path!r}")
        kwargs = _parse(route, parse_qsl(parts.query, keep_blank_values=True))
        if route == "chart":
            body = ROUTES[route](**kwargs, check=check)
        else:
            body = ROUTES[route](**kwargs)
            body = body if isinstance(body, bytes) else _app.json_bytes(body)
    except Exception as exc:  # noqa: BLE001 - a user's error becomes its one-line message
        detail = _app.error_detail(exc)
        if detail is None:
            raise
        return {"ok": False, "detail": detail}
    return {"ok": True, "json": body.decode()}


def _esm() -> str:
    """The widget's module: the page's explorer (``explorer.js``), the page's markup and style
    (``index.html``, ``style.css``) for a shadow root, and the glue (``widget.js``)."""
    page = (_STATIC / "index.html").read_text(encoding="utf-8")
    markup = page[page.index("<header>"):page.index("</main>") + len("</main>")]
    style = (_STATIC / "style.css").read_text(encoding="utf-8")
    # the page's document-wide rules, for the explorer's own box in the shadow root
    style = style.replace(":root", ":host")
    style = re.sub(r"\bbody\b", ".kapitza-explorer", style)
    return "\n".join([
        (_STATIC / "explorer.js").read_text(encoding="utf-8"),
        f"const MARKUP = {json.dumps(markup)};",
        f"const STYLE = {json.dumps(style)};",
        Path(__file__).with_name("widget.js").read_text(encoding="utf-8"),
    ])


# one computation at a time (the kernel stays free to run cells meanwhile)
_WORKER = concurrent.futures.ThreadPoolExecutor(max_workers=1, thread_name_prefix="kapitza-explorer")
_DEMO = dict(T=0.15, A=100.0)  # the page's first point: zone 0, the pendulum standing


class Explorer(anywidget.AnyWidget):
    """The explorer in a notebook cell: the exact stability chart and the pendulum on its vibrating
    pivot, the same page as ``kapitza serve`` shows, computed in this kernel.

    Parameters
    ----------
    point : dict, optional
        The chosen point: ``dict(eps=..., mu=...)`` or ``dict(T=..., A=...)`` (with ``l``, ``g``).
        Read back it holds all four. Clicking the chart sets it; setting it moves the marker and
        updates the verdict, the report and the motion.
    drive : str
        The drive's text form: ``"square"`` (the paper's), ``"sine"``, ``"rectangular:0.3"``...
    zeta : float
        The damping ratio.
    l, g : float
        The equivalent length [m] and gravity [m/s^2].
    plane : {"arnold", "physical", "rig"}
        The chart's plane.
    theta0 : float
        The start tilt of the motion [rad].

    Raises
    ------
    KapitzaValueError
        If a point, a drive, a damping ratio, a length, gravity, a plane or a tilt is refused (the
        web API's one-line message), when the explorer is made or when a trait is set later; the
        trait keeps its value then.

    Examples
    --------
    >>> from kapitza.widgets import Explorer
    >>> w = Explorer(point=dict(eps=0.5, mu=0.3))
    >>> w.verdict["verdict"]
    'stable (zone 0)'
    >>> w.point = dict(T=0.1, A=50)
    >>> round(w.point["eps"], 6), round(w.point["mu"], 6)
    (0.25, 0.442945)
    """

    _esm = traitlets.Unicode(_esm()).tag(sync=True)
    point = traitlets.Any().tag(sync=True)  # a dict; any other value gets the explorer's message
    drive = traitlets.Unicode("square").tag(sync=True)
    zeta = traitlets.Float(0.0).tag(sync=True)
    l = traitlets.Float(1.0).tag(sync=True)
    g = traitlets.Float(G_EARTH).tag(sync=True)
    plane = traitlets.Unicode("arnold").tag(sync=True)
    theta0 = traitlets.Float(0.1).tag(sync=True)

    def __init__(self, **kwargs):
        point = kwargs.pop("point", None)
        super().__init__(**kwargs)
        self.point = dict(_DEMO) if point is None else point
        self._dropped = set()
        self._lock = threading.Lock()
        self.on_msg(self._on_msg)

    # ----------------------------------------------------------- validation
    @traitlets.validate("point")
    def _valid_point(self, proposal):
        return self._complete(proposal["value"], self.l, self.g)

    @staticmethod
    def _complete(p, l, g) -> dict:
        """``{eps, mu, T, A}`` of a point given by ``(T, A)`` or ``(eps, mu)`` (``T, A`` win when
        both are given: the explorer keeps its point as ``T, A``)."""
        if not isinstance(p, dict):
            raise _v.KapitzaValueError(f"point must be a dict with eps and mu, or T and A; got {p!r}")
        extra = set(p) - {"eps", "mu", "T", "A"}
        if extra:
            raise _v.KapitzaValueError(f"point takes eps and mu, or T and A; got {', '.join(sorted(extra))}")
        if "T" in p or "A" in p:
            T = _v.one("T", _v.positive("T", p.get("T")))
            A = _v.one("A", _v.positive("A", p.get("A")))
            eps, mu = (float(v) for v in to_arnold(T, A, l, g))
        else:
            eps = _v.one("eps", _v.positive("eps", p.get("eps")))
            mu = _v.one("mu", _v.positive("mu", p.get("mu")))
            T, A = (float(v) for v in to_physical(eps, mu, l, g))
        return dict(eps=eps, mu=mu, T=T, A=A)

    @traitlets.validate("drive")
    def _valid_drive(self, proposal):
        text = proposal["value"]
        if len(text) > _app.LIMITS["drive_text"]:
            raise _v.KapitzaValueError(f"drive must be at most {_app.LIMITS['drive_text']} characters; got {len(text)}")
        parse_drive(text)  # a drive kapitza reads, or its message
        return text

    @traitlets.validate("zeta")
    def _valid_zeta(self, proposal):
        zeta = _v.one("zeta", _v.nonnegative("zeta", proposal["value"]))
        if zeta > _app.LIMITS["zeta"]:
            hi = _app.LIMITS["zeta"]
            raise _v.KapitzaValueError(f"zeta must satisfy zeta <= {hi:g} in the explorer; got {zeta!r}")
        return zeta

    @traitlets.validate("l", "g")
    def _valid_length(self, proposal):
        name = proposal["trait"].name
        return _v.one(name, _v.positive(name, proposal["value"]))

    @traitlets.validate("theta0")
    def _valid_theta0(self, proposal):
        theta0 = float(_v.one("theta0", _v.finite("theta0", proposal["value"])))
        _app._bounded("|theta0|", abs(theta0), _app.LIMITS["theta0"])
        return theta0

    @traitlets.validate("plane")
    def _valid_plane(self, proposal):
        if proposal["value"] not in ("arnold", "physical", "rig"):
            raise _v.KapitzaValueError(f"plane must be one of 'arnold', 'physical', 'rig'; got {proposal['value']!r}")
        return proposal["value"]

    @traitlets.observe("l", "g")
    def _keep_point(self, change):
        # the explorer keeps T and A as l or g change: eps and mu follow
        if self.point:
            self.point = dict(T=self.point["T"], A=self.point["A"])

    # ----------------------------------------------------------- answers
    @property
    def verdict(self) -> dict:
        """The verdict at the chosen point (what ``/api/verdict`` answers): ``stable``, ``zone``,
        ``kind`` and the sentence ``verdict``."""
        return _app.verdict_answer(T=self.point["T"], A=self.point["A"], l=self.l, g=self.g, drive=self.drive,
                                   zeta=self.zeta)

    def report(self) -> dict:
        """The stability report at the chosen point (what ``/api/point`` and ``kapitza stability
        --json`` give)."""
        return _app.point_answer(T=self.point["T"], A=self.point["A"], l=self.l, g=self.g, drive=self.drive,
                                 zeta=self.zeta)

    def _on_msg(self, widget, content, buffers):
        if not isinstance(content, dict):
            return
        if content.get("kind") == "drop":
            with self._lock:
                self._dropped.add(content.get("id"))
        elif content.get("kind") == "ask":
            _WORKER.submit(self._reply, content.get("id"), str(content.get("url", "")))

    def _reply(self, key, url):
        def check():
            if key in self._dropped:
                raise _Dropped

        try:
            check()
            reply = answer(url, check)
        except _Dropped:
            return
        except Exception as exc:  # noqa: BLE001 - not a user's error: said in the cell and logged
            _LOG.exception("the explorer could not answer %s", url)
            reply = {"ok": False, "detail": f"internal error: {type(exc).__name__}: {exc}"}
        finally:
            with self._lock:
                self._dropped.discard(key)
        self.send({"id": key, **reply})

