"""Stitching spectra of one surface measured at several scales (the figure: :func:`sealeak.render.plot_spectra`).

All binned spectra share bin edges 10^(k/bins_per_decade) (1/m), so a bin of one measurement is
the same q interval in every other. The stitched C in a bin is the mode-weighted mean of log C
over the measurements whose reliable range covers that bin::

    log C = Σ_i n_i log C_i / Σ_i n_i        (n_i: Fourier modes of measurement i in the bin)

and outside the overlaps simply the one measurement that covers the bin.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._spectrum import BinnedSpectrum

__all__ = ["stitch"]


def _bins_per_decade(b: BinnedSpectrum) -> float:
    return float(np.round(1.0 / np.log10(b.q_hi[0] / b.q_lo[0]), 6))


def stitch(spectra: Sequence[BinnedSpectrum], *, label: str = "stitched") -> BinnedSpectrum:
    """One 2D spectrum over the union of the reliable ranges of ``spectra`` (see the module docstring)."""
    spectra = list(spectra)
    if not spectra:
        raise InputError("spectra", [], "at least one spectrum")
    for b in spectra:
        if b.dim != 2:
            raise InputError("spectrum.dim", b.dim, f"{b.label}: convert profile spectra to 2D before stitching")
    bpd = {_bins_per_decade(b) for b in spectra}
    if len(bpd) != 1:
        raise InputError("bins_per_decade", sorted(bpd), "all spectra must use the same bins per decade")
    per = bpd.pop()
    keys, logC, logq, n = [], [], [], []
    for b in spectra:
        keep = b.reliable & (b.C > 0)
        keys.append(np.rint(per * np.log10(b.q_lo[keep])).astype(np.int64))
        logC.append(np.log(b.C[keep]))
        logq.append(np.log(b.q[keep]))
        n.append(np.maximum(b.modes[keep], 1).astype(float))
    k = np.concatenate(keys)
    if k.size < 2:
        names = ", ".join(Path(b.label.split(" [")[0]).name or "unnamed" for b in spectra)
        raise InputError("spectra", names, f"{k.size} reliable bin(s) in all, at least two are needed "
                                           f"(each measurement: {', '.join(str(b.nb_reliable) for b in spectra)})")
    lc, lq, w = np.concatenate(logC), np.concatenate(logq), np.concatenate(n)
    uk, inv = np.unique(k, return_inverse=True)
    wsum = np.bincount(inv, weights=w)
    C = np.exp(np.bincount(inv, weights=w * lc) / wsum)
    q = np.exp(np.bincount(inv, weights=w * lq) / wsum)
    count = np.bincount(inv)
    lo, hi = 10.0 ** (uk / per), 10.0 ** ((uk + 1) / per)
    notes = [f"stitched {len(spectra)} spectra: {int((count > 1).sum())} bins overlap "
             f"(mode-weighted mean of log C), union {lo[0]:.4g}..{hi[-1]:.4g} 1/m"]
    gaps = np.nonzero(np.diff(uk) > 1)[0]
    for g in gaps:
        notes.append(f"no measurement covers {hi[g]:.4g}..{lo[g + 1]:.4g} 1/m (C(q) interpolated across the gap)")
    return BinnedSpectrum(q=q, C=C, modes=np.rint(wsum).astype(np.int64), q_lo=lo, q_hi=hi,
                          reliable=np.ones(q.size, dtype=bool), q_reliable=(float(q[0]), float(q[-1])), dim=2,
                          label=label, notes=tuple(notes))
