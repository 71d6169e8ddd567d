"""A measured drive (kapitza.drives.from_samples): convergence to the drives it samples, at the
rate of its interpolation; its scaling, mean and errors."""
import numpy as np
import pytest

import kapitza
from kapitza.drives import from_samples

from drive_ivp import half_trace

MU = np.array([0.3, 0.3, 0.5])
N_ZONE = np.array([0, 1, 2])


def _edge_error(drive, ref):
    lo, hi = drive._edges0(MU, N_ZONE)
    rlo, rhi = ref._edges0(MU, N_ZONE)
    return np.max(np.abs(np.r_[(lo - rlo) / rlo, (hi - rhi) / rhi]))


def _rate(errors, sizes):
    """Observed order: the slope of log(error) against log(1/N), least squares."""
    return -np.polyfit(np.log(sizes), np.log(errors), 1)[0]


SIZES = [64, 128, 256, 512]


@pytest.mark.parametrize("kind", ["linear", "constant"])
def test_sampled_sine_converges_at_second_order(kind):
    # linear: O(h^2); held samples: O(h) in the shape, but that part is a shift in time, which
    # leaves the Floquet data unchanged, so the edges converge at O(h^2) as well
    errs = [_edge_error(from_samples(np.arange(N) / N, np.sin(2 * np.pi * np.arange(N) / N), kind=kind),
                        kapitza.SineWave()) for N in SIZES]
    assert 1.9 < _rate(errs, SIZES) < 2.1
    assert errs[-1] < 2e-5


def test_sampled_square_linear_converges_at_second_order():
    errs = [_edge_error(from_samples(np.arange(N) / N, np.where(np.arange(N) < N / 2, 1.0, -1.0)),
                        kapitza.SquareWave()) for N in SIZES]
    assert 1.9 < _rate(errs, SIZES) < 2.1


def test_sampled_square_with_a_misplaced_jump_converges_at_first_order():
    # an odd count of held samples cannot put the jump at T: O(h) in the edges
    sizes = [N + 1 for N in SIZES]
    errs = [_edge_error(from_samples(np.arange(N) / N, np.where(np.arange(N) / N < 0.5, 1.0, -1.0), kind="constant"),
                        kapitza.SquareWave()) for N in sizes]
    assert 0.9 < _rate(errs, sizes) < 1.1


def test_held_samples_of_the_square_are_the_square():
    # jump on a sample time: the piecewise-constant drive is the square wave itself
    N = 200
    d = from_samples(np.arange(N) * 1e-3, np.where(np.arange(N) < N / 2, 7.0, -7.0), kind="constant")
    assert d.A == 7.0 and d.T == pytest.approx(0.1) and d.mean == 0.0
    assert _edge_error(d, kapitza.SquareWave()) < 1e-12
    eps = np.linspace(0.2, 3.0, 57)
    assert (kapitza.is_stable(eps, 0.4, drive=d) == kapitza.is_stable(eps, 0.4)).all()


def test_mean_removed_and_scaled_to_the_peak():
    N = 1000
    t = 0.02 * np.arange(N) / N  # one period of 20 ms (50 Hz)
    a = 9.0 + 300.0 * np.sin(2 * np.pi * 50 * t) + 60.0 * np.sin(2 * np.pi * 150 * t + 0.3)
    d = from_samples(t, a)
    assert d.mean == pytest.approx(9.0, abs=1e-9)
    assert d.period == pytest.approx(0.02, rel=1e-12)
    assert d.T == pytest.approx(0.01, rel=1e-12)
    assert d.A == pytest.approx(np.max(np.abs(a - 9.0)), rel=1e-12)
    tau = np.linspace(0, 2, 4001)[:-1]
    assert np.max(np.abs(d._shape(tau))) == pytest.approx(1.0, abs=1e-12)
    # the drive's acceleration reproduces the samples at their times
    assert np.allclose(d.acceleration(t, d.T, d.A), a - 9.0, rtol=0, atol=1e-9)
    # the defaults of the contract: kinematics, averaging edge
    assert d._mean_square_velocity > 0 and d._stroke_coefficient > 0
    assert np.isfinite(kapitza.floquet(1.3, 0.35, drive=d).trace)
    r = kapitza.analyze(T=d.T, A=d.A, l=0.2, drive=d)
    assert "measured" in r.drive


def test_against_dop853_on_a_coarse_trace():
    t = np.arange(12) / 12.0
    a = np.array([0.1, 0.9, 1.0, 0.7, 0.2, -0.3, -0.8, -1.1, -0.9, -0.4, 0.0, 0.2])
    for kind in ("linear", "constant"):
        d = from_samples(t, a, kind=kind)
        for eps, mu in ((0.6, 0.3), (2.2, 0.5), (4.0, 0.2)):
            ref = half_trace(d._shape, eps, mu, breaks=d._breakpoints)
            tr = float(kapitza.floquet(eps, mu, drive=d).trace) / 2
            assert abs(tr - ref) <= 1e-9 * max(1.0, abs(ref))


def test_several_periods_are_averaged():
    N, k = 100, 3
    t = np.arange(N * k) / N
    rng = np.random.default_rng(0)
    a = np.sin(2 * np.pi * t) + 0.01 * rng.standard_normal(t.size)
    d = from_samples(t, a, period=1.0)
    assert d.periods == 3
    one = from_samples(t[:N], a.reshape(k, N).mean(axis=0))
    assert np.allclose(d.samples[1], one.samples[1], rtol=0, atol=1e-14)
    assert np.allclose(d.samples[0], one.samples[0], rtol=0, atol=1e-14)
    assert d.A == pytest.approx(one.A, rel=1e-14)
    with pytest.raises(ValueError, match="whole number of steps"):
        from_samples(t, a, period=0.995)


