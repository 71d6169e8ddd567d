"""Phase maps of both models, with the data the survival test needs.

Twins: :func:`_linear_step` (the linear phase flows of ``docs/theory.md`` section 3,
from :mod:`kapitza.propagation`) and :func:`kapitza.motion._elliptic._phase_step`
(the full equation) share one signature ``(theta, dtheta, s, t) -> (theta, dtheta)``;
the tests run one against the other at small amplitude.
"""
from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor

import numpy as np

from .. import _validate as _v
from .._square import _apply, _flow
from ._elliptic import _phase_step


def _linear_step(theta, dtheta, s, t):
    """Exact flow of ``theta'' = s theta`` over the time ``t``."""
    with np.errstate(over="ignore", invalid="ignore"):
        c, sd, ds = _flow(np.asarray(s, float), np.asarray(t, float))
        return _apply(c, sd, ds, theta, dtheta)


def _linear_amplitude(theta, dtheta, w):
    """Largest ``|theta|`` of the linear oscillation ``theta'' = -w^2 theta`` through this state."""
    return np.hypot(theta, dtheta / w)


def _nonlinear_amplitude(theta, dtheta, w):
    """Largest ``|theta|`` of the libration of ``theta'' = -w^2 sin(theta)`` through this state
    (``pi`` for a rotation): ``2 asin k`` with ``k^2 = sin^2(theta/2) + (theta'/(2w))^2``."""
    k = np.hypot(np.sin(0.5 * theta), dtheta / (2.0 * w))
    return 2.0 * np.arcsin(np.minimum(k, 1.0))


STEPS = {"nonlinear": _phase_step, "linear": _linear_step}
AMPLITUDES = {"nonlinear": _nonlinear_amplitude, "linear": _linear_amplitude}


def step_plan(drive, T, A, l, g):
    """``((s, duration), ...)`` of one period of a piecewise-constant drive, ``s = (g + a)/l`` of each
    step (``T``, ``A``, ``l``, ``g`` scalars or arrays, broadcast), from the drive's
    :meth:`~kapitza.Drive._steps`; None for a drive without steps (its motion is integrated)."""
    steps = drive._steps()
    if steps is None:
        return None
    return tuple(((g + A * lev) / l, 2.0 * f * T) for lev, f in zip(*steps))


#: Member-periods one call may map (``KAPITZA_ALLOW_LARGE=1`` lifts it): about a minute.
MAX_MEMBER_PERIODS = 100_000_000
#: The cost of one period's Python step, in member units (measured: 0.35 ms against 1 us per member).
STEP_COST = 1000


def bound_ensemble(periods, members, name="periods * (members + 1000)"):
    """Refuse ensembles whose work, ``periods * (members + STEP_COST)`` phase maps, is not bounded."""
    _v.bounded_work(name, float(periods) * (float(members) + STEP_COST), MAX_MEMBER_PERIODS,
                    what="member-periods mapped, about a minute of work")


def chunk_results(fn, bounds, args, workers=1, progress=None):
    """``(a, b, fn(*args(a, b)))`` for each ``(a, b)`` in ``bounds``, in order: in this process,
    or spread over :func:`kapitza._validate.workers` processes. ``progress(done, total)`` after each."""
    total = len(bounds)
    workers = _v.workers(workers, total)
    if workers > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(fn, *args(a, b)) for a, b in bounds]
            for i, ((a, b), f) in enumerate(zip(bounds, futures)):
                yield a, b, f.result()
                if progress is not None:
                    progress(i + 1, total)
    else:
        for i, (a, b) in enumerate(bounds):
            yield a, b, fn(*args(a, b))
            if progress is not None:
                progress(i + 1, total)
