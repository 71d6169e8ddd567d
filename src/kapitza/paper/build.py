"""Everything of the reproduction, written into one folder (the ``kapitza paper`` command)."""
from __future__ import annotations

import datetime
import functools
import multiprocessing
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path


from .. import __version__, _io
from .. import _validate as _v
from . import checks as C
from .report import Code, Heading, Image, Para, Table, nonlinear_section, plain_math, to_html, to_markdown

__all__ = ["PaperBuild", "build_paper", "TABLE_AMPLITUDES"]

#: Amplitudes [m/s^2] of the table of boundary half-periods (l = 1 m, g = 9.81 m/s^2).
TABLE_AMPLITUDES = (15.0, 30.0, 100.0, 1000.0)

PAPER = ("L. Csizmadia and L. Hatvani, *On the existence of periodic motions of the excited inverted "
         "pendulum by elementary methods* (2017)")

FORMULAS = """\
a(t) = +A on [2kT, (2k+1)T),  -A on [(2k+1)T, (2k+2)T)                      (2.2)
theta'' - (g + a(t))/l theta = 0                                              (2.3)
w_h = sqrt((A+g)/l),  w_e = sqrt((A-g)/l),  D = w_h / w_e
alpha(T) = 2 atan(D (e^{w_h T} - 1)/(e^{w_h T} + 1))
beta(T)  = 2 atan(D (e^{w_h T} + 1)/(e^{w_h T} - 1))
2T-periodic:  w_e T = alpha + 2k pi   (3.10)    w_e T = beta + (2k+1) pi   (3.11)
4T-periodic:  w_e T = alpha + (2k+1) pi (3.12)  w_e T = beta + 2k pi       (3.13)
phi_0 = atan((1 - e^{w_h T})/(1 + e^{w_h T}))   for (3.10), (3.12)        (3.19)
phi_0 = -atan((e^{w_h T} + 1)/(e^{w_h T} - 1))  for (3.11), (3.13)        (3.22)
eps = T sqrt(A)/sqrt(8 l),  mu = sqrt(g/A);   G_m: 2 sqrt(2) eps sqrt(1 - mu^2) = (2m+1) pi/2
stable (zone n)  <=>  alpha + n pi < w_e T < beta + n pi
reference for every check: tr M = 2 cosh(w_h T) cos(w_e T) + (D - 1/D) sinh(w_h T) sin(w_e T),
  M = E(T) H(T) the one-period matrix; solve_ivp (DOP853) where an independent integration is used"""


#: What Figure 8 draws in place of the paper's curve from its reference [6].
FIGURE8_NOTE = (
    "**Figure 8 is not the paper's Figure 8.** The paper draws, as thin boundary curves, the first approximating "
    "stability zone of its reference [6] (Csizmadia and Hatvani, Meccanica 49 (2014) 1091-1100), obtained there "
    "by an extension of the Levi-Weckesser method. This paper does not state that zone's formula, so kapitza does "
    "not draw it. Figure 8 draws instead, beside `G_0` and the exact first zone, three approximations derived in "
    "`kapitza.paper.approximations` and checked below (fig8-*): Kapitza's averaging criterion "
    "`eps > sqrt(3/2) mu`, both edges of the `O(eps^4)` truncation of `tr M`, and the series "
    "`eps^2 = (3/2) mu^2 (1 + (8/7) mu^4)` of the lower edge; its right panel gives their relative errors.")


@dataclass(frozen=True)
class PaperBuild:
    """What :func:`build_paper` wrote and found.

    Attributes
    ----------
    out : Path
    files : tuple of Path
    checks : tuple of CheckResult
    passed : bool
        True when every check passed.
    """

    out: Path
    files: tuple
    checks: tuple
    passed: bool


def _fmt(v, digits=3):
    if isinstance(v, float):
        if v == 0.0:
            return "0"
        return f"{v:.{digits}e}"
    return str(v)


def _bound(r):
    return f"{'≤' if r.sense == '<=' else '>'} {_fmt(r.tolerance)}"


#: CPU seconds of each task, measured once (2026-11-25, each task alone in a fresh process forked
#: after the imports, full parameter sets); the build hands the tasks out longest first, so that
#: the processes finish together. Tasks not listed take under 0.15 s.
TASK_SECONDS = {
    "Figure 6": 1.24, "Figure 4": 1.04, "Figure 7": 1.01, "Figure 8": 0.98, "Figure 5": 0.95, "Figure 3": 0.87,
    "Figure 2": 0.69, "Figure 1": 0.61, "check_thm34_ivp": 0.54, "check_thm33_ivp": 0.51,
    "check_trace_at_edges": 0.39, "check_interlacing": 0.33, "check_kapitza_velocity": 0.29,
}


