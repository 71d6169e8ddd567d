"""Fuzz suite: every public function and every command, fed hostile values.

The promises checked for each call (``docs/robustness.md``):

* either a ``ValueError``/``TypeError`` whose message names the parameter given the hostile
  value, or an answer with no NaN in it (``OverflowError`` is allowed only where it is
  documented, for linear motions that leave the range of a double);
* no warning escapes (warnings are errors here);
* every call finishes within a time bound;
* commands exit with 0, 1 or 2, print one line on stderr for status 2 and never a traceback.

Targets are found, not listed: the callables of ``kapitza.__all__`` and of the public
submodules (motion, mathieu, phase_plane, drives), with their signatures introspected, and the
subcommands of ``kapitza.cli.build_parser()`` with their options. A new public function or
command is fuzzed without editing this file; a new *parameter name* must be given a valid
value in ``VALID`` (``test_every_required_parameter_has_a_valid_value`` says which).

The short profile runs in the default suite; the long one is marked slow
(``pytest -m slow tests/test_fuzz.py -s``, or ``KAPITZA_FUZZ_EXAMPLES=N`` to scale it) and
prints a table of the cases and their outcomes.
"""
from __future__ import annotations

import collections
import contextlib
import dataclasses
import inspect
import io
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import kapitza
from kapitza import drives, mathieu, motion, phase_plane
from kapitza.cli import build_parser, main

NAN, INF = float("nan"), float("inf")

# ------------------------------------------------------------------ the targets
#: A valid value for each parameter name (cheap to compute with); optional parameters not
#: listed keep their defaults in the base call.
VALID = {
    "eps": 0.5, "mu": 0.3, "T": 0.15, "A": 100.0, "l": 1.0, "g": 9.81, "n": 1, "m": 1, "count": 3, "index": 1,
    "t": 0.5, "theta0": 0.1, "dtheta0": 0.0, "theta": 0.1, "dtheta": 0.0, "s": 10.0, "phi": 0.3, "d": 2.0,
    "D": 2.0, "phi0": -0.3, "w_h": 2.0, "r0": 1.0, "q": 1.0, "duty": 0.3, "levels": [1.0, -1.0],
    "fractions": [0.5, 0.5], "text": "square", "drives": ["square", "sine"], "drive": None, "zeta": 0.0,
    "damping": 0.0, "c": 0.0, "periods": 2, "every": 1, "points_per_period": 8, "n_theta": 5, "n_dtheta": 5,
    "tol": 0.5, "chunk": 64, "workers": 1, "branch": 0, "tilde": False, "log": False, "model": "nonlinear",
    "method": None, "rtol": 1e-10, "atol": 1e-12, "theta_max": 0.3, "dtheta_max": 2.0, "out": None,
    "progress": None, "r": 0.05, "a": [1.0, -1.0, 0.5, -0.5], "chain": kapitza.Chain([0.2, 0.2]),
}
#: Parameters that take something other than numbers (text, objects, callables).
NON_NUMERIC = {"text", "drive", "drives", "model", "method", "out", "progress", "chain"}
#: Parameters whose values are lists of numbers (a drive's steps).
LISTS = {"levels", "fractions"}
#: stability_grid's eps and mu are the grid's two axes (1-D each).
AXES = {"stability_grid": {"eps": [0.5, 1.0], "mu": [0.3, 0.4]}}
#: Valid values that differ from VALID for one function.
OVERRIDES = {"measured_rotation_number": {"periods": 16}, "from_samples": {"t": [0.0, 1.0, 2.0, 3.0]}}
#: eps-mu pairs that are valid only in the unit interval for these functions.
UNIT_MU = {"phase_angles", "zone_edges", "zone_width", "G_m_curve", "sine_zone_edges", "averaging_threshold",
           "threshold_table"}


def _public_callables():
    seen, out = set(), []
    for mod in (kapitza, motion, mathieu, phase_plane, drives):
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if not callable(obj) or id(obj) in seen:
                continue
            if inspect.isclass(obj) and (issubclass(obj, BaseException) or dataclasses.is_dataclass(obj)
                                         or inspect.isabstract(obj) or obj is drives.Drive):
                continue  # exceptions, result records and the protocol are not called with user input
            try:
                sig = inspect.signature(obj)
            except (TypeError, ValueError):
                continue
            seen.add(id(obj))
            out.append((f"{mod.__name__}.{name}", obj, sig))
    return out


