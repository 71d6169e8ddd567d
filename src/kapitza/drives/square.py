"""The paper's drive (2.2): ``+A`` for ``T``, then ``-A`` for ``T``.

Its Floquet data and zone edges are the closed forms of Theorems 3.3-3.4 and Corollary 4.1
(:mod:`kapitza._exact`, :mod:`kapitza.zones`): the fast path every other function keeps.
With damping the generic layer of :mod:`kapitza.drives._base` applies these same closed
forms at ``mu_c = mu sqrt(1 + zeta^2)`` (``docs/drives.md``, "The damped square wave").
"""
from __future__ import annotations

import numpy as np

from ._base import Floquet0, log_cosh
from ._piecewise import PiecewiseConstant


class SquareWave(PiecewiseConstant):
    """The paper's symmetric square wave: acceleration ``+A`` on ``[0, T)``, ``-A`` on ``[T, 2T)``."""

    name = "square"

    def __init__(self):
        super().__init__((1.0, -1.0), (0.5, 0.5))

    def _floquet0(self, eps, mu, certify=True):
        from ..propagation import _floquet

        tau, growth, theta, stable, zone = _floquet(eps, mu)
        with np.errstate(divide="ignore"):
            log_tau = np.where(np.isfinite(tau), np.log(np.abs(tau)), log_cosh(growth))
        return Floquet0(tau=tau, log_tau=log_tau, growth=growth, theta=theta, zone=zone)

    def _log_tau0(self, eps, mu):
        return self._floquet0(eps, mu, certify=False).log_tau

    def _edges0(self, mu, n):
        from ..zones import _edges_eps

        mu, n = np.broadcast_arrays(np.asarray(mu, float), np.asarray(n, np.int64))
        ok = mu < 1.0
        lo, hi = _edges_eps(np.where(ok, mu, 0.5), n)
        return np.where(ok, lo, np.nan), np.where(ok, hi, np.nan)

    def as_dict(self) -> dict:
        return {"drive": self.name}

    @property
    def label(self) -> str:
        return "square wave"

    def describe(self) -> str:
        return "square wave (+A for T, -A for T)"
