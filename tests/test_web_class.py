"""The explorer in front of a class and at a rig: Playwright driving Debian's Chromium.

A teacher opens the page (a pendulum already stands), frames zone 2 and clicks it (stable, but
only for tiny tilts: the page says this start will fall and offers a safe one), switches the drive
(the panel greys until the new drive's answer), projects the real pendulum alone; an engineer
enters a 50 Hz shaker with 3 mm amplitude and a 25 cm rod in rig mode and reads what would hold
it up; a phone at 390 x 844 shows the page without sideways scrolling and zooms the chart with
two fingers; the API page renders with the network cut. Screenshots go to ``out/web-screens/``.
"""
from __future__ import annotations

import urllib.request

import numpy as np
import pytest

import kapitza
from web_server import ARGS, CHROMIUM, SCREENS, running_server

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (apt-get install chromium)")

LONG = 120_000  # ms: the machine may be loaded
REPORT = 400_000  # ms: another drive's full report (its margins are root solves) on a loaded machine


@pytest.fixture(scope="module")
def site():
    from playwright.sync_api import sync_playwright

    SCREENS.mkdir(parents=True, exist_ok=True)
    with running_server() as (base, _, _proc), sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            yield base, browser
        finally:
            browser.close()


def _open(browser, url, **context):
    ctx = browser.new_context(**({"viewport": {"width": 1600, "height": 1000}} | context))
    page = ctx.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(url, timeout=LONG)  # the page's files wait behind earlier tests' computations on a loaded machine
    page.wait_for_function("document.getElementById('chart').dataset.fetches >= 1", timeout=REPORT)
    return page, errors


def _report(page):
    page.wait_for_function("document.getElementById('verdict').dataset.state === 'report'", timeout=REPORT)
    return page.evaluate("kapitza.panel.report")


def _pixel(page, x, y):
    p = page.evaluate(f"kapitza.pixel({x!r}, {y!r})")
    return p["x"], p["y"]


def test_first_load_shows_a_standing_pendulum(site):
    base, browser = site
    page, errors = _open(browser, base)
    rep = _report(page)
    assert rep["stable"] and rep["zone"] == 0
    page.wait_for_function("kapitza.anim.m !== null", timeout=LONG)
    motion = page.evaluate("kapitza.anim.m.summary.motion")
    assert motion["stays_up"]
    page.wait_for_function("document.getElementById('safe-tilt') !== null", timeout=LONG)
    text = page.inner_text("#verdict")
    assert text.startswith("The pendulum stays up") and "stands for starting tilts below" in text
    assert page.query_selector("#will-fall") is None          # 0.1 rad is a safe start in zone 0
    assert not page.evaluate("kapitza.chart.legendBox.narrow")   # the full legend on a desktop
    page.wait_for_timeout(1200)
    page.screenshot(path=str(SCREENS / "10-first-load-standing.png"))
    assert not errors
    page.context.close()


