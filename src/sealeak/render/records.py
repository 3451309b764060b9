"""JSON and CSV renderings of case results (an edge module: SI in, SI out, units declared).

Every document declares the SI unit of each field (``units``); NaN and infinities become ``null``
in JSON and empty cells in CSV.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._version import __version__
from ..cases import Case, CaseResult
from ..cases.sobol import SobolIndices
from ..cases.uncertainty import UncertaintyResult
from .notes import worded
from .sensitivity import sensitivity_fields, sensitivity_json, sensitivity_units
from .text import validity_notes
from .uncertainty import uncertainty_summary

__all__ = ["json_value", "json_rows", "json_document", "case_summary", "prediction_json", "prediction_csv"]


def json_value(x: Any) -> Any:
    """A JSON-safe value: NaN and inf become None, NumPy scalars plain Python."""
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return None if not math.isfinite(float(x)) else float(x)
    return x


def json_rows(columns: dict[str, Any], keys: Sequence[str], n: int) -> list[dict[str, Any]]:
    """``n`` JSON records of ``keys`` from ``columns`` (record key: one value per row, or one value for all rows).

    A column without a value for a row (an empty array: not computed) and empty text are ``null``.
    """
    def cell(values: Any, i: int) -> Any:
        if isinstance(values, (int, float)):
            return values
        value = values[i] if len(values) > i else None
        return None if isinstance(value, str) and not value else json_value(value)

    return [{k: cell(columns[k], i) for k in keys} for i in range(n)]


def json_document(doc: dict[str, Any]) -> str:
    """``doc`` as indented UTF-8 JSON text with a final newline (every JSON file sealeak writes)."""
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def case_summary(case: Case) -> dict[str, Any]:
    """The case's main inputs and derived quantities, SI units (for JSON and reports)."""
    s = case.spectrum
    return {
        "title": case.title,
        "variant": case.label or None,
        "source": case.source,
        "spectrum": {"description": case.spectrum_note, "label": s.label, "h_rms": s.h_rms,
                     "slope_rms": s.slope_rms, "curvature_rms": s.curvature_rms, "area_ratio": s.area_ratio,
                     "q_min": s.q_min, "q_max": s.q_max},
        "youngs_modulus": case.youngs_modulus, "poisson_ratio": case.poisson_ratio,
        "contact_modulus": case.e_star,
        "seal": {"shape": case.seal.shape, "width": case.seal.width, "length": case.seal.length,
                 "aspect_ratio": case.seal.aspect_ratio, "nominal_area": case.seal.nominal_area},
        "viscosity": case.fluid.viscosity,
        "fluid": {"name": case.fluid.name or None, "viscosity": case.fluid.viscosity, "density": case.fluid.density,
                  "molecular_size": case.fluid.molecular_length, "molecular_size_note": case.fluid.molecular_length_note},
        "pressure_difference": case.pressure_difference,
        "alpha": case.alpha, "percolation_threshold": case.percolation_threshold, "gamma": case.gamma,
        "q0": case.q0, "q0_note": case.q0_note, "model": case.model,
    } | ({"band": _band_summary(case)} if case.band is not None else {})


def _band_summary(case: Case) -> dict[str, Any]:
    """An O-ring's or a profile seal's description (SI): what the band rows were computed from."""
    band = case.band
    assert band is not None
    out: dict[str, Any] = {"kind": band.kind, "seal_line_length": band.length, "faces": band.faces,
                           "load": band.load_name, "notes": list(band.notes)}
    if band.kind == "o-ring" and band.oring is not None:
        out |= {"cross_section_diameter": band.cross_section_diameter, "mean_diameter": band.mean_diameter,
                "regime": list(band.oring.regime)}
    else:
        out["pressure_profile"] = band.profile_source
    return out


def _units(results: Sequence[CaseResult]) -> dict[str, str]:
    units: dict[str, str] = {}
    for r in results:
        units |= r.units
    return units


