"""Renderings of the numerically exact route (``sealeak simulate``): table, JSON and figures."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from numpy.typing import NDArray

from ..cases import Case, SimulationResult
from ..cases.simulation import JUNCTION_CELLS, GasSimulation
from ..cases.simulation_band import HERTZ_TOL, BandSimulationResult
from ..numerics import spanning_mask
from ..physics.profile import PressureProfile
from .figures import pressure_axis
from .plotstyle import literal_text, scale_functions
from .records import case_summary, json_document, json_value
from .text import fmt

__all__ = ["simulation_json", "simulation_rows", "simulation_table", "simulation_figures", "SIMULATION_UNITS", "SIMULATION_FIGURE_NAMES",
           "SIMULATION_GAS_UNITS", "SIMULATION_GAS_FIGURE_NAMES",
           "band_simulation_json", "band_simulation_table", "band_simulation_figures", "BAND_SIMULATION_UNITS",
           "BAND_SIMULATION_FIGURE_NAMES", "BAND_SIMULATION_GAS_UNITS"]


def _axes(figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    fig = Figure(figsize=figsize, dpi=150)
    return fig, fig.add_subplot()


SIMULATION_UNITS = {
    "squeeze_pressure": "Pa", "relative_contact_area": "1", "relative_contact_area_std": "1",
    "relative_contact_area_theory": "1", "mean_gap": "m", "mean_gap_std": "m", "percolating_fraction": "1",
    "leak_rate": "m^3/s", "leak_rate_std": "m^3/s", "leak_rate_critical_junction": "m^3/s", "alpha": "1",
    "alpha_std": "1", "junction_cells": "1", "junction_resolved": "1",
    "percolation_threshold": "1", "percolation_threshold_std": "1", "pressure_difference": "Pa",
    "size": "m",
}
SIMULATION_FIGURE_NAMES = ("simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png")
#: The extra figure of a gas case.
SIMULATION_GAS_FIGURE_NAMES = ("simulate_gas_leak_rate.png",)
#: Units of the gas keys of a ``simulate --json`` row (a gas case); names as ``predict``'s gas keys.
SIMULATION_GAS_UNITS = {
    "knudsen_number": "1", "flow_regime": "", "leak_rate_pv": "Pa*m^3/s", "leak_rate_pv_std": "Pa*m^3/s",
    "leak_rate_mbar_l_s": "mbar*l/s", "leak_rate_mass": "kg/s", "leak_rate_mass_std": "kg/s", "leak_rate_molar": "mol/s",
    "slip_gain": "1", "leak_rate_pv_critical_junction": "Pa*m^3/s", "alpha_gas": "1", "alpha_gas_std": "1",
    "gas_iterations": "1",
}
_GAS_ATTR = {"knudsen_number": "knudsen_critical_junction", "leak_rate_pv": "throughput", "leak_rate_pv_std": "throughput_std",
             "leak_rate_mass": "mass_flow", "leak_rate_mass_std": "mass_flow_std", "leak_rate_molar": "molar_flow",
             "slip_gain": "slip_gain", "leak_rate_pv_critical_junction": "throughput_critical_junction", "alpha_gas": "alpha",
             "alpha_gas_std": "alpha_std", "gas_iterations": "iterations"}


def simulation_json(case: Case, res: SimulationResult) -> str:
    """The ``sealeak simulate --json`` document: per-pressure results, threshold, settings, case."""
    doc: dict[str, Any] = {
        "units": SIMULATION_UNITS,
        "results": simulation_rows(res),
        "percolation_threshold": json_value(res.percolation_threshold),
        "percolation_threshold_std": json_value(res.percolation_threshold_std),
        "settings": {"grid": res.grid, "realizations": res.realizations, "seed": res.seed, "size": res.size,
                     "spectrum_cut_wavevector": res.q_cut, "spectrum": res.spectrum_note},
        "leak_rate_critical_junction_note": "critical-junction prediction with alpha = 1 for the same spectrum; "
                                            "alpha = leak_rate / leak_rate_critical_junction",
        "spread_note": "*_std are standard deviations over realisations (ddof = 1; alpha_std over the percolating "
                       "ones), not standard errors: the standard error of a mean is std/sqrt(realizations); "
                       "null with fewer than two values",
        "case": case_summary(case),
        "notes": list(res.notes),
    }
    if res.gas is not None:
        _gas_json(doc, res)
    return json_document(doc)


def simulation_rows(res: SimulationResult) -> list[dict[str, Any]]:
    """The per-pressure records of ``sealeak simulate --json`` (units :data:`SIMULATION_UNITS`), liquid keys only."""
    keys = [k for k in SIMULATION_UNITS if k not in ("percolation_threshold", "percolation_threshold_std",
                                          "pressure_difference", "size", "junction_cells", "junction_resolved")]
    return [{k: json_value(getattr(res, k)[i]) for k in keys}
            | {"pressure_difference": res.pressure_difference,
               "junction_cells": json_value(res.junction_cells[i]) if res.junction_cells.size else None,
               "junction_resolved": _resolved(res, i)}
            for i in range(res.squeeze_pressure.size)]


def _add_gas_json(doc: dict[str, Any], g: GasSimulation, units: dict[str, str], attrs: dict[str, str]) -> None:
    """The gas keys of a ``simulate --json`` document (uniform or O-ring): per row the gas leak and α_gas, and the gas."""
    doc["units"] = doc["units"] | units
    for i, row in enumerate(doc["results"]):
        row |= {k: json_value(getattr(g, a)[i]) for k, a in attrs.items()}
        row |= {"flow_regime": g.regime_critical_junction[i] or None,
                "leak_rate_mbar_l_s": json_value(g.throughput[i] / 0.1)}
    doc["gas"] = {"name": g.gas_name, "temperature": g.temperature, "upstream_pressure": g.upstream_pressure,
                  "downstream_pressure": g.downstream_pressure, "rarefaction": g.rarefaction,
                  "units": {"temperature": "K", "upstream_pressure": "Pa", "downstream_pressure": "Pa"}}


def _gas_json(doc: dict[str, Any], res: SimulationResult) -> None:
    """Add a gas case's keys to the ``simulate --json`` document: per row the gas leak, its α, and the gas settings."""
    assert res.gas is not None
    _add_gas_json(doc, res.gas, SIMULATION_GAS_UNITS, _GAS_ATTR)
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
                     f"{fmt(g.throughput[i] / 0.1, '12.3e')} {fmt(g.mass_flow[i], '10.3e')} {fmt(g.slip_gain[i], '9.4g')} "
                     f"{fmt(g.throughput_critical_junction[i], f'{theory_width}.3e')} {fmt(g.alpha[i], '7.3g')}{star} "
                     f"{fmt(g.alpha_std[i], '7.2g')} {g.iterations[i]:4d}")
    return lines


