"""Text and JSON renderings of the laboratory workflows: the α fit, the linearity check, the rig.

Each function takes the result object of :mod:`sealeak.cases.run` (SI units) and returns the text
``sealeak fit`` / ``sealeak rig`` print or the JSON document they write.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..cases import Case, FitResult, LinearityCheck, RigPrediction
from ..cases.band import BandColumns, BandResult
from ..cases.leak_tests import DecayPrediction, DecayReadingsResult, decay_rig
from ..cases.model import BandSeal
from ..io.leak_units import MBAR_L_PER_PA_M3, to_ml_per_min
from ..io.quantities import expand_keys, quantity, record_fields, units_for, units_of
from ..io.units import TIME_UNITS
from ..lab.data import LeakData
from ..lab.fitting import LinearFit, ScaleFit
from ..lab.pressure_decay import DecayReadings, PressureDecaySetup, ScaleFromDecay
from ..lab.rig import DecayRigSetup, ReadingsAnalysis, RigSetup
from ..physics.gas import Gas
from ..physics.validity import ALPHA_RANGE as PLAUSIBLE_ALPHA
from .notes import load_text, worded
from .records import json_document, json_value
from .text import fmt

__all__ = ["fit_text", "fit_json", "linearity_text", "linearity_json", "rig_text", "rig_json", "rig_condition",
           "decay_text", "decay_json", "decay_condition", "duration_text", "MBAR_L_PER_PA_M3",
           "is_gas_fit", "FIT_UNIT_TEXT", "GasFitRow", "RigModelRecord", "RigCapillaryRecord", "DecayModelRecord", "FIT_UNITS",
           "LINEARITY_UNITS",
           "RIG_UNITS", "DECAY_UNITS"]


#: How a :attr:`~sealeak.cases.FitResult.leak_rate_unit` reads in text and on figures.
FIT_UNIT_TEXT = {"m^3/s": "m³/s", "Pa*m^3/s": "Pa·m³/s"}


@dataclass(frozen=True, kw_only=True)
class GasFitRow:
    """The leak rates of one data row of a gas fit (``sealeak fit --json`` ``rows``), as pV throughputs.

    ``<model>`` in a key stands for each fitted model's name.
    """

    measured: float = quantity("Pa*m^3/s", "measured pV throughput, scaled to the reference ΔP")
    measured_mbar_l_s: float = quantity("mbar*l/s", "the same in mbar·l/s")
    fitted: float = quantity("Pa*m^3/s", "α times the model's pV throughput at the row's load", key="fitted_<model>")
    fitted_mbar_l_s: float = quantity("mbar*l/s", "the same in mbar·l/s", key="fitted_<model>_mbar_l_s")


@dataclass(frozen=True, kw_only=True)
class RigModelRecord:
    """One model of ``sealeak rig --json`` for a water column (``models``; SI units)."""

    conductance: float | None = quantity("m^3/(s*Pa)", "conductance K = Q/ΔP of the seal")
    time_constant: float | None = quantity("s", "τ = A/(K ρ g) of H(t) = H0 exp(−t/τ)")
    time_to_final_height: float | None = quantity("s", "closed-form time to fall to the final height")
    time_to_final_height_ode: float | None = quantity("s", "the same from the solved H(t) (null if not reached)")
    time: list[float | None] = quantity("s", "times of H(t), every 10th point")
    height: list[float | None] = quantity("m", "water height H(t) at those times")


@dataclass(frozen=True, kw_only=True)
class RigCapillaryRecord:
    """What a liquid with a contact angle adds to each model of ``sealeak rig --json`` (a water column; SI units)."""

    capillary_entry_pressure: float | None = quantity(
        "Pa", "entry pressure −γ(cos θ_r + cos θ_s)/u of the narrowest gap u (null without a leak channel)")
    stop_height: float | None = quantity("m", "height p_e/(ρg) at which the meniscus stops the fall (null: no stop)")
    time_to_stop: float | None = quantity("s", "time the level reaches it (0: held from the start; null: not reached)")


@dataclass(frozen=True, kw_only=True)
class DecayModelRecord:
    """One model of ``sealeak rig --json`` for a pressure-decay test (``models``; SI units)."""

    conductance: float | None = quantity("m^3/(Pa*s)", "conductance K of the seal")
    gap: float | None = quantity("m", "the narrowest gap h of the leak channel")
    knudsen_number: float | None = quantity("1", "Kn = λ/h at the mean pressure at the start (null without a leak)")
    flow_regime: str | None = quantity("", "flow regime at that Kn (null without a leak)")
    initial_leak_rate_pv: float | None = quantity("Pa*m^3/s", "pV leak rate at the start")
    initial_leak_rate_mbar_l_s: float | None = quantity("mbar*l/s", "the same in mbar·l/s")
    initial_leak_rate_mass: float | None = quantity("kg/s", "mass flow at the start")
    time_to_pressure_loss: float | None = quantity("s", "time to lose the pressure drop ΔP")
    time_to_pressure_loss_no_slip: float | None = quantity("s", "the same for no-slip (viscous) flow")
    standard_leak_rate_pv: float | None = quantity("Pa*m^3/s", "standard leak rate V·ΔP/Δt")
    standard_leak_rate_mbar_l_s: float | None = quantity("mbar*l/s", "the same in mbar·l/s")
    time: list[float | None] = quantity("s", "times of P(t)")
    pressure: list[float | None] = quantity("Pa (absolute)", "test-volume pressure P(t)")
    leak_rate_pv: list[float | None] = quantity("Pa*m^3/s", "pV leak rate at those times")


#: ``units`` of ``sealeak fit --json`` (a gas fit adds :class:`GasFitRow`'s for its ``rows``).
FIT_UNITS = units_for(("alpha", "alpha_std", "rms_log10_residual", "reference_pressure"), ScaleFit, LeakData)
#: ``units`` of ``sealeak fit --linearity --json`` (a band seal adds its load's).
LINEARITY_UNITS = units_for(("slope", "slope_std", "intercept", "intercept_std", "squeeze_pressure", "model_slopes",
                             "model_intercepts", "model_nonlinearity"), LinearFit, LinearityCheck)
#: ``units`` of ``sealeak rig --json`` for a water column (a band seal adds :data:`_RIG_BAND_UNITS` and its load's).
RIG_UNITS = units_for(("squeeze_pressure", "load", "final_height", "conductance", "time_constant", "time_to_final_height",
                       "time", "height", "interval_pressure_difference", "interval_leak_rate"),
                      RigPrediction, RigSetup, RigModelRecord, ReadingsAnalysis)
_RIG_CAPILLARY_UNITS = units_of(RigCapillaryRecord)
_RIG_BAND_UNITS = units_for(("contact_width", "mean_contact_pressure", "max_contact_pressure", "force_per_length",
                             "seal_line_length", "faces"), BandColumns, BandSeal)
#: ``units`` of ``sealeak rig --json`` for a pressure-decay test (a band seal adds its load's).
DECAY_UNITS = units_for(("squeeze_pressure", "load", "volume", "initial_pressure", "outside_pressure", "temperature",
                         "pressure_loss", "viscosity", "molar_mass",
                         *(k for k in units_of(DecayModelRecord) if k != "flow_regime"),
                         "interval_pressure", "interval_leak_rate_pv", "alpha"),
                        DecayPrediction, DecayRigSetup, PressureDecaySetup, Gas, DecayModelRecord, DecayReadings,
                        ScaleFromDecay)


def _band_load_units(load_name: str) -> dict[str, str]:
    """The unit of a band seal's load, keyed by its name (compression, profile_scale)."""
    return expand_keys(units_for(("<load>",), BandSeal), load=[load_name])


