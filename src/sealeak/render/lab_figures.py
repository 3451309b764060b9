"""Figures of the fit, the linearity check and the virtual rig (matplotlib, PNG; axes with units).

They follow the rules of :mod:`sealeak.render.figures`: log axes where values span decades, the
power of ten in the unit label, leak rates also in ml/min, legends where they cover no data, and
a figure with nothing to draw says so.
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..cases import FitResult, LinearityCheck
from ..lab.rig import ReadingsAnalysis, RigSetup, WaterColumn
from .figures import (
    color,
    finish_axes,
    laid_out,
    ml_per_min_axis,
    new_figure,
    place_legend,
    power_unit,
    pressure_x,
    say_nothing,
    subtitle,
)

__all__ = ["figure_fit", "figure_linearity", "figure_rig", "figure_readings"]

_NAMES = {"critical_junction": "critical junction", "effective_medium": "effective medium"}


@laid_out
def figure_fit(result: FitResult) -> Figure:
    """Measured Q against P0 (log scale) with both fitted models, and a second axis in ml/min."""
    fig, ax = new_figure("Measured leak rate and fitted theory")
    p0 = result.data.squeeze_pressure
    q, grid, models, fits = result.measured, result.grid, result.curves, result.fits
    same, ref_dp = result.same_pressure_difference, result.reference_pressure_difference
    scale = pressure_x(ax, np.concatenate([p0, grid]))
    ax.set_yscale("log")
    pos = np.isfinite(q) & (q > 0)
    ax.plot(p0[pos] / scale, q[pos], "ks", ms=4, label="measured")
    for i, (name, curve) in enumerate(models.items()):
        fit = fits[name]
        y = fit.alpha * np.asarray(curve, dtype=float)
        shown = np.isfinite(y) & (y > 0)
        if fit.fitted and shown.any():
            ax.plot(grid / scale, np.where(shown, y, np.nan), ("-", "--")[i % 2], color=color(i),
                    label=f"{_NAMES[name]}: α = {fit.alpha:.3g} ± {fit.alpha_std:.2g}, "
                          f"rms {fit.rms_log10_residual:.2g} decades")
    ax.set_ylabel("leak rate Q (m³/s)")
    note = f"ΔP = {ref_dp / 1e3:.3g} kPa" + ("" if same else " (measurements scaled to it, Q ∝ ΔP)")
    excluded = sum(len(f.excluded) for f in fits.values())
    subtitle(ax, note + (f"; {excluded} point exclusions (see the text output)" if excluded else ""))
    if not pos.any():
        ax.set_yscale("linear")
        say_nothing(ax, "no measured leak rate above zero to draw")
        finish_axes(ax)
        return fig
    finish_axes(ax)
    ml_per_min_axis(ax)
    place_legend(ax)
    return fig


def _leak_axis(ax: Axes, values: np.ndarray) -> float:
    """Label a linear leak-rate axis with its power of ten; returns the scale the values are divided by."""
    qscale, qunit = power_unit(values, "m³/s")
    ax.set_ylabel(f"leak rate Q ({qunit})")
    return qscale


def _model_lines(ax: Axes, x: np.ndarray, models: dict[str, np.ndarray], qscale: float) -> list[str]:
    """Draw the models' lines Q = K ΔP under the limits the data set; returns the names of those that leave the axes."""
    ax.autoscale_view()
    top = ax.get_ylim()[1]
    hidden = []
    for i, (name, y) in enumerate(models.items()):
        ax.plot(x / 1e3, y / qscale, ("--", ":")[i % 2], color=color(i + 1), label=name)
        if y.max() / qscale > 1.5 * top:
            hidden.append(name)
    ax.set_ylim(0, top)  # the measurements set the scale; a model far above them leaves the axes
    return hidden