def _gas_lines(res: SimulationResult) -> list[str]:
    """The gas table of ``sealeak simulate`` and what its columns mean."""
    g = res.gas
    assert g is not None
    lines = ["", f"gas leak of {g.gas_name}, {g.upstream_pressure / 1e3:.4g} kPa → {g.downstream_pressure / 1e3:.4g} kPa "
                 f"(absolute), {g.temperature - 273.15:.4g} °C, rarefaction {g.rarefaction}:",
             *_gas_rows(g, ("P0 (kPa)", 9), [f"{p / 1e3:9.4g}" for p in res.squeeze_pressure], ("Q_pV cj α=1", 12),
                        [_coarse(res, i) for i in range(res.squeeze_pressure.size)]),
             ""]
    lines += [
              "Q_pV sim: isothermal gas flow through the same gap fields, ∇·(g³ f(Kn) ∇p²) = 0, counted at the gas "
              "temperature; ṁ = Q_pV/(R_s T); slip gain: Q_pV over the same flow without rarefaction",
              f"Q_pV cj α=1: the critical-junction gas leak (gap u_c, the same rarefaction; as predict); α_gas = Q_pV sim / "
              f"Q_pV cj; Kn = λ/u_c at the mean pressure {0.5 * (g.upstream_pressure + g.downstream_pressure) / 1e3:.4g} kPa; "
              "iter: fixed-point iterations (most over the realisations; 0 without rarefaction)",
              "the table above (Q in m³/s, α) is the incompressible formula with the gas's viscosity, for comparison"]
    return lines