def is_gas_fit(result: FitResult) -> bool:
    """Whether the fit compared pV throughputs of a gas (``leak_rate_unit`` "Pa*m^3/s", docs/theory.md §11.9)."""
    return result.leak_rate_unit == "Pa*m^3/s"


def _gas_fit_lines(result: FitResult) -> list[str]:
    """The gas lines of ``sealeak fit``: the unit compared, and each row measured and fitted in Pa·m³/s and mbar·l/s."""
    data, fits = result.data, result.fits
    gas = result.case.gas
    lines = [f"leak rates compared as pV throughputs Q_pV in Pa·m³/s (1 Pa·m³/s = {MBAR_L_PER_PA_M3:g} mbar·l/s)"
             + (f" of {gas.gas.name}" if gas is not None else "")]
    if data.leak_rate_kind == "volume_flow":
        lines.append(f"volume flows in {data.columns['leak_rate']} counted at {data.reference_pressure / 1e3:.6g} kPa "
                     "(--at-pressure): Q_pV = p V̇")
    if not result.same_pressure_difference:
        return lines
    load = {"compression": ("ε (%)", 100.0), "profile_scale": ("scale", 1.0)}.get(result.load_name, ("P0 (kPa)", 1e-3))
    names = [n for n in fits if fits[n].fitted]
    head = f"{load[0]:>10} {'measured (Pa·m³/s)':>19} {'(mbar·l/s)':>11}"
    head += "".join(f" {n.replace('_', ' ') + ' (mbar·l/s)':>32}" for n in names)
    rows = ["", "measured and fitted (α × model) leak rates:", head]
    x = result.data.load
    for i in range(len(data)):
        q = float(result.measured[i])
        row = f"{x[i] * load[1]:>10.4g} {fmt(q, '.4e'):>19} {fmt(q * MBAR_L_PER_PA_M3, '.4e'):>11}"
        for n in names:
            row += f" {fmt(fits[n].alpha * float(fits[n].prediction[i]) * MBAR_L_PER_PA_M3, '.4e'):>32}"
        rows.append(row)
    return lines + rows