@functools.lru_cache(maxsize=4)
def _cases(quick, seed):
    return C.parameter_sets(quick, seed)


def _figure_task(n, out):
    from . import figures as F  # matplotlib is needed only here

    return F.write_figure(n, out)


def _check_task(i, quick, seed=20170915):
    return C.run_check(i, _cases(quick, seed))


def _pool(workers):
    # fork: the workers start at once with kapitza and matplotlib already imported (spawn would
    # import them again in each).
    from . import figures as _  # noqa: F401

    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else None)
    return ProcessPoolExecutor(max_workers=workers, mp_context=ctx)


def _run_tasks(tasks, workers, say):
    """Results of ``tasks`` (``(label, func, args)``), in order; in ``workers`` processes when > 1.
    ``say`` is told of each task as it finishes."""
    results = [None] * len(tasks)
    total = len(tasks)
    if workers <= 1:
        for k, (label, func, args) in enumerate(tasks):
            say(f"[{k + 1}/{total}] {label}")
            results[k] = func(*args)
        return results
    with _pool(workers) as pool:
        futures = {pool.submit(func, *args): k for k, (_, func, args) in enumerate(tasks)}
        for done, fut in enumerate(as_completed(futures), start=1):
            k = futures[fut]
            results[k] = fut.result()
            say(f"[{done}/{total}] done: {tasks[k][0]}")
    return results


