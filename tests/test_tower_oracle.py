"""The tower's verdicts and multipliers against a 40-digit oracle of the full 2N monodromy.

The oracle builds the mass, stiffness and friction matrices itself in mpmath (from the
centre-of-mass Jacobians, not from kapitza), multiplies the exact segment exponentials
``mpmath.expm(G_i h_i)`` of the first-order system ``z' = [[0, I], [(g + a) M^-1 K, -M^-1 C]] z``
and takes the eigenvalues with ``mpmath.eig``: no modal decomposition anywhere.
"""
import math

import mpmath as mp
import numpy as np
import pytest

import kapitza
from kapitza import Chain

G = 9.81
DPS = 40


def _oracle_matrices(lengths, masses, links, c):
    n = len(lengths)
    L = [mp.mpf(x) for x in lengths]
    m = [mp.mpf(x) for x in masses]
    cm = [x / 2 if links == "rod" else x for x in L]
    J = [mi * Li**2 / 12 if links == "rod" else mp.mpf(0) for mi, Li in zip(m, L)]
    M = mp.zeros(n, n)
    K = mp.zeros(n, n)
    for j in range(n):
        # horizontal velocity of link j's centre: sum_{i<j} L_i theta_i' + c_j theta_j'
        jac = [L[i] if i < j else (cm[j] if i == j else mp.mpf(0)) for i in range(n)]
        for a in range(n):
            for b in range(n):
                M[a, b] += m[j] * jac[a] * jac[b]
        M[j, j] += J[j]
        # height of link j's centre: sum_{i<j} L_i cos theta_i + c_j cos theta_j: -(1/2) theta^2 terms
        for i in range(n):
            K[i, i] += m[j] * jac[i]
    D = mp.zeros(n, n)
    for i in range(n):
        D[i, i] = 1
        if i:
            D[i, i - 1] = -1
    C = mp.mpf(c) * D.T * D
    return M, K, C


def oracle_multipliers(chain, T, A, drive):
    with mp.workdps(DPS):
        M, K, C = _oracle_matrices(chain.lengths, chain.masses, chain.links, chain.joint_damping)
        n = chain.n
        MK, MC = mp.inverse(M) * K, mp.inverse(M) * C
        P = mp.eye(2 * n)
        for s, f in zip(drive.levels, drive.fractions):
            acc = mp.mpf(G) + mp.mpf(A) * mp.mpf(s)
            G_ = mp.zeros(2 * n, 2 * n)
            for i in range(n):
                G_[i, n + i] = 1
                for j in range(n):
                    G_[n + i, j] = acc * MK[i, j]
                    G_[n + i, n + j] = -MC[i, j]
            P = mp.expm(G_ * (2 * mp.mpf(T) * mp.mpf(f))) * P
        ev = mp.eig(P, left=False, right=False)
        return [complex(z) for z in ev], float(max(abs(z) for z in ev)) - 1.0


def _chain(rng, n, links, friction):
    lengths = rng.uniform(0.1, 0.3, n)
    masses = rng.uniform(0.2, 2.0, n)
    ch = Chain(lengths, masses, links=links)
    if friction:
        zeta = rng.uniform(0.01, 0.2)
        c = zeta * 2.0 * ch.mass_matrix()[0, 0] * math.sqrt(G / ch.modal_lengths[0])
        ch = Chain(lengths, masses, links=links, joint_damping=c)
    return ch


def _point(rng, ch, drive, inside):
    """A point near the tower's band for ``drive``: the longest mode's eps inside the band (from
    the drive's zone-0 edges: above the longest mode's lower edge, below the shortest mode's
    upper edge), or below it, or beyond it."""
    ratio = math.sqrt(ch.modal_lengths[-1] / ch.modal_lengths[0])  # eps_N / eps_1 = sqrt(l_1 / l_N)
    mu = rng.uniform(0.005, 0.05)
    lo, hi = (float(x) for x in kapitza.zone_edges(mu, 0, drive=drive))
    top = hi * ratio
    if inside and top > lo:
        e1, e2 = lo * 1.01, top * 0.99
    elif rng.uniform() < 0.5:  # below the longest mode's zone 0: it falls
        e1, e2 = 0.5 * lo, 0.97 * lo
    else:  # beyond the shortest mode's zone 0
        e1, e2 = 1.03 * max(top, lo), 1.6 * max(top, lo)
    A = G / mu**2
    eps1 = math.exp(rng.uniform(math.log(e1), math.log(e2)))
    return eps1 * math.sqrt(8 * ch.modal_lengths[0] / A), A