def fit_text(result: FitResult) -> str:
    """The table ``sealeak fit`` prints: α ± its standard error, rms residual and points used per model, then notes.

    A gas case's fit (:func:`is_gas_fit`) names its unit, Pa·m³/s (the pV throughput), and lists
    each row measured and fitted in Pa·m³/s and mbar·l/s.
    """
    case, data, fits = result.case, result.data, result.fits
    reference = data.reference_pressure
    gas = is_gas_fit(result)
    lines = [f"{case.title}", f"fit of {len(data)} measured leak rate{'s' if len(data) != 1 else ''} from "
             f"{data.path} (columns: {', '.join(data.columns.values())})"]
    gas_lines = _gas_fit_lines(result) if gas else []
    head = 2 if gas and data.leak_rate_kind == "volume_flow" else 1
    lines += gas_lines[:head]
    if data.throughput and not gas:
        lines.append(f"leak rates in {data.columns['leak_rate']} are pV throughputs: converted to volume flows at "
                     f"{reference / 1e3:.6g} kPa (--at-pressure)")
    band = case.band
    if band is not None:
        n = int(np.unique(data.load).size)
        word = "compression" if band.load_name == "compression" else "profile scale"
        seal = "O-ring" if band.kind == "o-ring" else "pressure-profile seal"
        lines.append(f"model: the {seal}'s leak rate at each row's {word} (strips in series across the band), both "
                     f"theories at {n} distinct {word}{'s' if n != 1 else ''}")
    if gas:
        lines.append("least squares in log Q_pV: Q_pV,measured = α × Q_pV,model(α = 1)")
    else:
        lines.append("least squares in log Q: Q_measured = α × Q_model(α = 1)")
    lines.append("")
    lines.append(f"{'model':<20} {'α':>10} {'± se':>10} {'rms (decades)':>14} {'points':>7}")
    for name, f in fits.items():
        lines.append(f"{name.replace('_', ' '):<20} {fmt(f.alpha):>10} {fmt(f.alpha_std, '.2g'):>10} "
                     f"{fmt(f.rms_log10_residual, '.3g'):>14} {f.n_used:>7}")
    lines += gas_lines[head:]
    lines += ["note: " + m for m in worded(result.messages)]
    return "\n".join(lines) + "\n"


def fit_json(result: FitResult) -> str:
    """The ``sealeak fit --json`` document (α, its standard error, the excluded rows and the rows outside the theory's
    validity per model)."""
    data = result.data
    doc: dict[str, Any] = {"case": result.case.title, "data": data.path, "load_column": result.load_name,
                           "reference_pressure": data.reference_pressure,
                           "leak_rate_unit": result.leak_rate_unit,
                           "units": dict(FIT_UNITS),
                           "messages": worded(result.messages)}
    if is_gas_fit(result) and result.same_pressure_difference:
        # each row measured and fitted as pV throughputs, in the fit's unit and in the leak-test unit
        doc["units"] |= expand_keys(units_of(GasFitRow), model=list(result.fits))
        doc["rows"] = [{result.load_name: json_value(float(result.data.load[i])), "measured": json_value(float(result.measured[i])),
                        "measured_mbar_l_s": json_value(float(result.measured[i]) * MBAR_L_PER_PA_M3)}
                       | {f"fitted_{n}": json_value(f.alpha * float(f.prediction[i])) for n, f in result.fits.items()}
                       | {f"fitted_{n}_mbar_l_s": json_value(f.alpha * float(f.prediction[i]) * MBAR_L_PER_PA_M3)
                          for n, f in result.fits.items()}
                       for i in range(len(result.data))]
    for name, f in result.fits.items():
        doc[name] = {"alpha": json_value(f.alpha), "alpha_std": json_value(f.alpha_std),
                     "log10_alpha_std": json_value(f.log10_alpha_std),
                     "rms_log10_residual": json_value(f.rms_log10_residual), "points_used": f.n_used,
                     "excluded_rows": [i + 1 for i, _ in f.excluded],
                     "excluded_lines": [data.line_of(i) for i, _ in f.excluded],
                     "outside_validity_rows": [i + 1 for i in result.outside_validity.get(name, ())],
                     "outside_validity_lines": [data.line_of(i) for i in result.outside_validity.get(name, ())]}
    return json_document(doc)


