"""The compiled integrated path (numba, DOP853 per state) and the numpy DOP853 loop are twins: the same
equation, method, tolerances per component, window test and searches, so the same results to the
integration error (the largest safe tilt to its 1 % accuracy, but at a ragged edge of the safe set).
Checked here against scipy's own DOP853 step by step, against closed forms of linear motions, and
against the numpy path on small maps and start grids."""
import math
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("numba")

import kapitza
from kapitza.drives import parse_drive
from kapitza.motion.basins import INTEGRATED_ATOL, INTEGRATED_RTOL, _IntegratedPeriod, survival_chunk
from kapitza.sweeps.kernel import block_quantities, period_step

G = kapitza.parameters.G_EARTH
ZETA = 0.05
C_DAMPED = 2.0 * ZETA * math.sqrt(G)  # zeta = 0.05 at l = 1
KW = dict(plane="arnold", l=1.0, g=G, tol=0.5, quantities=("tilt",), directions=1, basin_resolution=5,
          accuracy=0.01, floor=1e-4)


def _jit():
    import kapitza.motion._integrated_jit as J

    return J


def _plan(drive, eps, mu, c=0.0, model="nonlinear"):
    T, A = (np.atleast_1d(np.asarray(v, float)) for v in kapitza.to_physical(eps, mu))
    period = _IntegratedPeriod(T, A, 1.0, G, c, parse_drive(drive) if isinstance(drive, str) else drive, 0.5,
                               model)
    return period, _jit().pack_plan(period), float(T[0])


def _hand_plan(T, s, c, m=64, linear=True):
    """A constant ``s`` (no drive), ``theta'' = s f(theta) - c theta'``, for closed forms."""
    return (np.array([2.0 * T]), np.zeros(1), np.array([m], np.int64), np.array([0.0, 1.0]), np.zeros(1),
            np.zeros(1), np.zeros(1), 1.0, float(s), float(c), linear, INTEGRATED_RTOL / math.sqrt(2.0),
            INTEGRATED_ATOL / math.sqrt(2.0))


@pytest.mark.parametrize("drive, c", [("sine", 0.0), ("square", C_DAMPED), ("rectangular:0.3", 0.2),
                                      ("triangle", 0.0)])
def test_one_period_is_scipys_dop853_to_rounding(drive, c):
    """The first period takes scipy's steps (the same initial step, control and restarts at the jumps)."""
    from scipy.integrate import solve_ivp

    period, plan, T = _plan(drive, 0.7, 0.4, c)
    y0 = np.array([0.3, -0.8])
    th, om = _jit().advance(y0[:1], y0[1:], [0], plan, 1)
    table = _jit().drive_table(period.drive)
    xs = table[0]
    A, rtol, atol = period.A[0], plan[-2], plan[-1]
    y = y0.copy()
    for k in range(xs.size - 1):
        a, b = xs[k], xs[k + 1]

        def rhs(x, z, k=k):
            shape = table[1][k] + table[2][k] * (x - xs[k]) + table[3][k] * np.sin(2 * np.pi * x)
            return [2 * T * z[1], 2 * T * ((G + A * shape) * np.sin(z[0]) - c * z[1])]

        y = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=rtol, atol=atol).y[:, -1]
    assert abs(th[0] - y[0]) < 1e-12 and abs(om[0] - y[1]) < 1e-11


def test_the_drive_tables_are_the_drives():
    J = _jit()
    tau = np.random.default_rng(1).uniform(0.0, 2.0, 2000)
    t = np.arange(40) / 40 * 0.025
    a = 650.0 * np.sin(2 * np.pi * t / 0.025) + 90.0 * np.sign(np.sin(6 * np.pi * t / 0.025))
    drives = [parse_drive(s) for s in ("square", "rectangular:0.3", "steps:2,-1,1,-1:0.2,0.3,0.2,0.3", "sine",
                                       "triangle")]
    drives += [kapitza.from_samples(t, a), kapitza.from_samples(t, a, kind="constant")]
    for d in drives:
        xs, sa, sb, sd = J.drive_table(d)
        x = 0.5 * tau
        k = np.searchsorted(xs, x, side="right") - 1
        got = sa[k] + sb[k] * (x - xs[k]) + sd[k] * np.sin(2 * np.pi * x)
        assert xs[0] == 0.0 and xs[-1] == 1.0 and np.all(np.diff(xs) > 0)
        assert np.max(np.abs(got - d._shape(tau))) < 1e-12, d


