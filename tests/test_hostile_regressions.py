"""Breaks found by hostile input, each pinned by a test: bounded work, exact angle reduction,
no NaN for fast starts, the DOP853 floor, named messages, atomic paths named as given,
Ctrl-C while the command starts. (The fuzz suite, tests/test_fuzz.py, looks for the next ones.)"""
import os
import signal
import subprocess
import sys
import time
import warnings

import mpmath
import numpy as np
import pytest

import kapitza as K
from kapitza import _validate as V
from kapitza import mathieu
from kapitza.motion import nonlinear_motion, phase_flow, simulate, stroboscopic_map, survival

from cli_util import assert_one_line_error, run


@pytest.fixture(autouse=True)
def _strict(monkeypatch):
    monkeypatch.delenv(V.ALLOW_LARGE_ENV, raising=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield


def _refused(fn, *needles):
    with pytest.raises(ValueError) as exc:
        fn()
    for n in needles:
        assert n in str(exc.value), (n, str(exc.value))
    return str(exc.value)


# ------------------------------------------------------------------ bounded work
@pytest.mark.parametrize("call, name", [
    (lambda: K.boundary_periods(100.0, 10**12), "count"),
    (lambda: K.boundary_table(100.0, 10**6), "count"),
    (lambda: K.periodic_solution(100.0, 10**12), "index"),
    (lambda: stroboscopic_map(0.1, 0.0, 0.15, 100.0, periods=10**12), "periods"),
    (lambda: survival(0.1, 0.0, 0.15, 100.0, periods=10**9), "periods"),
    (lambda: K.basin(0.15, 100.0, n_theta=10**12, n_dtheta=2), "n_theta"),
    (lambda: nonlinear_motion(1e300, 0.1, 0.0, 0.15, 100.0), "t / (2 T)"),
    (lambda: simulate(0.1, 0.0, 0.15, 100.0, periods=1e9), "periods * points_per_period"),
    (lambda: simulate(0.1, 0.0, 0.15, 100.0, damping=3e4), "stiff"),
    (lambda: mathieu.characteristic_a(10**6, 1.0), "rows of the truncated matrix"),
    (lambda: mathieu.characteristic_a(2, 1e300), "q must satisfy"),
])
def test_large_requests_are_refused_with_the_limit_and_the_way_past_it(call, name):
    # CPU seconds of this process, not wall time: a refusal does no work, however busy the machine is.
    t0 = time.process_time()
    msg = _refused(call, name)
    assert time.process_time() - t0 < 5.0
    if "must be <=" in msg:
        assert V.ALLOW_LARGE_ENV + "=1" in msg


def test_the_environment_variable_lifts_a_bound(monkeypatch):
    _refused(lambda: V.bounded_count("count", 11, 10), "<= 10")
    monkeypatch.setenv(V.ALLOW_LARGE_ENV, "1")
    assert V.bounded_count("count", 11, 10) == 11
    # beyond int64 nothing is wrapped, bound or no bound
    _refused(lambda: V.bounded_count("count", 10**400, 10), "below 2**62")


def test_workers_are_capped_at_the_cpus_and_the_chunks(monkeypatch):
    started = []
    import concurrent.futures as cf
    from kapitza.motion import _maps

    class Pool(cf.ThreadPoolExecutor):
        def __init__(self, max_workers):
            started.append(max_workers)
            super().__init__(max_workers)

    monkeypatch.setattr(_maps, "ProcessPoolExecutor", Pool)
    th = np.linspace(0.0, 0.1, 20)
    ref = stroboscopic_map(th, 0.0, 0.15, 100.0, periods=3, chunk=10)
    out = stroboscopic_map(th, 0.0, 0.15, 100.0, periods=3, chunk=10, workers=40)
    assert started and max(started) <= min(2, os.cpu_count())
    np.testing.assert_array_equal(out.theta, ref.theta)
    assert V.workers(40, 2) <= 2 and V.workers(1, 100) == 1


# ------------------------------------------------------------------ wrong answers and NaN
def test_huge_angles_are_reduced_exactly():
    # the truth: the motion from the exact double 1e15 is that from its remainder modulo 2 pi
    with mpmath.workprec(1200):
        r = float(mpmath.mpf(1e15) - mpmath.nint(mpmath.mpf(1e15) / (2 * mpmath.pi)) * 2 * mpmath.pi)
    truth = simulate(r, 0.0, 0.15, 100.0, periods=2).dtheta[-1]
    got = simulate(1e15, 0.0, 0.15, 100.0, periods=2)
    assert got.dtheta[-1] == pytest.approx(truth, rel=1e-9)
    assert got.dtheta[-1] == pytest.approx(2.782, abs=1e-3)
    th, om = nonlinear_motion(0.6, 1e15, 0.0, 0.15, 100.0)
    assert om == pytest.approx(nonlinear_motion(0.6, r, 0.0, 0.15, 100.0)[1], rel=1e-9)
    orb = stroboscopic_map(1e15, 0.0, 0.15, 100.0, periods=2)
    assert orb.dtheta[-1] == pytest.approx(stroboscopic_map(r, 0.0, 0.15, 100.0, periods=2).dtheta[-1], rel=1e-9)


@pytest.mark.parametrize("call", [
    lambda: phase_flow(1.0, 0.1, 1e155, 10.0),
    lambda: simulate(0.1, 1e155, 0.15, 100.0, periods=2),
    lambda: nonlinear_motion(1.0, 0.1, 1e155, 0.15, 100.0),
    lambda: stroboscopic_map(0.1, 1e300, 0.15, 100.0, periods=2),
])
def test_starts_too_fast_for_a_double_are_refused_by_name(call):
    _refused(call, "dtheta0")


def test_a_damped_motion_decays_past_1e_150_without_the_solver_stopping():
    orb = stroboscopic_map(0.1, 0.0, 0.15, 100.0, periods=600, damping=5.0, every=100)
    assert np.all(np.isfinite(orb.theta))
    assert abs(orb.theta[-1]) < 1e-150
    traj = simulate(0.1, 0.0, 0.15, 100.0, periods=600, points_per_period=4, damping=5.0)
    assert np.all(np.isfinite(traj.theta)) and abs(traj.theta[-1]) < 1e-150
    # the decay is the damped Floquet rate all the way down, also where the state is rescaled (below
    # 1e-100): a complex pair of modulus exp(-c T) per period (det M = exp(-2 c T)), so the log-amplitude
    # falls by 100 c T = 75 per 100 periods on average (the amplitude's modulation along the ellipse aside)
    logs = np.log(np.hypot(orb.theta[1:], orb.dtheta[1:]))
    assert np.mean(np.diff(logs)) == pytest.approx(-100 * 5.0 * 0.15, rel=0.01)


def test_tiny_rods_are_refused_or_finite():
    eps, mu = K.to_arnold(0.15, 100.0, 5e-324)
    assert np.isfinite(eps) and eps > 1e160
    rep = K.analyze(T=0.15, A=100.0, l=5e-324)
    assert rep.margin == rep.margin and not rep.stable
    _refused(lambda: simulate(0.1, 0.0, *K.to_physical(0.5, 0.3, 5e-324), l=5e-324), "l")
    _refused(lambda: K.to_arnold(1e300, 1e300, 1e-300), "eps")


# ------------------------------------------------------------------ messages
@pytest.mark.parametrize("call, needle", [
    (lambda: K.periodic_solution([100.0, 200.0], 1), "A must be a single number"),
    (lambda: K.analyze(T=[0.1, 0.2], A=100.0), "got T of shape (2,)"),
    (lambda: simulate([0.1, 0.2], 0.0, 0.15, 100.0), "theta0 must be a single number"),
    (lambda: K.is_stable([0.1, 0.2], [0.3, 0.2, 0.1]), "eps, mu must have shapes"),
    (lambda: K.to_arnold([0.1, 0.2], [1.0, 2.0, 3.0]), "T, A, l, g must have shapes"),
    (lambda: nonlinear_motion([1.0, 2.0], [0.1, 0.2, 0.3], 0.0, 0.15, 100.0), "t, theta0"),
    (lambda: K.periodic_solution(100.0, index=1e300), "1e+300"),
    (lambda: K.StepDrive([1.0, -1e-300], [1e-300, 1.0]), "rms velocity"),
    # a window below the default floor named only the floor, which the user had not given
    (lambda: K.safe_tilt(T=0.15, A=100.0, tol=1e-300), "tol must be > floor"),
    (lambda: K.safe_tilt(T=0.15, A=100.0, g=5e-324, damping=0.1), "damping c / (2 sqrt(g/l))"),
    (lambda: K.StepDrive([1e-200, -1e-200], [0.5, 0.5]), "rms velocity"),
])
def test_messages_name_the_parameter(call, needle):
    msg = _refused(call, needle)
    assert "only 0-dimensional" not in msg and "-9223372036854775808" not in msg


# ------------------------------------------------------------------ the command line
@pytest.mark.parametrize("argv, needles", [
    (["simulate", "--T", "0.15", "--A", "100", "--tol", "0"], ["--tol", "> 0"]),
    (["animate", "--T", "0.15", "--A", "100", "--tol", "-1"], ["--tol", "> 0"]),
    (["animate", "--T", "0.15", "--A", "100", "--dpi", "100000", "--quiet"], ["dpi", "KAPITZA_ALLOW_LARGE"]),
    (["animate", "--T", "0.15", "--A", "100", "--slowdown", "1e9", "--quiet"], ["frames", "KAPITZA_ALLOW_LARGE"]),
    (["animate", "--T", "0.15", "--A", "100", "--periods", "790", "--quiet"], ["GIF", "KAPITZA_ALLOW_LARGE"]),
    (["zones", "--zones", "1000", "--points", "100000", "--json"], ["--zones * --points"]),
    (["basin", "--T", "0.15", "--A", "100", "--periods", "1000000000", "--quiet"], ["periods"]),
    (["simulate", "--T", "0.15", "--A", "100", "--damping", "1e6"], ["c / (2 sqrt(g/l))"]),
    (["simulate", "--T", "0.15", "--A", "100", "--damping", "3e4", "--periods", "20"], ["stiff"]),
    # a motion of 5e-324 periods: its time axis had no width, and matplotlib's warning leaked
    (["animate", "--T", "0.15", "--A", "100", "--periods", "5e-324", "--quiet", "--out", "a.gif"],
     ["periods", "[0.001, inf)"]),
    (["simulate", "--T", "0.15", "--A", "100", "--periods", "1e-9", "--out", "s"], ["periods", "[0.001, inf)"]),
    # a duty of 1e-300: the drive's stroke underflowed to 0, and numpy's division warning leaked
    (["animate", "--T", "0.15", "--A", "100", "--drive", "rectangular", "--duty", "1e-300", "--quiet", "--out", "a.gif"],
     ["duty", "[1e-06, 0.999999]"]),
    (["stability", "--T", "0.15", "--A", "100", "--drive", "rectangular", "--duty", "0.9999999999"],
     ["duty", "[1e-06, 0.999999]"]),
])
def test_cli_refuses_in_one_line(argv, needles, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    t0 = time.process_time()
    code, out, err = run(argv, capsys)
    assert time.process_time() - t0 < 20.0
    assert_one_line_error(code, err, *needles)
    assert not list(tmp_path.iterdir())


def test_cli_names_the_users_path_not_the_temporary_file(capsys, tmp_path):
    target = tmp_path / "afile"
    target.write_text("")
    code, out, err = run(["periods", "--A", "100", "--csv", str(target / "x.csv")], capsys)
    assert_one_line_error(code, err, str(target / "x.csv"))
    assert "/." not in err.split(str(tmp_path))[-1]


def _full_pipe():
    """``(read end, write end)`` of a pipe whose buffer is already full: a process writing to it blocks
    until the read end is drained."""
    r, w = os.pipe()
    os.set_blocking(w, False)
    try:
        while True:
            os.write(w, b"x" * 4096)
    except BlockingIOError:
        pass
    os.set_blocking(w, True)  # the command must block, not fail, on its first write
    return r, w


def test_ctrl_c_while_the_command_starts_is_one_line_and_130(tmp_path):
    # -X importtime reports each module as it is imported: wait for the first of the package,
    # then interrupt while numpy and scipy are still being imported. The command's standard output
    # is a full pipe, drained only after the signal: it cannot finish before the interrupt arrives,
    # however loaded the machine (it may be importing still, or blocked writing its result).
    import threading

    env = dict(os.environ, PYTHONWARNINGS="error", PYTHONUNBUFFERED="1")
    r, w = _full_pipe()
    drained = threading.Thread(target=lambda: [None for _ in iter(lambda: os.read(r, 65536), b"")], daemon=True)
    try:
        with subprocess.Popen([sys.executable, "-X", "importtime", "-W", "error", "-m", "kapitza", "stability",
                               "--T", "0.15", "--A", "100"], stdout=w, stderr=subprocess.PIPE, text=True,
                              env=env, cwd=tmp_path) as p:
            os.close(w)
            w = None
            seen = []
            for line in p.stderr:
                seen.append(line)
                if "kapitza._interrupt" in line:
                    p.send_signal(signal.SIGINT)
                    break
            drained.start()  # only now can the command write (and exit)
            rest = p.stderr.read()
            code = p.wait(timeout=600)
    finally:
        if w is not None:
            os.close(w)
        if drained.ident is not None:
            drained.join(timeout=60)
        os.close(r)
    err = [ln for ln in (seen + rest.splitlines(True)) if "import time:" not in ln]
    assert "Traceback" not in "".join(err)
    assert code == 130 and [ln.strip() for ln in err] == ["kapitza: interrupted"], (code, err)


@pytest.mark.parametrize("drive", [None, K.RectangularWave(0.3), "sine"])
def test_linear_motion_refuses_times_beyond_the_phase_resolution(drive):
    # t / T = 1e323 overflowed in the phase index and leaked a RuntimeWarning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"t / T must be below 2\*\*52"):
            K.linear_motion(0.5, 0.1, 0.0, T=5e-324, A=100.0, drive=drive)


@pytest.mark.parametrize("eps", [1e6, 2.0**63, 1e300])
def test_period_map_taylor_refuses_eps_beyond_a_double_by_name(eps):
    # the cubic terms grow like exp(3 w_h T): cosh overflowed and leaked a RuntimeWarning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="eps must keep w_h T"):
            K.period_map_taylor(eps, 0.3)


def test_a_list_where_one_number_is_meant_is_refused_by_name():
    # float() of a two-element array said "only 0-dimensional arrays can be converted", naming nothing
    with pytest.raises(ValueError, match=r"tol must be a single number"):
        K.nonlinear_stability(0.5, 0.3, tol=[0.5, 0.5])
    with pytest.raises(ValueError, match=r"mu must be a single number"):
        from kapitza.resonances import twist_zeros

        twist_zeros([0.2, 0.3], 0)


def test_one_trajectory_followed_through_the_exact_flows_is_bounded():
    # t = 194,577 s at T = 0.15 (648,590 periods, each followed phase by phase) ran for minutes
    with pytest.raises(ValueError, match=r"t / \(2 T\).*200,000.*KAPITZA_ALLOW_LARGE"):
        simulate(0.1, 0.0, 0.15, 100.0, t=[0.0, 194576.95867068227])


def test_paper_build_starts_no_more_processes_than_cpus(tmp_path, monkeypatch):
    # --workers was not capped: 1000 asked forked one process per task (36)
    from kapitza.paper import build as B

    seen = []
    real = B._pool
    monkeypatch.setattr(B, "_pool", lambda workers: seen.append(workers) or real(workers))
    B.build_paper(tmp_path, quick=True, workers=1000, figures=(1,), checks=(0, 1, 2))
    assert all(w <= V.cpus() for w in seen) and (seen or V.cpus() == 1)
    with pytest.raises(ValueError, match="workers"):
        B.build_paper(tmp_path, workers=10**6)


def test_far_out_rigs_give_no_warning():
    # l / g overflowed in the damping ratio (0 * inf), and 2 g T^2 / l underflowed in amplitude_edges
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"2 g T\^2 / l"):
            K.analyze(T=0.15, A=100.0, l=1e300, g=1e-300)
        assert K.analyze(T=1e-200, A=1e250, l=1e-100).stable


def test_averaged_twist_of_a_huge_eps_is_refused_by_name_not_overflowed():
    # eps^4 overflowed (a RuntimeWarning) at eps = 1e300 although the twist is ~ -0.5 eps^2
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert K.averaged_twist(1e100, 0.3) == pytest.approx(-8.0 / 9.0 * 3.0 / (2.0 * np.pi * np.sqrt(16.0 / 3.0)) * 1e200,
                                                             rel=1e-12)
        with pytest.raises(ValueError, match="eps must be below about 1e154"):
            K.averaged_twist(1e300, [0.3, 0.3])


def test_subnormal_amplitude_and_radius_give_no_warning():
    # g / A overflowed in linear_motion at A = 5e-324; r = 5e-324 gave 0/0 in the rotation number
    from kapitza.motion import measured_rotation_number, motion_pair

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pair = motion_pair(0.1, 0.0, 0.15, 5e-324, 1.0, 9.81)
        assert np.all(np.isfinite(pair.motion.theta))
        with pytest.raises(ValueError, match=r"r must lie in \[1e-150"):
            measured_rotation_number(0.5, 0.3, r=5e-324, periods=16)


@pytest.mark.parametrize("q", [1.7976931348623157e308, -1.7976931348623157e308])
def test_mathieu_values_at_the_largest_double_are_refused_by_name(q):
    # q rounded up to a power of 1.05 overflowed in exp (a RuntimeWarning)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for fn in (mathieu.characteristic_a, mathieu.characteristic_b):
            with pytest.raises(ValueError, match=r"\|q\| <= 4e6"):
                fn([1, 1], q)


def test_exact_flows_refuse_a_phase_longer_than_their_argument_reduction_resolves(capsys, tmp_path):
    # l = 1e-300 makes w_h T = 1.6e150: the elliptic functions gave 0/0 (a RuntimeWarning, NaN)
    from kapitza.motion import motion_pair

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"w_h T = T sqrt\(\(g \+ A\) / l\) <= 100000"):
            motion_pair(0.1, 0.0, 0.15, 100.0, 1e-300, 9.81)
        # a window in which no zone lies draws no legend, and warns of none
        code, _, err = run(["chart", "--points", "40", "--no-magnify", "--out", str(tmp_path / "c"), "--duty",
                            "1e-6"], capsys)
        assert code == 0 and "legend" not in err and (tmp_path / "c.png").exists()