def linearity_text(case: Case, data: LeakData, check: LinearityCheck) -> str:
    """What ``sealeak fit --linearity`` prints: the line, its intercept against zero, the models' slopes."""
    line, p0, z = check.line, check.squeeze_pressure, check.intercept_z
    lines = [case.title, f"linearity of Q in ΔP: {len(data)} points from {data.path}", "",
             f"slope      {line.slope:.4g} ± {line.slope_std:.2g} m³/(s·Pa)",
             f"intercept  {line.intercept:.4g} ± {line.intercept_std:.2g} m³/s  "
             f"({fmt(z, '.2g')} standard errors from 0{'; consistent with a line through the origin' if z < 2 else ''})",
             f"R²         {line.r_squared:.5f}, rms residual {line.rms_residual:.3g} m³/s"]
    if case.band is not None and check.load is not None:
        lines.append(f"load       {load_text(check.load_name, check.load)} (from {check.squeeze_pressure_source}): mean contact "
                     f"pressure {fmt(p0 / 1e6 if p0 is not None else None)} MPa")
    elif p0 is not None:
        lines.append(f"P0         {p0 / 1e3:.4g} kPa (from {check.squeeze_pressure_source})")
    if p0 is not None:
        for name, k in check.model_slopes.items():
            lines.append(f"model      {name}: slope {k:.4g} m³/(s·Pa), intercept {check.model_intercepts[name]:.3g} m³/s"
                         + _model_nonlinearity(check, name))
        for name, p_e in check.capillary_entry_pressure.items():
            lines.append(f"           {name}: capillary entry pressure {fmt(p_e / 1e3 if np.isfinite(p_e) else None, '.4g')} "
                         "kPa (Q = 0 below it)")
        if check.alpha_from_slope is not None:
            lines.append(f"alpha      {check.alpha_from_slope:.3g}: the critical junction's α implied by the measured slope "
                         "(the slope over the critical junction's at α = 1)")
    lines += ["note: " + m for m in worded(check.messages)]
    return "\n".join(lines) + "\n"


def _model_nonlinearity(check: LinearityCheck, name: str) -> str:
    """How far a model's Q/ΔP changes over the measured ΔP (the fluid pressure coupled), for the text."""
    change = check.model_nonlinearity.get(name, 0.0)
    if abs(change) < 5e-4:
        return " (linear in ΔP)"
    return f"; its Q/ΔP {'rises' if change > 0 else 'falls'} by {abs(change) * 100:.3g} % over the measured ΔP"


def _by_model(check: LinearityCheck, values: dict[str, float]) -> dict[str, Any]:
    """A per-model field keyed by the model's record key (``critical_junction``), not its display name."""
    return {check.model_keys.get(k, k): json_value(v) for k, v in values.items()}


def linearity_json(case: Case, data: LeakData, check: LinearityCheck) -> str:
    """The ``sealeak fit --linearity --json`` document."""
    line, p0 = check.line, check.squeeze_pressure
    doc: dict[str, Any] = {"case": case.title, "data": data.path,
           "linearity": {"slope": json_value(line.slope), "slope_std": json_value(line.slope_std),
                         "intercept": json_value(line.intercept), "intercept_std": json_value(line.intercept_std),
                         "r_squared": json_value(line.r_squared), "points": line.n,
                         "squeeze_pressure": json_value(p0) if p0 is not None else None,
                         "model_labels": {v: k for k, v in check.model_keys.items()},
                         "model_slopes": _by_model(check, check.model_slopes),
                         "model_intercepts": _by_model(check, check.model_intercepts),
                         "model_nonlinearity": _by_model(check, check.model_nonlinearity),
                         "alpha_from_slope": (json_value(check.alpha_from_slope)
                                              if check.alpha_from_slope is not None else None)},
           "units": dict(LINEARITY_UNITS),
           "messages": worded(check.messages)}
    if case.capillarity is not None:
        doc["linearity"]["capillary_entry_pressure"] = _by_model(check, check.capillary_entry_pressure)
        doc["units"]["capillary_entry_pressure"] = "Pa"
    if case.band is not None:  # the band's load; squeeze_pressure is its mean contact pressure
        doc["linearity"][check.load_name] = json_value(check.load) if check.load is not None else None
        doc["units"] |= expand_keys(units_for(("<load>",), LinearityCheck), load=[check.load_name])
    return json_document(doc)


