"""Text, JSON and CSV renderings of predictions (an edge module: SI in, readable units out)."""

from __future__ import annotations

import csv
import io
import json
import math
from typing import Any, Sequence

import numpy as np

from . import __version__
from .case import Case
from .leakage import CriticalJunctionResult
from .units import length_unit

__all__ = ["RESULT_UNITS", "EFFECTIVE_MEDIUM_UNITS", "result_records", "prediction_json", "prediction_csv", "prediction_table",
           "case_summary", "json_value"]

#: SI unit of every field of a result record.
RESULT_UNITS: dict[str, str] = {
    "squeeze_pressure": "Pa",
    "pressure_difference": "Pa",
    "percolates": "1",
    "critical_magnification": "1",
    "critical_gap": "m",
    "critical_wavelength": "m",
    "leak_rate": "m^3/s",
    "contact_area_at_cutoff": "1",
}


#: SI unit of the effective-medium fields (added to a result record when the case asks for that model).
EFFECTIVE_MEDIUM_UNITS: dict[str, str] = {
    "percolates_effective_medium": "1",
    "effective_conductivity": "m^3/(Pa*s)",
    "effective_gap": "m",
    "leak_rate_effective_medium": "m^3/s",
    "mean_gap": "m",
    "gap_distribution_mean": "m",
}
_EM_ATTR = {"percolates_effective_medium": "percolates", "effective_conductivity": "effective_conductivity",
            "effective_gap": "effective_gap", "leak_rate_effective_medium": "leak_rate", "mean_gap": "mean_gap",
            "gap_distribution_mean": "gap_distribution_mean"}


def json_value(x: Any) -> Any:
    """A JSON-safe value: NaN and inf become None, NumPy scalars plain Python."""
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return None if not math.isfinite(float(x)) else float(x)
    return x


def result_records(result: CriticalJunctionResult, variant: str = "", effective: Any = None) -> list[dict[str, Any]]:
    """One dict per squeeze pressure with the fields of :data:`RESULT_UNITS` (SI values), plus those
    of :data:`EFFECTIVE_MEDIUM_UNITS` when an effective-medium result (same pressures) is given."""
    records = []
    for i in range(len(result)):
        rec: dict[str, Any] = {}
        if variant:
            rec["variant"] = variant
        for key in RESULT_UNITS:
            rec[key] = json_value(getattr(result, key)[i])
        if effective is not None:
            for key, attr in _EM_ATTR.items():
                rec[key] = json_value(getattr(effective, attr)[i])
        records.append(rec)
    return records


def _effective(effective: Sequence[Any] | None, n: int) -> list[Any]:
    return list(effective) if effective is not None else [None] * n


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
        "pressure_difference": case.pressure_difference,
        "alpha": case.alpha, "percolation_threshold": case.percolation_threshold, "gamma": case.gamma,
        "q0": case.q0, "q0_note": case.q0_note, "model": case.model,
    }