TARGETS = _public_callables()


def _base_kwargs(fname, sig):
    kw = {}
    for p in sig.parameters.values():
        if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        short = fname.rsplit(".", 1)[1]
        if short in AXES and p.name in AXES[short]:
            kw[p.name] = AXES[short][p.name]
        elif p.name in VALID and (p.default is inspect.Parameter.empty or p.name in VALID):
            kw[p.name] = VALID[p.name]
    params = sig.parameters
    if {"T", "A", "eps", "mu"} <= set(params) and params["eps"].default is None:
        kw.pop("eps", None)  # (eps, mu) is the alternative to (T, A): give one pair
        kw.pop("mu", None)
    short = fname.rsplit(".", 1)[1]
    kw.update(OVERRIDES.get(short, {}))
    if short == "analyze":
        kw = {"eps": 0.5, "mu": 0.3}
    return kw


def test_every_required_parameter_has_a_valid_value():
    missing = [(f, p.name) for f, _, sig in TARGETS for p in sig.parameters.values()
               if p.default is inspect.Parameter.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
               and p.name not in VALID]
    assert not missing, f"give these parameters a valid value in VALID: {missing}"


# ------------------------------------------------------------------ hostile values
def _masked():
    return np.ma.masked_array([0.5, 0.6], mask=[False, True])


HOSTILE = [NAN, INF, -INF, -0.0, 0.0, 1e-300, 1e300, 5e-324, -1.0, -1e-300, 10**12, -10**12, 10**400, 2**63,
           True, "1.5", b"1", "", None, 1 + 2j, np.complex128(0.5 + 0j), [0.5, 0.6], [[0.5], [0.6, 0.7]],
           np.array([0.5, 0.6, 0.7]), np.ones((2, 3)), [], np.array([]), object(), np.float32(0.5),
           np.int64(-3), np.uint64(2**63 + 5), "masked", np.datetime64("2020-01-01"), np.timedelta64(3, "s"),
           np.array([1, 2], dtype="m8[ms]")]
TEXT_HOSTILE = ["", "nonsense", "square:1", "rectangular:2", "steps:1,-1:0.5", "steps:1:1", "sine:3", 3.0, None,
                ["square"], b"square", "rectangular:nan"]


def _materialise(v):
    return _masked() if isinstance(v, str) and v == "masked" else v


@st.composite
def hostile_value(draw, name):
    if name in NON_NUMERIC:
        return draw(st.sampled_from(TEXT_HOSTILE + [NAN, [1, 2]]))
    kind = draw(st.integers(0, 9))
    if kind <= 5:
        v = draw(st.sampled_from(HOSTILE))
    elif kind == 6:
        v = draw(st.floats(allow_nan=True, allow_infinity=True))
    elif kind == 7:
        v = draw(st.integers(-10**20, 10**20))
    elif kind == 8:
        v = draw(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=0, max_size=4))
    else:
        v = draw(st.floats(min_value=-1e6, max_value=1e6))
    if name in LISTS and draw(st.booleans()):
        v = [v, -v] if isinstance(v, float) else [v]
    return _materialise(v)


# ------------------------------------------------------------------ checking one call
class CallTimeout(BaseException):
    """A call ran past its time bound (a BaseException: no ``except Exception`` swallows it)."""


@contextlib.contextmanager
def time_limit(seconds):
    def _alarm(signum, frame):
        raise CallTimeout(f"no answer within {seconds} s")

    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _nan_in(obj, depth=0):
    """Where a NaN hides in a result (``None`` if nowhere)."""
    if depth > 6:
        return None
    if isinstance(obj, (float, np.floating)):
        return "nan" if math.isnan(obj) else None
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fc" and np.isnan(obj).any():
            return f"nan in an array of shape {obj.shape}"
        return None
    if isinstance(obj, dict):
        obj = list(obj.values())
    if isinstance(obj, (list, tuple)):
        for v in obj[:1000]:
            r = _nan_in(v, depth + 1)
            if r:
                return r
        return None
    if dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            r = _nan_in(getattr(obj, f.name), depth + 1)
            if r:
                return f"{f.name}: {r}"
    return None