def build_paper(out, quick=False, progress=None, workers=None, figures=tuple(range(1, 9)), checks=None) -> PaperBuild:
    """Write Figures 1-8 (PNG, SVG, JSON, CSV), the checks and the report into ``out``.

    Parameters
    ----------
    out : path-like
        Folder to write into (created if absent).
    quick : bool
        Fewer parameter sets in each check (for a fast look; the full run is the default).
    progress : callable, optional
        Called with a short message as each step starts (one process) or ends (several).
    workers : int, optional
        Processes rendering the figures and running the checks side by side (default: the
        number of CPUs, at most 2); 1 does everything in this process, in order.
    figures : sequence of int, optional
        Which figures to write (default all eight; fewer only for a smoke test).
    checks : sequence of int, optional
        Indices into :data:`kapitza.paper.checks.CHECKS` (default all; fewer only for a smoke test).

    Returns
    -------
    PaperBuild
    """
    say = progress or (lambda msg: None)
    workers = 2 if workers is None else _v.bounded_count("workers", workers, 1024, minimum=1)
    figures = [int(n) for n in figures]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    checks = list(range(len(C.CHECKS))) if checks is None else [int(i) for i in checks]

    def name(i):
        return "check " + C.CHECKS[i][0].__name__.removeprefix("check_")

    tasks = ([(f"Figure {n} (PNG, SVG, JSON, CSV)", _figure_task, (n, out), TASK_SECONDS.get(f"Figure {n}", 0.1))
              for n in figures]
             + [(name(i), _check_task, (i, quick), TASK_SECONDS.get(C.CHECKS[i][0].__name__, 0.1)) for i in checks])
    # Longest first (a stable sort keeps the paper's order among equals): the processes finish together.
    tasks = [t[:3] for t in sorted(tasks, key=lambda t: -t[3])]
    workers = _v.workers(workers, len(tasks))  # no more processes than CPUs or tasks
    say(f"rendering {len(figures)} figures and running {len(checks)} checks"
        + (f" in {workers} processes" if workers > 1 else ""))
    done = dict(zip((t[0] for t in tasks), _run_tasks(tasks, workers, say)))
    files = []
    figs = []
    for n in figures:
        data, paths = done[f"Figure {n} (PNG, SVG, JSON, CSV)"]
        files += paths
        figs.append((n, data, paths))
    results = tuple(done[name(i)] for i in checks)
    passed = bool(results) and all(r.passed for r in results)  # no checks run is not a pass
    files.append(_io.write_json(out / "checks.json", dict(
        paper=PAPER, kapitza=__version__, quick=quick, passed=passed,
        claims={k: dict(title=t, statement=st) for k, (t, st) in C.CLAIMS.items()},
        checks=[r.as_dict() for r in results])))

    say("boundary half-periods table")
    table = C.period_table(TABLE_AMPLITUDES, 4)
    files.append(_io.write_csv(out / "periods.csv", table["header"], table["rows"],
                               comments=["boundary half-periods T_n (2T-periodic) and T~_n (4T-periodic), "
                                         "l = 1 m, g = 9.81 m/s^2 (Corollary 4.1); trace: tr M there"]))

    by_claim = {k: [r for r in results if r.claim == k] for k in C.CLAIMS}
    claim_ok = {k: bool(rs) and all(r.passed for r in rs) for k, rs in by_claim.items()}
    blocks = [
        Heading("Reproduction of the paper", 1),
        Para(f"{PAPER}. Every figure, number and verdict below was computed by kapitza {__version__} "
             f"on {datetime.date.today().isoformat()}"
             + (" (quick run: fewer parameter sets per check)." if quick else ".")),
        Para("**All checks passed.**" if passed else "**Some checks FAILED** — see the table and the sections below."),
        Heading("Summary"),
        Table(("result", "checks", "status"),
              tuple((C.CLAIMS[k][0], len(rs), "PASSED" if claim_ok[k] else "FAILED")
                    for k, rs in by_claim.items() if rs),
              status_column=2),
        Table(("check", "result", "cases", "worst", "bound", "status"),
              tuple((r.key, C.CLAIMS.get(r.claim, (r.claim,))[0].split(" (")[0].split(":")[0], r.cases,
                     _fmt(r.worst), _bound(r), r.status) for r in results), status_column=5),
        Heading("Formulas"),
        Code(FORMULAS),
        Heading("Boundary half-periods T_n, T~_n (l = 1 m, g = 9.81 m/s^2)"),
        Para("Each is a zone edge: `T_{n+1}` carries a 2T-periodic solution (tr M = 2), `T~_{n+1}` a 4T-periodic "
             "one (tr M = −2); within each amplitude the order is Corollary 4.1's "
             "`T_1 < T~_1 < T~_2 < T_2 < T_3 < T~_3 < ...`. The last column is tr M there (factored form); it "
             "deviates from ±2 by about 1e-16 e^{w_h T} because the trace is that steep at an edge rounded to a "
             "double."),
        Table(tuple(table["header"]),
              tuple((f"{row[0]:g}", row[1], f"{row[2]:.12g}", row[3], row[4], row[5], row[6], row[7],
                     f"{row[8]:.10g}", f"{row[9]:.6g}", f"{row[10]:.4g}",
                     f"{row[11]:+.12f}") for row in table["rows"])),
        Heading("The numbered results and their verification"),
    ]
    notes = []
    for k, rs in by_claim.items():
        if not rs:
            continue
        title, statement = C.CLAIMS[k]
        blocks += [Heading(f"{title} — {'PASSED' if claim_ok[k] else 'FAILED'}", 3),
                   Para(f"**Statement.** {statement}")]
        for r in rs:
            blocks += [
                Heading(f"{r.key}: {r.status}", 4),
                Para(f"**Claim checked.** {r.title}"),
                Para(f"**Method.** {r.method}"),
                Para(f"**Reference.** {r.reference}"),
                Para(f"**Result.** {r.cases} cases; worst {r.quantity}: **{_fmt(r.worst)}** (must be {_bound(r)}) "
                     f"— **{r.status}**" + (f"; worst at {r.worst_case}." if r.worst_case else ".")),
            ]
            if r.note:
                blocks.append(Para(f"**Discrepancy with the printed paper.** {r.note}"))
                notes.append((r.key, r.note))
            if r.table:
                blocks.append(Table(tuple(r.table["header"]),
                                    tuple(tuple(str(c) for c in row) for row in r.table["rows"])))
    blocks.append(Heading("Where the computation differs from the printed paper"))
    if notes:
        blocks += [Para(f"**{key}.** {note}") for key, note in notes]
    else:
        blocks.append(Para("No discrepancy was found in the numbered results."))
    blocks.append(Para(FIGURE8_NOTE))
    blocks += nonlinear_section()
    blocks.append(Heading("Figures"))
    for n, data, paths in figs:
        png = next(p for p in paths if p.suffix == ".png")
        blocks += [Heading(f"Figure {n}: {data.title}", 3),
                   Image(png, plain_math(f"Figure {n}. {data.caption}"), tuple(p for p in paths if p.suffix != ".png"))]
    say("report")
    files.append(_io.write_text(out / "report.md", to_markdown(blocks, out)))
    files.append(_io.write_text(out / "report.html",
                                to_html(blocks, out, "kapitza: reproduction of Csizmadia & Hatvani")))
    return PaperBuild(out=out, files=tuple(files), checks=results, passed=passed)
