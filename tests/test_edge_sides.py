"""Zone edges and verdicts agree at every double, and the rotation number agrees with the trace.

Zone ``n`` is ``eps_lo < eps < eps_hi`` (the docstring of :func:`kapitza.zone_edges`): the reported
edges are the doubles on the unstable side, so ``is_stable`` (certified to the last bit) is False at
each edge and True at its neighbour inside the zone. Off the zones the multipliers are real, so the
rotation angle is ``k pi`` with ``k`` even where they are positive (``tr M > 0``) and odd where
they are negative.
"""
import numpy as np
import pytest

import kapitza as K

DRIVES = [K.RectangularWave(0.3), K.RectangularWave(0.8), K.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3]),
          K.TriangleWave()]


@pytest.mark.parametrize("drive", [K.SquareWave()] + DRIVES, ids=lambda d: d.text())
def test_each_reported_edge_is_the_last_unstable_double(drive):
    rng = np.random.default_rng(7)
    mu = rng.uniform(0.05, min(0.95, 0.95 * drive.mu_max), 6)
    lo, hi = K.zone_edges(mu[:, None], np.arange(4)[None, :], drive=drive)
    checked = 0
    for m, a, b in zip(np.repeat(mu, 4), lo.ravel(), hi.ravel()):
        inner_a, inner_b = np.nextafter(a, np.inf), np.nextafter(b, -np.inf)
        if not (np.isfinite(a) and np.isfinite(b) and inner_a <= inner_b):
            continue  # no such zone here, or none with a double inside
        st = K.is_stable(np.array([a, inner_a, inner_b, b]), m, drive=drive)
        assert st.tolist() == [False, True, True, False], (m, a, b)
        checked += 1
    assert checked >= 12


def test_the_sine_drives_edges_are_on_the_certified_sides():
    # the Sturm counts' crossings lie within the rounding band of the certified verdict's change:
    # before they were moved, about half of these edges had is_stable True at the edge itself or
    # False at its neighbour inside
    mu = np.array([0.2, 0.45, 0.6, 0.85])
    lo, hi = K.zone_edges(mu[:, None], np.arange(4)[None, :], drive="sine")
    checked = 0
    for m, a, b in zip(np.repeat(mu, 4), lo.ravel(), hi.ravel()):
        inner_a, inner_b = np.nextafter(a, np.inf), np.nextafter(b, -np.inf)
        if not inner_a <= inner_b:
            continue
        st = K.is_stable(np.array([a, inner_a, inner_b, b]), m, drive="sine")
        assert st.tolist() == [False, True, True, False], (m, a, b)
        checked += 1
    assert checked >= 14


def test_the_sine_drives_verdicts_alone_are_the_certified_ones():
    # SineWave._verdict0 (long double counts where the double trace has lost its digits) against
    # is_stable (the full certified path, the exact trace there), on 13 doubles about each edge
    mu = np.array([0.3, 0.85, 0.93])
    lo, hi = K.zone_edges(mu[:, None], np.arange(3)[None, :], drive="sine", certify=False)
    eps = (np.concatenate([lo.ravel(), hi.ravel()]).view(np.int64)[:, None] + np.arange(-6, 7)).view(np.float64)
    m = np.broadcast_to(np.tile(np.repeat(mu, 3), 2)[:, None], eps.shape)
    assert np.array_equal(K.SineWave()._verdict0(eps, m), K.is_stable(eps, m, drive="sine"))


def test_the_square_waves_edges_about_thin_zones_are_the_certified_ones():
    # zones 1-3 near mu = 0.88-0.98 are a few doubles wide: the closed forms' roots lie up to 4 ulp
    # from the certified change there, so an edge could sit inside the zone or a zone of one stable
    # double be missed; every double from 8 below to 8 above the zone is asked
    mu = np.linspace(0.86, 0.99, 200)
    checked = 0
    for n in (1, 2, 3):
        lo, hi = K.zone_edges(mu, n)
        for m, a, b in zip(mu, lo, hi):
            if not (np.isfinite(a) and a < b and np.array(b).view(np.int64) - np.array(a).view(np.int64) <= 64):
                continue   # (no zone, or a wide one: test_each_reported_edge_is_the_last_unstable_double)
            bits = (np.array(a).view(np.int64) + np.arange(-8, 0)).tolist()
            bits += list(range(int(np.array(a).view(np.int64)), int(np.array(b).view(np.int64)) + 9))
            x = np.array(bits, np.int64).view(np.float64)
            st = K.is_stable(x, m)
            want = (x > a) & (x < b)
            if st.any():
                assert np.array_equal(st, want), (n, m, a, b)
                checked += 1
    assert checked >= 60


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: d.text())
def test_the_rotation_number_off_the_zones_has_the_parity_of_the_trace(drive):
    rng = np.random.default_rng(11)
    eps = rng.uniform(0.05, 12.0, 400)
    mu = rng.uniform(0.0, 1.2 * drive.mu_max, 400)
    f = K.floquet(eps, mu, drive=drive)
    rho = np.asarray(K.rotation_number(eps, mu, drive=drive))
    off = ~np.asarray(f.stable) & np.isfinite(f.trace)
    assert off.sum() > 100
    two_rho = 2.0 * rho[off]
    assert np.all(two_rho == np.rint(two_rho))
    odd = np.remainder(np.rint(two_rho), 2.0) == 1.0
    assert np.array_equal(odd, np.asarray(f.trace)[off] < 0)


