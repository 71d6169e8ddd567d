"""Validation at the public boundary: every public function rejects bad input with a
KapitzaValueError (a ValueError) naming the parameter and the value; valid input never
yields NaN (or a RuntimeWarning, which the test configuration turns into an error)."""
import math
import re

import numpy as np
import pytest

import kapitza as K
from kapitza import phase_plane as PP

NAN, INF = float("nan"), float("inf")
BAD = {
    "pos": [0.0, -1.0, NAN, INF, -INF],     # finite and > 0
    "unit": [0.0, -0.5, 1.0, 1.5, NAN, INF],  # 0 < mu < 1
    "fin": [NAN, INF, -INF],                # finite
    "t": [-1.0, NAN, INF],                  # finite and >= 0
    "int0": [-1, 1.5, NAN],                 # integer >= 0
    "int1": [0, -1, 2.5, NAN],              # integer >= 1
}

# (function, valid keyword arguments, {parameter: kind})
P4 = {"T": "pos", "A": "pos", "l": "pos", "g": "pos"}
SPECS = [
    (K.to_arnold, dict(T=0.15, A=100.0, l=1.0, g=9.81), P4),
    (K.to_physical, dict(eps=0.5, mu=0.3, l=1.0, g=9.81), {"eps": "pos", "mu": "pos", "l": "pos", "g": "pos"}),
    (K.frequencies, dict(A=100.0, l=1.0, g=9.81), {"A": "pos", "l": "pos", "g": "pos"}),
    (K.phase_angles, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "unit"}),
    (K.is_stable, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.zone_index, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.stability_margin, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.floquet, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.floquet_multipliers, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.growth_rate, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.rotation_number, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.stability_grid, dict(eps=[0.5, 1.0], mu=[0.3]), {"eps": "pos", "mu": "pos"}),
    (K.zone_edges, dict(mu=0.3, n=1), {"mu": "unit", "n": "int0"}),
    (K.zone_width, dict(mu=0.3, n=1), {"mu": "unit", "n": "int0"}),
    (K.G_m_curve, dict(mu=0.3, m=1), {"mu": "unit", "m": "int0"}),
    (K.period_edges, dict(A=100.0, n=1, l=1.0, g=9.81), {"A": "pos", "n": "int0", "l": "pos", "g": "pos"}),
    (K.amplitude_edges, dict(T=0.15, n=1, l=1.0, g=9.81), {"T": "pos", "n": "int0", "l": "pos", "g": "pos"}),
    (K.monodromy, dict(T=0.15, A=100.0, l=1.0, g=9.81), P4),
    (K.linear_motion, dict(t=1.0, theta0=0.1, dtheta0=0.0, T=0.15, A=100.0, l=1.0, g=9.81),
     {"t": "t", "theta0": "fin", "dtheta0": "fin", **P4}),
    (K.alpha, dict(T=0.15, A=100.0, l=1.0, g=9.81), P4),
    (K.beta, dict(T=0.15, A=100.0, l=1.0, g=9.81), P4),
    (K.boundary_periods, dict(A=100.0, count=3, l=1.0, g=9.81), {"A": "pos", "count": "int1", "l": "pos", "g": "pos"}),
    (K.boundary_table, dict(A=100.0, count=3, l=1.0, g=9.81), {"A": "pos", "count": "int1", "l": "pos", "g": "pos"}),
    (K.periodic_solution, dict(A=100.0, index=1, l=1.0, g=9.81), {"A": "pos", "index": "int1", "l": "pos", "g": "pos"}),
    (K.analyze, dict(eps=0.5, mu=0.3), {"eps": "pos", "mu": "pos"}),
    (K.analyze, dict(T=0.15, A=100.0, l=1.0, g=9.81), P4),
    (PP.f, dict(phi=0.3, d=2.0), {"phi": "fin", "d": "pos"}),
    (PP.angle_map, dict(phi=0.3, d=2.0), {"phi": "fin", "d": "pos"}),
    (PP.G, dict(phi=0.3), {"phi": "fin"}),
    (PP.G_inverse, dict(s=0.3, branch=0), {"s": "fin"}),
    (PP.h, dict(phi=0.3, D=2.0), {"phi": "fin", "D": "pos"}),
    (PP.phi_h, dict(t=0.1, phi0=0.3, w_h=2.0), {"t": "fin", "phi0": "fin", "w_h": "pos"}),
    (PP.notable_points, dict(phi0=-0.3, T=0.15, A=100.0, r0=1.0, l=1.0, g=9.81),
     {"phi0": "fin", "T": "pos", "A": "pos", "r0": "pos", "l": "pos", "g": "pos"}),
]

