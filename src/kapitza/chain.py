"""The tower: N linked pendulums standing on one vertically driven pivot (``docs/tower.md``).

Links ``j = 1..N`` counted from the pivot up, lengths ``L_j``, masses ``m_j``, each link's
centre of mass at ``c_j`` above its lower joint and moment of inertia ``J_j`` about it
(uniform rod: ``c = L/2``, ``J = m L^2/12``; point mass at the upper end of a massless rod:
``c = L``, ``J = 0``). With ``theta_j`` the angle of link ``j`` from the upright, the motion
linearised about the upright is

    M theta'' + C theta' = (g + a(t)) K theta,

    M_jj = J_j + m_j c_j^2 + L_j^2 S_j,      M_ij = L_i K_jj  (i < j),   M symmetric,
    K_jj = m_j c_j + L_j S_j,                S_j = sum_{i > j} m_i,

``K`` diagonal, and with the same friction torque ``-c (theta_j' - theta_{j-1}')`` at every
joint (``theta_0 = 0``: the pivot) ``C = c D^T D``, ``D`` the difference matrix.

Without friction the drive multiplies gravity, so the generalized eigenvectors ``K v = lambda
M v`` (``scipy.linalg.eigh(K, M)``, ``V^T M V = I``) decouple the chain: each modal coordinate
obeys the single pendulum's ``q'' = (g + a(t))/l_k q`` with the *modal length*
``l_k = 1/lambda_k``. The tower is stable exactly when every mode is, and each mode's
verdict, zone and margin are the single pendulum's (:func:`kapitza.analyze`, certified).
All modes share ``T``, ``A`` and so ``mu = sqrt(g/A)``; only ``eps_k = T sqrt(A/(8 l_k))``
differs, so the margins (relative changes of ``T`` at fixed ``A``) compare directly.

With friction ``C`` is not a combination of ``M`` and ``K`` and couples the modes: the
verdict comes from the ``2N``-dimensional monodromy of ``z = (theta, theta')``,
``z' = [[0, I], [(g + a) M^-1 K, -M^-1 C]] z``, as the exact product of the segment
exponentials for piecewise-constant drives and a DOP853 integration of one period (rtol
1e-12) for the others. Stable iff all ``2N`` multipliers lie strictly inside the unit circle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import _validate as _v
from ._display import Summary, multipliers as _fmt_multipliers, num
from .parameters import G_EARTH
from .system import Pendulum
from .zones import zone_edges

__all__ = ["Chain", "ChainReport", "ModeReport", "ChainFloquet", "analyze_chain", "chain_floquet", "TowerCurves",
           "tower_curves", "default_window", "LINKS"]

#: the link models: a uniform rod, or a point mass on a massless rod's upper end
LINKS = ("rod", "point")
#: the most links a chain may have (the mass matrix stays well conditioned far beyond)
MAX_LINKS = 32


#: the lengths [m] and masses [kg] a link may have (far beyond any bench; the matrices stay within a double)
LENGTH_RANGE = (1e-6, 1e4)
MASS_RANGE = (1e-9, 1e9)


def _positive_list(name, value, bounds):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise _v.KapitzaValueError(f"{name} must be a sequence of numbers; got {value!r}") from None
    arr = np.atleast_1d(arr)
    if arr.ndim != 1 or arr.size == 0:
        raise _v.KapitzaValueError(f"{name} must be a non-empty sequence of numbers; got {value!r}")
    if arr.size > MAX_LINKS:
        raise _v.KapitzaValueError(f"{name} may hold at most {MAX_LINKS} links (1 <= N <= {MAX_LINKS}); got {arr.size}")
    lo, hi = bounds
    bad = ~(np.isfinite(arr) & (arr >= lo) & (arr <= hi))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise _v.KapitzaValueError(f"{name} must lie in [{lo:g}, {hi:g}] ({lo:g} <= {name}[i] <= {hi:g}); "
                                   f"got {name}[{i}] = {float(arr[i])!r}")
    return tuple(float(x) for x in arr)


@dataclass(frozen=True, repr=False)
class Chain:
    """N rigid links standing on one pivot, joined by hinges: the tower.

    Parameters
    ----------
    lengths : sequence of float
        Link lengths [m] from the pivot up, each in [1e-6, 1e4] (1 to 32 links).
    masses : sequence of float, optional
        Link masses [kg], each in [1e-9, 1e9]; equal (1 kg each) if omitted. Only ratios matter
        without friction.
    links : {"rod", "point"}
        ``"rod"``: uniform rods (centre of mass at the middle, ``J = m L^2/12``);
        ``"point"``: massless rods with a point mass at each upper end.
    joint_damping : float
        Viscous friction ``c`` [N m s/rad] at every joint, the pivot included: torque
        ``-c (theta_j' - theta_{j-1}')``. >= 0.

    Raises
    ------
    ValueError
        If a length or mass is outside its range, there are no links or more than 32, ``links`` is
        neither ``"rod"`` nor ``"point"``, or ``joint_damping`` is negative.

    Notes
    -----
    ``docs/tower.md``. One link is the single pendulum: ``Chain([L])`` has the modal length
    ``2 L / 3`` of :meth:`kapitza.Pendulum.uniform_rod` (``L`` for ``links="point"``), and a
    joint friction ``c`` is the pendulum's damping ``c / I`` [1/s], ``I = M_11``.

    Examples
    --------
    Three 20 cm rods of 1 kg, one on another:

    >>> import kapitza
    >>> tower = kapitza.Chain([0.2, 0.2, 0.2])
    >>> tower
    Chain([0.2, 0.2, 0.2], masses=[1.0, 1.0, 1.0], links='rod')
    >>> tower.height
    0.6000...
    >>> tower.modal_lengths
    (0.4124..., 0.0666..., 0.0186...)
    >>> tower.describe()
    '3 links (uniform rods), lengths 0.2, 0.2, 0.2 m, masses 1, 1, 1 kg'
    """

    lengths: tuple
    masses: tuple = None  # type: ignore[assignment]  # (None: set by __post_init__)
    links: str = "rod"
    joint_damping: float = 0.0
    _modes: tuple = field(init=False, compare=False, hash=False, default=None)  # type: ignore[arg-type]

    def __post_init__(self):
        L = _positive_list("lengths", self.lengths, LENGTH_RANGE)
        m = (1.0,) * len(L) if self.masses is None else _positive_list("masses", self.masses, MASS_RANGE)
        if len(m) != len(L):
            raise _v.KapitzaValueError(
                f"masses must have one value per link ({len(L)} lengths); got {len(m)} masses")
        if self.links not in LINKS:
            raise _v.KapitzaValueError(f"links must be one of 'rod', 'point'; got {self.links!r}")
        if np.ndim(self.joint_damping) != 0:
            raise _v.KapitzaValueError(f"joint_damping must be a single number; got {self.joint_damping!r}")
        # (its matrix C = c D^T D, with entries 2 c, and C / inertia must be doubles)
        c = _v.one("joint_damping", _v.in_range("joint_damping", self.joint_damping, 0.0, 1e300, lo_open=False,
                                                hi_open=False))
        object.__setattr__(self, "lengths", L)
        object.__setattr__(self, "masses", m)
        object.__setattr__(self, "joint_damping", float(c))
        object.__setattr__(self, "_modes", _modes(self))

    # ---------------------------------------------------------------- geometry
    @property
    def n(self) -> int:
        """Number of links ``N``."""
        return len(self.lengths)

    @property
    def centres(self) -> np.ndarray:
        """Height ``c_j`` [m] of each link's centre of mass above its lower joint."""
        L = np.array(self.lengths)
        return 0.5 * L if self.links == "rod" else L

    @property
    def inertias(self) -> np.ndarray:
        """Moment of inertia ``J_j`` [kg m^2] of each link about its own centre of mass."""
        L, m = np.array(self.lengths), np.array(self.masses)
        return m * L * L / 12.0 if self.links == "rod" else np.zeros(self.n)

    @property
    def height(self) -> float:
        """Height of the standing tower [m]."""
        return float(sum(self.lengths))

    def mass_matrix(self) -> np.ndarray:
        """``M`` [kg m^2]: ``T_kin = theta'^T M theta' / 2`` to second order about the upright."""
        L, m, c, J = np.array(self.lengths), np.array(self.masses), self.centres, self.inertias
        above = np.concatenate([np.cumsum(m[::-1])[::-1][1:], [0.0]])  # S_j = sum_{i>j} m_i
        k = m * c + L * above
        M = np.diag(J + m * c * c + L * L * above)
        for i in range(self.n):
            for j in range(i + 1, self.n):
                M[i, j] = M[j, i] = L[i] * k[j]
        return M

    def stiffness_matrix(self) -> np.ndarray:
        """``K`` [kg m] (diagonal): the potential is ``-(g + a) theta^T K theta / 2`` near the upright."""
        L, m, c = np.array(self.lengths), np.array(self.masses), self.centres
        above = np.concatenate([np.cumsum(m[::-1])[::-1][1:], [0.0]])
        return np.diag(m * c + L * above)

    def damping_matrix(self) -> np.ndarray:
        """``C = c D^T D`` [N m s]: joint friction, ``D`` the difference matrix (pivot as joint 1)."""
        D = np.eye(self.n) - np.eye(self.n, k=-1)
        return self.joint_damping * (D.T @ D)

    # ---------------------------------------------------------------- modes
    @property
    def modal_lengths(self) -> tuple:
        """Equivalent lengths ``l_k = 1/lambda_k`` [m] of the modes, longest first."""
        return self._modes[0]

    @property
    def mode_shapes(self) -> np.ndarray:
        """``(N, N)``: column ``k`` is mode ``k``'s shape ``v_k`` (the link angles), ``V^T M V = I``."""
        return self._modes[1].copy()

    @property
    def pivot_inertia(self) -> float:
        """``M_11`` [kg m^2]: the whole tower's moment of inertia about the pivot when rigid is
        ``1^T M 1``; ``M_11`` is the first link's share (a one-link chain's ``I``)."""
        return float(self.mass_matrix()[0, 0])

    def pendulum(self, g=G_EARTH):
        """The single :class:`kapitza.Pendulum` of a one-link chain (its damping ``c / I`` [1/s])."""
        if self.n != 1:
            raise _v.KapitzaValueError(f"only a one-link chain is a single pendulum; this one has {self.n} links")
        c = self.joint_damping / self.pivot_inertia
        if self.links == "rod":
            return Pendulum.uniform_rod(self.lengths[0], g=g, damping=c)
        return Pendulum.point_mass(self.lengths[0], g=g, damping=c)

    # ---------------------------------------------------------------- questions
    def analyze(self, *, T=None, A=None, frequency=None, stroke=None, amplitude=None, g=G_EARTH, drive=None):
        """The tower's stability report (:func:`analyze_chain`)."""
        return analyze_chain(self, T=T, A=A, frequency=frequency, stroke=stroke, amplitude=amplitude, g=g,
                             drive=drive)

    def describe(self) -> str:
        """One line: the links, their lengths and masses, the friction."""
        kind = "uniform rods" if self.links == "rod" else "point masses on massless rods"
        L = ", ".join(f"{x:.6g}" for x in self.lengths)
        m = ", ".join(f"{x:.6g}" for x in self.masses)
        text = f"{self.n} link{'s' if self.n > 1 else ''} ({kind}), lengths {L} m, masses {m} kg"
        if self.joint_damping > 0:
            text += f", joint friction c = {self.joint_damping:.6g} N m s/rad"
        return text

    def as_dict(self) -> dict:
        return {"lengths": list(self.lengths), "masses": list(self.masses), "links": self.links,
                "joint_damping": self.joint_damping, "modal_lengths": list(self.modal_lengths)}

    def __repr__(self):
        extra = "" if self.joint_damping == 0 else f", joint_damping={self.joint_damping!r}"
        return f"Chain({list(self.lengths)!r}, masses={list(self.masses)!r}, links={self.links!r}{extra})"