def test_zone_2_is_framed_clicked_and_the_start_will_fall(site):
    base, browser = site
    page, errors = _open(browser, base)
    _report(page)
    mu0 = float(np.sqrt(9.81 / 100.0))  # the demo point's mu: the band 'show zone' frames
    lo, hi = (float(v) for v in kapitza.zone_edges(mu0, 2))
    page.select_option("#zone-n", "2")
    page.click("#show-zone")
    page.wait_for_function(f"kapitza.S.views.arnold.x1 - kapitza.S.views.arnold.x0 < {20 * (hi - lo)!r}", timeout=LONG)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=LONG)
    page.wait_for_timeout(300)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=LONG)
    v = page.evaluate("kapitza.S.views.arnold")
    assert v["x0"] < lo < hi < v["x1"] and v["y0"] < mu0 < v["y1"]
    # both edges are on screen across the whole height of the view
    for mu in (v["y0"] + 0.02 * (v["y1"] - v["y0"]), v["y1"] - 0.02 * (v["y1"] - v["y0"])):
        a, b = (float(x) for x in kapitza.zone_edges(mu, 2))
        assert v["x0"] < a < b < v["x1"]
    # the magnified inset: zone 2's two edges over its whole range of mu, as kapitza chart draws them
    page.wait_for_function("kapitza.inset.data && kapitza.inset.data.n === 2 && !document.getElementById('inset').hidden",
                           timeout=LONG)
    rows = page.evaluate("kapitza.inset.data.rows")
    assert len(rows) > 100 and rows[0][0] < 0.01 and rows[-1][0] > 0.5
    for mu, a, b in rows[::40]:
        ea, eb = (float(x) for x in kapitza.zone_edges(mu, 2))
        assert a == pytest.approx(ea, rel=1e-12) and b == pytest.approx(eb, rel=1e-12)
    page.screenshot(path=str(SCREENS / "11-show-zone-2.png"))
    x, y = _pixel(page, 0.5 * (lo + hi), mu0)
    page.mouse.click(x, y)
    rep = _report(page)
    assert rep["stable"] and rep["zone"] == 2
    page.wait_for_function("document.getElementById('safe-tilt') !== null", timeout=LONG)
    safe = float(page.get_attribute("#safe-tilt", "data-safe"))
    assert 0 < safe < 0.01
    assert page.query_selector("#will-fall") is not None
    assert "will fall" in page.inner_text("#will-fall")
    page.wait_for_timeout(800)
    page.screenshot(path=str(SCREENS / "12-zone-2-will-fall.png"))
    page.click("#set-safe")
    assert 0 < page.evaluate("kapitza.S.theta0") < safe
    assert page.query_selector("#will-fall") is None
    # the linear twin is bounded here: its note says so, not that it runs away
    assert "runs away" not in page.content()
    assert not errors
    page.context.close()


def test_switching_the_drive_greys_the_panel_until_the_new_report(site):
    base, browser = site
    page, errors = _open(browser, base + "?T=0.15&A=100")
    rep = _report(page)
    assert rep["drive"].startswith("square")
    # every state the banner shows is logged with the drive it belongs to
    page.evaluate("""(() => { window.seen = [];
        new MutationObserver(() => { const el = document.getElementById('verdict');
            window.seen.push([el.dataset.state, el.dataset.drive || '', el.className]); })
        .observe(document.getElementById('verdict'), {attributes: true, childList: true, subtree: true}); })()""")
    page.select_option("#drive", "sine")
    assert "busy" in page.get_attribute("#verdict", "class")
    assert "computing" in page.inner_text("#verdict")
    page.screenshot(path=str(SCREENS / "13-sine-computing.png"))
    page.wait_for_function("document.getElementById('verdict').dataset.drive === 'sine' && "
                           "document.getElementById('verdict').dataset.state === 'report'", timeout=REPORT)
    assert page.evaluate("kapitza.panel.report.drive").startswith("sine")
    seen = page.evaluate("window.seen")
    # (the square wave's safe tilt may land before the switch; from the switch on, only sine answers)
    first = next(i for i, s in enumerate(seen) if s[0] == "busy")
    after = [drive for state, drive, _ in seen[first:] if state in ("verdict", "report")]
    assert after and all(drive == "sine" for drive in after)
    page.screenshot(path=str(SCREENS / "14-sine-report.png"))
    assert not errors
    page.context.close()


