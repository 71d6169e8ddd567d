"""The explorer inside a notebook (``kapitza.widgets.Explorer``): the kernel answers the page's
requests with the web API's own answers, the point and the rig are linked to Python, a notebook
creates it and reads and sets the point, and Chromium draws it from the widget's own module.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("anywidget")
pytest.importorskip("fastapi")

import kapitza  # noqa: E402
from kapitza.widgets import Explorer, answer  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCREENS = ROOT / "out" / "web-screens"
CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists() else None)


@pytest.fixture(scope="module")
def web():
    """The web API of ``kapitza serve``, over HTTP."""
    import httpx

    from web_server import running_server

    with running_server() as (base, _, _proc), httpx.Client(base_url=base, timeout=120.0) as client:
        yield client


# ------------------------------------------------------------------ the answers
SAME = [
    "/api/chart?plane=arnold&eps_min=0&eps_max=4&mu_min=0&mu_max=1&drive=square&zeta=0&samples=60",
    "/api/chart?plane=physical&T_min=0&T_max=0.8&A_min=9.81&A_max=490&l=1&g=9.81&drive=square&samples=40",
    "/api/chart?plane=arnold&eps_min=0&eps_max=3&mu_min=0.1&mu_max=0.9&drive=sine&samples=12",
    "/api/chart?plane=rig&f_min=2&f_max=200&stroke_min=0.001&stroke_max=0.5&l=0.25&drive=square&samples=30",
    "/api/verdict?T=0.15&A=100&l=1&g=9.81&drive=square&zeta=0",
    "/api/verdict?eps=1.78&mu=0.3&drive=rectangular%3A0.3",
    "/api/verdict?frequency=50&stroke=0.01&rod=0.25&drive=sine&zeta=0.02",
    "/api/point?T=0.15&A=100&l=1&g=9.81&drive=square&zeta=0",
    "/api/point?eps=2.5&mu=0.3&drive=square",
    "/api/safe_tilt?T=0.15&A=100&l=1&g=9.81&drive=square&zeta=0&periods=20",
    "/api/motion?T=0.15&A=100&l=1&g=9.81&drive=square&zeta=0&theta0=0.1&periods=20&points_per_period=60",
    "/api/motion?eps=1.0&mu=0.5&drive=sine&zeta=0.1&theta0=0.3&periods=3&points_per_period=20",
]


@pytest.mark.parametrize("url", SAME)
def test_the_kernel_answers_as_the_web_api(web, url):
    r = web.get(url)
    assert r.status_code == 200, r.text
    got = answer(url)
    assert got["ok"], got
    assert json.loads(got["json"]) == r.json()


BAD = [
    "/api/verdict?eps=-1&mu=0.3",
    "/api/verdict?eps=0.5",
    "/api/verdict?eps=0.5&mu=0.3&T=0.1&A=10",
    "/api/point?eps=0.5&mu=0.3&drive=bogus",
    "/api/point?eps=0.5&mu=0.3&zeta=11",
    "/api/chart?eps_max=100",
    "/api/chart?samples=99999",
    "/api/chart?plane=arnold&drive=sine&eps_max=20",
    "/api/motion?T=0.1&A=50&periods=1000",
    "/api/motion?T=0.1&A=50&theta0=4",
    "/api/safe_tilt?eps=0.5&mu=0.3&drive=sine&periods=500",
]


@pytest.mark.parametrize("url", BAD)
def test_bad_input_gives_the_web_apis_one_line_message(web, url):
    r = web.get(url)
    assert r.status_code == 422
    got = answer(url)
    assert got == {"ok": False, "detail": r.json()["detail"]}
    assert "\n" not in got["detail"] and "Traceback" not in got["detail"]


def test_what_only_the_kernel_is_asked():
    assert answer("/api/export/chart.png")["detail"].startswith("the explorer answers /api/chart")
    assert answer("/api/verdict?eps=abc&mu=0.3") == {"ok": False, "detail": "eps must be a number; got 'abc'"}
    got = answer("/api/point?eps=0.5&mu=0.3&safe_tilt=maybe")
    assert got["detail"] == "safe_tilt must be true or false; got 'maybe'"
    # a name the route does not take is ignored, as the web API ignores it
    assert answer("/api/verdict?eps=0.5&mu=0.3&colour=red")["ok"]


# ------------------------------------------------------------------ the widget's messages
def _replies(w, *asks, expect=None, timeout=120.0):
    """The answers ``w`` sends for ``asks`` ((id, url) pairs), by id: ``expect`` of them (default all;
    one worker answers in turn, so the last answered means every earlier one was seen)."""
    expect = len(asks) if expect is None else expect
    sent = {}
    w.send = lambda content, buffers=None: sent.__setitem__(content["id"], content)
    for key, url in asks:
        w._on_msg(w, {"kind": "ask", "id": key, "url": url}, [])
    t0 = time.monotonic()
    while len(sent) < expect and time.monotonic() - t0 < timeout:
        time.sleep(0.01)
    return sent


def test_messages_from_the_page_are_answered_in_the_kernel(web):
    w = Explorer()
    url = "/api/verdict?eps=0.5&mu=0.3&drive=square"
    sent = _replies(w, ("a:1", url), ("a:2", "/api/verdict?eps=0.5&mu=-7"))
    assert sent["a:1"]["ok"] and json.loads(sent["a:1"]["json"]) == web.get(url).json()
    assert sent["a:2"] == {"id": "a:2", "ok": False, "detail": web.get("/api/verdict?eps=0.5&mu=-7").json()["detail"]}


def test_a_dropped_request_is_not_answered():
    w = Explorer()
    w._on_msg(w, {"kind": "drop", "id": "b:1"}, [])
    sent = _replies(w, ("b:1", "/api/verdict?eps=0.5&mu=0.3"), ("b:2", "/api/verdict?eps=0.5&mu=0.3"),
                    expect=1)
    assert set(sent) == {"b:2"}
    assert not w._dropped
    w._on_msg(w, "not a dict", [])  # ignored
    w._on_msg(w, {"kind": "unknown"}, [])


# ------------------------------------------------------------------ linked to Python
def test_the_point_is_set_and_read_from_python():
    w = Explorer(point=dict(eps=0.5, mu=0.3))
    assert w.point["eps"] == 0.5 and w.point["mu"] == 0.3
    T, A = (float(v) for v in kapitza.to_physical(0.5, 0.3, 1.0, kapitza.G_EARTH))
    assert w.point["T"] == pytest.approx(T, rel=1e-15) and w.point["A"] == pytest.approx(A, rel=1e-15)
    assert w.verdict["stable"] and w.verdict["zone"] == 0
    assert bool(kapitza.is_stable(0.5, 0.3)) is True
    # a point in the 4T resonance just above zone 1 (the page's verdict is the library's)
    w.point = dict(eps=2.9, mu=0.3)
    assert w.verdict["stable"] == bool(kapitza.is_stable(2.9, 0.3))
    assert w.verdict == answer_dict(f"/api/verdict?T={w.point['T']!r}&A={w.point['A']!r}")
    # as the page sends it after a click: all four, T and A kept
    w.point = dict(T=0.1, A=50.0, eps=123.0, mu=456.0)
    assert w.point["T"] == 0.1 and w.point["A"] == 50.0 and w.point["eps"] == pytest.approx(0.25, rel=1e-15)
    # l changes eps and keeps T and A (the explorer's point is T, A)
    w.l = 4.0
    assert w.point["T"] == 0.1 and w.point["eps"] == pytest.approx(0.125, rel=1e-15)


def answer_dict(url):
    return json.loads(answer(url)["json"])


def test_drive_and_damping_traits():
    w = Explorer(point=dict(eps=0.5, mu=0.3), drive="sine", zeta=0.05)
    assert w.verdict["zeta"] == 0.05
    assert w.report()["drive"].startswith("sine")
    w.drive = "rectangular:0.3"
    assert w.report()["drive"].startswith("rectangular")


@pytest.mark.parametrize("name, value, message", [
    ("point", dict(eps=-1.0, mu=0.3), "eps must be finite and > 0"),
    ("point", dict(eps=0.5), "mu must be"),
    ("point", dict(eps=0.5, mu=0.3, l=2), "point takes eps and mu, or T and A; got l"),
    ("point", [0.5, 0.3], "point must be a dict"),
    ("drive", "bogus", "drive must be one of"),
    ("zeta", -0.1, "zeta must be"),
    ("zeta", 11.0, "zeta must satisfy zeta <= 10 in the explorer"),
    ("l", 0.0, "l must be"),
    ("plane", "polar", "plane must be one of 'arnold', 'physical', 'rig'"),
    ("theta0", float("nan"), "theta0 must be finite"),
    ("theta0", 4.0, "|theta0| must satisfy |theta0| <= 3.15 in the explorer"),
])
def test_bad_traits_are_refused_with_the_librarys_message(name, value, message):
    w = Explorer()
    before = getattr(w, name)
    with pytest.raises(kapitza.KapitzaValueError, match=re.escape(message)):
        setattr(w, name, value)
    assert getattr(w, name) == before


def test_import_kapitza_stays_light_and_the_extra_is_named():
    code = ("import sys, kapitza; assert 'anywidget' not in sys.modules and 'kapitza.widgets' not in sys.modules; "
            "assert 'widgets' in dir(kapitza); print(kapitza.widgets.Explorer.__name__)")
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0 and run.stdout.strip() == "Explorer", run.stderr
    missing = "import sys; sys.modules['anywidget'] = None; import kapitza.widgets"
    run = subprocess.run([sys.executable, "-c", missing], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 1
    assert run.stderr.strip().splitlines()[-1] == (
        "ImportError: kapitza.widgets needs the 'widgets' extra (anywidget is missing): pip install 'kapitza[widgets]'")


# ------------------------------------------------------------------ in a notebook
def test_a_notebook_creates_the_explorer_and_sets_and_reads_the_point(tmp_path, monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    cells = [
        "from kapitza.widgets import Explorer\nw = Explorer(drive='square')\nw",
        "w.point = dict(eps=0.5, mu=0.3)\nprint('verdict:', w.verdict['verdict'])\n"
        "print('point:', w.point['eps'], w.point['mu'])",
        "w.point = dict(eps=2.9, mu=0.3)\nprint('verdict:', w.verdict['verdict'])",
        "try:\n    w.point = dict(eps=-1, mu=0.3)\nexcept ValueError as e:\n    print('refused:', e)\n"
        "print('kept:', w.point['eps'])",
    ]
    book = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    nbclient.NotebookClient(book, timeout=600, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outs = [o for c in book.cells for o in c.outputs]
    assert not [o for o in outs if o.output_type == "error"]
    view = outs[0]["data"]
    assert "application/vnd.jupyter.widget-view+json" in view  # a widget, not a text repr
    text = "".join(o.get("text", "") for o in outs)
    assert "verdict: stable (zone 0)\npoint: 0.5 0.3\n" in text
    assert "verdict: " + answer_dict("/api/verdict?eps=2.9&mu=0.3")["verdict"] in text
    assert "refused: eps must be finite and > 0 (0 < eps < inf); got -1.0\nkept: 2.9\n" in text


# ------------------------------------------------------------------ in a browser
_PAGE = """<!doctype html><html><head><meta charset="utf-8"><title>kapitza widget</title></head>
<body style="margin:0;background:#fff;font-family:sans-serif"><div id="cell" style="width:1000px"></div>
<script type="module">
// A stand-in for the notebook's widget manager: a model holding the traits, its messages to the
// kernel answered by kapitza.widgets.answer (exposed by the test as window.kernelAnswer).
const traits = TRAITS, handlers = {}, sets = [];
const fire = (name, arg) => (handlers[name] || []).forEach((f) => f(arg));
const model = {
  get: (k) => traits[k],
  set: (k, v) => { traits[k] = v; sets.push([k, v]); },
  save_changes() {},
  on: (name, f) => (handlers[name] = handlers[name] || []).push(f),
  off: (name, f) => { handlers[name] = (handlers[name] || []).filter((g) => g !== f); },
  send(msg) {
    if (msg.kind !== "ask") return;
    window.kernelAnswer(msg.url).then((reply) => fire("msg:custom", { id: msg.id, ...reply }));
  },
};
// Python sets a trait: the widget manager changes the model and says so.
window.fromPython = (k, v) => { traits[k] = v; fire("change:" + k); };
window.model = { traits, sets };
const url = URL.createObjectURL(new Blob([ESM], { type: "text/javascript" }));
const widget = (await import(url)).default, el = document.getElementById("cell");
window.cleanup = widget.render({ model, el });
window.ctl = el.kapitza;
</script></body></html>"""


def _wait_report(page, stable=None):
    page.wait_for_function("window.ctl && ctl.chart.data && ctl.panel.report && ctl.anim.m"
                           " && document.getElementById('cell').shadowRoot.getElementById('busy').hidden",
                           timeout=120000)
    if stable is not None:
        assert page.evaluate("ctl.panel.report.stable") is stable


@pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (apt-get install chromium)")
def test_the_widget_draws_in_chromium_from_its_own_module(tmp_path):
    from playwright.sync_api import sync_playwright

    w = Explorer(point=dict(eps=0.5, mu=0.3))
    traits = {k: getattr(w, k) for k in ("point", "l", "g", "drive", "zeta", "plane", "theta0")}
    html = _PAGE.replace("TRAITS", json.dumps(traits)).replace("ESM", json.dumps(w._esm))
    (tmp_path / "widget.html").write_text(html)
    SCREENS.mkdir(parents=True, exist_ok=True)
    args = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=args)
        try:
            page = browser.new_page(viewport={"width": 1020, "height": 1700})
            errors, asked = [], []
            page.on("pageerror", lambda e: errors.append(str(e)))

            def kernel_answer(url):
                asked.append(url)
                return answer(url)

            page.expose_function("kernelAnswer", kernel_answer)
            page.goto((tmp_path / "widget.html").as_uri())
            _wait_report(page, stable=True)
            assert page.evaluate("ctl.panel.report.zone") == 0
            assert {u.split("?")[0] for u in asked} >= {"/api/chart", "/api/verdict", "/api/point", "/api/motion"}
            page.wait_for_timeout(1500)  # the pendulum moves
            page.screenshot(path=str(SCREENS / "widget-01-in-a-cell.png"))

            # Python sets the point: the marker moves and the verdict follows
            T, A = (float(v) for v in kapitza.to_physical(2.9, 0.3, 1.0, kapitza.G_EARTH))
            page.evaluate(f"fromPython('point', {json.dumps(dict(eps=2.9, mu=0.3, T=T, A=A))})")
            page.wait_for_function(f"Math.abs(ctl.S.point.T - {T!r}) < 1e-12 && ctl.panel.report"
                                   f" && Math.abs(ctl.panel.report.eps - 2.9) < 1e-9", timeout=120000)
            assert page.evaluate("ctl.panel.report.stable") is bool(kapitza.is_stable(2.9, 0.3))
            assert page.evaluate("model.sets.filter(([k]) => k === 'point').length") == 0  # not echoed back

            # Python sets the drive: the chart is the sine's
            page.evaluate("fromPython('drive', 'sine')")
            page.wait_for_function("ctl.chart.data && ctl.chart.data.drive.startsWith('sine')", timeout=120000)

            # a click on the chart sets the model's point (what Python reads)
            xy = page.evaluate("ctl.pixel(1.2, 0.5)")
            page.mouse.click(xy["x"], xy["y"])
            page.wait_for_function("model.sets.some(([k]) => k === 'point')", timeout=60000)
            p_js = page.evaluate("model.sets.filter(([k]) => k === 'point').pop()[1]")
            assert p_js["eps"] == pytest.approx(1.2, abs=0.01) and p_js["mu"] == pytest.approx(0.5, abs=0.01)
            w.point = p_js  # as the widget manager hands it to Python
            assert w.point["T"] == p_js["T"] and w.point["eps"] == pytest.approx(p_js["eps"], rel=1e-12)
            _wait_report(page)
            assert page.evaluate("ctl.panel.report.drive").startswith("sine")
            page.wait_for_timeout(1500)
            page.screenshot(path=str(SCREENS / "widget-02-clicked-sine.png"))
            assert not errors, errors
            page.evaluate("cleanup()")
        finally:
            browser.close()


def test_the_tower_routes_are_answered_in_the_kernel():
    import json

    from kapitza.web import app as web_app
    from kapitza.widgets import answer

    got = answer("/api/tower/point?chain=0.2,0.2&masses=1,2&frequency=150&stroke=0.01")
    assert got["ok"]
    want = web_app.tower_point_answer(chain="0.2,0.2", masses="1,2", frequency=150.0, stroke=0.01)
    assert json.loads(got["json"])["stable"] == want["stable"] and json.loads(got["json"])["verdict"] == want["verdict"]
    band = json.loads(answer("/api/tower/chart?chain=0.2,0.2,0.2&grid=40&points=60")["json"])
    assert band["n_links"] == 3 and len(band["modal_lengths"]) == 3 and band["band"]
    motion = json.loads(answer("/api/tower/motion?chain=0.2,0.2&frequency=150&stroke=0.01&periods=20")["json"])
    assert motion["n_links"] == 2 and len(motion["theta"]) == 2 and motion["periods"] == 20
    damped = json.loads(answer("/api/tower/point?chain=0.2,0.15&masses=1,0.5&T=0.003&A=3000&joint_damping=0.004")["json"])
    want = web_app.tower_point_answer(chain="0.2,0.15", masses="1,0.5", T=0.003, A=3000.0, joint_damping=0.004)
    assert damped["joint_damping"] == 0.004 and damped["method"] == want["method"] != "modes"
    assert damped["growth"] == want["growth"] < 0
    bad = answer("/api/tower/point?chain=0.2,-1&frequency=150&stroke=0.01")
    assert not bad["ok"] and bad["detail"].startswith("chain must lie within") and "\n" not in bad["detail"]