def _modes(chain):
    """Modal lengths (longest first) and M-orthonormal shapes of ``K v = lambda M v``."""
    if chain.n == 1:
        # the single pendulum's own formulas, so that one link is Pendulum.uniform_rod/point_mass exactly
        L = chain.lengths[0]
        l = 2.0 * L / 3.0 if chain.links == "rod" else L
        return (l,), np.array([[1.0 / math.sqrt(chain.mass_matrix()[0, 0])]]), _first_order(chain)
    from scipy.linalg import eigh

    M, K = chain.mass_matrix(), chain.stiffness_matrix()
    # scale to O(1) entries (a chain in mm and g is the same chain): M/(m0 L0^2), K/(m0 L0)
    L0, m0 = max(chain.lengths), max(chain.masses)
    lam, V = eigh(K / (m0 * L0), M / (m0 * L0 * L0))
    lam = lam / L0  # lambda of K v = lambda M v
    V = V / (math.sqrt(m0) * L0)
    V = V * np.where(V[0] < 0, -1.0, 1.0)  # the first link tilts forward in every mode
    return tuple(float(1.0 / x) for x in lam), V, _first_order(chain)


def _first_order(chain):
    """``(M^-1 K, M^-1 C)`` of the first-order system."""
    M = chain.mass_matrix()
    return np.linalg.solve(M, chain.stiffness_matrix()), np.linalg.solve(M, chain.damping_matrix())


# ====================================================================== linear verdicts
@dataclass(frozen=True, repr=False)
class ModeReport(Summary):
    """One mode of the tower at one point: the single pendulum of length ``l`` (:func:`kapitza.analyze`).

    ``index`` counts from 1 (the longest mode, the one that falls first when the drive is too
    weak) to ``N`` (the shortest, the first to double its period when the drive is too strong).
    ``shape`` is the mode's link angles scaled to a largest ``|theta_j|`` of 1. The rest are the
    fields of :class:`kapitza.StabilityReport` of that pendulum (``margin`` along ``T`` at fixed
    ``A``; ``T_lo, T_hi`` the mode's nearest zone in ``T`` at this ``A``).

    Attributes
    ----------
    index : int
        The mode's number, 1 to ``N``.
    l : float
        The length [m] of the single pendulum this mode moves like.
    shape : tuple of float
        The link angles of the mode, the largest ``|theta_j|`` 1.
    eps, mu, stable, verdict, zone, nearest_zone, margin, growth, multipliers, eps_lo, eps_hi
        As in :class:`kapitza.StabilityReport`, for that pendulum.
    T_lo, T_hi : float or None
        The nearest zone's edges in ``T`` [s] at this ``A``.

    Examples
    --------
    >>> import kapitza
    >>> report = kapitza.analyze_chain(kapitza.Chain([0.2, 0.2, 0.2]), frequency=200.0, stroke=0.005)
    >>> [(m.index, round(m.l, 4), m.stable, round(m.margin, 3)) for m in report.modes]
    [(1, 0.4124, True, 0.129), (2, 0.0667, True, 0.65), (3, 0.0187, True, 0.815)]
    >>> [round(x, 4) for x in report.modes[0].shape]
    [0.6, 0.7955, 1.0]
    """

    index: int
    l: float
    shape: tuple
    eps: float
    mu: float
    stable: bool
    verdict: str
    zone: int
    nearest_zone: int
    margin: float
    growth: float
    multipliers: tuple
    eps_lo: float | None
    eps_hi: float | None
    T_lo: float | None = None
    T_hi: float | None = None

    def lines(self):
        return [("mode", f"{self.index}: l = {num(self.l, 8)} m, shape {_shape_text(self.shape)}"),
                ("verdict", self.verdict), ("margin", f"{100 * self.margin:.4g} %"),
                ("growth", f"{num(self.growth)} per period 2T")]

    def headline(self):
        return f"mode {self.index} (l = {num(self.l, 6)} m): {self.verdict}"

    def as_dict(self):
        d = dict(self.__dict__)
        d["shape"] = list(self.shape)
        d["multipliers"] = [[float(z.real), float(z.imag)] for z in self.multipliers]
        return {k: (None if isinstance(v, float) and not math.isfinite(v) and k != "margin" else v)
                for k, v in d.items()}


