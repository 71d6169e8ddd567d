"""The tower of linked pendulums: matrices, modes, the modal verdict and the Rig hook."""
import math

import numpy as np
import pytest

import kapitza
from kapitza import Chain, KapitzaValueError, Pendulum, Rig

G = 9.81


def _positions(chain, theta):
    """Centre-of-mass positions (x, y) of every link for the link angles ``theta`` (from the upright)."""
    x = y = 0.0
    out = []
    for L, c, th in zip(chain.lengths, chain.centres, theta):
        out.append((x + c * math.sin(th), y + c * math.cos(th)))
        x, y = x + L * math.sin(th), y + L * math.cos(th)
    return np.array(out)


def _matrices_by_differences(chain, h=1e-6):
    """M and K from the exact kinetic and potential energies by central differences (independent of chain.py)."""
    n = chain.n
    m = np.array(chain.masses)
    J = np.zeros((n, 2, n))  # d(com_j)/d(theta_i) at the upright
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        J[:, :, i] = (_positions(chain, e) - _positions(chain, -e)) / (2 * h)
    M = sum(m[j] * J[j].T @ J[j] for j in range(n)) + np.diag(chain.inertias)

    def V(th):
        return G * float(np.dot(m, _positions(chain, th)[:, 1]))

    K = np.zeros((n, n))
    hh = 1e-4
    for i in range(n):
        for k in range(n):
            ei, ek = np.zeros(n), np.zeros(n)
            ei[i] += hh
            ek[k] += hh
            K[i, k] = (V(ei + ek) - V(ei - ek) - V(-ei + ek) + V(-ei - ek)) / (4 * hh * hh)
    return M, -K / G


