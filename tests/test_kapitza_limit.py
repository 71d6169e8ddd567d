"""Kapitza's limit ``mu -> 0`` to the last bit, for every drive whose verdicts are certified.

There ``tr M / 2 - 1`` is of order ``eps^2 mu^2`` while the trace is of order 1: the doubles of a
product lose it entirely below ``mu`` of about 1e-4 (and ``8 eps^2`` underflows below 1e-154), the
sine's Sturm counts resolve ``a - a_0`` to ``u q`` only. The oracle is independent of the package:
the averaging threshold ``eps_K = mu / sqrt(8 k)``, ``k`` the mean square of the pivot's zero-mean
velocity shape integrated here in mpmath, is the lower edge of zone 0 up to a relative ``O(mu^2)``,
far below an ulp for ``mu <= 1e-20``: the reported edge must be the last unstable double below it.
"""
import mpmath
import numpy as np
import pytest

import kapitza as K
from kapitza.drives import from_samples


def _k(shape, breaks):
    """``k`` of ``<v^2> = k A^2 T^2``: half the integral over the period ``[0, 2)`` of ``(V - mean V)^2``,
    ``V`` the integral of the acceleration shape ``shape`` (mpmath, 40 digits)."""
    with mpmath.workdps(40):
        pts = [0, *breaks, 2]

        def V(t):
            return mpmath.quad(shape, [p for p in pts if p < t] + [t])

        mean = mpmath.quad(V, pts) / 2
        return mpmath.quad(lambda t: (V(t) - mean) ** 2, pts) / 2


def _triangle(t):
    return 1 - 2 * t if t <= 1 else -1 + 2 * (t - 1)


def _steps(t):
    return (2, -1, 1, -2)[min(int(2 * t), 3)]


SHAPES = {
    "square": (lambda t: 1 if t < 1 else -1, [1]),
    "steps": (_steps, [0.5, 1, 1.5]),
    "sine": (lambda t: mpmath.sin(mpmath.pi * t), []),
    "triangle": (_triangle, [1]),
}


def _measured_triangle():
    # samples at 1/32 of the period: their linear interpolation is the triangle wave itself
    t = np.arange(64) / 32.0
    return from_samples(t, [float(_triangle(x)) for x in t], period=2.0)


STEPS = "steps:2,-1,1,-2:0.25,0.25,0.25,0.25"   # (its levels have mean 0 exactly)
DRIVES = {"square": "square", "sine": "sine", "triangle": "triangle", "measured triangle": _measured_triangle(),
          "steps": STEPS}
ORACLE = {"square": "square", "sine": "sine", "triangle": "triangle", "measured triangle": "triangle",
          "steps": "steps"}


@pytest.fixture(scope="module")
def k_of():
    return {name: _k(*SHAPES[name]) for name in SHAPES}


@pytest.mark.parametrize("name", list(DRIVES))
@pytest.mark.parametrize("mu", [1e-20, 1e-150, 1e-300])
def test_zone_0_begins_at_the_averaging_threshold_to_the_last_bit(name, mu, k_of):
    drive = DRIVES[name]
    lo, hi = K.zone_edges(mu, 0, drive=drive)
    with mpmath.workdps(40):
        exact = mpmath.mpf(mu) / mpmath.sqrt(8 * k_of[ORACLE[name]])
        up = float(np.nextafter(lo, np.inf))
        # the reported edge is the last unstable double below the limit, its neighbour the first stable one
        assert mpmath.mpf(float(lo)) < exact < mpmath.mpf(up), (name, mu, lo, mpmath.nstr(exact, 20))
    assert hi > 0.3
    eps = np.array([np.nextafter(lo, 0), lo, up, np.nextafter(up, np.inf)])
    want = np.array([False, False, True, True])
    assert (K.is_stable(eps, mu, drive=drive) == want).all()
    assert (K.zone_index(eps, mu, drive=drive) == np.where(want, 0, -1)).all()
    assert (K.stability_grid(eps, [mu], drive=drive)[0] == want).all()


@pytest.mark.parametrize("name", list(DRIVES))
@pytest.mark.parametrize("mu", [1e-4, 1e-6, 1e-10])
def test_zone_0_in_kapitzas_regime_agrees_with_its_verdicts(name, mu, k_of):
    # (the engine's own edge was 1.5 % off at mu = 1e-4 and 3.5 times the limit at 1e-5, with is_stable
    # true on both sides of it; the sine's was 0 below mu = 1e-100)
    drive = DRIVES[name]
    lo, _ = K.zone_edges(mu, 0, drive=drive)
    exact = float(mpmath.mpf(mu) / mpmath.sqrt(8 * k_of[ORACLE[name]]))
    assert abs(lo / exact - 1.0) <= mu**2 + 4e-16
    eps = np.array([lo, np.nextafter(lo, np.inf), lo * (1 - 1e-6), lo * (1 + 1e-6)])
    want = np.array([False, True, False, True])
    assert (K.is_stable(eps, mu, drive=drive) == want).all()
    assert (K.stability_grid(np.sort(eps), [mu], drive=drive)[0] == want[np.argsort(eps)]).all()
    m = K.stability_margin(lo * 1.01, mu, drive=drive)   # (its edges as solved: the square's within 4 ulp)
    assert m.zone == 0 and abs(m.eps_lo / lo - 1.0) < 1e-15