def test_rig_mode_for_a_50_hz_shaker(site):
    base, browser = site
    page, errors = _open(browser, base)
    _report(page)
    page.select_option("#drive", "sine")
    page.check("#rig-mode")
    page.fill("#rig-rod", "0.25")
    page.dispatch_event("#rig-rod", "change")
    page.select_option("#rig-given", "amplitude")
    page.fill("#rig-f", "50")
    page.dispatch_event("#rig-f", "input")
    page.fill("#rig-x", "3")
    page.dispatch_event("#rig-x", "input")
    page.wait_for_function("kapitza.S.point && Math.abs(1 / (2 * kapitza.S.point.T) - 50) < 1e-9", timeout=LONG)
    # the verdict comes at once (the multipliers alone), the directions with the full report
    page.wait_for_function("['verdict', 'report'].includes(document.getElementById('verdict').dataset.state) && "
                           "document.getElementById('verdict').dataset.drive === 'sine' && "
                           "Math.abs(kapitza.panel.verdict.A - 296.088132) < 1e-3", timeout=LONG)
    assert not page.evaluate("kapitza.panel.verdict.stable")
    page.wait_for_function("document.getElementById('verdict').dataset.state === 'report' && "
                           "document.getElementById('verdict').dataset.drive === 'sine' && "
                           "Math.abs(kapitza.panel.report.A - 296.088132) < 1e-3", timeout=REPORT)
    rep = page.evaluate("kapitza.panel.report")
    assert not rep["stable"] and rep["l"] == pytest.approx(0.25 * 2 / 3, rel=1e-10)
    text = page.inner_text("#verdict")
    assert text.startswith("The pendulum falls")
    assert "95.9 Hz" in text and "5.76" in text          # Kapitza's threshold, the amplitude that holds it
    assert "30.18 g" in page.inner_text("#rig-g")
    page.wait_for_timeout(600)
    page.screenshot(path=str(SCREENS / "15-rig-50hz-3mm-25cm.png"))
    page.select_option("#rig-given", "stroke")
    page.wait_for_function("document.getElementById('verdict').dataset.state === 'report' && "
                           "document.getElementById('verdict').innerText.includes('stroke to 11.5')", timeout=REPORT)
    # the frequency-stroke chart, sized to the rig: the point inside, zone 0's band in view
    assert page.evaluate("kapitza.S.plane") == "rig"
    page.wait_for_function("kapitza.chart.data && kapitza.chart.data.plane === 'rig'", timeout=LONG)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=LONG)
    d = page.evaluate("kapitza.chart.data")
    v = page.evaluate("kapitza.S.views.rig")
    assert v["x0"] < 50 < v["x1"] and v["y0"] < 0.006 < v["y1"]
    zone0 = next(z for z in d["zones"] if z["n"] == 0)
    j = int(np.argmin(np.abs(np.array(d["y_values"]) - 0.006)))
    assert zone0["lo"][j] == pytest.approx(95.94 * 0.006 / d["y_values"][j], rel=0.05)
    # the upper (period-doubling) edge levels off towards its stroke as the frequency grows: drawn
    # all the way out of the view, not stopped at the last finite sample
    s_top = min(s for s, f in zip(d["y_values"], zone0["hi"]) if f is not None and f < 1e300)
    assert v["x1"] > 90 and 0.10 < s_top < 0.16
    red = page.evaluate("""(([f, s]) => { const c = document.getElementById('chart'), r = c.getBoundingClientRect();
        const p = kapitza.pixel(f, s), k = c.width / r.width, ctx = c.getContext('2d');
        const px = ctx.getImageData(Math.round((p.x - r.left) * k) - 6 * k, Math.round((p.y - r.top) * k) - 4 * k,
                                    12 * k, 8 * k).data;
        for (let i = 0; i < px.length; i += 4) if (px[i] > 150 && px[i + 1] < 110 && px[i + 2] < 110) return true;
        return false; })""", [0.97 * v["x1"], s_top])
    assert red
    page.wait_for_timeout(600)
    page.screenshot(path=str(SCREENS / "16-frequency-stroke-chart.png"))
    assert not errors
    page.context.close()


def test_hover_box_stays_inside_the_chart(site):
    base, browser = site
    page, errors = _open(browser, base + "?plane=arnold")
    _report(page)
    box = page.evaluate("(() => { const r = document.getElementById('chart').getBoundingClientRect(); "
                        "return [r.left, r.top, r.right, r.bottom]; })()")
    x, y = _pixel(page, 3.95, 0.5)  # an unstable point at the right edge
    page.mouse.move(x, y)
    page.wait_for_function("(document.getElementById('hover-verdict') || {}).textContent?.includes('falls')",
                           timeout=LONG)
    page.wait_for_timeout(200)
    r = page.evaluate("(() => { const r = document.getElementById('hover').getBoundingClientRect(); "
                      "return [r.left, r.top, r.right, r.bottom]; })()")
    assert box[0] <= r[0] and r[2] <= box[2] + 0.5 and box[1] <= r[1] and r[3] <= box[3] + 0.5
    page.screenshot(path=str(SCREENS / "17-hover-right-edge.png"))
    assert not errors
    page.context.close()


