"""The paper's numbered results, each checked numerically over many parameter sets.

Every check is a function ``check_*(cases) -> CheckResult``: it states the claim,
says how it is checked and against which equations, evaluates it over the
parameter sets of :func:`parameter_sets` and reports the worst error found next
to the tolerance it must meet. A check that raises is reported as failed with
the error message (:func:`run_checks`); nothing is dropped.

Independence. Wherever it can, a check compares two different routes to the same
number: the polar four-step map of (3.1) against the matrix of the linear flow;
the periodic start (3.19)/(3.22) propagated by the monodromy matrix and by
``scipy.integrate.solve_ivp`` (DOP853) on the raw equation (2.3); the boundary
half-periods against the roots of ``tr M = +-2`` found by bisection on the plain
matrix trace; the factored trace of :mod:`kapitza._exact` against the textbook
``cosh``/``cos`` formula; the paper's literal exponential forms of (3.10)-(3.13)
against the ``tanh`` forms the library solves.

Tolerances are set from the conditioning of what is measured (stated in each
``method``), not from the values observed.
"""
from __future__ import annotations

import math
import traceback
from dataclasses import asdict, dataclass

import numpy as np

from .. import _validate as _v
from ..parameters import G_EARTH, SQRT8
from ..periodic import alpha as alpha_T
from ..periodic import beta as beta_T
from ..periodic import boundary_periods, boundary_table, periodic_solution
from ..phase_plane import angle_map, f, h, notable_points, phi_h
from ..propagation import floquet, monodromy
from ..zones import G_m_curve, is_stable, zone_edges, zone_width
from ..motion.pivot import pivot_velocity
from . import approximations as ap

__all__ = [
    "CLAIMS",
    "CheckResult",
    "ParameterSet",
    "parameter_sets",
    "CHECKS",
    "run_checks",
    "period_table",
]

PI = np.pi
QPI = 0.25 * PI
EPS = np.finfo(float).eps

#: The paper's numbered results (and the approximations of Figure 8), in report order:
#: id -> (title, statement).
CLAIMS = {
    "sec2": (
        "Section 2: the phase-plane machinery",
        "In the hyperbolic phase (x_h, y_h) = (θ, θ'/ω_h) turns along hyperbolae, ẋ_h = ω_h y_h, ẏ_h = ω_h x_h "
        "(2.6), with polar angle φ_h(t) solving φ̇ = ω_h cos 2φ (2.7), given by (2.11); in the elliptic phase "
        "(x_e, y_e) = (θ, θ'/ω_e) turns clockwise on circles (2.12)-(2.13). At the switches y is stretched: "
        "(r, φ) ↦ (f(φ; d) r, ϕ(φ; d)), f(φ; d) = √(1 + (d² − 1) sin² φ), tan ϕ = d tan φ. "
        "f is even, ϕ is odd, ϕ(φ + kπ; d) = ϕ(φ; d) + kπ and ϕ(ϕ(φ; d); 1/d) = φ. "
        "In the proof of Lemma 3.1, h(φ) = |cos 2φ| / (1 + (D² − 1) sin² φ) (3.7) is strictly monotone between "
        "consecutive multiples of π/4.",
    ),
    "lemma3.1": (
        "Lemma 3.1 (2T-periodic solutions in polar form)",
        "Let φ_0 ∈ [−π/2, π/2). The trajectory is that of a 2T-periodic solution of (2.3) if and only if either "
        "(a) −π/4 < φ_0 < 0 and φ_1 = −φ_0, φ_3 = −φ_2 − 2kπ (3.2), or "
        "(b) −π/2 < φ_0 < −π/4 and φ_1 = −φ_0 − π, φ_3 = −φ_2 − π − 2(k+1)π (3.3), for some integer k ≥ 0, "
        "where (r_i, φ_i), i = 0..4, are the notable points (3.1) of one period: hyperbolic arc, stretch by D, "
        "clockwise rotation by ω_e T, contraction by 1/D.",
    ),
    "lemma3.2": (
        "Lemma 3.2 (4T-periodic solutions in polar form)",
        "Let φ_0 ∈ [−π/2, π/2). The trajectory is that of a 4T-periodic, not 2T-periodic, solution if and only if "
        "either (a) −π/4 < φ_0 < 0 and φ_1 = −φ_0, φ_3 = −φ_2 − π − 2kπ (3.8), or "
        "(b) −π/2 < φ_0 < −π/4 and φ_1 = −φ_0 − π, φ_3 = −φ_2 − 2π − 2kπ (3.9); then r_4 = r_0 and "
        "φ_4 ≡ φ_0 − π (mod 2π).",
    ),
    "thm3.3": (
        "Theorem 3.3 (2T-periodic solutions)",
        "(2.3) has a solution of period 2T if and only if, for some integer k ≥ 0, "
        "2 atan(D (e^{ω_h T} − 1)/(e^{ω_h T} + 1)) + 2kπ = ω_e T (3.10) or "
        "2 atan(D (e^{ω_h T} + 1)/(e^{ω_h T} − 1)) + (2k+1)π = ω_e T (3.11). "
        "The periodic solution starts at φ_0 = atan((1 − e^{ω_h T})/(1 + e^{ω_h T})) (3.19) in case (3.10) and at "
        "φ_0 = −atan((e^{ω_h T} + 1)/(e^{ω_h T} − 1)) (3.22) in case (3.11).",
    ),
    "thm3.4": (
        "Theorem 3.4 (4T-periodic solutions)",
        "(2.3) has a 4T-periodic solution that is not 2T-periodic if and only if, for some integer k ≥ 0, "
        "α(T) + (2k+1)π = ω_e T (3.12) or β(T) + 2kπ = ω_e T (3.13), with α(T) = 2 atan(D (e^{ω_h T} − 1)/"
        "(e^{ω_h T} + 1)) "
        "and β(T) = 2 atan(D (e^{ω_h T} + 1)/(e^{ω_h T} − 1)); it starts at (3.19) in case (3.12) and at (3.22) in "
        "case (3.13).",
    ),
    "sec4.alpha-beta": (
        "Section 4: α and β",
        "α is (increasing and) concave and β (decreasing and) convex in T, so each of (3.10)-(3.13) has exactly one "
        "solution T for fixed k ≥ 0 and A (Figure 6).",
    ),
    "cor4.1": (
        "Corollary 4.1 (oscillation theorem)",
        "For every A > g there are sequences T_n, T~_n with "
        "0 < T_1 < T~_1 < T~_2 < T_2 < T_3 < T~_3 < T~_4 < T_4 < …, and (2.3) with T = T_n (T = T~_n) has 2T-periodic "
        "(4T-periodic) solutions.",
    ),
    "sec4.zones": (
        "Section 4: the stability zones",
        "By Floquet theory the stability and instability regions on the ε-μ plane (ε = T√A/√(8l), μ = √(g/A)) are "
        "separated by the curves on which (2.3) has 2T- or 4T-periodic solutions, i.e. the solution sets of "
        "(3.10)-(3.13) (Figure 7): tr M = 2 on the former, tr M = −2 on the latter, |tr M| < 2 inside. The stability "
        "region has infinitely many components (zones n = 0, 1, 2, …, 'tongues'), located along the curves "
        "G_m: 2√2 ε √(1 − μ²) = (2m+1)π/2, in the sense that their heights and widths tend to zero as m → ∞.",
    ),
    "fig8": (
        "Figure 8: approximations of the first zone (derived here, not in the paper)",
        "Kapitza's averaging criterion for the square-wave drive: the pivot velocity is a zero-mean triangle wave of "
        "amplitude AT/2, ⟨v²⟩ = A²T²/12, and ⟨v²⟩ > g l ⇔ ε > √(3/2) μ. The exact trace has the everywhere "
        "convergent series tr M/2 = Σ_j (4ε)^{2j}/(2j)! U_j(μ²) (U_j Chebyshev of the second kind); its O(ε⁴) "
        "truncation gives both edges in closed form, and inverting it gives the lower edge "
        "ε² = (3/2) μ² (1 + (8/7) μ⁴ + …), so Kapitza's line tends to the exact lower edge as μ → 0 with relative "
        "error −(4/7) μ⁴.",
    ),
}


# ------------------------------------------------------------------ results
@dataclass(frozen=True)
class CheckResult:
    """The outcome of checking one claim.

    Attributes
    ----------
    key : str
        Short identifier, e.g. ``"thm3.3-dop853"``.
    claim : str
        Key into :data:`CLAIMS` (the numbered result this check belongs to).
    title : str
        One line: what is checked.
    method : str
        How it is checked (and why the tolerance is what it is).
    reference : str
        The paper's equations, lemmas or theorems used.
    cases : int
        Number of parameter sets (or points) evaluated.
    quantity : str
        What ``worst`` measures.
    worst : float
        The worst value over all cases (largest error, or smallest margin).
    tolerance : float
        The bound ``worst`` must meet.
    sense : str
        ``"<="`` (``worst <= tolerance``) or ``">"`` (``worst > tolerance``).
    passed : bool
        Whether it met the bound; NaN never passes.
    worst_case : str
        The parameters at which ``worst`` occurred.
    note : str
        A discrepancy with the paper's text found by this check, if any.
    table : dict or None
        Optional supporting table ``{"header": [...], "rows": [[...], ...]}``.
    """

    key: str
    claim: str
    title: str
    method: str
    reference: str
    cases: int
    quantity: str
    worst: float
    tolerance: float
    sense: str
    passed: bool
    worst_case: str = ""
    note: str = ""
    table: dict | None = None

    @property
    def status(self) -> str:
        return "PASSED" if self.passed else "FAILED"

    def as_dict(self) -> dict:
        d = asdict(self)
        d["status"] = self.status
        return d


