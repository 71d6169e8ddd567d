"""One start, two models: the nonlinear motion beside its linearisation (2.3).

What ``kapitza simulate`` writes and the explorer animates: both motions from the same
``(theta0, dtheta0)`` on the same samples, the pivot's height, the stroboscopic points
``t = 2kT``, and a summary of each motion.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..parameters import G_EARTH
from .nonlinear import Trajectory, simulate

__all__ = ["MotionPair", "motion_pair", "parameters_summary"]


def parameters_summary(T, A, l, g, report) -> dict:
    """The parameters of a motion with their Arnold form and verdict (:class:`kapitza.StabilityReport`)."""
    return dict(T=T, A=A, l=l, g=g, eps=report.eps, mu=report.mu, verdict=report.verdict, stable=report.stable,
                zone=report.zone)


@dataclass(frozen=True)
class MotionPair:
    """The motion of a model (``motion``) and, for comparison, the linear one (``linear``).

    Attributes
    ----------
    motion : Trajectory
        The nonlinear motion (or the linear one when only that was asked for).
    linear : Trajectory or None
        The linear motion on the same samples; None where it was not asked for or
        exceeds a double (then ``linear_note`` says so).
    linear_note : str or None

    Examples
    --------
    >>> from kapitza.motion import motion_pair
    >>> pair = motion_pair(0.1, 0.0, 0.15, 100.0, periods=5)
    >>> pair.motion
    <Trajectory: nonlinear (exact), T = 0.15 s, A = 100 m/s^2, 5 periods, 1001 samples,
     max |theta| = 0.4013 rad, stays up>
    >>> pair.linear.model, pair.linear_note
    ('linear', None)
    """

    motion: Trajectory
    linear: Trajectory | None = None
    linear_note: str | None = None

    def table(self):
        """``(header, columns, comments)``: the CSV ``kapitza simulate --out`` writes."""
        tr, lin = self.motion, self.linear
        header = ["t", "theta", "dtheta", "pivot_y"] + (["theta_linear", "dtheta_linear"] if lin is not None else [])
        cols = [tr.t, tr.theta, tr.dtheta, tr.pivot] + ([lin.theta, lin.dtheta] if lin is not None else [])
        comments = [f"kapitza simulate: T = {tr.T!r} s, A = {tr.A!r} m/s^2, l = {tr.l!r} m, g = {tr.g!r} m/s^2, "
                    f"c = {tr.c!r} 1/s",
                    f"{tr.model} model ({tr.method}); theta from the upright [rad], dtheta [rad/s], pivot_y [m]"]
        return header, cols, comments

    def summary(self, report=None) -> dict:
        """Summaries of the motion and of the linear one (or the note why it is absent); with the
        :class:`kapitza.StabilityReport` of the parameters, what ``kapitza simulate --json`` prints."""
        out: dict[str, Any] = {}
        if report is not None:
            tr = self.motion
            out["parameters"] = parameters_summary(tr.T, tr.A, tr.l, tr.g, report)
        out.update(theta0=self.motion.theta0, dtheta0=self.motion.dtheta0, motion=self.motion.summary())
        if self.linear is not None:
            out["linear"] = self.linear.summary()
        elif self.linear_note:
            out["linear"] = self.linear_note
        return out

    def as_dict(self) -> dict:
        """Everything sampled, for drawing: times, both motions, the pivot, the strobe points."""
        tr, lin = self.motion, self.linear
        tk, th, om = tr.strobe()
        strobe = dict(t=tk, theta=th, dtheta=om)
        if lin is not None:
            _, th_l, om_l = lin.strobe()
            strobe.update(theta_linear=th_l, dtheta_linear=om_l)
        return dict(T=tr.T, A=tr.A, l=tr.l, g=tr.g, c=tr.c, drive=tr.drive.describe(),
                    t=tr.t, pivot=tr.pivot, theta=tr.theta, dtheta=tr.dtheta,
                    theta_linear=None if lin is None else lin.theta, dtheta_linear=None if lin is None else lin.dtheta,
                    strobe=strobe, summary=self.summary())


def motion_pair(theta0, dtheta0, T, A, l=1.0, g=G_EARTH, *, model="nonlinear", compare_linear=True, **kwargs):
    """Simulate ``model`` from ``(theta0, dtheta0)`` and, with ``compare_linear``, the linear model too.

    Parameters
    ----------
    theta0, dtheta0, T, A, l, g :
        As in :func:`kapitza.simulate`.
    model : {'nonlinear', 'linear'}
    compare_linear : bool
        Also simulate the linear equation (2.3) on the same samples (when ``model`` is nonlinear).
    **kwargs :
        ``periods``, ``points_per_period``, ``damping``, ``zeta``, ``method``, ``rtol``, ``atol``, ``drive`` of
        :func:`kapitza.simulate`.

    Returns
    -------
    MotionPair
        The linear motion is left out, with a note, where it grows beyond a double.

    Raises
    ------
    ValueError
        As in :func:`kapitza.simulate`.

    Examples
    --------
    Started 0.5 rad from the upright the real pendulum falls over and turns; the linear model,
    whose motion only scales with the start, stays near the upright:

    >>> from kapitza.motion import motion_pair
    >>> pair = motion_pair(0.5, 0.0, 0.15, 100.0, periods=5)
    >>> float(abs(pair.motion.theta).max()), float(abs(pair.linear.theta).max())
    (11.1671..., 1.9380...)
    """
    traj = simulate(theta0, dtheta0, T, A, l, g, model=model, **kwargs)
    linear, note = None, None
    if compare_linear and model == "nonlinear":
        try:
            linear = simulate(theta0, dtheta0, T, A, l, g, model="linear", **kwargs)
        except OverflowError as exc:
            note = f"linear motion not shown: {exc}"
    return MotionPair(traj, linear, note)