def _turn_of_1_0(eps, mu, drive, sub=64):
    """The turn of the direction ``(1, 0)`` over the period, in units of pi, carried through each
    segment's exact flow in mpmath in ``sub`` parts (each turns it by less than pi / 2)."""
    import mpmath

    levels, fractions = drive._steps()
    with mpmath.workdps(60):
        E, m2 = 8 * mpmath.mpf(eps) ** 2, mpmath.mpf(mu) ** 2
        x, y, total = mpmath.mpf(1), mpmath.mpf(0), mpmath.mpf(0)
        for s, f in zip(levels, fractions):
            k, h = E * (m2 + mpmath.mpf(s)), 2 * mpmath.mpf(f) / sub
            w = mpmath.sqrt(abs(k))
            if k > 0:
                S = (mpmath.cosh(w * h), mpmath.sinh(w * h) / w, w * mpmath.sinh(w * h), mpmath.cosh(w * h))
            else:
                S = (mpmath.cos(w * h), mpmath.sin(w * h) / w, -w * mpmath.sin(w * h), mpmath.cos(w * h))
            for _ in range(sub):
                x1, y1 = S[0] * x + S[1] * y, S[2] * x + S[3] * y
                total += mpmath.atan2(x * y1 - y * x1, x * x1 + y * y1)
                n = mpmath.sqrt(x1 * x1 + y1 * y1)
                x, y = x1 / n, y1 / n
        return float(-total / mpmath.pi)


def test_a_huge_positive_trace_has_the_rotation_number_of_its_gap():
    # tr M/2 ~ 7.5e46 where the segment products reach e^147, beside a thin zone: the doubles' product
    # loses the trace's sign, which the exact one restores, and the eigenvector of the doubles' matrix
    # turns by 3 pi; any direction turns by less than pi from the gap's k pi, (1, 0) by 2.5 pi here
    # (the oracle), and the trace is positive: k = 2
    eps, mu, d = 10.06645231424355, 2.607491053933446, K.RectangularWave(0.9)
    assert K.floquet(eps, mu, drive=d).trace > 0
    turn = _turn_of_1_0(eps, mu, d)
    assert abs(turn - 2.0) < 1.0
    assert float(K.rotation_number(eps, mu, drive=d)) == 1.0


def test_a_triangle_zone_thinner_than_a_double_lies_where_its_trace_changes_sign():
    # zone 5 at mu = 0.5: no double is stable; the double search put it 17 doubles below the sign
    # change of the trace (the engine's trace there is formed from terms of e^30): it is reported
    # by the two adjacent doubles the certified trace changes sign between, each in its own gap
    d = K.TriangleWave()
    lo, hi = (float(v) for v in K.zone_edges(0.5, 5, drive=d))
    assert np.nextafter(lo, np.inf) == hi
    f = K.floquet([lo, hi], 0.5, drive=d)
    assert not f.stable.any() and f.trace[0] < -2.0 < 2.0 < f.trace[1]
    assert K.rotation_number([lo, hi], 0.5, drive=d).tolist() == [2.5, 3.0]


def test_beside_the_triangle_s_thin_zones_the_rotation_number_has_the_trace_s_parity():
    d = K.TriangleWave()
    for mu, n in [(0.5, 5), (0.6, 4), (0.8, 2)]:
        for edge in K.zone_edges(mu, n, drive=d):
            x = (np.array([float(edge)]).view(np.int64) + np.arange(-30, 31)).view(np.float64)
            f = K.floquet(x, mu, drive=d)
            off = ~np.asarray(f.stable)
            two = 2.0 * np.asarray(f.rotation_number)[off]
            assert np.all(two == np.rint(two))
            assert np.array_equal(np.remainder(np.rint(two), 2.0) == 1.0, np.asarray(f.trace)[off] < 0), (mu, n)


@pytest.mark.parametrize("drive", [K.SquareWave()] + DRIVES, ids=lambda d: d.text())
def test_the_grid_equals_is_stable_at_doubles_beside_the_edges(drive):
    rng = np.random.default_rng(5)
    for mu in rng.uniform(0.05, min(0.9, 0.9 * drive.mu_max), 5):
        lo, hi = K.zone_edges(mu, np.arange(3), drive=drive)
        edges = np.concatenate([lo, hi])
        edges = edges[np.isfinite(edges)]
        eps = np.unique((edges[:, None].view(np.int64) + np.arange(-3, 4)[None, :]).view(np.float64))
        grid = K.stability_grid(eps, np.array([mu]), drive=drive)[0]
        assert np.array_equal(grid, K.is_stable(eps, mu, drive=drive)), mu