#: NaN that a result documents, as an answer meaning "none": function -> fields ('*': anywhere).
DOCUMENTED_NAN = {
    # no zone to measure against where mu >= 1 or u > 2^52 (StabilityMargin's docstring)
    "kapitza.stability_margin": {"eps_lo", "eps_hi"},
    "kapitza.analyze": {"eps_lo", "eps_hi", "T_lo", "T_hi", "A_lo", "A_hi", "frequency_lo", "frequency_hi",
                        "stroke_lo", "stroke_hi"},
    # edges of a zone another drive (or damping) does not have at these parameters
    "kapitza.zone_edges": {"*"}, "kapitza.period_edges": {"*"}, "kapitza.amplitude_edges": {"*"},
    "kapitza.mathieu.sine_zone_edges": {"*"},
    # no rotation, twist or 1:4 coefficient outside the zones: "linearly unstable" (NonlinearVerdict's docstring)
    "kapitza.nonlinear_stability": {"rotation_number", "twist", "resonant_4"},
    # no zone 0 when damping has closed it (threshold_table's docstring)
    "kapitza.threshold_table": {"eps_exact", "relative_error"},
}


def _documented(fname, where):
    fields = DOCUMENTED_NAN.get(fname, set())
    return "*" in fields or where.split(":")[0] in fields
#: Bound per call [s] (the machine may be loaded: generous, but it catches hangs).
CALL_SECONDS = float(os.environ.get("KAPITZA_FUZZ_CALL_SECONDS", "120"))

OUTCOMES = collections.Counter()
FAILURES = []


#: Names a message may use for a parameter (the drive's text is "the drive", with its duty or steps).
ALIASES = {"text": ["drive", "duty", "levels", "fractions"], "drives": ["drive", "duty", "levels", "fractions"],
           "drive": ["duty", "levels", "fractions"], "c": ["damping"], "damping": ["zeta"]}


def _names_a_parameter(message, names):
    names = list(names) + [a for n in names for a in ALIASES.get(n, [])]
    return any(re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", message) for n in names)


def check_call(fname, fn, kwargs, changed):
    """Call once under the promises; return the outcome (a failure raises AssertionError)."""
    t0 = time.monotonic()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with time_limit(CALL_SECONDS):
                result = fn(**kwargs)
    except CallTimeout as exc:
        outcome = f"FAIL hang ({exc})"
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        if _names_a_parameter(msg, changed):
            outcome = "refused, naming the parameter"
        else:
            outcome = f"FAIL {type(exc).__name__} naming no parameter of {changed}: {msg[:200]}"
    except OverflowError as exc:
        outcome = ("overflow beyond a double (documented)" if "double" in str(exc)
                   else f"FAIL OverflowError: {exc}")
    except Warning as exc:
        outcome = f"FAIL warning escaped: {type(exc).__name__}: {exc}"
    except Exception as exc:  # noqa: BLE001 - every other exception is a break of the promise
        outcome = f"FAIL {type(exc).__name__}: {str(exc)[:200]}"
    else:
        where = _nan_in(result)
        if where and not _documented(fname, where):
            outcome = f"FAIL silent NaN ({where})"
        else:
            outcome = "answer, no NaN"
    OUTCOMES[(fname, outcome.split(":")[0] if outcome.startswith("FAIL") else outcome)] += 1
    OUTCOMES[("seconds", fname)] += time.monotonic() - t0
    if outcome.startswith("FAIL"):
        FAILURES.append((fname, {k: _short(v) for k, v in kwargs.items()}, outcome))
        raise AssertionError(f"{fname}({_call_text(kwargs)}): {outcome}")
    return outcome


def _short(v):
    r = repr(v)
    return r if len(r) < 60 else r[:57] + "..."


def _call_text(kwargs):
    return ", ".join(f"{k}={_short(v)}" for k, v in kwargs.items())


@st.composite
def api_case(draw):
    fname, fn, sig = draw(st.sampled_from(TARGETS))
    kwargs = _base_kwargs(fname, sig)
    if fname.rsplit(".", 1)[1] in UNIT_MU and "mu" in kwargs:
        kwargs["mu"] = 0.3
    names = [n for n in kwargs if n not in ("progress",)] or list(kwargs)
    if not names:
        return fname, fn, kwargs, []
    name = draw(st.sampled_from(names))
    kwargs[name] = draw(hostile_value(name))
    changed = [name]
    # sometimes a second numeric parameter as a 2-vector: mismatched or broadcasting shapes
    numeric = [n for n in names if n != name and n not in NON_NUMERIC and n not in LISTS]
    if numeric and draw(st.integers(0, 4)) == 0:
        other = draw(st.sampled_from(numeric))
        kwargs[other] = [kwargs[other], kwargs[other]] if not isinstance(kwargs[other], list) else kwargs[other]
        changed.append(other)
    return fname, fn, kwargs, changed


def _api_property(case):
    fname, fn, kwargs, changed = case
    check_call(fname, fn, kwargs, changed)


def _examples(short):
    n = os.environ.get("KAPITZA_FUZZ_EXAMPLES")
    return int(n) if n and not short else short


_FUZZ = dict(deadline=None, derandomize=False, database=None,
             suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])


