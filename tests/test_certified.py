"""Verdicts certified to the last bit for the square wave, and growth where rounding loses it."""
import numpy as np
import pytest

import kapitza as K
import oracle


def test_reported_wrong_answers_are_right_now():
    # an unstable point near an edge used to report growth 0 (truth 101.76)
    eps, mu = 33.86932275003924, 0.9994776637671322
    assert K.growth_rate(eps, mu) == pytest.approx(float(oracle.growth(eps, mu)), rel=1e-12)
    # tr M = 1.99999999999999846 here: stable, and the margin says so
    eps, mu = 0.5301303231328324, 0.4247369708803898
    assert bool(K.is_stable(eps, mu)) is oracle.stable(eps, mu) is True
    assert K.stability_margin(eps, mu).margin > 0
    rep = K.analyze(eps=eps, mu=mu)
    assert rep.stable and rep.margin > 0
    # the reported stability --T 25.06 --A 12 case: growth matches the reference, not 0
    e, m = K.to_arnold(25.059972220655787, 12.0)
    assert K.growth_rate(e, m) == pytest.approx(float(oracle.growth(float(e), float(m))), rel=1e-10)


def test_doubles_within_a_few_ulp_of_edges_get_the_exact_verdict():
    rng = np.random.default_rng(8)
    wrong = []
    cases = 0
    for mu in rng.uniform(0.05, 0.95, 40):
        n = int(rng.integers(0, 4))
        upper = bool(rng.integers(0, 2))
        e0 = float(oracle.edge_eps(float(mu), n, upper))
        pts = [e0]
        for k in range(1, 5):
            pts += [float(np.nextafter(pts[0] if k == 1 else pts[-2], np.inf))]
        up, dn = [e0], [e0]
        for _ in range(3):
            up.append(float(np.nextafter(up[-1], np.inf)))
            dn.append(float(np.nextafter(dn[-1], -np.inf)))
        for e in sorted(set(up + dn)):
            cases += 1
            got = bool(K.is_stable(e, float(mu)))
            if got != oracle.stable(e, float(mu)):
                wrong.append((e, float(mu), n, upper))
            # the margin's sign always agrees with the verdict
            assert (K.stability_margin(e, float(mu)).margin > 0) == got
    assert cases >= 200 and not wrong, wrong[:5]


def test_far_out_inputs_give_finite_answers_and_no_warnings():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        # A <= g: growth x + v - ..., formed without squaring (true 2.83e154 fits a double)
        assert K.growth_rate(0.5, 1e154) == pytest.approx(2.8284271247461903e154, rel=1e-12)
        assert np.isfinite(K.growth_rate(0.5, 1e155))
        lam = K.floquet_multipliers(0.5, 1e300)
        assert not np.any(np.isnan(lam))
        for kw in (dict(T=0.15, A=1e300), dict(T=1e300, A=100.0), dict(T=0.15, A=100.0, l=1e-300)):
            rep = K.analyze(**kw)
            assert not rep.stable and rep.nearest_zone == -1 and rep.margin == -np.inf
            assert np.isfinite(rep.growth) and rep.growth > 0


def test_fast_verdict_agrees_with_the_certified_path_at_every_distance_from_an_edge():
    # The fast test (tan form with a rounding bound) decides alone only outside its bound;
    # points from 0 to 2^40 ulp off edges of zones 0-39, at small, middling and near-1 mu,
    # must get the verdict and zone of the closed forms with their mpmath decision.
    from kapitza import zones as Z

    rng = np.random.default_rng(11)
    mus = np.concatenate([rng.uniform(0, 1, 24), 10 ** rng.uniform(-9, -1, 8), 1 - 10 ** rng.uniform(-9, -1, 8)])
    ns = rng.integers(0, 40, mus.size)
    ns[:12] = rng.integers(0, 3, 12)
    lo, hi = K.zone_edges(mus, ns)
    ks = np.unique(np.concatenate([np.arange(0, 8), np.round(np.geomspace(8, 2.0**40, 40))])).astype(np.int64)
    eps, mu = [], []
    for e0 in (lo, hi):
        for sign in (1, -1):
            eps.append((e0.view(np.int64)[:, None] + sign * ks[None, :]).view(float).ravel())
            mu.append(np.repeat(mus, ks.size))
    eps, mu = np.concatenate(eps), np.concatenate(mu)
    fast, n_fast = Z._verdict(eps, mu)
    careful, n_careful = Z._verdict_careful(eps, mu)
    assert eps.size > 5000
    assert np.array_equal(fast, careful)
    assert np.array_equal(n_fast[careful], n_careful[careful])
    # random points over the plane: the two agree everywhere, including mu >= 1
    e = rng.uniform(0, 20, 20000)
    m = rng.uniform(0, 1.2, 20000)
    assert np.array_equal(Z._verdict(e, m)[0], Z._verdict_careful(e, m)[0])
    assert np.array_equal(K.zone_index(e, m), np.where(Z._verdict_careful(e, m)[0],
                                                       Z._verdict_careful(e, m)[1], -1))


def test_threaded_blocks_give_the_one_thread_verdict(monkeypatch):
    """A large call shares its blocks among threads; the verdicts and zones are those of one
    thread block by block, edge points (sent on to the certified path) included."""
    import kapitza._square as Z

    rng = np.random.default_rng(11)
    N = 40 * Z._CHUNK + 123  # a short last block
    eps, mu = rng.uniform(1e-3, 4.0, N), rng.uniform(1e-3, 1.2, N)
    mu_e = rng.uniform(0.05, 0.95, 50)
    eps[:50] = K.zone_edges(mu_e, 0)[0]  # doubles on zone 0's lower edge: the careful path
    mu[:50] = mu_e
    assert Z._threads(-(-N // Z._CHUNK)) == min(2, Z._v.cpus()) or Z._v.cpus() == 1
    threaded = Z._verdict(eps, mu)
    monkeypatch.setattr(Z, "_threads", lambda blocks: 1)
    one = Z._verdict(eps, mu)
    assert np.array_equal(threaded[0], one[0]) and np.array_equal(threaded[1], one[1], equal_nan=True)
    assert np.array_equal(K.is_stable(eps, mu), one[0])