CASES = [(f, kw, p, kind) for f, kw, params in SPECS for p, kind in params.items()]


def _value_text(v):
    return repr(int(v)) if isinstance(v, int) else repr(float(v))


@pytest.mark.parametrize("f,kw,param,kind", CASES, ids=[f"{f.__name__}-{p}" for f, _, p, _ in CASES])
def test_bad_values_raise_naming_parameter_and_value(f, kw, param, kind):
    f(**kw)  # the baseline is valid
    for bad in BAD[kind]:
        args = dict(kw, **{param: bad})
        with pytest.raises(K.KapitzaValueError) as info:
            f(**args)
        msg = str(info.value)
        assert isinstance(info.value, ValueError)
        assert re.search(rf"\b{re.escape(param)}\b", msg), (f.__name__, param, msg)
        assert _value_text(bad) in msg, (f.__name__, param, bad, msg)
        assert "\n" not in msg
    # one bad element in an array: the message says where
    if kind in ("pos", "fin", "unit", "t"):
        good = kw[param] if np.ndim(kw[param]) == 0 else kw[param][0]
        args = dict(kw, **{param: [good, BAD[kind][0]] if kind != "fin" else [good, NAN]})
        if f in (K.stability_grid,) or f.__name__ in ("analyze", "boundary_table", "periodic_solution"):
            return  # 1-D grids / scalar-only functions
        with pytest.raises(K.KapitzaValueError, match=r"at index \(1,\)|t must be"):
            f(**args)
    # text is not a number
    with pytest.raises(K.KapitzaValueError, match=re.escape(param)):
        f(**dict(kw, **{param: "abc"}))


@pytest.mark.parametrize("f,kw", [
    (K.period_edges, dict(A=9.81, n=0)), (K.boundary_periods, dict(A=5.0, count=2)),
    (K.boundary_table, dict(A=9.0, count=2)), (K.periodic_solution, dict(A=9.81, index=1)),
    (K.alpha, dict(T=0.1, A=9.0)), (K.beta, dict(T=0.1, A=9.81)),
    (PP.notable_points, dict(phi0=-0.3, T=0.1, A=9.0)),
])
def test_A_at_most_g_is_refused_where_an_elliptic_phase_is_needed(f, kw):
    with pytest.raises(K.KapitzaValueError, match=r"A must exceed g"):
        f(**kw)


def test_other_refusals_name_what_is_wrong():
    with pytest.raises(K.KapitzaValueError, match="1-D"):
        K.stability_grid([[0.5, 1.0]], [0.3])
    with pytest.raises(K.KapitzaValueError, match="not both"):
        K.analyze(eps=0.5, mu=0.3, T=0.1, A=100.0)
    with pytest.raises(K.KapitzaValueError, match="together"):
        K.analyze(eps=0.5)
    with pytest.raises(K.KapitzaValueError, match="branch"):
        PP.G_inverse(0.3, 1)
    with pytest.raises(K.KapitzaValueError, match="must not be empty"):
        K.is_stable([], 0.3)


# ---------------------------------------------------------------- no NaN for valid input
def _assert_no_nan(obj, where):
    fields = [getattr(obj, k) for k in obj.__dataclass_fields__] if hasattr(obj, "__dataclass_fields__") else [obj]
    for v in fields:
        if isinstance(v, tuple):
            for w in v:
                _assert_no_nan(w, where)
            continue
        a = np.asarray(v)
        if a.dtype.kind in "fc":
            assert not np.isnan(a).any(), where


EPS = np.geomspace(1e-12, 1e6, 91)
MU_ALL = np.concatenate([np.geomspace(1e-12, 1e6, 37), [1.0, np.nextafter(1.0, 0.0), np.nextafter(1.0, 2.0)]])
MU_UNIT = np.array([1e-12, 1e-8, 1e-3, 0.1, 0.15, 0.5, 0.9, 1 - 1e-9, np.nextafter(1.0, 0.0)])