def test_a_drive_known_only_by_its_shape_stays_on_the_numpy_path():
    class Sawtooth(kapitza.Drive):
        name = "test-sawtooth"
        _breakpoints = (1.0,)

        def _shape(self, tau):
            return np.where(tau < 1.0, tau, tau - 2.0)

    class Sine2(kapitza.SineWave):  # a subclass with another shape is not the sine
        def _shape(self, tau):
            return np.sin(np.pi * tau) ** 3

    assert _jit().drive_table(Sawtooth()) is None and _jit().drive_table(Sine2()) is None
    kw = dict(KW, periods=5)
    a = block_quantities([0.4, 0.6], [0.2], drive=Sawtooth(), compiled=False, **kw)["max_safe_tilt"]
    b = block_quantities([0.4, 0.6], [0.2], drive=Sawtooth(), compiled=True, **kw)["max_safe_tilt"]
    assert np.array_equal(a, b) and np.all(a > 0)


def test_damped_linear_oscillation_decays_as_its_closed_form():
    """``theta'' = -w0^2 theta - c theta'``: after N periods, ``e^{-ct/2} (a cos + b sin)(w_d t)``."""
    w0, c, T, N = 3.0, 0.4, 0.37, 25
    plan = _hand_plan(T, -w0 * w0, c)
    th0, om0 = 0.2, -0.5
    th, om = _jit().advance([th0], [om0], [0], plan, N)
    t = 2.0 * T * N
    wd = math.sqrt(w0 * w0 - 0.25 * c * c)
    a, b = th0, (om0 + 0.5 * c * th0) / wd
    e = math.exp(-0.5 * c * t)
    want_th = e * (a * math.cos(wd * t) + b * math.sin(wd * t))
    want_om = -0.5 * c * want_th + e * wd * (-a * math.sin(wd * t) + b * math.cos(wd * t))
    assert abs(th[0] - want_th) < 1e-8 * abs(th0) and abs(om[0] - want_om) < 1e-8 * w0 * abs(th0)


