"""Results print as readable summaries: a short repr, a table for print, an HTML table in Jupyter."""
import json

import numpy as np
import pytest

import kapitza as K
from cli_util import run


def _results():
    eps = np.linspace(0.05, 3.0, 400)
    return [
        K.analyze(T=0.15, A=100.0),
        K.analyze(eps=0.5, mu=0.3, drive="sine"),
        K.floquet(0.5, 0.3),
        K.floquet(eps[:, None], np.linspace(0.01, 0.99, 300)[None, :]),
        K.stability_margin(0.5, 0.3),
        K.stability_margin(eps, 0.3),
        K.boundary_table(100.0, 2)[0],
        K.periodic_solution(A=100.0, index=1),
        K.simulate(0.1, 0.0, T=0.15, A=100.0, periods=200),
        K.simulate(0.1, 0.0, eps=1.06, mu=0.31, periods=20, model="linear"),
        K.stroboscopic_map(np.linspace(0.1, 0.5, 300), 0.0, T=0.15, A=100.0, periods=30, every=1),
        K.basin(0.15, 100.0, n_theta=30, n_dtheta=30, periods=10),
    ]


@pytest.mark.parametrize("obj", _results(), ids=lambda o: type(o).__name__)
def test_short_repr_table_and_html(obj):
    r = repr(obj)
    assert len(r) <= 300 and "\n" not in r and "array(" not in r, r
    text = str(obj)
    assert 3 <= len(text.splitlines()) <= 25 and "array(" not in text and "..." not in text.replace(" .. ", "")
    assert all(len(line) <= 160 for line in text.splitlines())
    html = obj._repr_html_()
    assert html.startswith("<table>") and html.count("<tr>") == len(obj.lines())


def test_trajectory_summary_says_whether_it_stays_up():
    up = K.simulate(0.1, 0.0, T=0.15, A=100.0, periods=50)
    s = up.summary()
    assert s["stays_up"] and s["falls_at"] is None and s["turns"] == 0
    assert s["max_abs_theta"] == pytest.approx(float(np.max(np.abs(up.theta))))
    assert "stays up" in repr(up) and "stays up" in str(up)
    down = K.simulate(0.1, 0.0, T=0.3, A=100.0, periods=20)
    d = down.summary()
    assert not d["stays_up"] and 0 < d["falls_at"] < 1.0
    assert abs(down.theta[np.searchsorted(down.t, d["falls_at"])]) >= np.pi / 2
    # the linear model's angle has no whole turns once it has grown
    lin = K.simulate(0.1, 0.0, T=0.3, A=100.0, periods=20, model="linear")
    assert lin.summary()["turns"] is None and "turns" not in str(lin)


def test_cli_simulate_prints_the_trajectory_summary(capsys):
    code, stdout, _ = run(["simulate", "--T", "0.15", "--A", "100", "--theta0", "0.1", "--periods", "5", "--json"],
                          capsys)
    assert code == 0
    out = json.loads(stdout)
    traj = K.simulate(0.1, 0.0, T=0.15, A=100.0, periods=5)
    assert out["motion"] == json.loads(json.dumps(traj.summary()))


def test_a_report_beside_a_zone_thinner_than_a_double_says_nothing_holds_it():
    # the sine's zone 10 at mu = 0.7 lies between two adjacent doubles: no knob setting is inside it
    r = K.analyze(eps=30.0, mu=0.7, drive="sine")
    assert r.nearest_zone == 10 and np.nextafter(r.eps_lo, np.inf) == r.eps_hi
    rows = dict(r.lines())
    assert "thinner than the spacing" in rows["to hold it"]
    assert "raise" not in str(r)


def test_a_zone_with_no_eps_inside_at_this_mu_may_still_be_reached_by_the_rig():
    # no double of eps lies inside the zone at the point's mu, but along the stroke (or the frequency)
    # the zone is wide, reached where mu is lower: the report names those knobs, not "nothing"
    from dataclasses import replace

    r = K.analyze(T=0.3, A=40.0, l=1.0, drive="sine")
    assert not r.stable and r.nearest_zone >= 0 and r.stroke_lo < r.stroke_hi
    e = float(np.nextafter(r.eps_lo, np.inf))
    thin = replace(r, eps_hi=e, T_hi=float(np.nextafter(r.T_lo, np.inf)))
    rows = thin.lines()
    held = [text for label, text in rows if label in ("to hold it", "")][-2:]
    assert "thinner than the spacing" not in str(thin)
    assert any("stroke" in t for t in held) and not any("lengthen" in t or "shorten" in t for t in held)
    # with every knob's range a single double, nothing holds it
    def next_up(v):
        return float(np.nextafter(v, np.inf))

    none = replace(thin, A_hi=next_up(r.A_lo), frequency_hi=next_up(r.frequency_lo), stroke_hi=next_up(r.stroke_lo))
    assert "thinner than the spacing" in dict(none.lines())["to hold it"]


def test_a_range_a_few_doubles_wide_is_written_with_the_digits_that_tell_its_ends_apart():
    from dataclasses import replace

    r = K.analyze(T=0.3, A=40.0, l=1.0, drive="sine")
    lo = r.stroke_lo
    hi = lo
    for _ in range(4):
        hi = float(np.nextafter(hi, np.inf))
    thin = replace(r, eps_hi=float(np.nextafter(r.eps_lo, np.inf)), stroke_hi=hi,
                   frequency_hi=float(np.nextafter(r.frequency_lo, np.inf)))
    # the zone's own lines too: eps (here one double apart) and the frequency with the digits that differ
    zone_line = dict(thin.lines())["zone (nearest)"]
    lo_s, hi_s = zone_line.split(": ", 1)[1].split(" < eps < ")
    assert lo_s != hi_s and float(lo_s) == thin.eps_lo and float(hi_s) == thin.eps_hi
    text = [d["text"] for d in thin.directions if d["knob"] == "stroke"][0]
    a, b = text.split(" to ", 1)[1].split(" mm")[0].split("-")
    assert a != b and float(a.replace(",", "")) < float(b.replace(",", ""))
    # the frequency's range is one double: left out; with the stroke's one double too, nothing holds it,
    # and the report says which (eps has no double inside the zone either)
    assert not any("the frequency to" in t for _, t in thin.lines())
    none = replace(thin, stroke_hi=float(np.nextafter(lo, np.inf)), A_hi=float(np.nextafter(r.A_lo, np.inf)))
    assert dict(none.lines())["to hold it"].endswith("(no eps inside it)")
    wide_eps = replace(none, eps_hi=r.eps_hi)
    assert dict(wide_eps.lines())["to hold it"].endswith("(no setting of the knobs inside it)")