def _shape_text(shape):
    return "(" + ", ".join(f"{x:+.3f}" for x in shape) + ")"


@dataclass(frozen=True, repr=False)
class ChainReport(Summary):
    """The stability of the upright tower at one point.

    ``print(report)`` gives a table, ``repr`` one line, :meth:`as_dict` the JSON.

    Attributes
    ----------
    stable : bool
        The verdict: every mode stable (undamped), or all ``2N`` multipliers strictly inside the
        unit circle (with joint friction).
    verdict : str
        A sentence saying which mode fails first and how.
    modal_lengths : tuple of float
        ``l_k``, longest first.
    modes : tuple of ModeReport
        Each mode as a single pendulum (without friction: with it, the modes of the frictionless
        chain, for orientation; the verdict is the full monodromy's).
    multipliers : tuple of complex
        The ``2N`` Floquet multipliers over one period ``2T``, largest modulus first.
    growth : float
        ``log max|lambda|`` per period ``2T`` (< 0: motions decay; 0: stable without friction).
    critical_mode : int
        The mode nearest to failing (stable) or failing fastest (unstable), 1 = longest.
    failure : str
        How it fails: ``"falls"`` (below zone 0: the drive too weak, the longest mode leans over),
        ``"period doubling"`` (a 4T-type edge: the shortest mode first, as the drive grows too
        strong), ``"2T resonance"`` (a 2T-type edge between zones) or ``"flutter"`` (with friction:
        complex multipliers leaving the unit circle).
    margin : float
        Signed relative change of ``T`` at fixed ``A`` to the nearest edge of the tower's band:
        > 0 inside, < 0 outside (the smallest of the modes' margins without friction).
    T_lo, T_hi, frequency_lo, frequency_hi, stroke_lo, stroke_hi : float or None
        The tower's stable interval through the point in ``T`` (at this ``A``), in frequency
        (at this stroke) and in stroke (at this frequency), where stable.
    method : str
        ``"modes"`` or the monodromy used with friction.

    Examples
    --------
    >>> import kapitza
    >>> report = kapitza.analyze_chain(kapitza.Chain([0.2, 0.2, 0.2]), frequency=200.0, stroke=0.005)
    >>> report.stable, report.critical_mode, report.failure
    (True, 1, 'falls')
    >>> round(report.frequency_lo, 1), report.frequency_hi
    (174.2, inf)
    >>> round(report.margin, 3)
    0.129
    """

    stable: bool
    verdict: str
    T: float
    A: float
    g: float
    stroke: float
    chain: str
    drive: str
    modal_lengths: tuple
    modes: tuple
    multipliers: tuple
    growth: float
    critical_mode: int
    failure: str
    margin: float
    method: str
    joint_damping: float = 0.0
    T_lo: float | None = None
    T_hi: float | None = None
    frequency_lo: float | None = None
    frequency_hi: float | None = None
    stroke_lo: float | None = None
    stroke_hi: float | None = None

    @property
    def frequency(self) -> float:
        """Drive frequency ``1/(2T)`` [Hz]."""
        return 0.5 / self.T

    def lines(self):
        rows = [("parameters", f"T = {num(self.T, 10)} s (frequency {num(self.frequency)} Hz), "
                               f"A = {num(self.A, 10)} m/s^2, stroke {num(1e3 * self.stroke)} mm, "
                               f"g = {num(self.g)} m/s^2"),
                ("tower", self.chain), ("drive", self.drive), ("verdict", self.verdict)]
        if self.joint_damping > 0:
            rows.append(("method", self.method))
        rows.append(("modal lengths", ", ".join(f"{num(x, 8)}" for x in self.modal_lengths) + " m (longest first)"))
        for m in self.modes:
            head = f"mode {m.index}"
            zone = f"zone {m.zone}" if m.stable else m.verdict.split(":")[0]
            rows.append((head, f"l = {num(m.l, 8)} m, eps = {num(m.eps, 8)}: {zone}, margin "
                               f"{100 * m.margin:+.4g} %, growth {num(m.growth, 6)}, shape {_shape_text(m.shape)}"))
        if self.joint_damping > 0:
            rows[-len(self.modes):] = [(k, v + " (frictionless)") for k, v in rows[-len(self.modes):]]
        rows.append(("multipliers", _fmt_multipliers(self.multipliers)))
        rows.append(("growth", f"{num(self.growth)} per period 2T (log of the largest |multiplier|"
                               + ("; < 0: motions decay)" if self.growth < 0 else ")")))
        if self.stable:
            rows.append(("margin", f"{100 * self.margin:.4g} % (T may change by this fraction at fixed A; "
                                   f"mode {self.critical_mode} {_how(self.failure)} first)"))
        else:
            rows.append(("margin",
                         f"{100 * self.margin:.4g} % (to the nearest edge of mode {self.critical_mode}'s zone)"))
        if self.T_lo is not None:
            rows.append(("band", f"{num(self.T_lo, 8)} < T < {num(self.T_hi, 8)} s at this A"))
        if self.frequency_lo is not None:
            hi = ("inf" if self.frequency_hi is None or not math.isfinite(self.frequency_hi)
                  else num(self.frequency_hi, 6))
            rows.append(("", f"{num(self.frequency_lo, 6)} < frequency < {hi} Hz at this stroke"))
        if self.stroke_lo is not None:
            rows.append(("",
                         f"{num(1e3 * self.stroke_lo, 6)} < stroke < {num(1e3 * self.stroke_hi, 6)} mm "
                         "at this frequency"))
        return rows

    def headline(self):
        return (f"{len(self.modal_lengths)}-link tower, T = {num(self.T, 6)} s, A = {num(self.A, 6)} m/s^2: "
                f"{self.verdict}")

    def as_dict(self) -> dict:
        d = {k: v for k, v in self.__dict__.items() if k != "modes"}
        d["frequency"] = self.frequency
        d["modal_lengths"] = list(self.modal_lengths)
        d["multipliers"] = [[float(z.real), float(z.imag)] for z in self.multipliers]
        d["modes"] = [m.as_dict() for m in self.modes]
        return {k: (None if isinstance(v, float) and not math.isfinite(v) and k not in ("margin", "growth") else v)
                for k, v in d.items()}


def _how(failure):
    return {"falls": "falls", "period doubling": "doubles its period", "2T resonance": "resonates (2T-type)",
            "flutter": "flutters"}.get(failure, failure)


def _rig_point(drive, T, A, frequency, stroke, amplitude):
    """Validated ``(T, A)`` from ``(T, A)`` or the frequency with the stroke, amplitude or ``A``."""
    if frequency is None:
        if T is None or A is None:
            raise _v.KapitzaValueError("give T and A, or the frequency with the stroke, amplitude or A")
        if stroke is not None or amplitude is not None:
            raise _v.KapitzaValueError("stroke and amplitude go with frequency, not with T and A")
        return _v.one("T", _v.positive("T", T)), _v.one("A", _v.positive("A", A))
    if T is not None:
        raise _v.KapitzaValueError("give T or frequency, not both")
    for name, v in (("frequency", frequency), ("stroke", stroke), ("amplitude", amplitude), ("A", A)):
        if v is not None:
            _v.one(name, _v.positive(name, v))
    T_, A_ = drive.from_rig(frequency, stroke=stroke, amplitude=amplitude, acceleration=A)
    return float(T_), float(A_)


def _edge_failure(n, lower):
    """What happens at the lower or upper edge of zone ``n``: ``"falls"``, ``"period doubling"``, ``"2T resonance"``."""
    if n == 0 and lower:
        return "falls"
    kind = ("2T", "4T")[(n + (0 if lower else 1)) % 2]
    return "period doubling" if kind == "4T" else "2T resonance"


def _verdict_failure(verdict):
    if "too weak" in verdict or "no elliptic" in verdict or "always unstable" in verdict:
        return "falls"
    if "4T" in verdict:
        return "period doubling"
    return "2T resonance"