def test_no_nan_from_the_eps_mu_functions_over_a_wide_range():
    e, m = EPS[:, None], MU_ALL[None, :]
    for f in (K.is_stable, K.zone_index, K.growth_rate, K.rotation_number, K.floquet, K.floquet_multipliers):
        _assert_no_nan(f(e, m), f.__name__)
    g = K.growth_rate(e, m)
    assert np.all(np.isfinite(g))  # finite everywhere, even where tr M is not
    sm = K.stability_margin(e, m)
    # the margins are -inf where mu >= 1; the edges of a zone that does not exist are NaN there only
    assert not np.isnan(sm.margin).any()
    assert np.array_equal(np.isnan(sm.eps_lo), np.broadcast_to(m >= 1, sm.eps_lo.shape))
    _assert_no_nan(K.stability_grid(EPS, MU_ALL), "stability_grid")
    for eps in (1e-9, 0.5, 3.0, 700.0, 1e5):
        for mu in (1e-9, 0.3, np.nextafter(1.0, 0.0), 1.0, 30.0):
            rep = K.analyze(eps=eps, mu=mu)
            d = rep.as_dict()
            assert all(not (isinstance(v, float) and math.isnan(v)) for v in d.values())


def test_no_nan_from_the_zone_functions_over_a_wide_range():
    mu = MU_UNIT[:, None]
    n = np.array([0, 1, 2, 10, 100, 10_000])[None, :]
    for out in (K.zone_edges(mu, n), K.zone_width(mu, n), K.zone_width(mu, n, log=True), K.G_m_curve(mu, n),
                K.phase_angles(EPS[:, None], MU_UNIT[None, :])):
        _assert_no_nan(out, "zones")
    assert np.all(np.isfinite(K.zone_width(mu, n, log=True)))


def test_no_nan_from_the_physical_functions_over_a_wide_range():
    T = np.geomspace(1e-9, 1e4, 14)[:, None]
    A = np.array([0.1, 9.81, 9.81 * (1 + 1e-12), 10.0, 100.0, 1e4, 1e8])[None, :]
    _assert_no_nan(K.monodromy(T, A), "monodromy")
    _assert_no_nan(K.to_arnold(T, A), "to_arnold")
    _assert_no_nan(K.amplitude_edges(T, 3), "amplitude_edges")
    for Ai in A.ravel()[3:]:
        _assert_no_nan(K.boundary_periods(Ai, 6), "boundary_periods")
        _assert_no_nan(K.alpha(T, Ai), "alpha")
        _assert_no_nan(K.beta(T, Ai), "beta")
        _assert_no_nan(PP.notable_points(np.linspace(-6.28, 0.0, 9)[:, None], T.ravel()[None, :], Ai), "notable_points")
    for Ti in T.ravel():
        for Ai in A.ravel():
            try:
                out = K.linear_motion(np.array([0.0, Ti, 3.3 * Ti]), 0.1, 0.2, Ti, Ai)
            except OverflowError as exc:  # documented: the motion leaves the range of a double
                assert "beyond the range of a double" in str(exc)
                continue
            _assert_no_nan(out, "linear_motion")


def test_no_nan_from_the_phase_plane_functions_at_extremes():
    t = np.array([-1e4, -100.0, -1.0, 0.0, 1.0, 100.0, 1e4])
    for phi0 in (-3 * math.pi / 4, -math.pi / 4, 0.0, math.pi / 4, 1.0, 5 * math.pi / 4):
        _assert_no_nan(PP.phi_h(t, phi0, 3.0), "phi_h")
    phis = np.array([-1e6, -10.0, -math.pi / 2, -math.pi / 4, 0.0, 1.0, math.pi / 2, 1e6])
    for d in (1e-12, 0.5, 1.0, 2.0, 1e12):
        for f in (PP.f, PP.angle_map, PP.h):
            _assert_no_nan(f(phis, d), f.__name__)
    for branch in (0, -1):
        _assert_no_nan(PP.G_inverse(np.array([-1e6, -400.0, 0.0, 400.0, 1e6]), branch), "G_inverse")


@pytest.mark.parametrize("value, what", [
    (np.array([0.5 + 3j]), "complex"),
    ("1.5", "text"),
    (b"1", "text"),
    (True, "truth value"),
    (np.ma.masked_array([0.5, 0.6], mask=[0, 1]), "masked"),
    ([0.5, "x"], "real number"),
    (10**400, "real number"),
])
def test_inputs_are_never_silently_converted(value, what):
    """Complex values, text, truth values and masked entries are refused, not read as numbers."""
    with pytest.raises(K.KapitzaValueError, match=f"eps must be a real number.*{what}"):
        K.is_stable(value, 0.3)


def test_counts_refuse_truth_values_text_and_huge_integers():
    for bad in (True, "3", 10**400):
        with pytest.raises(K.KapitzaValueError, match="n must be an integer"):
            K.zone_edges(0.3, bad)
    # an unmasked masked array and numpy scalars of any float type are fine
    assert K.is_stable(np.ma.masked_array([0.5, 0.6], mask=[0, 0]), 0.3).all()
    assert K.is_stable(np.float32(0.5), 0.3)