def test_projector_view(site):
    base, browser = site
    page, errors = _open(browser, base, viewport={"width": 1280, "height": 720})
    _report(page)
    page.wait_for_function("kapitza.anim.m !== null", timeout=LONG)
    page.click("#projector")
    assert not page.is_visible("#chart-panel") and page.is_visible("#stage")
    h = page.evaluate("document.getElementById('stage').getBoundingClientRect().height")
    assert h > 400
    page.wait_for_timeout(1200)
    page.screenshot(path=str(SCREENS / "18-projector.png"))
    page.keyboard.press("Escape")
    assert page.is_visible("#chart-panel")
    assert not errors
    page.context.close()


def test_phone_layout_and_pinch_zoom(site):
    base, browser = site
    page, errors = _open(browser, base, viewport={"width": 390, "height": 844}, device_scale_factor=2,
                         is_mobile=True, has_touch=True)
    _report(page)
    page.wait_for_function("kapitza.anim.m !== null", timeout=LONG)
    page.wait_for_timeout(800)
    assert page.evaluate("document.documentElement.scrollWidth") <= 390
    # the legend leaves the plot visible: the short one, under half the chart's width and a quarter of its height
    box = page.evaluate("kapitza.chart.legendBox")
    w, h = page.evaluate("[document.getElementById('chart').clientWidth, document.getElementById('chart').clientHeight]")
    assert box["narrow"] and box["w"] < 0.5 * w and box["h"] < 0.25 * h
    page.screenshot(path=str(SCREENS / "19-phone-390.png"), full_page=True)
    # two fingers spread apart on the chart zoom the chart, not the page
    before = page.evaluate("kapitza.S.views.arnold")
    r = page.evaluate("(() => { const r = document.getElementById('chart').getBoundingClientRect(); "
                      "return [r.left + r.width / 2, r.top + r.height / 2]; })()")
    cdp = page.context.new_cdp_session(page)
    cx, cy = r

    def touch(kind, d):
        pts = [] if kind == "touchEnd" else [{"x": cx - d, "y": cy, "id": 1}, {"x": cx + d, "y": cy, "id": 2}]
        cdp.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": pts})

    touch("touchStart", 30)
    for d in range(35, 121, 5):
        touch("touchMove", d)
        page.wait_for_timeout(16)
    touch("touchEnd", 0)
    page.wait_for_timeout(300)
    after = page.evaluate("kapitza.S.views.arnold")
    assert after["x1"] - after["x0"] < 0.6 * (before["x1"] - before["x0"])
    assert page.evaluate("window.visualViewport.scale") == pytest.approx(1.0)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=LONG)
    page.screenshot(path=str(SCREENS / "20-phone-pinched.png"))
    assert not errors
    page.context.close()


def test_api_docs_render_with_the_network_cut(site):
    base, browser = site
    for path in ("", "docs"):
        with urllib.request.urlopen(base + path, timeout=30) as r:
            html = r.read().decode()
        assert "http://" not in html and "https://" not in html, path
    ctx = browser.new_context(viewport={"width": 1280, "height": 900})
    outside = []

    def only_local(route):
        if route.request.url.startswith(base):
            return route.continue_()
        outside.append(route.request.url)
        return route.abort()

    ctx.route("**/*", only_local)
    page = ctx.new_page()
    page.goto(base + "docs", timeout=REPORT)
    page.wait_for_selector(".swagger-ui .opblock", timeout=LONG)
    assert "/api/point" in page.inner_text("body")
    page.screenshot(path=str(SCREENS / "21-docs-offline.png"))
    assert outside == []
    ctx.close()