def analyze_chain(chain, *, T=None, A=None, frequency=None, stroke=None, amplitude=None, g=G_EARTH, drive=None):
    """The stability report of the upright tower at one point.

    Parameters
    ----------
    chain : Chain
    T, A : float, optional
        Drive half-period [s] and acceleration scale [m/s^2].
    frequency, stroke, amplitude : float, optional
        Or the drive frequency [Hz] with the stroke (peak to peak) or the amplitude [m] (or ``A``).
    g : float
        Gravity [m/s^2].
    drive : Drive or str, optional
        The pivot's motion; the paper's square wave by default.

    Returns
    -------
    ChainReport

    Raises
    ------
    ValueError
        If a value is out of range, the point is given twice or not at all, or ``drive`` names no
        drive.

    Notes
    -----
    Without friction each mode is asked of :func:`kapitza.analyze` with ``l = l_k`` (the single
    pendulum's certified verdicts, zones and margins); with friction the verdict, multipliers
    and growth are the ``2N`` monodromy's (:func:`chain_floquet`). A one-link chain is the single
    pendulum, its friction included (``c / I``).

    Examples
    --------
    >>> import kapitza
    >>> tower = kapitza.Chain([0.2, 0.2, 0.2])
    >>> kapitza.analyze_chain(tower, frequency=200.0, stroke=0.005)
    <ChainReport: 3-link tower, T = 0.0025 s, A = 3200 m/s^2: stable: every mode in its zone (0, 0, 0);
     mode 1 (l = 0.4124... m) is the nearest to failing: it falls if T falls by 12.9 % at this A>
    >>> kapitza.analyze_chain(tower, frequency=100.0, stroke=0.005).verdict
    'unstable: mode 1 of 3 fails; mode 1 (l = 0.4124... m) grows fastest and falls: the drive is too weak
     to hold it up (it falls; below zone 0)'
    >>> kapitza.analyze_chain(tower, frequency=60.0, stroke=0.03).failure
    'period doubling'
    """
    from .drives import as_drive

    if not isinstance(chain, Chain):
        raise _v.KapitzaValueError(f"chain must be a kapitza.Chain; got {chain!r}")
    d = as_drive(drive)
    g = _v.one("g", _v.positive("g", g))
    T, A = _rig_point(d, T, A, frequency, stroke, amplitude)
    modes = _mode_reports(chain, T, A, g, d)
    with np.errstate(over="ignore"):  # +inf for a stroke beyond a double
        stroke_v = float(d.stroke(T, A))
    coupled = chain.joint_damping > 0 and chain.n > 1
    if not coupled:
        # one link with friction: the pendulum's damping c / I in its own (certified) report
        if chain.joint_damping > 0:
            modes = _mode_reports(chain, T, A, g, d, damping=chain.joint_damping / chain.pivot_inertia)
        return _modal_report(chain, modes, T, A, g, d, stroke_v)
    return _coupled_report(chain, modes, T, A, g, d, stroke_v)


def _mode_reports(chain, T, A, g, drive, damping=0.0):
    """Each mode as a single pendulum of length ``l_k``: one vectorised call of the public
    :func:`kapitza.floquet` and :func:`kapitza.stability_margin` for all modes (they share ``mu``).
    A one-link chain takes the single pendulum's own report (:func:`kapitza.analyze`)."""
    from . import analyze as analyze_one, floquet, stability_margin, to_arnold

    V = chain.mode_shapes
    shapes = [tuple(float(x) for x in V[:, k] / np.max(np.abs(V[:, k]))) for k in range(chain.n)]
    if chain.n == 1:
        r = analyze_one(T=T, A=A, l=chain.modal_lengths[0], g=g, drive=drive, damping=damping)
        return (ModeReport(index=1, l=chain.modal_lengths[0], shape=shapes[0], eps=r.eps, mu=r.mu, stable=r.stable,
                           verdict=r.verdict, zone=r.zone, nearest_zone=r.nearest_zone, margin=r.margin,
                           growth=r.growth, multipliers=tuple(r.multipliers), eps_lo=_finite(r.eps_lo),
                           eps_hi=_finite(r.eps_hi), T_lo=_finite(r.T_lo), T_hi=_finite(r.T_hi)),)
    l = np.array(chain.modal_lengths)
    eps, mu = to_arnold(T, A, l, g)
    mu = float(np.asarray(mu).flat[0])
    fl = floquet(eps, mu, drive=drive)
    mg = stability_margin(eps, mu, drive=drive)
    out = []
    for k in range(chain.n):
        stable, nz = bool(fl.stable[k]), int(mg.zone[k])
        lo, hi = _finite(mg.eps_lo[k]), _finite(mg.eps_hi[k])  # None: no zone to measure against
        if stable:
            verdict = f"stable (zone {int(fl.zone[k])})"
        elif mu >= drive.mu_max:
            verdict = "always unstable: the pivot never accelerates down faster than g"
        elif nz == 0 and lo is not None and eps[k] <= lo:
            verdict = "unstable: the drive is too weak to hold it up (it falls; below zone 0)"
        elif fl.trace[k] > 0:
            verdict = "unstable: parametric resonance, 2T-type (multipliers real, positive)"
        else:
            verdict = "unstable: parametric resonance, 4T-type, period doubling (multipliers real, negative)"
        scale = T / float(eps[k])  # T = eps sqrt(8 l / A): the zone in T at this A
        out.append(ModeReport(
            index=k + 1, l=float(l[k]), shape=shapes[k], eps=float(eps[k]), mu=mu, stable=stable, verdict=verdict,
            zone=int(fl.zone[k]), nearest_zone=nz, margin=float(mg.margin[k]), growth=float(fl.growth[k]),
            multipliers=tuple(complex(z) for z in fl.multipliers[k]), eps_lo=lo, eps_hi=hi,
            T_lo=_finite(lo * scale) if lo is not None else None,
            T_hi=_finite(hi * scale) if hi is not None else None))
    return tuple(out)


def _finite(v):
    """``v`` as a float, or None where it is missing or not finite (no zone: the single pendulum's NaN)."""
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def _modes_stable(chain, T, A, g, drive):
    """The undamped tower's verdict at arrays ``T, A`` (broadcast): every mode stable."""
    from . import is_stable, to_arnold

    T, A = np.broadcast_arrays(np.asarray(T, float), np.asarray(A, float))
    l = np.array(chain.modal_lengths).reshape((-1,) + (1,) * T.ndim)
    eps, mu = to_arnold(T[None], A[None], l, g)
    return np.all(is_stable(eps, np.broadcast_to(mu, eps.shape), drive=drive), axis=0)


def _ray_edges(stable, x0, reach=1e3, steps_per_octave=16, rtol=1e-10):
    """The edges ``(x_lo, x_hi)`` of the stable interval through ``x0`` of a vectorised predicate
    ``stable(x)``: stepping out by ``2^(1/16)`` (all steps in one call), then bisecting both
    brackets together to ``rtol``. None for an edge not met within a factor ``reach``."""
    j = np.arange(1, int(steps_per_octave * math.log2(reach)) + 1)
    ratio = 2.0 ** (j / steps_per_octave)
    xs = np.concatenate([x0 * ratio, x0 / ratio])
    ok = stable(xs)
    half = len(j)
    brackets = []
    for side in (ok[:half], ok[half:]):
        bad = np.flatnonzero(~side)
        if bad.size == 0:
            brackets.append(None)
        else:
            i = int(bad[0])
            brackets.append((i, ratio[i - 1] if i else 1.0, ratio[i]))
    a = np.array([b[1] if b else 1.0 for b in brackets])  # inside (as a ratio)
    b = np.array([b[2] if b else 1.0 for b in brackets])  # outside
    sign = np.array([1.0, -1.0])
    for _ in range(80):
        if np.all(b / a - 1.0 < rtol):
            break
        mid = np.sqrt(a * b)
        inside = stable(x0 * mid ** sign)
        a, b = np.where(inside, mid, a), np.where(inside, b, mid)
    edge = x0 * np.sqrt(a * b) ** sign
    return (None if brackets[1] is None else float(edge[1]), None if brackets[0] is None else float(edge[0]))


