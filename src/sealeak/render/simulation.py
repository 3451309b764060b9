"""Renderings of the numerically exact route (``sealeak simulate``): table, JSON and figures."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap
from matplotlib.container import ErrorbarContainer
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from numpy.typing import NDArray

from ..cases import Case, SimulationResult
from ..cases.simulation import JUNCTION_CELLS, GasSimulation, SimulationCapillarity
from ..cases.simulation_band import HERTZ_TOL, BandSimulationResult
from ..io.leak_units import celsius, to_mbar_l_per_s
from ..io.quantities import record_fields, units_of
from ..numerics import spanning_mask
from ..physics.profile import PressureProfile
from .notes import load_axis_label, load_text, worded
from .plotstyle import (
    GAS_LEAK_LABEL,
    PA_M3_PER_MBAR_L,
    color,
    finish_axes,
    gas_conditions_text,
    laid_out,
    literal_text,
    ml_per_min_axis,
    new_figure,
    pa_m3_axis,
    place_legend,
    pressure_axis,
    say_nothing,
    subtitle,
    sweep_axis,
)
from .records import case_summary, json_document, json_rows, json_value
from .text import fmt

__all__ = ["simulation_json", "simulation_rows", "simulation_table", "simulation_figures", "SIMULATION_UNITS", "SIMULATION_FIGURE_NAMES",
           "SIMULATION_GAS_UNITS", "SIMULATION_GAS_FIGURE_NAMES", "SIMULATION_CAPILLARY_UNITS",
           "band_simulation_json", "band_simulation_table", "band_simulation_figures", "BAND_SIMULATION_UNITS",
           "BAND_SIMULATION_FIGURE_NAMES", "BAND_SIMULATION_GAS_UNITS"]


#: SI unit of every key of ``simulate --json`` (declared on :class:`~sealeak.cases.SimulationResult`'s fields).
SIMULATION_UNITS = units_of(SimulationResult)
#: The keys of a ``simulate --json`` row, in the order written (values and units from the result's fields).
_ROW_KEYS = ("squeeze_pressure", "relative_contact_area", "relative_contact_area_std", "relative_contact_area_theory",
             "mean_gap", "mean_gap_std", "percolating_fraction", "leak_rate", "leak_rate_std",
             "leak_rate_critical_junction", "alpha", "alpha_std", "pressure_difference", "junction_cells",
             "junction_resolved")
SIMULATION_FIGURE_NAMES = ("simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png")
#: Units of the capillarity keys of a ``simulate --json`` row (a liquid with a contact angle).
SIMULATION_CAPILLARY_UNITS = units_of(SimulationCapillarity)
#: The extra figure of a gas case.
SIMULATION_GAS_FIGURE_NAMES = ("simulate_gas_leak_rate.png",)
#: Units of the gas keys of a ``simulate --json`` row (a gas case), declared on the gas result's fields; names as
#: ``predict``'s gas keys.
SIMULATION_GAS_UNITS = units_of(GasSimulation)
#: The gas keys of a ``simulate --json`` row, in the order written.
_GAS_ROW_KEYS = ("knudsen_number", "leak_rate_pv", "leak_rate_pv_std", "leak_rate_mass", "leak_rate_mass_std",
                 "leak_rate_molar", "slip_gain", "leak_rate_pv_critical_junction", "alpha_gas", "alpha_gas_std",
                 "gas_iterations", "flow_regime", "leak_rate_mbar_l_s")


def simulation_json(case: Case, res: SimulationResult) -> str:
    """The ``sealeak simulate --json`` document: per-pressure results, threshold, settings, case."""
    doc: dict[str, Any] = {
        "units": SIMULATION_UNITS,
        "results": simulation_rows(res),
        "percolation_threshold": json_value(res.percolation_threshold),
        "percolation_threshold_std": json_value(res.percolation_threshold_std),
        "settings": {"grid": res.grid, "realizations": res.realizations, "seed": res.seed, "size": res.size,
                     "spectrum_cut_wavevector": res.q_cut, "spectrum": res.spectrum_note},
        **_document_end(case, res, ("leak_rate_critical_junction", "critical-junction prediction with alpha = 1 for "
                                    "the same spectrum"), ": the standard error of a mean is std/sqrt(realizations)"),
    }
    if res.gas is not None:
        _gas_json(doc, res)
    _capillary_json(doc, res.capillarity)
    return json_document(doc)


def _capillary_json(doc: dict[str, Any], c: SimulationCapillarity | None) -> None:
    """A liquid with a contact angle: each row of a ``simulate --json`` document gets its entry pressures and held
    realisations (nothing without a contact angle)."""
    if c is None:
        return
    doc["units"] = doc["units"] | SIMULATION_CAPILLARY_UNITS
    columns = record_fields(c)
    for row, extra in zip(doc["results"], json_rows(columns, tuple(columns), len(doc["results"])), strict=True):
        row |= extra


def _document_end(case: Case, res: SimulationResult | BandSimulationResult, theory: tuple[str, str],
                  standard_error: str) -> dict[str, Any]:
    """The last keys of a ``simulate --json`` document: what the theory's key (``theory``: key, what it is) and α are,
    what the ``*_std`` keys are (``standard_error``: how to get one, if said), the case and the notes."""
    key, what = theory
    return {f"{key}_note": f"{what}; alpha = leak_rate / {key}",
            "spread_note": "*_std are standard deviations over realisations (ddof = 1; alpha_std over the percolating "
                           f"ones), not standard errors{standard_error}; null with fewer than two values",
            "case": case_summary(case),
            "notes": worded(res.notes)}


def simulation_rows(res: SimulationResult) -> list[dict[str, Any]]:
    """The per-pressure records of ``sealeak simulate --json`` (units :data:`SIMULATION_UNITS`), liquid keys only."""
    return json_rows(record_fields(res), _ROW_KEYS, res.squeeze_pressure.size)


def _add_gas_json(doc: dict[str, Any], g: GasSimulation, rename: dict[str, str]) -> None:
    """The gas keys of a ``simulate --json`` document (uniform or O-ring): per row the gas leak and α_gas, and the gas.

    ``rename``: record keys the geometry names otherwise (the O-ring's theory is the series resistance).
    """
    doc["units"] = doc["units"] | {rename.get(k, k): u for k, u in units_of(g).items()}
    columns = {rename.get(k, k): v for k, v in record_fields(g).items()}
    keys = tuple(rename.get(k, k) for k in _GAS_ROW_KEYS)
    for row, gas_row in zip(doc["results"], json_rows(columns, keys, len(doc["results"])), strict=True):
        row |= gas_row
    doc["gas"] = {"name": g.gas_name, "temperature": g.temperature, "upstream_pressure": g.upstream_pressure,
                  "downstream_pressure": g.downstream_pressure, "rarefaction": g.rarefaction,
                  "units": {"temperature": "K", "upstream_pressure": "Pa", "downstream_pressure": "Pa"}}


def _gas_json(doc: dict[str, Any], res: SimulationResult) -> None:
    """Add a gas case's keys to the ``simulate --json`` document: per row the gas leak, its α, and the gas settings."""
    assert res.gas is not None
    _add_gas_json(doc, res.gas, {})
    doc["gas_note"] = ("leak_rate_pv: the seal's pV throughput from isothermal gas flow through the same gap fields, "
                       "div(g^3 f(Kn) grad p^2) = 0, counted at the gas temperature; leak_rate_mass = leak_rate_pv/(R_s T); "
                       "slip_gain = leak_rate_pv / the same flow without rarefaction; leak_rate_pv_critical_junction: the "
                       "critical-junction gas leak with alpha = 1, gap u_c, the same rarefaction model (as predict); "
                       "alpha_gas = leak_rate_pv / leak_rate_pv_critical_junction; knudsen_number, flow_regime: at u_c and the "
                       "mean pressure (P_a + P_b)/2; gas_iterations: the most fixed-point iterations of any realisation; "
                       "leak_rate, alpha: the incompressible formula with the gas's viscosity, for comparison")


def _gas_rows(g: Any, label: tuple[str, int], rows: list[str], theory: tuple[str, int], coarse: list[bool]) -> list[str]:
    """The header and rows of a gas table: ``rows`` the formatted first column (header ``label``, its width), then
    Kn, regime, Q_pV ± sd (Pa·m³/s and mbar·l/s), ṁ, slip gain, the theory's Q_pV (header ``theory``), α_gas ± sd
    (``*`` where ``coarse``: the grid resolves the junction poorly), and the fixed-point iterations."""
    (name, width), (theory_name, theory_width) = label, theory
    lines = [f"{name:>{width}} {'Kn at u_c':>9} {'regime':>14} {'Q_pV sim (Pa·m³/s)':>19} {'± sd':>9} {'Q (mbar·l/s)':>12} "
             f"{'ṁ (kg/s)':>10} {'slip gain':>9} {theory_name:>{theory_width}} {'α_gas':>7} {'± sd':>8} {'iter':>4}"]
    for i, first in enumerate(rows):
        star = "*" if coarse[i] and np.isfinite(g.alpha[i]) else " "
        lines.append(f"{first} {fmt(g.knudsen_critical_junction[i], '9.3g')} "
                     f"{g.regime_critical_junction[i] or '—':>14} {fmt(g.throughput[i], '19.3e')} {fmt(g.throughput_std[i], '9.2e')} "
                     f"{fmt(to_mbar_l_per_s(g.throughput[i]), '12.3e')} {fmt(g.mass_flow[i], '10.3e')} {fmt(g.slip_gain[i], '9.4g')} "
                     f"{fmt(g.throughput_critical_junction[i], f'{theory_width}.3e')} {fmt(g.alpha[i], '7.3g')}{star} "
                     f"{fmt(g.alpha_std[i], '7.2g')} {g.iterations[i]:4d}")
    return lines


def _gas_lines(res: SimulationResult) -> list[str]:
    """The gas table of ``sealeak simulate`` and what its columns mean."""
    g = res.gas
    assert g is not None
    return _gas_block(g, "gas leak of {gas}, {conditions}:",
                      _gas_rows(g, ("P0 (kPa)", 9), [f"{p / 1e3:9.4g}" for p in res.squeeze_pressure], ("Q_pV cj α=1", 12),
                                list(coarse(res.junction_cells, res.squeeze_pressure.size))),
                      ("", ""), ("cj", "critical-junction", "gap u_c"))


def _gas_block(g: Any, head: str, table: list[str], flow: tuple[str, str], theory: tuple[str, str, str]) -> list[str]:
    """A gas table of ``sealeak simulate`` under its ``head`` (``{gas}``, ``{conditions}``: pressures, temperature,
    rarefaction), and what its columns mean: ``flow`` where the simulated gas flows (after "gas flow" and after its
    equation), ``theory`` the theory's short name, name and gap."""
    conditions = (f"{g.upstream_pressure / 1e3:.4g} kPa → {g.downstream_pressure / 1e3:.4g} kPa (absolute), "
                  f"{celsius(g.temperature):.4g} °C, rarefaction {g.rarefaction}")
    (where, edges), (short, name, gap) = flow, theory
    return ["", head.format(gas=g.gas_name, conditions=conditions), *table, "",
            f"Q_pV sim: isothermal gas flow{where} through the same gap fields, ∇·(g³ f(Kn) ∇p²) = 0{edges}, counted at "
            "the gas temperature; ṁ = Q_pV/(R_s T); slip gain: Q_pV over the same flow without rarefaction",
            f"Q_pV {short} α=1: the {name} gas leak ({gap}, the same rarefaction; as predict); α_gas = Q_pV sim / "
            f"Q_pV {short}; Kn = λ/u_c at the mean pressure {0.5 * (g.upstream_pressure + g.downstream_pressure) / 1e3:.4g} "
            "kPa; iter: fixed-point iterations (most over the realisations; 0 without rarefaction)",
            "the table above (Q in m³/s, α) is the incompressible formula with the gas's viscosity, for comparison"]


def simulation_table(case: Case, res: SimulationResult) -> str:
    """The table ``sealeak simulate`` prints: numerical against critical-junction leak rate and α."""
    lines = [f"{case.title}: numerically exact leak rate",
             f"grid {res.grid}x{res.grid} on a square of side {res.size * 1e3:.4g} mm, {res.realizations} "
             f"realisation(s), seed {res.seed}; {res.spectrum_note}", ""]
    lines.append(f"{'P0 (kPa)':>9} {'A/A0 sim':>9} {'A/A0 th':>8} {'ū (µm)':>9} {'perc':>5} "
                 f"{'Q sim (m³/s)':>13} {'± sd':>9} {'Q cj α=1':>10} {'α':>7} {'± sd':>7}")

    too_coarse = coarse(res.junction_cells, res.squeeze_pressure.size)
    for i in range(res.squeeze_pressure.size):
        lines.append(f"{res.squeeze_pressure[i] / 1e3:9.4g} {res.relative_contact_area[i]:9.3f} "
                     f"{res.relative_contact_area_theory[i]:8.3f} {res.mean_gap[i] * 1e6:9.4g} "
                     f"{res.percolating_fraction[i]:5.2f} {fmt(res.leak_rate[i], '13.3e')} {fmt(res.leak_rate_std[i], '9.2e')} "
                     f"{fmt(res.leak_rate_critical_junction[i], '10.3e')} {fmt(res.alpha[i], '7.3g')}"
                     f"{'*' if too_coarse[i] and np.isfinite(res.alpha[i]) else ' '}{fmt(res.alpha_std[i], '7.2g')}")
    if res.gas is not None:
        lines += _gas_lines(res)
    if res.capillarity is not None:
        lines += _capillary_lines(res.capillarity, res.pressure_difference, ("P0 (kPa)", res.squeeze_pressure / 1e3),
                                  "p_e at u_c (kPa)")
    lines.append("")
    lines.append(_spread_legend(res.realizations))
    if np.isfinite(res.percolation_threshold):
        found = int(np.isfinite(res.per_realization.get("percolation_threshold", np.ones(res.realizations))).sum())
        spread = (f"mean of {found} realisations, sd {res.percolation_threshold_std:.2g}"
                  if np.isfinite(res.percolation_threshold_std) else "one realisation")
        lines.append(f"the non-contact area stops percolating at A/A0 = {res.percolation_threshold:.3f} ({spread}; "
                     f"critical-junction theory assumes 1 - p_c = {1 - case.percolation_threshold:.3f})")
    lines += ["note: " + n for n in worded(res.notes)]
    return "\n".join(lines) + "\n"


def _capillary_lines(c: SimulationCapillarity, pressure_difference: float, first: tuple[str, NDArray[np.float64]],
                     theory: str) -> list[str]:
    """The capillarity table of ``sealeak simulate``: per load (``first``: the column's header and values) the entry
    pressure of the realisations' critical constrictions against the theory's (header ``theory``), and the
    realisations held (docs/theory.md §12.4)."""
    head, loads = first
    lines = ["", f"capillarity at ΔP = {pressure_difference / 1e3:.4g} kPa: entry pressure p_e = −γ(cos θ_r + cos θ_s)/u "
                 "of each realisation's critical constriction u (the narrowest gap on the widest path across)",
             f"{head:>16} {'p_e sim (kPa)':>13} {'± sd':>9} {theory:>22} {'held':>5} {'all held':>8}"]
    for i, load in enumerate(loads):
        lines.append(f"{load:16.4g} {fmt(c.capillary_entry_pressure[i] / 1e3, '13.4g')} "
                     f"{fmt(c.capillary_entry_pressure_std[i] / 1e3, '9.2g')} "
                     f"{fmt(c.capillary_entry_pressure_critical_junction[i] / 1e3, '22.4g')} {c.held_fraction[i]:5.2f} "
                     f"{'yes' if c.held_by_capillarity[i] else 'no':>8}")
    lines.append("held: fraction of realisations the fluid crosses but ΔP < p_e holds (Q = 0 there; the leak rates and α "
                 "above are the flow without capillarity)")
    return lines


def coarse(junction_cells: NDArray[np.float64], rows: int) -> NDArray[np.bool_]:
    """Per row (of any shape): whether the theory's junction spans fewer than :data:`JUNCTION_CELLS` grid cells,
    too few for α (see the notes); all False for ``rows`` rows when there is no theory's junction (no cells)."""
    cells = np.asarray(junction_cells, dtype=float)
    if not cells.size:
        return np.zeros(rows, dtype=bool)
    return np.isfinite(cells) & (cells < JUNCTION_CELLS)


def _spread_legend(realizations: int) -> str:
    """What the ± columns of the simulate table are (standard deviations over realisations, not standard errors)."""
    if realizations < 2:
        return "± sd: standard deviation over realisations; none with one realisation (—)"
    return (f"± sd: standard deviation over the {realizations} realisations (for α: over the percolating ones), "
            "the spread from one random surface to another; "
            f"the standard error of a mean is sd/√{realizations}")


# ---------------------------------------------------------------- the O-ring (band) simulation
#: SI unit of every key of an O-ring's ``simulate --json`` (declared on the result's fields); the load's key
#: (``compression`` or ``profile_scale``) leads.
BAND_SIMULATION_UNITS = units_of(BandSimulationResult)
BAND_SIMULATION_FIGURE_NAMES = ("simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png",
                                "simulate_band_pressure.png")
#: The keys of an O-ring's ``simulate --json`` row after the load, in the order written.
_BAND_ROW_KEYS = ("force_per_length", "model_contact_width", "model_max_pressure", "hertz_contact_width",
                  "hertz_max_pressure", "smooth_contact_width", "smooth_max_pressure", "smooth_width_error",
                  "smooth_pressure_error", "contact_width", "contact_width_std", "relative_contact_area",
                  "relative_contact_area_std", "percolating_fraction", "leak_rate", "leak_rate_std",
                  "leak_rate_series_resistance", "alpha", "alpha_std", "junction_cells", "junction_resolved",
                  "pressure_difference")


def _load_label(res: BandSimulationResult) -> tuple[str, float]:
    """Column label and the factor that shows the loads (compression in %, a scale factor as is)."""
    return ("compression (%)", 100.0) if res.load_name == "compression" else (res.load_name.replace("_", " "), 1.0)


def band_simulation_json(case: Case, res: BandSimulationResult) -> str:
    """The ``sealeak simulate --json`` document of an O-ring: per compression, the smooth check, settings, case."""
    units = {res.load_name: "1"} | BAND_SIMULATION_UNITS
    rows = [{res.load_name: json_value(res.loads[i])} | row
            for i, row in enumerate(json_rows(record_fields(res), _BAND_ROW_KEYS, res.loads.size))]
    doc: dict[str, Any] = {
        "units": units,
        "results": rows,
        "smooth_check": {"passed": res.smooth_check_passed, "tolerance": HERTZ_TOL,
                         "note": "the solver without roughness against Hertz line contact with the same force per "
                                 "length: b = sqrt(4 f R/(pi E*)), p_max = 2 f/(pi b); *_error = simulated/Hertz - 1"},
        "settings": {"grid": res.grid, "realizations": res.realizations, "seed": res.seed, "size": res.size,
                     "period": res.period, "seal_length": res.seal_length, "faces": res.faces, "radius": res.radius,
                     "spectrum_cut_wavevector": res.q_cut, "spectrum_low_wavevector": res.q_low,
                     "spectrum": res.spectrum_note},
        **_document_end(case, res, ("leak_rate_series_resistance", "series-resistance prediction of the "
                                    "critical-junction theory with alpha = 1 for the same spectrum and the Hertz profile "
                                    "of the same force"), ""),
    }
    if res.gas is not None:
        _band_gas_json(doc, res)
    _capillary_json(doc, res.capillarity)
    return json_document(doc)


#: The gas record keys an O-ring names otherwise: its theory's column is named as the band's liquid one.
_BAND_GAS_KEYS = {"leak_rate_pv_critical_junction": "leak_rate_pv_series_resistance"}
#: Units of the gas keys of an O-ring's ``simulate --json`` row.
BAND_SIMULATION_GAS_UNITS = {_BAND_GAS_KEYS.get(k, k): u for k, u in SIMULATION_GAS_UNITS.items()}


def _band_gas_json(doc: dict[str, Any], res: BandSimulationResult) -> None:
    """Add a gas O-ring's keys to the ``simulate --json`` document: per row the gas leak across the band, α_gas, the gas."""
    assert res.gas is not None
    _add_gas_json(doc, res.gas, _BAND_GAS_KEYS)
    doc["gas_note"] = ("leak_rate_pv: the seal's pV throughput from isothermal gas flow across the band through the same gap "
                       "fields, div(g^3 f(Kn) grad p^2) = 0 with P_a at x = 0 and P_b at x = W, scaled to the seal line as "
                       "leak_rate, counted at the gas temperature; leak_rate_mass = leak_rate_pv/(R_s T); slip_gain = "
                       "leak_rate_pv / the same flow without rarefaction; leak_rate_pv_series_resistance: the "
                       "series-resistance gas leak with alpha = 1 (K = leak_rate_series_resistance/(P_a - P_b), gap u_c at "
                       "the peak contact pressure, the same rarefaction model, as predict); alpha_gas = leak_rate_pv / "
                       "leak_rate_pv_series_resistance; knudsen_number, flow_regime: at that gap and the mean pressure "
                       "(P_a + P_b)/2; gas_iterations: the most fixed-point iterations of any realisation; "
                       "leak_rate, alpha: the incompressible formula with the gas's viscosity, for comparison")


def _band_gas_lines(res: BandSimulationResult) -> list[str]:
    """The gas table of ``sealeak simulate`` for an O-ring and what its columns mean."""
    g = res.gas
    assert g is not None
    label, factor = _load_label(res)
    return _gas_block(g, "Gas leak across the band: {gas}, {conditions}",
                      _gas_rows(g, (label, 16), [f"{x * factor:16.4g}" for x in res.loads], ("Q_pV series α=1", 15),
                                list(coarse(res.junction_cells, res.loads.size))),
                      (" across the band", ", P_a at the inlet edge, P_b at the outlet edge, scaled to the seal line as Q sim"),
                      ("series", "series-resistance", "K = Q series/ΔP, gap u_c at the peak contact pressure"))


def band_simulation_table(case: Case, res: BandSimulationResult) -> str:
    """The table ``sealeak simulate`` prints for an O-ring: the smooth check, then numerical against series leak rate and α."""
    label, factor = _load_label(res)
    cell = res.size / res.grid
    lines = [f"{case.title}: numerically exact leak rate of the O-ring",
             f"domain {res.size * 1e3:.4g} mm across the band (free edges) x {res.period * 1e3:.4g} mm along the seal "
             f"line (periodic), grid {res.grid}x{res.grid} ({cell * 1e6:.3g} µm cells), {res.realizations} "
             f"realisation(s), seed {res.seed}",
             f"cylinder radius R = {res.radius * 1e3:.4g} mm, seal line {res.seal_length * 1e3:.4g} mm, "
             f"{res.faces} face(s), ΔP = {res.pressure_difference / 1e3:.4g} kPa; {res.spectrum_note}", "",
             "Smooth check, no roughness: the solver against Hertz line contact, 2b = 2√(4fR/(πE*)), p_max = 2f/(πb)",
             f"{label:>16} {'f (N/m)':>9} {'2b Hertz (mm)':>14} {'2b sim (mm)':>12} {'Δ':>8} "
             f"{'p_max Hertz (MPa)':>18} {'p_max sim (MPa)':>16} {'Δ':>8}"]
    for i in range(res.loads.size):
        lines.append(f"{res.loads[i] * factor:16.4g} {res.force_per_length[i]:9.4g} {res.hertz_contact_width[i] * 1e3:14.4g} "
                     f"{fmt(res.smooth_contact_width[i] * 1e3, '12.4g')} {fmt(100 * res.smooth_width_error[i], '+7.2f')}% "
                     f"{res.hertz_max_pressure[i] / 1e6:18.4g} {res.smooth_max_pressure[i] / 1e6:16.4g} "
                     f"{fmt(100 * res.smooth_pressure_error[i], '+7.2f')}%")
    lines.append(f"agreement within {100 * HERTZ_TOL:g} % at every load: {'yes' if res.smooth_check_passed else 'NO (see the notes)'}")
    lines += ["", "Rough contact and flow across the band",
              f"{label:>16} {'width (mm)':>11} {'A/A0 band':>10} {'perc':>5} {'Q sim (m³/s)':>13} {'± sd':>9} "
              f"{'Q series α=1':>13} {'α':>8} {'± sd':>8}"]
    too_coarse = coarse(res.junction_cells, res.loads.size)
    for i in range(res.loads.size):
        star = "*" if too_coarse[i] and np.isfinite(res.alpha[i]) else " "
        lines.append(f"{res.loads[i] * factor:16.4g} {res.contact_width[i] * 1e3:11.4g} {fmt(res.relative_contact_area[i], '10.3f')} "
                     f"{res.percolating_fraction[i]:5.2f} {fmt(res.leak_rate[i], '13.3e')} {fmt(res.leak_rate_std[i], '9.2e')} "
                     f"{fmt(res.leak_rate_series_resistance[i], '13.3e')} {fmt(res.alpha[i], '8.3g')}{star}"
                     f" {fmt(res.alpha_std[i], '7.2g')}")
    lines += ["",
              "width: extent of the rough contact across the band; A/A0 band: contact fraction inside the Hertz band; "
              "perc: fraction of realisations in which fluid crosses the band",
              "Q series α=1: the series-resistance prediction Q = Ly ΔP / ∫dx/σ(p(x)) of the critical-junction theory "
              "with α = 1, same spectrum, Hertz profile of the same force; α = Q sim / Q series is the α of this O-ring",
              _spread_legend(res.realizations)]
    if res.gas is not None:
        lines += _band_gas_lines(res)
    if res.capillarity is not None:
        lines += _capillary_lines(res.capillarity, res.pressure_difference, (label, res.loads * factor),
                                  "p_e at u_c, peak (kPa)")
    lines += ["note: " + n for n in worded(res.notes)]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- figures: the square and the O-ring share each builder
@dataclass(frozen=True, kw_only=True)
class _Sweep:
    """What the leak-rate and α figures of one simulated geometry draw against, and the words that name it.

    Attributes
    ----------
    x, x_label, loads
        The loads as the x axis reads them (P0 in kPa or MPa, an O-ring's compression in %), the axis
        label, and what one load is called ("squeeze pressure", "compression").
    coarse
        Per load: the theory's critical junction spans fewer than :data:`JUNCTION_CELLS` grid cells, so
        its α reflects the grid (the theory drawn dotted, the α hollow).
    theory, short
        The prediction compared with ("critical-junction", "series-resistance") and its subscript in
        α's label ("cj", "series").
    method, seal, settings, pressure_difference
        How the numbers were computed (legend), the seal's name in the headings ("" for the periodic
        square, "O-ring"), the run's subtitle line (grid, realisations, the seal's size) and ΔP (Pa).
    alpha, alpha_label
        The α drawn for comparison in the leak-rate and α figures (the case's α; 1 for an O-ring) and
        the label of its line in the α figure.
    """

    x: NDArray[np.float64]
    x_label: str
    loads: str
    coarse: NDArray[np.bool_]
    theory: str
    short: str
    method: str
    seal: str
    settings: str
    pressure_difference: float
    alpha: float
    alpha_label: str

    @property
    def through(self) -> str:
        return f" through the {self.seal}" if self.seal else ""

    @property
    def liquid_settings(self) -> str:
        return f"{self.settings}, ΔP = {self.pressure_difference / 1e3:.3g} kPa"


def _run_text(res: SimulationResult | BandSimulationResult) -> str:
    return f"{res.grid}² grid, {res.realizations} realisation(s)"


def _gas_label(g: GasSimulation) -> str:
    return f"{g.gas_name} {g.upstream_pressure / 1e3:.4g} → {g.downstream_pressure / 1e3:.4g} kPa"


@literal_text
def simulation_figures(case: Case, res: SimulationResult) -> dict[str, Figure]:
    """The figures of ``sealeak simulate --plots``: leak rate, α and a contact map (and a gas case's gas leak), by file name."""
    scale, unit = pressure_axis(res.squeeze_pressure)
    sweep = _Sweep(x=res.squeeze_pressure / scale, x_label=f"squeeze pressure P0 ({unit})", loads="squeeze pressure",
                   coarse=coarse(res.junction_cells, res.squeeze_pressure.size),
                   theory="critical-junction", short="cj", method="BEM + Reynolds", seal="",
                   settings=f"{_run_text(res)}, Ly/Lx = {case.seal.aspect_ratio:.3g}",
                   pressure_difference=res.pressure_difference, alpha=case.alpha,
                   alpha_label=f"case α = {case.alpha:g}")
    figs = _sweep_figures(case, sweep, res, res.leak_rate_critical_junction)
    if res.contact_maps:
        pick = _map_pick(res.contact_maps, res.per_realization)
        figs["contact_map.png"] = _contact_map_figure(
            res.contact_maps[pick], (res.size, res.size), f"P0 = {res.squeeze_pressure[pick] / scale:.3g} {unit}",
            ("x (mm), flow from inlet x = 0 to outlet →", "y, periodic (mm)"),
            f"black: contact ({res.contact_maps[pick].mean():.1%}); blue: channels spanning inlet to outlet; "
            "grey: trapped fluid")
    return figs


@literal_text
def band_simulation_figures(case: Case, res: BandSimulationResult) -> dict[str, Figure]:
    """The figures of ``sealeak simulate --plots`` for an O-ring: leak rate, α, a contact map, the pressure across the
    band (and a gas O-ring's gas leak), by file name."""
    label, factor = _load_label(res)
    sweep = _Sweep(x=res.loads * factor,
                   x_label=load_axis_label(res.load_name), loads=label.split(" (")[0],
                   coarse=coarse(res.junction_cells, res.loads.size),
                   theory="series-resistance", short="series", method="cylinder on rough surface + Reynolds", seal="O-ring",
                   settings=f"{_run_text(res)}, seal line {res.seal_length * 1e3:.3g} mm",
                   pressure_difference=res.pressure_difference, alpha=1.0, alpha_label="α = 1")
    figs = _sweep_figures(case, sweep, res, res.leak_rate_series_resistance)
    if res.contact_maps:
        pick = _map_pick(res.contact_maps, res.per_realization)
        figs["contact_map.png"] = _contact_map_figure(
            res.contact_maps[pick], (res.size, res.period), load_text(res.load_name, res.loads[pick]),
            ("x across the band (mm), flow from x = 0 to the outlet →", "y along the seal line, periodic (mm)"),
            "black: contact; blue: channels crossing the band; grey: trapped or dead-end fluid; red dashes: Hertz band",
            edges=res.size / 2.0 + np.array([-0.5, 0.5]) * res.hertz_contact_width[pick])
    figs["simulate_band_pressure.png"] = _band_pressure_figure(res)
    return figs


def _sweep_figures(case: Case, sweep: _Sweep, res: SimulationResult | BandSimulationResult,
                   theory: NDArray[np.float64]) -> dict[str, Figure]:
    """The leak-rate and α figures of either geometry, and a gas case's gas leak-rate figure."""
    g = res.gas
    figs = {"simulate_leak_rate.png": _leak_rate_figure(case, sweep, res.leak_rate, res.leak_rate_std, theory),
            "simulate_alpha.png": _alpha_figure(sweep, res.alpha, res.alpha_std, g)}
    if g is not None:
        figs["simulate_gas_leak_rate.png"] = _leak_rate_figure(case, sweep, g.throughput, g.throughput_std,
                                                               g.throughput_critical_junction, g)
    return figs


@laid_out
def _leak_rate_figure(case: Case, sweep: _Sweep, q: NDArray[np.float64], q_std: NDArray[np.float64],
                      theory: NDArray[np.float64], gas: GasSimulation | None = None) -> Figure:
    """The simulated leak rate (mean ± sd over the realisations) against the theory's with α = 1 (log axis).

    Liquid: Q in m³/s with a second axis in ml/min; gas: the pV throughput in mbar·l/s with a second axis in
    Pa·m³/s, counted at the gas temperature (``q``, ``theory`` in SI units: m³/s, Pa·m³/s). Loads where no
    realisation leaks are × on the bottom edge.
    """
    k = PA_M3_PER_MBAR_L if gas is not None else 1.0  # plotted: q / k
    what = f"Leak rate of {gas.gas_name}" if gas is not None else "Leak rate"
    fig, ax = new_figure(f"{what}{sweep.through}: numerical against {sweep.theory} theory", figsize=(6.4, 5.4))
    sweep_axis(ax, sweep.x, sweep.x_label)
    method = sweep.method.replace("Reynolds", "gas flow in p²") if gas is not None else sweep.method
    drawn = _numerical_points(ax, sweep.x, q / k, q_std / k, f"numerical ({method}), mean ± sd")
    predicted = _theory_lines(ax, sweep, theory / k)
    drawn = np.concatenate([drawn, predicted])
    notes = [gas_conditions_text(case)] if gas is not None else []
    notes.append(f"{sweep.settings}; Q_pV counted at the gas temperature" if gas is not None else sweep.liquid_settings)
    if drawn.size and not predicted.size:
        notes.append(f"the {sweep.theory} theory finds no leak channel at any {sweep.loads}")
    if drawn.size:
        ax.set_yscale("log")
        ax.set_ylim(drawn.min() / 3.0, drawn.max() * 3.0)
    else:
        say_nothing(ax, f"no leak channel at any {sweep.loads}\n(numerically or in the {sweep.theory} theory)")
    ax.set_ylabel(f"{GAS_LEAK_LABEL} (mbar·l/s)" if gas is not None else "leak rate Q (m³/s)")
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    if drawn.size:
        (pa_m3_axis if gas is not None else ml_per_min_axis)(ax)
    _legend(ax)
    return fig


def _legend(ax: Axes) -> None:
    """The legend (:func:`place_legend`) with the simulated values (error bars) first, the rest in drawing order."""
    handles, labels = ax.get_legend_handles_labels()
    first = sorted(range(len(labels)), key=lambda i: not isinstance(handles[i], ErrorbarContainer))
    place_legend(ax, [handles[i] for i in first], [labels[i] for i in first])


def _numerical_points(ax: Axes, x: NDArray[np.float64], q: NDArray[np.float64], q_std: NDArray[np.float64],
                      label: str) -> NDArray[np.float64]:
    """The simulated leak rates > 0 with their ± sd bars (the lower bar kept above zero for the log axis), and the
    loads where no realisation leaks (no channel percolates: Q = 0, off a log axis) as × on the bottom edge of the
    axes, with a legend entry; returns the leak rates drawn as points."""
    ok = q > 0
    std = np.nan_to_num(q_std[ok])
    if ok.any():
        ax.errorbar(x[ok], q[ok], yerr=np.vstack([np.minimum(std, 0.9 * q[ok]), std]), fmt="o", ms=4, capsize=3, color=color(0),
                    label=label)
    sealed = q == 0
    if sealed.any():  # y in axes units: on the bottom edge whatever the leak-rate range
        ax.plot(x[sealed], np.zeros(int(sealed.sum())), "x", ms=6, mew=1.5, color=color(0),
                transform=ax.get_xaxis_transform(), clip_on=False,
                label="numerical: no leak channel in any realisation (Q = 0), × at the bottom")
    return np.asarray(q[ok], dtype=float)


def _theory_lines(ax: Axes, sweep: _Sweep, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """The theory's leak rate with α = 1 (and the case's α when it differs) solid where the grid resolves its junction,
    dotted where λc spans fewer than JUNCTION_CELLS cells (joined to its resolved neighbour); returns the values that
    set the axis: the resolved ones, or the flagged ones where none is resolved (their distance from the points is
    what the figure shows)."""
    name = sweep.theory.replace("-", " ")
    good = np.where(sweep.coarse, np.nan, q)
    shown = good[np.isfinite(good) & (good > 0)]
    if shown.size:
        ax.plot(sweep.x, good, "-", color=color(1), label=f"{name}, α = 1")
        if sweep.alpha != 1.0:
            ax.plot(sweep.x, sweep.alpha * good, "--", color=color(2), label=f"{name}, α = {sweep.alpha:g}")
    edge = np.where(sweep.coarse | np.roll(sweep.coarse, -1), q, np.nan)
    flagged = q[sweep.coarse & np.isfinite(q) & (q > 0)]
    if flagged.size:
        ax.plot(sweep.x, edge, ":", color=color(1), label=f"{name} where λc < {JUNCTION_CELLS} cells (grid too coarse)")
    return np.asarray(shown if shown.size else flagged, dtype=float)


@laid_out
def _alpha_figure(sweep: _Sweep, alpha: NDArray[np.float64], alpha_std: NDArray[np.float64],
                  gas: GasSimulation | None) -> Figure:
    """α (± sd over the percolating realisations) against the load where the grid resolves the junction, α_gas beside
    it for a gas, the comparison α, and the grid-flagged α hollow."""
    fig, ax = new_figure(f"The factor α of the {sweep.theory} theory{' for this ' + sweep.seal if sweep.seal else ''}, "
                         "computed")
    sweep_axis(ax, sweep.x, sweep.x_label)
    ratio = f"Q_num / Q_{sweep.short}(α=1)"
    curves = [(alpha, alpha_std, "o-", color(0),
               f"α = {ratio}, ± sd" if gas is None else f"α = {ratio}, incompressible formula (gas viscosity), ± sd")]
    if gas is not None:
        curves.append((gas.alpha, gas.alpha_std, "s--", color(3),
                       f"α_gas = Q_pV / Q_pV,{sweep.short}(α=1), {_gas_label(gas)}, ± sd"))
    top = sweep.alpha
    for a, sd, style, colour, label in curves:
        ok = np.isfinite(a) & ~sweep.coarse
        if ok.any():
            ax.errorbar(sweep.x[ok], a[ok], yerr=np.nan_to_num(sd[ok]), fmt=style, ms=4, capsize=3, color=colour,
                        label=label)
            top = max(top, float(np.max(a[ok] + np.nan_to_num(sd[ok]))))
    ax.axhline(sweep.alpha, color="k", ls="--", lw=0.8, label=sweep.alpha_label)
    _coarse_alpha(ax, sweep.x, alpha, sweep.coarse, top)
    if not np.isfinite(alpha).any():
        say_nothing(ax, f"no α: at no {sweep.loads} do both the simulation\nand the {sweep.theory} theory find a leak channel")
    ax.set_ylabel("α (1)")
    subtitle(ax, sweep.liquid_settings)
    finish_axes(ax)
    _legend(ax)
    return fig


def _coarse_alpha(ax: Axes, x: NDArray[np.float64], alpha: NDArray[np.float64], coarse: NDArray[np.bool_], top: float) -> None:
    """Draw the α of rows whose junction the grid resolves too coarsely hollow, clipped to 3 × ``top`` (the resolved
    values' range: their α can be absurdly large), with how many fall off scale; when no row is resolved there is no
    range to clip to, and every flagged α is drawn."""
    flagged = np.isfinite(alpha) & coarse
    if not flagged.any():
        return
    resolved = np.isfinite(alpha) & ~coarse
    limit = 3.0 * top if resolved.any() else float(np.max(alpha[flagged]))
    inside = flagged & (alpha <= limit)
    off = int(flagged.sum() - inside.sum())
    ax.plot(x[inside], alpha[inside], "o", mfc="none", color=color(0),
            label=f"λc < {JUNCTION_CELLS} cells: grid too coarse" + (f" ({off} more off scale)" if off else ""))
    ax.set_ylim(0.0, 1.1 * max(limit if off else 0.0, top, *alpha[inside]))


def _map_pick(maps: dict[int, NDArray[np.bool_]], per_realization: dict[str, Any]) -> int:
    """The load whose contact map is drawn: the highest at which realisation 0 percolates, else the middle one."""
    idx = sorted(maps)
    percolates = np.asarray(per_realization["percolates"], dtype=bool)
    perc_idx = [i for i in idx if percolates[0, i]]
    return perc_idx[-1] if perc_idx else idx[len(idx) // 2]


@laid_out
def _contact_map_figure(contact: NDArray[np.bool_], size: tuple[float, float], load: str, labels: tuple[str, str],
                        legend: str, edges: NDArray[np.float64] | None = None) -> Figure:
    """Realisation 0's contact map at one load: contact black, fluid that spans inlet to outlet blue, trapped fluid
    grey; x (flow) horizontal, ``size`` (x, y) in m; ``legend``: what the colours mean (the subtitle); ``edges``: x (m)
    of lines drawn red dashed (the Hertz band)."""
    fig, ax = new_figure(f"Contact map, realisation 0, {load}", figsize=(6.4, 5.6))
    img = np.where(contact, 0, np.where(spanning_mask(~contact), 2, 1))
    # img is indexed [x, y]; transpose so x runs horizontally (flow left to right)
    ax.imshow(img.T, cmap=ListedColormap(["#202020", "#d8d8d8", "#1f77b4"]), vmin=0, vmax=2,
              extent=(0, size[0] * 1e3, 0, size[1] * 1e3), origin="lower", interpolation="nearest")
    for xe in edges if edges is not None else ():
        ax.axvline(xe * 1e3, color="tab:red", ls="--", lw=1.0)
    ax.grid(False)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    subtitle(ax, legend)
    finish_axes(ax)
    return fig


@laid_out
def _band_pressure_figure(res: BandSimulationResult) -> Figure:
    """The contact pressure across the band per load: Hertz (analytic), the smooth cylinder simulated, and realisation
    0's rough contact averaged along the seal line."""
    fig, ax = new_figure("Contact pressure across the band, per load")
    xm = (res.x - res.size / 2.0) * 1e3
    handles: list[Artist] = []
    labels = []
    for i in range(res.loads.size):
        hertz = PressureProfile.semi_elliptic(res.hertz_contact_width[i], res.hertz_max_pressure[i])
        xs = np.linspace(0.0, res.hertz_contact_width[i], 201)
        handles += ax.plot((xs - res.hertz_contact_width[i] / 2.0) * 1e3, hertz.at(xs) / 1e6, "-", color=color(i), lw=1.2)
        labels.append(load_text(res.load_name, res.loads[i]))
        if i in res.smooth_line_pressure:
            sm = res.smooth_line_pressure[i]
            ax.plot(xm[sm > 0], sm[sm > 0] / 1e6, ".", color=color(i), ms=2.5)
        if i in res.line_pressure:
            ax.plot(xm, res.line_pressure[i] / 1e6, "-", color=color(i), lw=0.6, alpha=0.6)
    handles += [Line2D([], [], color="0.3", lw=1.2), Line2D([], [], color="0.3", ls="none", marker=".", ms=4),
                Line2D([], [], color="0.3", lw=0.6, alpha=0.6)]
    labels += ["Hertz (smooth, analytic)", "smooth cylinder, simulated", "rough, averaged along the seal line"]
    reach = 0.65 * float(np.nanmax(np.concatenate([res.hertz_contact_width, res.contact_width]))) * 1e3  # mm, past the edges
    ax.set_xlim(-reach, reach)
    ax.set_xlabel("x from the band's centre (mm)")
    ax.set_ylabel("contact pressure (MPa)")
    subtitle(ax, f"{res.grid}² grid, cells of {res.size / res.grid * 1e6:.3g} µm; the rough contact of realisation 0")
    finish_axes(ax)
    place_legend(ax, handles, labels)
    return fig