@pytest.mark.parametrize("drive", ["square", "sine", "triangle"])
def test_a_point_far_below_the_limit_falls_and_far_above_stands(drive):
    # the sine called eps = 1e-300 stable at mu = 0.5 and 1.5 (q underflowed to 0: the count of a_0 at
    # a = q = 0), the triangle unstable above the limit at mu = 1e-300 (8 eps^2 underflowed in the
    # fixed point of its exact product)
    for mu in (1e-300, 1e-160):
        c = float(K.averaging_threshold(mu, drive=drive))
        assert list(K.is_stable([0.5 * c, 2.0 * c], mu, drive=drive)) == [False, True]
    assert not K.analyze(eps=1e-300, mu=0.5, drive=drive).stable
    assert not K.analyze(eps=1e-300, mu=1.5, drive=drive).stable


@pytest.mark.parametrize("name", list(DRIVES))
@pytest.mark.parametrize("zeta", [0.1, 1.0])
@pytest.mark.parametrize("mu", [1e-3, 1e-40])
def test_damped_zone_0_begins_where_its_certified_verdict_does(name, zeta, mu, k_of):
    # damping leaves the averaged stiffness as it is: the damped lower edge of zone 0 is the averaging
    # threshold to O(mu^2); the triangle's was 7.5e-6 at mu = 1e-5 (the threshold 1.9e-5), 0 at 1e-8, and
    # the sine's hit 0/0 in Hill's determinant once q underflowed
    drive = DRIVES[name]
    lo, _ = K.zone_edges(mu, 0, drive=drive, zeta=zeta)
    exact = float(mpmath.mpf(mu) / mpmath.sqrt(8 * k_of[ORACLE[name]]))
    assert abs(lo / exact - 1.0) <= 10 * mu**2 + 8e-16
    up = np.nextafter(lo, np.inf)
    eps = np.array([np.nextafter(lo, 0), lo, up, np.nextafter(up, np.inf)])
    want = np.array([False, False, True, True])
    assert (K.is_stable(eps, mu, drive=drive, zeta=zeta) == want).all()
    assert (K.stability_grid(eps, [mu], drive=drive, zeta=zeta)[0] == want).all()


@pytest.mark.parametrize("mu", [1e-9, 1e-30, 1e-300])
def test_a_rounded_mean_level_moves_kapitzas_limit_as_it_should(mu):
    # duty 0.25: the level -1/3 rounds to a mean of +1.4e-17, which adds to mu^2 (the edge stays near
    # sqrt(1.4e-17) / sqrt(8 k) however small mu is); duty 0.3: -1.4e-17, which outweighs mu^2 below
    # mu = 3.8e-9: the mean stiffness attracts and zone 0 reaches eps -> 0 (its edges were 1e-2 to 3e31
    # times the averaging threshold, on the wrong side)
    for text in ("rectangular:0.25", "rectangular:0.3"):
        lo, hi = K.zone_edges(mu, 0, drive=text)
        if lo > 0:
            up = np.nextafter(lo, np.inf)
            eps = np.array([lo, up])
            want = np.array([False, True])
        else:
            assert text == "rectangular:0.3" and mu < 3.8e-9
            eps = np.array([5e-324, 1e-300, 0.5 * hi])
            want = np.ones(3, bool)
        assert (K.is_stable(eps, mu, drive=text) == want).all(), (text, lo)
        assert (K.stability_grid(eps, [mu], drive=text)[0] == want).all(), (text, lo)


def test_a_report_says_which_side_of_2_a_trace_that_rounds_to_2_is_on():
    # "trace tr M  2 (stable iff |tr M| < 2)" beside "stable (zone 0)" read as a contradiction
    stable = str(K.analyze(eps=1e-8, mu=1e-9, drive="triangle"))
    assert "stable (zone 0)" in stable and "|tr M| rounds to 2, and is below it in extended precision" in stable
    falls = str(K.analyze(eps=1e-8, mu=1e-7))
    assert "too weak" in falls and "|tr M| rounds to 2, and is at or above it" in falls
    assert "rounds to 2" not in str(K.analyze(T=0.15, A=100.0))


@pytest.mark.parametrize("drive", ["square", "rectangular:0.3", "triangle", "sine", "steps:1,-1,2,-2:0.3,0.3,0.2,0.2"])
@pytest.mark.parametrize("eps, mu", [(1e-10, 10.0), (1e-9, 0.5), (1e-12, 3.0), (1e-7, 0.2),
                                     (1e-160, 0.5), (1e-170, 1e10), (1e-300, 3.0), (1e-300, 0.5), (1e-160, 1e149)])
def test_the_growth_just_past_the_threshold_is_sqrt_32_eps_mu(drive, eps, mu):
    """Where the phase of the period is tiny, tr M / 2 = 1 + 16 eps^2 mu^2 + O(eps^4) for any shape of
    zero mean, and the growth acosh(tr M / 2) is sqrt(32) eps mu to about 1e-14 relative. The double
    trace rounds to 1 there: the triangle's growth came from a long double trace a few ulp of it
    off (1.4e-3 relative), the sine's was 0. Below eps mu = 1e-154 tr M / 2 - 1 leaves the normal
    doubles (and below eps = 1e-154 the sine's q): every drive but the square wave's closed forms
    below 1 gave a growth of 0 there, beside the verdict unstable."""
    g = float(K.floquet(eps, mu, drive=drive).growth)
    assert g == pytest.approx(32.0**0.5 * eps * mu, rel=1e-12)