def test_a_tower_growing_beyond_a_double_has_infinite_multipliers_without_a_warning():
    # g = 1e6: the multipliers' scale e^L beyond a double, and a zero part times inf gave NaN
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = K.chain_floquet(K.Chain([0.2, 0.2], masses=[1.0, 1.0], links="rod"), T=0.15, A=100.0, g=1e6, rtol=1e-10)
    m = np.asarray(f.multipliers)
    assert not np.isnan(m.real).any() and not np.isnan(m.imag).any() and np.isinf(np.abs(m)).any()


def test_a_huge_damping_ratio_on_the_command_line_gives_no_warning(capsys, tmp_path, monkeypatch):
    # zeta = 9573: the long double threshold cosh(kappa) e^-L was inf times 0 (numpy's warning)
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, _, err = run(["animate", "--T", "0.15", "--A", "100", "--periods", "0.1", "--dpi", "30", "--quiet",
                            "--out", "a.gif", "--zeta", "9573"], capsys)
    assert code == 0 and "Warning" not in err


def test_safe_tilt_with_a_subnormal_g_gives_no_warning():
    # g = 5e-324: l / g overflowed, and 0 damping times inf gave NaN with numpy's warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert K.safe_tilt(T=0.15, A=100.0, g=5e-324, tol=0.5, periods=2) >= 0.0