@settings(max_examples=120, **_FUZZ)
@given(api_case())
def test_api_under_hostile_input_short(case):
    _api_property(case)


@pytest.mark.slow
@settings(max_examples=_examples(6000), **_FUZZ)
@given(api_case())
def test_api_under_hostile_input_long(case):
    _api_property(case)


def test_every_target_is_reached_with_its_valid_call():
    """The base call of every target answers (so a refused hostile value is the value's doing)."""
    for fname, fn, sig in TARGETS:
        kwargs = _base_kwargs(fname, sig)
        if fname.rsplit(".", 1)[1] in UNIT_MU and "mu" in kwargs:
            kwargs["mu"] = 0.3
        assert check_call(fname, fn, kwargs, list(kwargs)) == "answer, no NaN", fname


# ------------------------------------------------------------------ answers against references
@settings(max_examples=60, deadline=None)
@given(st.floats(0.05, 3.0), st.floats(0.02, 0.98))
def test_verdicts_match_the_trace_formula(eps, mu):
    """Away from edges, ``is_stable`` is ``|tr M| < 2`` with tr M from the two phase matrices
    (``docs/theory.md`` section 3), growth is ``log`` of the larger multiplier, and scalar
    input gives numpy scalars."""
    T, A = kapitza.to_physical(eps, mu)
    w_h, w_e = math.sqrt(A + 9.81), math.sqrt(A - 9.81)
    ch, sh, c, s = math.cosh(w_h * T), math.sinh(w_h * T), math.cos(w_e * T), math.sin(w_e * T)
    trace = 2.0 * ch * c + (w_h / w_e - w_e / w_h) * sh * s
    if abs(abs(trace) - 2.0) < 1e-6:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        stable = kapitza.is_stable(eps, mu)
        growth = kapitza.growth_rate(eps, mu)
        zone = kapitza.zone_index(eps, mu)
    assert bool(stable) == (abs(trace) < 2.0)
    assert (zone >= 0) == bool(stable)
    # the larger multiplier's modulus: 1 on the unit circle, else |tr|/2 + sqrt(tr^2/4 - 1)
    big = 1.0 if abs(trace) < 2.0 else abs(trace) / 2.0 + math.sqrt(trace * trace / 4.0 - 1.0)
    assert growth == pytest.approx(math.log(big), rel=1e-7, abs=1e-9)
    for v in (stable, growth, zone):
        assert isinstance(v, np.generic), type(v)


def _scalar_kinds(obj):
    if isinstance(obj, tuple):
        return [k for v in obj for k in _scalar_kinds(v)]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return [k for f in dataclasses.fields(obj) for k in _scalar_kinds(getattr(obj, f.name))]
    return ["0-d array" if isinstance(obj, np.ndarray) and obj.ndim == 0 else
            "numpy scalar" if isinstance(obj, np.generic) else
            "array" if isinstance(obj, np.ndarray) else type(obj).__name__]