def prediction_json(cases: Sequence[Case], results: Sequence[CriticalJunctionResult],
                    effective: Sequence[Any] | None = None) -> str:
    """The ``predict --json`` document: ``units``, ``results`` (one object per pressure), cases, messages.

    ``effective``: effective-medium results per case (None where the case does not ask for them);
    their fields (``leak_rate_effective_medium`` etc.) join each results object.
    """
    records: list[dict[str, Any]] = []
    messages: list[str] = []
    ems = _effective(effective, len(cases))
    for case, res, em in zip(cases, results, ems):
        records.extend(result_records(res, case.label, em))
        messages.extend((f"{case.label}: " if case.label else "") + m for m in res.messages)
        if em is not None:
            messages.extend((f"{case.label}: " if case.label else "") + "effective medium: " + m for m in em.messages)
    units = dict(RESULT_UNITS)
    theory = "critical junction (Lorenz & Persson, EPL 86 (2009) 44006)"
    if any(em is not None for em in ems):
        units.update(EFFECTIVE_MEDIUM_UNITS)
        theory += "; effective medium (2D Bruggeman over Persson's gap distribution P(u))"
    doc = {
        "sealeak_version": __version__,
        "theory": theory,
        "units": units,
        "results": records,
        "cases": [case_summary(c) for c in cases],
        "messages": messages,
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def prediction_csv(cases: Sequence[Case], results: Sequence[CriticalJunctionResult],
                   effective: Sequence[Any] | None = None) -> str:
    """CSV with a header naming each column and its unit, e.g. ``leak_rate (m^3/s)``."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    study = any(c.label for c in cases)
    ems = _effective(effective, len(cases))
    units = dict(RESULT_UNITS)
    if any(em is not None for em in ems):
        units.update(EFFECTIVE_MEDIUM_UNITS)
    header = (["variant"] if study else []) + [f"{k} ({u})" for k, u in units.items()]
    writer.writerow(header)
    for case, res, em in zip(cases, results, ems):
        for rec in result_records(res, case.label, em):
            row = ([rec["variant"]] if study else []) + [
                "" if rec.get(k) is None else (str(rec[k]).lower() if isinstance(rec[k], bool) else f"{rec[k]:.10g}")
                for k in units]
            writer.writerow(row)
    return buf.getvalue()


def _fmt(x: float, fmt: str) -> str:
    if x is None or not np.isfinite(x):
        width = int("".join(ch for ch in fmt.split(".")[0] if ch.isdigit()) or 0)
        return "—".rjust(width)
    return format(x, fmt)


def _setting_lines(case: Case, em: Any) -> dict[str, list[str]]:
    """Text lines describing the rubber, seal, fluid and theory of a case (for the table header)."""
    seal = case.seal
    geom = (f"ring Di = {seal.inner_diameter * 1e3:.4g} mm, Do = {seal.outer_diameter * 1e3:.4g} mm"
            if seal.shape == "ring" else "rectangle")
    theory = [f"theory    critical junction, α = {case.alpha:g}, p_c = {case.percolation_threshold:g} "
              f"(A/A0 = {1 - case.percolation_threshold:.3g} at ζc), γ = {case.gamma:g}, "
              f"q0 = {case.q0:.4g} 1/m ({case.q0_note})"]
    if em is not None:
        theory.append("          effective medium: 2D Bruggeman over P(u), σ(u) = u³/(12η), no fit factor "
                      "(stops percolating at A(ζ1)/A0 = 0.5)")
    return {
        "rubber": [f"rubber    E = {case.youngs_modulus / 1e6:.4g} MPa, ν = {case.poisson_ratio:g}, "
                   f"E* = {case.e_star / 1e6:.4g} MPa"],
        "seal": [f"seal      {geom}: Lx = {seal.width * 1e3:.4g} mm, Ly = {seal.length * 1e3:.4g} mm, "
                 f"Ly/Lx = {seal.aspect_ratio:.4g}"],
        "fluid": [f"fluid     η = {case.fluid.viscosity * 1e3:.4g} mPa·s, ΔP = {case.pressure_difference / 1e3:.4g} kPa"],
        "theory": theory,
    }


def prediction_table(cases: Sequence[Case], results: Sequence[CriticalJunctionResult],
                     effective: Sequence[Any] | None = None) -> str:
    """A plain-text report: the case, then one table row per squeeze pressure.

    With effective-medium results (model "both") their leak rate stands next to the critical-junction
    one, and a second table gives ū(1), the mean of P(u), u_e and σ_eff.
    """
    lines: list[str] = []
    first = cases[0]
    lines.append(first.title)
    lines.append("=" * min(len(first.title), 100))
    first_blocks = _setting_lines(first, _effective(effective, len(cases))[0])
    for case, res, em in zip(cases, results, _effective(effective, len(cases))):
        s = case.spectrum
        if case.label or case is first:
            if case.label:
                lines.append("")
                lines.append(f"[{case.label}]")
            lines.append(f"surface   {case.spectrum_note}")
            lines.append(f"          h_rms = {s.h_rms * 1e6:.4g} µm, slope_rms = {s.slope_rms:.4g}, "
                         f"A_true/A0 = {s.area_ratio:.4g}, q = {s.q_min:.4g} .. {s.q_max:.4g} 1/m")
            # every setting for the first case; for the other variants, the settings that differ
            for key, block in _setting_lines(case, em).items():
                if case is first or block != first_blocks.get(key):
                    lines.extend(block)
        cj = case.model != "effective-medium" or em is None
        if cj:
            lines.append("")
            both = em is not None
            lam_scale, lam_unit = length_unit(res.critical_wavelength)
            gap_scale, gap_unit = length_unit(res.critical_gap)
            lines.append(f"{'P0 (kPa)':>10} {'ζc':>9} {f'λc ({lam_unit})':>10} {f'u_c ({gap_unit})':>10} "
                         + (f"{'Q_CJ (m³/s)':>12} {'Q_EM (m³/s)':>12} {'Q_CJ (ml/min)':>14} {'Q_EM (ml/min)':>14}"
                            if both else f"{'Q (m³/s)':>11} {'Q (ml/min)':>11}")
                         + f" {'A(ζ1)/A0':>9}")
            for i in range(len(res)):
                q = (f"{_fmt(res.leak_rate[i], '12.3e')} {_fmt(em.leak_rate[i], '12.3e')} "
                     f"{_fmt(res.leak_rate[i] * 6e7, '14.4g')} {_fmt(em.leak_rate[i] * 6e7, '14.4g')}" if both else
                     f"{_fmt(res.leak_rate[i], '11.3e')} {_fmt(res.leak_rate[i] * 6e7, '11.4g')}")
                lines.append(
                    f"{res.squeeze_pressure[i] / 1e3:10.4g} {_fmt(res.critical_magnification[i], '9.4g')} "
                    f"{_fmt(res.critical_wavelength[i] / lam_scale, '10.4g')} {_fmt(res.critical_gap[i] / gap_scale, '10.4g')} "
                    f"{q} {res.contact_area_at_cutoff[i]:9.3f}")
            for m in res.messages:
                lines.append("note: " + m)
        if em is not None:
            lines.append("")
            lines.append("effective medium (2D Bruggeman):")
            u_scale, u_unit = length_unit(np.concatenate([em.mean_gap, em.gap_distribution_mean]))
            lines.append(f"{'P0 (kPa)':>10} {'A(ζ1)/A0':>9} {f'ū(1) ({u_unit})':>10} {f'<u>_P ({u_unit})':>11} "
                         f"{f'u_e ({u_unit})':>10} "
                         f"{'σ_eff (m³/Pa/s)':>16} {'Q_EM (m³/s)':>12} {'Q_EM (ml/min)':>14}")
            for i in range(len(em)):
                lines.append(
                    f"{em.squeeze_pressure[i] / 1e3:10.4g} {em.contact_area_at_cutoff[i]:9.3f} "
                    f"{_fmt(em.mean_gap[i] / u_scale, '10.4g')} {_fmt(em.gap_distribution_mean[i] / u_scale, '11.4g')} "
                    f"{_fmt(em.effective_gap[i] / u_scale if em.percolates[i] else np.nan, '10.4g')} "
                    f"{_fmt(em.effective_conductivity[i] if em.percolates[i] else np.nan, '16.4e')} "
                    f"{_fmt(em.leak_rate[i], '12.3e')} {_fmt(em.leak_rate[i] * 6e7, '14.4g')}")
            lines.append("          <u>_P: mean of the gap distribution P(u) (>= ū(1): the folded Gaussians add to it); "
                         "u_e: the gap whose u³/(12η) equals σ_eff")
            for m in em.messages:
                lines.append("note: " + m)
    return "\n".join(lines) + "\n"
