"""The paper's numbered results, checked by kapitza.paper.checks."""
import numpy as np
import pytest

from kapitza import periodic_solution
from kapitza.paper import checks
from kapitza.paper.checks import CheckResult, all_checks


@pytest.fixture(scope="module")
def quick_results():
    return all_checks(quick=True)


def test_all_quick_checks_pass(quick_results):
    failed = [(r.key, r.worst, r.tolerance, r.error) for r in quick_results if not r.passed]
    assert not failed


def test_checks_in_paper_order(quick_results):
    keys = [r.key for r in quick_results]
    assert keys == ["lemma-3.1", "lemma-3.2", "theorem-3.3", "theorem-3.4", "corollary-4.1",
                    "section-4-zones", "kapitza-limit"]
    assert len(set(keys)) == len(keys)


def test_fields_filled(quick_results):
    for r in quick_results:
        assert isinstance(r, CheckResult)
        for name in ("key", "title", "statement", "method", "reference", "error"):
            assert isinstance(getattr(r, name), str) and getattr(r, name).strip(), (r.key, name)
        assert r.cases > 0
        assert np.isfinite(r.worst) and r.worst >= 0
        assert np.isfinite(r.tolerance) and r.tolerance >= 0
        assert r.passed == (r.worst <= r.tolerance)
        header, rows = r.table
        assert 3 <= len(rows) <= 8
        assert all(len(row) == len(header) for row in rows)


def test_return_error_detects_a_wrong_period():
    tol = 1e-13  # the tolerance of the exact-monodromy return in Theorems 3.3/3.4
    for tilde, sign in ((False, 1), (True, -1)):
        ps = periodic_solution(100.0, 1, tilde=tilde)
        good = checks.return_error(100.0, ps.T, ps.phi0, sign)
        bad = checks.return_error(100.0, ps.T * (1 + 1e-6), ps.phi0, sign)
        assert good <= tol
        assert bad > 1e3 * tol
        # the wrong sign (2T- versus 4T-periodic) fails by O(1)
        assert checks.return_error(100.0, ps.T, ps.phi0, -sign) > 0.1


def test_lemma_conditions_fail_off_the_boundary():
    e = checks._lemma_errors(100.0, 2, False)
    assert e["angle"] < 1e-12
    ps = periodic_solution(100.0, 2)
    from kapitza.phase_plane import notable_points

    p = notable_points(ps.phi0, ps.T * (1 + 1e-6), 100.0).phi
    # (3.3) second line misses by about w_e T * 1e-6 once T is wrong
    assert abs(p[3] + p[2] + np.pi + 2 * np.pi) > 1e-7


def test_sign_change_scan_counts_every_boundary():
    mismatch, n_targets, n_changes = checks._sign_change_mismatch(100.0, 4, False, 3000)
    assert mismatch == 0 and n_targets == n_changes == 4
