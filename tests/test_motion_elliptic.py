"""The exact phase flow: Jacobi functions against mpmath, the flow against DOP853 and a
30-digit Taylor integration, and the flow's own laws (group, reversal, energy)."""
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.special import ellipj

from kapitza import KapitzaValueError
from kapitza.motion import phase_flow
from kapitza.motion._elliptic import _jacobi, _phase_step, _phase_step_arrays, _phase_step_one, _series

W_H2 = (100.0 + 9.81) / 1.0  # w_h^2 for A = 100, l = 1
W_E2 = (100.0 - 9.81) / 1.0


# ------------------------------------------------------------------ Jacobi functions
@pytest.mark.parametrize("m1", [1.0, 0.9, 0.6, 0.5, 0.4, 1e-3, 1e-6, 1e-9, 1e-11, 1e-13, 1e-16, 1e-40, 0.0])
def test_jacobi_against_mpmath(m1):
    mp.mp.dps = 40
    u = np.concatenate([np.linspace(-25.0, 25.0, 37), [0.0, 1e-8, 0.3, 2.7]])
    sn, cn, dn, K = _jacobi(u, np.full(u.size, m1))
    m = 1 - mp.mpf(m1)
    for i, x in enumerate(u):
        ref = [mp.ellipfun(f, mp.mpf(x), m=m) for f in ("sn", "cn", "dn")]
        # Absolute error; |u| up to 25 costs ~|u| eps through the argument itself.
        for got, want in zip((sn[i], cn[i], dn[i]), ref):
            assert abs(got - float(want)) < 1e-14 * (1 + abs(x)), (m1, x, got, float(want))
    if m1 > 1e-30:
        assert K[0] == pytest.approx(float(mp.ellipk(m)), rel=4e-16)
    elif m1 == 0.0:
        assert np.isinf(K).all()


def test_jacobi_keeps_relative_accuracy_of_small_cn_dn_near_m_1():
    # cn and dn of (K - t | m) are k' sd t and k' nd t: tiny, and must keep their relative accuracy.
    mp.mp.dps = 50
    for m1 in (1e-8, 1e-14):
        m = 1 - mp.mpf(m1)
        K = mp.ellipk(m)
        for t in (0.5, 1e-3):
            u = float(K - t)
            _, cn, dn, _ = _jacobi(np.array([u]), np.array([m1]))
            ucorr = mp.mpf(u)
            assert cn[0] == pytest.approx(float(mp.ellipfun("cn", ucorr, m=m)), rel=1e-13)
            assert dn[0] == pytest.approx(float(mp.ellipfun("dn", ucorr, m=m)), rel=1e-13)


def test_series_and_ellipj_twins_agree_where_both_apply():
    # The complementary-nome series is used for m > 1/2 and scipy's ellipj below; both are valid
    # around m = 1/2 and must agree there.
    rng = np.random.default_rng(3)
    m = rng.uniform(0.3, 0.7, 500)
    u = rng.uniform(-0.8, 0.8, 500)  # |u| <= K/2 = 0.85 for these m: no quarter-period shift
    s1, c1, d1, _, j = _series(u, 1.0 - m)
    s2, c2, d2, _ = ellipj(u, m)
    assert np.all(j == 0)
    assert np.max(np.abs(s1 - s2)) < 3e-15
    assert np.max(np.abs(c1 - c2)) < 3e-15
    assert np.max(np.abs(d1 - d2)) < 3e-15


# ------------------------------------------------------------------ the flow
def dop853(theta, dtheta, s, t, rtol=1e-12):
    sol = solve_ivp(lambda _, y: [y[1], s * np.sin(y[0])], (0.0, t), [theta, dtheta], method="DOP853",
                    rtol=rtol, atol=1e-14)
    return sol.y[:, -1]


def separatrix_start(theta, s, m1):
    """A start at angle theta whose modulus satisfies 1 - k^2 = m1 (m1 < 0: rotation)."""
    w = np.sqrt(abs(s))
    d = -np.sin(theta / 2) if s > 0 else np.cos(theta / 2)  # cos(q/2) of the phase's pendulum
    return 2.0 * w * np.sqrt(d * d - m1)


CASES = []
for s in (W_H2, -W_E2):
    for th in (0.05, 0.7, 2.0, -2.6):
        d = -np.sin(th / 2) if s > 0 else np.cos(th / 2)
        for m1 in (1e-2, 1e-6, 1e-10, 0.0, -1e-10, -1e-6, -1e-2):
            if d * d >= m1:  # else no velocity gives this modulus at this angle
                CASES.append((s, th, m1))


@pytest.mark.parametrize("s,theta,m1", CASES)
def test_flow_matches_dop853_over_a_period_near_the_separatrix(s, theta, m1):
    """Libration, separatrix and rotation, both phases, over one drive period (T = 0.15 s)."""
    w = np.sqrt(abs(s))
    t = 0.3
    for sign in (1.0, -1.0):
        om = sign * separatrix_start(theta, s, m1)
        th1, om1 = phase_flow(t, theta, om, s)
        ref = dop853(theta, om, s, t)
        assert abs(th1 - ref[0]) < 1e-10
        assert abs(om1 - ref[1]) / w < 1e-10


