"""The paper's numbered results, checked by kapitza.paper.checks: they pass, and they can fail."""
import math

import numpy as np
import pytest

from kapitza.paper import checks as C


@pytest.fixture(scope="module")
def quick_results():
    return C.run_checks(quick=True)


@pytest.fixture(scope="module")
def quick_cases():
    return C.parameter_sets(quick=True)


def test_all_quick_checks_pass(quick_results):
    failed = [(r.key, r.worst, r.tolerance, r.worst_case, r.method) for r in quick_results if not r.passed]
    assert not failed


def test_every_numbered_result_is_checked(quick_results):
    claims = {r.claim for r in quick_results}
    for claim in ("lemma3.1", "lemma3.2", "thm3.3", "thm3.4", "cor4.1", "sec4.zones", "sec4.alpha-beta"):
        assert claim in claims
    assert set(claims) <= set(C.CLAIMS)
    keys = [r.key for r in quick_results]
    assert len(set(keys)) == len(keys)
    # Theorems are checked both ways: sufficiency by two propagators, necessity by the matrix and the trace roots
    for thm in ("thm3.3", "thm3.4"):
        for part in ("equations", "return-matrix", "return-dop853", "necessity", "only-if"):
            assert f"{thm}-{part}" in keys


def test_fields_filled(quick_results):
    for r in quick_results:
        assert isinstance(r, C.CheckResult)
        for name in ("key", "claim", "title", "method", "reference", "quantity"):
            assert isinstance(getattr(r, name), str) and getattr(r, name).strip(), (r.key, name)
        assert r.cases > 0
        assert np.isfinite(r.worst) and np.isfinite(r.tolerance)
        assert r.passed == (r.worst <= r.tolerance if r.sense == "<=" else r.worst > r.tolerance)
        assert r.status == ("PASSED" if r.passed else "FAILED")
        if r.table:
            assert all(len(row) == len(r.table["header"]) for row in r.table["rows"])


def test_discrepancies_with_the_printed_paper_are_reported(quick_results):
    notes = {r.key: r.note for r in quick_results if r.note}
    assert "antipodal" in notes["sec2-phi-h"]                 # (2.11), second branch
    assert "other way round" in notes["sec2-h"]               # monotonicity of h in the proof of Lemma 3.1
    assert "period is π" in notes["sec2-h"]


def test_h_really_is_decreasing_then_increasing():
    from kapitza.phase_plane import h

    D = 1.7
    assert h(0.0, D) == pytest.approx(1.0) and h(math.pi / 4, D) == pytest.approx(0.0, abs=1e-15)
    assert h(math.pi / 2, D) == pytest.approx(1 / D**2)
    assert h(0.3 + math.pi / 2, D) != pytest.approx(h(0.3, D))  # not pi/2-periodic
    assert h(0.3 + math.pi, D) == pytest.approx(h(0.3, D))


# ------------------------------------------------------------------ the checks can fail
def _with(monkeypatch, name, func):
    monkeypatch.setattr(C, name, func)


def test_a_wrong_periodic_start_fails_the_return_checks(monkeypatch, quick_cases):
    real = C.periodic_solution

    def shifted(A, j, tilde=False, l=1.0, g=9.81):
        s = real(A, j, tilde, l, g)
        w_h = math.sqrt((A + g) / l)
        phi0 = s.phi0 + 1e-6
        return type(s)(boundary=s.boundary, A=s.A, l=s.l, g=s.g, phi0=phi0, theta0=math.cos(phi0),
                       dtheta0=w_h * math.sin(phi0), period=s.period, sign=s.sign)

    _with(monkeypatch, "periodic_solution", shifted)
    for check in (C.check_thm33_matrix, C.check_thm34_matrix, C.check_thm33_direction, C.check_lemma31,
                  C.check_lemma32):
        r = check(quick_cases)
        assert not r.passed, r.key
    quick = C.parameter_sets(quick=True)
    r = C.check_thm33_ivp(quick)
    assert not r.passed


def test_wrong_boundary_periods_fail_the_only_if_and_equation_checks(monkeypatch, quick_cases):
    real_bp, real_bt = C.boundary_periods, C.boundary_table

    def bp(A, count, l=1.0, g=9.81):
        T, Tt = real_bp(A, count, l, g)
        return T * (1 + 1e-7), Tt

    def bt(A, count, l=1.0, g=9.81):
        import dataclasses

        return [dataclasses.replace(b, T=b.T * (1 + 1e-9)) for b in real_bt(A, count, l, g)]

    _with(monkeypatch, "boundary_periods", bp)
    assert not C.check_thm33_only_if(quick_cases).passed
    assert C.check_thm34_only_if(quick_cases).passed          # the T~_n were left alone
    _with(monkeypatch, "boundary_table", bt)
    assert not C.check_thm33_equations(quick_cases).passed
    assert not C.check_trace_at_edges(quick_cases).passed


def test_swapped_labels_fail(monkeypatch, quick_cases):
    real_bp = C.boundary_periods
    _with(monkeypatch, "boundary_periods", lambda A, count, l=1.0, g=9.81: real_bp(A, count, l, g)[::-1])
    assert not C.check_thm33_only_if(quick_cases).passed
    assert not C.check_interlacing(quick_cases).passed


def test_a_wrong_stability_verdict_fails(monkeypatch, quick_cases):
    real = C.is_stable
    _with(monkeypatch, "is_stable", lambda eps, mu: real(eps * (1 + 1e-3), mu))
    assert not C.check_stability_grid(quick_cases).passed


def test_a_check_that_raises_is_reported_as_failed(monkeypatch):
    def broken(cases):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr(C, "CHECKS", [(broken, "thm3.3")] + list(C.CHECKS[:1]))
    res = C.run_checks(quick=True)
    assert len(res) == 2
    assert not res[0].passed and "boom" in res[0].method and res[0].claim == "thm3.3"
    assert res[1].passed


def test_nan_never_passes():
    r = C._result("k", "thm3.3", "t", "m", "r", "q", [0.0, float("nan")], ["a", "b"], 1.0)
    assert not r.passed and r.worst_case == "b"
    r = C._result("k", "thm3.3", "t", "m", "r", "q", [], [], 1.0)
    assert not r.passed


def test_period_table_rows_are_ordered_and_at_the_trace():
    t = C.period_table((30.0, 100.0), 3)
    rows = t["rows"]
    assert len(rows) == 12
    for A in (30.0, 100.0):
        Ts = [r[2] for r in rows if r[0] == A]
        assert Ts == sorted(Ts)
    for r in rows:
        assert abs(r[-1] - (-2.0 if r[1].startswith("T~") else 2.0)) < 1e-14 * math.exp(r[-2]) * (1 + r[-2])
    assert [r[1] for r in rows[:6]] == ["T_1", "T~_1", "T~_2", "T_2", "T_3", "T~_3"]
    # the reference values of docs/theory.md section 5 (A = 100)
    ref = {"T_1": 0.10910018565, "T~_1": 0.20086632659, "T~_2": 0.50550270119, "T_2": 0.50757833281}
    for r in rows[6:10]:
        assert r[2] == pytest.approx(ref[r[1]], abs=1e-11)