def _rig_band(stable, T, A, stroke, **ray):
    """The stable interval through ``(T, A)`` in frequency at this stroke (``A T^2`` fixed) and in
    stroke at this frequency (``T`` fixed, the stroke proportional to ``A``)."""
    f0 = 0.5 / T
    f_lo, f_hi = _ray_edges(lambda f: stable(0.5 / f, A * (f / f0) ** 2), f0, **ray)
    a_lo, a_hi = _ray_edges(lambda a: stable(np.full(np.shape(a), T), a), A, **ray)
    return dict(frequency_lo=f_lo, frequency_hi=math.inf if f_hi is None else f_hi,
                stroke_lo=None if a_lo is None else stroke * a_lo / A,
                stroke_hi=None if a_hi is None else stroke * a_hi / A)


def _intersect(modes, lo, hi):
    """The intersection of the modes' intervals ``(lo, hi)``, or None where one is missing."""
    los = [getattr(m, lo) for m in modes]
    his = [getattr(m, hi) for m in modes]
    if any(v is None or not math.isfinite(v) for v in los) or any(v is None for v in his):
        return None, None
    return max(los), min(his)


def _modal_report(chain, modes, T, A, g, drive, stroke):
    stable = all(m.stable for m in modes)
    mult = sorted((z for m in modes for z in m.multipliers), key=lambda z: -abs(z))
    growth = max(m.growth for m in modes)
    if stable:
        k = min(range(len(modes)), key=lambda i: modes[i].margin)
        m = modes[k]
        lower = (m.eps - m.eps_lo) <= (m.eps_hi - m.eps)
        failure = _edge_failure(m.zone, lower)
        verdict = (f"stable: every mode in its zone ({', '.join(str(x.zone) for x in modes)}); "
                   f"mode {m.index} (l = {num(m.l, 6)} m) is the nearest to failing: it {_how(failure)} "
                   f"if T {'falls' if lower else 'grows'} by {100 * m.margin:.3g} % at this A")
        margin = m.margin
    else:
        bad = [x for x in modes if not x.stable]
        k = max(range(len(modes)), key=lambda i: (not modes[i].stable, modes[i].growth))
        m = modes[k]
        failure = _verdict_failure(m.verdict)
        which = ", ".join(str(x.index) for x in bad)
        why = m.verdict.split(": ", 1)[-1]
        verdict = (f"unstable: mode{'s' if len(bad) > 1 else ''} {which} of {len(modes)} "
                   f"{'fail' if len(bad) > 1 else 'fails'}; mode {m.index} (l = {num(m.l, 6)} m) grows fastest "
                   f"and {_how(failure)}: {why}")
        margin = min(x.margin for x in modes)
    band = {}
    if stable:
        band["T_lo"], band["T_hi"] = _intersect(modes, "T_lo", "T_hi")
        band.update(_rig_band(lambda T_, A_: _modes_stable(chain, T_, A_, g, drive), T, A, stroke))
    return ChainReport(
        stable=stable, verdict=verdict, T=T, A=A, g=g, stroke=stroke, chain=chain.describe(), drive=drive.describe(),
        modal_lengths=chain.modal_lengths, modes=modes, multipliers=tuple(mult), growth=float(growth),
        critical_mode=m.index, failure=failure, margin=float(margin), method="modes",
        joint_damping=chain.joint_damping, **band)


def _dominant(chain, fl, lower):
    """The mode the largest multiplier's motion is mostly made of (its modal coordinates
    ``q = V^-1 theta``), and how it grows: ``"flutter"`` (complex), ``"period doubling"`` (real,
    negative), ``"falls"`` (real, positive, below the band) or ``"2T resonance"``."""
    q = np.linalg.solve(chain.mode_shapes, fl.vectors[: chain.n, 0])
    k = int(np.argmax(np.abs(q)))
    lam = fl.multipliers[0]
    if abs(lam.imag) > 1e-9 * abs(lam):
        return k, "flutter"
    if lam.real < 0:
        return k, "period doubling"
    return k, "falls" if lower else "2T resonance"


def _coupled_report(chain, modes, T, A, g, drive, stroke):
    fl = chain_floquet(chain, T=T, A=A, g=g, drive=drive)
    lam = fl.multipliers[0]
    band = {}
    if fl.stable:
        def stable_at(Ts, As):
            # the searches settle edges to 1e-10 in T: rounding of the verdict there is immaterial
            return np.array([chain_floquet(chain, T=t, A=a, g=g, drive=drive, _certify=False).stable
                             for t, a in zip(np.ravel(Ts), np.ravel(As))])

        piecewise = _segments(drive, T, A, g) is not None
        # an integrated period costs far more than a segment product: coarser steps, T only
        ray = dict(reach=16.0, steps_per_octave=8 if piecewise else 4, rtol=1e-10 if piecewise else 1e-7)
        T_lo, T_hi = _ray_edges(lambda t: stable_at(t, np.full(np.shape(t), A)), T, **ray)
        band = dict(T_lo=T_lo, T_hi=T_hi)
        if piecewise:
            band.update(_rig_band(stable_at, T, A, stroke, **ray))
        d_lo = 1.0 - T_lo / T if T_lo else math.inf  # as the single pendulum's margin: relative to T
        d_hi = T_hi / T - 1.0 if T_hi else math.inf
        margin = min(d_lo, d_hi)
        # how it fails at the nearer edge: the motion that grows just beyond it
        lower = d_lo <= d_hi
        if math.isfinite(margin):
            beyond = chain_floquet(chain, T=T_lo * (1 - 1e-5) if lower else T_hi * (1 + 1e-5), A=A, g=g, drive=drive)
            k, failure = _dominant(chain, beyond, lower)
            what = (f"; mode {k + 1} (l = {num(chain.modal_lengths[k], 6)} m) is the nearest to failing: it "
                    f"{_how(failure)} if T {'falls' if lower else 'grows'} by {100 * margin:.3g} % at this A")
        else:  # pragma: no cover - a band open on both sides within a factor 16
            k, failure = _dominant(chain, fl, True)
            what = ""
        verdict = (f"stable: all {2 * chain.n} multipliers inside the unit circle (largest |lambda| = "
                   f"{abs(lam):.6g}), motions decay{what}")
    else:
        m0 = modes[0]
        k, failure = _dominant(chain, fl, m0.nearest_zone == 0 and m0.eps_lo is not None and m0.eps <= m0.eps_lo)
        margin = -min(abs(m.margin) for m in modes) if all(m.stable for m in modes) else min(m.margin for m in modes)
        verdict = (f"unstable: |lambda| = {abs(lam):.6g} > 1 (friction couples the modes); the growing motion is "
                   f"mostly mode {k + 1} (l = {num(chain.modal_lengths[k], 6)} m): it {_how(failure)}")
    return ChainReport(
        stable=bool(fl.stable), verdict=verdict, T=T, A=A, g=g, stroke=stroke, chain=chain.describe(),
        drive=drive.describe(), modal_lengths=chain.modal_lengths, modes=modes,
        multipliers=tuple(complex(z) for z in fl.multipliers), growth=float(fl.growth), critical_mode=k + 1,
        failure=failure, margin=float(margin), method=fl.method, joint_damping=chain.joint_damping, **band)


# ====================================================================== the 2N monodromy
@dataclass(frozen=True, repr=False)
class ChainFloquet(Summary):
    """The ``2N`` Floquet data of the tower over one period ``2T``.

    Attributes
    ----------
    multipliers : ndarray of complex, shape (2N,)
        Eigenvalues of the monodromy, largest modulus first.
    vectors : ndarray, shape (2N, 2N)
        The eigenvectors (columns, same order) in ``(theta, theta')``.
    growth : float
        ``log max|lambda|`` per period (formed from the renormalised product: finite).
    stable : bool
        All multipliers strictly inside the unit circle.
    monodromy : ndarray, shape (2N, 2N)
        ``exp(-log_scale)`` times the monodromy.
    log_scale : float
    method : str

    Examples
    --------
    >>> import kapitza
    >>> tower = kapitza.Chain([0.2, 0.2, 0.2], joint_damping=0.01)
    >>> fl = kapitza.chain_floquet(tower, T=0.0025, A=3200.0)
    >>> fl
    <ChainFloquet: stable, growth -5.6771e-05 per period>
    >>> fl.multipliers.shape, bool(abs(fl.multipliers).max() < 1)
    ((6,), True)
    """

    multipliers: np.ndarray
    vectors: np.ndarray
    growth: float
    stable: bool
    monodromy: np.ndarray
    log_scale: float
    method: str

    def lines(self):
        return [("verdict", "stable" if self.stable else "unstable"),
                ("multipliers", _fmt_multipliers(self.multipliers)),
                ("growth", f"{num(self.growth)} per period 2T"), ("method", self.method)]

    def headline(self):
        return f"{'stable' if self.stable else 'unstable'}, growth {num(self.growth)} per period"