@pytest.mark.parametrize("links", ["rod", "point"])
@pytest.mark.parametrize("seed", range(4))
def test_matrices_match_the_energies(links, seed):
    rng = np.random.default_rng(seed)
    n = 1 + seed
    ch = Chain(rng.uniform(0.05, 1.0, n), rng.uniform(0.1, 3.0, n), links=links)
    M, K = _matrices_by_differences(ch)
    np.testing.assert_allclose(ch.mass_matrix(), M, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(ch.stiffness_matrix(), K, rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("seed", range(6))
def test_modes_solve_the_generalised_problem(seed):
    rng = np.random.default_rng(100 + seed)
    n = int(rng.integers(2, 6))
    ch = Chain(rng.uniform(0.01, 2.0, n), rng.uniform(0.01, 5.0, n), links=("rod", "point")[seed % 2])
    M, K, V = ch.mass_matrix(), ch.stiffness_matrix(), ch.mode_shapes
    lam = 1.0 / np.array(ch.modal_lengths)
    np.testing.assert_allclose(V.T @ M @ V, np.eye(n), atol=1e-12)
    np.testing.assert_allclose(K @ V, M @ V * lam, rtol=1e-11, atol=1e-12 * np.abs(K).max())
    assert list(ch.modal_lengths) == sorted(ch.modal_lengths, reverse=True)
    # the longest mode is longer than the tower's own rigid-body equivalent length (Rayleigh quotient)
    one = np.ones(n)
    assert ch.modal_lengths[0] >= (one @ M @ one) / (one @ K @ one) * (1 - 1e-12)


@pytest.mark.parametrize("l", [0.1, 0.3, 1.7])
def test_double_point_pendulum_textbook_modes(l):
    ch = Chain([l, l], links="point", masses=[0.4, 0.4])
    np.testing.assert_allclose(ch.modal_lengths, [l / (2 - math.sqrt(2)), l / (2 + math.sqrt(2))], rtol=2e-15)
    # shapes (1, sqrt 2) and (1, -sqrt 2)
    V = ch.mode_shapes
    np.testing.assert_allclose(V[1] / V[0], [math.sqrt(2), -math.sqrt(2)], rtol=1e-13)


def test_double_rod_closed_form():
    # equal uniform rods: M = m L^2 [[4/3, 1/2], [1/2, 1/3]], K = m L diag(3/2, 1/2)
    L = 0.25
    ch = Chain([L, L])
    np.testing.assert_allclose(ch.mass_matrix(), L * L * np.array([[4 / 3, 1 / 2], [1 / 2, 1 / 3]]), rtol=1e-15)
    np.testing.assert_allclose(ch.stiffness_matrix(), L * np.diag([1.5, 0.5]), rtol=1e-15)
    # det(K - lambda M) = 0: (7/36) x^2 - (7/6) x + 3/4 = 0 with x = lambda L
    x = np.roots([7 / 36, -7 / 6, 3 / 4])
    np.testing.assert_allclose(sorted(L / x, reverse=True), ch.modal_lengths, rtol=1e-14)


@pytest.mark.parametrize("links, make", [("rod", Pendulum.uniform_rod), ("point", Pendulum.point_mass)])
@pytest.mark.parametrize("T, A", [(0.05, 300.0), (0.2, 100.0), (0.01, 50.0), (0.33, 80.0)])
def test_one_link_is_the_single_pendulum(links, make, T, A):
    L = 0.3
    ch = Chain([L], links=links, masses=[2.0])
    p = make(L)
    assert ch.modal_lengths == (p.l,)
    r = ch.analyze(T=T, A=A)
    s = kapitza.analyze(T=T, A=A, l=p.l, g=G)
    assert r.stable == s.stable
    assert r.multipliers == tuple(s.multipliers)
    assert r.margin == s.margin and r.growth == s.growth
    assert r.modes[0].zone == s.zone
    if s.stable:
        assert (r.T_lo, r.T_hi) == (s.T_lo, s.T_hi)


@pytest.mark.parametrize("drive", [None, kapitza.SineWave(), kapitza.RectangularWave(0.3)])
def test_one_link_with_friction_is_the_damped_pendulum(drive):
    ch = Chain([0.4], masses=[0.5], joint_damping=0.002)
    p = ch.pendulum()
    assert p.damping == pytest.approx(0.002 / (0.5 * 0.4**2 / 3), rel=1e-15)
    for T, A in [(0.05, 300.0), (0.2, 100.0), (0.02, 900.0)]:
        # the 2 x 2 monodromy of the chain machinery agrees with the damped pendulum's Floquet data
        f = kapitza.chain_floquet(ch, T=T, A=A, drive=drive)
        eps, mu = kapitza.to_arnold(T, A, p.l, G)
        s = kapitza.floquet(eps, mu, drive=drive, zeta=p.zeta)
        assert f.stable == bool(s.stable)
        np.testing.assert_allclose(sorted(np.abs(f.multipliers)), sorted(np.abs(s.multipliers)), rtol=1e-8)
    if drive is None:  # the report is the pendulum's own
        r = Rig(ch, drive).analyze(T=0.05, A=300.0)
        s = Rig(p, drive).analyze(T=0.05, A=300.0)
        assert r.stable == s.stable and r.growth == s.growth and r.margin == s.margin


@pytest.mark.parametrize("drive", [None, kapitza.SineWave(), kapitza.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])])
def test_verdict_is_every_mode(drive):
    rng = np.random.default_rng(7)
    ch = Chain([0.2, 0.15, 0.1], masses=[1.0, 0.7, 0.3])
    for _ in range(12 if drive is None else 4):
        T = 10 ** rng.uniform(-3, -1.3)
        A = 10 ** rng.uniform(2, 4)
        r = Rig(ch, drive).analyze(T=T, A=A)
        eps, mu = kapitza.to_arnold(T, A, np.array(ch.modal_lengths), G)
        each = kapitza.is_stable(eps, mu, drive=drive)
        assert r.stable == bool(np.all(each))
        assert [m.stable for m in r.modes] == list(each)
        assert len(r.multipliers) == 2 * ch.n
        if r.stable:
            assert r.margin > 0 and r.growth == 0
        else:
            assert r.margin < 0 and r.growth > 0


def test_band_edges_and_how_it_fails():
    ch = Chain([0.2, 0.2, 0.2])
    r = ch.analyze(T=0.0023, A=4000.0)
    assert r.stable and r.method == "modes"
    lo = ch.analyze(T=r.T_lo * (1 - 1e-6), A=4000.0)
    hi = ch.analyze(T=r.T_hi * (1 + 1e-6), A=4000.0)
    inside = [ch.analyze(T=t, A=4000.0).stable for t in (r.T_lo * (1 + 1e-6), r.T_hi * (1 - 1e-6))]
    assert inside == [True, True]
    # too weak: the longest mode falls; too strong: the shortest doubles its period
    assert not lo.stable and lo.critical_mode == 1 and lo.failure == "falls"
    assert not hi.stable and hi.critical_mode == 3 and hi.failure == "period doubling"
    # the band at fixed A is the intersection of the modes' zone-0 intervals
    assert r.T_lo == r.modes[0].T_lo and r.T_hi == r.modes[2].T_hi
    # the same point by frequency and stroke
    f = ch.analyze(frequency=r.frequency, stroke=r.stroke)
    assert f.stable and f.T == pytest.approx(r.T, rel=1e-14) and f.A == pytest.approx(r.A, rel=1e-12)
    assert "mode 1" in str(r) and "band" in str(r) and repr(r).startswith("<ChainReport:")
    d = r.as_dict()
    assert d["stable"] is True and len(d["modes"]) == 3 and len(d["multipliers"]) == 6


