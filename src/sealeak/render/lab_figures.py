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
from ..cases.leak_tests import DecayPrediction, DecayReadingsResult
from ..io.leak_units import celsius
from ..io.units import TIME_UNITS, YEAR
from ..lab.rig import DecayRigSetup, ReadingsAnalysis, RigSetup, WaterColumn
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
from .lab import MBAR_L_PER_PA_M3, is_gas_fit
from .notes import load_axis_label, load_text
from .plotstyle import second_leak_axis

__all__ = ["figure_fit", "figure_linearity", "figure_rig", "figure_readings", "figure_decay", "figure_decay_readings"]

_NAMES = {"critical_junction": "critical junction", "effective_medium": "effective medium"}

def _load_x(ax: Axes, load_name: str, values: np.ndarray) -> float:
    """Label the x axis with the load of the fit (P0, or a band seal's compression in % or profile scale); returns its scale."""
    if load_name == "squeeze_pressure":
        return pressure_x(ax, values)
    ax.set_xlabel(load_axis_label(load_name))
    scale = 0.01 if load_name == "compression" else 1.0
    v = np.asarray(values, dtype=float) / scale
    lo, hi = float(np.nanmin(v)), float(np.nanmax(v))
    pad = 0.05 * (hi - lo) if hi > lo else 0.05 * abs(hi) or 1.0
    ax.set_xlim(lo - pad, hi + pad)
    return scale


@laid_out
def figure_fit(result: FitResult) -> Figure:
    """Measured Q against the load (P0 on a log scale, or a band seal's compression or profile scale) with both
    fitted models, and a second axis in ml/min.

    A gas case's fit (``result.leak_rate_unit`` "Pa*m^3/s") draws pV throughputs Q_pV in Pa·m³/s with a
    second axis in mbar·l/s, and names the gas, T, P_b and the reference ΔP (docs/theory.md §11.9).
    """
    gas = is_gas_fit(result)
    fig, ax = new_figure("Measured gas leak rate and fitted theory" if gas else "Measured leak rate and fitted theory")
    load = result.data.load
    q, grid, models, fits = result.measured, result.grid, result.curves, result.fits
    same, ref_dp = result.same_pressure_difference, result.reference_pressure_difference
    scale = _load_x(ax, result.load_name, np.concatenate([load, grid]))
    ax.set_yscale("log")
    pos = np.isfinite(q) & (q > 0)
    ax.plot(load[pos] / scale, q[pos], "ks", ms=4, label="measured")
    outside = {n: rows for n, rows in result.outside_validity.items() if rows}
    if outside:  # rows the theory there does not describe (predict's valid = NO), kept in the fit
        rows = np.array(sorted({i for r in outside.values() for i in r}), dtype=int)
        rows = rows[pos[rows]]
        ax.plot(load[rows] / scale, q[rows], "o", mfc="none", mec="0.3", ms=9, mew=1.0,
                label=f"outside the validity of the {' and the '.join(_NAMES[n] for n in outside)} (kept in the fit)")
    measured_at = {"compression": "compressions", "profile_scale": "profile scales"}.get(result.load_name, "loads")
    for i, (name, curve) in enumerate(models.items()):
        fit = fits[name]
        x = result.curve_grids.get(name, grid)
        y = fit.alpha * np.asarray(curve, dtype=float)
        shown = np.isfinite(y) & (y > 0)
        if fit.fitted and shown.any():
            own = name in result.curve_grids  # drawn through its values at the measured loads only
            ax.plot(x / scale, np.where(shown, y, np.nan), ("-", "--")[i % 2], color=color(i), marker="o" if own else None,
                    ms=3, label=f"{_NAMES[name]}: α = {fit.alpha:.3g} ± {fit.alpha_std:.2g}, "
                                f"rms {fit.rms_log10_residual:.2g} decades" + (f" (at the measured {measured_at})" if own else ""))
    ax.set_ylabel("pV throughput Q_pV (Pa·m³/s)" if gas else "leak rate Q (m³/s)")
    note = f"ΔP = {ref_dp / 1e3:.3g} kPa" + ("" if same else " (measurements scaled to it, Q ∝ ΔP)")
    if gas and result.case.gas is not None:
        g = result.case.gas
        note = (f"{g.gas.name}, T = {celsius(g.temperature):.4g} °C, P_b = {g.downstream_pressure / 1e5:.4g} bar, "
                f"P_a = P_b + ΔP, ΔP = {ref_dp / 1e3:.4g} kPa"
                + ("" if same else " (measurements scaled to it with P_a² − P_b²)"))
        note += f"; rarefaction {g.rarefaction}"
    excluded = sum(len(f.excluded) for f in fits.values())
    subtitle(ax, note + (f"; {excluded} point exclusions (see the text output)" if excluded else ""))
    if not pos.any():
        ax.set_yscale("linear")
        say_nothing(ax, "no measured leak rate above zero to draw")
        finish_axes(ax)
        return fig
    finish_axes(ax)
    if gas:
        second_leak_axis(ax, MBAR_L_PER_PA_M3, "mbar·l/s", quantity="gas leak rate Q_pV")
    else:
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
    """Measured Q against ΔP with the fitted straight line and the models' Q(ΔP) (coupled, with capillarity), with ml/min."""
    line, p0 = check.line, check.squeeze_pressure
    fig, ax = new_figure("Leak rate against pressure difference")
    x = np.linspace(0.0, dp.max() * 1.1, 50)
    fitted = line.slope * x + line.intercept
    qscale = _leak_axis(ax, np.concatenate([q, fitted]))
    ax.plot(dp / 1e3, q / qscale, "ks", ms=4, label="measured")
    ax.plot(x / 1e3, fitted / qscale, "-", color=color(0),
            label=f"fit: slope {line.slope:.3g} ± {line.slope_std:.2g} m³/(s·Pa),\n"
                  f"intercept {line.intercept:.2g} ± {line.intercept_std:.2g} m³/s")
    ax.set_ylim(bottom=0)
    hidden = _model_lines(ax, check.curve_pressure_difference, check.model_curves, qscale)
    ax.set_xlabel("pressure difference ΔP (kPa)")
    ax.set_xlim(left=0)
    at = f"P0 = {p0 / 1e3:.3g} kPa" if p0 else ""
    if check.load is not None and p0:  # a band seal: its load, and the mean contact pressure there
        at = f"{load_text(check.load_name, check.load)} (mean contact pressure {p0 / 1e3:.3g} kPa)"
    notes = [at, "beyond the axes: " + ", ".join(hidden) if hidden else ""]
    subtitle(ax, "; ".join(n for n in notes if n))
    finish_axes(ax)
    ml_per_min_axis(ax, qscale)
    place_legend(ax)
    return fig