def _generator(Minv_K, Minv_C, acc):
    n = Minv_K.shape[0]
    G = np.zeros((2 * n, 2 * n))
    G[:n, n:] = np.eye(n)
    G[n:, :n] = acc * Minv_K
    G[n:, n:] = -Minv_C
    return G


def _segments(drive, T, A, g):
    """``[(g + a_i, duration_i)]`` of a piecewise-constant drive, or None."""
    levels = getattr(drive, "levels", None)
    fractions = getattr(drive, "fractions", None)
    if levels is None or fractions is None:
        return None
    return [(g + A * float(s), 2.0 * T * float(f)) for s, f in zip(levels, fractions)]


def chain_floquet(chain, *, T, A, g=G_EARTH, drive=None, rtol=1e-12, _certify=True) -> ChainFloquet:
    """The tower's ``2N`` monodromy, multipliers and growth at ``(T, A)``, friction included.

    Parameters
    ----------
    chain : Chain
    T, A, g : float
        Half-period [s], acceleration scale [m/s^2], gravity [m/s^2].
    drive : Drive or str, optional
        Square wave by default.
    rtol : float
        Tolerance of the integrated period (drives that are not piecewise constant).

    Returns
    -------
    ChainFloquet

    Raises
    ------
    ValueError
        If ``T``, ``A`` or ``g`` is out of range (a period over which the shortest mode could grow
        beyond a double's range is refused too), or ``drive`` names no drive.

    Notes
    -----
    Piecewise-constant drives: the exact product of the segment exponentials
    ``exp(G_i h_i)`` (:func:`scipy.linalg.expm`), a segment cut into pieces of
    ``||G_i|| h_i <= 8`` and the product renormalised after each so nothing overflows; other
    drives: DOP853 over one period. A verdict within 1e-9 of ``|lambda| = 1`` is settled in
    mpmath at 40 digits (piecewise-constant drives).

    Examples
    --------
    >>> import kapitza
    >>> tower = kapitza.Chain([0.2, 0.2, 0.2], joint_damping=0.01)
    >>> kapitza.chain_floquet(tower, T=0.0025, A=3200.0).stable
    True
    >>> kapitza.chain_floquet(tower, T=0.0025, A=3200.0, drive="sine")
    <ChainFloquet: unstable, growth 0.0108... per period>
    >>> kapitza.chain_floquet(tower, T=1 / 120, A=200.0).growth
    0.1534...
    """
    from .drives import as_drive

    if not isinstance(chain, Chain):
        raise _v.KapitzaValueError(f"chain must be a kapitza.Chain; got {chain!r}")
    d = as_drive(drive)
    T = _v.one("T", _v.positive("T", T))
    A = _v.one("A", _v.positive("A", A))
    g = _v.one("g", _v.positive("g", g))
    rtol = _v.one("rtol", _v.in_range("rtol", rtol, 1e-14, 1e-3, lo_open=False, hi_open=False))
    scale_check(chain, T, A, g, d)
    Minv_K, Minv_C = chain._modes[2]
    segs = _segments(d, T, A, g)
    if segs is not None:
        P, L = _segment_product(Minv_K, Minv_C, segs)
        method = "exact product of segment exponentials"
    else:
        P, L = _integrated_period(Minv_K, Minv_C, d, T, A, g, rtol)
        method = f"integrated period (DOP853, rtol {rtol:g})"
    w, vec = np.linalg.eig(P)
    order = np.argsort(-np.abs(w), kind="stable")
    w, vec = w[order], vec[:, order]
    with np.errstate(divide="ignore"):
        growth = float(np.log(np.abs(w[0])) + L)
    stable = growth < 0.0
    if chain.joint_damping == 0.0:
        # without friction the multipliers of a stable tower lie on the unit circle, where rounding
        # puts the largest on either side: the verdict is every mode's, certified as the single
        # pendulum's (docs/tower.md), and a stable tower's growth is 0
        stable = bool(_modes_stable(chain, T, A, g, d))
        if stable:
            growth = 0.0
        method += " (verdict of the modes)"
    elif _certify and segs is not None and abs(growth) < 1e-9:
        growth = _growth_mp(chain, segs)
        stable = growth < 0.0
        method += " (verdict settled in mpmath)"
    with np.errstate(over="ignore", under="ignore"):
        if L < 700:
            mult = w * math.exp(L)
        else:   # beyond a double: each nonzero part infinite (0 times inf would be NaN)
            w = np.asarray(w, complex)
            mult = np.empty(w.shape, complex)
            mult.real = np.where(w.real != 0, np.copysign(np.inf, w.real), 0.0)
            mult.imag = np.where(w.imag != 0, np.copysign(np.inf, w.imag), 0.0)
    return ChainFloquet(multipliers=mult, vectors=vec, growth=growth, stable=bool(stable), monodromy=P,
                        log_scale=float(L), method=method)


# Pade(13) coefficients and its scaling threshold theta_13 (Higham, SIAM J. Matrix Anal. Appl. 26, 2005)
_B13 = (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0, 129060195264000.0,
        10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0, 1.0)
_THETA13 = 5.371920351148152


def _expm(G):
    """``exp(G)`` by scaling and squaring with the [13/13] Pade approximant (Higham 2005).

    The chain's matrices are small (``2N x 2N``); numpy's products and solve are used rather than
    :func:`scipy.linalg.expm`, whose small-matrix kernels were measured 100-300x slower on a busy
    machine (threaded BLAS). Checked against ``mpmath.expm`` in ``tests/test_tower_oracle.py``."""
    norm = np.linalg.norm(G, 1)
    s = max(0, int(math.ceil(math.log2(norm / _THETA13)))) if norm > _THETA13 else 0
    X = G / 2.0**s
    b = _B13
    I = np.eye(G.shape[0])
    X2 = X @ X
    X4 = X2 @ X2
    X6 = X4 @ X2
    U = X @ (X6 @ (b[13] * X6 + b[11] * X4 + b[9] * X2) + b[7] * X6 + b[5] * X4 + b[3] * X2 + b[1] * I)
    V = X6 @ (b[12] * X6 + b[10] * X4 + b[8] * X2) + b[6] * X6 + b[4] * X4 + b[2] * X2 + b[0] * I
    R = np.linalg.solve(V - U, V + U)
    for _ in range(s):
        R = R @ R
    return R


def _segment_product(Minv_K, Minv_C, segs):
    """``exp(G_K h_K) ... exp(G_1 h_1) = e^L P`` with ``max|P| = 1``: a segment whose exponent
    could overflow (``||G h||_1 > 256``) is ``exp(G h / 2^k)`` squared ``k`` times, renormalised
    after every squaring."""
    P = np.eye(2 * Minv_K.shape[0])
    L = 0.0
    for acc, h in segs:
        G = _generator(Minv_K, Minv_C, acc) * h
        k = max(0, int(math.ceil(math.log2(np.linalg.norm(G, 1) / 256.0)))) if np.linalg.norm(G, 1) > 256.0 else 0
        if k > 60:
            raise _v.KapitzaValueError(
                f"the drive segment of {h:g} s is beyond what the segment product resolves for this tower "
                f"(||G h|| = {np.linalg.norm(G, 1):.3g})")
        E = _expm(G / 2.0**k)
        Ls = 0.0
        for _ in range(k):
            E = E @ E
            sc = np.max(np.abs(E))
            E /= sc
            Ls = 2.0 * Ls + math.log(sc)
        P = E @ P
        sc = np.max(np.abs(P))
        P /= sc
        L += Ls + math.log(sc)
    return P, L