def test_the_averaging_threshold_beyond_a_double_is_inf_without_a_warning():
    # mu = 1.8e308: mu / sqrt(2/3) overflowed with numpy's warning (found by the long fuzz run)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert K.averaging_threshold(1.7976931348623157e308) == np.inf
        assert K.averaging_threshold(1e308, drive="sine") == pytest.approx(0.5 * np.pi * 1e308)


def test_eps_mu_beyond_a_double_grows_without_limit_not_nan():
    # eps * mu = 9e307: x and v overflowed (a RuntimeWarning) and the growth came out NaN
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert K.growth_rate(0.5, 1.7976931348623157e308) == np.inf
        assert not np.any(np.isnan(K.floquet_multipliers(0.5, 1.7976931348623157e308)))
        with pytest.raises(ValueError, match=r"mu must lie in \(0, 1\)"):
            K.twist_coefficient(0.5, 1.7976931348623157e308)


def test_amplitude_edges_names_mismatched_shapes():
    with pytest.raises(ValueError, match=r"l, damping must have shapes that broadcast together"):
        K.amplitude_edges(0.15, 1, l=np.array([0.5, 0.6, 0.7]), damping=[0.0, 0.0])


def test_measured_rotation_number_bounds_its_periods():
    # periods = 1e12 asked numpy for 7 TiB (MemoryError)
    from kapitza.motion import measured_rotation_number

    with pytest.raises(ValueError, match=r"periods must be .*KAPITZA_ALLOW_LARGE"):
        measured_rotation_number(0.5, 0.3, r=0.05, periods=10**12)