@laid_out
def figure_rig(rig: RigSetup, columns: dict[str, WaterColumn], p0: float, condition: str | None = None) -> Figure:
    """Water height against time for each model (WaterColumn solutions).

    ``condition``: what presses the seal, for the subtitle (default: P0 and how the load was given;
    an O-ring or profile seal passes its compression or scale and peak pressure).
    """
    fig, ax = new_figure("Virtual water-column rig: level against time")
    longest = max((c.time[-1] for c in columns.values()), default=1.0)
    tscale, tunit = (3600.0, "h") if longest > 7200 else ((60.0, "min") if longest > 120 else (1.0, "s"))
    lscale, lunit = tscale, tunit  # the legend's time unit (without a power of ten)
    if longest > 2 * YEAR:  # a tight seal drains over years: years, with the power of ten in the axis unit
        power, tunit = power_unit([longest / YEAR], "years")
        tscale, lscale, lunit = YEAR * power, YEAR, "years"
    for i, (name, col) in enumerate(columns.items()):
        label = name + _column_label(col, lscale, lunit)
        ax.plot(col.time / tscale, col.height * 100, ("-", "--")[i % 2], color=color(i), label=label)
        if np.isfinite(col.time_to_final):
            ax.plot([col.time_to_final / tscale], [col.final_height * 100], "o", color=color(i), ms=4)
    ax.set_xlabel(f"time t ({tunit})")
    ax.set_ylabel("water height H (cm)")
    ax.set_ylim(0, 1.08 * rig.initial_height * 100)
    ax.set_xlim(left=0)
    if condition is None:
        condition = f"P0 = {p0 / 1e3:.3g} kPa ({rig.load_note or 'load'})"
    subtitle(ax, f"{condition}\ncylinder {rig.cylinder_diameter * 100:.3g} cm, "
                  f"ΔP = ρgH, ρ = {rig.density:g} kg/m³; dots: when the level falls to the final height asked for")
    if not columns:
        say_nothing(ax, "no model to simulate")
    finish_axes(ax)
    place_legend(ax)
    return fig


def _column_label(col: WaterColumn, lscale: float, lunit: str) -> str:
    """What the legend says of a water column: when it reached the final height, where capillarity stopped it
    (docs/theory.md §12.1), or that it did not leak."""
    if np.isfinite(col.time_to_final):
        return f": H = {col.final_height * 100:.3g} cm after {col.time_to_final / lscale:.3g} {lunit}"
    if col.stop_height is not None and col.time_to_stop == 0:
        return ": held by capillarity, the level stays"
    if col.stop_height is not None and np.isfinite(col.time_to_stop):
        return f": held by capillarity at H = {col.stop_height * 100:.3g} cm after {col.time_to_stop / lscale:.3g} {lunit}"
    return ": no leak, the level stays" if col.leak_rate[0] == 0 else ": the final height not reached"


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