def _integrated_period(Minv_K, Minv_C, drive, T, A, g, rtol):
    from scipy.integrate import solve_ivp

    n2 = 2 * Minv_K.shape[0]

    def rhs(t, y):
        tau = np.mod(t / T, 2.0)
        G = _generator(Minv_K, Minv_C, g + A * float(drive._shape(np.array(tau))))
        return (G @ y.reshape(n2, n2)).ravel()

    # the period cut at the drive's own breaks is not needed for a smooth shape; max_step keeps
    # DOP853 from stepping over a short feature of the acceleration
    sol = solve_ivp(rhs, (0.0, 2.0 * T), np.eye(n2).ravel(), method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                    max_step=2.0 * T / 64)
    if not sol.success:  # pragma: no cover - DOP853 on a linear system with smooth coefficients
        raise RuntimeError(f"the period could not be integrated: {sol.message}")
    P = sol.y[:, -1].reshape(n2, n2)
    s = np.max(np.abs(P))
    return P / s, math.log(s)


def _growth_mp(chain, segs, dps=40):
    """``log max|lambda|`` from the segment product in mpmath (a verdict rounding cannot settle)."""
    import mpmath as mp

    with mp.workdps(dps):
        M = mp.matrix(chain.mass_matrix().tolist())
        K = mp.matrix(chain.stiffness_matrix().tolist())
        C = mp.matrix(chain.damping_matrix().tolist())
        n = chain.n
        Minv = mp.inverse(M)
        MK, MC = Minv * K, Minv * C
        P = mp.eye(2 * n)
        for acc, h in segs:
            G = mp.zeros(2 * n, 2 * n)
            for i in range(n):
                G[i, n + i] = 1
                for j in range(n):
                    G[n + i, j] = mp.mpf(acc) * MK[i, j]
                    G[n + i, n + j] = -MC[i, j]
            P = mp.expm(G * mp.mpf(h)) * P
        ev = mp.eig(P, left=False, right=False)
        return float(mp.log(max(abs(z) for z in ev)))


# ====================================================================== the tower's chart (rig plane)
@dataclass(frozen=True, repr=False)
class TowerCurves(Summary):
    """The tower's stable band on the rig plane (drive frequency [Hz] against stroke [m]).

    Attributes
    ----------
    modal_lengths : tuple of float
        ``l_k``, longest first.
    mu : ndarray, shape (P,)
        The ``mu = sqrt(g/A)`` samples of the edge curves.
    frequency_lo, stroke_lo : ndarray, shape (N, P)
        Mode ``k``'s lower edge of zone 0 (a 2T-periodic motion; below it the mode falls).
    frequency_hi, stroke_hi : ndarray, shape (N, P)
        Mode ``k``'s upper edge of zone 0 (4T-periodic: beyond it the mode doubles its period).
    frequency, stroke : ndarray, shapes (F,), (S,)
        The grid of the band.
    stable : ndarray of bool, shape (S, F)
        The tower's verdict on the grid (every mode, every zone; with friction the 2N monodromy's).
    frequency_range, stroke_range : tuple
        The window.
    drive, chain : str
        Descriptions.

    Examples
    --------
    >>> import kapitza
    >>> band = kapitza.tower_curves(kapitza.Chain([0.2, 0.2, 0.2]), points=50, grid=30)
    >>> band
    <TowerCurves: band of a 3-link tower, square wave (+A for T, -A for T)>
    >>> band.frequency_lo.shape, band.stable.shape
    ((3, 49), (30, 30))
    """

    modal_lengths: tuple
    mu: np.ndarray
    frequency_lo: np.ndarray
    stroke_lo: np.ndarray
    frequency_hi: np.ndarray
    stroke_hi: np.ndarray
    frequency: np.ndarray
    stroke: np.ndarray
    stable: np.ndarray
    frequency_range: tuple
    stroke_range: tuple
    drive: str
    chain: str
    n_links: int

    def rows(self):
        """``(mode, l, edge, mu, frequency, stroke)`` rows of the edge curves, for CSV."""
        for k, l in enumerate(self.modal_lengths):
            for edge, F, S in (("lower (falls)", self.frequency_lo, self.stroke_lo),
                               ("upper (period doubling)", self.frequency_hi, self.stroke_hi)):
                for j, m in enumerate(self.mu):
                    if np.isfinite(F[k, j]) and np.isfinite(S[k, j]):
                        yield k + 1, l, edge, float(m), float(F[k, j]), float(S[k, j])

    def as_dict(self) -> dict:
        return {"chain": self.chain, "drive": self.drive, "modal_lengths": list(self.modal_lengths),
                "frequency_range": list(self.frequency_range), "stroke_range": list(self.stroke_range),
                "modes": [{"mode": k + 1, "l": l,
                           "lower": {"frequency": _finite_list(self.frequency_lo[k]),
                                     "stroke": _finite_list(self.stroke_lo[k])},
                           "upper": {"frequency": _finite_list(self.frequency_hi[k]),
                                     "stroke": _finite_list(self.stroke_hi[k])}}
                          for k, l in enumerate(self.modal_lengths)],
                "mu": self.mu.tolist(),
                "band": {"frequency": self.frequency.tolist(), "stroke": self.stroke.tolist(),
                         "stable": self.stable.astype(int).tolist()}}

    def lines(self):
        return [("tower", self.chain), ("drive", self.drive),
                ("window", f"frequency {num(self.frequency_range[0])} .. {num(self.frequency_range[1])} Hz, stroke "
                           f"{num(1e3 * self.stroke_range[0])} .. {num(1e3 * self.stroke_range[1])} mm"),
                ("stable", f"{100 * float(np.mean(self.stable)):.3g} % of the window (log grid)")]

    def headline(self):
        return f"band of a {self.n_links}-link tower, {self.drive}"


def _finite_list(a):
    return [float(x) if np.isfinite(x) else None for x in a]


def _mode_edges(drive, l, g, mu, n=0):
    """Zone ``n``'s edges of a pendulum ``l`` as (frequency, stroke) curves along ``mu`` (to a pixel:
    each edge as the drive's search leaves it, ``zone_edges(..., certify=False)``)."""
    try:
        lo, hi = zone_edges(mu, n, drive=drive, certify=False)
    except _v.KapitzaValueError:
        # a drive's solver refuses the edges nearest mu = 1 (the sine beyond q = 1e8), far below
        # any window's frequencies: keep the longest prefix of the increasing mu it takes, NaN beyond
        good, bad = 0, mu.size
        while bad - good > 1:
            mid = (good + bad) // 2
            try:
                zone_edges(mu[mid], n, drive=drive, certify=False)
                good = mid
            except _v.KapitzaValueError:
                bad = mid
        if bad == 0 or mu.size < 2:
            raise
        lo, hi = np.full(mu.size, np.nan), np.full(mu.size, np.nan)
        lo[:bad], hi[:bad] = (np.asarray(a, float)
                              for a in zone_edges(mu[:bad], n, drive=drive, certify=False))
    A = g / mu**2
    out = []
    for eps in (lo, hi):
        with np.errstate(invalid="ignore"):
            T = eps * np.sqrt(8.0 * l / A)
            out.append((0.5 / T, drive._stroke_coefficient * A * T * T))
    return out


