"""The data of the interactive prediction plots (the web app draws them with Plotly.js), as JSON.

The same quantities as the prediction figures (:mod:`sealeak.render.figures`): Q against the squeeze
pressure P0 of both theories (when the case asks for the effective medium), C(q), the contact area
A(ζ)/A0 and the mean separation ū(ζ) against the magnification ζ at a few pressures, and the gap
distribution u·P(u). Every array is in SI units (Pa, m³/s, 1/m, m⁴, m; a gas's leak rate in mbar·l/s); NaN and infinities are
``null``. The curves come from :func:`sealeak.cases.prediction_curves`: no physics here.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..cases import CaseResult, prediction_curves
from ..cases.uncertainty import UncertaintyResult
from .life import as_assembled, volume_limit
from .plotstyle import merge_identical
from .records import json_value

__all__ = ["prediction_plot_data"]


def _list(a: Any) -> list[Any]:
    return [json_value(x) for x in np.asarray(a, dtype=float).ravel()]


def _bands(results: Sequence[CaseResult], unc: UncertaintyResult | None) -> list[dict[str, Any] | None]:
    """Per case, the 5th, 50th and 95th percentiles of its leak rate over the samples (m³/s, a gas's mbar·l/s; 0: sealed
    in at least that share of the samples), in the order of its records; None without uncertain inputs."""
    if unc is None or not unc.study.inputs:  # (max_leak_rate alone: the nominal prediction, no band to draw)
        return [None] * len(results)
    out: list[dict[str, Any] | None] = []
    per_key: dict[str, tuple[Any, Any]] = {}  # the percentiles of every row, and which are taken from samples outside
    for i, r in enumerate(results):
        key = "leak_rate_mbar_l_s" if r.case.gas is not None and "leak_rate_mbar_l_s" in unc.values else "leak_rate"
        if key not in per_key:
            per_key[key] = unc.percentiles(key), unc.outside(key)
        idx = [j for j, row in enumerate(unc.study.rows) if row.case == i]
        p, outside = (a[:, idx] for a in per_key[key])
        out.append({"p05": _list(p[0]), "p50": _list(p[1]), "p95": _list(p[2]), "samples": unc.samples,
                    "p05_outside": [bool(v) for v in outside[0]], "p50_outside": [bool(v) for v in outside[1]],
                    "p95_outside": [bool(v) for v in outside[2]]})
    return out


def prediction_plot_data(results: Sequence[CaseResult], uncertainty: UncertaintyResult | None = None) -> dict[str, Any]:
    """Series of the interactive plots of a run (one case, or the variants of a study), SI units.

    ``leak``: per case, P0 (Pa), Q of the critical junction and, when computed, of the effective
    medium (m³/s; for a gas case, ``gas`` true, the pV throughput Q_pV in mbar·l/s, the unit of leak tests:
    the records' ``leak_rate_mbar_l_s``), ``valid`` the verdict of each point (false: outside the theory; a sealed
    point has Q = NaN, null in JSON), ``band`` with uncertain inputs the percentiles ``p05``, ``p50``, ``p95`` of Q
    over the samples in the same unit (else null); ``limit``: ``conditions.max_leak_rate`` where it is compared with Q
    (m³/s) or a gas's Q_pV (Pa·m³/s), ``value`` in SI and ``text`` as written (else null: none given, or a helium
    equivalent); ``spectra``: per case q (1/m), C (m⁴); ``sets``: per representative pressure ζ,
    A(ζ)/A0, ζ of ū, ū(ζ) (m); ``gaps``: u (m) and u·P(u) of each set. Of a file of the seal over its life with several
    cases, ``spectra``, ``sets`` and ``gaps`` are those of the case as assembled (:func:`~sealeak.render.life.as_assembled`),
    as in its figures.
    """
    shown = as_assembled(results)  # the seal over its life: its case as assembled here, every case in the life plots
    curves = prediction_curves(list(shown))
    leak = []
    for r, band in zip(results, _bands(results, uncertainty)):
        recs = r.records()
        x = next((k for k in ("squeeze_pressure", "compression", "profile_scale") if recs and k in recs[0]), "squeeze_pressure")
        gas = r.case.gas is not None  # a gas: the pV throughput in the leak-test unit (docs/theory.md §11.6)
        key = "leak_rate_mbar_l_s" if gas else "leak_rate"
        leak.append({"label": r.case.label or r.case.title, "x": x, "x_unit": r.units.get(x, ""), "gas": gas,
                     "unit": "mbar·l/s" if gas else "m³/s",
                     "squeeze_pressure": _list([rec.get(x, np.nan) for rec in recs]),
                     "valid": [bool(rec.get("valid", True)) for rec in recs],  # the validity verdict of each point
                     "leak_rate": _list([rec.get(key, np.nan) for rec in recs]),
                     "leak_rate_effective_medium": (_list([rec.get(f"{key}_effective_medium", np.nan) for rec in recs])
                                                    if any(f"{key}_effective_medium" in rec for rec in recs) else None),
                     "valid_effective_medium": [bool(rec.get("valid_effective_medium", True)) for rec in recs],
                     "band": band})
    label = len(shown) > 1
    # variants with the same contact (a study of fluids) have the same spectrum and the same curves at a pressure: each
    # is sent once, named after all of them
    groups = merge_identical([(cs.squeeze_pressure, cs.zeta, cs.area, cs.mean_gap, cs.zeta_c, density)
                              for cs, density in zip(curves.sets, curves.gap_density, strict=True)],
                             [cs.case.label if label else "" for cs in curves.sets])
    sets = [{"label": (f"{', '.join(names)}: " if names else "") + f"P0 = {cs.squeeze_pressure / 1e3:.4g} kPa",
             "squeeze_pressure": cs.squeeze_pressure, "zeta": _list(cs.zeta), "area": _list(cs.area),
             "zeta_gap": _list(cs.zeta[:-1]), "mean_gap": _list(cs.mean_gap), "zeta_c": json_value(cs.zeta_c)}
            for cs, names in ((curves.sets[k], names) for k, names in groups)]
    densities = [_list(curves.gap_density[k]) for k, _ in groups]
    spectra = [{"label": ", ".join(names), "q": _list(curves.spectra[k][0]), "C": _list(curves.spectra[k][1])}
               for k, names in merge_identical(curves.spectra, [r.case.label or r.case.spectrum.label or r.case.title
                                                                for r in shown])]
    return {
        "leak": leak,
        "limit": {"value": limit[0], "text": limit[1]} if (limit := volume_limit(uncertainty)) else None,
        "spectra": spectra,
        "sets": sets,
        "gaps": {"u": _list(curves.gap), "density": densities, "labels": [s["label"] for s in sets]},
    }