def _result(key, claim, title, method, reference, quantity, values, labels, tolerance, sense="<=",
            note="", table=None, cases=None):
    """Build a :class:`CheckResult` from per-case ``values`` (errors or margins) and their ``labels``."""
    values = np.asarray(values, float).ravel()
    if values.size == 0:
        return CheckResult(key, claim, title, method, reference, 0, quantity, float("nan"), tolerance, sense,
                           False, "no cases were evaluated", note, table)
    if np.isnan(values).any():
        i = int(np.flatnonzero(np.isnan(values))[0])
        worst = float("nan")
    elif sense == "<=":
        i = int(np.argmax(values))
        worst = float(values[i])
    else:
        i = int(np.argmin(values))
        worst = float(values[i])
    passed = bool(np.isfinite(worst) and (worst <= tolerance if sense == "<=" else worst > tolerance))
    label = labels[i] if i < len(labels) else ""
    return CheckResult(key, claim, title, method, reference, int(cases if cases is not None else values.size),
                       quantity, worst, float(tolerance), sense, passed, label, note, table)


def _failed(func, claim, exc) -> CheckResult:
    name = getattr(func, "__name__", str(func))
    msg = "".join(traceback.format_exception_only(type(exc), exc)).strip()
    return CheckResult(name.replace("check_", "").replace("_", "-"), claim, f"{name} raised an exception", msg, "",
                       0, "", float("nan"), float("nan"), "<=", False, "", "", None)


def _wrap(a, period=2.0 * PI):
    """``a`` reduced to ``[-period/2, period/2)``."""
    return np.mod(a + 0.5 * period, period) - 0.5 * period


# ------------------------------------------------------------------ parameter sets
@dataclass(frozen=True)
class ParameterSet:
    """One physical parameter set ``(A, l, g)`` with ``A > g``."""

    A: float
    l: float
    g: float

    @property
    def mu(self) -> float:
        return math.sqrt(self.g / self.A)

    @property
    def frequencies(self):
        w_h = math.sqrt((self.A + self.g) / self.l)
        w_e = math.sqrt((self.A - self.g) / self.l)
        return w_h, w_e, w_h / w_e

    def label(self, extra="") -> str:
        s = f"A={self.A:.6g}, l={self.l:.4g}, g={self.g:.4g} (mu={self.mu:.4g})"
        return s + (f", {extra}" if extra else "")


@dataclass(frozen=True)
class Cases:
    """What the checks run over: parameter sets, zones per set, and how many of each kind."""

    sets: tuple
    zones: int
    ivp_sets: int
    interlacing_A: int
    grid: int
    quick: bool = False
    seed: int = 20170915


#: Gravities drawn from (Earth, Moon, Mars, Jupiter), so nothing depends on g = 9.81.
_GRAVITIES = (G_EARTH, 1.62, 3.71, 24.79)


def parameter_sets(quick=False, seed=20170915) -> Cases:
    """The parameter sets the checks run over (reproducible).

    Parameters
    ----------
    quick : bool
        Fewer sets, zones and grid points (for tests); every check still runs.
    seed : int
        Seed of the generator that draws ``l`` and ``g``.

    Returns
    -------
    Cases
        ``mu = sqrt(g/A)`` spread over ``[0.05, 0.95]`` (``A = g / mu^2``), ``l`` drawn
        log-uniformly in ``[0.25, 4]`` m, ``g`` from four planetary values.
    """
    count = 10 if quick else 48
    rng = np.random.default_rng(seed)
    mus = np.linspace(0.05, 0.95, count)
    sets = []
    for mu in mus:
        g = float(rng.choice(_GRAVITIES))
        l = float(np.exp(rng.uniform(np.log(0.25), np.log(4.0))))
        sets.append(ParameterSet(A=g / mu**2, l=l, g=g))
    return Cases(sets=tuple(sets), zones=3 if quick else 5, ivp_sets=8 if quick else 24,
                 interlacing_A=40 if quick else 400, grid=120 if quick else 400, quick=quick, seed=seed)


def _edges_of(cases, tilde):
    """Every ``T_j`` (``tilde=False``) or ``T~_j`` of every set, with its periodic start."""
    out = []
    for ps in cases.sets:
        for j in range(1, cases.zones + 1):
            sol = periodic_solution(ps.A, j, tilde, ps.l, ps.g)
            out.append((ps, sol))
    return out


# Polar formulas need the angle to the asymptote, ~e^{-w_h T}, to carry relative accuracy; past this
# w_h T the double-precision angles of (2.11) lose it (the matrix checks have no such limit).
X_POLAR = 20.0
# The integrator is checked where e^{w_h T/2}, the growth an error made near the hyperbola's vertex
# undergoes, stays below ~1e4.
X_IVP = 18.0


# ------------------------------------------------------------------ section 2
def check_f_angle_map(cases) -> CheckResult:
    """Symmetries of ``f`` and of the angle map ``phi(.; d)`` stated in section 2."""
    rng = np.random.default_rng(cases.seed + 1)
    n = 2000 if cases.quick else 20000
    phi = rng.uniform(-20.0, 20.0, n)
    d = np.exp(rng.uniform(np.log(0.05), np.log(20.0), n))
    errs, labels = [], []

    def add(e, what):
        e = np.abs(e)
        i = int(np.argmax(e))
        errs.append(e[i])
        labels.append(f"{what} at phi={phi[i]:.6g}, d={d[i]:.4g}")

    add(f(-phi, d) - f(phi, d), "f even")
    add(angle_map(-phi, d) + angle_map(phi, d), "phi odd")
    for k in (-3, -1, 1, 2, 5):
        add(angle_map(phi + k * PI, d) - angle_map(phi, d) - k * PI, f"shift by {k} pi")
    add(angle_map(angle_map(phi, d), 1.0 / d) - phi, "phi(phi(.; d); 1/d) = id")
    # Geometric meaning: the image of (cos phi, sin phi) under (x, y) -> (x, d y).
    xs, ys = np.cos(phi), d * np.sin(phi)
    add(_wrap(angle_map(phi, d) - np.arctan2(ys, xs)), "direction of (x, d y)")
    add(f(phi, d) - np.hypot(xs, ys), "length of (x, d y)")
    return _result(
        "sec2-f-phi", "sec2", "f is even, ϕ is odd, ϕ(φ + kπ) = ϕ(φ) + kπ, ϕ(ϕ(φ; d); 1/d) = φ, and (f, ϕ) are "
        "the polar form of (x, y) ↦ (x, dy)",
        f"{n} random angles φ ∈ [−20, 20] and stretch factors d ∈ [0.05, 20] (log-uniform); the geometric meaning "
        "is checked against atan2/hypot of the stretched point. Tolerance: a few hundred units of rounding of "
        "angles up to |φ| ≈ 36.",
        "section 2 (definitions of ρ, f, ϕ)", "max absolute error [rad or 1]", errs, labels, 1e-12, cases=n)


def check_phi_h(cases) -> CheckResult:
    """(2.11) against the exact hyperbolic flow; the printed second branch of (2.11) noted."""
    rng = np.random.default_rng(cases.seed + 2)
    n = 2000 if cases.quick else 20000
    phi0 = rng.uniform(-2.0 * PI, 0.0, n)
    w = np.exp(rng.uniform(np.log(0.5), np.log(50.0), n))
    t = rng.uniform(0.0, 4.0, n) / w
    c, s = np.cosh(w * t), np.sinh(w * t)
    x0, y0 = np.cos(phi0), np.sin(phi0)
    x1, y1 = c * x0 + s * y0, s * x0 + c * y0  # (2.6) solved by the matrix exponential
    err_angle = np.abs(_wrap(phi_h(t, phi0, w) - np.arctan2(y1, x1)))
    err_start = np.abs(phi_h(np.zeros(n), phi0, w) - phi0)
    # (3.5) radius, away from the asymptotes where it is 0/0.
    ok = np.abs(np.cos(2.0 * phi0)) > 0.1
    ph = phi_h(t, phi0, w)
    r35 = np.sqrt(np.abs(np.cos(2.0 * phi0[ok])) / np.abs(np.cos(2.0 * ph[ok])))
    err_r = np.abs(r35 / np.hypot(x1[ok], y1[ok]) - 1.0)
    # The printed second branch of (2.11), for -3pi/4 < phi0 < -pi/4.
    p0 = rng.uniform(-0.75 * PI + 1e-3, -0.25 * PI - 1e-3, n)
    tt = rng.uniform(0.0, 3.0, n)
    printed = QPI + np.arctan(np.exp(-2.0 * tt) * np.tan(p0 - QPI))
    antipodal = np.abs(_wrap(printed - (phi_h(tt, p0, 1.0) + PI)))
    errs = [err_angle.max(), err_start.max(), err_r.max(), antipodal.max()]
    labels = ["angle of phi_h vs flow", "phi_h(0) = phi_0", "radius (3.5) vs flow",
              "printed (2.11) branch 2 = phi_h + pi"]
    note = ("The second branch of (2.11) as printed, π/4 + atan(e^{−2ω_h t} tan(φ_0 − π/4)) for −3π/4 < φ_0 < −π/4, "
            "equals φ_0 + π at t = 0: it describes the antipodal point on the same line. The continuous solution "
            "is −3π/4 + atan(e^{−2ω_h t} tan(φ_0 + 3π/4)); the measured difference of the printed branch from "
            f"φ_h + π is {antipodal.max():.2g} rad (kapitza.phase_plane.phi_h uses the continuous form).")
    return _result(
        "sec2-phi-h", "sec2",
                   "φ_h(t; φ_0) of (2.11) is the polar angle of the hyperbolic flow (2.6), and (3.5) its radius",
        f"{n} random φ_0 ∈ (−2π, 0], ω_h ∈ [0.5, 50], ω_h t ∈ [0, 4]; the reference is the matrix exponential "
        "[[cosh, sinh], [sinh, cosh]] applied to (cos φ_0, sin φ_0), compared modulo 2π; the radius only where "
        "|cos 2φ_0| > 0.1. The last entry confirms the misprint described below. Tolerance 1e-10: near the "
        "expanding asymptote |cos 2φ| shrinks like e^{−2ω_h t}, so angle and radius carry up to e^8/0.1 times "
        "rounding.",
        "(2.6), (2.7), (2.11), (3.5)", "max absolute error [rad or relative]", errs, labels, 1e-10, note=note, cases=n)


