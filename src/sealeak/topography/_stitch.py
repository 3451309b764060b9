"""Stitching spectra of one surface measured at several scales, and the spectrum figure.

All binned spectra share bin edges 10^(k/bins_per_decade) (1/m), so a bin of one measurement is
the same q interval in every other. The stitched C in a bin is the mode-weighted mean of log C
over the measurements whose reliable range covers that bin::

    log C = Σ_i n_i log C_i / Σ_i n_i        (n_i: Fourier modes of measurement i in the bin)

and outside the overlaps simply the one measurement that covers the bin.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..errors import InputError
from ._spectrum import BinnedSpectrum

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ._analysis import Analysis

__all__ = ["stitch", "plot_spectra"]


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
    return BinnedSpectrum(q, C, np.rint(wsum).astype(np.int64), lo, hi, np.ones(q.size, dtype=bool),
                          (float(q[0]), float(q[-1])), 2, label=label, notes=tuple(notes))


def _wavelength_um(x):  # type: ignore[no-untyped-def]
    """q (1/m) <-> wavelength (µm): λ = 2π/q (its own inverse up to the unit factor)."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(x > 0, 2.0 * np.pi * 1e6 / np.where(x > 0, x, 1.0), np.inf)


def plot_spectra(analysis: "Analysis | Sequence[BinnedSpectrum]", path: str | Path | None = None,
                 *, title: str | None = None) -> "Figure":
    """Log-log figure of each source's binned C(q) (reliable bins filled, others faint, with a legend
    entry), the stitched result and the fitted model; axes "wavevector q (1/m)" and "power spectrum
    C(q) (m⁴)", wavelength (µm) on the top axis. Saved to ``path`` when given.
    """
    from matplotlib.figure import Figure

    from ._analysis import Analysis

    if isinstance(analysis, Analysis):
        sources = [s.spectrum for s in analysis.sources if s.spectrum is not None]
        result = analysis.spectrum_or_none
        fit = analysis.fit
        several = len(analysis.sources) > 1
    else:
        sources, result, fit = list(analysis), None, None
        several = len(sources) > 1
    if not sources:
        raise InputError("spectra", [], "nothing to plot: no measurement gives a C(q)")
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.add_subplot()
    any_unreliable = False
    for i, b in enumerate(sources):
        color = f"C{i % 10}"
        name = Path(b.label.split(" [")[0]).name if b.label else f"source {i + 1}"
        rel = b.reliable
        ax.loglog(b.q[rel], b.C[rel], "o", ms=3.5, color=color, label=name)
        if (~rel).any():
            any_unreliable = True
            ax.loglog(b.q[~rel], b.C[~rel], "o", ms=3, color=color, alpha=0.35, mfc="none")
    if any_unreliable:  # one legend entry for the faint points of every source
        ax.plot([], [], "o", ms=3, color="0.35", alpha=0.6, mfc="none",
                label="outside the reliable range (not used)")
    if result is not None:
        qs, Cs = result.sample(400)
        ax.loglog(qs, Cs, "-", color="k", lw=1.5, label="combined C(q)" if several else "C(q), reliable range")
    if fit is not None:
        qs, Cs = fit.spectrum.sample(200)
        flag = "" if fit.hurst_in_range else " (H at its bound)"
        ax.loglog(qs, Cs, "--", color="0.4", lw=1.2, label=f"self-affine fit, H = {fit.hurst:.2f}{flag}")
    ax.set_xlabel("wavevector q (1/m)")
    ax.set_ylabel("power spectrum C(q) (m⁴)")
    top = ax.secondary_xaxis("top", functions=(_wavelength_um, _wavelength_um))
    top.set_xlabel("wavelength 2π/q (µm)")
    if title:
        ax.set_title(title)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize="small")
    if path is not None:
        fig.savefig(str(path), dpi=120)
    return fig
