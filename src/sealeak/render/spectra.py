"""The figure of measured spectra: each source's binned C(q), the combined C(q) and the fit."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..errors import InputError
from ..topography import Analysis, BinnedSpectrum

__all__ = ["plot_spectra"]


def _wavelength_um(x):  # type: ignore[no-untyped-def]
    """q (1/m) <-> wavelength (µm): λ = 2π/q (its own inverse up to the unit factor)."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(x > 0, 2.0 * np.pi * 1e6 / np.where(x > 0, x, 1.0), np.inf)


def plot_spectra(analysis: Analysis | Sequence[BinnedSpectrum], path: str | Path | None = None,
                 *, title: str | None = None) -> Figure:
    """Log-log figure of each source's binned C(q) (reliable bins filled, others faint, with a legend
    entry), the stitched result and the fitted model; axes "wavevector q (1/m)" and "power spectrum
    C(q) (m⁴)", wavelength (µm) on the top axis. Saved to ``path`` when given.
    """
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