def check_h_monotone(cases) -> CheckResult:
    """Monotonicity and period of ``h`` (3.7), as used in the proof of Lemma 3.1."""
    Ds = np.array([1.001, 1.1, 1.4, 2.0, 3.5, 10.0])
    viol, labels = [], []
    worst_period = 0.0
    for Dv in Ds:
        for m in range(-4, 4):
            a = m * 0.5 * PI
            dec = np.diff(h(np.linspace(a, a + QPI, 2001), Dv))  # first quarter: decreasing
            inc = np.diff(h(np.linspace(a + QPI, a + 0.5 * PI, 2001), Dv))  # second quarter: increasing
            viol.append(float(np.sum(dec >= 0) + np.sum(inc <= 0)))
            labels.append(f"D={Dv:g}, m={m}")
        phi = np.linspace(-PI, PI, 1001)
        assert np.allclose(h(phi + PI, Dv), h(phi, Dv), rtol=0, atol=1e-14)
        worst_period = max(worst_period, float(np.max(np.abs(h(phi + 0.5 * PI, Dv) - h(phi, Dv)))))
    note = ("The proof of Lemma 3.1 says h is strictly decreasing on [π/4 + mπ/2, π/2 + mπ/2] and strictly increasing "
            "on [mπ/2, π/4 + mπ/2]; it is the other way round (h(0) = 1, h(π/4) = 0, h(π/2) = 1/D²; with s = sin² φ, "
            "dh/ds = ∓(D² + 1)/(1 + (D² − 1)s)² on the two quarters). It also says h is periodic of period π/2; "
            f"for D ≠ 1 its period is π (max |h(φ + π/2) − h(φ)| = {worst_period:.3g} over the D tested). The proof "
            "only needs strict monotonicity on each quarter, evenness and period π, so its conclusion stands.")
    return _result(
        "sec2-h", "sec2", "h of (3.7) is strictly decreasing on [mπ/2, π/4 + mπ/2] and strictly increasing on "
        "[π/4 + mπ/2, (m+1)π/2], and has period π",
        "Sign of consecutive differences of h on 2001-point grids of each quarter period, m = −4..3, for six values "
        "of D; the count of wrong signs must be zero. The period π is asserted to 1e-14.",
        "(3.7), proof of Lemma 3.1", "number of differences of the wrong sign", viol, labels, 0.0, note=note,
        cases=len(viol))


# ------------------------------------------------------------------ Lemmas 3.1 and 3.2
def check_polar_map(cases) -> CheckResult:
    """The four-step polar map (3.1) equals the matrix propagation of (2.3)."""
    rng = np.random.default_rng(cases.seed + 3)
    n = 300 if cases.quick else 3000
    sets = [cases.sets[k] for k in rng.integers(len(cases.sets), size=n)]
    x = rng.uniform(0.05, X_POLAR * 0.5, n)
    phi0 = rng.uniform(-2.0 * PI, 0.0, n)
    keep = np.abs(np.cos(2.0 * phi0)) >= 1e-6
    sets, x, phi0 = [ps for ps, k in zip(sets, keep) if k], x[keep], phi0[keep]
    A, l, g = (np.array([getattr(ps, k) for ps in sets]) for k in "Alg")
    w_h, w_e = np.sqrt((A + g) / l), np.sqrt((A - g) / l)
    T = x / w_h
    npnt = notable_points(phi0, T, A, r0=1.0, l=l, g=g)
    r, phi = npnt.r.T, npnt.phi.T  # (5, n)

    def mul(M, v):  # 2x2 matrices (2, 2, n) times vectors (2, n)
        return np.array([M[0][0] * v[0] + M[0][1] * v[1], M[1][0] * v[0] + M[1][1] * v[1]])

    th0 = np.array([np.cos(phi0), w_h * np.sin(phi0)])
    ch, sh = np.cosh(x), np.sinh(x)
    s1 = mul([[ch, sh / w_h], [w_h * sh, ch]], th0)
    u = w_e * T
    s3 = mul([[np.cos(u), np.sin(u) / w_e], [-w_e * np.sin(u), np.cos(u)]], s1)
    s4 = np.einsum("nij,jn->in", monodromy(T, A, l, g), th0)
    scale = np.maximum(1.0, np.max(r, axis=0))
    errs = np.max([
        np.hypot(r[1] * np.cos(phi[1]) - s1[0], r[1] * np.sin(phi[1]) - s1[1] / w_h),
        np.hypot(r[2] * np.cos(phi[2]) - s1[0], r[2] * np.sin(phi[2]) - s1[1] / w_e),
        np.hypot(r[3] * np.cos(phi[3]) - s3[0], r[3] * np.sin(phi[3]) - s3[1] / w_e),
        np.hypot(r[4] * np.cos(phi[4]) - s4[0], r[4] * np.sin(phi[4]) - s4[1] / w_h),
    ], axis=0) / scale
    errs = errs.tolist()
    labels = [ps.label(f"T={t:.6g} (w_h T={xx:.3g}), phi0={p0:.6g}") for ps, t, xx, p0 in zip(sets, T, x, phi0)]
    return _result(
        "lemma3.1-map", "lemma3.1", "The notable points (3.1) (hyperbolic arc, stretch by D, rotation by ω_e T, "
        "contraction by 1/D) agree with the matrix propagation of (2.3) over one period",
        f"{len(errs)} random starts φ_0 ∈ (−2π, 0], ω_h T ∈ [0.05, {X_POLAR / 2:g}], over the parameter sets; "
        "points 1 and 2 are compared with H(T)(θ, θ'), point 3 with E(T)H(T)(θ, θ') and point 4 with "
        "kapitza.monodromy, each in its own scaled variables (θ, θ'/ω). Error relative to max r_i. "
        "Tolerance 1e-9: the polar angle near an asymptote is conditioned like e^{ω_h T} ≤ e^9 times rounding.",
        "(2.6)-(2.14), (3.1), (3.5)", "max |point − matrix| / max r_i", errs, labels, 1e-9)


def _lemma_conditions(cases, tilde):
    errs, labels, count = [], [], 0
    for ps, sol in _edges_of(cases, tilde):
        b = sol.boundary
        w_h, w_e, D = ps.frequencies
        x = w_h * b.T
        if x > X_POLAR:
            continue
        count += 1
        npnt = notable_points(sol.phi0, b.T, ps.A, r0=1.0, l=ps.l, g=ps.g)
        r, phi = npnt.r, npnt.phi
        k = b.k
        case_a = b.equation in ("3.10", "3.12")
        p0 = phi[0]
        inside = (-QPI < p0 < 0.0) if case_a else (-0.5 * PI < p0 < -QPI)
        if not tilde:
            e1 = phi[1] + phi[0] if case_a else phi[1] + phi[0] + PI
            e3 = phi[3] + phi[2] + 2 * k * PI if case_a else phi[3] + phi[2] + PI + 2 * (k + 1) * PI
            e4 = _wrap(phi[4] - phi[0])
        else:
            e1 = phi[1] + phi[0] if case_a else phi[1] + phi[0] + PI
            e3 = phi[3] + phi[2] + PI + 2 * k * PI if case_a else phi[3] + phi[2] + 2 * PI + 2 * k * PI
            e4 = _wrap(phi[4] - phi[0] + PI)
        # A rounding of phi_0 (which lies ~2 e^{-x} from an asymptote) grows by e^{x} in the hyperbolic
        # phase: that factor is the condition number of every residual here.
        e = max(abs(e1), abs(e3), abs(e4), abs(r[4] / r[0] - 1.0)) / math.exp(x)
        errs.append(e if inside else 1.0)
        labels.append(ps.label(f"{b.name} (eq. {b.equation}, k={k}, w_h T={x:.3g})"))
    return errs, labels, count


def check_lemma31(cases) -> CheckResult:
    """Lemma 3.1 at the 2T-periodic boundary periods ``T_n``."""
    errs, labels, count = _lemma_conditions(cases, tilde=False)
    return _result(
        "lemma3.1-conditions", "lemma3.1", "At every T_n the periodic start lies in the interval of case (a) "
        "(eq. 3.10) or (b) (eq. 3.11), satisfies (3.2) resp. (3.3) with the k of its equation, and returns: "
        "r_4 = r_0, φ_4 ≡ φ_0 (mod 2π)",
        f"{count} pairs (parameter set, T_n), n ≤ {cases.zones}, with ω_h T ≤ {X_POLAR:g}; φ_0 from (3.19)/(3.22) "
        "(kapitza.periodic_solution), the notable points by the polar map (3.1). Each residual is divided by "
        "e^{ω_h T}: φ_0 lies about 2e^{−ω_h T} from an asymptote and the hyperbolic phase amplifies its rounding "
        "by that factor. An interval violation counts as error 1. Tolerance 1e-13 (a T off by a relative δ leaves "
        "residuals of about ω_e T δ).",
        "Lemma 3.1, (3.1)-(3.3), (3.19), (3.22)", "max of |φ_1 + φ_0 (+π)|, |φ_3 + φ_2 + …|, |φ_4 − φ_0| mod 2π, "
        "|r_4/r_0 − 1|, each / e^{ω_h T}", errs, labels, 1e-13)