#: Ratio of the models' times to lose ΔP above which the pressure-decay figure draws time on a logarithmic axis.
DECAY_LOG_RATIO = 10.0


def _time_unit(longest: float) -> tuple[float, str]:
    """(seconds per unit, unit) of a time axis reaching ``longest`` s."""
    for size, _, unit in TIME_UNITS[:-1]:  # years, days, h, min
        if longest > 2 * size:
            return size, unit
    return 1.0, "s"


@laid_out
def figure_decay(rig: DecayRigSetup, pred: DecayPrediction, condition: str = "") -> Figure:
    """Absolute pressure P(t) in the test volume for each model, the level P1 − ΔP and the time it is reached."""
    fig, ax = new_figure("Virtual pressure-decay test: pressure against time")
    test = rig.test
    longest = max((m.decay.time[-1] for m in pred.models.values()), default=1.0)
    tscale, tunit = _time_unit(longest)
    target = test.initial_pressure - test.loss
    # times to lose ΔP that differ by more than DECAY_LOG_RATIO do not share a linear axis: the faster model would be
    # a vertical line at t = 0; a logarithmic time axis shows both (each curve from its first time > 0)
    losses = [m.decay.time_to_loss for m in pred.models.values() if np.isfinite(m.decay.time_to_loss) and m.decay.time_to_loss > 0]
    log_time = len(losses) > 1 and max(losses) > DECAY_LOG_RATIO * min(losses)
    for i, (name, m) in enumerate(pred.models.items()):
        d = m.decay
        reached = np.isfinite(d.time_to_loss)
        label = name + (f": ΔP lost after {d.time_to_loss / tscale:.3g} {tunit}" if reached else
                        (": no leak, the pressure stays" if m.conductance == 0 else ": ΔP not lost in the simulated time"))
        shown = d.time > 0 if log_time else slice(None)
        ax.plot(d.time[shown] / tscale, d.pressure[shown] / 100, ("-", "--")[i % 2], color=color(i), label=label)
        if reached:
            ax.plot([d.time_to_loss / tscale], [target / 100], "o", color=color(i), ms=4)
    ax.axhline(target / 100, color="0.5", lw=0.8, ls=":", label=f"P1 − ΔP = {target / 100:.6g} mbar")
    ax.set_ylabel("absolute pressure P in the test volume (mbar)")
    if log_time:
        ax.set_xscale("log")
        ax.set_xlabel(f"time t ({tunit}, logarithmic: the models' times differ by a factor {max(losses) / min(losses):.3g})")
    else:
        ax.set_xlabel(f"time t ({tunit})")
        ax.set_xlim(left=0)
    subtitle(ax, f"{condition}\n{rig.gas.name}, V = {test.volume * 1e3:.3g} l, P2 = {test.outside_pressure / 100:.4g} mbar "
                 f"outside, T = {celsius(test.temperature):.3g} °C, rarefaction: {rig.rarefaction_model}")
    if not pred.models:
        say_nothing(ax, "no model to simulate")
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_decay_readings(rig: DecayRigSetup, readings: DecayReadingsResult) -> Figure:
    """Measured P(t) readings with each model's P(t) scaled by the factor the readings imply (α for the critical junction),
    started at the first reading."""
    fig, ax = new_figure("Pressure-decay readings and the models fitted to them")
    r = readings.readings
    t0 = r.time[0]
    span = r.time[-1] - t0
    tscale, tunit = _time_unit(span)
    ax.plot((r.time - t0) / tscale, r.pressure / 100, "ks", ms=4, label="readings")
    for i, (name, sc) in enumerate(readings.scale.items()):
        curve = readings.fitted.get(name)
        if curve is None:
            continue
        what = "α" if name.startswith("critical") else "factor on K"
        ax.plot(curve.time / tscale, curve.pressure / 100, ("-", "--")[i % 2], color=color(i),
                label=f"{name}, {what} = {sc.alpha:.3g} ± {sc.alpha_std:.2g}")
    ax.set_xlabel(f"time since the first reading ({tunit})")
    ax.set_ylabel("absolute pressure P (mbar)")
    subtitle(ax, f"{rig.gas.name}, V = {rig.test.volume * 1e3:.3g} l, P2 = {rig.test.outside_pressure / 100:.4g} mbar; "
                 f"leak rate over the readings {r.leak_rate * 10:.3g} mbar·l/s")
    finish_axes(ax)
    place_legend(ax)
    return fig