def rig_condition(case: Case, pred: RigPrediction, short: bool = False) -> str:
    """What presses the seal in the rig: the load (N) and P0, or a band seal's compression (or scale) and contact.

    ``short``: the figure's version (load, or the band's load and peak pressure).
    """
    rig = case.rig
    assert rig is not None
    b = pred.band
    text = _seal_condition(case, b, pred.squeeze_pressure, rig.load, rig.load_note, short)
    if b is None or short:
        return text
    return text + f", seal line {b.band.length * 1e3:.4g} mm{' (2 faces)' if b.band.faces == 2 else ''}"


def _seal_condition(case: Case, b: BandResult | None, squeeze_pressure: float, load: float | None, load_note: str,
                    short: bool) -> str:
    """What presses the seal in a rig: the load (N) and P0 (Pa), or a band seal's load and its contact."""
    if b is None:
        if short:
            return f"P0 = {squeeze_pressure / 1e3:.3g} kPa ({load_note or 'load'})"
        return (f"{load:.4g} N ({load_note}) -> P0 = {squeeze_pressure / 1e3:.4g} kPa on the "
                f"{case.seal.nominal_area * 1e4:.4g} cm² seal")
    seal = "O-ring" if b.band.kind == "o-ring" else "pressure profile"
    at = load_text(b.band.load_name, float(b.band.loads[0]))
    if short:
        return f"{seal} at {at}, peak contact pressure {b.max_contact_pressure[0] / 1e6:.3g} MPa"
    return (f"{seal} at {at}: contact width {b.contact_width[0] * 1e3:.4g} mm, mean contact pressure "
            f"{b.mean_contact_pressure[0] / 1e6:.4g} MPa, peak {b.max_contact_pressure[0] / 1e6:.4g} MPa")


def _readings_head(source: str, time: np.ndarray, duration: str, header: str, leak_rate: np.ndarray,
                   rows: list[str], level: str, negative: str) -> list[str]:
    """The readings' block of the rig's text: where from, how many over how long (``duration``), the table of
    intervals (``header``, ``rows``) and a note where the ``level`` rises (a ``negative`` leak rate)."""
    lines = ["", f"readings from {source}: {time.size} points over {duration}", "", header, *rows]
    rising = int(np.count_nonzero(leak_rate < 0))
    if rising:
        lines.append(f"note: the {level} rises in {rising} of {leak_rate.size} intervals (reading noise?): those "
                     f"intervals show a negative {negative}")
    return lines


def _ode_agreement(pred: RigPrediction) -> str:
    """Whether the ODE's times to the final height agree with the closed form's (to 1e-6), in words: it was said to
    agree whatever the numbers (28 058 s against 24 498 s at H0 = 1e20 m)."""
    worst = 0.0
    for name, closed in pred.drain_time.items():
        ode = pred.columns[name].time_to_final
        if math.isfinite(closed) and math.isfinite(ode) and closed > 0:
            worst = max(worst, abs(ode - closed) / closed)
    if worst <= 1e-6:
        return "the ODE solution agrees"
    return f"the ODE solution's time differs from it by {100 * worst:.3g} %: trust neither"