def check_lemma32(cases) -> CheckResult:
    """Lemma 3.2 at the 4T-periodic boundary periods ``T~_n``."""
    errs, labels, count = _lemma_conditions(cases, tilde=True)
    return _result(
        "lemma3.2-conditions", "lemma3.2", "At every T~_n the periodic start lies in the interval of case (a) "
        "(eq. 3.12) or (b) (eq. 3.13), satisfies (3.8) resp. (3.9), and after one period r_4 = r_0, "
        "φ_4 ≡ φ_0 − π (mod 2π)",
        f"{count} pairs (parameter set, T~_n), n ≤ {cases.zones}, with ω_h T ≤ {X_POLAR:g}; as lemma3.1-conditions.",
        "Lemma 3.2, (3.1), (3.8), (3.9), (3.19), (3.22)", "max condition residual / e^{ω_h T}",
        errs, labels, 1e-13)


# ------------------------------------------------------------------ Theorems 3.3 and 3.4
def _literal_alpha(x, D):
    e = np.exp(x)
    return 2.0 * np.arctan(D * (e - 1.0) / (e + 1.0))


def _literal_beta(x, D):
    e = np.exp(x)
    return 2.0 * np.arctan(D * (e + 1.0) / (e - 1.0))


_EQUATION = {  # equation -> (curve, odd multiple of pi?) in u = curve + (2k + odd) pi
    "3.10": (_literal_alpha, 0),
    "3.11": (_literal_beta, 1),
    "3.12": (_literal_alpha, 1),
    "3.13": (_literal_beta, 0),
}


def _equation_residuals(cases, tilde):
    errs, labels = [], []
    for ps in cases.sets:
        w_h, w_e, D = ps.frequencies
        for b in boundary_table(ps.A, cases.zones, ps.l, ps.g):
            if b.tilde != tilde:
                continue
            x, u = w_h * b.T, w_e * b.T
            curve, odd = _EQUATION[b.equation]
            want = ("3.12", "3.13") if tilde else ("3.10", "3.11")
            ok = b.equation in want and b.period == ("4T" if tilde else "2T")
            with np.errstate(over="ignore"):
                res = abs(curve(x, D) + (2 * b.k + odd) * PI - u) / max(u, 1.0) if x < 700 else abs(
                    (2.0 * np.arctan(D) + (2 * b.k + odd) * PI - u) / u)
            errs.append(res if ok else 1.0)
            labels.append(ps.label(f"{b.name} (eq. {b.equation}, k={b.k})"))
    return errs, labels


def check_thm33_equations(cases) -> CheckResult:
    errs, labels = _equation_residuals(cases, tilde=False)
    return _result(
        "thm3.3-equations", "thm3.3", "Every T_n solves (3.10) or (3.11), as printed with exponentials, with the k "
        "kapitza reports",
        f"{len(errs)} T_n over the parameter sets, n ≤ {cases.zones}; the residual of the printed equation "
        "2 atan(D (e^x ∓ 1)/(e^x ± 1)) + mπ − ω_e T, x = ω_h T, relative to max(ω_e T, 1), evaluated independently "
        "of the tanh form the library solves. A T_n labelled with a 4T equation counts as error 1. "
        "Tolerance: 50 units of rounding.",
        "Theorem 3.3, (3.10), (3.11)", "max relative residual", errs, labels, 50 * EPS)


def check_thm34_equations(cases) -> CheckResult:
    errs, labels = _equation_residuals(cases, tilde=True)
    return _result(
        "thm3.4-equations", "thm3.4", "Every T~_n solves (3.12) or (3.13), as printed, with the k kapitza reports",
        f"{len(errs)} T~_n over the parameter sets; as thm3.3-equations.",
        "Theorem 3.4, (3.12), (3.13)", "max relative residual", errs, labels, 50 * EPS)


def _start_state(sol):
    w_h = math.sqrt((sol.A + sol.g) / sol.l)
    return np.array([math.cos(sol.phi0), w_h * math.sin(sol.phi0)]), w_h


def _return_matrix(cases, tilde):
    errs, labels = [], []
    for ps, sol in _edges_of(cases, tilde):
        v, w_h = _start_state(sol)
        M = monodromy(sol.T, ps.A, ps.l, ps.g)
        if not np.all(np.isfinite(M)):
            continue
        # In scaled variables (theta, theta'/w_h) the start is a unit vector.
        S = np.diag([1.0, 1.0 / w_h])
        Si = np.diag([1.0, w_h])
        Ms = S @ M @ Si
        vs = S @ v
        sign = -1.0 if tilde else 1.0
        e2 = np.linalg.norm(Ms @ vs - sign * vs) / np.linalg.norm(Ms, 2)
        e4 = np.linalg.norm(Ms @ (Ms @ vs) - vs) / np.linalg.norm(Ms, 2) ** 2
        errs.append(max(e2, e4) if tilde else e2)
        labels.append(ps.label(f"{sol.boundary.name} (w_h T={w_h * sol.T:.3g})"))
    return errs, labels


def check_thm33_matrix(cases) -> CheckResult:
    errs, labels = _return_matrix(cases, tilde=False)
    return _result(
        "thm3.3-return-matrix", "thm3.3", "The solution starting at (3.19) (case 3.10) or (3.22) (case 3.11) is "
        "2T-periodic: the monodromy matrix returns it to itself",
        f"{len(errs)} pairs (parameter set, T_n), n ≤ {cases.zones}. In the scaled variables (θ, θ'/ω_h) the start "
        "v is a unit vector; the error |M v − v| / ‖M‖ is the angular error in φ_0 it corresponds to (M has entries "
        "of size e^{ω_h T}, so this is the scale rounding allows). Tolerance 1e-12.",
        "Theorem 3.3 (sufficiency), (3.19), (3.22); docs/theory.md §3", "max |M v − v| / ‖M‖", errs, labels, 1e-12)


def check_thm34_matrix(cases) -> CheckResult:
    errs, labels = _return_matrix(cases, tilde=True)
    return _result(
        "thm3.4-return-matrix", "thm3.4", "The solution starting at (3.19) (case 3.12) or (3.22) (case 3.13) changes "
        "sign after 2T and returns after 4T",
        f"{len(errs)} pairs (parameter set, T~_n); max of |M v + v| / ‖M‖ and |M² v − v| / ‖M‖², as "
        "thm3.3-return-matrix.", "Theorem 3.4 (sufficiency), (3.19), (3.22)",
        "max |M v + v| / ‖M‖, |M² v − v| / ‖M‖²", errs, labels, 1e-12)


