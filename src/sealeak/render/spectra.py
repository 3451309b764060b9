"""The figure of measured spectra: each source's binned C(q), the combined C(q) and the fit.

How it reads: both axes logarithmic with a labelled tick at least every decade (1, 2, 5 within
an axis of two or three decades), the wavelength 2π/q on the top axis; the combined C(q) is drawn
only where a measurement covers the band: across a gap between measurements (stitched files of
different scales) the line is broken and the gap shaded (the PowerSpectrum used for predictions
interpolates log-log across it, docs/theory.md §7.6); the legend sits below the axes, never on
the data; a fit that carries warnings (H at a bound, reduced χ² above 100) says so in its label.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axis import Axis
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator

from ..errors import InputError
from ..topography import Analysis, BinnedSpectrum
from .plotstyle import literal_text

__all__ = ["plot_spectra", "spectrum_gaps"]


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _wavelength_um(x):  # type: ignore[no-untyped-def]
    """q (1/m) <-> wavelength (µm): λ = 2π/q (its own inverse up to the unit factor)."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(x > 0, 2.0 * np.pi * 1e6 / np.where(x > 0, x, 1.0), np.inf)


def spectrum_gaps(binned: BinnedSpectrum) -> list[tuple[float, float]]:
    """The q intervals (1/m) between consecutive bins of ``binned`` that no bin covers (stitching gaps)."""
    lo, hi = np.asarray(binned.q_lo), np.asarray(binned.q_hi)
    return [(float(hi[i]), float(lo[i + 1])) for i in range(lo.size - 1) if lo[i + 1] > hi[i] * (1 + 1e-9)]


def _broken_line(binned: BinnedSpectrum) -> tuple[np.ndarray, np.ndarray]:
    """Bin centres and C with a NaN between bins separated by a gap, so no segment crosses it."""
    keep = binned.reliable & (binned.C > 0) & np.isfinite(binned.C)
    q, C, lo, hi = binned.q[keep], binned.C[keep], binned.q_lo[keep], binned.q_hi[keep]
    xs, ys = [], []
    for i in range(q.size):
        if i and lo[i] > hi[i - 1] * (1 + 1e-9):
            xs.append(np.nan)
            ys.append(np.nan)
        xs.append(q[i])
        ys.append(C[i])
    return np.array(xs, dtype=float), np.array(ys, dtype=float)


def _power_label(v: float, _pos: object = None) -> str:
    """Plain numbers from 0.001 to 10⁴, else 10ⁿ or m×10ⁿ (plain text, no mathtext: quick to lay out)."""
    if not (np.isfinite(v) and v > 0):
        return ""
    if 1e-3 <= v < 1e4:
        return f"{v:.4g}"
    e = int(np.floor(np.log10(v) + 1e-9))
    m = v / 10.0**e
    power = "10" + str(e).translate(_SUPERSCRIPT)
    return power if abs(m - 1.0) < 1e-6 else f"{m:.2g}×{power}"


def _log_ticks(axis: Axis, lo: float, hi: float) -> None:
    """A labelled tick every decade, or at 1, 2, 5 when the axis spans three decades or less."""
    decades = float(np.log10(hi / lo)) if lo > 0 and hi > lo else 10.0
    subs: Sequence[float] = (1.0, 2.0, 5.0) if decades <= 3.0 else (1.0,)
    axis.set_major_locator(LogLocator(base=10.0, subs=subs, numticks=15))
    axis.set_major_formatter(FuncFormatter(_power_label))
    axis.set_minor_locator(LogLocator(base=10.0, subs=[float(s) for s in range(2, 10)], numticks=15) if decades <= 8.0
                           else NullLocator())
    axis.set_minor_formatter(NullFormatter())