def test_curve_samples_are_bounded():
    # points = 1e12 went straight to numpy (MemoryError)
    from kapitza.curves import zone_curves

    with pytest.raises(ValueError, match=r"points must be <= 200,000.*KAPITZA_ALLOW_LARGE"):
        zone_curves(points=10**12)


def test_damped_monodromy_of_strong_damping_is_finite_and_basin_names_its_own_speed():
    # c T = 725: the phi-flows' e^{cT} overflowed before e^{-cT} was applied (inf and NaN entries);
    # basin(dtheta_max=1e300) named survival's dtheta0 instead of dtheta_max
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for c in (4835.0, 26095.0):
            M = K.monodromy(0.15, 100.0, 1.0, 9.81, damping=c)
            assert np.all(np.isfinite(M))
        np.testing.assert_allclose(K.monodromy(0.15, 100.0, damping=0.5),
                                   [[2.74487496, 0.27273995], [-19.6943525, -1.64332755]], rtol=1e-7)
        with pytest.raises(ValueError, match=r"dtheta_max must satisfy"):
            K.basin(0.15, 100.0, periods=2, dtheta_max=1e300, n_theta=5, n_dtheta=5)


def test_phase_flow_refuses_a_scaled_time_beyond_its_accuracy():
    # t = 1.8e308: w t overflowed (a RuntimeWarning) inside the elliptic functions
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"sqrt\|s\| \|t\| <= 100000"):
            phase_flow(1.7976931348623157e308, 0.1, 0.0, 10.0)