def default_window(chain, drive=None, g=G_EARTH):
    """A rig-plane window showing the tower's whole band: the stroke from 1/100 of the band's
    top (the shortest mode's period doubling at high frequency) to 5 times it, the frequency from
    a fifth of the band's lowest (where the longest mode's lower edge meets that stroke) to 30 times it.

    Parameters
    ----------
    chain : Chain
    drive : Drive or str, optional
        The paper's square wave by default.
    g : float
        Gravity [m/s^2], 1e-3 .. 1e3.

    Returns
    -------
    ((float, float), (float, float))
        ``((frequency_min, frequency_max), (stroke_min, stroke_max))`` [Hz], [m].

    Raises
    ------
    ValueError
        If ``g`` is out of range or ``drive`` names no drive.

    Examples
    --------
    >>> import kapitza
    >>> from kapitza.chain import default_window
    >>> default_window(kapitza.Chain([0.2, 0.2, 0.2]))
    ((10.6107..., 1591.6162...), (0.0001..., 0.0820...))
    """
    from .drives import as_drive

    d = as_drive(drive)
    g = _v.one("g", _v.in_range("g", g, 1e-3, 1e3, lo_open=False, hi_open=False))
    if not 2e-3 < d.mu_max:
        raise _v.KapitzaValueError(f"the drive's mu_max = {d.mu_max:.3g} leaves no window to draw "
                                   "(it needs mu_max > 2e-3)")
    with np.errstate(all="ignore"):
        (_, _), (_, s_top) = _mode_edges(d, chain.modal_lengths[-1], g, np.array([1e-3]))
        s_top = float(s_top[0])
        mu = np.geomspace(1e-3, 0.9 * d.mu_max, 400)
        (f1, s1), _ = _mode_edges(d, chain.modal_lengths[0], g, mu)
        ok = np.isfinite(f1) & np.isfinite(s1) & (f1 > 0) & (s1 > 0)
        if not ok.any() or not (math.isfinite(s_top) and s_top > 0):
            raise _v.KapitzaValueError("no window found for this tower and drive: "
                                       "give frequency_range and stroke_range")
        order = np.argsort(s1[ok])
        f_c = float(np.exp(np.interp(np.log(s_top), np.log(s1[ok][order]), np.log(f1[ok][order]))))
    return (f_c / 5.0, 30.0 * f_c), (s_top / 100.0, 5.0 * s_top)


def tower_curves(chain, drive=None, g=G_EARTH, frequency_range=None, stroke_range=None, points=600, grid=None):
    """The tower's band on the rig plane: each mode's zone-0 edges and the verdict on a grid.

    Parameters
    ----------
    chain : Chain
    drive : Drive or str, optional
    g : float
        Gravity [m/s^2], 1e-3 .. 1e3.
    frequency_range, stroke_range : (float, float), optional
        The window [Hz], [m]; :func:`default_window` by default.
    points : int
        ``mu`` samples per edge curve (2 .. 20000).
    grid : int, optional
        Grid points per axis for the band: 200 by default (2 .. 2000); with joint friction each
        point is a ``2N`` monodromy, so 60 by default there (2 .. 400).

    Returns
    -------
    TowerCurves

    Raises
    ------
    ValueError
        If ``g``, ``points``, ``grid`` or a window is out of range, or ``drive`` names no drive.

    Notes
    -----
    Mode ``k`` is the pendulum ``l_k``: its zone-0 edges ``eps_lo(mu), eps_hi(mu)``
    (:func:`kapitza.zone_edges`) map to ``A = g / mu^2``, ``T = eps sqrt(8 l_k / A)``,
    frequency ``1/(2T)`` and stroke ``k_s A T^2 = 8 k_s l_k eps^2`` (``k_s`` the drive's stroke
    coefficient): on log axes the modes' curves are copies shifted by ``l_k``. The band is
    where every mode is stable (:func:`kapitza.is_stable` of each mode on the grid).

    Examples
    --------
    >>> import kapitza
    >>> band = kapitza.tower_curves(kapitza.Chain([0.2, 0.2, 0.2]), points=50, grid=30)
    >>> band.frequency_range, band.stroke_range
    ((10.6107..., 1591.6162...), (0.0001..., 0.0820...))
    >>> round(float(band.stable.mean()), 3)
    0.182
    """
    from .drives import as_drive

    if not isinstance(chain, Chain):
        raise _v.KapitzaValueError(f"chain must be a kapitza.Chain; got {chain!r}")
    d = as_drive(drive)
    g = _v.one("g", _v.in_range("g", g, 1e-3, 1e3, lo_open=False, hi_open=False))
    points = int(_v.bounded_count("points", points, 20_000, minimum=2))
    coupled = chain.joint_damping > 0  # one link too: the damped pendulum's verdict, not the free one's
    if grid is None:
        grid = 60 if coupled else 200
    grid = int(_v.bounded_count("grid", grid, 400 if coupled else 2000, minimum=2))
    fr0, sr0 = default_window(chain, d, g)
    fr = fr0 if frequency_range is None else _window("frequency_range", frequency_range)
    sr = sr0 if stroke_range is None else _window("stroke_range", stroke_range)
    # the mu the window reaches: A = stroke / (k T^2) = 4 k^-1 stroke f^2
    k_s = d._stroke_coefficient
    A_lo, A_hi = 4.0 * sr[0] * fr[0] ** 2 / k_s, 4.0 * sr[1] * fr[1] ** 2 / k_s
    mu_a = max(math.sqrt(g / A_hi), 1e-6)
    mu_b = min(math.sqrt(g / A_lo), d.mu_max * (1 - 1e-9))
    if mu_a >= mu_b:
        mu = np.array([min(mu_a, 0.5 * d.mu_max)])
    else:
        # log-spaced, and as densely towards mu_max, where the edges run off to low frequency
        top = d.mu_max - np.geomspace(d.mu_max - mu_b, max(d.mu_max - mu_a, 1e-9), points // 2)
        mu = np.unique(np.concatenate([np.geomspace(mu_a, mu_b, points - points // 2),
                                       top[(top > mu_a) & (top < mu_b)]]))
    F_lo, S_lo, F_hi, S_hi = [], [], [], []
    for l in chain.modal_lengths:
        (f1, s1), (f2, s2) = _mode_edges(d, l, g, mu)
        F_lo.append(f1), S_lo.append(s1), F_hi.append(f2), S_hi.append(s2)
    f = np.geomspace(fr[0], fr[1], grid)
    s = np.geomspace(sr[0], sr[1], grid)
    Fg, Sg = np.meshgrid(f, s)
    Tg = 0.5 / Fg
    Ag = Sg / (k_s * Tg * Tg)
    if coupled:
        stable = np.array([chain_floquet(chain, T=t, A=a, g=g, drive=d, _certify=False).stable
                           for t, a in zip(Tg.ravel(), Ag.ravel())]).reshape(Tg.shape)
    else:
        stable = _modes_stable(chain, Tg, Ag, g, d)
    return TowerCurves(modal_lengths=chain.modal_lengths, mu=mu, frequency_lo=np.array(F_lo), stroke_lo=np.array(S_lo),
                       frequency_hi=np.array(F_hi), stroke_hi=np.array(S_hi), frequency=f, stroke=s, stable=stable,
                       frequency_range=tuple(fr), stroke_range=tuple(sr), drive=d.describe(), chain=chain.describe(),
                       n_links=chain.n)


#: the most e-folds ``sqrt((g + A max s) / l_N) 2T`` of the fastest mode over one period that the
#: double-precision products and integrations are asked to resolve
MAX_EFOLDS = 1e4


def scale_check(chain, T, A, g, drive):
    """Refuse (:class:`kapitza.KapitzaValueError`) a period ``2T`` over which the chain's shortest
    mode could grow by more than ``e^MAX_EFOLDS`` under ``drive`` (checked input)."""
    peak = drive.peak
    with np.errstate(over="ignore"):
        x = math.sqrt((g + A * peak) / chain.modal_lengths[-1]) * 2.0 * T
    if not x <= MAX_EFOLDS:
        raise _v.KapitzaValueError(
            f"T, A and g (T = {T!r} s, A = {A!r} m/s^2, g = {g!r} m/s^2) let this tower's shortest mode grow by "
            f"e^{x:.3g} over one period, beyond the e^{MAX_EFOLDS:g} a double resolves: give a smaller T, A or g")


def _window(name, value):
    try:
        lo, hi = (float(x) for x in value)
    except (TypeError, ValueError):
        raise _v.KapitzaValueError(f"{name} must be two numbers (low, high); got {value!r}") from None
    if not (0.0 < lo < hi < math.inf):
        raise _v.KapitzaValueError(f"{name} must satisfy 0 < low < high < inf; got ({lo!r}, {hi!r})")
    return lo, hi
