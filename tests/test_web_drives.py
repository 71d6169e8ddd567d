"""The explorer's drives come from the registry: ``/api/drives`` lists every registered drive (a
user's own class included) and ``/api/drive`` gives what the page needs of one, from the library."""
from __future__ import annotations

import httpx
import numpy as np
import pytest

import kapitza
from kapitza.drives import DRIVES, parse_drive, register, text_forms
from kapitza.rig_plane import stroke_coefficient
from kapitza.web.app import drives_answer
from web_server import running_server

# A user's drive with one number, registered in the server's process before it starts.
USER_DRIVE = '''
import numpy as np
import kapitza
from kapitza.drives import register

@register
class Skewed(kapitza.Drive):
    """Acceleration +A for the fraction w of the period, then -A w/(1 - w), given by its shape."""
    name = "my-skewed"
    text_form = "my-skewed:W"
    title = "skewed square (user's)"
    parameters = ({"name": "w", "min": 0.0, "max": 1.0, "default": 0.4, "examples": (0.4,)},)

    def __init__(self, w):
        self.w = float(kapitza._validate.one("w", kapitza._validate.in_range("w", w, 0.0, 1.0)))
        self._breakpoints = (2.0 * self.w,)

    @classmethod
    def from_text(cls, parameters, text=None):
        return cls(kapitza._validate.number_text("w", parameters or ""))

    def text(self):
        return f"my-skewed:{self.w!r}"

    def as_dict(self):
        return {"drive": self.name, "w": self.w}

    def _shape(self, tau):
        return np.where(tau < 2.0 * self.w, 1.0, -self.w / (1.0 - self.w))
'''


@pytest.fixture(scope="module")
def server():
    # one process: the registry of the process that registered the class (more workers start afresh)
    with running_server("--workers", "1", prelude=USER_DRIVE) as (base, _, _proc):
        with httpx.Client(base_url=base, timeout=60.0) as client:
            yield client


def test_drives_are_the_registry_with_a_users_class(server):
    r = server.get("/api/drives")
    assert r.status_code == 200
    body = r.json()
    names = [d["name"] for d in body["drives"]]
    assert names == [*DRIVES, "my-skewed"]           # the registry's order, the user's class last
    assert body["default"] == "square"
    by = {d["name"]: d for d in body["drives"]}
    assert [by[n]["page"] for n in ("square", "rectangular", "sine", "triangle", "my-skewed")] == [True] * 5
    assert by["steps"]["page"] is False and by["steps"]["parameters"] is None   # lists: no field for them
    (duty,) = by["rectangular"]["parameters"]
    assert (duty["name"], duty["min"], duty["max"], duty["default"]) == ("duty", 1e-6, 1.0 - 1e-6, 0.3)
    assert by["rectangular"]["default"] == "rectangular:0.3"
    assert [x["text"] for x in by["rectangular"]["examples"]] == ["rectangular:0.3", "rectangular:0.7"]
    assert by["triangle"]["parameters"] == [] and by["triangle"]["default"] == "triangle"
    assert by["triangle"]["title"] == "triangle wave"
    user = by["my-skewed"]
    assert (user["title"], user["text_form"], user["default"]) == ("skewed square (user's)", "my-skewed:W", "my-skewed:0.4")
    assert user["parameters"][0]["name"] == "w"
    assert body["text_forms"] == [*text_forms(), "my-skewed:W"]


def test_drive_numbers_are_the_librarys(server):
    for text, zeta in (("square", 0.0), ("square", 0.1), ("sine", 0.0), ("triangle", 0.0), ("rectangular:0.8", 0.0),
                       ("rectangular:0.3", 0.05)):
        d = parse_drive(text)
        got = server.get("/api/drive", params=dict(drive=text, zeta=zeta)).json()
        assert got["mu_max"] == pytest.approx(d.mu_max, rel=1e-15)
        assert got["stroke_coefficient"] == pytest.approx(stroke_coefficient(d), rel=1e-15)
        assert got["closed_form"] is bool(d.closed_form(zeta))
        assert got["label"] == d.label
    assert server.get("/api/drive", params=dict(drive="square")).json()["closed_form"] is True
    assert server.get("/api/drive", params=dict(drive="square", zeta=0.1)).json()["closed_form"] is False
    assert server.get("/api/drive", params=dict(drive="rectangular:0.8")).json()["mu_max"] == pytest.approx(2.0)
    tri = server.get("/api/drive", params=dict(drive="triangle")).json()
    assert tri["stroke_coefficient"] == pytest.approx(1 / 6) and tri["exact_motion"] is False
    assert server.get("/api/drive", params=dict(drive="rectangular:0.3")).json()["exact_motion"] is True
    # the user's class: its numbers computed from its shape in the server
    user = server.get("/api/drive", params=dict(drive="my-skewed:0.4")).json()
    assert user["mu_max"] == pytest.approx(np.sqrt(0.4 / 0.6), rel=1e-12)
    assert user["stroke_coefficient"] == pytest.approx(stroke_coefficient(kapitza.RectangularWave(0.4)),
                                                       rel=1e-9)
    # and its chart and verdict are answered like any drive's
    v = server.get("/api/verdict", params=dict(eps=0.6, mu=0.3, drive="my-skewed:0.4")).json()
    assert v["stable"] is bool(kapitza.is_stable(0.6, 0.3, drive=kapitza.RectangularWave(0.4)))


@pytest.mark.parametrize("query, words", [
    (dict(drive="rectangular:1.5"), ["duty", "1.5"]),
    (dict(drive="sawtooth"), ["drive", "sawtooth", "triangle", "my-skewed:W"]),
    (dict(drive="my-skewed:2"), ["w", "2"]),
    (dict(drive="triangle:3"), ["triangle", "no parameters"]),
    (dict(drive="sine", zeta=-1), ["zeta", "-1"]),
    (dict(drive="x" * 250), ["drive", "200"]),
])
def test_bad_drive_is_422_with_one_line(server, query, words):
    r = server.get("/api/drive", params=query)
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert isinstance(detail, str) and "\n" not in detail and "Traceback" not in detail
    for w in words:
        assert w in detail, (w, detail)


def test_drives_answer_follows_the_registry_in_this_process():
    """The list is built from the registry when asked: a class registered here joins it; one whose
    default the registry cannot read back is listed but not offered by the page."""
    class NoDefault(kapitza.Drive):
        name = "my-nodefault"
        parameters = ({"name": "k", "min": 0.0, "max": 1.0},)   # no default: the page cannot build it
        _breakpoints = (1.0,)

        def _shape(self, tau):
            return np.where(tau < 1.0, 1.0, -1.0)

    register(NoDefault)
    try:
        by = {d["name"]: d for d in drives_answer()["drives"]}
        assert by["my-nodefault"]["page"] is False and by["my-nodefault"]["default"] is None
        assert by["square"]["page"] is True
    finally:
        del DRIVES["my-nodefault"]
    assert "my-nodefault" not in {d["name"] for d in drives_answer()["drives"]}


def test_the_notebook_answers_the_drive_routes():
    pytest.importorskip("anywidget")
    import json

    from kapitza.widgets import answer

    listed = json.loads(answer("/api/drives")["json"])
    assert "triangle" in [d["name"] for d in listed["drives"]]
    one = json.loads(answer("/api/drive?drive=rectangular%3A0.8")["json"])
    assert one["mu_max"] == pytest.approx(2.0)
    assert answer("/api/drive?drive=rectangular%3A1.5")["detail"] == "duty must lie in [1e-06, 0.999999]; got 1.5"
