"""The explorer in a real browser: Playwright driving Debian's Chromium against ``kapitza serve``.

A user opens the page, zooms into a tongue far thinner than the whole chart's pixels, clicks a
stable point and watches the pendulum stand up (and, at another point, fall), follows a shared
link and exports a file. Each state is written as a screenshot to ``out/web-screens/``.
Skipped only where Chromium is not installed (``apt-get install chromium``).
"""
from __future__ import annotations

import time

import pytest

import kapitza
from web_server import ARGS, CHROMIUM, SCREENS, running_server

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (apt-get install chromium)")



@pytest.fixture(scope="module")
def site():
    from playwright.sync_api import sync_playwright

    SCREENS.mkdir(parents=True, exist_ok=True)
    with running_server() as (base, _, _proc), sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        context = browser.new_context(viewport={"width": 1600, "height": 1000}, accept_downloads=True)
        try:
            yield base, context
        finally:
            context.close()
            browser.close()


def _new_page(context, url):
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(url)
    page.wait_for_function("document.getElementById('chart').dataset.fetches >= 1", timeout=60000)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=60000)
    return page, errors


def _settle(page):
    """Wait until the chart has fetched the edges of the current view."""
    page.wait_for_timeout(300)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=60000)
    page.wait_for_timeout(100)


def _pixel(page, x, y):
    p = page.evaluate(f"kapitza.pixel({x!r}, {y!r})")
    return p["x"], p["y"]


def _clock(page):
    return page.evaluate("({t: +document.getElementById('clock').dataset.t, "
                         "frames: +document.getElementById('clock').dataset.frames, "
                         "fps: +document.getElementById('clock').dataset.fps})")