def rig_text(case: Case, pred: RigPrediction, readings: ReadingsAnalysis | None = None,
             readings_source: str = "") -> str:
    """What ``sealeak rig`` prints: load and cylinder, then K, Q at H0, τ and the drain time per model."""
    rig = case.rig
    assert isinstance(rig, RigSetup)  # the water column (a pressure-decay rig has its own text)
    area = rig.cylinder_area
    dp0 = float(rig.pressure_difference(rig.initial_height))
    lines = [case.title, "virtual water-column rig (Lorenz & Persson, EPL 86 (2009) 44006)", "",
             f"{'load' if pred.band is None else 'seal':<11} {rig_condition(case, pred)}",
             f"cylinder    D = {rig.cylinder_diameter * 100:.4g} cm, A = {area * 1e4:.4g} cm², "
             f"H0 = {rig.initial_height * 100:.4g} cm (ΔP0 = {dp0 / 1e3:.4g} kPa), "
             f"ρ = {rig.density:g} kg/m³, g = {rig.gravity:g} m/s²", ""]
    h1 = _final_height(pred)
    lines.append(f"{'model':<32} {'K = Q/ΔP (m³/(s·Pa))':>22} {'Q at H0 (ml/min)':>17} {'τ (min)':>10} "
                 f"{'t to H = ' + format(h1 * 100, '.3g') + ' cm (min)':>26}")
    for name, k in pred.conductance.items():
        lines.append(f"{name:<32} {fmt(k, '22.4e')} {fmt(to_ml_per_min(pred.columns[name].leak_rate[0]), '17.4g')} "
                     f"{fmt(pred.time_constant[name] / 60, '10.4g')} {fmt(pred.drain_time[name] / 60, '26.4g')}")
    if case.coupled:
        lines.append("(fluid pressure coupled, theory §13: Q(ΔP) grows faster than K ΔP; K and τ at H0, the time from "
                     "the ODE of Q(ρgH) along the fall)")
    else:
        lines.append("(linear leak Q = K ΔP: H(t) = H0 exp(-t/τ), τ = A/(K ρ g); " + _ode_agreement(pred) + ")")
    if readings is not None:
        t = readings.time
        lines += _readings_head(readings_source, t, f"{t[-1] - t[0]:.4g} s", f"{'ΔP (kPa)':>10} {'Q (m³/s)':>12} {'Q (ml/min)':>11}",
                                readings.interval_leak_rate,
                                [f"{dpi / 1e3:10.4g} {qi:12.4e} {to_ml_per_min(qi):11.4g}"
                                 for dpi, qi in zip(readings.interval_pressure_difference, readings.interval_leak_rate)],
                                "level", "Q")
        lines.append(f"exponential fit of ln H(t): K = {readings.conductance:.4g} ± {readings.conductance_std:.2g} "
                     f"m³/(s·Pa), rms residual {readings.rms_log_residual:.2g} decades")
        for name, k in pred.conductance.items():
            if k > 0 and name.startswith("critical"):
                alpha = case.alpha * readings.conductance / k
                lines.append(f"α implied by the readings: {alpha:.3g} (case α = {case.alpha:g}){_far(alpha)}")
    lines += ["note: " + m for m in worded(pred.messages)]
    return "\n".join(lines) + "\n"


def _final_height(pred: RigPrediction) -> float:
    return next(iter(pred.columns.values())).final_height if pred.columns else float("nan")


def rig_json(case: Case, pred: RigPrediction, readings: ReadingsAnalysis | None = None) -> str:
    """The ``sealeak rig --json`` document: per model K, τ, drain times and H(t) every 10th point."""
    rig = case.rig
    assert rig is not None
    models = {}
    for name, k in pred.conductance.items():
        col = pred.columns[name]
        models[name] = record_fields(RigModelRecord(
            conductance=json_value(k), time_constant=json_value(pred.time_constant[name]),
            time_to_final_height=json_value(pred.drain_time[name]), time_to_final_height_ode=json_value(col.time_to_final),
            time=[json_value(x) for x in col.time[::10]], height=[json_value(x) for x in col.height[::10]]))
        if case.capillarity is not None:
            models[name] |= record_fields(RigCapillaryRecord(
                capillary_entry_pressure=json_value(pred.entry_pressure[name]), stop_height=json_value(col.stop_height),
                time_to_stop=json_value(col.time_to_stop)))
    doc: dict[str, Any] = {
        "case": case.title, "squeeze_pressure": pred.squeeze_pressure, "load": rig.load,
        "final_height": json_value(_final_height(pred)), "models": models,
        "units": dict(RIG_UNITS),
        "messages": worded(pred.messages)}
    if case.capillarity is not None:
        doc["units"] |= _RIG_CAPILLARY_UNITS
    b = pred.band
    if b is not None:  # a band seal: its load and contact; "load" is the contact force f·Ly, P0 its mean pressure
        doc[b.band.load_name] = float(b.band.loads[0])
        doc["band"] = {"contact_width": float(b.contact_width[0]), "mean_contact_pressure": float(b.mean_contact_pressure[0]),
                       "max_contact_pressure": float(b.max_contact_pressure[0]),
                       "force_per_length": float(b.force_per_length[0]), "seal_line_length": float(b.band.length),
                       "faces": b.band.faces}
        doc["units"] |= _band_load_units(b.band.load_name) | _RIG_BAND_UNITS
    if readings is not None:
        doc["readings"] = {"interval_pressure_difference": [json_value(x) for x in readings.interval_pressure_difference],
                           "interval_leak_rate": [json_value(x) for x in readings.interval_leak_rate],
                           "conductance": json_value(readings.conductance),
                           "conductance_std": json_value(readings.conductance_std)}
    return json_document(doc)