def _ivp_return(cases, tilde):
    """Integrate the starts of Theorem 3.3/3.4 through (2.3) with DOP853 and measure their return.

    All pairs (parameter set, edge) are one system of ODEs in the time ``t / T`` of each pair,
    integrated phase by phase (restarted at each switch, so no step straddles the jump of a(t)).
    The solver bounds the RMS of the scaled local errors over all ``2n`` components; with ``rtol``
    divided by ``sqrt(n)`` that bounds each pair's error as tightly as solving it alone would
    (RMS over its own two components), so one call does the work of ``n`` at the same accuracy.
    """
    from scipy.integrate import solve_ivp

    rtol = 1e-12
    pairs = []
    sets = cases.sets[:: max(1, len(cases.sets) // cases.ivp_sets)][: cases.ivp_sets]
    for ps in sets:
        for j in range(1, cases.zones + 1):
            sol = periodic_solution(ps.A, j, tilde, ps.l, ps.g)
            v, w_h = _start_state(sol)
            if w_h * sol.T <= X_IVP:
                pairs.append((ps, sol, v, w_h))
    if not pairs:
        return [], [], 0
    n = len(pairs)
    T = np.array([sol.T for _, sol, _, _ in pairs])
    rate = [np.array([(ps.g + ps.A) / ps.l for ps, _, _, _ in pairs]),  # theta'' = (g + a(t))/l theta (2.3)
            np.array([(ps.g - ps.A) / ps.l for ps, _, _, _ in pairs])]
    start = np.array([v for _, _, v, _ in pairs]).T  # (2, n): row 0 theta, row 1 theta'
    scale = np.array([np.ones(n), [w_h for *_, w_h in pairs]])
    tol = rtol / math.sqrt(n)
    y = start.ravel()
    states = []
    for seg in range(4 if tilde else 2):
        s = rate[seg % 2]

        def rhs(_, z, s=s):
            return np.concatenate((T * z[n:], (T * s) * z[:n]))

        r = solve_ivp(rhs, (0.0, 1.0), y, method="DOP853", rtol=tol, atol=1e-3 * tol * scale.ravel())
        y = r.y[:, -1]
        if seg % 2 == 1:
            states.append(y.reshape(2, n).copy())
    errs, labels = [], []
    for k, (ps, sol, v, w_h) in enumerate(pairs):
        # At an edge M = +-I + N with |N| ~ e^{w_h T}: an error made in one period is multiplied by |M|
        # in the next, so each return error is measured in units of rtol |M^p| (p periods).
        S = np.diag([1.0, 1.0 / w_h])
        Ms = S @ monodromy(sol.T, ps.A, ps.l, ps.g) @ np.diag([1.0, w_h])
        n1, n2 = np.linalg.norm(Ms, 2), np.linalg.norm(Ms @ Ms, 2)
        sc = scale[:, k]
        if tilde:
            e = max(np.linalg.norm((states[0][:, k] + v) / sc) / n1, np.linalg.norm((states[1][:, k] - v) / sc) / n2)
        else:
            e = np.linalg.norm((states[0][:, k] - v) / sc) / n1
        errs.append(e / rtol)
        labels.append(ps.label(f"{sol.boundary.name} (w_h T={w_h * sol.T:.3g})"))
    return errs, labels, n


def check_thm33_ivp(cases) -> CheckResult:
    errs, labels, count = _ivp_return(cases, tilde=False)
    return _result(
        "thm3.3-return-dop853", "thm3.3", "The start (3.19)/(3.22) integrated through (2.3) by an independent "
        "solver returns after 2T",
        f"{count} pairs (parameter set, T_n) with ω_h T ≤ {X_IVP:g}: scipy.integrate.solve_ivp (DOP853, "
        "rtol = 1e-12) on θ'' = (g ± A)/l θ, restarted at each switch t = T so no step straddles the jump of a(t); "
        "all pairs as one system in the time t/T of each, with rtol/√n so that the solver's RMS error norm bounds "
        "each pair's local error as when it is solved alone. "
        "Error |y(2T) − y(0)| in (θ, θ'/ω_h), in units of rtol·‖M‖ (‖M‖ ≈ e^{ω_h T} is the condition number of "
        "the return: the integration error made in the hyperbolic phase is amplified by up to that). "
        "Tolerance 100.", "Theorem 3.3 (sufficiency), (2.3), (3.19), (3.22)", "max return error / (rtol ‖M‖)",
        errs, labels, 100.0)


def check_thm34_ivp(cases) -> CheckResult:
    errs, labels, count = _ivp_return(cases, tilde=True)
    return _result(
        "thm3.4-return-dop853", "thm3.4", "The start (3.19)/(3.22) integrated through (2.3) by an independent solver "
        "changes sign after 2T and returns after 4T",
        f"{count} pairs (parameter set, T~_n) with ω_h T ≤ {X_IVP:g}; as thm3.3-return-dop853 over four phases, "
        "the error after 4T in units of rtol·‖M²‖ (at a 4T edge M = −I + N and an error of the first period "
        "is multiplied by ‖M‖ in the second).",
        "Theorem 3.4 (sufficiency), (2.3)", "max of |y(2T) + y(0)| / (rtol ‖M‖), |y(4T) − y(0)| / (rtol ‖M²‖)",
        errs, labels, 100.0)


def _fixed_direction(cases, tilde):
    errs, labels = [], []
    for ps, sol in _edges_of(cases, tilde):
        w_h = math.sqrt((ps.A + ps.g) / ps.l)
        if w_h * sol.T > 30.0:
            continue
        M = monodromy(sol.T, ps.A, ps.l, ps.g)
        K = M + np.eye(2) if tilde else M - np.eye(2)
        # Kernel of the rank-one K: orthogonal to its larger row.
        row = K[0] if np.linalg.norm(K[0]) >= np.linalg.norm(K[1]) else K[1]
        kern = np.array([-row[1], row[0]])
        ang = math.atan2(kern[1] / w_h, kern[0])
        errs.append(abs(_wrap(ang - sol.phi0, PI)))
        labels.append(ps.label(f"{sol.boundary.name} (w_h T={w_h * sol.T:.3g})"))
    return errs, labels


def check_thm33_direction(cases) -> CheckResult:
    errs, labels = _fixed_direction(cases, tilde=False)
    return _result(
        "thm3.3-necessity", "thm3.3", "Every 2T-periodic solution starts on the line given by (3.19)/(3.22): the "
        "fixed direction of the monodromy matrix is that angle",
        f"{len(errs)} pairs (parameter set, T_n) with ω_h T ≤ 30. At T_n, M − I has rank one; its kernel, computed "
        "from the matrix entries alone, is the set of 2T-periodic starts. Its polar angle in (θ, θ'/ω_h) is compared "
        "with φ_0 modulo π. Tolerance 1e-10 rad.", "Theorem 3.3 (necessity), Lemma 3.1, (3.16), (3.18)",
        "max |angle(ker(M − I)) − φ_0| mod π [rad]", errs, labels, 1e-10)


def check_thm34_direction(cases) -> CheckResult:
    errs, labels = _fixed_direction(cases, tilde=True)
    return _result(
        "thm3.4-necessity", "thm3.4", "Every 4T-periodic solution starts on the line given by (3.19)/(3.22): the "
        "kernel of M + I has that angle", f"{len(errs)} pairs (parameter set, T~_n) with ω_h T ≤ 30; as "
        "thm3.3-necessity with M + I.", "Theorem 3.4 (necessity), Lemma 3.2",
        "max |angle(ker(M + I)) − φ_0| mod π [rad]", errs, labels, 1e-10)


def _plain_trace_roots(sets, u_max, sign):
    """Roots in T of tr M - 2 sign (plain matrix product) on (0, u_max / w_e] for each parameter set,
    by bisection; one list of roots per set (all sets are sampled and bisected together)."""

    def F(T, A, l, g):
        M = monodromy(T, A, l, g)
        return M[..., 0, 0] + M[..., 1, 1] - 2.0 * sign

    grids = [np.linspace(1e-6, u_max, int(u_max / 0.004)) / ps.frequencies[1] for ps in sets]
    owner = np.repeat(np.arange(len(sets)), [t.size for t in grids])
    T = np.concatenate(grids)
    A, l, g = (np.array([getattr(ps, k) for ps in sets])[owner] for k in "Alg")
    v = F(T, A, l, g)
    # Sign changes between neighbours of the same set's grid.
    idx = np.flatnonzero((np.sign(v[:-1]) * np.sign(v[1:]) < 0) & (owner[:-1] == owner[1:]))
    lo, hi = T[idx], T[idx + 1]
    flo = v[idx]
    A, l, g, owner = A[idx], l[idx], g[idx], owner[idx]
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        fm = F(mid, A, l, g)
        left = np.sign(fm) == np.sign(flo)
        lo = np.where(left, mid, lo)
        flo = np.where(left, fm, flo)
        hi = np.where(left, hi, mid)
    roots = 0.5 * (lo + hi)
    return [roots[owner == k] for k in range(len(sets))]


def _iff_roots(cases, tilde):
    errs, labels = [], []
    zones = cases.zones
    sign = -1.0 if tilde else 1.0
    name = "T~_n" if tilde else "T_n"
    u_max = (zones - 0.5) * PI  # inside the instability gap after zone zones-2
    sets = [ps for ps in cases.sets if ps.frequencies[2] * u_max <= 300]
    for ps, roots in zip(sets, _plain_trace_roots(sets, u_max, sign)):
        w_e = ps.frequencies[1]
        Tn, Tt = boundary_periods(ps.A, zones, ps.l, ps.g)
        ref = Tt if tilde else Tn
        want = ref[w_e * ref < u_max]
        if roots.size != want.size:
            errs.append(1.0)
            labels.append(ps.label(f"{roots.size} roots of tr M = {2 * sign:+g} but {want.size} {name}"))
            continue
        errs.append(float(np.max(np.abs(roots / want - 1.0))) if want.size else 0.0)
        labels.append(ps.label(f"{want.size} roots"))
    return errs, labels


_IFF_METHOD = (
    "For each parameter set, tr M {} 2 is sampled with the plain matrix product E(T)H(T) (kapitza.monodromy) on "
    "a grid of step 0.004 in ω_e T up to just below the last zone counted, every sign change is refined by 80 "
    "bisections, and the roots are matched one to one with kapitza.boundary_periods. A count mismatch is error "
    "1. Tolerance 1e-9 relative: the plain trace loses e^{{ω_h T}}-sized digits but its slope is as large.")


def check_thm33_only_if(cases) -> CheckResult:
    """The T_n are all the roots of tr M = 2: the 'only if' of Theorem 3.3."""
    errs, labels = _iff_roots(cases, tilde=False)
    return _result(
        "thm3.3-only-if", "thm3.3", "There are no other 2T-periodic solutions: the roots of tr M = 2 are exactly "
        "the T_n, one for each equation (3.10)/(3.11) and k", _IFF_METHOD.format("−"),
        "Theorem 3.3 (necessity), section 4 (uniqueness), docs/theory.md §3",
        "max |root / T_n − 1| (1 on a count mismatch)", errs, labels, 1e-9)


def check_thm34_only_if(cases) -> CheckResult:
    """The T~_n are all the roots of tr M = -2: the 'only if' of Theorem 3.4."""
    errs, labels = _iff_roots(cases, tilde=True)
    return _result(
        "thm3.4-only-if", "thm3.4", "There are no other 4T-periodic solutions: the roots of tr M = −2 are exactly "
        "the T~_n, one for each equation (3.12)/(3.13) and k", _IFF_METHOD.format("+"),
        "Theorem 3.4 (necessity), section 4 (uniqueness), docs/theory.md §3",
        "max |root / T~_n − 1| (1 on a count mismatch)", errs, labels, 1e-9)


# ------------------------------------------------------------------ section 4
def check_alpha_beta_shape(cases) -> CheckResult:
    viol, labels = [], []
    for ps in cases.sets:
        w_h, w_e, D = ps.frequencies
        T = np.linspace(0.01, 12.0, 4001) / w_h
        a, b = alpha_T(T, ps.A, ps.l, ps.g), beta_T(T, ps.A, ps.l, ps.g)
        da, db = np.diff(a), np.diff(b)
        dda, ddb = np.diff(a, 2), np.diff(b, 2)
        mid = 2.0 * np.arctan(D)
        count = (np.sum(da <= 0) + np.sum(dda >= 0) + np.sum(db >= 0) + np.sum(ddb <= 0)
                 + np.sum(~((0 < a) & (a < mid) & (mid < b) & (b < PI))))
        viol.append(float(count))
        labels.append(ps.label())
    return _result(
        "sec4-alpha-beta", "sec4.alpha-beta", "α is increasing and concave, β decreasing and convex, "
        "0 < α < 2 atan D < β < π",
        f"{len(viol)} parameter sets; first and second differences of kapitza.alpha/beta on 4001 points with "
        "ω_h T ∈ [0.01, 12] (where the differences are still far above rounding). Count of wrong signs must be 0.",
        "section 4 (definitions of α, β)", "number of violations", viol, labels, 0.0)


def check_interlacing(cases) -> CheckResult:
    n_A = cases.interlacing_A
    count = 8
    bad, labels, rows = [], [], []
    g = G_EARTH
    ratios = np.geomspace(1.0 + 1e-4, 1e6, n_A)
    for i, ratio in enumerate(ratios):
        A = g * ratio
        mu = math.sqrt(g / A)
        Tn, Tt = boundary_periods(A, count, 1.0, g)
        n = np.arange(count)
        lo = np.where(n % 2 == 0, Tn, Tt)  # T_1, T~_2, T_3, T~_4, ...
        hi = np.where(n % 2 == 0, Tt, Tn)  # T~_1, T_2, T~_3, T_4, ...
        # Between zones the gaps are wide and the doubles are compared. Inside zone n the gap is the
        # zone's width, below a double's resolution of T for high zones: it is taken from the
        # cancellation-free log-width instead.
        between = (lo[1:] - hi[:-1]) / hi[:-1]
        log_within = zone_width(mu, n, log=True) + 0.5 * math.log(8.0 / A) - np.log(lo)
        count_bad = int(np.sum(~(between > 0)) + np.sum(~np.isfinite(log_within)) + np.sum(lo > hi)
                        + (lo[0] <= 0))
        bad.append(float(count_bad))
        labels.append(f"A={A:.8g} (mu={mu:.8g})")
        if i in np.unique(np.linspace(0, n_A - 1, 6).round().astype(int)):
            rows.append([f"{A:.6g}", f"{Tn[0]:.10g} < {Tt[0]:.10g} < {Tt[1]:.10g} < {Tn[1]:.10g}",
                         f"{between.min():.3g}", f"{log_within.min() / math.log(10.0):.4g}"])
    return _result(
        "cor4.1-interlacing", "cor4.1", "0 < T_1 < T~_1 < T~_2 < T_2 < T_3 < T~_3 < … for every A > g",
        f"{n_A} amplitudes A/g log-spaced in [1 + 1e-4, 1e6] (g = 9.81, l = 1), the first {count} T_n and T~_n "
        "each, put in the corollary's order. Gaps between zones are differences of kapitza.boundary_periods and "
        "must be positive; the gap inside zone n is its width, from kapitza.zone_width(log=True), whose "
        "logarithm must be finite (for high zones and A near g the width is far below a double's resolution of "
        "T, e.g. 10^-200 relative, so the edges themselves round to the same number).",
        "Corollary 4.1, Theorems 3.3-3.4", "number of gaps that are not positive (per amplitude)", bad, labels,
        0.0, table=dict(header=["A", "T_1 < T~_1 < T~_2 < T_2", "smallest relative gap between zones",
                                "log10 smallest relative zone width"], rows=rows), cases=n_A * (2 * count - 1))


def _plain_trace(x, u, D):
    with np.errstate(over="ignore", invalid="ignore"):
        return 2.0 * np.cosh(x) * np.cos(u) + (D - 1.0 / D) * np.sinh(x) * np.sin(u)


def check_trace_at_edges(cases) -> CheckResult:
    errs, labels = [], []
    for ps in cases.sets:
        w_h, w_e, D = ps.frequencies
        for b in boundary_table(ps.A, cases.zones, ps.l, ps.g):
            x, u = w_h * b.T, w_e * b.T
            if x > 700:
                continue
            want = -2.0 if b.tilde else 2.0
            scale = 2.0 * math.cosh(x) * max(u, 1.0)
            fac = float(floquet(b.eps, b.mu).trace)
            plain = float(_plain_trace(x, u, D))
            M = monodromy(b.T, ps.A, ps.l, ps.g)
            mat = float(M[0, 0] + M[1, 1])
            for val, how in ((fac, "factored"), (plain, "cosh formula"), (mat, "matrix product")):
                errs.append(abs(val - want) / scale)
                labels.append(ps.label(f"{b.name}, {how} (w_h T={x:.3g})"))
    return _result(
        "sec4-trace-at-edges", "sec4.zones", "tr M = 2 at every T_n and tr M = −2 at every T~_n, by three formulas",
        f"{len(errs) // 3} boundary periods; the trace by the factored form −2 sin(u − γ)/sin δ (kapitza.floquet), "
        "by 2 cosh x cos u + (D − 1/D) sinh x sin u, and as the trace of the matrix product E(T)H(T). The error is "
        "taken relative to 2 cosh(ω_h T)·max(ω_e T, 1), the size of the terms the trace is made of times the "
        "rounding of the edge itself. Tolerance 1e-13.", "Floquet theory (section 4), docs/theory.md §3",
        "max |tr M ∓ 2| / (2 cosh x · max(u, 1))", errs, labels, 1e-13)


def check_stability_grid(cases) -> CheckResult:
    n = cases.grid
    eps = np.linspace(4.0 / n, 4.0, n)
    mu = np.linspace(0.005, 0.995, n)
    E, Mu = np.meshgrid(eps, mu)
    x = SQRT8 * E * np.sqrt(1.0 + Mu**2)
    u = SQRT8 * E * np.sqrt((1.0 - Mu) * (1.0 + Mu))
    D = np.sqrt(1.0 + Mu**2) / np.sqrt((1.0 - Mu) * (1.0 + Mu))
    tr = _plain_trace(x, u, D)
    clear = np.abs(np.abs(tr) - 2.0) > 1e-9 * 2.0 * np.cosh(x)
    verdict = is_stable(E, Mu)
    mismatch = clear & (verdict != (np.abs(tr) < 2.0))
    idx = np.argwhere(mismatch)
    label = f"eps={E[tuple(idx[0])]:.6g}, mu={Mu[tuple(idx[0])]:.6g}" if idx.size else ""
    return _result(
        "sec4-stability-region", "sec4.zones", "The union of the zones α + nπ < ω_e T < β + nπ is exactly where "
        "|tr M| < 2",
        f"{n} × {n} grid, ε ∈ (0, 4], μ ∈ [0.005, 0.995]: kapitza.is_stable (zones from Theorems 3.3-3.4) against "
        "|tr M| < 2 by the plain cosh formula, skipping points within 1e-9·2cosh x of |tr M| = 2 where the plain "
        "formula cannot decide. Mismatches must be 0.", "section 4, Floquet theory",
        "number of mismatches", [float(mismatch.sum())], [label], 0.0, cases=int(clear.sum()))


def check_figure7_edges(cases) -> CheckResult:
    from . import data as D_

    fd = D_.figure7_data(points=200 if cases.quick else 600)
    errs, labels = [], []
    for s in fd.series_with(role="edge"):
        n = s.meta["zone"]
        eps, mu = np.asarray(s.x), np.asarray(s.y)
        p = np.sqrt(1.0 + mu * mu)
        q = np.sqrt((1.0 - mu) * (1.0 + mu))
        x, u, Dv = SQRT8 * eps * p, SQRT8 * eps * q, p / q
        ok = x < 700
        curve = _literal_alpha if s.meta["edge"] == "lower" else _literal_beta
        with np.errstate(over="ignore", invalid="ignore"):
            res = np.abs(curve(x[ok], Dv[ok]) + n * PI - u[ok]) / np.maximum(u[ok], 1.0)
        kind_ok = s.meta["period"] == ("2T" if (n % 2 == 0) == (s.meta["edge"] == "lower") else "4T")
        i = int(np.argmax(res))
        errs.append(float(res[i]) if kind_ok else 1.0)
        labels.append(f"zone {n} {s.meta['edge']} edge at mu={mu[ok][i]:.6g}")
    return _result(
        "sec4-figure7-edges", "sec4.zones", "The curves drawn in Figure 7 are the solution sets of (3.10)-(3.13), "
        "each labelled with the right period",
        f"Every sampled point of every edge of Figure 7 ({sum(len(s.x) for s in fd.series_with(role='edge'))} points): "
        "residual of the printed equation u = α + nπ (lower) or β + nπ (upper), relative to max(u, 1); the lower "
        "edge of an even zone must be labelled 2T, of an odd zone 4T. Tolerance 50 units of rounding.",
        "(3.10)-(3.13), Figure 7", "max relative residual", errs, labels, 50 * EPS,
        cases=sum(len(s.x) for s in fd.series_with(role="edge")))


def _mu_star(m):
    """Largest mu at which G_m lies inside zone m: D tanh(x/2) = 1 at u = (m + 1/2) pi."""
    u = (m + 0.5) * PI

    def F(mu):
        D = math.sqrt((1.0 + mu * mu) / ((1.0 - mu) * (1.0 + mu)))
        return D * math.tanh(0.5 * D * u) - 1.0

    lo, hi = 1e-300, 0.999999
    if F(lo) > 0:
        return 0.0
    for _ in range(200):
        mid = math.sqrt(lo * hi) if hi / lo > 4 else 0.5 * (lo + hi)
        if F(mid) < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def check_along_G(cases) -> CheckResult:
    """Zone m lies in the strip m pi < w_e T < (m+1) pi of G_m, its centre a fixed distance asin(mu^2) from G_m."""
    M = 9 if cases.quick else 13
    mu = np.linspace(0.02, 0.98, 25)
    m = np.arange(M)
    lo, hi = zone_edges(mu[:, None], m[None, :])
    q = np.sqrt((1.0 - mu) * (1.0 + mu))[:, None]
    ulo, uhi = SQRT8 * lo * q, SQRT8 * hi * q
    outside = (~((ulo > m * PI) & (uhi < (m + 1) * PI) & (ulo <= uhi))).sum(axis=1)
    offset = 0.5 * (ulo + uhi) - (m + 0.5) * PI  # G_m is u = (m + 1/2) pi
    limit = np.arcsin(mu**2)
    dev = np.abs(offset[:, -1] - limit)
    vals = list(dev) + [float(outside.sum())]
    labels = [f"zone {M - 1}, mu={v:.3g}: centre - G_{M - 1} - asin(mu^2) in u" for v in mu] + [
        "edges outside the strip m pi < u < (m+1) pi (count)"]
    i = len(mu) // 2
    rows = [[f"{mu[i]:.3g}", int(k), f"{ulo[i, k]:.8g}", f"{uhi[i, k]:.8g}", f"{offset[i, k]:.6g}",
             f"{limit[i]:.6g}", f"{offset[i, k] / (SQRT8 * q[i, 0] * 0.5 * (lo[i, k] + hi[i, k])):.3g}"]
            for k in (0, 1, 2, 4, M - 1)]
    return _result(
        "sec4-along-G", "sec4.zones", "The tongues lie along the curves G_m: zone m stays inside the strip "
        "mπ < ω_e T < (m+1)π whose middle is G_m, and its centre keeps a distance in ω_e T that tends to asin(μ²)",
        f"Edges of zones 0..{M - 1} at 25 values of μ ∈ [0.02, 0.98] (kapitza.zone_edges): count of edges outside "
        "the strip (must be 0); the centre's offset from G_m in u = ω_e T, which by docs/theory.md §5 is "
        "γ − π/2 + O(e^{−x}) with γ → π/2 + asin(μ²), must match asin(μ²) for the last zone to 1e-9. So the "
        "offset in ε relative to ε itself falls like 1/m, and vanishes like μ² as μ → 0.",
        "section 4 (G_m), (3.10)-(3.13)", "max |offset − asin(μ²)| [rad] (and the count)", vals, labels, 1e-9,
        table=dict(header=["mu", "zone m", "u_lo", "u_hi", "centre - G_m (u)", "asin(mu^2)",
                           "offset / u (relative)"], rows=rows), cases=mu.size * M)


def check_widths(cases) -> CheckResult:
    m_max = 8 if cases.quick else 12
    mu = np.linspace(0.005, 0.995, 200)
    logw = np.array([zone_width(mu, m, log=True) for m in range(m_max + 1)])
    ratios = np.exp(logw[1:] - logw[:-1])  # width(m+1)/width(m) at each mu
    worst_each = ratios.max(axis=1)
    maxw = np.exp(logw.max(axis=1))
    rows = [[m, f"{maxw[m]:.4g}", f"{np.exp(logw[m, 0]):.4g}", f"{np.exp(logw[m, -1]):.4g}"] for m in range(m_max + 1)]
    labels = [f"zone {m + 1} vs zone {m}" for m in range(m_max)]
    vals = list(worst_each) + [maxw[-1] / maxw[0]]
    labels.append(f"max width of zone {m_max} / max width of zone 0")
    return _result(
        "sec4-widths", "sec4.zones", "The widths of the tongues tend to zero: at every μ zone m+1 is narrower than "
        "zone m, and the largest width decays geometrically",
        f"Widths in ε of zones 0..{m_max} at 200 values of μ ∈ [0.005, 0.995] from kapitza.zone_width(log=True) "
        "(cancellation-free, finite even where a width underflows). The worst ratio width(m+1)/width(m) over all μ "
        f"must stay below 1/2 (it is close to e^{{-π}} ≈ 0.04 for small μ), and the largest width of zone {m_max} "
        "relative to zone 0's likewise.", "section 4 (stability zones)", "max width(m+1)/width(m)", vals, labels, 0.5,
        table=dict(header=["zone m", "max width over mu", "width at mu=0.005", "width at mu=0.995"], rows=rows),
        cases=mu.size * (m_max + 1))


def check_heights(cases) -> CheckResult:
    m_max = 6 if cases.quick else 8
    stars = [_mu_star(m) for m in range(m_max + 1)]
    errs, labels, rows = [], [], []
    for m, ms in enumerate(stars):
        # G_m is in zone m below mu*_m and outside it above.
        # 1e-3 either side of mu*_m: there D tanh(x/2) - 1 differs from 0 by ~2e-3 mu^2, well above rounding.
        grid = np.concatenate([np.geomspace(ms * 1e-3, ms * (1 - 1e-3), 40),
                               np.linspace(min(ms * (1 + 1e-3), 0.99), 0.99, 40)])
        grid = grid[(grid > 0) & (grid < 1)]
        inside = is_stable(G_m_curve(grid, m), grid)
        wrong = np.sum(inside != (grid < ms))
        errs.append(float(wrong))
        labels.append(f"G_{m}, mu*_{m} = {ms:.6g}")
        rows.append([m, f"{ms:.6g}", f"{math.sqrt(2.0) * math.exp(-(m + 0.5) * PI / 2):.3g}"])
    # mu*_m must decrease to 0.
    dec = [stars[m] - stars[m + 1] for m in range(m_max)]
    errs.append(float(sum(d <= 0 for d in dec)))
    labels.append("mu*_m not decreasing")
    errs.append(float(stars[-1] > 1e-3))
    labels.append(f"mu*_{m_max} = {stars[-1]:.3g} not below 1e-3")
    note = ("The paper gives no formula for the 'height' of a tongue. Here it is read as the range 0 < μ < μ*_m in "
            "which the curve G_m runs inside zone m; above μ*_m zone m still exists (every zone reaches μ → 1) but "
            "lies to the right of G_m and is exponentially thin. μ*_m solves D tanh(x/2) = 1 on G_m and behaves like "
            "√2 e^{−(m+½)π/2}.")
    return _result(
        "sec4-heights", "sec4.zones", "The tongues lie along G_m and their heights tend to zero: G_m is inside zone m "
        "exactly for μ < μ*_m, and μ*_m decreases to 0",
        f"For m = 0..{m_max}: μ*_m by bisection on D tanh(x/2) = 1 at ω_e T = (m + ½)π; kapitza.is_stable on G_m at "
        "80 values of μ (down to 1e-3 relative from μ*_m on either side) must agree with μ < μ*_m "
        "(count of disagreements), μ*_m must decrease "
        f"and μ*_{m_max} be below 1e-3.", "section 4 (G_m, stability zones), Figure 7",
        "number of violations", errs, labels, 0.0, note=note,
        table=dict(header=["m", "mu*_m (G_m inside zone m for mu < mu*_m)", "sqrt(2) e^{-(m+1/2) pi/2}"], rows=rows))


def check_infinitely_many(cases) -> CheckResult:
    n_max = 60 if cases.quick else 300
    mu = np.linspace(0.01, 0.99, 50)
    n = np.arange(n_max + 1)
    logw = zone_width(mu[None, :], n[:, None], log=True)
    lo, hi = zone_edges(mu[None, :], n[:, None])
    gaps = (lo[1:] - hi[:-1]) / hi[:-1]
    vals = [0.0 if np.all(np.isfinite(logw)) else -1.0, float(gaps.min())]
    labels = ["all widths positive and finite (log width finite)",
              f"smallest relative gap eps_lo(n+1) - eps_hi(n), zones 0..{n_max}"]
    return _result(
        "sec4-infinitely-many", "sec4.zones", "The stability region has infinitely many components: every zone "
        "n is non-empty for every μ ∈ (0, 1), and consecutive zones are separated by instability",
        f"Zones 0..{n_max} at 50 values of μ ∈ [0.01, 0.99]: log-widths from kapitza.zone_width(log=True) must be "
        "finite (width > 0 even where it underflows a double), and ε_hi(n) < ε_lo(n+1).",
        "section 4, Corollary 4.1", "smallest margin (must be > 0)", [1.0 if vals[0] == 0 else -1.0, vals[1]],
        labels, 0.0, sense=">", cases=int(mu.size * (n_max + 1)))


# ------------------------------------------------------------------ Figure 8 approximations
def check_kapitza_velocity(cases) -> CheckResult:
    rng = np.random.default_rng(cases.seed + 4)
    errs, labels = [], []
    N = 200000
    for _ in range(20):
        A = float(np.exp(rng.uniform(np.log(1.0), np.log(1e4))))
        T = float(np.exp(rng.uniform(np.log(1e-3), np.log(2.0))))
        l = float(np.exp(rng.uniform(np.log(0.1), np.log(10.0))))
        g = float(rng.choice(_GRAVITIES))
        t = (np.arange(N) + 0.5) * (2.0 * T / N)  # midpoint rule over one period 2T
        v = pivot_velocity(t, T, A)
        ms = float(np.mean(v * v))
        errs.append(abs(ms / float(ap.mean_square_velocity(A, T)) - 1.0))
        labels.append(f"<v^2> vs A^2 T^2/12 at A={A:.4g}, T={T:.4g}")
        errs.append(abs(float(np.mean(v))) / (A * T))
        labels.append(f"mean velocity at A={A:.4g}, T={T:.4g}")
        # dv/dt = a(t): +A on [0, T), -A on [T, 2T) (2.2), by differences inside each phase.
        dv = np.diff(v) / np.diff(t)
        a = np.where(t[:-1] % (2 * T) < T, A, -A)
        inner = np.abs(np.diff(np.where(t % (2 * T) < T, 1, -1))) == 0
        errs.append(float(np.max(np.abs(dv[inner] - a[inner]))) / A)
        labels.append(f"dv/dt = a(t) at A={A:.4g}, T={T:.4g}")
        eps = T * math.sqrt(A / (8.0 * l))
        mu = math.sqrt(g / A)
        errs.append(abs((A * A * T * T / (12.0 * g * l)) / ((2.0 / 3.0) * (eps / mu) ** 2) - 1.0))
        labels.append(f"A^2T^2/(12 g l) = (2/3)(eps/mu)^2 at A={A:.4g}, T={T:.4g}, l={l:.3g}, g={g:.3g}")
    return _result(
        "fig8-kapitza-criterion", "fig8", "The pivot velocity of the square wave is a zero-mean triangle wave with "
        "⟨v²⟩ = A²T²/12, so Kapitza's ⟨v²⟩ > g l reads ε > √(3/2) μ",
        "20 random (A, T, l, g): ⟨v²⟩ by the midpoint rule with 2·10⁵ points against A²T²/12; the mean of v; dv/dt "
        "against a(t) of (2.2) by differences; and the identity A²T²/(12 g l) = (2/3)(ε/μ)². Tolerance 1e-8 (the "
        "midpoint rule's error is ~1/N²).", "(2.2); Kapitza [14]; section 4 (ε, μ)", "max relative error",
        errs, labels, 1e-8, cases=20)


def check_kapitza_limit(cases) -> CheckResult:
    mu = np.geomspace(0.01, 0.08, 30)
    lo, _ = zone_edges(mu, 0)
    rel = ap.kapitza_edge(mu) / lo - 1.0
    coeff = rel / mu**4
    errs = list(np.abs(coeff + 4.0 / 7.0) / (4.0 / 7.0))
    labels = [f"Kapitza at mu={m:.4g}: (eps_K/eps_lo - 1)/mu^4 = {c:.8f}" for m, c in zip(mu, coeff)]
    # The two-term series: error -(c_2/2) mu^8 to leading order.
    c2 = ap.LOWER_EDGE_COEFFS[1]
    ms = np.geomspace(0.04, 0.15, 20)
    los, _ = zone_edges(ms, 0)
    c = (ap.lower_edge_series(ms, 2) / los - 1.0) / ms**8
    errs += list(np.abs(c + 0.5 * c2) / (0.5 * c2))
    labels += [f"series at mu={m:.4g}: (eps_2/eps_lo - 1)/mu^8 = {v:.6f}" for m, v in zip(ms, c)]
    tiny = np.geomspace(1e-6, 1e-3, 10)
    lt, _ = zone_edges(tiny, 0)
    lim = float(np.max(np.abs(ap.kapitza_edge(tiny) / lt - 1.0)))
    errs.append(lim / 1e-12 * 1e-3)
    labels.append(f"|eps_K/eps_lo - 1| = {lim:.2g} for mu <= 1e-3 (scaled: tolerance 1e-12)")
    return _result(
        "fig8-kapitza-limit", "fig8", "Kapitza's line ε = √(3/2) μ tends to the exact lower edge of zone 0 as "
        "μ → 0 (equivalently ε → 0), with relative error −(4/7) μ⁴; the two-term series in μ has error "
        "−(8424/13475) μ⁸",
        "(ε_K/ε_lo − 1)/μ⁴ at 30 values of μ ∈ [0.01, 0.08] against −4/7, and (ε_2/ε_lo − 1)/μ⁸ at 20 values of "
        "μ ∈ [0.04, 0.15] against −c_2/2 = −8424/13475 (relative deviations; the next terms are O(μ⁴) ≤ 5e-4 "
        "and rounding ≤ 1e-16/μ⁸ ≤ 4e-5); ε_lo from kapitza.zone_edges, which solves (3.10) with k = 0 without "
        "cancellation for small μ. For μ ≤ 1e-3, |ε_K/ε_lo − 1| must be below 1e-12 (reported scaled to the "
        "common tolerance). Tolerance 1e-3.", "(3.10) with k = 0; Figure 8",
        "max relative deviation of the error coefficient", errs, labels, 1e-3)


def check_trace_series(cases) -> CheckResult:
    rng = np.random.default_rng(cases.seed + 5)
    n = 400 if cases.quick else 4000
    eps = rng.uniform(0.01, 2.5, n)
    mu = rng.uniform(0.01, 0.99, n)
    exact = floquet(eps, mu).trace / 2.0
    x = SQRT8 * eps * np.sqrt(1 + mu**2)
    full = ap.trace_series(eps, mu, 80)
    e_full = np.abs(full - exact) / np.cosh(x)
    errs = [float(e_full.max())]
    i = int(np.argmax(e_full))
    labels = [f"80-term series vs exact trace at eps={eps[i]:.4g}, mu={mu[i]:.4g}"]
    # The remainder of the eps^4 truncation against the next two terms of the series: the exact trace
    # minus the truncation is (4 eps)^6/6! U_3(mu^2) + (4 eps)^8/8! U_4(mu^2) + O(eps^10).
    e_small = np.geomspace(0.03, 0.08, 20)
    for m in (0.3, 0.5, 0.9):
        rem = floquet(e_small, m).trace / 2.0 - ap.trace_series(e_small, m, 4)
        nxt = ap.trace_series(e_small, m, 8) - ap.trace_series(e_small, m, 4)
        errs.append(float(np.max(np.abs(rem / nxt - 1.0))))
        labels.append(f"remainder after eps^4 / (eps^6 + eps^8 terms) - 1 at mu={m}")
    return _result(
        "fig8-trace-series", "fig8", "tr M / 2 = Σ (4ε)^{2j}/(2j)! U_j(μ²) exactly, and the O(ε⁴) truncation used "
        "in Figure 8 is off by its next term, O(ε⁶)",
        f"{n} random (ε, μ) ∈ [0.01, 2.5] × [0.01, 0.99]: 80 terms against kapitza.floquet's trace (the factored "
        "form), relative to cosh x (the size of the trace's terms); and for ε ∈ [0.03, 0.08], μ ∈ {0.3, 0.5, 0.9} "
        "the exact trace minus its ε⁴ truncation against the ε⁶ and ε⁸ terms (relative; the rest is O(ε⁴) ≤ 1e-5, "
        "rounding ≤ 1e-7). Tolerance 1e-4.", "docs/theory.md §3; Arnold [1]", "max relative error",
        errs, labels, 1e-4, cases=n + 60)


#: Every check, in report order, with the claim it belongs to.
CHECKS = [
    (check_f_angle_map, "sec2"),
    (check_phi_h, "sec2"),
    (check_h_monotone, "sec2"),
    (check_polar_map, "lemma3.1"),
    (check_lemma31, "lemma3.1"),
    (check_lemma32, "lemma3.2"),
    (check_thm33_equations, "thm3.3"),
    (check_thm33_matrix, "thm3.3"),
    (check_thm33_ivp, "thm3.3"),
    (check_thm33_direction, "thm3.3"),
    (check_thm33_only_if, "thm3.3"),
    (check_thm34_equations, "thm3.4"),
    (check_thm34_matrix, "thm3.4"),
    (check_thm34_ivp, "thm3.4"),
    (check_thm34_direction, "thm3.4"),
    (check_thm34_only_if, "thm3.4"),
    (check_alpha_beta_shape, "sec4.alpha-beta"),
    (check_interlacing, "cor4.1"),
    (check_trace_at_edges, "sec4.zones"),
    (check_stability_grid, "sec4.zones"),
    (check_figure7_edges, "sec4.zones"),
    (check_infinitely_many, "sec4.zones"),
    (check_along_G, "sec4.zones"),
    (check_widths, "sec4.zones"),
    (check_heights, "sec4.zones"),
    (check_kapitza_velocity, "fig8"),
    (check_kapitza_limit, "fig8"),
    (check_trace_series, "fig8"),
]


def run_check(index, cases) -> CheckResult:
    """Run ``CHECKS[index]`` on ``cases``; a check that raises is returned as a failed result."""
    func, claim = CHECKS[index]
    try:
        with np.errstate(over="ignore", under="ignore"):
            return func(cases)
    except Exception as exc:  # a crashing check is a failed check, reported, never dropped
        return _failed(func, claim, exc)


def run_checks(quick=False, seed=20170915, only=None):
    """Run every check (or those whose key starts with one of ``only``).

    Parameters
    ----------
    quick : bool
        Fewer parameter sets (see :func:`parameter_sets`).
    seed : int
        Seed for the random parameter draws.
    only : sequence of str, optional
        Key prefixes to select checks by (``"thm3.3"``...); all if None.

    Returns
    -------
    tuple of CheckResult
        A check that raises is returned as a failed result carrying the error.
    """
    seed = int(_v.nonnegative_int("seed", seed))
    cases = parameter_sets(quick, seed)
    out = []
    for i in range(len(CHECKS)):
        res = run_check(i, cases)
        if only is None or any(res.key.startswith(p) for p in only):
            out.append(res)
    return tuple(out)


def period_table(As=(12.0, 20.0, 30.0, 50.0, 100.0, 1000.0), count=4, l=1.0, g=G_EARTH):
    """``T_n``, ``T~_n`` for several amplitudes, with their equations and the trace there.

    Parameters
    ----------
    As : sequence of float
        Amplitudes, each ``> g``.
    count : int
        Zones per amplitude (each gives one ``T_n`` and one ``T~_n``).
    l, g : float
        Rod length and gravity.

    Returns
    -------
    dict
        ``{"header": [...], "rows": [[...], ...]}``: one row per boundary period, in
        the order of Corollary 4.1, with ``w_h T`` and ``tr M`` by the factored formula
        (``tr M = +-2`` up to about ``1e-16 e^{w_h T}``: the trace is that steep at an edge
        rounded to a double).
    """
    rows = []
    for A in As:
        w_h = math.sqrt((A + g) / l)
        for b in boundary_table(A, count, l, g):
            tr = float(floquet(b.eps, b.mu).trace)
            rows.append([float(A), b.name, b.T, b.period, b.equation, b.k, b.zone, b.edge, b.eps, b.mu, w_h * b.T, tr])
    return dict(header=["A", "name", "T", "period", "equation", "k", "zone", "edge", "eps", "mu", "w_h T", "trace"],
                rows=rows)