def test_explorer_as_a_user_sees_it(site):
    base, context = site
    page, errors = _new_page(context, base)
    assert "kapitza explorer" in page.title()
    zones = page.evaluate("kapitza.chart.data.zones.map(z => z.n)")
    assert zones == [0, 1, 2, 3]
    page.screenshot(path=str(SCREENS / "01-chart.png"))

    # -- zoom into zone 2 at mu = 0.6, about 1e-5 wide (a hundredth of a pixel on the whole chart):
    # the mouse wheel over the tongue
    lo, hi = (float(v) for v in kapitza.zone_edges(0.6, 2))
    mid, width = 0.5 * (lo + hi), hi - lo
    for _ in range(60):
        x, y = _pixel(page, mid, 0.6)
        page.mouse.move(x, y)
        page.mouse.wheel(0, -400)
        page.wait_for_timeout(15)
        view = page.evaluate("kapitza.S.views.arnold")
        if view["x1"] - view["x0"] < 12 * width:
            break
    _settle(page)
    view = page.evaluate("kapitza.S.views.arnold")
    assert view["x1"] - view["x0"] < 12 * width and view["x0"] < lo and hi < view["x1"]
    data = page.evaluate("kapitza.chart.data.zones.filter(z => z.n === 2).map(z => [z.lo, z.hi])")
    assert len(data) == 1
    # the tongue is drawn several pixels wide, its edges where the library puts them
    x_lo, _ = _pixel(page, lo, 0.6)
    x_hi, _ = _pixel(page, hi, 0.6)
    assert x_hi - x_lo > 40
    x, y = _pixel(page, mid, 0.6)
    page.mouse.move(x, y)
    page.wait_for_function("(document.getElementById('hover-verdict') || {}).textContent?.includes('stable, zone 2')",
                           timeout=30000)
    page.screenshot(path=str(SCREENS / "02-zoom-zone2.png"))

    # -- back to the whole chart and click a stable point: T = 0.15 s, A = 100 m/s^2 (zone 0)
    page.click("#reset-view")
    _settle(page)
    eps, mu = (float(v) for v in kapitza.to_arnold(0.15, 100.0))
    x, y = _pixel(page, eps, mu)
    page.mouse.click(x, y)
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('stable (zone 0)')",
                           timeout=30000)
    page.wait_for_function("kapitza.anim.m !== null", timeout=30000)
    a = _clock(page)
    page.wait_for_timeout(2000)
    b = _clock(page)
    assert b["t"] > a["t"] and b["frames"] > a["frames"] + 30      # the animation advances
    fps = b["fps"]
    print(f"animation: {fps:.1f} frames/s in headless Chromium")
    motion = page.evaluate("kapitza.anim.m.summary")
    assert motion["motion"]["max_abs_theta"] < 1.0                 # it stays up
    page.wait_for_timeout(1500)
    page.screenshot(path=str(SCREENS / "03-stable-point-animation.png"))

    # -- at T = 0.3 s the same rod falls (below zone 1's reach: unstable)
    page.fill("#T", "0.3")
    page.dispatch_event("#T", "input")
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('unstable')", timeout=30000)
    page.wait_for_function("kapitza.anim.m && kapitza.anim.m.T === 0.3", timeout=30000)
    assert page.evaluate("kapitza.anim.m.summary.motion.max_abs_theta") > 1.5
    page.select_option("#speed", "1")
    page.wait_for_timeout(3500)
    page.screenshot(path=str(SCREENS / "04-unstable-point-falls.png"))

    # -- a shared link reproduces the view and the point
    page.fill("#T", "0.15")
    page.dispatch_event("#T", "input")
    page.click("#plane-physical")
    _settle(page)
    x, y = page.evaluate("(() => { const r = document.getElementById('chart').getBoundingClientRect(); "
                         "return [r.left + r.width / 2, r.top + r.height / 2]; })()")
    page.mouse.move(x, y)
    page.mouse.wheel(0, -300)
    _settle(page)
    page.wait_for_timeout(400)
    url = page.url
    state = page.evaluate("({plane: kapitza.S.plane, view: kapitza.S.views.physical, point: kapitza.S.point})")
    assert "plane=physical" in url and "T=0.15" in url
    other, errors2 = _new_page(context, url)
    other.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('stable (zone 0)')",
                            timeout=30000)
    again = other.evaluate("({plane: kapitza.S.plane, view: kapitza.S.views.physical, point: kapitza.S.point})")
    assert again == state
    other.wait_for_timeout(1500)
    other.screenshot(path=str(SCREENS / "05-shared-link.png"))

    # -- export the chart as PNG and the motion as CSV
    with other.expect_download() as info:
        other.click("#x-chart-png")
    png = SCREENS / "06-export-chart.png"
    info.value.save_as(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with other.expect_download() as info:
        other.click("#x-motion-csv")
    csv = SCREENS / "06-export-motion.csv"
    info.value.save_as(csv)
    text = csv.read_text()
    assert text.startswith("# kapitza simulate: T = 0.15 s") and "t,theta,dtheta,pivot_y" in text
    assert errors == [] and errors2 == []
    other.close()
    page.close()


def test_animation_frame_rate(site):
    """The animation runs in headless Chromium (its frame rate is printed; the benchmark records it)."""
    base, context = site
    page, _ = _new_page(context, base + "?T=0.15&A=100&theta0=0.3")
    page.wait_for_function("kapitza.anim.m !== null", timeout=30000)
    page.wait_for_timeout(500)
    a, t0 = _clock(page), time.perf_counter()
    page.wait_for_timeout(3000)
    b, t1 = _clock(page), time.perf_counter()
    fps = (b["frames"] - a["frames"]) / (t1 - t0)
    print(f"animation: {fps:.1f} frames/s over 3 s in headless Chromium")
    # The rate itself is a benchmark figure (60 frames/s on the idle machine, benchmarks/README.md);
    # here the animation must be running, which holds however busy the machine is.
    assert b["frames"] > a["frames"]
    page.close()


def test_other_drive_with_damping_and_an_overlay(site):
    """A 30 % duty cycle with damping ratio 0.05, the sine drive's zones overlaid, from a link."""
    base, context = site
    page = context.new_page()
    page.goto(base + "?plane=arnold&x0=0&x1=2&y0=0&y1=1&drive=rectangular&duty=0.3&zeta=0.05&overlay=sine"
                     "&T=0.2&A=150&theta0=0.3")
    page.wait_for_function("kapitza.chart.data && kapitza.chart.overlay", timeout=120000)
    page.wait_for_function("kapitza.anim.m !== null", timeout=120000)
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').includes('motions decay')", timeout=120000)
    main, over = page.evaluate("[kapitza.chart.data.drive, kapitza.chart.overlay.drive]")
    assert "duty 0.3" in main or "0.3" in main
    assert over.startswith("sine")
    assert page.evaluate("kapitza.chart.data.zones.length") >= 1
    assert page.evaluate("kapitza.chart.overlay.zones.length") >= 1
    page.wait_for_timeout(1500)
    page.screenshot(path=str(SCREENS / "07-duty-cycle-damped-sine-overlay.png"))
    page.close()


def _colour(page, x, y):
    """RGB of the chart canvas at the data point (x, y)."""
    return page.evaluate(f"""(() => {{
        const c = document.getElementById('chart'), r = c.getBoundingClientRect(), p = kapitza.pixel({x!r}, {y!r});
        const k = c.width / r.width;
        return Array.from(c.getContext('2d').getImageData(Math.round((p.x - r.left) * k),
                                                          Math.round((p.y - r.top) * k), 1, 1).data).slice(0, 3);
    }})()""")


def test_a_drive_that_holds_the_rod_up_below_g(site):
    """A duty cycle of 0.8 holds the rod up with A < g: choosing it, the default view follows the
    drive up to its mu_max = 2 and zone 0 is drawn above mu = 1. A duty of 0.3 cannot hold it up
    beyond mu_max = 0.65: that band is greyed as always unstable, as A > g is not."""
    base, context = site
    page, errors = _new_page(context, base + "?plane=arnold")
    page.select_option("#drive", "rectangular")
    page.fill("#duty", "0.8")
    page.dispatch_event("#duty", "change")
    page.wait_for_function("kapitza.chart.data && kapitza.chart.data.drive.includes('0.8')", timeout=120000)
    _settle(page)
    assert page.evaluate("kapitza.S.views.arnold") == {"x0": 0, "x1": 4, "y0": 0, "y1": pytest.approx(2.0)}
    lo, mu = page.evaluate("[kapitza.chart.data.zones[0].lo, kapitza.chart.data.y_values]")
    assert any(v is not None and m > 1.5 for v, m in zip(lo, mu))
    page.screenshot(path=str(SCREENS / "08-duty-0.8-below-g.png"))
    page.fill("#duty", "0.3")
    page.dispatch_event("#duty", "change")
    page.wait_for_function("kapitza.chart.data && kapitza.chart.data.drive.includes('0.3')", timeout=120000)
    _settle(page)
    assert page.evaluate("kapitza.S.views.arnold.y1") == 1
    grey = (238, 240, 243)  # COLORS.forbidden
    assert _colour(page, 1.3, 0.85) == list(grey)     # beyond mu_max = 0.655: always unstable
    assert _colour(page, 1.3, 0.62) != list(grey)     # below it: not greyed
    page.screenshot(path=str(SCREENS / "09-duty-0.3-grey-beyond-mu-max.png"))
    assert not errors
    page.close()


def test_drive_lists_come_from_the_registry_and_the_triangle_wave_works(site):
    """Both lists hold every drive the server offers, the triangle wave among them; choosing it draws
    its chart (mu up to 1, the stroke coefficient 1/6 from the server), a click on a stable point gives
    the verdict and the pendulum moves."""
    base, context = site
    page, errors = _new_page(context, base + "?plane=arnold")
    drives = page.evaluate("[...document.getElementById('drive').options].map(o => o.value)")
    assert drives == ["square", "rectangular", "sine", "triangle"]   # the registry's order; steps needs lists
    assert page.evaluate("document.getElementById('drive').value") == "square"
    overlays = page.evaluate("[...document.getElementById('overlay').options].map(o => o.value)")
    assert overlays == ["", "square", "rectangular:0.3", "rectangular:0.7", "sine", "triangle"]
    assert not page.is_visible("#duty")                              # the square wave has no number
    page.select_option("#drive", "triangle")
    page.wait_for_function("kapitza.chart.data && kapitza.chart.data.drive.startsWith('triangle')", timeout=120000)
    _settle(page)
    assert not page.is_visible("#duty")
    assert page.evaluate("kapitza.info().stroke_coefficient") == pytest.approx(1 / 6)
    zones = page.evaluate("kapitza.chart.data.zones.map(z => z.n)")
    assert 0 in zones
    # a point inside zone 0 of the triangle wave, at mu = 0.3
    lo, hi = (float(v) for v in kapitza.zone_edges(0.3, 0, drive="triangle"))
    eps = 0.5 * (lo + hi)
    assert kapitza.is_stable(eps, 0.3, drive="triangle")
    x, y = _pixel(page, eps, 0.3)
    page.mouse.click(x, y)
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('stable (zone 0)')",
                           timeout=120000)
    assert page.evaluate("document.getElementById('verdict').dataset.drive") == "triangle"
    page.wait_for_function("kapitza.anim.m !== null", timeout=120000)
    page.wait_for_function("document.getElementById('verdict').dataset.state === 'report'", timeout=120000)
    page.wait_for_function("document.getElementById('safe-tilt') !== null", timeout=120000)
    assert "drive=triangle" in page.evaluate("location.search")
    page.wait_for_timeout(1500)
    page.screenshot(path=str(SCREENS / "10-triangle-wave.png"))
    # the link brings the triangle back; a drive the server does not list is not taken from a link
    page2, errors2 = _new_page(context, page.evaluate("location.href"))
    assert page2.evaluate("document.getElementById('drive').value") == "triangle"
    page2.close()
    page3, errors3 = _new_page(context, base + "?drive=bogus")
    assert page3.evaluate("kapitza.S.drive") == "square"
    page3.close()
    # the rectangular wave's duty field shows, named and bounded as the server describes the duty
    page.select_option("#drive", "rectangular")
    page.wait_for_function("kapitza.chart.data && kapitza.chart.data.drive.includes('0.3')", timeout=120000)
    assert page.is_visible("#duty")
    assert page.evaluate("[document.getElementById('duty-name').textContent, document.getElementById('duty').value]") \
        == ["duty", "0.3"]
    assert not errors and not errors2 and not errors3
    page.close()