@pytest.mark.parametrize("s", [W_H2, -W_E2, 4.0, -4.0])
def test_flow_matches_dop853_on_random_states(s):
    rng = np.random.default_rng(11)
    w = np.sqrt(abs(s))
    th = rng.uniform(-7, 7, 25)
    om = rng.uniform(-3, 3, 25) * w
    t = rng.uniform(0, 2.0, 25) / w
    th1, om1 = phase_flow(t, th, om, s)
    for i in range(th.size):
        ref = dop853(th[i], om[i], s, t[i])
        assert abs(th1[i] - ref[0]) < 1e-10
        assert abs(om1[i] - ref[1]) / w < 1e-10


TAYLOR_CASES = [
    (0.3, -2 * np.sqrt(W_H2) * np.sin(0.15), W_H2, 0.3),            # on the separatrix, falling in
    (1e-3, -1e-3 * np.sqrt(W_H2) * (1 + 1e-6), W_H2, 0.3),            # a hair from the stable manifold
    pytest.param(-2.2061435, 1.89159812, -4.0, 7.02698366, marks=pytest.mark.slow),   # many librations
    pytest.param(-5.6981121, 29.12216138, W_H2, 1.07839035, marks=pytest.mark.slow),  # fast rotation
]


@pytest.mark.parametrize("th,om,s,t", TAYLOR_CASES)
def test_flow_against_a_30_digit_taylor_integration(th, om, s, t):
    mp.mp.dps = 30
    f = mp.odefun(lambda x, y: [y[1], s * mp.sin(y[0])], 0, [mp.mpf(th), mp.mpf(om)])
    ref = f(mp.mpf(t))
    th1, om1 = phase_flow(t, th, om, s)
    assert abs(th1 - float(ref[0])) < 2e-14 * max(1.0, abs(float(ref[0])))
    assert abs(om1 - float(ref[1])) < 2e-14 * max(1.0, abs(float(ref[1])))


def test_small_angles_keep_relative_accuracy():
    # theta ~ 1e-9: the flow is the linear one to O(theta^3), and the elliptic-function
    # evaluation must not lose the relative accuracy of such small numbers.
    for s in (W_H2, -W_E2):
        w = np.sqrt(abs(s))
        th0, om0, t = 1e-9, -0.4e-9 * w, 0.15
        th1, om1 = phase_flow(t, th0, om0, s)
        if s > 0:
            c, sh = np.cosh(w * t), np.sinh(w * t)
            lin = (c * th0 + sh * om0 / w, w * sh * th0 + c * om0)
        else:
            c, sn = np.cos(w * t), np.sin(w * t)
            lin = (c * th0 + sn * om0 / w, -w * sn * th0 + c * om0)
        assert th1 == pytest.approx(lin[0], rel=1e-13)
        assert om1 == pytest.approx(lin[1], rel=1e-13)


def test_upright_and_bottom_equilibria_stay():
    # pi and 2 pi are not doubles: an unstable equilibrium drifts from the rounding of its
    # angle like 1e-16 exp(w t), the stable one not at all.
    t = 0.7
    for s in (W_H2, -W_E2):
        w = np.sqrt(abs(s))
        eq = np.array([0.0, np.pi, -np.pi, 2 * np.pi])
        th, om = phase_flow(t, eq, 0.0, s)
        drift = 4e-16 * np.exp(w * t)
        assert np.all(np.abs(th - eq) <= drift)
        assert np.all(np.abs(om) <= w * drift)
        if s < 0:  # theta = 0 is exact, and the bottom of this phase's potential
            assert th[0] == 0.0 and om[0] == 0.0


def test_free_flight_and_broadcasting():
    th, om = phase_flow(np.array([0.0, 1.0, 2.0])[:, None], [0.1, 0.2], 0.5, 0.0)
    assert th.shape == (3, 2)
    assert np.allclose(th, np.array([0.1, 0.2]) + 0.5 * np.array([0.0, 1.0, 2.0])[:, None])
    assert np.allclose(om, 0.5)


def test_rotations_are_counted_not_wrapped():
    # Fast rotation over a long time: theta' ~ constant, theta ~ theta' t, many turns.
    s = -W_E2
    th, om = phase_flow(10.0, 0.0, 200.0, s)
    ref = dop853(0.0, 200.0, s, 10.0, rtol=1e-13)
    assert th > 300 * np.pi
    assert th == pytest.approx(ref[0], abs=1e-8)


@settings(max_examples=60, deadline=None)
@given(th=st.floats(-10, 10), p=st.floats(-3, 3), sgn=st.sampled_from([1.0, -1.0]),
       t1=st.floats(0, 0.5), t2=st.floats(0, 0.5))