def test_simulate_at_a_subnormal_half_period_refuses_without_a_warning():
    """T = 5e-324 and t = 0.5: t / (2T) overflows to inf; a ValueError naming the duration, no warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"t / \(2 T\).*got inf"):
            simulate(theta0=0.1, dtheta0=0.0, T=5e-324, A=100.0, t=0.5, model="nonlinear")


# ------------------------------------------------------------------ far ends of the doubles
def test_huge_eps_and_rod_give_no_overflow_warning():
    # 2 sqrt(2) eps overflowed in phase_angles; 8 l / A overflowed in period_edges and boundary_periods
    from kapitza import periodic

    _refused(lambda: K.phase_angles(1e308, 0.5), "eps must be <= 1e+307", "1e+308")
    far = np.array(K.period_edges(100.0, 2, l=1e308))
    assert np.allclose(far / np.array(K.period_edges(100.0, 2)), 1e154, rtol=1e-14)
    assert np.allclose(periodic.boundary_periods(100.0, 3, l=1e308)[1] / periodic.boundary_periods(100.0, 3)[1],
                       1e154, rtol=1e-14)
    # w_h T = inf: tanh and coth at their limit 1
    two_atan_D = 2.0 * np.arctan(np.sqrt(109.81 / 90.19))
    assert periodic.alpha(1e308, 100.0) == pytest.approx(two_atan_D, rel=1e-15)
    assert periodic.beta(1e308, 100.0) == pytest.approx(two_atan_D, rel=1e-15)
    _refused(lambda: K.period_map_taylor(1e308, 0.5), "eps must keep w_h T")


def test_h_at_a_huge_angle_has_no_warning_and_the_identity_of_the_double_angle():
    from kapitza import phase_plane

    phi = 1e308
    c2 = (np.cos(phi) - np.sin(phi)) * (np.cos(phi) + np.sin(phi))
    assert phase_plane.h(phi, 0.5) == pytest.approx(abs(c2) / (np.cos(phi) ** 2 + 0.25 * np.sin(phi) ** 2), rel=1e-12)
    assert phase_plane.h(np.pi / 8, 0.5) == pytest.approx(np.cos(np.pi / 4) / (1 - 0.75 * np.sin(np.pi / 8) ** 2))


@pytest.mark.parametrize("eps, mu", [(1e-200, 1e-300), (1e-300, 5e-324), (1e-310, 5e-324)])
def test_normal_form_at_tiny_eps_and_subnormal_mu_has_no_warning(eps, mu):
    # the double-precision pass divided by m12 sin w = 0 before the extended-precision redo
    from kapitza import normal_form

    assert np.isfinite(K.twist_coefficient(eps, mu))
    assert np.isfinite(normal_form.birkhoff_normal_form(eps, mu).twist)
    assert "rho_0" in str(K.nonlinear_stability(eps, mu))


@pytest.mark.parametrize("value, kind", [
    (np.datetime64("2020-01-01"), "date"), (np.timedelta64(5, "s"), "duration"),
    (np.array([1, 2], dtype="m8[s]"), "duration"), (np.array(["2020-01-01"], dtype="M8[D]"), "date"),
    (np.array([np.timedelta64(1, "s")], dtype=object), "date or duration"),
])
def test_dates_and_durations_are_refused_by_name_not_read_as_counts(value, kind):
    # numpy read them as counts of their unit: is_stable(datetime64('2020-01-01'), 0.3) answered False
    _refused(lambda: K.is_stable(value, 0.3), "eps must be a real number", kind)
    _refused(lambda: K.boundary_periods(100.0, value), "count must be an integer", kind)


# ------------------------------------------------------------------ memory of a chart with many zones
def test_refined_chart_of_many_zones_stays_within_its_sample_budget():
    # Each of the 54 zones crossing eps 59..60 added `points` samples a pass to the one mu axis that
    # all zones share: 54 x 57,886 edges at points = 1000 (2.6 GB), MemoryError at --points 20000.
    import tracemalloc

    from kapitza.curves import zone_curves

    tracemalloc.start()
    try:
        c = zone_curves((59.0, 60.0), (0.0, 1.0), 400)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert c.n.size == 54 and c.mu.size <= 4 * 400
    assert peak < 100e6, peak
    # still exact at the samples (the closed forms' roots, within 4 ulp of the certified edges that
    # zone_edges gives), and still refined where an edge crosses the window
    lo, hi = K.zone_edges(c.mu[None, ::37], c.n[:, None])
    assert np.all(np.abs(lo - c.eps_lo[:, ::37]) <= 4 * np.spacing(lo))
    assert np.all(np.abs(hi - c.eps_hi[:, ::37]) <= 4 * np.spacing(hi))
    assert c.mu.size > 400
    d = zone_curves((59.0, 60.0), (0.0, 1.0), 400, max_samples=500)
    assert 400 <= d.mu.size <= 500


def test_zoom_on_one_thin_tongue_is_refined_as_before():
    from kapitza.curves import zone_curves

    lo, hi = (float(v) for v in K.zone_edges(0.7, 3))
    w = hi - lo
    c = zone_curves((lo - 2 * w, hi + 2 * w), (0.7 - 1e-9, 0.7 + 1e-9), 400)
    inside = (c.eps_lo[c.n == 3][0] >= lo - 2 * w) & (c.eps_lo[c.n == 3][0] <= hi + 2 * w)
    assert inside.sum() >= 100 and c.mu.size <= 1600


@pytest.mark.slow
def test_chart_command_of_many_zones_at_20000_points_fits_in_memory(tmp_path):
    # kapitza chart --eps-min 59 --eps-max 60 --points 20000 died of MemoryError (~0.46 GB per 1000 points)
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (6 << 30, 6 << 30)); "
            "from kapitza.cli import main; sys.exit(main(sys.argv[1:]))")
    res = subprocess.run([sys.executable, "-c", code, "chart", "--eps-min", "59", "--eps-max", "60", "--points", "20000",
                          "--out", str(tmp_path / "c")], capture_output=True, text=True, timeout=3600)
    assert res.returncode == 0, res.stderr[-2000:]
    assert (tmp_path / "c.png").stat().st_size > 0


@pytest.mark.parametrize("call, words", [
    (lambda: __import__("kapitza.curves").curves.drive_curves("sine", [0.3], 4.0, -1.0), ["zeta", "-1"]),
    (lambda: __import__("kapitza.curves").curves.drive_curves("sine", [1.5], 4.0), ["mu", "1.5"]),
    (lambda: __import__("kapitza.curves").curves.drive_curves("sine", [0.3], 2.0, 0.0, 3.0), ["eps", "(3, 2)"]),
    (lambda: __import__("kapitza.rig_plane").rig_plane.rig_zone_curves(around=(-1, 0.1)), ["around", "-1"]),
    (lambda: __import__("kapitza.rig_plane").rig_plane.rig_window(l=-1), ["l", "-1"]),
])
def test_public_helpers_name_the_bad_argument(call, words):
    with pytest.raises(ValueError) as info:
        call()
    for w in words:
        assert w in str(info.value)


def test_a_folder_that_is_not_a_sweep_store_is_named(tmp_path):
    from kapitza.sweeps import open_store

    with pytest.raises(ValueError, match="not one"):
        open_store(tmp_path)
    with pytest.raises(FileNotFoundError):
        open_store(tmp_path / "missing")


def test_linear_motion_under_overwhelming_damping_decays_without_a_warning():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        th, dth = K.linear_motion(0.5, 0.1, 0.0, T=0.15, A=100.0, zeta=748)
    assert isinstance(th, np.float64) and 0.0 < th < 0.11 and np.isfinite(dth)


def test_linear_motion_of_any_drive_gives_scalars_for_scalars():
    th, dth = K.linear_motion(0.5, 0.1, 0.0, T=0.15, A=100.0, zeta=0.1, drive="sine")
    assert isinstance(th, np.float64) and isinstance(dth, np.float64)


@pytest.mark.parametrize("call", [
    lambda kw: K.stroboscopic_map(0.1, 0.0, T=0.15, A=100.0, periods=2, **kw),
    lambda kw: K.survival(0.1, 0.0, T=0.15, A=100.0, periods=2, **kw),
    lambda kw: K.basin(T=0.15, A=100.0, periods=2, n_theta=4, n_dtheta=4, **kw),
], ids=["stroboscopic_map", "survival", "basin"])
@pytest.mark.parametrize("name", ["zeta", "damping"])
def test_motions_of_one_damping_refuse_an_array_by_the_name_given(call, name):
    with pytest.raises(ValueError, match=f"^{name} must be a single number"):
        call({name: [0.05, 0.06]})


def test_a_sine_trace_of_exactly_zero_in_doubles_leaks_no_warning():
    # beside a zone thinner than a double at mu ~ 0.92 the half period's double products give
    # tr M = 0 exactly; log|tau| is -inf there (then recomputed), not a divide warning
    eps, mu = 15.900439837875606, 0.9237738693467337
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = K.floquet(eps, mu, drive="sine")
    assert not f.stable and f.trace > 2.0 and f.rotation_number == 1.0


def test_a_mark_at_the_largest_phases_gives_no_warning(capsys, tmp_path):
    # eps = 3.2e307, mu = 1e-300: x + u overflowed in the test of whether an exact decision is affordable
    from kapitza import _certify

    assert not _certify.affordable(np.array([1.7e308]), np.array([1.7e308]))[0]
    assert _certify.affordable(np.array([100.0]), np.array([3000.0]))[0]
    r = K.analyze(eps=9e306, mu=1e-300)
    assert not r.stable
    code, _, err = run(["chart", "--points", "40", "--no-magnify", "--out", str(tmp_path / "c"),
                        "--mark-eps", "9e+306", "--mark-mu", "1e-300"], capsys)
    assert code == 0 and "Warning" not in err
    code, _, err = run(["chart", "--points", "40", "--no-magnify", "--out", str(tmp_path / "c"),
                        "--mark-eps", "3.1779025153841154e+307", "--mark-mu", "1e-300"], capsys)
    assert_one_line_error(code, err, "eps must be <= 1e+307")


@pytest.mark.parametrize("drive", ["square", "triangle"])
def test_analyze_refuses_eps_beyond_the_phase_bound_by_name(drive):
    # analyze skipped the eps <= 1e307 test the array functions make: 2 sqrt(2) eps overflowed
    _refused(lambda: K.analyze(eps=1.7976931348623157e308, mu=0.5, drive=drive), "eps must be <= 1e+307",
             "1.7976931348623157e+308")


def test_the_integrated_engine_refuses_what_its_steps_cannot_resolve():
    # beyond 2^22 steps a period the steps were capped: growth 3.9e14 for 2.6e10, rotation numbers of the
    # wrong sign, NaN multipliers at eps = 1e150 and overflow beyond
    _refused(lambda: K.floquet(1e7, 0.5, drive="triangle"), "eps must satisfy eps <= 663178 at mu = 0.5",
             "4,194,304 steps", "got 10000000.0")
    _refused(lambda: K.is_stable([1.0, 1e160], 0.5, drive="triangle"), "eps must satisfy eps <= 663178",
             "got 1e+160")
    _refused(lambda: K.floquet(1e-200, 1e200, drive="triangle"), "mu must satisfy mu <= 1e+150", "got 1e+200")
    # within the reach the engine answers, and its growth is the phase's
    f = K.floquet(6.6e5, 1e-300, drive="triangle")
    assert f.growth == pytest.approx(1131369.0546137774 / 6e5 * 6.6e5, rel=1e-5)


def test_a_search_that_would_pass_the_reach_names_the_point_asked(monkeypatch):
    # the searches doubled eps past the engine's reach; they now stop at it, and an edge beyond it is
    # refused naming what the user gave (a smaller reach keeps this quick)
    from kapitza.engines.magnus import Engine

    monkeypatch.setattr(Engine, "MAX_STEPS", 1 << 12)
    d = K.drives.as_drive("triangle")
    monkeypatch.delitem(d.__dict__, "_engine", raising=False)
    reach = float(d._eps_reach(0.5))
    assert reach == pytest.approx(2048 / np.sqrt(8 * 1.25))
    # points in the last gap below the reach: the zone above lies past it
    refused = 0
    for eps in (reach - 0.125 * np.arange(1, 25)).tolist():
        try:
            K.analyze(eps=eps, mu=0.5, drive=d)
        except ValueError as err:
            assert str(err).startswith(f"eps = {eps!r} and mu = 0.5 put an edge beyond this drive's reach, "
                                       f"eps <= {reach:.6g} at mu = 0.5"), str(err)
            refused += 1
    assert 0 < refused < 24
    _refused(lambda: K.zone_edges(0.5, 10**6, drive=d), "mu = 0.5 and n = 1000000 put an edge")
    # an edge inside the reach, though the search's doubling would pass it, is found
    n = int(0.9 * reach * 0.2)
    while True:
        lo, hi = K.zone_edges(0.5, n, drive=d, certify=False)
        if hi > 0.8 * reach:
            break
        n += 10
    assert lo <= hi <= reach


def test_an_animation_of_a_huge_starting_angle_gives_no_warning(capsys, tmp_path, monkeypatch):
    # theta0 = 1e300: the clock printed theta as a line of 300 digits (constrained layout collapsed, with
    # matplotlib's warning), and the axis limits of a flat curve met (another warning)
    from kapitza.figures.motion import padded_limits

    lo, hi = padded_limits(1e300, 1e300)
    assert lo < 1e300 < hi
    assert padded_limits(0.0, 1.0) == (-0.08, 1.08)
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, _, err = run(["animate", "--T", "0.15", "--A", "100", "--periods", "0.1", "--dpi", "30", "--quiet",
                            "--out", "a.gif", "--theta0", "1e300"], capsys)
    assert code == 0 and "Warning" not in err and (tmp_path / "a.gif").exists()


def test_a_change_beside_a_tiny_value_is_not_a_row_of_digit_groups():
    # eps = 1e-300: "raise eps to 1.22e-300-0.663 (+22.5 % to +66,294,940,...,000 %)", 300 digits long
    from kapitza.advice import percent_change

    assert percent_change(0.663, 1e-300) == "+6.63e+301 %"
    assert percent_change(24.3, 1.0) == "+2,330 %" and percent_change(1.5, 1.0) == "+50 %"


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/full"])
def test_a_drive_file_that_never_ends_is_refused_not_read_to_exhaustion(device, capsys, monkeypatch):
    # --drive-file /dev/full read zeros until the machine ran out of memory (23 GB, killed)
    from kapitza.cli import _common

    monkeypatch.setattr(_common, "DRIVE_FILE_CHARS", 1 << 20)
    code, _, err = run(["stability", "--T", "0.15", "--A", "100", "--drive-file", device], capsys)
    assert_one_line_error(code, err, f"--drive-file {device}: a drive file must be at most 1,048,576 characters",
                          V.ALLOW_LARGE_ENV + "=1")


@pytest.mark.parametrize("flag", ["--theta-max", "--dtheta-max"])
def test_a_basin_grid_wider_than_the_doubles_is_refused_by_name(flag, capsys, tmp_path, monkeypatch):
    # --theta-max 3e307: np.linspace overflowed in its span, matplotlib in the axis' ticks (warnings)
    monkeypatch.chdir(tmp_path)
    code, _, err = run(["basin", "--T", "0.15", "--A", "100", "--resolution", "4", "--periods", "2", "--quiet",
                        "--out", "b", flag, "1.7976931348623157e+308"], capsys)
    assert_one_line_error(code, err, f"{flag[2:].replace('-', '_')} must lie in (0, 1e+300]")


@pytest.mark.parametrize("argv, needle", [
    # --tol 1.8e308: the axis limits +-tol overflowed in matplotlib's autoscale (a warning); the window of
    # every other motion function is (0, pi]
    (["animate", "--T", "0.15", "--A", "100", "--periods", "0.1", "--dpi", "30", "--quiet", "--out", "a.gif",
      "--tol", "1.7976931348623157e+308"], "tol must lie in (0, 3.14159]"),
    # --joint-damping 1.8e308: its matrix 2 c overflowed (a warning)
    (["tower", "--chain", "0.2,0.2", "--grid", "12", "--points", "30", "--out", "t", "--joint-damping",
      "1.7976931348623157e+308"], "joint_damping must lie in [0, 1e+300]"),
])
def test_the_largest_double_as_a_window_or_a_joint_damping_is_refused_by_name(argv, needle, capsys, tmp_path,
                                                                               monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(argv, capsys)
    assert_one_line_error(code, err, needle)


def test_a_chart_to_the_largest_double_is_refused_with_a_readable_count(capsys, tmp_path, monkeypatch):
    # --eps-max 1.8e308: the zone count overflowed (a warning); at 1e307 the message printed 307 digits
    monkeypatch.chdir(tmp_path)
    for top, count in (("1.7976931348623157e+308", "about 1.62e+308"), ("1e307", "about 9e+306")):
        code, _, err = run(["chart", "--points", "40", "--no-magnify", "--out", "c", "--eps-max", top], capsys)
        assert_one_line_error(code, err, f"the window holds {count} zones (more than 400)")


@pytest.mark.parametrize("kwargs, needle", [
    # a result with fewer entries than an input (A from mu and g alone): the message broadcast the
    # inputs to the result's shape and raised numpy's broadcast error instead
    (dict(eps=[0.5, 0.5], mu=[1.9927699841902062e+162], l=1.0, g=9.81), "give A = 0.0"),
    (dict(eps=0.5, mu=0.3, l=[1.0, 1.0], g=[1.7976931348623157e+308]), "give A = inf"),
    (dict(eps=[0.5, 0.5], mu=0.3, l=1.0, g=[1.7976931348623157e+308]), "g = 1.7976931348623157e+308"),
])
def test_derived_parameters_out_of_range_name_the_inputs_whatever_their_shapes(kwargs, needle):
    with pytest.raises(V.KapitzaValueError, match=needle.replace("+", r"\+").replace(".", r"\.")):
        K.to_physical(**kwargs)


@pytest.mark.parametrize("name", ["zeta", "damping"])
def test_an_integrated_motion_refuses_many_dampings_by_the_name_given(name):
    # DOP853 follows one parameter set: the message named the internal c
    with pytest.raises(V.KapitzaValueError, match=rf"single parameter set; got {name} of shape \(2,\)"):
        K.nonlinear_motion(0.5, 0.1, 0.0, 0.15, 100.0, **{name: [0.5, 0.6]})


def test_a_stroke_below_the_doubles_is_refused_for_every_drive(capsys):
    # T = 1e-300: the stroke A T^2 / 6 rounds to 0 and the report divided by it (the square wave
    # refused it already, on the paper's 2 g T^2 / l)
    code, _, err = run(["stability", "--T", "1e-300", "--A", "100", "--drive", "triangle"], capsys)
    assert_one_line_error(code, err, "whose stroke rounds to 0 m")
    with pytest.raises(V.KapitzaValueError, match="stroke"):
        K.analyze(T=1e-300, A=100.0, drive="sine")


def test_a_report_shows_changes_past_a_million_per_cent_in_scientific_notation():
    # T = 1e-150: the zone's stroke lies 1e149 % away; its percentage was printed with 150 digits
    text = str(K.analyze(T=1e-150, A=100.0, drive="triangle"))
    assert "+5.02e+149 %" in text
    assert max(len(w) for w in text.split()) < 40


def test_the_safe_tilt_at_an_extreme_mu_is_its_limit_with_no_warning():
    # mu = 1e-151 (g = 1e-300 m/s^2): with g = 9.81 the scaled problem had A ~ 1e303 and DOP853's
    # initial step overflowed (a warning); the answer is the mu -> 0 limit
    from kapitza.safety import safe_tilt

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        far = safe_tilt(0.53, 1e-151, drive="triangle", periods=20)
        near = safe_tilt(0.53, 1e-40, drive="triangle", periods=20)
        # mu = 2.2e-163 (g = 5e-324): mu^2 itself is 0 in doubles (a division by zero)
        sub = safe_tilt(0.53, 2.2e-163, drive="sine", periods=20)
        sine = safe_tilt(0.53, 1e-30, drive="sine", periods=20)
    assert far == near > 0.5 and sub == sine > 0.5


@pytest.mark.parametrize("argv, needle", [
    # mu = 3e160 (A = 1e-320): a = -2 mu^2 q overflowed (a warning)
    (["--T", "0.15", "--A", "1e-320"], "mu must satisfy mu <= 1e+150"),
    # mu = 1e149 (g = 1e300): the half period's phase sqrt(2 q (1 + mu^2)) overflowed its step count
    (["--T", "0.15", "--A", "100", "--g", "1e300"], "eps must satisfy eps <= 1.11072e-146 at mu = 1e+149"),
])
def test_the_sine_refuses_a_mu_beyond_its_reach_by_name(argv, needle, capsys):
    code, _, err = run(["stability", *argv, "--drive", "sine"], capsys)
    assert_one_line_error(code, err, needle)


def test_notable_points_refuse_a_half_period_whose_phase_overflows():
    # T = 1.7e307: w_h T overflowed (a warning) and the rotation's angle became -inf
    from kapitza.phase_plane import notable_points

    with pytest.raises(V.KapitzaValueError, match=r"T must satisfy T sqrt\(\(A \+ g\) / l\) <= 1\.8e308"):
        notable_points(phi0=-0.3, T=1.7155153728201348e+307, A=100.0)


def test_safe_tilt_with_arrays_of_l_and_a_subnormal_g_answers_point_by_point():
    # l = [1, 1], g = 5e-324: l / g overflowed in the damping ratio (a warning), and the points' common
    # scale (g = 9.81) then put A at infinity; each point now takes the scalar path's own scale
    from kapitza.safety import safe_tilt

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        both = safe_tilt(T=0.15, A=100.0, l=[1.0, 1.0], g=5e-324, periods=2, tol=0.5)
        one = safe_tilt(T=0.15, A=100.0, l=1.0, g=5e-324, periods=2, tol=0.5)
        mixed = safe_tilt(T=0.15, A=100.0, l=[1.0, 2.0], g=[5e-324, 9.81], periods=2, tol=0.5)
    assert both.shape == (2,) and both[0] == both[1] == one > 0.1
    assert mixed[0] == one and mixed[1] == safe_tilt(T=0.15, A=100.0, l=2.0, g=9.81, periods=2, tol=0.5)
    with pytest.raises(V.KapitzaValueError, match="damping c / \\(2 sqrt\\(g/l\\)\\) must be finite"):
        safe_tilt(T=0.15, A=100.0, l=[1.0, 1.0], g=5e-324, damping=0.1, periods=2, tol=0.5)


@pytest.mark.parametrize("drive", ["triangle", "sine"])
def test_a_damped_report_where_the_phi_system_has_no_zone_is_always_unstable(drive):
    # mu = 0.9 with zeta = 1.5: the damped phi-system's mu sqrt(1 + zeta^2) = 1.62 has no attracting
    # phase. The report's ladders climbed to the drive's reach at mu, not at 1.62, and the search
    # raised "put an edge beyond this drive's reach" instead of the verdict
    from kapitza.drives._api import damping_of

    mu, zeta, eps, g = 0.9, 1.5, 12.0, 9.81
    A = g / mu**2
    T = eps * np.sqrt(8.0 / A)
    r = K.analyze(T=T, A=A, l=1.0, g=g, drive=drive, damping=float(damping_of(zeta, 1.0, g)))
    assert not r.stable and r.verdict.startswith("always unstable") and r.nearest_zone == -1