def duration_text(seconds: float) -> str:
    """A time in s, with a readable unit beside it for long times: '1234 s (20.6 min)', '3.2e+08 s (10.1 years)'."""
    if not np.isfinite(seconds):
        return "never" if seconds > 0 else "n/a"
    for size, _, unit in TIME_UNITS[:-1]:  # years, days, h, min
        if seconds >= 2 * size:
            return f"{seconds:.4g} s ({seconds / size:.3g} {unit})"
    return f"{seconds:.4g} s"


def decay_condition(case: Case, pred: DecayPrediction, short: bool = False) -> str:
    """What presses the seal in the pressure-decay rig: the load and P0, or a band seal's load and contact."""
    rig = decay_rig(case)
    return _seal_condition(case, pred.band, pred.squeeze_pressure, rig.load, rig.load_note, short)


def _pv(q: float) -> str:
    """A pV throughput in Pa·m³/s and mbar·l/s."""
    if not np.isfinite(q):
        return "n/a"
    return f"{q:.4g} Pa·m³/s = {q * MBAR_L_PER_PA_M3:.4g} mbar·l/s"


def decay_text(case: Case, pred: DecayPrediction, readings: DecayReadingsResult | None = None,
               readings_source: str = "") -> str:
    """What ``sealeak rig`` prints for a pressure-decay test: the test, then per model K, the gap, Kn, the
    time to lose ΔP and the standard leak rate V·ΔP/Δt (docs/theory.md §11.7)."""
    rig = decay_rig(case)
    test = rig.test
    lines = [case.title, "virtual pressure-decay test: V dP/dt = -Q_pV(P, P2) (docs/theory.md §11.7)", "",
             f"{'load' if pred.band is None else 'seal':<8} {decay_condition(case, pred)}",
             f"{'gas':<8} {rig.gas_note}",
             f"{'volume':<8} V = {test.volume * 1e3:.4g} l, P1 = {test.initial_pressure / 100:.6g} mbar, "
             f"P2 = {test.outside_pressure / 100:.6g} mbar (absolute), ΔP to time = {test.loss / 100:.4g} mbar",
             f"{'flow':<8} " + ("Q_pV from P2 to P with the gas pressure taken off the contact pressure, slip at the local "
                                "gas pressure and gap (docs/theory.md §13.5)" if case.coupled else "Q_pV = K ∫ p f(Kn(p)) dp from P2 to P")
             + f", rarefaction: {rig.rarefaction_model}"]
    for name, m in pred.models.items():
        d, leak = m.decay, m.initial_leak
        lines += ["", name]
        if leak is None:
            lines.append("  no leak channel: the pressure stays at P1")
            continue
        lines += [f"  K = {m.conductance:.4g} m³/(Pa·s), narrowest gap h = {m.gap:.4g} m, Kn = {leak.knudsen_mean:.3g} "
                  f"at the mean pressure ({leak.regime} flow)",
                  f"  leak at the start: {_pv(leak.throughput)} ({leak.mass_flow:.4g} kg/s)",
                  f"  time to lose ΔP = {d.pressure_loss / 100:.4g} mbar: {duration_text(d.time_to_loss)}"
                  + (f"  (no-slip flow: {duration_text(m.viscous_time_to_loss)})" if rig.rarefaction_model != "no-slip" else ""),
                  f"  standard leak rate V·ΔP/Δt: {_pv(d.standard_leak_rate)}"]
    if readings is not None:
        r = readings.readings
        t = r.time
        lines += _readings_head(readings_source, t, duration_text(t[-1] - t[0]),
                                f"{'P (mbar)':>12} {'Q_pV (Pa·m³/s)':>15} {'(mbar·l/s)':>12}", r.interval_leak_rate,
                                [f"{pi / 100:12.6g} {qi:15.4e} {qi * MBAR_L_PER_PA_M3:12.4e}"
                                 for pi, qi in zip(r.interval_pressure, r.interval_leak_rate)],
                                "pressure", "leak rate")
        lines.append(f"leak rate over the readings V·(P_first − P_last)/(t_last − t_first): {_pv(r.leak_rate)}")
        lines.append(f"viscous fit of artanh(P2/P)/P2 against t: K = {r.conductance:.4g} ± {r.conductance_std:.2g} m³/(Pa·s)")
        for name, sc in readings.scale.items():
            what = "α implied by the readings" if name.startswith("critical") else "factor on its K implied by the readings"
            lines.append(f"{name}: {what}: {sc.alpha:.4g} ± {sc.alpha_std:.2g}"
                         + (f" (case α = {case.alpha:g}){_far(sc.alpha)}" if name.startswith("critical") else ""))
    lines += ["note: " + m for m in worded(pred.messages)]
    return "\n".join(lines) + "\n"


