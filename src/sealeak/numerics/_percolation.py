"""Connectivity of the non-contact (fluid) area and its percolation threshold.

Clusters are 4-connected (site percolation on the square lattice, threshold p_c = 0.592746 for
the occupied fraction; Newman & Ziff, PRL 85 (2000) 4104; docs/theory.md §6.4). The cell is open along x (axis 0:
inlet row x = 0, outlet row x = N-1) and periodic along y (axis 1): clusters that meet across the
y = 0 / y = N-1 seam are merged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..errors import InputError
from ._contact import ContactResult, solve_contact
from ._xp import to_numpy

IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

_FOUR = ndimage.generate_binary_structure(2, 1)


def _as_mask(mask: ArrayLike, name: str = "fluid_mask") -> BoolArray:
    m = to_numpy(mask)  # a mask on a GPU (a contact solved there) is labelled on the host
    if m.ndim != 2 or min(m.shape) < 1:
        raise InputError(name, f"array of shape {m.shape}", "must be a 2D boolean array")
    if m.dtype != np.bool_:
        if not np.isin(m, (0, 1)).all():
            raise InputError(name, f"array of dtype {m.dtype}", "must be boolean (or 0/1)")
        m = m.astype(bool)
    return m


def label_clusters(fluid_mask: ArrayLike, periodic_axis: int | None = 1) -> tuple[IntArray, int]:
    """Label 4-connected clusters of True cells, merging across the periodic axis.

    Returns ``(labels, count)``: labels 1..count on cluster cells, 0 elsewhere (consecutive after
    merging). ``periodic_axis`` is 1 (y, default), 0, or None (no periodic merging).
    Work: one scipy.ndimage.label pass plus a connected-components solve on the graph of label
    pairs facing each other across the seam (no Python loop over cells or labels).
    """
    m = _as_mask(fluid_mask)
    labels, count = ndimage.label(m, structure=_FOUR)
    labels = labels.astype(np.int64, copy=False)
    if periodic_axis is None or count == 0:
        return labels, int(count)
    if periodic_axis not in (0, 1):
        raise InputError("periodic_axis", periodic_axis, "allowed: 0, 1 or None")
    if periodic_axis == 1:
        a, b = labels[:, 0], labels[:, -1]
    else:
        a, b = labels[0, :], labels[-1, :]
    both = (a > 0) & (b > 0)
    if not both.any():
        return labels, int(count)
    # union of labels meeting across the seam: connected components of the label graph
    graph = coo_matrix((np.ones(int(both.sum())), (a[both], b[both])), shape=(count + 1, count + 1))
    _, comp = connected_components(graph, directed=False)
    # relabel to consecutive 1..k, keeping 0 for background (comp[0] is background's own component)
    used = np.zeros(comp.max() + 1, dtype=bool)
    used[comp[1:]] = True
    new_id = np.cumsum(used)  # component -> 1..k
    lut = np.empty(count + 1, dtype=np.int64)
    lut[0] = 0
    lut[1:] = new_id[comp[1:]]
    return lut[labels], int(new_id[-1])


def spanning_mask(fluid_mask: ArrayLike, periodic_axis: int | None = 1) -> BoolArray:
    """Cells of the clusters that touch both the inlet row (x = 0) and the outlet row (x = N-1)."""
    labels, count = label_clusters(fluid_mask, periodic_axis)
    if count == 0:
        return np.zeros(labels.shape, dtype=bool)
    inlet = np.zeros(count + 1, dtype=bool)
    outlet = np.zeros(count + 1, dtype=bool)
    inlet[labels[0, :]] = True
    outlet[labels[-1, :]] = True
    keep = inlet & outlet
    keep[0] = False
    return keep[labels]


def spans(fluid_mask: ArrayLike, periodic_axis: int | None = 1) -> bool:
    """True if a fluid cluster connects the inlet row x = 0 with the outlet row x = N-1."""
    labels, count = label_clusters(fluid_mask, periodic_axis)
    if count == 0:
        return False
    a = np.unique(labels[0, :])
    b = np.unique(labels[-1, :])
    common = np.intersect1d(a[a > 0], b[b > 0])
    return bool(common.size)


def critical_constriction(gap: ArrayLike, fluid_mask: ArrayLike, periodic_axis: int | None = 1) -> float:
    """The gap (m, the unit of ``gap``) of the narrowest constriction on the widest path from the inlet row x = 0 to
    the outlet row x = N-1: the largest h such that the cells of ``fluid_mask`` with gap >= h still connect them
    (a max–min path, the critical constriction of docs/theory.md eq. 12.5); NaN where the fluid
    does not span at all. Binary search over the distinct gaps of the fluid cells: about log2(N²) labellings.
    """
    g = np.asarray(gap, dtype=float)
    m = _as_mask(fluid_mask)
    if not spans(m, periodic_axis):
        return float("nan")
    values = np.unique(g[m])
    lo, hi = 0, values.size - 1  # the fluid spans with every gap >= values[lo]
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if spans(m & (g >= values[mid]), periodic_axis):
            lo = mid
        else:
            hi = mid - 1
    return float(values[lo])


@dataclass(frozen=True, kw_only=True)
class ThresholdResult:
    """Where the non-contact area stops percolating as the mean pressure grows.

    Attributes
    ----------
    pressure:
        Mean pressure (Pa) at the threshold: midpoint of the final bracket.
    contact_area:
        Relative contact area at the threshold: midpoint of the areas at the bracket ends.
    pressure_spanning, pressure_blocked:
        Final bracket (Pa): the fluid spans at the first and does not at the second.
    area_spanning, area_blocked:
        Relative contact areas at the bracket ends.
    contact_solves:
        Number of contact solutions computed.
    """

    pressure: float
    contact_area: float
    pressure_spanning: float
    pressure_blocked: float
    area_spanning: float
    area_blocked: float
    contact_solves: int


def percolation_threshold(
    heights: ArrayLike,
    size: float,
    e_star: float,
    *,
    p_lo: float,
    p_hi: float,
    rel_tol: float = 1e-3,
    tol: float = 1e-8,
    max_iter: int = 5000,
    workers: int = -1,
) -> ThresholdResult:
    """Bisection on the mean pressure for the loss of percolation of the non-contact area.

    The fluid (pressure == 0 cells) must span at ``p_lo`` and must not at ``p_hi`` (else
    InputError). The bracket is halved (geometric mean, pressures span decades) until
    (p_blocked - p_spanning) / p_blocked <= rel_tol; each contact solve is warm-started from the
    solution at the nearest lower pressure already computed. Fluid cells are those with zero
    pressure (the contact mask is pressure > 0, never gap == 0). Pressures in Pa, heights and
    ``size`` in m, ``e_star`` in Pa (docs/theory.md §6.4).
    """
    for name, v in (("p_lo", p_lo), ("p_hi", p_hi)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(name, v, "must be a finite pressure > 0 (Pa)")
    if not p_lo < p_hi:
        raise InputError("p_hi", p_hi, f"must exceed p_lo = {p_lo:.6g} Pa")
    if not (math.isfinite(rel_tol) and 0 < rel_tol < 1):
        raise InputError("rel_tol", rel_tol, "must be in (0, 1)")
    kw = dict(tol=tol, max_iter=max_iter, workers=workers)
    lo = solve_contact(heights, size, e_star, p_lo, **kw)  # type: ignore[arg-type]
    if not spans(~lo.contact):
        raise InputError("p_lo", p_lo, f"the non-contact area must percolate there (contact area {lo.contact_area:.4f})")
    hi = solve_contact(heights, size, e_star, p_hi, initial=lo, **kw)  # type: ignore[arg-type]
    if spans(~hi.contact):
        raise InputError("p_hi", p_hi, f"the non-contact area must not percolate there (contact area {hi.contact_area:.4f})")
    solves = 2
    a, b = lo, hi
    while (b.mean_pressure - a.mean_pressure) / b.mean_pressure > rel_tol:
        mid = math.sqrt(a.mean_pressure * b.mean_pressure)
        r = solve_contact(heights, size, e_star, mid, initial=a, **kw)  # type: ignore[arg-type]
        solves += 1
        if spans(~r.contact):
            a = r
        else:
            b = r
    return ThresholdResult(
        pressure=0.5 * (a.mean_pressure + b.mean_pressure),
        contact_area=0.5 * (a.contact_area + b.contact_area),
        pressure_spanning=a.mean_pressure,
        pressure_blocked=b.mean_pressure,
        area_spanning=a.contact_area,
        area_blocked=b.contact_area,
        contact_solves=solves,
    )


__all__ = ["label_clusters", "spans", "spanning_mask", "percolation_threshold", "ThresholdResult",
           "ContactResult"]
