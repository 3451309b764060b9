"""Figures of the fit, the linearity check and the virtual rig (matplotlib, PNG; axes with units)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ..cases import FitResult, LinearityCheck
from ..lab.rig import ReadingsAnalysis, RigSetup, WaterColumn
from .figures import new_figure, pressure_axis, subtitle

__all__ = ["figure_fit", "figure_linearity", "figure_rig", "figure_readings"]

_NAMES = {"critical_junction": "critical junction", "effective_medium": "effective medium"}


def figure_fit(result: FitResult) -> Figure:
    """Measured Q against P0 (log scale) with both fitted models."""
    fig, ax = new_figure("Measured leak rate and fitted theory")
    p0 = result.data.squeeze_pressure
    q, grid, models, fits = result.measured, result.grid, result.curves, result.fits
    same, ref_dp = result.same_pressure_difference, result.reference_pressure_difference
    scale, unit = pressure_axis(p0)
    pos = q > 0
    ax.semilogy(p0[pos] / scale, q[pos], "ks", ms=4, label="measured")
    for (name, curve), ls in zip(models.items(), ("-", "--")):
        fit = fits[name]
        if fit.fitted:
            ax.semilogy(grid / scale, fit.alpha * curve, ls,
                        label=f"{_NAMES[name]}: α = {fit.alpha:.3g} ± {fit.alpha_std:.2g}, "
                              f"rms {fit.rms_log10_residual:.2g} decades")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("leak rate Q (m³/s)")
    note = f"ΔP = {ref_dp / 1e3:.3g} kPa" + ("" if same else " (measurements scaled to it, Q ∝ ΔP)")
    excluded = sum(len(f.excluded) for f in fits.values())
    subtitle(ax, note + (f"; {excluded} point exclusions (see the text output)" if excluded else ""))
    ax.legend(loc="lower left", fontsize=8)  # Q falls with P0: the lower left corner is empty
    return fig


def figure_linearity(dp: np.ndarray, q: np.ndarray, check: LinearityCheck) -> Figure:
    """Measured Q against ΔP with the fitted straight line (and the models' lines through 0)."""
    line, model_lines, p0 = check.line, check.model_slopes, check.squeeze_pressure
    fig, ax = new_figure("Leak rate against pressure difference")
    ax.plot(dp / 1e3, q, "ks", ms=4, label="measured")
    x = np.linspace(0.0, dp.max() * 1.1, 50)
    ax.plot(x / 1e3, line.slope * x + line.intercept, "-",
            label=f"fit: slope {line.slope:.3g} ± {line.slope_std:.2g} m³/(s·Pa),\n"
                  f"intercept {line.intercept:.2g} ± {line.intercept_std:.2g} m³/s")
    for (name, slope), ls in zip(model_lines.items(), ("--", ":")):
        ax.plot(x / 1e3, slope * x, ls, label=name)
    ax.set_xlabel("pressure difference ΔP (kPa)")
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    ax.set_xlim(left=0)
    subtitle(ax, f"P0 = {p0 / 1e3:.3g} kPa" if p0 else "")
    ax.legend(loc="upper left")
    return fig


def figure_rig(rig: RigSetup, columns: dict[str, WaterColumn], p0: float) -> Figure:
    """Water height against time for each model (WaterColumn solutions)."""
    fig, ax = new_figure("Virtual water-column rig: level against time")
    longest = max((c.time[-1] for c in columns.values()), default=1.0)
    tscale, tunit = (3600.0, "h") if longest > 7200 else ((60.0, "min") if longest > 120 else (1.0, "s"))
    for (name, col), ls in zip(columns.items(), ("-", "--")):
        label = name + (f", H = {col.final_height * 100:.3g} cm after {col.time_to_final / tscale:.3g} {tunit}"
                        if np.isfinite(col.time_to_final) else "")
        line, = ax.plot(col.time / tscale, col.height * 100, ls, label=label)
        if np.isfinite(col.time_to_final):
            ax.plot([col.time_to_final / tscale], [col.final_height * 100], "o", color=line.get_color(), ms=4)
    ax.set_xlabel(f"time t ({tunit})")
    ax.set_ylabel("water height H (cm)")
    ax.set_ylim(bottom=0)
    ax.set_xlim(left=0)
    subtitle(ax, f"P0 = {p0 / 1e3:.3g} kPa ({rig.load_note or 'load'}), cylinder {rig.cylinder_diameter * 100:.3g} cm, "
                  f"ΔP = ρgH, ρ = {rig.density:g} kg/m³")
    ax.legend()
    return fig


def figure_readings(analysis: ReadingsAnalysis, model_conductance: dict[str, float]) -> Figure:
    """Leak rate against ΔP from rig readings, with the exponential-fit conductance and the models."""
    fig, ax = new_figure("Leak rate from the rig readings")
    dp = analysis.interval_pressure_difference
    ax.plot(dp / 1e3, analysis.interval_leak_rate, "ks", ms=4, label="readings: Q = -A_cyl ΔH/Δt")
    x = np.linspace(0.0, dp.max() * 1.1, 50)
    ax.plot(x / 1e3, analysis.conductance * x, "-",
            label=f"fit of ln H(t): Q = K ΔP, K = {analysis.conductance:.3g} ± {analysis.conductance_std:.2g} m³/(s·Pa)")
    for (name, k), ls in zip(model_conductance.items(), ("--", ":")):
        ax.plot(x / 1e3, k * x, ls, label=name)
    ax.set_xlabel("pressure difference ΔP = ρgH (kPa)")
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.legend()
    return fig