def test_group_law_reversibility_and_energy(th, p, sgn, t1, t2):
    s = sgn * W_H2
    w = np.sqrt(W_H2)
    om = p * w
    a = phase_flow(t1, th, om, s)
    b = phase_flow(t2, *a, s)
    c = phase_flow(t1 + t2, th, om, s)
    assert np.allclose(b, c, rtol=1e-11, atol=1e-11 * w)
    back = phase_flow(-(t1 + t2), *c, s)
    assert np.allclose(back, (th, om), rtol=1e-11, atol=1e-11 * w)
    energy = lambda x, v: 0.5 * v * v + s * np.cos(x)  # noqa: E731
    assert energy(*c) == pytest.approx(energy(th, om), rel=1e-12, abs=1e-12 * W_H2)


def test_phase_flow_validates():
    with pytest.raises(KapitzaValueError, match="theta0"):
        phase_flow(1.0, np.nan, 0.0, 1.0)
    with pytest.raises(KapitzaValueError, match="s must be finite"):
        phase_flow(1.0, 0.0, 0.0, np.inf)


# ------------------------------------------------------------------ one state and many: twins
def twin_states():
    """States of every branch: libration, rotation, on and a hair off the separatrix (m1 = 0 exactly,
    tiny |m1| either side), both sides of the switch of method at m = 1/2, free flight, small
    amplitudes, several turns, and times of many quarter periods (``w t`` up to 210)."""
    rng = np.random.default_rng(5)
    th, om, s, t = [], [], [], []
    for s_ in (W_H2, -W_E2, 4.0, -4.0, 0.0):
        for th_ in (0.0, 1e-9, 0.05, 0.7, 2.0, -2.6, np.pi, 9.0, -30.0):
            d = -np.sin(th_ / 2) if s_ > 0 else np.cos(th_ / 2)
            for m1 in (0.9, 0.51, 0.5, 0.49, 1e-2, 1e-10, 0.0, -1e-10, -1e-2, -0.5, -3.0):
                if d * d >= m1:
                    v = 2.0 * np.sqrt(abs(s_) or 1.0) * np.sqrt(d * d - m1)
                    for sign in (1.0, -1.0):
                        for t_ in (0.0, 1e-7, 0.15, 0.3, 2.7, 20.0):
                            th.append(th_), om.append(sign * v), s.append(s_), t.append(t_)
    n = 3000
    w = rng.uniform(0.5, 30.0, n)
    th += list(rng.uniform(-12, 12, n))
    om += list(rng.normal(0, 2, n) * w)
    s += list(rng.choice([-1.0, 1.0], n) * w * w)
    t += list(rng.exponential(1.0, n) / w)
    return (np.array(v) for v in (th, om, s, t))


def test_one_state_step_is_the_array_step_to_the_last_bit():
    """The per-state path (each branch chosen by ``if``) and the array path (masks) give the same
    doubles on every branch: they share every formula and numpy's own functions."""
    th, om, s, t = twin_states()
    want_th, want_om = _phase_step_arrays(th, om, s, t)
    got = np.array([_phase_step_one(*x) for x in zip(th, om, s, t)])
    assert np.array_equal(got[:, 0], want_th) and np.array_equal(got[:, 1], want_om)
    # and the array function hands one state to the per-state path, shaped as its input
    for shape in ((), (1,), (1, 1)):
        a, b = _phase_step(np.full(shape, th[7]), om[7], s[7], np.full(shape, t[7]))
        assert type(a) is type(b) is np.ndarray and a.shape == b.shape == shape
        assert a.item() == want_th[7] and b.item() == want_om[7]


@settings(max_examples=200, deadline=None)
@given(th=st.floats(-20, 20), p=st.floats(-4, 4), s=st.floats(-400, 400), t=st.floats(0, 3))
def test_one_state_step_is_the_array_step_property(th, p, s, t):
    om = p * np.sqrt(abs(s) + 1e-300)
    want = _phase_step_arrays(np.array([th]), np.array([om]), np.array([s]), np.array([t]))
    got = _phase_step_one(th, om, s, t)
    assert got[0] == want[0][0] and got[1] == want[1][0]


def test_the_saddle_stays_and_a_state_too_near_it_is_refused():
    # exactly upright in the hyperbolic phase: the saddle of the separatrix, for any time (sech(w t)
    # underflows beyond w t ~ 372 and its square beyond ~ 180; the flow once returned 0/0 there)
    import warnings

    from kapitza.motion import phase_flow
    from kapitza._validate import KapitzaValueError

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for t in (30.0, 40.0, 80.0, 200.0):
            assert phase_flow(t, 0.0, 0.0, 109.81) == (0.0, 0.0)
        th, om = phase_flow(np.array([40.0, 0.3, 200.0]), np.array([0.0, 0.5, 0.0]), np.array([0.0, 1.0, 0.0]), 109.81)
        assert th[0] == th[2] == om[0] == om[2] == 0.0
        assert np.isfinite(th[1]) and np.isfinite(om[1])
        # 1e-170 from it: still resolved while near the saddle (e^{w t} 1e-170), refused once the
        # modulus' complement (1e-340) would carry the motion
        th, _ = phase_flow(30.0, 1e-170, 0.0, 109.81)
        assert 1e-35 < th < 1e-33
        with pytest.raises(KapitzaValueError, match="within 1e-150 of the upright"):
            phase_flow(40.0, 1e-170, 0.0, 109.81)