def test_scalar_input_gives_numpy_scalars_everywhere():
    """One type for one kind of answer (README, "Results"): a function given single numbers
    returns numpy scalars (``np.float64``, ``np.int64``, ``np.bool_``), never 0-d arrays."""
    bad = []
    for fname, fn, sig in TARGETS:
        kwargs = _base_kwargs(fname, sig)
        if fname.rsplit(".", 1)[1] in UNIT_MU and "mu" in kwargs:
            kwargs["mu"] = 0.3
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            res = fn(**kwargs)
        if "0-d array" in _scalar_kinds(res):
            bad.append((fname, _scalar_kinds(res)))
    assert not bad, bad


# ------------------------------------------------------------------ the command line
#: A cheap valid command line for each command (a new command starts from no options).
BASE_ARGV = {
    "stability": ["--T", "0.15", "--A", "100"],
    "periods": ["--A", "100", "--count", "2"],
    "zones": ["--zones", "2", "--points", "5"],
    "chart": ["--points", "40", "--no-magnify", "--out", "c"],
    "compare": ["--points", "20", "--out", "cmp"],
    "simulate": ["--T", "0.15", "--A", "100", "--periods", "1", "--points-per-period", "8", "--orbits", "2",
                 "--strobe-periods", "2"],
    "animate": ["--T", "0.15", "--A", "100", "--periods", "0.1", "--dpi", "30", "--quiet", "--out", "a.gif"],
    "basin": ["--T", "0.15", "--A", "100", "--resolution", "4", "--periods", "2", "--quiet", "--out", "b"],
    "paper": ["--quick", "--quiet", "--out", "p"],
    "tower": ["--chain", "0.2,0.2", "--grid", "12", "--points", "30", "--out", "t"],
}
#: Commands whose base run takes minutes (or starts a Dask cluster): fuzzed in the long profile only.
SLOW_COMMANDS = {"paper", "sweep"}
#: Commands that run until stopped: ``serve``'s inputs are fuzzed through its HTTP API instead
#: (tests/test_web_fuzz.py) and its options tested in tests/test_web_api.py.
SERVERS = {"serve"}
CLI_HOSTILE = ["nan", "inf", "-inf", "-0.0", "0", "-1", "1e-300", "1e300", "5e-324", "1000000000000", "1" + "0" * 400,
               "abc", "", "1,2", "0x10", "1e9", "2.5", "-1e308", "/dev/full", "/proc/x/y.csv", "square:", "steps:1:1"]


def _commands():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    out = {}
    for name, p in sub.choices.items():
        opts = [a for a in p._actions if a.option_strings and not set(a.option_strings) & {"-h", "--help"}]
        out[name] = opts
    return out


COMMANDS = _commands()


@st.composite
def cli_case(draw, slow=False):
    names = sorted(n for n in COMMANDS if (slow or n not in SLOW_COMMANDS) and n not in SERVERS)
    cmd = draw(st.sampled_from(names))
    argv = [cmd] + list(BASE_ARGV.get(cmd, []))
    opts = COMMANDS[cmd]
    for _ in range(draw(st.integers(1, 2))):
        if not opts:
            break
        a = draw(st.sampled_from(opts))
        flag = a.option_strings[-1]
        if a.nargs == 0:
            argv.append(flag)
            continue
        if a.choices and draw(st.booleans()):
            value = str(draw(st.sampled_from(list(a.choices))))
        else:
            value = draw(st.one_of(st.sampled_from(CLI_HOSTILE), st.floats().map(repr),
                                   st.integers(-10**15, 10**15).map(str)))
        if flag in argv:
            i = argv.index(flag)
            argv[i + 1] = value
        else:
            argv += [flag, value]
    return argv