@laid_out
def figure_linearity(dp: np.ndarray, q: np.ndarray, check: LinearityCheck) -> Figure:
    """Measured Q against ΔP with the fitted straight line (and the models' lines through 0), with ml/min."""
    line, model_lines, p0 = check.line, check.model_slopes, check.squeeze_pressure
    fig, ax = new_figure("Leak rate against pressure difference")
    x = np.linspace(0.0, dp.max() * 1.1, 50)
    fitted = line.slope * x + line.intercept
    qscale = _leak_axis(ax, np.concatenate([q, fitted]))
    ax.plot(dp / 1e3, q / qscale, "ks", ms=4, label="measured")
    ax.plot(x / 1e3, fitted / qscale, "-", color=color(0),
            label=f"fit: slope {line.slope:.3g} ± {line.slope_std:.2g} m³/(s·Pa),\n"
                  f"intercept {line.intercept:.2g} ± {line.intercept_std:.2g} m³/s")
    ax.set_ylim(bottom=0)
    hidden = _model_lines(ax, x, {name: slope * x for name, slope in model_lines.items()}, qscale)
    ax.set_xlabel("pressure difference ΔP (kPa)")
    ax.set_xlim(left=0)
    notes = [f"P0 = {p0 / 1e3:.3g} kPa" if p0 else "", "beyond the axes: " + ", ".join(hidden) if hidden else ""]
    subtitle(ax, "; ".join(n for n in notes if n))
    finish_axes(ax)
    ml_per_min_axis(ax, qscale)
    place_legend(ax)
    return fig


@laid_out
def figure_rig(rig: RigSetup, columns: dict[str, WaterColumn], p0: float) -> Figure:
    """Water height against time for each model (WaterColumn solutions)."""
    fig, ax = new_figure("Virtual water-column rig: level against time")
    longest = max((c.time[-1] for c in columns.values()), default=1.0)
    tscale, tunit = (3600.0, "h") if longest > 7200 else ((60.0, "min") if longest > 120 else (1.0, "s"))
    for i, (name, col) in enumerate(columns.items()):
        label = name + (f": H = {col.final_height * 100:.3g} cm after {col.time_to_final / tscale:.3g} {tunit}"
                        if np.isfinite(col.time_to_final) else ": no leak, the level stays")
        ax.plot(col.time / tscale, col.height * 100, ("-", "--")[i % 2], color=color(i), label=label)
        if np.isfinite(col.time_to_final):
            ax.plot([col.time_to_final / tscale], [col.final_height * 100], "o", color=color(i), ms=4)
    ax.set_xlabel(f"time t ({tunit})")
    ax.set_ylabel("water height H (cm)")
    ax.set_ylim(0, 1.08 * rig.initial_height * 100)
    ax.set_xlim(left=0)
    subtitle(ax, f"P0 = {p0 / 1e3:.3g} kPa ({rig.load_note or 'load'}), cylinder {rig.cylinder_diameter * 100:.3g} cm, "
                  f"ΔP = ρgH, ρ = {rig.density:g} kg/m³\ndots: the final height reached")
    if not columns:
        say_nothing(ax, "no model to simulate")
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_readings(analysis: ReadingsAnalysis, model_conductance: dict[str, float]) -> Figure:
    """Leak rate against ΔP from rig readings, with the exponential-fit conductance and the models (ml/min too)."""
    fig, ax = new_figure("Leak rate from the rig readings")
    dp = analysis.interval_pressure_difference
    x = np.linspace(0.0, dp.max() * 1.1, 50)
    fitted = analysis.conductance * x
    models = {name: k * x for name, k in model_conductance.items()}
    qscale = _leak_axis(ax, np.concatenate([analysis.interval_leak_rate, fitted]))
    ax.plot(dp / 1e3, analysis.interval_leak_rate / qscale, "ks", ms=4, label="readings: Q = -A_cyl ΔH/Δt")
    ax.plot(x / 1e3, fitted / qscale, "-", color=color(0),
            label=f"fit of ln H(t): Q = K ΔP, K = {analysis.conductance:.3g} ± {analysis.conductance_std:.2g} m³/(s·Pa)")
    ax.set_ylim(bottom=0)
    hidden = _model_lines(ax, x, models, qscale)
    ax.set_xlabel("pressure difference ΔP = ρgH (kPa)")
    ax.set_xlim(left=0)
    if hidden:
        subtitle(ax, "beyond the axes: " + ", ".join(hidden) + " (K in the text output)")
    finish_axes(ax)
    ml_per_min_axis(ax, qscale)
    place_legend(ax)
    return fig