@pytest.mark.parametrize("c", [0.0, 0.6])
def test_survival_of_a_linear_hyperbolic_motion_is_its_exit_time(c):
    """``theta'' = w^2 theta - c theta'`` from rest: ``theta`` grows monotonically, and leaves the
    window at the root of ``alpha e^{r1 t} + beta e^{r2 t} = tol``."""
    from scipy.optimize import brentq

    w, T, tol = 2.0, 0.05, 0.5
    plan = _hand_plan(T, w * w, c)
    r1 = 0.5 * (-c + math.sqrt(c * c + 4 * w * w))
    r2 = 0.5 * (-c - math.sqrt(c * c + 4 * w * w))
    th0 = np.geomspace(1e-6, 0.4, 25)
    got = _jit().survival_compiled(th0, np.zeros_like(th0), np.zeros(th0.size, np.int64), plan, 10_000, tol)
    for x0, k in zip(th0, got):
        alpha, beta = x0 * -r2 / (r1 - r2), x0 * r1 / (r1 - r2)
        t_exit = brentq(lambda t: alpha * math.exp(r1 * t) + beta * math.exp(r2 * t) - tol, 0.0, 100.0)
        want = int(t_exit // (2 * T))
        if abs(t_exit / (2 * T) - round(t_exit / (2 * T))) > 1e-6:
            assert k == want, (x0, k, want)


@pytest.mark.parametrize("margin, survives", [(1e-4, False), (-1e-4, True)])
def test_an_excursion_between_the_sample_instants_is_seen(margin, survives):
    """A linear oscillation whose turning points fall between the check instants, its amplitude
    ``tol (1 + margin)``: out by 1e-4 it leaves, in by 1e-4 it stays."""
    w, T, tol = 5.0, 1.0, 0.5
    m = 64
    plan = _hand_plan(T, -w * w, 0.0, m=m)
    # the first turning point at t = (pi/2 - phase)/w, placed halfway between two instants
    t_turn = (7.5 / m) * 2.0 * T
    phase = math.pi / 2 - w * t_turn
    amp = tol * (1.0 + margin)
    th0, om0 = amp * math.sin(phase), amp * w * math.cos(phase)
    got = _jit().survival_compiled(np.array([th0]), np.array([om0]), np.zeros(1, np.int64), plan, 3, tol)
    assert (got[0] == 3) == survives


def _measured(kind):
    t = np.arange(24) / 24
    return kapitza.from_samples(t, np.sin(2 * np.pi * t) + 0.3 * np.cos(6 * np.pi * t), kind=kind)


@pytest.mark.parametrize("drive, c", [("sine", 0.0), ("square", C_DAMPED),
                                      # the numpy loop steps across the samples' jumps and kinks: minutes
                                      pytest.param("samples-linear", 0.1, marks=pytest.mark.slow),
                                      pytest.param("samples-constant", 0.1, marks=pytest.mark.slow)])
def test_survival_counts_agree_with_the_numpy_loop(drive, c):
    eps, mu = 0.55, 0.3
    if drive.startswith("samples-"):  # linear or held between its 24 samples (zone 1 at eps 0.5, mu 0.2)
        drive, eps, mu = _measured(drive.split("-")[1]), 0.5, 0.2
    period, plan, T = _plan(drive, eps, mu, c)
    th = np.linspace(-0.5, 0.5, 17)
    om = np.linspace(-1.0, 1.0, 17) / T
    th0, om0 = (a.ravel() for a in np.meshgrid(th, om))
    point = np.zeros(th0.size, dtype=np.int64)
    want = survival_chunk(th0, om0, period, 100, 0.5, idx=point)
    got = _jit().survival_compiled(th0, om0, point, plan, 100, 0.5)
    assert 0.03 < np.mean(want == 100) < 0.9  # both outcomes occur
    assert np.mean(got == want) >= 0.99


def _compare_maps(drive, c, eps, mu, periods, allowed):
    kw = dict(KW, periods=periods, drive=drive, c=c)
    want = block_quantities(eps, mu, compiled=False, **kw)["max_safe_tilt"]
    got = block_quantities(eps, mu, compiled=True, **kw)["max_safe_tilt"]
    assert np.count_nonzero(want > 0) >= 0.25 * want.size  # enough safe points to compare
    # within the stated accuracy (a start less than 1 % above lo leaves, on both paths)
    off = np.abs(got - want) > 0.01 * np.maximum(got, want) + 1e-12
    assert np.count_nonzero(off) <= allowed, (drive, c, np.argwhere(off), got[off], want[off])


# a corner of the chart where most points have a safe tilt: zones 0 and 1
EPS, MU = np.linspace(0.15, 0.6, 5), np.linspace(0.05, 0.45, 4)


@pytest.mark.parametrize("drive, c", [("sine", 0.0), ("square", C_DAMPED), ("rectangular:0.3", 0.2)])
def test_safe_tilts_agree_with_the_numpy_path(drive, c):
    """20 points, 100 periods: at most one ragged-edge point apart by more than 1 %."""
    _compare_maps(drive, c, EPS, MU, 100, allowed=1)


@pytest.mark.slow
@pytest.mark.parametrize("drive, c", [("sine", 0.0), ("square", C_DAMPED), ("rectangular:0.3", 0.2),
                                      ("triangle", 0.0), ("triangle", C_DAMPED)])
def test_safe_tilts_agree_with_the_numpy_path_on_a_larger_map(drive, c):
    """8 x 8 points over zones 0 and 1, 300 periods: at most 2 of 64 apart by more than 1 %."""
    _compare_maps(drive, c, np.linspace(0.1, 0.8, 8), np.linspace(0.05, 0.6, 8), 300, allowed=2)


def test_the_triangle_wave_map_agrees_with_the_numpy_path():
    _compare_maps("triangle", 0.0, EPS[1:4:2], MU[:2], 30, allowed=1)


def test_basin_quantities_agree_with_the_numpy_path():
    kw = dict(KW, quantities=("tilt", "radius", "basin"), directions=3, basin_resolution=7, periods=40,
              drive="sine", c=C_DAMPED)
    want = block_quantities([0.3, 0.6], [0.2, 0.45], compiled=False, **kw)
    got = block_quantities([0.3, 0.6], [0.2, 0.45], compiled=True, **kw)
    assert set(got) == set(want)
    for k in ("basin_area", "median_escape"):
        assert np.max(np.abs(got[k] - want[k])) <= (2.0 / 49 if k == "basin_area" else 1.0), k
    for k in ("max_safe_tilt", "max_safe_radius"):
        assert np.allclose(got[k], want[k], rtol=0.011), k


def test_period_step_is_unchanged_for_the_numpy_reference():
    """The numpy DOP853 loop stays the reference: compiled=False never touches the compiled module."""
    code = ("import sys; from kapitza.sweeps.kernel import block_quantities; "
            "block_quantities([0.5], [0.3], plane='arnold', l=1.0, g=9.81, drive='sine', periods=2, tol=0.5, "
            "quantities=('tilt',), directions=1, basin_resolution=5, accuracy=0.01, floor=1e-4, compiled=False); "
            "sys.exit(1 if 'kapitza.motion._integrated_jit' in sys.modules else 0)")
    assert subprocess.run([sys.executable, "-c", code], capture_output=True).returncode == 0
    assert isinstance(period_step(np.array([0.1]), np.array([50.0]), 1.0, G, 0.1, parse_drive("square"), 0.5),
                      _IntegratedPeriod)
