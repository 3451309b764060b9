"""Preprocessing before spectral analysis: detrending, filling undefined points, windowing.

Order: (1) fit and subtract the mean, a plane or a quadratic by least squares over the defined
points; (2) fill undefined points harmonically (Laplace equation with the defined neighbours as
boundary values); (3) for non-periodic data, multiply by a Hann window normalised to mean(w²) = 1,
which corrects, on average, the variance the window removes (E[mean((w h)²)] = E[h²] for a
stationary h).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy import sparse
from scipy.sparse.linalg import spsolve

from ..errors import InputError
from ._types import LineScans, Topography

__all__ = ["Prepared", "prepare", "hann_window", "DETRENDS", "WINDOWS"]

Detrend = Literal["auto", "none", "mean", "plane", "curvature"]
Window = Literal["auto", "hann", "none"]
DETRENDS = ("auto", "none", "mean", "plane", "curvature")
WINDOWS = ("auto", "hann", "none")
FloatArray = NDArray[np.float64]
Surface = Topography | LineScans


@dataclass(frozen=True, eq=False)
class Prepared:
    """A surface ready for the FFT.

    Attributes
    ----------
    surface:
        Detrended heights with undefined points filled (same type as the input); the statistics
        are computed from these (over the originally defined points, ``defined``).
    windowed:
        The heights the FFT sees (``surface.heights`` times the normalised window, if any).
    defined:
        Boolean mask of the points the file defined.
    notes:
        What was done, in order, as sentences.
    """

    surface: Surface
    windowed: FloatArray
    defined: NDArray[np.bool_]
    notes: tuple[str, ...]


def hann_window(n: int) -> FloatArray:
    """Periodic Hann window w_i = (1 - cos(2π i/n))/2, scaled to mean(w²) = 1 (i.e. × √(8/3))."""
    w = 0.5 * (1.0 - np.cos(2.0 * np.pi * np.arange(n) / n))
    return w / np.sqrt(np.mean(w**2))


def _basis_2d(nx: int, ny: int, order: int) -> list[FloatArray]:
    x = (np.arange(nx) - (nx - 1) / 2.0) / nx
    y = (np.arange(ny) - (ny - 1) / 2.0) / ny
    X, Y = np.meshgrid(x, y, indexing="ij")
    terms = [np.ones_like(X)]
    if order >= 1:
        terms += [X, Y]
    if order >= 2:
        terms += [X * X, X * Y, Y * Y]
    return terms


def _basis_1d(n: int, order: int) -> list[FloatArray]:
    x = (np.arange(n) - (n - 1) / 2.0) / n
    return [x**k for k in range(order + 1)]


def _subtract(h: FloatArray, good: NDArray[np.bool_], terms: list[FloatArray]) -> FloatArray:
    A = np.stack([t[good] for t in terms], axis=1)
    coef, *_ = np.linalg.lstsq(A, h[good], rcond=None)
    return h - sum(c * t for c, t in zip(coef, terms))


def _harmonic_fill(h: FloatArray, periodic: bool) -> FloatArray:
    """Solve ∇²h = 0 on the undefined points (5-point stencil), defined points fixed."""
    missing = np.isnan(h)
    nx, ny = h.shape
    idx = -np.ones(h.shape, dtype=np.int64)
    idx[missing] = np.arange(int(missing.sum()))
    rows, cols, vals = [], [], []
    rhs = np.zeros(int(missing.sum()))
    diag = np.zeros(int(missing.sum()))
    ii, jj = np.nonzero(missing)
    me = idx[ii, jj]
    known = np.where(missing, 0.0, h)
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        ni, nj = ii + di, jj + dj
        if periodic:
            ni, nj = ni % nx, nj % ny
            ok = np.ones(ni.shape, dtype=bool)
        else:
            ok = (ni >= 0) & (ni < nx) & (nj >= 0) & (nj < ny)
        ni_ok, nj_ok, me_ok = ni[ok], nj[ok], me[ok]
        diag += np.bincount(me_ok, minlength=diag.size)
        nb_missing = missing[ni_ok, nj_ok]
        rows.append(me_ok[nb_missing])
        cols.append(idx[ni_ok, nj_ok][nb_missing])
        vals.append(-np.ones(int(nb_missing.sum())))
        rhs += np.bincount(me_ok[~nb_missing], weights=known[ni_ok, nj_ok][~nb_missing], minlength=rhs.size)
    m = diag.size
    A = sparse.coo_matrix((np.concatenate(vals + [diag]),
                           (np.concatenate(rows + [np.arange(m)]), np.concatenate(cols + [np.arange(m)]))),
                          shape=(m, m)).tocsc()
    out = h.copy()
    out[missing] = spsolve(A, rhs)
    return out


def prepare(surface: Surface, *, detrend: Detrend = "auto", window: Window = "auto") -> Prepared:
    """Detrend, fill undefined points and window a map or line scans (see the module docstring).

    ``detrend``: ``"auto"`` (mean for periodic data, plane/line otherwise), ``"none"``, ``"mean"``,
    ``"plane"`` (tilt; per profile for line scans), ``"curvature"`` (quadratic).
    ``window``: ``"auto"`` (Hann for non-periodic data, none for periodic), ``"hann"``, ``"none"``.
    """
    if detrend not in DETRENDS:
        raise InputError("detrend", detrend, f"allowed: {', '.join(map(repr, DETRENDS))}")
    if window not in WINDOWS:
        raise InputError("window", window, f"allowed: {', '.join(map(repr, WINDOWS))}")
    periodic = surface.periodic
    if detrend == "auto":
        detrend = "mean" if periodic else "plane"
    if window == "auto":
        window = "none" if periodic else "hann"
    order = {"none": -1, "mean": 0, "plane": 1, "curvature": 2}[detrend]
    h = np.array(surface.heights, dtype=float)
    defined = ~np.isnan(h)
    notes: list[str] = []
    is_map = isinstance(surface, Topography)
    if order >= 0:
        if is_map:
            h = _subtract(h, defined, _basis_2d(h.shape[0], h.shape[1], order))
        else:
            terms = _basis_1d(h.shape[1], order)
            for k in range(h.shape[0]):
                if defined[k].sum() > order + 1:
                    h[k] = _subtract(h[k], defined[k], terms)
        what = {0: "mean", 1: "mean and tilt (plane fit)" if is_map else "mean and tilt of each profile",
                2: "mean, tilt and curvature (quadratic fit)"}[order]
        notes.append(f"removed {what}")
    else:
        notes.append("no detrending")
    if not defined.all():
        nmiss = int((~defined).sum())
        if is_map:
            h = _harmonic_fill(h, periodic)
        else:
            x = np.arange(h.shape[1])
            for k in range(h.shape[0]):
                g = defined[k]
                if not g.any():
                    h[k] = 0.0
                elif not g.all():
                    h[k, ~g] = np.interp(x[~g], x[g], h[k, g])
        notes.append(f"filled {nmiss} undefined points ({100.0 * nmiss / h.size:.2g} %) by "
                     f"{'harmonic' if is_map else 'linear'} interpolation")
    if isinstance(surface, Topography):
        prepared: Surface = Topography(heights=h, size=surface.size, periodic=periodic, source=surface.source,
                                       notes=surface.notes,
                                       resolution=surface.resolution, warnings=surface.warnings)
    else:
        prepared = LineScans(heights=h, length=surface.length, periodic=periodic, source=surface.source,
                             notes=surface.notes,
                             resolution=surface.resolution, warnings=surface.warnings)
    if window == "hann":
        if is_map:
            w = np.outer(hann_window(h.shape[0]), hann_window(h.shape[1]))
        else:
            w = hann_window(h.shape[1])[None, :]
        windowed = h * w
        notes.append("applied a Hann window normalised to mean(w²) = 1 (restores the variance it removes)")
    else:
        windowed = h
        if not periodic:
            notes.append("no window on non-periodic data: expect leakage from the edges")
    return Prepared(prepared, windowed, defined, tuple(notes))
