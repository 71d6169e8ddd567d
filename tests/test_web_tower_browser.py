"""The tower in the explorer, in a real browser (Playwright driving Debian's Chromium against
``kapitza serve``): a user chooses three links, sees the tower's band on the frequency-stroke plane,
clicks a point inside it and sees the tower stand and move; a point below it falls; back at one link
the single pendulum's chart returns. Screenshots go to ``out/web-screens/``."""
from __future__ import annotations


import numpy as np
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
        context = browser.new_context(viewport={"width": 1600, "height": 1000})
        try:
            yield base, context
        finally:
            context.close()
            browser.close()


def _settle(page):
    page.wait_for_timeout(300)
    page.wait_for_function("document.getElementById('busy').hidden", timeout=90000)


def _opened(site):
    """A new page of the explorer, loaded and settled, and the list its script errors go to."""
    base, context = site
    page = context.new_page()
    errors: list = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(base)
    page.wait_for_function("document.getElementById('chart').dataset.fetches >= 1", timeout=90000)
    _settle(page)
    return page, errors


def _chart_rgb(page, x, y):
    """The chart canvas's colour at the page point (x, y)."""
    return page.evaluate(f"""(() => {{ const c = document.getElementById('chart'), r = c.getBoundingClientRect(),
        k = c.width / r.width, d = c.getContext('2d').getImageData(Math.round(({x} - r.left) * k),
        Math.round(({y} - r.top) * k), 1, 1).data; return [d[0], d[1], d[2]]; }})()""")


def _deep_inside(stable):
    """A grid cell of the band whose neighbours within 3 cells are all stable (the band's middle)."""
    s = np.asarray(stable, dtype=bool)
    ok = s.copy()
    for di in range(-3, 4):
        for dj in range(-3, 4):
            ok &= np.roll(np.roll(s, di, 0), dj, 1)
    ok[:3], ok[-3:], ok[:, :3], ok[:, -3:] = False, False, False, False
    cells = np.argwhere(ok)
    assert len(cells), "the band has no cell far from its edges"
    return cells[len(cells) // 2]


def test_three_link_tower_stands_in_its_band(site):
    page, errors = _opened(site)
    context = page.context
    assert page.is_visible("#links") and not page.is_visible("#link-L1")   # one link: the single pendulum

    # -- three links of 0.2 m: the chart becomes the tower's band on the rig plane
    page.select_option("#links", "3")
    page.wait_for_function("document.getElementById('chart').dataset.tower === '3'", timeout=90000)
    _settle(page)
    assert page.is_visible("#link-L3") and not page.is_visible("#link-L4")
    assert page.evaluate("kapitza.S.plane") == "rig" and page.is_disabled("#plane-arnold")
    band = page.evaluate("kapitza.chart.tower")
    tower = kapitza.Chain([0.2, 0.2, 0.2])
    np.testing.assert_allclose(band["modal_lengths"], tower.modal_lengths, rtol=1e-14)
    stable = np.array(band["band"]["stable"], dtype=bool)
    assert 0.05 < stable.mean() < 0.6
    i, j = _deep_inside(stable)
    f, s = band["band"]["frequency"][j], band["band"]["stroke"][i]
    assert kapitza.analyze_chain(tower, frequency=f, stroke=s).stable
    p = page.evaluate(f"kapitza.pixel({f!r}, {s!r})")
    r, g, b = _chart_rgb(page, p["x"], p["y"])
    assert b > r + 30 and g > r + 20                                    # drawn: the band's blue shade
    page.screenshot(path=str(SCREENS / "tower-01-band.png"))
    page.locator("#tower-fields").scroll_into_view_if_needed()
    page.locator(".controls").screenshot(path=str(SCREENS / "tower-00-links.png"))
    assert not page.is_visible("#zeta") and not page.is_visible("#rig-rod")  # the single pendulum's only

    # -- a click inside the band: the tower stands, and its motion plays
    page.mouse.click(p["x"], p["y"])
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('stable')",
                           timeout=90000)
    assert "The tower stands" in page.inner_text("#verdict")
    page.wait_for_function("kapitza.anim.m && kapitza.anim.m.tower === true", timeout=120000)
    m = page.evaluate("({n: kapitza.anim.m.n_links, toppled: kapitza.anim.m.toppled, "
                      "top: Math.max(...kapitza.anim.m.thetas.flat().map(Math.abs))})")
    assert m["n"] == 3 and m["toppled"] is False and m["top"] < 1.0
    t0 = float(page.evaluate("document.getElementById('clock').dataset.t"))
    page.wait_for_timeout(1500)
    t1 = float(page.evaluate("document.getElementById('clock').dataset.t"))
    assert t1 != t0                                                     # the animation runs
    assert page.evaluate("document.getElementById('stage').dataset.tower") == "3"
    assert "top link" in page.inner_text(".plots")
    page.mouse.move(5, 990)                                             # the pointer off the chart
    page.wait_for_timeout(200)
    page.screenshot(path=str(SCREENS / "tower-02-stands.png"))

    # -- the address bar holds the tower, its view and the point: a shared link shows the same
    shared = page.url
    assert "links=3" in shared and "chain=0.2%2C0.2%2C0.2" in shared
    other = context.new_page()
    other.goto(shared)
    other.wait_for_function("document.getElementById('chart').dataset.tower === '3'", timeout=90000)
    other.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('stable')",
                            timeout=90000)
    assert other.evaluate("kapitza.S.views.tower.x0") == pytest.approx(band["view"]["f_min"], rel=1e-12)
    other.close()

    # -- far below the band in frequency the tower falls
    lo_f = band["view"]["f_min"] * 1.3
    p = page.evaluate(f"kapitza.pixel({lo_f!r}, {s!r})")
    page.mouse.click(p["x"], p["y"])
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('unstable')",
                           timeout=90000)
    assert "The tower falls" in page.inner_text("#verdict")
    page.wait_for_function("kapitza.anim.m && kapitza.anim.m.tower && kapitza.anim.m.toppled", timeout=120000)
    page.select_option("#speed", "1")
    page.mouse.move(5, 990)
    page.wait_for_timeout(2500)
    page.screenshot(path=str(SCREENS / "tower-03-falls.png"))

    # -- the projector view shows the tower large
    page.click("#projector")
    page.wait_for_timeout(800)
    page.screenshot(path=str(SCREENS / "tower-04-projector.png"))
    page.click("#projector")

    # -- back to one link: the single pendulum's chart and verdict
    page.select_option("#links", "1")
    page.wait_for_function("kapitza.chart.data && kapitza.chart.data.zones.length > 0", timeout=90000)
    page.wait_for_function("/^The pendulum/.test(document.getElementById('verdict').innerText)", timeout=90000)
    assert not page.is_disabled("#plane-arnold") and page.is_visible("#zeta")
    assert errors == []