@literal_text
def plot_spectra(analysis: Analysis | Sequence[BinnedSpectrum], path: str | Path | None = None,
                 *, title: str | None = None) -> Figure:
    """Log-log figure of each source's binned C(q) (reliable bins filled, others faint, with a legend
    entry), the stitched result (broken across bands no measurement covers, which are shaded) and
    the fitted model; axes "wavevector q (1/m)" and "power spectrum C(q) (m⁴)", wavelength (µm) on
    the top axis, legend below the axes. Saved to ``path`` when given.
    """
    if isinstance(analysis, Analysis):
        sources = [s.spectrum for s in analysis.sources if s.spectrum is not None]
        combined = analysis.binned if analysis.has_spectrum else None
        fit = analysis.fit
        several = len(analysis.sources) > 1
    else:
        sources, combined, fit = list(analysis), None, None
        several = len(sources) > 1
    if not sources:
        raise InputError("spectra", [], "nothing to plot: no measurement gives a C(q)")
    fig = Figure(figsize=(7.2, 5.6), layout="constrained")
    ax = fig.add_subplot()
    ax.set_xscale("log")
    ax.set_yscale("log")
    any_unreliable = False
    for i, b in enumerate(sources):
        color = f"C{i % 10}"
        name = Path(b.label.split(" [")[0]).name if b.label else f"source {i + 1}"
        rel = b.reliable
        ax.plot(b.q[rel], b.C[rel], "o", ms=3.5, color=color, label=name)
        if (~rel).any():
            any_unreliable = True
            ax.plot(b.q[~rel], b.C[~rel], "o", ms=3, color=color, alpha=0.35, mfc="none")
    if any_unreliable:  # one legend entry for the faint points of every source
        ax.plot([], [], "o", ms=3, color="0.35", alpha=0.6, mfc="none", label="outside the reliable range (not used)")
    if combined is not None:
        x, y = _broken_line(combined)
        ax.plot(x, y, "-", color="k", lw=1.5, label="combined C(q)" if several else "C(q), reliable range")
        gaps = spectrum_gaps(combined)
        for k, (a, b_) in enumerate(gaps):
            ax.axvspan(a, b_, color="0.9", lw=0, zorder=0,
                       label="no reliable C(q) in this band (not joined)" if k == 0 else None)
    if fit is not None:
        qs, Cs = fit.spectrum.sample(200)
        flags = []
        if fit.hurst in (0.0, 1.0) or min(fit.hurst, 1.0 - fit.hurst) < 1e-3:
            flags.append("H at its bound")
        if any("χ²" in w for w in fit.warnings):
            flags.append(f"poor fit, reduced χ² = {fit.chi2_red:.3g}")
        flag = f" ({'; '.join(flags)})" if flags else ""
        ax.plot(qs, Cs, "--", color="0.4", lw=1.2, label=f"self-affine fit, H = {fit.hurst:.2f}{flag}")
    ax.set_xlabel("wavevector q (1/m)")
    ax.set_ylabel("power spectrum C(q) (m⁴)")
    ax.autoscale_view()
    xlo, xhi = ax.get_xlim()
    ylo, yhi = ax.get_ylim()
    _log_ticks(ax.xaxis, xlo, xhi)
    _log_ticks(ax.yaxis, ylo, yhi)
    top = ax.secondary_xaxis("top", functions=(_wavelength_um, _wavelength_um))
    top.set_xlabel("wavelength 2π/q (µm)")
    _log_ticks(top.xaxis, *sorted(_wavelength_um(np.array([xlo, xhi]))))
    if title:
        ax.set_title(title)
    ax.grid(True, which="major", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    for ncol in (2, 1) if len(handles) > 2 else (1,):  # two columns where they fit the figure's width
        legend = fig.legend(handles, labels, loc="outside lower center", ncol=ncol, fontsize="small")
        fig.draw_without_rendering()
        if ncol == 1 or legend.get_window_extent().width <= 0.98 * fig.bbox.width:
            break
        legend.remove()
    if path is not None:
        fig.savefig(str(path), dpi=120)
    return fig