def _far(alpha: float) -> str:
    """What an α implied by readings far from order one says (outside the range in which predict warns about a given α
    and fit flags a fitted one, fit_alpha_far), or ""."""
    low, high = PLAUSIBLE_ALPHA
    if not np.isfinite(alpha) or low <= alpha <= high:
        return ""
    return (f"; outside {low:g} to {high:g} (α is a shape factor of order one): the model does not describe these "
            "readings as given; check their units, the rig's load and the case")


def decay_json(case: Case, pred: DecayPrediction, readings: DecayReadingsResult | None = None) -> str:
    """The ``sealeak rig --json`` document of a pressure-decay test: the test, and per model K, the gap, Kn,
    the leak at the start, Δt, V·ΔP/Δt and the whole P(t) (SI units, listed in ``units``)."""
    rig = decay_rig(case)
    test = rig.test
    models: dict[str, Any] = {}
    for name, m in pred.models.items():
        d, leak = m.decay, m.initial_leak
        models[name] = record_fields(DecayModelRecord(
            conductance=json_value(m.conductance), gap=json_value(m.gap),
            knudsen_number=json_value(leak.knudsen_mean) if leak else None, flow_regime=leak.regime if leak else None,
            initial_leak_rate_pv=json_value(leak.throughput) if leak else 0.0,
            initial_leak_rate_mbar_l_s=json_value(leak.throughput * MBAR_L_PER_PA_M3) if leak else 0.0,
            initial_leak_rate_mass=json_value(leak.mass_flow) if leak else 0.0,
            time_to_pressure_loss=json_value(d.time_to_loss), time_to_pressure_loss_no_slip=json_value(m.viscous_time_to_loss),
            standard_leak_rate_pv=json_value(d.standard_leak_rate),
            standard_leak_rate_mbar_l_s=json_value(d.standard_leak_rate * MBAR_L_PER_PA_M3),
            time=[json_value(x) for x in d.time], pressure=[json_value(x) for x in d.pressure],
            leak_rate_pv=[json_value(x) for x in d.throughput]))
    doc: dict[str, Any] = {
        "case": case.title, "kind": "pressure-decay", "squeeze_pressure": pred.squeeze_pressure,
        "load": json_value(rig.load) if rig.load is not None else None,
        "test": {"volume": test.volume, "initial_pressure": test.initial_pressure, "outside_pressure": test.outside_pressure,
                 "temperature": test.temperature, "pressure_loss": test.loss, "gas": rig.gas.name,
                 "viscosity": rig.gas.viscosity, "molar_mass": rig.gas.molar_mass, "rarefaction_model": rig.rarefaction_model},
        "models": models,
        "units": dict(DECAY_UNITS),
        "messages": worded(pred.messages)}
    b = pred.band
    if b is not None:
        doc[b.band.load_name] = float(b.band.loads[0])
        doc["units"] |= _band_load_units(b.band.load_name)
    if readings is not None:
        r = readings.readings
        doc["readings"] = {"interval_pressure": [json_value(x) for x in r.interval_pressure],
                           "interval_leak_rate_pv": [json_value(x) for x in r.interval_leak_rate],
                           "leak_rate_pv": json_value(r.leak_rate), "leak_rate_mbar_l_s": json_value(r.leak_rate * MBAR_L_PER_PA_M3),
                           "conductance": json_value(r.conductance), "conductance_std": json_value(r.conductance_std),
                           "scale": {name: {"alpha": json_value(sc.alpha), "alpha_std": json_value(sc.alpha_std)}
                                     for name, sc in readings.scale.items()}}
    return json_document(doc)