def simulation_table(case: Case, res: SimulationResult) -> str:
    """The table ``sealeak simulate`` prints: numerical against critical-junction leak rate and α."""
    lines = [f"{case.title}: numerically exact leak rate",
             f"grid {res.grid}x{res.grid} on a square of side {res.size * 1e3:.4g} mm, {res.realizations} "
             f"realisation(s), seed {res.seed}; {res.spectrum_note}", ""]
    lines.append(f"{'P0 (kPa)':>9} {'A/A0 sim':>9} {'A/A0 th':>8} {'ū (µm)':>9} {'perc':>5} "
                 f"{'Q sim (m³/s)':>13} {'± sd':>9} {'Q cj α=1':>10} {'α':>7} {'± sd':>7}")

    for i in range(res.squeeze_pressure.size):
        lines.append(f"{res.squeeze_pressure[i] / 1e3:9.4g} {res.relative_contact_area[i]:9.3f} "
                     f"{res.relative_contact_area_theory[i]:8.3f} {res.mean_gap[i] * 1e6:9.4g} "
                     f"{res.percolating_fraction[i]:5.2f} {fmt(res.leak_rate[i], '13.3e')} {fmt(res.leak_rate_std[i], '9.2e')} "
                     f"{fmt(res.leak_rate_critical_junction[i], '10.3e')} {fmt(res.alpha[i], '7.3g')}"
                     f"{'*' if _coarse(res, i) and np.isfinite(res.alpha[i]) else ' '}{fmt(res.alpha_std[i], '7.2g')}")
    if res.gas is not None:
        lines += _gas_lines(res)
    lines.append("")
    lines.append(_spread_legend(res.realizations))
    if np.isfinite(res.percolation_threshold):
        found = int(np.isfinite(res.per_realization.get("percolation_threshold", np.ones(res.realizations))).sum())
        spread = (f"mean of {found} realisations, sd {res.percolation_threshold_std:.2g}"
                  if np.isfinite(res.percolation_threshold_std) else "one realisation")
        lines.append(f"the non-contact area stops percolating at A/A0 = {res.percolation_threshold:.3f} ({spread}; "
                     f"critical-junction theory assumes 1 - p_c = {1 - case.percolation_threshold:.3f})")
    for n in res.notes:
        lines.append("note: " + n)
    return "\n".join(lines) + "\n"


def _coarse(res: SimulationResult, i: int) -> bool:
    """Whether the theory's junction at pressure ``i`` spans fewer grid cells than α needs (see the notes)."""
    cells = res.junction_cells
    return bool(cells.size and np.isfinite(cells[i]) and cells[i] < JUNCTION_CELLS)


def _resolved(res: SimulationResult, i: int) -> bool | None:
    """JSON ``junction_resolved``: λc spans at least JUNCTION_CELLS cells; None where the theory has no junction."""
    cells = res.junction_cells
    return None if not (cells.size and np.isfinite(cells[i])) else bool(cells[i] >= JUNCTION_CELLS)


def _spread_legend(realizations: int) -> str:
    """What the ± columns of the simulate table are (standard deviations over realisations, not standard errors)."""
    if realizations < 2:
        return "± sd: standard deviation over realisations; none with one realisation (—)"
    return (f"± sd: standard deviation over the {realizations} realisations (for α: over the percolating ones), "
            "the spread from one random surface to another; "
            f"the standard error of a mean is sd/√{realizations}")


