"""Figures of a prediction (matplotlib, PNG).

One function per figure; each takes case results (:class:`~sealeak.cases.CaseResult`) and the
curves computed for them (:func:`~sealeak.cases.prediction_curves`) and returns a matplotlib
:class:`~matplotlib.figure.Figure`; nothing here computes physics. Figures are built without
pyplot, so importing sealeak never selects or changes a matplotlib backend (a notebook keeps its
own). :func:`prediction_figures` returns them all by file name; :func:`save_figures` renders them
all, then writes them atomically.
For O-ring and pressure-profile seals the figures against one squeeze pressure give way to the band
figures of :mod:`sealeak.render.band` (p(x), u_c(x), Q against the load); C(q) stays. The style
helpers every figure shares live in :mod:`sealeak.render.plotstyle` (re-exported here).
Every axis is labelled with its unit. The reference paper's theory figures are: C(q) (its Fig. 4),
Q against P0 on a linear and a log10 scale (Figs. 6, 7), the critical pore size against P0 (Fig. 8)
and ζc against P0 (Fig. 9); Q against ΔP (Fig. 5) and A(ζ), ū(ζ), u1(ζ) complete the set.

How the figures read (the same rules for the laboratory figures, :mod:`sealeak.render.lab_figures`):

* an axis whose values span more than two decades is logarithmic, with a labelled tick at least
  every few decades (1, 2, 5 within a decade or two); a linear axis carries its power of ten in
  the unit label ("leak rate Q (10⁻¹² m³/s)"), never as a floating offset;
* leak rates have a second axis in ml/min (the unit of the command-line table);
* points outside the theory's validity (:attr:`~sealeak.cases.CaseResult.valid`, docs/theory.md
  §9.11: u_c below the fluid's molecular size, or not a thin film) are drawn hollow, not joined to
  the curve, and do not set the axis limits; one beyond the limits is a hollow triangle at that edge;
* a legend sits inside the axes only where it covers no data, otherwise below the axes;
* a figure with nothing to draw says so on the figure (e.g. no leak channel at any pressure).
"""

from __future__ import annotations

import io
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..cases import Case, CaseResult, CurveSet, PredictionCurves, prediction_curves
from ..io.files import write_files
from ..io.units import length_unit
from ..physics.validity import pressures_text
from .band import BAND_FIGURE_NAMES, band_figures, is_band_run
from .life import as_assembled, life_figure_names, life_figures
from .plotstyle import (
    GAS_LEAK_LABEL,
    ML_PER_MIN_PER_M3_PER_S,
    PA_M3_PER_MBAR_L,
    Series,
    color,
    draw_limit,
    draw_series,
    finish_axes,
    gas_conditions_text,
    gas_regime_text,
    gas_series,
    invalid_note,
    laid_out,
    limit_in_axis_unit,
    log_axis,
    merge_identical,
    ml_per_min_axis,
    new_figure,
    pa_m3_axis,
    place_legend,
    power_unit,
    pressure_axis,
    say_nothing,
    series_peaks,
    spans_decades,
    subtitle,
    sweep_axis,
)

__all__ = ["prediction_figures", "save_figures", "render_figures", "pressure_axis", "PREDICTION_FIGURE_NAMES",
           "new_figure", "subtitle", "place_legend", "finish_axes", "log_axis", "power_unit", "spans_decades",
           "ml_per_min_axis", "say_nothing", "Series", "draw_series", "color", "ML_PER_MIN_PER_M3_PER_S", "pressure_x",
           "figure_png", "laid_out", "prediction_figure_names", "is_gas_run", "figure_gas_leak_rate"]


# ---------------------------------------------------------------------- the prediction figures
def _set_label(cs: CurveSet, curves: PredictionCurves) -> str:
    """Legend label of a curve set: its squeeze pressure (and, in a study, the variant's name)."""
    scale, unit = pressure_axis(cs.case.squeeze_pressure)
    label = f"P0 = {cs.squeeze_pressure / scale:.3g} {unit}"
    return f"{cs.case.label}, {label}" if len(curves.spectra) > 1 else label


def _label(case: Case, fallback: str = "") -> str:
    return case.label or fallback


def pressure_x(ax: Axes, p0: np.ndarray) -> float:
    """Label the x axis with the squeeze pressure and span the whole sweep (log when it spans decades); returns the scale.

    The axis covers every pressure of the sweep, also those with nothing to draw (no leak channel).
    """
    scale, unit = pressure_axis(p0)
    sweep_axis(ax, np.asarray(p0, dtype=float) / scale, f"squeeze pressure P0 ({unit})")
    return scale


def _say_full_contact(ax: Axes, what: str, closed: Sequence[CurveSet]) -> None:
    """Say on an empty axes that there is no ``what`` to draw: full contact at the pressures of ``closed``."""
    say_nothing(ax, f"no {what} to draw: the surfaces are in full contact\n"
                + pressures_text([cs.squeeze_pressure for cs in closed], [True] * len(closed)))


