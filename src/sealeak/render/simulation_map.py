"""``sealeak simulate`` on measured maps (the map route): the table it prints and its ``--json`` document."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..cases import Case
from ..cases.simulation_map import MapInfo, MapSimulationResult
from ..io.quantities import units_of
from .notes import worded
from .records import case_summary, json_document, json_value
from .simulation import coarse
from .text import fmt

__all__ = ["map_simulation_json", "map_simulation_table", "MAP_SIMULATION_UNITS"]

#: SI unit of every per-pressure key of the map route's ``--json`` (declared on the result's fields).
MAP_SIMULATION_UNITS = units_of(MapSimulationResult) | {"side": "m", "domain": "m", "h_rms": "m", "skewness": "1",
                                                        "kurtosis": "1", "spectrum_h_rms": "m"}
#: The per-map, per-pressure keys, in the order written.
_MAP_KEYS = ("relative_contact_area", "mean_gap", "percolates", "leak_rate", "leak_rate_critical_junction",
             "leak_rate_effective_medium", "alpha", "alpha_effective_medium", "junction_cells")


def _map_doc(info: MapInfo, res: MapSimulationResult, r: int) -> dict[str, Any]:
    """One map's JSON record: what it is, and its results per pressure."""
    rows = [{"squeeze_pressure": json_value(p)} | {k: json_value(getattr(res, k)[r, i]) for k in _MAP_KEYS}
            for i, p in enumerate(res.squeeze_pressure)]
    return {"label": info.label, "side": info.side, "points": info.points, "domain": info.domain,
            "periodic": info.periodic, "mirrored": info.mirrored, "h_rms": json_value(info.h_rms),
            "skewness": json_value(info.skewness), "kurtosis": json_value(info.kurtosis),
            "spectrum_h_rms": json_value(info.spectrum.h_rms),
            "percolation_threshold": json_value(res.percolation_threshold[r]), "notes": worded(info.notes),
            "results": rows}


def map_simulation_json(case: Case, res: MapSimulationResult) -> str:
    """The ``sealeak simulate --json`` document of the map route: each map, and α over the maps per pressure."""
    summary = [{"squeeze_pressure": json_value(p), "alpha_mean": json_value(res.alpha_mean[i]),
                "alpha_std": json_value(res.alpha_std[i]),
                "alpha_effective_medium_mean": json_value(res.alpha_effective_medium_mean[i]),
                "alpha_effective_medium_std": json_value(res.alpha_effective_medium_std[i]),
                "percolating_fraction": json_value(res.percolates[:, i].mean())}
               for i, p in enumerate(res.squeeze_pressure)]
    doc = {
        "units": MAP_SIMULATION_UNITS,
        "route": "maps",
        "maps": [_map_doc(info, res, r) for r, info in enumerate(res.maps)],
        "summary": summary,
        "settings": {"grid": res.grid, "maps": len(res.maps)},
        "alpha_note": "alpha = leak_rate / leak_rate_critical_junction and alpha_effective_medium = leak_rate / "
                      "leak_rate_effective_medium, each map against the theories of its own C(q) (alpha = 1)",
        "case": case_summary(case),
        "notes": worded(res.notes),
    }
    return json_document(doc)


def map_simulation_table(case: Case, res: MapSimulationResult) -> str:
    """The table ``sealeak simulate`` prints on maps: per map its heights' shape, leak rate and α against both theories."""
    lines = [f"{case.title}: numerically exact leak rate on {len(res.maps)} measured map(s), grid {res.grid}x{res.grid}",
             ""]
    too_coarse = coarse(res.junction_cells, 0)
    for r, m in enumerate(res.maps):
        how = "periodic" if m.periodic else "not periodic: levelled and mirrored"
        lines.append(f"{m.label}: square of {m.side * 1e6:.4g} µm ({m.points} points, {how}), h_rms "
                     f"{m.h_rms * 1e6:.4g} µm, skewness {m.skewness:.3g}, kurtosis {m.kurtosis:.3g} (3: Gaussian)")
        lines.append(f"{'P0 (kPa)':>9} {'A/A0':>7} {'ū (µm)':>9} {'perc':>5} {'Q (m³/s)':>11} {'Q cj α=1':>10} "
                     f"{'Q em':>10} {'α cj':>7} {'α em':>7}")
        for i, p in enumerate(res.squeeze_pressure):
            lines.append(f"{p / 1e3:9.4g} {res.relative_contact_area[r, i]:7.3f} {res.mean_gap[r, i] * 1e6:9.4g} "
                         f"{'yes' if res.percolates[r, i] else 'no':>5} {fmt(res.leak_rate[r, i], '11.3e')} "
                         f"{fmt(res.leak_rate_critical_junction[r, i], '10.3e')} "
                         f"{fmt(res.leak_rate_effective_medium[r, i], '10.3e')} {fmt(res.alpha[r, i], '7.3g')}"
                         f"{'*' if too_coarse[r, i] and np.isfinite(res.alpha[r, i]) else ' '}{fmt(res.alpha_effective_medium[r, i], '7.3g')}")
        if np.isfinite(res.percolation_threshold[r]):
            lines.append(f"the non-contact area stops percolating at A/A0 = {res.percolation_threshold[r]:.3f}")
        lines.append("")
    if len(res.maps) > 1:
        lines.append(f"over the {len(res.maps)} maps (mean ± standard deviation):")
        lines.append(f"{'P0 (kPa)':>9} {'α cj':>7} {'± sd':>7} {'α em':>7} {'± sd':>7}")
        for i, p in enumerate(res.squeeze_pressure):
            lines.append(f"{p / 1e3:9.4g} {fmt(res.alpha_mean[i], '7.3g')} {fmt(res.alpha_std[i], '7.2g')} "
                         f"{fmt(res.alpha_effective_medium_mean[i], '7.3g')} "
                         f"{fmt(res.alpha_effective_medium_std[i], '7.2g')}")
        lines.append("")
    lines.append("α cj = Q/Q cj(α = 1), α em = Q/Q em: each map against the theories of its own C(q)")
    lines += ["note: " + n for n in worded(res.notes)]
    return "\n".join(lines) + "\n"