def _measured():
    t = np.linspace(0.0, 0.02, 200, endpoint=False)
    return K.drives.from_samples(t, 300.0 * np.sin(2 * np.pi * 50 * t) + 60.0 * np.sin(2 * np.pi * 150 * t + 0.3))


@pytest.mark.parametrize("drive", [K.SquareWave(), K.RectangularWave(0.3), DRIVES[2], K.TriangleWave(), K.SineWave(),
                                   _measured()], ids=["square", "rect0.3", "step4", "triangle", "sine", "measured"])
def test_the_damped_grid_equals_is_stable_at_doubles_beside_the_damped_edges(drive):
    rng = np.random.default_rng(6)
    checked = 0
    for zeta in (0.05, 0.3, 1.0):
        for mu in rng.uniform(0.05, 0.85, 2):
            lo, hi = K.zone_edges(mu, np.arange(3), drive=drive, zeta=zeta)
            edges = np.concatenate([lo, hi])
            edges = edges[np.isfinite(edges) & (edges > 0)]
            if not edges.size:
                continue
            eps = np.unique((edges[:, None].view(np.int64) + np.arange(-3, 4)[None, :]).view(np.float64))
            grid = K.stability_grid(eps, np.array([mu]), drive=drive, zeta=zeta)[0]
            assert np.array_equal(grid, K.is_stable(eps, mu, drive=drive, zeta=zeta)), (zeta, mu)
            checked += eps.size
    assert checked > 100


@pytest.mark.parametrize("drive, zeta, mu", [(K.RectangularWave(0.3), 1.0, 0.4), (K.RectangularWave(0.3), 2.0, 0.2),
                                             (K.SquareWave(), 2.0, 0.4)])
def test_zones_joined_by_damping_share_one_edge_in_every_call(drive, zeta, mu):
    # heavy damping joins neighbouring zones: the shared edge is the maximum of the gap's excess,
    # which a search locates only to about 1e-8; every call (one zone or several) gives the same
    # double, the same for both zones
    lo, hi = K.zone_edges(np.full(5, mu), np.arange(5), drive=drive, zeta=zeta)
    joined = 0
    for n in range(4):
        one_lo, one_hi = (float(v) for v in K.zone_edges(mu, n, drive=drive, zeta=zeta))
        assert (one_lo, one_hi) == (lo[n], hi[n]), n
        if hi[n] >= lo[n + 1] * (1 - 1e-6):
            joined += 1
            assert hi[n] == lo[n + 1], n
    assert joined >= 2


def test_a_thin_damped_sine_zone_asks_few_exact_traces(monkeypatch):
    # zone 0 at mu = 0.7, zeta = 1 is an ulp or two wide at eps = 39; each certified verdict beside
    # it is an exact trace of thousands of bits (about 0.7 s): the window of doubles that settles
    # thin zones of drives with an extended-precision product is not asked of the sine
    from kapitza.drives import _mathieu as M

    calls = []
    exact = M._exact_tau
    monkeypatch.setattr(M, "_exact_tau", lambda *a, **k: calls.append(a) or exact(*a, **k))
    rep = K.analyze(eps=2.0, mu=0.7, drive="sine", zeta=1.0)
    assert rep.nearest_zone == 0 and rep.eps_hi - rep.eps_lo < 1e-13
    assert len(calls) <= 8


@pytest.mark.parametrize("drive", [K.SquareWave(), K.RectangularWave(0.3)], ids=lambda d: d.text())
def test_certify_false_gives_the_curves_within_a_few_ulp(drive):
    mu = np.linspace(0.05, 0.95, 60) * min(1.0, drive.mu_max)
    lo, hi = K.zone_edges(mu[:, None], np.arange(3)[None, :], drive=drive)
    flo, fhi = K.zone_edges(mu[:, None], np.arange(3)[None, :], drive=drive, certify=False)
    ok = np.isfinite(lo)
    assert ok.sum() >= 100 and np.array_equal(ok, np.isfinite(flo))
    ulps = 4 if isinstance(drive, K.SquareWave) else 16   # (the root solves of steps: a few ulp, 6 seen)
    for a, b in ((lo, flo), (hi, fhi)):
        assert np.all(np.abs(a[ok] - b[ok]) <= ulps * np.spacing(a[ok]))
    if isinstance(drive, K.SquareWave):   # the closed forms' roots, as the charts draw them
        assert not (np.array_equal(lo, flo) and np.array_equal(hi, fhi))
    with pytest.raises(ValueError, match="certify must be True or False"):
        K.zone_edges(0.3, 0, drive=drive, certify="no")