@literal_text
def simulation_figures(case: Case, res: SimulationResult) -> dict[str, Figure]:
    """The figures of ``sealeak simulate --plots``: leak rate, α and a contact map, by file name."""
    figs = {}
    scale, unit = pressure_axis(res.squeeze_pressure)
    p = res.squeeze_pressure / scale
    coarse = np.array([_coarse(res, i) for i in range(p.size)], dtype=bool)
    fig, ax = _axes((6.4, 4.4))
    ok = _numerical_points(ax, p, res.leak_rate, res.leak_rate_std, f"numerical (BEM + Reynolds), {res.realizations} realisation(s), ± sd")
    good = _theory_line(ax, p, res.leak_rate_critical_junction, coarse, "critical junction", case.alpha)
    shown = np.concatenate([res.leak_rate[ok], good[np.isfinite(good) & (good > 0)]])
    if shown.size:
        ax.set_ylim(shown.min() / 3.0, shown.max() * 3.0)
    ax.set_yscale("log")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.set_title(f"Numerical against critical-junction leak rate\n{res.grid}² grid, ΔP = "
                 f"{res.pressure_difference / 1e3:.3g} kPa, Ly/Lx = {case.seal.aspect_ratio:.3g}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["simulate_leak_rate.png"] = fig

    fig, ax = _axes((6.4, 4.4))
    ok = np.isfinite(res.alpha) & ~coarse
    ax.errorbar(p[ok], res.alpha[ok], yerr=np.nan_to_num(res.alpha_std[ok]), fmt="o-", ms=4, capsize=3,
                label="α = Q_num / Q_cj(α=1), ± sd" if res.gas is None
                else "α = Q_num / Q_cj(α=1), incompressible formula (gas viscosity), ± sd")
    if res.gas is not None:
        g = res.gas
        good = np.isfinite(g.alpha) & ~coarse
        ax.errorbar(p[good], g.alpha[good], yerr=np.nan_to_num(g.alpha_std[good]), fmt="s--", ms=4, capsize=3, color="C3",
                    label=f"α_gas = Q_pV / Q_pV,cj(α=1), {g.gas_name} {g.upstream_pressure / 1e3:.4g} → "
                          f"{g.downstream_pressure / 1e3:.4g} kPa, ± sd")
    ax.axhline(case.alpha, color="k", ls="--", lw=0.8, label=f"case α = {case.alpha:g}")
    top = max(float(np.nanmax(res.alpha[ok] + np.nan_to_num(res.alpha_std[ok]))) if ok.any() else 0.0, case.alpha)
    if res.gas is not None and (np.isfinite(res.gas.alpha) & ~coarse).any():
        good = np.isfinite(res.gas.alpha) & ~coarse
        top = max(top, float(np.nanmax(res.gas.alpha[good] + np.nan_to_num(res.gas.alpha_std[good]))))
    _coarse_alpha(ax, p, res.alpha, coarse, top)
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("α (1)")
    ax.set_title("The factor α of the critical-junction theory, computed", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["simulate_alpha.png"] = fig

    fig, ax = _axes((5.6, 5.2))
    if res.contact_maps:
        pick, contact = _contact_map(ax, res.contact_maps, np.asarray(res.per_realization["percolates"], dtype=bool), res.size,
                                     res.size)
        ax.set_xlabel("x (mm), flow from inlet x = 0 to outlet →")
        ax.set_ylabel("y, periodic (mm)")
        ax.set_title(f"Contact map, realisation 0, P0 = {res.squeeze_pressure[pick] / scale:.3g} {unit}\n"
                     f"black: contact ({contact.mean():.1%}); blue: channels spanning inlet to outlet; "
                     f"grey: trapped fluid", fontsize=8)
    figs["contact_map.png"] = fig
    if res.gas is not None:
        figs["simulate_gas_leak_rate.png"] = _gas_figure(case, res, coarse)
    return figs


def _coarse_alpha(ax: Any, x: NDArray[np.float64], alpha: NDArray[np.float64], coarse: NDArray[np.bool_], top: float) -> None:
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
    ax.plot(x[inside], alpha[inside], "o", mfc="none", color="C0",
            label=f"λc < {JUNCTION_CELLS} cells: grid too coarse" + (f" ({off} more off scale)" if off else ""))
    ax.set_ylim(0.0, 1.1 * max(limit if off else 0.0, top, *alpha[inside]))


def _contact_map(ax: Any, maps: dict[int, NDArray[np.bool_]], percolates: NDArray[np.bool_], width: float,
                 height: float) -> tuple[int, NDArray[np.bool_]]:
    """Draw realisation 0's contact map at the highest percolating load (else the middle one): contact black,
    channels spanning inlet to outlet blue, trapped fluid grey; x (flow) horizontal, sizes in m. Returns (load, map)."""
    idx = sorted(maps)
    perc_idx = [i for i in idx if percolates[0, i]]
    pick = perc_idx[-1] if perc_idx else idx[len(idx) // 2]
    contact = maps[pick]
    img = np.where(contact, 0, np.where(spanning_mask(~contact), 2, 1))
    # img is indexed [x, y]; transpose so x runs horizontally (flow left to right)
    ax.imshow(img.T, cmap=ListedColormap(["#202020", "#d8d8d8", "#1f77b4"]), vmin=0, vmax=2,
              extent=(0, width * 1e3, 0, height * 1e3), origin="lower", interpolation="nearest")
    return pick, contact


def _numerical_points(ax: Any, x: NDArray[np.float64], q: NDArray[np.float64], q_std: NDArray[np.float64],
                      label: str) -> NDArray[np.bool_]:
    """The simulated leak rates > 0 with their ± sd bars (the lower bar kept above zero for the log axis), and the
    loads where no realisation leaks (no channel percolates: Q = 0, off a log axis) as × at the bottom edge of the
    axes, with a legend entry; returns which leak rates were drawn as points."""
    ok = q > 0
    std = np.nan_to_num(q_std[ok])
    bars = ax.errorbar(x[ok], q[ok], yerr=[np.minimum(std, 0.9 * q[ok]), std], fmt="o", ms=4, capsize=3, label=label)
    sealed = q == 0
    if sealed.any():  # y in axes units: on the bottom edge whatever the leak-rate range
        ax.plot(x[sealed], np.full(int(sealed.sum()), 0.0), "x", ms=6, mew=1.5, color=bars[0].get_color(),
                transform=ax.get_xaxis_transform(), clip_on=False,
                label="numerical: no leak channel in any realisation (Q = 0), × at the bottom")
    return np.asarray(ok, dtype=bool)


def _theory_line(ax: Any, x: NDArray[np.float64], q: NDArray[np.float64], coarse: NDArray[np.bool_], name: str,
                 alpha: float = 1.0, label: str | None = None, skip_empty: bool = False) -> NDArray[np.float64]:
    """The theory's leak rate with α = 1 (and the case's α when it differs) where the grid resolves the junction, and
    dotted where λc spans fewer than JUNCTION_CELLS cells (joined to its resolved neighbour); returns the resolved part."""
    good = np.where(coarse, np.nan, q)
    if not skip_empty or np.isfinite(good).any():
        ax.plot(x, good, "-", color="C1", label=label or f"{name}, α = 1")
    if alpha != 1.0:
        ax.plot(x, alpha * good, "--", color="C2", label=f"{name}, α = {alpha:g}")
    if coarse.any():
        edge = np.where(coarse | np.roll(coarse, -1), q, np.nan)
        ax.plot(x, edge, ":", color="C1", label=f"{name} where λc < {JUNCTION_CELLS} cells (grid too coarse)")
    return np.asarray(good, dtype=float)


def _gas_figure(case: Case, res: SimulationResult, coarse: NDArray[np.bool_]) -> Figure:
    """The gas case's leak rate: the simulated pV throughput against the critical-junction gas leak (α = 1, and the case's α)."""
    g = res.gas
    assert g is not None
    scale, unit = pressure_axis(res.squeeze_pressure)
    p = res.squeeze_pressure / scale
    fig, ax = _axes((6.4, 4.4))
    ok = _numerical_points(ax, p, g.throughput, g.throughput_std,
                           f"numerical (BEM + gas flow in p²), {res.realizations} realisation(s), ± sd")
    good = _theory_line(ax, p, g.throughput_critical_junction, coarse, "critical junction", case.alpha)
    shown = np.concatenate([g.throughput[ok], good[np.isfinite(good) & (good > 0)]])
    if shown.size:
        ax.set_ylim(shown.min() / 3.0, shown.max() * 3.0)
        ax.set_yscale("log")
        ax.secondary_yaxis("right", functions=scale_functions(10.0)).set_ylabel("Q (mbar·l/s)")
    else:
        ax.text(0.5, 0.5, "no leak channel at any squeeze pressure", transform=ax.transAxes, ha="center", va="center")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("pV throughput Q_pV (Pa·m³/s)")
    ax.set_title(f"Gas leak: {g.gas_name}, {g.upstream_pressure / 1e3:.4g} → {g.downstream_pressure / 1e3:.4g} kPa (absolute), "
                 f"{g.temperature - 273.15:.4g} °C, rarefaction {g.rarefaction}\n{res.grid}² grid, "
                 f"Ly/Lx = {case.seal.aspect_ratio:.3g}; Q_pV counted at the gas temperature", fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return fig


# ---------------------------------------------------------------- the O-ring (band) simulation
BAND_SIMULATION_UNITS = {
    "compression": "1", "profile_scale": "1", "force_per_length": "N/m", "model_contact_width": "m",
    "model_max_pressure": "Pa", "hertz_contact_width": "m", "hertz_max_pressure": "Pa", "smooth_contact_width": "m",
    "smooth_max_pressure": "Pa", "smooth_width_error": "1", "smooth_pressure_error": "1", "contact_width": "m",
    "contact_width_std": "m", "relative_contact_area": "1", "relative_contact_area_std": "1",
    "percolating_fraction": "1", "leak_rate": "m^3/s", "leak_rate_std": "m^3/s",
    "leak_rate_series_resistance": "m^3/s", "alpha": "1", "alpha_std": "1", "junction_cells": "1",
    "junction_resolved": "1", "pressure_difference": "Pa", "size": "m", "period": "m", "seal_length": "m",
    "radius": "m", "spectrum_cut_wavevector": "1/m", "spectrum_low_wavevector": "1/m",
}
BAND_SIMULATION_FIGURE_NAMES = ("simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png",
                                "simulate_band_pressure.png")
_BAND_ROW_KEYS = ("force_per_length", "model_contact_width", "model_max_pressure", "hertz_contact_width",
                  "hertz_max_pressure", "smooth_contact_width", "smooth_max_pressure", "smooth_width_error",
                  "smooth_pressure_error", "contact_width", "contact_width_std", "relative_contact_area",
                  "relative_contact_area_std", "percolating_fraction", "leak_rate", "leak_rate_std",
                  "leak_rate_series_resistance", "alpha", "alpha_std", "junction_cells")


def _band_coarse(res: BandSimulationResult, i: int) -> bool:
    """Whether the theory's junction at load ``i`` spans fewer grid cells than α needs (see the notes)."""
    c = res.junction_cells[i]
    return bool(np.isfinite(c) and c < JUNCTION_CELLS)


def _load_label(res: BandSimulationResult) -> tuple[str, float]:
    """Column label and the factor that shows the loads (compression in %, a scale factor as is)."""
    return ("compression (%)", 100.0) if res.load_name == "compression" else (res.load_name.replace("_", " "), 1.0)


def band_simulation_json(case: Case, res: BandSimulationResult) -> str:
    """The ``sealeak simulate --json`` document of an O-ring: per compression, the smooth check, settings, case."""
    units = {k: v for k, v in BAND_SIMULATION_UNITS.items()
             if k not in ("compression", "profile_scale") or k == res.load_name}
    rows = [{res.load_name: json_value(res.loads[i])}
            | {k: json_value(getattr(res, k)[i]) for k in _BAND_ROW_KEYS}
            | {"junction_resolved": None if not np.isfinite(res.junction_cells[i]) else bool(not _band_coarse(res, i)),
               "pressure_difference": res.pressure_difference}
            for i in range(res.loads.size)]
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
        "leak_rate_series_resistance_note": "series-resistance prediction of the critical-junction theory with alpha = 1 "
                                            "for the same spectrum and the Hertz profile of the same force; "
                                            "alpha = leak_rate / leak_rate_series_resistance",
        "spread_note": "*_std are standard deviations over realisations (ddof = 1; alpha_std over the percolating "
                       "ones), not standard errors; null with fewer than two values",
        "case": case_summary(case),
        "notes": list(res.notes),
    }
    if res.gas is not None:
        _band_gas_json(doc, res)
    return json_document(doc)


#: Units of the gas keys of an O-ring's ``simulate --json`` row: the uniform route's names, the theory's column
#: named as the band's liquid one (``leak_rate_pv_series_resistance``).
BAND_SIMULATION_GAS_UNITS = {("leak_rate_pv_series_resistance" if k == "leak_rate_pv_critical_junction" else k): v
                             for k, v in SIMULATION_GAS_UNITS.items()}
_BAND_GAS_ATTR = {("leak_rate_pv_series_resistance" if k == "leak_rate_pv_critical_junction" else k): a
                  for k, a in _GAS_ATTR.items()}


def _band_gas_json(doc: dict[str, Any], res: BandSimulationResult) -> None:
    """Add a gas O-ring's keys to the ``simulate --json`` document: per row the gas leak across the band, α_gas, the gas."""
    assert res.gas is not None
    _add_gas_json(doc, res.gas, BAND_SIMULATION_GAS_UNITS, _BAND_GAS_ATTR)
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
    lines = ["", f"Gas leak across the band: {g.gas_name}, {g.upstream_pressure / 1e3:.4g} kPa → "
                 f"{g.downstream_pressure / 1e3:.4g} kPa (absolute), {g.temperature - 273.15:.4g} °C, rarefaction {g.rarefaction}",
             *_gas_rows(g, (label, 16), [f"{x * factor:16.4g}" for x in res.loads], ("Q_pV series α=1", 15),
                        [_band_coarse(res, i) for i in range(res.loads.size)]),
             ""]
    lines += [
              "Q_pV sim: isothermal gas flow across the band through the same gap fields, ∇·(g³ f(Kn) ∇p²) = 0, P_a at "
              "the inlet edge, P_b at the outlet edge, scaled to the seal line as Q sim, counted at the gas temperature; "
              "ṁ = Q_pV/(R_s T); slip gain: Q_pV over the same flow without rarefaction",
              f"Q_pV series α=1: the series-resistance gas leak (K = Q series/ΔP, gap u_c at the peak contact pressure, the "
              f"same rarefaction; as predict); α_gas = Q_pV sim / Q_pV series; Kn = λ/u_c at the mean pressure "
              f"{0.5 * (g.upstream_pressure + g.downstream_pressure) / 1e3:.4g} kPa; "
              "iter: fixed-point iterations (most over the realisations; 0 without rarefaction)",
              "the table above (Q in m³/s, α) is the incompressible formula with the gas's viscosity, for comparison"]
    return lines


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
    for i in range(res.loads.size):
        star = "*" if _band_coarse(res, i) and np.isfinite(res.alpha[i]) else " "
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
    for n in res.notes:
        lines.append("note: " + n)
    return "\n".join(lines) + "\n"


@literal_text
def band_simulation_figures(case: Case, res: BandSimulationResult) -> dict[str, Figure]:
    """The figures of ``sealeak simulate --plots`` for an O-ring: leak rate, α, a contact map, the pressure across the band."""
    figs: dict[str, Figure] = {}
    label, factor = _load_label(res)
    loads = res.loads * factor
    coarse = np.array([_band_coarse(res, i) for i in range(loads.size)], dtype=bool)

    fig, ax = _axes((6.4, 4.4))
    ok = _numerical_points(ax, loads, res.leak_rate, res.leak_rate_std,
                           f"numerical (cylinder on rough surface + Reynolds), {res.realizations} realisation(s), ± sd")
    q_sr = res.leak_rate_series_resistance
    good = _theory_line(ax, loads, q_sr, coarse, "series resistance", label="series resistance, critical junction, α = 1")
    blocked = ~ok
    shown = np.concatenate([res.leak_rate[ok], good[np.isfinite(good) & (good > 0)]])  # the flagged theory may leave the axis
    if shown.size:
        ax.set_ylim(shown.min() / 3.0, shown.max() * 3.0)
        if blocked.any():  # no leak in any realisation: a hollow triangle at the bottom of the axis
            ax.plot(loads[blocked], np.full(int(blocked.sum()), shown.min() / 2.0), "v", mfc="none", color="C0",
                    label="numerical: no channel crosses the band (Q = 0)")
        ax.set_yscale("log")
    else:
        ax.text(0.5, 0.5, "no channel crosses the band at any load", transform=ax.transAxes, ha="center", va="center")
    ax.set_xlabel(label)
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.set_title(f"O-ring: numerical against series-resistance leak rate\n{res.grid}² grid, ΔP = "
                 f"{res.pressure_difference / 1e3:.3g} kPa, seal line {res.seal_length * 1e3:.3g} mm", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    figs["simulate_leak_rate.png"] = fig

    fig, ax = _axes((6.4, 4.4))
    ok = np.isfinite(res.alpha) & ~coarse
    ax.errorbar(loads[ok], res.alpha[ok], yerr=np.nan_to_num(res.alpha_std[ok]), fmt="o-", ms=4, capsize=3,
                label="α = Q_num / Q_series(α=1), ± sd")
    ax.axhline(1.0, color="k", ls="--", lw=0.8, label="α = 1")
    _coarse_alpha(ax, loads, res.alpha, coarse,
                  max(float(np.nanmax(res.alpha[ok] + np.nan_to_num(res.alpha_std[ok]))) if ok.any() else 0.0, 1.0))
    if not np.isfinite(res.alpha).any():
        ax.text(0.5, 0.5, "no α: the band holds no channel\n(numerically or in the theory)", transform=ax.transAxes,
                ha="center", va="center")
    ax.set_xlabel(label)
    ax.set_ylabel("α (1)")
    ax.set_title("The α of this O-ring: numerically exact over series-resistance leak rate", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["simulate_alpha.png"] = fig

    fig, ax = _axes((6.4, 5.4))
    if res.contact_maps:
        pick, contact = _contact_map(ax, res.contact_maps, np.asarray(res.per_realization["percolates"], dtype=bool), res.size,
                                     res.period)
        half = res.hertz_contact_width[pick] / 2.0
        for xe in (res.size / 2.0 - half, res.size / 2.0 + half):
            ax.axvline(xe * 1e3, color="C3", ls="--", lw=1.0)
        ax.set_xlabel("x across the band (mm), flow from x = 0 to the outlet →")
        ax.set_ylabel("y along the seal line, periodic (mm)")
        ax.set_title(f"Contact map, realisation 0, {label.split(' (')[0]} {loads[pick]:.3g}"
                     f"{' %' if res.load_name == 'compression' else ''}\n"
                     f"black: contact; blue: channels crossing the band; grey: trapped or dead-end fluid; "
                     f"red dashes: Hertz band", fontsize=8)
    figs["contact_map.png"] = fig

    fig, ax = _axes((6.4, 4.4))
    x = res.x
    xm = (x - res.size / 2.0) * 1e3
    unit = " %" if res.load_name == "compression" else ""
    for i in range(res.loads.size):
        color = f"C{i % 10}"
        hertz = PressureProfile.semi_elliptic(res.hertz_contact_width[i], res.hertz_max_pressure[i])
        xs = np.linspace(0.0, res.hertz_contact_width[i], 201)
        ax.plot((xs - res.hertz_contact_width[i] / 2.0) * 1e3, hertz.at(xs) / 1e6, "-", color=color, lw=1.2,
                label=f"{loads[i]:.3g}{unit}")
        if i in res.smooth_line_pressure:
            sm = res.smooth_line_pressure[i]
            ax.plot(xm[sm > 0], sm[sm > 0] / 1e6, ".", color=color, ms=2.5)
        if i in res.line_pressure:
            ax.plot(xm, res.line_pressure[i] / 1e6, "-", color=color, lw=0.6, alpha=0.6)
    first = ax.legend(fontsize=7, title=label.split(" (")[0], title_fontsize=7, loc="upper left")
    ax.add_artist(first)
    styles = [Line2D([], [], color="0.3", lw=1.2, label="Hertz (smooth, analytic)"),
              Line2D([], [], color="0.3", ls="none", marker=".", ms=4, label="smooth cylinder, simulated"),
              Line2D([], [], color="0.3", lw=0.6, alpha=0.6, label="rough, averaged along the seal line")]
    ax.legend(handles=styles, fontsize=7, loc="upper right")
    reach = 0.65 * float(np.nanmax(np.concatenate([res.hertz_contact_width, res.contact_width]))) * 1e3  # mm, past the edges
    ax.set_xlim(-reach, reach)
    ax.set_xlabel("x from the band's centre (mm)")
    ax.set_ylabel("contact pressure (MPa)")
    ax.set_title("Pressure across the band: Hertz, the smooth cylinder simulated, and the rough contact\n"
                 "averaged along the seal line (realisation 0)", fontsize=9)
    ax.grid(alpha=0.3)
    figs["simulate_band_pressure.png"] = fig
    if res.gas is not None:
        figs["simulate_gas_leak_rate.png"] = _band_gas_figure(res, coarse)
    return figs


def _band_gas_figure(res: BandSimulationResult, coarse: NDArray[np.bool_]) -> Figure:
    """A gas O-ring's leak rate: the simulated pV throughput across the band against the series-resistance gas leak (α = 1)."""
    g = res.gas
    assert g is not None
    label, factor = _load_label(res)
    loads = res.loads * factor
    fig, ax = _axes((6.4, 4.4))
    ok = _numerical_points(ax, loads, g.throughput, g.throughput_std,
                           f"numerical (cylinder on rough surface + gas flow in p²), {res.realizations} realisation(s), ± sd")
    q_sr = g.throughput_critical_junction
    _theory_line(ax, loads, q_sr, coarse, "series resistance", label="series resistance, critical junction, α = 1",
                 skip_empty=True)
    # the flagged theory stays on the axis: its distance from the points is what the figure shows
    shown = np.concatenate([g.throughput[ok], q_sr[np.isfinite(q_sr) & (q_sr > 0)]])
    if shown.size:
        ax.set_ylim(shown.min() / 3.0, shown.max() * 3.0)
        if (~ok).any():  # no leak in any realisation: a hollow triangle at the bottom of the axis
            ax.plot(loads[~ok], np.full(int((~ok).sum()), shown.min() / 2.0), "v", mfc="none", color="C0",
                    label="numerical: no channel crosses the band (Q = 0)")
        ax.set_yscale("log")
        ax.secondary_yaxis("right", functions=scale_functions(10.0)).set_ylabel("Q (mbar·l/s)")
        ax.legend(fontsize=7)
    else:  # nothing to draw: the loads on the axis, the reason in the middle, no empty legend
        pad = 0.05 * max(float(np.ptp(loads)), float(np.abs(loads).max()), 1e-12)
        ax.set_xlim(float(loads.min()) - pad, float(loads.max()) + pad)
        ax.set_yticks([])
        ax.text(0.5, 0.5, "no channel crosses the band at any load\n(numerically or in the series-resistance theory)",
                transform=ax.transAxes, ha="center", va="center")
    ax.set_xlabel(label)
    ax.set_ylabel("pV throughput Q_pV (Pa·m³/s)")
    ax.set_title(f"O-ring gas leak: {g.gas_name}, {g.upstream_pressure / 1e3:.4g} → {g.downstream_pressure / 1e3:.4g} kPa "
                 f"(absolute), {g.temperature - 273.15:.4g} °C, rarefaction {g.rarefaction}\n{res.grid}² grid, seal line "
                 f"{res.seal_length * 1e3:.3g} mm; Q_pV counted at the gas temperature", fontsize=8)
    ax.grid(alpha=0.3)
    return fig
