"""Each numbered result of the paper, stated and checked numerically.

Every check is a function ``check_<name>(quick=False) -> CheckResult``; :func:`all_checks`
runs them in the paper's order. A check compares the library with something
independent of the code path it verifies (the plain trace formula, the matrix
product, ``scipy.integrate.solve_ivp``), over many parameter sets, and reports the
worst error it saw against a stated tolerance.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from ..parameters import G_EARTH, SQRT8
from ..periodic import alpha, beta, boundary_periods, periodic_solution
from ..phase_plane import notable_points
from ..propagation import monodromy
from ..zones import G_m_curve, is_stable, stability_margin, zone_edges, zone_width
from ..motion.pivot import pivot_velocity
from .approximations import kapitza_edge, mean_square_velocity

__all__ = ["CheckResult", "all_checks"]


@dataclass(frozen=True)
class CheckResult:
    """The outcome of checking one numbered result.

    Attributes
    ----------
    key : str
        Short identifier, e.g. ``"theorem-3.3"``.
    title : str
        E.g. ``"Theorem 3.3 (2T-periodic solutions)"``.
    statement : str
        The result as the paper states it (Markdown; inline math in backticks).
    method : str
        How it was checked, and against what independent reference.
    reference : str
        The formula or computation used as the reference.
    cases : int
        Number of parameter sets (or points) checked.
    worst : float
        Worst error found (in the unit described by ``error``).
    tolerance : float
        The check passes when ``worst <= tolerance``.
    error : str
        What ``worst`` measures (e.g. "relative error of T_n").
    passed : bool
    table : tuple
        Optional ``(header, rows)`` with a few illustrative rows for the report.
    """

    key: str
    title: str
    statement: str
    method: str
    reference: str
    cases: int
    worst: float
    tolerance: float
    error: str
    passed: bool
    table: tuple = field(default=())


def all_checks(quick=False):
    """Run every check in the paper's order; ``quick`` uses fewer parameter sets."""
    return [fn(quick=quick) for fn in _CHECKS]


_CHECKS = []


# ---------------------------------------------------------------- shared helpers
PI = np.pi
_G = G_EARTH

#: Largest ``x = w_h T`` at which a periodic solution is followed from its start angle. The
#: start (3.19)/(3.22) lies ``~2 e^{-x}`` from the contracting asymptote ``-pi/4``; a double
#: rounds ``phi0`` by ``~1e-16``, which the hyperbolic phase amplifies by ``e^x``, and for
#: ``x > 37`` both (3.19) and (3.22) round to ``-pi/4`` itself.
X_MAX = 20.0


def _fmt(v):
    return f"{v:.3g}"


def _result(key, title, statement, method, reference, cases, worst, tolerance, error, header, rows):
    worst = float(worst)
    return CheckResult(
        key=key, title=title, statement=statement, method=method, reference=reference,
        cases=int(cases), worst=worst, tolerance=float(tolerance), error=error,
        passed=bool(np.isfinite(worst) and worst <= tolerance),
        table=(tuple(header), tuple(tuple(r) for r in rows)),
    )


def _pick_rows(rows, k=6):
    """At most ``k`` rows spread over ``rows`` (first and last included)."""
    if len(rows) <= k:
        return list(rows)
    idx = np.unique(np.linspace(0, len(rows) - 1, k).round().astype(int))
    return [rows[i] for i in idx]


def _omegas(A, l=1.0, g=_G):
    return np.sqrt((A + g) / l), np.sqrt((A - g) / l)


def _plain_trace(T, A, l=1.0, g=_G):
    """``tr M = 2 cosh x cos u + (D - 1/D) sinh x sin u`` evaluated as printed, and the sum of
    the absolute values of its two terms (the scale of its rounding error)."""
    w_h, w_e = _omegas(A, l, g)
    x, u = w_h * T, w_e * T
    D = w_h / w_e
    t1 = 2.0 * np.cosh(x) * np.cos(u)
    t2 = (D - 1.0 / D) * np.sinh(x) * np.sin(u)
    return t1 + t2, np.abs(t1) + np.abs(t2)


def _scaled(theta, dtheta, w_h):
    """The paper's hyperbolic phase variables ``(x_h, y_h) = (theta, theta'/w_h)``."""
    return np.array([theta, dtheta / w_h])