def check_cli(argv):
    """Run ``kapitza argv`` in this process under -W error semantics; check the exit contract."""
    out, err = io.StringIO(), io.StringIO()
    with tempfile.TemporaryDirectory() as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), time_limit(CALL_SECONDS * 2):
                    try:
                        code = main(argv)
                    except SystemExit as exc:
                        code = exc.code
        except CallTimeout as exc:
            code, err = "hang", io.StringIO(str(exc))
        except BaseException as exc:  # noqa: BLE001
            code = f"{type(exc).__name__}: {str(exc)[:200]}"
        finally:
            os.chdir(cwd)
    return _judge_cli("kapitza " + " ".join(argv), code, err.getvalue())


def _judge_cli(label, code, err):
    lines = [ln for ln in err.replace("\r", "\n").splitlines() if ln.strip()]
    if code not in (0, 1, 2):
        outcome = f"FAIL exit {code}"
    elif "Traceback" in err:
        outcome = "FAIL traceback"
    elif code == 2 and len(lines) != 1:
        outcome = f"FAIL {len(lines)} lines on stderr with status 2"
    elif code != 2 and any("Warning" in ln for ln in lines):
        outcome = "FAIL warning on stderr"
    else:
        outcome = {0: "exit 0", 1: "exit 1 (--check: unstable)", 2: "exit 2, one line"}[code]
    OUTCOMES[("kapitza " + label.split()[1], outcome)] += 1
    if outcome.startswith("FAIL"):
        FAILURES.append((label, {}, outcome + ": " + err[-300:]))
        raise AssertionError(f"{label}: {outcome}\n{err[-2000:]}")
    return outcome


@settings(max_examples=40, **_FUZZ)
@given(cli_case())
def test_cli_under_hostile_options_short(argv):
    check_cli(argv)


@pytest.mark.slow
@settings(max_examples=_examples(150), **_FUZZ)
@given(cli_case(slow=True))
def test_cli_under_hostile_options_long(argv):
    check_cli(argv)


def _subprocess_cli(argv, timeout=300):
    env = dict(os.environ)
    env.pop("KAPITZA_ALLOW_LARGE", None)
    with tempfile.TemporaryDirectory() as tmp:
        try:
            p = subprocess.run([sys.executable, "-W", "error", "-m", "kapitza", *argv], capture_output=True, text=True,
                               timeout=timeout, cwd=tmp, env=env)
        except subprocess.TimeoutExpired:
            return _judge_cli("kapitza " + " ".join(argv), "hang", "")
    return _judge_cli("kapitza " + " ".join(argv), p.returncode, p.stderr)


@pytest.mark.parametrize("argv", [
    ["stability", "--T", "nan", "--A", "100"],
    ["simulate", "--T", "0.15", "--A", "100", "--periods", "1", "--dtheta0", "1e300"],
    ["basin", "--T", "0.15", "--A", "100", "--resolution", "4", "--periods", "2", "--workers", "40", "--quiet"],
])
def test_cli_as_a_process_under_w_error(argv):
    """The real entry point, ``python -W error -m kapitza``, on a few hostile lines."""
    _subprocess_cli(argv)


@pytest.mark.slow
@settings(max_examples=_examples(30), **_FUZZ)
@given(cli_case(slow=True))
def test_cli_as_a_process_long(argv):
    _subprocess_cli(argv)


# ------------------------------------------------------------------ the summary table
@pytest.fixture(scope="module", autouse=True)
def _summary(request):
    yield
    calls = collections.Counter()
    table = collections.defaultdict(collections.Counter)
    for (target, outcome), n in OUTCOMES.items():
        if target == "seconds":
            continue
        table[target][outcome] += n
        calls[outcome] += n
    if not calls:
        return
    capman = request.config.pluginmanager.getplugin("capturemanager")
    with capman.global_and_fixture_disabled() if capman else contextlib.nullcontext():
        _print_summary(calls, table)


def _print_summary(calls, table, write=print):
    write("")
    write(f"fuzz summary: {sum(calls.values())} cases over {len(table)} targets")
    for outcome, n in calls.most_common():
        write(f"  {n:7d}  {outcome}")
    write(f"  {'target':44s} {'cases':>6s}  outcomes")
    for target in sorted(table):
        c = table[target]
        write(f"  {target:44s} {sum(c.values()):6d}  " + "; ".join(f"{o} {k}" for o, k in c.most_common()))
    for f in FAILURES[:20]:
        write(f"  FAILED {f[0]} {f[1]} {f[2][:300]}")


