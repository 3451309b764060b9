"""Figures of a prediction (matplotlib, PNG).

One function per figure; each takes case results (:class:`~sealeak.cases.CaseResult`) and the
curves computed for them (:func:`~sealeak.cases.prediction_curves`) and returns a matplotlib
:class:`~matplotlib.figure.Figure`; nothing here computes physics. Figures are built without
pyplot, so importing sealeak never selects or changes a matplotlib backend (a notebook keeps its
own). :func:`prediction_figures` returns them all by file name; :func:`save_figures` writes them
atomically.
Every axis is labelled with its unit. The reference paper's theory figures are: C(q) (its Fig. 4),
Q against P0 on a linear and a log10 scale (Figs. 6, 7), the critical pore size against P0 (Fig. 8)
and ζc against P0 (Fig. 9); Q against ΔP (Fig. 5) and A(ζ), ū(ζ), u1(ζ) complete the set.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..cases import Case, CaseResult, CurveSet, PredictionCurves, prediction_curves
from ..io.files import atomic_write
from ..io.units import length_unit
from ..physics.critical_junction import CriticalJunctionResult
from ..physics.effective_medium import EffectiveMediumResult

__all__ = ["prediction_figures", "save_figures", "pressure_axis", "PREDICTION_FIGURE_NAMES", "new_figure",
           "subtitle"]

_STYLE = {"figure.figsize": (6.4, 4.4), "figure.dpi": 150, "axes.grid": True, "grid.alpha": 0.3,
          "axes.titlesize": 10, "legend.fontsize": 8}


def pressure_axis(p: np.ndarray) -> tuple[float, str]:
    """(scale, unit) for showing pressures: kPa, or MPa when the largest exceeds 2 MPa."""
    return (1e6, "MPa") if np.nanmax(p) > 2e6 else (1e3, "kPa")


def _set_label(cs: CurveSet, curves: PredictionCurves) -> str:
    """Legend label of a curve set: its squeeze pressure (and, in a study, the variant's name)."""
    scale, unit = pressure_axis(cs.case.squeeze_pressure)
    label = f"P0 = {cs.squeeze_pressure / scale:.3g} {unit}"
    return f"{cs.case.label}, {label}" if len(curves.spectra) > 1 else label


def _label(case: Case, fallback: str = "") -> str:
    return case.label or fallback


def new_figure(title: str, figsize: tuple[float, float] | None = None) -> tuple[Figure, Axes]:
    """A figure with one axes in the project's style; ``title`` is the heading, :func:`subtitle` adds lines."""
    with mpl.rc_context(_STYLE):
        fig = Figure(figsize=figsize) if figsize else Figure()
        ax = fig.add_subplot()
    ax._sealeak_heading = title  # type: ignore[attr-defined]
    ax.set_title(title, fontsize=10, fontweight="bold")
    return fig, ax


def subtitle(ax: Axes, text: str) -> None:
    """Set the axes title to its heading plus ``text`` on the lines below."""
    heading = getattr(ax, "_sealeak_heading", "")
    ax.set_title(heading + ("\n" + text if text else ""), fontsize=9)


def figure_spectrum(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """C(q) against q, log-log, with q0 and the spectrum's nodes."""
    fig, ax = new_figure("Surface roughness power spectrum")
    for case, (q, c) in zip(cases, curves.spectra):
        ax.loglog(q, c, label=_label(case, case.spectrum.label or "C(q)"))
    case = cases[0]
    ax.axvline(case.q0, color="0.5", ls=":", lw=1)
    ax.annotate("q0 = 2π/L", (case.q0, ax.get_ylim()[0]), rotation=90, va="bottom", ha="right", fontsize=8, color="0.4")
    ax.set_xlabel("wavevector q (1/m)")
    ax.set_ylabel("power spectrum C(q) (m⁴)")
    stats = (f"h_rms = {case.spectrum.h_rms * 1e6:.3g} µm, slope_rms = {case.spectrum.slope_rms:.3g}, "
             f"A_true/A0 = {case.spectrum.area_ratio:.3g}") if len(cases) == 1 else ""
    subtitle(ax, (case.spectrum_note + ("\n" + stats if stats else "")) if len(cases) == 1 else "")
    if len(cases) > 1 or case.spectrum.label:
        ax.legend()
    return fig


def figure_contact_area(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """A(ζ)/A0 against ζ for a few squeeze pressures, with the percolation level 1 - p_c."""
    fig, ax = new_figure("Apparent relative contact area against magnification")
    for cs in curves.sets:
        line, = ax.semilogx(cs.zeta, cs.area, label=_set_label(cs, curves))
        if cs.percolates:
            ax.plot([cs.zeta_c], [1 - cs.case.percolation_threshold], "o", color=line.get_color(), ms=4)
    pc = cases[0].percolation_threshold
    ax.axhline(1 - pc, color="k", ls="--", lw=0.8, label=f"percolation: A/A0 = 1 - p_c = {1 - pc:.2f}")
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("relative contact area A(ζ)/A0 (1)")
    ax.set_ylim(0, 1.02)
    subtitle(ax, "dots: critical magnification ζc")
    ax.legend()
    return fig


def figure_separation(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """ū(ζ) (solid) and u1(ζ) (dashed) against ζ for the same squeeze pressures."""
    fig, ax = new_figure("Interfacial separation against magnification")
    top, bottom = 0.0, np.inf
    for cs in curves.sets:
        label, z, ubar, u1 = _set_label(cs, curves), cs.zeta[:-1], cs.mean_gap, cs.u1
        top = max(top, 3.0 * ubar[0])
        bottom = min(bottom, 1e-3 * ubar[0])
        shown = (ubar > 1e-6 * ubar[0])
        line, = ax.loglog(z, np.where(shown, ubar, np.nan) * 1e6, label=f"ū, {label}")
        shown = np.isfinite(u1) & (u1 > 1e-6 * ubar[0]) & (u1 < 1e3 * ubar[0])
        ax.loglog(z[1:], np.where(shown, u1, np.nan) * 1e6, ls="--",
                  color=line.get_color(), label=f"u1, {label}")
        if cs.percolates:
            ax.plot([cs.zeta_c], [cs.u1_c * 1e6], "o", color=line.get_color(), ms=4)
    ax.set_ylim(bottom * 1e6, top * 1e6)
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("separation (µm)")
    subtitle(ax, "solid: mean separation ū(ζ); dashed: u1(ζ); dots: u_c = u1(ζc)")
    ax.legend(ncol=2 if len(ax.lines) > 8 else 1)
    return fig


def _per_pressure(cases: Sequence[Case], results: Sequence[CriticalJunctionResult], title: str,
                  ylabel: str, values: Callable[[CriticalJunctionResult], np.ndarray], log: bool) -> Figure:
    fig, ax = new_figure(title)
    scale, unit = pressure_axis(np.concatenate([r.squeeze_pressure for r in results]))
    for case, res in zip(cases, results):
        y = values(res)
        ax.plot(res.squeeze_pressure / scale, y, "-o" if len(res) <= 12 else "-", ms=3,
                label=_label(case) or None)
    if log:
        ax.set_yscale("log")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel(ylabel)
    if any(c.label for c in cases):
        ax.legend()
    return fig


def _settings(case: Case) -> str:
    return (f"α = {case.alpha:g}, ΔP = {case.pressure_difference / 1e3:.3g} kPa, "
            f"η = {case.fluid.viscosity * 1e3:.3g} mPa·s, Ly/Lx = {case.seal.aspect_ratio:.3g}, "
            f"p_c = {case.percolation_threshold:g}, γ = {case.gamma:g}")


def figure_leak_rate(cases: Sequence[Case], results: Sequence[CriticalJunctionResult], log: bool,
                     effective: Sequence[EffectiveMediumResult | None] | None = None) -> Figure:
    """Q against P0, linear (paper Fig. 6) or log10 (paper Fig. 7).

    ``effective``: effective-medium results per case (or None); their curves are drawn dashed next
    to the critical-junction ones (model "both"), or alone (model "effective-medium").
    """
    ems = list(effective) if effective is not None else [None] * len(cases)
    title = "Leak rate against squeeze pressure" + (" (log scale)" if log else "")
    fig, ax = new_figure(title)
    scale, unit = pressure_axis(np.concatenate([r.squeeze_pressure for r in results]))
    shown_cj = shown_em = False
    for case, res, em in zip(cases, results, ems):
        prefix = f"{case.label}: " if case.label else ""
        marker = "-o" if len(res) <= 12 else "-"
        color = None
        if em is None or case.model != "effective-medium":
            y = np.log10(res.leak_rate) if log else res.leak_rate
            line, = ax.plot(res.squeeze_pressure / scale, y, marker, ms=3,
                            label=prefix + f"critical junction (α = {case.alpha:g})" if (em is not None or case.label) else None)
            color = line.get_color()
            shown_cj = True
        if em is not None:
            with np.errstate(divide="ignore"):
                y = np.log10(em.leak_rate) if log else em.leak_rate
            ax.plot(em.squeeze_pressure / scale, y, "--" if color else marker, ms=3, color=color,
                    label=prefix + "effective medium (Bruggeman)")
            shown_em = True
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("log10 of leak rate Q / (m³/s)" if log else "leak rate Q (m³/s)")
    if not log:
        ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
        ax.set_ylim(bottom=0)
    if ax.get_legend_handles_labels()[0]:
        ax.legend()
    missing = any((~r.percolates).any() for r in results) if shown_cj else False
    missing = missing or any(em is not None and (~em.percolates).any() for em in ems)
    settings = _settings(cases[0]) if shown_cj else (
        f"ΔP = {cases[0].pressure_difference / 1e3:.3g} kPa, η = {cases[0].fluid.viscosity * 1e3:.3g} mPa·s, "
        f"Ly/Lx = {cases[0].seal.aspect_ratio:.3g}, γ = {cases[0].gamma:g}")
    if shown_em and shown_cj:
        settings += "\nsolid: critical junction; dashed: effective medium (no fit factor)"
    subtitle(ax, settings + ("\nmissing points: the non-contact area does not percolate" if missing else ""))
    return fig


def figure_gap_distribution(curves: PredictionCurves) -> Figure:
    """P(u) (continuous part) for a few squeeze pressures; the δ(u) weight A(ζ1)/A0 in the legend."""
    fig, ax = new_figure("Distribution of interfacial separations P(u)")
    # u P(u) on a log u axis: the probability per unit ln u, readable across scales
    u = curves.gap
    top = 0.0
    for cs, y in zip(curves.sets, curves.gap_density):
        d = cs.distribution
        top = max(top, float(y.max()))
        line, = ax.semilogx(u * 1e6, y,
                            label=f"{_set_label(cs, curves)}: δ(u) weight A(ζ1)/A0 = {d.contact_fraction[0]:.3g}")
        ax.axvline(d.mean_gap[0] * 1e6, color=line.get_color(), ls=":", lw=1)
    ax.set_xlim(u[0] * 1e6, u[-1] * 1e6)
    ax.set_ylim(0, 1.45 * top)  # room for the legend
    ax.set_xlabel("interfacial separation u (µm)")
    ax.set_ylabel("u·P(u), probability per unit ln u (1)")
    subtitle(ax, "continuous part of P(u) (the δ(u) contact weight is in the legend); dotted: ū(1)")
    ax.legend()
    return fig


def figure_critical_junction(cases: Sequence[Case], results: Sequence[CriticalJunctionResult]) -> Figure:
    """u_c (solid) and λc (dashed) against P0 (the critical pore size, paper Fig. 8)."""
    fig, ax = new_figure("Critical constriction against squeeze pressure")
    scale, unit = pressure_axis(np.concatenate([r.squeeze_pressure for r in results]))
    # one length unit for both curves, chosen by the smaller quantity (the gap)
    lscale, lunit = length_unit(np.concatenate([r.critical_gap for r in results]))
    for case, res in zip(cases, results):
        suffix = f", {case.label}" if case.label else ""
        line, = ax.semilogy(res.squeeze_pressure / scale, res.critical_gap / lscale, label="height u_c" + suffix)
        ax.semilogy(res.squeeze_pressure / scale, res.critical_wavelength / lscale, ls="--",
                    color=line.get_color(), label="width λc = L/ζc" + suffix)
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel(f"critical pore size ({lunit})")
    if len(results) == 1:
        ok = results[0].percolates
        if ok.any():
            ratio = np.median(results[0].critical_wavelength[ok] / results[0].critical_gap[ok])
            subtitle(ax, f"median λc/u_c = {ratio:.3g}")
    if len(cases) > 2:  # a study: the curves fill the axes, the legend goes below them
        ax.legend(ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=8)
    else:
        ax.legend()
    return fig


def figure_critical_magnification(cases: Sequence[Case], results: Sequence[CriticalJunctionResult]) -> Figure:
    """ζc against P0 (paper Fig. 9)."""
    fig = _per_pressure(cases, results, "Critical magnification against squeeze pressure",
                        "critical magnification ζc (1)", lambda r: r.critical_magnification, False)
    subtitle(fig.axes[0], f"A(ζc)/A0 = 1 - p_c = {1 - cases[0].percolation_threshold:.2f}")
    return fig


def figure_pressure_difference(curves: PredictionCurves) -> Figure:
    """Q against ΔP at a fixed squeeze pressure (paper Fig. 5: linear through the origin).

    With effective-medium results for a case (model "both"), its Bruggeman leak rate is drawn dashed.
    """
    fig, ax = new_figure("Leak rate against fluid pressure difference")
    for sw in curves.pressure_difference:
        case, p0, dp = sw.case, sw.squeeze_pressure, sw.pressure_difference
        scale, unit = pressure_axis(np.array([p0]))
        label = (f"{case.label}, " if case.label else "") + f"P0 = {p0 / scale:.3g} {unit}"
        both = sw.effective_medium is not None
        line, = ax.plot(dp / 1e3, sw.critical_junction, "-", label=("critical junction, " if both else "") + label)
        if sw.effective_medium is not None:
            ax.plot(dp / 1e3, sw.effective_medium, "--", color=line.get_color(), label="effective medium, " + label)
    ax.set_xlabel("pressure difference ΔP = P_a - P_b (kPa)")
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    subtitle(ax, "Q = α (Ly/Lx) u_c³ ΔP/(12η): linear in ΔP at fixed P0 (P0 >> ΔP assumed)")
    ax.legend()
    return fig


def prediction_figures(results: Sequence[CaseResult], curves: PredictionCurves | None = None) -> dict[str, Figure]:
    """Every figure of a prediction, keyed by PNG file name.

    ``curves`` defaults to :func:`~sealeak.cases.prediction_curves` of ``results``. Effective-medium
    curves are drawn dashed next to the critical-junction ones (model "both"), or alone
    (model "effective-medium").
    """
    if curves is None:
        curves = prediction_curves(list(results))
    cases = [r.case for r in results]
    cj = [r.critical_junction for r in results]
    ems = [r.effective_medium for r in results]
    effective = ems if any(em is not None for em in ems) else None
    return {
        "spectrum.png": figure_spectrum(cases, curves),
        "contact_area.png": figure_contact_area(cases, curves),
        "separation.png": figure_separation(cases, curves),
        "gap_distribution.png": figure_gap_distribution(curves),
        "leak_rate.png": figure_leak_rate(cases, cj, log=False, effective=effective),
        "leak_rate_log.png": figure_leak_rate(cases, cj, log=True, effective=effective),
        "critical_junction.png": figure_critical_junction(cases, cj),
        "critical_magnification.png": figure_critical_magnification(cases, cj),
        "leak_rate_vs_pressure_difference.png": figure_pressure_difference(curves),
    }


def save_figures(figures: dict[str, Figure], folder: str | Path) -> list[str]:
    """Write figures as PNG into ``folder`` atomically; returns the paths written."""
    written = []
    for name, fig in figures.items():
        path = Path(folder) / name
        with atomic_write(path) as tmp:
            fig.savefig(tmp, format="png", bbox_inches="tight")
        written.append(str(path))
    return written


PREDICTION_FIGURE_NAMES = ("spectrum.png", "contact_area.png", "separation.png", "gap_distribution.png", "leak_rate.png",
                           "leak_rate_log.png", "critical_junction.png", "critical_magnification.png",
                           "leak_rate_vs_pressure_difference.png")