def _sweep_x(ax: Axes, results: Sequence[CaseResult]) -> float:
    """:func:`pressure_x` over the squeeze pressures (Pa) of every result's sweep; returns the scale."""
    return pressure_x(ax, np.concatenate([r.critical_junction.squeeze_pressure for r in results]))


def _subtitle_with_hollow(ax: Axes, notes: list[str], series: Sequence[Series]) -> None:
    """The subtitle: the notes, and the line on hollow markers when a series has any."""
    hollow = invalid_note(series)
    subtitle(ax, "\n".join([*notes, hollow] if hollow else notes))


@laid_out
def figure_spectrum(cases: Sequence[Case], spectra: Sequence[tuple[np.ndarray, np.ndarray]],
                    q0: tuple[float, float, str] | None = None) -> Figure:
    """C(q) against q, log-log, with q0 and the spectrum's nodes.

    ``spectra``: (q, C) of each case (:attr:`~sealeak.cases.PredictionCurves.spectra`); ``q0``:
    (lowest, highest, label) of the q0 a band seal's loads use (shaded when they differ), else the
    first case's q0 = 2π/L.
    """
    fig, ax = new_figure("Surface roughness power spectrum")
    # variants with the same spectrum (a study of fluids or loads) draw it once, named after all of them
    drawn = merge_identical(spectra, [_label(case, case.spectrum.label or "C(q)") for case in cases])
    for i, (k, labels) in enumerate(drawn):
        q, c = spectra[k]
        keep = np.isfinite(q) & np.isfinite(c) & (q > 0) & (c > 0)
        ax.loglog(q[keep], c[keep], color=color(i), label=", ".join(labels))
    case = cases[0]
    lo, hi, text = q0 if q0 is not None else (case.q0, case.q0, "q0 = 2π/L")
    if hi > lo * (1 + 1e-9):
        ax.axvspan(lo, hi, color="0.5", alpha=0.15, lw=0)
    ax.axvline(lo, color="0.5", ls=":", lw=1)
    ax.annotate(text, (lo, 0.03), xycoords=ax.get_xaxis_transform(), rotation=90, va="bottom", ha="right",
                fontsize=8, color="0.4")
    ax.set_xlabel("wavevector q (1/m)")
    ax.set_ylabel("power spectrum C(q) (m⁴)")
    stats = (f"h_rms = {case.spectrum.h_rms * 1e6:.3g} µm, slope_rms = {case.spectrum.slope_rms:.3g}, "
             f"A_true/A0 = {case.spectrum.area_ratio:.3g}") if len(drawn) == 1 else ""
    subtitle(ax, (case.spectrum_note + ("\n" + stats if stats else "")) if len(drawn) == 1 else "")
    finish_axes(ax)
    if len(drawn) > 1 or case.spectrum.label or any(len(labels) > 1 for _, labels in drawn):
        place_legend(ax)
    return fig


def _band_q0(results: Sequence[CaseResult]) -> tuple[float, float, str]:
    """(lowest, highest, label) of the q0 of every load of a band run (docs/theory.md §10.1)."""
    bands = [r.band for r in results if r.band is not None]
    q0 = np.concatenate([b.q0 for b in bands])
    own = all(np.allclose(b.q0, 2.0 * np.pi / b.contact_width, rtol=1e-12) for b in bands)
    many = q0.max() > q0.min() * (1 + 1e-9)
    label = ("q0 = 2π/w of each load (shaded)" if many else "q0 = 2π/w") if own else "q0 (set in the case file)"
    return float(q0.min()), float(q0.max()), label