def test_window_narrows_with_links():
    """More links: the longest mode grows, the shortest shrinks, so the band narrows."""
    L = 0.1
    ls = [Chain([L] * n).modal_lengths for n in range(1, 6)]
    longest = [x[0] for x in ls]
    shortest = [x[-1] for x in ls]
    assert all(a < b for a, b in zip(longest, longest[1:]))
    assert all(a > b for a, b in zip(shortest, shortest[1:]))


def test_rig_accepts_a_chain_and_gravity():
    ch = Chain([0.3, 0.2])
    a = Rig(ch, "sine").analyze(T=0.004, A=3000.0, g=1.62)
    b = ch.analyze(T=0.004, A=3000.0, g=1.62, drive=kapitza.SineWave())
    assert a.stable == b.stable and a.multipliers == b.multipliers and a.g == 1.62
    with pytest.raises(KapitzaValueError, match="pendulum must be"):
        Rig("tower", None)


@pytest.mark.parametrize("kwargs, match", [
    (dict(lengths=[]), "lengths"),
    (dict(lengths=[0.2, -1.0]), r"lengths\[1\]"),
    (dict(lengths=[1e-300]), "lengths"),
    (dict(lengths=[0.2], masses=[1e300]), "masses"),
    (dict(lengths=[0.2, float("nan")]), "lengths"),
    (dict(lengths="abc"), "lengths"),
    (dict(lengths=[0.2, 0.3], masses=[1.0]), "masses"),
    (dict(lengths=[0.2], masses=[0.0]), "masses"),
    (dict(lengths=[0.2], links="rope"), "links"),
    (dict(lengths=[0.2], joint_damping=-1.0), "joint_damping"),
    (dict(lengths=[0.2] * 40), "lengths"),
])
def test_bad_chains_are_refused(kwargs, match):
    with pytest.raises(KapitzaValueError, match=match):
        Chain(**kwargs)


def test_bad_points_are_refused():
    ch = Chain([0.2, 0.2])
    with pytest.raises(KapitzaValueError, match="T"):
        ch.analyze(T=-1.0, A=100.0)
    with pytest.raises(KapitzaValueError, match="g"):
        ch.analyze(T=0.01, A=100.0, g=0.0)
    with pytest.raises(KapitzaValueError, match="frequency"):
        ch.analyze(T=0.01, frequency=10.0, stroke=0.01)
    with pytest.raises(KapitzaValueError):
        ch.analyze(frequency=10.0)


def test_docs_quick_start_runs():
    """docs/tower.md's Python quick start runs as written and gives what its comments say."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "docs" / "tower.md").read_text()
    code = re.findall(r"```python\n(.*?)```", text, flags=re.S)[0]
    ns = {}
    exec(compile(code.replace("print(report)", "text = str(report)"), "tower.md", "exec"), ns)
    assert ns["report"].stable is True
    np.testing.assert_allclose(ns["tower"].modal_lengths, (0.4124, 0.0667, 0.0187), atol=6e-5)
    assert "mode 1" in ns["text"] and "band" in ns["text"]


def test_with_friction_the_report_says_which_mode_fails_and_how():
    ch = Chain([0.2, 0.2, 0.2], joint_damping=0.01)
    near_top = ch.analyze(T=0.0038, A=4000.0)
    assert near_top.stable and near_top.critical_mode == 3 and near_top.failure == "period doubling"
    assert near_top.growth < 0 and len(near_top.multipliers) == 6
    assert "exact product" in near_top.method
    below = ch.analyze(T=0.0015, A=4000.0)
    assert not below.stable and below.critical_mode == 1 and below.failure == "falls"
    beyond = ch.analyze(T=0.0045, A=4000.0)
    assert not beyond.stable and beyond.critical_mode == 3 and beyond.failure == "period doubling"
    # the band found by the verdict's bisection: a hair inside and outside each edge
    for edge, inside in ((near_top.T_lo, 1 + 1e-7), (near_top.T_hi, 1 - 1e-7)):
        assert kapitza.chain_floquet(ch, T=edge * inside, A=4000.0).stable
        assert not kapitza.chain_floquet(ch, T=edge / inside, A=4000.0).stable