def _ivp_period(theta0, dtheta0, T, A, l=1.0, g=_G, rtol=1e-12, atol=1e-14):
    """``(theta, theta')`` at ``t = 2T`` by ``solve_ivp`` (DOP853), one solve per half-period
    (the coefficient of (2.3) jumps at ``t = T``; ``theta``, ``theta'`` are carried over, (2.14))."""
    y = np.array([theta0, dtheta0], float)
    for k, s in enumerate(((g + A) / l, (g - A) / l)):
        sol = solve_ivp(lambda t, z, s=s: [z[1], s * z[0]], (k * T, (k + 1) * T), y,
                        method="DOP853", rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        y = sol.y[:, -1]
    return y


def return_error(A, T, phi0, sign, l=1.0, g=_G, ivp=False):
    """Return error of the solution starting at angle ``phi0`` after one drive period ``2T``.

    Parameters
    ----------
    A, T : float
        Amplitude (``A > g``) and half-period.
    phi0 : float
        Initial polar angle in ``(x_h, y_h) = (theta, theta'/w_h)``; unit radius.
    sign : {+1, -1}
        +1 for a 2T-periodic solution (``v(2T) = v(0)``), -1 for one with ``v(2T) = -v(0)``.
    l, g : float
    ivp : bool
        Propagate with ``scipy.integrate.solve_ivp`` (DOP853) instead of the exact monodromy.

    Returns
    -------
    float
        ``|v(2T) - sign v(0)| / (|v(0)| e^{w_h T})`` in the variables ``(x_h, y_h)``.

    Notes
    -----
    The periodic solution of Theorems 3.3-3.4 starts close to the contracting direction of
    the hyperbolic phase (``phi0 -> -pi/4`` or ``-3pi/4``, (3.19), (3.22)); a rounding of
    ``phi0`` is amplified by up to ``e^{w_h T}`` during ``[0, T)``, so that factor is the
    condition number of the return and the error is divided by it. A wrong ``T`` (relative
    error ``d``) gives a return error of order ``w_h T d``.
    """
    w_h, _ = _omegas(A, l, g)
    th0, dth0 = np.cos(phi0), w_h * np.sin(phi0)
    if ivp:
        th2, dth2 = _ivp_period(th0, dth0, T, A, l, g)
    else:
        M = monodromy(T, A, l, g)
        th2, dth2 = M @ np.array([th0, dth0])
    d = _scaled(th2, dth2, w_h) - sign * _scaled(th0, dth0, w_h)
    return float(np.hypot(*d) / np.exp(w_h * T))


def _amplitudes(quick, full_count, quick_count, lo=_G * 1.05, hi=500.0):
    return np.geomspace(lo, hi, quick_count if quick else full_count)


# ---------------------------------------------------------------- Lemmas 3.1 and 3.2
def _lemma_errors(A, j, tilde):
    """Deviations from (3.2)/(3.3) (``tilde=False``) or (3.8)/(3.9) (``tilde=True``) at the
    boundary period ``T_j`` / ``T~_j``, starting from the angle of (3.19)/(3.22)."""
    ps = periodic_solution(A, j, tilde=tilde)
    b = ps.boundary
    T, k = b.T, b.k
    pts = notable_points(ps.phi0, T, A)
    p0, p1, p2, p3, p4 = (float(v) for v in pts.phi)
    r0, r4 = float(pts.r[0]), float(pts.r[4])
    case_a = b.equation in ("3.10", "3.12")
    in_a = -PI / 4 < p0 < 0
    in_b = -PI / 2 < p0 < -PI / 4
    case_ok = in_a if case_a else in_b
    if not tilde:
        e1 = p1 + p0 if case_a else p1 + p0 + PI                       # (3.2)/(3.3), first line
        e3 = p3 + p2 + 2 * k * PI if case_a else p3 + p2 + PI + 2 * (k + 1) * PI
        shift = 0.0                                                      # phi4 = phi0 (mod 2 pi)
    else:
        e1 = p1 + p0 if case_a else p1 + p0 + PI                       # (3.8)/(3.9), first line
        e3 = p3 + p2 + PI + 2 * k * PI if case_a else p3 + p2 + 2 * PI + 2 * k * PI
        shift = -PI                                                      # phi4 = phi0 - pi (mod 2 pi)
    d4 = p4 - p0 - shift
    e4 = d4 - 2 * PI * np.round(d4 / (2 * PI))
    x = np.sqrt((A + _G)) * T
    er = abs(r4 / r0 - 1.0) / np.exp(x)
    return dict(name=b.name, eq=b.equation, T=T, x=x, case_ok=case_ok,
                angle=max(abs(e1), abs(e3), abs(e4)), radius=er)


def _polar_vs_matrix(n, seed=20240611):
    """Worst normwise difference between the four-step polar map of (3.1) and ``M v``."""
    rng = np.random.default_rng(seed)
    A = np.exp(rng.uniform(np.log(_G * 1.02), np.log(2000.0), n))
    w_h, _ = _omegas(A)
    x = rng.uniform(0.01, 20.0, n)
    T = x / w_h
    phi0 = rng.uniform(-2 * PI, 0.0, n)
    r0 = np.exp(rng.uniform(-2, 2, n))
    pts = notable_points(phi0, T, A, r0=r0)
    polar = np.stack([pts.r[:, 4] * np.cos(pts.phi[:, 4]), pts.r[:, 4] * np.sin(pts.phi[:, 4])], -1)
    M = monodromy(T, A)
    S = np.zeros_like(M)
    S[:, 0, 0], S[:, 1, 1] = 1.0, 1.0 / w_h
    Sinv = np.zeros_like(M)
    Sinv[:, 0, 0], Sinv[:, 1, 1] = 1.0, w_h
    Ms = S @ M @ Sinv                              # M acting on (x_h, y_h)
    v0 = np.stack([r0 * np.cos(phi0), r0 * np.sin(phi0)], -1)
    mv = np.einsum("nij,nj->ni", Ms, v0)
    err = np.linalg.norm(polar - mv, axis=-1) / (np.linalg.norm(Ms, 2, axis=(1, 2)) * r0)
    return float(err.max()), n


def _lemma_check(quick, tilde):
    As = _amplitudes(quick, 30, 5)
    J = 3 if quick else 6
    tol_angle, tol_radius, tol_map = 1e-12, 1e-13, 1e-13
    rows, worst_a, worst_r, bad_case, skipped = [], 0.0, 0.0, 0, 0
    for A in As:
        for j in range(1, J + 1):
            e = _lemma_errors(float(A), j, tilde)
            if e["x"] > X_MAX:
                skipped += 1
                continue
            worst_a = max(worst_a, e["angle"])
            worst_r = max(worst_r, e["radius"])
            bad_case += not e["case_ok"]
            rows.append((_fmt(A), e["name"], f"({e['eq']})", f"{e['T']:.10g}", _fmt(e["angle"]), _fmt(e["radius"])))
    worst_m, nm = _polar_vs_matrix(200 if quick else 4000)
    ratio = max(worst_a / tol_angle, worst_r / tol_radius, worst_m / tol_map) + (np.inf if bad_case else 0.0)
    cases = len(As) * J - skipped + nm
    error = (
        "largest ratio error/tolerance over three measures: angle conditions "
        f"(absolute, rad) {worst_a:.2e} (tol {tol_angle:g}); |r4/r0 - 1| / e^x {worst_r:.2e} "
        f"(tol {tol_radius:g}); polar map vs M, normwise {worst_m:.2e} (tol {tol_map:g}); "
        f"phi0 in the wrong case of the lemma: {bad_case} times; {skipped} (A, T) with w_h T > {X_MAX:g} "
        "not followed"
    )
    return ratio, cases, error, rows, len(As), J, nm


def check_lemma_3_1(quick=False):
    """Lemma 3.1: 2T-periodic trajectories and the conditions (3.2)/(3.3) on the notable points.

    Parameters
    ----------
    quick : bool
        Fewer amplitudes and random samples.

    Returns
    -------
    CheckResult

    Notes
    -----
    At every ``T_j`` the trajectory from ``phi0`` of (3.19) (cases (3.10)) or (3.22)
    (cases (3.11)) is followed through the notable points (3.1) with
    :func:`kapitza.phase_plane.notable_points`; (3.2) resp. (3.3) and the return
    ``r4 = r0``, ``phi4 = phi0 (mod 2 pi)`` are measured. Separately the four-step polar
    map (hyperbolic rotation (2.7), stretch by ``D``, clockwise rotation (2.13), stretch by
    ``1/D``) is compared with the matrix product ``M = E(T) H(T)``.
    """
    ratio, cases, error, rows, na, J, nm = _lemma_check(quick, tilde=False)
    return _result(
        "lemma-3.1", "Lemma 3.1 (2T-periodic trajectories on the phase plane)",
        "Let `phi_0` in `[-pi/2, pi/2)`. The trajectory is that of a 2T-periodic solution of (2.3) "
        "iff either (a) `-pi/4 < phi_0 < 0` and `phi_1 = -phi_0`, `phi_3 = -phi_2 - 2k pi` (3.2), or "
        "(b) `-pi/2 < phi_0 < -pi/4` and `phi_1 = -phi_0 - pi`, `phi_3 = -phi_2 - pi - 2(k+1) pi` (3.3), "
        "for some integer `k >= 0`; then `r_4 = r_0` and `phi_4 = phi_0 (mod 2 pi)`.",
        f"For {na} amplitudes A in geomspace(1.05 g, 500) and T = T_1..T_{J} (kapitza.boundary_table) "
        f"(those with w_h T > {X_MAX:g} are not followed: the start angle lies ~2 e^{{-x}} from the asymptote -pi/4, a double rounds it by ~1e-16 and the hyperbolic phase amplifies that by e^x; for x > 37 (3.19) and (3.22) both round to -pi/4), "
        "phi_0 from (3.19)/(3.22) (kapitza.periodic_solution); the notable points (3.1) from "
        "kapitza.phase_plane.notable_points; k from the equation (3.10)/(3.11) that T_j solves. "
        "The case (a)/(b) of phi_0 must match that equation. The radius error is divided by e^{w_h T}, "
        "the amplification of a rounding of phi_0 in the hyperbolic phase. "
        f"Separately, {nm} random (A, T, r_0, phi_0) with w_h T in (0.01, 20): the four-step polar map "
        "against the matrix product M (kapitza.monodromy), normwise relative to ||M||.",
        "The identities (3.2)/(3.3) themselves; for the map, M = E(T) H(T) from the closed-form "
        "flows of (2.4)-(2.5) (docs/theory.md section 3).",
        cases, ratio, 1.0, error,
        ("A", "T_j", "equation", "T", "angle error (rad)", "|r4/r0-1| / e^x"), _pick_rows(rows),
    )


def check_lemma_3_2(quick=False):
    """Lemma 3.2: 4T-periodic trajectories and the conditions (3.8)/(3.9).

    Parameters
    ----------
    quick : bool
        Fewer amplitudes and random samples.

    Returns
    -------
    CheckResult

    Notes
    -----
    As :func:`check_lemma_3_1`, at the periods ``T~_j`` (equations (3.12), (3.13)):
    (3.8) resp. (3.9), ``r4 = r0`` and ``phi4 = phi0 - pi (mod 2 pi)``.
    """
    ratio, cases, error, rows, na, J, nm = _lemma_check(quick, tilde=True)
    return _result(
        "lemma-3.2", "Lemma 3.2 (4T-periodic trajectories on the phase plane)",
        "Let `phi_0` in `[-pi/2, pi/2)`. The trajectory is that of a 4T-periodic solution of (2.3) "
        "which is not 2T-periodic iff either (a) `-pi/4 < phi_0 < 0` and `phi_1 = -phi_0`, "
        "`phi_3 = -phi_2 - pi - 2k pi` (3.8), or (b) `-pi/2 < phi_0 < -pi/4` and "
        "`phi_1 = -phi_0 - pi`, `phi_3 = -phi_2 - 2 pi - 2k pi` (3.9); then `r_4 = r_0`, "
        "`phi_4 = phi_0 - pi (mod 2 pi)`.",
        f"For {na} amplitudes A in geomspace(1.05 g, 500) and T = T~_1..T~_{J} "
        f"(those with w_h T > {X_MAX:g} are not followed: the start angle lies ~2 e^{{-x}} from the asymptote -pi/4, a double rounds it by ~1e-16 and the hyperbolic phase amplifies that by e^x; for x > 37 (3.19) and (3.22) both round to -pi/4)" ", phi_0 from (3.19) "
        "(equation 3.12) or (3.22) (equation 3.13) via kapitza.periodic_solution; notable points from "
        "kapitza.phase_plane.notable_points; k from the equation T~_j solves; radius error divided by "
        f"e^{{w_h T}}. The same {nm} random samples of the polar map against M as for Lemma 3.1.",
        "The identities (3.8)/(3.9) themselves; for the map, M = E(T) H(T).",
        cases, ratio, 1.0, error,
        ("A", "T~_j", "equation", "T", "angle error (rad)", "|r4/r0-1| / e^x"), _pick_rows(rows),
    )


# ---------------------------------------------------------------- Theorems 3.3 and 3.4
def _sign_change_mismatch(A, J, tilde, points):
    """Scan ``T`` and compare the sign changes of the plain ``tr M -+ 2`` with ``T_j`` / ``T~_j``.

    Returns the number of mismatches (sign changes without a boundary period in their grid
    cell, or boundary periods without a sign change) and the count of boundary periods.
    """
    T2, T4 = boundary_periods(A, J + 1)
    T2, T4 = T2[:J], T4[:J]
    # end halfway between zone J-1's upper edge and zone J's lower edge
    full2, full4 = boundary_periods(A, J + 1)
    upper = max(full2[J - 1], full4[J - 1])
    lower_next = min(full2[J], full4[J])
    grid = np.linspace(0.05 * T2[0], 0.5 * (upper + lower_next), points)
    tr, _ = _plain_trace(grid, A)
    f = tr + 2.0 if tilde else tr - 2.0
    s = np.sign(f)
    idx = np.flatnonzero(s[:-1] * s[1:] < 0)
    targets = np.sort(T4 if tilde else T2)
    hit = np.searchsorted(grid, targets) - 1       # grid cell of each boundary period
    mismatch = len(set(idx.tolist()) ^ set(hit.tolist())) + (len(set(hit.tolist())) != len(targets))
    return mismatch, len(targets), len(idx)


def _theorem_check(quick, tilde):
    As = _amplitudes(quick, 30, 4)
    J = 3 if quick else 6
    A_ivp = _amplitudes(quick, 8, 2)
    J_ivp = 2 if quick else 4
    tol_m, tol_ivp, tol_tr = 1e-13, 1e-9, 1e-13
    sign = -1 if tilde else 1
    target = -2.0 if tilde else 2.0
    worst_m = worst_tr = worst_ivp = 0.0
    rows, n_ret, n_ivp = [], 0, 0
    for A in As:
        for j in range(1, J + 1):
            ps = periodic_solution(float(A), j, tilde=tilde)
            T = ps.T
            w_h, w_e = _omegas(float(A))
            tr, scale = _plain_trace(T, float(A))
            # a relative perturbation d of T moves tr by about (x + u) * scale * d
            etr = abs(tr - target) / (scale * (1.0 + w_h * T + w_e * T))
            worst_tr = max(worst_tr, etr)
            em = np.nan
            if w_h * T <= X_MAX:
                em = return_error(float(A), T, ps.phi0, sign)
                worst_m = max(worst_m, em)
                n_ret += 1
            rows.append([float(A), ps.boundary.name, T, em, np.nan, etr])
    for A in A_ivp:
        for j in range(1, J_ivp + 1):
            ps = periodic_solution(float(A), j, tilde=tilde)
            if np.sqrt(float(A) + _G) * ps.T > X_MAX:
                continue
            e = return_error(float(A), ps.T, ps.phi0, sign, ivp=True)
            worst_ivp = max(worst_ivp, e)
            n_ivp += 1
            rows.append([float(A), ps.boundary.name, ps.T, return_error(float(A), ps.T, ps.phi0, sign), e, np.nan])
    # only there: sign changes of the plain tr M -+ 2 on a fine grid of T
    points = 1500 if quick else 6000
    mismatches = sum(_sign_change_mismatch(float(A), J, tilde, points)[0] for A in As)
    ratio = max(worst_m / tol_m, worst_ivp / tol_ivp, worst_tr / tol_tr) + (np.inf if mismatches else 0.0)
    error = (
        "largest ratio error/tolerance over three measures: exact-monodromy return "
        f"|v(2T) - s v(0)| / (|v(0)| e^x) {worst_m:.2e} (tol {tol_m:g}); the same by solve_ivp DOP853 "
        f"{worst_ivp:.2e} (tol {tol_ivp:g}); plain trace |tr M - ({target:+g})| / ((1 + x + u) S) "
        f"{worst_tr:.2e} (tol {tol_tr:g}); sign changes of tr M - ({target:+g}) not matching a boundary "
        f"period: {mismatches}; trace at {len(As) * J} periods, return at {n_ret} (w_h T <= {X_MAX:g}), "
        f"solve_ivp at {n_ivp}"
    )
    ivp_rows = [r for r in rows if np.isfinite(r[4])]
    shown = _pick_rows([r for r in rows if not np.isfinite(r[4])], 4) + _pick_rows(ivp_rows, 3)
    table_rows = [(_fmt(r[0]), r[1], f"{r[2]:.10g}", "-" if not np.isfinite(r[3]) else _fmt(r[3]),
                   "-" if not np.isfinite(r[4]) else _fmt(r[4]),
                   "-" if not np.isfinite(r[5]) else _fmt(r[5])) for r in shown]
    cases = len(As) * J + n_ivp
    return ratio, cases, error, table_rows, len(As), J, len(A_ivp), J_ivp, points


def check_theorem_3_3(quick=False):
    """Theorem 3.3: 2T-periodic solutions exist exactly where (3.10) or (3.11) holds.

    Parameters
    ----------
    quick : bool
        Fewer amplitudes, periods and grid points.

    Returns
    -------
    CheckResult

    Notes
    -----
    Sufficiency: the solution from ``phi0`` of (3.19)/(3.22) at ``T_j`` returns after ``2T``
    (exact monodromy and ``scipy.integrate.solve_ivp``); ``tr M = 2`` there by the plain
    formula. Necessity: on a fine grid of ``T`` the plain ``tr M - 2`` changes sign only in
    the grid cells holding a ``T_j`` (a 2T-periodic solution needs the multiplier 1, i.e.
    ``tr M = 2``).
    """
    ratio, cases, error, rows, na, J, nai, Ji, pts = _theorem_check(quick, tilde=False)
    return _result(
        "theorem-3.3", "Theorem 3.3 (2T-periodic solutions)",
        "(2.3) has a solution of period `2T` iff for some integer `k >= 0` either "
        "`2 atan(D (e^{w_h T} - 1)/(e^{w_h T} + 1)) + 2k pi = w_e T` (3.10) or "
        "`2 atan(D (e^{w_h T} + 1)/(e^{w_h T} - 1)) + (2k+1) pi = w_e T` (3.11).",
        f"For {na} amplitudes A in geomspace(1.05 g, 500) and T = T_1..T_{J} (roots of (3.10)/(3.11), "
        "kapitza.boundary_table), the solution with phi_0 of (3.19)/(3.22) (kapitza.periodic_solution) "
        f"is carried over one period 2T by the exact monodromy (kapitza.monodromy) where w_h T <= {X_MAX:g} "
        "(beyond, the start angle is not resolved by a double; see Lemma 3.1); for "
        f"{nai} amplitudes and T_1..T_{Ji} also by scipy.integrate.solve_ivp (DOP853, rtol 1e-12, "
        "atol 1e-14, each half-period separately). Return errors are in (theta, theta'/w_h) relative to "
        "|v(0)| and divided by e^{w_h T} (the amplification of a rounding of phi_0). The trace is "
        "evaluated by the plain formula and its distance from 2 is divided by S (1 + x + u), S the sum "
        "of the absolute values of its terms (its sensitivity to rounding of T). Only there: for each A, "
        f"tr M - 2 (plain formula) on {pts} equally spaced T from 0.05 T_1 to past T_{J}; every sign "
        "change must lie in the grid cell of a T_j and every T_j must produce one.",
        "v(2T) = v(0) for a 2T-periodic solution; tr M = 2 from the plain trace formula "
        "2 cosh x cos u + (D - 1/D) sinh x sin u (not the factored form kapitza uses); an independent "
        "ODE integrator.",
        cases, ratio, 1.0, error,
        ("A", "T_j", "T", "return (M)", "return (solve_ivp)", "|tr-2|/cond"), rows,
    )


def check_theorem_3_4(quick=False):
    """Theorem 3.4: 4T-periodic (not 2T-periodic) solutions exist exactly where (3.12) or (3.13) holds.

    Parameters
    ----------
    quick : bool
        Fewer amplitudes, periods and grid points.

    Returns
    -------
    CheckResult

    Notes
    -----
    As :func:`check_theorem_3_3` at ``T~_j``: ``v(2T) = -v(0)``, ``tr M = -2``, and the plain
    ``tr M + 2`` changes sign only at the ``T~_j``.
    """
    ratio, cases, error, rows, na, J, nai, Ji, pts = _theorem_check(quick, tilde=True)
    return _result(
        "theorem-3.4", "Theorem 3.4 (4T-periodic solutions)",
        "(2.3) has a 4T-periodic solution which is not 2T-periodic iff for some integer `k >= 0` either "
        "`2 atan(D (e^{w_h T} - 1)/(e^{w_h T} + 1)) + (2k+1) pi = w_e T` (3.12) or "
        "`2 atan(D (e^{w_h T} + 1)/(e^{w_h T} - 1)) + 2k pi = w_e T` (3.13).",
        f"For {na} amplitudes A in geomspace(1.05 g, 500) and T = T~_1..T~_{J} (roots of (3.12)/(3.13)), "
        "the solution with phi_0 of (3.19)/(3.22) is carried over 2T by the exact monodromy (w_h T <= "
        f"{X_MAX:g}) and, for "
        f"{nai} amplitudes and T~_1..T~_{Ji}, by solve_ivp (DOP853, rtol 1e-12, each half-period "
        "separately); it must come back to minus its start. Errors normalised as in Theorem 3.3. "
        f"Only there: tr M + 2 (plain formula) on {pts} equally spaced T per A changes sign exactly in "
        "the grid cells of the T~_j.",
        "v(2T) = -v(0); tr M = -2 from the plain trace formula; an independent ODE integrator.",
        cases, ratio, 1.0, error,
        ("A", "T~_j", "T", "return (M)", "return (solve_ivp)", "|tr+2|/cond"), rows,
    )


_CHECKS.extend([check_lemma_3_1, check_lemma_3_2, check_theorem_3_3, check_theorem_3_4])


# ---------------------------------------------------------------- Corollary 4.1
def check_corollary_4_1(quick=False):
    """Corollary 4.1: the boundary periods interlace, ``T_1 < T~_1 < T~_2 < T_2 < T_3 < ...``.

    Parameters
    ----------
    quick : bool
        Fewer amplitudes.

    Returns
    -------
    CheckResult

    Notes
    -----
    Section 4: ``alpha`` is increasing and concave and ``beta`` decreasing and convex in
    ``T``, so each of (3.10)-(3.13) has exactly one root per ``k``; ordered, the roots give
    the sequence of the corollary. Between zones the order is checked on the doubles; inside
    a zone the edges can be closer than a double resolves (the width shrinks like
    ``e^{-w_h T}``), so there ``T_j != T~_j`` is checked by :func:`kapitza.zone_width`
    (``log=True``), which never subtracts the edges.
    """
    nA = 20 if quick else 200
    zones = 12
    As = np.geomspace(_G * (1.0 + 1e-6), 1e5, nA)
    T2, T4 = boundary_periods(As, zones)
    n = np.arange(zones)
    even = n % 2 == 0
    lo = np.where(even, T2, T4)                   # T_1, T~_2, T_3, T~_4, ...
    hi = np.where(even, T4, T2)                   # T~_1, T_2, T~_3, T_4, ...
    between = (lo[:, 1:] - hi[:, :-1]) / hi[:, :-1]
    mu = np.sqrt(_G / As)
    logw = zone_width(mu[:, None], n[None, :], log=True)
    eps_lo = lo / np.sqrt(8.0 / As)[:, None]
    log10_rel_width = (logw - np.log(eps_lo)) / np.log(10.0)
    bad_between = int(np.sum(~(between > 0)))
    bad_within = int(np.sum(~np.isfinite(logw)) + np.sum(lo > hi))
    # alpha increasing and concave, beta decreasing and convex (second differences, uniform x grid)
    A_shape = np.geomspace(_G * (1.0 + 1e-6), 1e5, 5 if quick else 12)
    bad_shape = 0
    for A in A_shape:
        w_h, w_e = _omegas(A)
        x = np.linspace(0.01, 8.0, 400)
        a, b = alpha(x / w_h, A), beta(x / w_h, A)
        bad_shape += int(np.sum(np.diff(a) <= 0) + np.sum(np.diff(a, 2) >= 0)
                         + np.sum(np.diff(b) >= 0) + np.sum(np.diff(b, 2) <= 0))
    # one root per k: sign changes of u - alpha - j pi and u - beta - j pi on a grid of T
    bad_roots = 0
    for A in A_shape:
        w_h, w_e = _omegas(A)
        T = np.linspace(1e-6, (zones + 1) * PI / w_e, 20000 if quick else 60000)
        u = w_e * T
        a, b = alpha(T, A), beta(T, A)
        for j in range(zones):
            for F in (u - a - j * PI, u - b - j * PI):
                bad_roots += int(np.sum(np.sign(F[:-1]) * np.sign(F[1:]) < 0) != 1)
    violations = bad_between + bad_within + bad_shape + bad_roots
    min_between = float(between.min())
    min_within = float(log10_rel_width.min())
    rows = []
    for i in _pick_rows(list(range(nA)), 5):
        seq = np.ravel(np.stack([lo[i], hi[i]], -1))
        rows.append((_fmt(As[i]), f"{seq[0]:.12g} < {seq[1]:.12g} < {seq[2]:.12g} < {seq[3]:.12g}",
                     _fmt(float(between[i].min())), f"{float(log10_rel_width[i].min()):.4g}"))
    error = (
        f"number of violations: between-zone order {bad_between}, zones of non-positive width {bad_within}, "
        f"shape of alpha/beta {bad_shape}, equations without exactly one root {bad_roots}. Smallest relative "
        f"gap between zones {min_between:.3g}; smallest relative zone width 10^{min_within:.4g}"
    )
    return _result(
        "corollary-4.1", "Corollary 4.1 (interlacing of the boundary periods)",
        "For every `A > g` there are sequences `T_n`, `T~_n` with "
        "`0 < T_1 < T~_1 < T~_2 < T_2 < T_3 < ... < T~_n < T~_{n+1} < T_{n+1} < T_{n+2} < ...`; (2.3) has a "
        "2T-periodic solution at `T = T_n` and a 4T-periodic one at `T = T~_n`. (`alpha` is concave and "
        "`beta` convex, so each of (3.10)-(3.13) has exactly one root per `k`.)",
        f"For {nA} amplitudes A in geomspace(g (1 + 1e-6), 1e5) the first {zones} zones' edges "
        "(kapitza.boundary_periods) are put in the corollary's order: the gaps between zones must be "
        "positive as doubles; within a zone the edges may be closer than a double resolves, so there the "
        "width is taken from kapitza.zone_width(log=True), which must be finite (width > 0). For "
        f"{len(A_shape)} amplitudes: alpha(T), beta(T) (kapitza.periodic.alpha/beta) on 400 equally spaced "
        "w_h T in [0.01, 8] must have strictly positive/negative first and negative/positive second "
        "differences, and each of u - alpha - j pi, u - beta - j pi (j = 0..11) must change sign exactly "
        "once on a fine grid of T.",
        "Strict ordering of the computed sequence; finite differences of alpha and beta as printed in "
        "section 4; sign changes of (3.10)-(3.13) written as u - alpha - j pi, u - beta - j pi.",
        nA * zones + len(A_shape) * (2 + 2 * zones), violations, 0.0, error,
        ("A", "T_1 < T~_1 < T~_2 < T_2", "smallest relative gap between zones", "log10 smallest relative width"),
        rows,
    )


# ---------------------------------------------------------------- Section 4: stability zones
def check_stability_zones(quick=False):
    """Section 4: the stability zones, their position along ``G_m`` and their widths.

    Parameters
    ----------
    quick : bool
        Fewer random points and ``mu`` values.

    Returns
    -------
    CheckResult

    Notes
    -----
    (a) ``|tr M| < 2`` by the plain formula against :func:`kapitza.is_stable` at random
    ``(eps, mu)`` away from the edges, and at the centre and just outside both edges of
    each zone; (b) the edges of zone ``m`` lie in ``m pi < u < (m + 1) pi``, the strip of
    ``G_m`` (``u = (2m+1) pi/2``), and the zone's midpoint in ``u`` tends to
    ``(m + 1/2) pi + asin(mu^2)``; (c) :func:`kapitza.zone_width` decreases strictly in ``m``.
    """
    rng = np.random.default_rng(4)
    N = 2000 if quick else 40000
    eps = rng.uniform(0.02, 4.0, N)
    mu = rng.uniform(0.01, 0.99, N)
    A = _G / mu**2
    T = eps * np.sqrt(8.0 / A)
    tr, _ = _plain_trace(T, A)
    margin = stability_margin(eps, mu).margin
    away = np.abs(margin) > 1e-6
    mism_random = int(np.sum((np.abs(tr) < 2.0)[away] != is_stable(eps, mu)[away]))
    # centre and just outside each zone
    mus = np.linspace(0.02, 0.98, 7 if quick else 25)
    M = 12
    mism_edges, skipped, n_edge = 0, 0, 0
    for m_ in mus:
        lo, hi = zone_edges(m_, np.arange(M))
        w = zone_width(m_, np.arange(M))
        for n in range(M):
            if w[n] / lo[n] < 1e-6:
                skipped += 1
                continue
            pts = np.array([lo[n] - 1e-3 * w[n], 0.5 * (lo[n] + hi[n]), hi[n] + 1e-3 * w[n]])
            Ap = _G / m_**2
            trp, _ = _plain_trace(pts * np.sqrt(8.0 / Ap), Ap)
            expect = np.array([False, True, False])
            mism_edges += int(np.sum((np.abs(trp) < 2.0) != expect) + np.sum(is_stable(pts, m_) != expect))
            n_edge += 1
    # (b) strips of G_m and the offset of the midpoint
    q = np.sqrt((1.0 - mus) * (1.0 + mus))
    lo, hi = zone_edges(mus[:, None], np.arange(M)[None, :])
    ulo, uhi = SQRT8 * lo * q[:, None], SQRT8 * hi * q[:, None]
    mm = np.arange(M)[None, :]
    outside_strip = int(np.sum(~((ulo > mm * PI) & (uhi < (mm + 1) * PI) & (ulo <= uhi))))
    uG = SQRT8 * G_m_curve(mus[:, None], mm) * q[:, None]
    offset = 0.5 * (ulo + uhi) - uG
    limit = np.arcsin(mus**2)[:, None]
    off_last = float(np.max(np.abs(offset[:, -1] - limit[:, 0])))
    tol_off = 1e-9
    # (c) widths decrease strictly in m
    logw = zone_width(mus[:, None], mm, log=True)
    not_decreasing = int(np.sum(np.diff(logw, axis=1) >= 0))
    violations = mism_random + mism_edges + outside_strip + not_decreasing
    worst = off_last / tol_off + (np.inf if violations else 0.0)
    i = len(mus) // 2
    D = np.sqrt((1 + mus[i] ** 2) / (1 - mus[i] ** 2))
    rows = []
    for m_ in (0, 1, 2, 3, 6, 11):
        rows.append((f"{mus[i]:.3g}", str(m_), f"{ulo[i, m_]:.6g}", f"{uhi[i, m_]:.6g}",
                     _fmt(offset[i, m_] - limit[i, 0]), f"{logw[i, m_] / np.log(10):.4g}",
                     "-" if m_ == 0 else _fmt(np.exp(logw[i, m_] - logw[i, m_ - 1]))))
    error = (
        f"max over (error/tolerance) of |midpoint offset of zone {M - 1} from G_{M - 1} - asin(mu^2)| in u "
        f"{off_last:.2e} (tol {tol_off:g}); plus infinity if any violation: plain-trace verdict against "
        f"is_stable at {int(away.sum())} random points {mism_random}, at centres/just outside edges of "
        f"{n_edge} zones {mism_edges} ({skipped} zones thinner than 1e-6 eps not probed), edges outside "
        f"the strip m pi < u < (m+1) pi {outside_strip}, widths not strictly decreasing in m {not_decreasing}. "
        f"exp(-pi D) at mu = {mus[i]:.3g}: {np.exp(-PI * D):.3g}"
    )
    return _result(
        "section-4-zones", "Section 4 (stability zones along G_m)",
        "The stability region on the `eps`-`mu` plane has infinitely many components (stability zones), "
        "bounded by the solution sets of (3.10)-(3.13); they are located along the curves "
        "`G_m: 2 sqrt 2 eps sqrt(1 - mu^2) = (2m+1) pi/2`, and their widths (and heights) tend to zero "
        "as `m -> infinity`.",
        f"(a) {N} random (eps, mu) in (0.02, 4) x (0.01, 0.99): |tr M| < 2 by the plain formula against "
        "kapitza.is_stable, where the relative distance to the nearest edge (kapitza.stability_margin) "
        f"exceeds 1e-6; for {len(mus)} mu in [0.02, 0.98] and zones m = 0..{M - 1} (kapitza.zone_edges), "
        "the centre must be stable and eps_lo - 1e-3 w, eps_hi + 1e-3 w (w the width) unstable, by both. "
        f"(b) In u = 2 sqrt 2 eps sqrt(1 - mu^2) the edges of zone m must lie in (m pi, (m+1) pi), the strip "
        "whose middle is G_m; the midpoint's offset from G_m, gamma - pi/2 + O(e^{-x}) "
        "(docs/theory.md section 7), must tend to asin(mu^2), reached to 1e-9 by m = 11. So the zones "
        "follow G_m at a distance in u that does not grow with m and vanishes like mu^2 as mu -> 0; "
        "in eps the relative distance falls like 1/m. (c) kapitza.zone_width(log=True) must decrease "
        "strictly in m; the table gives the ratio of consecutive widths, which approaches exp(-pi D). "
        "Heights are not checked: the exact zone m reaches every mu in (0, 1) (its eps-interval is "
        "non-empty for every mu, part (a)), so its extent in mu does not shrink; only widths in eps do.",
        "The plain trace formula 2 cosh x cos u + (D - 1/D) sinh x sin u; the curves G_m; "
        "gamma = pi/2 + atan(mu^2 tanh x / sqrt(1 - mu^4)) -> pi/2 + asin(mu^2).",
        int(away.sum()) + 3 * n_edge + mus.size * M, worst, 1.0, error,
        ("mu", "m", "u_lo", "u_hi", "midpoint - G_m - asin(mu^2) (u)", "log10 width", "width ratio w_m/w_{m-1}"),
        rows,
    )


# ---------------------------------------------------------------- Kapitza's criterion
def check_kapitza_limit(quick=False):
    """Kapitza's averaging criterion as the limit of the first zone's lower edge.

    Parameters
    ----------
    quick : bool
        Fewer values of ``mu``.

    Returns
    -------
    CheckResult

    Notes
    -----
    For the square wave (2.2) the pivot velocity is a triangle wave with
    ``<v^2> = A^2 T^2 / 12``; ``<v^2> > g l`` reads ``eps > sqrt(3/2) mu``. The exact lower
    edge of zone 0 (eq. 3.10, ``k = 0``) satisfies ``eps_lo / mu -> sqrt(3/2)`` as ``mu -> 0``,
    with relative deviation ``(4/7) mu^4 + O(mu^8)``.
    """
    mu = np.geomspace(1e-6, 0.3, 10 if quick else 60)
    eps_lo, _ = zone_edges(mu, 0)
    d = eps_lo / kapitza_edge(mu) - 1.0
    small = mu <= 1e-3
    worst_lim = float(np.max(np.abs(d[small])))
    tol_lim = 1e-12
    mid = (mu >= 0.01) & (mu <= 0.1)
    coef = d[mid] / mu[mid] ** 4
    worst_coef = float(np.max(np.abs(coef - 4.0 / 7.0)))
    tol_coef = 1e-2
    # <v^2> of the triangle wave by a midpoint rule, against A^2 T^2 / 12
    A, T = 37.0, 0.21
    K = 200000
    t = (np.arange(K) + 0.5) * (2.0 * T / K)
    msq = float(np.mean(pivot_velocity(t, T, A) ** 2))
    e_v = abs(msq / float(mean_square_velocity(A, T)) - 1.0)
    tol_v = 1e-9
    worst = max(worst_lim / tol_lim, worst_coef / tol_coef, e_v / tol_v)
    rows = [(f"{m:.3g}", f"{e:.12g}", _fmt(dd), f"{dd / m**4:.6g}" if m >= 1e-3 else "- (rounding)")
            for m, e, dd in
            _pick_rows(list(zip(mu, eps_lo, d)), 7)]
    error = (
        f"max over (error/tolerance): |eps_lo/(sqrt(3/2) mu) - 1| for mu <= 1e-3 {worst_lim:.2e} (tol "
        f"{tol_lim:g}); |(eps_lo/(sqrt(3/2) mu) - 1)/mu^4 - 4/7| for 0.01 <= mu <= 0.1 {worst_coef:.2e} "
        f"(tol {tol_coef:g}); relative error of <v^2> = A^2 T^2/12 against a midpoint rule {e_v:.2e} "
        f"(tol {tol_v:g})"
    )
    return _result(
        "kapitza-limit", "Kapitza's criterion (high-frequency limit of the first zone)",
        "Kapitza's averaging criterion `<v^2> > g l` for the pivot velocity `v` is, for the square wave "
        "(2.2) with `<v^2> = A^2 T^2 / 12`, the line `eps = sqrt(3/2) mu`; it is the limit of the exact "
        "lower edge of the first stability zone ((3.10), `k = 0`) as `mu -> 0`.",
        f"The exact lower edge eps_lo(mu) (kapitza.zone_edges, zone 0) for {mu.size} mu in geomspace(1e-6, "
        "0.3) is divided by Kapitza's line (kapitza.paper.approximations.kapitza_edge); the deviation must "
        "vanish (to 1e-12 for mu <= 1e-3) and behave like (4/7) mu^4, the first term of the series "
        "eps^2 = (3/2) mu^2 (1 + (8/7) mu^4 + ...). <v^2> of the triangle-wave pivot velocity "
        "(kapitza.motion.pivot_velocity) by a 200000-point midpoint rule against A^2 T^2 / 12.",
        "Kapitza's line eps = sqrt(3/2) mu and the series coefficient 4/7 of the lower edge "
        "(kapitza.paper.approximations).",
        mu.size + 1, worst, 1.0, error,
        ("mu", "eps_lo", "eps_lo/(sqrt(3/2) mu) - 1", "(ratio - 1)/mu^4"), rows,
    )


_CHECKS.extend([check_corollary_4_1, check_stability_zones, check_kapitza_limit])