def test_thousands_of_samples():
    N = 5000
    t = np.arange(N) / N
    d = from_samples(t, np.sin(2 * np.pi * t) + 0.2 * np.sin(6 * np.pi * t))
    lo, hi = kapitza.zone_edges(0.3, 0, drive=d)
    assert 0 < lo < hi
    assert bool(kapitza.is_stable(0.5 * (lo + hi), 0.3, drive=d))


@pytest.mark.parametrize("t, a, kw, match", [
    ([0, 1, "x", 3], [1, -1, 1, -1], {}, r"sample 2 holds 'x'"),
    ([0, 1, 2, 3], [1, -1, float("nan"), -1], {}, r"a must be finite; sample 2"),
    ([0, 1, 1, 3], [1, -1, 1, -1], {}, r"strictly increasing; sample 2"),
    ([0], [1], {}, r"at least 2 samples"),
    ([0, 1, 2, 3], [9.8, 9.9, 9.7, 9.8], {}, r"mean acceleration .* larger than the signal's peak"),
    ([0, 1, 2], [2, 2, 2], {}, r"constant"),
    ([0, 1, 3], [1, -1, 0], {}, r"not uniform .*give the period"),
    ([0, 1, 2], [1, -1, 0], {"kind": "cubic"}, r"kind must be"),
    ([0, 1, 2], [1, -1, 0], {"period": -1.0}, r"period must be"),
])
def test_bad_input_names_the_row(t, a, kw, match):
    with pytest.raises(kapitza.KapitzaValueError, match=match):
        from_samples(t, a, **kw)


def test_non_uniform_with_a_period():
    t = np.array([0.0, 0.1, 0.25, 0.5, 0.62, 0.8])
    d = from_samples(t, np.sin(2 * np.pi * t), period=1.0)
    assert d.period == 1.0 and d.A > 0
    ref = half_trace(d._shape, 1.0, 0.3, breaks=d._breakpoints)
    assert float(kapitza.floquet(1.0, 0.3, drive=d).trace) / 2 == pytest.approx(ref, rel=1e-9)


# ---------------------------------------------------------------- the command line
from cli_util import assert_one_line_error, run  # noqa: E402


def _trace(path, rows, header="t,a"):
    path.write_text((header + "\n" if header else "") + "".join(f"{x},{y}\n" for x, y in rows))
    return str(path)


def test_cli_drive_file_uses_the_measured_T_and_A(tmp_path, capsys):
    N = 400
    t = 0.02 * np.arange(N) / N
    a = 300 * np.sin(2 * np.pi * 50 * t) + 40 * np.sin(2 * np.pi * 150 * t)
    f = _trace(tmp_path / "trace.csv", zip(t.tolist(), a.tolist()))
    code, out, err = run(["stability", "--drive-file", f, "--rod", "0.25", "--json"], capsys)
    assert code == 0, err
    import json

    rep = json.loads(out)
    d = from_samples(t, a)
    assert rep["T"] == pytest.approx(d.T) and rep["A"] == pytest.approx(d.A)
    eps, mu = kapitza.to_arnold(d.T, d.A, l=0.25 * 2 / 3)
    assert rep["stable"] == bool(kapitza.is_stable(eps, mu, drive=d))
    # without a header, and with explicit T and A
    f2 = _trace(tmp_path / "plain.csv", zip(t.tolist(), a.tolist()), header=None)
    code, out, err = run(["stability", "--drive-file", f2, "--T", "0.02", "--A", "200", "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["T"] == 0.02


@pytest.mark.parametrize("rows, needles", [
    ([(0, 1), (0.1, -1), (0.2, "abc")], ["row 4", "not a number"]),
    ([(0, 1), (0.1, -1), (0.05, 0)], ["row 4", "strictly increasing"]),
    ([(0, 1), (0.1, "nan"), (0.2, 0)], ["row 3", "finite"]),
    ([(0, 1)], ["at least 2 samples"]),
    ([(0, 9.8), (1, 9.9), (2, 9.7), (3, 9.8)], ["mean acceleration"]),
    ([(0, 1, 2)], ["row 2", "two columns"]),
])
def test_cli_bad_drive_file_is_one_line(tmp_path, capsys, rows, needles):
    p = tmp_path / "bad.csv"
    p.write_text("t,a\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
    code, _, err = run(["stability", "--drive-file", str(p), "--T", "0.1", "--A", "50"], capsys)
    assert_one_line_error(code, err, "--drive-file", *needles)


def test_cli_drive_file_conflicts(tmp_path, capsys):
    f = _trace(tmp_path / "t.csv", [(0, 1), (1, -1)])
    code, _, err = run(["stability", "--drive-file", f, "--drive", "sine", "--T", "0.1", "--A", "50"], capsys)
    assert_one_line_error(code, err, "not both")
    code, _, err = run(["stability", "--drive-period", "1", "--T", "0.1", "--A", "50"], capsys)
    assert_one_line_error(code, err, "--drive-period goes with --drive-file")
    code, _, err = run(["stability", "--drive-file", str(tmp_path / "none.csv"), "--T", "0.1", "--A", "50"], capsys)
    assert_one_line_error(code, err, "cannot read")