@laid_out
def figure_contact_area(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """A(ζ)/A0 against ζ for a few squeeze pressures, with the percolation level 1 - p_c."""
    fig, ax = new_figure("Apparent relative contact area against magnification")
    for i, cs in enumerate(curves.sets):
        ax.semilogx(cs.zeta, cs.area, color=color(i), label=_set_label(cs, curves))
        if cs.percolates:
            ax.plot([cs.zeta_c], [1 - cs.case.percolation_threshold], "o", color=color(i), ms=4)
    pc = cases[0].percolation_threshold
    ax.axhline(1 - pc, color="k", ls="--", lw=0.8, label=f"percolation: A/A0 = 1 - p_c = {1 - pc:.2f}")
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("relative contact area A(ζ)/A0 (1)")
    ax.set_ylim(0, 1.02)
    closed = [cs for cs in curves.sets if not cs.percolates]
    subtitle(ax, "dots: critical magnification ζc" + (
        "\nno dot: A(ζ) stays above 1 - p_c up to the cut-off, no leak channel" if closed else ""))
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_separation(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """ū(ζ) (solid) and u1(ζ) (dashed) against ζ for the same squeeze pressures."""
    fig, ax = new_figure("Interfacial separation against magnification")
    top, bottom = 0.0, np.inf
    closed = [cs for cs in curves.sets if cs.in_full_contact]
    hollow = False
    for i, cs in enumerate(curves.sets):
        if cs.in_full_contact:
            continue
        label, z, ubar, u1 = _set_label(cs, curves), cs.zeta[:-1], cs.mean_gap, cs.u1
        top = max(top, 3.0 * ubar[0])
        bottom = min(bottom, 1e-3 * ubar[0])
        shown = ubar > 1e-6 * ubar[0]
        ax.loglog(z[shown], ubar[shown] * 1e6, color=color(i), label=label)
        shown = np.isfinite(u1) & (u1 > 1e-6 * ubar[0]) & (u1 < 1e3 * ubar[0])
        ax.loglog(z[1:][shown], u1[shown] * 1e6, ls="--", color=color(i))
        if cs.percolates and np.isfinite(cs.u1_c) and cs.u1_c > 0:
            hollow |= not cs.valid
            ax.plot([cs.zeta_c], [cs.u1_c * 1e6], "o", color=color(i), ms=4.5,
                    mfc=color(i) if cs.valid else "none")
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("separation (µm)")
    if top == 0.0:
        _say_full_contact(ax, "separation", closed)
        ax.set_xscale("log")
        ax.set_xlim(1.0, max(float(cs.zeta[-1]) for cs in curves.sets))
        finish_axes(ax)
        return fig
    ax.set_ylim(bottom * 1e6, top * 1e6)
    d = cases[0].fluid.molecular_length
    if bottom < d < top:
        ax.axhline(d * 1e6, color="0.3", ls=":", lw=1, label=f"molecular size d = {d * 1e9:.2g} nm")
    notes = ["solid: mean separation ū(ζ); dashed: u1(ζ); dots: u_c = u1(ζc)"
             + ("; hollow: u_c below molecular size" if hollow else "")]
    if closed:
        notes.append("full contact (nothing to draw) at "
                     + ", ".join(f"{cs.squeeze_pressure / pressure_axis([cs.squeeze_pressure])[0]:.3g} "
                                 f"{pressure_axis([cs.squeeze_pressure])[1]}" for cs in closed))
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_gap_distribution(curves: PredictionCurves) -> Figure:
    """P(u) (continuous part) for a few squeeze pressures; the δ(u) weight A(ζ1)/A0 in the legend."""
    fig, ax = new_figure("Distribution of interfacial separations P(u)")
    # u P(u) on a log u axis: the probability per unit ln u, readable across scales
    u = curves.gap
    top = 0.0
    closed = []
    for i, (cs, y) in enumerate(zip(curves.sets, curves.gap_density)):
        d = cs.distribution
        if cs.in_full_contact or not u.size:
            closed.append(cs)
            continue
        top = max(top, float(np.nanmax(y)))
        ax.semilogx(u * 1e6, y, color=color(i),
                    label=f"{_set_label(cs, curves)}: δ(u) weight A(ζ1)/A0 = {d.contact_fraction[0]:.3g}")
        ax.axvline(d.mean_gap[0] * 1e6, color=color(i), ls=":", lw=1)
    ax.set_xlabel("interfacial separation u (µm)")
    ax.set_ylabel("u·P(u), probability per unit ln u (1)")
    if top == 0.0:
        _say_full_contact(ax, "gap distribution", closed)
        ax.set_xscale("log")
        ax.set_xlim(1e-4, 1e2)
        finish_axes(ax)
        return fig
    ax.set_xlim(u[0] * 1e6, u[-1] * 1e6)
    ax.set_ylim(0, 1.05 * top)
    subtitle(ax, "continuous part of P(u) (the δ(u) contact weight is in the legend); dotted: ū(1)"
             + ("\nfull contact (δ(u) weight 1) at " + pressures_text([c.squeeze_pressure for c in closed],
                                                                     [True] * len(closed)) if closed else ""))
    finish_axes(ax)
    place_legend(ax)
    return fig


def _settings(case: Case) -> str:
    return (f"α = {case.alpha:g}, ΔP = {case.pressure_difference / 1e3:.3g} kPa, "
            f"η = {case.fluid.viscosity * 1e3:.3g} mPa·s, Ly/Lx = {case.seal.aspect_ratio:.3g}, "
            f"p_c = {case.percolation_threshold:g}, γ = {case.gamma:g}")


def _no_leak_text(results: Sequence[CaseResult]) -> str:
    """Why a leak-rate figure is empty: no leak channel anywhere, or Q = 0 where there is one."""
    channel = any(r.critical_junction.percolates.any() or (r.effective_medium is not None and r.effective_medium.percolates.any())
                  for r in results)
    p0 = np.concatenate([r.critical_junction.squeeze_pressure for r in results])
    if channel:
        return f"the leak rate is zero at every squeeze pressure\n(ΔP = {results[0].case.pressure_difference:.3g} Pa)"
    return "no leak channel at any squeeze pressure\n(the non-contact area does not percolate: " + pressures_text(p0, np.ones(p0.size, bool)) + ")"


def _leak_series(results: Sequence[CaseResult], x_scale: float) -> list[Series]:
    """The leak-rate series of a run: critical junction (solid) and effective medium (dashed, or solid alone)."""
    out = []
    several = len(results) > 1
    for i, r in enumerate(results):
        res, em = r.critical_junction, r.effective_medium
        name = r.case.label if several else ""
        x = res.squeeze_pressure / x_scale
        if r.shows_critical_junction:
            label = name or ("critical junction" if em is not None else None)
            if em is not None and name:
                label = f"{name}, critical junction"
            out.append(Series(x, res.leak_rate, r.valid, color(i), "-", label or None, r.validity))
        if em is not None:
            valid = r.valid_effective_medium if r.valid_effective_medium is not None else np.ones(len(em), bool)
            why = r.validity_effective_medium or ()
            label = (f"{name}, effective medium" if name else "effective medium (Bruggeman)") if r.shows_critical_junction else (name or None)
            out.append(Series(em.squeeze_pressure / x_scale, np.where(em.percolates, em.leak_rate, np.nan), valid, color(i),
                              "--" if r.shows_critical_junction else "-", label, why))
    return out


@laid_out
def figure_leak_rate(results: Sequence[CaseResult], log: bool, limit: tuple[float, str] | None = None) -> Figure:
    """Q against P0, linear (paper Fig. 6) or log (paper Fig. 7), with a second axis in ml/min.

    Effective-medium curves (model "both") are drawn dashed next to the critical-junction ones, or
    alone (model "effective-medium"). The linear figure turns logarithmic when the curves' maxima
    differ by more than two decades (on a linear axis all but the largest would lie flat on zero).
    For gas cases the figure draws the gas leak rate instead (:func:`figure_gas_leak_rate`). ``limit``:
    ``conditions.max_leak_rate`` as :func:`~sealeak.render.life.volume_limit` gives it (m³/s, a gas's Pa·m³/s), drawn
    as a line.
    """
    if is_gas_run(results):
        return figure_gas_leak_rate(results, log, limit)
    cases = [r.case for r in results]
    fig, ax = new_figure("Leak rate against squeeze pressure" + (" (log scale)" if log else ""))
    scale = _sweep_x(ax, results)
    series = _leak_series(results, scale)
    peaks = series_peaks(series)
    logy = log or spans_decades(peaks, 1.0)  # a curve below a tenth of the largest would lie flat on zero
    shown_cj = any(r.shows_critical_junction for r in results)
    shown_em = any(r.effective_medium is not None for r in results)
    settings = _settings(cases[0]) if shown_cj else (
        f"effective medium (2D Bruggeman, no fit factor): ΔP = {cases[0].pressure_difference / 1e3:.3g} kPa, "
        f"η = {cases[0].fluid.viscosity * 1e3:.3g} mPa·s, Ly/Lx = {cases[0].seal.aspect_ratio:.3g}, γ = {cases[0].gamma:g}")
    if shown_em and shown_cj:
        settings += "\nsolid: critical junction; dashed: effective medium (no fit factor)"
    any_q = any(np.any(np.isfinite(s.y) & (s.y > 0)) for s in series)
    if not any_q:
        say_nothing(ax, _no_leak_text(results))
        ax.set_ylabel("leak rate Q (m³/s)")
        subtitle(ax, settings)
        finish_axes(ax)
        return fig
    qscale, qunit = (1.0, "m³/s") if logy else power_unit(peaks, "m³/s")
    _finish_leak_rate(ax, results, series, [settings], qscale, f"leak rate Q ({qunit})", log, logy, ml_per_min_axis, limit)
    return fig


def _finish_leak_rate(ax: Any, results: Sequence[CaseResult], series: list[Series], notes: list[str], qscale: float,
                      ylabel: str, log: bool, logy: bool, second_axis: Callable[[Any, float], Any],
                      limit: tuple[float, str] | None = None) -> None:
    """Draw a leak-rate figure's series (scaled by 1/``qscale``), ``conditions.max_leak_rate`` (``limit``, in the series'
    unit; :func:`~sealeak.render.plotstyle.draw_limit`), its notes (log scale, missing points, hollow markers), the
    second unit axis and the legend: shared by the liquid and the gas figure."""
    scaled = [Series(s.x, s.y / qscale, s.valid, s.color, s.style, s.label, s.why) for s in series]
    draw_series(ax, scaled, logy=logy, bottom_zero=not logy)
    ax.set_ylabel(ylabel)
    notes = list(notes)
    if where := draw_limit(ax, limit, qscale):
        notes.append(where)
    elif limit is not None and not logy:  # (Q falls about exponentially with the load: a chord overstates it)
        notes.append("linear axis: straight lines join the rows, so where they cross max_leak_rate is not where Q does; "
                     "read that on leak_rate_log.png")
    if not log and logy:
        notes.append("log scale: the curves differ by decades")
    notes += _missing_note(results, leak_rates=True)
    _subtitle_with_hollow(ax, notes, series)
    finish_axes(ax)
    second_axis(ax, qscale)
    place_legend(ax)


def is_gas_run(results: Sequence[CaseResult]) -> bool:
    """Whether every result is a gas case with gas leak rates (docs/theory.md §11.9): its figures show Q_pV, not K ΔP."""
    return bool(results) and all(r.case.gas is not None and r.gas for r in results)


def _gas_leak_series(results: Sequence[CaseResult], x_scale: float) -> tuple[list[Series], list]:
    """Per case and theory, in its own colour: the gas leak (solid) and the helium equivalent (dashed), mbar·l/s."""
    several = len(results) > 1
    out: list[Series] = []
    rows = []
    k = 0
    for r in results:
        gas = r.gas or {}
        theories = []
        if r.shows_critical_junction and "critical_junction" in gas:
            theories.append(("critical junction", gas["critical_junction"], r.valid, r.validity))
        if r.effective_medium is not None and "effective_medium" in gas:
            valid = r.valid_effective_medium if r.valid_effective_medium is not None else np.ones(len(r.effective_medium), bool)
            theories.append(("effective medium", gas["effective_medium"], valid, r.validity_effective_medium or ()))
        x = r.critical_junction.squeeze_pressure / x_scale
        for name, g, valid, why in theories:
            label = f"{r.case.label}, {name}" if several and r.case.label else name
            out += gas_series(x, g, valid, why, color(k), label)
            rows.append(g)
            k += 1
    return out, rows


@laid_out
def figure_gas_leak_rate(results: Sequence[CaseResult], log: bool, limit: tuple[float, str] | None = None) -> Figure:
    """The gas leak rate Q_pV (mbar·l/s, second axis Pa·m³/s) against P0 for gas cases (docs/theory.md §11.5, §11.9).

    Each theory in its own colour: the case's gas solid, its helium-equivalent leak rate (1 bar helium
    against vacuum, 20 °C) dashed where computed and not the same numbers. The heading names the gas;
    the first subtitle line its T, P_a and P_b; the Knudsen numbers and flow regimes of the drawn
    points follow. The values are the records' ``leak_rate_mbar_l_s`` (and ``leak_rate_helium_mbar_l_s``).
    """
    case = results[0].case
    names = sorted({r.case.gas.gas.name for r in results if r.case.gas is not None})
    fig, ax = new_figure(f"Leak rate of {' / '.join(names)} against squeeze pressure" + (" (log scale)" if log else ""))
    scale = _sweep_x(ax, results)
    series, rows = _gas_leak_series(results, scale)
    conditions = {gas_conditions_text(r.case) for r in results}
    notes = [gas_conditions_text(case) if len(conditions) == 1 else "gas conditions differ between the variants (see the text output)"]
    formula = ("Q_pV with the gas pressure taken off the contact (theory §13.5)" if case.coupled
               else "Q_pV = K ∫ p f(Kn) dp over P_b…P_a")
    settings = f"{formula}, Ly/Lx = {case.seal.aspect_ratio:.3g}"
    if any(r.shows_critical_junction for r in results):
        settings += f", α = {case.alpha:g}"
    if any(s.style == "--" for s in series):
        settings += "; dashed: helium equivalent (1 bar He against vacuum, 20 °C)"
    notes.append(settings)
    regime = gas_regime_text(rows)
    if regime:
        notes.append(regime)
    peaks = series_peaks(series)
    logy = log or spans_decades(peaks, 1.0)
    if not any(np.any(np.isfinite(s.y) & (s.y > 0)) for s in series):
        say_nothing(ax, _no_leak_text(results))
        ax.set_ylabel(f"{GAS_LEAK_LABEL} (mbar·l/s)")
        subtitle(ax, "\n".join(notes))
        finish_axes(ax)
        return fig
    qscale, qunit = (1.0, "mbar·l/s") if logy else power_unit(peaks, "mbar·l/s")
    _finish_leak_rate(ax, results, series, notes, qscale, f"{GAS_LEAK_LABEL} ({qunit})", log, logy, pa_m3_axis,
                      limit_in_axis_unit(limit, gas=True))
    return fig


def _missing_note(results: Sequence[CaseResult], leak_rates: bool = False) -> list[str]:
    """The subtitle line of a figure whose axis spans pressures without a leak channel (nothing drawn there), or none:
    of the critical junction's figures, or with ``leak_rates`` of the leak-rate figures (the critical junction where
    shown, the effective medium where computed)."""
    missing = any((~r.critical_junction.percolates).any() for r in results if r.shows_critical_junction or not leak_rates)
    missing = missing or (leak_rates and any(r.effective_medium is not None and (~r.effective_medium.percolates).any()
                                             for r in results))
    return ["missing points: no leak channel (the non-contact area does not percolate)"] if missing else []


@laid_out
def figure_critical_junction(results: Sequence[CaseResult]) -> Figure:
    """u_c (solid) and λc (dashed) against P0 (the critical pore size, paper Fig. 8)."""
    fig, ax = new_figure("Critical constriction against squeeze pressure")
    scale = _sweep_x(ax, results)
    # one length unit for both curves, chosen by the smaller quantity (the valid gaps)
    gaps = np.concatenate([np.where(r.valid, r.critical_junction.critical_gap, np.nan) for r in results])
    lscale, lunit = length_unit(gaps)
    several = len(results) > 1
    series = []
    for i, r in enumerate(results):
        res = r.critical_junction
        x = res.squeeze_pressure / scale
        series.append(Series(x, res.critical_gap / lscale, r.valid, color(i), "-",
                             r.case.label if several else "height u_c", r.validity))
        series.append(Series(x, res.critical_wavelength / lscale, r.valid, color(i), "--",
                             None if several else "width λc = L/ζc"))
    ax.set_ylabel(f"critical pore size ({lunit})")
    if not draw_series(ax, series, logy=True):
        ax.set_yscale("linear")
        say_nothing(ax, _no_leak_text(results).replace("the leak rate is zero", "no critical constriction"))
        finish_axes(ax)
        return fig
    lo, hi = ax.get_ylim()
    d = results[0].case.fluid.molecular_length / lscale
    notes = ["solid: height u_c; dashed: width λc = L/ζc"] if several else []
    if lo < d < hi:
        ax.axhline(d, color="0.3", ls=":", lw=1, label=f"molecular size d = {d * lscale * 1e9:.2g} nm")
    if len(results) == 1:
        res = results[0].critical_junction
        ok = res.percolates & results[0].valid
        if ok.any():
            ratio = np.median(res.critical_wavelength[ok] / res.critical_gap[ok])
            notes.append(f"median λc/u_c = {ratio:.3g}")
    notes += _missing_note(results)
    _subtitle_with_hollow(ax, notes, series)
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_critical_magnification(results: Sequence[CaseResult]) -> Figure:
    """ζc against P0 (paper Fig. 9); log when ζc spans more than two decades."""
    fig, ax = new_figure("Critical magnification against squeeze pressure")
    scale = _sweep_x(ax, results)
    several = len(results) > 1
    series = [Series(r.critical_junction.squeeze_pressure / scale, r.critical_junction.critical_magnification, r.valid,
                     color(i), "-", r.case.label if several else None, r.validity) for i, r in enumerate(results)]
    values = np.concatenate([np.where(s.valid, s.y, np.nan) for s in series])
    ax.set_ylabel("critical magnification ζc (1)")
    if not draw_series(ax, series, logy=spans_decades(values)):
        say_nothing(ax, _no_leak_text(results).replace("the leak rate is zero", "no critical magnification"))
        finish_axes(ax)
        return fig
    notes = [f"A(ζc)/A0 = 1 - p_c = {1 - results[0].case.percolation_threshold:.2f}", *_missing_note(results)]
    _subtitle_with_hollow(ax, notes, series)
    finish_axes(ax)
    place_legend(ax)
    return fig


#: The title line of a gas's Q_pV(ΔP) figure, uncoupled (False) or with the fluid pressure coupled in any case (True).
_GAS_SWEEP_FORMULA = {False: "Q_pV = K ∫ p f(Kn) dp at fixed P_b: not linear in ΔP (no slip: K (P_a² − P_b²)/2)",
                      True: "Q_pV at fixed P_b, the gas pressure taken off the contact (theory §13.5): not linear in ΔP"}


@laid_out
def figure_pressure_difference(curves: PredictionCurves) -> Figure:
    """Q against ΔP at a fixed squeeze pressure (paper Fig. 5: linear through the origin), with ml/min.

    With effective-medium results for a case (model "both"), its Bruggeman leak rate is drawn dashed.
    When the cases' leak rates differ by more than a decade, or one curve spans more than two, both axes are
    logarithmic (Q ∝ ΔP is then a line of slope one).

    For gas cases (every case of the run a gas) it draws the pV throughput Q_pV = K ∫ p f(Kn) dp from P_b
    to P_b + ΔP at the case's downstream pressure P_b (mbar·l/s, second axis Pa·m³/s; docs/theory.md §11.5,
    §11.9): curved, since the flow is compressible (no slip: K (P_a² − P_b²)/2) and the Knudsen number
    falls as the pressure rises; a dotted line marks the case's own ΔP. With the fluid pressure coupled each point is the
    exact gas coupling at its P_a (§13.5).
    """
    fig, ax = new_figure("Leak rate against fluid pressure difference")
    ax.set_xlabel("pressure difference ΔP = P_a - P_b (kPa)")
    gas = bool(curves.pressure_difference) and all(sw.gas for sw in curves.pressure_difference)
    sweeps = curves.pressure_difference
    ylabel = f"{GAS_LEAK_LABEL} (mbar·l/s)" if gas or (curves.sets and all(cs.case.gas is not None for cs in curves.sets)) \
        else "leak rate Q (m³/s)"
    if not sweeps:
        say_nothing(ax, "no leak channel at any squeeze pressure:\nno leak rate to draw against ΔP")
        ax.set_ylabel(ylabel)
        finish_axes(ax)
        return fig
    several = len({id(sw.case) for sw in sweeps}) > 1
    series = []
    for i, sw in enumerate(sweeps):
        case, p0, dp = sw.case, sw.squeeze_pressure, sw.pressure_difference
        scale, unit = pressure_axis(np.array([p0]))
        label = (f"{case.label}, " if several and case.label else "") + f"P0 = {p0 / scale:.3g} {unit}"
        both = sw.effective_medium is not None
        if case.model != "effective-medium" or not both:
            series.append(Series(dp / 1e3, sw.critical_junction, np.full(dp.size, sw.valid), color(i), "-",
                                 ("critical junction, " if both else "") + label))
        if sw.effective_medium is not None:
            series.append(Series(dp / 1e3, sw.effective_medium, np.full(dp.size, sw.valid_effective_medium), color(i),
                                 "--" if case.model != "effective-medium" else "-",
                                 ("effective medium, " if case.model != "effective-medium" else "") + label))
    if gas:  # pV throughputs in the leak-test unit
        series = [Series(s.x, s.y / PA_M3_PER_MBAR_L, s.valid, s.color, s.style, s.label, s.why) for s in series]
    peaks = series_peaks(series)
    if not peaks and not any(np.any(np.isfinite(s.y) & (s.y > 0)) for s in series):
        say_nothing(ax, "the leak rate is zero at every pressure difference")
        ax.set_ylabel(ylabel)
        finish_axes(ax)
        return fig
    # log-log where the cases differ by a decade, or where one curve spans two (a coupled gas leak grows steeply with ΔP)
    log = spans_decades(peaks, 1.0) or any(spans_decades(s.y, 2.0) for s in series)
    base = "mbar·l/s" if gas else "m³/s"
    qscale, qunit = (1.0, base) if log else power_unit(peaks, base)
    scaled = [Series(s.x, s.y / qscale, s.valid, s.color, s.style, s.label, s.why) for s in series]
    draw_series(ax, scaled, logy=log, logx=log, bottom_zero=not log)
    if not log:
        ax.set_xlim(left=0)
    if gas:
        ax.set_ylabel(f"{GAS_LEAK_LABEL} ({qunit})")
        for dp_case in sorted({sw.case.pressure_difference for sw in sweeps}):
            ax.axvline(dp_case / 1e3, color="0.5", lw=0.8, ls=":")
        conditions = {gas_conditions_text(sw.case) for sw in sweeps}
        notes = [next(iter(conditions)) if len(conditions) == 1 else "gas conditions differ between the variants (see the text output)",
                 _GAS_SWEEP_FORMULA[len({sw.case.coupled for sw in sweeps}) > 1 or sweeps[0].case.coupled],
                 "dotted: the case's ΔP"]
        if log:
            notes.append("log-log: the leak rates differ by decades")
    else:
        ax.set_ylabel(f"leak rate Q ({qunit})")
        formulas = []
        if any(sw.case.model != "effective-medium" or sw.effective_medium is None for sw in sweeps):
            formulas.append("Q = α (Ly/Lx) u_c³ ΔP/(12η)")
        if any(sw.effective_medium is not None for sw in sweeps):
            formulas.append("Q = (Ly/Lx) σ_eff ΔP (effective medium)")
        coupled = {sw.case.coupled for sw in sweeps}
        if coupled == {False}:
            notes = [", ".join(formulas) + ": linear in ΔP at fixed P0 (P0 >> ΔP assumed)"]
        else:  # docs/theory.md §13.2: Q = (Ly/Lx) ∫σ(s) ds over P0 − ΔP … P0
            integrals = {"Q = α (Ly/Lx) u_c³ ΔP/(12η)": "Q = (Ly/Lx) ∫ α u_c(s)³/(12η) ds",
                         "Q = (Ly/Lx) σ_eff ΔP (effective medium)": "Q = (Ly/Lx) ∫ σ_eff(s) ds (effective medium)"}
            notes = [", ".join(integrals[f] for f in formulas) + ", s from P0 − ΔP to P0",
                     "the fluid pressure opens the contact (theory §13): Q grows faster than ΔP at fixed P0"
                     if coupled == {True} else "linear in ΔP where the fluid pressure is ignored, faster where it is coupled "
                                               "(theory §13)"]
        if any(sw.case.capillarity is not None for sw in sweeps):  # docs/theory.md §12
            notes.append("0 below the capillary entry pressure p_e of the narrowest gap (held by capillarity)")
        if log:
            notes.append("log-log: the cases' leak rates differ by decades (Q ∝ ΔP has slope one)")
    if not all(s.valid.all() for s in series):
        notes.append("hollow markers: outside the theory's validity at that P0")
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    (pa_m3_axis if gas else ml_per_min_axis)(ax, qscale)
    place_legend(ax)
    return fig


def prediction_figures(results: Sequence[CaseResult], curves: PredictionCurves | None = None,
                       limit: tuple[float, str] | None = None) -> dict[str, Figure]:
    """Every figure of a prediction, keyed by PNG file name (:func:`prediction_figure_names`).

    ``limit``: ``conditions.max_leak_rate`` (m³/s, as written) for the figures of the seal over its life
    (:func:`~sealeak.render.life.volume_limit`).

    ``curves`` defaults to :func:`~sealeak.cases.prediction_curves` of ``results``. Effective-medium
    curves are drawn dashed next to the critical-junction ones (model "both"), or alone
    (model "effective-medium"). For O-ring and pressure-profile seals (every result has a
    ``band``) the figures against one squeeze pressure P0 make no sense: C(q) stays, with the
    loads' q0, and the band figures of :mod:`sealeak.render.band` replace the rest (``curves`` is
    not used; of a file of the seal over its life they draw the case as assembled,
    :func:`~sealeak.render.life.as_assembled`).
    """
    cases = [r.case for r in results]
    if is_band_run(results):
        shown = as_assembled(results)  # a life file's band figures: the seal as assembled (the same surface in each)
        spectra = [r.case.spectrum.sample(400) for r in shown]
        band = {"spectrum.png": figure_spectrum([r.case for r in shown], spectra, _band_q0(shown))} | band_figures(shown, limit)
        return band | life_figures(results, limit)
    if curves is None:
        curves = prediction_curves(list(results))
    return {
        "spectrum.png": figure_spectrum(cases, curves.spectra),
        "contact_area.png": figure_contact_area(cases, curves),
        "separation.png": figure_separation(cases, curves),
        "gap_distribution.png": figure_gap_distribution(curves),
        "leak_rate.png": figure_leak_rate(results, log=False, limit=limit),
        "leak_rate_log.png": figure_leak_rate(results, log=True, limit=limit),
        "critical_junction.png": figure_critical_junction(results),
        "critical_magnification.png": figure_critical_magnification(results),
        "leak_rate_vs_pressure_difference.png": figure_pressure_difference(curves),
    } | life_figures(results, limit)


def prediction_figure_names(cases: Sequence[Case]) -> tuple[str, ...]:
    """The files :func:`prediction_figures` writes for these cases (known before they are run)."""
    points = [c.life for c in cases if c.life is not None]
    life = life_figure_names(len({p.time for p in points}), len({p.temperature for p in points}))
    if cases and all(c.band is not None for c in cases):
        return ("spectrum.png", *BAND_FIGURE_NAMES, *life)
    return (*PREDICTION_FIGURE_NAMES, *life)


def figure_png(fig: Figure) -> bytes:
    """The PNG bytes of a figure (cropped to what it draws)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", bbox_inches="tight")
    return buf.getvalue()


def render_figures(figures: dict[str, Figure]) -> dict[str, bytes]:
    """Every figure as PNG bytes, by file name (render all before writing any: a failure leaves no file)."""
    return {name: figure_png(fig) for name, fig in figures.items()}


def save_figures(figures: dict[str, Figure] | dict[str, bytes], folder: str | Path) -> list[str]:
    """Write figures (or their PNG bytes) into ``folder``, all rendered first, all or none
    (:func:`~sealeak.io.files.write_files`); returns the paths written."""
    return write_files({str(Path(folder) / name): f if isinstance(f, bytes) else figure_png(f) for name, f in figures.items()})


PREDICTION_FIGURE_NAMES = ("spectrum.png", "contact_area.png", "separation.png", "gap_distribution.png", "leak_rate.png",
                           "leak_rate_log.png", "critical_junction.png", "critical_magnification.png",
                           "leak_rate_vs_pressure_difference.png")
