"""Every function that takes the physical (T, A) also takes Arnold's (eps, mu), with l and g."""
import numpy as np
import pytest

import kapitza as K
from kapitza import motion

EPS, MU, L, G = 0.53033, 0.313209, 0.8, 9.81


def _TA():
    T, A = K.to_physical(EPS, MU, L, G)
    return float(T), float(A)


def test_motion_functions_give_the_same_answer_for_either_parameter_set():
    T, A = _TA()
    arn = dict(eps=EPS, mu=MU, l=L, g=G)
    t = np.linspace(0.0, 6 * T, 13)
    a = K.simulate(0.1, 0.0, T, A, L, G, periods=3)
    b = K.simulate(0.1, 0.0, **arn, periods=3)
    assert (b.T, b.A) == (a.T, a.A) and np.array_equal(a.theta, b.theta)
    assert np.array_equal(K.nonlinear_motion(t, 0.1, 0.0, T, A, L, G)[0], K.nonlinear_motion(t, 0.1, 0.0, **arn)[0])
    assert np.array_equal(K.linear_motion(t, 0.1, 0.0, T, A, L, G)[0], K.linear_motion(t, 0.1, 0.0, **arn)[0])
    assert np.array_equal(motion.phase_energy(t, 0.1, 0.0, T, A, L, G), motion.phase_energy(t, 0.1, 0.0, **arn))
    assert np.array_equal(K.stroboscopic_map([0.1, 0.2], 0.0, T, A, L, G, periods=4).theta,
                          K.stroboscopic_map([0.1, 0.2], 0.0, **arn, periods=4).theta)
    assert np.array_equal(K.survival([0.1, 0.4], 0.0, T, A, L, G, periods=5), K.survival([0.1, 0.4], 0.0, **arn, periods=5))
    ba = K.basin(T, A, L, G, periods=5, n_theta=5, n_dtheta=4)
    bb = K.basin(**arn, periods=5, n_theta=5, n_dtheta=4)
    assert np.array_equal(ba.periods_survived, bb.periods_survived) and (bb.T, bb.A) == (ba.T, ba.A)


@pytest.mark.parametrize("fn", [lambda **kw: K.simulate(0.1, 0.0, periods=1, **kw),
                                lambda **kw: K.linear_motion(1.0, 0.1, 0.0, **kw),
                                lambda **kw: K.basin(periods=1, n_theta=2, n_dtheta=2, **kw),
                                lambda **kw: K.analyze(**kw)])
def test_one_parameter_set_exactly(fn):
    for kw, words in ((dict(), "either eps and mu, or T and A"),
                      (dict(T=0.15, A=100.0, eps=0.5, mu=0.3), "not both"),
                      (dict(eps=0.5), "eps and mu must be given together"),
                      (dict(T=0.15), "T and A must be given together"),
                      (dict(eps=-1.0, mu=0.3), "eps must be finite and > 0")):
        with pytest.raises(ValueError, match=words):
            fn(**kw)