def _records(results: Sequence[CaseResult], uncertainty: UncertaintyResult | None,
             sensitivity: SobolIndices | None = None) -> list[dict[str, Any]]:
    """Every row's record (SI), with the uncertainty fields of the row joined at its end, then its Sobol' indices."""
    records = [rec for r in results for rec in r.records()]
    if uncertainty is not None:
        records = [rec | extra for rec, extra in zip(records, uncertainty.row_fields(), strict=True)]
    if sensitivity is not None:
        records = [rec | extra for rec, extra in zip(records, sensitivity_fields(sensitivity), strict=True)]
    return records


def _all_units(results: Sequence[CaseResult], uncertainty: UncertaintyResult | None,
               sensitivity: SobolIndices | None) -> dict[str, str]:
    """The unit of every field of :func:`_records`."""
    return (_units(results) | (uncertainty.units if uncertainty is not None else {})
            | (sensitivity_units(sensitivity) if sensitivity is not None else {}))


def prediction_json(results: Sequence[CaseResult], uncertainty: UncertaintyResult | None = None,
                    sensitivity: SobolIndices | None = None) -> str:
    """The ``predict --json`` document: ``units``, ``results`` (one object per pressure), cases, messages.

    Effective-medium fields (``leak_rate_effective_medium`` etc.) join each results object of a
    case that asks for that model; with ``uncertainty`` its percentiles join each object, and the
    ``uncertainty`` object says how they were sampled; with ``sensitivity`` (its study's) the Sobol' indices
    of each input join each object (``sobol_first[KEY]`` ...) and the ``sensitivity`` object describes them.
    """
    records = [{k: json_value(v) for k, v in rec.items()} for rec in _records(results, uncertainty, sensitivity)]
    messages: list[str] = []
    warnings: list[str] = []
    for r in results:
        prefix = f"{r.case.label}: " if r.case.label else ""
        messages.extend(prefix + m for m in [*worded(r.messages), *validity_notes(r)])
        warnings.extend(prefix + w for w in r.warnings)
    theory = "critical junction (Lorenz & Persson, EPL 86 (2009) 44006)"
    if any(r.effective_medium is not None for r in results):
        theory += "; effective medium (2D Bruggeman over Persson's gap distribution P(u))"
    if any(r.case.coupled for r in results):
        theory += "; the fluid pressure in the band taken off the contact pressure (Persson, Tribol. Lett. 70 (2022))"
    doc = {
        "sealeak_version": __version__,
        "theory": theory,
        "units": _all_units(results, uncertainty, sensitivity),
        "results": records,
        "cases": [case_summary(r.case) for r in results],
        "warnings": warnings,
        "messages": messages,
    } | ({"uncertainty": uncertainty_summary(uncertainty)} if uncertainty is not None else {}) | (
        {"sensitivity": sensitivity_json(sensitivity, uncertainty.study)} if sensitivity is not None and uncertainty is not None else {})
    return json_document(doc)


def prediction_csv(results: Sequence[CaseResult], uncertainty: UncertaintyResult | None = None,
                   sensitivity: SobolIndices | None = None) -> str:
    """CSV with a header naming each column and its unit, e.g. ``leak_rate (m^3/s)``; with ``uncertainty`` its
    percentile columns last, then with ``sensitivity`` the Sobol' indices (``sobol_total[KEY] (1)`` ...)."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    study = any(r.case.label for r in results)
    units = _all_units(results, uncertainty, sensitivity)
    writer.writerow((["variant"] if study else []) + [f"{k} ({u})" if u else k for k, u in units.items()])
    for raw in _records(results, uncertainty, sensitivity):
        rec = {k: json_value(v) for k, v in raw.items()}
        row = ([rec["variant"]] if study else []) + [
            "" if rec.get(k) is None else (str(rec[k]).lower() if isinstance(rec[k], bool) else
                                           rec[k] if isinstance(rec[k], str) else f"{rec[k]:.10g}")
            for k in units]
        writer.writerow(row)
    return buf.getvalue()
