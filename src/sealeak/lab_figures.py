"""Figures of the fit, the linearity check and the virtual rig (matplotlib, PNG; axes with units)."""

from __future__ import annotations

from dataclasses import replace

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from .plotting import _fig, _subtitle, pressure_axis  # noqa: E402

__all__ = ["figure_fit", "figure_linearity", "figure_rig", "figure_readings"]

_NAMES = {"critical_junction": "critical junction", "effective_medium": "effective medium"}


def figure_fit(case, data, fits) -> Figure:
    """Measured Q against P0 (log scale) with both fitted models."""
    from .case import predict, predict_effective_medium

    fig, ax = _fig("Measured leak rate and fitted theory")
    p0 = data.squeeze_pressure
    dp = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    same = np.allclose(dp, dp[0])
    ref_dp = float(dp[0]) if same else case.pressure_difference
    q = data.leak_rate * (1.0 if same else ref_dp / np.where(dp > 0, dp, np.nan))
    scale, unit = pressure_axis(p0)
    grid = np.geomspace(p0.min(), p0.max(), 40) if p0.max() > p0.min() else np.array([p0.min()])
    models = {
        "critical_junction": predict(replace(case, alpha=1.0), squeeze_pressure=grid, pressure_difference=ref_dp).leak_rate,
        "effective_medium": predict_effective_medium(case, squeeze_pressure=grid, pressure_difference=ref_dp).leak_rate,
    }
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
    _subtitle(ax, note + (f"; {excluded} point exclusions (see the text output)" if excluded else ""))
    ax.legend(loc="lower left", fontsize=8)  # Q falls with P0: the lower left corner is empty
    return fig


def figure_linearity(dp, q, line, model_lines: dict[str, float], p0: float | None) -> Figure:
    """Measured Q against ΔP with the fitted straight line (and the models' lines through 0)."""
    fig, ax = _fig("Leak rate against pressure difference")
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
    _subtitle(ax, f"P0 = {p0 / 1e3:.3g} kPa" if p0 else "")
    ax.legend(loc="upper left")
    return fig


def figure_rig(rig, columns: dict[str, object], p0: float) -> Figure:
    """Water height against time for each model (WaterColumn solutions)."""
    fig, ax = _fig("Virtual water-column rig: level against time")
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
    _subtitle(ax, f"P0 = {p0 / 1e3:.3g} kPa ({rig.load_note or 'load'}), cylinder {rig.cylinder_diameter * 100:.3g} cm, "
                  f"ΔP = ρgH, ρ = {rig.density:g} kg/m³")
    ax.legend()
    return fig


def figure_readings(rig, analysis, model_conductance: dict[str, float]) -> Figure:
    """Leak rate against ΔP from rig readings, with the exponential-fit conductance and the models."""
    fig, ax = _fig("Leak rate from the rig readings")
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
