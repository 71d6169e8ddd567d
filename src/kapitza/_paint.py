"""A stability grid painted from zone edges, made equal to the pointwise verdict at its own doubles.

Every painter (the square wave's closed forms, the generic window of edges, the sine's counts)
fills each row between the edges of its zones; the pixels that lie so near an edge that the edge's
rounding could put them on the wrong side are then decided point by point, certified.
"""
from __future__ import annotations

import numpy as np

#: Pixels within this relative distance of a painted edge are decided pointwise (certified): the
#: edges of the closed forms and of the searches lie within a few ulp of the certified crossing,
#: far closer than this; farther pixels are on the side the interval says.
_EDGE_BAND = 1e-12


def settle_near_edges(eps, out, rows, lo, hi, i0, i1, verdict, band=None):
    """Repaint the pixels of ``out`` (painted from the edges ``lo``, ``hi`` of the rows ``rows``;
    ``i0``, ``i1`` the first pixels above each) that lie within :data:`_EDGE_BAND` of an edge with
    ``verdict(eps, rows)`` (boolean, certified; ``rows`` the row of each point), so that the grid
    equals ``is_stable`` at its own doubles; a normal grid has no pixel there, which the pixels on
    either side of each edge tell at the cost of a comparison. ``band``: relative, instead of
    :data:`_EDGE_BAND` (the edges of a drive given by its shape lie within about ``1e-12`` of the
    certified ones, not a few ulp)."""
    W = eps.size
    band = _EDGE_BAND if band is None else band

    def near(edge, i):
        below = np.where(i > 0, eps[np.maximum(i - 1, 0)], -np.inf)
        above = np.where(i < W, eps[np.minimum(i, W - 1)], np.inf)
        with np.errstate(invalid="ignore"):
            return (below >= edge * (1.0 - band)) | (above <= edge * (1.0 + band))

    sel_lo, sel_hi = near(lo, i0), near(hi, i1)
    if not (sel_lo.any() or sel_hi.any()):
        return out
    e = np.concatenate([lo[sel_lo], hi[sel_hi]])
    r = np.concatenate([rows[sel_lo], rows[sel_hi]])
    ok = np.isfinite(e)
    e, r = e[ok], r[ok]
    i0 = np.searchsorted(eps, e * (1.0 - band), side="left")
    i1 = np.searchsorted(eps, e * (1.0 + band), side="right")
    counts = i1 - i0
    if not counts.any():
        return out
    rr = np.repeat(r, counts)
    jj = np.repeat(i0, counts) + np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    key = np.unique(rr * eps.size + jj)
    rr, jj = key // eps.size, key % eps.size
    out[rr, jj] = np.asarray(verdict(eps[jj], rr), bool)
    return out