def _match(ours, oracle, rtol):
    ours = list(np.asarray(ours, complex))
    for z in oracle:
        i = int(np.argmin([abs(w - z) for w in ours]))
        assert abs(ours[i] - z) <= rtol * max(1.0, abs(z)), (ours, oracle)
        ours.pop(i)


DRIVES = [kapitza.SquareWave(), kapitza.RectangularWave(0.3), kapitza.StepDrive([2, -1, 1, -1], [0.2, 0.3, 0.2, 0.3])]


@pytest.mark.parametrize("n", [2, 3, pytest.param(4, marks=pytest.mark.slow)])
@pytest.mark.parametrize("links", ["rod", "point"])
@pytest.mark.parametrize("friction", [False, True])
def test_full_monodromy_against_mpmath(n, links, friction):
    rng = np.random.default_rng(1000 * n + 10 * (links == "rod") + friction)
    ch = _chain(rng, n, links, friction)
    verdicts = []
    for k in range(8):
        drive = DRIVES[k % len(DRIVES)]
        T, A = _point(rng, ch, drive, inside=k % 2 == 0)
        ref, excess = oracle_multipliers(ch, T, A, drive)
        rep = ch.analyze(T=T, A=A, drive=drive)
        if friction:
            ref_stable = excess < 0
        else:
            # undamped: stable means every multiplier on the unit circle (to the oracle's digits)
            if 1e-30 < abs(excess) < 1e-12:
                continue  # too near an edge for this test's tolerance on the multipliers
            ref_stable = abs(excess) <= 1e-30
        assert rep.stable == ref_stable, (T, A, drive, excess)
        verdicts.append(ref_stable)
        # the multipliers: the modes' pairs (undamped) or the 2N monodromy's (friction)
        _match(rep.multipliers, ref, 1e-7)
        fl = kapitza.chain_floquet(ch, T=T, A=A, drive=drive)
        _match(fl.multipliers, ref, 1e-7)
        if friction:
            assert fl.growth == pytest.approx(math.log1p(excess), abs=1e-9)
    assert len(verdicts) >= 5
    assert any(verdicts) and not all(verdicts), verdicts


def test_friction_verdict_near_an_edge_is_settled():
    """A point a hair inside and outside the damped band, located by bisection on the oracle."""
    ch = Chain([0.2, 0.15], [1.0, 0.5], joint_damping=0.004)
    A = 3000.0
    rep = ch.analyze(T=0.003, A=A)
    assert rep.stable and rep.T_hi is not None
    for factor, want in ((1 - 1e-7, True), (1 + 1e-7, False)):
        T = rep.T_hi * factor
        _, excess = oracle_multipliers(ch, T, A, kapitza.SquareWave())
        assert (excess < 0) == want
        assert ch.analyze(T=T, A=A).stable == want


def test_friction_couples_the_modes():
    """With joint friction the monodromy is not block-diagonal in the modal coordinates."""
    ch = Chain([0.2, 0.2, 0.2], joint_damping=0.01)
    V = ch.mode_shapes
    Cq = V.T @ ch.damping_matrix() @ V
    off = Cq - np.diag(np.diag(Cq))
    assert np.abs(off).max() > 0.05 * np.abs(np.diag(Cq)).max()


def test_sine_with_friction_against_an_independent_integration():
    from scipy.integrate import solve_ivp

    ch = Chain([0.2, 0.15, 0.1], [1.0, 0.6, 0.3], links="point", joint_damping=0.003)
    M = ch.mass_matrix()
    MK, MC = np.linalg.solve(M, ch.stiffness_matrix()), np.linalg.solve(M, ch.damping_matrix())
    n = ch.n
    for T, A in [(0.004, 2500.0), (0.01, 800.0), (0.002, 6000.0)]:
        def rhs(t, y):
            Y = y.reshape(2 * n, 2 * n)
            acc = G + A * math.sin(math.pi * t / T)
            return np.vstack([Y[n:], acc * MK @ Y[:n] - MC @ Y[n:]]).ravel()

        sol = solve_ivp(rhs, (0, 2 * T), np.eye(2 * n).ravel(), method="Radau", rtol=1e-11, atol=1e-13)
        ref = np.linalg.eigvals(sol.y[:, -1].reshape(2 * n, 2 * n))
        fl = kapitza.chain_floquet(ch, T=T, A=A, drive="sine")
        _match(fl.multipliers, ref, 1e-6)
        assert fl.stable == bool(np.max(np.abs(ref)) < 1)
