"""Renderings of the numerically exact route (``sealeak simulate``): table, JSON and figures."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure

from ..cases import Case, SimulationResult
from ..cases.simulation import JUNCTION_CELLS
from ..numerics import spanning_mask
from .figures import pressure_axis
from .records import case_summary, json_document, json_value
from .text import fmt

__all__ = ["simulation_json", "simulation_table", "simulation_figures", "SIMULATION_UNITS", "SIMULATION_FIGURE_NAMES"]


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


def simulation_json(case: Case, res: SimulationResult) -> str:
    """The ``sealeak simulate --json`` document: per-pressure results, threshold, settings, case."""
    keys = [k for k in SIMULATION_UNITS if k not in ("percolation_threshold", "percolation_threshold_std",
                                          "pressure_difference", "size", "junction_cells", "junction_resolved")]
    rows = [{k: json_value(getattr(res, k)[i]) for k in keys}
            | {"pressure_difference": res.pressure_difference,
               "junction_cells": json_value(res.junction_cells[i]) if res.junction_cells.size else None,
               "junction_resolved": _resolved(res, i)}
            for i in range(res.squeeze_pressure.size)]
    doc: dict[str, Any] = {
        "units": SIMULATION_UNITS,
        "results": rows,
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
    return json_document(doc)


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


def simulation_figures(case: Case, res: SimulationResult) -> dict[str, Figure]:
    """The figures of ``sealeak simulate --plots``: leak rate, α and a contact map, by file name."""
    figs = {}
    scale, unit = pressure_axis(res.squeeze_pressure)
    p = res.squeeze_pressure / scale
    coarse = np.array([_coarse(res, i) for i in range(p.size)], dtype=bool)
    fig, ax = _axes((6.4, 4.4))
    ok = res.leak_rate > 0
    std = np.nan_to_num(res.leak_rate_std[ok])
    lower = np.minimum(std, 0.9 * res.leak_rate[ok])  # keep the bar above zero on the log axis
    ax.errorbar(p[ok], res.leak_rate[ok], yerr=[lower, std], fmt="o", ms=4, capsize=3,
                label=f"numerical (BEM + Reynolds), {res.realizations} realisation(s), ± sd")
    q_cj = res.leak_rate_critical_junction
    good = np.where(coarse, np.nan, q_cj)
    ax.plot(p, good, "-", color="C1", label="critical junction, α = 1")
    if case.alpha != 1.0:
        ax.plot(p, case.alpha * good, "--", color="C2", label=f"critical junction, α = {case.alpha:g}")
    if coarse.any():  # the junction spans fewer than JUNCTION_CELLS cells: drawn faint, clipped to the data's range
        edge = np.where(coarse | np.roll(coarse, -1), q_cj, np.nan)
        ax.plot(p, edge, ":", color="C1", label=f"critical junction where λc < {JUNCTION_CELLS} cells (grid too coarse)")
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
                label="α = Q_num / Q_cj(α=1), ± sd")
    ax.axhline(case.alpha, color="k", ls="--", lw=0.8, label=f"case α = {case.alpha:g}")
    flagged = np.isfinite(res.alpha) & coarse
    if flagged.any():
        top = max(float(np.nanmax(res.alpha[ok] + np.nan_to_num(res.alpha_std[ok]))) if ok.any() else 0.0, case.alpha)
        limit = 3.0 * top
        inside = flagged & (res.alpha <= limit)
        off = int(flagged.sum() - inside.sum())
        ax.plot(p[inside], res.alpha[inside], "o", mfc="none", color="C0",
                label=f"λc < {JUNCTION_CELLS} cells: grid too coarse" + (f" ({off} more off scale)" if off else ""))
        ax.set_ylim(0.0, 1.1 * max(limit if off else 0.0, top, *res.alpha[inside]))
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("α (1)")
    ax.set_title("The factor α of the critical-junction theory, computed", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["simulate_alpha.png"] = fig

    fig, ax = _axes((5.6, 5.2))
    if res.contact_maps:
        idx = sorted(res.contact_maps)
        perc_idx = [i for i in idx if res.per_realization["percolates"][0, i]]
        pick = perc_idx[-1] if perc_idx else idx[len(idx) // 2]
        contact = res.contact_maps[pick]
        channel = spanning_mask(~contact)
        img = np.where(contact, 0, np.where(channel, 2, 1))
        cmap = ListedColormap(["#202020", "#d8d8d8", "#1f77b4"])
        # img is indexed [x, y]; transpose so x runs horizontally (flow left to right)
        ax.imshow(img.T, cmap=cmap, vmin=0, vmax=2, extent=(0, res.size * 1e3, 0, res.size * 1e3), origin="lower",
                  interpolation="nearest")
        ax.set_xlabel("x (mm), flow from inlet x = 0 to outlet →")
        ax.set_ylabel("y, periodic (mm)")
        ax.set_title(f"Contact map, realisation 0, P0 = {res.squeeze_pressure[pick] / scale:.3g} {unit}\n"
                     f"black: contact ({contact.mean():.1%}); blue: channels spanning inlet to outlet; "
                     f"grey: trapped fluid", fontsize=8)
    figs["contact_map.png"] = fig
    return figs