@pytest.mark.parametrize("value", [np.datetime64("2020-01-01"), np.timedelta64(3, "s")], ids=["datetime64", "timedelta64"])
def test_dates_and_durations_are_refused_by_every_target(value):
    """A date or a duration is never read as a count of its unit, by any public function."""
    refused = []
    for fname, fn, sig in TARGETS:
        kwargs = _base_kwargs(fname, sig)
        if fname.rsplit(".", 1)[1] in UNIT_MU and "mu" in kwargs:
            kwargs["mu"] = 0.3
        for name in [n for n in kwargs if n not in NON_NUMERIC and n != "progress"]:
            if check_call(fname, fn, {**kwargs, name: NAN}, [name]) != "refused, naming the parameter":
                continue  # a parameter this call does not read (periods beside t, rtol of the exact flows)
            outcome = check_call(fname, fn, {**kwargs, name: value}, [name])
            assert outcome == "refused, naming the parameter", (fname, name, outcome)
            refused.append((fname, name))
    assert len(refused) > 50


# ------------------------------------------------------------------ every drive, damped and not
#: Parameters of the registered drives that take some (the others are built with no arguments).
DRIVE_EXAMPLES = {"rectangular": "rectangular:0.3", "steps": "steps:2,-1,1,-1:0.2,0.3,0.2,0.3"}


def _registered_drives():
    out = []
    for name, cls in drives.DRIVES.items():
        try:
            out.append(cls())
        except TypeError:
            out.append(drives.parse_drive(DRIVE_EXAMPLES[name]))
    return out


@pytest.mark.parametrize("drive", _registered_drives(), ids=lambda d: d.name)
@pytest.mark.parametrize("damped", [False, True], ids=["undamped", "damped"])
def test_scalar_input_gives_numpy_scalars_with_every_drive(drive, damped):
    """The stability functions with every registered drive, with and without damping: numpy
    scalars for scalar input (never 0-d arrays, never Python floats), arrays for array input."""
    z = dict(zeta=0.05) if damped else {}
    c = dict(damping=0.1) if damped else {}
    calls = {
        "is_stable": lambda e, m: kapitza.is_stable(e, m, drive, **z),
        "zone_index": lambda e, m: kapitza.zone_index(e, m, drive, **z),
        "growth_rate": lambda e, m: kapitza.growth_rate(e, m, drive, **z),
        "rotation_number": lambda e, m: kapitza.rotation_number(e, m, drive, **z),
        "floquet": lambda e, m: kapitza.floquet(e, m, drive, **z),
        "stability_margin": lambda e, m: kapitza.stability_margin(e, m, drive, **z),
        "zone_edges": lambda e, m: kapitza.zone_edges(m, 0, drive, **z),
    }
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name, fn in calls.items():
            one = fn(0.5, 0.3)
            assert "0-d array" not in _scalar_kinds(one), (name, _scalar_kinds(one))
            assert all(k in ("numpy scalar", "array", "NoneType") for k in _scalar_kinds(one)), (name, _scalar_kinds(one))
            many = fn(np.array([0.5, 0.6]), np.array([0.3, 0.3]))
            assert "array" in _scalar_kinds(many) and "0-d array" not in _scalar_kinds(many), (name, _scalar_kinds(many))
        lo, hi = kapitza.period_edges(100.0, 0, 1.0, 9.81, drive, **c)
        assert isinstance(lo, np.float64) and isinstance(hi, np.float64), type(lo)
        lo, hi = kapitza.amplitude_edges(0.15, 0, 1.0, 9.81, drive, **c)
        assert isinstance(lo, np.float64) and isinstance(hi, np.float64)
        T, A = drive.from_rig(50.0, amplitude=0.003)
        assert isinstance(T, np.float64) and isinstance(A, np.float64)
        rep = kapitza.analyze(T=0.15, A=100.0, drive=drive, **c)
        assert isinstance(rep.growth, float) and rep.drive == drive.describe()
