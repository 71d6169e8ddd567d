"""One period of ``phi'' = 8 eps^2 (mu^2 + s(tau)) phi`` by a sixth-order Magnus product, with
the Pruefer rotation angle.

**The step.** With ``A(tau) = [[0, 1], [k(tau), 0]]``, ``k = 8 eps^2 (mu^2 + s)``, one step of
length ``h`` is ``exp(Omega)`` with the sixth-order Magnus generator on the three
Gauss-Legendre nodes ``c = 1/2 -+ sqrt(15)/10, 1/2`` (Blanes, Casas, Oteo and Ros, Phys. Rep.
470 (2009), eq. (253))::

    a1 = h A_2,   a2 = (sqrt(15) h / 3) (A_3 - A_1),   a3 = (10 h / 3) (A_3 - 2 A_2 + A_1),
    C1 = [a1, a2],   C2 = -[a1, 2 a3 + C1] / 60,
    Omega = a1 + a3 / 12 + [-20 a1 - a3 + C1, a2 + C2] / 240.

``Omega`` is traceless, ``Omega = [[p, q], [r, -p]]``, so ``exp(Omega) = cosh(w) I +
sinh(w)/w Omega`` with ``w^2 = p^2 + q r`` (``cos``/``sin`` when ``w^2 < 0``): ``det = 1`` to
rounding in every step. Where ``k`` is constant on a step the generator is ``h A`` exactly and
the step is the exact flow; where ``k`` is linear (piecewise-linear shapes) the local error is
``O(h^7)``. The grid is aligned with the shape's breakpoints (jumps, kinks), so no step straddles
one.

**The product without overflow.** A hyperbolic step is kept as ``e^w N`` with ``N`` bounded;
the ``N`` steps are multiplied pairwise in a balanced tree (``log2 N`` levels of numpy
operations over all steps and points at once), each product renormalised by a power of two and
its logarithmic scale ``L`` carried apart, so ``tr M = e^L tr N`` is finite for every input.

**The rotation angle.** The Pruefer angle ``psi = arg(phi, -phi')`` of the solution starting at
``(1, 0)`` is carried through the same tree. Over one step (phase below ``pi``) its turn is the
principal value of the change of angle. Composing ``R`` after ``L``: the map of directions is
an increasing lift ``F(psi) = psi + T_R(psi)`` with ``F(psi + pi) = F(psi) + pi``, so for
``psi in [0, pi)`` the turn lies in ``(T_R(0) - psi, T_R(0) - psi + pi)``, an interval shorter
than ``2 pi``: the principal value of the change of angle of ``R u(psi)`` fixes it. The turn of
``R L`` is ``T_L(0) + T_R(T_L(0) mod pi)``.

On a zone ``tr M / 2 = cos(theta)`` and the sign of ``M_12`` is that of ``sin(theta)``; the
carried angle of any direction lies within ``pi`` of the rotation angle ``theta``, which fixes
its whole turns. Off the zones ``theta = k pi`` (the turn of an eigenvector); the carried angle
of ``(1, 0)`` lies within ``pi`` of it and ``(-1)^k`` is the sign of ``tr M``, which fixes ``k``.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from .. import _validate as _v
from .._exact import gap_of_turn

PI = np.pi
LOG2 = np.log(2.0)
SQRT15 = np.sqrt(15.0)
#: Gauss-Legendre nodes on [0, 1] of the sixth-order step
NODES = np.array([0.5 - SQRT15 / 10.0, 0.5, 0.5 + SQRT15 / 10.0])
#: largest number of (point, step) pairs held in memory at once
CHUNK = 1 << 19
_COMPILED: Any = None  # the compiled module once looked up (False: numba not installed)
_TREE_WORK = 0  # point-steps asked of the engine before it was looked up (Engine.COMPILED_FROM)


#: the bytes of a :class:`Grid` a step (fifteen doubles: h, x, the shape at three nodes, ten coefficients)
_GRID_STEP_BYTES = 120
#: the steps of a :class:`Grid` formed at once
_GRID_BLOCK = 1 << 16


class Grid:
    """Steps over one period ``[0, 2]`` aligned with ``breaks``; the shape at their nodes.

    ``n`` is a power of two; the steps beyond the ``m`` real ones have length 0 (identity).
    """

    def __init__(self, shape, breaks, n):
        edges = np.unique(np.concatenate([[0.0, 2.0], np.asarray(breaks, float)]))
        lengths = np.diff(edges)
        m_seg = lengths.size
        if n < m_seg:
            raise ValueError("fewer steps than segments")
        # steps per segment proportional to its length, at least one each
        per = np.maximum(np.floor(lengths / 2.0 * n).astype(np.int64), 1)
        while per.sum() > n:
            per[np.argmax(per)] -= 1
        left = []
        width = []
        for a, L, k in zip(edges[:-1], lengths, per):
            left.append(a + L * np.arange(k) / k)
            width.append(np.full(k, L / k))
        left = np.concatenate(left)
        width = np.concatenate(width)
        pad = n - left.size
        self.m = left.size
        self.n = n
        self.h = np.concatenate([width, np.zeros(pad)])
        x = np.concatenate([left, np.zeros(pad)])
        self.x = x
        # Omega in closed form (module notes, with A = [[0, 1], [k, 0]]): with k2 = k(node 2),
        # g2 = (sqrt(15) h/3)(k3 - k1), g3 = (10 h/3)(k3 - 2 k2 + k1) and [X, Y] expanded,
        #   p = (-20 h g2 + 4/3 h^3 k2 g2 + h^2 g2 g3 / 30) / 240
        #   q = h + (h^3 g2^2 / 15 - 4/3 h^2 g3) / 240
        #   r = h k2 + g3 / 12 + (h g3 (20 h k2 + g3) / 15 - 2 h g2^2 (1 - h^2 k2 / 30)) / 240
        # k = E (mu^2 + s), E = 8 eps^2: each a polynomial in E and mu^2 with fixed coefficients.
        # (formed a block of steps at a time: a grid of millions of steps holds few temporaries)
        s = np.zeros((n, 3))
        self.s_nodes = s[: self.m]
        self.s2 = s[:, 1]
        for name in ("p1", "p2", "p2m", "q1", "q2", "r1", "r2", "r2m", "r3", "r3m"):
            setattr(self, name, np.empty(n))
        top = np.nextafter(2.0, 0.0)
        for b0 in range(0, n, _GRID_BLOCK):
            b = slice(b0, min(b0 + _GRID_BLOCK, n))
            h = self.h[b]
            real = min(b.stop, self.m) - b0
            if real > 0:
                nodes = x[b0:b0 + real, None] + h[:real, None] * NODES[None, :]
                s[b0:b0 + real] = np.asarray(shape(np.clip(nodes, 0.0, top)), float)
            sb = s[b]
            s2 = sb[:, 1]
            d2 = SQRT15 / 3.0 * h * (sb[:, 2] - sb[:, 0])       # g2 / E
            d3 = 10.0 / 3.0 * h * (sb[:, 2] - 2.0 * sb[:, 1] + sb[:, 0])  # g3 / E
            self.p1[b] = -20.0 * h * d2 / 240.0                         # p = E p1 + E^2 (p2 + m2 p2m)
            self.p2[b] = (4.0 / 3.0 * h**3 * s2 * d2 + h * h * d2 * d3 / 30.0) / 240.0
            self.p2m[b] = 4.0 / 3.0 * h**3 * d2 / 240.0
            self.q1[b] = -4.0 / 3.0 * h * h * d3 / 240.0               # q = h + E q1 + E^2 q2
            self.q2[b] = h**3 * d2 * d2 / 15.0 / 240.0
            # r = E (h (m2 + s2) + d3/12) + E^2 (r2 + m2 r2m) + E^3 (r3 + m2 r3m)
            self.r1[b] = h * s2 + d3 / 12.0
            self.r2[b] = (h * d3 * (20.0 * h * s2 + d3) / 15.0 - 2.0 * h * d2 * d2) / 240.0
            self.r2m[b] = (h * d3 * 20.0 * h / 15.0) / 240.0
            self.r3[b] = (2.0 * h * d2 * d2 * h * h * s2 / 30.0) / 240.0
            self.r3m[b] = (2.0 * h * d2 * d2 * h * h / 30.0) / 240.0


def load_compiled() -> bool:
    """Load the compiled period (:mod:`._compiled`, numba: its import and its cached code, 0.7-1.2 s),
    the compiled double-double tier of the certified verdicts of linear pieces (:mod:`._taylor_dd`)
    and the sine drive's compiled kernels (:mod:`._sine`) now, so that every later call of the
    engine runs them; until then the engine runs its numpy tree for the first
    :attr:`Engine.COMPILED_FROM` point-steps a process asks (a command of one report does not pay
    numba's start-up). Returns whether it is there (numba installed). The two give the same
    verdicts, zones and edges; traces and growths may differ in their last bits (the products are
    rounded in another order)."""
    global _COMPILED
    if _COMPILED is None:
        from . import _compiled

        if _compiled.available():
            from . import _sine, _taylor_dd

            _compiled.warm()
            _taylor_dd.warm()
            _sine.warm()
            _COMPILED = _compiled
        else:
            _COMPILED = False
    return bool(_COMPILED)


def compiled_pieces_tier():
    """:func:`kapitza.engines._taylor_dd.pieces_dd`, the compiled double-double tier of the certified
    verdicts of linear pieces, once the compiled engine is loaded (:func:`load_compiled`); else None
    (the long double and mpmath tiers decide alone)."""
    if not _COMPILED:
        return None
    from ._taylor_dd import pieces_dd

    return pieces_dd


def compiled_loop():
    """:mod:`kapitza.engines._compiled`, the compiled period (and the one-point searches' rows on it),
    once loaded (:func:`load_compiled`, or a process's first :attr:`Engine.COMPILED_FROM` point-steps);
    else None."""
    return _COMPILED or None


def compiled_sine():
    """:mod:`kapitza.engines._sine`, the sine drive's compiled kernels (Hill's continuant, the Taylor
    steps of the half period), once the compiled engine is loaded (:func:`load_compiled`); else None
    (their numpy forms run)."""
    if not _COMPILED:
        return None
    from . import _sine

    return _sine


def _polish(shape, x, h, sign):
    """``min sign * s`` near ``x``: the best of 17 samples on ``[x - h, x + h]`` (within the period),
    then of 17 on the two sample spacings around the best, and so on (eightfold narrower a round)
    until the spacing is below 1e-12. (A bounded search of our own: ``scipy.optimize`` alone costs
    a command 0.25-0.45 s to import.)"""
    lo, hi = max(x - h, 0.0), min(x + h, float(np.nextafter(2.0, 0.0)))
    best = np.inf
    while True:
        t = np.linspace(lo, hi, 17)
        v = sign * np.asarray(shape(t), float)
        v = np.where(np.isfinite(v), v, np.inf)
        i = int(np.argmin(v))
        best = min(best, float(v[i]))
        step = (hi - lo) / 16.0
        if not step > 1e-12:
            break
        lo, hi = max(float(t[i]) - step, lo), min(float(t[i]) + step, hi)
    return sign * best if np.isfinite(best) else np.inf


def _comm(X, Y):
    """``[X, Y]`` of traceless 2x2 matrices given as ``(p, q, r)`` = ``[[p, q], [r, -p]]``."""
    p1, q1, r1 = X
    p2, q2, r2 = Y
    return q1 * r2 - q2 * r1, 2.0 * (p1 * q2 - q1 * p2), 2.0 * (r1 * p2 - p1 * r2)


def _steps(grid, E, m2):
    """Entries ``(a, b, c, d)`` of each step (scaled by ``e^{-w}`` where hyperbolic) and the log
    scales; ``E = 8 eps^2``, ``m2 = mu^2``, columns ``(P, 1)``."""
    G = grid
    p = E * (G.p1 + E * (G.p2 + m2 * G.p2m))
    q = G.h + E * (G.q1 + E * G.q2)
    r = E * (G.h * m2 + G.r1 + E * ((G.r2 + m2 * G.r2m) + E * (G.r3 + m2 * G.r3m)))
    w2 = p * p + q * r
    w = np.sqrt(np.abs(w2))
    hyp = w2 > 0
    big = hyp & (w > 0.5)
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        e2 = np.exp(-2.0 * np.where(big, w, 0.0))
        ch = np.where(big, 0.5 * (1.0 + e2), np.where(hyp, np.cosh(w), np.cos(w)))
        shw = np.where(big, -0.5 * np.expm1(-2.0 * np.where(big, w, 0.0)),
                       np.where(hyp, np.sinh(w), np.sin(w))) / np.where(w > 0, w, 1.0)
    shw = np.where(w > 0, shw, 1.0)
    L = np.where(big, w, 0.0)
    return (ch + shw * p, shw * q, shw * r, ch - shw * p), L


def _renorm(a, b, c, d):
    m = np.maximum(np.maximum(np.abs(a), np.abs(b)), np.maximum(np.abs(c), np.abs(d)))
    _, e = np.frexp(np.where(m > 0, m, 1.0))
    return np.ldexp(a, -e), np.ldexp(b, -e), np.ldexp(c, -e), np.ldexp(d, -e), e


def _wrap(x):
    return np.remainder(x + PI, 2.0 * PI) - PI


def _reduce(mats, L, turn):
    """Balanced product of the steps along axis 1 (later steps to the right): ``(a, b, c, d), L, turn``."""
    a, b, c, d = mats
    while a.shape[1] > 1:
        a1, b1, c1, d1 = a[:, 0::2], b[:, 0::2], c[:, 0::2], d[:, 0::2]  # applied first
        a2, b2, c2, d2 = a[:, 1::2], b[:, 1::2], c[:, 1::2], d[:, 1::2]
        na = a2 * a1 + b2 * c1
        nb = a2 * b1 + b2 * d1
        nc = c2 * a1 + d2 * c1
        nd = c2 * b1 + d2 * d1
        na, nb, nc, nd, e = _renorm(na, nb, nc, nd)
        L = L[:, 0::2] + L[:, 1::2] + e * LOG2
        if turn is not None:
            t1, t2 = turn[:, 0::2], turn[:, 1::2]
            psi = np.remainder(t1, PI)  # the direction after the first factor, reduced to [0, pi)
            ux, uy = np.cos(psi), -np.sin(psi)
            vx, vy = a2 * ux + b2 * uy, c2 * ux + d2 * uy
            centre = t2 - psi + 0.5 * PI
            raw = np.arctan2(-vy, vx) - psi
            turn = t1 + centre + _wrap(raw - centre)
        a, b, c, d = na, nb, nc, nd
    return (a[:, 0], b[:, 0], c[:, 0], d[:, 0]), L[:, 0], (None if turn is None else turn[:, 0])


def period(grid, eps, mu, angle=True):
    """The monodromy over one period on ``grid`` at flat ``eps, mu`` (one grid for all).

    Returns ``((a, b, c, d), L, turn)``: ``M = e^L [[a, b], [c, d]]`` and the turn of the
    Pruefer angle of ``(1, 0)`` (None without ``angle``).
    """
    P = eps.size
    rows = max(1, CHUNK // grid.n)
    outs = []
    for i in range(0, P, rows):
        E = 8.0 * eps[i:i + rows, None] ** 2
        m2 = mu[i:i + rows, None] ** 2
        mats, L = _steps(grid, E, m2)
        turn = np.arctan2(-mats[2], mats[0]) if angle else None
        outs.append(_reduce(mats, L, turn))
    cat = np.concatenate
    mats = tuple(cat([o[0][j] for o in outs]) for j in range(4))
    L = cat([o[1] for o in outs])
    turn = cat([o[2] for o in outs]) if angle else None
    return mats, L, turn


def half_trace(mats, L):
    """``(tau, log|tau|)`` of ``M = e^L N``: ``tau = tr M / 2`` (``+-inf`` where it overflows)."""
    a, _, _, d = mats
    trN = a + d
    with np.errstate(divide="ignore", over="ignore"):
        log_tau = L + np.log(np.abs(0.5 * trN))
        tau = np.sign(trN) * np.where(log_tau < 709.0, np.exp(np.minimum(log_tau, 709.0)), np.inf)
    return tau, log_tau


def _acosh_from_log(log_tau, tau):
    """acosh|tau| for |tau| >= 1 from ``log|tau|`` (finite where ``tau`` overflows)."""
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        e = np.abs(tau) - 1.0
        small = np.log1p(np.where((e >= 0) & (e < 1.0), e + np.sqrt(np.abs(e) * (e + 2.0)), 0.0))
        big = log_tau + np.log1p(np.sqrt(-np.expm1(-2.0 * np.maximum(log_tau, 0.0))))
    return np.where(e < 1.0, small, big)


def rotation(mats, tau, turn):
    """``(theta, zone)`` from the carried turn of ``(1, 0)`` (module notes)."""
    b = mats[1]
    stable = np.abs(tau) < 1.0
    with np.errstate(invalid="ignore"):
        base = np.where(b >= 0, 1.0, -1.0) * np.arccos(np.clip(tau, -1.0, 1.0))
    kk = np.rint((turn - base) / (2.0 * PI))
    theta_st = 2.0 * PI * kk + base
    zone_st = np.where(b >= 0, 2 * kk, 2 * kk - 1)
    theta = np.where(stable, theta_st, PI * gap_of_turn(turn, tau < 0))
    zone = np.where(stable, zone_st, -1).astype(np.int64)
    return theta, zone


class Engine:
    """The integrated period of one shape: grids cached by size, steps chosen per point.

    ``shape`` maps ``tau`` in ``[0, 2)`` (arrays) to ``s``; ``breaks`` are its jumps and kinks
    inside ``(0, 2)``; ``min_steps`` resolves the shape itself. A point gets the smallest power
    of two of steps with a phase ``h sqrt(8 eps^2 max|mu^2 + s|)`` of at most :data:`PHASE` per
    step (measured: edges to about 1e-12 relative, ``docs/drives.md``).
    """

    #: largest phase per step
    PHASE = 0.05
    #: most steps per period (``eps`` of several thousand at the phase :attr:`PHASE` a step)
    MAX_STEPS = 1 << 22
    #: beyond the most steps, the largest phase a step may take: a step's turn is counted as the
    #: principal value of its angle (so below pi), and the traces agree with four times the steps
    #: to about 1e-13 relative up to here (measured on the triangle wave at ``eps = 1e6``)
    STEP_PHASE_MAX = 1.0
    #: the largest ``mu`` integrated (``mu^2`` and the coefficients ``8 eps^2 (mu^2 + s)`` stay doubles;
    #: far beyond ``mu_max`` gravity outweighs the drive by ``mu^2``)
    MU_MAX = 1e150
    #: run the compiled loop (:mod:`._compiled`) where numba is installed; the numpy tree otherwise
    compiled = True
    #: the numpy tree runs until the process has asked this many point-steps of the engine (each call
    #: counted as at least :attr:`CALL_WORK`), then the compiled loop is loaded (or earlier, by
    #: :func:`load_compiled`): numba's start-up, 0.7-1.2 s, is the time of about 2^21 point-steps in
    #: numpy, so a command of one report (some 10^5) does not pay it and a long session pays it once,
    #: after at most about as much time in the numpy tree
    COMPILED_FROM = 1 << 21
    #: a call's own cost in point-steps (numpy's fixed cost of a call, about 1 ms)
    CALL_WORK = 4096

    def __init__(self, shape, breaks=(), min_steps=256):
        self.shape = shape
        self.breaks = np.unique(np.asarray(breaks, float))
        self.breaks = self.breaks[(self.breaks > 0.0) & (self.breaks < 2.0)]
        need = max(int(min_steps), self.breaks.size + 1)
        self.min_steps = 1 << int(np.ceil(np.log2(need)))
        self._grids = {}
        g = self.grid(self.min_steps)
        # extremes of s on the nodes and at the segment ends (for the phase bound)
        ends = np.concatenate([[0.0], self.breaks, np.nextafter(self.breaks, 0.0), [np.nextafter(2.0, 0.0)]])
        vals = np.concatenate([g.s_nodes.ravel(), np.asarray(shape(np.concatenate([ends, g.x[: g.m]])), float)])
        # polish the extremes between the samples (a smooth shape's peak lies between nodes)
        xs = np.concatenate([g.x[: g.m][:, None] + g.h[: g.m][:, None] * NODES[None, :]]).ravel()
        flat = g.s_nodes.ravel()
        self.s_min = min(float(vals.min()), _polish(shape, xs[np.argmin(flat)], 2.0 / g.m, 1.0))
        self.s_max = max(float(vals.max()), _polish(shape, xs[np.argmax(flat)], 2.0 / g.m, -1.0))

    #: the grids kept for reuse, at most about this many bytes (a grid takes 120 bytes a step: one of
    #: 2^21 steps, 250 MB); the least recently used go first, before a new one is built
    GRID_BYTES = 1 << 28

    def grid(self, n):
        g = self._grids.pop(n, None)   # (re-inserted: the dict's order is the order of use)
        if g is None:
            while self._grids and _GRID_STEP_BYTES * (sum(self._grids) + n) > self.GRID_BYTES:
                del self._grids[next(iter(self._grids))]
            g = Grid(self.shape, self.breaks, n)
        self._grids[n] = g
        return g

    def steps_for(self, eps, mu):
        """Power-of-two step counts for flat ``eps, mu``; a point that :attr:`MAX_STEPS` would leave
        with more than :attr:`STEP_PHASE_MAX` of phase a step is refused by name (its turns would be
        miscounted and its trace unresolved), as is ``mu`` beyond :attr:`MU_MAX`."""
        if eps.size == 1:  # one point (root solves): the same in plain floats
            if not float(mu[0]) <= self.MU_MAX:
                self.refuse(eps, mu)
            m2 = float(mu[0]) ** 2
            root = math.sqrt(8.0 * max(abs(m2 + self.s_min), abs(m2 + self.s_max)))
            if not float(eps[0]) <= self._phase_cap / root:   # (eps_max, in floats)
                self.refuse(eps, mu)
            rate = root * float(eps[0])
            want = min(max(2.0 * rate / self.PHASE, self.min_steps), self.MAX_STEPS)
            return np.array([1 << max(int(math.ceil(math.log2(want))), 0)], np.int64) if want > 0 else \
                np.array([self.min_steps], np.int64)
        if mu.size and not np.max(mu) <= self.MU_MAX:
            self.refuse(eps, mu)
        m2 = mu * mu
        root = np.sqrt(8.0 * np.maximum(np.abs(m2 + self.s_min), np.abs(m2 + self.s_max)))
        if eps.size and not np.all(eps <= self._phase_cap / root):   # (eps_max)
            self.refuse(eps, mu)
        rate = root * eps  # phase per unit tau, at most
        want = np.maximum(2.0 * rate / self.PHASE, self.min_steps)
        n = np.exp2(np.ceil(np.log2(np.minimum(want, self.MAX_STEPS))))
        return n.astype(np.int64)

    @property
    def _phase_cap(self):
        """The largest ``eps sqrt(8 max|mu^2 + s|)``: :attr:`MAX_STEPS` steps over ``tau`` in ``[0, 2]``,
        each of a phase at most :attr:`STEP_PHASE_MAX`."""
        return 0.5 * self.STEP_PHASE_MAX * self.MAX_STEPS

    def eps_max(self, mu):
        """The largest ``eps`` integrated at ``mu`` (:meth:`steps_for`; ``mu <= MU_MAX``)."""
        m2 = np.asarray(mu, float) ** 2
        smax = np.maximum(np.abs(m2 + self.s_min), np.abs(m2 + self.s_max))
        return self._phase_cap / np.sqrt(8.0 * smax)

    def refuse(self, eps, mu):
        """Raise the error naming the first point of flat ``eps, mu`` that :meth:`steps_for` cannot integrate
        (:class:`kapitza._validate.ReachError` for an ``eps`` beyond :meth:`eps_max`)."""
        bad_mu = ~(mu <= self.MU_MAX)
        if bad_mu.any():
            m = float(mu[np.argmax(bad_mu)])
            raise _v.KapitzaValueError(f"mu must satisfy mu <= {self.MU_MAX:g} for this drive's integrated Floquet "
                                       f"data (8 eps^2 mu^2 must stay a double); got {m!r}")
        over = ~(eps <= self.eps_max(mu))
        i = int(np.argmax(over))
        e, m = float(eps[i]), float(mu[i])
        raise _v.ReachError(e, m, float(self.eps_max(m)), f"integrated Floquet data (at most {self.MAX_STEPS:,} "
                                                         f"steps a period, of a phase up to {self.STEP_PHASE_MAX:g})")

    def _groups(self, eps, mu):
        """``(n, rows)`` for each step count among the points (one group in the common case)."""
        n = self.steps_for(eps, mu)
        if n.size and n[0] == n[-1] and (n == n[0]).all():
            return [(int(n[0]), None)]
        return [(int(nv), np.flatnonzero(n == nv)) for nv in np.unique(n)]

    def _fast(self, groups, eps):
        """The compiled module for a call of these step groups, or None (the numpy tree)."""
        if not self.compiled:
            return None
        if _COMPILED is None:
            global _TREE_WORK
            _TREE_WORK += sum(max(nv * (eps.size if sel is None else sel.size), self.CALL_WORK) for nv, sel in groups)
            if _TREE_WORK < self.COMPILED_FROM:
                return None
            load_compiled()
        return _COMPILED or None

    def period(self, eps, mu, angle=True):
        """``((a, b, c, d), L, turn)`` at flat ``eps, mu`` (see :func:`period`)."""
        eps = np.asarray(eps, float).ravel()
        mu = np.asarray(mu, float).ravel()
        groups = self._groups(eps, mu)
        return self._period(eps, mu, angle, groups, self._fast(groups, eps))

    def _period(self, eps, mu, angle, groups, fast):
        out = np.empty((eps.size, 6))
        for nv, sel in groups:
            e, m = (eps, mu) if sel is None else (eps[sel], mu[sel])
            if fast is not None:
                o = fast.run(self.grid(nv), e, m, angle)
            else:
                mats, L, turn = period(self.grid(nv), e, m, angle)
                o = np.column_stack([*mats, L, turn if angle else np.zeros(e.size)])
            out[slice(None) if sel is None else sel] = o
        return (out[:, 0], out[:, 1], out[:, 2], out[:, 3]), out[:, 4], (out[:, 5] if angle else None)

    def floquet(self, eps, mu, growth=False):
        """``(tau, log_tau, theta, zone)`` at flat ``eps, mu`` (and ``acosh|tau|`` off the zones,
        0 on them, with ``growth``)."""
        eps = np.asarray(eps, float).ravel()
        mu = np.asarray(mu, float).ravel()
        groups = self._groups(eps, mu)
        fast = self._fast(groups, eps)
        if fast is None:
            mats, L, turn = self._period(eps, mu, True, groups, None)   # (its work counted once)
            tau, log_tau = half_trace(mats, L)
            theta, zone = rotation(mats, tau, turn)
            if growth:
                return tau, log_tau, theta, zone, np.where(zone >= 0, 0.0, _acosh_from_log(log_tau, tau))
            return tau, log_tau, theta, zone
        out = np.empty((eps.size, 6))
        for nv, sel in groups:
            e, m = (eps, mu) if sel is None else (eps[sel], mu[sel])
            out[slice(None) if sel is None else sel] = fast.run(self.grid(nv), e, m, True, True)
        res = out[:, 0], out[:, 1], out[:, 2], out[:, 3].astype(np.int64)
        return (*res, out[:, 4]) if growth else res

    def log_tau(self, eps, mu):
        mats, L, _ = self.period(eps, mu, False)
        return half_trace(mats, L)