def test_tower_with_joint_friction(site):
    """A user sets joint friction on a two-link tower: the band is the damped tower's (the 2N
    monodromy's, said in the caption), a click gives the damped verdict and motion, and the address
    bar keeps the friction."""
    page, errors = _opened(site)
    page.select_option("#links", "2")
    page.wait_for_function("document.getElementById('chart').dataset.tower === '2'", timeout=90000)
    _settle(page)
    free = page.evaluate("kapitza.chart.tower")
    assert free["band_method"] == "modes" and free["joint_damping"] == 0

    page.fill("#link-c", "0.5")
    page.press("#link-c", "Tab")
    page.wait_for_function("kapitza.chart.tower && kapitza.chart.tower.joint_damping === 0.5", timeout=120000)
    _settle(page)
    band = page.evaluate("kapitza.chart.tower")
    tower = kapitza.Chain([0.2, 0.2], joint_damping=0.5)
    assert band["band_method"] == "2N monodromy" and len(band["band"]["stable"]) == 60
    v = band["view"]
    ref = kapitza.tower_curves(tower, frequency_range=(v["f_min"], v["f_max"]),
                               stroke_range=(v["stroke_min"], v["stroke_max"]), points=300, grid=60)
    stable = np.array(band["band"]["stable"], dtype=bool)
    np.testing.assert_array_equal(stable, ref.stable)
    assert "Joint friction c = 0.5 N m s/rad" in page.inner_text("#caption")

    # a click in the damped band: the 2N monodromy's verdict (motions decay) and the damped motion
    i, j = _deep_inside(stable)
    f, s = band["band"]["frequency"][j], band["band"]["stroke"][i]
    p = page.evaluate(f"kapitza.pixel({f!r}, {s!r})")
    page.mouse.click(p["x"], p["y"])
    page.wait_for_function("(document.getElementById('verdict').dataset.verdict || '').startsWith('stable')",
                           timeout=120000)
    assert "multipliers inside the unit circle" in page.evaluate("document.getElementById('verdict').dataset.verdict")
    page.wait_for_function("kapitza.anim.m && kapitza.anim.m.tower === true && kapitza.anim.m.joint_damping === 0.5",
                           timeout=120000)
    assert "joint_damping=0.5" in page.url
    assert page.evaluate("kapitza.chart.tower && kapitza.chart.tower.joint_damping") == 0.5  # the band still shown
    page.mouse.move(5, 990)
    page.wait_for_timeout(1500)
    page.screenshot(path=str(SCREENS / "tower-05-friction.png"))
    page.locator("#tower-fields").scroll_into_view_if_needed()
    page.locator(".controls").screenshot(path=str(SCREENS / "tower-06-friction-field.png"))
    assert errors == []
